"""What a coarse-to-fine EM synthesis did: its stages and energies, for plots and diagnostics."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["StageInfo", "OptimizationInfo", "AnimationInfo", "Record"]


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
        neighbourhood of the output came from (with ``Search(augment=...)``
        the exemplar pixel that the centre of its flipped or rotated copy shows).
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
class Record:
    """What the stages of one coarse-to-fine synthesis have done so far, kept while it runs.

    A stage appends its energies with :meth:`log` and itself with
    :meth:`finish`; :meth:`info` turns the whole into an
    :class:`OptimizationInfo`.

    Examples
    --------
    >>> record = Record(levels=1)
    >>> record.log(2.0, 0.5); record.log(1.5, 0.4)
    >>> record.energy
    [2.0, 1.5]
    """

    levels: int  # levels that run at least one stage
    energy: list = field(default_factory=list)
    mse: list = field(default_factory=list)
    stage: list = field(default_factory=list)
    stages: list = field(default_factory=list)
    centers: np.ndarray | None = None  # the last stage's centres and the exemplar centres of their z_p
    sources: np.ndarray | None = None
    dominant: tuple | None = None  # the arguments of dominant_sources for the last stage, and its level

    def log(self, energy, mse):
        """One energy value of the current stage and its mean squared difference per value."""
        self.energy.append(energy)
        self.mse.append(mse)
        self.stage.append(len(self.stages))

    def finish(self, stage, centers, sources, dominant):
        """The end of a stage: its :class:`StageInfo`, its centres and their sources."""
        self.stages.append(stage)
        self.centers, self.sources, self.dominant = centers, sources, dominant

    def info(self, coordinates):
        """The :class:`OptimizationInfo`, with the source-coordinate map if ``coordinates`` (and the last
        stage ran at full resolution): ``coordinates(*self.dominant[1:])`` computes it."""
        level, *last = self.dominant or (None,)
        # augmented copies: the sources as the exemplar pixels they show
        sources = self.sources if not last else last[0].to_exemplar(self.sources)
        return OptimizationInfo(
            energy=np.asarray(self.energy), mse=np.asarray(self.mse), stage=np.asarray(self.stage, dtype=int),
            stages=self.stages, centers=self.centers, sources=sources * (2 ** self.stages[-1].level),
            coordinates=coordinates(*last) if level == 0 and coordinates is not None else None,
        )


@dataclass
class AnimationInfo:
    """What a frame-by-frame synthesis (:func:`~texsynth.animate_texture`) did.

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
