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

Not in the paper: orientation and magnification fields (the local frames of Zhang et
al. 2003, :mod:`texsynth.core.fields`) turn and magnify the texture locally:
the M-step samples every ``x_p`` on a grid turned and scaled around its
centre, the E-step splats ``z_p`` back there (:class:`WarpedPatches`; the Notes of
:func:`optimize_texture`).

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
   for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
   2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import dataclasses
import functools
import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import (as_rng, check_bool, check_choice, check_group, check_in_range, check_memory,
                              check_positive_float, check_positive_int, restore_channels)
from ..core.em import (MAX_WEIGHT, Animation, AnimationInfo, Average, Completeness, Constraints, ExemplarPatches, Fields, Guides,
                       Occurrence, Schedule, SearchMemo, StageInfo, Terms, WarpedPatches, carried_field,
                       check_constraint_memory, check_like, check_sizes, coarse_to_fine, confidence_weights,
                       expectation_maximization, field_step, frame_step, frame_terms, free_inside, histogram_groups,
                       irls_weights, nearest_step, prepare, robust_energy, source_map, touching_free, with_fields,
                       with_guides, with_margin)
from ..core.flows import flow_sequence, warp, warp_coordinates
from ..core.neighborhood import gaussian_falloff, grid_centers
from ..core.scale import scale_schedule
from ..core.search import ExemplarAtlas, Search, check_field_method, coherence_sets, is_auto, refuse_augment, resolve_field

__all__ = ["optimize_texture", "animate_texture", "PRESETS"]

# animate_texture: the stop test of the energy when the schedule's tolerance is "auto", and the terms its frames
# (Algorithm 2 with the warped previous frame as the target) leave off
_FRAME_TOLERANCE = 5e-3
_FRAME_TERMS_OFF = dict(occurrence_weight=0.0, copy_limit=None, completeness_weight=0.0, histogram_matching=False)
# M-step: search a neighbourhood again only if x_p moved since its last search by more than
# this fraction of the distance to its match then (0: search every neighbourhood every time)
_RESEARCH_TOLERANCE = 0.03
#: Presets of :func:`optimize_texture`: what its ``"auto"`` options mean.
PRESETS = ("default", "paper")
# preset "default": the stop test of the energy (an addition to the paper's test of unchanged z_p)
_DEFAULT_TOLERANCE = 5e-3
# preset "default": the completeness term is on at every level when the output has less than this many
# times the exemplar's area (at 1.5x the texture energy alone missed parts of every tuning photo), and
# at every level but the finest from there on: on the finest level too its votes blurred large flat
# areas of cobblestones at 4x, while without it at the coarse levels the arrangement kept coming back
# to a few parts of the exemplar (completeness 1.4-3.8 times a random-block mosaic's on the tuning
# photos at 4x, 1.1-2.4 with it; docs/methods/kwatra.md)
_COMPLETE_BELOW = 4.0
# preset "default": copy_limit (largest copies at 4x measured 0.66-0.77 of the exemplar without it)
_DEFAULT_COPY_LIMIT = 0.25
# preset "default" without the completeness term: the copy limit at the finest level, which otherwise
# only refines the coarser levels' arrangement (0.25 there cut blocks and stones mid-element at 4x; 0.3
# cuts only the outlying copies: cobblestones_2 0.35 -> 0.30, bricks_2 at 8x 0.36 -> 0.31, no visible
# change; docs/methods/kwatra.md)
_FINE_COPY_LIMIT = 0.3
# PatchMatch M-step: iterations of propagation and random search in a stage's first M-step (from the
# previous stage's field carried over, or from random neighbourhoods) and in each later one (from the
# current z_p)
_FIELD_ITERATIONS_FIRST = 4
_FIELD_ITERATIONS = 1

# --------------------------------------------------------------------------- results


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
    augment: str = "none"  # Search.augment: the exemplar's flipped and rotated copies are searched too (an atlas)

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
        return resolve_field(self.method, applies=applies, values=values) == "patchmatch"

    @property
    def index_method(self):
        """The index backend of the other M-steps (``"auto"`` lets the search profile decide)."""
        return "auto" if self.method == "patchmatch" else self.method

# --------------------------------------------------------------------------- features

# --------------------------------------------------------------------------- fields

# --------------------------------------------------------------------------- E-step

# --------------------------------------------------------------------------- M-step


# --------------------------------------------------------------------------- one stage
def _run_stage(opts, rng, labels, ex, x, at, record, progress):
    """Algorithm 1 (or 2) with the neighbourhoods ``ex`` of one size at the :class:`~texsynth.core.em.Level`
    ``at`` (its output guide: the last channels of ``x`` and of the exemplar, given, never synthesised);
    ``labels`` ``(L, G)``: the label vectors when the guides are label maps (:func:`histogram_groups`)."""
    t0 = time.perf_counter()
    level, shape, constraint, guide, fields = at.index, at.shape, at.constraint, at.guide, at.fields
    w = ex.size
    spacing = opts.grid(w)
    mode = opts.mode
    centers = grid_centers(shape, w, spacing, mode=mode)
    coords = opts.coords  # animation frame: the previous frame's correspondence, warped
    # hard constraints (λ = ∞) are in x_p already: the M-step is the plain nearest neighbour, and the
    # E-step weighs each neighbourhood by its confidence (Wexler et al. 2007)
    hard = constraint is not None and np.isinf(constraint[2])
    if hard and coords is None:
        free = touching_free(constraint[0], centers, w, spacing, mode)
        centers = centers[free] if free.any() else centers  # nothing free: the target, as every E-step makes it
    warp = None if fields is None else WarpedPatches(centers, w, *fields, shape, mode)
    stage = StageInfo(level=level, size=w, shape=tuple(shape), spacing=spacing, neighborhoods=len(centers),
                      exemplar_neighborhoods=len(ex), first=len(record.energy))
    nn = 0.0
    r, eps2 = opts.r, ex.eps2
    values = float(ex.weights.sum())

    prior = None if coords is None else ex.lookup(coords[centers[:, 0], centers[:, 1]] - w // 2, 0)
    fixed = None if coords is None else frame_terms(ex, centers, mode, constraint, ex.image.shape[-1])

    searched = None if hard else constraint
    confidence = None
    if hard and coords is None and opts.confidence is not None:
        confidence = confidence_weights(constraint[0], centers, w, mode, opts.confidence)
    use_field = opts.field(searched, ex, len(centers))
    stack = use_field and warp is not None  # fields: PatchMatch on the sampled neighbourhoods (nearest_step)
    use_field = use_field and not stack
    memo = SearchMemo(n=len(centers), dim=None if use_field else ex.weights.shape[0])
    weight, limit = opts.occurrence, opts.copy_limit
    occurrence = None
    finest = level == 0 and record.levels > 1  # the finest of several levels refines the arrangement
    if opts.coarse_copy_limit and finest:
        limit = _FINE_COPY_LIMIT  # only outlying copies are cut
    if (weight > 0 or limit is not None) and coords is None:
        occurrence = Occurrence(ex, centers, weight, limit)
    completeness = None
    lam = 0.0 if opts.coarse_completeness and finest else opts.completeness
    if lam > 0 and coords is None:
        completeness = Completeness(ex, centers, lam, spacing)
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
        if record.stages:
            carried = ex.lookup(carried_field(record, level, centers) - w // 2, carried)

    def frame_field(x, b):
        """A frame's searched candidates: PatchMatch's nearest of every ``x_p``, one iteration from the
        prior (the last frame's correspondence carried along the flow, already close)."""
        if prior is None:
            return field_step(ex, x, centers, mode, ex.centers(rng.integers(len(ex), size=n)),
                              _FIELD_ITERATIONS_FIRST, rng)[0]
        return field_step(ex, x, centers, mode, ex.centers(prior), _FIELD_ITERATIONS, rng)[0]

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
            first = stage.m_steps == 1 and not record.stages
            # a penalty that binds nowhere changes no ranking: the plain M-step
            occ = occurrence if occurrence is not None and occurrence.binding else None
            return field_step(ex, x, centers, mode, ex.centers(start), its, rng, occ,
                              None if first else sets, workspace)
        if coords is None:
            occ = None
            if occurrence is not None and zidx is not None:
                occurrence.update(ex, zidx)
                occ = occurrence if occurrence.binding else None
            if not stack:
                return nearest_step(ex, x, centers, mode, zidx, searched, memo, _RESEARCH_TOLERANCE, occ, warp)
            its = _FIELD_ITERATIONS_FIRST if stage.m_steps == 1 else _FIELD_ITERATIONS
            return nearest_step(ex, x, centers, mode, carried if zidx is None else zidx, searched, memo,
                                _RESEARCH_TOLERANCE, occ, warp, its, rng)
        # searched once per stage (PatchMatch from the prior, or the index); later iterations rank
        # coherent candidates
        memo.searched += len(centers) if zidx is None else 0
        return frame_step(ex, x, centers, mode, zidx, fixed, prior,
                          lookup=(frame_field if use_field else True) if zidx is None else False)

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
    groups = []
    if opts.histogram and searched is None and coords is None:  # no constraint, or hard ones
        # with hard constraints only the pixels nothing constrains are matched (uncrop, hole filling)
        free = None if constraint is None else constraint[0] < 1e-6
        groups = histogram_groups(ex, n_colours, free, shape, guide, labels)
    average = Average(ex, centers, shape, mode, constraint=constraint, x=x, warp=warp, confidence=confidence,
                      completeness=completeness, occurrence=occurrence, histograms=groups, guide=guide,
                      first_falloff=g0, falloff=ga)

    def match(x, state):
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
        state, rho, _ = match(x, (None, None))

    def log(rho, x):
        e = robust_energy(rho[:n], r, eps2, x, constraint)
        if completeness is not None:
            e += completeness.scale * float(np.sum((rho[n:] + eps2) ** (r / 2.0)))
        record.log(e, float(rho[:n].mean()) / values)
        return e

    max_it = opts.max_iterations
    # the penalised M-step may raise E on purpose (it breaks up copies): only the paper's
    # test, unchanged z_p, ends such a stage early
    tolerance = opts.tolerance if occurrence is None else None

    def report(it, energy, stop):
        stage.iterations = it + 1
        progress.advance({"level": level, "size": w, "iteration": it, "energy": energy},
                         n=max_it - it if stop else 1)

    x, (zidx, _), rho, _, stage.converged = expectation_maximization(
        x, state, rho, average, match, log, max_iterations=max_it, tolerance=tolerance, r=r, eps2=eps2,
        on_iteration=report,
    )
    stage.seconds, stage.nn_seconds, stage.searches = time.perf_counter() - t0, nn, memo.searched
    # for the source-coordinate map (computed once, after the last stage): what the last E-step weighs
    record.finish(stage, centers, ex.centers(zidx),
                  (level, ex, centers, zidx, irls_weights(rho[:n], r, eps2), tuple(shape), mode, warp))
    return x

# --------------------------------------------------------------------------- validation


def _check_options(schedule, terms, search, *, tileable, k=4, fields=False, confidence=None, paper=False,
                   coarse_copy_limit=False, coarse_completeness=False):
    """The options of one synthesis (no ``"auto"`` left in the groups), checked, as an :class:`_Options`."""
    k = check_positive_int(k, "k")
    method, candidates = search.method, search.resolved_candidates("all")
    if candidates == "k-coherent":
        # the k-coherent M-step is PatchMatch's propagation with the sets in place of its random search:
        # it goes where PatchMatch goes
        clash = ("gradient_weight > 0 (the gradient energy takes the index M-step)" if terms.gradient_weight else
                 "preset='paper' (the paper's M-step searches a tree)" if paper else
                 "orientation/magnification fields (rotated neighbourhoods take their own M-step)" if fields else
                 f"method={method!r} (an index M-step)" if method not in ("auto", "patchmatch") else None)
        if clash is None and search.augment != "none":
            clash = f"augment={search.augment!r} (the k-coherence sets are those of the exemplar itself)"
        if clash is not None:
            raise ValueError(f"candidates='k-coherent' does not combine with {clash}; pass candidates='all'")
    if confidence is not None and check_positive_float(confidence, "confidence", maximum=MAX_WEIGHT) <= 1:
        raise ValueError(f"confidence must be None or a base gamma > 1 (Wexler et al.: 1.3), got {confidence!r}")
    copy_limit = terms.copy_limit
    return _Options(
        histogram=check_bool(terms.histogram_matching, "histogram_matching"), paper=paper,
        coarse_copy_limit=coarse_copy_limit, coarse_completeness=coarse_completeness, fields=fields,
        confidence=None if confidence is None else float(confidence),
        r=check_in_range(terms.irls_exponent, "irls_exponent", 0.0, 2.0, low_open=True),
        mu=check_positive_float(terms.gradient_weight, "gradient_weight", allow_zero=True, maximum=MAX_WEIGHT),
        spacing=check_in_range(schedule.relative_grid_spacing, "relative_grid_spacing", 0.0, 1.0, low_open=True),
        max_iterations=check_positive_int(schedule.max_iterations, "max_iterations", maximum=MAX_ITERATIONS),
        tolerance=check_positive_float(schedule.tolerance, "tolerance", allow_zero=True),
        tileable=check_bool(tileable, "tileable"),
        falloff=check_bool(terms.falloff, "falloff"),
        method=check_field_method(method),
        occurrence=check_positive_float(terms.occurrence_weight, "occurrence_weight", allow_zero=True,
                                        maximum=MAX_WEIGHT),
        copy_limit=None if copy_limit is None else check_in_range(copy_limit, "copy_limit", 0.0, 1.0, low_open=True),
        completeness=check_positive_float(terms.completeness_weight, "completeness_weight", allow_zero=True,
                                          maximum=MAX_WEIGHT),
        candidates=candidates, k=k, augment=search.augment,
    )


def _preset(preset, problem, schedule, terms):
    """The groups with their ``"auto"`` values resolved by ``preset``, and the preset's flags (see
    :func:`optimize_texture`, Notes)."""
    ratio = problem.shape[0] * problem.shape[1] / (problem.ex.shape[0] * problem.ex.shape[1])
    if preset == "paper":
        auto = dict(tolerance=0.0, completeness_weight=0.0, copy_limit=None, histogram_matching=False)
    else:
        auto = dict(tolerance=_DEFAULT_TOLERANCE, completeness_weight=1.0, copy_limit=_DEFAULT_COPY_LIMIT,
                    histogram_matching=True)
    given = dict(tolerance=schedule.tolerance, completeness_weight=terms.completeness_weight,
                 copy_limit=terms.copy_limit, histogram_matching=terms.histogram_matching)
    out = {k: auto[k] if is_auto(v) else v for k, v in given.items()}
    out["completeness_weight"] = check_positive_float(out["completeness_weight"], "completeness_weight",
                                                      allow_zero=True, maximum=MAX_WEIGHT)
    # from 4x the exemplar's area the finest level only refines the arrangement: no completeness votes there
    # (they blur) and a looser copy limit (elements stay whole)
    coarse = preset == "default" and ratio >= _COMPLETE_BELOW
    flags = dict(coarse_completeness=coarse and is_auto(terms.completeness_weight), paper=preset == "paper")
    fine_votes = out["completeness_weight"] > 0 and not flags["coarse_completeness"]
    flags["coarse_copy_limit"] = preset == "default" and is_auto(terms.copy_limit) and not fine_votes
    schedule = dataclasses.replace(schedule, tolerance=out.pop("tolerance"))
    return schedule, dataclasses.replace(terms, **out), flags


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


# --------------------------------------------------------------------------- public API
def optimize_texture(exemplar, size, *, preset="default", schedule=Schedule(), terms=Terms(), search=Search(),
                     constraints=Constraints(), guides=Guides(), fields=Fields(), init=None, tileable=False, rng=None,
                     progress=False, return_info=False):
    """Synthesise a texture by texture optimization (Kwatra et al. 2005).

    Examples
    --------
    >>> import texsynth
    >>> exemplar = texsynth.data.load("bumpy")[:32, :32]
    >>> schedule = texsynth.Schedule(neighborhood_sizes=(16, 8), levels=1, max_iterations=2)
    >>> out, info = texsynth.optimize_texture(exemplar, 40, schedule=schedule, rng=0, return_info=True)
    >>> out.shape, [(s.level, s.size) for s in info.stages]
    ((40, 40, 3), [(0, 16), (0, 8)])

    Minimises the texture energy (eq. 1) of the output over its
    neighbourhoods on a sparse grid by alternating a weighted-average E-step
    and a nearest-neighbour M-step (Algorithm 1), with robust IRLS weights
    (Section 3.1), coarse-to-fine over resolution levels and neighbourhood
    sizes (Section 3.2), an optional gradient term, and optional soft
    constraints (Section 4, Algorithm 2) for controlled synthesis and hole
    filling [1]_.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` grey or ``(h, w, C)`` input texture ``Z``: uint8, uint16,
        bool or float, converted to float in [0, 1] (docs/conventions.md).
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
    schedule : Schedule
        The stages and when each stops (:class:`~texsynth.core.em.Schedule`):
        ``neighborhood_sizes`` (used largest first at every level, only
        those that fit the level, see Notes), ``levels``,
        ``relative_grid_spacing`` (centres ``w/4`` apart), ``max_iterations``
        (5: "usually 3-5 iterations per resolution/scale level were found to
        be enough", Section 5) and ``tolerance``. ``"auto"`` values follow
        ``preset``.
    terms : Terms
        The energy (:class:`~texsynth.core.em.Terms`): ``irls_exponent``
        (``r`` of Section 3.1, 0.8), ``gradient_weight`` (``μ`` of Section 3,
        0: off; the paper uses 10), ``falloff``, ``occurrence_weight``
        (Kaspar et al. 2015), ``copy_limit`` (ours, see Notes),
        ``completeness_weight`` (Simakov et al. 2008) and
        ``histogram_matching`` (after Kopf et al. 2007). ``"auto"``
        values follow ``preset``.
    search : Search
        The M-step's search (:class:`~texsynth.core.search.Search`).
        ``method``: the backend per (level, size) stage; ``"patchmatch"``
        is PatchMatch (Barnes et al. 2009) between the output and the
        exemplar, warm-started from the current ``z_p``, for the colour
        energy without soft constraints (the gradient energy and Algorithm 2
        take an index); ``"auto"`` (default) takes PatchMatch on stages where
        an exact search would compare more than
        :data:`~texsynth.core.search.FIELD_MIN_VALUES` values (preset
        ``"default"``), otherwise an index (exact on small levels, the PCA
        kd-tree above). ``candidates="k-coherent"``: k-coherent search
        (Ashikhmin 2001; Tong et al. 2002) in place of PatchMatch's
        random search on every stage, with k-coherence sets of ``k``
        (``"auto"``: 4) neighbourhoods, for the colour energy without soft
        constraints or fields, preset ``"default"``. The M-step never accepts
        a worse ``z_p``, so no backend can raise the energy within a stage.
        ``augment``: every M-step also searches the exemplar's flipped or
        rotated copies (not with ``"k-coherent"``).
    constraints : Constraints
        Eq. 2 (:class:`~texsynth.core.em.Constraints`): ``mask``, ``target``,
        ``constraint_weight`` (``λ``; ``float("inf")``: hard constraints,
        how :func:`texsynth.inpaint` fills), ``confidence`` (Wexler et al.'s
        ``γ`` under hard constraints) and ``exemplar_mask`` (the exemplar
        pixels that may be copied).
    guides : Guides
        Guided synthesis ("texture by numbers", Hertzmann et al. 2001,
        :class:`~texsynth.core.em.Guides`): ``exemplar_guide``,
        ``output_guide`` and ``guide_weight``.
    fields : Fields
        Orientation and magnification fields over the output (after Zhang
        et al. 2003, :class:`~texsynth.core.em.Fields`): ``orientation`` and
        ``magnification`` (of the elements, not of the output); see Notes.
    init : array_like, optional
        Output-shaped initial image; the coarsest level starts from its
        down-sampled version instead of random neighbourhoods.
    tileable : bool
        Periodic output: neighbourhoods wrap around the edges, so the result
        tiles seamlessly.
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
        A value out of its range (each option's entry gives it), arrays of
        another shape than the exemplar or the output, NaN, one guide
        without the other, options that do not combine (fields with the
        gradient term or soft constraints, ``candidates="k-coherent"`` with
        soft constraints, ``confidence`` without hard constraints).
    TypeError
        Unsupported dtypes or argument types, an option group of another type.

    Notes
    -----
    The Notes of :class:`~texsynth.core.em.Terms` (copy limit),
    :class:`~texsynth.core.em.Fields` (orientation and magnification fields) and
    :class:`~texsynth.core.em.Schedule` (sizes per level) describe those
    options; :mod:`texsynth.core.em` states what the implementation
    guarantees about the energy.

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
    searches are skipped (docs/methods/kwatra.md measures it).
    Soft constraints, eq. (2), ``E_c(x; x^c) = sum_{k in C} (x(k) -
    x^c(k))^2``, enter the E-step as a weighted average with the targets
    and the M-step as ``argmin_v ||x_p - v||^2 + λ ||v - x^c_p||^2_C``
    (Algorithm 2). For ``λ = 0`` (and without ``occurrence_weight`` and
    ``copy_limit``) the energy provably never rises within a stage (module
    docstring); in the example above:

    >>> bool(np.all(np.diff(info.energy[info.stage == 1]) <= 1e-9 * info.energy[0]))
    True

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

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
       for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
       2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`
    """
    t_start = time.perf_counter()
    preset = check_choice(preset, "preset", PRESETS)
    sched, terms, search = (check_group(schedule, Schedule, "schedule"), check_group(terms, Terms, "terms"),
                            check_group(search, Search, "search"))
    cons, guides, fields = (check_group(constraints, Constraints, "constraints"), check_group(guides, Guides, "guides"),
                            check_group(fields, Fields, "fields"))
    problem = prepare(exemplar, size, sched.neighborhood_sizes, sched.levels, constraint_weight=cons.constraint_weight,
                      mask=cons.mask, target=cons.target, exemplar_mask=cons.exemplar_mask, init=init,
                      auto_schedule=scale_schedule if preset == "default" else None)
    sched, terms, flags = _preset(preset, problem, sched, terms)
    problem = with_guides(problem, guides.exemplar_guide, guides.output_guide, guides.guide_weight)
    problem = with_fields(problem, fields.orientation, fields.magnification)
    tileable = check_bool(tileable, "tileable")
    margin = 0 if tileable or preset == "paper" or free_inside(problem) else problem.sizes[0] // 2
    opts = _check_options(sched, terms, search, tileable=tileable or margin > 0, k=search.resolved_k(4),
                          fields=problem.fields is not None, confidence=cons.confidence, **flags)
    if opts.confidence is not None and (problem.constraint is None or not np.isinf(problem.constraint[2])):
        raise ValueError("confidence weighs neighbourhoods by their distance to the known pixels of hard "
                         "constraints: pass mask, target and constraint_weight=float('inf'), or confidence=None")
    if opts.candidates == "k-coherent" and problem.constraint is not None and not np.isinf(problem.constraint[2]):
        raise ValueError("candidates='k-coherent' does not combine with soft constraints (Algorithm 2 takes the "
                         "index M-step); pass candidates='all', or constraint_weight=float('inf') for hard ones")
    if opts.fields and opts.mu > 0:
        raise ValueError(f"gradient_weight={opts.mu:g} does not combine with orientation/magnification fields (the "
                         f"gradient E-step solves on the pixel grid, not in rotated frames); pass "
                         f"gradient_weight=0 or no fields")
    shape = problem.shape
    if margin:  # a tileable canvas a little larger, cropped: no neighbourhood ends at the output's edges
        problem = with_margin(problem, margin)
    _check_memory(problem.shape, problem.ex.shape[-1], opts)
    check_constraint_memory(problem)
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
    """Coarse to fine (Section 3.2, :func:`texsynth.core.em.coarse_to_fine`); ``cache`` keeps the exemplar's
    neighbourhoods and their indexes across calls (animation frames). ``coordinates=False`` leaves the info's
    source-coordinate map out (nobody will see it)."""
    cache = {} if cache is None else cache
    # Search(augment=...): every level searches the atlas of its flipped and rotated copies, laid out alike
    atlas = None if opts.augment == "none" else ExemplarAtlas(problem.ex.shape[:2], opts.augment,
                                                              levels=problem.levels)

    def patches(level, w, image, valid):
        if (level, w) not in cache:
            cache[level, w] = ExemplarPatches(image, valid, w, gradient_weight=opts.mu, falloff=opts.falloff,
                                              method=opts.index_method, rng=rng, frame=opts.frame,
                                              guided=problem.guide is not None, atlas=atlas, level=level)
        return cache[level, w]

    return coarse_to_fine(problem, functools.partial(_run_stage, opts, rng, problem.labels), patches,
                          iterations=opts.max_iterations, wrap=opts.tileable, progress=progress, desc=desc,
                          coordinates=coordinates)


def _first_sources(x, problem, size, opts, rng, cache):
    """Correspondence of a given first frame: its nearest exemplar neighbourhoods (one M-step)."""
    centers = grid_centers(x.shape[:2], size, opts.grid(size), mode=opts.mode)
    exm = cache[(0, size)] = ExemplarPatches(problem.ex, problem.valid, size, gradient_weight=opts.mu,
                                             falloff=opts.falloff, method=opts.index_method, rng=rng, frame=True)
    zidx, _ = frame_step(exm, x, centers, opts.mode, None, None, None, lookup=True)
    return source_map(centers, exm.centers(zidx), x.shape[:2])


def animate_texture(exemplar, flows, *, n_frames=None, schedule=Schedule(), terms=Terms(), search=Search(),
                    animation=Animation(), tileable=False, first_frame=None, rng=None, progress=False,
                    return_info=False):
    """Animate a texture along a flow field (Kwatra et al. 2005, Section 4.1).

    Examples
    --------
    >>> import texsynth
    >>> exemplar = texsynth.data.load("bumpy")[:32, :32]
    >>> flow = texsynth.core.flows.translation((24, 24), (0.0, 2.0))  # 2 pixels right per frame
    >>> schedule = texsynth.Schedule(neighborhood_sizes=(8,), levels=1, max_iterations=2)
    >>> video = texsynth.animate_texture(exemplar, flow, n_frames=3, schedule=schedule,
    ...                                  animation=texsynth.Animation(max_frame_iterations=1), rng=0)
    >>> video.shape
    (3, 24, 24, 3)

    Frame 1 is an ordinary multi-level synthesis (:func:`optimize_texture`).
    Each next frame ``i + 1`` is initialised by warping frame ``i`` along the
    flow ``f_i`` and synthesised at a single resolution with the warped frame
    as the soft-constraint target (eq. 3 treated as eq. 2, Algorithm 2), so
    texture elements move with the flow but keep their shape [1]_.

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
    schedule, terms, search
        As in :func:`optimize_texture`, for frame 1 (``"auto"``: sizes 32, 16,
        8 over 3 levels as preset ``"paper"``, and a ``tolerance`` of 5e-3,
        which also ends the EM of each size of frames 2..L). Of ``terms``
        only ``irls_exponent``, ``gradient_weight`` and ``falloff`` apply,
        of ``search`` only ``method``, also for the frames' index (a kd-tree
        re-ranking 4 candidates with ``eps = 2`` when ``"auto"`` chooses it).
    animation : Animation
        The synthesis of frames 2..L (:class:`Animation`):
        ``frame_sizes``, ``max_frame_iterations``, ``constraint_weight``
        (``λ`` of the flow term), ``warp_order`` and ``frame_falloff``.
    tileable : bool
        Periodic frames: the warp wraps around, so every pixel has a target.
        Otherwise pixels that flow in from outside the frame are
        unconstrained and synthesised freely.
    first_frame : array_like, optional
        Use this ``(H, W[, C])`` image as frame 1 instead of synthesising it.
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

    The exemplar indexes are built once for the whole sequence, and frame
    ``i``'s correspondence with the exemplar (where each ``z_p`` came from),
    carried along ``f_i`` by :func:`texsynth.core.flows.warp_coordinates`,
    gives every neighbourhood of frame ``i + 1`` coherent candidates, so the
    index is searched only once per neighbourhood size and frame.

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
    """
    t_start = time.perf_counter()
    if not callable(flows) and np.ndim(flows) not in (3, 4):
        raise ValueError(f"flows must have shape (H, W, 2) or (L-1, H, W, 2), or be a callable, got shape "
                         f"{np.shape(flows)}")
    sched, terms, search = (check_group(schedule, Schedule, "schedule"), check_group(terms, Terms, "terms"),
                            check_group(search, Search, "search"))
    anim = check_group(animation, Animation, "animation")
    refuse_augment(search.augment, "animate_texture", "each frame continues the last one's correspondence with the "
                   "exemplar itself")
    unused = [f"{name}={getattr(terms, name)!r}" for name, off in _FRAME_TERMS_OFF.items()
              if getattr(terms, name) != off and not is_auto(getattr(terms, name))]
    unused += [f"{name}={getattr(search, name)!r}" for name in ("candidates", "k")
               if getattr(search, name) not in ("auto", "all")]
    if unused:
        raise ValueError(f"animate_texture does not use {', '.join(unused)} (the frames are Algorithm 2 with the "
                         f"warped previous frame as the target); leave them at their defaults")
    seq = flow_sequence(flows, n_frames)
    shape = seq.shape[1:3]
    # "auto" sizes and levels: the paper's (32, 16, 8) over 3 levels
    problem = prepare(exemplar, shape, sched.neighborhood_sizes, sched.levels, constraint_weight=anim.constraint_weight)
    fsizes = problem.sizes[-2:] if is_auto(anim.frame_sizes) else check_sizes(anim.frame_sizes, "frame_sizes")
    max_frame_iterations = check_positive_int(anim.max_frame_iterations, "max_frame_iterations")
    warp_order = check_positive_int(anim.warp_order, "warp_order", minimum=0)
    if warp_order > 5:
        raise ValueError(f"warp_order must be a spline order in 0..5 (3: cubic), got {warp_order}")
    frame_falloff = anim.frame_falloff
    if frame_falloff is not None:
        frame_falloff = check_positive_float(frame_falloff, "frame_falloff")
    prepare(exemplar, shape, fsizes, 1, sizes_name="frame_sizes")  # frame_sizes against the frame size
    sched = dataclasses.replace(sched, tolerance=_FRAME_TOLERANCE if is_auto(sched.tolerance) else sched.tolerance)
    opts = _check_options(sched, dataclasses.replace(terms, **_FRAME_TERMS_OFF), search, tileable=tileable)
    lam = check_positive_float(anim.constraint_weight, "constraint_weight", allow_zero=True, maximum=MAX_WEIGHT)
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
            x = check_like(first_frame, shape, ex.shape[-1], "first_frame").astype(ex.dtype)
        x = np.clip(x, 0.0, 1.0)
        cache = {}  # the frames' exemplar indexes, built once for the whole sequence
        if info.first is not None:
            sources = source_map(info.first.centers, info.first.sources, shape)
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
            sources = source_map(finfo.centers, finfo.sources, shape)
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
