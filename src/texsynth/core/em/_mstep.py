"""The M-step forms: each output neighbourhood's nearest exemplar neighbourhood, by the search layer.

:func:`nearest_step` (an index, or PatchMatch over neighbourhoods sampled in frames), :func:`field_step`
(PatchMatch between the images, Barnes et al. 2009), :func:`constrained_step` (Algorithm 2 of Kwatra et
al. 2005: candidates re-ranked with the soft constraint) and :func:`frame_step` (an animation frame's
coherent candidates). Every form keeps the current ``z_p`` unless a candidate is strictly better, so none
raises the energy it minimises; every choice among candidates is made by :mod:`texsynth.core.search`.
"""

from __future__ import annotations

import numpy as np

from .._validate import as_rng
from ..neighborhood import extract, grid_cells
from ..search import lowest_cost, nearest_candidates, patchmatch_features, sq_distances
from ._patches import output_patches, patch_features

__all__ = ["nearest_step", "field_step", "constrained_step", "frame_step", "frame_terms", "SearchMemo",
           "coherent_candidates", "random_candidates"]


# Candidates re-ranked by the modified M-step (Algorithm 2) for constrained patches.
_CONSTRAINED_CANDIDATES = 8


# Occurrence penalty / copy limit: index candidates re-ranked by distance + penalty
_OCCURRENCE_CANDIDATES = 4


class SearchMemo:
    """What the last search of every neighbourhood saw: its query and its distance then.

    Used by :func:`nearest_step` to skip the search of neighbourhoods that hardly
    moved since (see ``_RESEARCH_TOLERANCE``).
    """

    def __init__(self, n, dim):
        self.q = None if dim is None else np.zeros((n, dim), dtype=np.float32)
        self.rho = np.full(n, np.inf)
        self.searched = 0  # number of index queries (for StageInfo.searches)


def nearest_step(exemplar, x, centers, mode, matches, constraint, memo=None, tolerance=0.0, occurrence=None, warp=None,
                 iterations=0, rng=None):
    """z_p <- nearest exemplar neighbourhood of x_p (modified by Algorithm 2 under constraints).

    Returns the new indices and ``ρ_p`` of every (x_p, z_p) pair in float64.
    A candidate replaces the current ``z_p`` only if it is strictly better, so
    an approximate index can never make the step worse than keeping ``z_p``.

    With a ``memo`` of the previous searches, a neighbourhood is searched
    again only if ``x_p`` moved since its last search by more than
    ``tolerance`` times the distance it had then: if ``x_p`` moved by ``δ``
    (weighted norm) from a query whose nearest neighbour was at distance
    ``d``, no exemplar neighbourhood can be closer to the new ``x_p`` than
    ``d - δ`` while the current ``z_p`` is at most ``d + δ`` away (triangle
    inequality), so skipping loses at most ``2δ <= 2 tolerance d`` of the
    distance. Skipped neighbourhoods keep their ``z_p`` (their ``ρ_p`` is
    recomputed exactly), so the step still never raises the energy.

    With an ``occurrence`` penalty (Kaspar et al. 2015), candidates are ranked
    by ``ρ + penalty`` instead: the index's ``_OCCURRENCE_CANDIDATES`` nearest
    and the coherent candidates of every neighbourhood (searched or not,
    since the penalty changes as the others move).

    With a :class:`WarpedPatches` (orientation and magnification fields) ``x_p`` is the
    neighbourhood sampled in its frame, and the coherent candidates follow
    the frames. With ``iterations > 0`` (fields on a large stage) no index
    is built: PatchMatch runs on the stack of sampled ``x_p`` instead, from
    the current ``z_p``: each iteration ranks, for every searched
    neighbourhood at once, the coherent candidates of its four grid
    neighbours (propagation, in the frames) and one random exemplar
    neighbourhood within radii halving from the exemplar's size down to one
    pixel around its current ``z_p`` (random search), keeping the nearest.
    """
    q = patch_features(output_patches(x, centers, exemplar.size, mode, warp), exemplar.mu)
    q = q.astype(np.float64, copy=False)
    n = len(centers)
    stale = np.ones(n, dtype=bool)
    if memo is not None and matches is not None and tolerance > 0:
        moved = sq_distances(q, memo.q, exemplar.weights)
        stale = ~np.isfinite(memo.rho) | (moved > tolerance**2 * (memo.rho + exemplar.eps2))
    constrained = np.zeros(n, dtype=bool)  # neighbourhoods that touch constrained pixels
    if constraint is not None:
        m, t, lam = constraint
        mp = extract(m[..., None], centers, exemplar.size, mode=mode)[..., 0]  # (N, w, w)
        constrained = mp.reshape(n, -1).max(axis=1) > 0
    sel = np.flatnonzero(constrained & stale)
    free = np.flatnonzero(stale & ~constrained)
    pen = None if occurrence is None else occurrence.penalty
    if matches is None:
        new = np.zeros(n, dtype=np.int64)
        rho = np.full(n, np.inf)
        score = np.full(n, np.inf)
    else:
        new = matches.copy()
        rho = sq_distances(q, patch_features(exemplar.patches(matches), exemplar.mu), exemplar.weights)
        score = rho.copy()
        if pen is not None:  # the current z_p's own share of its occurrence does not count
            score += pen[matches] - occurrence.own + occurrence.copy_penalty(exemplar, matches, centers)

    def rank(rows, cand):
        if rows.size == 0:  # e.g. every neighbourhood touches a constrained pixel
            return
        r = sq_distances(q[rows], patch_features(exemplar.patches(cand), exemplar.mu), exemplar.weights)
        s = r if pen is None else r + pen[cand] + occurrence.copy_penalty(exemplar, cand, centers[rows])
        better = s < score[rows]
        rows = rows[better]
        new[rows], rho[rows], score[rows] = cand[better], r[better], s[better]

    if free.size and iterations:  # PatchMatch over the stack of sampled neighbourhoods
        for _ in range(iterations):
            offered = coherent_candidates(exemplar, centers, new, warp.inverse) + random_candidates(exemplar, new, rng)
            for c in offered:
                rows = free[c[free] != new[free]]  # a candidate equal to the current z_p cannot beat it
                rank(rows, c[rows])
    elif free.size:
        k = 1 if pen is None else min(_OCCURRENCE_CANDIDATES, len(exemplar))
        found = exemplar.index.query(q[free].astype(np.float32), k=k)[0]
        for j in range(k):
            rank(free, found[:, j])
    if matches is not None and pen is not None:
        # coherent candidates (Ashikhmin 2001): the z of the 4 grid neighbours shifted by the
        # offset to them, ranked like the index's answers
        rows = np.flatnonzero(~constrained)
        for c in coherent_candidates(exemplar, centers, new, None if warp is None else warp.inverse):
            rank(rows, c[rows])
    if sel.size:
        new, rho = constrained_step(exemplar, x, centers, mode, matches, constraint, q, sel, new, rho)
    if memo is not None:
        memo.q[stale] = q[stale]
        memo.rho[stale] = rho[stale]
        memo.searched += int(stale.sum())
    return new, rho


def field_step(exemplar, x, centers, mode, start, iterations, rng=None, occurrence=None, sets=None, workspace=None):
    """M-step by PatchMatch (Barnes et al. 2009): every ``z_p`` from a field warm-started at ``start``.

    With k-coherence ``sets`` (``candidates="k-coherent"``), the random
    search gives way to them: every continuation of a neighbour's ``z`` is
    offered with the ``k - 1`` exemplar neighbourhoods most like it (Tong et
    al. 2002).

    ``start`` holds an exemplar centre per neighbourhood (the current
    ``z_p``, or the previous stage's carried over). PatchMatch replaces a
    ``z_p`` only by a strictly nearer one (the same weighted distance ``ρ_p``
    with the fall-off), so the step never raises the energy. With an
    ``occurrence`` penalty or copy limit, candidates are ranked by ``ρ_p``
    plus the penalty instead, as in :func:`nearest_step`. ``workspace``: the
    stage's dict that PatchMatch copies the ``x_p`` into (reused, not fresh
    memory, in every M-step). Returns the new indices and their ``ρ_p``.
    """
    w = exemplar.size
    penalty = None
    if occurrence is not None:
        def penalty(q, c):
            idx = exemplar.grid[c[:, 0] - w // 2, c[:, 1] - w // 2]
            return occurrence.penalty[idx] + occurrence.copy_penalty(exemplar, idx, centers[q])
    mask = None if exemplar.valid.all() else exemplar.valid
    # x is float (H, W, C), with values beyond [0, 1] where an up-sampled level or the gradient solve
    # overshoots, and more than 4 channels with guide channels (``ex.guided``): the checked entry
    field, _, d2 = patchmatch_features(x, exemplar.image, w, centers=centers, init=start[:, None],
                                       iterations=iterations, exemplar_mask=mask, pixel_weights=exemplar.g, mode=mode,
                                       penalty=penalty, rng=rng, sets=sets, workspace=workspace)
    corner = field[:, 0] - w // 2
    new = exemplar.grid[corner[:, 0], corner[:, 1]]
    return new, d2[:, 0].astype(np.float64)  # ρ_p: the distances, without the penalty that ranked them


def constrained_step(exemplar, x, centers, mode, matches, constraint, queries, rows, chosen, rho):
    """Algorithm 2 (Kwatra et al. 2005) for the neighbourhoods ``rows`` that touch constrained pixels.

    Minimises ``||x_p - v||^2 + λ E_c(v) = ρ(x_p, v) + λ sum_k m_k (v_k - x^c_k)^2`` over exemplar
    neighbourhoods ``v``. The per-patch weights ``g + λ m`` differ from patch to patch, so no single index
    holds them: the index gives candidates for the completed-square query ``(g x + λ m x^c) / (g + λ m)``
    and the search layer re-ranks them by the exact criterion
    (:func:`texsynth.core.search.lowest_cost`); the current ``z_p`` (``matches``, if any) competes and
    keeps its place on a tie. ``queries`` are the feature vectors of every ``x_p``; ``chosen`` and ``rho``
    the step's indices and ``ρ_p`` so far, returned updated (as copies) at ``rows``.
    """
    m, t, lam = constraint
    size = exemplar.size
    xp = extract(x, centers[rows], size, mode=mode)
    tp = extract(t, centers[rows], size, mode=mode)
    g = exemplar.g[None, :, :, None]
    lm = lam * extract(m[..., None], centers[rows], size, mode=mode)
    blended = ((g * xp + lm * tp) / (g + lm)).reshape(len(rows), -1)
    # the constraint is on values only: the query keeps x_p's own differences
    qb = np.concatenate([blended, queries[rows, blended.shape[1]:]], axis=1)
    k = min(_CONSTRAINED_CANDIDATES, len(exemplar))
    cands = exemplar.index.query(qb.astype(np.float32), k=k)[0]
    if matches is not None:  # the current z_p competes too (ties keep it)
        cands = np.concatenate([cands, matches[rows, None]], axis=1)
    lm_flat = np.broadcast_to(lm, xp.shape).reshape(len(rows), -1)
    tflat = tp.reshape(len(rows), -1)
    costs = np.empty(cands.shape)
    rhos = np.empty(cands.shape)
    for j in range(cands.shape[1]):
        v = exemplar.patches(cands[:, j])
        rhos[:, j] = sq_distances(queries[rows], patch_features(v, exemplar.mu), exemplar.weights)
        diff = v.reshape(len(rows), -1) - tflat
        costs[:, j] = np.einsum("ij,ij->i", lm_flat * diff, diff)
    # ties keep the current z_p (the last column) or the nearer candidate
    best, _ = lowest_cost(rhos, costs, ties="last" if matches is not None else "first")
    chosen, rho = chosen.copy(), rho.copy()
    chosen[rows] = cands[np.arange(len(rows)), best]
    rho[rows] = rhos[np.arange(len(rows)), best]
    return chosen, rho


def frame_terms(exemplar, centers, mode, constraint, channels):
    """The parts of Algorithm 2's M-step criterion that only the constraint sets, fixed for a stage:
    ``W_p = g + λ m_p`` and ``λ m_p x^c_p`` per centre (float32), or None without a constraint."""
    if constraint is None:
        return None
    m, t, lam = constraint
    w, n = exemplar.size, len(centers)
    nv = w * w * channels
    lm = lam * np.repeat(extract(m[..., None], centers, w, mode=mode).reshape(n, -1), channels, axis=1)
    lm = lm.astype(np.float32)
    tp = extract(t, centers, w, mode=mode).reshape(n, -1).astype(np.float32, copy=False)
    wq = np.repeat(exemplar.weights.astype(np.float32)[None], n, axis=0)
    wq[:, :nv] += lm
    return wq, lm * tp


def frame_step(exemplar, x, centers, mode, matches, fixed, prior, lookup):
    """Algorithm 2's M-step for an animation frame, over coherent candidates.

    The candidates for each ``z_p`` are the current ``z_p``, the previous
    frame's correspondence carried along the flow (``prior``), the ``z`` of
    the four grid neighbours shifted by the offset to them (coherence, as in
    Ashikhmin 2001) and, if ``lookup``, a searched one: ``lookup(x, b)``
    returns it (PatchMatch's nearest of ``x_p``), or ``lookup=True`` takes the
    index's nearest neighbour of the completed-square query. They are ranked
    by the exact criterion
    ``ρ(x_p, v) + λ E_c = ||v - b_p||^2_{W_p} + const_p`` with
    ``W_p = g + λ m_p`` and ``b_p = (g x_p + λ m_p x^c_p) / W_p`` (values
    only; the differences keep ``x_p``'s), in float32; ties keep the current
    ``z_p``. ``fixed`` is :func:`frame_terms` of the constraint (None: no
    constraint). Returns the new indices and ``ρ_p`` in float64.
    """
    n = len(centers)
    q = patch_features(extract(x, centers, exemplar.size, mode=mode), exemplar.mu).astype(np.float32, copy=False)
    weights = exemplar.weights.astype(np.float32)
    wq, b = np.broadcast_to(weights, q.shape), q
    if fixed is not None:
        wq, lmtp = fixed
        nv = lmtp.shape[1]
        b = q.copy()
        b[:, :nv] = (weights[:nv] * q[:, :nv] + lmtp) / wq[:, :nv]
    cols = [c for c in (matches, prior) if c is not None]
    if cols:
        cols += coherent_candidates(exemplar, centers, cols[0])
    if callable(lookup):
        cols.append(lookup(x, b))
    elif lookup or not cols:
        cols.append(exemplar.index.query(b, k=1)[0][:, 0])
    cands = np.stack(cols, axis=1)
    choice, _ = nearest_candidates(b, cands, vectors=exemplar.feats, weights=wq)  # first minimum: ties keep z_p
    new = cands[np.arange(n), choice]
    return new, sq_distances(exemplar.feats[new], q, weights).astype(np.float64)


def random_candidates(exemplar, matches, rng=None):
    """PatchMatch's random search (Barnes et al. 2009): per ``z``, one neighbourhood at a uniform offset within
    each radius ``R, R/2, ..., 1`` (``R`` the exemplar's larger side) of its corner."""
    rng = as_rng(rng)
    out = []
    radius = max(exemplar.view.shape[:2])
    while radius >= 1:
        corner = exemplar.corner[matches] + rng.integers(-radius, radius + 1, size=(len(matches), 2))
        out.append(exemplar.lookup(corner, matches))
        radius //= 2
    return out


def coherent_candidates(exemplar, centers, matches, inverse=None):
    """For each centre, the ``z`` of its 4 grid neighbours shifted back by the offset to them (with the fields'
    ``inverse`` frames ``A^{-1}`` per centre: by that offset in the exemplar's frame, ``A^{-1} e``).

    The grid wraps round at its ends. ``centers`` may be a part of a grid (hard constraints keep only the
    neighbourhoods near unknown pixels): a centre whose neighbour is missing gets its own ``z`` back.
    """
    grid, gi, gj = grid_cells(centers)
    z = exemplar.corner[matches]
    out = []
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        nb = grid[(gi + di) % grid.shape[0], (gj + dj) % grid.shape[1]]
        has = nb >= 0
        nb = np.where(has, nb, np.arange(len(centers)))
        e = centers[nb] - centers
        if inverse is not None:
            e = np.einsum("nij,nj->ni", inverse, e)
        corner = np.where(has[:, None], z[nb] - e, z)
        out.append(exemplar.lookup(corner, matches))
    return out
