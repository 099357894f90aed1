"""Texture optimization: EM-like synthesis by energy minimisation (Kwatra et al. 2005).

The output ``X`` is judged by its *texture energy*: the distance of each of
its neighbourhoods ``x_p``, centred on a sparse grid ``X†`` spaced ``w/4``
apart, to the nearest exemplar neighbourhood ``z_p`` (eq. 1)::

    E_t(x; {z_p}) = sum_{p in X†} ||x_p - z_p||^2                       (1)

Synthesis (Algorithm 1) alternates two minimisations of ``E_t``:

E-step
    ``x <- argmin_x E_t(x; {z_p})``: every pixel becomes the weighted average
    of the ``z_p`` that overlap it (a Poisson-like linear system when the
    gradient term is on).
M-step
    ``z_p <- nearest exemplar neighbourhood of x_p`` for every ``p``
    (:class:`texsynth.core.search.PatchIndex`, built once per level and size,
    or PatchMatch between the output and the exemplar, warm-started from the
    current ``z_p``: :func:`texsynth.core.search.patchmatch`).

until the set ``{z_p}`` stops changing. Section 3.1 makes it robust: the
squared norm becomes ``||x_p - z_p||^r`` (``r = 0.8``), minimised by
iteratively reweighted least squares (IRLS) with weights
``ω_p = ||x_p - z_p||^(r - 2)``, and each neighbourhood's pixels are weighted
by a Gaussian fall-off. Section 3.2 runs it coarse to fine over 3 resolution
levels and, within each, neighbourhood sizes 32, 16 and 8.

Section 4 adds control: ``E = E_t + λ E_c`` with the soft constraint
``E_c(x; x^c) = sum_{k in C} (x(k) - x^c(k))^2`` (eq. 2) changes the E-step
into a weighted average with the targets and the M-step into a search for
neighbourhoods already consistent with them (Algorithm 2): with a mask that
leaves a hole this is hole filling. Section 4.1 animates a texture along a
flow (eq. 3), frame by frame, with the previous frame warped along the flow
as the soft-constraint target (:func:`animate_texture`).

Not in the paper: orientation and scale fields (the local frames of Zhang et
al. 2003, :mod:`texsynth.core.fields`) turn and magnify the texture locally:
the M-step samples every ``x_p`` on a grid turned and scaled around its
centre, the E-step splats ``z_p`` back there (:class:`_Warp`; the Notes of
:func:`optimize_texture`).

What the implementation guarantees
----------------------------------
The energy actually minimised is the robust texture energy

.. math:: E(x, \\{z_p\\}) = \\sum_p \\left(\\rho_p + \\varepsilon^2\\right)^{r/2}
          + \\lambda E_c(x), \\qquad
          \\rho_p = \\|x_p - z_p\\|_g^2 + \\mu \\|D x_p - D z_p\\|_g^2

where ``‖·‖_g`` carries the Gaussian fall-off and ``ε`` (an RMS difference of
1e-3 per value, a quarter of an 8-bit grey level) keeps the IRLS weight
finite when ``x_p == z_p``. Because ``s -> (s + ε²)^{r/2}`` is concave for
``r <= 2``, its tangent at the current ``ρ_p`` is an upper bound: the IRLS
E-step (weights ``ω_p = (r/2)(ρ_p + ε²)^{(r-2)/2}``, the paper's
``||x_p - z_p||^{r-2}`` up to the constant ``r/2`` and the guard ``ε``)
minimises a majoriser that touches ``E`` at the current ``x``, so it cannot
raise ``E``; the M-step keeps the old ``z_p`` unless the search found one
strictly closer, so it cannot raise ``E`` either, even with an approximate
search backend, or when it skips the search of a neighbourhood that hardly
moved. Hence, for ``λ = 0`` (and with the occurrence penalty and the copy
limit off, their defaults), ``E`` never rises between two iterations of one
(level, size) stage beyond floating-point noise (the E-step with ``μ > 0``
is solved by preconditioned conjugate gradients to a relative residual of
1e-10, reached in 16 iterations (median; 30 at most) on the systems of a
256 x 256 synthesis). The modified M-step of Algorithm 2 ranks candidates
by ``||x_p - v||^2 + λ E_c(y)``, which is *not* ``E``; with constraints the
energy usually falls but is not guaranteed to. The optional completeness term
of the bidirectional similarity (``completeness_weight``) keeps the guarantee:
its matches ``p(j)`` are only ever replaced by closer ones and its votes join
the same weighted average.

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
   for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
   2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import dataclasses
import numbers
import time
from dataclasses import dataclass, field

import numpy as np
from scipy import fft as sfft
from scipy import ndimage

from ..core._parallel import parallel_for
from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import (as_float_array, as_image, as_rng, as_size, check_bool, check_in_range, check_memory,
                              check_positive_float, check_positive_int, max_threads, restore_channels, with_channels)
from ..core.em import expectation_maximization, irls_weights
from ..core.fields import as_field, frames, level_field, sample, scatter, taps
from ..core.convolve import fft_convolve
from ..core.flows import flow_sequence, warp, warp_coordinates
from ..core.histogram import match_to_targets, quantile_targets
from ..core import search
from ..core.search import (PatchIndex, check_candidates, coherence_sets, nearest_candidates, patchmatch_features,
                           sq_distances)
from ..core.neighborhood import (PatchSum, all_patches, extract, gaussian_falloff, grid_axes, grid_cells, grid_centers,
                                 patches_within)
from ..core.pyramid import gaussian_pyramid, level_shapes, max_levels, upsample
from ..core.scale import feature_scale

__all__ = ["optimize_texture", "animate_texture", "OptimizationInfo", "StageInfo", "AnimationInfo"]

# IRLS guard: RMS difference per weighted value below which a neighbourhood
# counts as matched (1e-3 = a quarter of an 8-bit grey level).
_EPS_RMS = 1e-3
# Candidates re-ranked by the modified M-step (Algorithm 2) for constrained patches.
_CONSTRAINED_CANDIDATES = 8
# M-step: search a neighbourhood again only if x_p moved since its last search by more than
# this fraction of the distance to its match then (0: search every neighbourhood every time)
_RESEARCH_TOLERANCE = 0.03
# Occurrence penalty / copy limit: index candidates re-ranked by distance + penalty
_OCCURRENCE_CANDIDATES = 4
# copy_limit: penalty per unit of excess (offset count / limit - 1), in units of the
# occurrence scale (exemplar variance x summed weights of a neighbourhood)
_COPY_PENALTY = 3.0
# Largest weight of an energy term: far beyond any meaningful balance (the paper's mu is 10, a
# constraint of 100 is nearly hard), and below what overflows the float32 search features.
_MAX_WEIGHT = 1e6
#: Presets of :func:`optimize_texture`: what its ``"auto"`` options mean.
PRESETS = ("default", "paper")
# preset "default": the stop test of the energy (an addition to the paper's test of unchanged z_p)
_DEFAULT_TOLERANCE = 5e-3
# preset "default": the completeness term is on at every level when the output has less than this many
# times the exemplar's area (at 1.5x the texture energy alone missed parts of every tuning photo), and
# at every level but the finest from there on: on the finest level too its votes blurred large flat
# areas of cobblestones at 4x, while without it at the coarse levels the arrangement kept coming back
# to a few parts of the exemplar (completeness 1.4-3.8 times a random-block mosaic's on the tuning
# photos at 4x, 1.1-2.4 with it; docs/methods/optimization.md)
_COMPLETE_BELOW = 4.0
# preset "default": copy_limit (largest copies at 4x measured 0.66-0.77 of the exemplar without it)
_DEFAULT_COPY_LIMIT = 0.25
# preset "default" without the completeness term: the copy limit at the finest level, which otherwise
# only refines the coarser levels' arrangement (0.25 there cut blocks and stones mid-element at 4x; 0.3
# cuts only the outlying copies: cobblestones_2 0.35 -> 0.30, bricks_2 at 8x 0.36 -> 0.31, no visible
# change; docs/methods/optimization.md)
_FINE_COPY_LIMIT = 0.3
# preset "default": largest neighbourhood for exemplars whose feature scale is above _LARGE_FEATURES
# pixels (half of it otherwise), and the smaller side of the coarsest exemplar level
_LARGE_SIZE = 64
_LARGE_FEATURES = 32.0
_COARSEST_SIDE = 32
# PatchMatch M-step: iterations of propagation and random search in a stage's first M-step (from the
# previous stage's field carried over, or from random neighbourhoods) and in each later one (from the
# current z_p)
_FIELD_ITERATIONS_FIRST = 4
_FIELD_ITERATIONS = 1
# E-step: neighbourhood values added into the output at a time (32 MB of float64)
_E_STEP_VALUES = 2**22
# Fields: the bilinear taps of a stage's rotated neighbourhoods are kept while they take at most this
# many bytes (256^2 outputs: about 80 MB), else computed at every use
_WARP_CACHE_BYTES = 2**28
# Guides with at most this many distinct values (vectors) are label maps: histogram matching per label
_MAX_LABELS = 32
# Conjugate gradients of the gradient-energy E-step: relative residual and cap.
_CG_RTOL = 1e-10
_CG_MAXITER = 500


# --------------------------------------------------------------------------- results
@dataclass
class StageInfo:
    """One (resolution level, neighbourhood size) stage of the synthesis.

    Attributes
    ----------
    level : int
        0 is full resolution, 1 half, 2 a quarter.
    size : int
        Neighbourhood width ``w``.
    shape : tuple of int
        Output size at this level.
    spacing : int
        Grid spacing of ``X†`` (``w/4``).
    neighborhoods : int
        ``|X†|``, the number of output neighbourhoods (under hard
        constraints, those that touch an unconstrained pixel and the ring one
        grid step around them: the others are neither searched nor averaged).
    exemplar_neighborhoods : int
        Number of searchable exemplar neighbourhoods.
    iterations : int
        EM iterations run.
    converged : bool
        True if ``{z_p}`` stopped changing before ``max_iterations``.
    seconds : float
        Wall time of the stage (index build included).
    nn_seconds : float
        Part of it spent building the index and searching it (M-step).
    m_steps : int
        M-steps run (one per iteration, plus the first one of a stage that
        starts from the previous stage's image).
    searches : int
        Neighbourhoods looked up in the index over all M-steps; at most
        ``m_steps * neighborhoods`` (fewer when neighbourhoods that hardly
        moved since their last search are not searched again, see
        :func:`optimize_texture`).
    first : int
        Position of the stage's first energy value in
        :attr:`OptimizationInfo.energy`.
    completeness_weight : float
        Weight of the completeness term at this stage (0: off).
    copy_limit : float or None
        The copy limit at this stage (None: off).
    """

    level: int
    size: int
    shape: tuple
    spacing: int
    neighborhoods: int
    exemplar_neighborhoods: int
    iterations: int = 0
    converged: bool = False
    seconds: float = 0.0
    nn_seconds: float = 0.0
    m_steps: int = 0
    searches: int = 0
    first: int = 0
    completeness_weight: float = 0.0
    copy_limit: float | None = None


@dataclass
class OptimizationInfo:
    """What :func:`optimize_texture` did, for plots and diagnostics.

    Attributes
    ----------
    energy : numpy.ndarray
        The minimised energy ``E(x, {z_p})`` after every M-step, all stages
        concatenated in synthesis order (Figure 3 of the paper). Values of
        different stages are not comparable (other sizes, other levels).
    mse : numpy.ndarray
        The same iterations' eq. 1 energy normalised by the number of
        neighbourhoods and the (weighted) values per neighbourhood: the mean
        squared difference per value, comparable across stages (what
        Figure 3 plots).
    stage : numpy.ndarray of int
        Index into :attr:`stages` of every energy value.
    stages : list of StageInfo
        The stages in synthesis order.
    centers : numpy.ndarray
        ``(N, 2)`` centres ``X†`` (row, col) of the last stage, in output pixels
        (under hard constraints, those near the unconstrained pixels).
    sources : numpy.ndarray
        ``(N, 2)`` centre in the exemplar of each final ``z_p``: where each
        neighbourhood of the output came from.
    seconds : float
        Total wall time.
    coordinates : numpy.ndarray or None
        ``(H, W, 2)`` int, the source-coordinate map (``docs/conventions.md``):
        for every output pixel, the exemplar pixel that the final ``z_p`` of
        largest weight ``ω_p g(x - p)`` (IRLS weight times fall-off) puts
        there. The output blends about ``(w / spacing)^2`` overlapping
        ``z_p``, which agree closely once the synthesis has converged; the
        dominant one is a copy map, so :func:`texsynth.apply_coordinates`
        renders other channels as sharp, consistent copies. (A blend of all
        the ``z_p`` would not reproduce the output either: the E-step also
        solves the gradient energy, matches histograms and enforces
        constraints, which are no weighted sum of exemplar pixels; and it
        would take ``(w / spacing)^2`` times the memory.) None when the last
        stage ran at a coarser level than the output.
    weights : None
        A copy map has no weights.
    """

    energy: np.ndarray
    mse: np.ndarray
    stage: np.ndarray
    stages: list
    centers: np.ndarray
    sources: np.ndarray
    seconds: float = 0.0
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None

    @property
    def boundaries(self):
        """Index of the first energy value of every stage (level/size changes)."""
        return [s.first for s in self.stages]

    @property
    def nn_seconds(self):
        """Time spent building and searching nearest-neighbour indexes."""
        return float(sum(s.nn_seconds for s in self.stages))

    @property
    def nn_share(self):
        """Fraction of the wall time spent in nearest-neighbour search."""
        return self.nn_seconds / self.seconds if self.seconds > 0 else 0.0

    @property
    def level_seconds(self):
        """``{level: seconds}`` summed over that level's stages."""
        out = {}
        for s in self.stages:
            out[s.level] = out.get(s.level, 0.0) + s.seconds
        return out

    @property
    def stage_seconds(self):
        """Wall time per stage: ``{"level 1 size 16": seconds, ...}`` in synthesis order."""
        return {f"level {s.level} size {s.size}": s.seconds for s in self.stages}


@dataclass
class AnimationInfo:
    """What :func:`animate_texture` did.

    Attributes
    ----------
    first : OptimizationInfo
        The multi-level synthesis of frame 1 (None if ``first_frame`` was given).
    frames : list of OptimizationInfo
        The single-resolution constrained synthesis of frames 2..L.
    frame_seconds : numpy.ndarray
        Wall time of each frame 2..L (warping included).
    seconds : float
        Total wall time.
    """

    first: object
    frames: list = field(default_factory=list)
    frame_seconds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    seconds: float = 0.0

    @property
    def stage_seconds(self):
        """Wall time per frame: ``{"frame 1": ..., "frame 2": ..., ...}`` (frame 1 absent if given)."""
        out = {} if self.first is None else {"frame 1": self.first.seconds}
        out.update({f"frame {i + 2}": float(t) for i, t in enumerate(self.frame_seconds)})
        return out

    @property
    def energy(self):
        """The final energy of every synthesised frame, in order (1-D)."""
        infos = ([] if self.first is None else [self.first]) + self.frames
        return np.array([float(i.energy[-1]) for i in infos])


# --------------------------------------------------------------------------- options
@dataclass(frozen=True)
class _Options:
    """The settings of one synthesis (a call, or one frame of an animation), checked once."""

    r: float  # irls_exponent (Section 3.1)
    mu: float  # gradient_weight
    spacing: float  # grid spacing of X† as a fraction of the neighbourhood size (w/4)
    max_iterations: int
    tolerance: float
    tileable: bool = False
    falloff: bool = True
    method: str = "auto"  # the M-step's backend (texsynth.core.search.FIELD_METHODS)
    candidates: str = "all"  # "k-coherent": the M-step ranks k-coherent candidates (Tong et al. 2002)
    k: int = 4  # the size of the k-coherence sets
    occurrence: float = 0.0  # occurrence_weight
    copy_limit: float | None = None
    completeness: float = 0.0  # completeness_weight
    coords: np.ndarray | None = field(default=None, repr=False)  # a frame: last frame's correspondence, warped
    assembly: float | None = None  # a frame: frame_falloff
    histogram: bool = False  # histogram_matching: the output's colour histograms matched after every E-step
    paper: bool = False  # preset "paper": the index M-step, as the paper searches a tree over the exemplar
    coarse_copy_limit: bool = False  # the copy limit at every level but the finest, _FINE_COPY_LIMIT there
    coarse_completeness: bool = False  # the completeness term at every level but the finest
    fields: bool = False  # orientation / scale fields: rotated, scaled neighbourhoods (the index M-step)
    confidence: float | None = None  # Wexler's γ: neighbourhoods weighed by their confidence (hard constraints)

    @property
    def frame(self):
        """True for the constrained single-resolution synthesis of an animation frame."""
        return self.coords is not None

    @property
    def mode(self):
        return "wrap" if self.tileable else "valid"

    def grid(self, size):
        """Spacing in pixels of the centres of ``size``-wide neighbourhoods."""
        return max(1, int(round(size * self.spacing)))

    def field(self, constraint, ex, queries):
        """True if the M-step is PatchMatch (``method="patchmatch"``, or ``"auto"`` where it applies and
        the stage is large: :func:`texsynth.core.search.resolve_field`)."""
        applies = self.mu == 0 and (constraint is None or self.frame) and not self.paper
        if self.candidates == "k-coherent":  # every stage: the candidates are few whatever its size
            return applies
        values = float(len(ex)) * queries * ex.weights.shape[0]
        return search.resolve_field(self.method, applies=applies, values=values) == "patchmatch"

    @property
    def index_method(self):
        """The index backend of the other M-steps (``"auto"`` lets the search profile decide)."""
        return "auto" if self.method == "patchmatch" else self.method


# --------------------------------------------------------------------------- features
def _difference_weights(g):
    """Fall-off weights of the horizontal and vertical pixel differences of a patch."""
    return (g[:, 1:] + g[:, :-1]) / 2.0, (g[1:, :] + g[:-1, :]) / 2.0


def _features(patches, mu):
    """Vector of a neighbourhood: its values and, if ``μ > 0``, ``sqrt(μ) D x_p``.

    ``D`` is the forward difference inside the neighbourhood, horizontal then
    vertical, so the weighted squared distance of two feature vectors is
    ``ρ_p = ||x_p - z_p||_g^2 + μ ||D x_p - D z_p||_g^2``.
    """
    n = patches.shape[0]
    flat = patches.reshape(n, -1)
    if mu == 0:
        return flat
    s = np.sqrt(mu)
    dx = (patches[:, :, 1:] - patches[:, :, :-1]).reshape(n, -1) * s
    dy = (patches[:, 1:] - patches[:, :-1]).reshape(n, -1) * s
    return np.concatenate([flat, dx, dy], axis=1)


def _feature_weights(g, channels, mu):
    """Per-dimension weights matching :func:`_features` (fall-off repeated per channel)."""
    rep = lambda a: np.repeat(a.ravel(), channels)  # noqa: E731  (h, w, C) order
    if mu == 0:
        return rep(g)
    gx, gy = _difference_weights(g)
    return np.concatenate([rep(g), rep(gx), rep(gy)])


class _Exemplar:
    """The searchable neighbourhoods of one exemplar level for one size.

    The index over their feature vectors is built on first use: the
    PatchMatch M-step never needs it (it compares patches of the images).
    """

    def __init__(self, image, valid, size, opts, rng, frame=False, guided=False):
        mu = opts.mu
        self.image, self.size, self.mu = image, size, mu
        self.guided = guided  # the last channels are guides (may exceed 1 and make more than 4 channels)
        self.valid = valid
        self.view = all_patches(image, size)  # (Ny, Nx, w, w, C), a view
        ok = patches_within(valid > 0.5, size)
        self.corner = np.argwhere(ok)  # top-left corners of patches free of masked pixels
        self._index = self._feats = None
        self._build = (opts.index_method, "frame" if frame else "stage" if mu == 0 else "default", rng, frame)
        if len(self.corner) == 0:
            return
        self.g = gaussian_falloff(size) if opts.falloff else np.ones((size, size))
        self.weights = _feature_weights(self.g, image.shape[-1], mu)
        self.eps2 = _EPS_RMS**2 * float(self.weights.sum())
        self.grid = np.full(self.view.shape[:2], -1, dtype=np.int64)  # corner -> neighbourhood index
        self.grid[self.corner[:, 0], self.corner[:, 1]] = np.arange(len(self.corner))

    @property
    def index(self):
        """The :class:`~texsynth.core.search.PatchIndex` over every neighbourhood's features."""
        if self._index is None:
            method, profile, rng, frame = self._build
            # the index searches float32 copies (half the memory, twice the BLAS speed);
            # energies and the M-step's final choice use exact float64 distances
            feats = self.feats if frame else self._features()
            # the search layer's measured settings: "frame" (coherent candidates do most of the work),
            # "stage", or the defaults for the gradient energy's longer vectors
            self._index = PatchIndex(feats, weights=self.weights, method=method, profile=profile, rng=rng)
        return self._index

    @property
    def feats(self):
        """The float32 feature vectors of every neighbourhood (animation frames rank candidates on them)."""
        if self._feats is None:
            self._feats = self._features()
        return self._feats

    def _features(self):
        feats = np.empty((len(self.corner), self.weights.shape[0]), dtype=np.float32)
        step = max(1, 2**24 // max(1, self.weights.shape[0] * 8))
        for a in range(0, len(self.corner), step):
            feats[a : a + step] = _features(self.patches(np.arange(a, min(a + step, len(self.corner)))), self.mu)
        return feats

    def __len__(self):
        return len(self.corner)

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


# --------------------------------------------------------------------------- fields
class _Warp:
    """The rotated and scaled neighbourhoods ``x_p`` of one stage (orientation and scale fields).

    Neighbourhood ``p`` is read on the grid ``p + A(p) d``, ``A = S R(theta)``
    (:func:`texsynth.core.fields.frames`, as in Zhang et al. 2003), ``d`` the
    offsets of a ``w x w`` patch from its centre pixel ``w // 2``: the
    bilinear samples of the output there are the neighbourhood compared
    with the exemplar's plain ``z_p`` in the M-step, and the E-step adds the
    values of ``z_p`` back at the same positions with the same bilinear
    weights (:func:`texsynth.core.fields.splat`, the adjoint of the
    sampling). So a ``z_p`` appears in the output turned by ``theta(p)`` and
    magnified by ``S(p)``.
    """

    def __init__(self, centers, w, theta, scale, shape, mode):
        self.a, self.inverse = frames(theta[centers[:, 0], centers[:, 1]], scale[centers[:, 0], centers[:, 1]])
        i = np.arange(w, dtype=np.float64) - w // 2
        self.d = np.stack(np.meshgrid(i, i, indexing="ij"), -1).reshape(-1, 2)
        self.centers, self.w, self.shape, self.wrap = centers, w, tuple(shape), mode == "wrap"
        self.row = np.full(self.shape, -1, np.int64)  # centre -> its row in ``centers``
        self.row[centers[:, 0], centers[:, 1]] = np.arange(len(centers))
        self.cache = None  # the taps of every sample, computed once per stage where they fit the budget
        if len(centers) * w * w * 4 * 16 <= _WARP_CACHE_BYTES:
            self.cache = self._taps(centers)

    def _taps(self, at):
        """Flat pixel indices and bilinear weights ``(n, w * w, 4)`` of the samples of the neighbourhoods at ``at``."""
        if self.cache is not None:
            rows = self.row[at[:, 0], at[:, 1]]
            return self.cache[0][rows], self.cache[1][rows]
        return taps(self.positions(at), self.shape[0], self.shape[1], self.wrap)

    def positions(self, at):
        """``(n, w * w, 2)``: where the neighbourhoods centred at ``at`` (centres of the stage) read the output."""
        rows = self.row[at[:, 0], at[:, 1]]
        a, c, (dr, dc) = self.a[rows, :, :, None], self.centers[rows], self.d.T
        return np.stack([c[:, :1] + a[:, 0, 0] * dr + a[:, 0, 1] * dc, c[:, 1:] + a[:, 1, 0] * dr + a[:, 1, 1] * dc], -1)

    def extract(self, x, at):
        """The neighbourhoods ``(n, w, w, C)`` of ``x`` centred at ``at``, bilinear samples in their frames
        (a few thousand neighbourhoods at a time: the taps take eight times the samples' memory)."""
        out = np.empty((len(at), self.w, self.w, x.shape[-1]), x.dtype)
        step = max(1, _E_STEP_VALUES // out[0].size)
        for a in range(0, len(at), step):
            part = slice(a, a + step)
            out[part] = sample(x, *self._taps(at[part]))[0].reshape(out[part].shape)
        return out

    def add(self, sums, patches, at, patch_weights, pixel_weights):
        """Add ``patches`` ``(n, w, w, C)`` centred at ``at`` into ``sums = [values, weights]``."""
        n, c = len(at), patches.shape[-1]
        weights = np.asarray(patch_weights, np.float64)[:, None] * pixel_weights.reshape(1, -1)
        index, tap = self._taps(at)
        v, t = scatter(patches.reshape(n, -1, c), index, tap * weights[..., None], self.shape)
        sums[0] += v
        sums[1] += t


def _neighbourhoods(x, at, w, mode, warp):
    """The output neighbourhoods centred at ``at``: plain patches, or sampled in the fields' frames."""
    return extract(x, at, w, mode=mode) if warp is None else warp.extract(x, at)


# --------------------------------------------------------------------------- E-step
def _dx(u, wrap):
    return np.roll(u, -1, axis=1) - u if wrap else u[:, 1:] - u[:, :-1]


def _dy(u, wrap):
    return np.roll(u, -1, axis=0) - u if wrap else u[1:] - u[:-1]


def _dxT(e, wrap, shape):
    if wrap:
        return np.roll(e, 1, axis=1) - e
    out = np.zeros(shape + e.shape[2:], dtype=e.dtype)
    out[:, :-1] -= e
    out[:, 1:] += e
    return out


def _dyT(e, wrap, shape):
    if wrap:
        return np.roll(e, 1, axis=0) - e
    out = np.zeros(shape + e.shape[2:], dtype=e.dtype)
    out[:-1] -= e
    out[1:] += e
    return out


def _laplacian_eigenvalues(n, wrap):
    """Eigenvalues of D^T D on a line of n pixels: periodic (FFT) or Neumann (DCT-II)."""
    k = np.arange(n)
    return 2.0 - 2.0 * np.cos((2.0 if wrap else 1.0) * np.pi * k / n)


def _solve_gradient_system(data_w, rhs_data, wx, gx, wy, gy, mu, wrap, x0, stats=None):
    """Minimise sum_i a_i (x_i - m_i)^2 + μ sum_e b_e (D x - G)_e^2 over x.

    Normal equations ``(A + μ Dᵀ B D) x = A m + μ Dᵀ B G`` (the "Poisson-like
    linear system" of the paper, with spatially varying weights), solved by
    preconditioned conjugate gradients. The weights vary over 4-6 orders of
    magnitude (IRLS weights of matched and unmatched neighbourhoods), so the
    preconditioner first scales the system by its diagonal ``d``
    (``S = diag(sqrt(d))``; ``S⁻¹ K S⁻¹`` has a unit diagonal) and then
    inverts the constant-coefficient operator with the scaled system's mean
    coefficients, which the FFT (periodic output) or the DCT (non-periodic
    output, Neumann boundary) diagonalises exactly:
    ``P⁻¹ = S⁻¹ C⁻¹ S⁻¹``. Measured on the systems of a 3-level synthesis
    (64-256 px, μ = 10): 15-30 iterations to a relative residual of 1e-10,
    against 85-500 (and the 500-iteration cap at up to 4e-8) with the
    unscaled constant-coefficient preconditioner. ``stats``, a dict, receives ``iterations`` and ``residual``.
    """
    shape = data_w.shape
    a = data_w[..., None]
    bx, by = wx[..., None], wy[..., None]

    def apply(u):
        return a * u + mu * (_dxT(bx * _dx(u, wrap), wrap, shape) + _dyT(by * _dy(u, wrap), wrap, shape))

    b = rhs_data + mu * (_dxT(bx * gx, wrap, shape) + _dyT(by * gy, wrap, shape))
    # diagonal of the operator: a_i + μ (weights of the differences that touch pixel i)
    edges = np.zeros(shape)
    if wrap:
        edges += wx + np.roll(wx, 1, axis=1) + wy + np.roll(wy, 1, axis=0)
    else:
        edges[:, :-1] += wx
        edges[:, 1:] += wx
        edges[:-1] += wy
        edges[1:] += wy
    d = np.maximum(data_w + mu * edges, 1e-300)
    sd = np.sqrt(d)
    if wrap:
        bxs, bys = wx / (sd * np.roll(sd, -1, axis=1)), wy / (sd * np.roll(sd, -1, axis=0))
    else:
        bxs, bys = wx / (sd[:, :-1] * sd[:, 1:]), wy / (sd[:-1] * sd[1:])
    lam = (
        float((data_w / d).mean())
        + mu * float(bys.mean()) * _laplacian_eigenvalues(shape[0], wrap)[:, None]
        + mu * float(bxs.mean()) * _laplacian_eigenvalues(shape[1], wrap)[None, :]
    )[..., None]
    lam = np.maximum(lam, 1e-300)
    sd = sd[..., None]

    def precondition(r):
        r = r / sd
        if wrap:
            z = np.real(sfft.ifft2(sfft.fft2(r, axes=(0, 1)) / lam, axes=(0, 1)))
        else:
            z = sfft.idctn(sfft.dctn(r, type=2, axes=(0, 1), norm="ortho") / lam, type=2, axes=(0, 1), norm="ortho")
        return z / sd

    x = x0.copy()
    r = b - apply(x)
    z = precondition(r)
    p = z.copy()
    rz = np.einsum("ijc,ijc->c", r, z)
    bnorm = np.sqrt(np.einsum("ijc,ijc->c", b, b))
    iterations = 0
    for iterations in range(_CG_MAXITER + 1):
        if np.all(np.sqrt(np.einsum("ijc,ijc->c", r, r)) <= _CG_RTOL * np.maximum(bnorm, 1e-300)):
            break
        if iterations == _CG_MAXITER:
            break
        q = apply(p)
        pq = np.einsum("ijc,ijc->c", p, q)
        alpha = np.divide(rz, pq, out=np.zeros_like(rz), where=pq > 0)
        x += alpha * p
        r -= alpha * q
        z = precondition(r)
        rz_new = np.einsum("ijc,ijc->c", r, z)
        beta = np.divide(rz_new, rz, out=np.zeros_like(rz), where=rz > 0)
        p = z + beta * p
        rz = rz_new
    if stats is not None:
        stats["iterations"] = iterations
        stats["residual"] = float(np.max(np.sqrt(np.einsum("ijc,ijc->c", r, r)) / np.maximum(bnorm, 1e-300)))
    return x


def _grid_parts(centers, budget):
    """Slices of ``centers`` (a row-major grid, or a part of one) holding about ``budget`` centres each, in
    whole rows of the grid when ``centers`` is all of it."""
    ncols = int(np.count_nonzero(centers[:, 0] == centers[0, 0]))
    step = ncols * max(1, budget // ncols)
    return [slice(a, a + step) for a in range(0, len(centers), step)]


WEXLER_CONFIDENCE = 1.3
"""γ of Wexler, Shechtman & Irani 2007 (Sec. 3.2): a filled pixel's confidence is γ^-(its distance to the
known pixels); :func:`~texsynth.inpaint` and :func:`~texsynth.uncrop` use it."""


def _confidence(mask, centers, w, mode, gamma):
    """Each neighbourhood's confidence under hard constraints (Wexler, Shechtman & Irani 2007, Sec. 3.2).

    The mean over its pixels of 1 where the pixel is known (``mask``, fractional where a coarse pixel
    is partly known) and ``γ^-d`` elsewhere, ``d`` the distance to the nearest known pixel: in the
    E-step the neighbourhoods that lie mostly on known pixels outweigh the others near the
    boundary, so the fill continues what is known rather than meeting it along a seam.
    """
    known = mask >= 0.5
    if not known.any():
        return None
    h, w_ = mask.shape
    if mode == "wrap":  # distances round the torus
        d = ndimage.distance_transform_edt(np.tile(~known, (3, 3)))[h : 2 * h, w_ : 2 * w_]
    else:
        d = ndimage.distance_transform_edt(~known)
    conf = np.maximum(np.maximum(mask, gamma**-d), 1e-100)  # floored: far inside a hole only the ratios matter
    mean = ndimage.uniform_filter(conf, size=w, mode="wrap" if mode == "wrap" else "nearest")
    return np.maximum(mean[centers[:, 0], centers[:, 1]], 1e-100)  # a running sum can round below 0


def _touching_free(mask, centers, w, spacing, mode):
    """Which neighbourhoods at ``centers`` take part under hard constraints: those that hold a pixel not
    wholly constrained (``mask`` below 1), and the ring of grid neighbours one ``spacing`` further out.

    The others hold nothing but target pixels, which every E-step puts back whatever they vote, so they
    are neither searched nor averaged: the work follows the hole (or the border of an uncrop), not the
    image. The ring holds known pixels only, but PatchMatch propagates its matches into the
    neighbourhoods across the border: without it the uncrop seams of bark_1 rose from 1.93 to 2.26
    (``benchmarks/bench_completion.py``, two seeds; docs/methods/completion.md). A coarse pixel within
    1e-6 of 1 counts as constrained, as :func:`_pyramids` rounds the exemplar's valid mask.
    """
    reach = w + 2 * spacing  # the neighbourhood and the ring around it
    known = mask > 1 - 1e-6
    if mode == "wrap":  # neighbourhoods that cross the edge read the other side
        known = np.pad(known, ((0, reach - 1), (0, reach - 1)), mode="wrap")
        corner = (centers - reach // 2) % mask.shape
    else:  # beyond the output counts as constrained
        known = np.pad(known, spacing, constant_values=True)
        corner = centers - w // 2
    return ~patches_within(known, reach)[corner[:, 0], corner[:, 1]]


def _e_step(ex, zidx, centers, shape, omega, mode, mu, constraint, x0, g=None, votes=None, warp=None):
    """x <- argmin_x sum_p ω_p ρ_p(x) + λ E_c(x): eq. 1 (and eq. 2) minimised over x.

    The ``z_p`` of the grid ``centers`` are added a few grid rows at a time
    (memory grows with the output, not with the overlap); ``votes``
    ``(indices, centres, weights)`` are more neighbourhoods averaged in (the
    completeness term's ``q_j`` at ``p(j)``). With a :class:`_Warp` (fields,
    ``μ = 0``) every ``z_p`` is splatted at its rotated, scaled positions.
    Pixels that no neighbourhood reaches (a warp's gaps; under hard
    constraints, the pixels away from the unconstrained ones,
    :func:`_touching_free`) keep their value in ``x0``.
    """
    g = ex.g if g is None else g
    w, channels = ex.size, ex.image.shape[-1]
    wrap = mode == "wrap"
    h_, w_ = shape
    gxw, gyw = _difference_weights(g)
    shift = w // 2 - (w - 1) // 2  # centre of a (w-1)-wide difference patch, anchored at its left pixel
    values = PatchSum(shape, channels, mode=mode) if warp is None else [np.zeros(tuple(shape) + (channels,)),
                                                                        np.zeros(tuple(shape))]
    if mu > 0:  # gradient energy: accumulate the patches' differences like the patches themselves
        dx = PatchSum((h_, w_ if wrap else w_ - 1), channels, mode=mode)
        dy = PatchSum((h_ if wrap else h_ - 1, w_), channels, mode=mode)
    parts = [(zidx[p], centers[p], omega[p]) for p in _grid_parts(centers, _E_STEP_VALUES // (w * w * channels))]
    for zi, at, om in parts + ([] if votes is None else [votes]):
        z = ex.patches(zi)
        if warp is not None:
            warp.add(values, z, at, om, g)
            continue
        values.add(z, at, patch_weights=om, pixel_weights=g)
        if mu > 0:
            dx.add(z[:, :, 1:] - z[:, :, :-1], at - [0, shift], patch_weights=om, pixel_weights=gxw)
            dy.add(z[:, 1:] - z[:, :-1], at - [shift, 0], patch_weights=om, pixel_weights=gyw)
    if warp is None:
        mean, wd = values.average()
        data_w = wd.copy()
        rhs = wd[..., None] * mean
    else:  # the splatted sums
        rhs, data_w = values
    uncovered = data_w <= 0  # a pixel no neighbourhood reaches keeps its value (weight 1 on x0)
    if uncovered.any():
        rhs[uncovered] = x0[uncovered]
        data_w[uncovered] = 1.0
    hard = constraint is not None and np.isinf(constraint[2])
    if constraint is not None and not hard:  # eq. 2: the weighted average with the targets (Section 4)
        m, t, lam = constraint
        data_w += lam * m
        rhs += (lam * m)[..., None] * t
    if mu == 0:
        x = rhs / data_w[..., None]
    else:
        (gx, wx), (gy, wy) = dx.average(), dy.average()
        x = _solve_gradient_system(data_w, rhs, wx, gx, wy, gy, mu, wrap, x0.astype(np.float64))
    if hard:  # λ = ∞: the targets replace the average where the mask is 1 (blended where a coarse pixel is partly known)
        m, t, _ = constraint
        x = (1 - m)[..., None] * x + m[..., None] * t
    return x.astype(ex.image.dtype, copy=False)


# --------------------------------------------------------------------------- M-step
class _SearchMemo:
    """What the last search of every neighbourhood saw: its query and its distance then.

    Used by :func:`_m_step` to skip the search of neighbourhoods that hardly
    moved since (see ``_RESEARCH_TOLERANCE``).
    """

    def __init__(self, n, dim):
        self.q = None if dim is None else np.zeros((n, dim), dtype=np.float32)
        self.rho = np.full(n, np.inf)
        self.searched = 0  # number of index queries (for StageInfo.searches)


class _Occurrence:
    """Occurrence penalty (Kaspar et al. 2015) and copy limit of one stage's M-step.

    ``count[c]`` is the number of ``z_p`` with top-left corner ``c``. The
    occurrence of an exemplar pixel is the fall-off weight with which the
    ``z_p`` cover it, and the occurrence of a neighbourhood the fall-off
    weighted mean of its pixels' occurrences: ``o = count * A`` with ``A``
    the autocorrelation of the fall-off divided by its sum (one FFT
    convolution). ``ω`` is the occurrence every neighbourhood would have if
    the ``z_p`` were spread evenly over the exemplar; the penalty added to
    ``ρ`` of a candidate is ``weight * scale * o / ω``, with ``scale`` the
    exemplar's variance times the summed weights of a neighbourhood (the
    expected half-distance of two random neighbourhoods), so ``weight`` is
    free of units and image size.

    Copy limit: the *offset* of ``z_p`` is its exemplar corner minus its
    output corner; ``n(o)`` centres sharing one offset are a region copied
    verbatim. With ``limit`` = ``copy_limit`` x exemplar area / spacing² (the
    number of grid centres of a copied region covering that fraction of the
    exemplar), a candidate whose offset is shared by ``n > limit`` centres
    pays ``_COPY_PENALTY * scale * (n / limit - 1)``: the penalty grows with
    the excess, so the members with the closest alternatives (at the region's
    rim) leave first and the region shrinks from its edges.
    """

    def __init__(self, ex, centers, weight, copy_limit):
        n = len(centers)
        g = ex.g / ex.g.sum()
        self.kernel = fft_convolve(ex.g, g[::-1, ::-1])  # correlation, (2w-1, 2w-1), A(0) = sum g^2 / sum g
        self.self_weight = float(self.kernel[ex.size - 1, ex.size - 1])
        self.shape = ex.view.shape[:2]
        omega = n * float(ex.g.sum()) / len(ex)
        variance = float(ex.image.reshape(-1, ex.image.shape[-1]).var(axis=0).mean())
        self.factor = weight * variance * float(ex.weights.sum()) / omega
        self.penalty = np.zeros(len(ex))
        self.own = 0.0
        self.offsets = None
        self.centers = centers
        self.span = int(max(ex.image.shape[:2]) + centers.max() + ex.size + 2)
        spacing = max(1, int(np.diff(np.unique(centers[:, 1]))[:1].max(initial=1)))
        self.copy_limit = None
        if copy_limit is not None:  # the limit as a number of grid centres sharing one offset
            self.copy_limit = max(1.0, copy_limit * ex.image.shape[0] * ex.image.shape[1] / spacing**2)
        self.copy_factor = _COPY_PENALTY * variance * float(ex.weights.sum())

    def update(self, ex, zidx):
        count = np.zeros(self.shape)
        np.add.at(count, (ex.corner[zidx, 0], ex.corner[zidx, 1]), 1.0)
        occ = fft_convolve(count, self.kernel, mode="same")
        self.penalty = self.factor * np.maximum(occ[ex.corner[:, 0], ex.corner[:, 1]], 0.0)
        self.own = self.factor * self.self_weight  # a z_p's own share of its occurrence
        self.offsets = None
        if self.copy_limit is not None:
            key = self.offset_key(ex, zidx, self.centers)
            offsets, counts = np.unique(key, return_counts=True)
            over = counts > self.copy_limit  # only the offsets over the limit pay: the others' penalty is 0
            if over.any():
                self.offsets = offsets[over]
                self.excess = self.copy_factor * (counts[over] / self.copy_limit - 1.0)

    @property
    def binding(self):
        """Whether any candidate can pay: an occurrence penalty, or an offset over the copy limit."""
        return self.factor > 0 or self.offsets is not None

    def offset_key(self, ex, cand, at):
        """One integer per (exemplar neighbourhood ``cand``, output centre ``at``) pair: its offset."""
        off = ex.corner[cand] - (at - ex.size // 2) + self.span
        return off[:, 0] * (4 * self.span) + off[:, 1]

    def copy_penalty(self, ex, cand, at):
        """The copy limit's penalty of taking neighbourhoods ``cand`` at output centres ``at``."""
        if self.offsets is None:
            return 0.0
        key = self.offset_key(ex, cand, at)
        k = np.clip(np.searchsorted(self.offsets, key), 0, len(self.offsets) - 1)
        return np.where(self.offsets[k] == key, self.excess[k], 0.0)


class _Completeness:
    """The completeness term of the bidirectional similarity (Simakov et al. 2008) for one stage.

    Every exemplar neighbourhood ``q_j`` whose corner lies on a grid of the
    stage's spacing is matched to its nearest output neighbourhood ``x_p(j)``;
    the term is ``scale * sum_j (||x_p(j) - q_j||^2 + ε²)^(r/2)`` with
    ``scale = weight * |X†| / |J|``, so that ``weight = 1`` gives the two
    directions equal weight per neighbourhood, as in Simakov et al.'s
    ``d = d_complete / N_S + d_cohere / N_T`` multiplied by ``N_T``.
    In the E-step ``q_j`` is one more neighbourhood averaged at the centre
    ``p(j)`` (their update rule: every pixel the weighted mean of the colours
    the coherence and the completeness votes give it).

    With the PatchMatch M-step, ``p(j)`` is any output neighbourhood (found
    by PatchMatch from the exemplar to the output, warm-started from the last
    ``p(j)``); with an index M-step it is one of the grid centres ``X†``.
    """

    def __init__(self, ex, centers, weight, spacing):
        on_grid = (ex.corner[:, 0] % spacing == 0) & (ex.corner[:, 1] % spacing == 0)
        self.jidx = np.flatnonzero(on_grid)
        self.scale = weight * len(centers) / max(1, len(self.jidx))

    def search(self, ex, x, centers, mode, current, method, rng, warp=None):
        """``p(j)`` (output centres) of every ``q_j`` among ``centers``, never farther than ``current``, and ``ρ_j``."""
        feats = _features(ex.patches(self.jidx), ex.mu).astype(np.float64, copy=False)
        q = _features(_neighbourhoods(x, centers, ex.size, mode, warp), ex.mu)
        index = PatchIndex(q.astype(np.float32), weights=ex.weights, method=method, rng=rng)
        found = centers[index.query(feats.astype(np.float32), k=1)[0][:, 0]]
        rho = _rho_at(ex, x, found, mode, self.jidx, warp)
        if current is not None:
            keep = _rho_at(ex, x, current, mode, self.jidx, warp)
            better = rho < keep
            found = np.where(better[:, None], found, current)
            rho = np.where(better, rho, keep)
        return found, rho

    def search_field(self, ex, x, mode, current, iterations, rng):
        """The same by PatchMatch over every output neighbourhood (wrapping around a tileable output)."""
        w = ex.size
        pad = w - 1 if mode == "wrap" else 0
        image = np.pad(x, ((0, pad), (0, pad), (0, 0)), mode="wrap") if pad else x
        start = None if current is None else _unwrap(current, x.shape[:2], w, pad)[:, None]
        # float (H, W, C) arrays: x may overshoot [0, 1] a little, and has guide channels when guided
        field, d2 = patchmatch_features(ex.image, image, w, centers=ex.centers(self.jidx), init=start,
                                        iterations=iterations, exemplar_mask=None, pixel_weights=ex.g,
                                        mode="valid", penalty=None, rng=rng)
        found = field[:, 0]
        if pad:
            found = np.mod(found, x.shape[:2])
        return found, d2[:, 0].astype(np.float64)


def _unwrap(at, shape, w, pad):
    """Centres ``at`` of a tileable output as centres in its wrap-padded copy (the patch inside it)."""
    lo = w // 2
    hi = np.asarray(shape) + pad - w + w // 2
    out = at.copy()
    for axis in range(2):
        low = out[:, axis] < lo
        out[low, axis] += shape[axis]
        out[:, axis] = np.minimum(out[:, axis], hi[axis])
    return out


def _rho_at(ex, x, at, mode, zidx, warp=None):
    """``ρ`` between the output neighbourhoods centred at ``at`` and the exemplar's ``zidx``, in parts."""
    out = np.empty(len(at))
    step = max(1, _E_STEP_VALUES // ex.weights.shape[0])

    def part(i):  # each part's own rows of ``out``: the parts may run on several threads
        p = slice(i * step, (i + 1) * step)
        q = _features(_neighbourhoods(x, at[p], ex.size, mode, warp), ex.mu)
        out[p] = sq_distances(q, _features(ex.patches(zidx[p]), ex.mu), ex.weights)

    parts = -(-len(at) // step)
    parallel_for(part, parts, max_threads() if parts > 1 else 1)
    return out


def _m_step(ex, x, centers, mode, zidx, constraint, memo=None, tolerance=0.0, occurrence=None, warp=None,
            iterations=0, rng=None):
    """z_p <- nearest exemplar neighbourhood of x_p (modified by Algorithm 2 under constraints).

    Returns the new indices and ``ρ_p`` of every (x_p, z_p) pair in float64.
    A candidate replaces the current ``z_p`` only if it is strictly better, so
    an approximate index can never make the step worse than keeping ``z_p``.

    With a ``memo`` of the previous searches, a neighbourhood is searched
    again only if ``x_p`` moved since its last search by more than
    ``tolerance`` times the distance it had then: if ``x_p`` moved by ``δ``
    (weighted norm) from a query whose nearest neighbour was at distance
    ``d``, no exemplar neighbourhood can be closer to the new ``x_p`` than
    ``d - δ`` while the current ``z_p`` is at most ``d + δ`` away (triangle
    inequality), so skipping loses at most ``2δ <= 2 tolerance d`` of the
    distance. Skipped neighbourhoods keep their ``z_p`` (their ``ρ_p`` is
    recomputed exactly), so the step still never raises the energy.

    With an ``occurrence`` penalty (Kaspar et al. 2015), candidates are ranked
    by ``ρ + penalty`` instead: the index's ``_OCCURRENCE_CANDIDATES`` nearest
    and the coherent candidates of every neighbourhood (searched or not,
    since the penalty changes as the others move).

    With a :class:`_Warp` (orientation and scale fields) ``x_p`` is the
    neighbourhood sampled in its frame, and the coherent candidates follow
    the frames. With ``iterations > 0`` (fields on a large stage) no index
    is built: PatchMatch runs on the stack of sampled ``x_p`` instead, from
    the current ``z_p``: each iteration ranks, for every searched
    neighbourhood at once, the coherent candidates of its four grid
    neighbours (propagation, in the frames) and one random exemplar
    neighbourhood within radii halving from the exemplar's size down to one
    pixel around its current ``z_p`` (random search), keeping the nearest.
    """
    q = _features(_neighbourhoods(x, centers, ex.size, mode, warp), ex.mu).astype(np.float64, copy=False)
    n = len(centers)
    stale = np.ones(n, dtype=bool)
    if memo is not None and zidx is not None and tolerance > 0:
        moved = sq_distances(q, memo.q, ex.weights)
        stale = ~np.isfinite(memo.rho) | (moved > tolerance**2 * (memo.rho + ex.eps2))
    constrained = np.zeros(n, dtype=bool)  # neighbourhoods that touch constrained pixels
    if constraint is not None:
        m, t, lam = constraint
        mp = extract(m[..., None], centers, ex.size, mode=mode)[..., 0]  # (N, w, w)
        constrained = mp.reshape(n, -1).max(axis=1) > 0
    sel = np.flatnonzero(constrained & stale)
    free = np.flatnonzero(stale & ~constrained)
    pen = None if occurrence is None else occurrence.penalty
    if zidx is None:
        new = np.zeros(n, dtype=np.int64)
        rho = np.full(n, np.inf)
        score = np.full(n, np.inf)
    else:
        new = zidx.copy()
        rho = sq_distances(q, _features(ex.patches(zidx), ex.mu), ex.weights)
        score = rho.copy()
        if pen is not None:  # the current z_p's own share of its occurrence does not count
            score += pen[zidx] - occurrence.own + occurrence.copy_penalty(ex, zidx, centers)

    def rank(rows, cand):
        if rows.size == 0:  # e.g. every neighbourhood touches a constrained pixel
            return
        r = sq_distances(q[rows], _features(ex.patches(cand), ex.mu), ex.weights)
        s = r if pen is None else r + pen[cand] + occurrence.copy_penalty(ex, cand, centers[rows])
        better = s < score[rows]
        rows = rows[better]
        new[rows], rho[rows], score[rows] = cand[better], r[better], s[better]

    if free.size and iterations:  # PatchMatch over the stack of sampled neighbourhoods
        for _ in range(iterations):
            for c in (_coherent_candidates(ex, centers, new, warp.inverse) + _random_candidates(ex, new, rng)):
                rows = free[c[free] != new[free]]  # a candidate equal to the current z_p cannot beat it
                rank(rows, c[rows])
    elif free.size:
        k = 1 if pen is None else min(_OCCURRENCE_CANDIDATES, len(ex))
        found = ex.index.query(q[free].astype(np.float32), k=k)[0]
        for j in range(k):
            rank(free, found[:, j])
    if zidx is not None and pen is not None:
        # coherent candidates (Ashikhmin 2001): the z of the 4 grid neighbours shifted by the
        # offset to them, ranked like the index's answers
        rows = np.flatnonzero(~constrained)
        for c in _coherent_candidates(ex, centers, new, None if warp is None else warp.inverse):
            rank(rows, c[rows])
    if sel.size:
        new, rho = _m_step_constrained(ex, x, centers, mode, zidx, constraint, q, mp, sel, new, rho)
    if memo is not None:
        memo.q[stale] = q[stale]
        memo.rho[stale] = rho[stale]
        memo.searched += int(stale.sum())
    return new, rho


def _m_step_field(ex, x, centers, mode, start, iterations, rng, occurrence=None, sets=None, workspace=None):
    """M-step by PatchMatch (Barnes et al. 2009): every ``z_p`` from a field warm-started at ``start``.

    With k-coherence ``sets`` (``candidates="k-coherent"``), the random
    search gives way to them: every continuation of a neighbour's ``z`` is
    offered with the ``k - 1`` exemplar neighbourhoods most like it (Tong et
    al. 2002).

    ``start`` holds an exemplar centre per neighbourhood (the current
    ``z_p``, or the previous stage's carried over). PatchMatch replaces a
    ``z_p`` only by a strictly nearer one (the same weighted distance ``ρ_p``
    with the fall-off), so the step never raises the energy. With an
    ``occurrence`` penalty or copy limit, candidates are ranked by ``ρ_p``
    plus the penalty instead, as in :func:`_m_step`. ``workspace``: the
    stage's dict that PatchMatch copies the ``x_p`` into (reused, not fresh
    memory, in every M-step). Returns the new indices and their ``ρ_p``.
    """
    w = ex.size
    penalty = None
    if occurrence is not None:
        def penalty(q, c):
            idx = ex.grid[c[:, 0] - w // 2, c[:, 1] - w // 2]
            return occurrence.penalty[idx] + occurrence.copy_penalty(ex, idx, centers[q])
    mask = None if ex.valid.all() else ex.valid
    # x is float (H, W, C), with values beyond [0, 1] where an up-sampled level or the gradient solve
    # overshoots, and more than 4 channels with guide channels (``ex.guided``): the checked entry
    field, _, d2 = patchmatch_features(x, ex.image, w, centers=centers, init=start[:, None], iterations=iterations,
                                       exemplar_mask=mask, pixel_weights=ex.g, mode=mode, penalty=penalty, rng=rng,
                                       sets=sets, workspace=workspace, distances=True)
    corner = field[:, 0] - w // 2
    new = ex.grid[corner[:, 0], corner[:, 1]]
    return new, d2[:, 0].astype(np.float64)  # ρ_p: the distances, without the penalty that ranked them


def _carried_field(record, level, centers):
    """The last stage's ``z_p`` carried to ``centers`` at ``level``: each centre's exemplar position as
    the nearest old centre's source plus the offset to it (Section 3.2's up-sampling, for the field)."""
    prev = record["stages"][-1]
    dense = _source_map(record["centers"], record["sources"], prev.shape)
    f = 2 ** (prev.level - level)
    pos = np.minimum(centers // f, np.asarray(prev.shape) - 1)
    return np.rint(dense[pos[:, 0], pos[:, 1]] * f + (centers - pos * f)).astype(np.int64)


def _m_step_constrained(ex, x, centers, mode, zidx, constraint, q, mp, sel, new, rho):
    """Algorithm 2 for the neighbourhoods ``sel`` that touch constrained pixels."""
    m, t, lam = constraint
    # Algorithm 2: minimise ||x_p - v||^2 + λ E_c(y) = ρ(x_p, v) + λ sum_k m_k (v_k - x^c_k)^2 over v.
    # The per-patch weights g + λ m differ from patch to patch, so no single index
    # holds them: fetch candidates for the completed-square query
    # (g x + λ m x^c) / (g + λ m) and re-rank them by the exact criterion.
    xp = extract(x, centers[sel], ex.size, mode=mode)
    tp = extract(t, centers[sel], ex.size, mode=mode)
    g = ex.g[None, :, :, None]
    lm = lam * mp[sel][..., None]
    blended = ((g * xp + lm * tp) / (g + lm)).reshape(len(sel), -1)
    # the constraint is on values only: the query keeps x_p's own differences
    qb = np.concatenate([blended, q[sel, blended.shape[1]:]], axis=1)
    k = min(_CONSTRAINED_CANDIDATES, len(ex))
    cands = ex.index.query(qb.astype(np.float32), k=k)[0]
    if zidx is not None:  # the current z_p competes too (ties keep it)
        cands = np.concatenate([cands, zidx[sel, None]], axis=1)
    lm_flat = np.broadcast_to(lm, xp.shape).reshape(len(sel), -1)
    tflat = tp.reshape(len(sel), -1)
    scores = np.empty(cands.shape)
    rhos = np.empty(cands.shape)
    for j in range(cands.shape[1]):
        v = ex.patches(cands[:, j])
        rhos[:, j] = sq_distances(q[sel], _features(v, ex.mu), ex.weights)
        diff = v.reshape(len(sel), -1) - tflat
        scores[:, j] = rhos[:, j] + np.einsum("ij,ij->i", lm_flat * diff, diff)
    # ties keep the current z_p (the last column) or the nearer candidate
    best = cands.shape[1] - 1 - np.argmin(scores[:, ::-1], axis=1) if zidx is not None else np.argmin(scores, axis=1)
    new = new.copy()
    rho = rho.copy()
    new[sel] = cands[np.arange(len(sel)), best]
    rho[sel] = rhos[np.arange(len(sel)), best]
    return new, rho


def _frame_terms(ex, centers, mode, constraint, channels):
    """The parts of Algorithm 2's M-step criterion that only the constraint sets, fixed for a stage:
    ``W_p = g + λ m_p`` and ``λ m_p x^c_p`` per centre (float32), or None without a constraint."""
    if constraint is None:
        return None
    m, t, lam = constraint
    w, n = ex.size, len(centers)
    nv = w * w * channels
    lm = lam * np.repeat(extract(m[..., None], centers, w, mode=mode).reshape(n, -1), channels, axis=1)
    lm = lm.astype(np.float32)
    tp = extract(t, centers, w, mode=mode).reshape(n, -1).astype(np.float32, copy=False)
    wq = np.repeat(ex.weights.astype(np.float32)[None], n, axis=0)
    wq[:, :nv] += lm
    return wq, lm * tp


def _m_step_frame(ex, x, centers, mode, zidx, terms, prior, search):
    """Algorithm 2's M-step for an animation frame, over coherent candidates.

    The candidates for each ``z_p`` are the current ``z_p``, the previous
    frame's correspondence carried along the flow (``prior``), the ``z`` of
    the four grid neighbours shifted by the offset to them (coherence, as in
    Ashikhmin 2001) and, if ``search``, a searched one: ``search(x, b)``
    returns it (PatchMatch's nearest of ``x_p``), or ``search=True`` takes the
    index's nearest neighbour of the completed-square query. They are ranked
    by the exact criterion
    ``ρ(x_p, v) + λ E_c = ||v - b_p||^2_{W_p} + const_p`` with
    ``W_p = g + λ m_p`` and ``b_p = (g x_p + λ m_p x^c_p) / W_p`` (values
    only; the differences keep ``x_p``'s), in float32; ties keep the current
    ``z_p``. ``terms`` is :func:`_frame_terms` of the constraint (None: no
    constraint). Returns the new indices and ``ρ_p`` in float64.
    """
    n = len(centers)
    q = _features(extract(x, centers, ex.size, mode=mode), ex.mu).astype(np.float32, copy=False)
    weights = ex.weights.astype(np.float32)
    wq, b = np.broadcast_to(weights, q.shape), q
    if terms is not None:
        wq, lmtp = terms
        nv = lmtp.shape[1]
        b = q.copy()
        b[:, :nv] = (weights[:nv] * q[:, :nv] + lmtp) / wq[:, :nv]
    cols = [c for c in (zidx, prior) if c is not None]
    if cols:
        cols += _coherent_candidates(ex, centers, cols[0])
    if callable(search):
        cols.append(search(x, b))
    elif search or not cols:
        cols.append(ex.index.query(b, k=1)[0][:, 0])
    cands = np.stack(cols, axis=1)
    choice, _ = nearest_candidates(b, cands, vectors=ex.feats, weights=wq)  # first minimum: ties keep z_p
    new = cands[np.arange(n), choice]
    return new, sq_distances(ex.feats[new], q, weights).astype(np.float64)


def _random_candidates(ex, zidx, rng):
    """PatchMatch's random search (Barnes et al. 2009): per ``z``, one neighbourhood at a uniform offset within
    each radius ``R, R/2, ..., 1`` (``R`` the exemplar's larger side) of its corner."""
    out = []
    radius = max(ex.view.shape[:2])
    while radius >= 1:
        corner = ex.corner[zidx] + rng.integers(-radius, radius + 1, size=(len(zidx), 2))
        out.append(ex.lookup(corner, zidx))
        radius //= 2
    return out


def _coherent_candidates(ex, centers, zidx, inverse=None):
    """For each centre, the ``z`` of its 4 grid neighbours shifted back by the offset to them (with the fields'
    ``inverse`` frames ``A^{-1}`` per centre: by that offset in the exemplar's frame, ``A^{-1} e``).

    The grid wraps round at its ends. ``centers`` may be a part of a grid (hard constraints keep only the
    neighbourhoods near unknown pixels): a centre whose neighbour is missing gets its own ``z`` back.
    """
    grid, gi, gj = grid_cells(centers)
    z = ex.corner[zidx]
    out = []
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        nb = grid[(gi + di) % grid.shape[0], (gj + dj) % grid.shape[1]]
        has = nb >= 0
        nb = np.where(has, nb, np.arange(len(centers)))
        e = centers[nb] - centers
        if inverse is not None:
            e = np.einsum("nij,nj->ni", inverse, e)
        corner = np.where(has[:, None], z[nb] - e, z)
        out.append(ex.lookup(corner, zidx))
    return out


def _source_map(centers, sources, shape):
    """Dense correspondence of a frame: exemplar position of every pixel, from the
    ``z_p`` whose centre is nearest (``sources + (q - centre)``). ``centers``: a row-major grid, or a
    part of one (hard constraints: :func:`_touching_free`)."""
    if grid_axes(centers[:, 0], centers[:, 1]) is None:  # a part of a grid: the nearest centre by distance
        at = np.zeros(tuple(shape) + (2,), np.float64)
        defined = np.zeros(tuple(shape), bool)
        at[centers[:, 0], centers[:, 1]], defined[centers[:, 0], centers[:, 1]] = sources, True
        return _extend_nearest(at, defined)
    q = np.stack(np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij"), axis=-1)
    near = []
    for axis, length in enumerate(shape):
        grid = np.unique(centers[:, axis])
        pos = np.arange(length)
        k = np.clip(np.searchsorted(grid, pos), 1, len(grid) - 1)
        near.append(np.where(pos - grid[k - 1] <= grid[k] - pos, k - 1, k) if len(grid) > 1 else np.zeros_like(pos))
    k = near[0][:, None] * len(np.unique(centers[:, 1])) + near[1][None, :]
    return (sources[k] + q - centers[k]).astype(np.float64)


def _dominant_sources(ex, centers, zidx, omega, shape, mode, warp=None):
    """``(H, W, 2)``: at every pixel, the exemplar pixel of the ``z_p`` of largest ``ω_p g(x - p)``.

    For one offset inside the neighbourhood, distinct centres give distinct pixels, so the largest
    weight is kept by plain assignment, offset by offset. With fields (:class:`_Warp`) the weight is
    ``ω_p g(d)`` times the bilinear weight of the sample on the pixel. A pixel that no
    neighbourhood covers (hard constraints, away from the free pixels: :func:`_touching_free`) takes
    the source of the nearest covered pixel, offset by the distance to it and kept inside the
    exemplar, so the map stays a copy map.
    """
    if warp is not None:
        return _dominant_warped(ex, zidx, omega, shape, warp)
    out, best = _dominant_grid(ex, centers, zidx, omega, shape, mode)
    covered = best > -np.inf
    if covered.all() or not covered.any():
        return out
    return np.clip(_extend_nearest(out, covered), 0, np.asarray(ex.image.shape[:2]) - 1)  # covered: unchanged


def _extend_nearest(positions, defined):
    """``positions`` ``(H, W, 2)`` where ``defined``; elsewhere the nearest defined pixel's, moved by the
    offset to it (a map that continues its nearest copy)."""
    near = ndimage.distance_transform_edt(~defined, return_distances=False, return_indices=True)
    return positions[near[0], near[1]] + np.moveaxis(np.indices(defined.shape) - near, 0, -1)


def _dominant_grid(ex, centers, zidx, omega, shape, mode):
    """:func:`_dominant_sources` of plain neighbourhoods: the map and the largest weight at every pixel
    (-inf where no neighbourhood reaches)."""
    w = ex.size
    corner_out = centers - w // 2  # the E-step's patch placement (PatchSum: centred at the centre)
    corner_ex = ex.corner[zidx]
    best = np.full(tuple(shape), -np.inf)
    out = np.zeros(tuple(shape) + (2,), np.int64)
    for i in range(w):
        for j in range(w):
            r, c = corner_out[:, 0] + i, corner_out[:, 1] + j
            if mode == "wrap":
                r, c = r % shape[0], c % shape[1]
            else:
                keep = (r >= 0) & (r < shape[0]) & (c >= 0) & (c < shape[1])
                r, c = r[keep], c[keep]
            value = (omega * ex.g[i, j]) if mode == "wrap" else (omega * ex.g[i, j])[keep]
            src = corner_ex + (i, j) if mode == "wrap" else (corner_ex + (i, j))[keep]
            better = value > best[r, c]
            best[r[better], c[better]] = value[better]
            out[r[better], c[better]] = src[better]
    return out, best


def _dominant_warped(ex, zidx, omega, shape, warp):
    """:func:`_dominant_sources` of rotated, scaled neighbourhoods: each sample ``p + A(p) d`` gives its
    exemplar pixel ``z_p(d)`` to its four bilinear taps, weighted ``ω_p g(d)`` times the tap's weight."""
    w = ex.size
    corner_ex = ex.corner[zidx]
    best = np.full(shape[0] * shape[1], -np.inf)
    out = np.zeros((shape[0] * shape[1], 2), np.int64)
    for k, d in enumerate(warp.d):
        index, tap = taps(warp.centers + warp.a @ d, shape[0], shape[1], warp.wrap)
        value = ((omega * ex.g.flat[k])[:, None] * tap).reshape(-1)
        src = np.repeat(corner_ex + divmod(k, w), 4, axis=0)
        order = np.argsort(value, kind="stable")  # ascending: of repeated pixels the largest is assigned last
        index, value, src = index.reshape(-1)[order], value[order], src[order]
        better = value > best[index]
        best[index[better]] = value[better]
        out[index[better]] = src[better]
    return out.reshape(tuple(shape) + (2,))


def _energy(rho, r, eps2, x, constraint):
    """E = sum_p (ρ_p + ε²)^{r/2} + λ E_c(x): the robust eq. 1 plus eq. 2."""
    e = float(np.sum((rho + eps2) ** (r / 2.0)))
    if constraint is not None and np.isfinite(constraint[2]):  # hard constraints hold by construction
        m, t, lam = constraint
        e += lam * float(np.einsum("ij,ijc->", m, (x - t) ** 2))
    return e


def _nearest_label(guide, labels):
    """``(H, W)`` index of the label vector nearest to every pixel's guide channels ``(H, W, G)``."""
    return ((guide[..., None, :] - labels) ** 2).sum(-1).argmin(-1)


def _histogram_groups(ex, n_colours, free, shape, guide=None, labels=None):
    """What histogram matching matches after every E-step: ``(where, targets)`` pairs.

    ``where`` selects output pixels (None: all of them) and ``targets`` holds, per colour channel, the
    sorted values they get (exact quantile assignment, :mod:`texsynth.core.histogram`). Without labels:
    one pair, the pixels ``free`` of constraints (None: every pixel) against every exemplar pixel that
    may be copied. With label guides (``labels``, the label vectors scaled as the guide channels): one
    pair per label, its output pixels against the exemplar pixels of the same label, each pixel's label
    being the label vector nearest to its guide channels at this level (the pyramid blurs them); a
    label the exemplar level does not show takes every exemplar pixel. Matching every output pixel to the
    whole exemplar would shift the colours wherever the output's labels cover other proportions than
    the exemplar's. The guide channels are given, not matched.
    """
    allowed = ex.valid > 0.5
    parts = [(free, allowed)]
    if labels is not None:
        out_label, ex_label = _nearest_label(guide, labels), _nearest_label(ex.image[..., n_colours:], labels)
        parts = []
        for label in range(len(labels)):
            where = out_label == label if free is None else (out_label == label) & free
            own = allowed & (ex_label == label)
            parts.append((where, own if own.any() else allowed))
    groups = []
    for where, source in parts:
        count = shape[0] * shape[1] if where is None else int(where.sum())
        if count:
            pixels = ex.image[source]  # (pixels, C)
            groups.append((where, [quantile_targets(np.sort(pixels[:, c]), count).astype(ex.image.dtype)
                                   for c in range(n_colours)]))
    return groups


def _match_channel(image, c, where, targets):
    """Give channel ``c`` of ``image`` (at ``where``, or everywhere if None) the histogram ``targets``, in place."""
    if where is None:
        image[..., c] = match_to_targets(image[..., c], targets, False)[0]
    else:
        image[..., c][where] = match_to_targets(image[..., c][where], targets, False)[0]


# --------------------------------------------------------------------------- one stage
def _run_stage(ex, x, shape, level, opts, constraint, rng, record, progress, guide=None, fields=None, labels=None):
    """Algorithm 1 (or 2) at one level with one neighbourhood size; ``guide`` ``(H, W, G)``: the output
    guide at this level, the last ``G`` channels of ``x`` and of the exemplar (given, never synthesised);
    ``labels`` ``(L, G)``: the label vectors when the guides are label maps (:func:`_histogram_groups`);
    ``fields`` ``(theta, scale)``: the orientation and scale fields at this level (:class:`_Warp`)."""
    t0 = time.perf_counter()
    w = ex.size
    spacing = opts.grid(w)
    mode = opts.mode
    centers = grid_centers(shape, w, spacing, mode=mode)
    coords = opts.coords  # animation frame: the previous frame's correspondence, warped
    # hard constraints (λ = ∞) are in x_p already: the M-step is the plain nearest neighbour, and the
    # E-step weighs each neighbourhood by its confidence (Wexler et al. 2007)
    hard = constraint is not None and np.isinf(constraint[2])
    if hard and coords is None:
        free = _touching_free(constraint[0], centers, w, spacing, mode)
        centers = centers[free] if free.any() else centers  # nothing free: the target, as every E-step makes it
    warp = None if fields is None else _Warp(centers, w, *fields, shape, mode)
    stage = StageInfo(level=level, size=w, shape=tuple(shape), spacing=spacing, neighborhoods=len(centers),
                      exemplar_neighborhoods=len(ex), first=len(record["energy"]))
    nn = 0.0
    r, mu, eps2 = opts.r, opts.mu, ex.eps2
    values = float(ex.weights.sum())

    prior = None if coords is None else ex.lookup(coords[centers[:, 0], centers[:, 1]] - w // 2, 0)
    frame_terms = None if coords is None else _frame_terms(ex, centers, mode, constraint, ex.image.shape[-1])

    searched = None if hard else constraint
    confidence = None
    if hard and coords is None and opts.confidence is not None:
        confidence = _confidence(constraint[0], centers, w, mode, opts.confidence)
    use_field = opts.field(searched, ex, len(centers))
    stack = use_field and warp is not None  # fields: PatchMatch on the sampled neighbourhoods (_m_step)
    use_field = use_field and not stack
    memo = _SearchMemo(n=len(centers), dim=None if use_field else ex.weights.shape[0])
    weight, limit = opts.occurrence, opts.copy_limit
    occurrence = None
    finest = level == 0 and record["levels"] > 1  # the finest of several levels refines the arrangement
    if opts.coarse_copy_limit and finest:
        limit = _FINE_COPY_LIMIT  # only outlying copies are cut
    if (weight > 0 or limit is not None) and coords is None:
        occurrence = _Occurrence(ex, centers, weight, limit)
    completeness = None
    lam = 0.0 if opts.coarse_completeness and finest else opts.completeness
    if lam > 0 and coords is None:
        completeness = _Completeness(ex, centers, lam, spacing)
    stage.completeness_weight = lam if completeness is not None else 0.0
    stage.copy_limit = limit if occurrence is not None else None
    n = len(centers)
    sets = None
    if opts.candidates == "k-coherent" and use_field and coords is None:
        sets = coherence_sets(ex.image, ex.size, opts.k, pixel_weights=ex.g, rng=rng)
    workspace = {}  # the M-steps' PatchMatch copies the x_p into the same memory every time
    carried = None
    if (use_field or stack) and x is not None:  # the last stage's field, or random neighbourhoods after a given image
        carried = rng.integers(len(ex), size=n)
        if record["stages"]:
            carried = ex.lookup(_carried_field(record, level, centers) - w // 2, carried)

    def frame_field(x, b):
        """A frame's searched candidates: PatchMatch's nearest of every ``x_p``, one iteration from the
        prior (the last frame's correspondence carried along the flow, already close)."""
        if prior is None:
            return _m_step_field(ex, x, centers, mode, ex.centers(rng.integers(len(ex), size=n)),
                                 _FIELD_ITERATIONS_FIRST, rng)[0]
        return _m_step_field(ex, x, centers, mode, ex.centers(prior), _FIELD_ITERATIONS, rng)[0]

    def m_step(x, zidx):
        stage.m_steps += 1
        if use_field and coords is None:
            start = zidx if zidx is not None else carried
            if occurrence is not None:
                occurrence.update(ex, start)
            memo.searched += n
            its = _FIELD_ITERATIONS_FIRST if stage.m_steps == 1 else _FIELD_ITERATIONS
            # k-coherent candidates continue a field: the synthesis's first M-step, from random
            # neighbourhoods, has none worth continuing and searches at random
            first = stage.m_steps == 1 and not record["stages"]
            # a penalty that binds nowhere changes no ranking: the plain M-step
            occ = occurrence if occurrence is not None and occurrence.binding else None
            return _m_step_field(ex, x, centers, mode, ex.centers(start), its, rng, occ,
                                 None if first else sets, workspace)
        if coords is None:
            occ = None
            if occurrence is not None and zidx is not None:
                occurrence.update(ex, zidx)
                occ = occurrence if occurrence.binding else None
            if not stack:
                return _m_step(ex, x, centers, mode, zidx, searched, memo, _RESEARCH_TOLERANCE, occ, warp)
            its = _FIELD_ITERATIONS_FIRST if stage.m_steps == 1 else _FIELD_ITERATIONS
            return _m_step(ex, x, centers, mode, carried if zidx is None else zidx, searched, memo,
                           _RESEARCH_TOLERANCE, occ, warp, its, rng)
        # searched once per stage (PatchMatch from the prior, or the index); later iterations rank
        # coherent candidates
        memo.searched += len(centers) if zidx is None else 0
        return _m_step_frame(ex, x, centers, mode, zidx, frame_terms, prior,
                             search=(frame_field if use_field else True) if zidx is None else False)

    # animation frames: the E-step may assemble the z_p with a narrower fall-off (frame_falloff)
    ga = None if opts.assembly is None else gaussian_falloff(w, sigma=max(spacing, 1) * opts.assembly)
    g0 = None
    if x is None:  # bootstrap: z_p^0 <- random neighbourhood in Z
        state, rho = (rng.integers(len(ex), size=n), None), None
        # The first x is assembled from these neighbourhoods with a sharp fall-off
        # (σ = spacing/4), so each pixel comes from the nearest centre: averaging ~16
        # random neighbourhoods per pixel gives a flat image whose nearest exemplar
        # neighbourhoods are the flattest ones, and the synthesis collapses onto them.
        g0 = gaussian_falloff(w, sigma=max(spacing, 1) / 4.0)
    n_colours = ex.image.shape[-1] - (0 if guide is None else guide.shape[-1])
    if guide is not None and x is not None:  # the up-sampled guide channels -> this level's output guide
        x = x.copy()
        x[..., n_colours:] = guide
    current = x if x is not None else np.zeros(tuple(shape) + (ex.image.shape[-1],), ex.image.dtype)

    groups = []
    if opts.histogram and searched is None and coords is None:  # no constraint, or hard ones
        # with hard constraints only the pixels nothing constrains are matched (uncrop, hole filling)
        free = None if constraint is None else constraint[0] < 1e-6
        groups = _histogram_groups(ex, n_colours, free, shape, guide, labels)
    threads = max_threads() if groups else 1  # the channels are matched at once (sorting releases the GIL)

    def e_step(state, omega, it):
        nonlocal current
        zidx, pj = state
        omega = np.ones(n) if omega is None else omega
        votes = None
        if pj is not None:  # the completeness votes: q_j averaged at its centre p(j)
            vote_w = completeness.scale * omega[n:]
            if occurrence is not None and occurrence.offsets is not None:
                # no vote for an offset already copied beyond the copy limit
                vote_w = vote_w * (occurrence.copy_penalty(ex, completeness.jidx, pj) == 0)
            votes = (completeness.jidx, pj, vote_w)
        g = g0 if it == 0 and g0 is not None else ga  # bootstrap assembly, frame assembly or ex.g
        current = _e_step(ex, zidx, centers, shape, omega[:n] if confidence is None else omega[:n] * confidence,
                          mode, mu, constraint, current, g=g, votes=votes, warp=warp)
        for where, targets in groups:  # the exemplar's colour histograms, against the E-step's wash-out
            parallel_for(lambda c: _match_channel(current, c, where, targets[c]), len(targets), threads)
        if guide is not None:  # the output's guide channels are given: reset after every E-step
            current[..., n_colours:] = guide
        return current

    def search(x, state):
        """M-step: ``z_p`` of every centre and, with the completeness term, ``p(j)`` of every ``q_j``."""
        nonlocal nn
        zidx, pj = state
        t1 = time.perf_counter()
        new, rho = m_step(x, zidx)
        changed = not np.array_equal(new, zidx)
        if completeness is not None:
            if use_field:
                new_pj, rho_j = completeness.search_field(ex, x, mode, pj, _FIELD_ITERATIONS_FIRST, rng)
            else:
                new_pj, rho_j = completeness.search(ex, x, centers, mode, pj, opts.index_method, rng, warp)
            changed = changed or not np.array_equal(new_pj, pj)
            pj, rho = new_pj, np.concatenate([rho, rho_j])
        nn += time.perf_counter() - t1
        return (new, pj), rho, changed

    if x is not None:
        state, rho, _ = search(x, (None, None))

    def log(rho, x):
        e = _energy(rho[:n], r, eps2, x, constraint)
        if completeness is not None:
            e += completeness.scale * float(np.sum((rho[n:] + eps2) ** (r / 2.0)))
        record["energy"].append(e)
        record["mse"].append(float(rho[:n].mean()) / values)
        record["stage"].append(len(record["stages"]))
        return record["energy"][-1]

    max_it = opts.max_iterations
    # the penalised M-step may raise E on purpose (it breaks up copies): only the paper's
    # test, unchanged z_p, ends such a stage early
    tolerance = opts.tolerance if occurrence is None else None

    def report(it, energy, stop):
        stage.iterations = it + 1
        progress.advance({"level": level, "size": w, "iteration": it, "energy": energy},
                         n=max_it - it if stop else 1)

    x, (zidx, _), rho, _, stage.converged = expectation_maximization(
        x, state, rho, e_step, search, log, max_iterations=max_it, tolerance=tolerance, r=r, eps2=eps2,
        on_iteration=report,
    )
    # for the source-coordinate map (computed once, after the last stage): what the last E-step weighs
    record["dominant"] = (level, ex, centers, zidx, irls_weights(rho[:n], r, eps2), tuple(shape), mode, warp)
    stage.seconds = time.perf_counter() - t0
    stage.nn_seconds = nn
    stage.searches = memo.searched
    record["stages"].append(stage)
    record["centers"], record["sources"] = centers, ex.centers(zidx)
    return x


# --------------------------------------------------------------------------- validation
def check_sizes(sizes, name="neighborhood_sizes"):
    if isinstance(sizes, numbers.Integral) and not isinstance(sizes, bool):
        sizes = (sizes,)
    try:
        sizes = tuple(sizes)
    except TypeError:
        raise TypeError(f"{name} must be an int or a sequence of ints, got {sizes!r}") from None
    if not sizes:
        raise ValueError(f"{name} is empty; pass e.g. (32, 16, 8)")
    out = [check_positive_int(s, name, minimum=2) for s in sizes]
    return tuple(sorted(set(out), reverse=True))


def check_mask(mask, shape, name):
    arr = np.asarray(mask)
    if arr.ndim == 3 and arr.shape[-1] == 1:
        arr = arr[..., 0]
    if arr.ndim != 2 or arr.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} (one weight per pixel), got shape {np.shape(mask)}")
    return as_float_array(arr, name).astype(np.float64)


def _check_like(image, shape, channels, name):
    arr, _ = with_channels(as_image(image, name))
    if arr.shape[:2] != tuple(shape) or arr.shape[-1] != channels:
        want = tuple(shape) + ((channels,) if channels > 1 else ())
        raise ValueError(f"{name} must have the output's shape {want} (channels as the exemplar), got shape {np.shape(image)}")
    return arr


def _schedule(sizes, ex_shapes, out_shapes):
    """Neighbourhood sizes per level (Section 3.2): only those that fit the sub-sampled exemplar.

    At full resolution a size fits if the exemplar holds at least one
    neighbourhood; at sub-sampled levels it must hold a real choice of them,
    so the exemplar must be at least twice the neighbourhood size.
    """
    plan = []
    for level, (es, os_) in enumerate(zip(ex_shapes, out_shapes)):
        room = min(es) if level == 0 else min(es) // 2
        plan.append(tuple(s for s in sizes if s <= room and s <= min(os_)))
    return plan


@dataclass
class _Problem:
    """The checked inputs of one synthesis: exemplar, output, constraints."""

    ex: np.ndarray  # (h, w, C) float
    grey: bool  # the exemplar had no channel axis
    shape: tuple  # output (H, W)
    sizes: tuple  # neighbourhood widths, largest first
    levels: int
    valid: np.ndarray  # (h, w) 1 where exemplar pixels may be copied
    constraint: tuple | None = None  # (mask, target, lambda) of eq. 2
    x_init: np.ndarray | None = None
    guide: np.ndarray | None = None  # (H, W, G) output guide, scaled; ex then holds the exemplar guide's G last channels
    fields: tuple | None = None  # (theta, scale), (H, W) each: the orientation and scale fields
    labels: np.ndarray | None = None  # (L, G) label vectors (scaled) when the guides are label maps


def _check_options(*, irls_exponent, relative_grid_spacing, max_iterations, tolerance, gradient_weight, tileable=False,
                   falloff=True, method="auto", occurrence_weight=0.0, copy_limit=None, completeness_weight=0.0,
                   histogram_matching=False, paper=False, coarse_copy_limit=False, coarse_completeness=False,
                   fields=False, confidence=None, candidates="all", k=4):
    """The scalar options of :func:`optimize_texture`, checked, as an :class:`_Options`."""
    candidates = check_candidates(candidates)
    k = check_positive_int(k, "k")
    if candidates == "k-coherent":
        # the k-coherent M-step is PatchMatch's propagation with the sets in place of its random search:
        # it goes where PatchMatch goes
        clash = ("gradient_weight > 0 (the gradient energy takes the index M-step)" if gradient_weight else
                 "preset='paper' (the paper's M-step searches a tree)" if paper else
                 "orientation/scale fields (rotated neighbourhoods take their own M-step)" if fields else
                 f"method={method!r} (an index M-step)" if method not in ("auto", "patchmatch") else None)
        if clash is not None:
            raise ValueError(f"candidates='k-coherent' does not combine with {clash}; pass candidates='all'")
    if confidence is not None and check_positive_float(confidence, "confidence", maximum=_MAX_WEIGHT) <= 1:
        raise ValueError(f"confidence must be None or a base gamma > 1 (Wexler et al.: 1.3), got {confidence!r}")
    return _Options(
        histogram=check_bool(histogram_matching, "histogram_matching"), paper=paper,
        coarse_copy_limit=coarse_copy_limit, coarse_completeness=coarse_completeness, fields=fields,
        confidence=None if confidence is None else float(confidence),
        r=check_in_range(irls_exponent, "irls_exponent", 0.0, 2.0, low_open=True),
        mu=check_positive_float(gradient_weight, "gradient_weight", allow_zero=True, maximum=_MAX_WEIGHT),
        spacing=check_in_range(relative_grid_spacing, "relative_grid_spacing", 0.0, 1.0, low_open=True),
        max_iterations=check_positive_int(max_iterations, "max_iterations", maximum=MAX_ITERATIONS),
        tolerance=check_positive_float(tolerance, "tolerance", allow_zero=True),
        tileable=check_bool(tileable, "tileable"),
        falloff=check_bool(falloff, "falloff"),
        method=search.check_field_method(method),
        occurrence=check_positive_float(occurrence_weight, "occurrence_weight", allow_zero=True, maximum=_MAX_WEIGHT),
        copy_limit=None if copy_limit is None else check_in_range(copy_limit, "copy_limit", 0.0, 1.0, low_open=True),
        completeness=check_positive_float(completeness_weight, "completeness_weight", allow_zero=True,
                                          maximum=_MAX_WEIGHT),
        candidates=candidates, k=k,
    )


def is_auto(value):
    return isinstance(value, str) and value == "auto"


def _check_preset(preset):
    if not isinstance(preset, str) or preset not in PRESETS:
        raise ValueError(f"preset must be one of {', '.join(map(repr, PRESETS))}, got {preset!r}")
    return preset


def scale_schedule(ex, shape):
    """Neighbourhood sizes and levels of preset ``"default"``, from the exemplar and the output.

    The largest neighbourhood is 64 pixels for an exemplar whose feature
    scale (:func:`texsynth.core.scale.feature_scale`) is above 32 pixels and
    32 otherwise, at most a quarter of the exemplar's smaller side; each
    level uses it, half of it and a quarter of it (none below 4 pixels, none
    above the output's smaller side). Levels: as many as keep the coarsest
    exemplar at least 32 pixels on its smaller side.
    """
    side = min(ex.shape[:2])
    largest = _LARGE_SIZE if feature_scale(ex) > _LARGE_FEATURES else _LARGE_SIZE // 2
    largest = max(4, min(largest, 2 ** int(np.log2(max(side // 4, 1)))))
    sizes = tuple(w for w in (largest, largest // 2, largest // 4) if 4 <= w <= min(shape)) or (min(largest, *shape),)
    levels = max(1, int(np.log2(side / _COARSEST_SIDE)) + 1)
    return sizes, levels


def _preset(preset, problem, *, tolerance, completeness_weight, copy_limit, histogram_matching):
    """The values of the ``"auto"`` options under ``preset`` (see :func:`optimize_texture`, Notes)."""
    ratio = problem.shape[0] * problem.shape[1] / (problem.ex.shape[0] * problem.ex.shape[1])
    if preset == "paper":
        auto = dict(tolerance=0.0, completeness_weight=0.0, copy_limit=None, histogram_matching=False)
    else:
        auto = dict(tolerance=_DEFAULT_TOLERANCE, completeness_weight=1.0, copy_limit=_DEFAULT_COPY_LIMIT,
                    histogram_matching=True)
    given = dict(tolerance=tolerance, completeness_weight=completeness_weight, copy_limit=copy_limit,
                 histogram_matching=histogram_matching)
    out = {k: auto[k] if is_auto(v) else v for k, v in given.items()}
    out["completeness_weight"] = check_positive_float(out["completeness_weight"], "completeness_weight",
                                                      allow_zero=True, maximum=_MAX_WEIGHT)
    # from 4x the exemplar's area the finest level only refines the arrangement: no completeness votes there
    # (they blur) and a looser copy limit (elements stay whole)
    coarse = preset == "default" and ratio >= _COMPLETE_BELOW
    out["coarse_completeness"] = coarse and is_auto(completeness_weight)
    fine_votes = out["completeness_weight"] > 0 and not out["coarse_completeness"]
    out["coarse_copy_limit"] = preset == "default" and is_auto(copy_limit) and not fine_votes
    out["paper"] = preset == "paper"
    return out


def _free_inside(problem):
    """Hard constraints whose free pixels all lie at least the largest neighbourhood inside the output: the
    canvas needs no margin, as no neighbourhood of a free pixel meets an edge of the output."""
    if problem.constraint is None or not np.isinf(problem.constraint[2]):
        return False
    reach = problem.sizes[0]
    free = problem.constraint[0] < 1 - 1e-6
    return not (free[:reach].any() or free[-reach:].any() or free[:, :reach].any() or free[:, -reach:].any())


def _with_margin(problem, margin):
    """The problem on a canvas ``margin`` pixels larger (the output is its top-left part); constraints and
    the initial image extended by their edge values, the margin unconstrained."""
    pad = ((0, margin), (0, margin))
    constraint = problem.constraint
    if constraint is not None:
        m, t, lam = constraint
        constraint = (np.pad(m, pad), np.pad(t, pad + ((0, 0),), mode="edge"), lam)
    x_init = None if problem.x_init is None else np.pad(problem.x_init, pad + ((0, 0),), mode="edge")
    guide = None if problem.guide is None else np.pad(problem.guide, pad + ((0, 0),), mode="edge")
    fields = None if problem.fields is None else tuple(np.pad(f, pad, mode="edge") for f in problem.fields)
    shape = (problem.shape[0] + margin, problem.shape[1] + margin)
    return dataclasses.replace(problem, shape=shape, constraint=constraint, x_init=x_init, guide=guide, fields=fields)


def _check_memory(shape, channels, opts, frames=1):
    """Refuse an output whose arrays cannot fit. With an index M-step the largest stage holds every
    neighbourhood of the w/4 grid (``1 / spacing^2`` copies of the image: ``z_p``, their weighted
    copies in the E-step, the queries) and about a dozen image-sized arrays; with PatchMatch (the
    colour energy's large stages) the E-step adds the ``z_p`` a few rows at a time and about two
    dozen image-sized arrays remain (measured: 0.5 GiB at 1024^2); the gradient energy triples it;
    an animation keeps every frame."""
    pixels = float(shape[0]) * shape[1] * channels * 8
    field = opts.mu == 0 and not opts.paper and not opts.fields and opts.method in ("auto", "patchmatch")
    per_pixel = 24 if field else 4 / opts.spacing**2 + 12
    need = pixels * per_pixel * (3 if opts.mu > 0 else 1) + pixels * 2 * frames
    check_memory(need, tuple(shape), also={"n_frames": frames} if frames > 1 else None)


def _check_constraint_memory(problem):
    """Refuse soft constraints whose M-step (Algorithm 2) cannot fit: it queries an index of every
    exemplar neighbourhood of the largest size at the finest level, as float32 vectors (the image
    itself, when it is its own exemplar, at 512^2 and 64-px neighbourhoods: 9 GiB)."""
    if problem.constraint is None or not np.isfinite(problem.constraint[2]):
        return
    h, w, channels = problem.ex.shape
    size = max(problem.sizes)
    need = 3.0 * max(h - size + 1, 1) * max(w - size + 1, 1) * size * size * channels * 4
    try:
        check_memory(need, problem.ex.shape[:2], "exemplar", "the search index of the soft constraints (Algorithm 2)",
                     also={"neighborhood_sizes": problem.sizes})
    except ValueError as error:
        raise ValueError(f"{error}, or constraint_weight=float('inf') (hard constraints: the plain M-step, "
                         f"PatchMatch on large stages; texsynth.inpaint does this)") from None


def _check_constraint_weight(constraint_weight):
    """λ of eq. 2: a number in [0, 1e6], or infinity for hard constraints."""
    if isinstance(constraint_weight, numbers.Real) and not isinstance(constraint_weight, bool) \
            and constraint_weight == np.inf:
        return np.inf
    return check_positive_float(constraint_weight, "constraint_weight", allow_zero=True, maximum=_MAX_WEIGHT)


def _prepare(exemplar, size, neighborhood_sizes, levels, *, constraint_weight=1.0, mask=None, target=None,
             exemplar_mask=None, init=None, sizes_name="neighborhood_sizes", preset="paper"):
    """The arrays of :func:`optimize_texture`, checked, as a :class:`_Problem` (``"auto"`` sizes and
    levels resolved by ``preset``)."""
    ex = as_image(exemplar, "exemplar")
    ex, grey = with_channels(ex)
    shape = as_size(size)
    if is_auto(neighborhood_sizes) or is_auto(levels):
        auto_sizes, auto_levels = scale_schedule(ex, shape) if preset == "default" else ((32, 16, 8), 3)
        neighborhood_sizes = auto_sizes if is_auto(neighborhood_sizes) else neighborhood_sizes
        levels = auto_levels if is_auto(levels) else levels
    sizes = check_sizes(neighborhood_sizes, sizes_name)
    levels = check_positive_int(levels, "levels")
    lam = _check_constraint_weight(constraint_weight)
    smallest = sizes[-1]
    if smallest > min(ex.shape[:2]):
        raise ValueError(
            f"exemplar is {ex.shape[0]}x{ex.shape[1]} but the smallest neighborhood is {smallest}x{smallest}; "
            f"pass {sizes_name} no larger than {min(ex.shape[:2])} or a larger exemplar"
        )
    if smallest > min(shape):
        raise ValueError(
            f"size {shape} is smaller than the smallest neighborhood {smallest}x{smallest}; "
            f"pass a larger size or smaller {sizes_name}"
        )
    valid = np.ones(ex.shape[:2])
    if exemplar_mask is not None:
        valid = check_mask(exemplar_mask, ex.shape[:2], "exemplar_mask")
        valid = (valid > 0.5).astype(np.float64)
        free = patches_within(valid > 0.5, smallest)
        if not free.any():
            raise ValueError(
                f"exemplar_mask leaves no {smallest}x{smallest} neighborhood of the exemplar free of masked pixels; "
                "mark more pixels valid or pass smaller neighborhood_sizes"
            )
    channels = ex.shape[-1]
    constraint = None
    if mask is not None and target is None:
        raise ValueError("mask was given without target; pass target=image holding the wanted values at the masked pixels")
    if target is not None:
        t = _check_like(target, shape, channels, "target")
        m = np.ones(shape) if mask is None else check_mask(mask, shape, "mask")
        constraint = (m, t.astype(ex.dtype), lam)
    x_init = None if init is None else _check_like(init, shape, channels, "init").astype(ex.dtype)
    return _Problem(ex, grey, shape, sizes, levels, valid, constraint, x_init)


def _check_guide(guide, shape, name):
    """A guide ``(h, w)`` or ``(h, w, G)`` in [0, 1] of the spatial ``shape``, as ``(h, w, G)`` float."""
    if isinstance(guide, (str, bytes, dict, numbers.Number)):
        raise TypeError(f"{name} must be an array of shape {tuple(shape)} or {tuple(shape) + ('G',)} "
                        f"(guide channels in [0, 1]), got {guide!r}")
    arr = as_float_array(guide, name)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.ndim != 3 or arr.shape[:2] != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} or {tuple(shape) + ('G',)} (one label or guide "
                         f"value per pixel), got shape {np.shape(guide)}")
    return arr


def _with_guides(problem, exemplar_guide, output_guide, guide_weight):
    """Guided synthesis (image analogies' texture by numbers): the guides as extra channels.

    The exemplar guide is appended to the exemplar and the output guide kept for the output, both
    multiplied by ``sqrt(guide_weight)`` (the colours' [0, 1] units), so every neighbourhood distance
    compares the guides too; constraint targets and the initial image get the output guide's channels.
    """
    weight = check_positive_float(guide_weight, "guide_weight", allow_zero=True, maximum=_MAX_WEIGHT)
    if exemplar_guide is None and output_guide is None:
        return problem
    if exemplar_guide is None or output_guide is None:
        given, missing = ("exemplar_guide", "output_guide") if output_guide is None else ("output_guide",
                                                                                          "exemplar_guide")
        raise ValueError(f"{given} was given without {missing}; pass both (the exemplar's label map and the "
                         f"output's) or neither")
    ge = _check_guide(exemplar_guide, problem.ex.shape[:2], "exemplar_guide")
    go = _check_guide(output_guide, problem.shape, "output_guide")
    if ge.shape[-1] != go.shape[-1]:
        raise ValueError(f"exemplar_guide has {ge.shape[-1]} channel(s) but output_guide has {go.shape[-1]}; "
                         f"pass guides with the same channels (the same labels in both)")
    if weight == 0:  # guides of no weight: the unguided synthesis, bit for bit
        return problem
    dtype = problem.ex.dtype
    s = np.sqrt(weight)
    labels = np.unique(ge.reshape(-1, ge.shape[-1]), axis=0)
    used = np.unique(go.reshape(-1, go.shape[-1]), axis=0)
    if len(labels) > _MAX_LABELS or len(used) > _MAX_LABELS or not all((labels == u).all(-1).any() for u in used):
        labels = None  # continuous guides (or output values the exemplar lacks): one histogram for all
    else:
        labels = (labels * s).astype(dtype)
    ge, go = (ge * s).astype(dtype), (go * s).astype(dtype)
    ex = np.concatenate([problem.ex, ge], axis=-1)
    constraint = problem.constraint
    if constraint is not None:
        m, t, lam = constraint
        constraint = (m, np.concatenate([t, go], axis=-1), lam)
    x_init = None if problem.x_init is None else np.concatenate([problem.x_init, go], axis=-1)
    return dataclasses.replace(problem, ex=ex, constraint=constraint, x_init=x_init, guide=go, labels=labels)


def _with_fields(problem, orientation, scale):
    """The orientation and scale fields (Zhang et al. 2003's local frames) over the output, checked."""
    theta = as_field(orientation, problem.shape, "orientation")
    factor = as_field(scale, problem.shape, "scale", positive=True)
    if theta is None and factor is None:
        return problem
    if problem.constraint is not None and np.isfinite(problem.constraint[2]):
        raise ValueError("orientation and scale fields do not combine with soft constraints (target with a finite "
                         "constraint_weight: Algorithm 2 ranks plain neighbourhoods); pass "
                         "constraint_weight=float('inf') (hard constraints) or no fields")
    theta = np.zeros(problem.shape) if theta is None else theta
    factor = np.ones(problem.shape) if factor is None else factor
    return dataclasses.replace(problem, fields=(theta, factor))


def _pyramids(ex, valid, shape, levels, constraint, x_init, wrap):
    """Exemplar, its valid mask, output shapes, constraints and init at every level."""
    levels = max(1, min(levels, max_levels(ex.shape[:2]), max_levels(shape)))
    pmode = "wrap" if wrap else "reflect"
    ex_pyr = gaussian_pyramid(ex, levels)
    # a coarse exemplar pixel is valid only if no masked pixel contributed to it
    valid_pyr = [v > 1 - 1e-6 for v in gaussian_pyramid(valid, levels)]
    out_shapes = level_shapes(shape, levels)
    cons_pyr = [constraint] + [None] * (levels - 1)
    if constraint is not None:
        m, t, lam = constraint
        mp = gaussian_pyramid(m, levels, mode=pmode)
        mtp = gaussian_pyramid(m[..., None] * t, levels, mode=pmode)
        for lv in range(1, levels):
            # target of a coarse pixel: the mask-weighted average of the fine targets
            tl = np.divide(mtp[lv], mp[lv][..., None], out=np.zeros_like(mtp[lv]), where=mp[lv][..., None] > 1e-12)
            cons_pyr[lv] = (mp[lv], tl.astype(ex.dtype), lam)
    init_pyr = None if x_init is None else gaussian_pyramid(x_init, levels, mode=pmode)
    return ex_pyr, valid_pyr, out_shapes, cons_pyr, init_pyr


# --------------------------------------------------------------------------- public API
def optimize_texture(exemplar, size, *, preset="default", neighborhood_sizes="auto", levels="auto",
                     relative_grid_spacing=0.25, irls_exponent=0.8, max_iterations=5, tolerance="auto",
                     gradient_weight=0.0, mask=None, target=None, constraint_weight=1.0, exemplar_mask=None,
                     tileable=False, init=None, falloff=True, occurrence_weight=0.0, copy_limit="auto",
                     completeness_weight="auto", histogram_matching="auto", method="auto", candidates="all", k=4,
                     exemplar_guide=None, output_guide=None, guide_weight=1.0, orientation=None, scale=None,
                     confidence=None, rng=None, progress=False, return_info=False):
    """Synthesise a texture by texture optimization (Kwatra et al. 2005).

    Minimises the texture energy (eq. 1) of the output over its
    neighbourhoods on a sparse grid by alternating a weighted-average E-step
    and a nearest-neighbour M-step (Algorithm 1), with robust IRLS weights
    (Section 3.1), coarse-to-fine over resolution levels and neighbourhood
    sizes (Section 3.2), an optional gradient term, and optional soft
    constraints (Section 4, Algorithm 2) for controlled synthesis and hole
    filling.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` grey or ``(h, w, C)`` input texture ``Z``, any accepted
        dtype (see :func:`texsynth.core._validate.as_image`).
    size : int or (int, int)
        Output size ``(H, W)``, independent of the exemplar's size.
    preset : {"default", "paper"}
        What the ``"auto"`` options mean (see Notes). ``"default"``: the
        result a user would pick at production sizes (scale-aware sizes and
        levels, the completeness term where the output is small, a copy
        limit, the PatchMatch M-step on large stages, no exemplar edges
        along the output's edges). ``"paper"``: Kwatra et al.'s settings
        (sizes 32, 16, 8 over 3 levels, eq. 1 alone, the index M-step, the
        paper's stopping test, neighbourhoods inside the output).
    neighborhood_sizes : sequence of int or "auto"
        Neighbourhood widths ``w``, used largest first at every level; at
        each level only the sizes that fit the sub-sampled exemplar are used
        (see Notes). ``"auto"``: preset ``"default"`` chooses them from the
        exemplar's feature scale (Notes), ``"paper"`` takes ``(32, 16, 8)``.
    levels : int or "auto"
        Resolution levels; 1 synthesises at full resolution only. ``"auto"``:
        as many as keep the coarsest exemplar 32 pixels or more (preset
        ``"default"``), 3 (``"paper"``).
    relative_grid_spacing : float
        Spacing of the neighbourhood centres ``X†`` as a fraction of ``w``
        (default 1/4: "centers that are w/4 pixels apart").
    irls_exponent : float
        ``r`` of the robust energy ``||x_p - z_p||^r``, in (0, 2]; default 0.8
        (Section 3.1). ``r = 2`` is the plain least-squares eq. 1.
    max_iterations : int
        EM iterations per (level, size) stage at most; a stage also stops when
        ``{z_p}`` no longer changes. Default 5 ("usually 3-5 iterations per
        resolution/scale level were found to be enough", Section 5).
    tolerance : float or "auto"
        A stage also stops when one iteration lowers the energy by less than
        this fraction (an addition to the paper's test, which rarely fires
        with thousands of neighbourhoods). 0 keeps only the paper's
        criterion. Not used with ``occurrence_weight > 0`` or
        ``copy_limit``, whose penalties raise the energy on purpose.
        ``"auto"``: 5e-3 (preset ``"default"``), 0 (``"paper"``).
    gradient_weight : float
        ``μ`` of the gradient energy ``μ sum_p ||D x_p - D z_p||^2``
        (Section 3). Default 0 (off): the paper's Algorithm 1, its robust
        optimisation and its results are stated for the colour energy (1);
        the gradient term is offered as a generalisation ("we can
        generalize...") with ``μ = 10`` "in our experiments". Pass 10 to use
        it; the E-step then solves a Poisson-like linear system.
    mask : array_like, optional
        ``(H, W)`` constrained pixels ``C`` of eq. 2: bool, or weights in
        [0, 1] (soft masks). Requires ``target``.
    target : array_like, optional
        Output-shaped wanted values ``x^c``. Alone (no mask) it constrains
        every pixel.
    constraint_weight : float
        ``λ >= 0``, the weight of ``E_c`` against the texture energy (default
        1). With the default sizes and ``r``, the texture term weighs a pixel
        by roughly 1-10, so λ = 1 is a gentle pull and λ = 100 nearly hard.
        ``float("inf")``: hard constraints, the limit λ → ∞ (as in Wexler
        et al.'s and PatchMatch's hole filling): every E-step sets the
        masked pixels to ``target`` (blended by the mask where a coarse
        pixel is partly masked), so each ``x_p`` already holds them and the
        M-step is the plain nearest-neighbour search (PatchMatch on large
        stages, not Algorithm 2's index query of every constrained
        neighbourhood): how :func:`texsynth.inpaint` and
        :func:`texsynth.uncrop` fill large images. Only the neighbourhoods
        that touch an unconstrained pixel, and the ring one grid step around
        them (whose matches PatchMatch propagates across the border), are
        searched and averaged: the others vote only for pixels the E-step
        puts back, so the work follows the free pixels, not the output. The
        source-coordinate map of a pixel no such neighbourhood covers
        continues that of the nearest covered pixel.
    exemplar_mask : array_like, optional
        ``(h, w)`` bool: exemplar pixels that may be copied. Neighbourhoods
        touching a False pixel are never used (e.g. the hole when the
        exemplar is the image being filled).
    tileable : bool
        Periodic output: neighbourhoods wrap around the edges, so the result
        tiles seamlessly.
    init : array_like, optional
        Output-shaped initial image; the coarsest level starts from its
        down-sampled version instead of random neighbourhoods.
    falloff : bool
        Weight each neighbourhood's pixels by a Gaussian fall-off (σ = w/4)
        in both steps (Section 3.1). Default True.
    occurrence_weight : float
        ``λ_occ >= 0`` of the occurrence penalty of Kaspar et al. 2015 [2]_:
        the M-step ranks candidates by
        ``ρ_p + λ_occ · scale · o(z) / ω``, where ``o(z)`` is how much the
        current ``z_p`` already cover the exemplar pixels of ``z`` (fall-off
        weighted), ``ω`` the value of an even use of the whole exemplar and
        ``scale`` the exemplar's variance times the summed weights of a
        neighbourhood; the kd-tree's 4 nearest and the 4 coherent candidates
        (the grid neighbours' ``z`` shifted) compete. It spreads the output
        over more of the exemplar (completeness) but does not limit verbatim
        copies. Default 0 (off, the paper's M-step). With
        ``occurrence_weight > 0`` or ``copy_limit``, the energy is no longer
        guaranteed to fall within a stage (the M-step minimises another
        criterion), and a stage ends only by the paper's test or
        ``max_iterations``.
    copy_limit : float in (0, 1], None or "auto"
        Limit the size of verbatim copies: a penalty grows on every exemplar
        offset (exemplar position minus output position of ``z_p``) shared by
        more neighbourhood centres than a copied region covering
        ``copy_limit`` of the exemplar's area has (see Notes). None: off (the
        paper's M-step). Paired with ``completeness_weight`` it also
        withholds the completeness votes of over-limit offsets. ``"auto"``:
        0.25 (preset ``"default"``; when the finest level has no
        completeness term, 0.3 there, as it refines the coarser levels'
        arrangement: only outlying copies are cut there, not elements), None
        (``"paper"``).
    completeness_weight : float or "auto"
        ``λ_b >= 0``: adds the completeness half of the bidirectional
        similarity of Simakov et al. 2008 [3]_ to the energy: every exemplar
        neighbourhood ``q_j`` on the ``w/4`` grid must appear somewhere in
        the output, ``λ_b (|X†| / |J|) sum_j ||x_p(j) - q_j||^r`` with
        ``x_p(j)`` its nearest output neighbourhood on ``X†``. The M-step
        also finds ``p(j)``, and the E-step averages ``q_j`` at ``p(j)``
        with the ``z_p`` (Simakov et al.'s update rule); 1 weighs both
        directions equally per neighbourhood; 0 is off (the paper's eq. 1).
        Alone it makes the output contain the whole exemplar
        verbatim, so use it with ``copy_limit``: ``completeness_weight=1,
        copy_limit=0.2`` brings all of the exemplar without large copies, at
        about twice the time (docs/methods/optimization.md measures it).
        Without ``copy_limit`` the energy never rises within a stage, as for
        eq. 1. ``"auto"``: 1 (preset ``"default"``), on every level when
        the output has less than 4 times the exemplar's area and on every
        level but the finest from there on (the coarse levels choose which
        parts of the exemplar appear; on the finest level the votes would
        blur large flat areas); 0 (``"paper"``). An explicit value holds on
        every level. :attr:`StageInfo.completeness_weight` gives the weight
        each stage used.
    histogram_matching : bool or "auto"
        After every E-step, give each colour channel of the output the
        exemplar's histogram (exact quantile assignment,
        :mod:`texsynth.core.histogram`): a simple form of the histogram
        matching Kopf et al. 2007 [4]_ build into texture optimization (they
        re-weight the neighbourhoods' votes; here the output is remapped,
        which we could not compare with theirs). The E-step averages overlapping
        neighbourhoods, the average matches the exemplar's flattest ones
        best, and at large enlargements the output can wash out into one
        flat region; restoring the histogram breaks that loop. Not applied
        with soft constraints (``target``); with hard ones
        (``constraint_weight=inf``) only the unconstrained pixels are
        matched. With label guides (``exemplar_guide``/``output_guide`` of
        at most 32 distinct values, every output value also in the
        exemplar's) each output label region is matched to the exemplar
        pixels of the same label, so regions covering other proportions
        than in the exemplar keep their own colours; other guides: the
        whole exemplar. The energy may then rise within a stage.
        ``"auto"``: True (preset ``"default"``), False (``"paper"``).
    method : {"auto", "patchmatch", "exact", "kdtree", "tsvq"}
        Nearest-neighbour backend of the M-step (:mod:`texsynth.core.search`),
        chosen per (level, size) stage. ``"patchmatch"``: PatchMatch (Barnes
        et al. 2009) between the output and the exemplar, warm-started from
        the current ``z_p`` (and a stage's first M-step from the previous
        stage's field), memory proportional to the output; for the colour
        energy without constraints (the gradient energy and Algorithm 2 take
        the index). ``"auto"`` (default): PatchMatch on stages where an exact
        search would compare more than
        :data:`~texsynth.core.search.FIELD_MIN_VALUES` values (preset
        ``"default"``), otherwise an index: exact when the exemplar level
        holds few neighbourhoods, the PCA kd-tree above (profile ``"stage"``:
        16 candidates of a (1 + 2)-approximate search, re-ranked exactly).
        The M-step never accepts a worse ``z_p``, so an approximate backend
        cannot raise the energy within a stage.
    candidates : {"all", "k-coherent"}
        Which exemplar neighbourhoods the M-step compares ``x_p`` with.
        ``"all"`` (default): all of them, through ``method``.
        ``"k-coherent"``: k-coherent search (Ashikhmin 2001; Tong et al.
        2002 [7]_) on every stage: the ``z`` of ``x_p``'s four grid
        neighbours shifted by the offset to them (the continuations of the
        pieces they copy), each with its k-coherence set, the ``k - 1``
        exemplar neighbourhoods most like it (found once per stage among the
        neighbourhoods' 8 leading principal components, at least 2 pixels
        away). These take the place of PatchMatch's random search:
        the M-step is PatchMatch's propagation, in its scan order, over the
        sets, and still never accepts a worse ``z_p``. The synthesis's first
        M-step, from random neighbourhoods, searches as ``"all"`` does. For
        the colour energy (``gradient_weight=0``) without soft constraints,
        orientation or scale fields, with preset ``"default"`` and
        ``method`` ``"auto"`` or ``"patchmatch"``.
    k : int
        ``candidates="k-coherent"`` only: the size of the k-coherence sets
        (the neighbourhood itself and ``k - 1`` similar ones). Default 4;
        1 is Ashikhmin's search (continuations only).
    exemplar_guide, output_guide : array_like, optional
        Guided synthesis ("texture by numbers", Hertzmann et al. 2001 [5]_):
        ``(h, w)`` or ``(h, w, G)`` guide maps of the exemplar and ``(H, W)``
        or ``(H, W, G)`` of the output (the same ``G``), values in [0, 1]
        (any accepted dtype), e.g. a label map painted over each. Both or
        neither. The guides become ``G`` extra channels of the exemplar and
        of the output, multiplied by ``sqrt(guide_weight)``, so every
        neighbourhood distance (M-step, energy) compares the guides too;
        their Gaussian pyramids are built like the images'. The output's
        guide channels are given, not synthesised: every E-step (and each
        stage's start, after up-sampling) resets them to ``output_guide``;
        histogram matching leaves them out; they are stripped from the
        result.
    guide_weight : float
        Weight of the guide channels against the colours, ``>= 0`` (default
        1): a guide difference of 1 costs as much as a colour difference of
        ``sqrt(guide_weight)`` in one channel, in the colours' [0, 1] units.
        0 ignores the guides (the unguided result, bit for bit).
    orientation : None, float, array_like or callable
        Orientation field ``theta``: the angle in radians, counter-clockwise
        as the image is shown, by which the texture is turned at each output
        pixel (as in :func:`~texsynth.synthesize_controlled`): a number, an
        ``(H, W)`` array, or a callable ``orientation(rows, cols)`` of float
        arrays of output pixel coordinates. None (default): not turned, and
        the synthesis is exactly the one without fields.
    scale : None, float, array_like or callable
        Scale field ``S``: magnification of the texture at each output pixel
        (2: elements twice as large), same forms; finite, in [0.001, 1000].
        With either field every output neighbourhood ``x_p`` is sampled on
        a grid turned and scaled around its centre (see Notes); the M-step
        then uses the index (PatchMatch compares unrotated patches), and
        ``gradient_weight > 0`` and soft constraints are refused. Fields
        wrap with ``tileable=True``.
    confidence : None or float
        With hard constraints (``constraint_weight=float("inf")``): Wexler,
        Shechtman & Irani's confidence base ``γ`` (their value: 1.3,
        :data:`WEXLER_CONFIDENCE`). A filled pixel at distance ``d`` from the
        nearest known pixel has confidence ``γ^-d`` (a known pixel 1), and in
        the E-step each neighbourhood weighs by the mean confidence of its
        pixels, so near the boundary the neighbourhoods lying on known pixels
        decide and the fill continues them (2007, Sec. 3.2; TPAMI
        doi:10.1109/TPAMI.2007.60). Default None: all neighbourhoods alike,
        as in Kwatra et al. :func:`~texsynth.inpaint` and
        :func:`~texsynth.uncrop` use 1.3; :func:`~texsynth.make_tileable`
        does not, since there the two sides of its band meet in the middle,
        and the confidence made that meeting a seam (measured in
        ``docs/methods/completion.md``).
    rng : None, int or numpy.random.Generator
        Seeds the random initial neighbourhoods (and approximate indexes).
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``
        after every iteration.
    return_info : bool
        Also return an :class:`OptimizationInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``(H, W)`` or ``(H, W, C)``, the exemplar's layout and float dtype,
        clipped to [0, 1].
    info : OptimizationInfo
        Only with ``return_info=True``: energy per iteration with the stage
        boundaries (Figure 3), the final source of every ``z_p``, times.

    Raises
    ------
    ValueError
        Exemplar smaller than the smallest neighbourhood, ``size`` smaller
        than it, ``mask``/``target``/``init`` of another shape than the
        output, NaN in any input, ``constraint_weight < 0``,
        ``irls_exponent`` outside (0, 2], ``gradient_weight < 0``,
        ``occurrence_weight < 0``, ``completeness_weight < 0``, ``copy_limit`` outside
        (0, 1], one guide without the other, guides of another size than
        the exemplar / the output or with different channel counts, guide
        values outside [0, 1], ``guide_weight < 0``, ``orientation`` or
        ``scale`` not of the output's size, non-finite or (scale) not
        positive, fields with ``gradient_weight > 0`` or soft constraints.
    TypeError
        Unsupported dtypes or argument types.

    Notes
    -----
    Texture energy, eq. (1) with the robust norm of Section 3.1 and the
    gradient term::

        E_t(x; {z_p}) = sum_{p in X†} ||x_p - z_p||^r + μ ||D x_p - D z_p||^2

    The E-step minimises its IRLS majoriser ``sum_p ω_p ||x_p - z_p||^2``
    with ``ω_p = ||x_p - z_p||^{r-2}`` (a weighted average; with ``μ > 0``
    the normal equations ``(A + μ Dᵀ B D) x = A m + μ Dᵀ B G`` are solved by
    conjugate gradients, preconditioned by a diagonal scaling and the
    constant-coefficient operator inverted by FFT for tileable output, DCT
    otherwise, to a relative residual of 1e-10). The M-step finds each
    ``z_p`` by nearest-neighbour search; a neighbourhood is searched again
    only if ``x_p`` moved since its last search by more than 3 % of the
    distance it then had to its match (the triangle inequality bounds what
    such a search can gain by twice that move; the others keep ``z_p``, so
    the step still never raises the energy). At full resolution most
    neighbourhoods have converged after an iteration or two, so most
    searches are skipped (docs/methods/optimization.md measures it).
    Soft constraints, eq. (2), ``E_c(x; x^c) = sum_{k in C} (x(k) -
    x^c(k))^2``, enter the E-step as a weighted average with the targets
    and the M-step as ``argmin_v ||x_p - v||^2 + λ ||v - x^c_p||^2_C``
    (Algorithm 2). For ``λ = 0`` (and without ``occurrence_weight`` and
    ``copy_limit``) the energy provably never rises within a stage (module
    docstring).

    Copy limit: with ``copy_limit = c``, an exemplar offset shared by ``n``
    centres of the ``w/4`` grid costs every candidate that uses it
    ``3 · scale · max(0, n / n_c - 1)`` with ``n_c = c · h · w / spacing²``
    (the centres of a copied region covering ``c`` of the ``h x w``
    exemplar) and ``scale`` as for ``occurrence_weight``: the penalty grows
    with the excess, so a region sheds first the neighbourhoods with the
    closest alternatives, at its rim. This is our addition, not in the
    papers: eq. 1 rewards copies (a verbatim copy has zero energy), and the
    occurrence penalty does not limit them either (a region copied once uses
    its exemplar pixels less than an even spread of a larger output does).

    Presets. ``preset="default"`` chooses the schedule from the exemplar
    (:func:`texsynth.core.scale.feature_scale`: the wavelength below which
    85 % of its energy lies): the largest neighbourhood is 64 pixels when
    that scale is above 32 pixels, else 32, and at most a quarter of the
    exemplar's smaller side; every level uses it, half and a quarter of it
    (none below 4 pixels); levels go down until the exemplar is 32 pixels
    (a 256-pixel exemplar: 4 levels). A non-tileable output is the top-left
    part of a tileable canvas larger by half the largest neighbourhood, so
    no neighbourhood ends at an edge of the output (on the paper's grid the
    neighbourhoods along an edge match the exemplar's own edges, whose rows
    then pile up along the output's edges); not under hard constraints whose
    free pixels all lie at least the largest neighbourhood inside the output
    (a hole in an image: the known pixels already meet the edges, and no
    neighbourhood of the free ones reaches them at the finest level).
    ``preset="paper"`` is the paper:
    ``(32, 16, 8)`` over 3 levels, eq. 1 alone, the nearest-neighbour index
    (the paper searches a tree over the exemplar's neighbourhoods, here the
    PCA kd-tree, or exact search on small levels), the stopping test of
    unchanged ``z_p`` alone and neighbourhoods inside the output. Any
    option given explicitly wins over the preset.

    Orientation and scale fields (Kwatra et al. have none; this follows the
    local frames of Zhang et al. 2003 [6]_ and the lecture's "Synthesis with
    Local Size/Vector Field Control"): the neighbourhood of centre ``p`` is
    the output sampled bilinearly at ``p + A(p) d``, ``A = S R(theta)``, for
    the offsets ``d`` of a ``w x w`` patch (M-step: compared with the
    exemplar's plain neighbourhoods, fall-off ``g(d)``), and the E-step adds
    every value ``z_p(d)`` back at ``p + A(p) d`` with the same bilinear
    weights times ``ω_p g(d)`` (the adjoint of the sampling,
    :func:`texsynth.core.fields.splat`), normalised by the summed weights.
    That average is not the exact least-squares solution of the bilinear
    sampling (it is where ``A`` is a whole-pixel shift), so the guarantee
    that ``E`` never rises within a stage does not hold with fields. The
    fields are read at each level at the output pixels it samples; the
    coherent candidates of the copy limit follow the frames (the grid
    neighbour's ``z`` shifted by ``A^{-1} e``), while the copy limit's
    offsets stay unrotated, so it rarely fires where the field turns.

    Neighbourhood sizes per level: at full resolution every size not larger
    than the exemplar is used; at a level sub-sampled ``2^l`` times only
    sizes up to half the sub-sampled exemplar's smaller side, so the coarse
    search has a choice of neighbourhoods (a 128-pixel exemplar gives
    (16, 8) at 1/4, (32, 16, 8) at 1/2 and at full resolution).

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
       for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
       2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`
    .. [2] A. Kaspar, B. Neubert, D. Lischinski, M. Pauly and J. Kopf, "Self
       tuning texture optimization", Computer Graphics Forum (Eurographics
       2015) 34(2), pp. 349-359. :doi:`10.1111/cgf.12565`
    .. [3] D. Simakov, Y. Caspi, E. Shechtman and M. Irani, "Summarizing visual
       data using bidirectional similarity", CVPR 2008.
       :doi:`10.1109/CVPR.2008.4587842`
    .. [4] J. Kopf, C.-W. Fu, D. Cohen-Or, O. Deussen, D. Lischinski and
       T.-T. Wong, "Solid texture synthesis from 2D exemplars", ACM
       Transactions on Graphics (SIGGRAPH 2007) 26(3).
       :doi:`10.1145/1276377.1276380`
    .. [5] A. Hertzmann, C. E. Jacobs, N. Oliver, B. Curless and D. H. Salesin,
       "Image analogies", SIGGRAPH 2001, pp. 327-340.
       :doi:`10.1145/383259.383295`. Not checked against the paper (it is
       not in our papers folder): its texture by numbers matches
       neighbourhoods of the label images A, B together with those of A'
       (its own weights and search); here the labels are extra channels of
       Kwatra's neighbourhood distance, with our ``guide_weight``, and we
       could not compare results with the paper's figures.
    .. [6] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
       progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344` (not at
       hand; its orientation and scale control as summarised in
       :func:`~texsynth.synthesize_controlled`).
    .. [7] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       ACM TOG 21(3) (SIGGRAPH 2002), pp. 665-672.
       :doi:`10.1145/566654.566634` (not at hand: the k-coherence sets as
       :mod:`texsynth.core.search` describes them; their use in texture
       optimization's M-step is ours).

    Examples
    --------
    >>> from texsynth import data
    >>> ex = data.load("bumpy")[:32, :32]
    >>> out, info = optimize_texture(ex, 40, neighborhood_sizes=(16, 8), levels=1,
    ...                              max_iterations=2, rng=0, return_info=True)
    >>> out.shape, [(s.level, s.size) for s in info.stages]
    ((40, 40, 3), [(0, 16), (0, 8)])
    >>> bool(np.all(np.diff(info.energy[info.stage == 1]) <= 1e-9 * info.energy[0]))
    True
    """
    t_start = time.perf_counter()
    preset = _check_preset(preset)
    problem = _prepare(exemplar, size, neighborhood_sizes, levels, constraint_weight=constraint_weight, mask=mask,
                       target=target, exemplar_mask=exemplar_mask, init=init, preset=preset)
    auto = _preset(preset, problem, tolerance=tolerance, completeness_weight=completeness_weight,
                   copy_limit=copy_limit, histogram_matching=histogram_matching)
    problem = _with_guides(problem, exemplar_guide, output_guide, guide_weight)
    problem = _with_fields(problem, orientation, scale)
    tileable = check_bool(tileable, "tileable")
    margin = 0 if tileable or preset == "paper" or _free_inside(problem) else problem.sizes[0] // 2
    opts = _check_options(irls_exponent=irls_exponent, relative_grid_spacing=relative_grid_spacing,
                          max_iterations=max_iterations, gradient_weight=gradient_weight,
                          tileable=tileable or margin > 0, falloff=falloff, method=method,
                          occurrence_weight=occurrence_weight, fields=problem.fields is not None,
                          confidence=confidence, candidates=candidates, k=k, **auto)
    if opts.confidence is not None and (problem.constraint is None or not np.isinf(problem.constraint[2])):
        raise ValueError("confidence weighs neighbourhoods by their distance to the known pixels of hard "
                         "constraints: pass mask=, target= and constraint_weight=float('inf'), or confidence=None")
    if opts.candidates == "k-coherent" and problem.constraint is not None and not np.isinf(problem.constraint[2]):
        raise ValueError("candidates='k-coherent' does not combine with soft constraints (Algorithm 2 takes the "
                         "index M-step); pass candidates='all', or constraint_weight=float('inf') for hard ones")
    if opts.fields and opts.mu > 0:
        raise ValueError(f"gradient_weight={opts.mu:g} does not combine with orientation/scale fields (the "
                         f"gradient E-step solves on the pixel grid, not in rotated frames); pass "
                         f"gradient_weight=0 or no fields")
    shape = problem.shape
    if margin:  # a tileable canvas a little larger, cropped: no neighbourhood ends at the output's edges
        problem = _with_margin(problem, margin)
    _check_memory(problem.shape, problem.ex.shape[-1], opts)
    _check_constraint_memory(problem)
    rng = as_rng(rng)
    x, info = _synthesize(problem, opts, rng, progress=progress, desc="optimize_texture", coordinates=return_info)
    if margin:
        x = x[: shape[0], : shape[1]]
        w = info.stages[-1].size  # the neighbourhoods that lie inside the output
        corner = info.centers - w // 2
        inside = np.all((corner >= 0) & (corner + w <= np.asarray(shape)), axis=1)
        info.centers, info.sources = info.centers[inside], info.sources[inside]
        if info.coordinates is not None:
            info.coordinates = info.coordinates[: shape[0], : shape[1]].copy()
    info.seconds = time.perf_counter() - t_start
    if problem.guide is not None:  # the guide channels were given, not synthesised
        x = x[..., : x.shape[-1] - problem.guide.shape[-1]]
    out = restore_channels(np.clip(x, 0.0, 1.0), problem.grey)
    return (out, info) if return_info else out


def _synthesize(problem, opts, rng, *, progress=False, cache=None, desc, coordinates=True):
    """Coarse-to-fine driver (Section 3.2); ``cache`` keeps indexes across calls (animation frames).

    ``coordinates=False`` leaves the info's source-coordinate map out (nobody will see it).
    """
    cache = {} if cache is None else cache
    ex, shape = problem.ex, problem.shape
    ex_pyr, valid_pyr, out_shapes, cons_pyr, init_pyr = _pyramids(
        ex, problem.valid, shape, problem.levels, problem.constraint, problem.x_init, opts.tileable)
    guide_pyr = [None] * len(out_shapes)
    if problem.guide is not None:  # the output guide's pyramid, from the same code as the images'
        guide_pyr = [g.astype(ex.dtype, copy=False) for g in
                     gaussian_pyramid(problem.guide, len(out_shapes), mode="wrap" if opts.tileable else "reflect")]
    plan = _schedule(problem.sizes, [e.shape[:2] for e in ex_pyr], out_shapes)
    if not any(plan):
        raise ValueError(f"no neighborhood size in {problem.sizes} fits the exemplar {ex.shape[:2]} and the output {shape}")
    record = dict(energy=[], mse=[], stage=[], stages=[], centers=None, sources=None,
                  levels=sum(1 for p in plan if p))
    bar = Progress(progress, sum(len(p) for p in plan) * opts.max_iterations, desc)
    x, x_level = None, None
    try:
        for level in reversed(range(len(plan))):
            if not plan[level]:
                continue
            if x is None and init_pyr is not None:
                x = init_pyr[level]
            elif x is not None:
                # Section 3.2: up-sample the coarse result as the next level's initialisation
                for finer in range(x_level - 1, level - 1, -1):
                    x = upsample(x, out_shapes[finer], mode="wrap" if opts.tileable else "reflect")
            x_level = level
            for w in plan[level]:
                key = (level, w)
                if key not in cache:
                    cache[key] = _Exemplar(ex_pyr[level], valid_pyr[level], w, opts, rng, frame=opts.frame,
                                           guided=problem.guide is not None)
                if len(cache[key]) == 0:  # exemplar_mask leaves nothing at this level: skip it
                    continue
                fields = None if problem.fields is None else [level_field(f, level, out_shapes[level])
                                                              for f in problem.fields]
                x = _run_stage(cache[key], x, out_shapes[level], level, opts, cons_pyr[level], rng, record, bar,
                               guide=guide_pyr[level], fields=fields, labels=problem.labels)
    finally:
        bar.close()
    level, *last = record.get("dominant", (None,))
    info = OptimizationInfo(
        energy=np.asarray(record["energy"]), mse=np.asarray(record["mse"]),
        stage=np.asarray(record["stage"], dtype=int), stages=record["stages"],
        centers=record["centers"], sources=record["sources"] * (2 ** record["stages"][-1].level),
        coordinates=_dominant_sources(*last) if level == 0 and coordinates else None,
    )
    return x, info


def _first_sources(x, problem, size, opts, rng, cache):
    """Correspondence of a given first frame: its nearest exemplar neighbourhoods (one M-step)."""
    centers = grid_centers(x.shape[:2], size, opts.grid(size), mode=opts.mode)
    exm = cache[(0, size)] = _Exemplar(problem.ex, problem.valid, size, opts, rng, frame=True)
    zidx, _ = _m_step_frame(exm, x, centers, opts.mode, None, None, None, search=True)
    return _source_map(centers, exm.centers(zidx), x.shape[:2])


def animate_texture(exemplar, flows, *, n_frames=None, neighborhood_sizes=(32, 16, 8), levels=3,
                    frame_sizes=None, relative_grid_spacing=0.25, irls_exponent=0.8, max_iterations=5,
                    tolerance=5e-3,
                    max_frame_iterations=3, gradient_weight=0.0, constraint_weight=3.0, tileable=False,
                    first_frame=None, warp_order=3, frame_falloff=0.25, falloff=True, method="auto", rng=None,
                    progress=False, return_info=False):
    """Animate a texture along a flow field (Kwatra et al. 2005, Section 4.1).

    Frame 1 is an ordinary multi-level synthesis (:func:`optimize_texture`).
    Each next frame ``i + 1`` is initialised by warping frame ``i`` along the
    flow ``f_i`` and synthesised at a single resolution with the warped frame
    as the soft-constraint target (eq. 3 treated as eq. 2, Algorithm 2), so
    texture elements move with the flow but keep their shape. The exemplar
    indexes are built once for the whole sequence, and frame ``i``'s
    correspondence with the exemplar (where each ``z_p`` came from), carried
    along ``f_i`` by :func:`texsynth.core.flows.warp_coordinates`, gives every
    neighbourhood of frame ``i + 1`` coherent candidates, so the index is
    searched only once per neighbourhood size and frame.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` input texture.
    flows : array_like or callable
        ``(L-1, H, W, 2)`` flows (one per transition, may vary over time),
        one ``(H, W, 2)`` stationary flow, or a callable ``i -> (H, W, 2)``;
        displacements ``(d_row, d_col)`` in pixels per frame (see
        :mod:`texsynth.core.flows` for sink, source, vortex, rotation,
        translation). The frame size is the flows' ``(H, W)``.
    n_frames : int, optional
        Number of frames ``L``; required for a single flow or a callable.
    neighborhood_sizes, levels, relative_grid_spacing, irls_exponent, max_iterations, tolerance, gradient_weight, falloff, method
        As in :func:`optimize_texture`, for frame 1 (and ``method`` for the
        frames' index, a kd-tree re-ranking 4 candidates with ``eps = 2``
        when ``"auto"`` chooses the kd-tree).
    frame_sizes : sequence of int, optional
        Neighbourhood sizes of the single-resolution synthesis of frames
        2..L; default the last two of ``neighborhood_sizes`` (16, 8): the
        warped frame is already a good texture, so the large size, which
        rearranges whole elements, is not needed to repair it.
    max_frame_iterations : int
        EM iterations per size for frames 2..L at most (default 3); a size
        also stops when ``{z_p}`` no longer changes or the energy falls by
        less than ``tolerance``.
    constraint_weight : float
        ``λ`` of the flow term: how strongly a frame keeps the warped previous
        frame (default 3; the paper gives no value, and λ = 1 lets the
        texture wash out into flat regions: docs/methods/optimization.md).
    tileable : bool
        Periodic frames: the warp wraps around, so every pixel has a target.
        Otherwise pixels that flow in from outside the frame are
        unconstrained and synthesised freely.
    first_frame : array_like, optional
        Use this ``(H, W[, C])`` image as frame 1 instead of synthesising it.
    warp_order : int
        Spline order of the warp (default 3, cubic): a bilinear warp blurs a
        little at every frame and the blur accumulates over the sequence.
    frame_falloff : float or None
        ``σ`` of the Gaussian fall-off with which the E-step of frames 2..L
        averages the overlapping ``z_p``, in units of the grid spacing
        ``w/4``. Default 0.25: each pixel comes mostly from the ``z_p``
        centred nearest to it, so neighbourhoods that disagree by a pixel
        (inevitable when the texture moves by fractions of a pixel) are not
        averaged into blur. ``None`` uses the M-step's fall-off (σ = w/4),
        the plain Algorithm 2, with which the frames wash out into flat
        smeared regions; the paper gives no σ.
    rng, progress, return_info
        As in :func:`optimize_texture` (progress counts frames).

    Returns
    -------
    frames : numpy.ndarray
        ``(L, H, W)`` or ``(L, H, W, C)``.
    info : AnimationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        Flows of the wrong shape or with NaN, ``n_frames`` inconsistent with
        the flows, and everything :func:`optimize_texture` rejects.

    Notes
    -----
    Eq. (3), the flow energy ``E_c(x; f) = sum_i sum_p (x(p, i) -
    x(f_i(p), i + 1))^2``, couples a frame only to the previous one, which is
    known when the frame is synthesised; it is the soft constraint (2) with
    the previous frame warped along ``f_i`` as the target ``x^c``. Warping
    is backward with :func:`texsynth.core.flows.warp`.

    The M-step of a frame ranks, for every ``x_p``, the current ``z_p``, the
    previous frame's ``z`` carried along the flow, the ``z`` of the four grid
    neighbours shifted by the offset to them (coherent candidates, Ashikhmin
    2001) and, in the first iteration of each size, the index's nearest
    neighbour of the completed-square query; the exact criterion
    ``||x_p - v||^2 + λ E_c`` decides; the index is searched only in the
    first iteration of each size.

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
       for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
       2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`

    Examples
    --------
    >>> from texsynth import data
    >>> from texsynth.core import flows
    >>> ex = data.load("bumpy")[:32, :32]
    >>> f = flows.translation((24, 24), (0.0, 2.0))
    >>> video = animate_texture(ex, f, n_frames=3, neighborhood_sizes=(8,), levels=1,
    ...                         max_iterations=2, max_frame_iterations=1, rng=0)
    >>> video.shape
    (3, 24, 24, 3)
    """
    t_start = time.perf_counter()
    if not callable(flows) and np.ndim(flows) not in (3, 4):
        raise ValueError(f"flows must have shape (H, W, 2) or (L-1, H, W, 2), or be a callable, got shape {np.shape(flows)}")
    seq = flow_sequence(flows, n_frames)
    shape = seq.shape[1:3]
    sizes = check_sizes(neighborhood_sizes)
    fsizes = sizes[-2:] if frame_sizes is None else check_sizes(frame_sizes, "frame_sizes")
    max_frame_iterations = check_positive_int(max_frame_iterations, "max_frame_iterations")
    warp_order = check_positive_int(warp_order, "warp_order", minimum=0)
    if warp_order > 5:
        raise ValueError(f"warp_order must be a spline order in 0..5 (3: cubic), got {warp_order}")
    if frame_falloff is not None:
        frame_falloff = check_positive_float(frame_falloff, "frame_falloff")
    problem = _prepare(exemplar, shape, sizes, levels, constraint_weight=constraint_weight)
    _prepare(exemplar, shape, fsizes, 1, sizes_name="frame_sizes")  # frame_sizes against the frame size
    opts = _check_options(irls_exponent=irls_exponent, relative_grid_spacing=relative_grid_spacing,
                          max_iterations=max_iterations,
                          tolerance=tolerance, gradient_weight=gradient_weight, tileable=tileable, falloff=falloff,
                          method=method)
    lam = check_positive_float(constraint_weight, "constraint_weight", allow_zero=True, maximum=_MAX_WEIGHT)
    ex = problem.ex
    _check_memory(shape, ex.shape[-1], opts, frames=seq.shape[0] + 1)
    rng = as_rng(rng)
    count = seq.shape[0] + 1
    bar = Progress(progress, count, "animate_texture")
    info = AnimationInfo(first=None)
    try:
        if first_frame is None:
            x, info.first = _synthesize(problem, opts, rng, desc="frame 1")
        else:
            x = _check_like(first_frame, shape, ex.shape[-1], "first_frame").astype(ex.dtype)
        x = np.clip(x, 0.0, 1.0)
        cache = {}  # the frames' exemplar indexes, built once for the whole sequence
        if info.first is not None:
            sources = _source_map(info.first.centers, info.first.sources, shape)
        else:
            sources = _first_sources(x, problem, fsizes[-1], opts, rng, cache)
        bar.advance({"frame": 1})
        video = [x]
        seconds = []
        wmode = "wrap" if tileable else "nearest"
        for i in range(seq.shape[0]):
            t0 = time.perf_counter()
            # eq. 3 as eq. 2: the previous frame warped along f_i is target and initialisation;
            # its correspondence with the exemplar, carried along f_i too, offers every z_p a
            # coherent candidate (the index is searched once per size and frame)
            warped, ok = warp(x, seq[i], mode=wmode, spline_order=warp_order, return_valid=True)
            constraint = (ok.astype(np.float64), warped, lam)
            coords = warp_coordinates(sources, seq[i], mode=wmode)
            frame = dataclasses.replace(problem, sizes=fsizes, levels=1, constraint=constraint, x_init=warped)
            frame_opts = dataclasses.replace(opts, max_iterations=max_frame_iterations, coords=coords,
                                             assembly=frame_falloff)
            x, finfo = _synthesize(frame, frame_opts, rng, cache=cache, desc=f"frame {i + 2}")
            x = np.clip(x, 0.0, 1.0)
            sources = _source_map(finfo.centers, finfo.sources, shape)
            video.append(x)
            info.frames.append(finfo)
            seconds.append(time.perf_counter() - t0)
            bar.advance({"frame": i + 2, "energy": float(finfo.energy[-1])})
    finally:
        bar.close()
    info.frame_seconds = np.asarray(seconds)
    info.seconds = time.perf_counter() - t_start
    if info.first is not None:
        info.first.seconds = info.seconds - float(info.frame_seconds.sum())
    out = np.stack([restore_channels(v, problem.grey) for v in video])
    return (out, info) if return_info else out
