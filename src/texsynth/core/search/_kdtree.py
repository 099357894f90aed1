"""PCA + kd-tree: candidates from a kd-tree over PCA-reduced vectors, re-ranked by their exact distance.

The approximate search of Kwatra et al. 2005 (Section 3) and Wei & Levoy 2000
(Section 4.2). The PCA basis comes from a seeded subsample: from the D x D
scatter matrix up to 256 dimensions, by randomized subspace iteration above,
so 3072-D patches cost well under a second; :class:`scipy.spatial.cKDTree`
gives each query's candidates in the PCA space.

Options: ``n_components`` (PCA dimension; default the fewest components that
explain 98 % of the variance, within [8, 24]), ``leaf_size`` (default 16),
``n_candidates`` (how many are re-ranked exactly; default ``max(2 k, 16)``), ``eps`` (the
tree search's approximation factor, default 1).
"""

from __future__ import annotations

import numpy as np

from ._common import best_k_of_pairs, pair_sq_distances
from ._registry import register

# default kd-tree candidates re-ranked exactly (with k=1, recall@1 on real
# 147-D patches: 5 -> 0.89, 16 -> 0.98, 32 -> 0.99; see the benchmark)
_KD_CANDIDATES = 16
# default approximation factor of the kd-tree search: with eps = 1 the tree
# query is ~6x faster on 50000 grey 7x7 patches, recall@1 1.000 -> 0.988
_KD_EPS = 1.0
# PCA basis from at most this many vectors (SVD cost ~ sample * D^2).
_PCA_SAMPLE = 20_000
# PCA from the D x D scatter matrix up to this dimension, randomized above (see pca)
_PCA_COVARIANCE_MAX_DIM = 256
_PCA_OVERSAMPLES = 10
_PCA_POWER_ITERATIONS = 1
# relative eigenvalue below which a Gram direction counts as empty (~10 float32 eps)
_GRAM_RTOL = 1e-6
# PCA sample at most this many values (rows x D): 1365 rows of 3072-D patches; measured
# on real 32x32 colour patches, 1 power iteration and 2^22 values keep kd-tree recall@1
# within 0.01 of 3 iterations on 2^24 values (0.90 vs 0.90) at a third of the build time
_PCA_SAMPLE_VALUES = 2**22
# default PCA dimension: enough for this fraction of the variance, within the bounds
_PCA_VARIANCE = 0.98
_PCA_MIN, _PCA_MAX = 8, 24


class _KDTree:
    """PCA projection + cKDTree candidates + exact re-ranking."""

    name = "kdtree"

    @classmethod
    def build(cls, vectors, *, memory_budget, rng, n_components=None, leaf_size=None, n_candidates=None, eps=None):
        if n_components is not None and n_components > vectors.shape[1]:
            raise ValueError(
                f"n_components={n_components} exceeds the vector dimension "
                f"{vectors.shape[1]} (after dropping zero weights); pass n_components <= {vectors.shape[1]}"
            )
        return cls(vectors, n_components, leaf_size or 16, n_candidates, _KD_EPS if eps is None else eps,
                   memory_budget, rng)

    def __init__(self, vectors, n_components, leaf_size, n_candidates, eps, memory_budget, rng):
        from scipy.spatial import cKDTree

        self.eps = eps
        self.vectors = vectors
        self.memory_budget = memory_budget
        self.n_candidates = n_candidates
        n, dim = vectors.shape
        # PCA on a subsample (seeded) for large N
        sample = vectors
        rows = min(_PCA_SAMPLE, max(_PCA_MAX + _PCA_OVERSAMPLES, _PCA_SAMPLE_VALUES // dim))
        if n > rows:
            sample = vectors[np.sort(rng.choice(n, rows, replace=False))]
        self.mean = sample.mean(axis=0)
        s, vt, total = pca(sample - self.mean, n_components or _PCA_MAX, rng)
        if n_components is None:
            n_components = _default_components(s, dim, total)
        self.n_components = int(min(n_components, vt.shape[0]))
        self.basis = np.ascontiguousarray(vt[: self.n_components].T)
        self.tree = cKDTree(self._project(vectors), leafsize=leaf_size, balanced_tree=False)

    def _project(self, x):
        return (x - self.mean) @ self.basis

    def query(self, queries, k):
        n = self.vectors.shape[0]
        kk = min(n, self.n_candidates if self.n_candidates is not None else max(2 * k, _KD_CANDIDATES))
        kk = max(kk, k)
        # (1 + eps)-approximate tree search (Arya et al. 1998) in the PCA space
        _, cand = self.tree.query(self._project(queries), k=kk, eps=self.eps)
        cand = np.asarray(cand, dtype=np.int64).reshape(queries.shape[0], kk)
        m = queries.shape[0]
        rows = np.repeat(np.arange(m), kk)
        cols = cand.ravel()
        d2 = pair_sq_distances(queries, self.vectors, rows, cols, self.memory_budget)
        return best_k_of_pairs(m, rows, cols, d2, k)


# Hand-written rather than scikit-learn's PCA or randomized_svd: benchmarks/bench_packages.py measures
# 0.010 s against 0.021-0.076 s on 20 000 147-D rows (all capture the exact variance), and on 3072-D
# rows 0.020 s capturing 0.998 of the exact 24-component variance, where randomized_svd takes as
# long for 0.993 (n_iter=1) or 3.4x as long for 1.000.
def pca(centred, n_components, rng):
    """Leading singular values and right singular vectors of ``centred``, and its total variance.

    Up to ``_PCA_COVARIANCE_MAX_DIM`` dimensions: eigen-decomposition of the
    D x D scatter matrix (one GEMM, cost ~ n D^2, then D^3 for ``eigh``).
    Above it (large patches, e.g. 32 x 32 x 3 = 3072-D, where a full SVD of a
    9409-row sample took ~20-40 s on the 2-core VM): randomized subspace
    iteration for the ``n_components`` leading components (Halko, Martinsson
    & Tropp 2011, Algorithm 4.4: Gaussian test matrix with
    ``_PCA_OVERSAMPLES`` extra columns, ``_PCA_POWER_ITERATIONS`` QR-stabilised
    power iterations; cost ~ n D (n_components + oversamples) per pass,
    0.1-0.5 s). ``total`` is the sum of all squared singular values (the
    squared Frobenius norm), so the variance fraction of the leading
    components is known without computing the others.
    """
    n, dim = centred.shape
    total = float(np.einsum("ij,ij->", centred, centred, dtype=np.float64))
    rank = min(n, dim)
    if dim <= _PCA_COVARIANCE_MAX_DIM:
        scatter = (centred.T @ centred).astype(np.float64)
        ev, evec = np.linalg.eigh(scatter)  # ascending
        s = np.sqrt(np.maximum(ev[::-1][:rank], 0.0))
        return s, evec[:, ::-1][:, :rank].T, total
    k = min(n_components + _PCA_OVERSAMPLES, rank)
    basis = _orthonormal(centred @ rng.standard_normal((dim, k)).astype(centred.dtype))
    for _ in range(_PCA_POWER_ITERATIONS):
        basis = _orthonormal(centred @ _orthonormal(centred.T @ basis))
    # SVD of the small k x D projection B = Q^T X through its k x k Gram matrix
    b = basis.T @ centred
    ev, u = np.linalg.eigh((b @ b.T).astype(np.float64))
    ev, u = ev[::-1], u[:, ::-1]
    keep = ev > ev[0] * _GRAM_RTOL
    s = np.sqrt(ev[keep])
    vt = (u[:, keep].T @ b.astype(np.float64)) / s[:, None]
    return s[:n_components], vt[:n_components].astype(centred.dtype), total


def _orthonormal(y):
    """Orthonormal basis of the columns of a tall ``y`` through its small Gram matrix.

    Equivalent to the Q of a QR decomposition up to a rotation (all the
    randomized range finder needs); columns whose variance falls below
    ``_GRAM_RTOL`` of the largest are dropped. Chosen over ``numpy.linalg.qr``
    because LAPACK's threaded Householder QR of a 5461 x 34 float32 matrix
    took 0.4-0.7 s on the loaded 2-core VM (0.01-0.03 s idle), while the Gram
    route is one GEMM and a 34 x 34 eigen-decomposition.
    """
    ev, evec = np.linalg.eigh((y.T @ y).astype(np.float64))
    keep = ev > ev[-1] * _GRAM_RTOL
    return y @ (evec[:, keep] / np.sqrt(ev[keep])).astype(y.dtype)


def _default_components(singular_values, dim, total=None):
    """Fewest components explaining ``_PCA_VARIANCE`` of ``total`` (default: of the given values)."""
    var = np.asarray(singular_values, dtype=np.float64) ** 2
    if total is None:
        total = var.sum()
    if total <= 0:
        return 1
    m = int(np.searchsorted(np.cumsum(var) / total, _PCA_VARIANCE) + 1)
    return int(min(dim, max(min(_PCA_MIN, dim), min(m, _PCA_MAX))))


register("kdtree", _KDTree.build, options=("n_components", "leaf_size", "n_candidates", "eps"),
         summary="PCA-reduced kd-tree candidates, re-ranked by exact distance")


def point_tree(points, *, period=None):
    """A k-d tree over low-dimensional points: the search layer's one entry for geometric neighbours.

    Mesh vertices and face centres, tangent-field samples, patch centres on an image: whatever a
    method asks about points in space (not about patch vectors, which :class:`PatchIndex` serves)
    goes through here, so that every neighbour is chosen in :mod:`texsynth.core.search`.

    Parameters
    ----------
    points : array_like, shape (N, D)
        The points, D small (2 or 3).
    period : array_like of D floats, optional
        The coordinates wrap with this period per axis (a torus, e.g. a tileable image's
        ``shape``); points must lie in ``[0, period)``. None: plain Euclidean space.

    Returns
    -------
    scipy.spatial.cKDTree
        Query it with ``query(x, k=...)``, ``query_pairs(r)``, ... (scipy's API).

    Examples
    --------
    >>> tree = point_tree([[0.0, 0.0], [3.0, 4.0]])
    >>> d, i = tree.query([[2.5, 4.0]])
    >>> int(i[0]), float(d[0])
    (1, 0.5)
    >>> float(point_tree([[0.5, 0.5]], period=[10, 10]).query([[9.5, 0.5]])[0][0])
    1.0
    """
    from scipy.spatial import cKDTree

    return cKDTree(points, boxsize=None if period is None else np.asarray(period, dtype=np.float64))
