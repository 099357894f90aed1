"""Metrics of clips: how frames follow one another."""

from __future__ import annotations

import math

import numpy as np

from ..core._validate import check_positive_int

__all__ = ["temporal_correlation"]


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
