"""Keyframe-guided stylisation of a clip (in the spirit of Jamriška et al. 2019, "Stylizing video by example").

The module reads top-down as the paper's method does (its section numbers were not checked, so none are
quoted), built from texsynth's own parts:

- the motion: a dense optical flow between consecutive frames (:func:`texsynth.core.flows.estimate_flows`,
  TV-L1), or flows the user gives;
- the guides: for a keyframe ``k`` painted as ``S_k`` and a frame ``t``,
  pairs of images (source side: frame ``k``; target side: frame ``t``) that say which part of the
  painting belongs where:

  * ``G_col``: the frames' own colours (``I_k`` / ``I_t``; not one of the paper's guides, see Notes),
  * ``G_edge``: a difference of Gaussians of the frames' luminance (``E_k`` / ``E_t``),
  * ``G_pos``: the keyframe's pixel coordinates, advected along the motion to frame ``t``,
  * ``G_temp``: the painting itself against the previous output warped along the motion to frame ``t``
    (``S_k`` / ``Ô_{t∓1}``), which keeps consecutive outputs alike;

- the synthesis: each frame is one guided patch synthesis with ``S_k`` as the exemplar and the guide
  pairs as extra channels (:func:`texsynth.core.em.with_guides`), by the EM parts of texture
  optimization (:mod:`texsynth.core.em`: PatchMatch M-step, weighted-average E-step, IRLS weights),
  started from the warped previous output and from the previous frame's correspondence carried along
  the motion; the paper uses StyLit's synthesis (Fišer et al. 2016) with its uniformity term instead;
- the propagation: every keyframe's style is carried forward to the next keyframe and backward to the
  previous one, frame by frame;
- the blend: between two keyframes each frame has two syntheses, one per keyframe; they
  are blended with weights by temporal distance, linearly, or in the gradient domain (each pixel's
  gradients from the synthesis with the lower error, weighted by temporal distance, integrated by a
  screened Poisson solve around the linear blend). The paper's temporally coherent selection is not
  reproduced: most pixels change synthesis at once at the middle frame, a visible pop.

References
----------
.. [1] O. Jamriška, Š. Sochorová, O. Texler, M. Lukáč, J. Fišer, J. Lu, E. Shechtman and D. Sýkora,
   "Stylizing video by example", ACM Transactions on Graphics (SIGGRAPH 2019) 38(4).
   :doi:`10.1145/3306346.3323006`
.. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for example-based synthesis",
   ACM TOG 24(3), 2005. :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import dataclasses
import numbers
import time

import numpy as np
from scipy import ndimage

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, check_choice, check_group, check_memory, check_positive_float,
                              check_positive_int, is_auto, restore_channels, with_channels)
from ..core.em import (Average, ExemplarPatches, Schedule, StageInfo, carried_field, check_sizes, coarse_to_fine,
                       expectation_maximization, field_step, prepare, robust_energy, solve_gradient_system,
                       source_map, with_guides)
from ..core.flows import FLOW_METHODS, estimate_flows, flow_sequence, warp, warp_coordinates
from ..core.neighborhood import gaussian_falloff, grid_centers

__all__ = ["stylize_video", "StylizeInfo", "KEYFRAME_BLENDS"]

#: How the syntheses of two keyframes are blended between them.
KEYFRAME_BLENDS = ("gradient", "linear")
# "auto" schedule: neighbourhood sizes, and levels of every frame's synthesis with the temporal guide (a warm
# start from the last frame) and without it (each frame from random neighbourhoods)
_AUTO_SIZES = (8,)
_AUTO_LEVELS = 1
_AUTO_LEVELS_ALONE = 2
# The EM stop test of the energy when the schedule's tolerance is "auto"
_TOLERANCE = 5e-3
# PatchMatch iterations of a stage's first M-step and of each later one (as texture optimization's)
_FIELD_ITERATIONS_FIRST = 4
_FIELD_ITERATIONS = 1
# The E-step's fall-off in grid spacings (None: the exemplar's, w/4)
_ASSEMBLY = 0.25
# The IRLS exponent r (Kwatra et al. 2005, Section 3.1)
_IRLS = 0.8
# Edge guide: the difference of Gaussians sigma_1 < sigma_2 (pixels), and the gain that maps it into [0, 1]
_DOG_SIGMAS = (1.0, 2.0)
# Gradient blend: the weight of the linear blend against the chosen gradients (screened Poisson: structures
# larger than about 1/sqrt(_SCREEN) pixels follow the linear blend; at 0.05, 4-5 px, the middle frames between two
# keyframes were as hazy as the linear blend's; at 0.002 they keep the painting's contrast), and the
# width of the Gaussian that smooths the error maps before a pixel's gradients are chosen (neighbourhood sizes)
_SCREEN = 0.002
_ERROR_SMOOTHING = 1.0
# Tried and not kept: each pixel switching from one synthesis to the other at its own time (a smooth threshold
# field carried along the motion) took the middle frame's pop (flicker 0.10-0.15 at the two middle transitions of
# 12 frames of waves at 96^2, 0.03-0.04 elsewhere) down to 0.05-0.07 at every transition between the keyframes,
# but the mean rose (0.055 against 0.051) and every blended frame showed hazy seams between the two syntheses


@dataclasses.dataclass
class StylizeInfo:
    """What :func:`stylize_video` computed.

    Attributes
    ----------
    flows : numpy.ndarray
        ``(T - 1, H, W, 2)``: the motion between consecutive frames used (estimated or given).
    keyframes : tuple of int
        The keyframe indices, sorted.
    weights : numpy.ndarray
        ``(T, K)``: the share of each keyframe's synthesis in each output frame (the linear blend's weights;
        rows sum to 1).
    errors : numpy.ndarray
        ``(K, T, H, W)``: each keyframe's synthesis error per pixel (the patch distance ``ρ_p`` of the nearest
        neighbourhood centre, per value), NaN where that keyframe was not synthesised (0 at the keyframe).
    energies : numpy.ndarray
        ``(K, T)``: the last energy of each synthesis (NaN where there was none).
    syntheses : int
        Frames synthesised (frames between two keyframes count twice).
    seconds : float
        Wall time in all.
    stage_seconds : dict
        ``{"flows": ..., "synthesis": ...}``: of the optical flow, and of the syntheses and blends.
    """

    flows: np.ndarray
    keyframes: tuple
    weights: np.ndarray
    errors: np.ndarray
    energies: np.ndarray
    syntheses: int = 0
    seconds: float = 0.0
    stage_seconds: dict = dataclasses.field(default_factory=dict)


# --------------------------------------------------------------------------- inputs
def _check_keyframes(keyframes, n_frames, shape):
    """``{index: painting}`` (or a list of pairs) as a sorted list of ``(index, (H, W, C) float)``, checked."""
    if isinstance(keyframes, dict):
        pairs = list(keyframes.items())
    elif isinstance(keyframes, (list, tuple)):
        pairs = list(keyframes)
        if not all(isinstance(p, (list, tuple)) and len(p) == 2 for p in pairs):
            raise TypeError("keyframes must be a dict {frame index: painted image} or a list of (frame index, "
                            "painted image) pairs")
    else:
        raise TypeError(f"keyframes must be a dict {{frame index: painted image}} or a list of (index, image) pairs, "
                        f"got {type(keyframes).__name__}")
    if not pairs:
        raise ValueError("keyframes is empty; pass at least one painted frame, e.g. {0: painting}")
    out, grey = {}, None
    for index, image in pairs:
        if not isinstance(index, numbers.Integral) or isinstance(index, bool):
            raise TypeError(f"keyframes: a frame index must be an int, got {type(index).__name__} {index!r}")
        index = int(index)
        if not 0 <= index < n_frames:
            raise ValueError(f"keyframes: frame index {index} is outside the clip's frames 0..{n_frames - 1}")
        if index in out:
            raise ValueError(f"keyframes: frame {index} is painted twice; pass one painting per frame")
        arr, g = with_channels(as_image(image, f"keyframes[{index}]"))
        if arr.shape[:2] != tuple(shape):
            raise ValueError(f"keyframes[{index}] has shape {arr.shape[:2]} but the frames are {tuple(shape)}; "
                             f"paint keyframes at the frames' size")
        if grey is not None and (g != grey or arr.shape[-1] != next(iter(out.values())).shape[-1]):
            raise ValueError(f"keyframes[{index}] has {arr.shape[-1]} channel(s), unlike the other keyframes; pass "
                             f"paintings with the same channels")
        grey = g
        out[index] = arr
    return sorted(out.items()), grey


def _edges(luminance):
    """The edge guide: a difference of Gaussians of the luminance, mapped into [0, 1] around 0.5."""
    s1, s2 = _DOG_SIGMAS
    dog = np.stack([ndimage.gaussian_filter(f, s1) - ndimage.gaussian_filter(f, s2) for f in luminance])
    scale = 4.0 * float(np.abs(dog).std()) + 1e-12  # the clip's own contrast: the same map for every frame
    return np.clip(0.5 + dog / (2 * scale), 0.0, 1.0)


def _pull(image, flow, order=1):
    """``image`` of frame ``t + 1`` seen from frame ``t`` (``out[p] = image[p + flow[p]]``, edges clamped): the
    backward propagation of an output along the forward flow ``flow`` of frame ``t``."""
    h, w = flow.shape[:2]
    rows, cols = np.meshgrid(np.arange(h, dtype=np.float64), np.arange(w, dtype=np.float64), indexing="ij")
    at = [rows + flow[..., 0], cols + flow[..., 1]]
    return np.stack([ndimage.map_coordinates(image[..., c], at, order=order, mode="nearest")
                     for c in range(image.shape[-1])], axis=-1)


def _push(image, flow, order=1):
    """``image`` of frame ``t`` moved into frame ``t + 1`` along ``flow`` (forward propagation)."""
    return warp(image, flow, mode="nearest", spline_order=order)


# --------------------------------------------------------------------------- one frame
class _Frame:
    """The guided synthesis of one frame from one keyframe's painting (composed from :mod:`texsynth.core.em`)."""

    def __init__(self, schedule, rng, assembly=_ASSEMBLY):
        self.sizes, self.levels, self.iterations, self.tolerance, self.spacing = schedule
        self.rng, self.assembly = rng, assembly

    def __call__(self, style, source_guide, target_guide, weight, init, prior):
        """``style`` ``(H, W, C)``; guides ``(H, W, G)`` in [0, 1]; ``weight`` the guides' weight; ``init`` the
        start image (or None); ``prior`` ``(H, W, 2)`` style positions per pixel to warm-start from (or None).
        Returns the image, its dense style positions, the per-pixel error and the last energy."""
        rng, shape = self.rng, style.shape[:2]
        problem = prepare(style, shape, self.sizes, self.levels, init=init)
        problem = with_guides(problem, source_guide, target_guide, weight)
        channels = style.shape[-1]
        last = {}

        def stage(ex, x, level, record, bar):
            w = ex.size
            spacing = max(1, int(round(w * self.spacing)))
            centers = grid_centers(level.shape, w, spacing, mode="valid")
            n = len(centers)
            # the E-step assembles each pixel mostly from its nearest centres' z_p (a fall-off of a quarter of
            # the grid spacing, as animate_texture's frames): the plain average of the overlapping z_p softens
            # every frame a little, and the temporal guide carries the softening on to the next
            sharp = None if self.assembly is None else gaussian_falloff(w, self.assembly * spacing)
            average = Average(ex, centers, level.shape, "valid", x=x, guide=level.guide, falloff=sharp,
                              first_falloff=sharp)
            info = StageInfo(level=level.index, size=w, shape=tuple(level.shape), spacing=spacing, neighborhoods=n,
                             exemplar_neighborhoods=len(ex), first=len(record.energy))
            if record.stages:  # the last stage's field, carried to this grid (Section 3.2's up-sampling)
                start = ex.lookup(carried_field(record, level.index, centers) - w // 2, rng.integers(len(ex), size=n))
            elif prior is not None:  # the previous frame's correspondence, carried along the motion
                f = 2 ** level.index
                at = np.minimum(centers * f, np.asarray(shape) - 1)
                start = ex.lookup(prior[at[:, 0], at[:, 1]] / f - w // 2, rng.integers(len(ex), size=n))
            else:
                start = rng.integers(len(ex), size=n)

            def match(x, state):  # the state is (z_p, completeness matches): Average's form, with no such term
                zidx = state[0]
                info.m_steps += 1
                its = _FIELD_ITERATIONS_FIRST if info.m_steps == 1 else _FIELD_ITERATIONS
                new, rho = field_step(ex, x, centers, "valid", ex.centers(zidx), its, rng)
                return (new, None), rho, not np.array_equal(new, zidx)

            def energy(rho, x):
                e = robust_energy(rho, _IRLS, ex.eps2, x, None)
                record.log(e, float(rho.mean()) / float(ex.weights.sum()))
                return e

            rho, state = None, (start, None)
            if x is not None:
                state, rho, _ = match(x, state)
            x, (zidx, _), rho, its, converged = expectation_maximization(
                x, state, rho, average, match, energy, max_iterations=self.iterations, tolerance=self.tolerance,
                r=_IRLS, eps2=ex.eps2)
            info.iterations, info.converged = its, converged
            record.finish(info, centers, ex.centers(zidx), None)
            last.update(rho=rho / float(ex.weights.sum()), centers=centers, level=level.index)
            return x

        def patches(level, size, image, valid):
            return ExemplarPatches(image, valid, size, method="exact", rng=rng, guided=True)

        x, info = coarse_to_fine(problem, stage, patches, iterations=self.iterations, coordinates=False)
        x = np.clip(x[..., :channels], 0.0, 1.0)
        positions = source_map(info.centers, info.sources, shape)
        error = _dense(last["rho"], last["centers"], shape, last["level"])
        return x, positions, error, float(info.energy[-1])


def _dense(values, centers, shape, level):
    """Per-pixel values of the grid ``centers`` (at pyramid ``level``): each pixel takes its nearest centre's."""
    f = 2 ** level
    near = []
    for axis, length in enumerate(shape):
        grid = np.unique(centers[:, axis]) * f
        pos = np.arange(length)
        k = np.clip(np.searchsorted(grid, pos), 1, max(len(grid) - 1, 1))
        near.append(np.where(pos - grid[k - 1] <= grid[np.minimum(k, len(grid) - 1)] - pos, k - 1, k)
                    if len(grid) > 1 else np.zeros_like(pos))
    ncols = len(np.unique(centers[:, 1]))
    return values[near[0][:, None] * ncols + near[1][None, :]]


# --------------------------------------------------------------------------- the blend
def _gradient_blend(images, errors, weights):
    """The paper's gradient-domain blend in a simple form: two syntheses ``images`` blended in the gradient domain.

    Every pixel takes its gradients from the synthesis whose smoothed error over its temporal weight is the
    lower, and the gradients are integrated by a screened Poisson solve around the linear blend."""
    linear = np.einsum("k,khwc->hwc", weights, images)
    score = np.stack([e / max(wt, 1e-12) for e, wt in zip(errors, weights)])
    choice = np.argmin(score, axis=0)
    masks = [(choice == k).astype(np.float64) for k in range(len(images))]
    gx = sum(0.5 * (m[:, 1:] + m[:, :-1])[..., None] * (im[:, 1:] - im[:, :-1]) for m, im in zip(masks, images))
    gy = sum(0.5 * (m[1:] + m[:-1])[..., None] * (im[1:] - im[:-1]) for m, im in zip(masks, images))
    shape = linear.shape[:2]
    data_w = np.full(shape, _SCREEN)
    x = solve_gradient_system(data_w, _SCREEN * linear, np.ones((shape[0], shape[1] - 1)), gx,
                              np.ones((shape[0] - 1, shape[1])), gy, 1.0, False, linear.copy())
    return np.clip(x, 0.0, 1.0)


# --------------------------------------------------------------------------- the method
def stylize_video(frames, keyframes, *, schedule=Schedule(), color_weight=1.0, edge_weight=1.0, positional_weight=2.0,
                  temporal_weight=0.5, keyframe_blend="gradient", flows=None, rng=None, progress=False,
                  return_info=False):
    """Paint every frame of a clip in the style of its painted keyframes (Jamriška et al. 2019).

    Examples
    --------
    >>> import texsynth
    >>> frames = texsynth.data.clip("waves", n_frames=3, size=24)
    >>> painting = 1.0 - frames[0]  # any painted version of frame 0
    >>> schedule = texsynth.Schedule(neighborhood_sizes=(6,), levels=1, max_iterations=1)
    >>> texsynth.stylize_video(frames, {0: painting}, schedule=schedule, rng=0).shape
    (3, 24, 24, 3)

    Every frame ``t`` is a guided patch synthesis whose exemplar is the
    painting ``S_k`` of a keyframe ``k`` and whose guides pair frame ``k``
    with frame ``t``: their colours, their edges, the keyframe's pixel
    positions carried along the motion to frame ``t``, and the painting
    against the previous output carried to frame ``t`` (the temporal guide).
    Each keyframe's style is carried frame by frame forward to the next
    keyframe and backward to the previous one (to the clip's ends beyond the
    first and last); between two keyframes the two syntheses are blended by
    temporal distance. A keyframe's own output is its painting.

    Parameters
    ----------
    frames : array_like
        ``(T, H, W)`` or ``(T, H, W, C)`` the clip.
    keyframes : dict or list
        ``{frame index: painting}`` or a list of ``(frame index, painting)``;
        each painting ``(H, W)`` or ``(H, W, C')`` at the frames' size (its
        channels need not be the frames': the output has the paintings').
    schedule : Schedule
        Every frame's synthesis (:class:`texsynth.core.em.Schedule`):
        ``neighborhood_sizes`` (``"auto"``: ``(8,)``), ``levels``
        (``"auto"``: 1 with the temporal guide, whose frames start from
        the last output; 2 without), ``relative_grid_spacing``, ``max_iterations`` per
        stage (5 is the class's default; the doctest uses 1) and
        ``tolerance`` (``"auto"``: 5e-3 of the energy).
    color_weight, edge_weight, positional_weight, temporal_weight : float
        The weights of the guide pairs against the painting's own colours
        (``0`` leaves a guide out): the frames' colours, their edges (a
        difference of Gaussians), the advected keyframe positions and the
        temporal guide. ``temporal_weight=0`` also makes every frame
        independent of the last (no warm start): each frame on its own.
    keyframe_blend : {"gradient", "linear"}
        Between two keyframes: ``"linear"``, the two syntheses weighted by
        temporal distance; ``"gradient"``, each pixel's gradients taken from
        the synthesis whose error over its weight is lower, integrated
        around the linear blend (a screened Poisson solve).
    flows : array_like, optional
        ``(T - 1, H, W, 2)`` the motion, flow ``i`` the displacement of frame
        ``i``'s pixels into frame ``i + 1`` (:mod:`texsynth.core.flows`), or
        ``"tvl1"`` / ``"ilk"``: estimated by
        :func:`texsynth.core.flows.estimate_flows` (None: ``"tvl1"``).
    rng : None, int or numpy.random.Generator
        Seeds PatchMatch; the same seed gives the same clip.
    progress : bool or callable
        Counts syntheses.
    return_info : bool
        Also return a :class:`StylizeInfo`.

    Returns
    -------
    video : numpy.ndarray
        ``(T, H, W[, C'])``, the paintings' channel layout.
    info : StylizeInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        Keyframe indices outside the clip or given twice, paintings of
        another size, flows of another shape, negative weights, a
        neighbourhood larger than a frame, or a clip too large for memory.
    TypeError
        Keyframes that are neither a dict nor a list of pairs.

    Notes
    -----
    Frame ``t`` minimises, as texture optimization does (Kwatra et al.
    2005, eq. 1 with IRLS weights), ``E = sum_p ||x̃_p - z̃_p||^r`` over the
    neighbourhoods of ``x̃ = [O_t, √w_col I_t, √w_edge E_t, √w_pos P_t,
    √w_temp Ô_{t∓1}]`` and of the exemplar ``[S_k, √w_col I_k, √w_edge E_k,
    √w_pos P_k, √w_temp S_k]`` (all weights relative to the largest, which
    becomes the core's ``guide_weight``); only ``O_t`` is synthesised.
    ``P`` holds normalised ``(row, col)`` positions; ``P_t`` is ``P_k``
    carried along the motion and ``Ô_{t∓1}`` the previous output carried to
    frame ``t``. Carrying forward warps along the flow
    (:func:`texsynth.core.flows.warp`), carrying backward samples frame
    ``t + 1`` at ``p + f_t(p)``.

    The paper [1]_ synthesises with StyLit's (Fišer et al. 2016) patch
    retrieval with a uniformity term and uses an edge, a positional and a
    temporal guide; here the colour guide is added (the frames' own colours
    hold most of what says where a painting's colours go on these clips),
    the synthesis is Kwatra et al.'s EM with PatchMatch, and the blend is
    the simple one described under ``keyframe_blend``.

    References
    ----------
    .. [1] O. Jamriška, Š. Sochorová, O. Texler, M. Lukáč, J. Fišer, J. Lu,
       E. Shechtman and D. Sýkora, "Stylizing video by example", ACM TOG
       38(4), 2019. :doi:`10.1145/3306346.3323006`
    """
    t_start = time.perf_counter()
    video = as_image(frames, "frames", spatial_dims=3)
    video = video if video.ndim == 4 else video[..., None]
    n, shape = video.shape[0], video.shape[1:3]
    keys, grey = _check_keyframes(keyframes, n, shape)
    channels = keys[0][1].shape[-1]
    sched = check_group(schedule, Schedule, "schedule")
    weights = {name: check_positive_float(value, name, allow_zero=True, maximum=1e6) for name, value in
               (("color_weight", color_weight), ("edge_weight", edge_weight),
                ("positional_weight", positional_weight), ("temporal_weight", temporal_weight))}
    sizes = _AUTO_SIZES if is_auto(sched.neighborhood_sizes) else check_sizes(sched.neighborhood_sizes)
    levels = sched.levels
    if is_auto(levels):
        levels = _AUTO_LEVELS if weights["temporal_weight"] != 0 else _AUTO_LEVELS_ALONE
    iterations = check_positive_int(sched.max_iterations, "max_iterations")
    tolerance = _TOLERANCE if is_auto(sched.tolerance) else sched.tolerance
    if tolerance is not None:
        tolerance = check_positive_float(tolerance, "tolerance", allow_zero=True)
    spacing = check_positive_float(sched.relative_grid_spacing, "relative_grid_spacing", maximum=1.0)
    prepare(keys[0][1], shape, sizes, levels)  # the sizes against the frames, before any work
    blend = check_choice(keyframe_blend, "keyframe_blend", KEYFRAME_BLENDS)
    # memory: the clip, its guides and flows, a synthesis per keyframe side, the result (float64), and one
    # frame's exemplar with its guides and PatchMatch's patches
    per_frame = float(shape[0]) * shape[1] * 8
    guide_channels = video.shape[-1] + 1 + 2 + channels
    need = per_frame * n * (video.shape[-1] + 2 + 1 + 3 * channels + 2) \
        + per_frame * (channels + guide_channels) * (sizes[0] ** 2 // max(1, int(spacing * sizes[0]) ** 2) + 4)
    check_memory(need, (n,) + tuple(shape), "frames", "the stylised clip, its guides and flows")
    t0 = time.perf_counter()
    if flows is None or isinstance(flows, str):
        estimator = check_choice("tvl1" if flows is None else flows, "flows", FLOW_METHODS)
        motion = estimate_flows(video, estimator=estimator) if n > 1 else np.zeros((0,) + tuple(shape) + (2,))
    else:
        if n < 2:
            raise ValueError("flows was given for a clip of one frame; pass flows=None")
        motion = flow_sequence(flows, n, shape=shape)
    flow_seconds = time.perf_counter() - t0
    rng = as_rng(rng)

    # the guides of every frame: colours, edges (the paper's edge guide)
    colour = video
    luminance = video.mean(axis=-1) if video.shape[-1] != 3 else video @ np.array([0.2125, 0.7154, 0.0721])
    edges = _edges(luminance)[..., None]
    rows, cols = np.meshgrid(np.linspace(0, 1, shape[0]), np.linspace(0, 1, shape[1]), indexing="ij")
    positions = np.stack([rows, cols], axis=-1)
    top = max(weights.values())
    scale = {k: np.sqrt(v / top) if top > 0 else 0.0 for k, v in weights.items()}
    temporal = weights["temporal_weight"] > 0
    synth = _Frame((tuple(sizes), levels, iterations, tolerance, spacing), rng)
    k_index = [k for k, _ in keys]
    outputs = {}  # (key slot, frame) -> image
    errors = np.full((len(keys), n) + tuple(shape), np.nan)
    energies = np.full((len(keys), n), np.nan)
    plan = []  # (key slot, direction, last frame)
    for slot, (k, _) in enumerate(keys):
        back = k_index[slot - 1] + 1 if slot > 0 else 0
        ahead = k_index[slot + 1] - 1 if slot + 1 < len(keys) else n - 1
        plan += [(slot, -1, back), (slot, +1, ahead)]
    total = sum(abs(end - keys[slot][0]) for slot, d, end in plan)
    bar = Progress(progress, max(total, 1), "stylize_video")

    def guide(t):  # the frame's own guides: colours and edges
        return [scale["color_weight"] * colour[t], scale["edge_weight"] * edges[t]]

    try:
        for slot, direction, end in plan:
            k, painting = keys[slot]
            outputs[slot, k] = painting
            errors[slot, k] = 0.0
            source_side = np.concatenate(guide(k) + [scale["positional_weight"] * positions,
                                                     scale["temporal_weight"] * painting], axis=-1)
            out, pos, prior = painting, positions, positions * (np.asarray(shape) - 1)
            for t in range(k + direction, end + direction, direction):
                f = motion[t - 1] if direction > 0 else motion[t]
                move = _push if direction > 0 else _pull
                carried = np.clip(move(out, f), 0.0, 1.0)
                pos = np.clip(move(pos, f), 0.0, 1.0)
                target_side = np.concatenate(guide(t) + [scale["positional_weight"] * pos,
                                                         scale["temporal_weight"] * carried], axis=-1)
                # the correspondence with the painting, carried without blurring (each pixel its source's)
                start = None if not temporal else (warp_coordinates(prior, f) if direction > 0
                                                   else _pull(prior, f, order=0))
                out, prior, error, energy = synth(painting, source_side, target_side, top,
                                                  carried if temporal else None, start)
                outputs[slot, t], errors[slot, t], energies[slot, t] = out, error, energy
                bar.advance({"frame": t, "keyframe": k, "energy": energy})
    finally:
        bar.close()

    # the blend: by temporal distance between the two keyframes around a frame
    share = np.zeros((n, len(keys)))
    result = np.empty((n,) + tuple(shape) + (channels,))
    for t in range(n):
        after = int(np.searchsorted(k_index, t))
        if after < len(keys) and k_index[after] == t:
            share[t, after] = 1.0
        elif after == 0:
            share[t, 0] = 1.0
        elif after == len(keys):
            share[t, -1] = 1.0
        else:
            a, b = k_index[after - 1], k_index[after]
            share[t, after - 1], share[t, after] = (b - t) / (b - a), (t - a) / (b - a)
        used = np.flatnonzero(share[t] > 0)
        images = np.stack([outputs[s, t] for s in used])
        if len(used) == 1 or blend == "linear":
            result[t] = np.einsum("k,khwc->hwc", share[t, used], images)
        else:
            smooth = [ndimage.gaussian_filter(errors[s, t], _ERROR_SMOOTHING * sizes[0]) for s in used]
            result[t] = _gradient_blend(images, smooth, share[t, used])
    out = np.stack([restore_channels(f, grey) for f in result]).astype(keys[0][1].dtype, copy=False)
    if not return_info:
        return out
    seconds = time.perf_counter() - t_start
    info = StylizeInfo(flows=motion, keyframes=tuple(k_index), weights=share, errors=errors, energies=energies,
                       syntheses=total, seconds=seconds,
                       stage_seconds={"flows": flow_seconds, "synthesis": max(0.0, seconds - flow_seconds)})
    return out, info
