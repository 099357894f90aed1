"""Texton masks, local orientation and size control, progressive variation (Zhang et al. 2003), in 2-D.

Zhang, Zhou, Velho, Guo and Shum [1]_ synthesise *progressively-variant*
textures: a texture whose elements keep their shape while their orientation,
size and appearance change over the output. A progressively-variant texture
is the tuple ``(T, M, F, V)``: the texture image ``T``, its **texton mask**
``M`` (which kind of texture element each pixel belongs to), a transition
function ``F`` and an orientation field ``V``. This module is the 2-D part of
the method, built on Wei-Levoy multi-resolution pixel synthesis with
k-coherent candidates (:func:`~texsynth.synthesize_pixels` with
``candidates="k-coherent"``, which Zhang et al. use for speed):

1. **Texton mask as a feature channel.** The mask is appended to the colour
   as one more channel, scaled by ``sqrt(texton_weight)``, so that every
   neighbourhood distance is

   .. math:: \\|N(p) - N(x)\\|^2 = \\sum_{d} \\|c(p + d) - c(x + d)\\|^2
             + w_M \\, (M(p + d) - M(x + d))^2

   and the mask is synthesised along with the colour: a neighbourhood that
   cuts an element in two costs ``w_M`` per pixel of the cut, whatever the
   element's colour, so elements stay whole.
2. **Orientation and magnification fields.** The output neighbourhood of pixel ``p``
   is sampled in the local frame, at ``p + S(p) R(theta(p)) d`` for every
   footprint offset ``d`` (bilinear, toroidal), at this level and at the
   parent level; it is compared with the exemplar's plain neighbourhood at
   ``x + d``. The exemplar is therefore copied rotated by ``theta`` and
   magnified by ``S``: the lecture's "local size control" and "vector field
   control". The copy ``s(p)`` is a continuous exemplar position, so a
   piece continued from the neighbour ``r = p + e`` is

   .. math:: s(p) = s(r) - (S(p) R(\\theta(p)))^{-1} e

   (Ashikhmin's rule ``s(r) - e`` in the local frame), and the output
   pixel is the exemplar sampled bilinearly at ``s(p)``.
3. **Progressive variation between two exemplars.** With ``exemplar_b`` and
   a ``blend`` map, the candidates of every pixel come from both exemplars'
   k-coherence sets, and a transition channel (the paper's ``F``: 0 on
   ``exemplar``, 1 on ``exemplar_b``; on the output the user's ``blend``,
   dithered into element-sized blobs, :func:`_dithered`) is compared with
   weight ``blend_weight``; where a copied piece ends, the new one starts in
   ``exemplar_b`` with the local probability of the target (the per-pixel
   choice of exemplar). Pieces of both exemplars meet along element
   boundaries, because the texton masks (one per exemplar: a mixed texton
   mask) are compared too.

Magnified (``S > 1``), a footprint samples every ``S``-th pixel; there only
the adjacent neighbours' copies are continued and each sample is a small
tent average (:func:`_bilinear` with ``spread``), so that interleaved copies
cannot hide between the samples. ``docs/methods/texton.md`` has the choices
made where the paper is silent, the measurements and the failures.

References
----------
.. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
   progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
   (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_array, as_float_array, as_image, as_rng, as_size, check_choice, check_group,
                              check_memory,
                              check_positive_float, check_positive_int, restore_channels, with_channels)
from ..core.fields import as_field as _field, bilinear as _bilinear, frames as _frames, level_field as _level_field
from ..core.fields import taps as _taps
from ..core.neighborhood import SHAPES, causal_parts, footprint, mask_offsets, patch_shape, wavefronts
from ..core.pyramid import gaussian_pyramid, level_shapes
from ..core.textons import find_textons
from ..core.search import KCoherence, Search, check_method, is_auto, nearest_candidates, refuse_augment, resolve
from ._options import check_fits, check_output_levels, default_parent_size
from ._wei_levoy import Neighborhood, Source, candidate_pixels

__all__ = ["synthesize_controlled", "find_textons", "ControlledSynthesisInfo"]

# Precision of the matching (pyramids, queries, distances); the output is sampled from the exemplar as given.
_WORK_DTYPE = np.float32


@dataclass
class ControlledSynthesisInfo:
    """Extra results of :func:`synthesize_controlled`.

    Attributes
    ----------
    texton_mask : numpy.ndarray or None
        ``(H, W)``: the synthesised texton mask, the exemplar's mask at the
        nearest exemplar pixel of every output pixel's copy (None without a
        texton mask).
    coordinates : numpy.ndarray
        The source-coordinate map of ``docs/conventions.md`` (for
        :func:`texsynth.apply_coordinates`): ``(H, W, 2)`` int64, the
        exemplar pixel each output pixel copies, where every copy sits on a
        whole pixel (no fields, or fields that keep it so); else
        ``(H, W, 4, 2)``, the four exemplar pixels of each bilinear sample,
        largest weight first. With ``exemplar_b``, a pixel's coordinates are
        in the exemplar :attr:`sources` names.
    weights : numpy.ndarray or None
        ``(H, W, 4)`` bilinear weights of ``coordinates`` (None for copies).
    positions : numpy.ndarray
        ``(H, W, 2)`` float: the continuous exemplar position ``s(p)``
        (row, col) every output pixel was sampled at.
    sources : numpy.ndarray
        ``(H, W)`` int: 0 where the pixel came from ``exemplar``, 1 where it
        came from ``exemplar_b``.
    energy : numpy.ndarray
        Per level, coarsest first: the mean squared distance of the chosen
        neighbourhoods (their known part).
    stage : numpy.ndarray of int
        The stage of each energy value (the level's index in synthesis order).
    level_shapes : list of tuple
        Output shape of each level, coarsest first.
    method : str
        The search backend that found the k-coherence sets.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time per level.
    """

    texton_mask: np.ndarray | None = None
    coordinates: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2), np.int64))
    weights: np.ndarray | None = None
    positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2)))
    sources: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), int))
    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stage: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    level_shapes: list = field(default_factory=list)
    method: str = "exact"
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


# --------------------------------------------------------------------------- #
# the texton mask (find_textons: texsynth.core.textons, shared with the surface method)
# --------------------------------------------------------------------------- #
def _as_texton_mask(value, image, name):
    """A texton mask of the exemplar's size as floats in [0, 1] (None: no mask)."""
    if value is None:
        return None
    if isinstance(value, str):
        if value != "auto":
            raise ValueError(f"{name} must be 'auto', None or an array of the exemplar's size, got {value!r}")
        return find_textons(image).astype(np.float64)
    arr = as_array(value, name)
    if arr.ndim == 3 and arr.shape[-1] == 1:
        arr = arr[..., 0]
    if arr.shape != image.shape[:2]:
        raise ValueError(f"{name} must have the exemplar's size {image.shape[:2]} (one label per pixel), "
                         f"got shape {arr.shape}; pass a mask of that size or texton_mask='auto'")
    return as_float_array(arr, name).astype(np.float64)


# --------------------------------------------------------------------------- #
# the blend field (orientation and scale fields: texsynth.core.fields)
# --------------------------------------------------------------------------- #
def _dithered(blend, sigma, rng):
    """The blend map as a binary target: 1 where ``blend`` exceeds smooth noise of uniform distribution.

    The noise is white noise blurred by ``sigma`` pixels (toroidal) and
    mapped to a uniform distribution by its ranks, so the share of ones
    around a pixel is ``blend`` there, in blobs about ``sigma`` wide.
    """
    from scipy.ndimage import gaussian_filter

    noise = gaussian_filter(rng.standard_normal(blend.shape), sigma, mode="wrap")
    ranks = np.empty(noise.size)
    ranks[np.argsort(noise, axis=None, kind="stable")] = np.arange(noise.size)
    return (blend > (ranks.reshape(blend.shape) + 0.5) / noise.size).astype(np.float64)


# --------------------------------------------------------------------------- #
# the exemplars at one level: one numbering of both exemplars' positions
# --------------------------------------------------------------------------- #
@dataclass
class _Grids:
    """Every exemplar position of one level (both exemplars), numbered ``base[e] + row * cols + col``."""

    vectors: np.ndarray  # (N, D) full footprint at this level + the parent's
    sets: np.ndarray  # (N, k) k-coherence sets, global numbers
    coords: np.ndarray  # (N, 2) exemplar pixel of every position
    which: np.ndarray  # (N,) exemplar of every position
    origin: np.ndarray  # (E, 2) first cell of each exemplar's grid
    shape: np.ndarray  # (E, 2) rows, cols of each grid
    base: np.ndarray  # (E,) first global number of each grid
    images: list  # exemplar level images (h, w, C')
    method: str


def _level_grids(sources, level, levels, k, method, seed):
    full = causal_parts(sources[0].size, sources[0].shape)[2]
    similar = full.copy()
    similar[sources[0].size[0] // 2, sources[0].size[1] // 2] = True
    vectors, sets, coords, which, origin, shape, base = [], [], [], [], [], [], []
    used = None
    start = 0
    for e, src in enumerate(sources):
        cen = candidate_pixels(src, level, levels)
        grid = tuple(int(v) for v in cen[-1] - cen[0] + 1)
        sim = src.vectors(level, levels, cen, similar) if k > 1 else None
        kc = KCoherence(sim, grid, min(k, len(cen)), method=method, profile="default",
                        rng=np.random.default_rng([seed, level, 3, e]))
        used = kc.method or used
        vectors.append(src.vectors(level, levels, cen, full))
        members = kc.sets + start
        if members.shape[1] < k:  # a tiny exemplar: repeat its own position
            members = np.concatenate([members, np.repeat(members[:, :1], k - members.shape[1], 1)], 1)
        sets.append(members)
        coords.append(cen)
        which.append(np.full(len(cen), e))
        origin.append(cen[0])
        shape.append(grid)
        base.append(start)
        start += len(cen)
    return _Grids(np.concatenate(vectors), np.concatenate(sets), np.concatenate(coords).astype(np.float64),
                  np.concatenate(which), np.array(origin), np.array(shape), np.array(base),
                  [s.pyramid[level] for s in sources], used or method)


def _random_cells(grids, exemplar, rng):
    """A random position of the given exemplar (per entry): Ashikhmin's restart."""
    n = grids.shape[:, 0] * grids.shape[:, 1]
    return grids.base[exemplar] + np.minimum((rng.random(exemplar.shape) * n[exemplar]).astype(np.intp),
                                             n[exemplar] - 1)


def _cells_of(grids, pos, exemplar):
    """Global numbers of the cells nearest to continuous positions, and where they leave their grid."""
    origin, shape = grids.origin[exemplar], grids.shape[exemplar]
    local = np.floor(pos + 0.5).astype(np.intp) - origin  # not rint: halves would round to even, alternately
    outside = np.any((local < 0) | (local >= shape), axis=-1)
    local = np.where(outside[..., None], 0, local)
    return grids.base[exemplar] + local[..., 0] * shape[..., 1] + local[..., 1], outside


def _sample_exemplars(grids, pos, exemplar, channels):
    """The exemplar pixels (first ``channels`` channels) at continuous positions, per source exemplar."""
    out = np.empty(pos.shape[:-1] + (channels,), grids.images[0].dtype)
    for e, image in enumerate(grids.images):
        here = exemplar == e
        if here.any():
            out[here] = _bilinear(image[..., :channels], pos[here], wrap=False)[0]
    return out


# --------------------------------------------------------------------------- #
# one level
# --------------------------------------------------------------------------- #
@dataclass
class _State:
    """Where every output pixel of a level was copied from: continuous position and exemplar."""

    pos: np.ndarray  # (H * W, 2)
    exemplar: np.ndarray  # (H * W,)
    shape: tuple


def _initial_state(grids, parent, shape, inverse, blend, rng):
    """Coarsest level: random positions (exemplar by ``blend``); finer: the parent's copies continued."""
    h, w = shape
    if parent is None:
        exemplar = (rng.random(h * w) < blend.reshape(-1)).astype(np.intp) if blend is not None else np.zeros(h * w, np.intp)
        cells = _random_cells(grids, exemplar, rng)
        return _State(grids.coords[cells].copy(), exemplar, shape)
    rows, cols = np.divmod(np.arange(h * w), w)
    up = (rows // 2) * parent.shape[1] + cols // 2
    child = np.stack([rows - 2 * (rows // 2), cols - 2 * (cols // 2)], 1).astype(np.float64)
    # s_l(p) = 2 s_{l+1}(p // 2) + (S R)^-1 (p - 2 (p // 2)): the parent's copy, one level finer
    pos = 2.0 * parent.pos[up] + np.einsum("nij,nj->ni", inverse, child)
    exemplar = parent.exemplar[up].copy()
    lo = grids.origin[exemplar]
    pos = np.clip(pos, lo, lo + grids.shape[exemplar] - 1)
    return _State(pos, exemplar, shape)


def _controlled_level(lv_out, lv_parent, grids, src, fields, state, channels, rng):
    """Zhang et al. at one level: scanline (wavefront) order, k-coherent candidates in the local frame.

    ``fields`` holds, per output pixel of the level, ``A = S R`` and its
    inverse, the dithered blend map (or None) and ``S``. Returns
    (energy, state).
    """
    height, width, cw = lv_out.shape  # a copy writes the first ``channels`` (colour, mask), not the transition
    a, inverse, blend, factor = fields
    enlarged = factor > 1.0
    spread = np.maximum(factor - 1.0, 0.0) / 2.0 if enlarged.any() else None
    above, left, full = causal_parts(src.size, src.shape)
    causal = above | left
    similar = full.copy()
    similar[src.size[0] // 2, src.size[1] // 2] = True
    d_full = mask_offsets(full).astype(np.float64)
    pmask = footprint(src.parent_size, src.shape)
    d_par = mask_offsets(pmask).astype(np.float64)
    # the neighbours whose copies are continued: the causal ones, and below the coarsest level all of the
    # footprint (their copies are the parent's prediction until they are synthesised), as in texsynth.pixel._kcoherent
    e_cand = (mask_offsets(causal) if lv_parent is None
              else np.concatenate([mask_offsets(causal), mask_offsets(similar & ~causal)]))
    flat = lv_out.reshape(-1, cw)
    flat[:, :channels] = _sample_exemplars(grids, state.pos, state.exemplar, channels)
    done = np.zeros(height * width, bool)
    n = height * width
    # the parent's part of every query is fixed during the level: p // 2 + A d at the parent level
    parent_part = None
    if lv_parent is not None:
        rows, cols = np.divmod(np.arange(n), width)
        centre = np.stack([rows // 2, cols // 2], 1).astype(np.float64)
        parent_part = np.empty((n, len(d_par) * cw), lv_out.dtype)
        for s0 in range(0, n, 8192):
            sl = slice(s0, min(n, s0 + 8192))
            pos = centre[sl, None, :] + np.einsum("nij,dj->ndi", a[sl], d_par)
            parent_part[sl] = _bilinear(lv_parent, pos, wrap=True)[0].reshape(sl.stop - sl.start, -1)
    order, bounds = wavefronts(height, width, src.size[1] // 2 + 1)
    k = grids.sets.shape[1]
    energy = 0.0
    for t in range(len(bounds) - 1):
        pix = order[bounds[t] : bounds[t + 1]]
        m = len(pix)
        r, c = np.divmod(pix, width)
        # k-coherent candidates: s(r) - A^-1 e for every neighbour r = p + e (Ashikhmin in the local frame)
        # Magnified (S > 1), the query samples every S-th pixel and cannot see a copy continued from two
        # pixels away interleave with another: there only the adjacent neighbours' copies are continued.
        e = np.where(enlarged[pix, None, None], np.clip(e_cand, -1, 1)[None], e_cand[None])
        nb = ((r[:, None] + e[..., 0]) % height) * width + (c[:, None] + e[..., 1]) % width
        cont = state.pos[nb] - np.einsum("mij,mej->mei", inverse[pix], e)
        cells, outside = _cells_of(grids, cont, state.exemplar[nb])
        if outside.any():  # a piece that leaves its exemplar ends; the next starts at random (exemplar by blend)
            fresh = np.zeros(m, np.intp) if blend is None else (rng.random(m) < blend[pix]).astype(np.intp)
            fresh = np.broadcast_to(fresh[:, None], outside.shape)[outside]
            cells[outside] = _random_cells(grids, fresh, rng)
            cont[outside] = grids.coords[cells[outside]]
        cands = grids.sets[cells].reshape(m, -1)
        # the query: this level's footprint at p + A d (the synthesised part only), the parent's whole
        pos = np.stack([r, c], 1)[:, None, :].astype(np.float64) + np.einsum("mij,dj->mdi", a[pix], d_full)
        # magnified: each value is the mean over a tent about 2S - 1 pixels wide, so it sees every pixel
        here, known = _bilinear(lv_out, pos, wrap=True, done=done,
                                spread=None if spread is None else spread[pix, None])
        query = here.reshape(m, -1)
        weights = np.repeat(known, cw, axis=1)
        if parent_part is not None:
            query = np.concatenate([query, parent_part[pix]], 1)
            weights = np.concatenate([weights, np.ones((m, parent_part.shape[1]), weights.dtype)], 1)
        choice, d2 = nearest_candidates(query, cands, vectors=grids.vectors, weights=weights)
        best = cands[np.arange(m), choice]
        # the copy goes on at the continuous position where the winner is a continuation, else at its cell
        j, member = np.divmod(choice, k)
        pos_new = grids.coords[best].copy()
        cont_win = member == 0
        pos_new[cont_win] = cont[np.flatnonzero(cont_win), j[cont_win]]
        state.pos[pix] = pos_new
        state.exemplar[pix] = grids.which[best]
        flat[pix, :channels] = _sample_exemplars(grids, pos_new, grids.which[best], channels)
        done[pix] = True
        energy += float(d2.sum())
    return energy / n, state


# --------------------------------------------------------------------------- #
# the public function
# --------------------------------------------------------------------------- #
def _coordinate_map(state, shapes, size):
    """The source-coordinate map: whole-pixel copies ``(H, W, 2)``, else bilinear taps ``(H, W, 4, 2)`` and weights."""
    whole = np.rint(state.pos)
    if np.array_equal(whole, state.pos):
        return whole.astype(np.int64).reshape(size + (2,)), None
    index = np.empty(state.pos.shape[:1] + (4,), np.intp)
    weight = np.empty(index.shape)
    for e, (h, w) in enumerate(shapes):
        here = state.exemplar == e
        index[here], weight[here] = _taps(state.pos[here], h, w, wrap=False)
    order = np.argsort(-weight, axis=1, kind="stable")
    index, weight = np.take_along_axis(index, order, 1), np.take_along_axis(weight, order, 1)
    rows, cols = np.divmod(index, np.asarray(shapes)[state.exemplar, 1][:, None])
    return np.stack([rows, cols], -1).astype(np.int64).reshape(size + (4, 2)), weight.reshape(size + (4,))


def _work_image(image, mask, texton_weight, transition, blend_weight):
    """Colour, then ``sqrt(w_M) M``, then the transition value ``sqrt(w_F) F``: one matching image."""
    parts = [image]
    if mask is not None:
        parts.append(np.sqrt(texton_weight) * mask[..., None])
    if transition is not None:
        parts.append(np.full(image.shape[:2] + (1,), np.sqrt(blend_weight) * transition))
    return np.concatenate(parts, axis=-1)


def synthesize_controlled(
    exemplar,
    size,
    *,
    texton_mask="auto",
    texton_weight=1.0,
    orientation=None,
    magnification=None,
    exemplar_b=None,
    blend=None,
    blend_weight=1.0,
    neighborhood=Neighborhood(),
    search=Search(candidates="k-coherent"),
    rng=None,
    progress=False,
    return_info=False,
):
    """Texton-mask synthesis with local orientation and size control and progressive variation (Zhang et al. 2003).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> brick = texsynth.data.load("brick")[:32, :32]
    >>> out, info = texsynth.synthesize_controlled(brick, 24, orientation=np.pi / 2, rng=0, return_info=True,
    ...                                            neighborhood=texsynth.Neighborhood(levels=2))  # turned 90°
    >>> out.shape, info.texton_mask.shape
    ((24, 24, 3), (24, 24))

    Pixel-based synthesis that matches the texton mask (the texture's
    elements) along with the colours, so elements keep their shape, with
    the texture turned and magnified locally by fields and, with a second
    exemplar, a progressive variation from one to the other [1]_.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    size : int or (int, int)
        Output ``(height, width)``.
    texton_mask : "auto", array_like or None
        The texton mask ``M`` of the exemplar: ``(h, w)`` values in [0, 1]
        (bool, or labels scaled to [0, 1]) marking its texture elements.
        ``"auto"`` (default): :func:`find_textons` (Otsu's threshold of the
        blurred luminance; call it with your own ``sigma`` or ``threshold``
        and pass the result to adjust it). None: colour alone (Wei-Levoy
        with k-coherent candidates). With ``exemplar_b``: ``"auto"``, None
        or a pair ``(mask, mask_b)``.
    texton_weight : float
        Weight of a texton-mask difference against a colour difference
        (per pixel, colours in [0, 1]); the paper's ``w_M``. Default 1: a pixel on the wrong side
        of an element boundary costs as much as the largest colour
        difference of one channel. 0 compares colour alone.
    orientation : None, float, array_like or callable
        Angle in radians, counter-clockwise as the image is shown, by which
        the texture is turned at each output pixel (``theta``): a
        number (everywhere), an array of the output size, or a callable
        ``orientation(rows, cols)`` of float arrays of output pixel
        coordinates returning the angles. None: 0.
    magnification : None, float, array_like or callable
        How much larger the texture's elements appear at each output pixel
        (2: twice as large; the output's size is ``size``); ``S``, same forms
        as ``orientation``; finite, in [0.001, 1000]. None: 1.
    exemplar_b : array_like, optional
        A second exemplar, same channels, for a progressive variation.
    blend : None, float, array_like or callable
        With ``exemplar_b``: where the output shows which exemplar, 0
        (``exemplar``) to 1 (``exemplar_b``), same forms as ``orientation``,
        values in [0, 1] (e.g. ``lambda r, c: c / width`` for a left-to-right
        variation). It is dithered into blobs about an element wide (see
        Notes), so the share of ``exemplar_b`` around a pixel is ``blend``
        there.
    blend_weight : float
        Weight of the transition channel (default 1); the paper's ``w_F``.
        Larger: the
        output follows the dithered ``blend`` more closely; smaller: the
        elements decide more where one exemplar gives way to the other.
    neighborhood : Neighborhood
        As in :func:`~texsynth.synthesize_pixels`
        (:class:`~texsynth.pixel.Neighborhood`: 5x5, square, 3x3 parent, 3
        levels).
    search : Search
        The k-coherent search (:class:`~texsynth.core.search.Search`):
        ``k`` the size of the k-coherence sets (``"auto"``: 1, Ashikhmin's
        candidates, the continuations of the neighbours' copies), ``method``
        the backend that finds them (``k > 1``). ``candidates`` is
        ``"k-coherent"`` (default) or ``"auto"``: the only kind here.
    rng, progress
        As in :func:`~texsynth.synthesize_pixels` (``rng`` seeds the initial
        positions and the restarts; the bar advances once per level).
    return_info : bool
        Also return a :class:`ControlledSynthesisInfo` (with the synthesised
        texton mask).

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channel layout; tileable where the fields
        are.
    info : ControlledSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid exemplar or option, a texton mask of another size than
        its exemplar, fields not of the output size, non-finite fields,
        non-positive magnifications, blend values outside [0, 1], ``blend`` without
        ``exemplar_b`` (or the reverse), exemplars with different channels,
        or a size that cannot fit in memory.

    Notes
    -----
    Every level is synthesised in scanline order (pixels of one wavefront at
    once, as :func:`~texsynth.synthesize_pixels` with k-coherent
    candidates). The query of pixel ``p`` is its footprint sampled at
    ``p + A(p) d``, ``A = S R(theta)``, at this level (only the already
    synthesised pixels count: the bilinear weight of the synthesised corners
    weighs each value) and at the parent level around ``p // 2`` (all of it);
    with ``A = 1`` the synthesised part is Wei-Levoy's causal neighbourhood.
    Its distance to the exemplar's neighbourhood at ``x`` is the sum over
    colour, ``w_M`` times the texton mask and ``w_F`` times the transition
    channel. The candidates ``x`` are the k-coherence sets [2]_ of the
    continuations ``s(r) - A^{-1}(r - p)`` of the neighbours' copies.

    >>> two = texsynth.Search(candidates="k-coherent", k=2)  # k-coherence sets of 2
    >>> out = texsynth.synthesize_controlled(brick, 24, neighborhood=texsynth.Neighborhood(levels=2), search=two, rng=0)
    >>> texsynth.synthesize_controlled(brick, 24, magnification=0.0)
    Traceback (most recent call last):
    ...
    ValueError: magnification must be positive everywhere (a factor: 2 doubles the elements), got a minimum of 0

    What could not be checked: the paper [1]_ was not at hand; this follows
    its published abstract, the lecture slides that summarise it ("texton
    masks keep elements from breaking apart", "local size control",
    "vector field control") and common re-implementations. Not from the
    paper: the automatic mask (Otsu), the weights' defaults (``w_M = w_F =
    1``), the continuous copy positions (bilinear), counting only
    synthesised pixels in a rotated neighbourhood, the handling of
    magnification (adjacent continuations, tent-averaged samples), float32
    matching, and the transition channel of a dithered ``blend`` (white
    noise blurred by ``2^(levels-1) neighborhood_size / 2`` pixels and made
    uniform by its ranks, compared with ``blend``) with blend-drawn restarts
    as the 2-D form of the paper's transition function. Compared as it is,
    ``blend`` put one sharp border where it crosses 0.5. The paper
    synthesises on surfaces; its
    feature-based warping and blending tools, which make in-between
    elements, are not implemented: two different exemplars meet here as
    whole elements of each, in proportions that follow ``blend``.

    References
    ----------
    .. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
       progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344`
    .. [2] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       SIGGRAPH 2002. :doi:`10.1145/566654.566634`
    """
    start = time.perf_counter()
    size = as_size(size)
    nb = check_group(neighborhood, Neighborhood, "neighborhood")
    search = check_group(search, Search, "search")
    refuse_augment(search.augment, "synthesize_controlled", "its orientation and magnification fields turn and "
                   "scale the exemplar's own k-coherent copies")
    if search.resolved_candidates("k-coherent") != "k-coherent":
        raise ValueError(f"synthesize_controlled searches k-coherent candidates only; pass "
                         f"search=Search(candidates='k-coherent'), got candidates={search.candidates!r}")
    levels, k, method = nb.levels, check_positive_int(search.resolved_k(1), "k"), check_method(search.method)
    texton_weight = check_positive_float(texton_weight, "texton_weight", allow_zero=True, maximum=1e6)
    blend_weight = check_positive_float(blend_weight, "blend_weight", allow_zero=True, maximum=1e6)
    shape = check_choice(nb.neighborhood_shape, "neighborhood_shape", SHAPES)
    rng = as_rng(rng)
    image, grey = with_channels(as_image(exemplar, "exemplar"))
    if k > image.shape[0] * image.shape[1]:
        raise ValueError(f"k={k} but the exemplar has only {image.shape[0] * image.shape[1]} positions to choose "
                         f"among; pass a small k (1-4)")
    images = [image]
    if exemplar_b is not None:
        image_b, _ = with_channels(as_image(exemplar_b, "exemplar_b"))
        if image_b.shape[-1] != image.shape[-1]:
            raise ValueError(f"exemplar_b has {image_b.shape[-1]} channels but exemplar has {image.shape[-1]}; "
                             f"pass exemplars with the same channels")
        images.append(image_b)
        if blend is None:
            raise ValueError("exemplar_b needs a blend map (0: exemplar, 1: exemplar_b), e.g. "
                             "blend=lambda rows, cols: cols / cols.max()")
    elif blend is not None:
        raise ValueError("blend needs exemplar_b, the texture that blend=1 shows; pass exemplar_b or no blend")
    # pre-flight: the output pyramid, the copies' positions and frames, and a level's parent queries
    n = float(size[0]) * size[1]
    channels = image.shape[-1]
    check_memory(n * 8 * (4 * (channels + 2) + 16 + 9 * (channels + 2)), size)
    theta = _field(orientation, size, "orientation")
    factor = _field(magnification, size, "magnification", positive=True)
    blend_map = _field(blend, size, "blend")
    if blend_map is not None and (blend_map.min() < 0 or blend_map.max() > 1):
        raise ValueError(f"blend must lie in [0, 1] (0: exemplar, 1: exemplar_b), got values in "
                         f"[{blend_map.min():.4g}, {blend_map.max():.4g}]")
    if isinstance(texton_mask, tuple) and len(images) == 2:
        masks = [_as_texton_mask(texton_mask[0], image, "texton_mask[0]"),
                 _as_texton_mask(texton_mask[1], images[1], "texton_mask[1]")]
        if (masks[0] is None) != (masks[1] is None):
            raise ValueError("texton_mask must give a mask for both exemplars or for neither")
    elif isinstance(texton_mask, str) or texton_mask is None or len(images) == 1:
        masks = [_as_texton_mask(texton_mask, img, "texton_mask") for img in images]
    else:
        raise ValueError("with exemplar_b, texton_mask must be 'auto', None or a pair (mask, mask_b)")
    size_n = patch_shape(nb.neighborhood_size, "neighborhood_size")
    auto_parent = is_auto(nb.parent_size)
    psize = default_parent_size(size_n) if auto_parent else patch_shape(nb.parent_size, "parent_size")
    sources = []
    for e, (img, mask) in enumerate(zip(images, masks)):
        name = "exemplar" if e == 0 else "exemplar_b"
        check_fits(img, size_n, name, "neighborhood_size")
        check_fits(img, psize, name, "neighborhood_size" if auto_parent else "parent_size")
        work = _work_image(img.astype(np.float64), mask, texton_weight, float(e) if len(images) == 2 else None,
                           blend_weight)
        pyramid = [np.asarray(level, _WORK_DTYPE) for level in gaussian_pyramid(work, levels)]
        sources.append(Source(pyramid, size_n, psize, None, name, shape=shape))
    cw = sources[0].pyramid[0].shape[-1]
    written = channels + (masks[0] is not None)
    out_shapes = level_shapes(size, levels)
    out_pyr = [np.zeros(s + (cw,), _WORK_DTYPE) for s in out_shapes]
    check_output_levels(sources, size, out_pyr, levels)
    seed = int(rng.integers(2**62))
    target = None
    if blend_map is not None:  # the transition channel of the output: the blend map, dithered; not synthesised
        sigma = 2.0 ** (levels - 1) * max(size_n) / 2.0
        target = gaussian_pyramid(_dithered(blend_map, sigma, np.random.default_rng([seed, 7])), levels,
                                  mode="wrap")
        for lvl in range(levels):
            out_pyr[lvl][..., -1] = np.sqrt(blend_weight) * target[lvl]
    used = resolve(method, max(len(candidate_pixels(s, 0, levels)) for s in sources),
                          int(footprint(size_n, shape).sum()) * cw, profile="default", queries=1)
    info = ControlledSynthesisInfo(method=used)
    state = None
    energies = []
    with Progress(progress, levels, "Zhang et al.") as bar:
        for level in range(levels - 1, -1, -1):
            t0 = time.perf_counter()
            shp = out_shapes[level]
            th = np.zeros(shp) if theta is None else _level_field(theta, level, shp)
            sc = np.ones(shp) if factor is None else _level_field(factor, level, shp)
            a, inverse = _frames(th, sc)
            bl = None if target is None else np.clip(target[level], 0.0, 1.0).reshape(-1)
            grids = _level_grids(sources, level, levels, k, used, seed)
            draw = np.random.default_rng([seed, level])
            state = _initial_state(grids, state, shp, inverse, bl, draw)
            energy, state = _controlled_level(out_pyr[level], out_pyr[level + 1] if level + 1 < levels else None,
                                              grids, sources[0], (a, inverse, bl, sc.reshape(-1)), state, written,
                                              draw)
            energies.append(energy)
            info.level_shapes.append(shp)
            info.stage_seconds[f"level {level}"] = time.perf_counter() - t0
            bar.advance({"level": level})
    info.method = grids.method
    out = np.empty(size + (channels,), np.float64)
    for e, img in enumerate(images):  # the final colour: the exemplars themselves, sampled at the copies
        here = state.exemplar == e
        out.reshape(-1, channels)[here] = _bilinear(img.astype(np.float64), state.pos[here], wrap=False)[0]
    dtype = np.float32 if all(img.dtype == np.float32 for img in images) else np.float64
    out = restore_channels(out.astype(dtype, copy=False), grey)
    if return_info:
        info.positions = state.pos.reshape(size + (2,))
        info.coordinates, info.weights = _coordinate_map(state, [img.shape[:2] for img in images], size)
        info.sources = state.exemplar.reshape(size)
        if masks[0] is not None:
            result = np.empty(size[0] * size[1])
            nearest = np.rint(state.pos).astype(np.intp)
            for e, mask in enumerate(masks):
                here = state.exemplar == e
                result[here] = mask[nearest[here, 0], nearest[here, 1]]
            info.texton_mask = result.reshape(size)
        info.energy = np.asarray(energies)
        info.stage = np.arange(levels)
        info.seconds = time.perf_counter() - start
        return out, info
    return out
