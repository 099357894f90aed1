"""Pyramids: Gaussian, Laplacian and steerable, plus the periodic-plus-smooth split.

The shared multi-scale layer of texsynth. Every function here works on arrays
that the public API has already converted to floating point (docs/conventions.md,
"Images"), channels last; nothing here rescales values.

Gaussian and Laplacian pyramids (Burt & Adelson 1983)
-----------------------------------------------------
:func:`downsample` ("REDUCE") blurs every spatial axis with the 5-tap binomial
kernel ``[1, 4, 6, 4, 1] / 16`` and keeps every second sample starting at
index 0, so an axis of ``n`` samples becomes ``ceil(n / 2)`` (odd sizes are
fine). :func:`upsample` ("EXPAND") is its adjoint up to a factor ``2`` per axis:
zeros are inserted between the samples and the result is filtered with
``2 * [1, 4, 6, 4, 1] / 16`` along each axis. The Laplacian pyramid stores
``L_i = G_i - EXPAND(G_{i+1})`` and the coarsest Gaussian level, so
:func:`reconstruct_laplacian` is exact for *any* EXPAND (it only undoes the
subtractions, up to floating-point rounding, about 1e-16 per level). EXPAND by
zero insertion + binomial is chosen over linear interpolation because it is
the classical Burt-Adelson operator, the adjoint of REDUCE (so the Laplacian
levels are the usual band-pass images) and it keeps constants exactly. scikit-image's ``pyramid_gaussian`` is
another operator (a Gaussian of sigma 2/3 and a resize; its first level differs
from REDUCE by up to 0.24 on a photograph) and ``pyramid_laplacian`` has no
reconstruction, so the papers' pyramids are built here (``benchmarks/bench_packages.py``).

Boundaries: ``mode="reflect"`` mirrors about the edge sample without repeating
it (``c b | a b c``, numpy's ``pad(mode="reflect")``, scipy.ndimage's
``"mirror"``), which keeps the zero-inserted samples of EXPAND symmetric;
``mode="wrap"`` is periodic (tileable textures).

Steerable pyramid (Simoncelli & Freeman 1995)
---------------------------------------------
:class:`SteerablePyramid` is the frequency-domain construction of Portilla &
Simoncelli (2000) (``SteerablePyramidFreq`` of pyrtools / matlabPyrTools):

- high-pass / low-pass split with log-radial raised-cosine masks
  ``H0(r)^2 + L0(r)^2 = 1`` (transition band ``r`` in ``[1/2, 1]``);
- at every scale ``s`` an annulus ``H(2^s r)`` cut into ``K`` orientations by
  angular masks ``A_k(t) = alpha_K cos(t - pi k / K)^(K-1)`` with
  ``alpha_K^2 = 2^(2(K-1)) ((K-1)!)^2 / (K (2(K-1))!)`` so that
  ``sum_k A_k^2 = 1`` for every angle;
- the low-pass band ``L(2^s r)`` is subsampled by cropping its centred spectrum
  to ``ceil(n / 2)`` samples per axis (odd and non-power-of-two sizes work,
  because the low-pass mask is zero outside the crop).

The masks are computed from closed-form expressions (not lookup tables) and
the crop is rescaled by ``sqrt(N_{s+1} / N_s)`` (``N`` = number of pixels), so
the transform is a Parseval tight frame: the coefficients' energy equals the
image's energy and reconstruction is exact to rounding (about 1e-15). With this
scaling the low-pass residual after ``S`` scales has ``2^S`` times the image's
mean (the classical orthonormal-wavelet convention); pyrtools' low-pass has
``4^S`` times the mean instead. Boundaries are periodic (FFT).

With ``is_complex=True`` each oriented band is the analytic signal of the real
band (its angular mask is doubled on one half-plane and zero on the other):
``band.real`` is the real band, ``abs(band)`` the local magnitude and
``angle(band)`` the local phase that Portilla & Simoncelli's statistics use.

Periodic-plus-smooth decomposition (Moisan 2011)
------------------------------------------------
:func:`periodic_smooth_decomposition` splits an image ``u = p + s`` into a
periodic component ``p`` with no jump across the image border (so its Fourier
transform has no "cross" from the border discontinuity) and a smooth
component ``s``. Spectral methods (Heeger-Bergen, Portilla-Simoncelli) analyse
``p``.

References
----------
.. [1] P. J. Burt and E. H. Adelson, "The Laplacian pyramid as a compact image
   code", IEEE Trans. Communications 31(4), 1983. doi:10.1109/TCOM.1983.1095851
.. [2] E. P. Simoncelli and W. T. Freeman, "The steerable pyramid: a flexible
   architecture for multi-scale derivative computation", ICIP 1995.
   doi:10.1109/ICIP.1995.537667
.. [3] J. Portilla and E. P. Simoncelli, "A parametric texture model based on
   joint statistics of complex wavelet coefficients", IJCV 40(1), 2000.
   doi:10.1023/A:1026553619983
.. [4] L. Moisan, "Periodic plus smooth image decomposition", J. Math. Imaging
   and Vision 39(2), 2011. doi:10.1007/s10851-010-0227-1
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from scipy.ndimage import correlate1d

from ._validate import as_float_array, check_choice, check_memory, check_positive_int

__all__ = [
    "BINOMIAL_KERNEL",
    "downsample",
    "upsample",
    "max_levels",
    "level_shapes",
    "gaussian_pyramid",
    "laplacian_pyramid",
    "reconstruct_laplacian",
    "SteerableCoefficients",
    "SteerablePyramid",
    "max_scales",
    "periodic_smooth_decomposition",
]

#: The 5-tap binomial kernel of Burt & Adelson's REDUCE/EXPAND (a = 3/8).
BINOMIAL_KERNEL = np.array([1.0, 4.0, 6.0, 4.0, 1.0]) / 16.0

# numpy's pad(mode="reflect") (c b | a b c) is scipy.ndimage's "mirror".
_NDIMAGE_MODES = {"reflect": "mirror", "wrap": "wrap"}


# --------------------------------------------------------------------------- helpers
def _check_mode(mode):
    return _NDIMAGE_MODES[check_choice(mode, "mode", _NDIMAGE_MODES)]


def _as_shape(shape):
    """A spatial shape: a non-empty tuple of non-negative ints, any number of axes."""
    try:
        axes = () if isinstance(shape, str) else tuple(shape)
    except TypeError:
        axes = ()
    if not axes or not all(isinstance(s, numbers.Integral) and not isinstance(s, bool) for s in axes):
        raise TypeError(f"shape must be a tuple of ints (a spatial shape such as image.shape[:2]), got {shape!r}")
    if min(axes) < 0:
        raise ValueError(f"shape must be non-negative ints (a spatial shape), got {shape!r}")
    return tuple(int(s) for s in axes)


def _spatial(image, spatial_dims, name="image"):
    """Validate the layout (spatial axes, optionally one trailing channel axis)."""
    check_choice(spatial_dims, "spatial_dims", (2, 3))
    arr = np.asarray(image)
    if arr.ndim not in (spatial_dims, spatial_dims + 1):
        axes = "(H, W)" if spatial_dims == 2 else "(D, H, W)"
        raise ValueError(
            f"{name} must have {spatial_dims} spatial axes {axes} and optionally a trailing channel "
            f"axis for spatial_dims={spatial_dims}, got shape {arr.shape}"
        )
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape}); pass an array with at least one sample")
    if arr.dtype in (np.uint8, np.uint16, np.bool_):
        return as_float_array(arr, name)  # scaled to [0, 1] as everywhere in texsynth
    if not np.issubdtype(arr.dtype, np.floating):
        raise TypeError(f"{name} must be floating point (any range: pyramid bands are signed) or "
                        f"uint8/uint16/bool, got dtype {arr.dtype}")
    _check_finite(arr, name)
    return arr


def _check_finite(arr, name):
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) first")


def _blur(image, spatial_dims, ndmode, kernel=BINOMIAL_KERNEL):
    out = image
    for axis in range(spatial_dims):
        out = correlate1d(out, kernel.astype(image.dtype), axis=axis, mode=ndmode)
    return out


def level_shapes(shape, levels):
    """The shapes of a pyramid's ``levels`` levels, the finest ``shape`` first: each axis ``n`` becomes
    ``ceil(n / 2)`` at the next level, as :func:`downsample` keeps every other sample, the first kept.

    Examples
    --------
    >>> level_shapes((5, 8), 3)
    [(5, 8), (3, 4), (2, 2)]
    """
    shapes = [tuple(_as_shape(shape))]
    for _ in range(check_positive_int(levels, "levels") - 1):
        shapes.append(tuple((n + 1) // 2 for n in shapes[-1]))
    return shapes


def max_levels(shape):
    """Largest number of Gaussian/Laplacian levels for a spatial ``shape``.

    Each level halves every axis (``ceil(n / 2)``) and an axis of one pixel
    cannot be halved again, so ``1 + ceil(log2(min(shape)))`` levels exist.

    >>> max_levels((64, 48)), max_levels((5, 7)), max_levels((1, 9))
    (7, 4, 1)
    """
    smallest = min(_as_shape(shape))
    return 1 + max(0, math.ceil(math.log2(smallest))) if smallest > 0 else 0


# --------------------------------------------------------------------------- REDUCE / EXPAND
def downsample(image, *, spatial_dims=2, mode="reflect"):
    """Blur with the 5-tap binomial kernel and keep every second sample (REDUCE).

    Parameters
    ----------
    image : numpy.ndarray
        Float array with ``spatial_dims`` spatial axes and optionally a
        trailing channel axis: ``(H, W)``, ``(H, W, C)``, ``(D, H, W)`` or
        ``(D, H, W, C)``.
    spatial_dims : {2, 3}
        Number of leading spatial axes.
    mode : {"reflect", "wrap"}
        Boundary: mirror about the edge samples, or periodic.

    Returns
    -------
    numpy.ndarray
        Every spatial axis of length ``n`` becomes ``ceil(n / 2)``; samples
        ``0, 2, 4, ...`` of the blurred image.

    Examples
    --------
    >>> downsample(np.ones((5, 8, 3))).shape
    (3, 4, 3)
    >>> float(downsample(np.ones((6, 6))).max())
    1.0
    """
    arr = _spatial(image, spatial_dims)
    ndmode = _check_mode(mode)
    out = arr
    for axis in range(spatial_dims):  # blur and decimate one axis at a time: half the work of blur-then-decimate
        out = correlate1d(out, BINOMIAL_KERNEL.astype(arr.dtype), axis=axis, mode=ndmode)
        out = out[(slice(None),) * axis + (slice(None, None, 2),)]
    return out


def upsample(image, shape, *, spatial_dims=2, mode="reflect"):
    """Zero-insert to ``shape`` and filter with ``2 * [1, 4, 6, 4, 1] / 16`` (EXPAND).

    Parameters
    ----------
    image : numpy.ndarray
        Output of :func:`downsample` of an image with spatial ``shape``.
    shape : tuple of int
        Target spatial shape; each axis must satisfy ``ceil(shape / 2) ==``
        the image's extent (the inverse of :func:`downsample`'s sizes).
    spatial_dims : {2, 3}
        Number of leading spatial axes.
    mode : {"reflect", "wrap"}
        Boundary, as in :func:`downsample`.

    Returns
    -------
    numpy.ndarray
        Spatial shape ``shape``, same channels.

    Raises
    ------
    ValueError
        If ``shape`` is not a size that downsamples to the image's size.

    Examples
    --------
    >>> upsample(np.ones((3, 4)), (5, 8)).shape
    (5, 8)
    >>> bool(np.allclose(upsample(np.ones((3, 4)), (5, 8)), 1.0))
    True
    """
    arr = _spatial(image, spatial_dims)
    ndmode = _check_mode(mode)
    shape = _as_shape(shape)
    small = arr.shape[:spatial_dims]
    expected = tuple((s + 1) // 2 for s in shape)
    if len(shape) != spatial_dims or expected != small:
        raise ValueError(
            f"shape {shape} does not downsample to the image's spatial shape {small}; "
            f"pass a shape whose axes are 2*n or 2*n - 1 for n in {small}"
        )
    out = np.zeros(shape + arr.shape[spatial_dims:], dtype=arr.dtype)
    out[(slice(None, None, 2),) * spatial_dims] = arr
    return _blur(out, spatial_dims, ndmode, 2.0 * BINOMIAL_KERNEL)


def _check_levels(levels, spatial_shape):
    if not isinstance(levels, numbers.Integral) or isinstance(levels, bool):
        raise TypeError(f"levels must be an integer >= 1, got {levels!r}")
    most = max_levels(spatial_shape)
    if levels < 1 or levels > most:
        raise ValueError(
            f"levels={levels} is not possible for spatial shape {tuple(spatial_shape)}: the coarsest "
            f"level would be smaller than 1 pixel; pass levels between 1 and {most}"
        )
    return int(levels)


def gaussian_pyramid(image, levels, *, spatial_dims=2, mode="reflect"):
    """Gaussian pyramid: ``[image, REDUCE(image), REDUCE^2(image), ...]``.

    Parameters
    ----------
    image : numpy.ndarray
        Float image, volume or video (see :func:`downsample` for layouts).
    levels : int
        Number of levels including the input, ``1 <= levels <=``
        :func:`max_levels` of the spatial shape.
    spatial_dims : {2, 3}
        Number of leading spatial axes.
    mode : {"reflect", "wrap"}
        Boundary of the blur.

    Returns
    -------
    list of numpy.ndarray
        Index 0 is the input (finest), the last entry the coarsest level.

    Raises
    ------
    ValueError
        If ``levels < 1`` or the coarsest level would be below one pixel.

    Examples
    --------
    >>> [g.shape for g in gaussian_pyramid(np.zeros((9, 6)), 3)]
    [(9, 6), (5, 3), (3, 2)]
    """
    arr = _spatial(image, spatial_dims)
    levels = _check_levels(levels, arr.shape[:spatial_dims])
    pyramid = [arr]
    for _ in range(levels - 1):
        pyramid.append(downsample(pyramid[-1], spatial_dims=spatial_dims, mode=mode))
    return pyramid


def laplacian_pyramid(image, levels, *, spatial_dims=2, mode="reflect"):
    """Laplacian pyramid: band-pass levels ``G_i - EXPAND(G_{i+1})`` and the coarsest ``G``.

    Parameters
    ----------
    image, levels, spatial_dims, mode
        As in :func:`gaussian_pyramid`.

    Returns
    -------
    list of numpy.ndarray
        ``levels`` arrays; the last one is the coarsest Gaussian level.

    Examples
    --------
    >>> img = np.random.default_rng(0).random((13, 10, 3))
    >>> pyr = laplacian_pyramid(img, 3)
    >>> float(np.abs(reconstruct_laplacian(pyr) - img).max()) < 1e-12
    True
    """
    gauss = gaussian_pyramid(image, levels, spatial_dims=spatial_dims, mode=mode)
    bands = [
        fine - upsample(coarse, fine.shape[:spatial_dims], spatial_dims=spatial_dims, mode=mode)
        for fine, coarse in zip(gauss[:-1], gauss[1:])
    ]
    return bands + [gauss[-1]]


def reconstruct_laplacian(pyramid, *, spatial_dims=2, mode="reflect"):
    """Invert :func:`laplacian_pyramid` (exact up to rounding).

    Parameters
    ----------
    pyramid : sequence of numpy.ndarray
        Band-pass levels, finest first, then the coarsest Gaussian level.
    spatial_dims, mode
        As used to build the pyramid.

    Returns
    -------
    numpy.ndarray
        The image: ``G_i = L_i + EXPAND(G_{i+1})`` from the coarsest level up.
    """
    if len(pyramid) < 1:
        raise ValueError("pyramid is empty; pass the list returned by laplacian_pyramid")
    image = _spatial(pyramid[-1], spatial_dims, "pyramid[-1]")
    for band in reversed(pyramid[:-1]):
        band = _spatial(band, spatial_dims, "pyramid level")
        image = band + upsample(image, band.shape[:spatial_dims], spatial_dims=spatial_dims, mode=mode)
    return image


# --------------------------------------------------------------------------- steerable pyramid
@dataclass
class SteerableCoefficients:
    """Coefficients of a :class:`SteerablePyramid`.

    Attributes
    ----------
    highpass : numpy.ndarray
        High-pass residual, the image's size (real).
    bands : list of list of numpy.ndarray
        ``bands[s][k]``: scale ``s`` (0 = finest) and orientation ``k`` (angle
        ``pi * k / K`` from the horizontal frequency axis: band ``k`` responds
        to gratings whose wave vector points at that angle). Real, or complex
        analytic bands for a complex pyramid. Scale ``s`` has spatial size
        ``ceil(n / 2^s)`` per axis.
    lowpass : numpy.ndarray
        Low-pass residual (real), size ``ceil(n / 2^S)`` per axis.
    """

    highpass: np.ndarray
    bands: list
    lowpass: np.ndarray

    def arrays(self):
        """All coefficient arrays, finest first: high-pass, ``bands[0][0..K-1]``, ..., low-pass."""
        return [self.highpass] + [b for scale in self.bands for b in scale] + [self.lowpass]


def max_scales(shape):
    """Largest number of scales of a :class:`SteerablePyramid` for a 2-D ``shape``.

    ``floor(log2(min(shape))) - 2`` (the rule of pyrtools' ``SteerablePyramidFreq``):
    the coarsest oriented band keeps at least 8 pixels and the low-pass
    residual at least 4 pixels along each axis.

    >>> max_scales((512, 512)), max_scales((64, 100)), max_scales((7, 7))
    (7, 4, 0)
    """
    smallest = min(_as_shape(shape))
    return max(0, int(math.floor(math.log2(smallest))) - 2) if smallest > 0 else 0


def _frequency_grid(shape, half):
    """Radius and angle of the FFT grid (natural order), frequencies normalised to [-1, 1).

    ``half=True`` gives the grid of ``rfft2`` (columns ``0 .. n//2`` only).
    """
    fy = sfft.fftfreq(shape[0]) * 2.0
    fx = (sfft.rfftfreq(shape[1]) if half else sfft.fftfreq(shape[1])) * 2.0
    y, x = np.meshgrid(fy, fx, indexing="ij")
    return np.hypot(x, y), np.arctan2(y, x)


def _crop_index(n):
    """Indices (natural FFT order) kept when an axis of n samples is cropped to ceil(n/2)."""
    m = (n + 1) // 2
    return np.r_[0 : m - m // 2, n - m // 2 : n]


def _crop_half_index(n):
    """Columns of an rfft2 spectrum kept when the (full) width n is cropped to m = ceil(n/2).

    The columns ``0 .. m//2`` of the parent; for even ``m`` column ``m/2`` stands for the
    child's Nyquist frequency, where the low-pass mask is zero.
    """
    m = (n + 1) // 2
    return np.arange(m // 2 + 1)


def _radial_masks(radius, scale):
    """High/low masks of the annulus r in [2^-(scale+1), 2^-scale] (sqrt raised cosine).

    ``hi = cos(pi/2 * t)``, ``lo = sin(pi/2 * t)`` with ``t = clip(-log2(r) - scale, 0, 1)``,
    so ``hi^2 + lo^2 = 1`` exactly and ``lo = 0`` for ``r >= 2^-scale`` (the crop is lossless).
    """
    with np.errstate(divide="ignore"):
        t = np.clip(-np.log2(radius) - scale, 0.0, 1.0)
    hi = np.where(t <= 0, 1.0, np.where(t >= 1, 0.0, np.cos(0.5 * np.pi * t)))
    lo = np.where(t <= 0, 0.0, np.where(t >= 1, 1.0, np.sin(0.5 * np.pi * t)))
    return hi, lo


def _angular_masks(cos_t, sin_t, orientations, is_complex):
    """Real angular masks A_k(t) = alpha_K cos(t - pi k/K)^(K-1), stacked (K, h, w).

    The band's spectrum is ``(-i)^(K-1) A_k`` (the phase factor is applied by the caller). For a
    complex pyramid the mask is doubled on the half-plane ``cos(t - pi k/K) > 0`` and zeroed on the
    other (weight 1 on the boundary), so the real part of the band is the real band.
    """
    order = orientations - 1
    alpha = math.sqrt(
        2.0 ** (2 * order) * math.factorial(order) ** 2 / (orientations * math.factorial(2 * order))
    )
    masks = np.empty((orientations,) + cos_t.shape)
    for k in range(orientations):
        phi = np.pi * k / orientations
        c = cos_t * math.cos(phi) + sin_t * math.sin(phi)  # cos(t - phi)
        a = masks[k]
        a[...] = alpha
        for _ in range(order):
            a *= c
        if is_complex:
            a *= np.where(np.abs(c) < 1e-12, 1.0, np.where(c > 0, 2.0, 0.0))
    return masks


class SteerablePyramid:
    """FFT-based steerable pyramid with exact (tight-frame) reconstruction.

    Parameters
    ----------
    shape : tuple of int
        ``(height, width)`` of the images to decompose (any sizes, odd too).
    scales : int
        Number of oriented scales ``S``, ``0 <= S <= max_scales(shape)``
        (Portilla & Simoncelli use 4).
    orientations : int
        Number of orientations ``K >= 1`` (Portilla & Simoncelli use 4).
    is_complex : bool
        Return analytic (complex) oriented bands (Portilla & Simoncelli 2000,
        sec. 2); their real part is the real band.

    Raises
    ------
    ValueError
        If ``scales`` exceeds :func:`max_scales` (the message names the sizes
        that work) or ``orientations < 1``.

    Notes
    -----
    Masks, in normalised frequency ``r`` in [0, 1] (1 = Nyquist) and angle ``t``::

        H0(r)^2 + L0(r)^2 = 1                       (high / low split)
        H(2^s r)^2 + L(2^s r)^2 = 1                  (annulus of scale s)
        sum_k A_k(t)^2 = 1,  A_k = alpha_K cos(t - pi k / K)^(K-1)

    so the analysis operator is an isometry and synthesis is its adjoint
    (a Parseval tight frame). All masks are built once in the constructor.

    References
    ----------
    .. [1] E. P. Simoncelli and W. T. Freeman, ICIP 1995. doi:10.1109/ICIP.1995.537667
    .. [2] J. Portilla and E. P. Simoncelli, IJCV 40(1), 2000. doi:10.1023/A:1026553619983

    Examples
    --------
    >>> img = np.random.default_rng(0).random((33, 40))
    >>> pyr = SteerablePyramid(img.shape, scales=3, orientations=4)
    >>> c = pyr.decompose(img)
    >>> [b.shape for b in (c.highpass, c.bands[0][0], c.bands[2][3], c.lowpass)]
    [(33, 40), (33, 40), (9, 10), (5, 5)]
    >>> float(np.abs(pyr.reconstruct(c) - img).max()) < 1e-12
    True
    """

    def __init__(self, shape, scales=4, orientations=4, *, is_complex=False):
        try:
            shape = tuple(int(s) for s in shape)
        except TypeError:
            raise TypeError(f"shape must be a pair (height, width), got {shape!r}") from None
        if len(shape) != 2 or min(shape) < 1:
            raise ValueError(f"shape must be two positive ints (height, width), got {shape}")
        for value, name, low in ((scales, "scales", 0), (orientations, "orientations", 1)):
            if not isinstance(value, numbers.Integral) or isinstance(value, bool):
                raise TypeError(f"{name} must be an integer >= {low}, got {value!r}")
        most = max_scales(shape)
        if scales < 0 or scales > most:
            need = 2 ** (max(scales, 0) + 2) if scales < 60 else float("inf")  # no huge integers in a message
            raise ValueError(
                f"scales={scales} is too many for an image of shape {shape}: {scales} scales need at least "
                f"{need} pixels along each axis; pass scales between 0 and {most}"
            )
        if orientations < 1:
            raise ValueError(f"orientations must be an integer >= 1, got {orientations}")
        # the masks of every band (about 4/3 of the image per orientation, as for the bands)
        check_memory(float(shape[0]) * shape[1] * 8 * (2 * orientations + 4), shape, "shape", "the pyramid's masks",
                     also={"orientations": orientations})
        self.shape = shape
        self.scales = int(scales)
        self.orientations = int(orientations)
        self.is_complex = bool(is_complex)
        self._build_masks()

    def _build_masks(self):
        self._sizes = level_shapes(self.shape, self.scales + 1)  # every scale: each axis n -> ceil(n / 2)
        self._phase = (-1j) ** (self.orientations - 1)  # the bands' spectra are (-i)^(K-1) H A_k L
        # Real bands live on the half (rfft2) grid; analytic bands need the full grid.
        self._half = self._masks_on_grid(half=True, analytic=False)
        self._full = self._masks_on_grid(half=False, analytic=True) if self.is_complex else None

    def _masks_on_grid(self, half, analytic):
        """H0, L0, and per scale: the (K, h, w) masks H(2^s r) A_k(t), L(2^s r) and the crop indices."""
        radius, angle = _frequency_grid(self.shape, half)
        hi0, lo0 = _radial_masks(radius, 0)  # H0, L0: transition r in [1/2, 1]
        bands, lows, crops = [], [], []
        for s in range(self.scales):
            hi, lo = _radial_masks(radius, s + 1)
            bands.append(_angular_masks(np.cos(angle), np.sin(angle), self.orientations, analytic) * hi)
            lows.append(lo)
            n_rows, n_cols = self._sizes[s]
            rows = _crop_index(n_rows)
            cols = _crop_half_index(n_cols) if half else _crop_index(n_cols)
            crops.append((rows, cols))
            radius, angle = radius[np.ix_(rows, cols)], angle[np.ix_(rows, cols)]
        return {"half": half, "hi0": hi0, "lo0": lo0, "bands": bands, "lows": lows, "crops": crops}

    def array_shapes(self):
        """Shapes of :meth:`SteerableCoefficients.arrays`, in the same order.

        >>> SteerablePyramid((20, 30), 2, 2).array_shapes()
        [(20, 30), (20, 30), (20, 30), (10, 15), (10, 15), (5, 8)]
        """
        bands = [tuple(self._sizes[s]) for s in range(self.scales) for _ in range(self.orientations)]
        return [self.shape] + bands + [tuple(self._sizes[self.scales])]

    def _gain(self, s):
        """sqrt(N_{s+1} / N_s): keeps the crop an isometry (Parseval) from scale s to s + 1."""
        (h0, w0), (h1, w1) = self._sizes[s], self._sizes[s + 1]
        return math.sqrt(h1 * w1 / (h0 * w0))

    def decompose(self, image):
        """Decompose a 2-D image of the pyramid's shape.

        Parameters
        ----------
        image : numpy.ndarray
            Real array of shape ``self.shape``.

        Returns
        -------
        SteerableCoefficients
            float32 arrays for a float32 image, float64 otherwise (complex64 /
            complex128 bands for a complex pyramid).
        """
        image = np.asarray(image)
        if image.shape != self.shape:
            raise ValueError(f"image has shape {image.shape} but the pyramid was built for {self.shape}; "
                             f"build SteerablePyramid(image.shape, ...) for it")
        if not np.isrealobj(image):
            raise TypeError("image must be real")
        _check_finite(image, "image")
        dtype = np.float32 if image.dtype == np.float32 else np.float64
        grid = self._full if self.is_complex else self._half
        if grid["half"]:
            spectrum = sfft.rfft2(image)

            def inverse(x, size):
                return sfft.irfft2(x, s=size, axes=(-2, -1)).astype(dtype, copy=False)
        else:
            spectrum = sfft.fft2(image)
            cdtype = np.complex64 if dtype == np.float32 else np.complex128

            def inverse(x, size):
                return sfft.ifft2(x, axes=(-2, -1)).astype(cdtype, copy=False)

        highpass = np.real(inverse(spectrum * grid["hi0"], self.shape)).astype(dtype, copy=False)
        low = spectrum * grid["lo0"]
        bands = []
        for s in range(self.scales):
            bands.append(list(inverse((low * self._phase)[None] * grid["bands"][s], self._sizes[s])))
            rows, cols = grid["crops"][s]
            low = (low * grid["lows"][s])[np.ix_(rows, cols)] * self._gain(s)
        lowpass = np.real(inverse(low, self._sizes[-1])).astype(dtype, copy=False)
        return SteerableCoefficients(highpass, bands, lowpass)

    def reconstruct(self, coeffs):
        """Image from coefficients (the adjoint of :meth:`decompose`; exact inverse).

        Complex bands contribute their real part (the real band).

        Parameters
        ----------
        coeffs : SteerableCoefficients

        Returns
        -------
        numpy.ndarray
            Real image of shape ``self.shape``.
        """
        if len(coeffs.bands) != self.scales or any(len(b) != self.orientations for b in coeffs.bands):
            raise ValueError(
                f"coeffs has {len(coeffs.bands)} scales x {[len(b) for b in coeffs.bands]} orientations but the "
                f"pyramid has {self.scales} x {self.orientations}"
            )
        grid = self._half  # synthesis only needs real bands: half spectra throughout
        low = sfft.rfft2(np.asarray(coeffs.lowpass, dtype=float))
        for s in reversed(range(self.scales)):
            rows, cols = grid["crops"][s]
            parent = np.zeros((self._sizes[s][0], self._sizes[s][1] // 2 + 1), dtype=complex)
            parent[np.ix_(rows, cols)] = low / self._gain(s)
            low = parent * grid["lows"][s]
            # A complex band's real part is the real band (the analytic mask M has
            # (M(w) + conj(M(-w))) / 2 = the real mask), so both kinds use the real masks.
            band_spectra = sfft.rfft2(np.real(np.stack(coeffs.bands[s])), axes=(-2, -1))
            low += np.conj(self._phase) * np.einsum("khw,khw->hw", band_spectra, grid["bands"][s])
        spectrum = low * grid["lo0"] + sfft.rfft2(np.asarray(coeffs.highpass, dtype=float)) * grid["hi0"]
        return sfft.irfft2(spectrum, s=self.shape)


# --------------------------------------------------------------------------- periodic + smooth
def periodic_smooth_decomposition(image):
    """Split ``image = periodic + smooth`` (Moisan 2011).

    Parameters
    ----------
    image : numpy.ndarray
        Float ``(H, W)`` or ``(H, W, C)`` image; channels are split independently.

    Returns
    -------
    periodic, smooth : numpy.ndarray
        Same shape and dtype as ``image``. ``smooth`` has zero mean and is the
        solution of ``Laplacian(s) = v`` (Moisan's eq. 9, solved in Fourier),
        where ``v`` is the boundary image of the jumps across the border:
        ``v = u(opposite edge) - u(edge)`` on the border pixels, 0 inside.
        ``periodic = image - smooth`` has the same periodic Laplacian as the
        image's interior (free-boundary) Laplacian, so its Fourier transform
        has no cross of border artefacts.

    References
    ----------
    .. [1] L. Moisan, "Periodic plus smooth image decomposition", J. Math.
       Imaging Vis. 39(2), 161-179, 2011. doi:10.1007/s10851-010-0227-1

    Examples
    --------
    >>> u = np.tile(np.linspace(0, 1, 8), (8, 1))  # a ramp: one big jump at the border
    >>> p, s = periodic_smooth_decomposition(u)
    >>> bool(np.allclose(p + s, u)), abs(float(s.mean())) < 1e-12
    (True, True)
    >>> bool(np.abs(p[:, 0] - p[:, -1]).max() < np.abs(u[:, 0] - u[:, -1]).max())
    True
    """
    arr = _spatial(image, 2)
    u = arr if arr.ndim == 3 else arr[..., None]
    h, w = u.shape[:2]
    v = np.zeros(u.shape, dtype=np.float64)  # boundary image (Moisan eq. 4)
    v[0] += u[-1] - u[0]
    v[-1] += u[0] - u[-1]
    v[:, 0] += u[:, -1] - u[:, 0]
    v[:, -1] += u[:, 0] - u[:, -1]
    q = np.cos(2 * np.pi * np.arange(h) / h)[:, None]
    r = np.cos(2 * np.pi * np.arange(w) / w)[None, :]
    denom = 2 * q + 2 * r - 4  # eigenvalues of the periodic discrete Laplacian
    denom[0, 0] = 1.0
    v_hat = sfft.fft2(v, axes=(0, 1))
    s_hat = v_hat / denom[..., None]
    s_hat[0, 0] = 0.0  # the smooth component has zero mean
    smooth = sfft.ifft2(s_hat, axes=(0, 1)).real.astype(arr.dtype, copy=False)
    if arr.ndim == 2:
        smooth = smooth[..., 0]
    return (arr - smooth).astype(arr.dtype, copy=False), smooth
