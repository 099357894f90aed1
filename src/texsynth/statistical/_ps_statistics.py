"""Portilla-Simoncelli texture statistics: joint statistics of complex wavelet coefficients.

Portilla & Simoncelli (2000) describe a texture by several hundred numbers (710 for the defaults)
measured on a complex steerable pyramid (4 scales x 4 orientations by
default). This module measures them (:func:`ps_statistics`), compares them
(:func:`statistics_snr`) and mixes them (:func:`interpolate_statistics`), following the
authors' MATLAB ``textureSynth`` (textureAnalysis.m); the synthesis that imposes them on
an image is :mod:`texsynth.statistical._portilla_simoncelli`.

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
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..core._validate import as_image, check_in_range, check_positive_int, one_blas_thread, with_channels
from ..core.color import color_pca
from ..core.pyramid import SteerableCoefficients, SteerablePyramid, level_shapes, max_scales, periodic_smooth_decomposition
from ..core.search import is_auto

__all__ = ["PSStatistics", "ps_statistics", "statistics_snr", "interpolate_statistics", "SNR_GROUPS", "SNR_CAP"]


#: SNR reported when a statistic is matched exactly (dB); keeps averages finite.
SNR_CAP = 150.0


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


def snr_db(target, current):
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
def single_threaded_blas(function):
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
def pyramid_plan(shape, scales, orientations):
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


def expand_band(x, shape):
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


def parent_columns(bands_parent, shape, where=None):
    """Expanded parent magnitudes (mean-free) and real/imaginary parts of the phase-doubled parent.

    bands_parent: (C, K, h, w) complex at scale s + 1. Returns (N, C K) and (N, 2 C K). ``where``
    (N,) bool: the magnitudes' mean is the region's (default: all pixels').
    """
    c, k = bands_parent.shape[:2]
    up = expand_band(bands_parent, shape).reshape(c * k, -1)
    mag = np.abs(up)
    mag -= mag.mean(axis=1, keepdims=True) if where is None else mag[:, where].mean(axis=1, keepdims=True)
    doubled = _double_phase(up)
    # columns: channel c: [Re of K orientations, Im of K orientations]
    real = np.concatenate([np.concatenate([doubled[i * k:(i + 1) * k].real, doubled[i * k:(i + 1) * k].imag])
                           for i in range(c)])
    return mag.T, real.T


# --------------------------------------------------------------------------- weighted measurements
def central_lags(full, radius):
    """Central (2 radius + 1)^2 lags of a circular autocorrelation stored in natural FFT order."""
    lags = np.arange(-radius, radius + 1)
    return full[np.ix_(lags % full.shape[0], lags % full.shape[1])]


def _autocorrelation(x, weight, radius):
    """Central autocorrelation sum_x m m' x x' / sum_x m m' (circular; m = region mask)."""
    if weight is None:
        spec = sfft.rfft2(x)
        full = sfft.irfft2(np.abs(spec) ** 2, s=x.shape) / x.size
        return central_lags(full, radius)
    spec, mspec = sfft.rfft2(x * weight), sfft.rfft2(weight)
    num = sfft.irfft2(np.abs(spec) ** 2, s=x.shape)
    den = sfft.irfft2(np.abs(mspec) ** 2, s=x.shape)
    num, den = central_lags(num, radius), central_lags(den, radius)
    if np.any(den < 0.5):
        raise ValueError("mask region is too small or too thin to measure the autocorrelation "
                         f"of a {x.shape[0]}x{x.shape[1]} band; pass a larger mask or fewer scales")
    return num / den


def weighted_moments(x, weight=None):
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
        mean, var, skew, kurt = weighted_moments(x, weights[0])
        inside = x if mask is None else x[mask > 0]
        pixel[c] = mean, var, skew, kurt, inside.min(), inside.max()
        highpass, bands, lowpass = plan.decompose(x)
        hp_mean, hp_variance = weighted_moments(highpass, weights[0])[:2]
        hp_var[c] = hp_variance + hp_mean ** 2  # mean square, as textureAnalysis.m's vHPR0
        lowpass = lowpass - weighted_moments(lowpass, weights[S])[0]
        low = plan.coarsest_lowpass(lowpass)
        for s in range(S, -1, -1):
            if s < S:
                low = expand_band(low, plan.sizes[s]) + plan.band_image(s, bands[s])
                all_bands[s][c] = bands[s]
                for k in range(K):
                    mag = np.abs(bands[s][k])
                    mag_mean[c, s, k] = weighted_moments(mag, weights[s])[0]
                    r = _analysis_radius(plan.sizes[s], neighborhood)
                    ac = _autocorrelation(mag - mag_mean[c, s, k], weights[s], r)
                    mag_ac[c, s, k] = _put_central(ac, neighborhood)
            r = _analysis_radius(plan.sizes[s], neighborhood)
            ac = _autocorrelation(low, weights[s], r)
            low_ac[c, s] = _put_central(ac, neighborhood)
            m = weighted_moments(low, weights[s])
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
            pmag, preal = parent_columns(np.stack(all_bands[s + 1]), plan.sizes[s])
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


def check_scales_fit(scales, shape, what):
    """The pyramid needs 2^(scales+2) pixels along each axis (its coarsest band keeps 8)."""
    if scales > max_scales(shape):
        need = 2 ** (scales + 2) if scales < 60 else float("inf")  # no trillion-bit integers in a message
        sizes = ", ".join(f"{s} scale{'s' if s > 1 else ''}: >= {2 ** (s + 2)} px" for s in range(1, min(scales, 6) + 1))
        name = "size" if what == "output" else what
        raise ValueError(
            f"{name} is {shape[0]}x{shape[1]} but scales={scales} needs at least {need}x{need} pixels "
            f"({sizes}); pass scales={max(max_scales(shape), 1)} or a larger {name}"
        )


def check_neighborhood(neighborhood_size):
    neighborhood_size = check_positive_int(neighborhood_size, "neighborhood_size", minimum=1)
    if neighborhood_size % 2 == 0:
        raise ValueError(f"neighborhood_size must be odd (a centred window, e.g. 7 as in the paper), "
                         f"got {neighborhood_size}")
    return neighborhood_size


#: Values of ``periodic_exemplar`` (the vocabulary of :func:`~texsynth.statistical.heeger_bergen`).
PERIODIC_EXEMPLAR = ("periodic+smooth", "none")


def check_periodic(periodic_exemplar):
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


def to_components(image, color_mean, color_basis):
    """(H, W, C) image -> (C, H, W) decorrelated components."""
    return np.moveaxis((image - color_mean) @ color_basis, -1, 0)


def from_components(components, stats):
    return np.moveaxis(components, 0, -1) @ stats.color_basis.T + stats.color_mean


@single_threaded_blas
def ps_statistics(image, *, scales=4, orientations=4, neighborhood_size=7, mask=None, color_basis="auto",
                  periodic_exemplar="none"):
    """Portilla-Simoncelli statistics of a grey or colour texture.

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> metal = texsynth.data.load("metal")[:64, :64]
    >>> stats = texsynth.ps_statistics(metal, scales=3)
    >>> stats.lowpass_autocorrelation.shape, stats.magnitude_cross_orientation.shape
    ((1, 4, 7, 7), (3, 4, 4))
    >>> bool(np.isclose(stats.pixel[0, 1], metal.var()))  # the pixel variance
    True

    The statistics :func:`portilla_simoncelli` imposes (Portilla and
    Simoncelli's section 3 [1]_): pixel marginals, auto-correlations of the
    low-pass bands and of the magnitudes, cross-correlations of the
    steerable pyramid's magnitudes across orientations and scales and of
    its real parts across scales, per colour axis and across them.

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
    color_basis : array_like or "auto"
        ``(C, C)`` orthogonal matrix whose columns are the colour axes to
        analyse in; ``"auto"`` (default): the principal axes of the image's colours (in the
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
    """
    img = as_image(image, "image").astype(np.float64, copy=False)
    img, _ = with_channels(img)
    scales = check_positive_int(scales, "scales", minimum=1)
    orientations = check_positive_int(orientations, "orientations", minimum=1)
    neighborhood_size = check_neighborhood(neighborhood_size)
    shape = img.shape[:2]
    check_scales_fit(scales, shape, "image")
    m = _check_mask(mask, shape)
    return measure_statistics(img, scales, orientations, neighborhood_size, m, color_basis, check_periodic(periodic_exemplar))


def measure_statistics(img, scales, orientations, neighborhood, mask, color_basis, periodic_smooth):
    C = img.shape[-1]
    pixels = img.reshape(-1, C) if mask is None else img[mask > 0]
    if C == 1:
        mean, basis = np.zeros(1), np.eye(1)
    else:
        mean, basis = color_pca(pixels, canonical_signs=True)
    if not is_auto(color_basis):
        basis = np.asarray(color_basis, dtype=float)
        if basis.shape != (C, C) or not np.allclose(basis.T @ basis, np.eye(C), atol=1e-6):
            raise ValueError(f"color_basis must be an orthogonal {C}x{C} matrix (e.g. stats.color_basis), "
                             f"got shape {basis.shape}")
    comps = to_components(img, mean, basis)
    plan = pyramid_plan(img.shape[:2], scales, orientations)
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
        out[c] = (*weighted_moments(x, mask), inside.min(), inside.max())
    return out


# --------------------------------------------------------------------------- comparing / mixing statistics
def check_statistics(statistics, name="statistics"):
    if not isinstance(statistics, PSStatistics):
        raise TypeError(f"{name} must be a PSStatistics (from ps_statistics), got {type(statistics).__name__}")
    return statistics


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
    a, t = check_statistics(statistics), check_statistics(target, "target")
    _check_compatible(a, t)
    C, S, K = t.channels, t.scales, t.orientations
    out = {g: [] for g in SNR_GROUPS}
    for c in range(C):
        out["pixel"] += [snr_db(t.pixel[c, i], a.pixel[c, i]) for i in (1, 2, 3)]
        out["pixel_range"].append(snr_db(t.pixel[c, 4:], a.pixel[c, 4:]))
        out["highpass"].append(snr_db(t.highpass_variance[c], a.highpass_variance[c]))
        for s in range(S + 1):
            out["lowpass_moments"] += [snr_db(t.lowpass_moments[c, s, i], a.lowpass_moments[c, s, i]) for i in (0, 1)]
            out["lowpass_autocorrelation"].append(snr_db(t.lowpass_autocorrelation[c, s],
                                                       a.lowpass_autocorrelation[c, s]))
            if s < S:
                out["magnitude_autocorrelation"] += [snr_db(t.magnitude_autocorrelation[c, s, k],
                                                          a.magnitude_autocorrelation[c, s, k]) for k in range(K)]
    for s in range(S):
        out["magnitude_cross_orientation"].append(snr_db(t.magnitude_cross_orientation[s],
                                                       a.magnitude_cross_orientation[s]))
        if s < S - 1:
            out["magnitude_cross_scale"].append(snr_db(t.magnitude_cross_scale[s], a.magnitude_cross_scale[s]))
            out["real_cross_scale"].append(snr_db(t.real_cross_scale[s], a.real_cross_scale[s]))
        if C > 1:
            out["cross_channel"] += [snr_db(t.real_cross_channel[s, k], a.real_cross_channel[s, k]) for k in range(K)]
    if C > 1:
        out["cross_channel"] += [snr_db(t.lowpass_cross_channel[s], a.lowpass_cross_channel[s]) for s in range(S + 1)]
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
    a, b = check_statistics(a, "a"), check_statistics(b, "b")
    _check_compatible(a, b)
    alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
    if alpha == 0.0:
        return dataclasses.replace(a)
    if alpha == 1.0:
        return dataclasses.replace(b)
    mixed = {name: (1 - alpha) * value + alpha * getattr(b, name) for name, value in a.arrays().items()}
    return dataclasses.replace(a, **mixed)
