"""Tests of the shared pyramid layer: exact reconstruction, tight frame, orientation, shapes, errors."""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from skimage.transform import resize

from texsynth.io import load_image
from texsynth.core.pyramid import BINOMIAL_KERNEL, SteerablePyramid, downsample, gaussian_pyramid, laplacian_pyramid, max_levels, max_scales, periodic_smooth_decomposition, reconstruct_laplacian, upsample

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
EXACT = 1e-10  # the brief's bound; float64 rounding gives about 1e-15


@pytest.fixture(scope="module")
def metal():
    """lcv/metal.pgm resized to 48x56 (non-square, real texture)."""
    return resize(load_image(TEXTURES / "lcv" / "metal.pgm"), (48, 56), anti_aliasing=True)


@pytest.fixture(scope="module")
def bread():
    return resize(load_image(TEXTURES / "jcjohnson" / "bread.png"), (37, 50), anti_aliasing=True)


# ----------------------------------------------------------------------------- REDUCE / EXPAND
def test_downsample_is_binomial_blur_then_decimation():
    # Compare with an explicit computation: reflect-pad by 2, 5-tap binomial per axis, every 2nd sample.
    img = np.random.default_rng(1).random((9, 12))
    pad = np.pad(img, 2, mode="reflect")
    k = BINOMIAL_KERNEL
    rows = sum(k[i] * pad[i : i + 9, :] for i in range(5))
    full = sum(k[i] * rows[:, i : i + 12] for i in range(5))
    np.testing.assert_allclose(downsample(img), full[::2, ::2], atol=1e-14)
    wrapped = np.pad(img, 2, mode="wrap")
    rows = sum(k[i] * wrapped[i : i + 9, :] for i in range(5))
    full = sum(k[i] * rows[:, i : i + 12] for i in range(5))
    np.testing.assert_allclose(downsample(img, mode="wrap"), full[::2, ::2], atol=1e-14)


def test_upsample_is_adjoint_of_downsample_with_wrap():
    # With periodic boundaries and even sizes, EXPAND = 4 * REDUCE^T in 2-D (factor 2 per axis).
    rng = np.random.default_rng(2)
    x, y = rng.random((16, 12)), rng.random((8, 6))
    lhs = np.sum(downsample(x, mode="wrap") * y)
    rhs = np.sum(x * upsample(y, (16, 12), mode="wrap")) / 4
    assert abs(lhs - rhs) < 1e-12


def test_upsample_keeps_constants_and_rejects_wrong_shape():
    assert np.allclose(upsample(np.full((4, 5, 2), 0.3), (7, 9)), 0.3)
    with pytest.raises(ValueError, match="does not downsample"):
        upsample(np.zeros((4, 5)), (10, 10))


@pytest.mark.parametrize("mode", ["reflect", "wrap"])
def test_laplacian_exact_grey_colour(metal, bread, mode):
    for img in (metal, bread):
        pyr = laplacian_pyramid(img, 4, mode=mode)
        assert len(pyr) == 4
        assert np.abs(reconstruct_laplacian(pyr, mode=mode) - img).max() < EXACT


def test_laplacian_exact_volume_and_float32():
    vol = np.random.default_rng(3).random((9, 14, 11, 2))
    pyr = laplacian_pyramid(vol, 3, spatial_dims=3)
    assert [p.shape for p in pyr] == [(9, 14, 11, 2), (5, 7, 6, 2), (3, 4, 3, 2)]
    assert np.abs(reconstruct_laplacian(pyr, spatial_dims=3) - vol).max() < EXACT
    img32 = vol[0].astype(np.float32)
    pyr32 = laplacian_pyramid(img32, 3)
    assert all(p.dtype == np.float32 for p in pyr32)
    assert np.abs(reconstruct_laplacian(pyr32) - img32).max() < 1e-5  # float32 rounding


def test_laplacian_bands_are_bandpass(metal):
    # A smooth image has almost no energy in the finest Laplacian band; the real texture has much more.
    yy, xx = np.mgrid[:48, :56]
    smooth = 0.5 + 0.4 * np.sin(2 * np.pi * xx / 56)
    assert np.abs(laplacian_pyramid(smooth, 2, mode="wrap")[0]).max() < 0.01
    assert np.abs(laplacian_pyramid(metal, 2, mode="wrap")[0]).max() > 0.05


def test_gaussian_pyramid_shapes_odd_sizes():
    shapes = [g.shape for g in gaussian_pyramid(np.zeros((13, 7, 3)), 4)]
    assert shapes == [(13, 7, 3), (7, 4, 3), (4, 2, 3), (2, 1, 3)]
    assert [g.shape for g in gaussian_pyramid(np.zeros((5, 6, 7)), 3, spatial_dims=3)] == [
        (5, 6, 7), (3, 3, 4), (2, 2, 2)]
    # every level is a blurred version: a constant stays constant
    assert all(np.allclose(g, 0.25) for g in gaussian_pyramid(np.full((11, 9), 0.25), 5))


def test_gaussian_pyramid_bad_levels():
    img = np.zeros((13, 7))
    assert max_levels(img.shape) == 4  # 7 -> 4 -> 2 -> 1
    gaussian_pyramid(img, 4)
    with pytest.raises(ValueError, match=r"levels=5 .* between 1 and 4"):
        gaussian_pyramid(img, 5)
    with pytest.raises(ValueError, match="levels=0"):
        gaussian_pyramid(img, 0)
    with pytest.raises(TypeError, match="levels"):
        gaussian_pyramid(img, 2.0)
    with pytest.raises(ValueError, match="mode"):
        gaussian_pyramid(img, 2, mode="nearest")
    with pytest.raises(ValueError, match="spatial axes"):
        downsample(np.zeros((4, 4, 4, 4)))
    with pytest.raises(TypeError, match="floating point"):
        downsample(np.zeros((4, 4), dtype=np.int32))
    # uint8 is scaled to [0, 1] as at every public boundary of texsynth
    assert gaussian_pyramid(np.full((4, 4), 255, np.uint8), 2)[1].max() == pytest.approx(1.0)


@pytest.mark.parametrize("call, match", [
    (lambda: downsample(np.zeros((8, 8)), mode=["wrap"]), r"mode must be one of 'reflect', 'wrap', got list"),
    (lambda: downsample(np.zeros((8, 8)), mode=np.array(["wrap", "reflect"])), "mode must be one of"),
    (lambda: upsample(np.zeros((4, 4)), (8, 8), mode=["wrap"]), "mode must be one of"),
    (lambda: gaussian_pyramid(np.zeros((8, 8)), 2, mode=["wrap"]), "mode must be one of"),
    (lambda: laplacian_pyramid(np.zeros((8, 8)), 2, mode=np.array(["wrap"])), "mode must be one of"),
    (lambda: downsample(np.zeros((8, 8)), spatial_dims=np.array([2, 3])), "spatial_dims must be one of 2, 3"),
    (lambda: downsample(np.zeros((8, 8)), spatial_dims=2.0), "spatial_dims must be one of 2, 3"),
    (lambda: max_levels("x"), "shape must be a tuple of ints"),
    (lambda: max_levels(None), "shape must be a tuple of ints"),
    (lambda: max_levels(8), "shape must be a tuple of ints"),
    (lambda: max_levels(()), "shape must be a tuple of ints"),
    (lambda: max_levels((-1, 4)), r"shape must be .*non-negative.*got \(-1, 4\)"),
    (lambda: max_scales("x"), "shape must be a tuple of ints"),
    (lambda: max_scales([[1, 2]]), "shape must be a tuple of ints"),
    (lambda: max_scales((8.5, 8)), "shape must be a tuple of ints"),
    (lambda: upsample(np.zeros((4, 4)), "x"), "shape must be a tuple of ints"),
    (lambda: upsample(np.zeros((4, 4)), (7.5, 8)), "shape must be a tuple of ints"),
])
def test_junk_options_name_the_parameter(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()


@pytest.mark.parametrize("call", [
    lambda a: gaussian_pyramid(a, 2),
    lambda a: laplacian_pyramid(a, 2),
    lambda a: SteerablePyramid(a.shape, 1, 4).decompose(a),
])
def test_pyramids_refuse_non_finite_and_empty_input(call):
    bad = np.zeros((8, 8))
    bad[3, 4] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        call(bad)
    bad[3, 4] = np.inf
    with pytest.raises(ValueError, match="NaN or infinite"):
        call(bad)
    with pytest.raises(ValueError, match="empty|shape"):
        call(np.zeros((0, 8)))


# ----------------------------------------------------------------------------- steerable pyramid
@pytest.mark.parametrize("orientations", [1, 2, 4, 6])
@pytest.mark.parametrize("shape", [(32, 32), (33, 33), (31, 45), (40, 96)])
def test_steerable_exact_reconstruction(shape, orientations):
    img = np.random.default_rng(sum(shape) + orientations).random(shape)
    for is_complex in (False, True):
        pyr = SteerablePyramid(shape, max_scales(shape), orientations, is_complex=is_complex)
        coeffs = pyr.decompose(img)
        assert np.abs(pyr.reconstruct(coeffs) - img).max() < EXACT


def test_steerable_exact_on_real_texture(metal):
    pyr = SteerablePyramid(metal.shape, 3, 4)
    assert np.abs(pyr.reconstruct(pyr.decompose(metal)) - metal).max() < EXACT


@pytest.mark.parametrize("orientations", [1, 3, 4])
def test_steerable_is_a_parseval_tight_frame(metal, orientations):
    # The masks satisfy H0^2 + L0^2 = 1, H^2 + L^2 = 1, sum_k A_k^2 = 1 and the crops are rescaled by
    # sqrt(N_{s+1}/N_s), so the real coefficients carry exactly the image's energy.
    pyr = SteerablePyramid(metal.shape, 3, orientations)
    coeffs = pyr.decompose(metal)
    energy = sum(float(np.sum(a**2)) for a in coeffs.arrays())
    assert abs(energy / np.sum(metal**2) - 1) < 1e-12
    # and the adjoint is the inverse: <Ax, c> = <x, A^T c> for coefficients of another image
    other = pyr.decompose(np.random.default_rng(0).random(metal.shape))
    lhs = sum(float(np.sum(a * b)) for a, b in zip(coeffs.arrays(), other.arrays()))
    rhs = float(np.sum(metal * pyr.reconstruct(other)))
    assert abs(lhs - rhs) < 1e-9 * abs(rhs)


def test_complex_bands_real_part_is_real_band(metal):
    real = SteerablePyramid(metal.shape, 3, 4).decompose(metal)
    cplx = SteerablePyramid(metal.shape, 3, 4, is_complex=True).decompose(metal)
    assert cplx.bands[0][0].dtype == np.complex128 and real.bands[0][0].dtype == np.float64
    for rs, cs in zip(real.bands, cplx.bands):
        for r, c in zip(rs, cs):
            assert np.abs(c.real - r).max() < 1e-12
            # analytic: the imaginary part is not trivially zero (a Hilbert pair of the real band)
            assert np.sum(c.imag**2) > 0.5 * np.sum(r**2)
    np.testing.assert_allclose(cplx.highpass, real.highpass, atol=1e-12)


def test_band_and_residual_shapes_odd():
    pyr = SteerablePyramid((37, 50), 3, 2)
    coeffs = pyr.decompose(np.zeros((37, 50)))
    assert [b[0].shape for b in coeffs.bands] == [(37, 50), (19, 25), (10, 13)]
    assert coeffs.lowpass.shape == (5, 7)
    assert len(coeffs.arrays()) == 2 + 3 * 2


@pytest.mark.parametrize("orientations", [2, 4, 6])
def test_orientation_selectivity(orientations):
    # A grating whose wave vector is at angle theta (from the column axis toward the row axis) puts most of
    # the oriented energy in the band k whose angle pi*k/K is nearest theta (mod pi).
    n = 64
    yy, xx = np.mgrid[:n, :n]
    pyr = SteerablePyramid((n, n), 3, orientations)
    for theta in np.linspace(0, np.pi, 7, endpoint=False) + 0.1:
        f = 0.3  # cycles per pixel: inside scale 0's annulus (normalised radius 0.6)
        grating = np.cos(2 * np.pi * f * (np.cos(theta) * xx + np.sin(theta) * yy))
        coeffs = pyr.decompose(grating)
        energy = np.array([np.sum(b**2) for b in coeffs.bands[0]])
        distance = np.abs((theta - np.pi * np.arange(orientations) / orientations + np.pi / 2) % np.pi - np.pi / 2)
        assert np.argmax(energy) == np.argmin(distance)
        assert energy.max() > 0.4 * energy.sum()  # clearly dominant, not a tie


def test_steerable_float32_keeps_dtype():
    img = np.random.default_rng(0).random((24, 24)).astype(np.float32)
    pyr = SteerablePyramid(img.shape, 2, 4)
    c = pyr.decompose(img)
    assert c.highpass.dtype == np.float32 and c.bands[1][2].dtype == np.float32
    assert np.abs(pyr.reconstruct(c) - img).max() < 1e-5


def test_steerable_bad_input():
    assert max_scales((64, 100)) == 4
    with pytest.raises(ValueError, match=r"scales=5 .* at least 128 pixels .* between 0 and 4"):
        SteerablePyramid((64, 100), 5, 4)
    with pytest.raises(ValueError, match="orientations"):
        SteerablePyramid((64, 64), 2, 0)
    with pytest.raises(TypeError, match="scales"):
        SteerablePyramid((64, 64), 2.5, 4)
    pyr = SteerablePyramid((32, 32), 2, 4)
    with pytest.raises(ValueError, match="shape"):
        pyr.decompose(np.zeros((32, 31)))
    with pytest.raises(ValueError, match="orientations"):
        SteerablePyramid((32, 32), 2, 2).reconstruct(pyr.decompose(np.zeros((32, 32))))


@settings(max_examples=20, deadline=None)
@given(h=st.integers(4, 40), w=st.integers(4, 40), k=st.integers(1, 5), cplx=st.booleans())
def test_steerable_exact_any_shape(h, w, k, cplx):
    img = np.random.default_rng(h * 100 + w).random((h, w))
    pyr = SteerablePyramid((h, w), max_scales((h, w)), k, is_complex=cplx)
    assert np.abs(pyr.reconstruct(pyr.decompose(img)) - img).max() < EXACT


@settings(max_examples=20, deadline=None)
@given(h=st.integers(1, 30), w=st.integers(1, 30), levels=st.integers(1, 6))
def test_laplacian_any_shape(h, w, levels):
    img = np.random.default_rng(h * 100 + w).random((h, w))
    if levels > max_levels((h, w)):
        with pytest.raises(ValueError, match="levels"):
            laplacian_pyramid(img, levels)
    else:
        assert np.abs(reconstruct_laplacian(laplacian_pyramid(img, levels)) - img).max() < EXACT


# ----------------------------------------------------------------------------- periodic + smooth
def _periodic_laplacian(u):
    return sum(np.roll(u, s, axis=a) for s in (1, -1) for a in (0, 1)) - 4 * u


def _interior_laplacian(u):
    """Free-boundary Laplacian: sum over the neighbours inside the image of (neighbour - u)."""
    out = np.zeros_like(u)
    out[1:] += u[:-1] - u[1:]
    out[:-1] += u[1:] - u[:-1]
    out[:, 1:] += u[:, :-1] - u[:, 1:]
    out[:, :-1] += u[:, 1:] - u[:, :-1]
    return out


def test_periodic_smooth_characterisation(bread):
    # Moisan 2011, Theorem 1: the periodic component p is the unique image with mean(p) = mean(u) whose
    # periodic Laplacian equals the interior Laplacian of u.
    p, s = periodic_smooth_decomposition(bread)
    assert p.shape == bread.shape and s.shape == bread.shape
    np.testing.assert_allclose(p + s, bread, atol=1e-12)
    for c in range(3):
        np.testing.assert_allclose(_periodic_laplacian(p[..., c]), _interior_laplacian(bread[..., c]), atol=1e-10)
        assert abs(s[..., c].mean()) < 1e-12


def test_periodic_component_removes_the_spectral_cross(metal):
    # A photograph under uneven lighting is not periodic: the border jump puts a "cross" of energy on the
    # frequency axes. Measured on metal with a 0.3 lighting ramp: axis/off-axis power in the ring
    # 0.02 < |f| < 0.15 is 11.5 for the image and 1.4 for its periodic component; the border jump relative
    # to the mean neighbour jump is 4.6 versus 0.4. Thresholds sit between the two.
    yy, xx = np.mgrid[:48, :56]
    lit = 0.7 * metal + 0.3 * (0.5 * xx / 55 + 0.5 * yy / 47)
    p, _ = periodic_smooth_decomposition(lit)

    def cross(u):
        power = np.abs(np.fft.fft2(u - u.mean())) ** 2
        fy = np.abs(np.fft.fftfreq(u.shape[0]))[:, None]
        fx = np.abs(np.fft.fftfreq(u.shape[1]))[None, :]
        axis = (fy == 0) | (fx == 0)
        ring = (np.hypot(fy, fx) > 0.02) & (np.hypot(fy, fx) < 0.15)
        return power[ring & axis].mean() / power[ring & ~axis].mean()

    def border_jump(u):
        jump = np.mean((u[0] - u[-1]) ** 2) + np.mean((u[:, 0] - u[:, -1]) ** 2)
        return jump / (np.mean(np.diff(u, axis=0) ** 2) + np.mean(np.diff(u, axis=1) ** 2))

    assert cross(lit) > 5 and cross(p) < 2.5
    assert border_jump(lit) > 2 and border_jump(p) < 1


def test_complex_band_magnitude_is_the_envelope():
    # For a grating, the analytic band is A exp(i phase): its magnitude is flat (the local amplitude
    # Portilla-Simoncelli use) while its real part oscillates between -A and A.
    n = 64
    yy, xx = np.mgrid[:n, :n]
    grating = np.cos(2 * np.pi * (8 * xx + 3 * yy) / n)  # periodic on the grid, |f| = 0.13 cycles/pixel
    coeffs = SteerablePyramid((n, n), 3, 4, is_complex=True).decompose(grating)
    energies = [np.sum(np.abs(b) ** 2) for s in coeffs.bands for b in s]
    band = [b for s in coeffs.bands for b in s][int(np.argmax(energies))]
    magnitude = np.abs(band)
    assert magnitude.std() < 1e-6 * magnitude.mean()
    assert band.real.std() > 0.5 * magnitude.mean()
    # the phase advances by 2 pi * 8 / width per band pixel (8 cycles across, whatever the band's scale)
    phase_step = np.angle(band[:, 1:] / band[:, :-1])
    np.testing.assert_allclose(np.abs(phase_step), 2 * np.pi * 8 / band.shape[1], atol=1e-6)
