"""The exemplar's own feature scale, from which the methods choose their scale-aware defaults.

A texture's elements (bricks, pebbles, cells, letters) have a size, and a
synthesis keeps them whole only if some neighbourhood at some pyramid level
covers one. :func:`feature_scale` measures that size from the exemplar, so
that the methods can choose their neighbourhood sizes, levels and grids from
it instead of from fixed numbers.

The grey, mean-free periodic component of the exemplar (Moisan's
periodic-plus-smooth decomposition, so the border adds no cross to the
spectrum) is split into half-octave bands of wavelength; the feature scale is
the wavelength below which :data:`SCALE_ENERGY` of the energy lies. Fine detail
inside the elements (grain, noise) carries energy at short wavelengths but
does not move this percentile much, while the elements themselves and their
arrangement do; the correlation length of the autocorrelation, tried first,
was dominated by that detail (paving of 40 px cells: 2 px).
"""

from __future__ import annotations

import numpy as np

from ._validate import as_image, with_channels
from .pyramid import periodic_smooth_decomposition

__all__ = ["feature_scale", "octave_energy", "SCALE_ENERGY"]

#: Fraction of the energy below the feature scale (measured on the shared textures: 0.85 puts
#: pebbles at about 20 px, paving cells at about 35 px, bricks at about 50 px of a 192 px photo).
SCALE_ENERGY = 0.85


def octave_energy(image):
    """Share of the image's energy in half-octave bands of wavelength: ``(wavelengths, shares)``.

    The wavelengths run from 4 pixels (2 in the first band's lower edge) to
    half the smaller side; the shares sum to 1 (all zero for a flat image).

    Examples
    --------
    >>> stripes = np.tile(np.sin(np.arange(64) * 2 * np.pi / 16), (64, 1)) / 2 + 0.5
    >>> lams, shares = octave_energy(stripes)
    >>> float(lams[np.argmax(shares)])
    16.0
    """
    img, _ = with_channels(as_image(image, "image"))
    grey = img.astype(np.float64).mean(axis=-1)
    p = periodic_smooth_decomposition(grey)[0]
    p = p - p.mean()
    power = np.abs(np.fft.fft2(p)) ** 2
    freq = np.hypot(np.fft.fftfreq(grey.shape[0])[:, None], np.fft.fftfreq(grey.shape[1])[None, :])
    top = np.log2(max(min(grey.shape) / 2, 4.0))
    wavelengths = 2.0 ** np.arange(2.0, top + 0.01, 0.5)
    shares = np.array([power[(freq >= 2**-0.25 / lam) & (freq < 2**0.25 / lam)].sum() for lam in wavelengths])
    total = shares.sum()
    return wavelengths, shares / total if total > 0 else shares


def feature_scale(image):
    """The size in pixels of the exemplar's elements (see the module notes).

    Parameters
    ----------
    image : array_like
        The exemplar, ``(H, W)`` or ``(H, W, C)``, at least 8 pixels a side.

    Returns
    -------
    float
        The wavelength below which :data:`SCALE_ENERGY` of the energy lies,
        between 4 pixels and a quarter of the smaller side (an element must
        repeat in the exemplar to be a texture's).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> fine = rng.random((128, 128))  # white noise: elements of about a pixel
    >>> squares = np.kron(rng.random((8, 8)), np.ones((16, 16)))  # 16-pixel squares
    >>> feature_scale(fine) < 8 < 12 < feature_scale(squares) <= 32
    True
    """
    wavelengths, shares = octave_energy(image)
    limit = max(4.0, min(np.shape(image)[:2]) / 4.0)
    if not shares.any():
        return 4.0
    cumulative = np.cumsum(shares)
    k = int(np.searchsorted(cumulative, SCALE_ENERGY))
    if k >= len(wavelengths):
        return float(limit)
    # interpolate in log-wavelength between the band that crosses the level and the one before
    below = cumulative[k - 1] if k else 0.0
    t = (SCALE_ENERGY - below) / max(shares[k], 1e-12)
    lam = wavelengths[k] * 2 ** (0.5 * (t - 1.0)) if k else wavelengths[0]
    return float(np.clip(lam, 4.0, limit))
