"""Tests of Ruiters et al. 2010 patch-based texture interpolation (texsynth.interpolate_textures)."""

from dataclasses import replace

import numpy as np
import pytest
from scipy import ndimage

from texsynth.optimization._ruiters import _relax

from texsynth.optimization import edge_feature_map, interpolate_neighborhoods, ridge_feature_map, interpolate_textures, linear_blend, transition_alpha_map
from texsynth.optimization import (Correspondences, InterpolationSchedule, InterpolationUpdate, NeighborhoodSet,
                                   VaryingAlpha)
from texsynth.core.search import Search
from texsynth.metrics import mosaic_baseline, noise_baseline, texture_energy
from texsynth.core.search import PatchIndex
from texsynth.core.neighborhood import accumulate, all_patches, extract, grid_centers
from texsynth.optimization import Schedule, optimize_texture

from conftest import load_texture

SCHEDULE = InterpolationSchedule(stages=((2, 9), (1, 9)), max_iterations=3)
SMALL = dict(schedule=SCHEDULE, neighborhood_set=NeighborhoodSet(max_neighborhoods=96), rng=0)
NO_STATISTICS = InterpolationUpdate(statistics_step=False)


@pytest.fixture(scope="module")
def pair():
    """Brick <-> slate wall (the README's interpolation pair), 48 px crops."""
    a = load_texture("rohitrango/t1.png", 48)
    b = load_texture("rohitrango/t7.png", 48)
    return a, b


def grad_mag(img):
    g = img.mean(-1) if img.ndim == 3 else img
    return np.hypot(ndimage.sobel(g, 0), ndimage.sobel(g, 1))


# --------------------------------------------------------------------------- neighbourhoods
@pytest.mark.parametrize("alpha,source", [(0.0, 0), (1.0, 1)])
def test_endpoint_neighbourhoods_are_input_patches(pair, alpha, source):
    # at alpha = 0 the warp of N1 is the identity and its weight 1: N' holds exact patches of I1
    a, b = pair
    n = interpolate_neighborhoods(a, b, alpha, 9, neighborhood_set=NeighborhoodSet(max_neighborhoods=128), rng=0)
    ref = (a, b)[source]
    vecs = all_patches(ref, 9).reshape(-1, 9 * 9 * 3)
    _, d2 = PatchIndex(vecs, method="exact").query(n[..., :3].reshape(len(n), -1).astype(np.float64), k=1)
    assert float(np.sqrt(d2.max() / vecs.shape[1])) < 1e-3  # float32 storage only
    other = (b, a)[source]
    vecs_o = all_patches(other, 9).reshape(-1, 9 * 9 * 3)
    _, d2o = PatchIndex(vecs_o, method="exact").query(n[..., :3].reshape(len(n), -1).astype(np.float64), k=1)
    assert float(np.sqrt(d2o.mean() / vecs.shape[1])) > 0.03  # and they are not the other texture's


def test_endpoint_set_covers_every_neighbourhood(pair):
    # the TPS problems are capped to a stride of corners, but each kept pair is reused
    # shifted by up to the stride: at alpha = 0 (where every pair is kept) N' holds almost
    # every neighbourhood of I1. Measured 0.90 (the last stride-1 rows and columns of
    # corners are not reached); without the shifted copies it is 1/stride^2 = 0.04.
    a, b = pair
    n = interpolate_neighborhoods(a, b, 0.0, 9, neighborhood_set=NeighborhoodSet(max_neighborhoods=96), rng=0)
    vecs = all_patches(a, 9).reshape(-1, 9 * 9 * 3)
    _, d2 = PatchIndex(n[..., :3].reshape(len(n), -1).astype(np.float64), method="exact").query(vecs, k=1)
    assert np.mean(np.sqrt(d2[:, 0] / vecs.shape[1]) < 1e-3) > 0.85


def test_keep_fraction_halves_the_set(pair):
    a, b = pair
    full = interpolate_neighborhoods(a, b, 0.5, 9, neighborhood_set=NeighborhoodSet(keep_fraction=1.0,
                                                                                     max_neighborhoods=128), rng=0)
    half = interpolate_neighborhoods(a, b, 0.5, 9, neighborhood_set=NeighborhoodSet(keep_fraction=0.5,
                                                                                     max_neighborhoods=128), rng=0)
    # half the pairs, each with the same shifted copies (fewer near the borders)
    assert 0.4 < len(half) / len(full) < 0.6


# --------------------------------------------------------------------------- synthesis
@pytest.fixture(scope="module")
def results(pair):
    a, b = pair
    return {al: interpolate_textures(a, b, al, **SMALL) for al in (0.0, 0.5, 1.0)}


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("alpha", [0.0, 1.0])
def test_endpoints_match_texture_optimization(pair, results, alpha, seed):
    a, b = pair
    ref, other = (a, b) if alpha == 0 else (b, a)
    ours = results[alpha] if seed == 0 else interpolate_textures(a, b, alpha, **{**SMALL, "rng": seed})
    # our output is periodic (wrap), so the reference is periodic texture optimization
    # with the same two scales (16 then 8 px at half, then full resolution)
    kwatra = optimize_texture(ref, 48, schedule=Schedule(neighborhood_sizes=(16, 8), levels=2), tileable=True,
                              rng=seed)
    energy = lambda x: texture_energy(x, ref, patch_size=8)  # noqa: E731
    e_ours, e_kwatra = energy(ours), energy(kwatra)
    e_mosaic = energy(mosaic_baseline(ref, 48, rng=seed))
    e_noise = energy(noise_baseline(ref, 48, rng=seed))
    # Measured 2026-11-23 (seeds 0, 1, 2): ours / Kwatra 1.09, 1.38, 1.29 at alpha = 0 and 1.11,
    # 1.39, 1.27 at alpha = 1. On the scale that matters, from Kwatra's energy to a random-block
    # mosaic's (mosaic 0.0022-0.017, noise 0.0066-0.055), ours is 0.05-0.19 of the way. Before
    # the last stage dropped the Portilla-Simoncelli step at the ends (see _statistics_weight)
    # the ratios were 1.14-1.93 and 3 of these 6 cases failed (seeds 1 and 2: 1.73-1.93x);
    # before the earlier fixes (noise initialisation, unscaled distance channel, a set of
    # 1/stride^2 of the patches) the ends were 2.0-2.8x Kwatra.
    assert e_ours < 1.6 * e_kwatra
    assert e_ours - e_kwatra < 0.3 * (e_mosaic - e_kwatra)
    assert e_ours < 0.25 * e_noise
    assert e_ours < 0.3 * texture_energy(ours, other, patch_size=8)  # and it is not the other texture


def test_halfway_is_between_and_not_blurred(pair, results):
    a, b = pair
    ours = results[0.5]
    e_a, e_b = texture_energy(ours, a, patch_size=8), texture_energy(ours, b, patch_size=8)
    e0, e1 = texture_energy(results[0.0], a, patch_size=8), texture_energy(results[1.0], b, patch_size=8)
    # neither input: measured (2026-11-23, seeds 0-2) 0.0135-0.0141 against I1 and
    # 0.020-0.021 against I2, the endpoints 0.0009 and 0.0054; a copy of either input would be
    # at its endpoint's level
    assert e_a > 3 * e0 and e_b > 1.5 * e1
    # ... but built from both: nearer to each input than the other input is (the slate against
    # the brick 0.046, the brick against the slate 0.031): measured 0.29-0.30 and 0.64-0.68 of
    # those. (The linear blend, which contains both at half contrast, has 0.0075 and 0.016;
    # before the stiffer affine part of the warps ours had 0.0104-0.0116 and 0.019-0.021.)
    assert e_a < 0.5 * texture_energy(b, a, patch_size=8)
    assert e_b < 0.8 * texture_energy(a, b, patch_size=8)
    blend = linear_blend(a, b, 0.5)
    # not blurred: the 90th percentile of the gradient magnitude is 0.85 (brick 0.67, slate
    # 2.0, blend 1.10 with its doubled lines); the blend blurred by a Gaussian of 1 px, the
    # look of the old noise-initialised synthesis, drops to 0.53
    blurred = ndimage.gaussian_filter(blend, (1.0, 1.0, 0.0))
    assert np.percentile(grad_mag(ours), 90) > 1.3 * np.percentile(grad_mag(blurred), 90)


def test_alpha_map_transition(pair):
    a, b = pair
    amap = transition_alpha_map((24, 72))
    out = interpolate_textures(a, b, amap, varying=VaryingAlpha(alpha_steps=3),
                               update=InterpolationUpdate(statistics_step=True), **SMALL)
    assert out.shape == (24, 72, 3)
    # share of I2 in each third: E(band, I1) / (E(band, I1) + E(band, I2)), 0 for a copy of I1 and
    # 1 for a copy of I2. Measured (seeds 0, 1, 2): 0.05-0.06 / 0.39-0.44 / 0.83-0.90. A strip that
    # ignored the map (one texture throughout) has the same share in every third; the middle
    # must be a mixture, at most three times closer to either input than to the other.
    share = []
    for band in (out[:, :24], out[:, 24:48], out[:, 48:]):
        e1, e2 = texture_energy(band, a, patch_size=8), texture_energy(band, b, patch_size=8)
        share.append(e1 / (e1 + e2))
    assert share[0] < 0.15 and share[2] > 0.6
    assert 0.25 < share[1] < 0.75


def test_statistics_bands_work_on_their_own_part_of_the_map():
    # Section 4.5: the statistical step of each alpha runs "only on the relevant parts of the
    # image according to the distribution map". On brick | slate with the map 0 | 1 each half
    # already has its band's statistics and keeps its mean and deviation (measured errors
    # 0.0000 / 0.0006 and deviations 0.081 / 0.233 against 0.081 / 0.235). The same bands run on
    # the whole image, as before 2026-11-23, measured the mixture and shifted the means by
    # 0.016 / 0.027 and the slate's deviation to 0.273.
    from texsynth.optimization._ruiters import _Statistics

    a, b = load_texture("rohitrango/t1.png", 64), load_texture("rohitrango/t7.png", 64)
    image = np.concatenate([a, b], 1)
    amap = np.zeros(image.shape[:2])
    amap[:, 64:] = 1.0
    out = _Statistics(a, b, [0.0, 1.0], image.shape[:2]).step(image, amap)
    for half, ref in ((out[:, :64], a), (out[:, 64:], b)):
        assert np.abs(half.mean((0, 1)) - ref.mean((0, 1))).max() < 0.005
        assert abs(half.std() - ref.std()) < 0.1 * ref.std()


def test_same_seed_same_output_and_grey(pair):
    a, b = pair
    kw = dict(SMALL, schedule=replace(SCHEDULE, max_iterations=1))
    x = interpolate_textures(a[..., 0], b[..., 0], 0.5, update=NO_STATISTICS, **kw)
    seen = []
    y = interpolate_textures(a[..., 0], b[..., 0], 0.5, update=NO_STATISTICS,
                             progress=lambda step, total, info: seen.append((step, total, info["stage"])), **kw)
    assert x.shape == (48, 48) and np.array_equal(x, y)
    # one report per (stage, iteration), counting up to the announced total
    stages = SCHEDULE.stages
    assert [s[:2] for s in seen] == [(i + 1, len(stages)) for i in range(len(stages))]
    assert [s[2] for s in seen] == [tuple(st) for st in stages]


# --------------------------------------------------------------------------- bad input
def test_bad_input(pair):
    a, b = pair
    with pytest.raises(ValueError, match=r"features\[0\]"):
        interpolate_textures(a, b, 0.5, features=(np.zeros((10, 10), bool), np.zeros((48, 48), bool)), **SMALL)
    with pytest.raises(ValueError, match="alpha"):
        interpolate_textures(a, b, 1.5, **SMALL)
    with pytest.raises(ValueError, match="alpha map"):
        interpolate_textures(a, b, np.full((32, 32), 2.0), **SMALL)
    with pytest.raises(ValueError, match="size"):
        interpolate_textures(a, b, np.zeros((32, 32)), size=(40, 40), **SMALL)
    with pytest.raises(ValueError, match="2-D"):
        interpolate_textures(a, b, np.zeros((4, 32, 32)), **SMALL)
    with pytest.raises(ValueError, match="channels"):
        interpolate_textures(a, b[..., 0], 0.5, **SMALL)
    with pytest.raises(ValueError, match="neighbourhood"):
        interpolate_textures(a[:8, :8], b[:8, :8], 0.5, **SMALL)


def test_empty_feature_map_falls_back_to_colour_only(pair, monkeypatch):
    a, b = pair
    empty = np.zeros((48, 48), bool)

    def no_rpm(*args, **kwargs):
        raise AssertionError("TPS-RPM ran although both feature maps are empty")

    # identity warps: no point matching
    monkeypatch.setattr("texsynth.optimization._ruiters_neighborhoods.tps_rpm", no_rpm)
    with pytest.warns(RuntimeWarning, match="colour-only"):
        out, info = interpolate_textures(a, b, 0.5, features=(empty, empty), update=NO_STATISTICS,
                                         return_info=True, **SMALL)
    assert info.colour_only
    assert out.shape == a.shape


def test_edge_feature_map_marks_edges(pair):
    f = edge_feature_map(pair[0])
    assert f.dtype == bool and 0.02 < f.mean() < 0.5


def test_ridge_feature_map_follows_light_mortar():
    # jcjohnson brick: light mortar lines between red bricks. The ridge map's lines lie on
    # the mortar (within 1 px of a pixel brighter than 0.6): measured 81 %; Canny marks the
    # two borders of each joint and misses them by a pixel or more: 14 %.
    img = load_texture("jcjohnson/brick.png")
    grey = img.mean(-1)
    mortar = ndimage.binary_dilation(grey > 0.6, iterations=1)
    ridge, canny = ridge_feature_map(img), edge_feature_map(img)
    assert ridge.dtype == bool and 0.03 < ridge.mean() < 0.3
    assert mortar[ridge].mean() > 0.7 > 0.3 > mortar[canny].mean()


# --------------------------------------------------------------------------- speed-ups are exact
def _relax_reference(centres, z, weights, shape, radius, spring, max_sweeps):
    """The relaxation written plainly: every centre, every shift, every sweep, float64."""
    n, s = len(centres), z.shape[1]
    original = centres.copy()
    offsets = [(dr, dc) for dr in range(-radius, radius + 1) for dc in range(-radius, radius + 1)]
    d = np.abs(original[:, None, :] - original[None, :, :]).astype(float)
    d = np.minimum(d, np.array(shape, float) - d)
    dist = (d**2).sum(-1)
    np.fill_diagonal(dist, np.inf)
    nbrs = np.argsort(dist, axis=1, kind="stable")[:, :8]
    for _ in range(max_sweeps):
        total, wsum = accumulate(z, centres, shape, patch_weights=weights, mode="wrap")
        num = total * wsum[..., None]
        disp = centres - original
        mean_nbr = disp[nbrs].mean(1)
        cost = np.empty((n, len(offsets)))
        for j, (dr, dc) in enumerate(offsets):
            cost_j = np.empty(n)
            for i in range(n):
                at = centres[i : i + 1] + [dr, dc]
                other_num = extract(num, at, s, mode="wrap")[0]
                other_w = extract(wsum[..., None], at, s, mode="wrap")[0]
                # remove the centre's own (unshifted) patch where it overlaps the shifted window
                rr, cc = np.meshgrid(np.arange(s) + dr, np.arange(s) + dc, indexing="ij")
                inside = (rr >= 0) & (rr < s) & (cc >= 0) & (cc < s)
                own = np.zeros_like(other_num)
                own[inside] = z[i][rr[inside], cc[inside]] * weights[i]
                other_num = other_num - own
                other_w = other_w - inside[..., None] * weights[i]
                avg = other_num / other_w
                cost_j[i] = ((z[i] - avg) ** 2).mean()
            cost[:, j] = cost_j + spring * ((disp + [dr, dc] - mean_nbr) ** 2).sum(1)
        best = np.argmin(cost, axis=1)
        stay = offsets.index((0, 0))
        moved = cost[np.arange(n), best] < cost[:, stay] - 1e-12
        if not moved.any():
            break
        centres = (centres + np.array(offsets)[best] * moved[:, None]) % np.array(shape)
    return centres


@pytest.mark.parametrize("shape", [(36, 36), (12, 36)])
def test_relaxation_equals_plain_reference(pair, shape):
    # _relax reads a (s + 2r)-window once per sweep, works in float32 and re-evaluates after
    # the first sweep only the centres near a move; the result must be the plain algorithm's.
    # Brick patches from jittered positions pasted on a grid: they disagree with each other
    # and the relaxation moves many of them, over several sweeps. The 12-row image is
    # smaller than the window (13), as at the coarse level of a small output.
    a, b = pair
    s = 9
    centres = grid_centers(shape, s, 3)
    rng = np.random.default_rng(0)
    jitter = centres + rng.integers(-2, 3, centres.shape)
    z = extract(a, jitter % 48, s, mode="wrap")
    weights = rng.uniform(0.5, 2.0, len(centres))
    ref = _relax_reference(centres, z, weights, shape, 2, 0.002, 5)
    ours = _relax(centres, z, weights, shape, 2, 0.002, 5)
    one_sweep = _relax(centres, z, weights, shape, 2, 0.002, 1)
    assert np.array_equal(ours, ref)
    # not a trivial comparison: centres moved (measured 10 % on the 12-row image, 24 % on 36 x 36)
    assert (ours != centres).any(1).mean() > 0.05
    if shape == (36, 36):  # here the test exercises the later sweeps: they move centres the first left
        assert not np.array_equal(one_sweep, ours)


def test_stops_when_energy_stops_falling(pair):
    # Kwatra et al.'s criterion: a stage ends at the first iteration whose energy is not
    # (1 - tolerance) times the previous one
    a, b = pair
    six = replace(SCHEDULE, max_iterations=6)
    kw = dict(SMALL, update=InterpolationUpdate(statistics_step=True))
    _, full = interpolate_textures(a, b, 0.5, return_info=True, **dict(kw, schedule=replace(six, tolerance=None)))
    assert np.bincount(full.stage).tolist() == [7, 7]  # the first search, then one per iteration
    _, stop = interpolate_textures(a, b, 0.5, return_info=True, **dict(kw, schedule=replace(six, tolerance=0.0)))
    for k in range(2):
        e = stop.energy[stop.stage == k]
        assert np.all(np.diff(e[:-1]) <= 0)  # fell until the last iteration
        assert len(e) == 7 or e[-1] >= e[-2]  # ... which ran all or did not fall
    # the first stage is run identically until it stops
    first = stop.energy[stop.stage == 0]
    np.testing.assert_array_equal(first, full.energy[full.stage == 0][: len(first)])
    assert len(stop.energy) < len(full.energy)
    with pytest.raises(ValueError, match="tolerance"):
        interpolate_textures(a, b, 0.5, **dict(SMALL, schedule=replace(SCHEDULE, tolerance=1.5)))
    with pytest.raises(ValueError, match="mean_shift_iterations"):
        interpolate_textures(a, b, 0.5, update=InterpolationUpdate(mean_shift_iterations=-1), **SMALL)
    with pytest.raises(TypeError, match="schedule must be a.* InterpolationSchedule"):
        interpolate_textures(a, b, 0.5, schedule=dict(max_iterations=2))


# --------------------------------------------------------------------------- Section 4.1: correspondences
def _stage(a, b, size, k=1, max_neighborhoods=1024):
    from texsynth.optimization._ruiters_neighborhoods import check_inputs, stage_textures

    p = check_inputs(a, b, None, Correspondences(n_correspondences=k),
                     NeighborhoodSet(max_neighborhoods=max_neighborhoods), Search())
    return p, *stage_textures(p, 1, size)


def _weighted_d2(t_src, t_dst, corners, size, weights):
    """Brute force: weighted squared distance of each src corner's neighbourhood to every dst neighbourhood."""
    q = all_patches(t_src.image, size)[corners[:, 0], corners[:, 1]].reshape(len(corners), -1)
    view = all_patches(t_dst.image, size)
    v = view.reshape(-1, q.shape[1])
    w = np.tile(weights, size * size)
    d2 = ((q**2) * w).sum(1)[:, None] - 2 * (q * w) @ v.T + ((v**2) * w).sum(1)[None, :]
    return d2, view.shape[:2]


@pytest.mark.parametrize("size", [9, 17])
def test_warps_do_not_squeeze_the_patches(pair, size):
    # The feature points of a patch lie along a few mortar lines, which leave TPS-RPM's affine
    # part free across them. With Chui and Rangarajan's affine_lambda_init = 0.01 a third to a
    # half of the warps squeezed one axis below half (smallest singular value of the warp's
    # linear fit; measured here 0.31 / 0.37 at s = 9, 0.50 / 0.34 at s = 17), and N' filled
    # with stretched, smeared patches. The defaults of interpolate_textures (10): 0.01 / 0.11
    # and 0.05 / 0.17.
    from texsynth.optimization._ruiters_neighborhoods import _correspondences, _warps

    a, b = pair
    p, t1, t2 = _stage(a, b, size, max_neighborhoods=96)
    rng = np.random.default_rng(0)
    c1, c2 = _correspondences(t1, t2, size, p, rng)
    fwd, bwd, grid, ok = _warps(t1, t2, c1, c2, size, 24, rng, p.rpm)
    assert ok.mean() > 0.5  # most pairs have feature points to align
    g = grid.reshape(-1, 2) - grid.reshape(-1, 2).mean(0)
    for warp in (fwd, bwd):
        w = warp[ok].reshape(ok.sum(), -1, 2)
        w = w - w.mean(1, keepdims=True)
        linear = np.einsum("bpi,pj->bij", w, g) / (g**2).sum(0)  # least-squares fit on the square grid
        squeezed = np.linalg.svd(linear, compute_uv=False)[:, 1] < 0.5
        assert squeezed.mean() < 0.25


@pytest.mark.parametrize("k", [1, 2])
def test_correspondences_are_the_k_nearest_in_both_directions(pair, k):
    # Section 4.1: for every (capped) neighbourhood of I1 its k nearest among all neighbourhoods
    # of I2 under ||W_C (N1 - N2)|| (colour + distance channel), AND the same from I2 into I1
    # ("it is important to perform these searches ... in both textures"), checked against
    # a brute-force search written here
    from texsynth.optimization._ruiters_neighborhoods import _correspondences

    a, b = pair
    s = 7
    p, t1, t2 = _stage(a[:32, :32], b[:32, :32], s, k=k, max_neighborhoods=64)
    assert len(t1.corners) == len(t2.corners) == 49  # 26 x 26 neighbourhoods, capped to a stride of 4
    c1, c2 = _correspondences(t1, t2, s, p, np.random.default_rng(0))
    pairs = {tuple(r) for r in np.concatenate([c1, c2], 1)}
    assert len(pairs) == len(c1) <= 2 * k * 49  # unique pairs; a pair found both ways counts once
    for src, dst, forward in ((t1, t2, True), (t2, t1, False)):
        d2, grid = _weighted_d2(src, dst, src.corners, s, p.channel_weights)
        for q, row in zip(src.corners, d2):
            mine = [r[2:] if forward else r[:2] for r in pairs if tuple(r[:2] if forward else r[2:]) == tuple(q)]
            found = np.sort([row[np.ravel_multi_index(m, grid)] for m in mine])
            # the query's k nearest (by distance: robust to exact ties) are among its pairs
            np.testing.assert_allclose(found[:k], np.sort(row)[:k], rtol=1e-4, atol=1e-6)
    # both directions contribute: pairs whose I2 side is one of I2's capped corners but whose I1
    # side is no capped corner of I1 exist only because of the search from I2 into I1
    on1 = {tuple(c) for c in t1.corners}
    on2 = {tuple(c) for c in t2.corners}
    assert any(r[:2] not in on1 and r[2:] in on2 for r in pairs)
    assert any(r[:2] in on1 and r[2:] not in on2 for r in pairs)


def test_correspondences_by_pca_kdtree_agree_with_exact_search(pair, monkeypatch):
    # The paper's PCA + kd-tree search (used above _CORRESPONDENCE_EXACT_MAX = 20000
    # neighbourhoods, i.e. for textures above about 150 px per stage) forced on 48 px brick <->
    # slate, 9 x 9 neighbourhoods (1600 per texture, 400 capped corners each). PatchIndex's
    # kd-tree (PCA to <= 24 dimensions, 16 candidates from an eps = 1 tree search, re-ranked
    # exactly) is deterministic here (no PCA subsample below 20000 vectors). Measured: 81 % of
    # the exact pairs found (per direction 98 % brick -> slate, 64 % slate -> brick; on pebbles
    # <-> paving 75 %, skimage brick <-> gravel 91 %); the misses are near ties: the best
    # correspondence found per neighbourhood is on average 0.0 % / 3.7 % farther than the exact
    # nearest, 20 % at the 95th percentile. The bounds leave room for BLAS/platform rounding
    # of the near ties.
    from texsynth.optimization import _ruiters_neighborhoods as interpolation
    from texsynth.optimization._ruiters_neighborhoods import _correspondences

    a, b = pair
    s = 9
    p, t1, t2 = _stage(a, b, s)
    w = p.channel_weights
    exact = _correspondences(t1, t2, s, p, np.random.default_rng(0))
    used = []

    class Spy(PatchIndex):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            used.append(self.method)

    monkeypatch.setattr(interpolation, "PatchIndex", Spy)
    approx = _correspondences(t1, t2, s, replace(p, method="kdtree"), np.random.default_rng(0))
    assert used == ["kdtree", "kdtree"]  # both directions took the kd-tree path
    e = {tuple(r) for r in np.concatenate(exact, 1)}
    k = {tuple(r) for r in np.concatenate(approx, 1)}
    assert len(e & k) / len(e) > 0.7
    for side, (src, dst) in enumerate(((t1, t2), (t2, t1))):
        d2, grid = _weighted_d2(src, dst, src.corners, s, w)
        true = d2.min(1)
        ca, cb = approx if side == 0 else approx[::-1]
        best = np.full(len(src.corners), np.inf)
        index = {tuple(c): i for i, c in enumerate(src.corners)}
        for q, m in zip(ca, cb):
            i = index.get(tuple(q))
            if i is not None:
                best[i] = min(best[i], d2[i, np.ravel_multi_index(m, grid)])
        ratio = best / np.maximum(true, 1e-12)
        assert np.all(ratio >= 1 - 1e-4)  # returned pairs are real pairs: never closer than exact
        assert ratio.mean() < 1.1 and np.percentile(ratio, 95) < 1.4


# --------------------------------------------------------------------------- Section 4.2: colour adjustment
def _identity_blend(t1, t2, c1, c2, size, alpha):
    from texsynth.optimization._ruiters_neighborhoods import _blend_pairs

    grid = np.stack(np.indices((size, size)), -1).reshape(1, -1, 2).astype(float)
    g = np.broadcast_to(grid, (len(c1),) + grid.shape[1:])
    blend, _ = _blend_pairs(t1, t2, c1, c2, g, g, g, alpha, 0.5)
    return blend.reshape(len(c1), size, size, -1)


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.5, 1.0])
def test_colour_adjustment_interpolates_means_and_deviations(pair, alpha):
    # Section 4.2: "the mean and variance of the color channels in both input textures are
    # computed, and then linearly interpolated according to alpha. The color values of the two
    # neighborhoods are then shifted and scaled accordingly." The library interpolates the
    # deviation (not the variance) linearly: see the docs page. With identity warps:
    a, b = pair
    # (1) I2 an affine recolouring of I1 (per channel gain and offset): both patches adjusted
    # to the same interpolated statistics are then one and the same patch, so the blend of the
    # whole-texture patch has exactly the interpolated mean and deviation per channel
    gain, offset = np.array([0.5, 1.2, 0.8]), np.array([0.3, -0.05, 0.1])
    b_affine = a * gain + offset
    s = 48
    _, t1, t2 = _stage(a, b_affine, s)
    zero = np.zeros((1, 2), int)
    n = _identity_blend(t1, t2, zero, zero, s, alpha)[0]
    m1, s1 = a.reshape(-1, 3).mean(0), a.reshape(-1, 3).std(0)
    np.testing.assert_allclose(n[..., :3].reshape(-1, 3).mean(0), (1 - alpha) * m1 + alpha * (gain * m1 + offset),
                               atol=1e-6)
    np.testing.assert_allclose(n[..., :3].reshape(-1, 3).std(0), (1 - alpha) * s1 + alpha * gain * s1, rtol=1e-4)
    # (2) a real pair (brick, slate), every 9 x 9 patch at the same corner of both: each patch is
    # shifted and scaled, N1 -> (N1 - m1) s / s1 + m, N2 -> (N2 - m2) s / s2 + m, then blended;
    # the distance channel is blended but not adjusted; the blend's deviation from the patch mean
    # is then restored to the interpolated deviation of the two patches (contrast-preserving
    # blend, gain between 1 and 1 / sqrt((1 - a)^2 + a^2))
    s = 9
    _, t1, t2 = _stage(a, b, s)
    corners = np.stack(np.nonzero(np.ones((40, 40), bool)), 1)[::7]
    n = _identity_blend(t1, t2, corners, corners, s, alpha)
    p1 = all_patches(t1.image, s)[corners[:, 0], corners[:, 1]]
    p2 = all_patches(t2.image, s)[corners[:, 0], corners[:, 1]]
    mean = (1 - alpha) * t1.mean + alpha * t2.mean
    dev = (1 - alpha) * t1.std + alpha * t2.std
    adj1 = (p1[..., :3] - t1.mean) / t1.std * dev + mean
    adj2 = (p2[..., :3] - t2.mean) / t2.std * dev + mean
    blend = (1 - alpha) * adj1 + alpha * adj2
    dev = lambda p: np.sqrt(((p - p.mean((1, 2), keepdims=True)) ** 2).sum((1, 2, 3)))  # noqa: E731
    gain = np.clip(((1 - alpha) * dev(adj1) + alpha * dev(adj2)) / dev(blend), 1.0, 1.0 / np.hypot(1 - alpha, alpha))
    centre = blend.mean((1, 2), keepdims=True)
    expected = np.clip(centre + gain[:, None, None, None] * (blend - centre), 0, None)
    np.testing.assert_allclose(n[..., :3], expected, atol=1e-5)
    if 0 < alpha < 1:  # the gain is used: the blend alone is flatter
        assert gain.mean() > 1.05
    np.testing.assert_allclose(n[..., 3], (1 - alpha) * p1[..., 3] + alpha * p2[..., 3], atol=1e-6)


# --------------------------------------------------------------------------- sharpness of the intermediates
def _sharpness(img):
    """Mean absolute difference of vertically plus horizontally neighbouring grey values."""
    g = img.mean(-1)
    return float(np.abs(np.diff(g, axis=0)).mean() + np.abs(np.diff(g, axis=1)).mean())


def test_halfway_is_as_sharp_as_the_linear_blend():
    # pebbles <-> paving at 96 px with the settings of examples/plot_interpolation_pairs.py, the
    # pair on which the intermediates "melted". Sharpness as above: inputs 0.168 and 0.088, linear
    # blend 0.099; before the fix the output at alpha = 0.5 was 0.063 (0.64 of the blend's). The
    # fix (cubic warps, contrast-preserving blend of each pair, mean shift started at the densest
    # value with bandwidth 0.03), calibrated over seeds 0-4 (`python benchmarks/calibrate_tests.py
    # interpolation_halfway`): 1.00-1.04 of the blend's sharpness, texture energy 1.03-1.10 (to a)
    # and 0.99-1.07 (to b) of the blend's. Each change alone stays below 0.8 of the blend's
    # sharpness, so the bound 0.9 (an 11 % margin under the worst seed) fails without the
    # combination; the energy bound 1.25 (a 14 % margin) keeps it from buying sharpness with noise
    # (a final Portilla-Simoncelli step gave 1.33 of the blend's energy).
    from skimage.transform import resize

    a = resize(load_texture("rohitrango/t4.png"), (96, 96), anti_aliasing=True)  # as in the example
    b = resize(load_texture("rohitrango/t13.png"), (96, 96), anti_aliasing=True)
    features = (ridge_feature_map(a), ridge_feature_map(b))
    out = interpolate_textures(a, b, 0.5, features=features,
                               schedule=InterpolationSchedule(stages=((2, 17), (1, 17), (1, 9)), max_iterations=4),
                               neighborhood_set=NeighborhoodSet(max_neighborhoods=400), rng=0)
    blend = linear_blend(a, b, 0.5)
    assert _sharpness(out) > 0.9 * _sharpness(blend)
    assert texture_energy(out, a) < 1.25 * texture_energy(blend, a)
    assert texture_energy(out, b) < 1.25 * texture_energy(blend, b)


def test_mean_shift_returns_the_dominant_mode_not_the_mean():
    # two groups of patches disagree on every pixel: 3 patches of 0.2 and 2 of 0.8 (equal
    # weights, same centre). The weighted mean is 0.44; the mean shift from the densest value
    # returns the larger group's 0.2, whereas started at the mean (the old update) it stayed
    # between the groups
    from texsynth.optimization._ruiters import _mean_shift_update

    z = np.concatenate([np.full((3, 5, 5, 2), 0.2), np.full((2, 5, 5, 2), 0.8)])
    centres = np.full((5, 2), 4)
    x = _mean_shift_update(z, centres, np.ones(5), (9, 9), 0.1, 3, 1)
    np.testing.assert_allclose(x[2:7, 2:7], 0.2, atol=1e-6)
    mean = _mean_shift_update(z, centres, np.ones(5), (9, 9), 0.1, 0, 1)  # 0 iterations: the weighted mean
    np.testing.assert_allclose(mean[2:7, 2:7], 0.44, atol=1e-6)


def test_linear_blend_refuses_bad_alpha():
    a, b = np.zeros((4, 4)), np.ones((4, 4))
    for bad in (float("nan"), -0.5, 2.0):
        with pytest.raises(ValueError, match="alpha"):
            linear_blend(a, b, bad)
    with pytest.raises(TypeError, match="alpha"):
        linear_blend(a, b, "0.5")
    with pytest.raises(ValueError, match="alpha map"):
        linear_blend(a, b, np.zeros((3, 3)))
    assert linear_blend(a, b, np.full((4, 4), 0.5)).tolist() == np.full((4, 4), 0.5).tolist()


# --------------------------------------------------------------------------- k-coherent correspondences
@pytest.mark.parametrize("names", [("rohitrango/t1.png", "rohitrango/t7.png"),
                                   ("embark/multiexample/1.jpg", "embark/multiexample/2.jpg")])
def test_k_coherent_correspondences_come_close_to_exact_search(names):
    """Search(candidates="k-coherent") finds the correspondences by k-coherent search: approximate, so their
    mean distance is above exact search's, but most of the way from random pairs to exact."""
    import warnings

    from texsynth.optimization._ruiters_neighborhoods import _correspondences, check_inputs, stage_textures

    a, b = load_texture(names[0], 96), load_texture(names[1], 96)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # no feature maps: colour-only correspondences
        p = check_inputs(a, b, None, Correspondences(), NeighborhoodSet(max_neighborhoods=256),
                         Search(method="exact"))
    t1, t2 = stage_textures(p, 1, 13)
    view1, view2 = all_patches(t1.image, 13), all_patches(t2.image, 13)

    def mean_distance(c1, c2):
        return float((((view1[c1[:, 0], c1[:, 1]] - view2[c2[:, 0], c2[:, 1]]) ** 2) * p.channel_weights).sum(
            (1, 2, 3)).mean())

    rng = np.random.default_rng(0)
    exact = mean_distance(*_correspondences(t1, t2, 13, p, rng))
    coherent = mean_distance(*_correspondences(t1, t2, 13, replace(p, candidates="k-coherent"), rng))
    c1 = t1.corners[rng.integers(len(t1.corners), size=500)]
    c2 = np.stack([rng.integers(view2.shape[0], size=500), rng.integers(view2.shape[1], size=500)], 1)
    random = mean_distance(c1, c2)
    # measured (seeds 0-2): k-coherent 1.12-1.15x exact on the brick/slate pair, 1.22-1.24x on the
    # ink pair; random pairs 1.88x and 4.16x. Bound: at most 1.35x, and at most a third of the way
    # from exact back to random
    assert exact <= coherent < 1.35 * exact
    assert coherent - exact < (random - exact) / 3


def test_interpolation_with_k_coherent_correspondences(pair):
    a, b = pair
    coherent = Search(candidates="k-coherent")
    out = interpolate_textures(a, b, 0.5, search=coherent, **SMALL)
    assert out.shape == a.shape and np.all((out >= 0) & (out <= 1))
    np.testing.assert_array_equal(out, interpolate_textures(a, b, 0.5, search=coherent, **SMALL))
    assert not np.array_equal(out, interpolate_textures(a, b, 0.5, **SMALL))
    # the k-coherence sets' size is the search's k ("auto": 4)
    np.testing.assert_array_equal(out, interpolate_textures(a, b, 0.5, search=replace(coherent, k=4), **SMALL))
    assert not np.array_equal(out, interpolate_textures(a, b, 0.5, search=replace(coherent, k=2), **SMALL))
    with pytest.raises(ValueError, match="candidates must be one of 'all', 'k-coherent'"):
        interpolate_textures(a, b, 0.5, search=Search(candidates="coherent"), **SMALL)
