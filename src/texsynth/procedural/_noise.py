"""Perlin gradient noise in 2-D and 3-D, on regular grids or at arbitrary points.

This module implements the noise function of the lecture slide "Perlin's Noise"
(Perlin 1985) with the improvements of Perlin 2002:

- an integer lattice ``(i, j, k)``; at each lattice point a pseudo-random
  gradient vector, chosen by hashing the lattice coordinates through a
  permutation table ``P`` of 0..255 (``hash = P[P[P[i] + j] + k]``, Perlin
  2002), here a permutation drawn from ``rng`` so every seed gives another,
  reproducible noise;
- the noise value at ``x`` is the interpolation of the 2^d "wavelets"
  ``g_c . (x - c)`` of the surrounding lattice corners ``c`` with the fade
  curve ``6t^5 - 15t^4 + 10t^3`` (quintic, Perlin 2002) or ``3t^2 - 2t^3``
  (cubic Hermite, Perlin 1985);
- the lattice is replicated to fill all space (the hash repeats every 256
  cells) or, with ``period``, wraps every ``period`` cells, so a grid that
  spans a whole number of periods tiles seamlessly.

In 3-D the gradients are the 16-entry table of Perlin 2002 (the 12 cube-edge
directions, four of them twice). In 2-D they are eight directions 45 degrees
apart: the 3-D table at ``z = 0`` (used by the ``noise`` package) has many
gradients with a zero x or y component, which shows as horizontal and
vertical bands. The value is exactly 0 at every lattice point and lies in
about [-1, 1].

Grid evaluation is separable: on a regular grid the lattice index, the
fractional position and the fade weight of a sample depend on its column
alone (x) or its row alone (y), so the noise of a block of rows that share a
lattice row is a small matrix product
``noise[rows, :] = Y[rows, :] @ M[cell_row]`` with ``Y`` (rows x 4d) holding
the y factors and ``M`` (4d x width) the x factors multiplied by the corner
gradients. That is several times faster than evaluating every pixel on its
own, and gives the same numbers as the point evaluation (up to rounding).

Memory is proportional to the output, whatever the frequency: a grid is
filled in blocks of rows (slices of a volume), and only the lattice rows and
cells that a block's samples fall in are hashed, as Perlin's own code hashes
the corners of each sample (the whole lattice of a 64 x 64 image at frequency
20000 would have 4e8 points).

Every product is computed term by term (:func:`_contract`), so each value is
rounded the same way whatever the block, the window, the SIMD level of the
CPU or the BLAS: a block of a chunked image equals the same pixels of the
whole image bit for bit on any machine.

References
----------
.. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985, Computer Graphics
   19(3), 287-296. https://doi.org/10.1145/325165.325247
.. [2] K. Perlin, "Improving noise", SIGGRAPH 2002, ACM Transactions on
   Graphics 21(3), 681-682. https://doi.org/10.1145/566654.566636
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..core._validate import as_rng, as_size, check_memory, check_positive_float

__all__ = ["perlin", "FADES", "band_limit_octaves"]

# Perlin 2002, "Improving noise": 12 gradient directions to the cube's edge
# midpoints, padded to 16 entries so that ``hash & 15`` selects one.
_GRADIENTS = np.array(
    [
        (1, 1, 0), (-1, 1, 0), (1, -1, 0), (-1, -1, 0),
        (1, 0, 1), (-1, 0, 1), (1, 0, -1), (-1, 0, -1),
        (0, 1, 1), (0, -1, 1), (0, 1, -1), (0, -1, -1),
        (1, 1, 0), (0, -1, 1), (-1, 1, 0), (0, -1, -1),
    ],
    dtype=np.float64,
)

# 2-D: eight directions 45 degrees apart, length sqrt(2) (so the value range
# is about [-1, 1] as in 3-D), each twice so that ``hash & 15`` selects one.
# The 3-D table at z = 0 (what the `noise` package does) has 6 of 16 gradients
# with a zero x component: a lattice row that draws several of them in a row
# gives a visible horizontal band of near-zero noise (seen with rng=3).
_GRADIENTS_2D = np.sqrt(2.0) * np.array(
    [(np.cos(a), np.sin(a)) for a in np.arange(16) * (np.pi / 4)]
).round(15)


def _gradient_table(ndim):
    return _GRADIENTS_2D if ndim == 2 else _GRADIENTS


def _fade_quintic(t):
    """Perlin 2002: 6t^5 - 15t^4 + 10t^3 (zero first and second derivative at 0, 1)."""
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def _fade_cubic(t):
    """Perlin 1985: the cubic Hermite 3t^2 - 2t^3 (zero first derivative at 0, 1)."""
    return t * t * (3.0 - 2.0 * t)


FADES = {"quintic": _fade_quintic, "cubic": _fade_cubic}
"""Interpolation (fade) curves by name."""


# --------------------------------------------------------------------------
# validation helpers shared by the procedural package
# --------------------------------------------------------------------------

# Largest lattice coordinate: at 2**52 a float64 has no fractional bits left, so
# every sample would sit on a lattice point (where the noise is 0).
MAX_COORDINATE = 2.0**52


def _is_real(value):
    """A real number that is not a bool (``True`` is not a frequency)."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def _is_sequence(value):
    """A tuple, list or array of at least one dimension (one value per axis)."""
    return isinstance(value, (tuple, list)) or (isinstance(value, np.ndarray) and value.ndim > 0)


def finite_real(value):
    """A real, non-bool number that converts to a finite float."""
    if not _is_real(value):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:  # an int beyond the float range
        return False


def check_float(value, name, *, allow_zero=False):
    """``check_positive_float``, also for ints too large for a float (ValueError naming ``name``)."""
    try:
        return check_positive_float(value, name, allow_zero=allow_zero)
    except OverflowError:
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be a finite number {bound}, got {value!r} (too large for a float)") from None


def check_fade(fade):
    if isinstance(fade, str):
        if fade not in FADES:
            raise ValueError(f"fade must be one of {sorted(FADES)} or a callable, got {fade!r}")
        return FADES[fade]
    if not callable(fade):
        raise TypeError(f"fade must be one of {sorted(FADES)} or a callable t -> weight, got {type(fade).__name__}")
    probe = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    try:
        values = np.asarray(fade(probe.copy()))
    except Exception as exc:  # the user's callable: say which parameter failed
        raise ValueError(f"fade callable failed on t = {probe.tolist()}: {exc!r}") from exc
    if values.shape != probe.shape or not (np.issubdtype(values.dtype, np.floating)
                                           or np.issubdtype(values.dtype, np.integer)):
        raise ValueError(f"fade callable must return real weights of the same shape as t (got shape {values.shape}, "
                         f"dtype {values.dtype} for t of shape {probe.shape})")
    if not np.all(np.isfinite(values)) or abs(values[0]) > 1e-6 or abs(values[-1] - 1) > 1e-6:
        raise ValueError(f"fade callable must be finite with fade(0) = 0 and fade(1) = 1 (else the noise jumps at "
                         f"cell borders), got {values.tolist()} at t = {probe.tolist()}")
    return fade


def check_dtype(dtype):
    try:
        dt = None if dtype is None else np.dtype(dtype)  # (np.dtype(None) would be float64)
    except (TypeError, ValueError):
        dt = None
    if dt is None or dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise TypeError(f"dtype must be numpy.float32 or numpy.float64, got {dtype!r}")
    return dt


def check_size(size, name="size"):
    """A 2-D (H, W) or 3-D (D, H, W) size; an int means a square image."""
    if isinstance(size, numbers.Integral) and not isinstance(size, (bool, np.bool_)):
        return as_size(size, name, 2)
    if not isinstance(size, (tuple, list, np.ndarray)):
        raise TypeError(f"{name} must be an int or a tuple (H, W) or (D, H, W), got {size!r}")
    ndim = len(size)
    if ndim not in (2, 3):
        raise ValueError(f"{name} must be (H, W) for an image or (D, H, W) for a volume, got {size!r}")
    return as_size(tuple(size), name, ndim)


def check_fits(size, itemsize, copies, name="size", value=None):
    """Refuse, before allocating, an output that cannot fit in memory (:func:`~texsynth.core._validate.check_memory`).

    ``copies`` is how many arrays of ``size`` elements of ``itemsize`` bytes the
    call holds at once (the result and its full-size companions); the message
    names the parameter ``name`` (given as ``value``, default ``size``).
    """
    check_memory(float(math.prod(size)) * itemsize * copies, size if value is None else value, name)


def check_points(points):
    try:
        pts = np.asarray(points)
    except (TypeError, ValueError) as exc:  # ragged lists
        raise ValueError(f"points must be an array of shape (N, 2) or (N, 3) (columns x, y[, z]): {exc}") from None
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (N, 2) or (N, 3) (columns x, y[, z]), got shape {pts.shape}")
    if not (np.issubdtype(pts.dtype, np.floating) or np.issubdtype(pts.dtype, np.integer)):
        raise TypeError(f"points must be real numbers, got dtype {pts.dtype}")
    pts = pts.astype(np.float64)
    if not np.all(np.isfinite(pts)):
        raise ValueError("points contains NaN or infinite coordinates; pass finite lattice coordinates")
    return pts


def check_period(period, ndim):
    """``None`` or a positive integer lattice period per axis, in (x, y[, z]) order."""
    if period is None:
        return None
    items = tuple(period) if _is_sequence(period) else (period,) * ndim
    hint = f"an int or {ndim} ints (x, y{', z' if ndim == 3 else ''})"
    if len(items) != ndim:
        raise ValueError(f"period must be {hint}, got {period!r}")
    out = []
    for p in items:
        if isinstance(p, np.ndarray) and p.ndim == 0:
            p = p.item()
        integral = isinstance(p, numbers.Integral) and _is_real(p)
        value = int(p) if integral or (finite_real(p) and float(p).is_integer()) else 0
        if value < 1:
            raise ValueError(f"period must be {hint}, each a positive integer number of lattice cells, "
                             f"got {period!r}")
        if value > MAX_COORDINATE:
            raise ValueError(f"period must be at most 2**52 lattice cells (float64 coordinates cannot go "
                             f"further), got {period!r}")
        out.append(value)
    return tuple(out)


def check_offset(offset, ndim):
    if offset is None:
        return (0.0,) * ndim
    items = tuple(offset) if _is_sequence(offset) else (offset,) * ndim
    items = tuple(o.item() if isinstance(o, np.ndarray) and o.ndim == 0 else o for o in items)
    if len(items) != ndim or not all(finite_real(o) for o in items):
        raise ValueError(f"offset must be a number or {ndim} finite numbers (x, y[, z]), got {offset!r}")
    return tuple(float(o) for o in items)


def check_extent(largest, what, hint):
    """Lattice coordinates must stay below 2**52, where float64 still resolves a cell."""
    if not largest <= MAX_COORDINATE:  # also catches inf and NaN
        raise ValueError(f"{what} put lattice coordinates at up to {largest:.3g}, beyond 2**52 = 4.5e15 where "
                         f"float64 has no fractional part left (the noise would be 0 everywhere); {hint}")


def grid_extent(size, spacing, origin):
    """Largest absolute lattice coordinate of the grid (``origin`` in x, y[, z] order)."""
    with np.errstate(over="ignore", invalid="ignore"):
        return max(max(abs(o), abs(o + spacing * (n - 1))) for o, n in zip(origin, size[::-1]))


def permutation(rng):
    """Perlin's permutation table of 0..255, drawn from ``rng``, doubled to 512 entries."""
    perm = as_rng(rng).permutation(256)
    return np.concatenate([perm, perm]).astype(np.intp)


def pixel_spacing(size, frequency):
    """Lattice units per pixel: ``frequency`` cells across the longest axis (square cells)."""
    return float(frequency) / max(size)


def band_limit(size, frequency, lacunarity):
    """:func:`band_limit_octaves` without the argument checks."""
    cell = max(size) / float(frequency)
    if cell < 1:
        return 1
    if math.isinf(cell):  # frequency so low that size / frequency overflows: logarithms instead
        ratio = (math.log(max(size)) - math.log(frequency)) / math.log(lacunarity)
    else:
        ratio = np.log(cell) / np.log(lacunarity)
    return int(np.floor(ratio + 1e-9)) + 1


def check_lacunarity(lacunarity):
    lacunarity = check_float(lacunarity, "lacunarity")
    if lacunarity <= 1:
        raise ValueError(f"lacunarity must be > 1 (each octave finer than the last), got {lacunarity}")
    return lacunarity


def band_limit_octaves(size, frequency, lacunarity=2.0):
    """Number of octaves up to the band limit of a grid.

    Octave ``i`` has lattice spacing ``max(size) / (frequency * lacunarity**i)``
    pixels; the sum stops at the last octave whose spacing is still at least
    one pixel (the slide "Turbulence Function": truncate when
    ``1 / 2^(k+1)`` is smaller than one pixel).

    Parameters
    ----------
    size : int or tuple of int
        ``(H, W)`` or ``(D, H, W)`` grid (an int means a square image).
    frequency : float
        Lattice cells of the first octave across the longest axis (> 0).
    lacunarity : float, default 2.0
        Frequency ratio between octaves (> 1).

    Returns
    -------
    int
        At least 1 (a first octave finer than a pixel is still one octave).

    Raises
    ------
    ValueError
        For a non-positive size or frequency, or ``lacunarity <= 1``.
    TypeError
        For a size, frequency or lacunarity of the wrong type (e.g. a bool).

    Examples
    --------
    >>> band_limit_octaves((1024, 1024), 8)
    8
    >>> band_limit_octaves(64, 64)
    1
    """
    size = check_size(size)
    frequency = check_float(frequency, "frequency")
    lacunarity = check_lacunarity(lacunarity)
    return band_limit(size, frequency, lacunarity)


# --------------------------------------------------------------------------
# hashing: gradients at lattice points
# --------------------------------------------------------------------------


def _wrap(indices, period):
    """Lattice index -> permutation index: wrap by the period, then by 256."""
    if period is not None:
        indices = np.mod(indices, period)
    return indices & 255


# --------------------------------------------------------------------------
# evaluation at arbitrary points (the direct form of the algorithm)
# --------------------------------------------------------------------------


def noise_points(points, perm, period, fade, dtype, gradients=None):
    """Perlin noise at ``points`` (N, d) in lattice units, columns (x, y[, z]).

    ``gradients`` (16, 3) can replace the gradient table (the benchmark uses
    the ``noise`` package's variant to cross-check against it).
    """
    n, ndim = points.shape
    per = period or (None,) * ndim
    if gradients is None:
        gradients = _gradient_table(ndim)
    tables = [np.ascontiguousarray(gradients[:, a], dtype=dtype) for a in range(ndim)]
    cell = np.floor(points)
    frac = (points - cell).astype(dtype).T  # (d, N): position inside the cell, in [0, 1)
    cell = cell.astype(np.intp).T
    w1 = fade(frac)  # interpolation weights of the upper corner ...
    w0 = 1 - w1  # ... and of the lower corner, per axis
    corners = [[_wrap(cell[a], per[a]), _wrap(cell[a] + 1, per[a])] for a in range(ndim)]
    px = [np.take(perm, c) for c in corners[0]]  # P[x], P[x + 1]
    out = np.zeros(n, dtype=dtype)
    wavelet = np.empty(n, dtype=dtype)
    # Sum over the 2^d corners c of  prod_a w_a(c_a) * g_c . (x - c)  -- the
    # multilinear interpolation of the corner wavelets, written as a sum.
    for corner in np.ndindex(*(2,) * ndim):
        h = np.take(perm, px[corner[0]] + corners[1][corner[1]])  # P[P[x] + y]
        h = np.take(perm, h + corners[2][corner[2]]) if ndim == 3 else np.take(perm, h)
        h &= 15
        weight = w1[0] if corner[0] else w0[0]
        for a in range(1, ndim):
            weight = weight * (w1[a] if corner[a] else w0[a])
        np.multiply(np.take(tables[0], h), frac[0] - corner[0], out=wavelet)
        for a in range(1, ndim):
            wavelet += np.take(tables[a], h) * (frac[a] - corner[a])
        wavelet *= weight
        out += wavelet
    return out


# --------------------------------------------------------------------------
# separable evaluation on a regular grid
# --------------------------------------------------------------------------
#
# On a grid the corner sum of ``noise_points`` factorises axis by axis. With
# w0 = 1 - fade(f), w1 = fade(f) per axis, contracting the x axis of the
# lattice gradients g gives, for every lattice row (and slice),
#     s(x)   = w0(x) f(x) gx[i] + w1(x) (f(x) - 1) gx[i + 1]   (the x part of g . d)
#     V_a(x) = w0(x) ga[i] + w1(x) ga[i + 1]                   (a = y, z: still to be
#                                                                multiplied by f_a - c_a)
# then contracting y (rows r of lattice row j) gives
#     P(r, x)  = w0 (s[j] + f Vy[j]) + w1 (s[j+1] + (f - 1) Vy[j+1])
#     Qz(r, x) = w0 Vz[j] + w1 Vz[j+1]
# and z the noise  n = w0 (P[k] + f Qz[k]) + w1 (P[k+1] + (f - 1) Qz[k+1]).
# Each contraction of samples that share a cell is one small matrix product
# (samples x 4) @ (4 x rest).
#
# Memory. Only the lattice rows (and slices) that the samples of a block of
# the output fall in are hashed, and the output is filled block by block along
# its first axis, so the temporaries are proportional to a block whatever the
# frequency (the whole lattice of a 64 x 64 image at frequency 20000 would be
# 4e8 points).
#
# Rounding. A BLAS product rounds each element by its kernel's blocking, which
# depends on the CPU (OpenBLAS's Haswell kernel computes an element of a gemm as
# one fused multiply-add chain; its Nehalem kernel does not, and rounds by the
# product's shape), so a block of the image could differ from the whole image
# on one machine and not on another. The products here have 2 or 4 terms, so
# they are written out term by term (:func:`_contract`): numpy's element-wise
# multiply and add round every element alone, the same on every CPU.

_BLOCK = 1 << 18  # lattice points of one block-sized temporary (2 MiB in float64)
_SHORT_RUN = 8  # rows: runs shorter on average are contracted a block at a time (fewer, larger calls)


def _axis_factors(coords, fade, dtype):
    """Cell index (relative to the first), and the factors w0, w0*f, w1, w1*(f-1)."""
    cell = np.floor(coords)
    frac = coords - cell
    w1 = fade(frac)
    w0 = 1.0 - w1
    cell = cell.astype(np.int64)
    first = int(cell[0])
    factors = np.stack([w0, w0 * frac, w1, w1 * (frac - 1.0)], axis=1).astype(dtype)  # (n, 4)
    return cell - first, first, factors


class _Axis:
    """The samples of one grid axis: lattice cells, interpolation factors and runs."""

    def __init__(self, coords, fade, dtype, period):
        self.rel, self.first, self.factors = _axis_factors(coords, fade, dtype)
        self.period = period
        self.n_lattice = int(self.rel[-1]) + 2  # lattice points spanned (the old whole-lattice size)
        edges = np.flatnonzero(np.diff(self.rel)) + 1
        self.starts = np.concatenate([[0], edges]).astype(np.intp)
        self.stops = np.concatenate([edges, [len(self.rel)]]).astype(np.intp)

    def wrapped(self, lattice):
        """Permutation index of relative lattice coordinates ``lattice``."""
        return _wrap(self.first + np.asarray(lattice, dtype=np.int64), self.period)

    def pieces(self, a, b):
        """The runs of samples in one cell, clipped to ``[a, b)``: ``(cell, start, stop)``."""
        first = int(np.searchsorted(self.stops, a, side="right"))
        last = int(np.searchsorted(self.starts, b, side="left"))
        return [(int(self.rel[self.starts[r]]), max(int(self.starts[r]), a), min(int(self.stops[r]), b))
                for r in range(first, last)]


def _contract(factors, terms, out):
    """``out = sum_k factors[:, k] terms[k]``, term by term (see Rounding above): a product
    ``factors @ matrix`` with ``terms = matrix[:, None]``, or one whose rows differ per sample.

    ``factors`` is ``(n, K)`` (K = 2 or 4), each ``terms[k]`` ``(1, m)`` or ``(n, m)``; every element
    of ``out`` (``(n, m)``) is ``((f0 t0 + f1 t1) + f2 t2) + f3 t3``, each operation rounded alone.
    """
    np.multiply(factors[:, :1], terms[0], out=out)
    term = np.empty_like(out)
    for k in range(1, factors.shape[1]):
        np.multiply(factors[:, k : k + 1], terms[k], out=term)
        out += term
    return out


class _GridNoise:
    """Perlin noise on the grid ``x = origin + spacing * index`` (per axis), block by block.

    ``size`` is in array order ((H, W) or (D, H, W)); ``origin`` in (x, y[, z])
    order. :meth:`fill` writes the rows (2-D) or slices (3-D) ``[a, b)``.
    Equal to ``noise_points`` at the grid's coordinates up to rounding.
    """

    def __init__(self, size, spacing, origin, perm, period, fade, dtype, x_start=0, y_start=0):
        self.size, self.ndim, self.perm, self.dtype = tuple(size), len(size), perm, dtype
        self.y0 = y_start  # the first row's index in a larger grid (2-D); fill and blocks take those indices
        period = period or (None,) * self.ndim
        self.axes = []
        for a, n in enumerate(self.size[::-1]):
            start = {0: x_start, 1: y_start}.get(a, 0) if self.ndim == 2 else 0  # a window of a larger grid
            coords = origin[a] + spacing * np.arange(start, start + n, dtype=np.float64)
            self.axes.append(_Axis(coords, fade, dtype, period[a]))
        ax = self.axes[0]
        width = self.size[-1]
        # Hash P[x] per lattice column and gather the columns' corners afterwards when the
        # columns span fewer lattice points than there are samples (cells of a pixel or
        # more), else per sample column directly (left corner i and right corner i + 1).
        self.x_lattice = ax.n_lattice <= width
        if self.x_lattice:
            self.px = [np.take(perm, ax.wrapped(np.arange(ax.n_lattice)))]
        else:
            self.px = [np.take(perm, ax.wrapped(ax.rel + c)) for c in (0, 1)]
        table = _gradient_table(self.ndim)
        self.tables = [table[:, k].astype(dtype) for k in range(self.ndim)]
        self.fyq = np.ascontiguousarray(self.axes[1].factors[:, [0, 2]])  # w0, w1 of y (3-D Qz)
        ay = self.axes[1]
        self.runs = list(zip(ay.starts.tolist(), ay.stops.tolist()))  # rows that share a lattice row

    def blocks(self, first=None, last=None):
        """Ranges ``[a, b)`` within ``[first, last)`` (default: all) of the first array axis whose
        lattice rows (slices) hold about ``_BLOCK`` points each (a block of samples finer than the
        lattice touches up to twice as many lattice rows as it has rows). Any cut gives the same
        values (:func:`_contract`)."""
        n, inner = self.size[0], math.prod(self.size[1:])
        first = self.y0 if first is None else first
        last = self.y0 + n if last is None else last
        per_row = min(2.0, max(1.0, self.axes[-1].n_lattice / n))
        step = max(1, int(_BLOCK / (inner * per_row)))
        return [(a, min(a + step, last)) for a in range(first, last, step)]

    def fill(self, out, a, b):
        """Write the noise of rows (2-D) or slices (3-D) ``[a, b)`` into ``out`` (C-contiguous)."""
        a, b = a - self.y0, b - self.y0
        if self.ndim == 2:
            self._fill_2d(out, a, b)
        else:
            self._fill_3d(out, a, b)
        return out

    # -- x: hash the lattice rows (and slices), contract the x axis ---------------

    def _contract_x(self, wy, wz=None):
        """s and V_a (see above) at the wrapped lattice rows ``wy`` (and slices ``wz``).

        The gradient index is ``P[P[P[x] + y] + z] & 15`` (Perlin 2002; z = 0 in
        2-D), hashed for the needed lattice points only.
        """
        grads = []
        for px in self.px:
            h = np.take(self.perm, px[None, :] + wy[:, None])  # P[P[x] + y], (Ny, columns)
            if wz is None:
                h = np.take(self.perm, h)  # P[P[P[x] + y] + 0]
            else:
                h = np.take(self.perm, h[None, :, :] + wz[:, None, None])  # (Nz, Ny, columns)
            h &= 15
            grads.append([np.take(t, h) for t in self.tables])
        if self.x_lattice:  # gradients per lattice column: gather the corners of every sample
            cx = self.axes[0].rel
            grads = [[np.take(g, cx + c, axis=-1) for g in grads[0]] for c in (0, 1)]
        (left, right), fx = grads, self.axes[0].factors
        s = left[0] * fx[:, 1] + right[0] * fx[:, 3]
        v = [left[k] * fx[:, 0] + right[k] * fx[:, 2] for k in range(1, self.ndim)]
        return s, v

    # -- 2-D -------------------------------------------------------------------------

    def _fill_2d(self, out, a, b):
        ay = self.axes[1]
        width = self.size[1]
        pieces = ay.pieces(a, b)
        cells = np.array([p[0] for p in pieces], dtype=np.int64)
        lattice = np.unique(np.concatenate([cells, cells + 1]))  # the lattice rows this block touches
        s, v = self._contract_x(ay.wrapped(lattice))
        # rows 2p .. 2p + 3 of `matrix` are [s_j; Vy_j; s_j+1; Vy_j+1] for lattice row j = lattice[p]
        matrix = np.stack([s, v[0]], axis=1).reshape(-1, width)
        del s, v
        out2 = out.reshape(b - a, width)
        fy = ay.factors
        rows = 2 * np.searchsorted(lattice, cells)
        if len(pieces) * _SHORT_RUN > b - a:  # short runs (cells of a few pixels): the block in one go
            rows = np.repeat(rows, [stop - start for _, start, stop in pieces])
            _contract(fy[a:b], [matrix[rows + k] for k in range(4)], out2)
            return
        for (_, start, stop), r in zip(pieces, rows.tolist()):
            # (samples x 4) @ [s_j; Vy_j; s_j+1; Vy_j+1]
            _contract(fy[start:stop], matrix[r : r + 4, None], out2[start - a : stop - a])

    # -- 3-D -------------------------------------------------------------------------

    def _fill_3d(self, out, a, b):
        _, ay, az = self.axes
        _, height, width = self.size
        zpieces = az.pieces(a, b)
        zcells = np.array([p[0] for p in zpieces], dtype=np.int64)
        zlat = np.unique(np.concatenate([zcells, zcells + 1]))  # lattice slices this block touches
        nz = len(zlat)
        planes = np.empty((2, height, nz, width), dtype=self.dtype)  # P and Qz per row and slice
        flat_planes = planes.reshape(2, height, nz * width)
        fy, fyq = ay.factors, self.fyq
        # contract y, each run of rows: (rows x 4) @ [s_j; Vy_j; s_j+1; Vy_j+1] and
        # (rows x 2) @ [Vz_j; Vz_j+1] over every lattice slice at once
        for group, ylat, pos in self._row_batches(self.runs, nz):
            s, v = self._contract_x(ay.wrapped(ylat), az.wrapped(zlat))  # each (Nz, Ny, W)
            # rows 2p .. 2p + 3 of `sy` are [s_j; Vy_j; s_j+1; Vy_j+1], rows p, p + 1 of `vz` [Vz_j; Vz_j+1]
            sy = np.stack([s, v[0]], axis=0).transpose(2, 0, 1, 3).reshape(2 * len(ylat), -1)
            vz = v[1].transpose(1, 0, 2).reshape(len(ylat), -1)
            del s, v
            for (r0, r1), p in zip(group, pos):
                _contract(fy[r0:r1], sy[2 * p : 2 * p + 4, None], flat_planes[0, r0:r1])
                _contract(fyq[r0:r1], vz[p : p + 2, None], flat_planes[1, r0:r1])
            del sy, vz
        # contract z: (slices x 4) @ [P_k; Qz_k; P_k+1; Qz_k+1]
        matrix = np.empty((4, height, width), dtype=self.dtype)
        out2 = out.reshape(b - a, height * width)
        fz = az.factors
        for (_, start, stop), q in zip(zpieces, np.searchsorted(zlat, zcells).tolist()):
            matrix[0], matrix[1] = planes[0, :, q], planes[1, :, q]
            matrix[2], matrix[3] = planes[0, :, q + 1], planes[1, :, q + 1]
            _contract(fz[start:stop], matrix.reshape(4, 1, height * width), out2[start - a : stop - a])

    def _row_batches(self, runs, nz):
        """Batches of runs of rows ``(r0, r1)`` whose lattice rows x ``nz`` slices x W stay
        within ``_BLOCK``: ``(runs, lattice rows, index of each run's lattice row)``."""
        ay, width = self.axes[1], self.size[2]
        limit = max(1, _BLOCK // max(1, 2 * nz * width))
        for k in range(0, len(runs), limit):
            group = runs[k : k + limit]
            cells = ay.rel[[r0 for r0, _ in group]]
            ylat = np.unique(np.concatenate([cells, cells + 1]))
            yield group, ylat, np.searchsorted(ylat, cells).tolist()


def window_grid(size, spacing, origin, perm, period, fade, dtype, window):
    """The noise of the grid ``size``, or of its ``window`` (rows, cols slices; 2-D): the same
    values as the whole grid's there (:func:`_contract`)."""
    if window is None:
        return _GridNoise(size, spacing, origin, perm, period, fade, dtype)
    rows, cols = window
    return _GridNoise((rows.stop - rows.start, cols.stop - cols.start), spacing, origin, perm, period, fade, dtype,
                      cols.start, rows.start)


def window_rows(size, window):
    """``(first, last)``: the rows of ``window`` (all rows without one)."""
    return (0, size[0]) if window is None else (window[0].start, window[0].stop)


def _noise_grid(size, spacing, origin, perm, period, fade, dtype, window=None):
    """Perlin noise on a grid (see :class:`_GridNoise`), or on the ``window`` of it (see :func:`window_grid`)."""
    grid = window_grid(size, spacing, origin, perm, period, fade, dtype, window)
    first, last = window_rows(size, window)
    out = np.empty((last - first,) + grid.size[1:], dtype=dtype)
    for a, b in grid.blocks(first, last):
        grid.fill(out[a - first : b - first], a, b)
    return out


# --------------------------------------------------------------------------
# public function
# --------------------------------------------------------------------------


def no_chunks(chunks):
    if chunks is not None:
        raise ValueError("chunks= renders a grid (size=) block by block; with points= pass chunks=None")


def chunked(size, chunks, dtype, render, copies, channels=None):
    """``chunks=``: the lazy image whose blocks are ``render(rows, cols)`` (2-D grids only)."""
    if len(size) != 2:
        raise ValueError(f"chunks= renders 2-D images block by block; size={size} is a volume, pass chunks=None")
    from ..core.chunked import chunked_image

    return chunked_image(size, channels, dtype, chunks, render, bytes_per_pixel=copies * dtype.itemsize)


def perlin(size=None, *, frequency=8, points=None, period=None, offset=None, fade="quintic",
           rng=None, dtype=np.float64, chunks=None):
    """Perlin gradient noise on a grid (image or volume) or at arbitrary points.

    Examples
    --------
    >>> import texsynth
    >>> img = texsynth.procedural.perlin((32, 32), frequency=4, rng=0)
    >>> img.shape, bool(abs(img).max() <= 1)
    ((32, 32), True)
    >>> float(img[0, 0]), float(img[8, 8])       # lattice points (8 px per cell)
    (0.0, 0.0)

    Gradient noise: each sample blends, by a fade curve, the dot products of
    its lattice cell's pseudo-random corner gradients with its offsets from
    the corners. The default is Perlin's improved noise [2]_; ``fade="cubic"``
    gives the fade of his 1985 noise [1]_.

    Parameters
    ----------
    size : int or tuple of int, optional
        ``(H, W)`` for an image or ``(D, H, W)`` for a volume (an int means a
        square image). Give either ``size`` or ``points``.
    frequency : float, default 8
        Lattice cells across the longest axis of the grid (cells are square,
        so a 256 x 512 image with ``frequency=8`` has 4 x 8 cells). Ignored
        for ``points``, which are already in lattice units.
    points : array_like, shape (N, 2) or (N, 3), optional
        Coordinates in lattice units, columns ``(x, y[, z])``: the lecture's
        "evaluation of the function on the object surface" (mesh vertices,
        ray-surface intersections). Grid sample ``[row, col]`` (``[depth,
        row, col]``) lies at ``x = col * s``, ``y = row * s``, ``z = depth * s``
        with ``s = frequency / max(size)``, plus ``offset``.
    period : int or tuple of int, optional
        Make the lattice wrap every ``period`` cells (per axis in (x, y[, z])
        order): the noise is then periodic. A grid spanning a whole number of
        periods tiles seamlessly, e.g. a square image with
        ``period=frequency``.
    offset : float or tuple of float, optional
        Translation of the grid in lattice units, (x, y[, z]) order.
    fade : {"quintic", "cubic"} or callable, default "quintic"
        Interpolation curve: Perlin 2002's ``6t^5 - 15t^4 + 10t^3`` or Perlin
        1985's cubic Hermite ``3t^2 - 2t^3``. A callable maps an array of
        ``t`` in [0, 1) to weights, with ``fade(0) = 0`` and ``fade(1) = 1``.
    rng : None, int or numpy.random.Generator
        Seeds the permutation table (which gradient sits at which lattice point).
    dtype : numpy.float32 or numpy.float64, default float64
        Precision of the computation and result; float32 is about twice as
        fast on large grids.
    chunks : None, int or (int, int)
        2-D grids only: return a lazy ``dask.array`` of ``size`` rendered
        block by block (blocks of ``chunks`` rows and columns, an int meaning
        square), for outputs larger than memory; write it with
        :func:`texsynth.io.save_chunked`. Every block equals the same pixels
        of the in-memory result bit for bit. Needs Dask
        (the ``dask`` extra: ``pip install '.[dask]'`` in a checkout).

    Returns
    -------
    numpy.ndarray or dask.array.Array
        ``size`` (grid) or ``(N,)`` (points), values in [-1, 1] (standard
        deviation about 0.31 in 2-D, 0.27 in 3-D), exactly 0 at lattice
        points; a ``dask.array`` with ``chunks``.

    Raises
    ------
    ValueError
        If neither or both of ``size`` and ``points`` are given, for a
        non-positive size or frequency, a period that is not a positive
        integer, an unknown fade, lattice coordinates beyond 2**52 (a huge
        frequency or offset), or an output larger than this machine's memory.
    TypeError
        For arguments of the wrong type (a bool or string as a number, a
        dtype other than float32/float64).

    Notes
    -----
    At ``x`` in the cell with lower corner ``i`` (integer vector), with
    ``f = x - i`` and corner gradients ``g_c`` for ``c`` in {0, 1}^d:

    .. math:: n(x) = \\sum_c \\prod_a w(c_a, f_a)\\, g_{i+c} \\cdot (f - c),
              \\quad w(0, t) = 1 - s(t),\\ w(1, t) = s(t)

    with the fade ``s`` ([2]_, eq. in section 2). The gradient index is
    ``P[P[P[i_x] + i_y] + i_z] mod 16`` into Perlin's 2002 table of cube-edge
    directions ([2]_, section 3) in 3-D, and (with ``i_z = 0``) into eight
    directions 45 degrees apart in 2-D; with ``period`` the lattice index is
    taken modulo the period first.

    Only the lattice cells that the samples fall in are hashed, and a grid is
    filled in blocks of rows (slices), so memory is proportional to the
    output whatever the frequency.

    The noise is band-limited around the lattice frequency and its
    distribution over a region does not depend on where the region lies
    (translation invariance, the slide "Perlin's Noise"); pointwise, the
    variance is zero at lattice points and largest between them.

    At points (in lattice units), periodic, and on a volume:

    >>> pts = texsynth.procedural.perlin(points=[[0.5, 0.25], [1.0, 1.0]], rng=0)
    >>> float(pts[1])
    0.0
    >>> tile = texsynth.procedural.perlin((16, 16), frequency=4, period=4, rng=1)
    >>> texsynth.procedural.perlin((8, 8, 8), frequency=2, rng=0).shape
    (8, 8, 8)

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247
    .. [2] K. Perlin, "Improving noise", SIGGRAPH 2002.
       https://doi.org/10.1145/566654.566636
    """
    fade_fn = check_fade(fade)
    dt = check_dtype(dtype)
    if (size is None) == (points is None):
        raise ValueError("give exactly one of size (a grid) or points (lattice coordinates), "
                         f"got size={size!r} and points={'None' if points is None else 'an array'}")
    if points is not None:
        no_chunks(chunks)
        pts = check_points(points)
        ndim = pts.shape[1]
        per = check_period(period, ndim)
        pts = pts + np.asarray(check_offset(offset, ndim))
        check_extent(float(np.abs(pts).max(initial=0.0)), "points (plus offset)",
                     "pass smaller coordinates (the lattice repeats every 256 cells, or every period)")
        return noise_points(pts, permutation(rng), per, fade_fn, dt)
    size = check_size(size)
    frequency = check_float(frequency, "frequency")
    per = check_period(period, len(size))
    origin = check_offset(offset, len(size))
    spacing = pixel_spacing(size, frequency)
    check_extent(grid_extent(size, spacing, origin), f"frequency={frequency:g} and offset={offset!r}",
                 "pass a smaller frequency or offset")
    perm = permutation(rng)
    if chunks is not None:
        return chunked(size, chunks, dt, lambda rows, cols: _noise_grid(size, spacing, origin, perm, per, fade_fn,
                                                                        dt, (rows, cols)), 2)
    check_fits(size, dt.itemsize, 1)
    return _noise_grid(size, spacing, origin, perm, per, fade_fn, dt)
