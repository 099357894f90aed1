"""Portilla-Simoncelli texture synthesis: noise projected onto the set of images with given statistics.

Portilla & Simoncelli (2000) synthesise a new texture by starting from Gaussian noise and
projecting it, again and again, onto the set of images with the statistics of
:mod:`texsynth.statistical._ps_statistics` (:class:`~texsynth.statistical.PSStatistics`).
This module follows the authors' MATLAB ``textureSynth`` (textureSynthesis.m), written
from the paper and that code's structure.

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
:func:`~texsynth.statistical.interpolate_statistics`, the paper's sec. 6). ``ps_step(...,
mask=region)`` imposes statistics on a region of an image only: every
statistic is measured on the region, the correction is computed from it, and
the pixels outside are kept.

Colour (Ruiters et al. 2010, sec. 4.5)
--------------------------------------
Synthesis works in the principal components of the exemplar's colours, with the
cross-channel statistics of :mod:`texsynth.statistical._ps_statistics` imposed at every
band and scale; the result is mapped back to the input's colours and clipped to the
exemplar's range.

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

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from numpy.polynomial import polynomial as npoly

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import as_image, as_rng, as_size, check_memory, check_positive_int, restore_channels, with_channels
from ..core.search import is_auto
from ._ps_statistics import (SNR_GROUPS, PSStatistics, central_lags, check_neighborhood, check_periodic,
                             check_scales_fit, check_statistics, expand_band, from_components, measure_statistics,
                             parent_columns, pyramid_plan, single_threaded_blas, snr_db, to_components,
                             weighted_moments)

__all__ = ["PSInfo", "ps_step", "portilla_simoncelli"]


#: Momentum of textureSynthesis.m's "accelerator": im <- im + 0.8 (im - previous).
ACCELERATION = 0.8


# textureSynthesis.m skips autocorrelation / moment projections of low-pass images
# whose variance is below 1e-4 of the pixel variance (they carry no structure).
_NEGLIGIBLE_VARIANCE = 1e-4


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


# --------------------------------------------------------------------------- projections (the paper's section 4)
def _region_autocorrelation(x, where, reach):
    """Circular autocorrelation over pairs of pixels both in the region, natural FFT order.

    ``sum m(p) m(p+d) x(p) x(p+d) / sum m(p) m(p+d)`` (the weighted estimate of
    :func:`_autocorrelation`); every lag up to ``reach`` in each direction needs a pair inside.
    """
    w = where.astype(float)
    num = sfft.irfft2(np.abs(sfft.rfft2(x * w)) ** 2, s=x.shape)
    den = np.rint(sfft.irfft2(np.abs(sfft.rfft2(w)) ** 2, s=x.shape))
    if np.any(central_lags(den, min(reach, (min(x.shape) - 1) // 2)) < 1):
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
    snr = snr_db(target, central_lags(full, radius))
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
        return x, snr_db(target, 0.0 if order == 3 else 3.0)
    d = (x - mean) / sd  # unit variance: lambda is dimensionless
    dr = sel(d)  # the region's values: every moment below is the region's
    d2 = dr * dr
    m3 = float(np.mean(d2 * dr))
    current = m3 if order == 3 else float(np.mean(d2 * d2))
    snr = snr_db(target, current)

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
    return x @ _covariance_map(current, target), snr_db(target, current)


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
    return x @ mx + y @ my, snr_db(target_x, bx), snr_db(target_xy, bxy)


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


# --------------------------------------------------------------------------- one iteration
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
            pmag, preal = parent_columns(bands[s + 1], (h, w), rows(s))
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
        low = np.stack([expand_band(low[c], (h, w)) + plan.band_image(s, z[c]) for c in range(C)])
        low = adjust_lowpass(low, s)
    # High-pass residual: reduce its variance if too large; add it; pixel statistics.
    out = np.empty_like(comps)
    for c in range(C):
        hp = highpass[c]
        var, target = float(np.mean(inside(hp * hp, 0))), stats.highpass_variance[c]
        snr.add("highpass", snr_db(target, var))
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
        mean, var, _, _ = weighted_moments(x, None if where is None else where.astype(float))
        xin = x if where is None else x[where]
        snr.add("pixel", snr_db(var0, var))
        snr.add("pixel_range", snr_db([lo, hi], [xin.min() - mean + mean0, xin.max() - mean + mean0]))
        x = (x - mean) * np.sqrt(var0 / max(var, 1e-300)) + mean0
        x, v1 = _impose_moment(x, skew0, 3, where)
        x, v2 = _impose_moment(x, kurt0, 4, where)
        snr.add("pixel", v1, v2)
        out[c] = np.clip(x, lo, hi)
    if comps.shape[0] > 1:  # the colours themselves stay within the exemplar's range
        rgb = np.clip(from_components(out, stats), stats.color_range[:, 0], stats.color_range[:, 1])
        out = to_components(rgb, stats.color_mean, stats.color_basis)
    return out


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


@single_threaded_blas
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
        Target statistics (:func:`~texsynth.statistical.ps_statistics`, :func:`~texsynth.statistical.interpolate_statistics`).
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
    >>> from texsynth.statistical import ps_statistics, statistics_snr
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
    stats = check_statistics(statistics)
    img = as_image(image, "image")
    dtype = img.dtype
    img, grey = with_channels(img.astype(np.float64, copy=False))
    if img.shape[-1] != stats.channels:
        raise ValueError(f"image has {img.shape[-1]} channel(s) but the statistics were measured on "
                         f"{stats.channels}; pass an image with {stats.channels} channel(s)")
    check_scales_fit(stats.scales, img.shape[:2], "image")
    weight, region = _check_step_mask(mask, img.shape[:2], stats.scales)
    plan = pyramid_plan(img.shape[:2], stats.scales, stats.orientations)
    comps = _step(to_components(img, stats.color_mean, stats.color_basis), stats, plan, _SNR(), region)
    out = np.clip(from_components(comps, stats), 0.0, 1.0)
    if weight is not None:  # outside the region the image stays as it was (exactly where mask == 0)
        out = (1.0 - weight)[..., None] * img + weight[..., None] * out
    return restore_channels(out.astype(dtype, copy=False), grey)


# --------------------------------------------------------------------------- synthesis
def _synthesise(stats, shape, iterations, gen, progress):
    """Iterate the projections from Gaussian noise with the accelerator; (components, PSInfo fields)."""
    plan = pyramid_plan(shape, stats.scales, stats.orientations)
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
        if not is_auto(value) and value != getattr(stats, attribute):
            raise ValueError(f"{name}={value} but the statistics were measured with {name}={getattr(stats, attribute)}; "
                             f"leave {name} out when passing statistics (it is theirs)")
    if periodic_smooth:
        raise ValueError("periodic_exemplar applies to the analysis of an exemplar, and these statistics are "
                         "already measured; pass periodic_exemplar='periodic+smooth' to ps_statistics instead")


@single_threaded_blas
def portilla_simoncelli(exemplar, size=None, *, scales="auto", orientations="auto", neighborhood_size="auto", iterations=50,
                        periodic_exemplar="none", rng=None, progress=False, return_info=False):
    """Synthesise a texture with an exemplar's (or given) Portilla-Simoncelli statistics.

    Examples
    --------
    >>> import texsynth
    >>> metal = texsynth.data.load("metal")[:64, :64]
    >>> out, info = texsynth.portilla_simoncelli(metal, (64, 96), scales=3, iterations=3, rng=0, return_info=True)
    >>> out.shape, len(info.snr["pixel"])
    ((64, 96), 3)

    Starting from noise, imposes the exemplar's statistics of its complex
    steerable pyramid (marginals, auto-correlations, correlations of
    magnitudes and phases across positions, orientations and scales) by
    projections, iterated [1]_; colour as Ruiters et al. extend it [2]_.

    Parameters
    ----------
    exemplar : array_like or PSStatistics
        Grey ``(H, W)`` or colour ``(H, W, C)`` texture (uint8, uint16 or
        float in [0, 1]), at least ``2^(scales+2)`` pixels per axis (64x64 for
        the default 4 scales). Or the statistics themselves, as
        :func:`~texsynth.statistical.ps_statistics` measures them or :func:`~texsynth.statistical.interpolate_statistics`
        mixes them: then ``size`` is required and ``scales``,
        ``orientations`` and ``neighborhood_size`` are the statistics' own.
    size : int or (int, int), optional
        Output ``(height, width)``, default the exemplar's (required with
        statistics); any size with at least ``2^(scales+2)`` pixels per axis
        (the statistics do not depend on the image's size).
    scales, orientations, neighborhood_size : int or "auto"
        Pyramid scales, orientations and the autocorrelation window;
        ``"auto"`` (the default) means 4, 4 and 7 as in the paper for an
        exemplar, and the statistics' own for statistics (another value is
        then an error).
    iterations : int
        Number of projection iterations (50 in the paper's examples).
    periodic_exemplar : {"none", "periodic+smooth"}
        Analyse the exemplar's periodic component (see :func:`~texsynth.statistical.ps_statistics`);
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
    rng=seed)``; with statistics mixed by :func:`~texsynth.statistical.interpolate_statistics`
    it gives the paper's interpolated textures (sec. 6), here halfway
    between metal and reptile skin:

    >>> a = texsynth.ps_statistics(metal, scales=3)
    >>> b = texsynth.ps_statistics(texsynth.data.load("reptile")[:64, :64], scales=3)
    >>> mixed = texsynth.portilla_simoncelli(texsynth.interpolate_statistics(a, b, 0.5), (48, 64), iterations=3,
    ...                                      rng=0)
    >>> mixed.shape, mixed.dtype
    ((48, 64), dtype('float64'))

    There is no mask: the synthesis starts from noise everywhere; to impose
    statistics on a region of an existing image, iterate ``ps_step(image,
    statistics, mask=region)``.

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
    """
    t_start = time.perf_counter()
    if isinstance(exemplar, PSStatistics):
        stats = exemplar
        _check_from_statistics(stats, size, scales, orientations, neighborhood_size, check_periodic(periodic_exemplar))
        shape = as_size(size)
        iterations = check_positive_int(iterations, "iterations", minimum=1, maximum=MAX_ITERATIONS)
        check_scales_fit(stats.scales, shape, "output")
        _check_memory(shape, stats.channels, stats.scales, stats.orientations)
        dtype, grey = np.dtype(np.float64), stats.channels == 1
        gen = as_rng(rng)
    else:
        ex = as_image(exemplar, "exemplar")
        dtype = ex.dtype
        ex, grey = with_channels(ex.astype(np.float64, copy=False))
        shape = ex.shape[:2] if size is None else as_size(size)
        scales = check_positive_int(4 if is_auto(scales) else scales, "scales", minimum=1)
        orientations = check_positive_int(4 if is_auto(orientations) else orientations, "orientations", minimum=1)
        neighborhood_size = check_neighborhood(7 if is_auto(neighborhood_size) else neighborhood_size)
        iterations = check_positive_int(iterations, "iterations", minimum=1, maximum=MAX_ITERATIONS)
        check_scales_fit(scales, ex.shape[:2], "exemplar")
        check_scales_fit(scales, shape, "output")
        _check_memory(shape, ex.shape[-1], scales, orientations)
        gen = as_rng(rng)
        stats = measure_statistics(ex, scales, orientations, neighborhood_size, None, "auto",
                                   check_periodic(periodic_exemplar))
    t_synthesis = time.perf_counter()
    components, history, change = _synthesise(stats, shape, iterations, gen, progress)
    out = np.clip(from_components(components, stats), 0.0, 1.0)
    out = restore_channels(out.astype(dtype, copy=False), grey)
    if return_info:
        end = time.perf_counter()
        return out, PSInfo(history, change, stats, seconds=end - t_start,
                           stage_seconds={"analysis": t_synthesis - t_start, "synthesis": end - t_synthesis})
    return out
