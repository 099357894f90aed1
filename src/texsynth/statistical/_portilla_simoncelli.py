"""Portilla-Simoncelli texture synthesis from joint statistics of complex wavelet coefficients.

Portilla & Simoncelli (2000) describe a texture by several hundred numbers (710 for the defaults)
measured on a complex steerable pyramid (4 scales x 4 orientations by
default) and synthesise a new texture by starting from Gaussian noise and
projecting it, again and again, onto the set of images with those numbers.
This module follows the authors' MATLAB ``textureSynth`` (textureAnalysis.m /
textureSynthesis.m), written from the paper and that code's structure.

The statistics (the paper's section 3; :class:`PSStatistics`)
-------------------------------------------------------------
With ``z_{s,k}`` the complex (analytic) band of scale ``s`` and orientation
``k``, ``l_s`` the low-pass image of scale ``s`` (the partial reconstruction
of the pyramid from scale ``s`` down, sampled at that scale's resolution) and
``h`` the high-pass residual:

1. marginal statistics of the pixels: mean, variance, skewness, kurtosis,
   minimum and maximum; skewness and kurtosis of every ``l_s`` (sec. 3.1);
2. raw coefficient correlation: the central ``Na x Na`` autocorrelation of
   every ``l_s`` (sec. 3.2, ``Na`` = ``neighborhood``);
3. coefficient magnitude statistics (sec. 3.3): the central autocorrelation of
   every ``|z_{s,k}|`` (mean removed), the correlation of magnitudes across
   orientations at the same scale and with the parent's magnitudes (the
   coarser scale expanded to this one);
4. cross-scale phase statistics (sec. 3.4): the correlation of ``Re z_{s,k}``
   with the real and imaginary parts of the phase-doubled parent
   ``p^2 / |p|`` (``p`` the expanded band of scale ``s + 1``);
5. the variance of the high-pass residual.

All numbers are in image units: band values are rescaled by
``sqrt(N_s / N_0)`` (``N_s`` pixels at scale ``s``), so that a band of scale
``s`` has the amplitude of the image structure it represents whatever the
image's size. Autocorrelations are central (lags ``-(Na-1)/2 .. (Na-1)/2``),
so statistics measured on an image of one size can be imposed on an image of
another size.

Synthesis (the paper's section 4; :func:`ps_step`)
--------------------------------------------------
One iteration, as textureSynthesis.m orders it: decompose the current image;
impose the autocorrelation, skewness and kurtosis on the coarsest low-pass
image; then from coarse to fine, at every scale: impose the magnitudes'
cross-orientation and cross-scale correlations (the modified covariance
adjustment, eq. 8), the magnitudes' autocorrelations, put the magnitudes back
under the bands' phases, impose the real parts' correlation with the
phase-doubled parent, project the bands back to analytic signals, add them to
the expanded coarser low-pass image and impose that image's autocorrelation,
skewness and kurtosis; reduce the high-pass residual's variance if it is too
large; add it, and impose the pixel mean, variance, skewness, kurtosis and
range. :func:`portilla_simoncelli` iterates this from noise, with the MATLAB
code's "accelerator" (the new image is pushed 0.8 times further along the
last change, and the last un-pushed image is returned), from an exemplar or
from given statistics (e.g. two textures' mixed by
:func:`interpolate_statistics`, the paper's sec. 6). ``ps_step(...,
mask=region)`` imposes statistics on a region of an image only: every
statistic is measured on the region, the correction is computed from it, and
the pixels outside are kept.

Colour (Ruiters et al. 2010, sec. 4.5)
--------------------------------------
The colour channels are decorrelated by a principal component analysis of
the exemplar's colours, and every component gets the grey statistics above.
Added, as Ruiters et al. describe ("an additional cross correlation between
the three color channels for each band of the pyramid"): the magnitude
correlations of item 3 and the phase statistics of item 4 are taken jointly
over all channels (``C K x C K`` matrices instead of ``K x K``), and for every
band the ``C x C`` covariance of the real parts across channels and for every
scale the ``C x C`` covariance of the low-pass images are recorded and
imposed (their correlation coefficients, keeping the variances the grey
projections set). Synthesis works in the principal components; the result is
mapped back to the input's colours and clipped to the exemplar's range.

Differences from textureSynth, all deliberate: the pyramid is
:class:`texsynth.core.pyramid.SteerablePyramid` (any image size, not only
multiples of ``2^(scales+2)``); values are in image units (above); the
exemplar is analysed as it is, without the MATLAB code's tiny added noise
(so statistics are deterministic; eigenvalues are clamped instead); the phase
is doubled as the paper writes it (``p^2/|p|``; the MATLAB code doubles
``atan2(Re, Im)``, a reflected angle, which carries the same information);
the orthogonal factor of every covariance adjustment is the one that changes
the data least (orthogonal Procrustes), and the skewness/kurtosis projections
solve their polynomial equations directly from the sample moments of the
data and of the gradient direction.

References
----------
.. [1] J. Portilla and E. P. Simoncelli, "A parametric texture model based on
   joint statistics of complex wavelet coefficients", International Journal
   of Computer Vision 40(1), 49-70, 2000. doi:10.1023/A:1026553619983
.. [2] A. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
   interpolation", Computer Graphics Forum 29(4) (EGSR), 2010.
   doi:10.1111/j.1467-8659.2010.01736.x
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from numpy.polynomial import polynomial as npoly

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS, one_blas_thread
from ..core._validate import (as_image, as_rng, as_size, check_in_range, check_memory, check_positive_int,
                              restore_channels, with_channels)
from ..core.pyramid import SteerableCoefficients, SteerablePyramid, level_shapes, max_scales, periodic_smooth_decomposition

__all__ = [
    "PSStatistics",
    "PSInfo",
    "ps_statistics",
    "ps_step",
    "statistics_snr",
    "interpolate_statistics",
    "portilla_simoncelli",
]

#: Momentum of textureSynthesis.m's "accelerator": im <- im + 0.8 (im - previous).
ACCELERATION = 0.8
#: SNR reported when a statistic is matched exactly (dB); keeps averages finite.
SNR_CAP = 150.0
# textureSynthesis.m skips autocorrelation / moment projections of low-pass images
# whose variance is below 1e-4 of the pixel variance (they carry no structure).
_NEGLIGIBLE_VARIANCE = 1e-4

SNR_GROUPS = (
    "pixel",
    "pixel_range",
    "lowpass_moments",
    "lowpass_autocorrelation",
    "magnitude_autocorrelation",
    "magnitude_cross_orientation",
    "magnitude_cross_scale",
    "real_cross_scale",
    "highpass",
    "cross_channel",
)


# --------------------------------------------------------------------------- the statistics
@dataclass(eq=False)
class PSStatistics:
    """Portilla-Simoncelli statistics of a grey or colour texture.

    ``C`` channels (1 for grey; the principal components for colour),
    ``S`` scales, ``K`` orientations, ``Na`` neighbourhood. Autocorrelation
    windows are ``Na x Na`` with NaN where the band was too small to measure
    that lag. Index ``c * K + k`` runs over (channel, orientation) pairs.

    Attributes
    ----------
    scales, orientations, neighborhood : int
    color_mean : numpy.ndarray, (C,)
        Mean colour subtracted before the principal component analysis (0 for grey).
    color_basis : numpy.ndarray, (C, C)
        Principal axes as columns (identity for grey): components = (x - mean) @ basis.
    color_range : numpy.ndarray, (C, 2)
        Minimum and maximum of every input channel.
    pixel : numpy.ndarray, (C, 6)
        Mean, variance, skewness, kurtosis, minimum, maximum of every component.
    lowpass_moments : numpy.ndarray, (C, S + 1, 2)
        Skewness and kurtosis of the low-pass images ``l_0 .. l_S``.
    lowpass_autocorrelation : numpy.ndarray, (C, S + 1, Na, Na)
    magnitude_means : numpy.ndarray, (C, S, K)
    magnitude_autocorrelation : numpy.ndarray, (C, S, K, Na, Na)
    magnitude_cross_orientation : numpy.ndarray, (S, C K, C K)
        Covariance of the (mean-free) magnitudes of all bands of one scale.
    magnitude_cross_scale : numpy.ndarray, (S - 1, C K, C K)
        Covariance of the magnitudes with the expanded parent's magnitudes.
    real_cross_scale : numpy.ndarray, (S - 1, C K, 2 C K)
        Covariance of the real parts with the real and imaginary parts of the
        phase-doubled expanded parent.
    real_cross_channel : numpy.ndarray, (S, K, C, C)
        Covariance of the real parts of one band across channels.
    lowpass_cross_channel : numpy.ndarray, (S + 1, C, C)
        Covariance of the low-pass images across channels.
    highpass_variance : numpy.ndarray, (C,)
    """

    scales: int
    orientations: int
    neighborhood: int
    color_mean: np.ndarray
    color_basis: np.ndarray
    color_range: np.ndarray
    pixel: np.ndarray
    lowpass_moments: np.ndarray
    lowpass_autocorrelation: np.ndarray
    magnitude_means: np.ndarray
    magnitude_autocorrelation: np.ndarray
    magnitude_cross_orientation: np.ndarray
    magnitude_cross_scale: np.ndarray
    real_cross_scale: np.ndarray
    real_cross_channel: np.ndarray
    lowpass_cross_channel: np.ndarray
    highpass_variance: np.ndarray

    @property
    def channels(self):
        """Number of channels ``C``."""
        return int(self.color_basis.shape[0])

    def arrays(self):
        """The statistics arrays by name (everything but the sizes and the colour basis)."""
        skip = {"scales", "orientations", "neighborhood", "color_basis"}
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name not in skip}


@dataclass
class PSInfo:
    """Convergence of :func:`portilla_simoncelli`.

    Attributes
    ----------
    snr : dict of str to numpy.ndarray
        For every group of statistics (``SNR_GROUPS``), one value per
        iteration: the signal-to-noise ratio ``10 log10(|target|^2 /
        |target - current|^2)`` in dB, averaged over the group, measured just
        before the iteration's projection of that group (as textureSynthesis.m's
        ``snrP``). Capped at ``SNR_CAP``.
    change : numpy.ndarray
        Root-mean-square change of the image in every iteration.
    statistics : PSStatistics
        The target statistics (the exemplar's, or the ones given).
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"analysis"`` (measuring the exemplar's statistics; 0 when they
        were given) and ``"synthesis"`` (the iterated projections).
    """

    snr: dict
    change: np.ndarray
    statistics: PSStatistics = field(repr=False)
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


def _snr(target, current):
    """10 log10(|target|^2 / |target - current|^2), capped (textureSynth's snr.m)."""
    target, current = np.asarray(target, dtype=float), np.asarray(current, dtype=float)
    ok = np.isfinite(target) & np.isfinite(current)
    signal = float(np.sum(target[ok] ** 2))
    noise = float(np.sum((target[ok] - current[ok]) ** 2))
    if noise <= signal * 10 ** (-SNR_CAP / 10) or noise == 0.0:
        return SNR_CAP
    if signal == 0.0:
        return -SNR_CAP
    return float(min(SNR_CAP, 10 * math.log10(signal / noise)))


# --------------------------------------------------------------------------- pyramid plumbing
def _single_threaded_blas(function):
    """Run with one BLAS thread: the products here are tall and thin ((N, m) with m <= 2 C K), where
    threads gain nothing, and multi-threaded OpenBLAS spin-waits for 20-70 ms per product on a busy
    machine (measured on the 2-core VM under load: 0.1 ms single-threaded)."""

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with one_blas_thread():
            return function(*args, **kwargs)

    return wrapper


class _Plan:
    """Pyramids and masks for one image shape (cached: building masks costs FFT-sized arrays).

    The full complex pyramid analyses the image; per scale ``s`` a one-scale pyramid of that
    scale's size synthesises the oriented bands alone (textureSynthesis.m's "fake pyramid",
    with the top low-pass mask L0), and zero-scale pyramids give the L0-filtered coarsest
    low-pass band and the H0-filtered high-pass residual.
    """

    def __init__(self, shape, scales, orientations):
        self.shape, self.scales, self.orientations = shape, scales, orientations
        self.pyramid = SteerablePyramid(shape, scales, orientations, is_complex=True)
        self.sizes = sizes = level_shapes(shape, scales + 1)
        # Image units: a band of scale s carries sqrt(N_0 / N_s) times the image's amplitude.
        self.gain = [math.sqrt(h * w / (shape[0] * shape[1])) for h, w in sizes]
        self.band_pyramids = [SteerablePyramid(sizes[s], 1, orientations) for s in range(scales)]
        self.top = SteerablePyramid(shape, 0, orientations)
        self.bottom = SteerablePyramid(sizes[scales], 0, orientations)
        self.analytic = [_analytic_masks(sizes[s], orientations) for s in range(scales)]

    def decompose(self, image):
        """Complex pyramid in image units: (highpass, bands[s] as (K, h, w), lowpass)."""
        c = self.pyramid.decompose(image)
        bands = [np.stack(c.bands[s]) * self.gain[s] for s in range(self.scales)]
        return c.highpass, bands, c.lowpass * self.gain[self.scales]

    def coarsest_lowpass(self, lowpass):
        """l_S: the low-pass residual filtered by L0 (textureAnalysis.m's buildSFpyr(lo, 0, 0))."""
        return self.bottom.decompose(lowpass).lowpass

    def band_image(self, s, bands):
        """Image of the real parts of the K bands of scale s alone, at that scale's size."""
        h, w = self.sizes[s]
        nxt = self.sizes[s + 1]
        coeffs = SteerableCoefficients(np.zeros((h, w)), [list(np.real(bands))], np.zeros(nxt))
        return self.band_pyramids[s].reconstruct(coeffs)

    def highpass_image(self, highpass):
        coeffs = SteerableCoefficients(highpass, [], np.zeros(self.shape))
        return self.top.reconstruct(coeffs)


@functools.lru_cache(maxsize=8)
def _plan(shape, scales, orientations):
    return _Plan(shape, scales, orientations)


def _analytic_masks(shape, orientations):
    """Fourier masks making a real band analytic again (textureSynthesis.m, "Re-create analytic subbands").

    2 on the half-plane of band k's passband, 0 on the opposite one, 1 on the line between, at
    DC and on Nyquist rows/columns (which have no opposite frequency).
    """
    fy = sfft.fftfreq(shape[0])[:, None]
    fx = sfft.fftfreq(shape[1])[None, :]
    angle = np.arctan2(fy, fx)
    masks = np.empty((orientations,) + tuple(shape))
    for k in range(orientations):
        c = np.cos(angle - np.pi * k / orientations)
        masks[k] = np.where(np.abs(c) < 1e-12, 1.0, np.where(c > 0, 2.0, 0.0))
        masks[k][0, 0] = 1.0
        if shape[0] % 2 == 0:
            masks[k][shape[0] // 2, :] = 1.0
        if shape[1] % 2 == 0:
            masks[k][:, shape[1] // 2] = 1.0
    return masks


def _expand(x, shape):
    """Interpolate ``x`` (size ceil(n/2)) to ``shape`` by zero-padding its spectrum (MATLAB ``expand``).

    Values keep their amplitude; complex (analytic) bands stay analytic. Exact for the
    pyramid's bands, whose spectra vanish near the coarse grid's Nyquist frequency.
    """
    small = x.shape[-2:]
    spectrum = sfft.fft2(x, axes=(-2, -1))
    out = np.zeros(x.shape[:-2] + tuple(shape), dtype=complex)
    idx = []
    for m, n in zip(small, shape):
        f = np.arange(m)
        f = np.where(f < m - m // 2, f, f - m)
        idx.append(f % n)
    out[..., idx[0][:, None], idx[1][None, :]] = spectrum * (shape[0] * shape[1] / (small[0] * small[1]))
    out = sfft.ifft2(out, axes=(-2, -1))
    return out if np.iscomplexobj(x) else out.real


def _double_phase(z):
    """p^2 / |p|: same magnitude, doubled phase (sec. 3.4; 0 where p = 0)."""
    mag = np.abs(z)
    return np.where(mag > 0, z * z / np.where(mag > 0, mag, 1.0), 0.0)


def _parents(bands_parent, shape, where=None):
    """Expanded parent magnitudes (mean-free) and real/imaginary parts of the phase-doubled parent.

    bands_parent: (C, K, h, w) complex at scale s + 1. Returns (N, C K) and (N, 2 C K). ``where``
    (N,) bool: the magnitudes' mean is the region's (default: all pixels').
    """
    c, k = bands_parent.shape[:2]
    up = _expand(bands_parent, shape).reshape(c * k, -1)
    mag = np.abs(up)
    mag -= mag.mean(axis=1, keepdims=True) if where is None else mag[:, where].mean(axis=1, keepdims=True)
    doubled = _double_phase(up)
    # columns: channel c: [Re of K orientations, Im of K orientations]
    real = np.concatenate([np.concatenate([doubled[i * k:(i + 1) * k].real, doubled[i * k:(i + 1) * k].imag])
                           for i in range(c)])
    return mag.T, real.T


# --------------------------------------------------------------------------- weighted measurements
def _central(full, radius):
    """Central (2 radius + 1)^2 lags of a circular autocorrelation stored in natural FFT order."""
    lags = np.arange(-radius, radius + 1)
    return full[np.ix_(lags % full.shape[0], lags % full.shape[1])]


def _autocorrelation(x, weight, radius):
    """Central autocorrelation sum_x m m' x x' / sum_x m m' (circular; m = region mask)."""
    if weight is None:
        spec = sfft.rfft2(x)
        full = sfft.irfft2(np.abs(spec) ** 2, s=x.shape) / x.size
        return _central(full, radius)
    spec, mspec = sfft.rfft2(x * weight), sfft.rfft2(weight)
    num = sfft.irfft2(np.abs(spec) ** 2, s=x.shape)
    den = sfft.irfft2(np.abs(mspec) ** 2, s=x.shape)
    num, den = _central(num, radius), _central(den, radius)
    if np.any(den < 0.5):
        raise ValueError("mask region is too small or too thin to measure the autocorrelation "
                         f"of a {x.shape[0]}x{x.shape[1]} band; pass a larger mask or fewer scales")
    return num / den


def _moments(x, weight=None):
    """Weighted mean, variance, skewness and kurtosis."""
    w = np.ones_like(x) if weight is None else weight
    total = float(w.sum())
    mean = float((w * x).sum() / total)
    d = x - mean
    d2 = d * d
    m2, m3, m4 = (float((w * v).sum() / total) for v in (d2, d2 * d, d2 * d2))
    if m2 <= 0:
        return mean, 0.0, 0.0, 3.0
    return mean, m2, m3 / m2 ** 1.5, m4 / m2 ** 2


def _masked_rows(matrix, weight):
    """Rows (pixels) of an (N, m) matrix inside the region (all rows without a mask)."""
    return matrix if weight is None else matrix[weight.ravel() > 0]


def _scale_weights(mask, sizes):
    """The region at every scale: the mask subsampled like the pyramid (samples 0, 2, 4, ...)."""
    if mask is None:
        return [None] * len(sizes)
    out = [mask]
    for _ in sizes[1:]:
        out.append(out[-1][::2, ::2])
    return [w.astype(float) for w in out]


# --------------------------------------------------------------------------- analysis
def _put_central(values, neighborhood):
    out = np.full((neighborhood, neighborhood), np.nan)
    la, le = (neighborhood - 1) // 2, (values.shape[0] - 1) // 2
    out[la - le:la + le + 1, la - le:la + le + 1] = values
    return out


def _analysis_radius(shape, neighborhood):
    """Largest central lag measured on a band (textureAnalysis.m: min(Na, size/2 - 1))."""
    return max(0, min((neighborhood - 1) // 2, min(shape) // 2 - 1))


def _analyse(components, plan, neighborhood, mask):
    """Statistics of decorrelated channels (C, H, W); everything except the colour fields."""
    C, S, K = components.shape[0], plan.scales, plan.orientations
    weights = _scale_weights(mask, plan.sizes)
    pixel = np.zeros((C, 6))
    low_mom = np.zeros((C, S + 1, 2))
    low_ac = np.full((C, S + 1, neighborhood, neighborhood), np.nan)
    mag_mean = np.zeros((C, S, K))
    mag_ac = np.full((C, S, K, neighborhood, neighborhood), np.nan)
    hp_var = np.zeros(C)
    lowpass_images = [[None] * (S + 1) for _ in range(C)]
    all_bands = [[None] * C for _ in range(S)]
    for c in range(C):
        x = components[c]
        mean, var, skew, kurt = _moments(x, weights[0])
        inside = x if mask is None else x[mask > 0]
        pixel[c] = mean, var, skew, kurt, inside.min(), inside.max()
        highpass, bands, lowpass = plan.decompose(x)
        hp_mean, hp_variance = _moments(highpass, weights[0])[:2]
        hp_var[c] = hp_variance + hp_mean ** 2  # mean square, as textureAnalysis.m's vHPR0
        lowpass = lowpass - _moments(lowpass, weights[S])[0]
        low = plan.coarsest_lowpass(lowpass)
        for s in range(S, -1, -1):
            if s < S:
                low = _expand(low, plan.sizes[s]) + plan.band_image(s, bands[s])
                all_bands[s][c] = bands[s]
                for k in range(K):
                    mag = np.abs(bands[s][k])
                    mag_mean[c, s, k] = _moments(mag, weights[s])[0]
                    r = _analysis_radius(plan.sizes[s], neighborhood)
                    ac = _autocorrelation(mag - mag_mean[c, s, k], weights[s], r)
                    mag_ac[c, s, k] = _put_central(ac, neighborhood)
            r = _analysis_radius(plan.sizes[s], neighborhood)
            ac = _autocorrelation(low, weights[s], r)
            low_ac[c, s] = _put_central(ac, neighborhood)
            m = _moments(low, weights[s])
            low_mom[c, s] = m[2], m[3]
            lowpass_images[c][s] = low
    # Joint (cross-orientation, cross-scale, cross-channel) covariances.
    mag_co = np.zeros((S, C * K, C * K))
    mag_cs = np.zeros((max(S - 1, 0), C * K, C * K))
    real_cs = np.zeros((max(S - 1, 0), C * K, 2 * C * K))
    real_cc = np.zeros((S, K, C, C))
    low_cc = np.zeros((S + 1, C, C))
    for s in range(S):
        z = np.stack(all_bands[s])  # (C, K, h, w)
        n = z.shape[-2] * z.shape[-1]
        mags = np.abs(z).reshape(C * K, n).T - mag_mean[:, s].reshape(1, C * K)
        mags = _masked_rows(mags, weights[s])
        mag_co[s] = mags.T @ mags / mags.shape[0]
        reals = _masked_rows(z.real.reshape(C * K, n).T, weights[s])
        for k in range(K):
            rk = reals[:, k::K]
            real_cc[s, k] = rk.T @ rk / rk.shape[0]
        if s < S - 1:
            pmag, preal = _parents(np.stack(all_bands[s + 1]), plan.sizes[s])
            pmag, preal = _masked_rows(pmag, weights[s]), _masked_rows(preal, weights[s])
            mag_cs[s] = mags.T @ pmag / mags.shape[0]
            real_cs[s] = reals.T @ preal / reals.shape[0]
    for s in range(S + 1):
        lows = _masked_rows(np.stack([lowpass_images[c][s].ravel() for c in range(C)]).T, weights[s])
        low_cc[s] = lows.T @ lows / lows.shape[0]
    return dict(pixel=pixel, lowpass_moments=low_mom, lowpass_autocorrelation=low_ac, magnitude_means=mag_mean,
                magnitude_autocorrelation=mag_ac, magnitude_cross_orientation=mag_co,
                magnitude_cross_scale=mag_cs, real_cross_scale=real_cs, real_cross_channel=real_cc,
                lowpass_cross_channel=low_cc, highpass_variance=hp_var)


def _pca_basis(pixels):
    """Principal axes (columns, largest variance first) with a deterministic sign."""
    mean = pixels.mean(axis=0)
    centred = pixels - mean
    _, basis = np.linalg.eigh(centred.T @ centred / max(len(pixels), 1))
    basis = basis[:, ::-1]
    signs = np.sign(basis[np.argmax(np.abs(basis), axis=0), np.arange(basis.shape[1])])
    return mean, basis * np.where(signs == 0, 1.0, signs)


def _check_scales_fit(scales, shape, what):
    """The pyramid needs 2^(scales+2) pixels along each axis (its coarsest band keeps 8)."""
    if scales > max_scales(shape):
        need = 2 ** (scales + 2) if scales < 60 else float("inf")  # no trillion-bit integers in a message
        sizes = ", ".join(f"{s} scale{'s' if s > 1 else ''}: >= {2 ** (s + 2)} px" for s in range(1, min(scales, 6) + 1))
        name = "size" if what == "output" else what
        raise ValueError(
            f"{name} is {shape[0]}x{shape[1]} but scales={scales} needs at least {need}x{need} pixels "
            f"({sizes}); pass scales={max(max_scales(shape), 1)} or a larger {name}"
        )


def _check_neighborhood(neighborhood_size):
    neighborhood_size = check_positive_int(neighborhood_size, "neighborhood_size", minimum=1)
    if neighborhood_size % 2 == 0:
        raise ValueError(f"neighborhood_size must be odd (a centred window, e.g. 7 as in the paper), "
                         f"got {neighborhood_size}")
    return neighborhood_size


#: Values of ``periodic_exemplar`` (the vocabulary of :func:`~texsynth.statistical.heeger_bergen`).
PERIODIC_EXEMPLAR = ("periodic+smooth", "none")


def _check_periodic(periodic_exemplar):
    """True for Moisan's periodic component, False for the image itself."""
    if not isinstance(periodic_exemplar, str) or periodic_exemplar not in PERIODIC_EXEMPLAR:
        raise ValueError(f"periodic_exemplar must be one of {PERIODIC_EXEMPLAR}, got {periodic_exemplar!r}")
    return periodic_exemplar == "periodic+smooth"


def _check_mask(mask, shape):
    if mask is None:
        return None
    m = np.asarray(mask)
    if m.shape != tuple(shape):
        raise ValueError(f"mask must have the image's spatial shape {tuple(shape)}, got {m.shape}")
    if not (m.dtype == bool or np.issubdtype(m.dtype, np.number)) or not np.all(np.isfinite(m)):
        raise TypeError(f"mask must be a boolean or numeric (H, W) array, got dtype {m.dtype}")
    m = (m > 0.5) if m.dtype != bool else m
    if not m.any():
        raise ValueError("mask selects no pixel; pass a mask with True where statistics are measured")
    return m.astype(float)


def _components(image, color_mean, color_basis):
    """(H, W, C) image -> (C, H, W) decorrelated components."""
    return np.moveaxis((image - color_mean) @ color_basis, -1, 0)


def _image_from_components(components, stats):
    return np.moveaxis(components, 0, -1) @ stats.color_basis.T + stats.color_mean


@_single_threaded_blas
def ps_statistics(image, *, scales=4, orientations=4, neighborhood_size=7, mask=None, color_basis=None,
                  periodic_exemplar="none"):
    """Portilla-Simoncelli statistics of a grey or colour texture.

    Parameters
    ----------
    image : array_like
        Grey ``(H, W)`` or colour ``(H, W, C)`` (uint8, uint16 or float in
        [0, 1]); at least ``2^(scales+2)`` pixels along each axis.
    scales : int
        Number of pyramid scales (4 in the paper).
    orientations : int
        Number of orientations (4 in the paper).
    neighborhood_size : int
        Odd size ``Na`` of the central autocorrelation windows (7 in the paper).
    mask : array_like of bool, optional
        ``(H, W)``: measure the statistics only on these pixels (the pyramid
        is still computed on the whole image, so bands near the region's
        border see a little of the outside). At every scale the mask is
        subsampled like the bands.
    color_basis : array_like, optional
        ``(C, C)`` orthogonal matrix whose columns are the colour axes to
        analyse in; default the principal axes of the image's colours (in the
        mask). Pass ``other.color_basis`` to make two sets of statistics
        comparable (:func:`interpolate_statistics` needs the same basis).
    periodic_exemplar : {"none", "periodic+smooth"}
        ``"periodic+smooth"`` analyses the periodic component of Moisan's
        periodic-plus-smooth decomposition instead of the image (removes the
        cross that the border jump adds to the spectrum of a non-tileable
        exemplar). ``"none"`` by default, as in textureAnalysis.m; the pixel
        statistics are always the image's.

    Returns
    -------
    PSStatistics

    Raises
    ------
    ValueError
        If the image is too small for ``scales`` (the message lists the sizes
        that work), not finite, ``neighborhood_size`` is even, or the mask is empty
        or of the wrong shape.

    Notes
    -----
    See the module docstring and the paper's section 3 (the statistics, its
    eqs. 4-7). The magnitudes' and low-pass images' autocorrelations are
    ``A(dy, dx) = mean_x u(x) u(x + d)`` over the central ``Na x Na`` lags.

    References
    ----------
    .. [1] J. Portilla and E. P. Simoncelli, IJCV 40(1), 49-70, 2000.
       doi:10.1023/A:1026553619983

    Examples
    --------
    >>> from texsynth import data
    >>> stats = ps_statistics(data.load("metal")[:64, :64], scales=3)
    >>> stats.lowpass_autocorrelation.shape, stats.magnitude_cross_orientation.shape
    ((1, 4, 7, 7), (3, 4, 4))
    >>> bool(np.isclose(stats.pixel[0, 1], data.load("metal")[:64, :64].var()))
    True
    """
    img = as_image(image, "image").astype(np.float64, copy=False)
    img, _ = with_channels(img)
    scales = check_positive_int(scales, "scales", minimum=1)
    orientations = check_positive_int(orientations, "orientations", minimum=1)
    neighborhood_size = _check_neighborhood(neighborhood_size)
    shape = img.shape[:2]
    _check_scales_fit(scales, shape, "image")
    m = _check_mask(mask, shape)
    return _statistics(img, scales, orientations, neighborhood_size, m, color_basis, _check_periodic(periodic_exemplar))


def _statistics(img, scales, orientations, neighborhood, mask, color_basis, periodic_smooth):
    C = img.shape[-1]
    pixels = img.reshape(-1, C) if mask is None else img[mask > 0]
    if C == 1:
        mean, basis = np.zeros(1), np.eye(1)
    else:
        mean, basis = _pca_basis(pixels)
    if color_basis is not None:
        basis = np.asarray(color_basis, dtype=float)
        if basis.shape != (C, C) or not np.allclose(basis.T @ basis, np.eye(C), atol=1e-6):
            raise ValueError(f"color_basis must be an orthogonal {C}x{C} matrix (e.g. stats.color_basis), "
                             f"got shape {basis.shape}")
    comps = _components(img, mean, basis)
    plan = _plan(img.shape[:2], scales, orientations)
    analysed = np.stack([periodic_smooth_decomposition(c)[0] for c in comps]) if periodic_smooth else comps
    values = _analyse(analysed, plan, neighborhood, mask)
    if periodic_smooth:  # the pixel statistics are the image's own
        values["pixel"] = _analyse_pixels(comps, mask)
    color_range = np.stack([pixels.min(axis=0), pixels.max(axis=0)], axis=1)
    return PSStatistics(scales, orientations, neighborhood, mean, basis, color_range, **values)


def _analyse_pixels(comps, mask):
    out = np.zeros((comps.shape[0], 6))
    for c, x in enumerate(comps):
        inside = x if mask is None else x[mask > 0]
        out[c] = (*_moments(x, mask), inside.min(), inside.max())
    return out


# --------------------------------------------------------------------------- projections
def _region_autocorrelation(x, where, reach):
    """Circular autocorrelation over pairs of pixels both in the region, natural FFT order.

    ``sum m(p) m(p+d) x(p) x(p+d) / sum m(p) m(p+d)`` (the weighted estimate of
    :func:`_autocorrelation`); every lag up to ``reach`` in each direction needs a pair inside.
    """
    w = where.astype(float)
    num = sfft.irfft2(np.abs(sfft.rfft2(x * w)) ** 2, s=x.shape)
    den = np.rint(sfft.irfft2(np.abs(sfft.rfft2(w)) ** 2, s=x.shape))
    if np.any(_central(den, min(reach, (min(x.shape) - 1) // 2)) < 1):
        raise ValueError("mask region is too small or too thin to impose the autocorrelation "
                         f"of a {x.shape[0]}x{x.shape[1]} band; pass a larger mask or fewer scales")
    return num / np.maximum(den, 1.0)


def _impose_autocorrelation(x, target, where=None):
    """Filter ``x`` so its central autocorrelation becomes ``target`` (textureSynth's modacor22).

    Solve for a symmetric ``g`` on the window with ``(A_x * g)(u) = target(u)`` for every lag ``u``
    of the window, then filter with ``sqrt(|FFT g|)``: the new autocorrelation is ``A_x * g``.
    With a region ``where`` (bool, x's shape) ``A_x`` is the region's autocorrelation (pairs of
    pixels both inside, as ``ps_statistics(mask=)`` measures it) and the filter is applied to the
    whole of ``x``. Returns (image, snr before).
    """
    radius = (target.shape[0] - 1) // 2
    spec = sfft.rfft2(x)
    if where is None:
        full = sfft.irfft2(np.abs(spec) ** 2, s=x.shape) / x.size
    else:
        full = _region_autocorrelation(x, where, 2 * radius)
    snr = _snr(target, _central(full, radius))
    lags = np.arange(-radius, radius + 1)
    oy, ox = np.meshgrid(lags, lags, indexing="ij")
    oy, ox = oy.ravel(), ox.ravel()
    system = full[(oy[:, None] - oy[None, :]) % x.shape[0], (ox[:, None] - ox[None, :]) % x.shape[1]]
    g = np.linalg.lstsq(system, target.ravel(), rcond=1e-10)[0]
    kernel = np.zeros(x.shape)
    kernel[oy % x.shape[0], ox % x.shape[1]] = g
    gain = np.sqrt(np.abs(sfft.rfft2(kernel).real))
    return sfft.irfft2(spec * gain, s=x.shape), snr


def _impose_moment(x, target, order, where=None):
    """Impose skewness (order 3) or kurtosis (order 4), keeping mean and variance (modskew / modkurt).

    Gradient projection: ``x + lambda g`` with ``g`` the moment's gradient made orthogonal to the
    constant and to ``x`` (``d^2 - (m3/m2) d - m2`` for skewness, ``d^3 - (m4/m2) d - m3`` for
    kurtosis, ``d = x - mean``), rescaled to the variance; ``lambda`` is the root of the moment's
    rational function of ``lambda`` nearest to 0 (or its extremum if the target cannot be reached).
    With a region ``where`` (bool, x's shape) every moment is the region's and the same change
    is applied to all of ``x``. Returns (image, snr before).
    """
    sel = (lambda a: a) if where is None else (lambda a: a[where])
    mean = float(np.mean(sel(x)))
    sd = float(np.sqrt(np.mean(sel((x - mean) ** 2))))
    if sd == 0.0:
        return x, _snr(target, 0.0 if order == 3 else 3.0)
    d = (x - mean) / sd  # unit variance: lambda is dimensionless
    dr = sel(d)  # the region's values: every moment below is the region's
    d2 = dr * dr
    m3 = float(np.mean(d2 * dr))
    current = m3 if order == 3 else float(np.mean(d2 * d2))
    snr = _snr(target, current)

    def gradient(v):
        v2 = v * v
        return v2 - m3 * v - 1.0 if order == 3 else v2 * v - current * v - m3

    gr = gradient(dr)
    # numerator: mean((d + lambda g)^order) = sum_j binom(order, j) mean(d^(order-j) g^j) lambda^j
    dpow, gpow = [np.ones_like(dr), dr], [np.ones_like(dr), gr]
    for _ in range(order - 1):
        dpow.append(dpow[-1] * dr)
        gpow.append(gpow[-1] * gr)
    num = np.array([math.comb(order, j) * float(np.mean(dpow[order - j] * gpow[j])) for j in range(order + 1)])
    den = np.array([1.0, 2.0 * float(np.mean(dr * gr)), float(np.mean(gr * gr))])  # variance of d + lambda g

    def value(lam):
        return npoly.polyval(lam, num) / npoly.polyval(lam, den) ** (order / 2)

    if order == 4:
        equation = npoly.polysub(num, target * npoly.polymul(den, den))
    else:
        equation = npoly.polysub(npoly.polymul(num, num), target ** 2 * npoly.polypow(den, 3))
    roots = npoly.polyroots(equation) if np.any(equation[1:] != 0) else np.array([])
    real = roots[np.abs(roots.imag) <= 1e-6 * np.maximum(1.0, np.abs(roots.real))].real
    real = real[np.abs(value(real) - target) <= 1e-4 * max(1.0, abs(target))] if real.size else real
    if real.size:
        lam = real[np.argmin(np.abs(real))]
    else:  # unreachable target: go to the extremum of the moment nearest to it
        deriv = npoly.polysub(2 * npoly.polymul(npoly.polyder(num), den),
                              order * npoly.polymul(num, npoly.polyder(den)))
        cand = npoly.polyroots(deriv) if np.any(deriv[1:] != 0) else np.array([])
        cand = np.concatenate([[0.0], cand[np.abs(cand.imag) <= 1e-6 * np.maximum(1.0, np.abs(cand.real))].real])
        lam = cand[np.argmin(np.abs(value(cand) - target))]
    if where is None:
        y = d + lam * gr
    else:  # the step changes the region only (the gradient grows as d^3: outside it is unbounded)
        y = d.copy()
        y[where] += lam * gr
    y -= np.mean(sel(y))
    y *= sd / max(float(np.sqrt(np.mean(sel(y * y)))), 1e-300)
    return y + mean, snr


def _root(matrix, inverse=False):
    """Symmetric (inverse) square root, eigenvalues clamped at a tiny fraction of the largest."""
    vals, vecs = np.linalg.eigh((matrix + matrix.T) / 2)
    floor = max(float(vals.max()), 0.0) * 1e-12 + 1e-300
    vals = np.maximum(vals, floor if inverse else 0.0)
    return (vecs * (vals ** (-0.5 if inverse else 0.5))) @ vecs.T


def _covariance_map(current, desired):
    """M with M^T current M = desired, the one nearest the identity (orthogonal Procrustes)."""
    cur_inv, des = _root(current, inverse=True), _root(desired)
    u, _, vt = np.linalg.svd(des @ cur_inv)
    return cur_inv @ vt.T @ u.T @ des


def _impose_covariance(x, target, where=None):
    """x (N, m) -> x M with covariance ``target`` (adjustCorr1s; the paper's eq. 8 without parents).

    With ``where`` ((N,) bool) the covariance is the region rows' and M is applied to all rows.
    """
    xr = x if where is None else x[where]
    current = xr.T @ xr / xr.shape[0]
    return x @ _covariance_map(current, target), _snr(target, current)


def _impose_cross_covariance(x, target_x, y, target_xy, where=None):
    """Modify only x (N, m): x^T x / N -> target_x and x^T y / N -> target_xy (adjustCorr2s, eq. 8).

    New x = x Mx + y My with ``My = By^-1 (Cxy^T - Bxy^T Mx)`` and ``Mx`` mapping the current
    covariance of x given y onto the desired one. With ``where`` ((N,) bool) the covariances are
    the region rows' and the maps are applied to all rows. Returns (x, snr of x^T x, snr of x^T y).
    """
    xr, yr = (x, y) if where is None else (x[where], y[where])
    n = xr.shape[0]
    bx, bxy, by = xr.T @ xr / n, xr.T @ yr / n, yr.T @ yr / n
    by_inv = np.linalg.pinv(by, rcond=1e-12, hermitian=True)
    current = bx - bxy @ by_inv @ bxy.T
    desired = target_x - target_xy @ by_inv @ target_xy.T
    mx = _covariance_map(current, desired)
    my = by_inv @ (target_xy.T - bxy.T @ mx)
    return x @ mx + y @ my, _snr(target_x, bx), _snr(target_xy, bxy)


def _with_variances(covariance, variances):
    """The correlation matrix of ``covariance`` with the given variances (cross-channel targets)."""
    sd = np.sqrt(np.maximum(np.diag(covariance), 1e-300))
    corr = covariance / np.outer(sd, sd)
    s = np.sqrt(np.maximum(variances, 0.0))
    return corr * np.outer(s, s)


def _window_for(target, shape):
    """Central part of a target window that the output band can take (4 le + 1 <= size)."""
    la = (target.shape[0] - 1) // 2
    avail = int(np.sum(np.isfinite(target[la]))) // 2
    le = max(0, min(la, avail, (min(shape) - 1) // 4))
    return target[la - le:la + le + 1, la - le:la + le + 1]


class _SNR:
    """Accumulates the snr values of every group during one iteration."""

    def __init__(self):
        self.values = {g: [] for g in SNR_GROUPS}

    def add(self, group, *values):
        self.values[group].extend(values)

    def means(self):
        return {g: (float(np.mean(v)) if v else float("nan")) for g, v in self.values.items()}


def _step(comps, stats, plan, snr, region=None):
    """One projection iteration on decorrelated components (C, H, W) (textureSynthesis.m's loop body).

    ``region``: None (the whole image, textureSynthesis.m) or, for every scale ``0 .. S``, the
    boolean region at that scale's size: every statistic is then measured on the region and the
    linear corrections (covariance maps, autocorrelation filters) are applied to the whole band,
    the skewness/kurtosis steps to the region only (the caller keeps the outside).
    """
    C, S, K = comps.shape[0], plan.scales, plan.orientations
    pixel = stats.pixel

    def at(s):  # the region at scale s, (h, w) bool
        return None if region is None else region[s]

    def rows(s):  # the region at scale s as rows of an (N, m) matrix
        return None if region is None else region[s].ravel()

    def inside(image, s):  # the region's pixels of an (h, w) array of scale s
        return image if region is None else image[region[s]]

    def inside_rows(matrix, s):  # the region's rows of an (N, m) matrix of scale s
        return matrix if region is None else matrix[region[s].ravel()]

    decomposed = [plan.decompose(comps[c]) for c in range(C)]
    highpass = [d[0] for d in decomposed]
    bands = [np.stack([d[1][s] for d in decomposed]) for s in range(S)]  # per scale (C, K, h, w)

    def adjust_lowpass(low, s):
        """Autocorrelation, cross-channel covariance, skewness and kurtosis of l_s (sec. 4, step 1)."""
        out = []
        for c in range(C):
            variance = stats.lowpass_autocorrelation[c, s][(stats.neighborhood - 1) // 2, (stats.neighborhood - 1) // 2]
            x = low[c]
            if variance / max(pixel[c, 1], 1e-300) > _NEGLIGIBLE_VARIANCE:
                x, v = _impose_autocorrelation(x, _window_for(stats.lowpass_autocorrelation[c, s], x.shape), at(s))
                snr.add("lowpass_autocorrelation", v)
            else:
                x = x * np.sqrt(variance / max(float(np.mean(inside(x * x, s))), 1e-300))
            out.append(x)
        out = np.stack(out)
        if C > 1:
            flat = out.reshape(C, -1).T
            target = _with_variances(stats.lowpass_cross_channel[s], np.mean(inside_rows(flat * flat, s), axis=0))
            flat, v = _impose_covariance(flat, target, rows(s))
            snr.add("cross_channel", v)
            out = flat.T.reshape(out.shape)
        for c in range(C):
            variance = stats.lowpass_autocorrelation[c, s][(stats.neighborhood - 1) // 2, (stats.neighborhood - 1) // 2]
            if variance / max(pixel[c, 1], 1e-300) > _NEGLIGIBLE_VARIANCE:
                out[c], v1 = _impose_moment(out[c], stats.lowpass_moments[c, s, 0], 3, at(s))
                out[c], v2 = _impose_moment(out[c], stats.lowpass_moments[c, s, 1], 4, at(s))
                snr.add("lowpass_moments", v1, v2)
        return out

    # Coarsest low-pass image: mean removed, L0-filtered.
    low = np.stack([plan.coarsest_lowpass(d[2] - np.mean(inside(d[2], S))) for d in decomposed])
    low = adjust_lowpass(low, S)
    for s in range(S - 1, -1, -1):
        z = bands[s]  # (C, K, h, w) complex
        h, w = z.shape[-2:]
        n = h * w
        # Magnitudes: cross-orientation and cross-scale covariance (eq. 8), mean-free.
        mags = np.abs(z).reshape(C * K, n).T
        mags = mags - inside_rows(mags, s).mean(axis=0)
        target_co = stats.magnitude_cross_orientation[s]
        if s == S - 1:
            mags, v = _impose_covariance(mags, target_co, rows(s))
            snr.add("magnitude_cross_orientation", v)
        else:
            pmag, preal = _parents(bands[s + 1], (h, w), rows(s))
            mags, v1, v2 = _impose_cross_covariance(mags, target_co, pmag, stats.magnitude_cross_scale[s], rows(s))
            snr.add("magnitude_cross_orientation", v1)
            snr.add("magnitude_cross_scale", v2)
        mags = mags.T.reshape(C, K, h, w)
        # Magnitude autocorrelation, then the magnitudes go back under the bands' phases.
        for c in range(C):
            for k in range(K):
                target = _window_for(stats.magnitude_autocorrelation[c, s, k], (h, w))
                a, v = _impose_autocorrelation(mags[c, k], target, at(s))
                snr.add("magnitude_autocorrelation", v)
                mag = np.maximum(a + stats.magnitude_means[c, s, k], 0.0)
                cur = np.abs(z[c, k])
                z[c, k] = z[c, k] * (mag / np.where(cur > 0, cur, 1.0))
        # Real parts: cross-scale phase statistics (with the phase-doubled parent) and cross-channel.
        reals = z.real.reshape(C * K, n).T.copy()
        if s < S - 1 or C > 1:
            for k in range(K):
                cols = np.arange(C) * K + k
                x = reals[:, cols]
                target_x = _with_variances(stats.real_cross_channel[s, k], np.mean(inside_rows(x * x, s), axis=0))
                if s < S - 1:
                    x, v1, v2 = _impose_cross_covariance(x, target_x, preal, stats.real_cross_scale[s][cols], rows(s))
                    snr.add("real_cross_scale", v2)
                else:
                    x, v1 = _impose_covariance(x, target_x, rows(s))
                if C > 1:
                    snr.add("cross_channel", v1)
                reals[:, cols] = x
            # Re-create analytic sub-bands from the (now non-analytic) real parts.
            spectra = sfft.fft2(reals.T.reshape(C, K, h, w), axes=(-2, -1))
            z = sfft.ifft2(spectra * plan.analytic[s][None], axes=(-2, -1))
        bands[s] = z
        # l_s = expand(l_{s+1}) + the bands of scale s, then its own statistics.
        low = np.stack([_expand(low[c], (h, w)) + plan.band_image(s, z[c]) for c in range(C)])
        low = adjust_lowpass(low, s)
    # High-pass residual: reduce its variance if too large; add it; pixel statistics.
    out = np.empty_like(comps)
    for c in range(C):
        hp = highpass[c]
        var, target = float(np.mean(inside(hp * hp, 0))), stats.highpass_variance[c]
        snr.add("highpass", _snr(target, var))
        if var > target:
            hp = hp * np.sqrt(target / var)
        out[c] = low[c] + plan.highpass_image(hp)
    return _impose_pixels(out, stats, snr, at(0))


def _impose_pixels(comps, stats, snr, where=None):
    """Mean, variance, skewness, kurtosis and range of every component (end of sec. 4).

    With a region ``where`` (bool) the moments and the range are the region's.
    """
    out = np.empty_like(comps)
    for c in range(comps.shape[0]):
        mean0, var0, skew0, kurt0, lo, hi = stats.pixel[c]
        x = comps[c]
        mean, var, _, _ = _moments(x, None if where is None else where.astype(float))
        xin = x if where is None else x[where]
        snr.add("pixel", _snr(var0, var))
        snr.add("pixel_range", _snr([lo, hi], [xin.min() - mean + mean0, xin.max() - mean + mean0]))
        x = (x - mean) * np.sqrt(var0 / max(var, 1e-300)) + mean0
        x, v1 = _impose_moment(x, skew0, 3, where)
        x, v2 = _impose_moment(x, kurt0, 4, where)
        snr.add("pixel", v1, v2)
        out[c] = np.clip(x, lo, hi)
    if comps.shape[0] > 1:  # the colours themselves stay within the exemplar's range
        rgb = np.clip(_image_from_components(out, stats), stats.color_range[:, 0], stats.color_range[:, 1])
        out = _components(rgb, stats.color_mean, stats.color_basis)
    return out


def _check_statistics(statistics, name="statistics"):
    if not isinstance(statistics, PSStatistics):
        raise TypeError(f"{name} must be a PSStatistics (from ps_statistics), got {type(statistics).__name__}")
    return statistics


def _check_step_mask(mask, shape, scales):
    """(blend weights in [0, 1] as float (H, W), the region at every scale) or (None, None) for no mask.

    The region is ``mask > 0.5`` (what ``ps_statistics(mask=)`` measures), subsampled like the
    pyramid's bands; it must keep pixels at every scale. A mask of ones is no mask.
    """
    if mask is None:
        return None, None
    m = np.asarray(mask)
    if m.shape != tuple(shape):
        raise ValueError(f"mask must have the image's spatial shape {tuple(shape)}, got {m.shape}")
    if not (m.dtype == bool or np.issubdtype(m.dtype, np.integer) or np.issubdtype(m.dtype, np.floating)):
        raise TypeError(f"mask must be a boolean or numeric (H, W) array, got dtype {m.dtype}")
    m = m.astype(np.float64)
    if not np.all(np.isfinite(m)) or m.min() < 0 or m.max() > 1:
        raise ValueError("mask values must be in [0, 1] (True/1 inside the region, 0 outside, fractions "
                         f"to blend), got values in [{np.nanmin(m)}, {np.nanmax(m)}]")
    if np.all(m == 1.0):
        return None, None
    region = [m > 0.5]
    for s in range(1, scales + 1):
        region.append(region[-1][::2, ::2])
    if not region[0].any():
        raise ValueError("mask selects no pixel; pass a mask with True (> 0.5) where the statistics are imposed")
    for s, r in enumerate(region):
        if not r.any():
            raise ValueError(f"mask selects no pixel (mask > 0.5) at scale {s} ({r.shape[0]}x{r.shape[1]} "
                             "samples, every second one of the scale above); pass a larger region or fewer scales")
    return m, region


@_single_threaded_blas
def ps_step(image, statistics, *, mask=None):
    """Apply ONE Portilla-Simoncelli projection iteration to ``image``.

    For algorithms that interleave one statistical step with their own
    iterations (Ruiters et al. 2010 do one per iteration of their patch
    interpolation loop).

    Parameters
    ----------
    image : array_like
        Grey ``(H, W)`` or colour ``(H, W, C)`` with the statistics' number of
        channels; any size with at least ``2^(scales+2)`` pixels per axis.
    statistics : PSStatistics
        Target statistics (:func:`ps_statistics`, :func:`interpolate_statistics`).
    mask : array_like, optional
        ``(H, W)`` boolean or values in [0, 1]: impose the statistics on this
        region only (Ruiters et al. 2010, sec. 4.5 run the statistical step
        "only on the relevant parts of the image"). Every statistic is
        measured on the region ``mask > 0.5`` (as ``ps_statistics(image,
        mask=mask > 0.5)`` measures it) and the correction is computed from
        the region alone; the result is ``(1 - mask) * image + mask *
        projected``, so pixels where the mask is 0 keep their values exactly
        and fractional values blend (a feathered edge). Default None: the
        whole image, as textureSynthesis.m.

    Returns
    -------
    numpy.ndarray
        The projected image, same shape and float dtype, in [0, 1].

    Raises
    ------
    ValueError
        If the channels do not match, the image is too small for the
        statistics' scales, or the mask has the wrong shape, values outside
        [0, 1], or a region too small for the statistics' coarsest scale.

    Notes
    -----
    Without the momentum ("accelerator") that :func:`portilla_simoncelli`
    adds between iterations; see the module docstring for the order of the
    projections (the paper's section 4, fig. 7).

    With a mask every projection (covariance maps of eq. 8, the
    autocorrelation filters, the skewness/kurtosis steps, the pixel
    statistics) is computed from the region's statistics at each scale (the
    region subsampled like the bands) and applied to the whole band, so the
    pyramid stays consistent; only the region's pixels are kept. Near the
    region's border the bands mix inside and outside, as they do in
    ``ps_statistics(mask=)``, so a region converges to its target the more
    closely the larger it is compared with the coarsest scale's filters
    (``2^scales`` pixels).

    References
    ----------
    .. [1] J. Portilla and E. P. Simoncelli, IJCV 40(1), 49-70, 2000.
       doi:10.1023/A:1026553619983

    Examples
    --------
    >>> from texsynth import data
    >>> target = ps_statistics(data.load("metal")[:64, :64], scales=3)
    >>> noise = np.random.default_rng(0).random((64, 64))
    >>> before = statistics_snr(ps_statistics(noise, scales=3), target)["magnitude_autocorrelation"]
    >>> after = statistics_snr(ps_statistics(ps_step(noise, target), scales=3), target)
    >>> bool(after["magnitude_autocorrelation"] > before)
    True

    On the right half only: the left half keeps its values.

    >>> right = np.zeros((64, 64), bool)
    >>> right[:, 32:] = True
    >>> out = ps_step(noise, target, mask=right)
    >>> bool(np.array_equal(out[:, :32], noise[:, :32]))
    True
    """
    stats = _check_statistics(statistics)
    img = as_image(image, "image")
    dtype = img.dtype
    img, grey = with_channels(img.astype(np.float64, copy=False))
    if img.shape[-1] != stats.channels:
        raise ValueError(f"image has {img.shape[-1]} channel(s) but the statistics were measured on "
                         f"{stats.channels}; pass an image with {stats.channels} channel(s)")
    _check_scales_fit(stats.scales, img.shape[:2], "image")
    weight, region = _check_step_mask(mask, img.shape[:2], stats.scales)
    plan = _plan(img.shape[:2], stats.scales, stats.orientations)
    comps = _step(_components(img, stats.color_mean, stats.color_basis), stats, plan, _SNR(), region)
    out = np.clip(_image_from_components(comps, stats), 0.0, 1.0)
    if weight is not None:  # outside the region the image stays as it was (exactly where mask == 0)
        out = (1.0 - weight)[..., None] * img + weight[..., None] * out
    return restore_channels(out.astype(dtype, copy=False), grey)


# --------------------------------------------------------------------------- comparing / mixing statistics
def _check_compatible(a, b):
    same = (a.scales, a.orientations, a.neighborhood, a.channels) == (b.scales, b.orientations, b.neighborhood,
                                                                       b.channels)
    if not same:
        raise ValueError(
            "statistics differ in (scales, orientations, neighborhood, channels): "
            f"{(a.scales, a.orientations, a.neighborhood, a.channels)} vs "
            f"{(b.scales, b.orientations, b.neighborhood, b.channels)}; measure both with the same options"
        )
    if not np.allclose(a.color_basis, b.color_basis, atol=1e-9):
        raise ValueError("statistics were measured in different colour bases; measure the second with "
                         "ps_statistics(..., color_basis=first.color_basis)")


def statistics_snr(statistics, target):
    """Signal-to-noise ratio (dB) of every statistics group of ``statistics`` relative to ``target``.

    ``10 log10(|target|^2 / |target - statistics|^2)`` per statistic, averaged
    over the group (``SNR_GROUPS``; groups without any statistic, e.g.
    ``cross_channel`` for grey images, are NaN). Higher is closer; capped at
    ``SNR_CAP``.

    Examples
    --------
    >>> from texsynth import data
    >>> s = ps_statistics(data.load("metal")[:64, :64], scales=3)
    >>> statistics_snr(s, s)["pixel"] == SNR_CAP
    True
    """
    a, t = _check_statistics(statistics), _check_statistics(target, "target")
    _check_compatible(a, t)
    C, S, K = t.channels, t.scales, t.orientations
    out = {g: [] for g in SNR_GROUPS}
    for c in range(C):
        out["pixel"] += [_snr(t.pixel[c, i], a.pixel[c, i]) for i in (1, 2, 3)]
        out["pixel_range"].append(_snr(t.pixel[c, 4:], a.pixel[c, 4:]))
        out["highpass"].append(_snr(t.highpass_variance[c], a.highpass_variance[c]))
        for s in range(S + 1):
            out["lowpass_moments"] += [_snr(t.lowpass_moments[c, s, i], a.lowpass_moments[c, s, i]) for i in (0, 1)]
            out["lowpass_autocorrelation"].append(_snr(t.lowpass_autocorrelation[c, s],
                                                       a.lowpass_autocorrelation[c, s]))
            if s < S:
                out["magnitude_autocorrelation"] += [_snr(t.magnitude_autocorrelation[c, s, k],
                                                          a.magnitude_autocorrelation[c, s, k]) for k in range(K)]
    for s in range(S):
        out["magnitude_cross_orientation"].append(_snr(t.magnitude_cross_orientation[s],
                                                       a.magnitude_cross_orientation[s]))
        if s < S - 1:
            out["magnitude_cross_scale"].append(_snr(t.magnitude_cross_scale[s], a.magnitude_cross_scale[s]))
            out["real_cross_scale"].append(_snr(t.real_cross_scale[s], a.real_cross_scale[s]))
        if C > 1:
            out["cross_channel"] += [_snr(t.real_cross_channel[s, k], a.real_cross_channel[s, k]) for k in range(K)]
    if C > 1:
        out["cross_channel"] += [_snr(t.lowpass_cross_channel[s], a.lowpass_cross_channel[s]) for s in range(S + 1)]
    return {g: (float(np.mean(v)) if v else float("nan")) for g, v in out.items()}


def interpolate_statistics(a, b, alpha):
    """Linear interpolation ``(1 - alpha) a + alpha b`` of two sets of statistics.

    Portilla & Simoncelli (2000, sec. 6) and Ruiters et al. (2010, sec. 4.5)
    interpolate textures by interpolating their statistics linearly.

    Parameters
    ----------
    a, b : PSStatistics
        Measured with the same scales, orientations, neighbourhood, channels
        and colour basis (``ps_statistics(img_b, color_basis=a.color_basis)``).
    alpha : float
        In [0, 1]: 0 gives ``a``, 1 gives ``b``.

    Returns
    -------
    PSStatistics
        Autocorrelation lags measured in only one of the two are NaN (not
        imposed).

    Raises
    ------
    ValueError
        For incompatible statistics or ``alpha`` outside [0, 1].

    Examples
    --------
    >>> from texsynth import data
    >>> a = ps_statistics(data.load("metal")[:64, :64], scales=3)
    >>> b = ps_statistics(data.load("reptile")[:64, :64], scales=3)
    >>> m = interpolate_statistics(a, b, 0.5)
    >>> bool(np.isclose(m.pixel[0, 0], (a.pixel[0, 0] + b.pixel[0, 0]) / 2))
    True
    """
    a, b = _check_statistics(a, "a"), _check_statistics(b, "b")
    _check_compatible(a, b)
    alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
    if alpha == 0.0:
        return dataclasses.replace(a)
    if alpha == 1.0:
        return dataclasses.replace(b)
    mixed = {name: (1 - alpha) * value + alpha * getattr(b, name) for name, value in a.arrays().items()}
    return dataclasses.replace(a, **mixed)


# --------------------------------------------------------------------------- synthesis
def _synthesise(stats, shape, iterations, gen, progress):
    """Iterate the projections from Gaussian noise with the accelerator; (components, PSInfo fields)."""
    plan = _plan(shape, stats.scales, stats.orientations)
    C = stats.channels
    # Gaussian noise with the target's mean and variance (textureSynthesis.m's start).
    current = (gen.standard_normal((C,) + shape) * np.sqrt(stats.pixel[:, 1])[:, None, None]
               + stats.pixel[:, 0][:, None, None])
    previous = current
    history = {g: np.full(iterations, np.nan) for g in SNR_GROUPS}
    change = np.zeros(iterations)
    with Progress(progress, iterations, "Portilla-Simoncelli") as bar:
        for it in range(iterations):
            snr = _SNR()
            projected = _step(current, stats, plan, snr)
            means = snr.means()
            for g in SNR_GROUPS:
                history[g][it] = means[g]
            change[it] = float(np.sqrt(np.mean((projected - previous) ** 2)))
            current = projected + ACCELERATION * (projected - previous)  # the "accelerator"
            previous = projected
            bar.advance({g: v for g, v in means.items() if np.isfinite(v)})
    return previous, history, change


def _check_memory(shape, channels, scales, orientations):
    """Refuse an output whose complex steerable pyramid (of every channel, with its magnitudes and
    phase-doubled parents) cannot fit."""
    check_memory(float(shape[0]) * shape[1] * channels * 16 * (3 * scales * orientations + 10), tuple(shape),
                 also={"orientations": orientations})


def _check_from_statistics(stats, size, scales, orientations, neighborhood_size, periodic_smooth):
    """Options that only an exemplar's analysis uses must be left out (or agree) with given statistics."""
    if size is None:
        raise ValueError("size is required when synthesising from statistics (they carry no image size); "
                         "pass size=(height, width), e.g. size=256")
    for name, value, attribute in (("scales", scales, "scales"), ("orientations", orientations, "orientations"),
                               ("neighborhood_size", neighborhood_size, "neighborhood")):
        if value is not None and value != getattr(stats, attribute):
            raise ValueError(f"{name}={value} but the statistics were measured with {name}={getattr(stats, attribute)}; "
                             f"leave {name} out when passing statistics (it is theirs)")
    if periodic_smooth:
        raise ValueError("periodic_exemplar applies to the analysis of an exemplar, and these statistics are "
                         "already measured; pass periodic_exemplar='periodic+smooth' to ps_statistics instead")


@_single_threaded_blas
def portilla_simoncelli(exemplar, size=None, *, scales=None, orientations=None, neighborhood_size=None, iterations=50,
                        periodic_exemplar="none", rng=None, progress=False, return_info=False):
    """Synthesise a texture with an exemplar's (or given) Portilla-Simoncelli statistics.

    Parameters
    ----------
    exemplar : array_like or PSStatistics
        Grey ``(H, W)`` or colour ``(H, W, C)`` texture (uint8, uint16 or
        float in [0, 1]), at least ``2^(scales+2)`` pixels per axis (64x64 for
        the default 4 scales). Or the statistics themselves, as
        :func:`ps_statistics` measures them or :func:`interpolate_statistics`
        mixes them: then ``size`` is required and ``scales``,
        ``orientations`` and ``neighborhood_size`` are the statistics' own.
    size : int or (int, int), optional
        Output ``(height, width)``, default the exemplar's (required with
        statistics); any size with at least ``2^(scales+2)`` pixels per axis
        (the statistics do not depend on the image's size).
    scales, orientations, neighborhood_size : int, optional
        Pyramid scales, orientations and the autocorrelation window; None
        (the default) means 4, 4 and 7 as in the paper for an exemplar, and
        the statistics' own for statistics (another value is then an error).
    iterations : int
        Number of projection iterations (50 in the paper's examples).
    periodic_exemplar : {"none", "periodic+smooth"}
        Analyse the exemplar's periodic component (see :func:`ps_statistics`);
        not with statistics.
    rng : None, int or numpy.random.Generator
        Seed of the initial Gaussian noise.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``
        after every iteration with ``info`` the mean SNR (dB) of each group.
    return_info : bool
        Also return a :class:`PSInfo` (the SNR per iteration, textureSynth's
        ``snrP``).

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channels (the statistics' channels:
        ``(H, W)`` for one), in [0, 1], the exemplar's float dtype (float64
        from statistics). The output is periodic (it tiles).
    info : PSInfo
        Only if ``return_info=True``.

    Raises
    ------
    ValueError
        If the exemplar or the output is too small for ``scales`` (the message
        lists which sizes work), the exemplar has NaN/inf values,
        ``iterations < 1`` or ``neighborhood_size`` is even; with statistics, if
        ``size`` is missing, ``scales``/``orientations``/``neighborhood_size``
        disagree with them or ``periodic_exemplar`` is set.

    Notes
    -----
    The initial image is Gaussian noise with the target's mean and
    variance. Each iteration is :func:`ps_step` (the paper's fig. 7: the
    statistics of sec. 3 imposed by the projections of sec. 4: eq. 8 for
    covariances, gradient projections for skewness and kurtosis, a
    symmetric filter for autocorrelations), followed by textureSynthesis.m's
    momentum ``x <- x + 0.8 (x - x_previous)``; the last projected image is
    returned. Colour as Ruiters et al. (2010, sec. 4.5) extend it: principal
    components of the colours plus cross-channel correlations of every band
    (module docstring).

    ``portilla_simoncelli(ps_statistics(exemplar, ...), size, rng=seed)`` is
    the same, bit for bit, as ``portilla_simoncelli(exemplar, size, ...,
    rng=seed)``; with statistics mixed by :func:`interpolate_statistics`
    it gives the paper's interpolated textures (sec. 6). There is no mask:
    the synthesis starts from noise everywhere; to impose statistics on a
    region of an existing image, iterate ``ps_step(image, statistics,
    mask=region)``.

    Known failures (as in the paper, fig. 12): textures with long straight
    structures or large objects come out as broken fragments; text keeps
    letter-like strokes but no readable letters.

    References
    ----------
    .. [1] J. Portilla and E. P. Simoncelli, "A parametric texture model based
       on joint statistics of complex wavelet coefficients", IJCV 40(1),
       49-70, 2000. doi:10.1023/A:1026553619983
    .. [2] A. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
       interpolation", Computer Graphics Forum 29(4), 2010.
       doi:10.1111/j.1467-8659.2010.01736.x

    Examples
    --------
    >>> from texsynth import data
    >>> out, info = portilla_simoncelli(data.load("metal")[:64, :64], (64, 96), scales=3,
    ...                                 iterations=3, rng=0, return_info=True)
    >>> out.shape, len(info.snr["pixel"])
    ((64, 96), 3)

    From statistics, here halfway between metal and reptile skin:

    >>> a = ps_statistics(data.load("metal")[:64, :64], scales=3)
    >>> b = ps_statistics(data.load("reptile")[:64, :64], scales=3)
    >>> mixed = portilla_simoncelli(interpolate_statistics(a, b, 0.5), (48, 64), iterations=3, rng=0)
    >>> mixed.shape, mixed.dtype
    ((48, 64), dtype('float64'))
    """
    t_start = time.perf_counter()
    if isinstance(exemplar, PSStatistics):
        stats = exemplar
        _check_from_statistics(stats, size, scales, orientations, neighborhood_size, _check_periodic(periodic_exemplar))
        shape = as_size(size)
        iterations = check_positive_int(iterations, "iterations", minimum=1, maximum=MAX_ITERATIONS)
        _check_scales_fit(stats.scales, shape, "output")
        _check_memory(shape, stats.channels, stats.scales, stats.orientations)
        dtype, grey = np.dtype(np.float64), stats.channels == 1
        gen = as_rng(rng)
    else:
        ex = as_image(exemplar, "exemplar")
        dtype = ex.dtype
        ex, grey = with_channels(ex.astype(np.float64, copy=False))
        shape = ex.shape[:2] if size is None else as_size(size)
        scales = check_positive_int(4 if scales is None else scales, "scales", minimum=1)
        orientations = check_positive_int(4 if orientations is None else orientations, "orientations", minimum=1)
        neighborhood_size = _check_neighborhood(7 if neighborhood_size is None else neighborhood_size)
        iterations = check_positive_int(iterations, "iterations", minimum=1, maximum=MAX_ITERATIONS)
        _check_scales_fit(scales, ex.shape[:2], "exemplar")
        _check_scales_fit(scales, shape, "output")
        _check_memory(shape, ex.shape[-1], scales, orientations)
        gen = as_rng(rng)
        stats = _statistics(ex, scales, orientations, neighborhood_size, None, None, _check_periodic(periodic_exemplar))
    t_synthesis = time.perf_counter()
    components, history, change = _synthesise(stats, shape, iterations, gen, progress)
    out = np.clip(_image_from_components(components, stats), 0.0, 1.0)
    out = restore_channels(out.astype(dtype, copy=False), grey)
    if return_info:
        end = time.perf_counter()
        return out, PSInfo(history, change, stats, seconds=end - t_start,
                           stage_seconds={"analysis": t_synthesis - t_start, "synthesis": end - t_synthesis})
    return out
