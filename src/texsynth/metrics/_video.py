"""Metrics of clips: how frames follow one another."""

from __future__ import annotations

import math

import numpy as np

from ..core._validate import check_positive_int

__all__ = ["temporal_correlation", "flicker"]


def temporal_correlation(frames, lag=1):
    """The temporal correlation of a clip at ``lag`` frames, pooled over its pixels and channels.

    Examples
    --------
    >>> import numpy as np
    >>> from texsynth.metrics import temporal_correlation
    >>> t = np.arange(40)[:, None, None]
    >>> round(temporal_correlation(0.5 + 0.4 * np.sin(0.2 * t + np.zeros((1, 4, 4)))), 2)
    0.98

    With ``d(t) = y(t) - ybar`` (``ybar`` the per-value mean over time),
    ``sum_t <d(t), d(t + lag)> / sqrt(sum_t |d(t)|^2 sum_t |d(t + lag)|^2)`` over
    ``t = 1 .. T - lag``: near 1 for smooth motion, near 0 for frames in random order (a frame-shuffled
    clip), 0 for a static clip. A synthesised dynamic texture should keep its clip's value.

    Parameters
    ----------
    frames : array_like
        A clip ``(T, H, W[, C])`` with more than ``lag`` frames.
    lag : int
        Frames between the two frames compared.

    Returns
    -------
    float
        In [-1, 1].
    """
    frames = np.asarray(frames, np.float64)
    lag = check_positive_int(lag, "lag")
    if frames.ndim < 3 or frames.shape[0] <= lag:
        raise ValueError(f"frames must be a clip (T, H, W[, C]) with more than lag = {lag} frames, got shape "
                         f"{frames.shape}")
    d = frames - frames.mean(axis=0)
    a, b = d[:-lag].reshape(-1), d[lag:].reshape(-1)
    aa, bb = float(a @ a), float(b @ b)
    if min(aa, bb) <= 1e-24 * a.size:  # no change but the rounding of the mean: a static clip
        return 0.0
    return float(a @ b) / math.sqrt(aa * bb)


def flicker(frames, flows):
    """Temporal flicker: the mean absolute change between consecutive frames along the motion.

    Examples
    --------
    >>> import numpy as np
    >>> from texsynth.metrics import flicker
    >>> still = np.repeat(np.random.default_rng(0).random((1, 16, 16, 3)), 4, axis=0)
    >>> flicker(still, np.zeros((3, 16, 16, 2)))
    0.0

    Frame ``t + 1`` is seen from frame ``t`` (sampled at ``p + flows[t][p]``, bilinear, edges clamped)
    and compared with frame ``t``: 0 for a clip that only moves with the flows; a stylised clip whose
    frames are painted each on its own scores far above the clip it was painted from.

    Parameters
    ----------
    frames : array_like
        A clip ``(T, H, W[, C])``, ``T >= 2``.
    flows : array_like
        ``(T - 1, H, W, 2)`` displacements ``(d_row, d_col)`` from each frame to the next
        (:func:`texsynth.core.flows.estimate_flows`).

    Returns
    -------
    float
    """
    from scipy import ndimage

    frames = np.asarray(frames, np.float64)
    flows = np.asarray(flows, np.float64)
    if frames.ndim < 3 or frames.shape[0] < 2:
        raise ValueError(f"frames must be a clip (T, H, W[, C]) with at least 2 frames, got shape {frames.shape}")
    if flows.shape != (frames.shape[0] - 1,) + frames.shape[1:3] + (2,):
        raise ValueError(f"flows must have shape {(frames.shape[0] - 1,) + frames.shape[1:3] + (2,)} (one flow "
                         f"between each two frames), got {flows.shape}")
    video = frames if frames.ndim == 4 else frames[..., None]
    rows, cols = np.meshgrid(np.arange(video.shape[1], dtype=float), np.arange(video.shape[2], dtype=float),
                             indexing="ij")
    changes = []
    for t in range(len(flows)):
        at = [rows + flows[t][..., 0], cols + flows[t][..., 1]]
        seen = np.stack([ndimage.map_coordinates(video[t + 1][..., c], at, order=1, mode="nearest")
                         for c in range(video.shape[-1])], axis=-1)
        changes.append(np.abs(seen - video[t]).mean())
    return float(np.mean(changes))
