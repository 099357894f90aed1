"""Exemplar augmentation (``Search(augment=...)``, ``quilt(augment=...)``): the exemplar's flipped and rotated
copies as more candidates, with every source-coordinate map still pointing into the exemplar itself."""

import numpy as np
import pytest
from scipy import ndimage

import texsynth as ts
from texsynth.core.em import ExemplarPatches, Schedule
from texsynth.core.pyramid import gaussian_pyramid
from texsynth.core.search import AUGMENTS, ExemplarAtlas, Search, augmentations, augmented_set
from texsynth.data import load
from texsynth.pixel import Neighborhood

L2 = Neighborhood(levels=2)
KW = Schedule(neighborhood_sizes=(16, 8), levels=2, max_iterations=3)


def _exemplar(shape=(20, 27)):
    """A non-square colour exemplar whose every pixel differs from every other."""
    rng = np.random.default_rng(7)
    return rng.random(shape + (3,))


def _stripes(n=32, period=8):
    """Vertical stripes: the value varies along the columns only."""
    return np.tile(0.5 + 0.4 * np.sin(2 * np.pi * np.arange(n) / period), (n, 1))


def _horizontal_share(image, window=8):
    """Share of the pixels whose surroundings vary along the rows (horizontal stripes) 4x more than along the
    columns."""
    dy = ndimage.uniform_filter(np.diff(image, axis=0)[:, :-1] ** 2, window)
    dx = ndimage.uniform_filter(np.diff(image, axis=1)[:-1] ** 2, window)
    return float(np.mean(dy > 4 * dx))


# --------------------------------------------------------------------------- the augmented set
def test_augmented_set_holds_the_transforms():
    ex = _exemplar()
    expected = {
        "none": [ex],
        "flips": [ex, ex[:, ::-1], ex[::-1]],
        "rotations": [np.rot90(ex, k) for k in range(4)],
        "both": [np.rot90(ex, k) for k in range(4)] + [np.rot90(ex[:, ::-1], k) for k in range(4)],
    }
    for augment in AUGMENTS:
        got = augmented_set(ex, augment)
        assert len(got) == len(expected[augment]) == len(augmentations(augment))
        for a, b in zip(got, expected[augment]):
            np.testing.assert_array_equal(a, b)
    both = augmented_set(ex[:20, :20], "both")  # the eight symmetries of the square are all different
    assert len({a.tobytes() for a in both}) == 8


@pytest.mark.parametrize("augment", ["flips", "rotations", "both"])
def test_atlas_pixels_show_the_exemplar_pixels_their_origin_names(augment):
    ex = _exemplar((21, 26))
    levels = 3
    atlas = ExemplarAtlas(ex.shape[:2], augment, levels=levels)
    image, valid = atlas.apply(ex)
    origin = atlas.origin()
    assert np.array_equal(valid, origin[..., 0] >= 0) and valid.sum() == len(atlas) * ex.shape[0] * ex.shape[1]
    np.testing.assert_array_equal(image[valid], ex[origin[valid][:, 0], origin[valid][:, 1]])
    # every exemplar pixel is shown once per copy
    counts = np.zeros(ex.shape[:2], int)
    np.add.at(counts, (origin[valid][:, 0], origin[valid][:, 1]), 1)
    assert np.all(counts == len(atlas))
    # the layout holds at every level: corners halve, copies keep a gap, their own pyramid fits
    pyramid = atlas.pyramid(ex, levels, gaussian_pyramid)
    for level in range(levels):
        corners = atlas.corners(level)
        np.testing.assert_array_equal(corners, atlas.corners(0) >> level)
        ends = corners[:, 1] + np.array([w for _, w in atlas.tile_shapes(level)])
        assert np.all(ends[:-1] < corners[1:, 1])  # at least one gap column
        for t, transform in enumerate(atlas.transforms):
            np.testing.assert_array_equal(atlas.tiles(pyramid)[t][level],
                                          gaussian_pyramid(np.ascontiguousarray(transform.apply(ex)), levels)[level])


def test_every_neighbourhood_of_an_augmented_exemplar_is_a_transformed_exemplar_neighbourhood():
    ex = _exemplar((18, 23))
    patches = ExemplarPatches(ex, np.ones(ex.shape[:2]), 6, atlas=ExemplarAtlas(ex.shape[:2], "both"))
    assert len(patches) == 8 * (18 - 5) * (23 - 5)
    rows, cols = np.meshgrid(np.arange(6), np.arange(6), indexing="ij")
    for i in np.random.default_rng(0).choice(len(patches), 60, replace=False):
        corner = patches.corner[i]
        where = patches.to_exemplar(np.stack([corner[0] + rows, corner[1] + cols], axis=-1))
        np.testing.assert_array_equal(patches.patches(np.array([i]))[0], ex[where[..., 0], where[..., 1]])
    assert patches.own.sum() == (18 - 5) * (23 - 5)  # the exemplar's own neighbourhoods: the first copy


# --------------------------------------------------------------------------- maps into the exemplar
@pytest.mark.parametrize("augment", ["flips", "rotations", "both"])
def test_copy_methods_coordinates_render_their_output(augment):
    ex = load("bumpy")[:30, :37]  # not square: a quarter turn has its own shape
    search = Search(augment=augment)
    out, info = ts.synthesize_pixels(ex, 28, neighborhood=L2, search=search, rng=0, return_info=True)
    np.testing.assert_array_equal(ts.apply_coordinates(ex, info), out)
    out, info = ts.synthesize_pixels(ex, 28, neighborhood=L2, order="independent", search=search, rng=0,
                                     return_info=True)
    np.testing.assert_array_equal(ts.apply_coordinates(ex, info), out)
    out, info = ts.efros_leung(ex[:20, :23], 20, neighborhood_size=5, search=search, rng=0, return_info=True)
    np.testing.assert_array_equal(ts.apply_coordinates(ex[:20, :23], info), out)
    out, info = ts.quilt(ex, 64, block=16, augment=augment, rng=0, return_info=True)
    np.testing.assert_array_equal(ts.apply_coordinates(ex, info), out)
    out, info = ts.patch_sampling(ex, 64, block=16, augment=augment, rng=0, return_info=True)
    np.testing.assert_allclose(ts.apply_coordinates(ex, info), out, atol=1e-12)
    b = load("brick")[:26, :34]
    out, info = ts.mix_textures([ex, b], 20, neighborhood=L2, max_iterations=2, search=search, rng=0,
                                return_info=True)
    np.testing.assert_allclose(ts.apply_coordinates([ex, b], info), out, atol=1e-12)


@pytest.mark.parametrize("augment", ["flips", "both"])
def test_texture_optimization_map_points_into_the_exemplar(augment):
    ex = load("bumpy")[:40, :48]
    out, info = ts.optimize_texture(ex, 56, schedule=KW, search=Search(augment=augment), rng=0, return_info=True)
    c = info.coordinates
    assert c.shape == (56, 56, 2) and c.min() >= 0 and np.all(c.max(axis=(0, 1)) < ex.shape[:2])
    assert info.sources.min() >= 0 and np.all(info.sources.max(axis=0) < ex.shape[:2])
    # the dominant copy map reproduces the blend about as closely as without augmentation
    rendered = np.abs(ts.apply_coordinates(ex, info) - out).mean()
    plain, plain_info = ts.optimize_texture(ex, 56, schedule=KW, rng=0, return_info=True)
    assert rendered < 0.05 and rendered < 10 * np.abs(ts.apply_coordinates(ex, plain_info) - plain).mean()


def test_a_match_in_a_turned_copy_maps_to_the_pixel_it_shows():
    # an exemplar whose pixels all differ: a copy's output pixel names one exemplar pixel by its value
    ex = _exemplar((12, 17))[..., :1]
    out, info = ts.quilt(ex, 32, block=8, augment="rotations", rng=3, return_info=True)
    c = info.coordinates
    np.testing.assert_array_equal(ex[c[..., 0], c[..., 1]], out)
    # along an output row, a copy of the exemplar steps one column right; a quarter turn steps along its rows
    step = c[:, 1:] - c[:, :-1]
    assert np.any(np.all(np.abs(step) == (1, 0), axis=-1))
    assert np.any(np.all(step == (0, 1), axis=-1))  # and the exemplar itself is used too


# --------------------------------------------------------------------------- none is the default
def test_augment_none_is_the_default():
    ex = load("bumpy")[:32, :32]
    none = Search(augment="none")
    assert Search() == none
    np.testing.assert_array_equal(ts.synthesize_pixels(ex, 24, neighborhood=L2, search=none, rng=1),
                                  ts.synthesize_pixels(ex, 24, neighborhood=L2, rng=1))
    np.testing.assert_array_equal(ts.optimize_texture(ex, 40, schedule=KW, search=none, rng=1),
                                  ts.optimize_texture(ex, 40, schedule=KW, rng=1))
    np.testing.assert_array_equal(ts.efros_leung(ex[:20, :20], 16, neighborhood_size=5, search=none, rng=1),
                                  ts.efros_leung(ex[:20, :20], 16, neighborhood_size=5, rng=1))
    np.testing.assert_array_equal(ts.quilt(ex, 48, block=12, augment="none", rng=1), ts.quilt(ex, 48, block=12, rng=1))


# --------------------------------------------------------------------------- refusals
def test_bad_values_are_refused_naming_augment():
    with pytest.raises(ValueError, match="augment must be one of 'none', 'flips', 'rotations', 'both'"):
        Search(augment="flip")
    with pytest.raises(TypeError, match="augment"):
        Search(augment=True)
    with pytest.raises(ValueError, match="augment"):
        ts.quilt(load("bumpy"), 48, augment="mirror")


def test_methods_that_cannot_use_it_refuse_it():
    ex = load("bumpy")[:32, :32]
    both = Search(augment="both")
    calls = {
        "synthesize_solid": lambda: ts.synthesize_solid([ex], 8, search=both),
        "synthesize_controlled": lambda: ts.synthesize_controlled(ex, 24, search=Search(candidates="k-coherent",
                                                                                         augment="both")),
        "animate_texture": lambda: ts.animate_texture(ex, np.zeros((24, 24, 2)), n_frames=2, search=both),
        "interpolate_textures": lambda: ts.interpolate_textures(ex, ex, 0.5, search=both),
        "synthesize_surface": lambda: ts.synthesize_surface(ts.surface.sphere(100), ex, search=both),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError, match=f"augment='both' is not available in {name}") as err:
            call()
        assert "optimize_texture, synthesize_pixels" in str(err.value) and "augment='none'" in str(err.value)
    with pytest.raises(ValueError, match="k-coherent.*augment|augment.*k-coherent"):
        ts.synthesize_pixels(ex, 24, search=Search(candidates="k-coherent", augment="flips"))
    with pytest.raises(ValueError, match="k-coherent.*augment|augment.*k-coherent"):
        ts.optimize_texture(ex, 40, schedule=KW, search=Search(candidates="k-coherent", augment="flips"))


# --------------------------------------------------------------------------- what it does
def test_rotations_turn_vertical_stripes_horizontal_somewhere():
    """An exemplar of vertical stripes: with augment="rotations" the syntheses hold horizontal stripes, which
    without it they do not (both sides measured here, over four seeds)."""
    ex = _stripes()
    seeds = range(4)
    share = {}
    for augment in ("none", "rotations"):
        search = Search(augment=augment)
        share[augment, "pixels"] = [_horizontal_share(ts.synthesize_pixels(ex, 48, neighborhood=L2, search=search,
                                                                           rng=s)) for s in seeds]
        share[augment, "optimize"] = [_horizontal_share(ts.optimize_texture(ex, 48, schedule=KW, search=search,
                                                                            rng=s)) for s in seeds]
    for method in ("pixels", "optimize"):
        none, turned = np.mean(share["none", method]), np.mean(share["rotations", method])
        assert turned > 0.15 and turned > 2.5 * none + 0.05, (method, share)
    # texture optimization keeps the stripes upright without it, and turns some in every seed with it
    assert max(share["none", "optimize"]) < 0.05 < min(share["rotations", "optimize"])
