"""core.convolve: FFT convolution with scipy.signal.fftconvolve's values, without importing scipy.signal."""

import subprocess
import sys

import numpy as np
import pytest
from scipy import signal

from texsynth.core.convolve import fft_convolve


@pytest.mark.parametrize("shapes", [((249, 249), (127, 127)), ((33, 40), (15, 15)), ((100, 80), (7, 10)),
                                    ((5, 6), (9, 4))])
@pytest.mark.parametrize("mode", ["full", "same"])
def test_the_same_values_as_scipy_signal_bit_for_bit(shapes, mode):
    # texture optimization's digests (tests/test_optimization_fields.py) rely on the same values
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
    with pytest.raises(ValueError, match="2-D arrays"):
        fft_convolve(np.ones(3), np.ones((2, 2)))


def test_texture_optimization_does_not_load_scipy_signal():
    # scipy.signal costs 0.3 s to import, a sixth of a small synthesis in a fresh process
    code = ("import sys, numpy as np, texsynth; texsynth.optimize_texture(np.random.default_rng(0).random((32, 32)), "
            "40, neighborhood_sizes=(8,), max_iterations=1, copy_limit=0.3, rng=0); "
            "print('scipy.signal' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
