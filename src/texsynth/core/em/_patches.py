"""The exemplar's neighbourhoods and their feature vectors, the objects both EM steps work on.

:class:`ExemplarPatches` holds the searchable neighbourhoods of one exemplar level for one size (their
index is built on first use); :func:`patch_features` turns neighbourhoods into the vectors whose weighted
squared distance is ``ρ_p = ||x_p - z_p||_g^2 + μ ||D x_p - D z_p||_g^2`` (Kwatra et al. 2005, eq. 1 with
the fall-off of Section 3.1 and the gradient term); :func:`distances_at` evaluates ``ρ`` for given pairs.
"""

from __future__ import annotations

import numpy as np

from .._parallel import parallel_for
from .._validate import max_threads
from ..neighborhood import all_patches, extract, gaussian_falloff, patches_within
from ..search import PatchIndex, sq_distances

__all__ = ["ExemplarPatches", "patch_features", "feature_weights", "difference_weights", "output_patches",
           "distances_at", "unwrap_centers", "EPS_RMS", "BLOCK_VALUES"]


# IRLS guard: RMS difference per weighted value below which a neighbourhood
# counts as matched (1e-3 = a quarter of an 8-bit grey level).
EPS_RMS = 1e-3


# E-step: neighbourhood values added into the output at a time (32 MB of float64)
BLOCK_VALUES = 2**22


def difference_weights(pixel_weights):
    """Fall-off weights of the horizontal and vertical pixel differences of a patch."""
    return (pixel_weights[:, 1:] + pixel_weights[:, :-1]) / 2.0, (pixel_weights[1:, :] + pixel_weights[:-1, :]) / 2.0


def patch_features(patches, gradient_weight):
    """Vector of a neighbourhood: its values and, if ``μ > 0``, ``sqrt(μ) D x_p``.

    ``D`` is the forward difference inside the neighbourhood, horizontal then
    vertical, so the weighted squared distance of two feature vectors is
    ``ρ_p = ||x_p - z_p||_g^2 + μ ||D x_p - D z_p||_g^2``.
    """
    n = patches.shape[0]
    flat = patches.reshape(n, -1)
    if gradient_weight == 0:
        return flat
    s = np.sqrt(gradient_weight)
    dx = (patches[:, :, 1:] - patches[:, :, :-1]).reshape(n, -1) * s
    dy = (patches[:, 1:] - patches[:, :-1]).reshape(n, -1) * s
    return np.concatenate([flat, dx, dy], axis=1)


def feature_weights(pixel_weights, channels, gradient_weight):
    """Per-dimension weights matching :func:`patch_features` (fall-off repeated per channel)."""
    rep = lambda a: np.repeat(a.ravel(), channels)  # noqa: E731  (h, w, C) order
    if gradient_weight == 0:
        return rep(pixel_weights)
    gx, gy = difference_weights(pixel_weights)
    return np.concatenate([rep(pixel_weights), rep(gx), rep(gy)])


class ExemplarPatches:
    """The searchable neighbourhoods of one exemplar level for one size.

    The index over their feature vectors is built on first use: the
    PatchMatch M-step never needs it (it compares patches of the images).

    Parameters
    ----------
    image : numpy.ndarray
        ``(h, w, C)`` float exemplar level.
    valid : numpy.ndarray
        ``(h, w)``: 1 where exemplar pixels may be copied; neighbourhoods that touch another pixel are left out.
    size : int
        Neighbourhood width ``w``.
    mu : float
        Weight of the gradient term in the feature vectors (:func:`patch_features`).
    falloff : bool
        Weigh the pixels by a Gaussian fall-off (σ = w/4), else evenly.
    method : str
        The index backend (:class:`texsynth.core.search.PatchIndex`).
    rng : numpy.random.Generator
        For approximate indexes.
    frame : bool
        An animation frame's settings of the search layer (its index searches the stored vectors).
    guided : bool
        The last channels are guides (they may exceed 1 and make more than 4 channels).
    atlas : ExemplarAtlas, optional
        Augmentation (``Search(augment=...)``): the neighbourhoods are those of this
        :class:`~texsynth.core.search.ExemplarAtlas` of ``image`` (pyramid ``level``) with ``valid``, so
        every index, field and coherence works on the flipped and rotated copies too;
        :meth:`to_exemplar` maps their positions back to ``image``'s.
    level : int
        The pyramid level of ``image`` in the ``atlas``'s layout.

    Examples
    --------
    >>> import numpy as np
    >>> patches = ExemplarPatches(np.random.default_rng(0).random((16, 16, 3)), np.ones((16, 16)), 8)
    >>> len(patches), patches.weights.shape
    (81, (192,))
    """

    def __init__(self, image, valid, size, *, gradient_weight=0.0, falloff=True, method="auto", rng=None, frame=False,
                 guided=False, atlas=None, level=0):
        self.original, self.atlas, self.level = image, atlas, level  # the exemplar level itself, and its copies
        if atlas is not None:
            image, valid = atlas.apply(image, level, valid)
        self.image, self.size, self.mu = image, size, gradient_weight
        self.guided = guided  # the last channels are guides (may exceed 1 and make more than 4 channels)
        self.valid = valid
        self.view = all_patches(image, size)  # (Ny, Nx, w, w, C), a view
        ok = patches_within(valid > 0.5, size)
        self.corner = np.argwhere(ok)  # top-left corners of patches free of masked pixels
        self._index = self._feats = None
        self._build = (method, "frame" if frame else "stage" if gradient_weight == 0 else "default", rng, frame)
        if len(self.corner) == 0:
            return
        self.g = gaussian_falloff(size) if falloff else np.ones((size, size))
        self.weights = feature_weights(self.g, image.shape[-1], gradient_weight)
        self.eps2 = EPS_RMS**2 * float(self.weights.sum())
        self.grid = np.full(self.view.shape[:2], -1, dtype=np.int64)  # corner -> neighbourhood index
        self.grid[self.corner[:, 0], self.corner[:, 1]] = np.arange(len(self.corner))

    @property
    def index(self):
        """The :class:`~texsynth.core.search.PatchIndex` over every neighbourhood's features."""
        if self._index is None:
            method, profile, rng, frame = self._build
            # the index searches float32 copies (half the memory, twice the BLAS speed);
            # energies and the M-step's final choice use exact float64 distances
            feats = self.feats if frame else self._all_features()
            # the search layer's measured settings: "frame" (coherent candidates do most of the work),
            # "stage", or the defaults for the gradient energy's longer vectors
            self._index = PatchIndex(feats, weights=self.weights, method=method, profile=profile, rng=rng)
        return self._index

    @property
    def feats(self):
        """The float32 feature vectors of every neighbourhood (animation frames rank candidates on them)."""
        if self._feats is None:
            self._feats = self._all_features()
        return self._feats

    def _all_features(self):
        feats = np.empty((len(self.corner), self.weights.shape[0]), dtype=np.float32)
        step = max(1, 2**24 // max(1, self.weights.shape[0] * 8))
        for a in range(0, len(self.corner), step):
            feats[a : a + step] = patch_features(self.patches(np.arange(a, min(a + step, len(self.corner)))), self.mu)
        return feats

    def __len__(self):
        return len(self.corner)

    def to_exemplar(self, positions):
        """Positions ``(..., 2)`` in :attr:`image` as the exemplar pixels they show (themselves without an atlas)."""
        return positions if self.atlas is None else self.atlas.to_exemplar(positions, self.level)

    @property
    def own(self):
        """Which neighbourhoods lie in the exemplar itself (all of them without an atlas: its first tile)."""
        return np.ones(len(self), bool) if self.atlas is None else self.corner[:, 1] < self.original.shape[1]

    def patches(self, idx):
        c = self.corner[idx]
        return self.view[c[:, 0], c[:, 1]]

    def centers(self, idx):
        return self.corner[idx] + self.size // 2

    def lookup(self, corners, fallback):
        """Index of the neighbourhood with top-left corner ``round(corners)`` (clipped into
        the exemplar); ``fallback`` where that neighbourhood touches masked pixels."""
        r = np.clip(np.rint(corners[:, 0]).astype(np.int64), 0, self.grid.shape[0] - 1)
        c = np.clip(np.rint(corners[:, 1]).astype(np.int64), 0, self.grid.shape[1] - 1)
        idx = self.grid[r, c]
        return np.where(idx >= 0, idx, fallback)


def output_patches(x, centers, patch_size, mode, warp):
    """The output neighbourhoods centred at ``centers``: plain patches, or sampled in the fields' frames."""
    return extract(x, centers, patch_size, mode=mode) if warp is None else warp.extract(x, centers)


def unwrap_centers(centers, shape, patch_size, pad):
    """Centres ``centers`` of a tileable output as centres in its wrap-padded copy (the patch inside it)."""
    lo = patch_size // 2
    hi = np.asarray(shape) + pad - patch_size + patch_size // 2
    out = centers.copy()
    for axis in range(2):
        low = out[:, axis] < lo
        out[low, axis] += shape[axis]
        out[:, axis] = np.minimum(out[:, axis], hi[axis])
    return out


def distances_at(exemplar, x, centers, mode, matches, warp=None):
    """``ρ`` between the output neighbourhoods centred at ``centers`` and the exemplar's ``matches``, in parts."""
    out = np.empty(len(centers))
    step = max(1, BLOCK_VALUES // exemplar.weights.shape[0])

    def part(i):  # each part's own rows of ``out``: the parts may run on several threads
        p = slice(i * step, (i + 1) * step)
        q = patch_features(output_patches(x, centers[p], exemplar.size, mode, warp), exemplar.mu)
        out[p] = sq_distances(q, patch_features(exemplar.patches(matches[p]), exemplar.mu), exemplar.weights)

    parts = -(-len(centers) // step)
    parallel_for(part, parts, max_threads() if parts > 1 else 1)
    return out
