"""Quality metrics and test helpers, calibrated on real textures against the baselines."""

import inspect

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy import ndimage

from texsynth import metrics
from texsynth.core.search import METHODS
from texsynth.testing import TextureAssertionError, assert_texture_like, relative_scores

# stochastic, structured and text: the kinds the metrics must rank the same way
CASES = ["skimage/gravel.png", "jcjohnson/brick.png", "lcv/text.pgm"]


@pytest.fixture(params=CASES)
def exemplar(request, texture):
    return texture(request.param, 48)


def test_baselines_rank_as_calibrated(exemplar):
    report = metrics.texture_report(exemplar, exemplar, patch_size=8)
    ref = report.reference
    # the tiled exemplar is the best possible coherence and the worst copy
    assert ref["tiled"]["energy"] < 1e-12 < ref["mosaic"]["energy"] < ref["noise"]["energy"]
    assert ref["tiled"]["verbatim_copy"] > 0.9
    assert ref["noise"]["verbatim_copy"] == 0.0
    # a mosaic of 12-px blocks copies about one block (144 px of 2304 = 0.0625); allow its neighbours
    assert 0.04 < ref["mosaic"]["verbatim_copy"] < 0.25
    # noise is worst on coherence and completeness, and far off in spectrum
    assert ref["noise"]["completeness"] > ref["mosaic"]["completeness"]
    assert ref["noise"]["spectrum"] > 2 * ref["mosaic"]["spectrum"]
    # histogram-matched noise matches the histogram better than a mosaic that samples part of it
    assert ref["noise"]["histogram"] < ref["mosaic"]["histogram"]


def test_metrics_are_zero_on_the_exemplar_itself(exemplar):
    for fn in (metrics.texture_energy, metrics.completeness):
        assert fn(exemplar, exemplar, patch_size=6) == 0.0
    assert metrics.histogram_distance(exemplar, exemplar) == 0.0
    assert metrics.spectrum_distance(exemplar, exemplar) == 0.0
    assert metrics.verbatim_copy(exemplar, exemplar, patch_size=6) == pytest.approx(1.0)


def test_energy_grows_with_blur_and_completeness_catches_missing_content(texture):
    ex = texture("skimage/gravel.png", 48)
    blurred = ndimage.gaussian_filter(ex, 1.5)
    assert metrics.texture_energy(blurred, ex) > 5 * metrics.texture_energy(ex[:40, :40], ex) + 1e-4
    # an output made of only the top-left quarter repeated is coherent but incomplete
    quarter = np.tile(ex[:24, :24], (2, 2))
    assert metrics.completeness(quarter, ex) > 3 * metrics.completeness(np.roll(ex, 20, axis=(0, 1)), ex)


def test_verbatim_copy_measures_the_largest_single_offset_region(texture):
    ex = texture("jcjohnson/bread.png", 48)
    fresh = metrics.noise_baseline(ex, 64, rng=1)
    out = fresh.copy()
    out[8:32, 16:40] = ex[10:34, 5:29]  # paste a 24x24 block: 576 / 2304 = 0.25 of the exemplar
    frac = metrics.verbatim_copy(out, ex, patch_size=8, stride=1)
    assert 0.2 <= frac <= 0.26  # the union of matched patches covers the block (up to the noise around it)
    assert metrics.verbatim_copy(fresh, ex, patch_size=8) == 0.0


def test_spectrum_distance_compares_different_sizes(texture):
    ex = texture("lcv/metal.pgm", 64)
    other_crop = texture("lcv/metal.pgm", 128)[64:, 64:]
    noise = metrics.noise_baseline(ex, 96, rng=0)
    assert metrics.spectrum_distance(other_crop, ex) < 0.5 * metrics.spectrum_distance(noise, ex)


def test_assert_texture_like_passes_a_fresh_crop_and_fails_noise_and_copies(texture):
    big = texture("skimage/gravel.png", 112)
    ex, other = big[:48, :48], big[56:, 56:]
    report = assert_texture_like(other, ex)  # another crop of the same texture is a texture like it
    assert relative_scores(report)["verbatim_copy"] == 0.0
    with pytest.raises(TextureAssertionError, match="energy") as info:
        assert_texture_like(metrics.noise_baseline(ex, 56, rng=0), ex)
    assert "bound" in str(info.value) and "baselines" in str(info.value)
    with pytest.raises(TextureAssertionError, match="verbatim_copy"):
        assert_texture_like(metrics.tiled_baseline(ex, 64), ex)


def test_baseline_shapes_layouts_and_seeds(texture):
    ex = texture("jcjohnson/bread.png", 40)
    grey = ex.mean(-1)
    for image in (ex, grey):
        for name, b in metrics.baselines(image, (30, 50), rng=3).items():
            assert b.shape == (30, 50) + image.shape[2:], name
    assert np.array_equal(metrics.noise_baseline(ex, 20, rng=5), metrics.noise_baseline(ex, 20, rng=5))
    assert np.array_equal(np.sort(metrics.noise_baseline(grey, 40, rng=0).ravel()), np.sort(grey.ravel()))


@pytest.mark.parametrize("call, match", [
    (lambda ex: metrics.texture_energy(ex, ex, patch_size=64), "patch_size"),
    (lambda ex: metrics.texture_energy(ex, ex[..., :1]), "channels"),
    (lambda ex: metrics.verbatim_copy(ex, ex, value_tolerance=0), "tolerance"),
    (lambda ex: metrics.texture_energy(ex, ex, stride=0), "stride"),
    (lambda ex: metrics.mosaic_baseline(ex, 20, block=100), "block"),
    (lambda ex: metrics.texture_energy(ex * 255, ex), "divide by 255"),
])
def test_bad_input(call, match, texture):
    with pytest.raises((ValueError, TypeError), match=match):
        call(texture("jcjohnson/bread.png", 32))


def test_rng_defaults_to_none_and_the_exact_metrics_do_not_depend_on_it(texture):
    ex = texture("skimage/gravel.png", 40)
    out = texture("skimage/gravel.png", 96)[48:, 48:]
    for fn in (metrics.texture_energy, metrics.completeness, metrics.verbatim_copy):
        assert inspect.signature(fn).parameters["rng"].default is None, fn.__name__
        values = {fn(out, ex, patch_size=6, rng=rng) for rng in (None, 0, 7, np.random.default_rng(3))}
        assert len(values) == 1, fn.__name__  # 0 was the old default: the defaults' values are unchanged
    # the baselines are random: their seed stays fixed so that a report (and an assertion) is reproducible
    assert inspect.signature(metrics.texture_report).parameters["rng"].default == 0
    assert inspect.signature(metrics.baselines).parameters["rng"].default == 0


def test_rng_seeds_an_approximate_method():
    rng = np.random.default_rng(0)
    ex, out = rng.random((40, 40)), rng.random((40, 40))
    a = metrics.texture_energy(out, ex, patch_size=5, method="kdtree", rng=1)
    assert a == metrics.texture_energy(out, ex, patch_size=5, method="kdtree", rng=1)
    assert a >= metrics.texture_energy(out, ex, patch_size=5)  # approximate: never below exact


def test_spectrum_distance_needs_two_pixels_per_side_and_a_shared_band():
    rng = np.random.default_rng(0)
    for small in (np.zeros((1, 1)), np.zeros((1, 16)), np.zeros((16, 1, 3))):
        big = rng.random((16, 16) + small.shape[2:])
        with pytest.raises(ValueError, match=r"at least 2x2 pixels.*output is (1x|16x1)"):
            metrics.spectrum_distance(small, big)
        with pytest.raises(ValueError, match=r"at least 2x2 pixels.*exemplar is (1x|16x1)"):
            metrics.spectrum_distance(big, small)
    assert np.isfinite(metrics.spectrum_distance(rng.random((2, 2)), rng.random((2, 2))))
    with pytest.raises(ValueError, match="share no frequency band.*fewer bins"):
        metrics.spectrum_distance(rng.random((2, 2)), rng.random((3, 3)))


def test_size_errors_name_the_image_that_is_too_small():
    rng = np.random.default_rng(0)
    small, big = rng.random((4, 4)), rng.random((20, 20))
    for fn in (metrics.texture_energy, metrics.completeness, metrics.verbatim_copy):
        with pytest.raises(ValueError, match=r"larger than the output \(4, 4\)"):
            fn(small, big, patch_size=8)
        with pytest.raises(ValueError, match=r"larger than the exemplar \(4, 4\)"):
            fn(big, small, patch_size=8)


def test_images_that_are_not_arrays_are_typeerrors_naming_them():
    ex = np.random.default_rng(0).random((12, 12))
    with pytest.raises(TypeError, match="output must be an array.*NoneType"):
        metrics.texture_energy(None, ex)
    with pytest.raises(TypeError, match="exemplar must be an array"):
        metrics.histogram_distance(ex, [[0.1], [0.1, 0.2]])
    with pytest.raises(FileNotFoundError, match="exemplar"):  # a str or Path is a file to load (docs/conventions.md)
        metrics.noise_baseline("no-such-bread.png", 8)
    with pytest.raises(TypeError, match="with_baselines must be True or False"):
        metrics.texture_report(ex, ex, patch_size=4, with_baselines="no")


# bad values of every parameter of the public metrics; each must be refused with a
# TypeError/ValueError naming the parameter
EX = np.random.default_rng(0).random((12, 12))
_BAD_FLOATS = st.sampled_from([np.nan, np.inf, -np.inf, -0.5, 1.5, 255.0])
_BAD_IMAGES = st.one_of(
    st.none(), st.text(max_size=3), st.integers(), st.booleans(), st.just([[0.1], [0.2, 0.3]]),
    hnp.arrays(np.float64, st.tuples(st.integers(1, 12), st.integers(1, 12)), elements=_BAD_FLOATS),
    hnp.arrays(st.sampled_from([np.int64, np.complex128, object]), (12, 12)),
    st.sampled_from([(12,), (12, 12, 5), (1, 12, 12, 1), (0, 12), (12, 0, 1)]).map(np.zeros),
)
_BAD_SIZES = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.integers(max_value=0),
                       st.floats(), st.tuples(st.integers(1, 4), st.integers(max_value=0)),
                       st.tuples(st.integers(1, 4), st.integers(1, 4), st.integers(1, 4)))
_NOT_INTS = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.floats())
_BAD_PATCH = st.one_of(_NOT_INTS, st.integers(max_value=0), st.integers(13, 10**6), st.tuples(st.integers(1, 3)))
_BAD_STRIDE = st.one_of(st.booleans(), st.text(max_size=3), st.floats(), st.integers(max_value=0))
_BAD_POSITIVE = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.floats(max_value=0),
                          st.sampled_from([np.nan, np.inf]))
_BAD_METHODS = st.one_of(st.none(), st.integers(), st.text(max_size=8).filter(lambda m: m not in METHODS))
_BAD_RNG = st.one_of(st.integers(max_value=-1), st.floats(), st.text(max_size=3), st.booleans())

_METRIC_CASES = {}
for _fn in (metrics.texture_energy, metrics.completeness, metrics.verbatim_copy, metrics.histogram_distance,
            metrics.spectrum_distance, metrics.texture_report):
    _kw = {"patch_size": 4} if "patch_size" in inspect.signature(_fn).parameters else {}
    _METRIC_CASES[f"{_fn.__name__} output"] = (lambda v, f=_fn, kw=_kw: f(v, EX, **kw), "output", _BAD_IMAGES)
    _METRIC_CASES[f"{_fn.__name__} exemplar"] = (lambda v, f=_fn, kw=_kw: f(EX, v, **kw), "exemplar", _BAD_IMAGES)
for _fn in (metrics.texture_energy, metrics.completeness, metrics.verbatim_copy, metrics.texture_report):
    _METRIC_CASES[f"{_fn.__name__} patch_size"] = (lambda v, f=_fn: f(EX, EX, patch_size=v), "patch_size", _BAD_PATCH)
for _fn in (metrics.texture_energy, metrics.completeness, metrics.verbatim_copy):
    _METRIC_CASES[f"{_fn.__name__} stride"] = (lambda v, f=_fn: f(EX, EX, patch_size=4, stride=v), "stride", _BAD_STRIDE)
    _METRIC_CASES[f"{_fn.__name__} method"] = (lambda v, f=_fn: f(EX, EX, patch_size=4, method=v), "method", _BAD_METHODS)
    _METRIC_CASES[f"{_fn.__name__} rng"] = (lambda v, f=_fn: f(EX, EX, patch_size=4, rng=v), "rng", _BAD_RNG)
for _fn in (metrics.noise_baseline, metrics.mosaic_baseline, metrics.tiled_baseline, metrics.baselines):
    _METRIC_CASES[f"{_fn.__name__} exemplar"] = (lambda v, f=_fn: f(v, 8), "exemplar", _BAD_IMAGES)
    _METRIC_CASES[f"{_fn.__name__} size"] = (lambda v, f=_fn: f(EX, v), "size", _BAD_SIZES)
for _fn in (metrics.noise_baseline, metrics.mosaic_baseline, metrics.baselines, metrics.texture_report):
    _METRIC_CASES[f"{_fn.__name__} rng"] = (
        lambda v, f=_fn: f(EX, EX, patch_size=4, rng=v) if f is metrics.texture_report else f(EX, 8, rng=v),
        "rng", _BAD_RNG)
_METRIC_CASES.update({
    "verbatim_copy tolerance": (lambda v: metrics.verbatim_copy(EX, EX, patch_size=4, value_tolerance=v), "tolerance", _BAD_POSITIVE),
    "spectrum_distance bins": (lambda v: metrics.spectrum_distance(EX, EX, bins=v), "bins",
                               st.one_of(_NOT_INTS, st.integers(max_value=1))),
    "mosaic_baseline block": (lambda v: metrics.mosaic_baseline(EX, 8, block=v), "block",
                              st.one_of(st.booleans(), st.text(max_size=3), st.floats(), st.integers(max_value=0),
                                        st.integers(13, 10**6))),
    "texture_report with_baselines": (lambda v: metrics.texture_report(EX, EX, patch_size=4, with_baselines=v),
                                      "with_baselines", st.one_of(st.none(), st.integers(), st.text(max_size=3))),
})


@pytest.mark.parametrize("case", sorted(_METRIC_CASES))
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_bad_input_is_refused_naming_the_parameter(case, data):
    call, name, strategy = _METRIC_CASES[case]
    # the message names the parameter; a string is a file name, missing here (FileNotFoundError)
    with pytest.raises((TypeError, ValueError, FileNotFoundError), match=name):
        call(data.draw(strategy, label=name))


def test_long_wavelength_spectrum_tells_a_repeated_small_tile_from_a_fresh_crop(texture):
    # large-scale structure: a 32-px tile of the exemplar repeated over 128 px has the exemplar's
    # short wavelengths (its own pixels) but none of its long ones (only the period's harmonics);
    # a fresh crop of the same texture keeps both. Above 16 px the tile is far; below it, close.
    big = texture("skimage/gravel.png", 256)
    ex, fresh = big[:128, :128], big[128:, 128:]
    tiled = np.tile(ex[:32, :32], (4, 4))
    long_tiled = metrics.spectrum_distance(tiled, ex, min_wavelength=16)
    assert metrics.spectrum_distance(fresh, ex, min_wavelength=16) < 0.5 * long_tiled
    assert metrics.spectrum_distance(tiled, ex, max_wavelength=8) < long_tiled
    with pytest.raises(ValueError, match="min_wavelength"):
        metrics.spectrum_distance(ex, ex, min_wavelength=500)


def test_texture_report_measures_the_baselines_of_a_seed_once(monkeypatch):
    from texsynth.metrics import _patches as metrics  # the module whose globals texture_report reads

    rng = np.random.default_rng(4)
    ex, a, b = rng.random((24, 24, 3)), rng.random((32, 32, 3)), rng.random((32, 32, 3))
    first = metrics.texture_report(a, ex, rng=11)
    made = []
    real = metrics.baselines
    monkeypatch.setattr(metrics, "baselines", lambda *args, **kwargs: made.append(1) or real(*args, **kwargs))
    second = metrics.texture_report(b, ex, rng=11)
    assert made == [] and second.reference == first.reference  # measured once, for the first output
    second.reference["noise"]["energy"] = -1.0  # a caller's change does not reach the next report
    assert metrics.texture_report(b, ex, rng=11).reference == first.reference
    metrics.texture_report(b, ex, rng=None)  # fresh baselines: never from the cache
    metrics.texture_report(b, ex * 0.9, rng=11)  # another exemplar
    assert made == [1, 1]
    # the cached figures are those a fresh measurement gives
    monkeypatch.setattr(metrics, "_BASELINE_METRICS", {})
    assert metrics.texture_report(b, ex, rng=11).reference == first.reference
