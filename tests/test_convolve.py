"""core.convolve: FFT convolution with scipy.signal.fftconvolve's values, without importing scipy.signal."""

import subprocess
import sys

import numpy as np
import pytest
from scipy import signal

from texsynth.core.convolve import correlate_bank, fft_convolve


@pytest.mark.parametrize("shapes", [((249, 249), (127, 127)), ((33, 40), (15, 15)), ((100, 80), (7, 10)),
                                    ((5, 6), (9, 4))])
@pytest.mark.parametrize("mode", ["full", "same"])
def test_the_same_values_as_scipy_signal_bit_for_bit(shapes, mode):
    # both sides computed in this run: the same steps as scipy.signal, so the same bits on any machine
    rng = np.random.default_rng(0)
    a, b = rng.random(shapes[0]), rng.random(shapes[1])
    assert np.array_equal(fft_convolve(a, b, mode), signal.fftconvolve(a, b, mode=mode))


def test_a_flipped_kernel_is_the_correlation():
    rng = np.random.default_rng(1)
    g = rng.random((16, 16))
    assert np.allclose(fft_convolve(g, g[::-1, ::-1] / g.sum()), signal.correlate(g, g / g.sum(), mode="full"))


def test_bad_mode_and_shapes_are_refused():
    with pytest.raises(ValueError, match="mode must be one of"):
        fft_convolve(np.ones((3, 3)), np.ones((2, 2)), mode="valid")
    with pytest.raises(TypeError, match="mode must be one of 'full', 'same', got ndarray"):
        fft_convolve(np.ones((3, 3)), np.ones((2, 2)), mode=np.array(["full", "same"]))
    with pytest.raises(ValueError, match="2-D arrays"):
        fft_convolve(np.ones(3), np.ones((2, 2)))


@pytest.mark.parametrize("image_shape, kernel_shape", [((37, 45, 3), (5, 7, 9, 3)), ((16, 16, 1), (2, 16, 16, 1)),
                                                      ((20, 9, 2), (3, 1, 9, 2))])
def test_correlate_bank_is_every_patch_dotted_with_every_kernel(image_shape, kernel_shape):
    from numpy.lib.stride_tricks import sliding_window_view

    rng = np.random.default_rng(2)
    image, kernels = rng.random(image_shape), rng.standard_normal(kernel_shape)
    patches = np.moveaxis(sliding_window_view(image, kernel_shape[1:3], axis=(0, 1)), 2, -1)
    want = np.einsum("yxuvc,juvc->jyx", patches, kernels)
    got = correlate_bank(image, kernels)
    assert got.shape == want.shape and got.dtype == np.float64
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-10)


def test_correlate_bank_refuses_mismatched_shapes():
    with pytest.raises(ValueError, match="same C"):
        correlate_bank(np.ones((8, 8, 3)), np.ones((2, 3, 3, 1)))
    with pytest.raises(ValueError, match="do not fit"):
        correlate_bank(np.ones((8, 8, 1)), np.ones((2, 9, 3, 1)))


def test_texture_optimization_does_not_load_scipy_signal():
    # scipy.signal costs 0.3 s to import, a sixth of a small synthesis in a fresh process
    code = ("import sys, numpy as np, texsynth; from texsynth.optimization import Schedule, Terms; "
            "texsynth.optimize_texture(np.random.default_rng(0).random((32, 32)), 40, "
            "schedule=Schedule(neighborhood_sizes=(8,), max_iterations=1), terms=Terms(copy_limit=0.3), rng=0); "
            "print('scipy.signal' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
