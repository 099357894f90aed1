"""Random phase noise and asymptotic discrete spot noise (Galerne, Gousseau & Morel 2011).

A *micro-texture* is characterised by the modulus of its Fourier transform:
its phases carry no perceptual information, so replacing them by random ones
gives a new sample of the same texture. Two processes do it in one FFT:

random phase noise (RPN)
    ``m + F^-1( û(ξ) e^{iθ(ξ)} )`` with ``θ`` a uniform random phase that is
    odd-symmetric (``θ(-ξ) = -θ(ξ)``, so the result is real) and ``m`` the
    exemplar's mean: the Fourier modulus of the exemplar is kept exactly, the
    phases are scrambled. Colour images: the *same* ``θ`` is added to the
    phase of every channel, which keeps the phase differences between
    channels and therefore the colours.
asymptotic discrete spot noise (ADSN)
    ``m + t * W`` with the spot ``t = (u - m) / sqrt(|M|)``, ``W`` a standard
    Gaussian white noise and ``*`` the periodic convolution: a stationary
    Gaussian field whose covariance is the exemplar's normalised
    autocorrelation ``C_u = t * t̃``. Colour: every channel's spot is convolved
    with the *same* ``W``.

Both are applied to the periodic component of the exemplar (Moisan's
periodic-plus-smooth decomposition, :func:`texsynth.core.pyramid.
periodic_smooth_decomposition`, shared with Heeger-Bergen): the jump between
opposite borders of a photograph otherwise puts a bright cross in ``|û|``,
which the output copies as horizontal and vertical streaks.

Output sizes (the paper's spot extension): a larger output is the synthesis, at the
output's size ``Ω``, of the spot ``s = (p - m) / sqrt(|M|)`` zero-padded to
``Ω`` (the exemplar embedded in a constant image of its mean); the
normalisation keeps the variance of every pixel equal to the exemplar's. A
smaller output is the synthesis at the exemplar's size, cropped.

What could not be checked: the paper itself (doi:10.1109/TIP.2010.2052822)
was not at hand. This module follows the published
descriptions of the IPOL companion (doi:10.5201/ipol.2011.ggm_rpn), Moisan's
``perdecomp`` and public reimplementations. The
paper's spot extension also multiplies the embedded exemplar by a smooth
window that falls to 0 near its border; that window's exact shape and width
could not be confirmed, so the spot is zero-padded as it is.

References
----------
.. [1] B. Galerne, Y. Gousseau and J.-M. Morel, "Random phase textures: theory
   and synthesis", IEEE Trans. Image Processing 20(1), 257-267, 2011.
   doi:10.1109/TIP.2010.2052822
.. [2] B. Galerne, Y. Gousseau and J.-M. Morel, "Micro-texture synthesis by phase
   randomization", Image Processing On Line 1, 2011. doi:10.5201/ipol.2011.ggm_rpn
.. [3] L. Moisan, "Periodic plus smooth image decomposition", J. Math. Imaging
   Vis. 39(2), 2011. doi:10.1007/s10851-010-0227-1
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from ..core._validate import as_image, as_rng, as_size, check_memory, max_threads, restore_channels, with_channels
from ..core.pyramid import periodic_smooth_decomposition

__all__ = ["random_phase_noise", "RandomPhaseInfo"]

#: Values of ``process``: the random processes of Galerne et al.
PROCESSES = ("rpn", "adsn")
#: Values of ``periodic_exemplar`` (the vocabulary of :func:`~texsynth.statistical.heeger_bergen`).
PERIODIC_EXEMPLAR = ("periodic+smooth", "none")


@dataclass
class RandomPhaseInfo:
    """Diagnostics of :func:`random_phase_noise`.

    Attributes
    ----------
    process : str
        ``"rpn"`` or ``"adsn"``.
    periodic_exemplar : str
        ``"periodic+smooth"`` or ``"none"``.
    mean : numpy.ndarray
        ``(C,)`` the exemplar's mean colour ``m`` (the output's expected mean).
    synthesis_shape : tuple of int
        Size of the synthesis before the crop: the output's size where it is
        larger than the exemplar's, the exemplar's where it is smaller.
    clipped : float
        Fraction of output values clipped to [0, 1] (0 unless the exemplar
        has strong contrast; where it is 0 the modulus is kept exactly).
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"periodic component"``, ``"spot spectrum"``, ``"noise"``,
        ``"synthesis"`` (inverse FFT, mean, clip).
    """

    process: str
    periodic_exemplar: str
    mean: np.ndarray
    synthesis_shape: tuple
    clipped: float = 0.0
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


def random_phase_noise(exemplar, size=None, *, process="rpn", periodic_exemplar="periodic+smooth", rng=None,
                       return_info=False):
    """Synthesise a micro-texture by phase randomisation (Galerne, Gousseau & Morel 2011).

    Examples
    --------
    >>> import texsynth
    >>> exemplar = texsynth.data.load("metal")[:64, :64]
    >>> out, info = texsynth.random_phase_noise(exemplar, (48, 96), rng=0, return_info=True)
    >>> out.shape, out.dtype, info.synthesis_shape
    ((48, 96), dtype('float64'), (64, 96))
    >>> bool(abs(out.mean() - exemplar.mean()) < 0.02)
    True

    Keeps the exemplar's Fourier modulus and replaces its phase by a random
    one (or convolves its spot with white noise): a new sample of a
    micro-texture with the exemplar's spectrum, colours and
    autocorrelation [1]_ [2]_.

    Parameters
    ----------
    exemplar : array_like
        Grey ``(H, W)`` or colour ``(H, W, C)`` texture (uint8, uint16 or
        float in [0, 1]). A micro-texture: sand, gravel, grass, brushed metal,
        wood grain, clouds.
    size : int or (int, int), optional
        Output ``(height, width)``; default the exemplar's size. Any size:
        larger outputs use the paper's spot extension, smaller ones are crops
        of a synthesis at the exemplar's size.
    process : {"rpn", "adsn"}
        The random process. ``"rpn"`` (default): random phase noise, the exemplar's Fourier
        modulus with a uniform random phase added. ``"adsn"``: asymptotic
        discrete spot noise, the normalised spot convolved with Gaussian
        white noise (a Gaussian field with the exemplar's autocorrelation).
        The paper shows both give perceptually the same textures.
    periodic_exemplar : {"periodic+smooth", "none"}
        ``"periodic+smooth"`` (default, the paper's choice): synthesise from
        the periodic component of Moisan's decomposition, which removes the
        cross that the border jump puts in the spectrum. ``"none"``: the
        exemplar as it is (for exemplars that already tile).
    rng : None, int or numpy.random.Generator
        Seed of the random phase (RPN) or the white noise (ADSN).
    return_info : bool
        Also return a :class:`RandomPhaseInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channels, in [0, 1], the exemplar's float
        dtype. The output is periodic at the synthesis size (an output of the
        exemplar's size, or larger, tiles seamlessly).
    info : RandomPhaseInfo
        Only if ``return_info=True``.

    Raises
    ------
    ValueError
        For an unknown ``process`` or ``periodic_exemplar``, a bad ``size``, an
        exemplar with NaN/inf values or of the wrong shape, or a size that
        does not fit in memory (refused before anything is allocated).
    TypeError
        For an ``rng`` that is not None, an int or a Generator.

    Notes
    -----
    With ``p`` the periodic component of the exemplar ``u`` on ``M`` (``|M| =
    HW`` pixels), ``m`` its mean and ``Ω`` the synthesis domain, the spot is
    ``s = (p - m) / sqrt(|M|)`` zero-padded to ``Ω`` and

    - RPN: ``v = m + sqrt(|Ω|) F^-1( ŝ(ξ) e^{iθ(ξ)} )``, with ``e^{iθ} = Ŵ /
      |Ŵ|`` the phase of the FFT of a real white noise (odd-symmetric, real
      at the self-conjugate frequencies); at ``Ω = M`` this is exactly
      ``m + F^-1(|p̂ - m̂| e^{i(φ + θ)})``, the exemplar's modulus;
    - ADSN: ``v = m + s * W`` (periodic convolution on ``Ω``), ``W`` standard
      Gaussian white noise, so ``E[(v(x) - m)(v(x + τ) - m)] = Σ_y s(y)
      s(y + τ)`` is the exemplar's autocorrelation.

    Both keep every pixel's expected value ``m`` and variance (the
    exemplar's). The FFTs are real FFTs in float32 (``scipy.fft`` on all
    cores); the result is clipped to [0, 1].

    What works and what fails: micro-textures (phase-invariant textures)
    come out as new samples of the same texture; anything with edges or
    objects (bricks, text, pebbles with outlines) fails: its structure lives
    in the phases, which are thrown away, so the output is a blurry
    oriented noise with the right colours and spectrum.

    References
    ----------
    .. [1] B. Galerne, Y. Gousseau and J.-M. Morel, "Random phase textures:
       theory and synthesis", IEEE TIP 20(1), 2011.
       doi:10.1109/TIP.2010.2052822
    .. [2] B. Galerne, Y. Gousseau and J.-M. Morel, "Micro-texture synthesis by
       phase randomization", IPOL 1, 2011. doi:10.5201/ipol.2011.ggm_rpn
    """
    t_start = time.perf_counter()
    ex = as_image(exemplar, "exemplar")
    dtype = ex.dtype
    ex, grey = with_channels(ex.astype(np.float64, copy=False))
    shape = ex.shape[:2] if size is None else as_size(size)
    for value, name, allowed in ((process, "process", PROCESSES),
                                 (periodic_exemplar, "periodic_exemplar", PERIODIC_EXEMPLAR)):
        if not isinstance(value, str) or value not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    channels = ex.shape[-1]
    full = (max(shape[0], ex.shape[0]), max(shape[1], ex.shape[1]))  # the synthesis domain Ω
    n_full = float(full[0]) * full[1]
    # float32 spot and output, complex64 spectra of the spot and the noise (each about the image's size),
    # and the output in its dtype
    check_memory(n_full * (channels * (4 + 8 + 4) + 8 + 4) + float(shape[0]) * shape[1] * channels * 8,
                 tuple(shape))
    gen = as_rng(rng)
    workers = max_threads()
    stages = {}

    # The periodic component p and the normalised spot s = (p - m) / sqrt(|M|) (the spot extension).
    t = time.perf_counter()
    base = periodic_smooth_decomposition(ex)[0] if periodic_exemplar == "periodic+smooth" else ex
    mean = ex.reshape(-1, channels).mean(axis=0)  # p and u have the same mean (the smooth part's is 0)
    spot = np.ascontiguousarray(np.moveaxis(base - mean, -1, 0), dtype=np.float32)  # (C, H, W)
    spot /= np.float32(np.sqrt(ex.shape[0] * ex.shape[1]))
    stages["periodic component"] = time.perf_counter() - t

    # ŝ on Ω: the real FFT zero-pads the spot to the synthesis size.
    t = time.perf_counter()
    spectrum = sfft.rfft2(spot, s=full, axes=(1, 2), workers=workers)
    del spot
    stages["spot spectrum"] = time.perf_counter() - t

    # The noise: one real white noise for every channel, so its spectrum is Hermitian-symmetric.
    t = time.perf_counter()
    noise = sfft.rfft2(gen.standard_normal(full, dtype=np.float32), workers=workers, overwrite_x=True)
    if process == "rpn":
        # e^{iθ} = Ŵ / |Ŵ| times sqrt(|Ω|): the phase of a white noise, uniform and odd-symmetric, and
        # real (0 or π) at the self-conjugate frequencies (DC, Nyquist) where the FFT of a real noise is real.
        modulus = np.abs(noise)
        np.maximum(modulus, np.finfo(np.float32).tiny, out=modulus)  # |Ŵ(ξ)| = 0 has probability 0
        np.divide(np.float32(np.sqrt(n_full)), modulus, out=modulus)
        noise *= modulus
        del modulus
        noise[0, 0] = np.float32(np.sqrt(n_full))  # θ(0) = 0: the mean m is kept exactly
    stages["noise"] = time.perf_counter() - t

    # v = m + F^-1(ŝ · phase) (RPN) or m + F^-1(ŝ · Ŵ) = m + s * W (ADSN), cropped to the output.
    t = time.perf_counter()
    spectrum *= noise
    del noise
    result = sfft.irfft2(spectrum, s=full, axes=(1, 2), workers=workers, overwrite_x=True)
    del spectrum
    image = np.empty(tuple(shape) + (channels,), dtype=dtype)
    clipped = 0
    for c in range(channels):
        band = result[c, : shape[0], : shape[1]] + np.float32(mean[c])
        clipped += int(np.count_nonzero((band < 0) | (band > 1)))
        np.clip(band, 0.0, 1.0, out=image[..., c], casting="unsafe")
    del result
    stages["synthesis"] = time.perf_counter() - t

    image = restore_channels(image, grey)
    if not return_info:
        return image
    info = RandomPhaseInfo(process, periodic_exemplar, mean, full, clipped / image.size,
                           seconds=time.perf_counter() - t_start, stage_seconds=stages)
    return image, info
