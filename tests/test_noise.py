"""Tests of Perlin noise (texsynth.procedural._noise: perlin, band_limit_octaves).

The properties are those the lecture slides list for Perlin's noise (value 0 on
the lattice, band limit, translation invariance, seeds). Thresholds were
calibrated on this implementation and on a counter-example that must fail (white
noise, a rescaled distribution, a non-periodic lattice); each comment gives both.
The bad-input strategies below are shared with tests/test_patterns.py and
tests/test_reaction_diffusion.py.
"""

from __future__ import annotations

import inspect
import math
import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import ks_2samp

import texsynth.procedural._noise as noise_module
from texsynth.procedural import band_limit_octaves, perlin, turbulence
from texsynth.procedural._noise import _GRADIENTS, _GRADIENTS_2D, permutation

from _bad_input import bad_input_tests

# --------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------


def _scalar_perlin(x, y, z, perm):
    """Perlin's 2002 reference algorithm, one point at a time (independent of the vectorised code)."""

    def fade(t):
        return t * t * t * (t * (t * 6 - 15) + 10)

    def lerp(t, a, b):
        return a + t * (b - a)

    def grad(h, dx, dy, dz):
        g = _GRADIENTS[h & 15]
        return g[0] * dx + g[1] * dy + g[2] * dz

    X, Y, Z = int(np.floor(x)) & 255, int(np.floor(y)) & 255, int(np.floor(z)) & 255
    x, y, z = x - np.floor(x), y - np.floor(y), z - np.floor(z)
    u, v, w = fade(x), fade(y), fade(z)
    p = perm
    A = p[X] + Y
    AA, AB = p[A] + Z, p[A + 1] + Z
    B = p[X + 1] + Y
    BA, BB = p[B] + Z, p[B + 1] + Z
    return lerp(w, lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
                        lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(p[AB + 1], x, y - 1, z - 1), grad(p[BB + 1], x - 1, y - 1, z - 1))))


def _scalar_perlin_2d(x, y, perm):
    """The 2-D version: hash P[P[P[x] + y]], gradients of the 2-D table."""
    fade = lambda t: t * t * t * (t * (t * 6 - 15) + 10)  # noqa: E731
    X, Y = int(np.floor(x)), int(np.floor(y))
    fx, fy = x - X, y - Y
    total = 0.0
    for cx in (0, 1):
        for cy in (0, 1):
            h = perm[perm[perm[(X + cx) & 255] + ((Y + cy) & 255)]] & 15
            g = _GRADIENTS_2D[h]
            wx = fade(fx) if cx else 1 - fade(fx)
            wy = fade(fy) if cy else 1 - fade(fy)
            total += wx * wy * (g[0] * (fx - cx) + g[1] * (fy - cy))
    return total


def _radial_power(img):
    """Power spectrum and radial frequency (cycles per image) of a square image."""
    power = np.abs(np.fft.fft2(img - img.mean())) ** 2
    k = np.fft.fftfreq(img.shape[0]) * img.shape[0]
    return power, np.hypot(k[:, None], k[None, :])


def _grid_points(shape, frequency, offset):
    """The lattice coordinates (x, y[, z]) of every grid sample, in C order."""
    s = frequency / max(shape)
    return np.indices(shape).reshape(len(shape), -1)[::-1].T * s + np.asarray(offset)


# --------------------------------------------------------------------------
# Perlin noise
# --------------------------------------------------------------------------


def test_matches_perlins_reference_algorithm():
    # Scalar transcription of Perlin 2002 with the same permutation: agreement to
    # rounding (1e-12) shows hash, gradients, fade and interpolation are Perlin's
    # (3-D); 2-D uses the same hash at z = 0 with the 8-direction 2-D table.
    perm = permutation(5)
    pts = np.random.default_rng(0).uniform(-20, 300, size=(200, 3))
    ours3 = perlin(points=pts, rng=5)
    ref3 = [_scalar_perlin(x, y, z, perm) for x, y, z in pts]
    np.testing.assert_allclose(ours3, ref3, atol=1e-12)
    ours2 = perlin(points=pts[:, :2], rng=5)
    ref2 = [_scalar_perlin_2d(x, y, perm) for x, y, _ in pts]
    np.testing.assert_allclose(ours2, ref2, atol=1e-12)


@pytest.mark.parametrize("shape,frequency", [((37, 53), 3.0), ((40, 40), 17.5), ((9, 11, 13), 4.0), ((12, 6, 7), 9.0),
                                             ((64, 48), 2000.0), ((5, 4, 333), 1700.0), ((3, 1, 700), 9000.0)])
def test_grid_equals_points(shape, frequency):
    # The separable grid evaluation must give the point evaluation's numbers
    # (float64 rounding only), with offset and period; also finer than a pixel,
    # where only the lattice cells under the samples are hashed (and 3-D rows
    # are one-row products over whole gemv blocks).
    ndim = len(shape)
    offset = (0.3, 1.7, 2.2)[:ndim]
    period = (3, 5, 7)[:ndim]
    grid = perlin(shape, frequency=frequency, offset=offset, period=period, rng=3)
    pts = perlin(points=_grid_points(shape, frequency, offset), period=period, rng=3)
    np.testing.assert_allclose(grid.ravel(), pts, atol=1e-12)
    g32 = perlin(shape, frequency=frequency, offset=offset, period=period, rng=3, dtype=np.float32)
    assert g32.dtype == np.float32
    np.testing.assert_allclose(g32, grid, atol=2e-5)  # float32 rounding of weights in [0, 1]


@pytest.mark.parametrize("fade", ["quintic", "cubic"])
def test_zero_at_lattice_points(fade):
    img = perlin((64, 64), frequency=8, rng=0, fade=fade)  # 8 px per cell
    assert np.all(img[::8, ::8] == 0)
    assert np.abs(img).max() > 0.3  # ... and not zero elsewhere
    vol = perlin((16, 16, 16), frequency=4, rng=0, fade=fade)
    assert np.all(vol[::4, ::4, ::4] == 0)
    ints = np.random.default_rng(1).integers(-500, 500, size=(50, 3)).astype(float)
    assert np.all(perlin(points=ints, rng=2, fade=fade) == 0)


def test_cubic_and_quintic_differ_between_lattice_points():
    q = perlin((32, 32), frequency=4, rng=0, fade="quintic")
    c = perlin((32, 32), frequency=4, rng=0, fade="cubic")
    assert np.abs(q - c).max() > 0.01


def test_value_range_2d_and_3d():
    # Measured over 2e5 random points: 2-D -0.93..0.99 (std 0.31, 8 gradient
    # directions), 3-D about +-0.97 (std 0.27, as the notes report for the
    # `noise` package); the bound for gradients of length sqrt(2) is 1.
    rng = np.random.default_rng(0)
    v2 = perlin(points=rng.uniform(0, 100, (200000, 2)), rng=0)
    v3 = perlin(points=rng.uniform(0, 100, (200000, 3)), rng=0)
    assert 0.9 < np.abs(v2).max() <= 1.0 and 0.27 < v2.std() < 0.35
    assert 0.9 < np.abs(v3).max() <= 1.0 and 0.22 < v3.std() < 0.32
    assert abs(v2.mean()) < 0.01 and abs(v3.mean()) < 0.01


def test_band_limited_around_lattice_frequency():
    # Fraction of spectral power between half and twice the lattice frequency:
    # measured 0.75-0.78 for noise over seeds 0-2, 0.08-0.09 for white noise.
    # Above 4x the lattice frequency noise has almost nothing (measured 1.2e-6
    # to 1.6e-6) while turbulence keeps its higher octaves (0.029-0.038).
    for seed in range(2):
        img = perlin((96, 96), frequency=8, period=8, rng=seed)
        power, r = _radial_power(img)
        assert power[(r >= 4) & (r <= 16)].sum() / power.sum() > 0.6
        assert power[r > 32].sum() / power.sum() < 1e-4
        turb = turbulence((96, 96), frequency=8, period=8, rng=seed)
        tp, _ = _radial_power(turb)
        assert tp[r > 32].sum() / tp.sum() > 0.01
    white = np.random.default_rng(0).standard_normal((96, 96))
    wp, _ = _radial_power(white)
    assert wp[(r >= 4) & (r <= 16)].sum() / wp.sum() < 0.2


def test_translation_invariant_in_distribution():
    # The histogram over a region does not depend on where it lies (sub-cell
    # shift, or far away). KS statistic measured 0.0245 at 256^2 with 1024
    # cells (std ratio 0.995-1.010); rescaling the values by 1.2 gives 0.056, so
    # 0.04 separates them.
    a = perlin((256, 256), frequency=32, rng=0).ravel()
    for offset in [(0.37, 0.61), (1000.37, 50.61)]:
        b = perlin((256, 256), frequency=32, rng=0, offset=offset).ravel()
        assert ks_2samp(a, b).statistic < 0.04
        assert abs(a.std() / b.std() - 1) < 0.03
    assert ks_2samp(a, 1.2 * a).statistic > 0.04


def test_same_seed_same_output_and_generator_accepted():
    a = perlin((32, 48), frequency=6, rng=7)
    b = perlin((32, 48), frequency=6, rng=7)
    assert np.array_equal(a, b)
    c = perlin((32, 48), frequency=6, rng=np.random.default_rng(7))
    assert np.array_equal(a, c)
    assert np.array_equal(turbulence((16, 16), frequency=2, rng=3), turbulence((16, 16), frequency=2, rng=3))


def test_different_seeds_uncorrelated():
    # 576 cells per image: sample correlations of independent seeds measured
    # |r| <= 0.053 over 10 pairs; 0.15 is about 4 standard deviations (the same
    # seed gives r = 1, so a seed that did not change the permutation fails).
    for s in range(5):
        a = perlin((96, 96), frequency=24, rng=s).ravel()
        b = perlin((96, 96), frequency=24, rng=s + 100).ravel()
        assert abs(np.corrcoef(a, b)[0, 1]) < 0.15


def test_period_makes_noise_exactly_periodic():
    base = perlin((32, 32), frequency=4, period=4, rng=1)
    shifted = perlin((32, 32), frequency=4, period=4, rng=1, offset=(4, 8))
    np.testing.assert_allclose(base, shifted, atol=1e-12)
    pts = np.random.default_rng(0).uniform(0, 10, (100, 3))
    np.testing.assert_allclose(perlin(points=pts, period=(3, 5, 7), rng=0),
                               perlin(points=pts + [3, 10, 7], period=(3, 5, 7), rng=0), atol=1e-12)
    # without a period the lattice repeats only every 256 cells
    assert np.abs(perlin((32, 32), frequency=4, rng=1) - perlin((32, 32), frequency=4, rng=1, offset=(4, 8))).max() > 0.1


def test_tileable_opposite_edges_continue():
    # Across the wrap-around seam (last column -> first column) the step must be
    # like an ordinary neighbour step. 16 px per cell, edges mid-cell (offset
    # 0.5, away from the lattice lines where noise is small): with the period
    # the mean wrap step / mean interior step was measured 0.7-1.2 (seeds 0-2);
    # without, the two edges are independent and the ratio was 6.4-11 for noise
    # and 3.2-4.4 for turbulence.
    kw = dict(frequency=8, offset=(0.5, 0.5), rng=2)
    for img_tiled, img_free in [
        (perlin((128, 128), period=8, **kw), perlin((128, 128), **kw)),
        (turbulence((128, 128), period=8, octaves=3, **kw), turbulence((128, 128), octaves=3, **kw)),
    ]:
        for img, tiled in [(img_tiled, True), (img_free, False)]:
            for axis in (0, 1):
                a = np.moveaxis(img, axis, 1)
                ratio = np.abs(a[:, 0] - a[:, -1]).mean() / np.abs(np.diff(a, axis=1)).mean()
                assert (ratio < 1.5) if tiled else (ratio > 2.5), (tiled, axis, ratio)


def test_band_limit_octaves():
    # 64 px with 4 cells: cells of 16, 8, 4, 2, 1 px -> 5 octaves; a 6th would be 0.5 px
    assert band_limit_octaves((64, 64), 4) == 5
    assert band_limit_octaves((1024, 1024), 8) == 8
    assert band_limit_octaves((100, 30), 4) == 5  # 25 px cells: 25, 12.5, 6.25, 3.1, 1.6
    assert band_limit_octaves((8, 8), 16) == 1  # finer than a pixel already: one octave


@pytest.mark.parametrize("fade", ["quintic", "cubic"])
def test_noise_stays_in_the_range_the_command_line_maps_from(fade):
    # the command line maps perlin from [-1, 1] to [0, 1] (texsynth.registry), without a pass over the
    # image: |noise| <= 1 in 2-D (at a cell centre, every corner's gradient pointing there)
    from texsynth.registry import METHODS

    assert METHODS["perlin"].values == (-1.0, 1.0)
    noise = perlin((256, 256), frequency=64, fade=fade, rng=1)  # 64 cells a side: many near their peak
    assert np.abs(noise).max() <= 1 + 1e-12


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------


@pytest.mark.parametrize("call,match", [
    (lambda: perlin((0, 8)), "size"),
    (lambda: perlin((8, 8, 8, 8)), "size"),
    (lambda: perlin((8, 8), frequency=0), "frequency"),
    (lambda: perlin((8, 8), frequency=-2), "frequency"),
    (lambda: perlin((8, 8), period=0), "period"),
    (lambda: perlin((8, 8), period=1.5), "period"),
    (lambda: perlin((8, 8), period=(2, 2, 2)), "period"),
    (lambda: perlin((8, 8), fade="linear"), "fade"),
    (lambda: perlin((8, 8), dtype=np.int32), "dtype"),
    (lambda: perlin(), "exactly one"),
    (lambda: perlin((8, 8), points=[[0, 0]]), "exactly one"),
    (lambda: perlin(points=[[0, 0, 0, 0]]), "points"),
    (lambda: perlin(points=[[np.nan, 0]]), "points"),
    (lambda: perlin((8, 8), offset=(1, 2, 3)), "offset"),
])
def test_bad_inputs(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()


def test_bad_rng_type():
    with pytest.raises(TypeError, match="rng"):
        perlin((8, 8), rng="seed")


@settings(max_examples=25, deadline=None)
@given(h=st.integers(-3, 40), w=st.integers(-3, 40), freq=st.floats(-2, 20, allow_nan=False))
def test_shape_and_frequency_validation(h, w, freq):
    if h < 1 or w < 1 or freq <= 0:
        with pytest.raises(ValueError, match="size|frequency"):
            perlin((h, w), frequency=freq, rng=0)
    else:
        out = perlin((h, w), frequency=freq, rng=0)
        assert out.shape == (h, w) and np.isfinite(out).all() and np.abs(out).max() <= 1


# --------------------------------------------------------------------------
# bad input, property-based: every public function, every parameter
# --------------------------------------------------------------------------
#
# Each case is (function, parameter, strategy of bad values, call). A bad value
# must raise ValueError or TypeError whose message names the parameter; never
# an OverflowError, IndexError or AttributeError from inside, a NaN result or
# a multi-gigabyte allocation. These would have caught the reliability issue's
# items: band_limit_octaves(64, 8) ("'int' object is not iterable"),
# stability_limit(nan) (returned nan), marble(16, frequency=1e-308)
# (OverflowError), apply_colormap with NaN values (returned NaN colours), ...
# The strategies and the grid cases serve tests/test_patterns.py and
# tests/test_reaction_diffusion.py too, which import them from here; the two
# tests over the cases are made by tests/_bad_input.py for all three.

_NON_NUMBERS = st.sampled_from([None, True, False, "3", [1.0], (2.0,), np.array([1.0, 2.0]), {}, object()])
_NON_FINITE = st.sampled_from([math.nan, math.inf, -math.inf, np.float32("nan"), 10**400])
_NEGATIVE = st.floats(max_value=-1e-300, allow_nan=False, allow_infinity=False)
_BAD_POSITIVE = st.one_of(_NON_NUMBERS, _NON_FINITE, _NEGATIVE, st.just(0), st.just(0.0))  # for "> 0" numbers
_BAD_NON_NEGATIVE = st.one_of(_NON_NUMBERS, _NON_FINITE, _NEGATIVE)  # for ">= 0" numbers
_BAD_COUNT = st.one_of(st.sampled_from([True, "3", 2.5, 3.0, math.nan, [1]]), st.integers(-10**6, 0))
_BAD_SIZE = st.one_of(
    st.sampled_from([None, True, "8x8", b"ab", 8.0, (8,), (8, 8, 8, 8), (8.0, 8), (math.nan, 8), {8: 8}, (True, 8)]),
    st.integers(-10**6, 0),
    st.tuples(st.integers(-5, 0), st.integers(1, 8)),
    st.tuples(st.integers(10**7, 10**12), st.integers(10**7, 10**12)),  # cannot fit in memory: refused up front
)
_BAD_RNG = st.sampled_from([-1, True, "seed", 2.5, np.random.RandomState(0)])
_BAD_DTYPE = st.sampled_from([None, np.int32, bool, "foo", 5, np.complex128, np.float16])
_BAD_FADE = st.sampled_from([None, 3, "linear", ["quintic"], lambda t: t * np.nan, lambda t: 0.5 + 0 * t,
                             lambda t: t[:2], lambda t: "x"])
_BAD_PERIOD = st.one_of(st.sampled_from([1.5, math.nan, math.inf, True, "4", (2, 2, 2), (2, None), [[1, 2]], 10**30]),
                        st.integers(-10**6, 0))
_BAD_OFFSET = st.sampled_from([math.nan, (1, 2, 3), "a", (True, 0), (1e300, 0), (0, math.inf), 10**400, [[0, 0]]])
_BAD_POINTS = st.sampled_from([[[math.nan, 0]], [[0, 0, 0, 0]], [["a", "b"]], [[True, False]], [[1, 2], [3]],
                               [[1e300, 0]], np.zeros((3, 2), complex), 5, [1.0, 2.0]])
_BAD_COLORMAP = st.sampled_from([5, 2.5, True, "no-such-map", [(1, 1, 1)], [None, None], [(0, 0), (1, 1)],
                                 [(0, 0, 2), (1, 1, 1)], np.zeros((2, 3, 3)), [(math.nan, (0, 0, 0)), (1, (1, 1, 1))],
                                 [(0.8, (0, 0, 0)), (0.2, (1, 1, 1))], [(True, (0, 0, 0)), (1, (1, 1, 1))],
                                 [("1", "0", "0"), (1, 1, 1)], [(0, None), (1, None)], "#ff0000",
                                 lambda v: v, lambda v: None, lambda v: np.full(v.shape + (3,), np.nan),
                                 lambda v: np.zeros(v.shape + (3,), complex)])


def grid_cases(functions):
    """The bad-input cases of the grid functions ``[(name, function), ...]`` (perlin, turbulence, fbm, marble, wood)."""
    cases = []
    for name, fn in functions:
        cases += [
            (name, "size", _BAD_SIZE, lambda v, fn=fn: fn(v, rng=0)),
            (name, "frequency", st.one_of(_BAD_POSITIVE, st.just(1e300)), lambda v, fn=fn: fn((8, 8), frequency=v)),
            (name, "fade", _BAD_FADE, lambda v, fn=fn: fn((8, 8), fade=v)),
            (name, "rng", _BAD_RNG, lambda v, fn=fn: fn((8, 8), rng=v)),
            (name, "dtype", _BAD_DTYPE, lambda v, fn=fn: fn((8, 8), dtype=v)),
        ]
        if name != "perlin":
            cases += [(name, "octaves", st.one_of(_BAD_COUNT, st.just(3000)), lambda v, fn=fn: fn((8, 8), octaves=v)),
                      # so low that the band limit needs more than 1024 octaves (2**1024 overflows;
                      # OverflowError in 0.1)
                      (name, "frequency", st.floats(5e-324, 8e-308), lambda v, fn=fn: fn(16, frequency=v))]
        if name in ("perlin", "turbulence", "fbm"):
            extra = {} if name == "perlin" else {"octaves": 2}
            cases += [
                (name, "points", _BAD_POINTS, lambda v, fn=fn, extra=extra: fn(points=v, **extra)),
                (name, "offset", _BAD_OFFSET, lambda v, fn=fn: fn((8, 8), offset=v)),
                (name, "period", _BAD_PERIOD, lambda v, fn=fn, extra=extra: fn((8, 8), period=v, **extra)),
            ]
    return cases


_BAD_INPUT_CASES = grid_cases([("perlin", perlin)]) + [
    # (a size too large to allocate is still a valid grid to count octaves for)
    ("band_limit_octaves", "size", _BAD_SIZE.filter(lambda v: not (isinstance(v, tuple) and len(v) == 2
                                                                    and isinstance(v[0], int) and v[0] > 1)),
     lambda v: band_limit_octaves(v, 8)),
    ("band_limit_octaves", "frequency", _BAD_POSITIVE, lambda v: band_limit_octaves((64, 64), v)),
    ("band_limit_octaves", "lacunarity", st.one_of(_BAD_POSITIVE, st.floats(0, 1)),
     lambda v: band_limit_octaves((64, 64), 8, v)),
]
test_bad_input_cases_cover_every_public_function, test_bad_input_raises_naming_the_parameter = \
    bad_input_tests(noise_module, _BAD_INPUT_CASES)


def test_bad_input_issue_examples():
    # the reliability issue's reproducer of this module
    assert band_limit_octaves(64, 8) == band_limit_octaves((64, 64), 8) == 4


# --------------------------------------------------------------------------
# memory: proportional to the output, not to the noise lattice
# --------------------------------------------------------------------------


def _peak_bytes(fn):
    perlin((4, 4), rng=0)  # one-time set-up (the BLAS thread controller) is not the call's memory
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_memory_bounded_by_output_not_lattice():
    # The whole gradient lattice of a 64 x 64 image at frequency 20000 is 20001^2 points (3.2 GB per
    # float64 component; texsynth 0.1 peaked at 8.7 GiB). Hashing only the cells the pixels fall in,
    # measured 0.6 MiB.
    assert _peak_bytes(lambda: perlin((64, 64), frequency=20000, rng=0)) < 4 * 2**20
    # 3-D, finer than a pixel in every direction: measured 6.6 MiB (0.1: a 20001^3 lattice)
    assert _peak_bytes(lambda: perlin((64, 64, 64), frequency=20000, rng=0, dtype=np.float32)) < 32 * 2**20


def test_blocks_do_not_change_the_output(monkeypatch):
    # Same seed, same output, bit for bit, whatever the block size: blocks split runs of rows that
    # share a lattice cell (never into a one-row product, which BLAS rounds differently).
    calls = [lambda: perlin((40, 50), frequency=900, rng=2), lambda: perlin((3, 1, 700), frequency=9000, rng=4)]
    reference = [c() for c in calls]
    for block in (7, 64, 1000):
        monkeypatch.setattr(noise_module, "_BLOCK", block)
        for c, ref in zip(calls, reference):
            assert np.array_equal(c(), ref)


# --------------------------------------------------------------------------
# size, positional or keyword
# --------------------------------------------------------------------------


def test_size_keyword():
    expected = perlin((16, 16), rng=0)
    assert np.array_equal(perlin(size=(16, 16), rng=0), expected)
    assert "size" in inspect.signature(perlin).parameters


def test_band_limit_octaves_size_keyword():
    assert band_limit_octaves(size=(1024, 512), frequency=8) == 8
