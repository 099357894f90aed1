"""Quality metrics and test helpers, calibrated on real textures against the baselines."""

import numpy as np
import pytest
from scipy import ndimage

from texsynth import metrics
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
    (lambda ex: metrics.verbatim_copy(ex, ex, tolerance=0), "tolerance"),
    (lambda ex: metrics.texture_energy(ex, ex, stride=0), "stride"),
    (lambda ex: metrics.mosaic_baseline(ex, 20, block=100), "block"),
    (lambda ex: metrics.texture_energy(ex * 255, ex), "divide by 255"),
])
def test_bad_input(call, match, texture):
    with pytest.raises((ValueError, TypeError), match=match):
        call(texture("jcjohnson/bread.png", 32))
