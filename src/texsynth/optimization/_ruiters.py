"""Patch-based texture interpolation (Ruiters, Schnabel and Klein 2010).

Interpolating two textures by blending the images ghosts every feature
(Figure 1a of the paper). Ruiters et al. instead interpolate the *MRF* of
the textures: for every neighbourhood of each texture they find the most
similar neighbourhood of the other one (Section 4.1), align the two patches'
features with a thin-plate-spline warp found by TPS-RPM point matching,
warp each patch part of the way and blend them (Section 4.2), keep the
best-aligned half of these interpolated neighbourhoods, and synthesise a new
texture from that set by texture optimization with irregular patch centres,
a relaxation of the pasted patches, a per-pixel mean-shift mode instead of
the mean, and one Portilla-Simoncelli step per iteration (Sections 4.3-4.5,
Pseudocode 1)::

    TextureInterpolation(I1, I2, F1, F2, alpha)
      add distance channel to I1 and I2
      initialise I with noise
      for each (r, s) in (2, 33), (2, 17), (1, 17):
        N' = InterpolateNeighborhoods(I1, I2, F1, F2, alpha, r, s)
        repeat N times:
          nearest neighbours in N' for irregular centres of I
          relax the neighbourhood centres
          update the pixels of I by mean shift
          one statistical synthesis step

A spatially varying interpolation (a transition strip, or any grey image of
alpha values) uses interpolated neighbourhoods for several alphas with alpha
as an extra channel that the synthesis matches to the user's map
(Section 4.5, Figures 4 and 7).

The interpolated neighbourhoods (Sections 4.1-4.2, ``InterpolateNeighborhoods``)
are :mod:`texsynth.optimization._ruiters_neighborhoods`; this module is the
synthesis from them (Sections 4.3-4.5) and the options of the whole method,
in groups: :class:`InterpolationSchedule`, :class:`Correspondences`,
:class:`NeighborhoodSet`, :class:`InterpolationUpdate`, :class:`VaryingAlpha`
and :class:`~texsynth.core.search.Search`.

References
----------
.. [1] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
   interpolation", Computer Graphics Forum 29(4) (EGSR 2010), 1421-1429.
   :doi:`10.1111/j.1467-8659.2010.01739.x`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import (as_array, as_float_array, as_image, as_rng, as_size, check_bool, check_group,
                              check_in_range, check_memory, check_positive_float, check_positive_int,
                              restore_channels)
from ..core.search import PatchIndex, Search, point_tree
from ..core.neighborhood import accumulate, extract, gaussian_falloff, grid_centers
from ..core.em import expectation_maximization
from ..statistical import interpolate_statistics, ps_statistics, ps_step
from ._ruiters_neighborhoods import (Correspondences, NeighborhoodSet, check_inputs, downsample, edge_feature_map,
                                     interpolate_neighborhoods, interpolated_set, ridge_feature_map, stage_textures)

__all__ = [
    "interpolate_textures",
    "InterpolationSchedule",
    "InterpolationUpdate",
    "VaryingAlpha",
    "InterpolationInfo",
    # Sections 4.1-4.2, from texsynth.optimization._ruiters_neighborhoods
    "interpolate_neighborhoods",
    "Correspondences",
    "NeighborhoodSet",
    "edge_feature_map",
    "ridge_feature_map",
    "transition_alpha_map",
    "linear_blend",
]

_EPS = 1e-3  # ε² of the IRLS weights (texsynth.core.em.irls_weights): finite for perfect matches


@dataclass
class InterpolationInfo:
    """Extra results of :func:`interpolate_textures`.

    Attributes
    ----------
    energy : numpy.ndarray
        Mean distance of the pasted neighbourhoods to the synthesized image:
        per (r, s) stage, after the stage's first search, then after each
        iteration; all stages in order.
    stage : numpy.ndarray of int
        The stage (index into ``stages``) of each energy value.
    pairs : list of int
        Corresponding neighbourhood pairs per (r, s) stage.
    kept : list of int
        Interpolated neighbourhoods kept in ``N'`` per stage (all alphas).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time per step of the method: ``"correspondences"``,
        ``"tps_rpm"``, ``"warping"`` (warp, blend, similarity filter),
        ``"synthesis"`` (searches, relaxation, mean shift) and
        ``"statistics"`` (Portilla-Simoncelli).
    colour_only : bool
        True when the feature maps were empty and the warps fell back to
        the identity.
    """

    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stage: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    pairs: list = field(default_factory=list)
    kept: list = field(default_factory=list)
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    colour_only: bool = False

    def add(self, key, t0):
        self.stage_seconds[key] = self.stage_seconds.get(key, 0.0) + time.perf_counter() - t0


# --------------------------------------------------------------------------- inputs
def transition_alpha_map(size, *, start=0.0, stop=1.0):
    """A left-to-right ramp of alpha values for a transition strip (Figure 4).

    >>> transition_alpha_map((2, 5))[0].tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    h, w = as_size(size, "size")
    start = check_in_range(start, "start", 0.0, 1.0)
    stop = check_in_range(stop, "stop", 0.0, 1.0)
    check_memory(float(h) * w * 8, (h, w), what="the map")
    return np.broadcast_to(np.linspace(start, stop, w), (h, w)).copy()


def linear_blend(a, b, alpha):
    """Plain cross-fade ``(1 - alpha) a + alpha b`` (Figure 1a: ghosted features).

    ``alpha`` is a number in [0, 1] or an ``(H, W)`` map of them.

    >>> linear_blend(np.zeros((2, 2)), np.ones((2, 2)), 0.25).tolist()
    [[0.25, 0.25], [0.25, 0.25]]
    """
    a = as_image(a, "a")
    b = as_image(b, "b")
    if a.shape != b.shape:
        raise ValueError(f"a {a.shape} and b {b.shape} must have the same shape for a linear blend")
    if np.ndim(alpha) == 0:
        alpha = np.float64(check_in_range(alpha, "alpha", 0.0, 1.0))
    else:
        alpha = as_float_array(as_array(alpha, "alpha"), "alpha")  # a map: finite values in [0, 1]
        if alpha.shape != a.shape[:2]:
            raise ValueError(f"alpha map has shape {alpha.shape} but the images are {a.shape[:2]}; pass an "
                             f"(H, W) map of the images' size or one number")
        if a.ndim == 3:
            alpha = alpha[..., None]
    return (1.0 - alpha) * a + alpha * b


# --------------------------------------------------------------------------- option groups
@dataclass(frozen=True)
class InterpolationSchedule:
    """The stages of an interpolation and the iterations of each (Ruiters et al. 2010, Pseudocode 1, Section 4.4).

    Examples
    --------
    >>> import texsynth
    >>> schedule = texsynth.InterpolationSchedule(stages=((1, 9),))  # one stage, full resolution, 9x9
    >>> schedule.max_iterations
    10

    An option group of :func:`~texsynth.interpolate_textures`
    (``schedule=InterpolationSchedule(...)``); on the command line its fields
    are flags (``--stages``, ``--max-iterations``, ...).

    Parameters
    ----------
    stages : sequence of (int, int)
        Coarse-to-fine ``(r, s)``: downsampling factor and neighbourhood size;
        the paper's default ``(2, 33), (2, 17), (1, 17)``, with ``(2, 49)``
        first for large regular features.
    max_iterations : int
        Synthesis iterations per stage (10 in the paper).
    tolerance : float or None
        Kwatra et al.'s stopping rule: a stage ends early at the first
        iteration whose energy (``info.energy``) is above ``(1 -
        tolerance)`` times the previous one; default 0.0, stop when the
        energy stops falling. ``None`` always runs ``max_iterations`` (the
        paper's fixed N = 10).
    relative_grid_spacing : float
        Cell size of the irregular-centre grid as a fraction of ``s``
        (Kwatra et al.'s ``w/4``).
    candidate_stride : int
        Spacing of the candidate centres tried inside each cell; 1 tries
        every pixel as the paper does, 2 (default) a quarter of them.
    """

    stages: tuple = ((2, 33), (2, 17), (1, 17))
    max_iterations: int = 10
    tolerance: object = 0.0
    relative_grid_spacing: float = 0.25
    candidate_stride: int = 2


@dataclass(frozen=True)
class InterpolationUpdate:
    """How each iteration of an interpolation updates the pixels (Ruiters et al. 2010, Sections 4.4-4.5).

    Examples
    --------
    >>> import texsynth
    >>> update = texsynth.InterpolationUpdate(statistics_step=False)  # no Portilla-Simoncelli step
    >>> update.mean_shift_iterations
    3

    The steps of an iteration besides the search: the relaxation of the
    pasted neighbourhoods, the per-pixel mean shift that turns them into
    pixels, and the Portilla-Simoncelli step. An option group of
    :func:`~texsynth.interpolate_textures` (``update=InterpolationUpdate(...)``);
    on the command line its fields are flags (``--relaxation-radius``, ...).

    Parameters
    ----------
    relaxation_radius : int
        Search radius of the relaxation step, in pixels (0: no relaxation).
    spring_weight : float
        Weight of the spring term keeping a centre's displacement near its
        neighbours' (per squared pixel, against mean squared colour error),
        at most 1e6.
    mean_shift_bandwidth : float
        Colour bandwidth of the per-pixel mean shift (Gaussian kernel on
        the colour distance, colours in [0, 1]; at most 100). Default 0.03: with 0.1 the
        kernel spans the disagreement of the overlapping patches and the
        mode is their mean (Notes of :func:`~texsynth.interpolate_textures`).
    mean_shift_iterations : int
        Mean-shift steps per update (0 keeps the IRLS-weighted mean).
    statistics_step : bool
        Perform one Portilla-Simoncelli step with linearly interpolated
        statistics per iteration (Section 4.5); in the last stage it is
        weighted by ``2 min(alpha, 1 - alpha)`` (Notes of
        :func:`~texsynth.interpolate_textures`).
    """

    relaxation_radius: int = 2
    spring_weight: float = 0.002
    mean_shift_bandwidth: float = 0.03
    mean_shift_iterations: int = 3
    statistics_step: bool = True


@dataclass(frozen=True)
class VaryingAlpha:
    """How a spatially varying interpolation is synthesised (Ruiters et al. 2010, Section 4.5).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.VaryingAlpha(alpha_steps=5)
    VaryingAlpha(alpha_steps=5, alpha_weight=4.0, statistics_bands=5)

    Used only when ``alpha`` is a distribution map (a transition strip,
    Figure 4, or any grey image, Figure 7). An option group of
    :func:`~texsynth.interpolate_textures` (``varying=VaryingAlpha(...)``);
    on the command line its fields are flags (``--alpha-steps``, ...).

    Parameters
    ----------
    alpha_steps : int
        Alphas (equidistant) with interpolated patches for a distribution
        map (20 in the paper).
    alpha_weight : float
        Weight of the alpha channel in the synthesis search: high values
        follow the distribution map exactly, low ones favour smooth
        transitions. At most 1e6.
    statistics_bands : int
        Alphas (equidistant) with their own statistical synthesis step for a
        distribution map, each run "only on the relevant parts of the image"
        (the pixels nearest to its alpha); the results are blended by alpha
        (Section 4.5).
    """

    alpha_steps: int = 20
    alpha_weight: float = 4.0
    statistics_bands: int = 5


# --------------------------------------------------------------------------- Sections 4.3-4.4
class _PatchSet:
    """The searchable set N' (flattened patches) with per-channel weights."""

    def __init__(self, patches, channel_weights, method, rng):
        self.patches = patches
        self.size = patches.shape[1]
        self.weights = np.tile(channel_weights, self.size * self.size)
        self.index = PatchIndex(patches.reshape(len(patches), -1), weights=self.weights, method=method, rng=rng)

    def query(self, x, centers):
        # float32 before the copy of the (many, overlapping) candidate neighbourhoods: half the bytes
        q = extract(x.astype(np.float32), centers, self.size, mode="wrap").reshape(len(centers), -1)
        idx, d2 = self.index.query(q, k=1)
        return idx[:, 0], d2[:, 0] / self.weights.sum()


def _bootstrap(patches, shape, spacing, rng):
    """Initial image: random neighbourhoods of ``N'`` on the regular grid, each pixel from its nearest centre.

    The paper initialises with noise; the nearest neighbourhoods of noise (or
    of an average of many random patches) are the flattest ones, and the
    synthesis collapses onto them (horizontal streaks, lost elements). A
    random tiling of ``N'`` (Kwatra et al.'s bootstrap, sharp fall-off
    ``sigma = spacing / 4``) is noise at the scale of the grid cells but keeps
    the patches' contrast.
    """
    centres = grid_centers(shape, patches.shape[1], spacing, mode="wrap")
    z = patches[rng.integers(0, len(patches), len(centres))].astype(np.float64)
    x, _ = accumulate(z, centres, shape, pixel_weights=gaussian_falloff(patches.shape[1], sigma=spacing / 4.0),
                      mode="wrap")
    return x


def _irregular_centres(x, nset, spacing, candidate_stride):
    """Within each cell of the regular grid, the centre whose best match has the lowest error (4.4)."""
    h, w = x.shape[:2]
    gy, gx = np.arange(0, h, spacing), np.arange(0, w, spacing)
    off = np.arange(0, spacing, candidate_stride)
    cell_r, cell_c, dr, dc = np.meshgrid(gy, gx, off, off, indexing="ij")
    cand = np.stack([(cell_r + dr) % h, (cell_c + dc) % w], -1).reshape(len(gy) * len(gx), -1, 2)
    idx, err = nset.query(x, cand.reshape(-1, 2))
    idx, err = idx.reshape(cand.shape[:2]), err.reshape(cand.shape[:2])
    best = np.argmin(err, axis=1)
    rows = np.arange(len(cand))
    return cand[rows, best], idx[rows, best], err[rows, best]


def _grid_neighbours(original, shape, count=8):
    """Indices of the ``count`` nearest other centres (periodic distance), shape (n, count)."""
    n = len(original)
    count = min(count, n - 1)
    if count < 1:
        return np.zeros((n, 0), int)
    pts = original.astype(np.float64)
    _, nb = point_tree(pts, period=shape).query(pts, k=count + 1)
    others = nb != np.arange(n)[:, None]
    others[others.sum(1) > count, -1] = False  # a duplicate position returned before the centre itself
    return nb[others].reshape(n, count)


def _relax(centres, z, weights, shape, radius, spring, max_sweeps):
    """Shift the pasted neighbourhoods to agree with their overlapping neighbours (Section 4.4).

    For every centre the shift within ``radius`` minimising the squared
    difference between its patch and the leave-one-out average of all other
    patches, plus ``spring * |displacement - mean displacement of its grid
    neighbours|^2`` (the spring term); repeated until no centre moves.

    Implementation: the weighted sums of all patches are read once per sweep
    in a window of ``s + 2 radius`` around each centre (every candidate shift
    is a slice of it), the centre's own contribution is subtracted in that
    frame, and the arithmetic is float32. After the first sweep only the
    centres whose window or grid neighbours saw a move are re-evaluated: the
    others' costs are unchanged, so they stay where they are (the result is
    that of re-evaluating every centre).
    """
    n, s, c = len(centres), z.shape[1], z.shape[-1]
    original = centres.copy()
    offsets = np.array([(dr, dc) for dr in range(-radius, radius + 1) for dc in range(-radius, radius + 1)])
    stay = len(offsets) // 2  # (0, 0)
    big = s + 2 * radius
    nbrs = _grid_neighbours(original, shape)
    z32 = z.astype(np.float32)
    w32 = weights.astype(np.float32)
    # the centre's own weighted patch and weight, zero-padded to the window frame
    own = np.zeros((n, big, big, c + 1), np.float32)
    own[:, radius : radius + s, radius : radius + s, :c] = z32 * w32[:, None, None, None]
    own[:, radius : radius + s, radius : radius + s, c] = w32[:, None, None]
    cost = np.zeros((n, len(offsets)))
    dirty = np.ones(n, bool)
    for _ in range(max_sweeps):
        total, wsum = accumulate(z, centres, shape, patch_weights=weights, mode="wrap")
        sums = np.concatenate([total * wsum[..., None], wsum[..., None]], -1).astype(np.float32)
        todo = np.flatnonzero(dirty)
        # wrap-pad first: the window may be larger than a small (coarse-level) image
        sums = np.pad(sums, ((big // 2, big - 1 - big // 2),) * 2 + ((0, 0),), mode="wrap")
        win = extract(sums, centres[todo] + big // 2, big, mode="valid")
        win -= own[todo]  # leave-one-out: everything but the centre's own patch
        zt = z32[todo]
        floor = 1e-4 * w32[todo, None, None, None]  # float32 rounding of the subtraction, far below any real overlap
        disp = centres - original
        mean_nbr = disp[nbrs].mean(1) if nbrs.shape[1] else np.zeros_like(disp)
        covered = bool(np.all(win[..., c:] > floor))  # the usual case: others overlap every pixel
        for j, (dr, dc) in enumerate(offsets):
            other = win[:, radius + dr : radius + dr + s, radius + dc : radius + dc + s]
            if covered:
                diff = other[..., :c] / other[..., c:] - zt
            else:  # a pixel only this patch covers does not count
                ok = other[..., c:] > floor
                diff = np.where(ok, other[..., :c] / np.where(ok, other[..., c:], 1.0), zt) - zt
            data = np.einsum("nijk,nijk->n", diff, diff) / z[0].size
            cost[todo, j] = data + spring * ((disp[todo] + (dr, dc) - mean_nbr[todo]) ** 2).sum(1)
        best = np.argmin(cost, axis=1)
        moved = cost[np.arange(n), best] < cost[:, stay] - 1e-12
        if not moved.any():
            break
        before = centres
        centres = (centres + offsets[best] * moved[:, None]) % np.array(shape)
        # re-evaluate the centres whose window reaches a moved patch (old or new place) or whose
        # grid neighbours moved (spring term)
        touched = np.zeros(shape, bool)
        touched[before[moved, 0], before[moved, 1]] = True
        touched[centres[moved, 0], centres[moved, 1]] = True
        touched = ndimage.maximum_filter(touched, size=2 * (s + radius) + 1, mode="wrap")
        dirty = touched[centres[:, 0], centres[:, 1]] | moved[nbrs].any(1)
    return centres


def _mean_shift_update(z, centres, weights, shape, bandwidth, iterations, n_colour, chunk=4096):
    """Per-pixel mode of the overlapping patch values (mean shift, Kopf et al. 2007).

    The values pasted on each pixel, weighted by the patch's IRLS weight and
    Kwatra et al.'s Gaussian fall-off, are gathered per pixel; the mean shift
    (Gaussian kernel of width ``bandwidth`` on the colour channels) starts at
    the value of highest kernel density among them and climbs to its mode.
    Started at the weighted mean instead, it climbed to the mode nearest the
    mean, which for two disagreeing groups of patches is the mean itself (a
    blur): see :func:`interpolate_textures`. ``iterations = 0`` returns the
    weighted mean (the Kwatra E-step). Pixels are processed ``chunk`` at a time.
    """
    g = gaussian_falloff(z.shape[1])  # Kwatra et al.'s Gaussian fall-off of each neighbourhood
    if iterations == 0:
        return accumulate(z, centres, shape, patch_weights=weights, pixel_weights=g, mode="wrap")[0]
    s, c = z.shape[1], z.shape[-1]
    h, w = shape
    rows = (centres[:, :1] - s // 2 + np.arange(s)) % h
    cols = (centres[:, 1:] - s // 2 + np.arange(s)) % w
    pixel = (rows[:, :, None] * w + cols[:, None, :]).ravel()
    order = np.argsort(pixel, kind="stable")
    pixel = pixel[order]
    count = np.bincount(pixel, minlength=h * w)
    slot = np.arange(len(pixel)) - (np.cumsum(count) - count)[pixel]
    values = np.zeros((h * w, count.max(), c), np.float32)  # the values pasted on each pixel, zero-padded
    wts = np.zeros((h * w, count.max()), np.float32)
    values[pixel, slot] = z.reshape(-1, c)[order]
    wts[pixel, slot] = (weights[:, None, None] * g).ravel()[order]
    scale = -0.5 / bandwidth**2
    x = np.zeros((h * w, c), np.float32)
    for lo in range(0, h * w, chunk):
        v, wt = values[lo : lo + chunk], wts[lo : lo + chunk]
        col = v[..., :n_colour]
        sq = (col**2).sum(-1)
        d2 = np.maximum(sq[:, :, None] + sq[:, None, :] - 2.0 * np.einsum("pkc,pjc->pkj", col, col), 0.0)
        density = np.einsum("pkj,pj->pk", np.exp(scale * d2), wt)
        density[wt == 0] = -1.0  # padding
        mode = v[np.arange(len(v)), density.argmax(1)]
        for _ in range(iterations):
            k = wt * np.exp(scale * ((col - mode[:, None, :n_colour]) ** 2).sum(-1))
            total = k.sum(1)[:, None]
            mode = np.where(total > 0, np.einsum("pk,pkc->pc", k, v) / np.maximum(total, 1e-30), mode)
        x[lo : lo + chunk] = mode
    return x.reshape(h, w, c).astype(np.float64)


# --------------------------------------------------------------------------- Section 4.5
class _Statistics:
    """Interpolated Portilla-Simoncelli statistics per alpha band at one resolution."""

    def __init__(self, c1, c2, alphas, shape):
        scales = int(min(4, np.floor(np.log2(min(min(shape), *c1.shape[:2], *c2.shape[:2]))) - 2))
        self.ok = scales >= 1
        if not self.ok:
            return
        s1 = ps_statistics(c1, scales=scales)
        s2 = ps_statistics(c2, scales=scales, color_basis=s1.color_basis)
        self.alphas = np.asarray(alphas, dtype=float)
        self.stats = [interpolate_statistics(s1, s2, float(al)) for al in self.alphas]

    def step(self, colour, alpha_map):
        if not self.ok:
            return colour
        colour = np.clip(colour, 0.0, 1.0)
        if len(self.stats) == 1:
            return ps_step(colour, self.stats[0])
        # Section 4.5: "the statistical synthesis independently for several equidistantly sampled
        # values of alpha, each time only on the relevant parts of the image according to the
        # distribution map. Then, the results are blended using alpha as blending weight." Band k
        # measures and imposes its statistics on the pixels nearest to its alpha (tent weight
        # w_k > 1/2) and its change is blended in with w_k (ps_step's fractional mask)
        change = np.zeros_like(colour)
        total = np.zeros(colour.shape[:2])
        spacing = self.alphas[1] - self.alphas[0]
        for al, st in zip(self.alphas, self.stats):
            w = np.maximum(0.0, 1.0 - np.abs(alpha_map - al) / spacing)
            if not np.any(w > 0.5):
                continue
            try:
                projected = ps_step(colour, st, mask=w)
            except ValueError:  # a region too thin for the autocorrelation window (small coarse images)
                projected = colour + w[..., None] * (ps_step(colour, st) - colour)  # the whole image's step
            change += projected - colour
            total += w
        return colour + change / np.maximum(total, 1e-12)[..., None]


# --------------------------------------------------------------------------- public
def interpolate_textures(a, b, alpha, *, size=None, features=None, schedule=InterpolationSchedule(),
                         correspondences=Correspondences(), neighborhood_set=NeighborhoodSet(),
                         update=InterpolationUpdate(), varying=VaryingAlpha(), search=Search(), rng=None,
                         progress=False, return_info=False):
    """Interpolate two textures by warping and blending their neighbourhoods (Ruiters et al. 2010).

    Examples
    --------
    >>> import texsynth
    >>> a, b = texsynth.data.load("bumpy")[:24, :24], texsynth.data.load("bread")[:24, :24]
    >>> schedule = texsynth.InterpolationSchedule(stages=((1, 9),), max_iterations=1)
    >>> out = texsynth.interpolate_textures(a, b, 0.5, schedule=schedule, rng=0,
    ...                                     neighborhood_set=texsynth.NeighborhoodSet(max_neighborhoods=32))
    >>> out.shape
    (24, 24, 3)

    Pairs every neighbourhood of ``a`` with its most similar one in ``b``
    (and back), aligns each pair by a thin-plate-spline warp (TPS-RPM),
    blends the warped pairs at ``alpha`` into a set ``N'`` of interpolated
    neighbourhoods, and synthesises the output from ``N'`` by texture
    optimization with a Portilla-Simoncelli step per iteration [1]_.

    Parameters
    ----------
    a, b : array_like
        The textures ``I1`` and ``I2`` (grey or colour, same channels), at
        least as large as the largest neighbourhood at its resolution.
    alpha : float or array_like
        The interpolation amount in [0, 1] (0 gives ``a``, 1 gives ``b``), or
        a distribution map ``(H, W)`` of alpha values for a spatially varying
        texture (a transition strip, Figure 4, or any grey image, Figure 7);
        the output then has the map's size.
    size : int or (int, int), optional
        Output size for a scalar ``alpha``; default the size of ``a``.
    features : (array_like, array_like), optional
        Binary feature maps ``(F1, F2)`` of the two textures' sizes (the
        paper uses hand-made maps of edges, ridges, cracks). Default: the
        centre lines of ridges and valleys (:func:`ridge_feature_map`),
        which mark mortar joints and grooves as single lines; Canny edges
        (:func:`edge_feature_map`, the paper's "not very satisfactory"
        detector) are the alternative. An empty map falls back to
        colour-only correspondences with identity warps (with a warning).
    schedule : InterpolationSchedule
        The coarse-to-fine ``stages`` ``(r, s)`` (the paper's ``(2, 33),
        (2, 17), (1, 17)``), ``max_iterations`` per stage (10), when a stage
        stops early, and the irregular-centre grid
        (:class:`InterpolationSchedule`).
    correspondences : Correspondences
        How corresponding neighbourhoods are found (Section 4.1), aligned by
        TPS-RPM and compared (Section 4.2): ``n_correspondences``,
        ``distance_weight``, ``feature_weight``, ``max_feature_points``,
        ``rpm_options`` (:class:`Correspondences`).
    neighborhood_set : NeighborhoodSet
        Which interpolated neighbourhoods make up ``N'`` and how many:
        ``keep_fraction`` (the paper's half), ``max_neighborhoods``,
        ``max_set_size`` (:class:`NeighborhoodSet`).
    update : InterpolationUpdate
        The steps of an iteration besides the search: relaxation, per-pixel
        mean shift and the Portilla-Simoncelli step (Sections 4.4-4.5,
        :class:`InterpolationUpdate`).
    varying : VaryingAlpha
        How a distribution map is synthesised (``alpha_steps``,
        ``alpha_weight``, ``statistics_bands``; Section 4.5,
        :class:`VaryingAlpha`); used only when ``alpha`` is a map.
    search : texsynth.core.search.Search
        ``method``: the search backend (:mod:`texsynth.core.search`) of the
        correspondences (``"auto"``: exact up to 20000 neighbourhoods of the
        other texture, kd-tree above) and of the synthesis in ``N'``
        (``"auto"``: exact up to a few thousand neighbourhoods, kd-tree
        above). ``candidates``: how the correspondences (Section 4.1) are
        searched: ``"all"`` (default, the paper; ``"auto"`` too), every
        neighbourhood of the other texture through ``method``, or
        ``"k-coherent"``: k-coherent search (Ashikhmin 2001; Tong et al.
        2002, :doi:`10.1145/566654.566634`, not at hand): the capped
        neighbourhoods lie on a grid, so a grid neighbour's match shifted by
        the offset to it is a candidate, offered with its k-coherence set of
        ``k`` (``"auto"``: 4; :func:`~texsynth.core.search.coherence_sets`),
        in PatchMatch's scan order, 3 iterations after one PatchMatch
        iteration from random matches (which gives the search something to
        continue); the ``n_correspondences`` nearest found are kept.
        Approximate, and cheaper where the other texture has many
        neighbourhoods (see docs/methods/ruiters.md).
    rng : None, int or numpy.random.Generator
        Noise initialisation, feature subsampling, search indices.
    progress : bool or callable
        ``True`` shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return an :class:`InterpolationInfo`.

    Returns
    -------
    image : numpy.ndarray
        The interpolated texture, grey or colour like ``a``.
    info : InterpolationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        For ``alpha`` outside [0, 1] (or a map with such values or not 2-D),
        feature maps of another size than their textures, textures smaller
        than a stage's neighbourhood, or other out-of-range options.
    TypeError
        For an option group of the wrong type (``schedule={...}``).

    Notes
    -----

    Correspondences use ``||W_C (N_i^(1) - N_j^(2))||_2`` over colour and
    distance channels (Section 4.1), searched in both directions through
    :mod:`texsynth.core.search` (profile ``"correspondence"``: exact up to
    20000 neighbourhoods of the other texture, the paper's PCA + kd-tree
    above); the synthesis searches ``N'`` with the default profile. Each pair
    is colour-adjusted to the alpha-interpolated means and deviations,
    TPS-RPM (eq. 1) gives ``theta_12`` and ``theta_21`` from the same
    correspondences, and

    .. math:: N'(x) = (1 - \\alpha) N_1(\\theta'_{21}(x)) + \\alpha N_2(\\theta'_{12}(x)),
              \\quad \\theta'_{12} = (1-\\alpha)\\theta_{12} + \\alpha I,\\;
              \\theta'_{21} = \\alpha\\theta_{21} + (1-\\alpha) I.

    The synthesis per iteration: irregular centres (best centre per grid
    cell), relaxation with a spring term, IRLS weights ``(rho + eps)^((r-2)/2)``
    with ``r = 0.8`` (Kwatra et al. 2005) and a per-pixel mean-shift mode
    (Kopf et al. 2007) started at the densest pasted value, then one
    Portilla-Simoncelli step with linearly interpolated statistics.

    Departures for speed, all options: TPS-RPM anneals faster than the
    authors' schedule (``rpm_options``), feature points and neighbourhoods
    are capped, candidate centres use a stride of 2, and a stage stops
    when its energy stops falling (``tolerance``). The distance channel is
    synthesized with the colour (so the output's features are matched too)
    and dropped at the end.

    Departures for quality, each measured on ``docs/methods/ruiters.md``:

    - the synthesis starts from a random tiling of ``N'`` rather than noise
      (the nearest neighbourhoods of noise are the flattest ones, and the
      result collapsed onto horizontal streaks);
    - the distance channel is scaled to the colours' deviation (unscaled it
      dominated the search and the colours averaged to grey);
    - each kept pair is reused at shifted positions (otherwise ``N'`` held
      one position in ``stride**2`` and elements broke up);
    - the keep fraction depends on alpha (above);
    - the overlapping patches carry Kwatra et al.'s Gaussian fall-off;
    - the Portilla-Simoncelli step comes *before* the patch step of each
      iteration (after it, as listed in Pseudocode 1, its colour fringes and
      broken lines stayed in the output), and in the last (r, s) stage it is
      weighted by ``2 min(alpha, 1 - alpha)`` (per pixel for a map): it
      restores the detail that blending removes, and at alpha = 0 and 1
      nothing is blended, so there the last stage is Kwatra et al.'s texture
      optimization on the input's own neighbourhoods while the coarser
      stages keep the full step, which prevents a collapse onto flat
      patches;
    - the affine part of TPS-RPM is regularised towards the identity with
      ``affine_lambda_init = 10`` instead of Chui and Rangarajan's 0.01: a
      patch's feature points lie along a few mortar lines or cracks, which
      leave the affine part free across them, and the warps squeezed patches
      across one axis into smeared swirls;
    - against blur: the warps sample with cubic splines (bilinear sampling at
      a warp's fractional positions is a blur); the blend of each pair keeps
      the contrast the colour adjustment intended (the average of two partly
      uncorrelated patches has less: its deviation from the patch mean is
      rescaled to ``(1 - a)`` times that of the warped ``N1`` plus ``a``
      times that of ``N2``, with a gain between 1 and ``1 / sqrt((1 - a)^2 +
      a^2)``, the observation behind Heitz and Neyret's variance-preserving
      blending); and the per-pixel mean shift starts at the densest of the
      pasted values with a bandwidth of 0.03 rather than at their mean with
      0.1, where the "mode" of disagreeing patches was their mean.

    The output is periodic.

    References
    ----------
    .. [1] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
       interpolation", EGSR 2010. :doi:`10.1111/j.1467-8659.2010.01739.x`
    .. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture
       optimization for example-based synthesis", SIGGRAPH 2005.
       :doi:`10.1145/1073204.1073263`
    .. [3] J. Kopf et al., "Solid texture synthesis from 2D exemplars",
       SIGGRAPH 2007. :doi:`10.1145/1276377.1276380`
    .. [4] H. Chui and A. Rangarajan, "A new algorithm for non-rigid point
       matching", CVPR 2000. :doi:`10.1109/CVPR.2000.854733`
    .. [5] J. Portilla and E. P. Simoncelli, "A parametric texture model
       based on joint statistics of complex wavelet coefficients", IJCV
       40(1), 2000. :doi:`10.1023/A:1026553619983`
    .. [6] E. Heitz and F. Neyret, "High-performance by-example noise using
       a histogram-preserving blending operator", HPG 2018.
       :doi:`10.1145/3233304`
    """
    t_start = time.perf_counter()
    info = InterpolationInfo()
    stage_energies = []
    p = check_inputs(a, b, features, correspondences, neighborhood_set, search)
    schedule = check_group(schedule, InterpolationSchedule, "schedule")
    update = check_group(update, InterpolationUpdate, "update")
    varying = check_group(varying, VaryingAlpha, "varying")
    info.colour_only = p.colour_only
    rng = as_rng(rng)
    alpha_map = None
    if np.ndim(alpha) == 0:
        alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
        out_shape = p.a.shape[:2] if size is None else as_size(size)
        alphas = [alpha]
    else:
        alpha_map = np.asarray(alpha, dtype=np.float64)
        if alpha_map.ndim != 2:
            raise ValueError(f"alpha must be a number or a 2-D distribution map (H, W), got shape {alpha_map.shape}")
        if size is not None and as_size(size) != alpha_map.shape:
            raise ValueError(f"alpha map has shape {alpha_map.shape} but size is {as_size(size)}; they must agree")
        if not np.all(np.isfinite(alpha_map)) or alpha_map.min() < 0 or alpha_map.max() > 1:
            raise ValueError(
                f"alpha map values must lie in [0, 1], got [{np.nanmin(alpha_map):.3g}, {np.nanmax(alpha_map):.3g}]"
            )
        out_shape = alpha_map.shape
        alphas = list(np.linspace(0.0, 1.0, check_positive_int(varying.alpha_steps, "alpha_steps", 2)))
    # the per-pixel mean shift gathers the ~(1/relative_grid_spacing)^2 values pasted on every pixel
    # (float32, colour + distance + alpha channels), the relaxation a few image-sized sums
    check_memory(float(out_shape[0]) * out_shape[1] * (p.a.shape[-1] + 2) * 200, tuple(out_shape))
    stages = _check_stages(schedule.stages)
    max_iterations = check_positive_int(schedule.max_iterations, "max_iterations", maximum=MAX_ITERATIONS)
    # weights above 1e6 make their term all that counts, and far beyond they overflow float32
    alpha_weight = check_positive_float(varying.alpha_weight, "alpha_weight", allow_zero=True, maximum=1e6)
    bands = check_positive_int(varying.statistics_bands, "statistics_bands", 2)
    relative_grid_spacing = check_in_range(schedule.relative_grid_spacing, "relative_grid_spacing", 0.0, 1.0,
                                           low_open=True)
    candidate_stride = check_positive_int(schedule.candidate_stride, "candidate_stride")
    relaxation_radius = check_positive_int(update.relaxation_radius, "relaxation_radius", 0)
    if relaxation_radius >= min(s for _, s in stages):
        raise ValueError(f"relaxation_radius={relaxation_radius} lets a neighbourhood move past its own size; pass "
                         f"less than the smallest stage's neighbourhood size {min(s for _, s in stages)}")
    spring_weight = check_positive_float(update.spring_weight, "spring_weight", allow_zero=True, maximum=1e6)
    # colours lie in [0, 1]: a bandwidth of 100 already averages every colour
    bandwidth = check_positive_float(update.mean_shift_bandwidth, "mean_shift_bandwidth", maximum=100.0)
    ms_iterations = check_positive_int(update.mean_shift_iterations, "mean_shift_iterations", 0, MAX_ITERATIONS)
    tolerance = schedule.tolerance
    if tolerance is not None:
        tolerance = check_in_range(tolerance, "tolerance", 0.0, 1.0)
    n_colour = p.a.shape[-1]
    channel_weights = p.channel_weights
    if alpha_map is not None:
        channel_weights = np.append(channel_weights, alpha_weight)
    with Progress(progress, len(stages) * max_iterations, "interpolate") as bar:
        x = None
        for stage, (r, s) in enumerate(stages):
            shape = (max(1, out_shape[0] // r), max(1, out_shape[1] // r))
            if min(shape) < s:
                raise ValueError(f"output {out_shape} at resolution 1/{r} is smaller than the neighbourhood {s}; "
                                 f"pass a larger size or smaller stages")
            t1, t2 = stage_textures(p, r, s)
            patches = interpolated_set(t1, t2, s, alphas, p, rng, info)
            info.kept.append(len(patches))
            t0 = time.perf_counter()
            nset = _PatchSet(patches, channel_weights, p.method, rng)
            amap = None if alpha_map is None else ndimage.zoom(alpha_map, (shape[0] / out_shape[0], shape[1] / out_shape[1]),
                                                               order=1)[: shape[0], : shape[1]]
            spacing = max(1, int(round(relative_grid_spacing * s)))
            if x is None:
                x = _bootstrap(patches[..., : n_colour + 1], shape, spacing, rng)
            elif x.shape[:2] != shape:
                x = ndimage.zoom(x, (shape[0] / x.shape[0], shape[1] / x.shape[1], 1), order=1)
            if amap is not None:
                x = np.concatenate([x[..., : n_colour + 1], amap[..., None]], -1)
            info.add("synthesis", t0)
            t0 = time.perf_counter()
            stats = _Statistics(downsample(p.a, r), downsample(p.b, r),
                                alphas if alpha_map is None else np.linspace(0, 1, bands), shape) if check_bool(
                    update.statistics_step, "statistics_step") else None
            info.add("statistics", t0)
            ps_weight = _statistics_weight(alphas[0] if amap is None else amap[..., None], stage == len(stages) - 1)

            def m_step(x, _previous):
                """M-step of Pseudocode 1: (PS step,) irregular centres and their nearest N' neighbourhoods."""
                if stats is not None and np.any(ps_weight > 0):
                    # Section 4.5, one Portilla-Simoncelli step per iteration, taken *before* the
                    # patch search: the step restores fine detail and contrast that the search then
                    # finds in N', and the patch update removes its colour fringes and broken
                    # features (taken after it, as listed in Pseudocode 1, they stay in the output)
                    t0 = time.perf_counter()
                    x = x.copy()
                    step = np.clip(stats.step(x[..., :n_colour], amap), 0.0, 1.0)
                    x[..., :n_colour] += ps_weight * (step - x[..., :n_colour])
                    info.add("statistics", t0)
                t0 = time.perf_counter()
                centres, idx, err = _irregular_centres(x, nset, spacing, min(candidate_stride, spacing))
                z = patches[idx].astype(np.float64)
                if amap is not None:
                    z[..., -1] = extract(x, centres, s, mode="wrap")[..., -1]  # the map is enforced, not replaced
                info.add("synthesis", t0)
                return (centres, z), err, True

            def e_step(state, weights, _iteration):
                """E-step: relaxation of the pasted neighbourhoods, then the per-pixel mean-shift mode."""
                t0 = time.perf_counter()
                centres, z = state
                if relaxation_radius > 0:
                    centres = _relax(centres, z, weights, shape, relaxation_radius, spring_weight, max_sweeps=5)
                x = _mean_shift_update(z, centres, weights, shape, bandwidth, ms_iterations, n_colour)
                x[..., :n_colour] = np.clip(x[..., :n_colour], 0.0, 1.0)
                info.add("synthesis", t0)
                return x

            energies = []

            def energy(err, _x):
                energies.append(float(err.mean()))
                return energies[-1]

            def report(iteration, value, stop):
                bar.advance({"stage": (r, s), "energy": value}, n=max_iterations - iteration if stop else 1)

            state, err, _ = m_step(x, None)
            x, *_ = expectation_maximization(
                x, state, err, e_step, m_step, energy, max_iterations=max_iterations,
                tolerance=tolerance, eps2=_EPS, on_iteration=report,
            )
            stage_energies.append(energies)
    if x.shape[:2] != out_shape:
        x = ndimage.zoom(x, (out_shape[0] / x.shape[0], out_shape[1] / x.shape[1], 1), order=1)
    out = np.clip(x[..., :n_colour], 0.0, 1.0).astype(p.a.dtype)
    out = restore_channels(out, p.grey)
    info.energy = np.concatenate([np.asarray(e, float) for e in stage_energies])
    info.stage = np.repeat(np.arange(len(stage_energies)), [len(e) for e in stage_energies])
    info.seconds = time.perf_counter() - t_start
    return (out, info) if return_info else out


def _statistics_weight(alpha, last):
    """Weight of the Portilla-Simoncelli step: 1, and ``2 min(alpha, 1 - alpha)`` in the last stage.

    The statistics step restores the detail that blending two warped patches
    removes, and blending removes it in proportion to ``min(alpha, 1 - alpha)``
    (the same factor sets the keep fraction, see :func:`_interpolated_set`).
    At alpha = 0 and 1 ``N'`` holds the input's own neighbourhoods and the
    last stage becomes Kwatra et al.'s texture optimization; the coarser
    stages keep the full step, which is what stops the synthesis collapsing
    onto flat patches (see Notes of :func:`interpolate_textures`).

    >>> float(_statistics_weight(0.25, True)), _statistics_weight(0.0, False)
    (0.5, 1.0)
    """
    return 2.0 * np.minimum(alpha, 1.0 - alpha) if last else 1.0


def _check_stages(stages):
    try:
        stages = [(int(r), int(s)) for r, s in stages]
    except (TypeError, ValueError):
        raise ValueError(f"stages must be a sequence of (r, s) pairs, got {stages!r}") from None
    if not stages or any(r < 1 or s < 3 for r, s in stages):
        raise ValueError(f"stages need r >= 1 and s >= 3, got {stages}")
    return stages
