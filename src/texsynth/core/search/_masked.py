"""Masked search: distances over the known part of each query.

A query that is only partly known (an output pixel's window while its
surroundings are still being grown, as in Efros & Leung 1999 [1]_; a window on
the rim of a hole) is compared with every indexed vector over its known
dimensions only:

.. math:: d(q, v) = \\sum_d m_d w_d (q_d - v_d)^2

with ``m`` the query's mask (1 = known) and ``w`` the per-dimension weights
(e.g. a Gaussian fall-off repeated over the channels). Expanded as
``sum m w q^2 - 2 (m w q).v + (m w).v^2``, a group of queries costs one matrix
product: ``[-2 m w q | m w]`` against the stacked ``[v | v^2]`` of the indexed
vectors, computed once. Dimensions that no query of the group knows are left
out of the product when they are many.

*Blocks.* Queries often know a whole group of dimensions together (the
half-window below a pixel on the top side of a growing region). On a block
``B`` known whole, ``sum_B w (q - v)^2 = ||y_q||^2 - 2 y_q.y_v + ||y_v||^2``
with ``y = sqrt(w) v_B``: one product of ``|B|`` columns instead of ``2 |B|``,
and ``||y_v||^2`` computed once. A query uses the first block it knows whole;
the rest of its known dimensions are compared by the masked product above.
``method="pca"`` is the acceleration of the IPOL implementation of
Efros-Leung [2]_: ``y`` are the coordinates in a PCA basis of the indexed
vectors' block, truncated to ``n_components``, so the block costs ``d`` columns
instead of ``|B|``, and the distance misses the block's residual outside the
kept components (all kept, it is exact up to rounding).

References
----------
.. [1] A. A. Efros and T. K. Leung, "Texture synthesis by non-parametric
   sampling", ICCV 1999. :doi:`10.1109/ICCV.1999.790383`
.. [2] C. Aguerrebere, Y. Gousseau and G. Tartavel, "Exemplar-based texture
   synthesis: the Efros-Leung algorithm", Image Processing On Line 3 (2013),
   pp. 223-241. :doi:`10.5201/ipol.2013.59`
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import as_rng, check_memory, check_positive_float, check_positive_int
from ._common import as_vectors, as_weights
from ._index import DEFAULT_MEMORY_BUDGET
from ._kdtree import pca

__all__ = ["MASKED_METHODS", "MaskedIndex", "masked_sq_distances"]

#: Valid values of ``method`` for masked queries (``"auto"`` is ``"exact"``).
MASKED_METHODS = ("auto", "exact", "pca")

# default PCA dimension of a block: the fewest components that keep this fraction of its variance
_PCA_VARIANCE = 0.99
# above _PCA_COVARIANCE_MAX_DIM dimensions the PCA is randomized; ask it for at most this many
_PCA_RANDOMIZED_COMPONENTS = 64


@dataclass(frozen=True)
class _Block:
    """A block of dimensions compared on its own: ``y = sqrt(w) v_B`` (exact) or ``(y - mean) @ basis`` (PCA)."""

    dims: np.ndarray  # (|B|,) the block's dimensions
    sqrt_w: np.ndarray  # (|B|,)
    mean: np.ndarray | None  # (|B|,) PCA only
    basis: np.ndarray | None  # (|B|, d) PCA only
    coords_t: np.ndarray  # (d, N) the indexed vectors' coordinates y, transposed
    sq_norms: np.ndarray  # (N,) their squared norms


def _check_n_components(n_components):
    if n_components is None:
        return None
    return check_positive_int(n_components, "n_components")


class MaskedIndex:
    """Exact (or PCA-accelerated) search for queries known only in part.

    Parameters
    ----------
    vectors : array_like, shape (N, D)
        The searchable vectors (e.g. every exemplar window, flattened).
        float32 is searched in float32, anything else in float64.
    weights : array_like, shape (D,), optional
        Non-negative per-dimension weights ``w`` (default 1).
    method : {"auto", "exact", "pca"}
        ``"exact"`` (and ``"auto"``): exact masked distances by BLAS.
        ``"pca"``: the ``blocks`` a query knows whole are compared in a
        truncated PCA basis (see the module notes); needs ``blocks``.
    blocks : sequence of array_like of int, optional
        Groups of dimensions that queries often know whole (e.g. the four
        half-windows of a patch). A query uses the first block it knows
        whole, at half the cost of the masked product (exactly, unless
        ``method="pca"``); queries that know none use the masked product.
    n_components : int, optional
        PCA dimension of every block. Default: per block, the fewest
        components that keep 99 % of its weighted variance.
    memory_budget : int
        Bytes one block of distances (and its candidate lists) may take.
        Default 256 MiB.
    rng : None, int or numpy.random.Generator
        Seeds the randomized PCA of blocks above 256 dimensions (smaller
        blocks use an exact eigen-decomposition and no randomness).

    Attributes
    ----------
    n, dim : int
        Number and dimension of the indexed vectors.
    method : str
        ``"exact"`` or ``"pca"``.
    n_components : list of int
        The PCA dimension of each block (empty for ``"exact"``).

    Raises
    ------
    ValueError, TypeError
        For vectors that are not a finite real 2-D array, bad weights, an
        unknown method, missing or out-of-range blocks, or ``n_components``
        that is not a positive integer.

    Examples
    --------
    >>> v = np.array([[0.0, 0.0], [1.0, 5.0], [1.0, 0.0]])
    >>> index = MaskedIndex(v)
    >>> index.sq_distances([[1.0, 9.0]], [[True, False]])  # the second value is unknown
    array([[1., 0., 0.]])
    >>> idx, d2, best, count = index.near_best([[1.0, 9.0]], [[True, False]], 0.1, [0.99])
    >>> idx.tolist(), count.tolist()
    ([2], [2])
    """

    def __init__(self, vectors, *, weights=None, method="exact", blocks=None, n_components=None,
                 memory_budget=DEFAULT_MEMORY_BUDGET, rng=None):
        v = as_vectors(vectors, "vectors")
        self.n, self.dim = v.shape
        if not isinstance(method, str) or method not in MASKED_METHODS:
            raise ValueError(f"method must be one of {', '.join(map(repr, MASKED_METHODS))}, got {method!r}")
        self.method = "exact" if method == "auto" else method
        n_components = _check_n_components(n_components)
        self.memory_budget = check_positive_int(memory_budget, "memory_budget")
        rng = as_rng(rng)
        w = np.ones(self.dim) if weights is None else as_weights(weights, self.dim)
        self.vectors = v
        self.weights = w.astype(v.dtype)
        # [v | v^2] and the blocks' own copies (fewer columns in PCA), before any is made
        copies = 2.0 + sum(np.size(b) for b in (blocks or ())) / max(1, self.dim)
        check_memory(copies * v.nbytes, (self.n, self.dim), "vectors", "the stacked vectors [v | v^2] and blocks")
        # the right-hand side of every product: [v | v^2] transposed, (2D, N)
        self._stacked = np.ascontiguousarray(np.concatenate([v, v * v], axis=1).T)
        self._max_norm = float(((v * v) @ self.weights).max())
        if self.method == "pca" and not blocks:
            raise ValueError("method='pca' needs blocks: groups of dimensions that queries know together "
                             "(e.g. the half-windows of a patch); pass blocks=[dims, ...] or method='exact'")
        self._blocks = [self._build_block(b, i, n_components, rng) for i, b in enumerate(blocks or ())]
        self.n_components = [b.coords_t.shape[0] for b in self._blocks] if self.method == "pca" else []

    def __repr__(self):
        return f"MaskedIndex(n={self.n}, dim={self.dim}, method={self.method!r})"

    def _build_block(self, dims, i, n_components, rng):
        dims = np.asarray(dims)
        if dims.ndim != 1 or dims.size == 0 or not np.issubdtype(dims.dtype, np.integer):
            raise ValueError(f"blocks[{i}] must be a non-empty 1-D array of dimension indices, got {dims!r}")
        if dims.min() < 0 or dims.max() >= self.dim:
            raise ValueError(f"blocks[{i}] holds dimensions outside 0..{self.dim - 1}; pass indices of the vectors' "
                             f"columns")
        dims = np.unique(dims)
        sqrt_w = np.sqrt(self.weights[dims])
        y = self.vectors[:, dims] * sqrt_w
        mean = basis = None
        if self.method == "pca":
            mean = y.mean(axis=0)
            y -= mean
            s, vt, total = pca(y, min(dims.size, n_components or _PCA_RANDOMIZED_COMPONENTS), rng)
            if n_components is None:  # the fewest components that keep _PCA_VARIANCE of the variance
                kept = np.cumsum(s.astype(np.float64) ** 2) / total if total > 0 else np.ones(len(s))
                d = int(min(len(s), np.searchsorted(kept, _PCA_VARIANCE) + 1))
            else:
                d = min(n_components, len(s))
            basis = np.ascontiguousarray(vt[:d].T, dtype=y.dtype)
            y = y @ basis
        return _Block(dims, sqrt_w, mean, basis, np.ascontiguousarray(y.T), np.einsum("nd,nd->n", y, y))

    # ------------------------------------------------------------------ checks
    def _check_queries(self, queries, mask):
        q = as_vectors(queries, "queries")
        if q.shape[1] != self.dim:
            raise ValueError(f"queries have dimension {q.shape[1]} but the index holds vectors of dimension "
                             f"{self.dim}; pass queries of shape (M, {self.dim})")
        m = np.asarray(mask)
        if m.shape != q.shape:
            raise ValueError(f"mask must have the queries' shape {q.shape} (True where a value is known), "
                             f"got shape {m.shape}")
        if m.dtype != np.bool_:
            if not np.issubdtype(m.dtype, np.number) or not np.all((m == 0) | (m == 1)):
                raise ValueError("mask must be boolean (True where a query value is known) or hold only 0 and 1")
            m = m.astype(bool)
        return np.asarray(q, dtype=self.vectors.dtype), m

    # ------------------------------------------------------------------ distances
    def _route(self, mask):
        """Per query: the index of the first block it knows whole, or -1 (exact)."""
        if not self._blocks:
            return np.full(mask.shape[0], -1)
        whole = np.stack([mask[:, b.dims].all(axis=1) for b in self._blocks])  # (blocks, M)
        return np.where(whole.any(axis=0), whole.argmax(axis=0), -1)

    def _distances(self, q, mask, block):
        """``(M, N)`` masked squared distances of one group of queries, all using ``block`` (None: none)."""
        rest = mask
        d2 = None
        if block is not None:  # the block, known whole: ||y_q - y_v||^2, y the (PCA) coordinates
            y = q[:, block.dims] * block.sqrt_w
            if block.basis is not None:
                y = (y - block.mean) @ block.basis
            d2 = (-2.0 * y) @ block.coords_t
            d2 += block.sq_norms[None, :]
            d2 += np.einsum("md,md->m", y, y)[:, None]
            rest = mask.copy()
            rest[:, block.dims] = False
        # the rest: sum m w q^2 - 2 (m w q).v + (m w).v^2 over the columns some query knows; a few
        # columns are gathered, many are multiplied in place (a gather costs as much as the product)
        cols = np.flatnonzero(rest.any(axis=0))
        if cols.size == 0:
            return np.zeros((q.shape[0], self.n), q.dtype) if d2 is None else d2
        if 2 * cols.size > self.dim:
            cols = np.arange(self.dim)
        a = rest[:, cols] * self.weights[cols]
        qc = q[:, cols]
        left = np.concatenate([-2.0 * a * qc, a], axis=1)
        right = self._stacked if cols.size == self.dim else self._stacked[np.concatenate([cols, cols + self.dim])]
        part = left @ right
        part += np.einsum("md,md,md->m", a, qc, qc)[:, None]
        if d2 is None:
            return part
        d2 += part
        return d2

    def _chunks(self, mask, per_row_bytes):
        """Groups of query rows (same block) of at most ``memory_budget`` bytes each, with their block."""
        route = self._route(mask)
        rows = max(1, self.memory_budget // max(1, self.n * per_row_bytes))
        for b in np.unique(route):
            members = np.flatnonzero(route == b)
            for start in range(0, members.size, rows):
                yield members[start : start + rows], (None if b < 0 else self._blocks[b])

    def sq_distances(self, queries, mask):
        """Masked squared distances of every query to every indexed vector.

        Parameters
        ----------
        queries : array_like, shape (M, D)
        mask : array_like of bool, shape (M, D)
            True where a query's value is known.

        Returns
        -------
        numpy.ndarray, shape (M, N)
            ``sum_d mask w (q - v)^2`` (approximate in the blocks for
            ``method="pca"``), clipped at 0.

        Raises
        ------
        ValueError
            For queries of another dimension, a mask of another shape, or a
            result that does not fit in memory.
        """
        q, m = self._check_queries(queries, mask)
        check_memory(float(q.shape[0]) * self.n * q.itemsize, (q.shape[0], self.n), "queries",
                     "the distance matrix (one row per query)")
        out = np.empty((q.shape[0], self.n), dtype=q.dtype)
        for rows, block in self._chunks(m, 2 * q.itemsize):
            out[rows] = self._distances(q[rows], m[rows], block)
        return np.maximum(out, 0.0, out=out)

    def near_best(self, queries, mask, error_tolerance, fractions):
        """Per query, one vector among those within ``(1 + error_tolerance)`` of the nearest.

        The candidate set of a query is every indexed vector ``v`` with
        ``d(q, v) <= (1 + error_tolerance) d_min(q)`` (Efros & Leung's rule, on
        squared distances as in their pseudo-code), widened by the rounding
        error of the BLAS expansion so that exact ties always count. Of the
        ``count`` candidates, in index order, the one at position
        ``floor(fraction * count)`` is returned: pass uniform random numbers
        in [0, 1) for a uniform random pick.

        Parameters
        ----------
        queries : array_like, shape (M, D)
        mask : array_like of bool, shape (M, D)
            True where a query's value is known.
        error_tolerance : float
            ``>= 0``; 0 keeps only the nearest (and exact ties).
        fractions : array_like, shape (M,)
            Numbers in [0, 1), one per query.

        Returns
        -------
        indices : numpy.ndarray of int64, shape (M,)
        sq_distances : numpy.ndarray, shape (M,)
            The chosen vectors' masked squared distances.
        best : numpy.ndarray, shape (M,)
            The nearest distance ``d_min`` of each query.
        counts : numpy.ndarray of int64, shape (M,)
            Size of each query's candidate set.

        Raises
        ------
        ValueError, TypeError
            For bad queries or mask (see :meth:`sq_distances`), a negative or
            non-finite ``error_tolerance`` or fractions outside [0, 1).
        """
        q, m = self._check_queries(queries, mask)
        error_tolerance = check_positive_float(error_tolerance, "error_tolerance", allow_zero=True, maximum=1e6)
        u = np.asarray(fractions, dtype=np.float64)
        if u.shape != (q.shape[0],) or not np.all((u >= 0) & (u < 1)):
            raise ValueError(f"fractions must be {q.shape[0]} numbers in [0, 1) (one per query), got shape {u.shape}"
                             f"{'' if u.shape != (q.shape[0],) else ' with values outside [0, 1)'}")
        # rounding error of the expansion, as in the exact backend: (D + 2) eps (||q||_mw^2 + max ||v||_w^2)
        q_norms = np.einsum("md,md,d->m", q * m, q, self.weights)
        tol = (self.dim + 2) * np.finfo(q.dtype).eps * (q_norms + self._max_norm)
        indices = np.empty(q.shape[0], dtype=np.int64)
        chosen, best = np.empty(q.shape[0], dtype=q.dtype), np.empty(q.shape[0], dtype=q.dtype)
        counts = np.empty(q.shape[0], dtype=np.int64)
        # per row: the distances, the candidate flags and (at most) one int64 pair per candidate
        for rows, block in self._chunks(m, q.itemsize + 1 + 16):
            d2 = self._distances(q[rows], m[rows], block)
            low = d2.min(axis=1)
            r, c = np.nonzero(d2 <= (low * (1.0 + error_tolerance) + tol[rows])[:, None])
            n_in = np.bincount(r, minlength=rows.size)
            pick = np.cumsum(n_in) - n_in + np.minimum((u[rows] * n_in).astype(np.int64), n_in - 1)
            indices[rows] = c[pick]
            chosen[rows] = d2[r[pick], c[pick]]
            best[rows], counts[rows] = low, n_in
        return indices, np.maximum(chosen, 0.0), np.maximum(best, 0.0), counts


def masked_sq_distances(queries, mask, vectors, weights=None):
    """Masked squared distances ``sum_d mask w (q - v)^2`` of every query to every vector.

    One-shot form of :meth:`MaskedIndex.sq_distances` (exact).

    Parameters
    ----------
    queries : array_like, shape (M, D)
    mask : array_like of bool, shape (M, D)
        True where a query's value is known.
    vectors : array_like, shape (N, D)
    weights : array_like, shape (D,), optional
        Non-negative per-dimension weights (default 1).

    Returns
    -------
    numpy.ndarray, shape (M, N)

    Examples
    --------
    >>> masked_sq_distances([[1.0, 2.0]], [[False, True]], [[0.0, 0.0], [5.0, 2.0]])
    array([[4., 0.]])
    """
    return MaskedIndex(vectors, weights=weights).sq_distances(queries, mask)
