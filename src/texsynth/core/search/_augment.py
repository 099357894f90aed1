"""Exemplar augmentation: the exemplar's flipped and rotated copies as more neighbourhoods to choose from.

``Search(augment="flips" | "rotations" | "both")`` lets a synthesis copy
from the exemplar and from its mirror images or quarter turns: a texture
of few elements in any orientation (scales, pebbles, bumps) gains
variety, a directional one (wood grain, brick courses) loses its
direction. It is Embark's ``--flip-and-rotate``.

:func:`augmentations` names the transforms of each setting,
:func:`augmented_set` applies them. A method searches them through an
:class:`ExemplarAtlas`: the copies laid out side by side in one image,
each its own tile, separated by at least one gap pixel that no
neighbourhood may touch. Every neighbourhood of a tile is a neighbourhood
of one transformed copy (a rotated copy of a non-square exemplar has its
own shape: it is its own tile), so the method's search, its coherence
(copies that run on) and its PatchMatch work on the atlas as on any
exemplar with an exemplar mask; :meth:`ExemplarAtlas.to_exemplar` maps a
match back to the pixel of the original exemplar it came from, which keeps
every source-coordinate map a map into the exemplar
(``docs/conventions.md``). The first tile is the exemplar itself at the
atlas's origin, so exemplar coordinates are atlas coordinates too.

A coarse-to-fine method gives every pyramid level its atlas from the same
layout (``ExemplarAtlas(shape, augment, levels=n)``): a tile's corner at
level ``l`` is its corner at level 0 divided by ``2^l``, so a position
doubled from one level to the next stays in its tile (the parent of a
pixel, a field carried to the next level).

>>> import numpy as np
>>> ex = np.arange(6.0).reshape(2, 3)
>>> [t.name for t in augmentations("flips")]
['identity', 'mirror left-right', 'mirror up-down']
>>> atlas = ExemplarAtlas(ex.shape, "rotations")
>>> image, valid = atlas.apply(ex)
>>> image.shape, atlas.corners().tolist()
((3, 14), [[0, 0], [0, 4], [0, 7], [0, 11]])
>>> image[:3, 4:6]  # the quarter turn: a 3x2 tile
array([[2., 5.],
       [1., 4.],
       [0., 3.]])
>>> atlas.to_exemplar(np.array([[0, 4]])).tolist()  # its top-left pixel is the exemplar's top-right one
[[0, 2]]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._template import WindowSearch

__all__ = ["AUGMENTS", "AUGMENT_METHODS", "Transform", "augmentations", "augmented_set", "check_augment",
           "refuse_augment", "ExemplarAtlas", "window_search"]

#: Values of ``augment``: which flipped and rotated copies of the exemplar a search also draws from.
AUGMENTS = ("none", "flips", "rotations", "both")

#: The public functions that take ``Search(augment=...)``; the others refuse it naming these.
AUGMENT_METHODS = ("optimize_texture", "synthesize_pixels", "mix_textures", "efros_leung", "quilt", "patch_sampling",
                   "near_regular_texture")


@dataclass(frozen=True)
class Transform:
    """One symmetry of the square: mirror left-right if ``flip``, then turn ``turns`` quarter turns
    counter-clockwise (:func:`numpy.rot90`)."""

    name: str
    turns: int
    flip: bool

    def apply(self, image):
        """``image`` ``(h, w, ...)`` transformed on its first two axes (a view)."""
        image = np.asarray(image)
        return np.rot90(image[:, ::-1] if self.flip else image, self.turns, axes=(0, 1))

    def shape(self, shape):
        """The ``(h, w)`` of a transformed ``(h, w)`` image."""
        return (shape[1], shape[0]) if self.turns % 2 else (shape[0], shape[1])

    def origin(self, shape):
        """``(h', w', 2)`` int64: the pixel of the ``(h, w)`` image each pixel of its transform shows."""
        return np.ascontiguousarray(self.apply(np.indices(tuple(shape), dtype=np.int64).transpose(1, 2, 0)))


_IDENTITY = Transform("identity", 0, False)
_TRANSFORMS = {
    "none": (_IDENTITY,),
    "flips": (_IDENTITY, Transform("mirror left-right", 0, True), Transform("mirror up-down", 2, True)),
    "rotations": (_IDENTITY, Transform("rotate 90", 1, False), Transform("rotate 180", 2, False),
                  Transform("rotate 270", 3, False)),
}
_TRANSFORMS["both"] = _TRANSFORMS["rotations"] + tuple(
    Transform(f"mirror left-right, rotate {90 * k}" if k else "mirror left-right", k, True) for k in range(4))


def check_augment(augment):
    """``augment`` itself if it is one of :data:`AUGMENTS`, else a ValueError (TypeError) listing them.

    >>> check_augment("flip")
    Traceback (most recent call last):
    ...
    ValueError: augment must be one of 'none', 'flips', 'rotations', 'both', got 'flip'
    """
    words = ", ".join(map(repr, AUGMENTS))
    if not isinstance(augment, str):
        raise TypeError(f"augment must be one of {words}, got {type(augment).__name__} {augment!r}")
    if augment not in AUGMENTS:
        raise ValueError(f"augment must be one of {words}, got {augment!r}")
    return augment


def refuse_augment(augment, name, reason):
    """A ValueError naming ``augment``, the function ``name`` that cannot use it and the ``reason``, and the
    functions that take it; nothing for ``augment="none"``.

    >>> refuse_augment("both", "synthesize_solid", "each view fixes the texture's orientation in its plane")
    Traceback (most recent call last):
    ...
    ValueError: augment='both' is not available in synthesize_solid (each view fixes the texture's orientation in \
its plane); optimize_texture, synthesize_pixels, mix_textures, efros_leung, quilt, patch_sampling, \
near_regular_texture take it; pass augment='none'
    """
    if check_augment(augment) != "none":
        raise ValueError(f"augment={augment!r} is not available in {name} ({reason}); "
                         f"{', '.join(AUGMENT_METHODS)} take it; pass augment='none'")


def augmentations(augment):
    """The transforms of ``augment``, the identity first: 1 for ``"none"``; the identity and the two mirror
    images for ``"flips"``; the four quarter turns for ``"rotations"``; all eight symmetries of the square
    (the dihedral group) for ``"both"``."""
    return _TRANSFORMS[check_augment(augment)]


def augmented_set(exemplar, augment):
    """The exemplar's augmented set: a list of its transformed copies (views), the exemplar first.

    >>> [a.shape for a in augmented_set(np.zeros((2, 3)), "rotations")]
    [(2, 3), (3, 2), (2, 3), (3, 2)]
    """
    return [t.apply(exemplar) for t in augmentations(augment)]


class ExemplarAtlas:
    """The augmented set of a ``(h, w)`` exemplar laid out side by side, and the map back to the exemplar.

    Tile ``t`` (:func:`augmentations` order) has its top-left corner at row 0 and a column that is a
    multiple of ``2^(levels - 1)``; tiles are separated by at least one gap pixel at every level up to
    ``levels - 1`` (a pyramid level ``l`` of ``ceil(h / 2^l)`` rows and columns, as
    :func:`texsynth.core.pyramid.gaussian_pyramid` makes them).

    Parameters
    ----------
    shape : (int, int)
        The exemplar's ``(h, w)`` at level 0.
    augment : {"none", "flips", "rotations", "both"}
        Which copies (:func:`augmentations`).
    levels : int
        The pyramid levels the layout must hold.
    """

    def __init__(self, shape, augment, *, levels=1):
        self.shape = (int(shape[0]), int(shape[1]))
        self.transforms = augmentations(augment)
        self.levels = int(levels)
        align = 2 ** (self.levels - 1)
        widths = [t.shape(self.shape)[1] for t in self.transforms]
        pitch = [align * (-(-w // align) + 1) for w in widths]  # the tile and at least `align` gap columns
        self._columns = np.concatenate([[0], np.cumsum(pitch)[:-1]]).astype(np.int64)
        self._width = int(sum(pitch))
        self._origins = {}

    def __len__(self):
        return len(self.transforms)

    def level_shape(self, level=0):
        """The exemplar's ``(h, w)`` at pyramid ``level``."""
        return tuple(-(-s // 2**level) for s in self.shape)

    def corners(self, level=0):
        """``(T, 2)`` int64: each tile's top-left corner at ``level``."""
        return np.stack([np.zeros(len(self), np.int64), self._columns >> level], axis=1)

    def tile_shapes(self, level=0):
        """Each tile's ``(h, w)`` at ``level``."""
        return [t.shape(self.level_shape(level)) for t in self.transforms]

    def atlas_shape(self, level=0):
        """The atlas's ``(H, W)`` at ``level``."""
        return max(h for h, _ in self.tile_shapes(level)), -(-self._width // 2**level)

    def compose(self, copies, level=0):
        """The atlas of given copies (each transform's image at ``level``, e.g. a level of its own pyramid):
        ``(image, valid)``, ``valid`` True on the tiles' pixels and False in the gaps (which hold 0)."""
        first = np.asarray(copies[0])
        shape = self.atlas_shape(level)
        image = np.zeros(shape + first.shape[2:], first.dtype)
        valid = np.zeros(shape, bool)
        for tile, (r, c), want in zip(copies, self.corners(level), self.tile_shapes(level)):
            if tuple(np.shape(tile)[:2]) != want:
                raise ValueError(f"a tile of shape {np.shape(tile)[:2]} does not fit its place {want} at level {level}")
            image[r : r + want[0], c : c + want[1]] = tile
            valid[r : r + want[0], c : c + want[1]] = True
        return image, valid

    def apply(self, image, level=0, valid=None):
        """The atlas of the exemplar ``image`` at ``level`` (each tile a transform of it) and its valid mask:
        the tiles' pixels where ``valid`` (the exemplar's own mask, if any) is true."""
        atlas, inside = self.compose([t.apply(image) for t in self.transforms], level)
        if valid is not None:
            mask, _ = self.compose([t.apply(valid) for t in self.transforms], level)
            inside = inside & (mask > 0.5)
        return atlas, inside

    def pyramid(self, image, levels, build):
        """The atlas at every level of the copies' own pyramids, finest first: ``build(copy, levels)``
        (e.g. :func:`~texsynth.core.pyramid.gaussian_pyramid`) of each transformed copy of ``image``, so that
        the parent of a tile's pixel ``(r, c)`` is its own pixel ``(r // 2, c // 2)`` one level coarser."""
        per_copy = [build(np.ascontiguousarray(t.apply(image)), levels) for t in self.transforms]
        return [self.compose([p[level] for p in per_copy], level)[0] for level in range(levels)]

    def tiles(self, pyramid):
        """Each copy's own pyramid cut out of the atlas ``pyramid`` (its levels, finest first): views."""
        return [[image[r : r + h, c : c + w] for level, image in enumerate(pyramid)
                 for (r, c), (h, w) in [(self.corners(level)[t], self.tile_shapes(level)[t])]]
                for t in range(len(self))]

    def inside(self, level=0):
        """``(H, W)`` bool: the atlas pixels that belong to a tile (False in the gaps)."""
        return self.origin(level)[..., 0] >= 0

    def origin(self, level=0):
        """``(H, W, 2)`` int64: the exemplar pixel (at ``level``) that each atlas pixel shows, -1 in the gaps."""
        if level not in self._origins:
            out, inside = self.compose([t.origin(self.level_shape(level)) for t in self.transforms], level)
            out[~inside] = -1
            self._origins[level] = out
        return self._origins[level]

    def to_exemplar(self, coordinates, level=0):
        """Atlas positions ``(..., 2)`` (inside the tiles) as the exemplar positions they show, at ``level``."""
        c = np.asarray(coordinates)
        return self.origin(level)[c[..., 0], c[..., 1]]


def window_search(image, window, augment="none"):
    """``(search, atlas)``: a :class:`~texsynth.core.search.WindowSearch` over the ``(H, W, C)`` ``image``, or
    over the :class:`ExemplarAtlas` of its ``augment`` copies with every window inside one copy (``atlas``
    None for ``"none"``); the blocks are cut from ``search.image``, and ``atlas.to_exemplar`` maps their
    pixels back to ``image``'s.

    >>> search, atlas = window_search(np.zeros((6, 5, 1)), (4, 4), "rotations")
    >>> search.image.shape, search.n_positions
    ((6, 26, 1), 24)
    """
    if check_augment(augment) == "none":
        return WindowSearch(image, window), None
    atlas = ExemplarAtlas(image.shape[:2], augment)
    copies, valid = atlas.apply(image)
    return WindowSearch(copies, window, valid), atlas
