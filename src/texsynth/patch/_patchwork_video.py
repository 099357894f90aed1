"""Harrison's patchwork for video: looping video textures (Harrison 2002, Section 4).

Patches stay fixed in space (the Voronoi cells of :mod:`texsynth.patch._patchwork`);
each cell plays its own *intermediate sequence* ``N_i(x, t)``, a chain of input
clips joined by cosine transitions (eqs. 3-6), and every output frame pieces the
cells' frames together with eq. 2. Symbols as in :mod:`texsynth.patch._patchwork`
(the paper's Table 1), plus ``t`` (output frame), ``tau`` (input frame),
``p_{i,k}`` (key frames of cell ``i``'s sequence) and ``q_{i,k}`` (their input
frames), ``A(x)`` (the input's average over time).

References
----------
.. [1] P. Harrison, "Patchwork texture synthesis", Technical report,
   Monash University, 2002, Section 4.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_memory, check_positive_int, is_auto,
                              with_channels)
from ._patchwork import (SOURCE_MIN_WEIGHT, Geometry, band_sources, blend, check_grid_spacing, check_neighbors,
                         check_output_memory, check_sharpness, finish_output, padded_flat, patchwork_info,
                         warn_if_cells_leave)

__all__ = ["patchwork_video"]


# --------------------------------------------------------------------------
# Section 4: video


class _Intermediate:
    """The intermediate sequences ``N_i(x, t)`` of every cell (eqs. 3-6), evaluated lazily.

    Each cell has key frames ``p_{i,k}`` evenly spaced over the output loop
    (with a random phase per cell, so cells change source at different times)
    and source frames ``q_{i,k}`` chosen so that ``t - p_{i,k} + q_{i,k}``
    stays inside the input for the two intervals around ``p_{i,k}``. The last
    interval wraps to the first key plus ``n_frames``: the loop is seamless.
    """

    def __init__(self, n_cells, n_frames, n_input, spacing, gen):
        self.N = n_frames
        nk = max(1, math.ceil(n_frames / spacing))
        step = n_frames / nk
        phase = gen.random((n_cells, 1)) * step
        keys = np.floor(phase + np.arange(nk) * step).astype(np.intp)  # p_{i,k}
        self.keys = np.concatenate([keys, keys[:, :1] + n_frames], 1)  # ... and p_{i,nk} = p_{i,0} + N
        length = np.diff(self.keys, axis=1)  # L_k = p_{k+1} - p_k
        before = np.roll(length, 1, axis=1)  # L_{k-1}
        # t - p_k ranges over (-L_{k-1}, L_k) where frame k has nonzero weight
        first, last = before - 1, n_input - length
        q = first + np.floor(gen.random(first.shape) * (last - first + 1)).astype(np.intp)
        self.sources = np.concatenate([q, q[:, :1]], 1)  # q_{i,nk} = q_{i,0}

    def at(self, t):
        """Per-cell source frames and coefficients of eq. 6 at output frame ``t``."""
        p0 = self.keys[:, 0]
        tt = p0 + np.mod(t - p0, self.N)  # t in [p_0, p_0 + N)
        k = np.sum(self.keys[:, :-1] <= tt[:, None], axis=1) - 1
        rows = np.arange(len(tt))
        pk, pk1 = self.keys[rows, k], self.keys[rows, k + 1]
        u = (tt - pk) / (pk1 - pk)  # eq. 5
        w1 = 0.5 + 0.5 * np.cos(np.pi * u)  # eq. 3
        w2 = 0.5 - 0.5 * np.cos(np.pi * u)  # eq. 4
        tau1 = tt - pk + self.sources[rows, k]
        tau2 = tt - pk1 + self.sources[rows, k + 1]
        norm = np.sqrt(w1**2 + w2**2)
        # eq. 6: N = (w1 I1 + w2 I2 - A) / sqrt(w1^2 + w2^2) + A = c1 I1 + c2 I2 + cA A
        coef = np.stack([w1 / norm, w2 / norm, 1 - 1 / norm], 1).astype(np.float32)
        return tau1, tau2, coef


def check_video(frames, name="frames"):
    video = as_image(frames, name, spatial_dims=3)
    if video.shape[0] < 2:
        raise ValueError(
            f"{name} must hold at least 2 frames (T, H, W[, C]), got {video.shape[0]}; "
            "for a single image use patchwork()"
        )
    return video


def resolve_frame_spacing(frame_spacing, n_input, n_frames):
    """Spacing of the key frames: longest allowed by default (two intervals must fit in the input)."""
    longest = (n_input + 1) // 2
    if is_auto(frame_spacing):  # a third of the input: long transitions, and varied source frames q_i
        return max(1, min((n_input + 2) // 3, n_frames))
    d = check_positive_int(frame_spacing, "frame_spacing")
    if 2 * d - 1 > n_input:
        raise ValueError(
            f"frame_spacing {d} needs at least {2 * d - 1} input frames, got {n_input}; "
            f"pass frame_spacing <= {longest}"
        )
    return d


def _frame_slots(coords, omega, slot_cells, tau1, tau2, coef):
    """One output frame's source-coordinate map (eqs. 2 and 6): every cell's slot (its input pixel
    ``coords``, coefficient ``omega`` of eq. 2, cell ``slot_cells``) split into its three terms of eq.
    6, ``c1 I(tau1) + c2 I(tau2) + cA A``: input frames ``tau1``, ``tau2`` and -1 (the average frame
    ``A``), weights ``omega * c``; slots of weight below ``SOURCE_MIN_WEIGHT`` dropped."""
    from ..core.coordinates import compact_slots

    shape = omega.shape[:-1] + (3 * omega.shape[-1],)
    frames = np.stack([tau1[slot_cells], tau2[slot_cells], np.full_like(slot_cells, -1)], -1).reshape(shape)
    weights = (omega[..., None] * coef[slot_cells]).reshape(shape)
    weights[np.abs(weights) < SOURCE_MIN_WEIGHT] = 0  # as patchwork: terms below 1/512 left out
    coords = np.repeat(coords, 3, axis=-2)
    return compact_slots(coords, weights, frames)


def _video_map(pieces, n_frames, H, W):
    """The per-frame maps ``(rows, (coordinates, weights, frames) per frame)`` of the bands assembled into
    ``(n_frames, H, W, K, 2)``, ``(n_frames, H, W, K)`` and ``(n_frames, H, W, K)`` arrays."""
    from ..core.coordinates import compact_slots

    k = max(w.shape[-1] for _, frames in pieces for _, w, _ in frames)
    check_memory(float(n_frames) * H * W * k * (16 + 4 + 8), (H, W), what="the source-coordinate map",
                 also={"n_frames": n_frames})
    coordinates = np.zeros((n_frames, H, W, k, 2), np.int64)
    weights = np.zeros((n_frames, H, W, k), np.float32)
    sources = np.zeros((n_frames, H, W, k), np.intp)
    for idx, frames in pieces:
        for t, (c, w, f) in enumerate(frames):
            n = w.shape[-1]
            coordinates[t, idx, :, :n], weights[t, idx, :, :n], sources[t, idx, :, :n] = c, w, f
    flat = compact_slots(coordinates.reshape(n_frames * H, W, k, 2), weights.reshape(n_frames * H, W, k),
                         sources.reshape(n_frames * H, W, k))
    return tuple(a.reshape((n_frames, H) + a.shape[1:]) for a in flat)


def synthesize_video(geom, vid, n_frames, spacing, gen, local_means, progress, desc, record=False):
    """Output frames: eq. 2 (or 7) over the intermediate sequences' frames, one Voronoi arrangement.

    ``record`` (eq. 2 only): also return the source-coordinate map of every frame (:func:`_video_map`),
    else None."""
    T, Hin, Win, C = vid.shape
    H, W = geom.rows.n_out, geom.cols.n_out
    n_cells = geom.grid_shape[0] * geom.grid_shape[1]
    seq = _Intermediate(n_cells, n_frames, T, spacing, gen)
    src = vid.astype(np.float32)
    A = src.mean(0)  # A(x), the per-pixel average over time (eq. 6)
    a = None
    if local_means is None:
        a = src.reshape(-1, C).mean(0, dtype=np.float64).astype(np.float32)  # a, eq. 2
        src = src - a
        A = A - a
    pads = geom.pad()
    top, bottom, left, right = pads
    if any(pads):
        src = np.pad(src, ((0, 0), (top, bottom), (left, right), (0, 0)), mode="symmetric")
    A_flat, width = padded_flat(A, pads)
    frame_size = A_flat.shape[0]
    video = src.reshape(-1, C)
    out = np.empty((n_frames, H, W, C), np.float32)
    bands = geom.bands()
    bar = Progress(progress, len(bands) * n_frames, desc)
    cells = np.zeros((H, W), np.intp)
    pieces = []  # record: per band, its rows and each frame's map (bookkeeping beside the blend)
    for band in bands:
        parts, cell_blocks = geom.band_weights(band, width, pads, need_cells=True)
        idx, block_cells = geom.to_output(band, cell_blocks[..., None])
        cells[idx] = block_cells[..., 0]
        if record:
            band_map = [geom.to_output(band, x)[1] for x in band_sources(parts, pads, width, (Hin, Win), True)]
            pieces.append((idx, []))
        for t in range(n_frames):
            tau1, tau2, coef = seq.at(t)
            if record:
                pieces[-1][1].append(_frame_slots(*band_map, tau1, tau2, coef))

            def sample(n, ids, flat, tau1=tau1, tau2=tau2, coef=coef):
                c = coef[ids][:, None, :, None, :, None]  # (By, 1, Bx, 1, 3, 1)
                o1 = (tau1[ids] * frame_size)[:, None, :, None]
                o2 = (tau2[ids] * frame_size)[:, None, :, None]
                return (
                    c[..., 0, :] * video.take(flat + o1, axis=0)
                    + c[..., 1, :] * video.take(flat + o2, axis=0)
                    + c[..., 2, :] * A_flat.take(flat, axis=0)
                )

            blended = blend(parts, sample, C, local_means)
            _, rows = geom.to_output(band, blended)
            out[t, idx] = rows if a is None else rows + a
            bar.advance({"band": band.start, "frame": t})
    bar.close()
    return out, cells, seq, _video_map(pieces, n_frames, H, W) if record else None


def patchwork_video(
    frames,
    size,
    n_frames,
    *,
    grid_spacing="auto",
    sharpness=6,
    frame_spacing="auto",
    tileable=False,
    neighbors=4,
    rng=None,
    return_info=False,
    progress=False,
):
    """Synthesise a looping video texture (Harrison 2002, Section 4).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> metal = texsynth.data.load("metal")[:64, :64]
    >>> clip = np.stack([np.roll(metal, t, axis=1) for t in range(6)])  # drifting texture
    >>> loop, info = texsynth.patchwork_video(clip, 48, 8, grid_spacing=16, rng=0, return_info=True)
    >>> loop.shape
    (8, 48, 48)

    Patches are fixed in space; each cell plays its own *intermediate
    sequence*, a chain of input clips joined by cosine transitions (eqs. 3-6),
    and every output frame pieces the cells' frames together with eq. 2.
    Static parts of the input stay static. The output loops seamlessly: its
    last frame leads into its first as smoothly as any two consecutive
    frames [1]_.

    Parameters
    ----------
    frames : array_like
        Input video ``(T, H, W)`` or ``(T, H, W, C)`` with ``T >= 2``.
    size : int or (int, int)
        Output frame size ``(height, width)``.
    n_frames : int
        Number of output frames (the loop length).
    grid_spacing, sharpness, tileable, neighbors : see :func:`~texsynth.patch.patchwork`
        Spatial patches (paper: 64 and ``f = 6``).
    frame_spacing : int or "auto"
        Spacing of the key frames ``p_i`` of the intermediate sequences (the
        length of one transition). The paper gives no value; ``"auto"``
        (default) is ``(T + 2) // 3`` (at most ``n_frames``), which leaves about ``T / 3``
        choices for each source frame ``q_i``. At most ``(T + 1) // 2``: the
        two intervals around a key frame must fit in the input.
    rng : None, int or numpy.random.Generator
        Random source.
    return_info : bool
        Also return a :class:`~texsynth.patch.PatchworkInfo` (``frame_keys``,
        ``frame_sources`` hold the temporal ``p_i``, ``q_i``), with the
        source-coordinate map of every output frame (``coordinates``,
        ``weights``, ``source_index``: which input frame, -1 for the
        average frame ``A``), which :func:`texsynth.apply_coordinates`
        renders another channel sequence through (see Notes). The map
        takes 28 bytes a slot, and ``K`` (the most slots any pixel of any
        frame uses) is 2-3 times :func:`~texsynth.patch.patchwork`'s: 33 for a 128 px
        output at ``grid_spacing=32`` (8.5 used on average), 0.9 kB per
        pixel and frame.
    progress : bool or callable
        Report progress per output frame.

    Returns
    -------
    video : numpy.ndarray
        ``(n_frames, height, width[, C])``.
    info : PatchworkInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        For fewer than 2 input frames, a ``grid_spacing`` larger than the
        frames, ``sharpness <= 0`` or a ``frame_spacing`` the input is too
        short for.

    Notes
    -----
    With ``u = (t - p_i) / (p_{i+1} - p_i)`` (eq. 5), the transition weights
    are ``w_1 = 1/2 + cos(pi u)/2`` (eq. 3) and ``w_2 = 1/2 - cos(pi u)/2``
    (eq. 4), and the intermediate sequence is (eq. 6)

    .. math:: N(x, t) = \\frac{w_1 I(x, t - p_i + q_i) + w_2 I(x, t - p_{i+1}
              + q_{i+1}) - A(x)}{\\sqrt{w_1^2 + w_2^2}} + A(x)

    where ``A(x)`` is the average of the input over time. Since
    ``w_1 + w_2 = 1`` this equals ``(w_1 (I_1 - A) + w_2 (I_2 - A)) /
    sqrt(w_1^2 + w_2^2) + A``: the temporal variation about ``A`` keeps its
    standard deviation through a transition.

    Intermediate pixels are computed only where and when needed, so memory
    is proportional to the input plus the output.

    Eq. 6 is linear in the input, ``N = c_1 I_1 + c_2 I_2 + c_A A``, so eq. 2
    over the cells' ``N_i`` is a weighted sum of input pixels, each in some
    input frame, plus the mean ``a``: ``info.coordinates`` records it per
    output frame, three slots per cell (frames ``tau_1``, ``tau_2`` and the
    average frame ``A``, source -1), and rendering the input frames through
    it (``apply_coordinates(list(frames), info)``) reproduces the video up
    to the cells of coefficient below 1/512 and the clipping to [0, 1]
    (``tests/test_coordinates.py``); in the example above:

    >>> bool(np.abs(np.clip(texsynth.apply_coordinates(list(clip), info), 0, 1) - loop).max() < 0.01)
    True

    Another channel of the same clip (a height or normal sequence, one
    image per input frame) then animates exactly as the colour did.

    References
    ----------
    .. [1] P. Harrison, "Patchwork texture synthesis", Technical report,
       Monash University, 2002, Section 4.
    """
    start = time.perf_counter()
    video = check_video(frames)
    vid, grey = with_channels(video, spatial_dims=3)
    H, W = as_size(size)
    N = check_positive_int(n_frames, "n_frames")
    f = check_sharpness(sharpness)
    m = check_neighbors(neighbors)
    s = check_grid_spacing(grid_spacing, vid.shape[1:3], f, m, "frames")
    spacing = resolve_frame_spacing(frame_spacing, vid.shape[0], N)
    gen = as_rng(rng)
    check_output_memory((H, W), vid.shape[-1], s, frames=N, cells=return_info)
    if return_info:  # the map holds at least the 3 terms of eq. 6 of one cell per pixel and frame (typically 15-20)
        check_memory(float(N) * H * W * 3 * (16 + 4 + 8), (H, W), what="the source-coordinate map of return_info",
                     also={"n_frames": N})
    geom = Geometry((H, W), vid.shape[1:3], s, f, m, check_bool(tileable, "tileable"), gen)
    warn_if_cells_leave(geom, s, vid.shape[1:3], f, m, "frames")
    out, cells, seq, sources = synthesize_video(geom, vid, N, spacing, gen, None, progress, "patchwork_video",
                                                 record=return_info)
    result, clipped = finish_output(out, video.dtype, grey)
    if return_info:
        coordinates, weights, frame_index = sources
        info = patchwork_info(geom, cells, clipped, start, frame_keys=seq.keys[:, :-1], frame_sources=seq.sources[:, :-1],
                     coordinates=coordinates, weights=weights, source_index=frame_index)
        return result, info
    return result
