"""Near-regular texture synthesis on the lattice (texsynth.patch._near_regular), after Liu, Lin & Hays 2004.

The exemplars are grids built here: tiles of random grey levels (or colours) framed by dark grout lines every
``PERIOD`` pixels, with noise; what the output must keep is measured on both sides in each test.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import texsynth
from texsynth.metrics import LATTICE_KEPT_THRESHOLD, lattice_kept
from texsynth.patch import near_regular_texture

PERIOD, GROUT, GROUT_LEVEL = 24, 6, 0.15


def tiles(period=PERIOD, n=5, *, shape=None, grout=GROUT, seed=0, channels=3, shift=(0, 0), noise=0.03):
    """Tiles of random levels in [0.5, 0.9] framed by lines ``grout`` px wide (rows and columns ``0..grout-1``
    of every period, moved by ``shift``), plus Gaussian noise."""
    rng = np.random.default_rng(seed)
    py, px = (period, period) if np.isscalar(period) else period
    h, w = shape if shape is not None else (py * n, px * n)
    rows, cols = np.mgrid[:h, :w]
    rows, cols = rows - shift[0], cols - shift[1]
    levels = rng.uniform(0.5, 0.9, (h // py + 2, w // px + 2, channels))
    image = levels[rows // py + 1, cols // px + 1]
    image[(rows % py < grout) | (cols % px < grout)] = GROUT_LEVEL
    image = np.clip(image + rng.normal(0, noise, image.shape), 0, 1)
    return image[..., 0] if channels == 1 else image


def lines(image, axis):
    """``(centres, widths)`` of the dark lines across an image along ``axis`` (0: horizontal lines, one per run
    of rows whose mean is nearer the grout's level than the tiles'), the runs cut by the border left out."""
    grey = image if image.ndim == 2 else image.mean(-1)
    profile = grey.mean(axis=1 - axis)
    dark = profile < (GROUT_LEVEL + np.median(profile)) / 2
    edges = np.flatnonzero(np.diff(np.r_[0, dark.astype(np.int8), 0]))
    starts, stops = edges[::2], edges[1::2]
    whole = (starts > 0) & (stops < len(profile))
    return (starts + stops - 1)[whole] / 2, (stops - starts)[whole]


def assert_lines_on_lattice(out, ex, period=PERIOD):
    """Both axes: the output's lines lie one period apart (none missing, none extra) and are as wide as the
    exemplar's."""
    for axis in (0, 1):
        p = period if np.isscalar(period) else period[axis]
        centres, widths = lines(out, axis)
        _, ex_widths = lines(ex, axis)
        assert len(centres) >= out.shape[axis] // p - 2, (axis, centres)
        assert np.all(np.abs(np.diff(centres) - p) <= 1), (axis, centres)
        assert np.all(np.abs(widths - np.median(ex_widths)) <= 1), (axis, widths, ex_widths)


# --------------------------------------------------------------------------- the lattice is kept


def test_grout_lines_stay_on_a_lattice_of_the_same_period():
    ex = tiles()
    out, info = near_regular_texture(ex, 240, rng=0, return_info=True)
    assert out.shape == (240, 240, 3)
    assert info.found_by == "dark lines" and info.steps == (PERIOD, PERIOD)
    assert_lines_on_lattice(out, ex)


def test_the_output_keeps_the_exemplars_lattice_as_the_structure_metric_measures_it():
    ex = tiles()
    out = near_regular_texture(ex, 240, rng=0)
    quilted = texsynth.quilt(ex, 240, rng=0)
    kept, quilt_kept = lattice_kept(out, ex), lattice_kept(quilted, ex)
    assert kept >= LATTICE_KEPT_THRESHOLD, (kept, quilt_kept)
    assert kept >= quilt_kept - 0.05, (kept, quilt_kept)  # quilting, same exemplar and size, for comparison


def test_the_lattice_found_is_the_one_the_grid_was_built_on():
    for shift in [(0, 0), (7, 11)]:
        _, info = near_regular_texture(tiles(shift=shift), 96, rng=0, return_info=True)
        py, px, oy, ox = info.lattice
        centre = (GROUT - 1) / 2  # the middle of the grout rows 0..GROUT-1 of each period
        assert abs(py - PERIOD) < 0.1 and abs(px - PERIOD) < 0.1, info.lattice
        assert abs(oy - (shift[0] + centre) % PERIOD) < 0.2 and abs(ox - (shift[1] + centre) % PERIOD) < 0.2


def test_an_explicit_lattice_gives_the_output_of_the_one_found():
    ex = tiles(seed=1)
    out, info = near_regular_texture(ex, 150, rng=3, return_info=True)
    again, info_again = near_regular_texture(ex, 150, lattice=info.lattice, rng=3, return_info=True)
    assert info_again.found_by == "given" and info_again.lattice == info.lattice
    assert np.array_equal(out, again)


def test_oblong_cells_keep_both_families_of_lines():
    period = (12, 36)  # courses of 12 px, elements 36 px long: blocks span three courses
    ex = tiles(period, shape=(120, 144), grout=3, seed=2)
    out, info = near_regular_texture(ex, (200, 216), rng=0, return_info=True)
    assert info.cells == (3, 1) and info.augment == "none"
    assert_lines_on_lattice(out, ex, period)


def test_tileable_output_wraps_round_on_the_lattice():
    ex = tiles(seed=4)
    out = near_regular_texture(ex, (144, 168), tileable=True, rng=0)
    tiled = np.tile(out, (2, 2, 1))
    assert_lines_on_lattice(tiled, ex)
    # no seam where the copies meet: the jump across the border is like the jumps one and more cells inside it
    # (the same place on the lattice: a tile's edge beside a line)
    for axis, n in ((0, 144), (1, 168)):
        jumps = np.abs(np.diff(tiled, axis=axis)).mean(axis=(1 - axis, 2))
        inside = jumps[n - 1 - PERIOD * np.arange(1, n // PERIOD)]
        assert jumps[n - 1] <= 1.5 * inside.max() + 0.02, (axis, jumps[n - 1], inside)


def test_no_cell_beside_a_copy_of_itself_and_every_transform_drawn():
    ex = tiles(seed=5)
    _, info = near_regular_texture(ex, 240, rng=0, return_info=True)
    assert info.augment == "both" and info.n_candidates == 8 * 16  # 4 x 4 whole cells in 5 periods
    n_cols = len(np.unique(info.corners[:, 1]))
    cells = info.cell_indices.reshape(-1, n_cols)
    assert not np.any(cells[:, 1:] == cells[:, :-1]) and not np.any(cells[1:] == cells[:-1])
    assert len(np.unique(info.transforms)) > 1


# --------------------------------------------------------------------------- copies and the coordinate map


@pytest.mark.parametrize("augment", ["none", "both"])
def test_the_coordinate_map_reproduces_the_output(augment):
    ex = tiles(seed=6)
    out, info = near_regular_texture(ex, (130, 170), augment=augment, rng=1, return_info=True)
    assert info.coordinates.shape == (130, 170, 2) and info.weights is None
    assert np.array_equal(texsynth.apply_coordinates(ex, info), out)  # every pixel is a copy
    h, w = ex.shape[:2]
    r, c = info.sources[0]
    assert 0 <= r < h and 0 <= c < w


def test_grey_and_float32_keep_their_layout_and_a_seed_its_output():
    ex = tiles(channels=1, seed=7).astype(np.float32)
    a = near_regular_texture(ex, 100, rng=5)
    b = near_regular_texture(ex, 100, rng=5)
    c = near_regular_texture(ex, 100, rng=6)
    assert a.shape == (100, 100) and a.dtype == np.float32
    assert np.array_equal(a, b) and not np.array_equal(a, c)


# --------------------------------------------------------------------------- errors


def test_no_lattice_raises_naming_lattice_and_the_alternatives():
    noise = np.random.default_rng(0).random((96, 96))
    with pytest.raises(ValueError, match="lattice") as caught:
        near_regular_texture(noise, 128)
    assert "texsynth.quilt" in str(caught.value) and "period_rows" in str(caught.value)


@pytest.mark.parametrize("options, parameter, error", [
    (dict(lattice=(24, 24, 0)), "lattice", ValueError),
    (dict(lattice=(0, 24, 0, 0)), "lattice", ValueError),
    (dict(lattice=(24, 500, 0, 0)), "lattice", ValueError),
    (dict(lattice=(24, 24, float("nan"), 0)), "lattice", ValueError),
    (dict(lattice="grid"), "lattice", ValueError),
    (dict(lattice=24), "lattice", TypeError),
    (dict(overlap=24), "overlap", ValueError),
    (dict(overlap=-1), "overlap", ValueError),
    (dict(overlap=2.5), "overlap", TypeError),
    (dict(error_tolerance=-0.1), "error_tolerance", ValueError),
    (dict(augment="spin"), "augment", ValueError),
    (dict(lattice=(12, 36, 0, 0), augment="rotations"), "augment", ValueError),
    (dict(tileable="yes"), "tileable", TypeError),
    (dict(tileable=True), "tileable", ValueError),  # 100 px is not whole cells of 24
    (dict(rng=-1), "rng", ValueError),
])
def test_bad_options_raise_naming_the_parameter(options, parameter, error):
    with pytest.raises(error, match=parameter):
        near_regular_texture(tiles(), 100, **options)


def test_bad_sizes_and_exemplars_raise_before_any_work():
    ex = tiles()
    with pytest.raises(ValueError, match="size"):
        near_regular_texture(ex, 0)
    with pytest.raises(ValueError, match="size"):  # refused by the memory check, before anything is allocated
        near_regular_texture(ex, (10**6, 10**6))
    with pytest.raises(ValueError, match="exemplar"):
        near_regular_texture(np.full((32, 32), np.nan), 64)


@settings(max_examples=25, deadline=None)
@given(st.one_of(
    st.tuples(st.floats(-50, 1.9), st.floats(2, 100), st.integers(0, 50), st.integers(0, 50)),
    st.tuples(st.integers(2, 100), st.integers(121, 10**4), st.integers(0, 50), st.integers(0, 50)),
    st.lists(st.integers(2, 50), min_size=0, max_size=3).map(tuple),
    st.lists(st.integers(2, 50), min_size=5, max_size=6).map(tuple),
    st.text(min_size=1, max_size=8).filter(lambda s: s != "auto"),
))
def test_any_bad_lattice_raises_naming_lattice(value):
    with pytest.raises((ValueError, TypeError)) as caught:
        near_regular_texture(tiles(), 64, lattice=value)
    assert "lattice" in str(caught.value), (value, caught.value)
