"""Tests of Efros-Leung synthesis (texsynth.pixel.efros_leung) and the masked search it stands on."""

import itertools

import numpy as np
import pytest
from scipy import ndimage

from conftest import load_texture
from texsynth.core.search import MaskedIndex, Search, masked_sq_distances
from texsynth.metrics import texture_report, verbatim_copy
from texsynth.pixel import Sampling, efros_leung
from texsynth.testing import relative_scores


@pytest.fixture(scope="module")
def bread():
    return load_texture("jcjohnson/bread.png", 24)


# --------------------------------------------------------------------------- #
# the masked distance of the search layer
# --------------------------------------------------------------------------- #
def brute_force(queries, mask, vectors, weights):
    """sum_d mask w (q - v)^2 by two loops and a sum."""
    out = np.zeros((len(queries), len(vectors)))
    for i, (q, m) in enumerate(zip(queries, mask)):
        for j, v in enumerate(vectors):
            out[i, j] = sum(w * (a - b) ** 2 for a, b, k, w in zip(q, v, m, weights) if k)
    return out


@pytest.mark.parametrize("blocks", [None, [np.arange(0, 4), np.arange(4, 9)]])
def test_masked_distances_equal_a_brute_force_loop(blocks):
    rng = np.random.default_rng(0)
    vectors, queries, weights = rng.random((13, 9)), rng.random((7, 9)), rng.random(9)
    mask = rng.random((7, 9)) > 0.5
    mask[0], mask[1] = False, True  # nothing known (all distances 0), everything known
    mask[2, :4] = mask[3, 4:] = True  # whole blocks known: the block path
    want = brute_force(queries, mask, vectors, weights)
    index = MaskedIndex(vectors, weights=weights, blocks=blocks)
    np.testing.assert_allclose(index.sq_distances(queries, mask), want, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(masked_sq_distances(queries, mask, vectors, weights), want, rtol=1e-12, atol=1e-14)
    # PCA keeping every component is a rotation of each block: the same distances
    full = MaskedIndex(vectors, weights=weights, method="pca", blocks=[np.arange(0, 4), np.arange(4, 9)],
                       n_components=9)
    np.testing.assert_allclose(full.sq_distances(queries, mask), want, rtol=1e-10, atol=1e-12)


def test_near_best_is_the_paper_rule_on_a_brute_force_loop():
    rng = np.random.default_rng(1)
    vectors, queries = rng.random((40, 6)), rng.random((25, 6))
    mask = rng.random((25, 6)) > 0.3
    vectors[7] = vectors[3]  # an exact tie: a tolerance of 0 must keep both
    queries[0], mask[0] = vectors[3], True
    d = brute_force(queries, mask, vectors, np.ones(6))
    for tolerance in (0.0, 0.1, 0.5):
        u = rng.random(25)
        idx, d2, best, count = MaskedIndex(vectors).near_best(queries, mask, tolerance, u)
        for i in range(25):
            inside = np.flatnonzero(d[i] <= (1 + tolerance) * d[i].min() + 1e-12)
            assert count[i] == inside.size and idx[i] == inside[int(u[i] * inside.size)]
            assert d2[i] == pytest.approx(d[i, idx[i]], abs=1e-12) and best[i] == pytest.approx(d[i].min(), abs=1e-12)
    _, _, _, count = MaskedIndex(vectors).near_best(queries[:1], mask[:1], 0.0, [0.5])
    assert count[0] == 2


def test_pca_blocks_approximate_the_exact_distances():
    """Truncated to the default 99 % of the variance: close to the exact distances on real patches."""
    ex = load_texture("jcjohnson/bread.png", 40)
    w = 7
    v = np.lib.stride_tricks.sliding_window_view(ex, (w, w), axis=(0, 1)).transpose(0, 1, 3, 4, 2).reshape(-1, w * w * 3)
    dims = np.arange(w * w * 3).reshape(w, w, 3)
    bottom = dims[w // 2 + 1:].ravel()
    mask = np.zeros((50, v.shape[1]), bool)
    mask[:, bottom] = True
    mask[:, dims[w // 2, : w // 2].ravel()] = True  # and the left half of the centre row
    q = v[::23][:50] + np.random.default_rng(0).normal(0, 0.02, (50, v.shape[1]))
    exact = MaskedIndex(v).sq_distances(q, mask)
    pca = MaskedIndex(v, method="pca", blocks=[bottom])
    assert pca.n_components[0] < bottom.size  # 33 of 63 on these 7x7 bread windows
    approx = pca.sq_distances(q, mask)
    assert np.median(np.abs(approx - exact) / exact) < 0.05  # the residual outside 99 % of the variance


# --------------------------------------------------------------------------- #
# the algorithm: constructed cases
# --------------------------------------------------------------------------- #
def pseudo_code(exemplar, size, w, epsilon, max_error, seed):
    """Efros's pseudo-code, literally: one pixel at a time, distances by direct differences.

    Draws from the generator as efros_leung does: the seed's exemplar position,
    then per pass the permutation of the pass's pixels (row-major) and one
    uniform number per pixel in pass order.
    """
    rng = np.random.default_rng(seed)
    ex = exemplar[..., None] if exemplar.ndim == 2 else exemplar
    h, wd, c = ex.shape
    t = w // 2
    g = np.exp(-((np.arange(w) - t)[:, None] ** 2 + (np.arange(w) - t)[None, :] ** 2) / (2 * (w / 6.4) ** 2))
    windows = np.lib.stride_tricks.sliding_window_view(ex, (w, w), axis=(0, 1)).transpose(0, 1, 3, 4, 2)
    windows = windows.reshape(-1, w, w, c)
    centres = np.argwhere(np.ones((h - w + 1, wd - w + 1), bool)) + t
    out = np.zeros((size + 2 * t, size + 2 * t, c))
    known = np.zeros((size + 2 * t, size + 2 * t), bool)
    top = np.argwhere(np.ones((h - 2, wd - 2), bool))[rng.integers((h - 2) * (wd - 2))]
    r0 = size // 2 + t - 1
    out[r0:r0 + 3, r0:r0 + 3], known[r0:r0 + 3, r0:r0 + 3] = ex[top[0]:top[0] + 3, top[1]:top[1] + 3], True
    threshold = max_error
    while not known[t:-t, t:-t].all():
        inner = known[t:-t, t:-t]
        rows, cols = np.nonzero(ndimage.binary_dilation(inner, np.ones((3, 3))) & ~inner)
        counts = np.array([known[r:r + w, q:q + w].sum() for r, q in zip(rows, cols)])
        perm = rng.permutation(rows.size)
        order = perm[np.argsort(-counts[perm], kind="stable")]
        u = rng.random(rows.size)
        progress = False
        for k, i in enumerate(order):
            r, q = rows[i], cols[i]
            m = known[r:r + w, q:q + w]
            d = ((windows - out[r:r + w, q:q + w]) ** 2 * (g * m)[..., None]).sum(axis=(1, 2, 3)) / (c * (g * m).sum())
            inside = np.flatnonzero(d <= (1 + epsilon) * d.min() + 1e-12)
            pick = inside[int(u[k] * inside.size)]
            if threshold is None or d[pick] < threshold:
                out[r + t, q + t], known[r + t, q + t], progress = ex[tuple(centres[pick])], True, True
        if not progress:
            threshold *= 1.1
    result = out[t:-t, t:-t]
    return result[..., 0] if exemplar.ndim == 2 else result


@pytest.mark.parametrize("max_error", [0.3, 0.002, None])
def test_batches_give_the_pseudo_code_one_pixel_at_a_time(bread, max_error):
    """Each pass in batches equals the pass one pixel at a time in its order (and the threshold rule)."""
    ex = bread[:14, :14]
    got = efros_leung(ex, 13, neighborhood_size=5, sampling=Sampling(max_error=max_error), rng=3)
    want = pseudo_code(ex, 13, 5, 0.1, max_error, 3)
    np.testing.assert_array_equal(got, want)


def test_low_max_error_rises_by_ten_percent_per_empty_pass(bread):
    _, info = efros_leung(bread, 16, neighborhood_size=5, sampling=Sampling(max_error=1e-4), rng=0, return_info=True)
    steps = np.log(info.max_error / 1e-4) / np.log(1.1)
    assert steps > 10 and abs(steps - round(steps)) < 1e-6  # rose in whole 10 % steps
    _, info = efros_leung(bread, 16, neighborhood_size=5, sampling=Sampling(max_error=None), rng=0, return_info=True)
    assert info.max_error is None


def test_periodic_exemplar_with_zero_error_tolerance_regrows_its_period_exactly():
    period = np.random.default_rng(0).random((6, 5))  # no two 3x3 cyclic blocks alike
    ex = np.tile(period, (4, 5))  # 24 x 25
    out, info = efros_leung(ex, 32, neighborhood_size=5, sampling=Sampling(error_tolerance=0.0), rng=0,
                            return_info=True)
    # the output is the periodic pattern, shifted so that the seed lands where it came from
    r0, c0 = info.source[16, 16] - 16
    rows, cols = np.ogrid[:32, :32]
    np.testing.assert_array_equal(out, period[(rows + r0) % 6, (cols + c0) % 5])
    assert np.all(info.n_candidates[info.layer > 0] >= 1)


def test_every_pixel_is_copied_from_where_info_says(bread):
    out, info = efros_leung(bread, (20, 18), neighborhood_size=7, rng=1, return_info=True)
    assert out.shape == (20, 18, 3) and out.dtype == np.float64
    np.testing.assert_array_equal(out, bread[info.source[..., 0], info.source[..., 1]])
    assert info.passes == info.layer.max() and info.batches >= info.passes
    assert np.isnan(info.error[info.layer == 0]).all() and np.isfinite(info.error[info.layer > 0]).all()
    assert (info.layer == 0).sum() == 9  # the 3x3 seed
    assert info.sigma == pytest.approx(7 / 6.4) and info.seconds > 0 and set(info.stage_seconds) == {"index", "growth"}


def test_seeded_runs_reproduce_bit_for_bit_and_seeds_matter(bread):
    a = efros_leung(bread, 20, neighborhood_size=5, rng=7)
    np.testing.assert_array_equal(a, efros_leung(bread, 20, neighborhood_size=5, rng=np.random.default_rng(7)))
    assert not np.array_equal(a, efros_leung(bread, 20, neighborhood_size=5, rng=8))
    b = efros_leung(bread, 20, neighborhood_size=5, search=Search(method="pca"), rng=7)
    np.testing.assert_array_equal(b, efros_leung(bread, 20, neighborhood_size=5, search=Search(method="pca"), rng=7))


def test_hole_filling_keeps_the_known_pixels_and_copies_from_outside_the_hole():
    image = load_texture("lcv/reptil_skin.pgm", 32)
    known = np.ones((32, 32), bool)
    known[10:22, 12:26] = False
    filled, info = efros_leung(image, (32, 32), neighborhood_size=7, target=image, mask=known, exemplar_mask=known,
                               rng=0, return_info=True)
    assert filled.shape == image.shape  # grey in, grey out
    np.testing.assert_array_equal(filled[known], image[known])
    hole = ~known
    src = info.source[hole]
    np.testing.assert_array_equal(filled[hole], image[src[:, 0], src[:, 1]])
    # each copied window lay wholly on known pixels
    assert all(known[r - 3:r + 4, c - 3:c + 4].all() for r, c in src)
    assert (info.source[known] == -1).all() and (info.layer[known] == 0).all() and info.layer[hole].min() == 1
    # grown from the rim inwards: the pass that filled a pixel is its distance into the hole
    depth = ndimage.distance_transform_cdt(hole, metric="chessboard")
    np.testing.assert_array_equal(info.layer[hole], depth[hole])


def test_seed_center_places_the_seed(bread):
    _, info = efros_leung(bread, 16, neighborhood_size=5, seed_center=(0, 15), rng=0, return_info=True)
    assert set(map(tuple, np.argwhere(info.layer == 0))) == {(0, 14), (0, 15), (1, 14), (1, 15)}  # clipped


def test_float32_and_grey_layouts(bread):
    grey = bread.mean(axis=-1).astype(np.float32)
    out = efros_leung(grey, 12, neighborhood_size=5, rng=0)
    assert out.shape == (12, 12) and out.dtype == np.float32
    assert efros_leung(grey[..., None], 12, neighborhood_size=5, rng=0).shape == (12, 12, 1)


def test_progress_counts_every_filled_pixel(bread):
    seen = []
    efros_leung(bread, 12, neighborhood_size=5, rng=0, progress=lambda step, total, info: seen.append((step, total)))
    assert seen[-1] == (144 - 9, 144 - 9) and all(a[0] <= b[0] for a, b in itertools.pairwise(seen))


# --------------------------------------------------------------------------- #
# quality on a real texture, against the baselines
# --------------------------------------------------------------------------- #
def test_quality_on_a_real_texture_against_the_baselines():
    """Bread 32x32 -> 40x40, w = 9, exact and PCA, against the baselines of the same size.

    Scores of texsynth.testing.relative_scores (0 = the tiled exemplar, 1 =
    noise), measured with seeds 0-2 (exact and PCA alike): energy
    -0.008-0.036, completeness 0.12-0.18, spectrum 0.14-0.19, largest copy
    0.28-0.51 of the exemplar. Baselines: random-block mosaic 0.23,
    0.18, 0.27, 0.07; tiled 0, 0, 0.16, 1.0; noise 1, 1, 1, 0. Breaking the
    candidate rule to error_tolerance = 1 (ten times the paper's ε) gives 0.17, 0.26,
    0.33, 0.06; a uniform pick among all windows 0.95, 0.80, 0.91, 0. Bounds:
    - energy <= 0.12: Efros-Leung stitches exemplar regions, so it is almost
      as coherent as the tiled exemplar; the loose candidate set fails it;
    - completeness <= 0.25: as good as the mosaic (0.18) with a margin; a
      result locked onto one region of the exemplar would score far above;
    - spectrum <= 0.3: the mosaic's 0.27 with a margin (noise: 1);
    - copy <= 0.75: Efros-Leung copies large regions (its known verbatim-copy
      behaviour, here half the exemplar when the output is 1.6 times its
      area), but must not paste the whole exemplar (the tiled 1.0).
    """
    ex = load_texture("jcjohnson/bread.png", 32)
    for method in ("exact", "pca"):
        out = efros_leung(ex, 40, neighborhood_size=9, search=Search(method=method), rng=0)
        scores = relative_scores(texture_report(out, ex, patch_size=6))
        assert scores["energy"] <= 0.12, (method, scores)
        assert scores["completeness"] <= 0.25, (method, scores)
        assert scores["spectrum"] <= 0.3, (method, scores)
        assert scores["verbatim_copy"] <= 0.75, (method, scores)


def test_larger_windows_copy_larger_regions():
    """The paper's Figure 2: the window size is the randomness knob."""
    ex = load_texture("lcv/text.pgm", 32)
    small = efros_leung(ex, 36, neighborhood_size=3, rng=0)
    large = efros_leung(ex, 36, neighborhood_size=15, rng=0)
    assert verbatim_copy(large, ex, patch_size=6) > 2 * verbatim_copy(small, ex, patch_size=6)


# --------------------------------------------------------------------------- #
# bad input
# --------------------------------------------------------------------------- #
@pytest.mark.parametrize("kwargs, error, words", [
    ({"neighborhood_size": 6}, ValueError, "neighborhood_size must be odd.*pass 5 or 7"),
    ({"neighborhood_size": 0}, ValueError, "neighborhood_size must be an odd integer >= 3"),
    ({"neighborhood_size": -5}, ValueError, "neighborhood_size"),
    ({"neighborhood_size": 5.0}, TypeError, "neighborhood_size"),
    ({"neighborhood_size": 31}, ValueError, "exemplar is 24x24 but neighborhood_size=31.*<= 23"),
    ({"error_tolerance": -0.1}, ValueError, "error_tolerance must be a finite number >= 0"),
    ({"error_tolerance": float("nan")}, ValueError, "error_tolerance"),
    ({"max_error": 0.0}, ValueError, "max_error"),
    ({"sigma": -1.0}, ValueError, "sigma"),
    ({"seed_center": (20, 3)}, ValueError, r"seed_center=\(20, 3\) lies outside the output of size \(16, 16\)"),
    ({"seed_center": (-1, 3)}, ValueError, "seed_center"),
    ({"seed_center": 5}, TypeError, "seed_center must be a pair"),
    ({"method": "kdtree"}, ValueError, "method must be one of 'auto', 'exact', 'pca'"),
    ({"mask": np.ones((16, 16), bool)}, ValueError, "mask was given without target"),
    ({"target": np.zeros((16, 16, 3))}, ValueError, "target was given without mask"),
    ({"target": np.zeros((16, 16, 3)), "mask": np.ones((15, 16), bool)}, ValueError, r"mask must have shape \(16, 16\)"),
    ({"target": np.zeros((16, 16, 3)), "mask": np.full((16, 16), 0.5)}, ValueError, "mask must be binary"),
    ({"target": np.zeros((16, 16, 3)), "mask": np.zeros((16, 16), bool)}, ValueError, "mask marks no known pixel"),
    ({"target": np.zeros((16, 15, 3)), "mask": np.ones((16, 16), bool)}, ValueError, "target must have the output's"),
    ({"target": np.full((16, 16, 3), np.nan), "mask": np.ones((16, 16), bool)}, ValueError, "target contains NaN"),
    ({"target": np.zeros((16, 16, 3)), "mask": np.eye(16, dtype=bool), "seed_center": (3, 3)}, ValueError,
     "seed_center is for synthesis from a seed"),
    ({"exemplar_mask": np.ones((5, 5), bool)}, ValueError, r"exemplar_mask must have shape \(24, 24\)"),
    ({"exemplar_mask": np.eye(24, dtype=bool)}, ValueError, "exemplar_mask leaves no 5x5 window"),
    ({"candidates": "k-coherent"}, ValueError, "efros_leung compares every exemplar window"),
    ({"k": 3}, ValueError, "k='auto'"),
    ({"sampling": {"error_tolerance": 0.1}}, TypeError, "sampling must be a Sampling"),
])
def test_bad_arguments_name_the_parameter_and_the_fix(bread, kwargs, error, words):
    kwargs = {"neighborhood_size": 5, **kwargs}
    with pytest.raises(error, match=words):  # the groups' fields are checked when the group is made
        sampling = {name: kwargs.pop(name) for name in ("error_tolerance", "max_error", "sigma") if name in kwargs}
        search = {name: kwargs.pop(name) for name in ("method", "candidates", "k") if name in kwargs}
        kwargs = {**kwargs, **({"sampling": Sampling(**sampling)} if sampling else {}),
                  **({"search": Search(**search)} if search else {})}
        efros_leung(bread, 16, rng=0, **kwargs)


def test_sampling_defaults_are_the_papers(bread):
    assert Sampling() == Sampling(error_tolerance=0.1, max_error=0.3, sigma="auto")
    auto = efros_leung(bread, 14, neighborhood_size=5, rng=0)
    assert np.array_equal(auto, efros_leung(bread, 14, neighborhood_size=5, sampling=Sampling(sigma=5 / 6.4), rng=0))
    assert np.array_equal(auto, efros_leung(bread, 14, neighborhood_size=5, seed_center=(7, 7), rng=0))
    assert np.array_equal(auto, efros_leung(bread, 14, neighborhood_size=5, search=Search(method="exact"), rng=0))


def test_bad_exemplar_and_size(bread):
    bad = bread.copy()
    bad[3, 3, 0] = np.nan
    with pytest.raises(ValueError, match="exemplar contains NaN"):
        efros_leung(bad, 16, neighborhood_size=5)
    with pytest.raises(ValueError, match="size must be positive"):
        efros_leung(bread, (0, 16), neighborhood_size=5)
    with pytest.raises(ValueError, match="size=.*more than the .* available; pass a smaller size"):
        efros_leung(bread, 10**6, neighborhood_size=5)


def test_bad_search_input():
    v = np.random.default_rng(0).random((10, 4))
    with pytest.raises(ValueError, match=r"mask must have the queries' shape \(2, 4\)"):
        MaskedIndex(v).sq_distances(v[:2], np.ones((2, 3), bool))
    with pytest.raises(ValueError, match="fractions must be 2 numbers in \\[0, 1\\)"):
        MaskedIndex(v).near_best(v[:2], np.ones((2, 4), bool), 0.1, [0.5, 1.0])
    with pytest.raises(ValueError, match="method='pca' needs blocks"):
        MaskedIndex(v, method="pca")
    with pytest.raises(ValueError, match=r"blocks\[0\] holds dimensions outside 0..3"):
        MaskedIndex(v, blocks=[[2, 4]])
