"""Video textures: endless play and seamless loops of a short clip (Schödl, Szeliski, Salesin & Essa 2000).

The module reads top-down as the paper does:

- Section 3.1, frame distances ``D_ij = ||I_i - I_j||_2`` and the transition probabilities
  ``P_ij ∝ exp(-D_{i+1, j} / sigma)``: a jump from frame ``i`` to frame ``j`` is good when ``j``
  looks like the frame that would have followed ``i``;
- Section 3.2, preserving dynamics: the distances filtered along the diagonals with binomial weights,
  ``D'_ij = sum_{k=-m}^{m-1} w_k D_{i+k, j+k}``;
- Section 3.3, avoiding dead ends: the anticipated future cost
  ``D''_ij = (C_ij)^p + alpha min_k D''_jk`` (``C`` below), iterated to a fixed point (the paper relates it to
  Q-learning; its expectation form, ``alpha sum_k P''_jk D''_jk``, is not implemented, see
  :func:`video_texture`'s Notes);
- Section 3.4, pruning: only the local maxima of the transition matrix, and none below a threshold;
- Section 4.1, random play: a Markov chain over the frames, sampled from ``P''``;
- Section 4.2, video loops: compound loops of exactly the requested length built from primitive
  (backward) loops by dynamic programming, then scheduled into an order that plays;
- Section 5, rendering: cross-fades at the jumps (morphing is out of scope).

Symbols as in the paper: ``I_i`` the input frames (``i = 0 .. T-1`` here), ``D``, ``D'``, ``D''`` the
three cost matrices, ``P''`` the transition probabilities used for play, ``sigma``, ``p``, ``alpha``.
We write the *transition cost* of a jump ``i -> j`` as ``C_ij = D'_{i+1, j}`` (the shift by one that
the paper's ``P_ij ∝ exp(-D'_{i+1, j} / sigma)`` makes), so the continuation ``i -> i+1`` costs 0.

References
----------
.. [1] A. Schödl, R. Szeliski, D. H. Salesin, I. Essa, "Video textures", Proc. SIGGRAPH 2000,
   pp. 489-498, doi:10.1145/344779.345012.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, check_bool, check_in_range, check_memory,
                              check_positive_float, check_positive_int, with_channels)

__all__ = ["video_texture", "VideoTextureInfo"]

#: Video loops: at most this many primitive loops (local minima of the transition cost along its
#: diagonals, the cheapest first) enter the dynamic programme, whose work grows with their square ...
MAX_PRIMITIVE_LOOPS = 32
#: ... and at most this many of each length (measured: 1 lets compound loops reach more lengths than 2).
PER_LENGTH = 1
#: The future cost's fixed-point iteration stops when the bound on its remaining error,
#: ``alpha / (1 - alpha) * max |change|``, is below this fraction of the largest finite cost.
TOLERANCE = 1e-6
#: ... or after this many sweeps (``info.converged`` then says False).
MAX_SWEEPS = 100_000
#: Costs compared at once in a step of the loop table (64 MB of float64).
_DP_BLOCK = 1 << 23
#: Pixel values per block of the Gram matrix (bounds the float64 copy of the frames).
_BLOCK = 1 << 14


@dataclasses.dataclass(frozen=True)
class VideoTextureInfo:
    """What :func:`video_texture` computed and chose.

    Attributes
    ----------
    sequence : numpy.ndarray
        ``(n_frames,)`` int, the input frame shown at each output frame (before
        cross-fading).
    jumps : numpy.ndarray
        ``(J,)`` int, the output frames ``t`` after which the play jumps
        (``sequence[t + 1] != sequence[t] + 1``). A loop's wrap from its last
        frame to its first is a jump too (``t = n_frames - 1``).
    jump_costs : numpy.ndarray
        ``(J,)`` float, the transition cost ``C_ij = D'_{i+1, j}`` of each jump
        ``i -> j`` (the filtered distance between ``j`` and the frame that would
        have followed ``i``).
    distances : numpy.ndarray
        ``(T, T)`` the frame distances ``D`` (Section 3.1).
    filtered_distances : numpy.ndarray
        ``(T, T)`` the filtered distances ``D'`` (Section 3.2).
    future_costs : numpy.ndarray
        ``(T, T)`` the anticipated future costs ``D''`` of the transitions
        ``i -> j`` (Section 3.3); ``inf`` where a transition does not exist
        (from the last frame) or leads only into a dead end.
    probabilities : numpy.ndarray
        ``(T, T)`` the pruned transition probabilities ``P''`` that random
        play samples (rows sum to 1; the last frame's row is 0).
    sigma : float
        The ``sigma`` used (in units of ``D'``).
    sweeps : int
        Sweeps of the future-cost iteration.
    converged : bool
        Whether it reached its tolerance within its sweeps.
    loops : tuple of (int, int) or None
        Video loops: the primitive loops (backward transitions
        ``source -> destination``, ``destination <= source``, each playing
        frames ``destination .. source``) in the order they are played; None
        for random play.
    loop_cost : float or None
        Video loops: the loop's cost, ``sum C_ij^p`` over its transitions.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Seconds per stage (``"distances"``, ``"filter"``, ``"future cost"``,
        ``"prune"``, ``"loops"`` or ``"play"``, ``"render"``).
    """

    sequence: np.ndarray
    jumps: np.ndarray
    jump_costs: np.ndarray
    distances: np.ndarray
    filtered_distances: np.ndarray
    future_costs: np.ndarray
    probabilities: np.ndarray
    sigma: float
    sweeps: int
    converged: bool
    loops: tuple | None
    loop_cost: float | None
    seconds: float
    stage_seconds: dict


# --------------------------------------------------------------------------
# Section 3.1: frame distances


def frame_distances(video):
    """``D_ij = ||I_i - I_j||_2`` over all pixels and channels, from the Gram matrix.

    ``||a - b||^2 = a.a + b.b - 2 a.b``; the frames are centred on their mean
    frame first (which leaves every distance unchanged and keeps the
    cancellation small), one block of pixels at a time in float64, so a float32
    clip is never copied whole.
    """
    T = video.shape[0]
    flat = video.reshape(T, -1)
    gram = np.zeros((T, T))
    for start in range(0, flat.shape[1], _BLOCK):
        block = flat[:, start:start + _BLOCK].astype(np.float64)
        block -= block.mean(0)
        gram += block @ block.T
    norms = np.diag(gram).copy()
    d2 = norms[:, None] + norms[None, :] - 2.0 * gram
    d2 = 0.5 * (d2 + d2.T)  # BLAS need not give an exactly symmetric product
    np.maximum(d2, 0.0, out=d2)
    D = np.sqrt(d2)
    np.fill_diagonal(D, 0.0)
    return D


# --------------------------------------------------------------------------
# Section 3.2: preserving dynamics


def binomial_taps(n_taps):
    """Offsets ``k = -m .. m-1`` and binomial weights ``w_k`` of an ``n_taps = 2m`` filter.

    An odd count (1: no filtering) puts the extra tap after the centre.

    >>> binomial_taps(4)
    (array([-2, -1,  0,  1]), array([0.125, 0.375, 0.375, 0.125]))
    """
    k = np.arange(n_taps) - n_taps // 2
    w = np.array([math.comb(n_taps - 1, i) for i in range(n_taps)], float)
    return k, w / w.sum()


def filtered_distances(D, n_taps):
    """``D'_ij = sum_{k=-m}^{m-1} w_k D_{i+k, j+k}``: distances filtered along the diagonals.

    Defined where every tap lies inside the clip (``m <= i, j <= T - m`` for
    ``2m`` taps); elsewhere ``inf``: a jump needs the frames around both its
    ends. The diagonal is 0 (every ``D_{i+k, i+k}`` is), so playing on from
    any frame stays possible.
    """
    T = D.shape[0]
    offsets, weights = binomial_taps(n_taps)
    lo, hi = int(-offsets[0]), T - int(offsets[-1])  # i + k in [0, T) for every k
    Dp = np.full_like(D, np.inf)
    inner = np.zeros((max(hi - lo, 0),) * 2)
    for k, w in zip(offsets, weights):
        inner += w * D[lo + k:hi + k, lo + k:hi + k]
    Dp[lo:hi, lo:hi] = inner
    np.fill_diagonal(Dp, 0.0)
    return Dp


def transition_costs(Dp):
    """``C_ij = D'_{i+1, j}``, the cost of showing ``j`` after ``i``; the last frame has no successor (inf)."""
    C = np.full_like(Dp, np.inf)
    C[:-1] = Dp[1:]
    return C


def resolve_sigma(temperature, C, exponent):
    """``(sigma, width)``: the paper's ``sigma``, ``temperature`` times the mean nonzero transition cost ("a
    small multiple of the average (nonzero) D_ij"), and the width of ``P'' ∝ exp(-D'' / width)``, the same
    multiple of the mean nonzero ``C^p`` (``D''`` is in the units of ``C^p``; for ``p = 1`` it is ``sigma``)."""
    finite = C[np.isfinite(C) & (C > 0)]
    if finite.size == 0:  # every frame alike: any width
        return 1.0, 1.0
    return temperature * float(finite.mean()), temperature * float(np.mean(finite**exponent))


def softmax_rows(cost, width):
    """Rows of ``exp(-cost / width)`` normalised to sum to 1 (``P_ij ∝ exp(-C_ij / sigma)``); all-inf rows are 0."""
    low = cost.min(1, keepdims=True)
    ok = np.isfinite(low)
    with np.errstate(invalid="ignore"):
        shifted = np.where(ok, cost - np.where(ok, low, 0.0), np.inf)  # shifted so the best is exp(0) = 1
    P = np.exp(-shifted / width)
    total = P.sum(1, keepdims=True)
    np.divide(P, total, out=P, where=total > 0)
    return P


# --------------------------------------------------------------------------
# Section 3.3: avoiding dead ends and anticipating the future


def _discounted(m, discount):
    """``alpha m``, with an infinite future staying infinite whatever ``alpha`` (also 0)."""
    out = discount * np.where(np.isinf(m), 0.0, m)
    out[np.isinf(m)] = np.inf
    return out


def future_costs(C, exponent, discount):
    """The anticipated future cost ``D''_ij = C_ij^p + alpha min_k D''_jk`` of every transition, at its fixed point.

    Iterated as ``m_j <- min_k D''_jk``, ``D''_ij <- C_ij^p + alpha m_j``, each
    sweep over the whole matrix at once (vectorised, Jacobi order: the paper
    sweeps its rows from the last to the first, which converges in fewer
    sweeps to the same point). It starts from ``m = 0`` (no future), so the
    costs only grow, and stops when ``alpha / (1 - alpha)`` times the largest
    change, which bounds the distance to the fixed point, is below
    ``TOLERANCE`` of the largest finite cost. A frame whose every transition
    is ``inf`` (the last frame) has an infinite future, and so have the
    transitions into it, whatever ``alpha``.

    Returns ``(D'', sweeps, converged)``.
    """
    T = C.shape[0]
    Cp = np.power(C, exponent)
    m = np.zeros(T)  # m_j = min_k D''_jk, the cheapest way on from frame j
    out = np.empty_like(Cp)
    scale = float(Cp[np.isfinite(Cp)].max(initial=0.0)) or 1.0
    bound = discount / (1.0 - discount)
    sweeps, converged = 0, False
    while sweeps < MAX_SWEEPS:
        sweeps += 1
        np.add(Cp, _discounted(m, discount)[None, :], out=out)
        new = out.min(1)
        finite = np.isfinite(new)
        same = np.array_equal(finite, np.isfinite(m))
        change = float(np.abs(new[finite] - m[finite]).max(initial=0.0)) if same else np.inf
        m = new
        scale = max(scale, float(m[finite].max(initial=0.0)))
        if same and bound * change <= TOLERANCE * scale:
            converged = True
            break
    np.add(Cp, _discounted(m, discount)[None, :], out=out)
    return out, sweeps, converged


# --------------------------------------------------------------------------
# Section 3.4: pruning the transitions


def prune_transitions(P, threshold):
    """Keep the local maxima of ``P`` (3 x 3 neighbourhoods) whose probability is at least ``threshold``.

    The continuation ``i -> i+1`` is exempt from the local-maximum test (the
    continuations of neighbouring rows are its neighbours), and each row keeps
    its most probable transition, so no frame that play can reach loses all
    its ways on. Rows are renormalised.
    """
    from scipy.ndimage import maximum_filter

    T = P.shape[0]
    keep = (P > 0) & (P >= maximum_filter(P, size=3, mode="constant", cval=0.0))
    rows = np.arange(T - 1)
    keep[rows, rows + 1] = P[rows, rows + 1] > 0
    keep &= P >= threshold
    live = P.max(1) > 0
    keep[np.flatnonzero(live), P[live].argmax(1)] = True
    out = np.where(keep, P, 0.0)
    total = out.sum(1, keepdims=True)
    np.divide(out, total, out=out, where=total > 0)
    return out


# --------------------------------------------------------------------------
# Section 4.1: random play


def random_play(P, n_frames, future, gen):
    """An endless sequence cut to ``n_frames``: start at a random frame with a finite future, then draw each next
    frame from its row of ``P''`` (one uniform number per output frame, inverted through the row's cumulative sum)."""
    live = np.isfinite(future) & (P.sum(1) > 0)
    starts = np.flatnonzero(live)
    cols = [np.flatnonzero(row) for row in P]
    cdfs = [np.cumsum(row[c]) for row, c in zip(P, cols)]
    u = gen.random(n_frames)
    seq = np.empty(n_frames, np.intp)
    s = int(starts[min(int(u[0] * len(starts)), len(starts) - 1)])
    seq[0] = s
    for t in range(1, n_frames):
        cdf = cdfs[s]
        k = int(np.searchsorted(cdf, u[t] * cdf[-1], side="right"))
        s = int(cols[s][min(k, len(cdf) - 1)])
        seq[t] = s
    return seq


# --------------------------------------------------------------------------
# Section 4.2: video loops


def primitive_loops(C, limit=None, per_length=None):
    """Candidate primitive loops: backward transitions ``i -> j`` (``j <= i - 2``; frames ``j .. i``, length
    ``i - j + 1 >= 3``), the cheapest ``limit``, at most ``per_length`` of each length, each a local minimum along
    its diagonal.

    A loop length that suits the clip shows as a valley along a diagonal of
    ``C`` (the same jump a frame earlier or later is about as good), with a
    local minimum wherever the noise puts one; the cap per length keeps a few
    valleys from filling the candidates, so that many lengths, the near-misses
    beside the valleys too, can be added up to the length asked for.

    Returns ``(sources, destinations, costs)``, cheapest first.
    """
    limit = MAX_PRIMITIVE_LOOPS if limit is None else limit
    per_length = PER_LENGTH if per_length is None else per_length
    T = C.shape[0]
    padded = np.pad(C, 1, constant_values=np.inf)
    before, after = padded[:-2, :-2], padded[2:, 2:]  # C[i-1, j-1], C[i+1, j+1]
    # backward (j <= i), and not a freeze or a step back (j >= i - 1): those touch the continuation i -> i+1,
    # the pruning's local-maximum test removes them from play, and they would stop the motion
    cand = np.isfinite(C) & (C <= before) & (C <= after) & np.tril(np.ones((T, T), bool), -2)
    i, j = np.nonzero(cand)
    order = np.argsort(C[i, j], kind="stable")
    i, j = i[order], j[order]
    length = i - j
    by_length = np.argsort(length, kind="stable")  # grouped by length, cheapest first within each group
    grouped = length[by_length]
    first = np.searchsorted(grouped, grouped)  # where each one's group starts
    rank = np.empty_like(length)  # how many cheaper candidates have the same length
    rank[by_length] = np.arange(len(grouped)) - first
    keep = np.flatnonzero(rank < per_length)[:limit]
    return i[keep], j[keep], C[i[keep], j[keep]]


def loop_table(sources, destinations, costs, n_frames, progress=None):
    """The dynamic programme of compound loops: ``T[l, t]``, the least cost of a compound loop of length ``l``
    that contains primitive loop ``t``.

    A compound loop is a multiset of primitive loops whose ranges ``[j, i]`` form
    one connected interval; it plays every one of its transitions once. Two
    compound loops, one containing ``t`` and one containing ``s``, join into one
    when the ranges of ``t`` and ``s`` overlap:
    ``T[l, t] = min(cost_t if len_t == l, min_{s ~ t, l'} T[l', t] + T[l - l', s])``,
    which reaches every connected multiset (cut a spanning tree at an edge
    ``t - s``). Work ``O(n_frames^2 K^2)`` for ``K`` primitive loops, over the
    lengths that have a loop only.

    Returns ``(table, split, partner)``: ``split[l, t]`` is ``l'`` (0: the
    primitive loop itself) and ``partner[l, t]`` is ``s``.
    """
    K = len(costs)
    lengths = sources - destinations + 1
    overlap = (destinations[:, None] <= sources[None, :]) & (destinations[None, :] <= sources[:, None])
    blocked = np.where(overlap, 0.0, np.inf)  # (t, s)
    table = np.full((n_frames + 1, K), np.inf)
    split = np.zeros((n_frames + 1, K), np.int64)
    partner = np.zeros((n_frames + 1, K), np.int64)
    has = np.zeros(n_frames + 1, bool)  # lengths with any loop
    for length in range(1, n_frames + 1):
        prim = np.where(lengths == length, costs, np.inf)
        ls = np.flatnonzero(has[1:length]) + 1  # l' with a loop, and l - l' too
        ls = ls[has[length - ls]]
        value, split_at, other = prim, np.zeros(K, np.int64), np.arange(K)
        step = max(1, _DP_BLOCK // (K * K))
        for c in range(0, ls.size, step):  # blocks of l' bound the memory: (l', t, s) costs at once
            part = ls[c:c + step]
            # T[l', t] + T[l - l', s], s overlapping t
            total = table[part][:, :, None] + table[length - part][:, None, :] + blocked[None]
            flat = total.transpose(1, 0, 2).reshape(K, -1)
            best = flat.argmin(1)
            cand = flat[np.arange(K), best]
            better = cand < value
            value = np.where(better, cand, value)
            split_at = np.where(better, part[best // K], split_at)
            other = np.where(better, best % K, other)
        table[length], split[length], partner[length] = value, split_at, other
        has[length] = np.isfinite(table[length]).any()
        if progress is not None:
            progress.advance({"length": length})
    return table, split, partner


def loop_members(split, partner, length, t):
    """The primitive loops (indices) of the compound loop ``T[length, t]``."""
    members, stack = [], [(length, t)]
    while stack:
        ell, col = stack.pop()
        cut = int(split[ell, col])
        if cut == 0:
            members.append(col)
        else:
            stack.append((cut, col))
            stack.append((ell - cut, int(partner[ell, col])))
    return members


def schedule_loops(sources, destinations):
    """Order the transitions of a compound loop so that it plays: each next source at or after the last
    destination.

    The paper's scheduling: play first the transition that starts last (the
    largest source); removing it leaves sets of primitive loops whose ranges
    are disjoint intervals; schedule each set the same way, from left to right.
    After the first jump (to ``j``) each set's first source is at or after
    ``j`` (it overlaps the removed loop's range), each set ends inside its own
    range, left of the next set, and the last destination lies before the first
    source, so the loop closes. Returns indices into the inputs, in play order.
    """
    order = []
    stack = [list(range(len(sources)))]
    while stack:
        group = stack.pop()
        if not group:
            continue
        first = max(group, key=lambda q: (sources[q], destinations[q]))
        order.append(first)
        rest = sorted((q for q in group if q != first), key=lambda q: (destinations[q], sources[q]))
        parts, reach = [], -1
        for q in rest:  # connected components of the remaining ranges, left to right
            if parts and destinations[q] <= reach:
                parts[-1].append(q)
                reach = max(reach, sources[q])
            else:
                parts.append([q])
                reach = sources[q]
        stack.extend(reversed(parts))  # the leftmost is scheduled next
    return order


def loop_sequence(sources, destinations):
    """Frames of a scheduled compound loop: from the last destination up to the first source, jump, and so on."""
    runs, prev = [], destinations[-1]
    for i, j in zip(sources, destinations):
        runs.append(np.arange(prev, i + 1))
        prev = j
    return np.concatenate(runs)


def video_loop(C, exponent, n_frames, progress):
    """The cheapest compound loop of exactly ``n_frames`` frames: ``(sequence, loops, cost)``."""
    src, dst, cost = primitive_loops(C)
    if cost.size == 0:
        raise ValueError("frames has no backward jump to loop on (the clip is too short for the filter); pass a "
                         "longer clip, fewer filter_taps, or loop=False")
    table, split, partner = loop_table(src, dst, np.power(cost, exponent), n_frames, progress)
    t = int(np.argmin(table[n_frames]))
    if not np.isfinite(table[n_frames, t]):
        found = np.flatnonzero(np.isfinite(table).any(1))
        below = [int(v) for v in found[found < n_frames][-3:]]
        prims = sorted(set((src - dst + 1).tolist()))
        raise ValueError(
            f"no loop of n_frames={n_frames} frames can be made from this clip's good transitions; "
            + (f"the longest below are {below}, " if below else "")
            + f"its primitive loops are {prims[:12]}{' ...' if len(prims) > 12 else ''} frames long "
            "(compound loops add them up): pass one of those lengths or a sum of them")
    members = loop_members(split, partner, n_frames, t)
    order = schedule_loops(src[members], dst[members])
    s, d = src[members][order], dst[members][order]
    return loop_sequence(s, d), tuple((int(a), int(b)) for a, b in zip(s, d)), float(table[n_frames, t])


# --------------------------------------------------------------------------
# Section 5: rendering with cross-fades


def find_jumps(sequence, cyclic):
    """Output frames ``t`` after which the play jumps (with the wrap, for a loop)."""
    nxt = np.roll(sequence, -1) if cyclic else sequence[1:]
    jumps = np.flatnonzero(nxt != sequence[: len(nxt)] + 1)
    return jumps


def crossfade_plan(sequence, jumps, width, n_input, cyclic):
    """Per output frame: the two input frames blended and the weight of the second.

    A jump ``i -> j`` after output frame ``t`` fades, over ``w`` output frames
    ``t + d`` (``d = 1 - w // 2 .. w - w // 2``), from the old branch ``i + d``
    (the clip as it would have gone on) to the new branch ``j + d - 1`` (the clip
    as it led up to ``j``), with weights ``(q + 1/2) / w``. ``w`` shrinks to the
    gap to the next and the previous jump so that fades never overlap; branch
    frames beyond the clip's ends are clamped to them.
    """
    n = len(sequence)
    old, new, a = sequence.copy(), sequence.copy(), np.zeros(n)
    width = min(width, n)
    if width == 0 or len(jumps) == 0:
        return old, new, a
    if cyclic:
        gaps = np.diff(np.concatenate([jumps, [jumps[0] + n]]))
        widths = np.minimum(width, np.minimum(gaps, np.roll(gaps, 1)))
    else:
        gaps = np.diff(jumps)
        after = np.concatenate([gaps, [width]])
        before = np.concatenate([[width], gaps])
        widths = np.minimum(width, np.minimum(after, before))
    for t, w in zip(jumps, widths):
        i = sequence[t]
        j = sequence[(t + 1) % n]
        q = np.arange(w)
        d = 1 - w // 2 + q
        pos = t + d
        if cyclic:
            pos %= n
        ok = (pos >= 0) & (pos < n)
        pos, d, q = pos[ok], d[ok], q[ok]
        old[pos] = np.clip(i + d, 0, n_input - 1)
        new[pos] = np.clip(j + d - 1, 0, n_input - 1)
        a[pos] = (q + 0.5) / w
    return old, new, a


def render(video, old, new, a, chunk=64):
    """``(1 - a) I_old + a I_new`` for every output frame, ``chunk`` frames at a time."""
    out = np.empty((len(old),) + video.shape[1:], video.dtype)
    shape = (-1,) + (1,) * (video.ndim - 1)
    for s in range(0, len(old), chunk):
        sl = slice(s, s + chunk)
        w = a[sl].astype(video.dtype).reshape(shape)
        blend = video[old[sl]] * (1 - w)
        blend += video[new[sl]] * w
        out[sl] = blend
    np.clip(out, 0.0, 1.0, out=out)
    return out


# --------------------------------------------------------------------------
# the public function


def video_texture(
    frames,
    n_frames,
    *,
    loop=False,
    filter_taps=4,
    temperature=0.1,
    exponent=2.0,
    discount=0.99,
    prune=0.01,
    crossfade=4,
    rng=None,
    return_info=False,
    progress=False,
):
    """Play a short clip endlessly, or make a seamless loop of it (Schödl et al. 2000).

    Examples
    --------
    >>> import numpy as np
    >>> from texsynth.video import video_texture
    >>> t = np.arange(60)[:, None, None]
    >>> x = np.arange(32)[None, None, :]
    >>> swing = 16 + 10 * np.sin(2 * np.pi * t / 20)  # a pendulum: period 20 frames
    >>> clip = np.exp(-((x - swing) ** 2) / 8) * np.ones((1, 8, 1))  # (60, 8, 32) grey
    >>> loop, info = video_texture(clip, 40, loop=True, rng=0, return_info=True)
    >>> loop.shape
    (40, 8, 32)
    >>> {source - destination + 1 for source, destination in info.loops} <= {20, 40}  # whole periods
    True
    >>> endless = video_texture(clip, 500, rng=0)  # random play: any length
    >>> endless.shape
    (500, 8, 32)

    The clip is analysed for the places where it can jump to another frame
    without the jump being seen: a jump from frame ``i`` to frame ``j`` is good
    when ``j`` and its neighbours in time look like the frames that would have
    followed ``i`` (Sections 3.1-3.2 of [1]_). Random play (``loop=False``)
    then walks a Markov chain over the frames, mostly playing on and now and
    then jumping, and never into a part of the clip it cannot leave well (a
    *dead end*, such as the clip's end; Sections 3.3, 4.1). ``loop=True``
    instead finds the cheapest *compound loop* of exactly ``n_frames`` frames:
    a set of backward jumps that, played in the right order, returns to its
    first frame as smoothly as any two consecutive frames follow each other
    (Section 4.2). Each jump is hidden by a short cross-fade (Section 5).

    Parameters
    ----------
    frames : array_like or str
        The input clip ``(T, H, W)`` or ``(T, H, W, C)``, or a file
        (:func:`texsynth.io.load_frames`); at least ``filter_taps + 1`` frames
        (5 by default), and a few periods of its motion for good jumps. The
        camera must be still: frames are compared pixel by pixel.
    n_frames : int
        Output frames: any number for random play; the exact loop length for
        ``loop=True``.
    loop : bool
        False (default): random play, an endless sequence cut to ``n_frames``.
        True: a seamless loop whose last frame leads into its first.
    filter_taps : int
        ``2m`` taps of the binomial filter along the diagonals of ``D``
        (Section 3.2); the paper's ``m = 1`` or ``2``: 2 or 4 (default 4:
        weights 1/8, 3/8, 3/8, 1/8, two frames before and two after each jump
        compared). 1 compares the single frames (no dynamics).
    temperature : float
        The paper's ``sigma`` of the transition probabilities
        ``P ∝ exp(-C / sigma)`` as a multiple of the mean nonzero transition
        cost (the paper: "a small multiple of the average (nonzero) D_ij"; the
        default 0.1 is ours, measured on the test and figure clips). Smaller:
        only the very best jumps, rarely; larger: more variety, worse jumps.
        ``P''``, whose costs ``D''`` are in the units of ``C^p``, uses the same
        multiple of the mean nonzero ``C^p``.
    exponent : float
        The paper's ``p`` in ``D'' = C^p + ...``: larger favours several good
        jumps over one poor one (default 2; the paper's value could not be
        checked). Also the power of the transition costs that a loop's cost
        sums.
    discount : float
        The paper's ``alpha`` in [0, 1), the weight of future costs (default
        0.99: close to 1, a long look-ahead; the paper's value could not be
        checked). 0: no look-ahead (the clip's last frame is still never
        entered).
    prune : float or None
        Section 3.4: keep only the local maxima of ``P''`` and drop the
        transitions less probable than ``prune`` (default 0.01), then
        renormalise; None: no pruning. Random play only.
    crossfade : int
        Output frames over which each jump is cross-faded (default 4: two
        before the jump and two after); 0: hard cuts. Morphing (the paper's
        other option) is not implemented.
    rng : None, int or numpy.random.Generator
        Random source of random play (a loop is chosen deterministically).
    return_info : bool
        Also return a :class:`VideoTextureInfo`: the frames played, the jumps
        and their costs, the matrices ``D, D', D'', P''``, the loops.
    progress : bool or callable
        Report progress per stage (and, for a loop, per length of the loop
        table).

    Returns
    -------
    video : numpy.ndarray
        ``(n_frames, H, W[, C])`` float in [0, 1] (float32 for float32 input,
        float64 otherwise), the input's channel layout.
    info : VideoTextureInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        For a clip too short for the filter, a parameter out of range, a loop
        length that the clip's good transitions cannot make (the message names
        the lengths that can be made), or ``T x T`` cost matrices or an output
        larger than the memory available.
    TypeError
        For a parameter of the wrong type.

    Notes
    -----
    **Distances (Section 3.1).** ``D_ij = ||I_i - I_j||_2`` over all pixels
    and channels, computed from the Gram matrix of the (mean-centred) frames.
    **Dynamics (Section 3.2).** ``D'_ij = sum_{k=-m}^{m-1} w_k D_{i+k, j+k}``
    with binomial ``w_k``; the cost of the jump ``i -> j`` is
    ``C_ij = D'_{i+1, j}``, so the continuation ``i -> i+1`` costs 0, and
    ``P_ij ∝ exp(-C_ij / sigma)``. A pendulum passing the same point in the
    two directions gives the same frame but different neighbours in time:
    the filter tells them apart.
    **Dead ends (Section 3.3).** The anticipated cost of a jump adds the
    discounted cost of the cheapest way on from its destination,

    .. math:: D''_{ij} = (C_{ij})^p + \\alpha \\min_k D''_{jk},

    iterated from ``D'' = C^p`` until the change bounds the remaining error
    below ``1e-6`` of the largest cost; ``P''_ij ∝ exp(-D''_ij / sigma'')``
    with ``sigma''`` the multiple of the mean nonzero ``C^p`` that ``sigma``
    is of the mean nonzero ``C`` (we could not check the width the paper gives
    ``P''``; ``sigma^p`` instead made every jump but the forced ones
    vanishingly rare: 3 jumps in 600 frames of the flame clip of the docs). This is the
    paper's "min" form. Its expectation form,
    ``D''_ij = C_ij^p + alpha sum_k P''_jk D''_jk`` with ``P''`` computed from
    ``D''`` itself, was tried and not kept: at the default ``temperature`` its
    fixed-point iteration oscillated (no convergence in 20 000 sweeps, with or
    without damping, on the test clips), while the min form converges in
    about ``log(tolerance) / log(alpha)`` sweeps.
    The last frame has no successor: its future, and the cost of every jump
    into it, is infinite, so no play enters it; frames that lead only to bad
    jumps (a scene that ends, a light that goes out) get large futures and
    play leaves before them.
    **Pruning (Section 3.4).** Local maxima of ``P''`` in 3 x 3
    neighbourhoods (a jump next to a better one is the same jump a frame off),
    at least ``prune``; each row keeps its best transition.
    **Loops (Section 4.2).** A *primitive loop* is one backward jump
    ``i -> j`` (``j <= i``); it plays frames ``j .. i`` (length ``i - j + 1``)
    and costs ``C_ij^p``. The candidates are the cheapest local minimum
    along each diagonal of ``C`` (each loop length), for the 32 cheapest
    lengths of 3 frames or more. A *compound loop* is a multiset of primitive
    loops whose ranges overlap into one interval; its length and cost are the
    sums. A dynamic
    programme over (length, primitive loop) finds the cheapest compound loop
    of length ``n_frames`` (work ``O(n_frames^2 32^2)``), and the paper's
    scheduling orders its jumps into one playable loop. A loop's cost sums
    ``C^p`` rather than ``D''``: inside a loop the future is the loop itself.
    **Cross-fades (Section 5).** Each jump fades linearly between the clip as
    it would have gone on and the clip as it led up to the destination.

    What we could not check: the paper was not at hand; the method is
    implemented from its published description as summarised in course notes.
    Its equation numbers, the value of ``sigma`` (only "a small multiple of
    the average"), its ``p`` and ``alpha`` (2 and "close to 1" are our
    defaults), which future-cost form it used in practice (we understand it
    computed the min form, row by row from the last), its pruning
    threshold, the exact neighbourhood of its local maxima, the number of
    primitive loops it fed to the loop table and the length of its
    cross-fades are ours. So is the handling of the clip's ends: a jump
    needs every tap of the filter inside the clip.

    References
    ----------
    .. [1] A. Schödl, R. Szeliski, D. H. Salesin, I. Essa, "Video textures",
       Proc. SIGGRAPH 2000, pp. 489-498, doi:10.1145/344779.345012.
    """
    start = time.perf_counter()
    video = as_image(frames, "frames", spatial_dims=3)
    if video.shape[0] < 2:
        raise ValueError(f"frames must hold at least 2 frames (T, H, W[, C]), got {video.shape[0]}")
    T = video.shape[0]
    n_out = check_positive_int(n_frames, "n_frames")
    loop = check_bool(loop, "loop")
    taps = check_positive_int(filter_taps, "filter_taps")
    if taps >= T:
        raise ValueError(f"filter_taps={taps} needs a clip of at least {taps + 1} frames, but frames holds {T}; "
                         f"pass a longer clip or filter_taps <= {T - 1}")
    temperature = check_positive_float(temperature, "temperature", maximum=1e6)
    p = check_positive_float(exponent, "exponent", maximum=16.0)
    alpha = check_in_range(discount, "discount", 0.0, 1.0, high_open=True)
    if prune is not None:
        prune = check_in_range(prune, "prune", 0.0, 1.0, high_open=True)
    fade = check_positive_int(crossfade, "crossfade", minimum=0)
    gen = as_rng(rng)
    return_info = check_bool(return_info, "return_info")
    vid, _ = with_channels(video, spatial_dims=3)
    # T x T float64 matrices held at once (D, D', weights, C, C^p, D'', P'' and temporaries), then the output
    check_memory(8.0 * T * T * 10, video.shape, name="frames", what=f"the {T} x {T} frame-distance matrices")
    frame_bytes = float(np.prod(video.shape[1:])) * video.dtype.itemsize
    table = 8.0 * 3 * (n_out + 1) * MAX_PRIMITIVE_LOOPS + 3 * 8.0 * _DP_BLOCK if loop else 0.0
    check_memory(frame_bytes * (n_out + 3 * 64) + 8.0 * T * T * 6 + table, n_out, name="n_frames",
                 what="the output" + (" and the loop table" if loop else ""))

    stages = {}
    with Progress(progress, 6 + (n_out if loop else 0), "video_texture") as bar:

        def stage(name, t0):
            stages[name] = time.perf_counter() - t0
            bar.advance({"stage": name})
            return time.perf_counter()

        t0 = time.perf_counter()
        D = frame_distances(vid)  # Section 3.1
        t0 = stage("distances", t0)
        Dp = filtered_distances(D, taps)  # Section 3.2
        C = transition_costs(Dp)
        sigma, width = resolve_sigma(temperature, C, p)
        t0 = stage("filter", t0)
        Dpp, sweeps, converged = future_costs(C, p, alpha)  # Section 3.3
        if not np.isfinite(Dpp).any():
            raise ValueError(f"frames: no frame of the {T} can jump anywhere, so every play runs into the clip's end "
                             f"(a clip of {T} frames is too short for filter_taps={taps}); pass a longer clip or "
                             "fewer filter_taps")
        t0 = stage("future cost", t0)
        P = softmax_rows(Dpp, width)
        if prune is not None:
            P = prune_transitions(P, prune)  # Section 3.4
        t0 = stage("prune", t0)
        if loop:  # Section 4.2
            sequence, loops, loop_cost = video_loop(C, p, n_out, bar)
            t0 = stage("loops", t0)
        else:  # Section 4.1
            sequence, loops, loop_cost = random_play(P, n_out, Dpp.min(1), gen), None, None
            t0 = stage("play", t0)
        jumps = find_jumps(sequence, loop)
        old, new, a = crossfade_plan(sequence, jumps, fade, T, loop)  # Section 5
        out = render(video, old, new, a)
        stage("render", t0)

    if not return_info:
        return out
    nxt = sequence[(jumps + 1) % n_out]
    info = VideoTextureInfo(
        sequence=sequence, jumps=jumps, jump_costs=C[sequence[jumps], nxt], distances=D, filtered_distances=Dp,
        future_costs=Dpp, probabilities=P, sigma=float(sigma), sweeps=sweeps, converged=converged, loops=loops,
        loop_cost=loop_cost, seconds=time.perf_counter() - start, stage_seconds=stages)
    return out, info
