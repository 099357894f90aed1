"""Tests of PatchMatch (texsynth.core.search._patchmatch): nearest-neighbour fields between two images."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texsynth.core.neighborhood import extract, gaussian_falloff, grid_centers
from texsynth.core.search import PatchIndex
from texsynth.core.search._patchmatch import FIELD_METHODS, nearest_field, patchmatch


# --------------------------------------------------------------------------- #
# helpers
# --------------------------------------------------------------------------- #
def naive_sq(image, exemplar, centers, field, patch, mode="valid", weights=None):
    """Distances of a field recomputed in float64 from the patches themselves."""
    image, exemplar = np.asarray(image, np.float64), np.asarray(exemplar, np.float64)
    if image.ndim == 2:
        image, exemplar = image[..., None], exemplar[..., None]
    q = extract(image, centers, patch, mode=mode)
    n, k = field.shape[:2]
    s = extract(exemplar, field.reshape(-1, 2), patch, mode="valid").reshape(n, k, *q.shape[1:])
    w = np.ones((patch, patch)) if weights is None else weights
    return (((s - q[:, None]) ** 2) * w[None, None, :, :, None]).sum(axis=(2, 3, 4))


def dense_centers(shape, patch):
    h, w = shape
    rr, cc = np.mgrid[patch // 2 : h - patch + patch // 2 + 1, patch // 2 : w - patch + patch // 2 + 1]
    return np.stack([rr.ravel(), cc.ravel()], axis=1)


def score(d2, exact):
    """recall@1 (a tie at the exact distance counts as a hit) and the mean distance ratio."""
    hit = d2[:, 0] <= exact[:, 0] * (1 + 1e-9) + 1e-12
    pos = exact[:, 0] > 0
    return float(hit.mean()), float(np.mean(d2[pos, 0] / exact[pos, 0]))


# Real photographs: the queries are patches of one crop, the exemplar another crop (or another
# photograph of the same set), so most queries have no exact copy in the exemplar, as in synthesis.
PAIRS = {
    "ink (colour)": ("embark/multiexample/2.jpg", (100, 100), "embark/multiexample/1.jpg", (0, 0)),
    "gravel (grey)": ("skimage/gravel.png", (300, 300), "skimage/gravel.png", (0, 0)),
    "bricks (colour)": ("rohitrango/t1.png", (96, 96), "rohitrango/t1.png", (0, 0)),
    "text (grey)": ("lcv/text.pgm", (100, 100), "lcv/text.pgm", (0, 0)),
}


def pair(texture, name, image_size=96, exemplar_size=64):
    a, (ra, ca), b, (rb, cb) = PAIRS[name]
    image = texture(a)[ra : ra + image_size, ca : ca + image_size]
    exemplar = texture(b)[rb : rb + exemplar_size, cb : cb + exemplar_size]
    return image, exemplar


# --------------------------------------------------------------------------- #
# recall against exact search on real photographs
# --------------------------------------------------------------------------- #
# Measured (3 seeds, 5 iterations; 96 px crops against a 64 px exemplar; patch 7 dense, or 8 on
# the w/4 = 2 px grid of texture optimization):
#   pair      dense recall / ratio     grid recall / ratio       random field ratio (dense / grid)
#   ink       0.415-0.426 / 1.04       0.236-0.247 / 1.07        17.4-18.1 / 15.0-15.8
#   gravel    0.322-0.339 / 1.20       0.188-0.194 / 1.28-1.29   12.4-12.9 /  9.7-10.1
#   bricks    0.429-0.474 / 1.09-1.12  0.256-0.275 / 1.18-1.20    7.9      /  6.7-6.8
#   text      0.282-0.295 / 1.70-1.83  0.176-0.198 / 2.05-2.21   73.8-74.7 / 45.0-45.7
# A random field (iterations=0) has recall 0.000-0.001. The same 8 cases with a step broken
# (seed 0): without propagation recall 0.013-0.029 (ratio 1.7-5.0), without random search
# 0.009-0.046 (ratio 1.4-4.9), without the reversed scan of every other iteration 0.074-0.233
# (about half; ratio 1.09-2.85). The thresholds sit at about 2/3 of the lowest measured recall
# and allow ~1.5x the measured excess ratio, so another seed or platform does not fail them, while
# each of those breakages fails all 8. The ratio must also be at most a fifth of the random
# field's: most of the way from random to exact.
RECALL_THRESHOLDS = {  # name: (dense recall, dense ratio, grid recall, grid ratio)
    "ink (colour)": (0.28, 1.07, 0.16, 1.11),
    "gravel (grey)": (0.22, 1.30, 0.12, 1.42),
    "bricks (colour)": (0.28, 1.18, 0.17, 1.30),
    "text (grey)": (0.19, 2.3, 0.12, 2.8),
}


@pytest.mark.parametrize("name", list(PAIRS))
@pytest.mark.parametrize("grid", [False, True], ids=["dense", "grid"])
def test_recall_and_distance_ratio_against_exact_search(texture, name, grid):
    image, exemplar = pair(texture, name)
    patch = 8 if grid else 7
    centers = grid_centers(image.shape[:2], patch, patch // 4, mode="valid") if grid else None
    exact_field, exact = nearest_field(image, exemplar, patch, centers=centers, method="exact")
    field, d2 = patchmatch(image, exemplar, patch, centers=centers, iterations=5, rng=0)
    _, random_d2 = patchmatch(image, exemplar, patch, centers=centers, iterations=0, rng=0)
    recall, ratio = score(d2, exact)
    random_recall, random_ratio = score(random_d2, exact)
    min_recall, max_ratio = RECALL_THRESHOLDS[name][2:] if grid else RECALL_THRESHOLDS[name][:2]
    assert recall >= min_recall, (recall, random_recall)
    assert ratio <= max_ratio and ratio <= random_ratio / 5, (ratio, random_ratio)
    assert random_recall < 0.01
    # never nearer than the exact nearest, and the distances are exact
    assert np.all(d2[:, 0] >= exact[:, 0] * (1 - 1e-9) - 1e-12)
    c = exact_field.shape[0]
    used = centers if grid else dense_centers(image.shape[:2], patch)
    assert field.shape == (c, 1, 2)
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, used, field, patch), rtol=1e-9, atol=1e-12)


def test_exact_field_matches_patch_index(texture):
    image, exemplar = pair(texture, "bricks (colour)", 40, 32)
    field, d2 = nearest_field(image, exemplar, 5, method="exact")
    vectors = np.lib.stride_tricks.sliding_window_view(exemplar, (5, 5), axis=(0, 1))
    ny, nx = vectors.shape[:2]
    vectors = np.moveaxis(vectors, 2, -1).reshape(ny * nx, -1)
    centers = dense_centers(image.shape[:2], 5)
    queries = extract(image, centers, 5, mode="valid").reshape(len(centers), -1)
    idx, ref = PatchIndex(vectors, method="exact").query(queries)
    np.testing.assert_array_equal(field[:, 0], np.stack(np.divmod(idx[:, 0], nx), axis=1) + 2)
    np.testing.assert_allclose(d2, ref, rtol=1e-12)


# --------------------------------------------------------------------------- #
# the field improves, and only improves
# --------------------------------------------------------------------------- #
@pytest.mark.parametrize("k", [1, 3])
def test_field_never_worsens_with_iterations(texture, k):
    image, exemplar = pair(texture, "ink (colour)", 48, 40)
    centers = grid_centers(image.shape[:2], 8, 2, mode="valid")
    previous = None
    means = []
    for iterations in range(6):
        # the same seed draws the same numbers for the first iterations, so each run
        # continues the previous one by one iteration
        _, d2 = patchmatch(image, exemplar, 8, centers=centers, k=k, iterations=iterations, rng=7)
        if previous is not None:
            assert np.all(d2 <= previous)  # every rank of every query, elementwise
        previous = d2
        means.append(float(d2.mean()))
    assert means[-1] < 0.2 * means[0]  # and it does improve: far below the random start


def test_warm_start_from_the_exact_field_stays_exact(texture):
    image, exemplar = pair(texture, "gravel (grey)", 48, 40)
    for k in (1, 2):
        field, exact = nearest_field(image, exemplar, 7, k=k, method="exact")
        warm, d2 = patchmatch(image, exemplar, 7, k=k, init=field, iterations=3, rng=0)
        np.testing.assert_allclose(d2, exact, rtol=1e-9, atol=1e-12)
        # a patch is replaced only by a strictly nearer one: the exact answer stays where no tie is
        same = np.all(warm == field, axis=-1)
        assert same.mean() > 0.99


def test_warm_start_continues_a_field(texture):
    image, exemplar = pair(texture, "bricks (colour)", 48, 40)
    f2, d2 = patchmatch(image, exemplar, 7, iterations=2, rng=1)
    _, d3 = patchmatch(image, exemplar, 7, iterations=1, init=f2, rng=2)
    assert np.all(d3 <= d2) and d3.mean() < d2.mean()
    # init=field with zero iterations gives back that field and its exact distances
    f0, d0 = patchmatch(image, exemplar, 7, iterations=0, init=f2, rng=3)
    np.testing.assert_array_equal(f0, f2)
    np.testing.assert_array_equal(d0, d2)


def test_init_is_moved_inside_the_exemplar():
    rng = np.random.default_rng(0)
    image, exemplar = rng.random((12, 12)), rng.random((10, 10))
    init = np.full((64, 1, 2), -50)  # far outside: moved to the corner patch
    f, _ = patchmatch(image, exemplar, 5, init=init, iterations=0)
    assert np.all(f == 2)


# --------------------------------------------------------------------------- #
# propagation follows the paper's sequential scan
# --------------------------------------------------------------------------- #
def sequential_propagation(image, exemplar, patch, centers, field, iterations):
    """Barnes et al.'s propagation, one query at a time in scan order (reversed every other iteration)."""
    rows, cols = np.unique(centers[:, 0]), np.unique(centers[:, 1])
    grid = {(r, c): i for i, (r, c) in enumerate(centers.tolist())}
    lo, hi = patch // 2, np.array(exemplar.shape[:2]) - patch + patch // 2
    field = field[:, 0].copy()
    d = naive_sq(image, exemplar, centers, field[:, None], patch)[:, 0]
    for it in range(iterations):
        forward = it % 2 == 0
        order = [(i, j) for i in range(len(rows)) for j in range(len(cols))]
        for i, j in order if forward else order[::-1]:
            q = grid[(rows[i], cols[j])]
            for di, dj in ((0, -1), (-1, 0)) if forward else ((0, 1), (1, 0)):
                if not (0 <= i + di < len(rows) and 0 <= j + dj < len(cols)):
                    continue
                nb = grid[(rows[i + di], cols[j + dj])]
                cand = np.clip(field[nb] + centers[q] - centers[nb], lo, hi)
                if np.array_equal(cand, field[q]):
                    continue
                dc = naive_sq(image, exemplar, centers[q : q + 1], cand[None, None], patch)[0, 0]
                if dc < d[q]:
                    field[q], d[q] = cand, dc
    return field, d


def test_anti_diagonal_order_equals_the_sequential_scan(texture, monkeypatch):
    """With random search switched off, the vectorised propagation gives every query exactly the
    match the paper's one-at-a-time scan gives it."""
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "bricks (colour)", 40, 32)
    centers = grid_centers(image.shape[:2], 6, 3, mode="valid")  # 3, 6, ..., 36, 37: an uneven last step
    start, _ = patchmatch(image, exemplar, 6, centers=centers, iterations=0, rng=5)
    monkeypatch.setattr(pm._Problem, "random_search", lambda self, field, q, rng: None)
    got, got_d = pm.patchmatch(image, exemplar, 6, centers=centers, init=start, iterations=3, rng=0)
    want, want_d = sequential_propagation(image, exemplar, 6, centers, start, 3)
    np.testing.assert_array_equal(got[:, 0], want)
    np.testing.assert_allclose(got_d[:, 0], want_d, rtol=1e-9)
    assert not np.array_equal(want, start[:, 0])  # propagation did something


# --------------------------------------------------------------------------- #
# masks, wrap, weights, k
# --------------------------------------------------------------------------- #
def test_exemplar_mask_is_respected(texture):
    image, exemplar = pair(texture, "bricks (colour)", 48, 48)
    mask = np.ones(exemplar.shape[:2], dtype=bool)
    mask[10:30, 15:35] = False  # a hole
    mask[:, 44] = False  # and a line
    for k in (1, 2):
        field, d2 = patchmatch(image, exemplar, 5, k=k, exemplar_mask=mask, iterations=4, rng=0)
        r = field[..., 0, None] + np.arange(5) - 2
        c = field[..., 1, None] + np.arange(5) - 2
        touched = mask[r[..., :, None], c[..., None, :]]  # (N, k, 5, 5)
        assert touched.all()
        exact_field, exact = nearest_field(image, exemplar, 5, k=k, exemplar_mask=mask, method="exact")
        assert np.all(d2 >= exact * (1 - 1e-9) - 1e-12)
        assert mask[exact_field[..., 0], exact_field[..., 1]].all()
    # without the mask the answers do use the hole: the mask really restricted them
    free, _ = nearest_field(image, exemplar, 5, method="exact")
    assert not mask[free[:, 0, 0], free[:, 0, 1]].all()


def test_exemplar_mask_from_an_alpha_hole(texture):
    bricks = texture("embark/bricks.png", rgb=False)  # alpha has a round hole
    exemplar = bricks[180:290, 180:290]  # a third of it in the hole
    mask = exemplar[..., 3] > 0.5
    assert not mask.all()
    image = bricks[:40, :40, :3]
    field, _ = patchmatch(image, exemplar[..., :3], 7, exemplar_mask=mask, iterations=2, rng=0)
    r = field[:, 0, 0, None] + np.arange(7) - 3
    c = field[:, 0, 1, None] + np.arange(7) - 3
    assert mask[r[:, :, None], c[:, None, :]].all()


def test_wrap_mode_finds_patches_across_the_border(texture):
    exemplar = texture("jcjohnson/bread.png")[:72, :72]
    # a crop of the exemplar, rolled: image pixel (r, c) is crop pixel ((r - 17) % 48, (c - 23) % 48),
    # so a patch that wraps around the image's border is a contiguous patch of the crop (unless it
    # also crosses the roll's seam inside the image), and the exemplar holds it exactly
    crop = exemplar[8:56, 12:60]
    image = np.roll(crop, (17, 23), axis=(0, 1))
    p = 7
    centers = grid_centers(image.shape[:2], p, 2, mode="wrap")
    field, d2 = patchmatch(image, exemplar, p, centers=centers, mode="wrap", iterations=5, rng=0)
    in_crop = (centers - [17, 23]) % 48
    border = np.any((centers < p // 2) | (centers >= 48 - p // 2), axis=1)
    contiguous = np.all((in_crop >= p // 2) & (in_crop < 48 - p // 2), axis=1)
    across = border & contiguous
    assert across.sum() > 50
    found = d2[across, 0] == 0
    assert found.mean() > 0.97, found.mean()
    # and the patch found is that one (a flat patch might also occur elsewhere)
    right = np.all(field[across, 0] == in_crop[across] + [8, 12], axis=1)
    assert right[found].mean() > 0.99
    # in valid mode those centres are refused
    with pytest.raises(ValueError, match="centers"):
        patchmatch(image, exemplar, p, centers=centers, mode="valid")


def test_pixel_weights_are_honoured(texture):
    image, exemplar = pair(texture, "ink (colour)", 40, 36)
    g = gaussian_falloff(7)
    field, d2 = patchmatch(image, exemplar, 7, pixel_weights=g, iterations=3, rng=0)
    centers = dense_centers(image.shape[:2], 7)
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers, field, 7, weights=g), rtol=1e-9)
    exact_field, exact = nearest_field(image, exemplar, 7, pixel_weights=g, method="exact")
    np.testing.assert_allclose(exact, naive_sq(image, exemplar, centers, exact_field, 7, weights=g), rtol=1e-9)
    assert np.all(d2 >= exact * (1 - 1e-9))
    unweighted, _ = nearest_field(image, exemplar, 7, method="exact")
    assert not np.array_equal(unweighted, exact_field)  # the weights changed the answer


def test_k_nearest_are_distinct_and_sorted(texture):
    image, exemplar = pair(texture, "gravel (grey)", 40, 40)
    k = 4
    centers = grid_centers(image.shape[:2], 6, 2, mode="valid")
    field, d2 = patchmatch(image, exemplar, 6, centers=centers, k=k, iterations=4, rng=0)
    assert field.shape == (len(centers), k, 2) and d2.shape == (len(centers), k)
    flat = field[..., 0] * 1000 + field[..., 1]
    assert all(len(set(row)) == k for row in flat.tolist())
    assert np.all(np.diff(d2, axis=1) >= 0)
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers, field, 6), rtol=1e-9, atol=1e-12)
    _, exact = nearest_field(image, exemplar, 6, centers=centers, k=k, method="exact")
    assert np.all(d2 >= exact * (1 - 1e-9) - 1e-12)
    # and the k-th found is mostly among the true k nearest's range
    _, d1 = patchmatch(image, exemplar, 6, centers=centers, k=1, iterations=4, rng=0)
    assert np.mean(d2[:, 0] <= d1[:, 0]) > 0.5  # k > 1 searches more: its first is as good or better


def test_irregular_centres(texture):
    image, exemplar = pair(texture, "ink (colour)", 64, 48)
    rng = np.random.default_rng(0)
    centers = rng.integers(3, 61, size=(300, 2))
    centers[5] = centers[4]  # a repeated centre is allowed
    _, exact = nearest_field(image, exemplar, 7, centers=centers, method="exact")
    field, d2 = patchmatch(image, exemplar, 7, centers=centers, iterations=5, rng=0)
    _, d0 = patchmatch(image, exemplar, 7, centers=centers, iterations=0, rng=0)
    assert score(d2, exact)[1] < score(d0, exact)[1] / 5
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers, field, 7), rtol=1e-9)


def test_a_part_of_a_grid_is_scanned_as_a_grid(texture, monkeypatch):
    # The grid points near a hole (texture optimization under hard constraints searches only those):
    # a disc of the w/4 grid, 697 of 2025 points. Measured after 2 iterations, seed 0 (seeds 1, 2
    # alike): distance ratio to the exact nearest 1.41 scanned as a part of the grid, 1.44 for the
    # same queries within the whole grid, 1.86 as scattered centres (propagation from the 4 nearest,
    # one neighbour per iteration). Thresholds: within 10 % of the whole grid's, and below 0.85 of
    # the scattered treatment's, which a scan that lost its grid would not be.
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "bricks (colour)")
    full = grid_centers(image.shape[:2], 8, 2, mode="valid")
    disc = ((full - 48) ** 2).sum(1) < 30**2
    centers = full[disc]
    assert pm._Neighbors(centers, image.shape[:2], "valid").grid is not None
    assert pm._Neighbors(np.random.default_rng(0).integers(4, 92, (300, 2)), image.shape[:2], "valid").grid is None
    _, exact = nearest_field(image, exemplar, 8, centers=centers, method="exact")
    field, part = patchmatch(image, exemplar, 8, centers=centers, iterations=2, rng=0)
    np.testing.assert_allclose(part, naive_sq(image, exemplar, centers, field, 8), rtol=1e-9)
    _, whole = patchmatch(image, exemplar, 8, centers=full, iterations=2, rng=0)
    monkeypatch.setattr(pm, "_GRID_MIN_FILL", 2.0)  # no set of centres counts as a grid
    _, scattered = patchmatch(image, exemplar, 8, centers=centers, iterations=2, rng=0)
    ratio = score(part, exact)[1]
    assert ratio <= 1.1 * score(whole[disc], exact)[1]
    assert ratio < 0.85 * score(scattered, exact)[1]


def test_irregular_centres_wrap_across_the_border():
    rng = np.random.default_rng(2)
    exemplar = rng.random((30, 30, 2))
    image = np.roll(exemplar[2:26, 3:27], (5, 7), axis=(0, 1))
    centers = rng.integers(-24, 48, size=(200, 2))  # any integer centre: taken modulo the image
    field, d2 = patchmatch(image, exemplar, 5, centers=centers, mode="wrap", iterations=8, rng=0)
    assert field.shape == (200, 1, 2)
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers % 24, field, 5, mode="wrap"), rtol=1e-9)
    # noise has no near matches, only the exact copies: patches not crossing the roll's seam
    in_crop = (centers % 24 - [5, 7]) % 24
    findable = np.all((in_crop >= 2) & (in_crop <= 21), axis=1)
    found = d2[:, 0] == 0
    # measured 0.78 after 8 iterations (0.32 after 4, 0.90 after 12): propagation among
    # irregular centres moves a match one neighbour per iteration
    assert found[findable].mean() > 0.6 and not found[~findable].any()
    np.testing.assert_array_equal(field[found, 0], in_crop[found] + [2, 3])


def test_parallel_schedule_also_improves_the_field(texture, monkeypatch):
    """The jump-flood schedule measured against the scan in the benchmark is a correct PatchMatch too."""
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "ink (colour)")
    centers = grid_centers(image.shape[:2], 8, 2, mode="valid")
    _, exact = nearest_field(image, exemplar, 8, centers=centers, method="exact")
    _, scan = patchmatch(image, exemplar, 8, centers=centers, iterations=5, rng=0)
    monkeypatch.setattr(pm, "_iterate", pm._iterate_parallel)
    previous = None
    for iterations in (1, 3, 5):
        _, d2 = pm.patchmatch(image, exemplar, 8, centers=centers, iterations=iterations, rng=0)
        assert previous is None or np.all(d2 <= previous)
        previous = d2
    recall, ratio = score(d2, exact)
    # measured: recall 0.23, ratio 1.08 (the scan: 0.24, 1.07); thresholds as the grid's above
    assert recall >= RECALL_THRESHOLDS["ink (colour)"][2] and ratio <= RECALL_THRESHOLDS["ink (colour)"][3]
    assert abs(d2.mean() / scan.mean() - 1) < 0.1


def test_reflect_mode_and_default_centres():
    rng = np.random.default_rng(1)
    image, exemplar = rng.random((11, 13, 2)), rng.random((9, 10, 2))
    f, d2 = patchmatch(image, exemplar, 5, iterations=1, rng=0)
    assert f.shape == (7 * 9, 1, 2)
    f, d2 = patchmatch(image, exemplar, 5, mode="wrap", iterations=1, rng=0)
    assert f.shape == (11 * 13, 1, 2)
    f, d2 = patchmatch(image, exemplar, 5, mode="reflect", iterations=2, rng=0)
    centers = np.argwhere(np.ones((11, 13), bool))
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers, f, 5, mode="reflect"), rtol=1e-9)
    assert np.all((f >= 2) & (f <= [6, 7]))  # wholly inside the exemplar


def test_dtype_and_grey_input(texture):
    image, exemplar = pair(texture, "gravel (grey)", 32, 32)
    assert image.ndim == 2
    f64, d64 = patchmatch(image, exemplar, 5, iterations=2, rng=0)
    f32, d32 = patchmatch(image.astype(np.float32), exemplar.astype(np.float32), 5, iterations=2, rng=0)
    assert d64.dtype == np.float64 and d32.dtype == np.float32 and f32.dtype == np.int64
    u8, _ = patchmatch((image * 255).round().astype(np.uint8), exemplar, 5, iterations=0, rng=0)
    assert u8.shape == f64.shape


# --------------------------------------------------------------------------- #
# determinism
# --------------------------------------------------------------------------- #
@pytest.mark.parametrize("kwargs", [{}, {"k": 3}, {"mode": "wrap"}, {"centers": "grid"}])
def test_same_rng_same_field(texture, kwargs):
    image, exemplar = pair(texture, "bricks (colour)", 40, 32)
    if kwargs.get("centers") == "grid":
        kwargs = {"centers": grid_centers(image.shape[:2], 8, 2, mode="valid")}
    p = 8 if "centers" in kwargs else 5
    a = patchmatch(image, exemplar, p, iterations=3, rng=11, **kwargs)
    b = patchmatch(image, exemplar, p, iterations=3, rng=np.random.default_rng(11), **kwargs)
    c = patchmatch(image, exemplar, p, iterations=3, rng=12, **kwargs)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert not np.array_equal(a[0], c[0])


def test_nearest_field_dispatches(texture):
    image, exemplar = pair(texture, "ink (colour)", 32, 32)
    a = nearest_field(image, exemplar, 5, method="patchmatch", iterations=2, rng=3)
    b = patchmatch(image, exemplar, 5, iterations=2, rng=3)
    np.testing.assert_array_equal(a[0], b[0])
    _, exact = nearest_field(image, exemplar, 5, method="exact")
    for method in ("kdtree", "tsvq", "auto"):
        f, d2 = nearest_field(image, exemplar, 5, method=method, rng=0)
        assert f.shape == (28 * 28, 1, 2) and np.all(d2 >= exact * (1 - 1e-9))
    assert set(FIELD_METHODS) == {"auto", "exact", "kdtree", "tsvq", "patchmatch"}


# --------------------------------------------------------------------------- #
# distance bounds: projections on principal components skip candidates, never change the field
# --------------------------------------------------------------------------- #
def _counting_bounds(monkeypatch):
    """Count the candidates the bounds see and the ones they let through to an exact distance."""
    import texsynth.core.search._patchmatch as pm

    seen = [0, 0]
    may_beat = pm._Bound.may_beat

    def counted(self, q, ids, worst):
        out = may_beat(self, q, ids, worst)
        seen[0] += out.size
        seen[1] += int(out.sum())
        return out

    monkeypatch.setattr(pm._Bound, "may_beat", counted)
    return seen


BOUND_CASES = {
    "colour": ("ink (colour)", {}),
    "k=3, weights": ("ink (colour)", {"k": 3, "pixel_weights": gaussian_falloff(12)}),
    "mask, wrap": ("bricks (colour)", {"exemplar_mask": np.pad(np.ones((40, 40), bool), 12), "mode": "wrap"}),
    "penalty": ("bricks (colour)", {"penalty": lambda q, c: 0.05 * (c[:, 0] < 32)}),
    "grey 16 px": ("gravel (grey)", {}),
    "colour 8 px": ("bricks (colour)", {"pixel_weights": gaussian_falloff(8)}),
}


@pytest.mark.parametrize("case", list(BOUND_CASES))
def test_bounds_change_the_work_not_the_field(texture, monkeypatch, case):
    """Patches of 128 values or more are first compared by their projections on the exemplar's
    leading principal components: the field must be the one the exact comparisons alone find, bit
    for bit, while most candidates are ruled out without an exact distance."""
    import texsynth.core.search._patchmatch as pm

    name, kwargs = BOUND_CASES[case]
    patch = 16 if "grey" in case else 8 if "8 px" in case else 12  # 256, 192, 432 values: >= _BOUND_MIN_DIM
    monkeypatch.setattr(pm, "_BOUND_MIN_WORK", 0)  # bounds however few the queries (the grey case has 441)
    image, exemplar = pair(texture, name, 96, 64)
    centers = grid_centers(image.shape[:2], patch, patch // 4, mode="wrap" if "wrap" in case else "valid")
    seen = _counting_bounds(monkeypatch)
    got = patchmatch(image, exemplar, patch, centers=centers, iterations=4, rng=3, **kwargs)
    # measured: 44-54 % of the candidates reach an exact distance in the 12-px colour cases and the
    # 16-px grey one, 31 % with 8-px colour patches; bounds that ruled out nothing would let 100 % through
    assert seen[0] > 0 and seen[1] < 0.75 * seen[0]
    monkeypatch.setattr(pm, "_BOUND_MIN_DIM", 10**9)
    want = patchmatch(image, exemplar, patch, centers=centers, iterations=4, rng=3, **kwargs)
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])


def test_the_bound_never_exceeds_the_distance(texture):
    """The projected distance is a lower bound of the exact weighted distance, and a useful one."""
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "ink (colour)", 96, 64)
    centers = grid_centers(image.shape[:2], 12, 3, mode="valid")
    problem = pm._Problem(image, exemplar, 12, centers, 1, None, gaussian_falloff(12), "valid")
    rng = np.random.default_rng(0)
    q = rng.integers(len(centers), size=5000)
    ids = problem.allowed_ids[rng.integers(problem.allowed_ids.shape[0], size=5000)]
    diff = problem.bound.queries[q] - problem.bound.exemplar[ids]
    lower = np.einsum("ij,ij->i", diff, diff)
    exact = problem.distances(q, ids)
    assert np.all(lower <= exact * (1 + 1e-12))
    # measured: the bound is 0.88 of the distance on average here (16 of 432 components); a
    # basis that missed the patches' main variation (e.g. random directions) would hold about 16/432
    assert np.mean(lower / exact) > 0.5


def test_bounds_only_where_the_queries_pay_for_the_exemplars_projections(texture):
    """The exemplar's projections cost about the same for 10 queries as for 10,000: a search with fewer
    query values than _BOUND_MIN_WORK per exemplar patch position compares exactly from the start."""
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "ink (colour)", 96, 64)
    centers = grid_centers(image.shape[:2], 12, 3, mode="valid")  # 841 queries x 432 values, 2809 positions
    assert pm._Problem(image, exemplar, 12, centers, 1, None, None, "valid").bound is not None
    assert pm._Problem(image, exemplar, 12, centers[:40], 1, None, None, "valid").bound is None


def test_bounds_follow_an_exemplar_changed_in_place(texture, monkeypatch):
    """The exemplar's projections are kept between searches by content: an exemplar changed in
    place is projected again (a stale bound would rule out the right patches)."""
    import texsynth.core.search._patchmatch as pm

    image, exemplar = pair(texture, "ink (colour)", 64, 48)
    exemplar = exemplar.copy()
    patchmatch(image, exemplar, 12, iterations=2, rng=0)
    exemplar[:] = exemplar[::-1, ::-1]  # the same values, moved
    got = patchmatch(image, exemplar, 12, iterations=2, rng=0)
    monkeypatch.setattr(pm, "_BOUND_MIN_DIM", 10**9)
    want = patchmatch(image, exemplar, 12, iterations=2, rng=0)
    np.testing.assert_array_equal(got[0], want[0])


@pytest.mark.parametrize("channels, patch, m", [(3, 12, 16), (1, 8, 4), (3, 4, 48)])
def test_project_patches_gives_m_shortened_differences(texture, channels, patch, m):
    """m columns (at most the patch dimension), one row per patch position, and squared distances
    between rows never above the weighted distances between the patches."""
    from numpy.lib.stride_tricks import sliding_window_view

    from texsynth.core.search import project_patches

    image = texture("embark/multiexample/2.jpg")[:40, :40]
    image = image[..., :channels] if channels == 3 else image[..., :1]
    g = gaussian_falloff(patch)
    proj = project_patches(image, patch, m, pixel_weights=g)
    n = (41 - patch) ** 2
    assert proj.shape == (n, min(m, patch * patch * channels))
    patches = np.moveaxis(sliding_window_view(image, (patch, patch), axis=(0, 1)), 2, -1).reshape(n, -1)
    w = np.repeat(g.ravel(), channels)
    rng = np.random.default_rng(0)
    a, b = rng.integers(n, size=(2, 2000))
    exact = (((patches[a] - patches[b]) ** 2) * w).sum(1)
    bound = ((proj[a] - proj[b]) ** 2).sum(1)
    assert np.all(bound <= exact * (1 + 1e-9) + 1e-12)
    with pytest.raises(ValueError, match="exemplar must be"):
        project_patches(image[: patch - 1, : patch - 1], patch, m)
    with pytest.raises(ValueError, match="n_components"):  # refused before anything is allocated
        project_patches(np.broadcast_to(image[:1, :1], (10**5, 10**5, image.shape[-1])), patch, m)


def test_a_negative_penalty_is_refused():
    """The bounds rule a candidate out by its distance alone, which is sound for costs >= 0 only."""
    with pytest.raises(ValueError, match="penalty must return one finite, non-negative cost"):
        patchmatch(IMG, EX, 3, penalty=lambda q, c: -np.ones(len(q)), rng=0)


# --------------------------------------------------------------------------- #
# bad input
# --------------------------------------------------------------------------- #
IMG = np.random.default_rng(0).random((12, 12, 3))
EX = np.random.default_rng(1).random((10, 10, 3))


@pytest.mark.parametrize(
    "args, kwargs, exc, match",
    [
        ((IMG, EX, 11), {}, ValueError, "patch_size .* larger than the exemplar"),
        ((IMG[:4], EX, 5), {}, ValueError, "patch_size .* larger than the image"),
        ((IMG, EX, 0), {}, ValueError, "patch_size must be positive"),
        ((IMG, EX, 2.5), {}, TypeError, "patch_size"),
        ((IMG, EX[..., :1], 3), {}, ValueError, "image has 3 channels but exemplar has 1"),
        ((IMG * 255, EX, 3), {}, ValueError, "image is floating point"),
        ((IMG, None, 3), {}, TypeError, "exemplar must be an array"),
        ((IMG, EX, 3), {"centers": [[0, 0]]}, ValueError, r"centers\[0\] = \[0, 0\] puts its"),
        ((IMG, EX, 3), {"centers": [[1.0, 2.0]]}, ValueError, "centers must be a non-empty integer array"),
        ((IMG, EX, 3), {"centers": np.zeros((0, 2), int)}, ValueError, "centers must be a non-empty"),
        ((IMG, EX, 3), {"centers": [[20, 1]], "mode": "reflect"}, ValueError, "centers.* outside the image"),
        ((IMG, EX, 3), {"k": 0}, ValueError, "k must be an integer >= 1"),
        ((IMG, EX, 3), {"k": True}, TypeError, "k must be an integer"),
        ((IMG, EX, 3), {"k": 65}, ValueError, "k=65 but the exemplar holds only 64 patches"),
        ((IMG, EX, 3), {"iterations": -1}, ValueError, "iterations must be an integer >= 0"),
        ((IMG, EX, 3), {"iterations": 1.5}, TypeError, "iterations"),
        ((IMG, EX, 3), {"init": np.zeros((99, 1, 2), int)}, ValueError,
         r"init must be an integer array of shape \(100, 1, 2\)"),
        ((IMG, EX, 3), {"init": np.zeros((100, 1, 2))}, ValueError, "init must be an integer array"),
        ((IMG, EX, 3), {"exemplar_mask": np.ones((5, 5), bool)}, ValueError,
         "exemplar_mask must have the exemplar's shape"),
        ((IMG, EX, 3), {"exemplar_mask": np.zeros((10, 10), bool)}, ValueError, "exemplar_mask leaves no"),
        ((IMG, EX, 3), {"exemplar_mask": np.eye(10, dtype=bool)}, ValueError, "exemplar_mask leaves no"),
        ((IMG, EX, 3), {"exemplar_mask": np.full((10, 10), "a")}, TypeError, "exemplar_mask must be a bool array"),
        ((IMG, EX, 3), {"pixel_weights": np.ones(9)}, ValueError, r"pixel_weights must have shape \(3, 3\)"),
        ((IMG, EX, 3), {"pixel_weights": -np.ones((3, 3))}, ValueError,
         "pixel_weights must be finite and non-negative"),
        ((IMG, EX, 3), {"pixel_weights": np.zeros((3, 3))}, ValueError, "pixel_weights are all zero"),
        ((IMG, EX, 3), {"mode": "mirror"}, ValueError, "mode must be one of 'valid', 'wrap', 'reflect'"),
        ((IMG, EX, 3), {"rng": "seed"}, TypeError, "rng"),
    ],
)
def test_bad_input_names_the_parameter(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        patchmatch(*args, **kwargs)


def test_bad_method():
    with pytest.raises(ValueError, match="method must be one of 'auto', 'exact', 'kdtree', 'tsvq', 'patchmatch'"):
        nearest_field(IMG, EX, 3, method="ball")


def test_a_field_too_large_for_memory_is_refused_before_allocating(monkeypatch):
    import texsynth.core._validate as validate

    monkeypatch.setattr(validate, "available_memory", lambda: 10_000)
    with pytest.raises(ValueError, match="centers=.* need about .* for the field"):
        patchmatch(IMG, EX, 3)


@settings(max_examples=40, deadline=None)
@given(
    h=st.integers(1, 14), w=st.integers(1, 14), eh=st.integers(1, 10), ew=st.integers(1, 10),
    channels=st.integers(1, 3), patch=st.integers(1, 6), k=st.integers(1, 4), iterations=st.integers(0, 2),
    mode=st.sampled_from(["valid", "wrap", "reflect"]), seed=st.integers(0, 3),
)
def test_any_shape_gives_a_sorted_exact_field_or_a_named_error(h, w, eh, ew, channels, patch, k, iterations, mode,
                                                                seed):
    rng = np.random.default_rng(seed)
    image, exemplar = rng.random((h, w, channels)), rng.random((eh, ew, channels))
    try:
        field, d2 = patchmatch(image, exemplar, patch, k=k, iterations=iterations, mode=mode, rng=seed)
    except ValueError as exc:
        assert any(name in str(exc) for name in ("patch_size", "k=")), str(exc)
        return
    n = (h - patch + 1) * (w - patch + 1) if mode == "valid" else h * w
    assert field.shape == (n, k, 2) and d2.shape == (n, k)
    assert np.all((field >= patch // 2) & (field <= np.array([eh, ew]) - patch + patch // 2))
    assert np.all(np.diff(d2, axis=1) >= 0)
    flat = field[..., 0] * 100 + field[..., 1]
    assert all(len(set(row)) == k for row in flat.tolist())
    centers = dense_centers((h, w), patch) if mode == "valid" else np.argwhere(np.ones((h, w), bool))
    np.testing.assert_allclose(d2, naive_sq(image, exemplar, centers, field, patch, mode=mode), rtol=1e-9, atol=1e-12)


def test_query_patches_gathered_into_the_workspace():
    # the query patches of a regular grid are one strided copy, into the memory a workspace keeps: the same
    # values as fancy indexing, the same array again for a search of the same size, a new one for another
    from numpy.lib.stride_tricks import sliding_window_view

    from texsynth.core.search import patchmatch_features
    from texsynth.core.search._patchmatch import _gather

    rng = np.random.default_rng(5)
    img = rng.random((40, 37, 3)).astype(np.float32)
    view = np.moveaxis(sliding_window_view(img, (6, 6), axis=(0, 1)), 2, -1)
    rows, cols = (v.ravel() for v in np.meshgrid(np.arange(0, 34, 3), np.arange(1, 31, 4), indexing="ij"))
    workspace = {}
    first = _gather(view, rows, cols, workspace)
    assert np.array_equal(first, view[rows, cols])
    again = _gather(view, rows, cols + 1, workspace)
    assert again is first and np.array_equal(again, view[rows, cols + 1])
    other = _gather(view, rows[: len(rows) // 2], cols[: len(cols) // 2], workspace)
    assert other is not first and np.array_equal(other, view[rows[: len(rows) // 2], cols[: len(cols) // 2]])
    scattered = rng.permutation(len(rows))  # no grid in row-major order: fancy indexing, no workspace
    assert np.array_equal(_gather(view, rows[scattered], cols[scattered], workspace), view[rows, cols][scattered])

    exemplar = rng.random((24, 24, 3)).astype(np.float32)
    centers = grid_centers(img.shape[:2], 6, 3, mode="wrap")
    kwargs = dict(centers=centers, init=None, iterations=2, exemplar_mask=None, pixel_weights=gaussian_falloff(6),
                  mode="wrap", penalty=None)
    plain = patchmatch_features(img, exemplar, 6, rng=np.random.default_rng(1), **kwargs)
    kept = {}
    for _ in range(2):  # the second search reuses the first one's memory
        reused = patchmatch_features(img, exemplar, 6, rng=np.random.default_rng(1), workspace=kept, **kwargs)
        assert np.array_equal(plain[0], reused[0]) and np.array_equal(plain[1], reused[1])
    assert kept["queries"].shape[0] == len(centers)


def test_distances_without_the_penalty_that_ranked_them():
    # with a penalty PatchMatch ranks by distance + penalty; the third value is the held patches' plain
    # weighted distances, which a caller needs as its energy (texture optimization's ρ_p under the copy limit)
    from texsynth.core.search import patchmatch_features

    rng = np.random.default_rng(4)
    img, exemplar = rng.random((30, 30, 3)), rng.random((20, 20, 3))
    g = gaussian_falloff(5)
    centers = grid_centers((30, 30), 5, 2, mode="wrap")
    def penalty(q, c):  # favours the exemplar's left half, strongly enough to change choices
        return 0.5 * (c[:, 1] > 10)
    field, cost, dist = patchmatch_features(img, exemplar, 5, centers=centers, init=None, iterations=3,
                                            exemplar_mask=None, pixel_weights=g, mode="wrap", penalty=penalty,
                                            rng=np.random.default_rng(0))
    q = extract(img, centers, 5, mode="wrap")
    z = extract(exemplar, field[:, 0], 5, mode="valid")
    exact = np.einsum("nhwc,hw->n", (q - z) ** 2, g)
    np.testing.assert_allclose(dist[:, 0], exact, rtol=1e-12)
    np.testing.assert_allclose(cost[:, 0], exact + penalty(None, field[:, 0]), rtol=1e-12)
    assert (field[:, 0, 1] > 10).any() and (cost[:, 0] > dist[:, 0]).any()  # the penalty did apply somewhere
    plain = patchmatch_features(img, exemplar, 5, centers=centers, init=None, iterations=3, exemplar_mask=None,
                                pixel_weights=g, mode="wrap", penalty=None, rng=np.random.default_rng(0))
    assert plain[2] is plain[1]  # without a penalty the costs are the distances
