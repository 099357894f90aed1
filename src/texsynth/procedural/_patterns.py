"""Turbulence, fractional Brownian motion, marble and wood from Perlin noise.

The lecture slides "Turbulence Function", "Marble Texture Function" and
"Solid Textures" are the specification:

- ``turbulence(x) = sum_{i=0..k} |noise(2^i x)| / 2^i``, the sum truncated at the
  band limit: the last octave is the one whose lattice spacing is still at
  least one pixel (the slide: stop when 1/2^(k+1) is smaller than a pixel);
  its power spectrum falls off as 1/f;
- fBm, the signed sum ``sum_i gain^i noise(lacunarity^i x)`` (Brownian motion has
  a 1/f^2 spectrum), normalised by sum_i gain^i;
- ``marble(x, y, z) = marble_color(sin(x + turbulence(x, y, z)))``: alternating
  layers bent by turbulence, coloured by a transfer function;
- wood: rings sin(radius) around a trunk axis, bent by turbulence (Peachey's
  and Perlin's solid texture of 1985).

Each octave ``i >= 1`` is shifted by an irrational offset ``i * (phi - 1,
sqrt(2) - 1, sqrt(3) - 1)`` lattice cells. Without it, the octaves of a grid
aligned with the lattice sample their own lattice points (where Perlin noise
is exactly 0) wherever the coarser octaves do, which shows as a regular grid
of dark dots; the shift decorrelates the octaves' lattices and changes nothing
else (noise is translation invariant in distribution).

References
----------
.. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985, Computer Graphics
   19(3), 287-296. https://doi.org/10.1145/325165.325247
.. [2] D. R. Peachey, "Solid texturing of complex surfaces", SIGGRAPH 1985,
   Computer Graphics 19(3), 279-286. https://doi.org/10.1145/325165.325246
"""

from __future__ import annotations

import numbers

import numpy as np

from ..core._validate import check_positive_float, check_positive_int
from ._noise import (
    _check_dtype,
    _check_fade,
    _check_offset,
    _check_period,
    _check_points,
    _check_shape,
    _noise_grid,
    _noise_points,
    _permutation,
    _pixel_spacing,
    band_limit_octaves,
)

__all__ = ["turbulence", "fbm", "marble", "wood", "apply_colormap", "MARBLE_COLORS", "WOOD_COLORS"]

# Irrational per-octave shift in lattice cells (x, y, z): golden ratio, sqrt 2, sqrt 3.
_OCTAVE_SHIFT = np.array([(np.sqrt(5.0) - 1) / 2, np.sqrt(2.0) - 1, np.sqrt(3.0) - 1])

MARBLE_COLORS = [
    (0.00, (0.20, 0.21, 0.24)),
    (0.12, (0.45, 0.46, 0.50)),
    (0.35, (0.80, 0.80, 0.82)),
    (1.00, (0.97, 0.96, 0.94)),
]
"""Default marble transfer function: thin dark-grey veins in white stone."""

WOOD_COLORS = [
    (0.00, (0.42, 0.24, 0.11)),
    (0.35, (0.66, 0.44, 0.24)),
    (1.00, (0.86, 0.68, 0.45)),
]
"""Default wood transfer function: dark late-wood rings, light early wood."""


# --------------------------------------------------------------------------
# octave sums
# --------------------------------------------------------------------------


def _check_octaves(octaves, shape, frequency, lacunarity, points):
    if octaves is None:
        if points is not None:
            raise ValueError("octaves=None (up to the band limit) needs a grid; with points, pass octaves=k, "
                             "e.g. octaves=6")
        return band_limit_octaves(shape, frequency, lacunarity)
    return check_positive_int(octaves, "octaves")


def _octave_sum(shape, points, *, frequency, octaves, lacunarity, gain, absolute, period, offset,
                fade, rng, dtype):
    """sum_{i < octaves} gain^i * [abs] noise(lacunarity^i x + shift_i)."""
    fade_fn = _check_fade(fade)
    dt = _check_dtype(dtype)
    lacunarity = check_positive_float(lacunarity, "lacunarity")
    gain = check_positive_float(gain, "gain")
    if lacunarity <= 1:
        raise ValueError(f"lacunarity must be > 1 (each octave finer than the last), got {lacunarity}")
    if (shape is None) == (points is None):
        raise ValueError("give exactly one of shape (a grid) or points (lattice coordinates)")
    if points is not None:
        pts = _check_points(points)
        ndim = pts.shape[1]
    else:
        shape = _check_shape(shape)
        ndim = len(shape)
        frequency = check_positive_float(frequency, "frequency")
    octaves = _check_octaves(octaves, shape, frequency, lacunarity, points)
    per = _check_period(period, ndim)
    if per is not None and not float(lacunarity).is_integer():
        raise ValueError(f"period needs an integer lacunarity (octave periods period * lacunarity**i must be "
                         f"integers), got lacunarity={lacunarity}")
    origin = np.asarray(_check_offset(offset, ndim))
    perm = _permutation(rng)
    total = None
    buf = None
    for i in range(octaves):
        scale = lacunarity**i
        amp = gain**i
        per_i = None if per is None else tuple(int(round(p * scale)) for p in per)
        shift = origin * scale + i * _OCTAVE_SHIFT[:ndim]
        if points is not None:
            layer = _noise_points(pts * scale + shift, perm, per_i, fade_fn, dt)
        else:
            # octave 0 writes the total, later octaves one reused buffer
            if total is not None and buf is None:
                buf = np.empty(shape, dtype=dt)
            out = np.empty(shape, dtype=dt) if total is None else buf
            spacing = _pixel_spacing(shape, frequency) * scale
            layer = _noise_grid(shape, spacing, tuple(shift), perm, per_i, fade_fn, dt, out=out)
        if absolute:
            np.abs(layer, out=layer)
        if amp != 1.0:
            layer *= dt.type(amp)
        if total is None:
            total = layer
        else:
            total += layer
    return total, octaves


def turbulence(shape=None, *, frequency=8, octaves=None, points=None, period=None, offset=None,
               fade="quintic", rng=None, dtype=np.float64):
    """Perlin's turbulence: the sum of absolute noise octaves, band-limited.

    Parameters
    ----------
    shape : int or tuple of int, optional
        ``(H, W)`` image or ``(D, H, W)`` volume; or give ``points``.
    frequency : float, default 8
        Lattice cells of the first octave across the longest axis.
    octaves : int, optional
        Number of terms ``k + 1``. None sums up to the band limit: the last
        octave is the one whose lattice spacing is still at least one pixel
        (:func:`band_limit_octaves`); required with ``points``.
    points : array_like (N, 2) or (N, 3), optional
        Lattice coordinates ``(x, y[, z])`` of the first octave.
    period : int or tuple of int, optional
        Lattice period of the first octave (octave i wraps every
        ``period * 2**i`` of its cells): the result is periodic, and tiles
        when the grid spans whole periods (square image: ``period=frequency``).
    offset : float or tuple, optional
        Translation in first-octave lattice units, (x, y[, z]).
    fade : {"quintic", "cubic"}, default "quintic"
        Interpolation curve of the noise (see :func:`perlin`).
    rng : None, int or numpy.random.Generator
        Seed of the permutation table (shared by all octaves).
    dtype : numpy.float32 or numpy.float64
        Precision; float32 is faster.

    Returns
    -------
    numpy.ndarray
        ``shape`` or ``(N,)``, values >= 0 (mean about 0.4, below 2).

    Raises
    ------
    ValueError
        Non-positive shape or frequency, ``octaves < 1``, a period that is
        not a positive integer, or ``octaves=None`` with ``points``.

    Notes
    -----
    The slide "Turbulence Function" ([1]_, section 4):

    .. math:: \\mathrm{turbulence}(x) = \\sum_{i=0}^{k} \\frac{|\\mathrm{noise}(2^i x)|}{2^i}

    truncated when :math:`1/2^{k+1}` is smaller than a pixel. Octave ``i >= 1``
    is evaluated at ``2^i x + i (phi - 1, sqrt 2 - 1, sqrt 3 - 1)``: the
    irrational shift stops the octaves from sampling the lattice points
    (zeros) of the coarser ones in step.

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247

    Examples
    --------
    >>> from texsynth.procedural import turbulence
    >>> t = turbulence((64, 64), frequency=4, rng=0)      # 5 octaves: 16 px down to 1 px cells
    >>> t.shape, bool(t.min() >= 0)
    ((64, 64), True)
    >>> turbulence(points=[[0.5, 0.5, 0.5]], octaves=3, rng=0).shape
    (1,)
    """
    total, _ = _octave_sum(shape, points, frequency=frequency, octaves=octaves, lacunarity=2.0, gain=0.5,
                           absolute=True, period=period, offset=offset, fade=fade, rng=rng, dtype=dtype)
    return total


def fbm(shape=None, *, frequency=8, octaves=None, lacunarity=2.0, gain=0.5, points=None, period=None,
        offset=None, fade="quintic", rng=None, dtype=np.float64):
    """Fractional Brownian motion: the signed, normalised sum of noise octaves.

    Parameters
    ----------
    shape, frequency, points, period, offset, fade, rng, dtype
        As in :func:`turbulence`.
    octaves : int, optional
        Number of octaves; None sums up to the band limit (the last octave
        whose lattice spacing is at least one pixel).
    lacunarity : float, default 2.0
        Frequency ratio between octaves (> 1; an integer if ``period`` is
        given).
    gain : float, default 0.5
        Amplitude ratio between octaves ("persistence"); 0.5 gives a 1/f
        amplitude spectrum.

    Returns
    -------
    numpy.ndarray
        ``shape`` or ``(N,)``, values in about [-1, 1].

    Raises
    ------
    ValueError
        As :func:`turbulence`, and for ``lacunarity <= 1`` or ``gain <= 0``.

    Notes
    -----
    .. math:: \\mathrm{fbm}(x) = \\frac{\\sum_{i<n} g^i\\, \\mathrm{noise}(\\lambda^i x + s_i)}{\\sum_{i<n} g^i}

    with lacunarity :math:`\\lambda`, gain :math:`g` and the irrational
    octave shifts :math:`s_i` of :func:`turbulence`. Without the absolute
    value of turbulence, the sum keeps the sign of the noise: smooth hills
    and valleys rather than turbulence's creases. The normalisation is the
    one of the ``noise`` package's ``pnoise2(..., octaves=n)``.

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247

    Examples
    --------
    >>> from texsynth.procedural import fbm
    >>> f = fbm((32, 32), frequency=4, octaves=3, rng=0)
    >>> bool(abs(f).max() <= 1)
    True
    """
    total, n = _octave_sum(shape, points, frequency=frequency, octaves=octaves, lacunarity=lacunarity,
                           gain=gain, absolute=False, period=period, offset=offset, fade=fade, rng=rng,
                           dtype=dtype)
    gain = float(gain)
    total /= total.dtype.type(sum(gain**i for i in range(n)))
    return total


# --------------------------------------------------------------------------
# transfer functions (colour maps)
# --------------------------------------------------------------------------


def _parse_color(color):
    if isinstance(color, str):
        text = color.lstrip("#")
        if len(text) != 6:
            raise ValueError(f"colormap colour strings must be '#rrggbb', got {color!r}")
        try:
            return tuple(int(text[i : i + 2], 16) / 255.0 for i in (0, 2, 4))
        except ValueError:
            raise ValueError(f"colormap colour strings must be '#rrggbb', got {color!r}") from None
    rgb = tuple(float(c) for c in color)
    if len(rgb) not in (3, 4) or not all(0 <= c <= 1 for c in rgb):
        raise ValueError(f"colormap colours must be RGB(A) values in [0, 1] or '#rrggbb', got {color!r}")
    return rgb[:3]


def _colormap_function(colormap, default):
    """Turn a colour list, a (position, colour) list, a callable or a name into f(t) -> RGB."""
    if colormap is None:
        colormap = default
    if isinstance(colormap, str):
        try:
            import matplotlib
        except ImportError:  # pragma: no cover - matplotlib is in the examples extra
            raise ValueError(f"colormap={colormap!r} names a matplotlib colour map, but matplotlib is not "
                             "installed; pass a list of colours instead") from None
        try:
            colormap = matplotlib.colormaps[colormap]
        except KeyError:
            raise ValueError(f"colormap {colormap!r} is not a matplotlib colour map name") from None
    if callable(colormap):
        return colormap
    try:
        entries = list(colormap)
    except TypeError:
        raise TypeError(f"colormap must be None, a list of colours, a callable or a matplotlib name, "
                        f"got {type(colormap).__name__}") from None
    if len(entries) < 2:
        raise ValueError(f"colormap needs at least 2 colours, got {len(entries)}")
    paired = all(isinstance(e, (tuple, list)) and len(e) == 2 and isinstance(e[0], numbers.Real)
                 and not isinstance(e[1], numbers.Real) for e in entries)
    if paired:
        positions = np.array([float(p) for p, _ in entries])
        colors = np.array([_parse_color(c) for _, c in entries])
        if np.any(np.diff(positions) < 0) or positions[0] < 0 or positions[-1] > 1:
            raise ValueError(f"colormap positions must increase within [0, 1], got {positions.tolist()}")
    else:
        colors = np.array([_parse_color(c) for c in entries])
        positions = np.linspace(0.0, 1.0, len(colors))

    def piecewise_linear(t):
        return np.stack([np.interp(t, positions, colors[:, ch]) for ch in range(3)], axis=-1)

    return piecewise_linear


def apply_colormap(values, colormap=None, *, default=MARBLE_COLORS, dtype=None):
    """Map values in [0, 1] to RGB through a transfer function.

    Parameters
    ----------
    values : numpy.ndarray
        Scalar field in [0, 1] (clipped).
    colormap : None, sequence, callable or str
        A list of colours (RGB triples in [0, 1] or ``'#rrggbb'``) spaced
        evenly over [0, 1]; a list of ``(position, colour)`` pairs; a callable
        ``f(values) -> (..., 3 or 4)`` (e.g. a matplotlib ``Colormap``; alpha is
        dropped); or a matplotlib colour-map name (needs matplotlib).
        None uses ``default``.
    default
        The colour list used for ``colormap=None``.
    dtype : numpy dtype, optional
        Output dtype (default: that of ``values`` if floating).

    Returns
    -------
    numpy.ndarray
        ``values.shape + (3,)``, in [0, 1].

    Examples
    --------
    >>> apply_colormap(np.array([0.0, 1.0]), [(0, 0, 0), "#ffffff"]).tolist()
    [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]
    """
    fn = _colormap_function(colormap, default)
    values = np.clip(np.asarray(values), 0.0, 1.0)
    out_dtype = np.dtype(dtype) if dtype is not None else (
        values.dtype if np.issubdtype(values.dtype, np.floating) else np.dtype(np.float64))
    rgb = np.asarray(fn(values))
    if rgb.shape[:-1] != values.shape or rgb.shape[-1] not in (3, 4):
        raise ValueError(f"colormap callable must return shape {values.shape + (3,)} (or 4 channels), "
                         f"got {rgb.shape}")
    return np.clip(rgb[..., :3], 0.0, 1.0).astype(out_dtype, copy=False)


# --------------------------------------------------------------------------
# marble and wood
# --------------------------------------------------------------------------


def _unit_coords(shape, dtype):
    """Per-axis pixel positions divided by the longest axis, array order, broadcastable."""
    n = max(shape)
    grids = []
    for a, size in enumerate(shape):
        v = (np.arange(size, dtype=np.float64) / n).astype(dtype)
        grids.append(v.reshape([-1 if b == a else 1 for b in range(len(shape))]))
    return grids


def _sine_transfer(turb, strength, base_phase, colormap, default, return_info):
    """color(t), t = (1 + sin(base_phase + strength * turbulence)) / 2, computed in place in ``turb``."""
    phase = turb
    phase *= turb.dtype.type(strength)
    phase += base_phase.astype(turb.dtype, copy=False)
    field = np.sin(phase, out=phase)
    field += 1
    field *= 0.5
    image = apply_colormap(field, colormap, default=default)
    return (image, field) if return_info else image


def marble(shape, *, frequency=4, veins=3, turbulence_strength=6.0, octaves=None, colormap=None, period=None,
           fade="quintic", rng=None, dtype=np.float64, return_info=False):
    """Marble: layers ``sin(x)`` bent by turbulence, through a colour transfer function.

    Parameters
    ----------
    shape : int or tuple of int
        ``(H, W)`` image or ``(D, H, W)`` solid (volume).
    frequency : float, default 4
        Lattice cells of the turbulence's first octave across the longest axis.
    veins : float, default 3
        Periods of the layer function ``sin`` across the longest axis (along x,
        the columns).
    turbulence_strength : float, default 6.0
        Radians of phase per unit of turbulence: 0 gives straight layers,
        larger values fold them more.
    octaves : int, optional
        Turbulence octaves; None goes to the band limit.
    colormap : None, list of colours, list of (position, colour), callable or str
        The transfer function ``marble_color`` from ``t = (1 + sin) / 2`` in
        [0, 1] to RGB (see :func:`apply_colormap`). None: white marble with
        dark-grey veins (:data:`MARBLE_COLORS`).
    period : int, optional
        Turbulence period (see :func:`turbulence`); with an integer ``veins``
        and ``period=frequency`` a square image tiles seamlessly.
    fade, rng, dtype
        As in :func:`turbulence`.
    return_info : bool, default False
        Also return the scalar field ``t`` in [0, 1] before colouring.

    Returns
    -------
    image : numpy.ndarray
        ``shape + (3,)`` RGB in [0, 1].
    field : numpy.ndarray
        Only with ``return_info=True``: ``shape``, the values fed to the
        transfer function.

    Raises
    ------
    ValueError
        For bad shape, frequency, octaves, period or colormap.

    Notes
    -----
    The slide "Marble Texture Function" ([1]_, section 6.2):

    .. math:: f_{marble}(x, y, z) = \\mathrm{marble\\_color}(\\sin(x + \\mathrm{turbulence}(x, y, z)))

    here with ``x = 2 pi veins u`` (``u`` = column / longest axis) and the
    turbulence scaled by ``turbulence_strength``. A solid (3-D) marble can be
    cut by any surface: sample the volume at the surface points.

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247

    Examples
    --------
    >>> from texsynth.procedural import marble
    >>> img = marble((32, 32), rng=0)
    >>> img.shape, bool(img.min() >= 0 and img.max() <= 1)
    ((32, 32, 3), True)
    """
    veins = check_positive_float(veins, "veins", allow_zero=True)
    strength = check_positive_float(turbulence_strength, "turbulence_strength", allow_zero=True)
    turb = turbulence(shape, frequency=frequency, octaves=octaves, period=period, fade=fade, rng=rng, dtype=dtype)
    x = _unit_coords(turb.shape, turb.dtype)[-1]
    return _sine_transfer(turb, strength, 2 * np.pi * veins * x, colormap, MARBLE_COLORS, return_info)


def wood(shape, *, frequency=4, rings=10, turbulence_strength=2.0, octaves=None, center=None, colormap=None,
         fade="quintic", rng=None, dtype=np.float64, return_info=False):
    """Wood: concentric rings ``sin(radius)`` around a trunk axis, bent by turbulence.

    Parameters
    ----------
    shape : int or tuple of int
        ``(H, W)`` image (a cross-section of the trunk) or ``(D, H, W)``
        solid whose trunk runs along the depth axis.
    frequency : float, default 4
        Lattice cells of the turbulence's first octave across the longest axis.
    rings : float, default 10
        Rings per unit distance (the longest axis is one unit).
    turbulence_strength : float, default 2.0
        Radians of ring phase per unit of turbulence.
    octaves : int, optional
        Turbulence octaves; None goes to the band limit.
    center : (float, float), optional
        Trunk centre ``(row, col)`` as fractions of the height and width;
        default ``(0.5, 0.5)``.
    colormap : None or colour map
        Transfer function (see :func:`apply_colormap`); None gives
        :data:`WOOD_COLORS`.
    fade, rng, dtype, return_info
        As in :func:`marble`.

    Returns
    -------
    image : numpy.ndarray
        ``shape + (3,)`` RGB in [0, 1] (and the field with ``return_info``).

    Raises
    ------
    ValueError
        For bad shape, frequency, octaves, centre or colormap.

    Notes
    -----
    The solid wood texture of Peachey [1]_ and Perlin [2]_:

    .. math:: f_{wood}(x, y, z) = \\mathrm{wood\\_color}(\\sin(2\\pi\\, \\mathrm{rings}\\, r
              + s\\, \\mathrm{turbulence}(x, y, z))),\\quad r = \\sqrt{(x - x_0)^2 + (y - y_0)^2}

    References
    ----------
    .. [1] D. R. Peachey, "Solid texturing of complex surfaces", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325246
    .. [2] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247

    Examples
    --------
    >>> from texsynth.procedural import wood
    >>> wood((4, 16, 16), rng=0).shape
    (4, 16, 16, 3)
    """
    rings = check_positive_float(rings, "rings", allow_zero=True)
    strength = check_positive_float(turbulence_strength, "turbulence_strength", allow_zero=True)
    if center is None:
        center = (0.5, 0.5)
    if len(tuple(center)) != 2 or not all(isinstance(c, numbers.Real) for c in center):
        raise ValueError(f"center must be (row, col) fractions of the image, got {center!r}")
    turb = turbulence(shape, frequency=frequency, octaves=octaves, fade=fade, rng=rng, dtype=dtype)
    shp = turb.shape
    y, x = _unit_coords(shp, turb.dtype)[-2:]
    n = max(shp)
    y0 = turb.dtype.type(center[0] * (shp[-2] - 1) / n)
    x0 = turb.dtype.type(center[1] * (shp[-1] - 1) / n)
    radius = np.sqrt((y - y0) ** 2 + (x - x0) ** 2)
    return _sine_transfer(turb, strength, 2 * np.pi * rings * radius, colormap, WOOD_COLORS, return_info)
