"""Tests of video textures (Schödl et al. 2000): the paper's matrices, dead ends, loops, cross-fades, errors.

No clip is bundled: every clip is generated here. A *pendulum* is a blob swinging on a sinusoid (period 20
frames, or 23.7 so that no frame comes back exactly) over a grey background, with camera noise; a *dead end*
clip is a pendulum whose last frames turn into something unlike any earlier frame.
"""

import itertools

import numpy as np
import pytest

from texsynth.core._validate import memory_limit
from texsynth.video import VideoTextureInfo, video_texture
from texsynth.video._schodl import (binomial_taps, crossfade_plan, find_jumps, loop_sequence, loop_table,
                                    schedule_loops)


def pendulum(n=100, period=20, size=32, noise=0.02, seed=0, colour=False):
    """``(n, size, size[, 3])``: a blob swinging left and right (and a little up and down) with ``period``."""
    gen = np.random.default_rng(seed)
    t = np.arange(n)[:, None, None]
    yy, xx = np.mgrid[:size, :size]
    phase = 2 * np.pi * t / period
    cx = size / 2 + 0.3 * size * np.sin(phase)
    cy = size / 3 + 0.08 * size * np.cos(2 * phase)
    blob = np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * (size / 12) ** 2))
    clip = 0.2 + 0.6 * blob + noise * gen.standard_normal(blob.shape)
    if colour:
        clip = clip[..., None] * np.array([1.0, 0.8, 0.6])
    return np.clip(clip, 0, 1)


def dead_end(n=100, tail=10, **kw):
    """A pendulum whose last ``tail`` frames brighten while a white square sweeps in: unlike every other frame."""
    clip = pendulum(n, **kw)
    for q, f in enumerate(range(n - tail, n)):
        clip[f] = np.clip(clip[f] + 0.05 * (q + 1), 0, 1)
        clip[f, 3:12, 3 + q:12 + q] = 1.0
    return clip


def jump_distances(info, T):
    """``D_{i+1, j}`` of every jump ``i -> j`` of the play (the wrap too, for a loop): the frame shown against
    the frame that would have followed."""
    seq, jumps = info.sequence, info.jumps
    return info.distances[np.minimum(seq[jumps] + 1, T - 1), seq[(jumps + 1) % len(seq)]]


# ----------------------------------------------------------------------------- the paper's matrices
def test_distances_filter_and_transition_costs_are_the_papers():
    clip = pendulum(40, colour=True)
    T = len(clip)
    _, info = video_texture(clip, 10, rng=0, return_info=True)
    flat = clip.reshape(T, -1)
    direct = np.sqrt(((flat[:, None] - flat[None]) ** 2).sum(-1))  # Section 3.1, written out
    np.testing.assert_allclose(info.distances, direct, rtol=1e-9, atol=1e-9)
    # Section 3.2: D'_ij = sum_{k=-2}^{1} w_k D_{i+k, j+k}, binomial weights 1, 3, 3, 1 (/8), where all taps fit
    k, w = binomial_taps(4)
    assert k.tolist() == [-2, -1, 0, 1] and np.allclose(w * 8, [1, 3, 3, 1])
    D, Dp = info.distances, info.filtered_distances
    for i, j in [(2, 2), (5, 17), (30, 9), (37, 37), (2, 37)]:
        assert Dp[i, j] == pytest.approx(sum(wk * D[i + kk, j + kk] for kk, wk in zip(k, w)), abs=1e-12)
    assert np.isinf(Dp[1, 5]) and np.isinf(Dp[5, 39]) and np.isfinite(Dp[5, 38])  # where a tap would leave the clip
    assert np.all(np.diag(Dp) == 0)


def test_the_filter_tells_the_two_directions_of_a_swing_apart():
    # period 20: frames 2 and 8 show the blob at the same place, swinging in opposite directions
    clip = pendulum(60, noise=0.0)
    _, info = video_texture(clip, 10, rng=0, return_info=True)
    D, Dp = info.distances, info.filtered_distances
    assert D[2 + 20, 8] < 1e-6 * D.max()  # the same picture ...
    assert Dp[22, 8] > 0.3 * np.median(D[D > 0])  # ... but not the same motion
    assert Dp[22, 2] < 1e-6 * D.max()  # a whole period on: the same picture and motion


def test_future_costs_are_the_fixed_point_of_the_min_equation():
    clip = dead_end(seed=1)
    _, info = video_texture(clip, 10, rng=0, return_info=True)
    assert info.converged and info.sweeps > 1
    Dp = info.filtered_distances
    C = np.full_like(Dp, np.inf)
    C[:-1] = Dp[1:]  # the transition cost of i -> j is D'_{i+1, j}
    m = info.future_costs.min(1)
    rhs = C**2 + 0.99 * m[None, :]  # D''_ij = C_ij^p + alpha min_k D''_jk, p = 2
    finite = np.isfinite(rhs)
    assert np.array_equal(finite, np.isfinite(info.future_costs))
    # the stopping rule bounds the distance to the fixed point by 1e-6 of the largest cost
    scale = max(info.future_costs[finite].max(), 1.0)
    assert np.abs(info.future_costs[finite] - rhs[finite]).max() <= 2e-6 * scale
    assert np.isinf(m[-1]) and np.all(np.isinf(info.future_costs[:, -1]))  # the last frame has no way on


def test_pruned_probabilities_are_rows_of_local_maxima():
    from scipy.ndimage import maximum_filter

    clip = pendulum(80, period=23.7)
    T = len(clip)
    _, info = video_texture(clip, 10, rng=0, return_info=True, prune=0.01)
    P = info.probabilities
    live = P.sum(1) > 0
    np.testing.assert_allclose(P[live].sum(1), 1.0, atol=1e-12)
    assert not live[-1]
    _, unpruned = video_texture(clip, 10, rng=0, return_info=True, prune=None)
    Q = unpruned.probabilities
    kept = np.argwhere(P > 0)
    continuation = kept[:, 1] == kept[:, 0] + 1
    local = Q[kept[:, 0], kept[:, 1]] >= maximum_filter(Q, size=3, mode="constant")[kept[:, 0], kept[:, 1]]
    best = kept[:, 1] == Q.argmax(1)[kept[:, 0]]
    assert np.all(continuation | local | best)
    assert np.count_nonzero(Q) > 20 * np.count_nonzero(P)  # most transitions go
    assert (P > 0).sum(1)[live].min() >= 1 and (P > 0).sum() < T * 4


# ----------------------------------------------------------------------------- dead ends (Section 3.3)
def test_random_play_never_runs_into_a_dead_end():
    for seed in range(3):
        clip = dead_end(seed=seed)
        T = len(clip)
        out, info = video_texture(clip, 3000, rng=seed, return_info=True)
        assert out.shape == (3000,) + clip.shape[1:]
        assert not np.isin(np.arange(T - 10, T), info.sequence).any()  # never enters the tail it could not leave
        # every step is a transition of P''
        assert np.all(info.probabilities[info.sequence[:-1], info.sequence[1:]] > 0)
        # without looking ahead (alpha = 0) the play walks into the tail and stays there
        _, blind = video_texture(clip, 3000, rng=seed, discount=0.0, return_info=True)
        assert np.isin(blind.sequence, np.arange(T - 10, T)).mean() > 0.5
        assert not np.isin(T - 1, blind.sequence)  # even so, never the last frame: it has no successor


def test_random_play_jumps_are_good_jumps():
    # calibrated on seeds 0-4: the worst jump of 2000 frames measured 0.44-0.45 (period 20) and 0.65-0.66
    # (period 23.7) of the median consecutive-frame distance; a random jump costs 1.8-2.1 of it. Bound: 0.9,
    # a margin of 1.36 over the largest measured.
    for seed, period in [(0, 20), (3, 23.7)]:
        clip = pendulum(120, period=period, seed=seed, size=48)
        T = len(clip)
        _, info = video_texture(clip, 2000, rng=seed, return_info=True)
        D = info.distances
        consecutive = np.median(D[np.arange(T - 1), np.arange(1, T)])
        worst = jump_distances(info, T).max()
        assert len(info.jumps) > 50  # it does jump: the output is not the clip played through
        assert worst <= 0.9 * consecutive


# ----------------------------------------------------------------------------- video loops (Section 4.2)
@pytest.mark.parametrize("seed", range(5))
def test_a_loops_worst_jump_is_as_good_as_a_step_of_the_clip(seed):
    # the quality bound. Calibrated on seeds 0-4: the worst jump of loops of 40-200 frames measured
    # 0.42-0.43 (period 20: whole periods, the noise floor) and 0.48-0.91 (period 23.7, where most lengths
    # need a jump that is not a whole period) of the clip's median consecutive-frame distance. Bound: 1.2, a
    # margin of 1.32 over the largest. Baseline computed here: a random jump costs 1.8-2.1 times a
    # consecutive step; the worst loop jump measured at most 0.45 of it, bound 0.6 (margin 1.33).
    for period, lengths in [(20, (40, 100)), (23.7, (48, 100, 200))]:
        clip = pendulum(120, period=period, seed=seed, size=48)
        T = len(clip)
        gen = np.random.default_rng(seed)
        for n in lengths:
            out, info = video_texture(clip, n, loop=True, return_info=True)
            D = info.distances
            consecutive = np.median(D[np.arange(T - 1), np.arange(1, T)])
            random_jump = np.median(D[gen.integers(1, T, 2000), gen.integers(0, T, 2000)])
            worst = jump_distances(info, T).max()
            assert worst <= 1.2 * consecutive, (period, n, worst / consecutive)
            assert worst <= 0.6 * random_jump, (period, n, worst / random_jump)


def test_a_loop_has_exactly_n_frames_and_wraps_seamlessly():
    clip = pendulum(100, seed=2)
    T = len(clip)
    for n in (20, 40, 60, 100, 137):
        out, info = video_texture(clip, n, loop=True, crossfade=0, return_info=True)
        seq = info.sequence
        assert out.shape == (n,) + clip.shape[1:] and seq.shape == (n,)
        np.testing.assert_array_equal(out, clip[seq])  # no cross-fade: the frames themselves
        assert sum(s - d + 1 for s, d in info.loops) == n
        # every step plays on or takes one of the loop's jumps, the wrap included, each jump exactly once
        steps = list(zip(seq, np.roll(seq, -1)))
        jumps = sorted((int(a), int(b)) for a, b in steps if b != a + 1)
        assert jumps == sorted(info.loops)
        assert info.jumps[-1] == n - 1  # the wrap is a jump, and a good one
        consecutive = np.median(info.distances[np.arange(T - 1), np.arange(1, T)])
        assert info.distances[seq[-1] + 1, seq[0]] <= 1.2 * consecutive  # the bound of the quality test
        assert info.loop_cost == pytest.approx(sum(info.filtered_distances[a + 1, b] ** 2 for a, b in info.loops))
    # period 20: a loop of one period is one period
    _, info = video_texture(clip, 20, loop=True, return_info=True)
    assert [s - d + 1 for s, d in info.loops] == [20]


def test_a_loop_length_the_clip_cannot_make_is_refused_with_the_lengths_it_can():
    clip = pendulum(100, seed=0)
    with pytest.raises(ValueError, match=r"no loop of n_frames=7 frames .* primitive loops are \[.*20"):
        video_texture(clip, 7, loop=True)


def _brute_force(sources, destinations, costs, max_length):
    """Least cost of a connected multiset of primitive loops, per (length, member): every multiset tried."""
    K = len(costs)
    lengths = sources - destinations + 1
    best = np.full((max_length + 1, K), np.inf)
    for counts in itertools.product(*[range(max_length // L + 1) for L in lengths]):
        counts = np.array(counts)
        total = int(counts @ lengths)
        if total == 0 or total > max_length:
            continue
        members = np.flatnonzero(counts)
        # connected: the overlap graph of the members has one component
        seen, todo = {members[0]}, [members[0]]
        while todo:
            a = todo.pop()
            for b in members:
                if b not in seen and destinations[a] <= sources[b] and destinations[b] <= sources[a]:
                    seen.add(b)
                    todo.append(b)
        if len(seen) < len(members):
            continue
        cost = counts @ costs
        best[total, members] = np.minimum(best[total, members], cost)
    return best


def test_the_loop_table_finds_the_cheapest_compound_loop():
    gen = np.random.default_rng(0)
    for _ in range(6):
        K = 4
        destinations = gen.integers(0, 14, K)
        sources = destinations + gen.integers(2, 6, K)
        costs = gen.random(K)
        table, split, partner = loop_table(sources, destinations, costs, 14)
        np.testing.assert_allclose(table, _brute_force(sources, destinations, costs, 14), rtol=1e-12)


def test_scheduling_plays_every_compound_loop():
    gen = np.random.default_rng(1)
    for _ in range(200):
        k = int(gen.integers(1, 9))
        d = np.sort(gen.integers(0, 30, k))
        s = d + gen.integers(2, 12, k)
        # make the ranges overlap into one interval (a compound loop)
        for q in range(1, k):
            d[q] = min(d[q], s[:q].max())
        order = schedule_loops(s, d)
        assert sorted(order) == list(range(k))
        src, dst = s[order], d[order]
        # after each jump, the next jump's source lies ahead; the last destination lies before the first source
        assert np.all(src[1:] >= dst[:-1]) and src[0] >= dst[-1]
        seq = loop_sequence(src, dst)
        assert len(seq) == int((s - d + 1).sum())
        steps = list(zip(seq, np.roll(seq, -1)))
        assert sorted((a, b) for a, b in steps if b != a + 1) == sorted(zip(s.tolist(), d.tolist()))


# ----------------------------------------------------------------------------- cross-fades (Section 5)
def test_cross_fades_blend_the_two_branches_around_each_jump():
    clip = pendulum(100, period=23.7, seed=1, colour=True)
    T = len(clip)
    out, info = video_texture(clip, 100, loop=True, crossfade=4, return_info=True)
    seq, jumps = info.sequence, info.jumps
    faded = np.zeros(len(seq), bool)
    for t in jumps:
        i, j = seq[t], seq[(t + 1) % len(seq)]
        for q, d in enumerate(range(-1, 3)):  # d = 1 - w // 2 + q, w = 4: output frames t-1 .. t+2
            pos = (t + d) % len(seq)
            a = (q + 0.5) / 4
            expected = (1 - a) * clip[min(i + d, T - 1)] + a * clip[max(j + d - 1, 0)]
            np.testing.assert_allclose(out[pos], expected, atol=1e-12)
            faded[pos] = True
    np.testing.assert_array_equal(out[~faded], clip[seq[~faded]])  # away from the jumps: the clip's frames


def test_cross_fades_shrink_so_that_they_never_overlap():
    seq = np.array([0, 1, 2, 10, 11, 3, 4, 5, 6, 7])  # jumps after frames 2 and 4, two frames apart
    jumps = find_jumps(seq, cyclic=False)
    assert jumps.tolist() == [2, 4]
    old, new, a = crossfade_plan(seq, jumps, 6, 20, cyclic=False)
    assert np.count_nonzero(a) == 4  # each fade shrank to the 2 frames between the jumps
    assert np.all((a >= 0) & (a < 1))


# ----------------------------------------------------------------------------- the contract
def test_same_rng_same_output_and_layouts():
    clip = pendulum(60, period=23.7, colour=True)
    a = video_texture(clip, 300, rng=5)
    b = video_texture(clip, 300, rng=np.random.default_rng(5))
    assert a.tobytes() == b.tobytes()
    _, i1 = video_texture(clip, 300, rng=5, return_info=True)
    _, i2 = video_texture(clip, 300, rng=6, return_info=True)
    assert not np.array_equal(i1.sequence, i2.sequence)
    # grey in, grey out; float32 stays float32; uint8 becomes float64 in [0, 1]
    grey = pendulum(40)
    assert video_texture(grey, 7, rng=0).shape == (7, 32, 32)
    assert video_texture(grey.astype(np.float32), 7, rng=0).dtype == np.float32
    u8 = video_texture((grey * 255).astype(np.uint8)[..., None], 7, rng=0)
    assert u8.dtype == np.float64 and u8.shape == (7, 32, 32, 1) and 0 <= u8.min() and u8.max() <= 1


def test_info_and_progress():
    clip = pendulum(60)
    seen = []
    out, info = video_texture(clip, 40, loop=True, return_info=True,
                              progress=lambda step, total, i: seen.append((step, total)))
    assert isinstance(info, VideoTextureInfo)
    assert seen[-1][0] == seen[-1][1] == 6 + 40
    assert set(info.stage_seconds) == {"distances", "filter", "future cost", "prune", "loops", "render"}
    assert info.seconds >= sum(info.stage_seconds.values()) * 0.99
    assert info.jump_costs.shape == info.jumps.shape and info.sigma > 0


@pytest.mark.parametrize("kwargs, exc, name", [
    (dict(n_frames=0), ValueError, "n_frames"),
    (dict(n_frames=2.5), TypeError, "n_frames"),
    (dict(loop="yes"), TypeError, "loop"),
    (dict(filter_taps=0), ValueError, "filter_taps"),
    (dict(filter_taps=500), ValueError, "filter_taps"),
    (dict(temperature=-1.0), ValueError, "temperature"),
    (dict(temperature="big"), TypeError, "temperature"),
    (dict(exponent=0), ValueError, "exponent"),
    (dict(discount=1.0), ValueError, "discount"),
    (dict(discount=-0.1), ValueError, "discount"),
    (dict(prune=1.5), ValueError, "prune"),
    (dict(crossfade=-1), ValueError, "crossfade"),
    (dict(crossfade=1.5), TypeError, "crossfade"),
    (dict(rng="seed"), TypeError, "rng"),
    (dict(progress="yes"), TypeError, "progress"),
    (dict(frames=np.zeros((1, 8, 8))), ValueError, "frames"),
    (dict(frames=np.zeros(5)), ValueError, "frames"),
    (dict(frames=np.full((4, 8, 8), np.nan)), ValueError, "frames"),
    (dict(frames=np.zeros((3, 8, 8))), ValueError, "frames"),  # too short for the 4-tap filter
    (dict(frames=np.random.default_rng(0).random((4, 8, 8))), ValueError, "frames"),  # no jump anywhere
])
def test_bad_input_names_the_parameter(kwargs, exc, name):
    args = dict(frames=pendulum(30), n_frames=10)
    args.update(kwargs)
    with pytest.raises(exc, match=name):
        video_texture(**args)


def test_what_cannot_fit_is_refused_before_anything_is_allocated():
    clip = pendulum(30)
    with pytest.raises(ValueError, match=r"n_frames=1000000000000 needs about .* pass a smaller n_frames"):
        video_texture(clip, 10**12)
    with memory_limit(2e5, "a test's limit"), pytest.raises(
            ValueError, match=r"frames=\(60, 32, 32\) needs about .* the 60 x 60 frame-distance matrices"):
        video_texture(pendulum(60), 10)
