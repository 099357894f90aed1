"""The shared neighbourhood layer: extraction, scatter-average, grids, masks."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texsynth.core.neighborhood import (PatchSum, accumulate, all_patches, causal_mask, extract, gaussian_falloff,
                                       grid_centers, multilevel_vectors, patches_within, _patch_coords)


@pytest.fixture
def brick(texture):
    return texture("jcjohnson/brick.png", (40, 48))


def _all_centers(shape):
    return np.argwhere(np.ones(shape, bool))


@pytest.mark.parametrize("mode", ["wrap", "reflect"])
@pytest.mark.parametrize("size", [1, 3, 4, (5, 2)])
def test_scatter_average_of_every_patch_reproduces_the_image_exactly(brick, mode, size):
    centers = _all_centers(brick.shape[:2])
    patches = extract(brick, centers, size, mode=mode)
    out, weight = accumulate(patches, centers, brick.shape[:2], mode=mode)
    assert np.abs(out - brick).max() < 1e-12
    h, w = (size, size) if np.isscalar(size) else size
    if mode == "wrap":
        assert np.all(weight == h * w)  # on a torus every pixel lies in exactly h*w patches
    else:  # reflect folds outside pixels onto their mirror images: no weight is lost
        assert weight.sum() == len(centers) * h * w and weight.min() >= 1


def test_scatter_average_on_a_sparse_valid_grid_reproduces_the_image(brick):
    centers = grid_centers(brick.shape[:2], 8, 2, mode="valid")
    patches = extract(brick, centers, 8, mode="valid")
    out, weight = accumulate(patches, centers, brick.shape[:2], pixel_weights=gaussian_falloff(8),
                             patch_weights=np.linspace(0.5, 2, len(centers)), mode="valid")
    assert weight.min() > 0  # the grid covers the border too
    assert np.abs(out - brick).max() < 1e-12


def test_per_patch_pixel_weights_weight_each_patch_pixel(brick):
    centers = _all_centers(brick.shape[:2])[::7]
    patches = extract(brick, centers, 5)
    pixel = np.random.default_rng(1).random((len(centers), 5, 5)) + 0.1
    out, weight = accumulate(patches, centers, brick.shape[:2], pixel_weights=pixel)
    covered = weight > 0
    # an independent loop over patches: sum of weighted values / sum of weights per pixel
    num = np.zeros(brick.shape)
    den = np.zeros(brick.shape[:2])
    for (r, c), patch, wgt in zip(centers, patches, pixel):
        rows = (r - 2 + np.arange(5)) % brick.shape[0]
        cols = (c - 2 + np.arange(5)) % brick.shape[1]
        num[np.ix_(rows, cols)] += patch * wgt[..., None]
        den[np.ix_(rows, cols)] += wgt
    assert np.allclose(weight, den)
    assert np.allclose(out[covered], num[covered] / den[covered, None])


def test_accumulate_is_a_weighted_average():
    patches = np.stack([np.zeros((1, 1, 1)), np.ones((1, 1, 1))])
    out, weight = accumulate(patches, [[0, 0], [0, 0]], (1, 2), patch_weights=[1.0, 3.0], mode="valid")
    assert out[0, 0, 0] == pytest.approx(0.75) and weight[0, 0] == 4.0
    assert out[0, 1, 0] == 0.0 and weight[0, 1] == 0.0  # uncovered pixels are 0 with zero weight


def test_all_patches_agrees_with_extract(brick):
    for mode in ("valid", "wrap", "reflect"):
        view = all_patches(brick, (5, 3), mode=mode)
        if mode == "valid":
            corners = np.array([[7, 11], [0, 0], [view.shape[0] - 1, view.shape[1] - 1]])
            centers = corners + [5 // 2, 3 // 2]
        else:
            corners = centers = np.array([[0, 0], [7, 11], [39, 47]])
        got = extract(brick, centers, (5, 3), mode=mode)
        assert np.array_equal(view[corners[:, 0], corners[:, 1]], got)
    assert not view.flags.writeable or view.base is not None  # a view, no copy per patch


def test_wrap_and_reflect_boundaries():
    img = np.arange(5.0).reshape(1, 5, 1).repeat(3, axis=0)
    wrap = extract(img, [[1, 0]], (1, 3), mode="wrap")[0, 0, :, 0]
    refl = extract(img, [[1, 0]], (1, 3), mode="reflect")[0, 0, :, 0]
    assert wrap.tolist() == [4, 0, 1] and refl.tolist() == [1, 0, 1]
    with pytest.raises(ValueError, match="mode='valid'"):
        extract(img, [[1, 0]], (1, 3), mode="valid")


def test_grids_cover_and_respect_spacing():
    for mode in ("wrap", "reflect", "valid"):
        centers = grid_centers((37, 29), 8, 2, mode=mode)
        patches = np.ones((len(centers), 8, 8, 1))
        _, weight = accumulate(patches, centers, (37, 29), mode=mode)
        assert weight.min() > 0
    assert len(grid_centers((32, 32), 8, 2, mode="wrap")) == 16 * 16
    with pytest.raises(ValueError, match="gaps"):
        grid_centers((32, 32), 4, 5)


def test_causal_mask_is_what_scanline_order_has_already_visited():
    for size in (3, 5, (5, 7)):
        mask = causal_mask(size)
        h, w = mask.shape
        order = np.arange(h * w).reshape(h, w)
        assert np.array_equal(mask, order < order[h // 2, w // 2])


def test_gaussian_falloff_shape():
    g = gaussian_falloff((5, 7), sigma=1.5)
    assert g.shape == (5, 7) and g.max() == 1.0 == g[2, 3]
    assert np.allclose(g, g[::-1, ::-1])
    with pytest.raises(ValueError, match="sigma"):
        gaussian_falloff(5, sigma=0)


def test_multilevel_vectors_take_the_parent_under_the_pixel():
    fine = np.zeros((8, 8, 1))
    parent = np.arange(16.0).reshape(4, 4, 1)
    v = multilevel_vectors(fine, parent, [[5, 6]], 3, 1)
    assert v.shape == (1, 10) and v[0, -1] == parent[2, 3, 0]


@pytest.mark.parametrize("call, match", [
    (lambda img: extract(img, [[0, 0]], 50), "larger than the image"),
    (lambda img: extract(img[..., 0], [[0, 0]], 3), r"channels-last"),
    (lambda img: extract(img, [[0.5, 0]], 3), "integer array"),
    (lambda img: extract(img, [[0, 0]], 3, mode="mirror"), "mode must be one of"),
    (lambda img: extract(img, [[0, 0]], 0), "size must be positive"),
    (lambda img: accumulate(np.ones((2, 3, 3, 1)), [[0, 0]], (8, 8)), "one centre per patch"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), patch_weights=[-1.0]), "non-negative"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), pixel_weights=np.ones((2, 2))),
     "pixel_weights"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), patch_weights=[np.nan]), "finite"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (0, 8)), "shape must be positive"),
    (lambda img: grid_centers((0, 8), 3, 1), "shape must be positive"),
    (lambda img: grid_centers((8, 8), 3, 0), "spacing must be positive"),
    (lambda img: patches_within(np.ones(8, bool), 2), r"mask must be .*\(H, W\).* got shape \(8,\)"),
    (lambda img: patches_within(np.ones((8, 8, 2), bool), 2), r"mask must be .*\(H, W\)"),
    (lambda img: all_patches(img, 2, mode=np.array(["wrap", "valid"])), "mode must be one of 'valid', 'wrap'"),
    (lambda img: all_patches(img, 2, mode=["wrap"]), r"mode must be one of .*, got list"),
    (lambda img: extract(img, [[0, 0]], 3, mode=np.array(["wrap", "valid"])), "mode must be one of"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), mode=np.array(["wrap", "x"])),
     "mode must be one of"),
    (lambda img: grid_centers((8, 8), 3, 1, mode=np.array(["wrap", "x"])), "mode must be one of"),
    (lambda img: gaussian_falloff(3, sigma="x"), "sigma must be a real number"),
    (lambda img: gaussian_falloff(3, sigma=[1.0]), "sigma must be a real number"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), patch_weights="x"),
     "patch_weights must be .*numbers"),
    (lambda img: accumulate(np.ones((1, 3, 3, 1)), [[0, 0]], (8, 8), pixel_weights=[[1], [1, 2]]),
     "pixel_weights must be .*numbers"),
])
def test_bad_input(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call(np.zeros((8, 8, 1)))


@settings(max_examples=25, deadline=None)
@given(h=st.integers(1, 12), w=st.integers(1, 12), c=st.integers(1, 4),
       ph=st.integers(1, 6), pw=st.integers(1, 6), mode=st.sampled_from(["wrap", "reflect"]),
       seed=st.integers(0, 2**16), dtype=st.sampled_from([np.float64, np.float32, np.uint8]))
def test_extract_then_accumulate_is_identity_property(h, w, c, ph, pw, mode, seed, dtype):
    img = np.random.default_rng(seed).random((h, w, c))
    img = (img * 255).astype(dtype) if dtype == np.uint8 else img.astype(dtype)
    if ph > h or pw > w:
        with pytest.raises(ValueError, match="larger than the image"):
            extract(img, [[0, 0]], (ph, pw), mode=mode)
        return
    centers = _all_centers((h, w))
    patches = extract(img, centers, (ph, pw), mode=mode)
    assert patches.dtype == img.dtype  # extraction copies values, whatever their type
    out, _ = accumulate(patches, centers, (h, w), mode=mode)
    assert out.dtype == (np.float32 if dtype == np.float32 else np.float64)
    assert np.allclose(out, img, atol=1e-5 if dtype == np.float32 else 1e-12)


@pytest.mark.parametrize("mode", ["valid", "wrap"])
@pytest.mark.parametrize("shape,size,spacing", [((37, 41), 8, 2), ((30, 30), 7, 3), ((16, 20), 5, 5), ((9, 9), 9, 4)])
def test_patch_sum_grid_blocks_equal_the_scatter(mode, shape, size, spacing):
    # grids (irregular last row and column in valid mode, a short wrap-around gap in wrap mode) go
    # through the block path; the reference adds the same patches with bincount
    rng = np.random.default_rng(1)
    centers = grid_centers(shape, size, spacing, mode=mode)
    patches = rng.random((len(centers), size, size, 2))
    aw, pw = rng.random(len(centers)), rng.random((len(centers), size, size))
    grid = PatchSum(shape, 2, mode=mode)
    grid.add(patches, centers, patch_weights=aw, pixel_weights=pw)
    assert grid._grid(centers, (size, size)) is not None
    scatter = PatchSum(shape, 2, mode=mode)
    rows, cols = _patch_coords(centers, (size, size), shape, mode)
    scatter._scatter(patches, rows, cols, aw, pw)
    np.testing.assert_allclose(grid.average()[0], scatter.average()[0], rtol=1e-12)
    np.testing.assert_allclose(grid.total, scatter.total, rtol=1e-12)


def test_patch_sum_in_parts_equals_accumulate():
    rng = np.random.default_rng(2)
    centers = grid_centers((40, 33), 6, 2, mode="wrap")
    patches = rng.random((len(centers), 6, 6, 3))
    whole = accumulate(patches, centers, (40, 33), pixel_weights=gaussian_falloff(6), mode="wrap")[0]
    acc = PatchSum((40, 33), 3, mode="wrap")
    ncols = len(np.unique(centers[:, 1]))
    for rows in np.array_split(np.arange(len(centers) // ncols), 4):  # whole grid rows: still grids
        part = (rows[:, None] * ncols + np.arange(ncols)).ravel()
        acc.add(patches[part], centers[part], pixel_weights=gaussian_falloff(6))
    np.testing.assert_allclose(acc.average()[0], whole, rtol=1e-12)


@pytest.mark.parametrize("mode", ["valid", "wrap"])
def test_patch_sum_on_threads_is_bit_identical(monkeypatch, mode):
    # the block path splits each phase's grid rows among threads; the patches of a phase do not overlap,
    # so every pixel receives the same additions in the same order: the same sums, bit for bit (a race or
    # a wrong split would change or lose some of them)
    from texsynth.core import neighborhood

    rng = np.random.default_rng(3)
    shape = (61, 47)
    centers = grid_centers(shape, 8, 2, mode=mode)
    patches = rng.random((len(centers), 8, 8, 3))
    aw = rng.random(len(centers))
    sums = []
    for threads in (1, 2, 3):
        monkeypatch.setattr(neighborhood, "_THREADED_VALUES", 0)
        monkeypatch.setattr(neighborhood, "max_threads", lambda t=threads: t)
        acc = PatchSum(shape, 3, mode=mode)
        acc.add(patches, centers, patch_weights=aw, pixel_weights=gaussian_falloff(8))
        sums.append((acc.sums.copy(), acc.total.copy()))
    for s, t in sums[1:]:
        assert np.array_equal(s, sums[0][0]) and np.array_equal(t, sums[0][1])
    reference = accumulate(patches, centers, shape, patch_weights=aw, pixel_weights=gaussian_falloff(8), mode=mode)[0]
    np.testing.assert_allclose(acc.average()[0], reference, rtol=1e-12)


def test_patches_within_matches_the_windows_minimum():
    # the summed-area table must give exactly the patches whose every pixel is True (the brute-force minimum
    # over all_patches' windows), for masks with isolated and clustered holes and non-square patches
    from texsynth.core.neighborhood import patches_within

    rng = np.random.default_rng(7)
    for _ in range(40):
        shape = tuple(int(v) for v in rng.integers(4, 30, 2))
        mask = rng.random(shape) > rng.choice([0.02, 0.2, 0.6])
        size = tuple(int(v) for v in rng.integers(1, min(shape) + 1, 2))
        brute = all_patches(mask[..., None].astype(float), size).min(axis=(2, 3, 4)) > 0.5
        assert np.array_equal(patches_within(mask, size), brute)
    assert patches_within(np.ones((5, 6), bool), (5, 6)).tolist() == [[True]]
    assert not patches_within(np.zeros((5, 6), bool), 1).any()


def test_patch_sum_keeps_tiny_weights_of_float32_patches():
    # Wexler's confidence weighs a neighbourhood far from the known pixels by 1.3^-d (1e-102 for d = 900 px of
    # an uncrop): weighted in float32 the patch underflowed to 0 while the total kept the weight, and the average
    # came out black (bars of black pixels in a 512 -> 1024 uncrop of pebbles_1)
    from texsynth.core.neighborhood import PatchSum, grid_centers

    centers = grid_centers((32, 32), 8, 2, mode="wrap")
    patches = np.full((len(centers), 8, 8, 3), 0.5, dtype=np.float32)
    total = PatchSum((32, 32), 3, mode="wrap")
    total.add(patches, centers, patch_weights=np.full(len(centers), 1e-102))
    mean, weight = total.average()
    assert np.all(weight > 0)
    np.testing.assert_allclose(mean, 0.5, rtol=1e-6)


# --------------------------------------------------------------------------- footprints, scanline parts, volumes
def test_footprints_and_causal_parts():
    from texsynth.core.neighborhood import causal_parts, footprint, mask_offsets

    assert footprint(3, "disc").all() and footprint((5, 5), "disc").sum() == 21
    assert footprint((9, 9), "disc").sum() == 69 and footprint((4, 6), "square").all()
    disc = footprint((5, 9), "disc")  # an ellipse: the centre row whole, the corners out
    assert disc[2].all() and not disc[0, :2].any() and np.array_equal(disc, disc[::-1, ::-1])
    for shape in ("square", "disc"):
        above, left, full = causal_parts(5, shape)
        foot = footprint(5, shape)
        assert np.array_equal(above | left, causal_mask(5) & foot)  # the causal part of the footprint
        assert not (above & left).any() and not full[2, 2]
        assert np.array_equal(full, foot & ~(np.arange(25).reshape(5, 5) == 12))
        assert left.sum() == 2 and np.array_equal(left[2], [True, True, False, False, False])
    np.testing.assert_array_equal(mask_offsets(np.eye(3, dtype=bool)), [[-1, -1], [0, 0], [1, 1]])
    with pytest.raises(ValueError, match="shape must be one of 'square', 'disc'"):
        footprint(5, "circle")


def test_wavefronts_order_every_causal_neighbour_first():
    from texsynth.core.neighborhood import causal_parts, mask_offsets, wavefronts

    height, width, size = 7, 9, (5, 5)
    order, bounds = wavefronts(height, width, size[1] // 2 + 1)
    assert np.array_equal(np.sort(order), np.arange(height * width))
    front = np.empty(height * width, int)
    for t in range(len(bounds) - 1):
        front[order[bounds[t]:bounds[t + 1]]] = t
    front = front.reshape(height, width)
    above, left, full = causal_parts(size)
    for r in range(height):
        for c in range(width):
            for dr, dc in mask_offsets(above | left):  # causal neighbours inside the image: on earlier fronts
                if 0 <= r + dr < height and 0 <= c + dc < width:
                    assert front[r + dr, c + dc] < front[r, c]
            for dr, dc in mask_offsets(full & ~(above | left)):  # the others: on later fronts
                if 0 <= r + dr < height and 0 <= c + dc < width:
                    assert front[r + dr, c + dc] > front[r, c]


def test_multilevel_vectors_masks_and_parent_alone():
    from texsynth.core.neighborhood import footprint

    rng = np.random.default_rng(0)
    img, par = rng.random((12, 12, 2)), rng.random((6, 6, 2))
    centers = [[5, 6], [0, 11]]
    disc = footprint(5, "disc")
    v = multilevel_vectors(img, par, centers, 5, 5, mask=causal_mask(5), parent_mask=disc)
    here = extract(img, centers, 5)[:, causal_mask(5)].reshape(2, -1)
    there = extract(par, np.asarray(centers) // 2, 5)[:, disc].reshape(2, -1)
    assert np.array_equal(v, np.concatenate([here, there], 1))
    assert np.array_equal(multilevel_vectors(img, None, centers, 5, 5, mask=causal_mask(5)), here)
    with pytest.raises(ValueError, match="parent_mask must have shape"):
        multilevel_vectors(img, par, centers, 5, 3, parent_mask=disc)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_plane_vectors_are_each_slices_windows(axis):
    from texsynth.core.neighborhood import footprint, plane_vectors

    rng = np.random.default_rng(axis)
    vol, par = rng.random((10, 11, 12, 2)), rng.random((5, 6, 6, 2))
    mask = footprint(3, "disc") & ~np.eye(3, dtype=bool)
    got = plane_vectors(vol, par, axis, 3, 3, mask=mask).reshape(10, 11, 12, -1)
    for voxel in [(0, 0, 0), (9, 10, 11), (4, 7, 2)]:
        plane = np.moveaxis(vol, axis, 0)[voxel[axis]]  # the slice across the axis, its own 2-D image
        parent = np.moveaxis(par, axis, 0)[voxel[axis] // 2]
        centre = [tuple(v for a, v in enumerate(voxel) if a != axis)]
        want = multilevel_vectors(plane, parent, centre, 3, 3, mask=mask)[0]
        np.testing.assert_array_equal(got[voxel], want)
