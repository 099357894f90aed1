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

import math
import numbers

import numpy as np

from ..core._validate import check_positive_int, is_auto
from ._noise import (
    MAX_COORDINATE,
    band_limit,
    check_dtype,
    check_extent,
    check_fade,
    check_fits,
    check_float,
    check_lacunarity,
    check_offset,
    check_period,
    check_points,
    check_size,
    chunked,
    finite_real,
    grid_extent,
    no_chunks,
    noise_points,
    permutation,
    pixel_spacing,
    window_grid,
    window_rows,
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


def _check_octaves(octaves, size, frequency, lacunarity, points):
    if is_auto(octaves):
        if points is not None:
            raise ValueError("octaves='auto' (up to the band limit) needs a grid; with points, pass octaves=k, "
                             "e.g. octaves=6")
        return band_limit(size, frequency, lacunarity)
    return check_positive_int(octaves, "octaves")


def _octave_plan(octaves, lacunarity, gain, per, origin, extent, dtype, frequency_text):
    """Scale, amplitude, period and shift of every octave, checked before anything is computed.

    ``extent(scale, shift)`` is the largest lattice coordinate of an octave.
    """
    plan = []
    ndim = len(origin)
    amplitudes = 0.0
    for i in range(octaves):
        try:
            scale = lacunarity**i
        except OverflowError:
            scale = float("inf")
        try:
            amp = gain**i
        except OverflowError:
            amp = float("inf")
        amplitudes += amp
        if not amplitudes < float(np.finfo(dtype).max) / 4:
            raise ValueError(f"gain={gain:g} with octaves={octaves} gives octave amplitudes up to {amp:.3g}, beyond "
                             f"the range of {np.dtype(dtype).name}; use a gain <= 1 or fewer octaves")
        what = (f"octaves={octaves} with {frequency_text} and lacunarity={lacunarity:g} (octave {i + 1} is "
                f"{lacunarity:g}**{i} times finer)")
        if math.isinf(scale):
            raise ValueError(f"{what}: lacunarity**{i} overflows float64; pass a larger frequency or at most "
                             f"octaves={i}")
        per_i = None if per is None else tuple(int(round(p * scale)) for p in per)
        if per_i is not None and max(per_i) > MAX_COORDINATE:
            raise ValueError(f"period={per} with octaves={octaves} and lacunarity={lacunarity:g} gives octave "
                             f"{i + 1} a period of {max(per_i):.3g} cells, beyond 2**52; pass fewer octaves")
        shift = origin * scale + i * _OCTAVE_SHIFT[:ndim]
        check_extent(extent(scale, shift), what,
                     f"pass at most octaves={i}" if i else "pass a smaller frequency, offset or points")
        plan.append((scale, amp, per_i, shift))
    return plan


def _octave_sum(size, points, *, frequency, octaves, lacunarity, gain, absolute, period, offset,
                fade, rng, dtype, chunks=None, finish=None, copies=1, channels=None):
    """sum_{i < octaves} gain^i * [abs] noise(lacunarity^i x + shift_i).

    With ``chunks``, a lazy image (:func:`~texsynth.core.chunked.chunked_image`) whose block is
    ``finish(total, rows, cols)`` of the block's sum (``total`` itself without ``finish``);
    ``copies`` and ``channels`` describe what ``finish`` makes of a block.
    """
    fade_fn = check_fade(fade)
    dt = check_dtype(dtype)
    lacunarity = check_lacunarity(lacunarity)
    gain = check_float(gain, "gain")
    if (size is None) == (points is None):
        raise ValueError("give exactly one of size (a grid) or points (lattice coordinates)")
    if points is not None:
        no_chunks(chunks)
        pts = check_points(points)
        ndim = pts.shape[1]
    else:
        size = check_size(size)
        ndim = len(size)
        frequency = check_float(frequency, "frequency")
    octaves = _check_octaves(octaves, size, frequency, lacunarity, points)
    per = check_period(period, ndim)
    if per is not None and not float(lacunarity).is_integer():
        raise ValueError(f"period needs an integer lacunarity (octave periods period * lacunarity**i must be "
                         f"integers), got lacunarity={lacunarity}")
    origin = np.asarray(check_offset(offset, ndim))
    given = "" if offset is None else f" and offset={offset!r}"
    if points is not None:
        largest = float(np.abs(pts).max(initial=0.0))
        plan = _octave_plan(octaves, lacunarity, gain, per, origin,
                            lambda scale, shift: largest * scale + float(np.abs(shift).max()), dt,
                            "these points" + given)
    else:
        if chunks is None:
            check_fits(size, dt.itemsize, 1)
        spacing = pixel_spacing(size, frequency)
        plan = _octave_plan(octaves, lacunarity, gain, per, origin,
                            lambda scale, shift: grid_extent(size, spacing * scale, tuple(shift)), dt,
                            f"frequency={frequency:g}{given}")
    perm = permutation(rng)
    if points is not None:
        total = None
        for scale, amp, per_i, shift in plan:
            layer = noise_points(pts * scale + shift, perm, per_i, fade_fn, dt)
            total = _accumulate(total, layer, amp, absolute, dt)
        return total, octaves

    def grid_sum(window):
        # Grid: every octave is evaluated block by block (rows, or slices of a volume) into the
        # total, so that the only full-size array is the result (of the window, with chunks).
        grids = [window_grid(size, spacing * scale, tuple(shift), perm, per_i, fade_fn, dt, window)
                 for scale, amp, per_i, shift in plan]
        first, last = window_rows(size, window)
        total = np.empty((last - first,) + grids[0].size[1:], dtype=dt)
        buf = None
        for a, b in grids[0].blocks(first, last):
            block = total[a - first : b - first]
            _accumulate(None, grids[0].fill(block, a, b), plan[0][1], absolute, dt)  # octave 0 writes the total
            for grid, (_, amp, _, _) in zip(grids[1:], plan[1:]):
                if buf is None:
                    buf = np.empty_like(block)  # the first block is the largest
                _accumulate(block, grid.fill(buf[: b - a], a, b), amp, absolute, dt)
        return total

    if chunks is None:
        return grid_sum(None), octaves

    def render(rows, cols):
        total = grid_sum((rows, cols))
        return total if finish is None else finish(total, rows, cols)

    return chunked(size, chunks, dt, render, copies + 1, channels), octaves


def _accumulate(total, layer, amp, absolute, dt):
    """``total += amp * [abs] layer`` in place (``layer`` itself if ``total`` is None)."""
    if absolute:
        np.abs(layer, out=layer)
    if amp != 1.0:
        layer *= dt.type(amp)
    if total is None:
        return layer
    total += layer
    return total


def turbulence(size=None, *, frequency=8, octaves="auto", points=None, period=None, offset=None,
               fade="quintic", rng=None, dtype=np.float64, chunks=None):
    """Perlin's turbulence: the sum of absolute noise octaves, band-limited.

    Examples
    --------
    >>> import texsynth
    >>> t = texsynth.procedural.turbulence((64, 64), frequency=4, rng=0)  # 5 octaves: 16 px down to 1 px cells
    >>> t.shape, bool(t.min() >= 0)
    ((64, 64), True)
    >>> texsynth.procedural.turbulence(points=[[0.5, 0.5, 0.5]], octaves=3, rng=0).shape
    (1,)

    Sums ``|noise(2^i x)| / 2^i`` over octaves down to the pixel size: a
    non-negative field of creases, which :func:`marble` and :func:`wood`
    bend their layers with (Perlin 1985 [1]_).

    Parameters
    ----------
    size : int or tuple of int, optional
        ``(H, W)`` image or ``(D, H, W)`` volume (an int means a square
        image); or give ``points``.
    frequency : float, default 8
        Lattice cells of the first octave across the longest axis.
    octaves : int or "auto"
        Number of terms ``k + 1``. ``"auto"`` (default) sums up to the band limit: the last
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
    chunks : None, int or (int, int)
        2-D grids only: a lazy ``dask.array`` rendered block by block, for
        outputs larger than memory (see :func:`perlin`).

    Returns
    -------
    numpy.ndarray or dask.array.Array
        ``size`` or ``(N,)``, values >= 0 (mean about 0.4, below 2).

    Raises
    ------
    ValueError
        Non-positive size or frequency, ``octaves < 1``, a period that is
        not a positive integer, ``octaves="auto"`` with ``points``, octaves so
        many (or a frequency so low that the band limit needs so many) that
        the finest one's lattice coordinates pass 2**52, or an output larger
        than this machine's memory.
    TypeError
        For arguments of the wrong type (a bool or string as a number, a
        float ``octaves``, a dtype other than float32/float64).

    Notes
    -----

    The slide "Turbulence Function" ([1]_, section 4):

    .. math:: \\mathrm{turbulence}(x) = \\sum_{i=0}^{k} \\frac{|\\mathrm{noise}(2^i x)|}{2^i}

    truncated when :math:`1/2^{k+1}` is smaller than a pixel. Octave ``i >= 1``
    is evaluated at ``2^i x + i (phi - 1, sqrt 2 - 1, sqrt 3 - 1)``: the
    irrational shift stops the octaves from sampling the lattice points
    (zeros) of the coarser ones in step.

    Every octave is evaluated block by block into the result, hashing only
    the lattice cells the samples fall in, so the peak memory is about the
    size of the result (measured 1.06x for 8192 x 8192, 11 octaves) for any
    frequency and number of octaves.

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247
    """
    total, _ = _octave_sum(size, points, frequency=frequency, octaves=octaves, lacunarity=2.0, gain=0.5,
                           absolute=True, period=period, offset=offset, fade=fade, rng=rng, dtype=dtype,
                           chunks=chunks)
    return total


def fbm(size=None, *, frequency=8, octaves="auto", lacunarity=2.0, gain=0.5, points=None, period=None,
        offset=None, fade="quintic", rng=None, dtype=np.float64, chunks=None):
    """Fractional Brownian motion: the signed, normalised sum of noise octaves.

    Examples
    --------
    >>> import texsynth
    >>> f = texsynth.procedural.fbm((32, 32), frequency=4, octaves=3, rng=0)
    >>> bool(abs(f).max() <= 1)
    True

    Sums octaves of Perlin noise, each at ``lacunarity`` times the
    frequency and ``gain`` times the amplitude of the one before, divided
    by the sum of the amplitudes [1]_.

    Parameters
    ----------
    size, frequency, points, period, offset, fade, rng, dtype, chunks
        As in :func:`turbulence`.
    octaves : int or "auto"
        Number of octaves; ``"auto"`` (default) sums up to the band limit (the last octave
        whose lattice spacing is at least one pixel).
    lacunarity : float, default 2.0
        Frequency ratio between octaves (> 1; an integer if ``period`` is
        given).
    gain : float, default 0.5
        Amplitude ratio between octaves ("persistence"); 0.5 gives a 1/f
        amplitude spectrum.

    Returns
    -------
    numpy.ndarray or dask.array.Array
        ``size`` or ``(N,)``, values in about [-1, 1] (lazy with ``chunks``).

    Raises
    ------
    ValueError
        As :func:`turbulence`, and for ``lacunarity <= 1``, ``gain <= 0`` or a
        gain whose octave amplitudes overflow the dtype.
    TypeError
        As :func:`turbulence`.

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
    """

    def normalise(total, rows=None, cols=None):  # by sum_i gain^i (n: the octaves, known by then)
        total /= total.dtype.type(sum(float(gain) ** i for i in range(n)))
        return total

    total, n = _octave_sum(size, points, frequency=frequency, octaves=octaves, lacunarity=lacunarity,
                           gain=gain, absolute=False, period=period, offset=offset, fade=fade, rng=rng,
                           dtype=dtype, chunks=chunks, finish=normalise)
    return total if chunks is not None else normalise(total)


# --------------------------------------------------------------------------
# transfer functions (colour maps)
# --------------------------------------------------------------------------


def _parse_color(color, name):
    """One colour: ``'#rrggbb'`` or 3 (RGB) or 4 (RGBA, alpha dropped) numbers in [0, 1]."""
    hint = f"{name} colours must be RGB(A) values in [0, 1] or '#rrggbb'"
    if isinstance(color, str):
        text = color.lstrip("#")
        if len(text) != 6:
            raise ValueError(f"{name} colour strings must be '#rrggbb', got {color!r}")
        try:
            return tuple(int(text[i : i + 2], 16) / 255.0 for i in (0, 2, 4))
        except ValueError:
            raise ValueError(f"{name} colour strings must be '#rrggbb', got {color!r}") from None
    if not isinstance(color, (tuple, list, np.ndarray)):
        raise TypeError(f"{hint}, got {color!r}")
    items = [c.item() if isinstance(c, np.ndarray) and c.ndim == 0 else c for c in color]
    if len(items) not in (3, 4) or not all(finite_real(c) and 0 <= float(c) <= 1 for c in items):
        raise ValueError(f"{hint}, got {color!r}")
    return tuple(float(c) for c in items)[:3]


def colormap_function(colormap, name="colormap"):
    """Turn a colour list, a (position, colour) list, a callable or a name into f(t) -> RGB."""
    if isinstance(colormap, str):
        try:
            import matplotlib
        except ImportError:  # pragma: no cover - matplotlib is in the examples extra
            raise ValueError(f"{name}={colormap!r} names a matplotlib colour map, but matplotlib is not "
                             "installed; pass a list of colours instead") from None
        try:
            colormap = matplotlib.colormaps[colormap]
        except KeyError:
            raise ValueError(f"{name} {colormap!r} is not a matplotlib colour map name") from None
    if callable(colormap):
        return colormap
    if not isinstance(colormap, (tuple, list, np.ndarray)):
        raise TypeError(f"{name} must be None, a list of colours, a list of (position, colour) pairs, a callable "
                        f"or a matplotlib name, got {type(colormap).__name__}")
    entries = list(colormap)
    if len(entries) < 2:
        raise ValueError(f"{name} needs at least 2 colours, got {len(entries)}")
    paired = all(isinstance(e, (tuple, list)) and len(e) == 2 and isinstance(e[0], numbers.Real)
                 and not isinstance(e[1], numbers.Real) for e in entries)
    if paired:
        if not all(finite_real(p) for p, _ in entries):
            raise ValueError(f"{name} positions must be finite numbers in [0, 1], got {[p for p, _ in entries]!r}")
        positions = np.array([float(p) for p, _ in entries])
        colors = np.array([_parse_color(c, name) for _, c in entries])
        if np.any(np.diff(positions) < 0) or positions[0] < 0 or positions[-1] > 1:
            raise ValueError(f"{name} positions must increase within [0, 1], got {positions.tolist()}")
    else:
        colors = np.array([_parse_color(c, name) for c in entries])
        positions = np.linspace(0.0, 1.0, len(colors))

    # per stop: its colour and the slope of the segment it starts (0 for the last: constant beyond it)
    widths = np.diff(positions)
    slopes = np.zeros_like(colors)
    np.divide(np.diff(colors, axis=0), widths[:, None], out=slopes[:-1], where=widths[:, None] > 0)

    def piecewise_linear(t):
        """``colour(p_k) + (t - p_k) slope_k`` with ``p_k`` the last stop at or below ``t`` (the first
        colour below the first stop), in ``t``'s floating dtype."""
        dt = t.dtype if np.issubdtype(t.dtype, np.floating) else np.dtype(np.float64)
        t = t.astype(dt, copy=False)
        stop = np.maximum(np.searchsorted(positions.astype(dt), t, side="right") - 1, 0)
        offset = np.maximum(t - positions.astype(dt)[stop], 0)
        out = np.empty(t.shape + (3,), dt)
        for ch in range(3):
            np.multiply(offset, slopes[:, ch].astype(dt)[stop], out=out[..., ch])
            out[..., ch] += colors[:, ch].astype(dt)[stop]
        return out

    return piecewise_linear


def _check_values(values):
    """The scalar field of :func:`apply_colormap`: real numbers, no NaN."""
    try:
        arr = np.asarray(values)
    except (TypeError, ValueError) as exc:  # ragged lists
        raise ValueError(f"values must be an array of numbers in [0, 1]: {exc}") from None
    if not (np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer) or arr.dtype == bool):
        raise TypeError(f"values must be real numbers in [0, 1], got dtype {arr.dtype}")
    if np.issubdtype(arr.dtype, np.floating) and np.isnan(arr).any():
        raise ValueError(f"values contains {int(np.isnan(arr).sum())} NaN; replace them (e.g. np.nan_to_num) "
                         "before colouring")
    return arr


def apply_colormap(values, colormap=None, *, default=MARBLE_COLORS, dtype=None):
    """Map values in [0, 1] to RGB through a transfer function.

    Parameters
    ----------
    values : numpy.ndarray
        Scalar field in [0, 1] (clipped, so infinities become 0 or 1; NaN is
        refused).
    colormap : None, sequence, callable or str
        A list of colours (RGB triples in [0, 1] or ``'#rrggbb'``) spaced
        evenly over [0, 1]; a list of ``(position, colour)`` pairs; a callable
        ``f(values) -> (..., 3 or 4)`` (e.g. a matplotlib ``Colormap``; alpha is
        dropped); or a matplotlib colour-map name (needs matplotlib).
        None uses ``default``.
    default
        The colour list used for ``colormap=None``.
    dtype : numpy floating dtype, optional
        Output dtype (default: that of ``values`` if floating, else float64).

    Returns
    -------
    numpy.ndarray
        ``values.shape + (3,)``, in [0, 1].

    Raises
    ------
    ValueError
        For NaN values, malformed colours or positions, fewer than two
        colours, an unknown matplotlib name, or a callable that returns the
        wrong shape or non-finite colours.
    TypeError
        For values that are not real numbers, a colormap of the wrong type,
        or a dtype that is not floating point.

    A lazy ``dask.array`` of values (e.g. :func:`turbulence` with
    ``chunks=``) gives a lazy RGB array, coloured block by block.

    Examples
    --------
    >>> apply_colormap(np.array([0.0, 1.0]), [(0, 0, 0), "#ffffff"]).tolist()
    [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]
    """
    if hasattr(values, "map_blocks") and getattr(values, "ndim", 0) >= 1:  # lazy (dask): block by block
        colormap_function(default, "default") if colormap is None else colormap_function(colormap)
        out = values.dtype if np.issubdtype(values.dtype, np.floating) and dtype is None else np.dtype(dtype or float)
        return values.map_blocks(apply_colormap, colormap, default=default, dtype=out, new_axis=values.ndim,
                                 chunks=values.chunks + ((3,),))
    arr = _check_values(values)
    fn = colormap_function(default, "default") if colormap is None else colormap_function(colormap)
    values = np.clip(arr, 0.0, 1.0)
    if dtype is None:
        out_dtype = values.dtype if np.issubdtype(values.dtype, np.floating) else np.dtype(np.float64)
    else:
        try:
            out_dtype = np.dtype(dtype)
        except (TypeError, ValueError):
            out_dtype = None
        if out_dtype is None or not np.issubdtype(out_dtype, np.floating):
            raise TypeError(f"dtype must be a floating-point dtype (e.g. numpy.float32) or None, got {dtype!r}")
    result = fn(values)  # a user's callable may raise its own error
    name = "default" if colormap is None else "colormap"
    try:
        rgb = np.asarray(result)
    except (TypeError, ValueError) as exc:  # ragged output
        raise ValueError(f"{name} callable must return an array of shape {values.shape + (3,)}: {exc}") from None
    if rgb.ndim == 0 or rgb.shape[:-1] != values.shape or rgb.shape[-1] not in (3, 4):
        shape = rgb.shape
        raise ValueError(f"{name} callable must return shape {values.shape + (3,)} (or 4 channels), got {shape}")
    if not (np.issubdtype(rgb.dtype, np.floating) or np.issubdtype(rgb.dtype, np.integer)):
        raise ValueError(f"{name} callable must return real RGB values, got dtype {rgb.dtype}")
    if not np.all(np.isfinite(rgb[..., :3])):
        raise ValueError(f"{name} callable returned NaN or infinite colours")
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


def _check_phase(dtype, largest, names):
    """The phase of the sine transfer must stay finite in ``dtype`` (else sin gives NaN)."""
    dt = check_dtype(dtype)
    if not largest < float(np.finfo(dt).max) / 16:
        given = ", ".join(f"{k}={v!r}" for k, v in names.items())
        raise ValueError(f"{given} give phases up to {largest:.3g} radians, beyond the range of {dt.name}; "
                         "use smaller values (a phase step of more than pi per pixel is aliased anyway)")


def _marble_wood_checks(size, colormap, dtype, return_info, chunks):
    """Checks shared by marble and wood, before the turbulence is computed."""
    size = check_size(size)
    if colormap is not None:
        colormap_function(colormap)  # a bad colour map fails before the turbulence is computed
    if chunks is None:
        check_fits(size, check_dtype(dtype).itemsize, 8 if return_info else 7)  # field, RGB and temporaries
    elif return_info:
        raise ValueError("return_info=True returns the whole field in memory; with chunks= pass return_info=False")
    return size


def _coloured_turbulence(colour, size, chunks, *, frequency, octaves, period, fade, rng, dtype):
    """``colour(turbulence, rows, cols)`` over the grid, or block by block (lazily) with ``chunks``."""
    turb, _ = _octave_sum(size, None, frequency=frequency, octaves=octaves, lacunarity=2.0, gain=0.5, absolute=True,
                          period=period, offset=None, fade=fade, rng=rng, dtype=dtype, chunks=chunks,
                          finish=colour, copies=7, channels=3)
    return turb if chunks is not None else colour(turb, slice(None), slice(None))


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


def marble(size, *, frequency=4, veins=3, turbulence_strength=6.0, octaves="auto", colormap=None, period=None,
           fade="quintic", rng=None, dtype=np.float64, return_info=False, chunks=None):
    """Marble: layers ``sin(x)`` bent by turbulence, through a colour transfer function.

    Examples
    --------
    >>> import texsynth
    >>> img = texsynth.procedural.marble((32, 32), rng=0)
    >>> img.shape, bool(img.min() >= 0 and img.max() <= 1)
    ((32, 32, 3), True)

    The phase of ``sin`` along the columns is shifted by
    :func:`turbulence`, so straight layers fold like the veins of marble;
    the result goes through a colour transfer function (Perlin 1985 [1]_).

    Parameters
    ----------
    size : int or tuple of int
        ``(H, W)`` image or ``(D, H, W)`` solid (volume); an int means a
        square image.
    frequency : float, default 4
        Lattice cells of the turbulence's first octave across the longest axis.
    veins : float, default 3
        Periods of the layer function ``sin`` across the longest axis (along x,
        the columns).
    turbulence_strength : float, default 6.0
        Radians of phase per unit of turbulence: 0 gives straight layers,
        larger values fold them more.
    octaves : int or "auto"
        Turbulence octaves; ``"auto"`` (default) goes to the band limit.
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
    chunks : None, int or (int, int)
        2-D images only: a lazy ``dask.array`` ``(H, W, 3)`` rendered block
        by block, for outputs larger than memory (see :func:`perlin`); not
        with ``return_info``.

    Returns
    -------
    image : numpy.ndarray
        ``size + (3,)`` RGB in [0, 1].
    field : numpy.ndarray
        Only with ``return_info=True``: ``size``, the values fed to the
        transfer function.

    Raises
    ------
    ValueError
        For a bad size, frequency, octaves, period or colormap, negative
        ``veins`` or ``turbulence_strength``, or values so large that the
        phase overflows the dtype.
    TypeError
        For arguments of the wrong type (see :func:`turbulence`).

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
    """
    veins = check_float(veins, "veins", allow_zero=True)
    strength = check_float(turbulence_strength, "turbulence_strength", allow_zero=True)
    _check_phase(dtype, 2 * np.pi * veins + 2 * strength, {"veins": veins, "turbulence_strength": strength})
    size = _marble_wood_checks(size, colormap, dtype, return_info, chunks)

    def colour(turb, rows, cols):
        x = _unit_coords(size, turb.dtype)[-1][..., cols]
        return _sine_transfer(turb, strength, 2 * np.pi * veins * x, colormap, MARBLE_COLORS, return_info)

    return _coloured_turbulence(colour, size, chunks, frequency=frequency, octaves=octaves, period=period, fade=fade,
                                rng=rng, dtype=dtype)


def wood(size, *, frequency=4, rings=10, turbulence_strength=2.0, octaves="auto", center=None, colormap=None,
         fade="quintic", rng=None, dtype=np.float64, return_info=False, chunks=None):
    """Wood: concentric rings ``sin(radius)`` around a trunk axis, bent by turbulence.

    Examples
    --------
    >>> import texsynth
    >>> texsynth.procedural.wood((4, 16, 16), rng=0).shape  # a solid: 4 slices across the trunk
    (4, 16, 16, 3)

    Rings of the distance from the trunk axis, their phase shifted by
    :func:`turbulence`, through a colour transfer function: the solid wood
    of Peachey [1]_ and Perlin [2]_.

    Parameters
    ----------
    size : int or tuple of int
        ``(H, W)`` image (a cross-section of the trunk) or ``(D, H, W)``
        solid whose trunk runs along the depth axis; an int means a square
        image.
    frequency : float, default 4
        Lattice cells of the turbulence's first octave across the longest axis.
    rings : float, default 10
        Rings per unit distance (the longest axis is one unit).
    turbulence_strength : float, default 2.0
        Radians of ring phase per unit of turbulence.
    octaves : int or "auto"
        Turbulence octaves; ``"auto"`` (default) goes to the band limit.
    center : (float, float), optional
        Trunk centre ``(row, col)`` as fractions of the height and width
        (finite; outside [0, 1] puts the trunk outside the image); default
        ``(0.5, 0.5)``.
    colormap : None or colour map
        Transfer function (see :func:`apply_colormap`); None gives
        :data:`WOOD_COLORS`.
    fade, rng, dtype, return_info, chunks
        As in :func:`marble`.

    Returns
    -------
    image : numpy.ndarray
        ``size + (3,)`` RGB in [0, 1] (and the field with ``return_info``).

    Raises
    ------
    ValueError
        For a bad size, frequency, octaves, centre or colormap, negative
        ``rings`` or ``turbulence_strength``, or values so large that the
        phase overflows the dtype.
    TypeError
        For arguments of the wrong type (see :func:`turbulence`).

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
    """
    rings = check_float(rings, "rings", allow_zero=True)
    strength = check_float(turbulence_strength, "turbulence_strength", allow_zero=True)
    if center is None:
        center = (0.5, 0.5)
    items = tuple(center) if isinstance(center, (tuple, list, np.ndarray)) else ()
    if len(items) != 2 or not all(finite_real(c) for c in items):
        raise ValueError(f"center must be (row, col), two finite fractions of the image, got {center!r}")
    reach = 2 + max(abs(float(c)) for c in items)  # largest distance from the trunk, in image widths
    _check_phase(dtype, 2 * np.pi * rings * reach + 2 * strength,
                 {"rings": rings, "center": center, "turbulence_strength": strength})
    if not reach < np.sqrt(float(np.finfo(check_dtype(dtype)).max)) / 16:
        raise ValueError(f"center={center!r} is too far from the image for {np.dtype(dtype).name} distances")
    size = _marble_wood_checks(size, colormap, dtype, return_info, chunks)

    def colour(turb, rows, cols):
        y, x = _unit_coords(size, turb.dtype)[-2:]
        n = max(size)
        y0 = turb.dtype.type(center[0] * (size[-2] - 1) / n)
        x0 = turb.dtype.type(center[1] * (size[-1] - 1) / n)
        radius = np.sqrt((y[rows] - y0) ** 2 + (x[..., cols] - x0) ** 2)
        return _sine_transfer(turb, strength, 2 * np.pi * rings * radius, colormap, WOOD_COLORS, return_info)

    return _coloured_turbulence(colour, size, chunks, frequency=frequency, octaves=octaves, period=None, fade=fade,
                                rng=rng, dtype=dtype)
