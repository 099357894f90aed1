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

__all__ = ["feature_scale", "octave_energy", "scale_schedule", "SCALE_ENERGY"]

#: Fraction of the energy below the feature scale (measured on texture photographs: 0.85 puts
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


#: :func:`scale_schedule`: the largest neighbourhood for exemplars whose feature scale is above
#: ``LARGE_FEATURES`` pixels (half of it otherwise), and the smaller side of the coarsest exemplar level.
LARGE_SIZE = 64
LARGE_FEATURES = 32.0
COARSEST_SIDE = 32


def scale_schedule(exemplar, shape):
    """Neighbourhood sizes and levels of preset ``"default"``, from the exemplar and the output.

    The largest neighbourhood is 64 pixels for an exemplar whose feature
    scale (:func:`texsynth.core.scale.feature_scale`) is above 32 pixels and
    32 otherwise, at most a quarter of the exemplar's smaller side; each
    level uses it, half of it and a quarter of it (none below 4 pixels, none
    above the output's smaller side). Levels: as many as keep the coarsest
    exemplar at least 32 pixels on its smaller side. Texture optimization's preset ``"default"`` and
    the completion functions use it.

    Examples
    --------
    >>> import numpy as np
    >>> scale_schedule(np.random.default_rng(0).random((256, 256, 1)), (512, 512))
    ((32, 16, 8), 4)
    """
    side = min(exemplar.shape[:2])
    largest = LARGE_SIZE if feature_scale(exemplar) > LARGE_FEATURES else LARGE_SIZE // 2
    largest = max(4, min(largest, 2 ** int(np.log2(max(side // 4, 1)))))
    sizes = tuple(w for w in (largest, largest // 2, largest // 4) if 4 <= w <= min(shape)) or (min(largest, *shape),)
    levels = max(1, int(np.log2(side / COARSEST_SIDE)) + 1)
    return sizes, levels
