"""k-coherent candidates: where the neighbours of an output position came from, and what resembles it.

Pixel and patch synthesis copies exemplar positions to the output, and
neighbouring output positions mostly come from neighbouring exemplar
positions. Ashikhmin [1]_ turned that into a search: instead of comparing an
output neighbourhood with every exemplar neighbourhood, compare it with the
few positions its already-synthesised neighbours suggest. If the output
position ``r = p + d`` was copied from the exemplar position ``s(r)``, then
``p`` continuing that piece of the exemplar would be copied from

.. math:: s(r) + (p - r) = s(p + d) - d \\qquad \\text{(Ashikhmin's candidate)}

Tong et al. [2]_ add, for every exemplar position ``x``, its *k-coherence
set* ``S_k(x)``: ``x`` and the ``k - 1`` exemplar positions whose
neighbourhoods are most similar to ``x``'s, computed once before synthesis;
the candidates of ``p`` are then

.. math:: C(p) = \\bigcup_{d} S_k\\bigl(s(p + d) - d\\bigr)

(``k = 1`` is Ashikhmin's search). The best candidate is chosen by
:func:`~texsynth.core.search.nearest_candidates` (or by an algorithm's own
energy over the candidates), so a search costs ``|d| k`` distances instead of
one per exemplar position.

:class:`KCoherence` holds the sets and turns neighbour sources into
candidate lists for a whole batch of queries at once;
:func:`neighbor_sources` reads the sources of the neighbours from a
(toroidal) field of exemplar positions. The positions are the cells of a
rectangular grid of ``shape = (rows, cols)`` (the exemplar positions whose
neighbourhoods fit, as an algorithm lays them out), numbered row by row, so
a field, a candidate list and the rows of the caller's vector table use the
same integers. Wei-Levoy synthesis (``texsynth.synthesize_pixels(...,
candidates="k-coherent")``, Ashikhmin's search with ``k=1``) uses it with one
grid cell per exemplar pixel; an algorithm whose field lives on a
sparser grid (texture optimization's neighbourhood centres every few pixels,
correspondences) gathers its own sources and passes the offsets in exemplar
pixels.

What could not be checked: the papers themselves were not at hand. The
candidate rule follows their published descriptions (Ashikhmin's abstract
and course re-implementations; the k-coherence construction as Tong et al.'s
abstract, their patent US 7,149,368 and Li-Yi Wei's public code describe
it). That ``S_k(x)`` starts with ``x`` itself is as in those codes. The
``min_distance`` exclusion is not Tong et al.'s: Lefebvre and Hoppe [3]_
keep the members of a similarity set apart for the same reason (the pixel
next to ``x`` is nearly always the most similar, and adds nothing the shift
of a neighbouring source does not already give).

References
----------
.. [1] M. Ashikhmin, "Synthesizing natural textures", Proc. ACM Symposium on
   Interactive 3D Graphics (I3D) 2001, pp. 217-226.
   :doi:`10.1145/364338.364405`
.. [2] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum, "Synthesis
   of bidirectional texture functions on arbitrary surfaces", ACM TOG 21(3)
   (SIGGRAPH 2002), pp. 665-672. :doi:`10.1145/566654.566634`
.. [3] S. Lefebvre and H. Hoppe, "Parallel controllable texture synthesis",
   ACM TOG 24(3) (SIGGRAPH 2005), pp. 777-786. :doi:`10.1145/1073204.1073261`
"""

from __future__ import annotations

import numpy as np

from .._validate import as_rng, check_memory, check_positive_int
from ._index import DEFAULT_MEMORY_BUDGET, PatchIndex
from ._patchmatch import project_patches

__all__ = ["KCoherence", "neighbor_sources", "coherence_sets", "check_candidates", "COHERENT_MODES", "CANDIDATES"]

#: Values of an algorithm's ``candidates``: which exemplar neighbourhoods a query is compared with,
#: all of them (through an index or PatchMatch), or the k-coherent candidates of its neighbours'
#: sources (Ashikhmin 2001, Tong et al. 2002).
CANDIDATES = ("all", "k-coherent")


def check_candidates(candidates):
    """``candidates`` itself if it is one of :data:`CANDIDATES`, else a ValueError listing them."""
    if not isinstance(candidates, str) or candidates not in CANDIDATES:
        raise ValueError(f"candidates must be one of {', '.join(map(repr, CANDIDATES))}, got {candidates!r}")
    return candidates


# coherence_sets: the patches' principal components the sets are found among, and how far (pixels,
# Chebyshev) a member lies from the patch itself at least
_SET_COMPONENTS = 8
_SET_MIN_DISTANCE = 2

#: What replaces a shifted candidate that leaves the grid: a random cell (Ashikhmin), the
#: nearest edge cell, the cell it wraps around to (a tileable exemplar), or its mirror image.
COHERENT_MODES = ("random", "nearest", "wrap", "reflect")


def _as_offsets(offsets, m, j):
    d = np.asarray(offsets)
    if not np.issubdtype(d.dtype, np.integer) or d.shape not in ((j, 2), (m, j, 2)):
        raise ValueError(
            f"offsets must be integers of shape ({j}, 2) or ({m}, {j}, 2) (row, col of r - p for each "
            f"of the {j} neighbours), got dtype {d.dtype} and shape {d.shape}"
        )
    return d


def _fold(coords, length, mode):
    """Grid coordinates outside ``0..length-1`` brought back by ``mode`` (not ``"random"``)."""
    if mode == "nearest":
        return np.clip(coords, 0, length - 1)
    if mode == "wrap":
        return np.mod(coords, length)
    if length == 1:
        return np.zeros_like(coords)
    period = 2 * (length - 1)
    folded = np.mod(coords, period)
    return np.where(folded < length, folded, period - folded)


class KCoherence:
    """The k-coherence sets of an exemplar's positions, and the coherent candidates of queries.

    Parameters
    ----------
    vectors : array_like, shape (N, D)
        One neighbourhood vector per grid cell, row by row
        (``N = shape[0] * shape[1]``): what makes two exemplar positions
        similar. Not needed with ``k=1`` (pass None).
    shape : (int, int)
        ``(rows, cols)`` of the grid of exemplar positions.
    k : int
        Size of each set: the position itself and its ``k - 1`` most similar
        positions (Tong et al.). 1 (default) is Ashikhmin's search.
    min_distance : int
        Members of a set other than ``x`` lie at least this many cells from
        ``x`` (Chebyshev distance). 0 (default) is Tong et al.'s plain
        k nearest; see the module notes.
    weights, method, profile, memory_budget, rng
        As in :class:`~texsynth.core.search.PatchIndex`, which finds the
        sets (``method="auto"``: exact below the measured crossover size,
        PCA kd-tree above).

    Attributes
    ----------
    sets : numpy.ndarray of int64, shape (N, k)
        ``sets[x, 0] == x``; then the most similar positions, nearest first.
    shape, k, n : as given (``n = N``)
    method : str or None
        The backend that found the sets (None for ``k=1``).

    Raises
    ------
    ValueError, TypeError
        For a ``shape`` that does not match ``vectors``, ``k`` outside
        ``1..N``, a negative ``min_distance``, sets that would not fit in
        memory, or invalid vectors and search options.

    Examples
    --------
    >>> v = np.array([[0.0], [5.0], [0.1], [5.1], [9.0], [0.2]])   # a 2 x 3 grid
    >>> kc = KCoherence(v, (2, 3), k=2, method="exact")
    >>> kc.sets.tolist()
    [[0, 2], [1, 3], [2, 0], [3, 1], [4, 3], [5, 2]]
    >>> kc.candidates([[4, 0]], [[0, 1], [0, -1]]).tolist()   # p's right neighbour came from 4, its left from 0
    [[3, 1, 1, 3]]
    """

    def __init__(self, vectors, shape, k=1, *, min_distance=0, weights=None, method="auto", profile="default",
                 memory_budget=DEFAULT_MEMORY_BUDGET, rng=None):
        shape = tuple(shape) if isinstance(shape, (tuple, list, np.ndarray)) else shape
        if not (isinstance(shape, tuple) and len(shape) == 2):
            raise TypeError(f"shape must be a pair (rows, cols) of the grid of exemplar positions, got {shape!r}")
        self.shape = (check_positive_int(shape[0], "shape[0]"), check_positive_int(shape[1], "shape[1]"))
        self.n = self.shape[0] * self.shape[1]
        self.k = check_positive_int(k, "k")
        if self.k > self.n:
            raise ValueError(f"k={self.k} but the grid holds {self.n} positions; pass k <= {self.n}")
        self.min_distance = check_positive_int(min_distance, "min_distance", 0)
        self.method = None
        own = np.arange(self.n)
        if self.k == 1:
            self.sets = own[:, None]
            return
        # Exclusion square around x: (2 m - 1)^2 cells, x included; ask for enough to keep k - 1 outside it.
        excluded = (2 * self.min_distance - 1) ** 2 if self.min_distance else 1
        n_query = min(self.n, self.k - 1 + excluded)
        # the sets, the query's indices and distances, and their sort keys
        check_memory(4.0 * self.n * n_query * 8, self.k, "k", "the k-coherence sets", also={"shape": self.shape})
        index = PatchIndex(vectors, weights=weights, method=method, profile=profile, queries=self.n,
                           memory_budget=memory_budget, rng=rng)
        if index.n != self.n:
            raise ValueError(
                f"vectors hold {index.n} rows but shape {self.shape} has {self.n} positions; "
                f"pass one vector per grid cell, row by row"
            )
        self.method = index.method
        idx, _ = index.query(vectors, k=n_query)
        rows, cols = np.divmod(idx, self.shape[1])
        near = np.maximum(np.abs(rows - (own // self.shape[1])[:, None]),
                          np.abs(cols - (own % self.shape[1])[:, None])) < self.min_distance
        # members other than x, nearest first: those far enough from x, then (if too few) the rest
        key = np.where(idx == own[:, None], 2, near.astype(np.int8))
        order = np.argsort(key, axis=1, kind="stable")[:, : self.k - 1]
        self.sets = np.concatenate([own[:, None], np.take_along_axis(idx, order, axis=1)], axis=1)

    def __repr__(self):
        return f"KCoherence(shape={self.shape}, k={self.k}, min_distance={self.min_distance})"

    def candidates(self, sources, offsets, *, mode="random", rng=None):
        """The k-coherent candidates of a batch of queries.

        Parameters
        ----------
        sources : array_like of int, shape (M, J)
            For each query ``p`` and each of its neighbours ``r_j = p + d_j``,
            the grid cell ``s(r_j)`` that neighbour was copied from.
        offsets : array_like of int, shape (J, 2) or (M, J, 2)
            ``d_j = r_j - p`` as (row, col), in grid cells (exemplar pixels
            for a per-pixel grid; an algorithm whose neighbours lie ``g``
            pixels apart passes ``g * d``).
        mode : {"random", "nearest", "wrap", "reflect"}
            What replaces a shifted position ``s(r_j) - d_j`` that leaves the
            grid: a random cell (default; Ashikhmin's rule: a copied piece
            that reaches the exemplar's edge ends there), the nearest edge
            cell, the cell it wraps around to (for a tileable exemplar), or
            its mirror image about the edge. "nearest" repeats the edge
            row or column for as long as the copy goes on (streaks).
        rng : None, int or numpy.random.Generator
            Draws the random cells of ``mode="random"``.

        Returns
        -------
        numpy.ndarray of int64, shape (M, J * k)
            Per query, ``S_k(s(r_j) - d_j)`` for ``j = 0..J-1`` in turn: grid
            cells, with repeats where neighbours agree (they score the same,
            and :func:`~texsynth.core.search.nearest_candidates` keeps the
            first).

        Raises
        ------
        ValueError
            For sources outside ``0..N-1`` or not 2-D, offsets of another
            shape, or an unknown ``mode``.
        """
        src = np.asarray(sources)
        if src.ndim != 2 or not np.issubdtype(src.dtype, np.integer):
            raise ValueError(f"sources must be a 2-D integer array (queries, neighbours), got {src.dtype} {src.shape}")
        if src.size and (src.min() < 0 or src.max() >= self.n):
            raise ValueError(f"sources must be grid cells 0..{self.n - 1}, got values in {src.min()}..{src.max()}")
        if mode not in COHERENT_MODES:
            raise ValueError(f"mode must be one of {', '.join(map(repr, COHERENT_MODES))}, got {mode!r}")
        d = _as_offsets(offsets, *src.shape)
        rows, cols = np.divmod(src, self.shape[1])
        rows, cols = rows - d[..., 0], cols - d[..., 1]
        if mode == "random":
            outside = (rows < 0) | (rows >= self.shape[0]) | (cols < 0) | (cols >= self.shape[1])
            shifted = np.where(outside, 0, rows * self.shape[1] + cols)
            shifted[outside] = as_rng(rng).integers(0, self.n, size=int(outside.sum()))
        else:
            shifted = _fold(rows, self.shape[0], mode) * self.shape[1] + _fold(cols, self.shape[1], mode)
        return self.sets[shifted].reshape(src.shape[0], -1)


def neighbor_sources(field, centers, offsets):
    """The sources of the neighbours ``p + d`` of output positions ``p``, read from a toroidal field.

    Parameters
    ----------
    field : numpy.ndarray of int, shape (H, W)
        The grid cell each output position was copied from.
    centers : array_like of int, shape (M, 2)
        Output positions ``p`` (row, col).
    offsets : array_like of int, shape (J, 2)
        Neighbour offsets ``d`` (row, col); ``p + d`` wraps around the field.

    Returns
    -------
    numpy.ndarray, shape (M, J)
        ``field[(p + d) mod (H, W)]``, ready for :meth:`KCoherence.candidates`.

    Examples
    --------
    >>> field = np.arange(6).reshape(2, 3)
    >>> neighbor_sources(field, [[0, 0]], [[0, -1], [1, 0]]).tolist()
    [[2, 3]]
    """
    c = np.asarray(centers)
    d = np.asarray(offsets)
    h, w = field.shape
    return field[(c[:, 0, None] + d[None, :, 0]) % h, (c[:, 1, None] + d[None, :, 1]) % w]


def coherence_sets(exemplar, patch_size, k, *, pixel_weights=None, rng=None):
    """The k-coherence sets of every ``patch_size`` patch of an exemplar, as PatchMatch offers them.

    Tong et al. compare whole neighbourhoods; at the 16- to 64-pixel patches
    of texture optimization and interpolation that is 768-12288 values per
    position, so here the sets are found among the patches' projections on
    their 8 leading principal components
    (:func:`~texsynth.core.search.project_patches`, the descriptors of
    PatchMatch's distance bounds) by the PCA kd-tree: 0.3-1.0 s for the
    37 000-58 000 patches of a 256 px exemplar (16 components took twice as
    long); whoever uses the candidates ranks them by the exact distance.
    Members lie at least 2 pixels from the patch itself (the one a pixel
    over is always the most similar and adds nothing); a farther exclusion
    asks the kd-tree for the whole excluded square and took 10-50x as long.

    Parameters
    ----------
    exemplar : numpy.ndarray
        Float ``(H, W, C)``.
    patch_size : int
    k : int
        Size of each set.
    pixel_weights : numpy.ndarray, optional
        ``(patch_size, patch_size)`` weights of the patch pixels.
    rng : None, int or numpy.random.Generator
        Seeds the kd-tree's PCA.

    Returns
    -------
    numpy.ndarray of int64, shape ((H - patch_size + 1) * (W - patch_size + 1), k)
        Row-major top-left corners; ``sets[x, 0] == x``.

    Examples
    --------
    >>> img = np.random.default_rng(0).random((24, 24, 3))
    >>> sets = coherence_sets(img, 6, 3, rng=0)
    >>> sets.shape, bool(np.all(sets[:, 0] == np.arange(361)))
    ((361, 3), True)
    """
    ex = np.asarray(exemplar)
    vectors = project_patches(ex, patch_size, _SET_COMPONENTS, pixel_weights=pixel_weights)
    shape = (ex.shape[0] - patch_size + 1, ex.shape[1] - patch_size + 1)
    k = min(check_positive_int(k, "k"), vectors.shape[0])
    return KCoherence(vectors, shape, k=k, min_distance=_SET_MIN_DISTANCE, rng=rng).sets
