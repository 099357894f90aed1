"""Tests of turbulence, fBm, marble and wood (texsynth.procedural._patterns).

Their defining equations (the lecture slides "Turbulence Function" and "Marble
Texture Function", Peachey's wood), the colour maps, bad input (with the
strategies of tests/test_noise.py) and memory. Thresholds were calibrated on this
implementation and on a counter-example that must fail; each comment gives both.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import texsynth.procedural._noise as noise_module
import texsynth.procedural._patterns as patterns_module
from texsynth.procedural import apply_colormap, fbm, marble, perlin, turbulence, wood
from texsynth.procedural._patterns import _OCTAVE_SHIFT

from _bad_input import bad_input_tests
from test_noise import _BAD_COLORMAP, _BAD_NON_NEGATIVE, _BAD_POSITIVE, _peak_bytes, _radial_power, grid_cases

# --------------------------------------------------------------------------
# turbulence and fBm
# --------------------------------------------------------------------------


def test_turbulence_truncated_at_band_limit():
    full = turbulence((64, 64), frequency=4, rng=0)
    assert np.array_equal(full, turbulence((64, 64), frequency=4, octaves=5, rng=0))
    assert not np.allclose(full, turbulence((64, 64), frequency=4, octaves=6, rng=0))
    assert not np.allclose(full, turbulence((64, 64), frequency=4, octaves=4, rng=0))


def test_turbulence_is_sum_of_absolute_octaves():
    # turbulence(x) = sum_i |noise(2^i x + shift_i)| / 2^i  (slide "Turbulence Function")
    pts = np.random.default_rng(0).uniform(0, 20, (50, 3))
    expected = sum(np.abs(perlin(points=pts * 2**i + i * _OCTAVE_SHIFT, rng=4)) / 2**i for i in range(4))
    np.testing.assert_allclose(turbulence(points=pts, octaves=4, rng=4), expected, atol=1e-12)
    signed = sum(0.5**i * perlin(points=pts * 2**i + i * _OCTAVE_SHIFT, rng=4) for i in range(4)) / sum(0.5**i for i in range(4))
    np.testing.assert_allclose(fbm(points=pts, octaves=4, rng=4), signed, atol=1e-12)


@pytest.mark.parametrize("fade", ["quintic", "cubic"])
def test_turbulence_and_fbm_stay_in_the_ranges_the_command_line_maps_from(fade):
    # the command line maps fbm from [-1, 1] and turbulence from [0, 2] to [0, 1] (texsynth.registry),
    # without a pass over the image: turbulence < 1 + 1/2 + 1/4 + ... = 2 since |noise| <= 1
    from texsynth.registry import METHODS

    assert METHODS["fbm"].values == (-1.0, 1.0)
    assert METHODS["turbulence"].values == (0.0, 2.0)
    assert 0 <= turbulence((256, 256), frequency=4, fade=fade, rng=1).min()
    assert turbulence((256, 256), frequency=4, fade=fade, rng=1).max() < 2


def test_grid_octaves_not_stuck_on_lattice():
    # Without the per-octave irrational shift every octave is 0 on the base
    # lattice and turbulence is exactly 0 there; with it, it is not.
    t = turbulence((64, 64), frequency=4, rng=0)
    assert t[::16, ::16].min() > 0
    assert t.min() >= 0


def test_turbulence_spectrum_falls_with_frequency():
    # 1/f amplitude falloff: mean power at 16-64 cycles is far below that at
    # 2-8 cycles (measured ratio 0.0007-0.0013; flat white noise would give 1).
    t = turbulence((128, 128), frequency=4, period=4, rng=1)
    power, r = _radial_power(t)
    low = power[(r >= 2) & (r < 8)].mean()
    high = power[(r >= 16) & (r < 64)].mean()
    assert high < low / 100


def test_fbm_range_and_options():
    f = fbm((64, 64), frequency=4, rng=0)
    assert np.abs(f).max() <= 1
    assert not np.allclose(f, fbm((64, 64), frequency=4, rng=0, lacunarity=3.0, octaves=3))
    with pytest.raises(ValueError, match="lacunarity"):
        fbm((16, 16), frequency=2, octaves=2, lacunarity=2.5, period=2)
    with pytest.raises(ValueError, match="lacunarity"):
        fbm((16, 16), frequency=2, octaves=2, lacunarity=1.0)


def test_volumes_and_float32():
    t = turbulence((8, 16, 16), frequency=4, rng=0, dtype=np.float32)
    assert t.shape == (8, 16, 16) and t.dtype == np.float32
    np.testing.assert_allclose(t, turbulence((8, 16, 16), frequency=4, rng=0), atol=1e-4)


# --------------------------------------------------------------------------
# marble and wood
# --------------------------------------------------------------------------


def test_marble_layers_without_turbulence():
    # turbulence_strength=0 leaves marble_color(sin(x)): every column one value
    img, field = marble((32, 48), veins=2, turbulence_strength=0, rng=0, return_info=True)
    assert img.shape == (32, 48, 3)
    assert np.allclose(field, field[:1])
    x = np.arange(48) / 48
    np.testing.assert_allclose(field[0], (1 + np.sin(2 * np.pi * 2 * x)) / 2, atol=1e-12)
    _, bent = marble((32, 48), veins=2, turbulence_strength=6, rng=0, return_info=True)
    assert np.abs(bent - bent[:1]).max() > 0.5  # turbulence bends the layers


def test_marble_solid_and_range():
    vol = marble((6, 24, 24), rng=0, dtype=np.float32)
    assert vol.shape == (6, 24, 24, 3) and vol.dtype == np.float32
    assert vol.min() >= 0 and vol.max() <= 1
    # default colours: white stone (median luminance measured 0.83) with darker veins (min 0.22)
    lum = marble((64, 64), rng=1).mean(axis=-1)
    assert np.median(lum) > 0.7 and lum.min() < 0.4


def test_marble_tiles_with_period_and_integer_veins():
    img = marble((64, 64), frequency=4, period=4, veins=2, octaves=3, rng=0)
    step = np.abs(np.diff(img, axis=1)).mean()
    assert np.abs(img[:, 0] - img[:, -1]).mean() < 1.5 * step


def test_wood_rings_concentric_without_turbulence():
    img, field = wood((33, 33), rings=5, turbulence_strength=0, rng=0, return_info=True)
    assert img.shape == (33, 33, 3)
    # the field depends on the distance from the centre only: mirror symmetric
    np.testing.assert_allclose(field, field[::-1], atol=1e-12)
    np.testing.assert_allclose(field, field.T, atol=1e-12)
    vol = wood((4, 20, 20), rng=0)
    assert vol.shape == (4, 20, 20, 3) and 0 <= vol.min() and vol.max() <= 1


def test_colormaps():
    t = np.linspace(0, 1, 5)
    two = apply_colormap(t, [(0, 0, 0), (1, 1, 1)])
    np.testing.assert_allclose(two, np.repeat(t[:, None], 3, axis=1))
    hexes = apply_colormap(t, ["#000000", "#ff0000"])
    np.testing.assert_allclose(hexes[:, 0], t)
    pairs = apply_colormap(np.array([0.5]), [(0.0, (0, 0, 0)), (0.5, (1, 0, 0)), (1.0, (0, 0, 1))])
    np.testing.assert_allclose(pairs, [[1, 0, 0]])
    rgba = apply_colormap(t, lambda v: np.stack([v, v, v, np.ones_like(v)], axis=-1))
    assert rgba.shape == (5, 3)
    img = marble((16, 16), colormap=[(0, 0, 1), (0, 0, 1)], rng=0)
    assert np.allclose(img, [0, 0, 1])
    for bad in ["#12", [(0, 0, 2), (1, 1, 1)], [(1, 1, 1)], 5, [(0.8, (0, 0, 0)), (0.2, (1, 1, 1))]]:
        with pytest.raises((ValueError, TypeError), match="colormap"):
            apply_colormap(t, bad)
    with pytest.raises(ValueError, match="colormap callable"):
        apply_colormap(t, lambda v: v)


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------


@pytest.mark.parametrize("call,match", [
    (lambda: turbulence((8, 8), octaves=0), "octaves"),
    (lambda: turbulence(points=[[0, 0]]), "octaves"),
    (lambda: fbm((8, 8), gain=0), "gain"),
    (lambda: marble((8, 8), veins=-1), "veins"),
    (lambda: wood((8, 8), center=(1, 2, 3)), "center"),
])
def test_bad_inputs(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()


@settings(max_examples=20, deadline=None)
@given(period=st.one_of(st.integers(-3, 0), st.floats(0.1, 5.0).filter(lambda p: not float(p).is_integer())))
def test_bad_periods(period):
    with pytest.raises(ValueError, match="period"):
        turbulence((8, 8), frequency=2, octaves=2, period=period)


# property-based: every public function of the module, every parameter (see tests/test_noise.py)
def _other_cases():
    t = np.linspace(0, 1, 5)
    grey = [(0, 0, 0), (1, 1, 1)]
    return [
        ("fbm", "lacunarity", st.one_of(_BAD_POSITIVE, st.floats(0, 1), st.just(1e300)),
         lambda v: fbm((8, 8), lacunarity=v, octaves=3)),
        ("fbm", "gain", st.one_of(_BAD_POSITIVE, st.just(1e200)), lambda v: fbm((8, 8), gain=v, octaves=3)),
        ("fbm", "gain", st.floats(1e25, 1e300), lambda v: fbm((8, 8), gain=v, octaves=3, dtype=np.float32)),
        ("marble", "veins", st.one_of(_BAD_NON_NEGATIVE, st.just(1e308)), lambda v: marble((8, 8), veins=v)),
        ("marble", "veins", st.floats(1e37, 3e38), lambda v: marble((8, 8), veins=v, dtype=np.float32)),
        ("marble", "turbulence_strength", _BAD_NON_NEGATIVE, lambda v: marble((8, 8), turbulence_strength=v)),
        ("marble", "colormap", _BAD_COLORMAP, lambda v: marble((8, 8), colormap=v)),
        ("wood", "rings", st.one_of(_BAD_NON_NEGATIVE, st.just(1e308)), lambda v: wood((8, 8), rings=v)),
        ("wood", "center", st.sampled_from([5, (1, 2, 3), (math.nan, 0.5), (True, 0.5), ("a", "b"), (1e300, 0), "ab"]),
         lambda v: wood((8, 8), center=v)),
        ("wood", "colormap", _BAD_COLORMAP, lambda v: wood((8, 8), colormap=v)),
        ("apply_colormap", "values",
         st.sampled_from([None, [math.nan, 0.5], np.array(["a", "b"]), np.array([1j]), [[0.1], [0.2, 0.3]], object()]),
         lambda v: apply_colormap(v, grey)),
        ("apply_colormap", "colormap", _BAD_COLORMAP, lambda v: apply_colormap(t, v)),
        ("apply_colormap", "default", _BAD_COLORMAP.filter(lambda c: not callable(c)),
         lambda v: apply_colormap(t, None, default=v)),
        ("apply_colormap", "dtype", st.sampled_from([int, "foo", bool, 5, np.int8]),
         lambda v: apply_colormap(t, grey, dtype=v)),
    ]


_BAD_INPUT_CASES = grid_cases([("turbulence", turbulence), ("fbm", fbm), ("marble", marble), ("wood", wood)]) + \
    _other_cases()
test_bad_input_cases_cover_every_public_function, test_bad_input_raises_naming_the_parameter = \
    bad_input_tests(patterns_module, _BAD_INPUT_CASES)


def test_bad_input_issue_examples():
    # the reliability issue's reproducers of this module, one by one
    for fn in (marble, turbulence, fbm, wood):
        with pytest.raises(ValueError, match="frequency=1e-308"):
            fn(16, frequency=1e-308)
    with pytest.raises(ValueError, match="values contains 1 NaN"):
        apply_colormap(np.array([0.5, np.nan]), [(0, 0, 0), (1, 1, 1)])
    # a tiny frequency whose octaves stay representable still works: 336 octaves, a smooth image
    img = turbulence(4, frequency=1e-100, rng=0)
    assert np.isfinite(img).all() and img.min() >= 0


# --------------------------------------------------------------------------
# memory: proportional to the output, not to the noise lattice
# --------------------------------------------------------------------------


def test_memory_bounded_by_output_not_lattice():
    # 11 octaves from 26 cells: the finest lattice has 26625^2 points (0.1: 3.8 GiB for 10 octaves); 0.5 MiB
    assert _peak_bytes(lambda: turbulence((48, 48), frequency=26, octaves=11, rng=0)) < 4 * 2**20


def test_memory_proportional_to_output_with_blocks(monkeypatch):
    # With blocks of 2^16 samples the temporaries stay small next to the result: 1024^2 turbulence
    # to the band limit (8 MiB result) measured 1.71x in all; 0.1 needed 12x. (At the default
    # block size, turbulence(8192) measured 1.06x: docs/methods/patterns.md.)
    monkeypatch.setattr(noise_module, "_BLOCK", 1 << 16)
    result = 1024 * 1024 * 8
    assert _peak_bytes(lambda: turbulence((1024, 1024), frequency=8, rng=0)) < 2.0 * result


def test_blocks_do_not_change_the_output(monkeypatch):
    # Same seed, same output, bit for bit, whatever the block size of the noise (tests/test_noise.py):
    # every octave is added block by block.
    calls = [lambda: turbulence((70, 65), frequency=3, rng=1),
             lambda: turbulence((9, 10, 11), frequency=2.5, rng=3, dtype=np.float32)]
    reference = [c() for c in calls]
    for block in (7, 64, 1000):
        monkeypatch.setattr(noise_module, "_BLOCK", block)
        for c, ref in zip(calls, reference):
            assert np.array_equal(c(), ref)


# --------------------------------------------------------------------------
# size, positional or keyword
# --------------------------------------------------------------------------

_SIZED = [(turbulence, (16, 16), {"rng": 0}), (fbm, (16, 16), {"rng": 0}), (marble, (16, 16), {"rng": 0}),
          (wood, (16, 16), {"rng": 0})]


@pytest.mark.parametrize("fn,size,kwargs", _SIZED, ids=[f.__name__ for f, _, _ in _SIZED])
def test_size_keyword(fn, size, kwargs):
    expected = fn(size, **kwargs)
    assert np.array_equal(fn(size=size, **kwargs), expected)
    assert "size" in inspect.signature(fn).parameters
