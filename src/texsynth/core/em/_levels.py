"""Coarse to fine: an EM synthesis level by level and, within a level, size by size (Kwatra et al. 2005, Sec. 3.2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._progress import Progress
from ..fields import level_field
from ..pyramid import gaussian_pyramid, upsample
from ._problem import level_sizes, pyramids
from ._record import Record
from ._sources import dominant_sources

__all__ = ["coarse_to_fine", "Level"]


@dataclass(frozen=True, eq=False)
class Level:
    """One resolution level of a coarse-to-fine synthesis: what each of its stages works at.

    Attributes
    ----------
    index : int
        0 is full resolution, 1 half, 2 a quarter.
    shape : tuple of int
        The output's ``(H, W)`` at this level.
    constraint : tuple or None
        ``(mask, target, λ)`` of eq. 2 at this level (masks and targets down-sampled, ``λ`` unchanged).
    guide : numpy.ndarray or None
        ``(H, W, G)``: the output guide at this level (the last ``G`` channels of the output).
    fields : list or None
        ``[orientation, scale]`` at this level's pixels.
    """

    index: int
    shape: tuple
    constraint: tuple | None = None
    guide: np.ndarray | None = None
    fields: list | None = None


def coarse_to_fine(problem, run_stage, exemplar_patches, *, iterations, wrap=False, progress=False, desc="synthesis",
                   coordinates=True):
    """Run the stages of a synthesis coarse to fine (Section 3.2): each level's result, up-sampled, starts the next.

    The exemplar, its valid mask, the constraints, the initial image and the
    output guide get Gaussian pyramids (:func:`pyramids`); at every level the
    neighbourhood sizes that fit it (:func:`level_sizes`) run largest first.

    Parameters
    ----------
    problem : Problem
        The checked inputs (:func:`prepare`).
    run_stage : callable
        ``run_stage(exemplar, x, level, record, bar) -> x``: one stage with the exemplar's neighbourhoods of
        one size at this :class:`Level`, from ``x`` (None before the first); it logs into the
        :class:`Record` and advances the progress ``bar``.
    patches : callable
        ``patches(level, size, image, valid) -> ExemplarPatches`` of the exemplar level (the caller may keep
        them across calls: an animation's frames share them).
    iterations : int
        Iterations per stage at most (the progress bar's length).
    wrap : bool
        A periodic output: the pyramids and the up-sampling wrap round.
    progress : bool or callable
        As everywhere (``docs/conventions.md``).
    desc : str
        The progress bar's label.
    coordinates : bool
        Compute the source-coordinate map of the last stage (when it ran at full resolution).

    Returns
    -------
    x : numpy.ndarray
        The last stage's image.
    info : OptimizationInfo

    Examples
    --------
    See ``docs/architecture.md`` ("Add an EM method").
    """
    ex, shape = problem.ex, problem.shape
    mode = "wrap" if wrap else "reflect"
    ex_pyr, valid_pyr, out_shapes, cons_pyr, init_pyr = pyramids(
        ex, problem.valid, shape, problem.levels, problem.constraint, problem.x_init, wrap)
    guide_pyr = [None] * len(out_shapes)
    if problem.guide is not None:  # the output guide's pyramid, from the same code as the images'
        guide_pyr = [g.astype(ex.dtype, copy=False)
                     for g in gaussian_pyramid(problem.guide, len(out_shapes), mode=mode)]
    plan = level_sizes(problem.sizes, [e.shape[:2] for e in ex_pyr], out_shapes)
    if not any(plan):
        raise ValueError(f"no neighborhood size in {problem.sizes} fits the exemplar {ex.shape[:2]} and the output "
                         f"{shape}")
    record = Record(levels=sum(1 for p in plan if p))
    bar = Progress(progress, sum(len(p) for p in plan) * iterations, desc)
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
                    x = upsample(x, out_shapes[finer], mode=mode)
            x_level = level
            for w in plan[level]:
                exemplar = exemplar_patches(level, w, ex_pyr[level], valid_pyr[level])
                if len(exemplar) == 0:  # an exemplar mask leaves nothing at this level: skip it
                    continue
                fields = None if problem.fields is None else [level_field(f, level, out_shapes[level])
                                                              for f in problem.fields]
                x = run_stage(exemplar, x, Level(level, tuple(out_shapes[level]), cons_pyr[level], guide_pyr[level],
                                                 fields), record, bar)
    finally:
        bar.close()
    return x, record.info(dominant_sources if coordinates else None)
