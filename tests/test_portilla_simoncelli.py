"""Tests of Portilla-Simoncelli statistics and synthesis (texsynth.portilla_simoncelli).

All on 64x64 crops of the authors' own samples (../shared/textures/lcv) with 3 scales, so the
file runs in a few seconds. Thresholds are in dB of signal-to-noise ratio of the statistics
(``statistics_snr``: 10 log10(|target|^2 / |target - measured|^2)); 15 dB means the statistics
differ from the target by 18 % of its norm, 20 dB by 10 %.
"""

import functools
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import gaussian_filter

from texsynth import cli
from texsynth.statistical import heeger_bergen
from texsynth.io import load_image, save_image
from texsynth.statistical import SNR_CAP, SNR_GROUPS, PSStatistics, interpolate_statistics, portilla_simoncelli, ps_statistics, ps_step, statistics_snr
from texsynth.statistical._portilla_simoncelli import _impose_autocorrelation, _impose_cross_covariance, _impose_moment

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
GREY_GROUPS = [g for g in SNR_GROUPS if g != "cross_channel"]


def texture(name, top=0, left=0, side=64):
    path = TEXTURES / name
    if not path.is_file():
        pytest.skip(f"{path} is missing (the shared textures folder)")
    image = load_image(path)
    return image[top:top + side, left:left + side]


@pytest.fixture(scope="module")
def metal():
    return texture("lcv/metal.pgm")


@pytest.fixture(scope="module")
def water():
    return texture("embark/1.jpg", side=64)


def assert_same_statistics(a, b, rtol=1e-9, atol=1e-12):
    for name, value in a.arrays().items():
        np.testing.assert_allclose(getattr(b, name), value, rtol=rtol, atol=atol, equal_nan=True, err_msg=name)


# --------------------------------------------------------------------------- statistics
def test_statistics_shapes_and_pixel_moments(metal):
    s = ps_statistics(metal, scales=3, orientations=4, neighborhood_size=5)
    assert s.pixel.shape == (1, 6)
    assert s.lowpass_autocorrelation.shape == (1, 4, 5, 5)
    assert s.magnitude_autocorrelation.shape == (1, 3, 4, 5, 5)
    assert s.magnitude_cross_orientation.shape == (3, 4, 4)
    assert s.magnitude_cross_scale.shape == (2, 4, 4)
    assert s.real_cross_scale.shape == (2, 4, 8)
    d = metal - metal.mean()
    expected = [metal.mean(), d.var(), np.mean(d ** 3) / d.std() ** 3, np.mean(d ** 4) / d.var() ** 2,
                metal.min(), metal.max()]
    np.testing.assert_allclose(s.pixel[0], expected, rtol=1e-10)
    # The centre of a low-pass autocorrelation is its variance, and l_0 plus the high-pass
    # residual is the whole image, so their variances add up to about the image's (they are
    # nearly orthogonal: the pyramid is a tight frame).
    assert s.lowpass_autocorrelation[0, 0, 2, 2] + s.highpass_variance[0] == pytest.approx(d.var(), rel=0.05)
    # autocorrelations are symmetric: A(d) = A(-d)
    ac = s.magnitude_autocorrelation[0, 1, 2]
    np.testing.assert_allclose(ac, ac[::-1, ::-1], rtol=1e-10)


def test_statistics_invariant_to_circular_shifts(metal):
    base = ps_statistics(metal, scales=3)
    # A shift by a multiple of 2^scales moves every band by whole samples: exact invariance.
    assert_same_statistics(base, ps_statistics(np.roll(metal, (8, -16), axis=(0, 1)), scales=3), rtol=1e-8)
    # Any other shift moves the subsampled magnitudes by fractions of a sample: statistics
    # still agree to better than 55 dB (measured 64-150 dB), far above the 15 dB of a synthesis.
    snr = statistics_snr(ps_statistics(np.roll(metal, (3, 5), axis=(0, 1)), scales=3), base)
    assert min(snr[g] for g in GREY_GROUPS) > 55


def test_statistics_are_size_independent():
    # Two crops of one stationary texture at different sizes have similar statistics
    # (image units, central autocorrelations): closer than to another texture.
    big = ps_statistics(texture("lcv/metal.pgm", side=128), scales=3)
    small = ps_statistics(texture("lcv/metal.pgm", side=64), scales=3)
    other = ps_statistics(texture("lcv/reptil_skin.pgm", side=64), scales=3)
    same = statistics_snr(small, big)
    different = statistics_snr(other, big)
    assert np.mean([same[g] for g in GREY_GROUPS]) > np.mean([different[g] for g in GREY_GROUPS]) + 5


def test_mask_selects_region():
    metal = texture("lcv/metal.pgm")
    reptile = texture("lcv/reptil_skin.pgm")
    both = np.concatenate([metal, reptile], axis=1)  # 64 x 128: metal left, reptile right
    left = np.zeros(both.shape, bool)
    left[:, :64] = True
    masked = ps_statistics(both, scales=3, mask=left)
    inside = both[:, :64]
    np.testing.assert_allclose(masked.pixel[0, :2], [inside.mean(), inside.var()], rtol=1e-10)
    # the masked statistics describe metal, not reptile skin
    a = statistics_snr(masked, ps_statistics(metal, scales=3))
    b = statistics_snr(masked, ps_statistics(reptile, scales=3))
    assert np.mean([a[g] for g in GREY_GROUPS]) > np.mean([b[g] for g in GREY_GROUPS]) + 5
    # a mask of ones is no mask
    assert_same_statistics(ps_statistics(metal, scales=3, mask=np.ones(metal.shape, bool)),
                           ps_statistics(metal, scales=3))


def test_colour_statistics_have_cross_channel_terms(water):
    s = ps_statistics(water, scales=3)
    assert s.channels == 3
    np.testing.assert_allclose(s.color_basis.T @ s.color_basis, np.eye(3), atol=1e-12)
    assert s.magnitude_cross_orientation.shape == (3, 12, 12)
    assert s.real_cross_channel.shape == (3, 4, 3, 3)
    # principal components are uncorrelated as pixels ...
    comps = (water.reshape(-1, 3) - s.color_mean) @ s.color_basis
    cov = np.cov(comps.T, bias=True)
    assert np.abs(cov - np.diag(np.diag(cov))).max() < 1e-12
    # ... but not band by band: the cross-channel statistics carry information
    corr = s.real_cross_channel / np.sqrt(np.einsum("skii,skjj->skij", s.real_cross_channel, s.real_cross_channel))
    assert np.abs(corr[..., 0, 1]).max() > 0.05


# --------------------------------------------------------------------------- projections
def test_moment_projection_hits_reachable_targets(metal):
    x = metal - metal.mean()
    for order, target in ((3, 0.8), (3, -0.3), (4, 4.0), (4, 2.5)):
        y, _ = _impose_moment(x, target, order)
        d = y - y.mean()
        value = np.mean(d ** order) / d.std() ** order
        assert value == pytest.approx(target, abs=1e-6)
        assert y.mean() == pytest.approx(x.mean(), abs=1e-12)
        assert y.var() == pytest.approx(x.var(), rel=1e-10)


def test_autocorrelation_projection(metal):
    target = ps_statistics(metal, scales=3).lowpass_autocorrelation[0, 1][2:5, 2:5]  # 3x3, lags <= 1

    def central(y):
        full = np.fft.ifft2(np.abs(np.fft.fft2(y)) ** 2).real / y.size
        return full[np.ix_([-1, 0, 1], [-1, 0, 1])]

    noise = np.random.default_rng(0).standard_normal((32, 32))
    # From smooth noise FFT g is nearly non-negative: within 1e-3 in one step (measured 3e-4), and
    # exact once FFT g >= 0 (second step, measured 4e-16).
    smooth = gaussian_filter(noise, 1.0, mode="wrap")
    y, before = _impose_autocorrelation(smooth, target)
    np.testing.assert_allclose(central(y), target, atol=1e-3 * target[1, 1])
    y, _ = _impose_autocorrelation(y, target)
    np.testing.assert_allclose(central(y), target, atol=1e-10 * target[1, 1])
    assert before < 0
    # From white noise FFT g goes negative and is rectified, so each step is approximate, but
    # repeated projections converge (measured relative errors 0.43, 0.089, 0.017, 0.0045).
    errors = []
    y = noise
    for _ in range(4):
        y, _ = _impose_autocorrelation(y, target)
        errors.append(np.abs(central(y) - target).max() / target[1, 1])
    assert np.all(np.diff(errors) < 0) and errors[-1] < 0.01


def test_cross_covariance_projection_is_exact():
    rng = np.random.default_rng(1)
    x, y = rng.standard_normal((5000, 3)), rng.standard_normal((5000, 2))
    a = rng.standard_normal((3, 3))
    target_x = a @ a.T + np.eye(3)
    target_xy = np.array([[0.3, 0.0], [0.1, -0.2], [0.0, 0.4]])
    new, _, _ = _impose_cross_covariance(x, target_x, y, target_xy)
    np.testing.assert_allclose(new.T @ new / 5000, target_x, atol=1e-10)
    np.testing.assert_allclose(new.T @ y / 5000, target_xy, atol=1e-10)


# --------------------------------------------------------------------------- ps_step and synthesis
def test_ps_step_moves_noise_toward_target(metal):
    target = ps_statistics(metal, scales=3)
    image = np.random.default_rng(0).random((64, 64))
    history = []
    for _ in range(6):
        snr = statistics_snr(ps_statistics(image, scales=3), target)
        history.append([snr[g] for g in GREY_GROUPS])
        image = ps_step(image, target)
    history.append(list(statistics_snr(ps_statistics(image, scales=3), target).values())[:len(GREY_GROUPS)])
    history = np.array(history)
    mean = history.mean(axis=1)
    # rises on average: a positive least-squares slope and most steps up (measured: 2.4 -> 27 dB)
    assert np.polyfit(np.arange(len(mean)), mean, 1)[0] > 1.0
    assert np.sum(np.diff(mean) > 0) >= len(mean) - 2
    assert mean[-1] > mean[0] + 15
    assert np.all(history[-1] > history[0])  # every group ends closer than the noise started


def _disk(n=96, radius=30):
    yy, xx = np.mgrid[:n, :n]
    return np.hypot(yy - n / 2, xx - n / 2) < radius


def test_masked_step_keeps_the_outside_and_imposes_on_the_region():
    # Reptile-skin statistics imposed on a disk of a metal image (96x96, disk of radius 30, 3 scales).
    base = texture("lcv/metal.pgm", side=96)
    target = ps_statistics(texture("lcv/reptil_skin.pgm"), scales=3)
    disk = _disk()
    groups = [g for g in GREY_GROUPS if g != "pixel_range"]  # the range is often exact (SNR_CAP) from the start

    def region_snr(image):  # the region's statistics, as ps_statistics(mask=) measures them
        snr = statistics_snr(ps_statistics(image, scales=3, mask=disk), target)
        return np.mean([snr[g] for g in groups])

    masked, naive = base, base
    history = [region_snr(base)]
    for _ in range(8):
        masked = ps_step(masked, target, mask=disk)
        naive = np.where(disk, ps_step(naive, target), naive)  # whole-image step pasted into the region
        assert np.array_equal(masked[~disk], base[~disk])  # outside: exactly as it was
        history.append(region_snr(masked))
    pasted = region_snr(naive)
    # Measured (metal crops at 0, 100 and 160; targets text, nuts, reptile skin): the region starts at
    # -0.4..3.9 dB and ends (mean of the last 3 of 8 steps, which oscillate by a few dB: the region's
    # coarsest band is only 8x8 samples) at 11.6-16.7 dB, 7.8-13.9 dB higher; pasting whole-image steps
    # instead ends at 1.7-5.6 dB, because the projections then fit region and outside together. For this
    # case: 0.5 -> 14.4 dB, pasted 2.2 dB. Thresholds keep 3-5 dB margins.
    final = np.mean(history[-3:])
    assert final > history[0] + 8, history
    assert final > 10, history
    assert final > pasted + 6, (final, pasted)


def test_masked_step_soft_mask_ones_and_errors(metal):
    target = ps_statistics(texture("lcv/reptil_skin.pgm"), scales=3)
    # A mask of ones is no mask, bit for bit.
    np.testing.assert_array_equal(ps_step(metal, target, mask=np.ones(metal.shape)), ps_step(metal, target))
    # A soft mask blends: (1 - m) image + m projected, the projection measured on m > 0.5.
    ramp = np.clip(np.linspace(-0.5, 1.5, 64), 0, 1)[None, :].repeat(64, axis=0)
    soft = ps_step(metal, target, mask=ramp)
    hard = ps_step(metal, target, mask=ramp > 0.5)  # the projection itself wherever ramp > 0.5
    inside = ramp > 0.5
    np.testing.assert_allclose(soft[inside], ((1 - ramp) * metal + ramp * hard)[inside], atol=1e-12)
    assert np.array_equal(soft[ramp == 0], metal[ramp == 0])
    # colour, float32: the outside keeps its values and the dtype
    water = texture("embark/1.jpg").astype(np.float32)
    left = np.zeros(water.shape[:2], bool)
    left[:, :40] = True
    out = ps_step(water, ps_statistics(water, scales=3), mask=left)
    assert out.dtype == np.float32 and np.array_equal(out[:, 40:], water[:, 40:])
    with pytest.raises(ValueError, match="mask must have the image's spatial shape"):
        ps_step(metal, target, mask=np.ones((10, 10)))
    with pytest.raises(ValueError, match=r"mask values must be in \[0, 1\]"):
        ps_step(metal, target, mask=np.full(metal.shape, 2.0))
    with pytest.raises(ValueError, match="mask selects no pixel"):
        ps_step(metal, target, mask=np.zeros(metal.shape, bool))
    dot = np.zeros(metal.shape, bool)
    dot[1, 1] = True
    with pytest.raises(ValueError, match="at scale 1"):  # subsampled away at the next scale
        ps_step(metal, target, mask=dot)
    corner = np.zeros(metal.shape, bool)
    corner[:9, :9] = True
    with pytest.raises(ValueError, match="mask region is too small"):
        ps_step(metal, target, mask=corner)
    with pytest.raises(TypeError, match="mask"):
        ps_step(metal, target, mask=np.full(metal.shape, "a"))


def test_command_line_portilla_simoncelli(tmp_path):
    src = save_image(tmp_path / "metal.png", texture("lcv/metal.pgm", side=32))
    out = tmp_path / "ps.png"
    assert cli.main(["portilla-simoncelli", str(src), "-o", str(out), "--scales", "2", "--iterations", "1",
                     "--size", "40x24", "--seed", "0"]) == 0
    image = load_image(out)
    assert image.shape == (24, 40) and 0.0 <= image.min() and image.max() <= 1.0
    assert cli.main(["portilla-simoncelli", str(src), "-o", str(tmp_path / "same.png"), "--scales", "2",
                     "--iterations", "1", "--no-progress"]) == 0
    assert load_image(tmp_path / "same.png").shape == (32, 32)  # default: the input's size


# The PS authors' own samples (the paper's figs. 3-8 use them), 64x64 top-left crops, 3 scales.
CLASSIC = ["lcv/metal.pgm", "lcv/reptil_skin.pgm", "lcv/text.pgm", "lcv/nuts.pgm"]
# The groups of joint statistics that Heeger-Bergen does not impose (it matches each band's histogram
# alone), and the low-pass groups that it matches only in part (through the low-pass band's histogram and
# the bands' power). The marginal groups (pixel, pixel_range, highpass) are left out of the comparison:
# HB's grey output of the exemplar's size is a permutation of the exemplar's pixels, so its pixel
# statistics are exact (SNR_CAP) and PS cannot beat them.
JOINT_GROUPS = ["magnitude_autocorrelation", "magnitude_cross_orientation", "magnitude_cross_scale",
                "real_cross_scale"]
LOWPASS_GROUPS = ["lowpass_moments", "lowpass_autocorrelation"]


@functools.lru_cache(maxsize=None)
def classic_run(name):
    """SNR (dB per group) against a 64x64 crop's statistics of: PS (15 iterations), HB (5 iterations),
    clipped Gaussian noise with the crop's mean and variance (PS's start), and a second crop of the same
    photograph (what a perfect synthesis could be). Seed 0; computed once for the tests below."""
    exemplar = texture(name)
    other = texture(name, 128, 128)
    target = ps_statistics(exemplar, scales=3)

    def snr(image):
        return statistics_snr(ps_statistics(image, scales=3), target)

    noise = np.clip(np.random.default_rng(0).normal(exemplar.mean(), exemplar.std(), exemplar.shape), 0, 1)
    return {"ps": snr(portilla_simoncelli(exemplar, scales=3, iterations=15, rng=0)),
            "hb": snr(heeger_bergen(exemplar, scales=3, iterations=5, rng=0)),
            "noise": snr(noise), "natural": snr(other)}


@pytest.mark.parametrize("name", CLASSIC)
def test_synthesis_matches_exemplar_statistics(name):
    run = classic_run(name)
    got, start, natural = run["ps"], run["noise"], run["natural"]
    # Tolerance, measured on these four crops: the noise start is at -28..13 dB in every group but
    # pixel_range (21-39 dB; seeds 0-2), and a second crop of the same texture, which a perfect synthesis
    # could be, lies at -3..150 dB. After 15 iterations (seeds 0-4) every group is at 15.7-150 dB except
    # the cross-scale phase statistics (real_cross_scale), the slowest to converge, at 13.2-16.2 dB on
    # nuts and 17-29 dB on the others. Floors of 12 dB (25 % relative error) and 10 dB (32 %) for the
    # phase group leave about 3 dB of margin for other seeds and platforms.
    for g in GREY_GROUPS:
        floor = 10 if g == "real_cross_scale" else 12
        assert got[g] > floor, (name, g, got[g])
        assert got[g] > start[g] or got[g] == SNR_CAP, (name, g, got[g], start[g])
    # On average the synthesis is closer than the natural variation between two crops: measured +12.6 to
    # +16.1 dB on nuts and +21 to +32 dB on the other three; 8 dB leaves the margin.
    assert np.mean([got[g] for g in GREY_GROUPS]) > np.mean([natural[g] for g in GREY_GROUPS]) + 8


@pytest.mark.parametrize("name", CLASSIC)
def test_portilla_simoncelli_beats_heeger_bergen_on_joint_statistics(name):
    run = classic_run(name)
    ps, hb = run["ps"], run["hb"]
    # HB's output matches the marginals exactly, which is why the comparison leaves them out.
    assert hb["pixel"] == SNR_CAP
    # Measured over the four crops: on the magnitude and phase groups PS is at 13-34 dB, HB at -4..17 dB and
    # noise at -0.2..4 dB (seeds 0-2); PS leads HB by at least 11.8 dB in every one of these groups (0-4).
    # A lead of 8 dB (PS's error under 40 % of HB's) keeps a 4 dB margin.
    for g in JOINT_GROUPS:
        assert ps[g] > hb[g] + 8, (name, g, ps[g], hb[g])
    # Low-pass groups: HB gets part of them on stochastic textures (2.9-29 dB; noise 0.1-13 dB), PS 27-47
    # dB (seeds 0-2); smallest lead 5.5 dB over seeds 0-4 (nuts, whose low-pass image HB's low-pass
    # histogram already describes well); 3 dB keeps the margin.
    for g in LOWPASS_GROUPS:
        assert ps[g] > hb[g] + 3, (name, g, ps[g], hb[g])


def test_convergence_info(metal):
    out, info = portilla_simoncelli(metal, (64, 80), scales=3, iterations=8, rng=0, return_info=True)
    assert out.shape == (64, 80)
    assert set(info.snr) == set(SNR_GROUPS)
    assert info.change.shape == (8,)
    assert np.all(np.isnan(info.snr["cross_channel"]))  # grey: no cross-channel statistics
    mean = np.nanmean([info.snr[g] for g in GREY_GROUPS], axis=0)
    assert mean[-1] > mean[0] + 15  # measured ~ +30 dB after 8 iterations
    assert isinstance(info.statistics, PSStatistics)


def test_seed_reproducibility(metal):
    a = portilla_simoncelli(metal, scales=3, iterations=2, rng=5)
    b = portilla_simoncelli(metal, scales=3, iterations=2, rng=np.random.default_rng(5))
    c = portilla_simoncelli(metal, scales=3, iterations=2, rng=6)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).mean() > 0.05


def test_synthesis_from_statistics_is_synthesis_from_the_exemplar(metal):
    a = ps_statistics(metal, scales=3)
    b = ps_statistics(texture("lcv/reptil_skin.pgm"), scales=3)
    at_zero = interpolate_statistics(a, b, 0.0)
    # Same statistics, same seed, same iteration scheme (noise start, momentum): the same image, bit for bit.
    from_stats, info = portilla_simoncelli(at_zero, (64, 72), iterations=4, rng=0, return_info=True)
    from_exemplar, info_ex = portilla_simoncelli(metal, (64, 72), scales=3, iterations=4, rng=0, return_info=True)
    np.testing.assert_array_equal(from_stats, from_exemplar)
    for g in SNR_GROUPS:
        np.testing.assert_array_equal(info.snr[g], info_ex.snr[g])
    assert info.statistics is at_zero and from_stats.dtype == np.float64
    # scales/orientations/neighborhood are the statistics' own: repeating them is allowed
    np.testing.assert_array_equal(
        portilla_simoncelli(a, (64, 72), scales=3, orientations=4, neighborhood_size=7, iterations=4, rng=0), from_stats)


def test_synthesis_from_interpolated_statistics_lies_between(metal):
    a = ps_statistics(metal, scales=3)
    b = ps_statistics(texture("lcv/reptil_skin.pgm"), scales=3)
    mid = interpolate_statistics(a, b, 0.5)
    got = ps_statistics(portilla_simoncelli(mid, 64, iterations=15, rng=0), scales=3)
    to_mid, to_a, to_b = statistics_snr(got, mid), statistics_snr(got, a), statistics_snr(got, b)
    ends = statistics_snr(a, mid)  # where the two textures themselves are: 0.2-32 dB, mean 11.9 dB
    # Measured over seeds 0-4: every group within 21.8-150 dB of the interpolated target (mean 46-50 dB),
    # while the output is 8.8-14.4 dB (mean) from either texture. 15 dB per group (18 % relative error, as
    # the synthesis from an exemplar) and a 20 dB lead of the midpoint on average keep wide margins.
    for g in GREY_GROUPS:
        assert to_mid[g] > 15, (g, to_mid[g])
        assert to_mid[g] > ends[g] or to_mid[g] == SNR_CAP, (g, to_mid[g], ends[g])
    mean = {k: np.mean([v[g] for g in GREY_GROUPS]) for k, v in (("mid", to_mid), ("a", to_a), ("b", to_b))}
    assert mean["mid"] > max(mean["a"], mean["b"]) + 20, mean
    # and the plain numbers lie between the two textures'
    for value, ends_ in ((got.pixel[0, 1], (a.pixel[0, 1], b.pixel[0, 1])),
                         (got.magnitude_means.mean(), (a.magnitude_means.mean(), b.magnitude_means.mean()))):
        assert min(ends_) < value < max(ends_)


def test_synthesis_from_statistics_errors(metal, water):
    stats = ps_statistics(metal, scales=3)
    with pytest.raises(ValueError, match="size is required"):
        portilla_simoncelli(stats)
    with pytest.raises(ValueError, match="scales=4 but the statistics were measured with scales=3"):
        portilla_simoncelli(stats, 64, scales=4)
    with pytest.raises(ValueError, match="neighborhood_size=5"):
        portilla_simoncelli(stats, 64, neighborhood_size=5)
    with pytest.raises(ValueError, match="periodic_exemplar"):
        portilla_simoncelli(stats, 64, periodic_exemplar="periodic+smooth")
    with pytest.raises(ValueError, match="size is 16x64 but scales=3"):
        portilla_simoncelli(stats, (16, 64))
    with pytest.raises(ValueError, match="iterations"):
        portilla_simoncelli(stats, 64, iterations=0)
    colour = portilla_simoncelli(ps_statistics(water, scales=3), (40, 48), iterations=1, rng=0)
    assert colour.shape == (40, 48, 3) and colour.dtype == np.float64


def test_layouts_and_dtypes(metal, water):
    grey = portilla_simoncelli(metal, 72, scales=3, iterations=1, rng=0)
    assert grey.shape == (72, 72) and grey.dtype == np.float64
    single = portilla_simoncelli(metal[..., None].astype(np.float32), (64, 70), scales=3, iterations=1, rng=0)
    assert single.shape == (64, 70, 1) and single.dtype == np.float32
    u8 = portilla_simoncelli((water * 255).astype(np.uint8), scales=3, iterations=1, rng=0)
    assert u8.shape == (64, 64, 3) and u8.dtype == np.float64
    for out in (grey, single, u8):
        assert out.min() >= 0 and out.max() <= 1
    step = ps_step(water.astype(np.float32), ps_statistics(water, scales=3))
    assert step.shape == water.shape and step.dtype == np.float32


def test_colour_synthesis_enforces_cross_channel_statistics(water):
    target = ps_statistics(water, scales=3)
    out, info = portilla_simoncelli(water, scales=3, iterations=10, rng=0, return_info=True)
    got = statistics_snr(ps_statistics(out, scales=3, color_basis=target.color_basis), target)
    # measured ~18 dB; PCA noise start ~0 dB; the clipping to the exemplar's colour range
    # (the last step) disturbs the band cross-correlations a little.
    assert got["cross_channel"] > 10
    assert info.snr["cross_channel"][-1] > info.snr["cross_channel"][0] + 5
    # the colours stay the exemplar's: mean colour within 0.03
    np.testing.assert_allclose(out.reshape(-1, 3).mean(axis=0), water.reshape(-1, 3).mean(axis=0), atol=0.03)


def test_interpolate_statistics(metal):
    a = ps_statistics(metal, scales=3)
    b = ps_statistics(texture("lcv/reptil_skin.pgm"), scales=3)
    assert_same_statistics(interpolate_statistics(a, b, 0.0), a, rtol=0, atol=0)
    assert_same_statistics(interpolate_statistics(a, b, 1.0), b, rtol=0, atol=0)
    mid = interpolate_statistics(a, b, 0.25)
    for name, value in a.arrays().items():
        np.testing.assert_allclose(getattr(mid, name), 0.75 * value + 0.25 * getattr(b, name), err_msg=name)
    with pytest.raises(ValueError, match="alpha"):
        interpolate_statistics(a, b, 1.5)
    with pytest.raises(ValueError, match="scales"):
        interpolate_statistics(a, ps_statistics(metal, scales=2), 0.5)
    with pytest.raises(TypeError, match="PSStatistics"):
        interpolate_statistics(a, {}, 0.5)


def test_interpolate_colour_needs_one_basis(water):
    a = ps_statistics(water, scales=3)
    b = ps_statistics(texture("jcjohnson/bread.png", side=96), scales=3)
    with pytest.raises(ValueError, match="color_basis"):
        interpolate_statistics(a, b, 0.5)
    b = ps_statistics(texture("jcjohnson/bread.png", side=96), scales=3, color_basis=a.color_basis)
    assert interpolate_statistics(a, b, 0.5).channels == 3


# --------------------------------------------------------------------------- bad input
def test_too_small_names_the_sizes_that_work(metal):
    with pytest.raises(ValueError, match=r"exemplar is 32x32 but scales=4 needs at least 64x64.*scales=3"):
        portilla_simoncelli(metal[:32, :32])
    with pytest.raises(ValueError, match="size is 40x80"):
        portilla_simoncelli(metal, (40, 80), iterations=1)
    with pytest.raises(ValueError, match="needs at least 64x64"):
        ps_statistics(metal[:48])
    with pytest.raises(ValueError, match="image is 32x32"):
        ps_step(metal[:32, :32], ps_statistics(metal))


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 5), st.integers(4, 70), st.integers(4, 70))
def test_size_rule_property(scales, h, w):
    image = np.full((h, w), 0.5)
    if min(h, w) >= 2 ** (scales + 2):
        assert ps_statistics(image + 0.01 * np.sin(np.arange(w)), scales=scales).scales == scales
    else:
        with pytest.raises(ValueError, match=f"needs at least {2 ** (scales + 2)}x{2 ** (scales + 2)}"):
            ps_statistics(image, scales=scales)


def test_bad_values_and_options(metal):
    bad = metal.copy()
    bad[3, 3] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        portilla_simoncelli(bad, scales=3)
    with pytest.raises(ValueError, match="iterations must be an integer >= 1, got 0"):
        portilla_simoncelli(metal, scales=3, iterations=0)
    with pytest.raises(ValueError, match="neighborhood_size must be odd"):
        ps_statistics(metal, scales=3, neighborhood_size=6)
    with pytest.raises(TypeError, match="scales"):
        ps_statistics(metal, scales=2.5)
    with pytest.raises(ValueError, match="mask must have the image's spatial shape"):
        ps_statistics(metal, scales=3, mask=np.ones((10, 10), bool))
    with pytest.raises(ValueError, match="mask selects no pixel"):
        ps_statistics(metal, scales=3, mask=np.zeros(metal.shape, bool))
    with pytest.raises(ValueError, match="3 channel"):
        ps_step(metal, ps_statistics(np.stack([metal] * 3, axis=-1), scales=3))
    with pytest.raises(TypeError, match="PSStatistics"):
        ps_step(metal, None)
    with pytest.raises(ValueError, match="orthogonal"):
        ps_statistics(np.stack([metal] * 3, axis=-1), scales=3, color_basis=np.ones((3, 3)))
