"""PatchMatch: nearest-neighbour fields between two images (Barnes et al. 2009; k nearest: Barnes et al. 2010).

The other backends of the search layer answer "which of these vectors is
nearest to that one?"; this module answers the question texture optimization,
hole filling and reshuffling ask of two *images*: for every patch of an image,
which patch of an exemplar is nearest? Its queries are patches of one image,
and neighbouring queries overlap, so a good match of one query, shifted by the
offset to its neighbour, is a good candidate for the neighbour (coherence).
PatchMatch exploits that instead of indexing the exemplar.

:func:`patchmatch` is the algorithm; :func:`nearest_field` asks the same
question of any backend (``method="exact"``, ``"kdtree"``, ``"tsvq"`` through
:class:`~texsynth.core.search.PatchIndex`, or ``"patchmatch"``), so an
algorithm can switch between them with one argument.
"""

from __future__ import annotations

import hashlib
import numbers

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from .._validate import (
    as_image,
    as_rng,
    check_memory,
    check_positive_int,
    with_channels,
)
from ..convolve import correlate_bank
from ..neighborhood import MODES, grid_axes, grid_cells, patch_shape, patches_within
from ._kdtree import pca, point_tree
from ._registry import forced_method

__all__ = ["patchmatch", "patchmatch_features", "nearest_field", "project_patches", "FIELD_METHODS", "FIELD_MIN_VALUES", "check_field_method", "resolve_field"]

#: Ratio between the radii of successive random-search windows (Barnes et al. 2009, Sec. 3.2: alpha = 1/2).
ALPHA = 0.5
# one block of candidate patches and their differences (bytes): small blocks stay in cache
_BLOCK_BYTES = 4 * 2**20
# the query patches are extracted once and kept while they take at most this many bytes
# (a dense field of a 1024 px colour image with 7x7 patches: 1M x 147 float32 = 0.6 GB is not)
_QUERY_CACHE_BYTES = 256 * 2**20
# irregular centres: propagate from this many nearest other centres
_IRREGULAR_NEIGHBORS = 4
# centres that fill at least this share of the rectilinear grid of their rows and columns are scanned as
# that grid with cells missing (the part of texture optimization's grid that touches a hole); scattered
# centres fill about 1/N of theirs
_GRID_MIN_FILL = 0.25
# distance bounds (see _Bound): patches of at least this many values are first compared by their
# projections on this many leading principal components of the exemplar's patches, estimated from
# this many of them (16 components: 256 -> 1024 px texture optimization 14.3 s, against 14.7 s with
# 8, 15.1 s with 64 and 16.4 s without bounds; 512 samples: 12.2-12.6 s against 13.2-13.3 s with
# 1024 and 12.6-12.8 s with 256, the same output; benchmarks/bench_bounds.py, docs/methods/search.md);
# 128 values bring in 8 x 8 colour patches (192): grass_1 256 -> 1024 px 18.1-18.8 s against 20.6-20.8 s
# with 256, the same output (bench_bounds.py --min-dims), and hole filling and uncrop unchanged
_BOUND_MIN_DIM = 128
_BOUND_COMPONENTS = 16
# ... and only for searches whose queries hold at least this many values per exemplar patch position: the
# exemplar's projections cost about the same whatever the queries, and a few queries (the neighbourhoods
# near a small hole: 10 or fewer) save less than that (hole filling of a 512 px photograph 1.45-1.79 s without
# bounds, 1.85-2.29 s with them); texture optimization's grids hold hundreds to thousands
_BOUND_MIN_WORK = 64
_BOUND_SAMPLES = 512
# project_patches (the k-coherence sets' descriptors): components from this many patches
_PROJECTION_SAMPLES = 1024
# the exemplar's projections are kept for the next search of the same exemplar while they take at
# most this much (a 724 x 724 exemplar); larger exemplars are searched without bounds
_BOUND_MAX_BYTES = 64 * 2**20
_BOUND_CACHE = {}


# --------------------------------------------------------------------------- the problem
class _Problem:
    """The checked inputs of one search and the patch distances between them.

    Positions in the exemplar are kept as flat indices ``row * enx + col`` of
    a patch's top-left corner among the ``(eny, enx)`` patches that lie wholly
    inside the exemplar; the centres returned are those corners plus
    ``patch_size // 2``.
    """

    def __init__(self, image, exemplar, patch_size, centers, k, exemplar_mask, pixel_weights, mode, penalty=None,
                 checked=False, workspace=None):
        if penalty is not None and not callable(penalty):
            raise TypeError(f"penalty must be a callable penalty(queries, centres) -> costs, got {penalty!r}")
        self.penalty = penalty
        if not isinstance(mode, str) or mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(map(repr, MODES))}, got {mode!r}")
        self.mode = mode
        if checked:  # float (H, W, C) arrays of a caller that knows them (any C, any finite values)
            img, ex = image, exemplar
        else:
            img, _ = with_channels(as_image(image, "image"))
            ex, _ = with_channels(as_image(exemplar, "exemplar"))
        if img.shape[-1] != ex.shape[-1]:
            raise ValueError(
                f"image has {img.shape[-1]} channels but exemplar has {ex.shape[-1]}; "
                "pass images with the same channels (e.g. both RGB)"
            )
        dtype = np.float32 if img.dtype == ex.dtype == np.float32 else np.float64
        self.dtype = dtype
        ph, pw = self.patch = patch_shape(patch_size)
        for name, arr in (("image", img), ("exemplar", ex)):  # in every mode, as core.neighborhood
            if ph > arr.shape[0] or pw > arr.shape[1]:
                raise ValueError(
                    f"patch_size ({ph}, {pw}) is larger than the {name} {arr.shape[:2]}; "
                    f"pass a smaller patch_size or a larger {name}"
                )
        self.k = k = _check_k(k)
        channels = img.shape[-1]
        self.dim = ph * pw * channels

        # the exemplar's patches (always wholly inside it) and which of them may be used
        self.exemplar = np.ascontiguousarray(ex, dtype=dtype)
        self.eny, self.enx = ex.shape[0] - ph + 1, ex.shape[1] - pw + 1
        self.eview = np.moveaxis(sliding_window_view(self.exemplar, (ph, pw), axis=(0, 1)), 2, -1)
        self.allowed = _allowed(exemplar_mask, ex.shape[:2], self.patch)
        self.allowed_ids = np.flatnonzero(self.allowed)
        self.radii = _radii(max(self.eny, self.enx))  # random search's, the same for every query
        free = self.allowed_ids.shape[0]
        if free < k:
            held = (f"the exemplar holds only {free} patches of size ({ph}, {pw})" if exemplar_mask is None else
                    f"exemplar_mask leaves only {free} patches of size ({ph}, {pw}) free of masked pixels")
            raise ValueError(f"k={k} but {held}; pass k <= {free}")

        # the query patches: centres -> top-left corners in the (padded) image
        self.shape = img.shape[:2]
        self.centers = _check_centers(centers, self.shape, self.patch, mode)
        n = self.centers.shape[0]
        check_memory(self.bytes_held(n, img.size), f"<{n} centres>", "centers", "the field and its patches",
                     also={"k": k, "patch_size": patch_size})
        if mode == "valid":
            padded = img
            corners = self.centers - (ph // 2, pw // 2)
        else:
            pads = ((ph // 2, ph - 1 - ph // 2), (pw // 2, pw - 1 - pw // 2), (0, 0))
            padded = np.pad(img, pads, mode="wrap" if mode == "wrap" else "reflect")
            corners = self.centers  # the pad shifts every corner by exactly (ph // 2, pw // 2)
        self.image = np.ascontiguousarray(padded, dtype=dtype)
        self.qview = np.moveaxis(sliding_window_view(self.image, (ph, pw), axis=(0, 1)), 2, -1)
        self.qr, self.qc = corners[:, 0].copy(), corners[:, 1].copy()
        self.queries = None
        if n * self.dim * np.dtype(dtype).itemsize <= _QUERY_CACHE_BYTES:
            self.queries = _gather(self.qview, self.qr, self.qc, workspace).reshape(n, self.dim)

        self.wsqrt = None
        if pixel_weights is not None:
            w = _check_pixel_weights(pixel_weights, self.patch)
            self.wsqrt = np.repeat(np.sqrt(w).ravel(), channels).astype(dtype)
        self.block = max(16, _BLOCK_BYTES // (self.dim * np.dtype(dtype).itemsize))
        self.neighbors = _Neighbors(self.centers, self.shape, mode)
        self.sets = None  # k-coherence sets (patchmatch_features's sets)
        bound_bytes = self.eny * self.enx * _BOUND_COMPONENTS * 8
        worth = self.dim >= _BOUND_MIN_DIM and n * self.dim >= _BOUND_MIN_WORK * self.eny * self.enx
        self.bound = _Bound(self) if worth and bound_bytes <= _BOUND_MAX_BYTES else None

    def bytes_held(self, n, image_values):
        """Largest memory held at once: the image copies, the cached queries, the field, one block and the
        bounds' projections (at most :data:`_BOUND_MAX_BYTES` for the exemplar, ``N m`` values for the queries)."""
        item = 8.0
        field = n * self.k * (8 + item) * 3  # positions and distances, and the merge's temporaries
        queries = min(n * self.dim * item, _QUERY_CACHE_BYTES)
        bounds = _BOUND_MAX_BYTES + n * _BOUND_COMPONENTS * item
        return (2 * (image_values + self.exemplar.size) * item + field + queries + bounds + 4 * _BLOCK_BYTES
                + 8.0 * n * 8)

    # ----------------------------------------------------------------- distances
    def distances(self, q, ids):
        """Exact weighted squared distances between query patches ``q`` and exemplar patches ``ids``.

        By direct differences, ``block`` pairs at a time; the same pair always
        gives the same value, bit for bit (no BLAS, whose blocking may depend
        on the batch).
        """
        out = np.empty(q.shape[0], dtype=self.dtype)
        er, ec = np.divmod(ids, self.enx)
        for a in range(0, q.shape[0], self.block):
            b = slice(a, a + self.block)
            diff = self.eview[er[b], ec[b]].reshape(-1, self.dim)
            if self.queries is not None:
                diff -= self.queries[q[b]]
            else:
                diff -= self.qview[self.qr[q[b]], self.qc[q[b]]].reshape(-1, self.dim)
            if self.wsqrt is not None:
                diff *= self.wsqrt
            out[b] = np.einsum("ij,ij->i", diff, diff)
        return out

    def cost(self, q, ids):
        """What ranks exemplar patches ``ids`` for queries ``q`` (the distance, plus the penalty if any), and
        the distances themselves (the same array without a penalty)."""
        d = self.distances(q, ids)
        if self.penalty is None:
            return d, d
        r, c = np.divmod(ids, self.enx)
        centres = np.stack([r + self.patch[0] // 2, c + self.patch[1] // 2], axis=1)
        extra = np.asarray(self.penalty(q, centres), dtype=self.dtype)
        if extra.shape != d.shape or not np.all(np.isfinite(extra)) or np.any(extra < 0):
            raise ValueError(f"penalty must return one finite, non-negative cost per candidate (shape "
                             f"{d.shape}), got shape {extra.shape} and values down to {np.min(extra, initial=0)}")
        return d + extra, d

    def to_ids(self, r, c):
        """Flat exemplar ids of top-left corners ``(r, c)``, clamped into the exemplar."""
        np.minimum(np.maximum(r, 0, out=r), self.eny - 1, out=r)  # ufuncs: np.clip's overhead is per call
        np.minimum(np.maximum(c, 0, out=c), self.enx - 1, out=c)
        return r * self.enx + c

    # ----------------------------------------------------------------- the field
    def random_ids(self, shape, rng):
        """Exemplar patches drawn uniformly among the allowed ones."""
        return self.allowed_ids[rng.integers(self.allowed_ids.shape[0], size=shape)]

    def start(self, init, rng):
        """The initial field (Barnes et al. 2009, Sec. 3.1): random, or ``init`` repaired."""
        n, k = self.centers.shape[0], self.k
        if init is None:
            ids = self.random_ids((n, k), rng)
        else:
            ids = self.init_ids(init)
            bad = ~self.allowed[ids]
            ids[bad] = self.random_ids(int(bad.sum()), rng)
        if k > 1:  # k distinct patches per query (Barnes et al. 2010): redraw repeats
            while True:
                srt = np.sort(ids, axis=1)
                rows = np.flatnonzero(np.any(srt[:, 1:] == srt[:, :-1], axis=1))
                if rows.shape[0] == 0:
                    break
                sub = ids[rows]
                o = np.argsort(sub, axis=1, kind="stable")
                s = np.take_along_axis(sub, o, axis=1)
                dup = np.zeros(sub.shape, dtype=bool)
                dup[:, 1:] = s[:, 1:] == s[:, :-1]
                again = np.zeros(sub.shape, dtype=bool)
                np.put_along_axis(again, o, dup, axis=1)
                sub[again] = self.random_ids(int(again.sum()), rng)
                ids[rows] = sub
        q = np.repeat(np.arange(n), k)
        d, dist = (a.reshape(n, k) for a in self.cost(q, ids.ravel()))
        order = np.argsort(d, axis=1, kind="stable")
        field = _Field(np.take_along_axis(ids, order, axis=1), np.take_along_axis(d, order, axis=1))
        if self.penalty is not None and k == 1:  # the distances of the held patches, without the penalty
            field.dist = dist.copy()
        return field

    def init_ids(self, init):
        n, k = self.centers.shape[0], self.k
        arr = np.asarray(init)
        if arr.shape != (n, k, 2) or not (np.issubdtype(arr.dtype, np.integer) and arr.dtype != np.bool_):
            raise ValueError(
                f"init must be an integer array of shape ({n}, {k}, 2): the exemplar centres (row, col) of "
                f"{k} patch(es) for each of the {n} centres, got dtype {arr.dtype} and shape {arr.shape}"
            )
        ph, pw = self.patch
        r = arr[..., 0].astype(np.int64) - ph // 2
        c = arr[..., 1].astype(np.int64) - pw // 2
        return self.to_ids(r, c)

    def result(self, field, distances=False):
        """The held centres and costs; with ``distances``, also their distances without the penalty (None if
        a penalty ranked k > 1 patches, whose distances are not kept)."""
        ph, pw = self.patch
        r, c = np.divmod(field.ids, self.enx)
        centers = np.stack([r + ph // 2, c + pw // 2], axis=-1).astype(np.int64)
        if not distances:
            return centers, field.d2
        return centers, field.d2, field.d2 if self.penalty is None else field.dist

    # ----------------------------------------------------------------- candidates
    def offer(self, field, q, cand):
        """Let queries ``q`` (distinct) take any of their candidates ``cand`` ``(n, m)`` that is better.

        A candidate already held, or not allowed, is skipped; the k held
        patches stay distinct and sorted; a candidate replaces a held patch only
        if strictly nearer (ties keep what is held, so the field never changes
        without improving).
        """
        held = field.ids[q]
        ok = self.allowed[cand]
        for j in range(self.k):
            ok &= cand != held[:, j : j + 1]
        rows, cols = np.nonzero(ok)
        worst = field.d2[q, -1]
        if self.bound is not None and rows.shape[0]:  # skip candidates that provably cannot be better
            may = self.bound.may_beat(q[rows], cand[rows, cols], worst[rows])
            rows, cols = rows[may], cols[may]
        if rows.shape[0] == 0:
            return
        d, dist = self.cost(q[rows], cand[rows, cols])
        better = d < worst[rows]
        if not better.any():
            return
        if self.k == 1:
            # per row the nearest candidate (the first of equals)
            dense = np.full(cand.shape, np.inf, dtype=d.dtype)
            dense[rows[better], cols[better]] = d[better]
            j = np.argmin(dense, axis=1)
            top = dense[np.arange(j.shape[0]), j]
            take = np.flatnonzero(top < np.inf)
            field.ids[q[take], 0] = cand[take, j[take]]
            field.d2[q[take], 0] = top[take]
            if field.dist is not None:  # the taken candidates' distances without the penalty
                dense[rows[better], cols[better]] = dist[better]
                field.dist[q[take], 0] = dense[take, j[take]]
            return
        rows, cols, d = rows[better], cols[better], d[better]
        self.merge(field, q, rows, cand[rows, cols], d)

    def merge(self, field, q, rows, ids, d):
        """k > 1: per query, the k nearest distinct of its held patches and the new ones."""
        k = self.k
        uq, inv = np.unique(rows, return_inverse=True)
        counts = np.bincount(inv)
        m = int(counts.max())
        slot = np.arange(rows.shape[0]) - (np.cumsum(counts) - counts)[inv]
        # rows arrive sorted (np.nonzero), so inv is sorted and slot counts 0.. within a row
        pos = np.full((uq.shape[0], k + m), -1, dtype=np.int64)
        dist = np.full((uq.shape[0], k + m), np.inf, dtype=self.dtype)
        qq = q[uq]
        pos[:, :k], dist[:, :k] = field.ids[qq], field.d2[qq]
        pos[inv, k + slot], dist[inv, k + slot] = ids, d
        # a patch offered twice (two neighbours propose it) counts once: drop the later copy
        o = np.argsort(pos, axis=1, kind="stable")
        s = np.take_along_axis(pos, o, axis=1)
        dup = np.zeros(s.shape, dtype=bool)
        dup[:, 1:] = (s[:, 1:] == s[:, :-1]) & (s[:, 1:] >= 0)
        drop = np.zeros(s.shape, dtype=bool)
        np.put_along_axis(drop, o, dup, axis=1)
        dist[drop] = np.inf
        best = np.argsort(dist, axis=1, kind="stable")[:, :k]  # ties: held patches first
        field.ids[qq] = np.take_along_axis(pos, best, axis=1)
        field.d2[qq] = np.take_along_axis(dist, best, axis=1)

    def propagate(self, field, q, nbrs, shifts):
        """Propagation (Barnes et al. 2009, Sec. 3.2): neighbour ``nbrs[:, j]``'s patches, shifted by
        ``shifts[:, j]`` (the offset from that neighbour's centre to the query's), for queries ``q``."""
        has = nbrs >= 0
        if not has.any():
            return
        src = field.ids[np.where(has, nbrs, 0)]  # (n, J, k)
        r, c = np.divmod(src, self.enx)
        r += shifts[:, :, 0, None]
        c += shifts[:, :, 1, None]
        cand = self.to_ids(r, c)
        # no neighbour that way: offer what is held, which is skipped
        cand[~has] = field.ids[q][:, None, :].repeat(has.shape[1], axis=1)[~has]
        if self.sets is not None:  # k-coherence: each continuation and the patches most like it
            cand = self.sets[cand]
        self.offer(field, q, cand.reshape(q.shape[0], -1))

    def random_search(self, field, q, rng):
        """Random search (Barnes et al. 2009, Sec. 3.2): ``v0 + w alpha^i R_i`` for each held ``v0``.

        ``w`` is the larger side of the exemplar's patch positions, ``i = 0,
        1, ...`` while ``w alpha^i >= 1``; each window is clipped to the
        exemplar and sampled uniformly inside. None with k-coherence sets
        (they take its place, Tong et al. 2002).
        """
        if self.sets is not None:
            return
        radii = self.radii
        held = field.ids[q]  # (n, k)
        r0, c0 = np.divmod(held, self.enx)
        u = rng.random((q.shape[0], self.k, radii.shape[0], 2))
        lo = np.maximum(r0[..., None] - radii, 0)
        hi = np.minimum(r0[..., None] + radii, self.eny - 1)
        r = lo + (u[..., 0] * (hi - lo + 1)).astype(np.int64)
        lo = np.maximum(c0[..., None] - radii, 0)
        hi = np.minimum(c0[..., None] + radii, self.enx - 1)
        c = lo + (u[..., 1] * (hi - lo + 1)).astype(np.int64)
        self.offer(field, q, (r * self.enx + c).reshape(q.shape[0], -1))  # inside the exemplar already


class _Bound:
    """Lower bounds of the patch distances: the distances between the patches' projections.

    Projecting the weighted patches on ``m`` orthonormal vectors ``B`` (the
    leading principal components of a sample of the exemplar's weighted
    patches) shortens every difference: ``||B (a - b)||^2 <= ||a - b||^2``.
    A candidate whose projected distance already exceeds what the query
    holds cannot be better and is skipped without reading its patch, so the
    field found is the one the exact comparisons alone would find; only the
    work changes. With ``m`` = 16 values per patch instead of ``ph pw C``,
    a bound costs a small fraction of an exact distance. The exemplar's
    projections are correlations with the components (one FFT bank), kept
    for the next search of the same exemplar (texture optimization searches
    it once per EM iteration); the queries' are one matrix product.
    Projections are float64 whatever the images, so their rounding is far
    below the slack allowed for the exact distances' own.
    """

    def __init__(self, problem):
        self.kernels, self.offset, self.exemplar = _bound_exemplar(problem)
        n = problem.centers.shape[0]
        self.queries = np.empty((n, self.offset.shape[0]))
        for a in range(0, n, problem.block):
            q = np.arange(a, min(a + problem.block, n))
            patches = (problem.queries[q] if problem.queries is not None else
                       problem.qview[problem.qr[q], problem.qc[q]].reshape(q.shape[0], -1))
            np.matmul(patches.astype(np.float64, copy=False), self.kernels, out=self.queries[q[0] : q[-1] + 1])
        self.queries -= self.offset
        # the exact distances are summed in the problem's precision: a bound rules a candidate out only
        # when it exceeds the held distance by more than their rounding (dim values, each off by at most
        # a unit in the last place)
        self.slack = 1.0 + max(1e-3, 4 * problem.dim * float(np.finfo(problem.dtype).eps))

    def may_beat(self, q, ids, worst):
        """Which candidates ``ids`` of queries ``q`` may be nearer than ``worst`` (their bound is not above it)."""
        diff = self.queries[q] - self.exemplar[ids]
        return np.einsum("ij,ij->i", diff, diff) <= worst * self.slack


def _gather(view, rows, cols, workspace=None):
    """``view[rows, cols]``; by one strided copy where ``(rows, cols)`` is a regular grid in row-major order.

    A regular grid of patches of a sliding-window view is itself a strided view, copied in one pass. With a
    ``workspace`` dict the copy goes into the array it keeps under ``"queries"`` (made or replaced when the
    shape changes): the searches of one EM stage fill the same memory again instead of taking hundreds of
    megabytes of fresh pages from the system each time (texture optimization 256 -> 1024 px: 12.8 s
    against 13.3-14.2 s).
    """
    axes = grid_axes(rows, cols) if rows.shape[0] else None
    if axes is None:
        return view[rows, cols]
    r, c = axes
    step_r, step_c = (int(v[1] - v[0]) if v.shape[0] > 1 else 1 for v in (r, c))
    if not (np.array_equal(r, r[0] + step_r * np.arange(r.shape[0]))
            and np.array_equal(c, c[0] + step_c * np.arange(c.shape[0]))):  # an uneven grid: no strided view
        return view[rows, cols]
    patches = view[r[0] : r[-1] + 1 : step_r, c[0] : c[-1] + 1 : step_c]
    shape = (rows.shape[0],) + view.shape[2:]
    if workspace is None:
        return np.ascontiguousarray(patches).reshape(shape)
    out = workspace.get("queries")
    if out is None or out.shape != shape or out.dtype != patches.dtype:
        out = workspace["queries"] = np.empty(shape, patches.dtype)
    np.copyto(out.reshape(patches.shape), patches)
    return out


def project_patches(exemplar, patch_size, n_components=16, *, pixel_weights=None):
    """Every patch of an exemplar projected on the leading principal components of its patches.

    Compact descriptors of the patches: what PatchMatch's distance bounds
    compare, and what texture optimization's k-coherence sets are found
    among. The components are those of a sample of 1024 (weighted) patches
    (a fixed seed: the same exemplar gives the same projections).

    Parameters
    ----------
    exemplar : numpy.ndarray
        Float ``(H, W, C)``.
    patch_size : int or (int, int)
    n_components : int
        ``m``, at most the patch dimension.
    pixel_weights : numpy.ndarray, optional
        ``(ph, pw)`` weights of the patch pixels in the distance (the
        projections are of ``sqrt(weights) * patch``).

    Returns
    -------
    numpy.ndarray
        float64 ``((H - ph + 1) * (W - pw + 1), m)``, row-major top-left
        corners; squared distances between rows are lower bounds of the
        weighted squared distances between the patches.

    Examples
    --------
    >>> img = np.random.default_rng(0).random((20, 20, 3))
    >>> project_patches(img, 5, 4).shape
    (256, 4)
    """
    ph, pw = patch_shape(patch_size)
    shape = np.shape(exemplar)
    if len(shape) != 3 or ph > shape[0] or pw > shape[1]:
        raise ValueError(f"exemplar must be (H, W, C) and hold a ({ph}, {pw}) patch, got shape {shape}")
    m = check_positive_int(n_components, "n_components")
    positions = (shape[0] - ph + 1) * (shape[1] - pw + 1)
    # a float64 copy of the exemplar, the projections, their FFT bank's output and one transposed copy
    check_memory(8.0 * (2 * np.prod(shape) + 3.0 * positions * min(m, ph * pw * shape[2])), m, "n_components",
                 "the patch projections", also={"exemplar": shape})
    ex = np.ascontiguousarray(exemplar, dtype=np.float64)
    view = np.moveaxis(sliding_window_view(ex, (ph, pw), axis=(0, 1)), 2, -1)
    wsqrt = np.ones(ph * pw * ex.shape[-1])
    if pixel_weights is not None:
        wsqrt = np.repeat(np.sqrt(_check_pixel_weights(pixel_weights, (ph, pw))).ravel(), ex.shape[-1])
    enx = view.shape[1]
    ids = np.arange(view.shape[0] * enx)
    return _projections(ex, view, enx, ids, wsqrt, min(m, wsqrt.shape[0]), _PROJECTION_SAMPLES)[2]


def _projections(exemplar, eview, enx, ids, wsqrt, m, samples):
    """The components of a sample of ``samples`` patches ``ids`` as ``(dim, m)`` kernels, the sample
    mean's projection, and every patch's projection ``(eny * enx, m)`` less that mean's."""
    ph, pw = eview.shape[2:4]
    # a fixed generator: the same exemplar, the same projections
    rng = np.random.default_rng(0)
    sample = ids[rng.choice(ids.shape[0], size=min(samples, ids.shape[0]), replace=False)]
    er, ec = np.divmod(sample, enx)
    x = eview[er, ec].reshape(sample.shape[0], -1).astype(np.float64) * wsqrt
    mean = x.mean(axis=0)
    _, vt, _ = pca(x - mean, min(m, *x.shape), rng)
    basis = np.linalg.qr(vt[:m].T)[0].T  # re-orthonormalised, so a projection can only shorten a difference
    kernels = np.ascontiguousarray((basis * wsqrt).T)  # (dim, m): patch @ kernels = B (w^1/2 patch)
    offset = basis @ mean
    proj = correlate_bank(exemplar, kernels.T.reshape(-1, ph, pw, exemplar.shape[-1]))
    return kernels, offset, np.ascontiguousarray(proj.reshape(proj.shape[0], -1).T) - offset


def _bound_exemplar(problem):
    """The exemplar side of :class:`_Bound`: the weighted components as a ``(dim, m)`` matrix, the
    projection of the sample mean, and every allowed exemplar patch's projection ``(eny * enx, m)``.

    Kept for the last exemplar searched, keyed by its content (not its identity, so an exemplar
    changed in place is projected again).
    """
    wsqrt = np.ones(problem.dim) if problem.wsqrt is None else problem.wsqrt.astype(np.float64)
    digest = hashlib.sha1(problem.exemplar.tobytes())
    for extra in (wsqrt, problem.allowed):
        digest.update(np.ascontiguousarray(extra).tobytes())
    key = (digest.hexdigest(), problem.exemplar.shape, problem.patch)
    if key in _BOUND_CACHE:
        return _BOUND_CACHE[key]
    # the components of the allowed patches; a fixed seed: the bound changes the work, never the field
    entry = _projections(problem.exemplar, problem.eview, problem.enx, problem.allowed_ids, wsqrt,
                         _BOUND_COMPONENTS, _BOUND_SAMPLES)
    _BOUND_CACHE.clear()
    _BOUND_CACHE[key] = entry
    return entry


class _Field:
    """The current answer: ``ids`` ``(N, k)`` exemplar patches, ``d2`` their distances, ascending."""

    def __init__(self, ids, d2):
        self.ids = np.ascontiguousarray(ids)
        self.d2 = np.ascontiguousarray(d2)
        self.dist = None  # with a penalty and k = 1: the held patches' distances without it


def _radii(w):
    """Random-search radii ``w alpha^i`` (rounded) while they are at least one pixel."""
    radii = []
    r = float(w)
    while r >= 1.0:
        radii.append(round(r))
        r *= ALPHA
    return np.asarray(radii, dtype=np.int64)


# --------------------------------------------------------------------------- neighbours of the queries
class _Neighbors:
    """Which queries propagate to which, and the offsets between their centres.

    Centres that form a (possibly uneven) rectilinear grid, in any order, or
    fill at least a quarter of one (a part of a grid: the cells of the others
    are missing), are handled as a grid: each query's neighbours are the next
    grid points left, up, right and down (across the border in
    ``mode="wrap"``), none where that cell is missing. Any other set of
    centres uses the nearest other centres.
    """

    def __init__(self, centers, shape, mode):
        self.centers, self.shape, self.wrap = centers, shape, mode == "wrap"
        self._scans = {}
        n = centers.shape[0]
        grid, gi, gj = grid_cells(centers)
        self.grid = None
        if n >= _GRID_MIN_FILL * grid.size and np.count_nonzero(grid >= 0) == n:  # no centre repeated
            self.grid, self.gi, self.gj = grid, gi, gj
            diag = self.gi + self.gj
            order = np.argsort(diag, kind="stable")
            bounds = np.searchsorted(diag[order], np.arange(grid.shape[0] + grid.shape[1]))
            # queries on each anti-diagonal gi + gj = t: their left and upper neighbours lie on t - 1
            self.diagonals = np.split(order, bounds[1:])
        if self.grid is None:
            self._irregular()

    def scan(self, forward):
        """Grid: every query's left and upper neighbours (``forward``; else right and lower), ``(N, 2)``,
        -1 where there is none, and the offsets from them ``(N, 2, 2)``; computed once per direction."""
        if forward not in self._scans:
            q = np.arange(self.centers.shape[0])
            dirs = ((0, -1), (-1, 0)) if forward else ((0, 1), (1, 0))
            nbrs = np.stack([self.toward(q, di, dj) for di, dj in dirs], axis=1)
            shifts = np.stack([self.shift(q, np.maximum(nbrs[:, j], 0)) for j in range(2)], axis=1)
            self._scans[forward] = nbrs, shifts
        return self._scans[forward]

    def shift(self, q, nb):
        """Offsets ``centre(q) - centre(nb)`` (shortest way round in wrap mode)."""
        d = self.centers[q] - self.centers[nb]
        if self.wrap:
            size = np.asarray(self.shape)
            d = (d + size // 2) % size - size // 2
        return d

    def toward(self, q, di, dj, step=1):
        """The grid neighbour ``step`` points away in direction ``(di, dj)``, -1 where there is none."""
        ni, nj = self.gi[q] + di * step, self.gj[q] + dj * step
        nr, nc = self.grid.shape
        if self.wrap:
            ni, nj = ni % nr, nj % nc
            ok = np.ones(q.shape[0], dtype=bool)
        else:
            ok = (ni >= 0) & (ni < nr) & (nj >= 0) & (nj < nc)
        out = np.full(q.shape[0], -1, dtype=np.int64)
        out[ok] = self.grid[ni[ok], nj[ok]]
        return out

    def _irregular(self):
        n = self.centers.shape[0]
        m = min(_IRREGULAR_NEIGHBORS, n - 1)
        self.near = np.full((n, max(m, 0)), -1, dtype=np.int64)
        if m < 1:
            return
        pts = self.centers.astype(np.float64)
        box = None
        if self.wrap:
            box = np.asarray(self.shape, dtype=np.float64)
            pts = np.mod(pts, box)
        tree = point_tree(pts, period=box)
        _, idx = tree.query(pts, k=m + 1)
        # drop the query itself (with repeated centres the tree may list another copy first)
        self_hit = idx == np.arange(n)[:, None]
        keep = np.where(self_hit.any(axis=1)[:, None], ~self_hit, np.arange(m + 1)[None, :] < m)
        self.near = idx[keep].reshape(n, m).astype(np.int64)


# --------------------------------------------------------------------------- one iteration
def _iterate(problem, field, it, rng):
    """Propagation and random search over the whole field, once (Barnes et al. 2009, Sec. 3.2).

    Iteration ``it`` even: scan order, propagating from the left and upper
    neighbours; odd: reverse scan order, from the right and lower ones. On a
    grid the scan runs by anti-diagonals (see :func:`patchmatch`, Notes);
    other centres have no scan order and take :func:`_iterate_parallel`.
    """
    nb = problem.neighbors
    if nb.grid is None:
        return _iterate_parallel(problem, field, it, rng)
    forward = it % 2 == 0
    nbrs, shifts = nb.scan(forward)
    for q in nb.diagonals if forward else nb.diagonals[::-1]:
        if q.shape[0] == 0:
            continue
        problem.propagate(field, q, nbrs[q], shifts[q])
        problem.random_search(field, q, rng)


def _iterate_parallel(problem, field, it, rng):
    """One iteration with every query at once (Jacobi style), then random search for all.

    On a grid, jump flooding: the neighbours ``2^j, ..., 2, 1`` grid steps
    away (left and up on even iterations, right and down on odd ones), so a
    match can cross the field in one iteration. Other centres: their nearest
    centres. Used for irregular centres; on grids, ``benchmarks/bench_patchmatch.py``
    measures it against the anti-diagonal scan (which the library uses).
    """
    nb = problem.neighbors
    n = problem.centers.shape[0]
    q = np.arange(n)
    if nb.grid is None:
        if nb.near.shape[1]:
            shifts = np.stack([nb.shift(q, nb.near[:, j]) for j in range(nb.near.shape[1])], axis=1)
            problem.propagate(field, q, nb.near, shifts)
    else:
        dirs = ((0, -1), (-1, 0)) if it % 2 == 0 else ((0, 1), (1, 0))
        for step in 2 ** np.arange(int(np.log2(max(nb.grid.shape))), -1, -1):
            for di, dj in dirs:
                nbrs = nb.toward(q, di, dj, int(step))[:, None]
                shifts = nb.shift(q, np.maximum(nbrs[:, 0], 0))[:, None, :]
                for a in range(0, n, problem.block):
                    b = slice(a, a + problem.block)
                    problem.propagate(field, q[b], nbrs[b], shifts[b])
    for a in range(0, n, problem.block):
        problem.random_search(field, q[a : a + problem.block], rng)


# --------------------------------------------------------------------------- checks
def _check_k(k):
    if not isinstance(k, numbers.Integral) or isinstance(k, bool):
        raise TypeError(f"k must be an integer >= 1, got {k!r}")
    if k < 1:
        raise ValueError(f"k must be an integer >= 1, got {k}")
    return int(k)


def _check_centers(centers, shape, patch, mode):
    """``(N, 2)`` int64 centres; default every pixel (``"valid"``: every pixel whose patch fits)."""
    ph, pw = patch
    height, width = shape
    if centers is None:
        if mode == "valid":
            rr, cc = np.mgrid[ph // 2 : height - ph + ph // 2 + 1, pw // 2 : width - pw + pw // 2 + 1]
        else:
            rr, cc = np.mgrid[0:height, 0:width]
        return np.stack([rr.ravel(), cc.ravel()], axis=1).astype(np.int64)
    arr = np.asarray(centers)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] == 0 or not np.issubdtype(arr.dtype, np.integer) \
            or arr.dtype == np.bool_:
        raise ValueError(
            f"centers must be a non-empty integer array of shape (N, 2) holding (row, col), got dtype "
            f"{arr.dtype} and shape {arr.shape}; e.g. texsynth.core.neighborhood.grid_centers(image.shape[:2], "
            "patch_size, grid_spacing)"
        )
    arr = arr.astype(np.int64)
    if mode == "valid":
        lo = np.array([ph // 2, pw // 2])
        hi = np.array([height - ph + ph // 2, width - pw + pw // 2])
        bad = np.any((arr < lo) | (arr > hi), axis=1)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"centers[{i}] = {arr[i].tolist()} puts its ({ph}, {pw}) patch outside the image {tuple(shape)} "
                f"in mode='valid' (centres must lie in rows {lo[0]}..{hi[0]}, columns {lo[1]}..{hi[1]}); "
                "move the centres inside or pass mode='wrap' or 'reflect'"
            )
        return arr
    if mode == "wrap":  # a torus: any integer centre is some pixel's
        return np.mod(arr, np.asarray(shape))
    bad = np.any((arr < 0) | (arr >= np.asarray(shape)), axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"centers[{i}] = {arr[i].tolist()} lies outside the image {tuple(shape)}; "
                         "pass centres of pixels of the image (mode='reflect' mirrors the patches, not the centres)")
    return arr


def _allowed(mask, shape, patch):
    """Flat bool over the exemplar's patches: True where the patch touches no False pixel of ``mask``."""
    ph, pw = patch
    eny, enx = shape[0] - ph + 1, shape[1] - pw + 1
    if mask is None:
        return np.ones(eny * enx, dtype=bool)
    m = np.asarray(mask)
    if m.ndim == 3 and m.shape[-1] == 1:
        m = m[..., 0]
    if m.shape != tuple(shape):
        raise ValueError(f"exemplar_mask must have the exemplar's shape {tuple(shape)} (one value per pixel), "
                         f"got shape {np.shape(mask)}")
    if m.dtype != np.bool_:
        if not np.issubdtype(m.dtype, np.number) or np.issubdtype(m.dtype, np.complexfloating):
            raise TypeError(
                f"exemplar_mask must be a bool array (True where pixels may be copied), got dtype {m.dtype}"
            )
        if not np.all(np.isfinite(m)):
            raise ValueError("exemplar_mask contains NaN or infinite values; pass a bool array")
        m = m > 0.5
    allowed = patches_within(m, patch)[:eny, :enx].ravel()  # a patch is allowed if it holds no masked pixel
    if not allowed.any():
        raise ValueError(
            f"exemplar_mask leaves no ({ph}, {pw}) patch of the exemplar free of masked (False) pixels; "
            "mark more pixels True or pass a smaller patch_size"
        )
    return allowed


def _check_pixel_weights(weights, patch):
    w = np.asarray(weights)
    if w.dtype == object or not np.issubdtype(w.dtype, np.number) or np.issubdtype(w.dtype, np.complexfloating):
        raise TypeError(f"pixel_weights must be a real array of shape {patch}, got dtype {w.dtype}")
    w = w.astype(np.float64)
    if w.shape != tuple(patch):
        raise ValueError(f"pixel_weights must have shape {tuple(patch)} (one weight per patch pixel), got shape "
                         f"{w.shape}; e.g. texsynth.core.neighborhood.gaussian_falloff(patch_size)")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ValueError("pixel_weights must be finite and non-negative; replace NaN or negative weights")
    if not np.any(w > 0):
        raise ValueError("pixel_weights are all zero, so every distance would be 0; give some pixel a positive weight")
    return w


# --------------------------------------------------------------------------- public
def patchmatch(image, exemplar, patch_size, *, centers=None, k=1, iterations=5, init=None, exemplar_mask=None,
               pixel_weights=None, mode="valid", penalty=None, rng=None):
    """Approximate nearest-neighbour field: for every patch of ``image``, the nearest patches of ``exemplar``.

    PatchMatch (Barnes et al. 2009 [1]_; k nearest neighbours as in Barnes et
    al. 2010 [2]_) finds, for the patch centred at each of ``centers`` in
    ``image``, the ``k`` nearest (weighted sum of squared differences) patches
    that lie wholly inside ``exemplar``, without indexing the exemplar:

    1. **Initialisation** (Sec. 3.1). Each query gets ``k`` distinct random
       exemplar patches, drawn uniformly among the allowed ones, or starts
       from ``init`` (the previous EM iteration's field, or a coarser level's
       upsampled by the caller).
    2. **Propagation** (Sec. 3.2). In scan order, each query tries the
       patches of its left and upper neighbours, each shifted by the offset
       from that neighbour's centre to its own: where the exemplar was copied
       coherently, the neighbour's match shifted is this query's match. Every
       other iteration scans in reverse order, from the right and lower
       neighbours, so information flows both ways.
    3. **Random search** (Sec. 3.2). Around each held patch ``v0``, one
       candidate ``u_i = v0 + w alpha^i R_i`` per radius: ``w`` the larger
       side of the exemplar, ``alpha = 1/2``, ``i = 0, 1, ...`` while
       ``w alpha^i >= 1``, ``R_i`` uniform in ``[-1, 1]^2`` (the window is
       clipped to the exemplar and sampled uniformly inside).
    4. A candidate replaces a held patch only if it is strictly nearer and not
       held already; each query keeps its ``k`` best distinct patches (for
       ``k > 1``, propagation offers all ``k`` patches of each neighbour and
       random search runs around each of the ``k``, as in [2]_).

    Steps 2-3 are one iteration; ``iterations`` of them are run in full.

    Parameters
    ----------
    image : array_like
        ``(H, W)`` or ``(H, W, C)``: the image whose patches are queried
        (Barnes' A; texture optimization's current output ``x``).
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)``, the same channels: the image whose patches
        are searched (Barnes' B). Its patches always lie wholly inside it.
    patch_size : int or (int, int)
        Patch size; a patch centred at ``(r, c)`` covers rows
        ``r - h//2 ... r - h//2 + h - 1`` (:mod:`texsynth.core.neighborhood`).
    centers : array_like of int, shape (N, 2), optional
        Centres ``(row, col)`` in ``image`` of the patches to match. On a
        regular (or rectilinear) grid, such as texture optimization's ``w/4``
        grid from :func:`~texsynth.core.neighborhood.grid_centers`, or on a
        part of one that fills at least a quarter of its rows times columns
        (the grid points near a hole), propagation runs between grid
        neighbours; other sets of centres propagate from their 4 nearest
        centres. Default: every pixel (a dense field; in
        ``"valid"`` mode every pixel whose patch fits).
    k : int
        How many nearest exemplar patches per query, distinct.
    iterations : int
        Iterations of propagation and random search, all run (0: only the
        initial field, with its exact distances). Default 5, as Barnes et al.
        report convergence after 4-5 iterations.
    init : array_like of int, shape (N, k, 2), optional
        Exemplar centres to start from instead of random ones. Centres whose
        patch would leave the exemplar are moved inside; patches that touch a
        masked pixel, and repeats within a row, are replaced by random ones.
    exemplar_mask : array_like of bool, shape (h, w), optional
        Exemplar pixels that may be copied: no returned patch touches a False
        pixel (as texture optimization's ``exemplar_mask``; hole filling).
    pixel_weights : array_like, shape (patch_size), optional
        Non-negative weight per patch pixel (e.g.
        :func:`~texsynth.core.neighborhood.gaussian_falloff`); the distance
        is ``sum_{pixels} w (a - b)^2`` over all channels.
    mode : {"valid", "wrap", "reflect"}
        How ``image``'s patches meet its border: inside only, wrapped around
        (tileable outputs: patches and propagation cross the border), or
        mirrored.
    penalty : callable, optional
        ``penalty(queries, centres)``: a finite, non-negative cost added to the distance of
        each candidate when candidates are ranked, for the queries numbered
        ``queries`` ``(n,)`` and the exemplar patches centred at ``centres``
        ``(n, 2)`` (e.g. the occurrence and copy penalties of texture
        optimization, Kaspar et al. 2015). It is called on every batch of
        candidates, so keep it vectorised; it must not change during the
        search.
    rng : None, int or numpy.random.Generator
        Seeds the initialisation and the random search. Same seed, same field,
        bit for bit.

    Returns
    -------
    field : numpy.ndarray of int64, shape (N, k, 2)
        Exemplar centres ``(row, col)`` of the ``k`` patches found for each
        query, nearest first.
    sq_distances : numpy.ndarray, shape (N, k)
        Their exact weighted squared distances, ascending (float32 if both
        images are float32, float64 otherwise); with a ``penalty``, the
        distances plus the penalty, which is what they are ranked by.

    Raises
    ------
    ValueError, TypeError
        For images that are not images or differ in channels, a
        ``patch_size`` larger than the exemplar or the image, centres whose
        patch leaves the image in ``"valid"`` mode, ``k`` larger than the
        allowed exemplar patches, an ``exemplar_mask`` that leaves no patch
        free, ``init`` or ``pixel_weights`` of the wrong shape, an unknown
        ``mode``, a ``penalty`` that returns negative or non-finite costs,
        or a field too large for the free memory.

    See Also
    --------
    nearest_field : The same question asked of any backend.
    texsynth.core.search.PatchIndex : Nearest neighbours of independent vectors.
    texsynth.core.neighborhood.grid_centers : The w/4 grid of texture optimization.

    Notes
    -----
    **Order.** The paper visits queries one at a time in scan order; query
    ``(i, j)`` reads the current matches of ``(i, j-1)`` and ``(i-1, j)``,
    which the scan has already updated. Those two lie on the anti-diagonal
    ``i + j - 1``, so visiting the grid by anti-diagonals, all queries of one
    anti-diagonal at once (vectorised), gives every query exactly the
    neighbours' states the sequential scan gives it: the propagation is the
    paper's (a test checks it against a one-at-a-time scan), a good match
    travels across the whole field in one pass, and nothing is lost in
    recall. The Python loop runs over the ``nr + nc - 1`` anti-diagonals of an
    ``nr x nc`` grid, not over the queries. The random numbers are drawn per
    anti-diagonal, so they differ from a sequential implementation's (equally
    good results, not identical ones).

    The usual vectorised alternative, every query at once from its
    neighbours ``2^j, ..., 2, 1`` grid steps away (jump flooding, Jacobi
    style), was measured against it in ``benchmarks/bench_patchmatch.py``
    (512 px photograph against a 256 px one, w = 8, 16, 32 on the w/4 grid):
    after one iteration, what a warm start in an EM loop runs, its energy
    (sum of distances) was 4-6 % higher and its recall@1 at most the scan's
    (0.009-0.011 against 0.009-0.037); after 5 iterations its energy was
    1-2 % lower, but it took 1.55-1.7x as long, and at equal time (the scan
    running 8 iterations) the scan was as good or better (energy 1.134
    against 1.164 at w = 8, 1.105 against 1.108, 1.067 against 1.073).
    Centres that do not form a grid have no scan order: they take that
    parallel form, propagating from their 4 nearest centres (a match travels
    one neighbour per iteration, so recall per iteration is lower than on a
    grid).

    **Cost.** Each iteration evaluates about ``k (2 + log2(max(h, w)) + 1)``
    candidates per query by direct differences (the patch dimension each),
    blocks of 4 MiB at a time; candidates already held are skipped. The query
    patches are extracted once while they take at most 256 MiB, otherwise per
    block. Memory held: the images, the field (``N k`` positions and
    distances) and those blocks, never the exemplar's patches (a kd-tree or
    exact index holds every one of them); a field that cannot fit is refused
    before it is allocated. Measured: a dense 7 x 7 field of a 1024 x 1024
    colour image (1M queries), 2.8 s and 214 MB per iteration; the w/4 grid
    of a 4096 x 4096 output with w = 32 (262 144 queries of 3072 values),
    5.9 s and 0.7 GB (two cores shared, float32).

    **Bounds.** Patches of 256 values or more (e.g. 10 x 10 colour) are
    first compared by their projections on the 16 leading principal
    components of the exemplar's (weighted) patches: a projection can only
    shorten a difference, so a candidate whose projected distance already
    exceeds the distance a query holds cannot be better and is skipped
    without reading its patch. The field is the one the exact comparisons
    alone would find, bit for bit; only the work changes (in texture
    optimization 256 -> 1024 px, 95 % of the 16 px candidates, 81 % of the
    32 px ones and 45 % of the 64 px ones were ruled out that way). The
    exemplar's projections (one FFT correlation per component) are kept for
    the next search of the same exemplar; exemplars with more than 2**19
    patch positions (about 724 x 724), and searches whose queries hold
    fewer than 64 values per exemplar patch position (a few queries, as near
    a small hole: the projections would cost more than they save), are
    searched without bounds, and a ``penalty`` must be non-negative (it is
    added to distances the bound has not seen).

    **Patents.** PatchMatch is covered by a patent held by Adobe (US
    8,861,869, "Determining correspondence between image regions"), as other
    open implementations note. Adobe also holds US 8,571,328 (same title:
    among others, k nearest patches kept in a heap with repeats removed) and
    US 10,762,680 and US 11,551,390 (parallel "wavefront" propagation along
    pixel waves, each wave from the previous one), which describe techniques
    close to the k > 1 search and the anti-diagonal order here. Check whether
    they apply to your use.

    References
    ----------
    .. [1] C. Barnes, E. Shechtman, A. Finkelstein and D. B. Goldman,
       "PatchMatch: a randomized correspondence algorithm for structural image
       editing", ACM TOG 28(3) (SIGGRAPH 2009). :doi:`10.1145/1531326.1531330`
    .. [2] C. Barnes, E. Shechtman, D. B. Goldman and A. Finkelstein, "The
       generalized PatchMatch correspondence algorithm", ECCV 2010.
       :doi:`10.1007/978-3-642-15558-1_3`

    Examples
    --------
    An image whose patches all occur in the exemplar: PatchMatch finds them.

    >>> rng = np.random.default_rng(0)
    >>> exemplar = rng.random((40, 40, 3))
    >>> image = exemplar[5:25, 10:30]
    >>> field, d2 = patchmatch(image, exemplar, 5, rng=0)
    >>> field.shape, d2.shape
    ((256, 1, 2), (256, 1))
    >>> bool(np.all(field[0, 0] == [7, 12])), float(d2.max())
    (True, 0.0)
    """
    problem = _Problem(image, exemplar, patch_size, centers, k, exemplar_mask, pixel_weights, mode, penalty)
    return _run(problem, init, check_positive_int(iterations, "iterations", 0), as_rng(rng))


def _run(problem, init, iterations, rng, distances=False):
    """The field of ``problem`` after ``iterations`` of propagation and random search from ``init``."""
    field = problem.start(init, rng)
    for it in range(iterations):
        _iterate(problem, field, it, rng)
    return problem.result(field, distances)


def patchmatch_features(image, exemplar, patch_size, *, centers=None, k=1, iterations=5, init=None,
                        exemplar_mask=None, pixel_weights=None, mode="valid", penalty=None, rng=None, sets=None,
                        workspace=None):
    """:func:`patchmatch` of feature arrays: float ``(H, W, C)`` arrays the caller has checked.

    The search of :func:`patchmatch`, for the M-step of an EM loop that asks
    it many times: ``image`` and ``exemplar`` are taken as they are, with any
    number of channels and values beyond [0, 1] (texture optimization's
    guide channels, weighted), and are not converted or checked as images.
    The other arguments are checked as :func:`patchmatch` checks them.

    Parameters
    ----------
    image, exemplar : numpy.ndarray
        Float ``(H, W, C)`` and ``(h, w, C)``, the same ``C``, finite.
    patch_size, centers, k, iterations, init, exemplar_mask, pixel_weights, mode, penalty, rng
        As in :func:`patchmatch`.
    sets : numpy.ndarray of int, shape (eny * enx, k), optional
        k-coherence sets of the exemplar's patch positions (row-major
        top-left corners, :func:`~texsynth.core.search.coherence_sets`):
        every propagated candidate is offered with its set, and the random
        search is left out, so an iteration is Tong et al.'s k-coherent
        search in PatchMatch's scan order.
    workspace : dict, optional
        Kept by the caller across searches of the same size (one EM stage)
        and never shared between searches running at once; the query patches
        are copied into the memory it holds.

    Returns
    -------
    field : numpy.ndarray of int64, shape (N, k, 2)
        As :func:`patchmatch` returns it.
    sq_distances : numpy.ndarray, shape (N, k)
        As :func:`patchmatch` returns it (with a ``penalty``: plus the penalty).
    plain_distances : numpy.ndarray, shape (N, k)
        The distances without the ``penalty`` (``sq_distances`` itself
        without one; None if a penalty ranked ``k > 1`` patches), so a caller
        that ranks by distance plus penalty needs no second pass for them.
    """
    problem = _Problem(image, exemplar, patch_size, centers, k, exemplar_mask, pixel_weights, mode, penalty,
                       checked=True, workspace=workspace)
    problem.sets = sets
    return _run(problem, init, check_positive_int(iterations, "iterations", 0), as_rng(rng), distances=True)


#: :func:`resolve_field`: problems up to this much work (exemplar patches times queries times the
#: patch dimension, what an exact search computes: about 0.03 s of BLAS on two cores) take an index in
#: ``"auto"``. Lowered from 2**31 (2026-11-24): with PatchMatch on the stages between 2**29 and
#: 2**31 values, texture optimization of 8 photographs 64 -> 96 px and 7 of them 128 -> 256 px was
#: 14-25 % faster, with completeness and large-scale spectrum distance as often better as worse and
#: verbatim copies as large or smaller (docs/methods/search.md).
FIELD_MIN_VALUES = 2**29

#: Values of ``method`` for :func:`nearest_field`.
FIELD_METHODS = ("auto", "exact", "kdtree", "tsvq", "patchmatch")


def check_field_method(method, name="method"):
    """``method`` itself if it is one of :data:`FIELD_METHODS`, else a ValueError listing them."""
    if not isinstance(method, str) or method not in FIELD_METHODS:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, FIELD_METHODS))}, got {method!r}")
    return method


def resolve_field(method, *, applies=True, values=None):
    """What ``method`` means for the field of an EM loop's M-step: ``"patchmatch"`` or an index backend.

    ``"auto"`` is ``"patchmatch"`` where PatchMatch ``applies`` (the
    algorithm's distance is a weighted sum of squared pixel differences, and
    the loop warm-starts it from its previous field, which
    ``benchmarks/bench_patchmatch.py`` shows matching five cold iterations
    after one) and the problem is larger than :data:`FIELD_MIN_VALUES`
    ``values`` (exemplar patches times queries times the patch dimension):
    below that an exact or kd-tree index answers quickly, and better. :func:`~texsynth.core.search.use` switching every search to
    one backend also keeps ``"auto"``, for the index's profile to decide.

    Examples
    --------
    >>> from texsynth.core import search
    >>> resolve_field("auto"), resolve_field("auto", applies=False), resolve_field("exact")
    ('patchmatch', 'auto', 'exact')
    >>> resolve_field("auto", values=1000)
    'auto'
    >>> with search.use("kdtree"):
    ...     resolve_field("auto")
    'auto'
    """
    check_field_method(method)
    large = values is None or values > FIELD_MIN_VALUES
    if method == "auto" and applies and large and forced_method.get() is None:
        return "patchmatch"
    return method


def nearest_field(image, exemplar, patch_size, *, centers=None, k=1, iterations=5, init=None, exemplar_mask=None,
                  pixel_weights=None, mode="valid", method="auto", rng=None):
    """The nearest exemplar patches of image patches, by any backend of the search layer.

    The question of :func:`patchmatch`, with the same arguments and answer,
    asked of ``method``: ``"patchmatch"``, or ``"exact"``, ``"kdtree"``,
    ``"tsvq"`` (a :class:`~texsynth.core.search.PatchIndex` over every allowed
    exemplar patch, queried with the image's patches; ``iterations`` and
    ``init`` are then unused). ``"auto"`` means the ``"default"`` profile's
    choice among the index backends (:func:`texsynth.core.search.resolve`),
    or what :func:`texsynth.core.search.use` sets.

    Parameters
    ----------
    image, exemplar, patch_size, centers, k, iterations, init, exemplar_mask, pixel_weights, mode
        As :func:`patchmatch`.
    method : str
        One of :data:`FIELD_METHODS`.
    rng : None, int or numpy.random.Generator
        Seeds PatchMatch, or the build of an approximate index.

    Returns
    -------
    field : numpy.ndarray of int64, shape (N, k, 2)
        Exemplar centres of the k patches found for each query, nearest first.
    sq_distances : numpy.ndarray, shape (N, k)
        Their exact weighted squared distances, ascending.

    See Also
    --------
    patchmatch : The PatchMatch algorithm and its arguments.
    texsynth.core.search.PatchIndex : The index behind the other methods.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> exemplar = rng.random((30, 30))
    >>> f1, d1 = nearest_field(exemplar[3:13, 4:14], exemplar, 5, method="exact")
    >>> f2, d2 = nearest_field(exemplar[3:13, 4:14], exemplar, 5, method="patchmatch", rng=0)
    >>> bool(np.array_equal(f1, f2)), f1[0, 0].tolist()
    (True, [5, 6])
    """
    check_field_method(method)
    if method == "patchmatch":
        return patchmatch(image, exemplar, patch_size, centers=centers, k=k, iterations=iterations, init=init,
                          exemplar_mask=exemplar_mask, pixel_weights=pixel_weights, mode=mode, rng=rng)
    from ._index import PatchIndex

    problem = _Problem(image, exemplar, patch_size, centers, k, exemplar_mask, pixel_weights, mode)
    check_positive_int(iterations, "iterations", 0)
    ids = problem.allowed_ids
    check_memory(float(ids.shape[0]) * problem.dim * np.dtype(problem.dtype).itemsize * 2, problem.exemplar.shape,
                 "exemplar", "the exemplar's patch vectors", also={"patch_size": patch_size})
    er, ec = np.divmod(ids, problem.enx)
    vectors = problem.eview[er, ec].reshape(ids.shape[0], problem.dim)
    weights = None if problem.wsqrt is None else problem.wsqrt.astype(np.float64) ** 2
    index = PatchIndex(vectors, weights=weights, method=method, queries=problem.centers.shape[0], rng=rng)
    n = problem.centers.shape[0]
    idx = np.empty((n, problem.k), dtype=np.int64)
    d2 = np.empty((n, problem.k), dtype=problem.dtype)
    step = max(1, _QUERY_CACHE_BYTES // 4 // (problem.dim * np.dtype(problem.dtype).itemsize))
    for a in range(0, n, step):
        sl = slice(a, a + step)
        q = problem.qview[problem.qr[sl], problem.qc[sl]].reshape(-1, problem.dim)
        idx[sl], d2[sl] = index.query(q, k=problem.k)
    return problem.result(_Field(ids[idx], d2))
