"""Template search: the masked distance of a template to every window of an image, by FFT.

Patch-pasting methods (image quilting, patch-based sampling) ask one question
per pasted block: *how far is each h x w window of the exemplar from what the
output already shows here?* Only part of the block is known (its overlap, or
boundary zone), so the distance is masked:

.. math:: d(p) = \\sum_x m(x)\\, \\|I(p + x) - T(x)\\|^2
        = \\sum_x m(x) \\|I(p+x)\\|^2 - 2 \\sum_x m(x)\\, T(x) \\cdot I(p+x) + \\sum_x m(x) \\|T(x)\\|^2

for every top-left corner ``p`` of a window inside the image. The first term
is the correlation of the image's squared norm with the mask, the second the
correlation of the image with the masked template; both are products of
Fourier transforms (the image's are computed once, the mask's term once per
distinct mask), so one query costs a few real FFTs of the image's size
instead of ``windows x h x w`` multiply-adds: the "FFT correlation" of Efros
& Freeman's quilting and of Kwatra et al.'s graph-cut patch matching. The
distances are exact up to the FFT's rounding (relative 1e-12 here); values
within the rounding error of 0 are returned as 0, so exact matches compare
equal (``error_tolerance=0`` then keeps every exact copy, not one at random
of the rounding).

:func:`within_tolerance` and :func:`within_radius` turn a distance map into
the candidate set of a method: every window within ``(1 + error_tolerance)``
of the best (Efros & Leung, Efros & Freeman), or within a radius, else the
nearest (Liang et al.).
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sp_fft

from .._validate import check_memory
from ..neighborhood import patches_within

__all__ = ["TemplateSearch", "WindowSearch", "within_radius", "within_tolerance"]

# FFT rounding: distances below this fraction of the terms' magnitude are 0
# (double precision FFTs of 2**16-2**20 points err by ~1e-14 relative; 1e-9 is
# far above that and far below any distance between 8- or 16-bit images' windows)
_ROUNDING = 1e-9


class WindowSearch:
    """Masked squared distances between a template and every window of an image.

    Parameters
    ----------
    image : numpy.ndarray
        ``(H, W, C)`` float array (the exemplar), searched as it is.
    window : (int, int)
        ``(h, w)`` of the windows (at most the image's size).
    valid : numpy.ndarray, optional
        ``(H, W)`` bool: the pixels a window may hold (an
        :class:`~texsynth.core.search.ExemplarAtlas`'s tiles); a window that
        holds another pixel is at distance ``inf`` and never drawn.

    Attributes
    ----------
    shape : (int, int)
        The number of window positions ``(H - h + 1, W - w + 1)``; position
        ``(i, j)`` is the window whose top-left pixel is ``(i, j)``.
    image : numpy.ndarray
        The image the windows are cut from.
    n_positions : int
        The number of positions a window may take (all of them without ``valid``).

    Examples
    --------
    >>> image = np.random.default_rng(0).random((12, 10, 3))
    >>> search = WindowSearch(image, (4, 5))
    >>> mask = np.zeros((4, 5)); mask[:, :2] = 1  # only the left two columns are known
    >>> d2 = search.sq_distances(image[3:7, 2:7], mask)
    >>> d2.shape, tuple(int(i) for i in np.unravel_index(np.argmin(d2), d2.shape)), float(d2.min())
    ((9, 6), (3, 2), 0.0)
    """

    def __init__(self, image, window, valid=None):
        image = np.asarray(image, dtype=np.float64)
        self.image = image
        if image.ndim != 3:
            raise ValueError(f"image must be a channels-last array (H, W, C), got shape {image.shape}")
        h, w = int(window[0]), int(window[1])
        H, W, C = image.shape
        if not (1 <= h <= H and 1 <= w <= W):
            raise ValueError(f"window ({h}, {w}) must fit in the image ({H}, {W}); pass a smaller window")
        # the circular correlation of an (H, W) image is the valid one for every window that does
        # not wrap; padding to a fast FFT length changes nothing but the speed
        self._fft_shape = (sp_fft.next_fast_len(H, real=True), sp_fft.next_fast_len(W, real=True))
        check_memory(16.0 * self._fft_shape[0] * self._fft_shape[1] * (C + 4), (H, W), "image",
                     "the image's Fourier transforms")
        self.window = (h, w)
        self.shape = (H - h + 1, W - w + 1)
        self.allowed = None if valid is None else patches_within(valid, (h, w))
        self.n_positions = self.shape[0] * self.shape[1] if valid is None else int(self.allowed.sum())
        self._spectrum = sp_fft.rfft2(image, s=self._fft_shape, axes=(0, 1))
        sq_norm = np.einsum("ijc,ijc->ij", image, image)
        self._sq_spectrum = sp_fft.rfft2(sq_norm, s=self._fft_shape)
        self._peak = float(sq_norm.max())
        self._energies = {}

    def _correlate(self, spectrum_product):
        """The valid part of the inverse transform of a product of spectra."""
        out = sp_fft.irfft2(spectrum_product, s=self._fft_shape, axes=(0, 1))
        return out[: self.shape[0], : self.shape[1]]

    def _kernel_spectrum(self, kernel):
        return np.conj(sp_fft.rfft2(kernel, s=self._fft_shape, axes=(0, 1)))

    def masked_energy(self, mask):
        """``sum_x m(x) ||I(p + x)||^2`` for every window ``p`` (cached per mask)."""
        key = mask.tobytes()
        if key not in self._energies:
            self._energies[key] = self._correlate(self._sq_spectrum * self._kernel_spectrum(mask))
        return self._energies[key]

    def sq_distances(self, template, mask=None):
        """``d(p) = sum_x m(x) ||I(p + x) - T(x)||^2`` for every window position ``p``.

        Parameters
        ----------
        template : numpy.ndarray
            ``(h, w, C)``: what the windows are compared with (values where the
            mask is 0 are ignored).
        mask : numpy.ndarray, shape (h, w), optional
            Non-negative weight of every template pixel (bool or float); 0
            for pixels that are not known. Default: every pixel, weight 1.

        Returns
        -------
        numpy.ndarray, shape :attr:`shape`
            Squared distances, >= 0, exact up to the FFT's rounding (values
            within it of 0 are 0).
        """
        template = np.asarray(template, dtype=np.float64)
        h, w = self.window
        if template.shape != (h, w, self._spectrum.shape[2]):
            raise ValueError(f"template must have shape {(h, w, self._spectrum.shape[2])}, got {template.shape}")
        m = np.ones((h, w)) if mask is None else np.asarray(mask, dtype=np.float64)
        if m.shape != (h, w):
            raise ValueError(f"mask must have shape {(h, w)}, got {m.shape}")
        if not (np.all(np.isfinite(m)) and m.min() >= 0):
            raise ValueError("mask must be finite and non-negative (1 = known pixel, 0 = unknown)")
        weighted = template * m[..., None]
        constant = float(np.einsum("ijc,ijc->", weighted, template))  # sum_x m(x) ||T(x)||^2
        cross = np.einsum("ijc,ijc->ij", self._spectrum, self._kernel_spectrum(weighted))  # sum over channels
        d2 = self.masked_energy(m) - 2.0 * self._correlate(cross) + constant
        rounding = _ROUNDING * (constant + self._peak * m.sum())
        d2[d2 < rounding] = 0.0
        if self.allowed is not None:
            d2[~self.allowed] = np.inf
        return d2

    def draw(self, rng):
        """A window position ``(top, left)`` drawn uniformly among those allowed (one ``rng.integers`` draw)."""
        k = int(rng.integers(self.n_positions))
        return divmod(k if self.allowed is None else int(np.flatnonzero(self.allowed)[k]), self.shape[1])


class TemplateSearch:
    """Squared distances between a fixed template and every placement of it over a partly known image.

    :class:`WindowSearch`'s question with the roles exchanged: the template
    (graph-cut textures' whole input) is fixed and known everywhere, and the
    image it is placed over (the output) is known only where ``known`` is
    true, so the distance of the placement whose top-left pixel is ``p`` is

    .. math:: d(p) = \\sum_x k(p + x)\\, \\|O(p + x) - T(x)\\|^2
            = \\sum_x k\\|O\\|^2 (p + x) - 2 \\sum_x (k O)(p + x) \\cdot T(x) + \\sum_x k(p + x) \\|T(x)\\|^2

    over the pixels ``x`` of the template, with ``n(p) = sum_x k(p + x)``
    known pixels under it: four correlations, each a product of Fourier
    transforms (the template's are computed once per image shape).

    Parameters
    ----------
    template : numpy.ndarray
        ``(h, w, C)`` float array.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> template = rng.random((4, 5, 3))
    >>> image = rng.random((10, 12, 3)); image[3:7, 2:7] = template
    >>> known = np.ones((10, 12)); known[:, 4:] = 0  # only the left four columns are known
    >>> d2, n = TemplateSearch(template).sq_distances(image, known)
    >>> d2.shape, float(d2[3, 2]), float(n[3, 2])
    ((7, 8), 0.0, 8.0)
    """

    def __init__(self, template):
        template = np.asarray(template, dtype=np.float64)
        if template.ndim != 3:
            raise ValueError(f"template must be a channels-last array (h, w, C), got shape {template.shape}")
        self.template = template
        self._spectra = {}

    def _template_spectra(self, fft_shape):
        if fft_shape not in self._spectra:
            t = self.template[::-1, ::-1]  # correlation = convolution with the flipped template
            ones = np.ones(t.shape[:2])
            self._spectra[fft_shape] = (sp_fft.rfft2(t, s=fft_shape, axes=(0, 1)),
                                        sp_fft.rfft2(np.einsum("ijc,ijc->ij", t, t), s=fft_shape),
                                        sp_fft.rfft2(ones, s=fft_shape))
        return self._spectra[fft_shape]

    def sq_distances(self, image, known):
        """``(d, n)``: the masked squared distance and the number of known pixels of every placement.

        Parameters
        ----------
        image : numpy.ndarray
            ``(H, W, C)`` with ``H >= h`` and ``W >= w``; values where ``known`` is 0 are ignored.
        known : numpy.ndarray
            ``(H, W)``, 1 where the image is known, 0 elsewhere (or non-negative weights).

        Returns
        -------
        d, n : numpy.ndarray, shape (H - h + 1, W - w + 1)
            ``d[p]`` and ``n[p]`` for the placement whose top-left pixel is
            ``p``; ``d`` is exact up to the FFT's rounding (values within it of
            0 are 0), ``n`` rounded to whole pixels for a binary ``known``.
        """
        image = np.asarray(image, dtype=np.float64)
        k = np.asarray(known, dtype=np.float64)
        h, w, C = self.template.shape
        H, W = k.shape
        if image.shape != (H, W, C) or H < h or W < w:
            raise ValueError(f"image must have shape (H, W, {C}) with H >= {h}, W >= {w}, and known (H, W); got "
                             f"{image.shape} and {k.shape}")
        fft_shape = (sp_fft.next_fast_len(H, real=True), sp_fft.next_fast_len(W, real=True))
        check_memory(16.0 * fft_shape[0] * fft_shape[1] * (C + 6), (H, W), "image", "the placements' transforms")
        t_spec, t_sq_spec, ones_spec = self._template_spectra(fft_shape)
        masked = image * k[..., None]
        sq = np.einsum("ijc,ijc->ij", masked, image)  # k ||O||^2
        k_spec = sp_fft.rfft2(k, s=fft_shape)

        def valid(spectrum_product):
            # circular convolution of an (H, W) image with an (h, w) kernel: rows h-1..H-1 are the valid ones
            return sp_fft.irfft2(spectrum_product, s=fft_shape, axes=(0, 1))[h - 1:H, w - 1:W]

        cross = np.einsum("ijc,ijc->ij", sp_fft.rfft2(masked, s=fft_shape, axes=(0, 1)), t_spec)
        d = valid(sp_fft.rfft2(sq, s=fft_shape) * ones_spec) - 2.0 * valid(cross) + valid(k_spec * t_sq_spec)
        n = valid(k_spec * ones_spec)
        rounding = _ROUNDING * (float(sq.max(initial=0.0)) + float(np.einsum("ijc,ijc->", self.template,
                                                                             self.template))) * h * w
        d[d < rounding] = 0.0
        return d, np.round(n, 6)


def within_tolerance(sq_distances, error_tolerance):
    """Flat indices of the distances within ``(1 + error_tolerance)`` of the smallest.

    The candidate set of Efros & Leung (1999, with ``epsilon = 0.1``) and of
    image quilting (Efros & Freeman 2001, Section 2.1: "within 0.1 times the
    error of the best"): ``d <= (1 + error_tolerance) * min(d)``. With a best
    distance of 0, only the exact matches qualify.

    Examples
    --------
    >>> within_tolerance(np.array([[2.0, 1.0], [1.05, 3.0]]), 0.1).tolist()
    [1, 2]
    """
    d = np.asarray(sq_distances).ravel()
    return np.flatnonzero(d <= (1.0 + error_tolerance) * d.min())


def within_radius(sq_distances, max_sq_distance):
    """Flat indices of the distances below ``max_sq_distance``; the nearest one if there is none.

    The candidate set of patch-based sampling (Liang et al. 2001): every patch
    whose boundary-zone distance is below ``d_max``, or the closest patch when
    none is.

    Examples
    --------
    >>> within_radius(np.array([3.0, 0.5, 0.2]), 1.0).tolist(), within_radius(np.array([3.0, 2.0]), 1.0).tolist()
    ([1, 2], [1])
    """
    d = np.asarray(sq_distances).ravel()
    inside = np.flatnonzero(d < max_sq_distance)
    return inside if inside.size else np.array([int(np.argmin(d))])
