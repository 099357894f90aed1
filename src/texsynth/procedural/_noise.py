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

References
----------
.. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985, Computer Graphics
   19(3), 287-296. https://doi.org/10.1145/325165.325247
.. [2] K. Perlin, "Improving noise", SIGGRAPH 2002, ACM Transactions on
   Graphics 21(3), 681-682. https://doi.org/10.1145/566654.566636
"""

from __future__ import annotations

import contextlib
import numbers

import numpy as np

from ..core._validate import as_rng, as_size, check_positive_float

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


def _check_fade(fade):
    if callable(fade):
        return fade
    if fade not in FADES:
        raise ValueError(f"fade must be one of {sorted(FADES)} or a callable, got {fade!r}")
    return FADES[fade]


def _check_dtype(dtype):
    dt = np.dtype(dtype)
    if dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise ValueError(f"dtype must be numpy.float32 or numpy.float64, got {dt}")
    return dt


def _check_shape(shape):
    """A 2-D (H, W) or 3-D (D, H, W) shape; an int means a square image."""
    if isinstance(shape, numbers.Integral) and not isinstance(shape, bool):
        return as_size(shape, "shape", 2)
    try:
        ndim = len(shape)
    except TypeError:
        raise TypeError(f"shape must be an int or a tuple (H, W) or (D, H, W), got {shape!r}") from None
    if ndim not in (2, 3):
        raise ValueError(f"shape must be (H, W) for an image or (D, H, W) for a volume, got {shape!r}")
    return as_size(shape, "shape", ndim)


def _check_points(points):
    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"points must have shape (N, 2) or (N, 3) (columns x, y[, z]), got shape {pts.shape}")
    if not (np.issubdtype(pts.dtype, np.floating) or np.issubdtype(pts.dtype, np.integer)):
        raise TypeError(f"points must be real numbers, got dtype {pts.dtype}")
    pts = pts.astype(np.float64)
    if not np.all(np.isfinite(pts)):
        raise ValueError("points contains NaN or infinite coordinates; pass finite lattice coordinates")
    return pts


def _check_period(period, ndim):
    """``None`` or a positive integer lattice period per axis, in (x, y[, z]) order."""
    if period is None:
        return None
    items = (period,) * ndim if np.ndim(period) == 0 else tuple(period)
    if len(items) != ndim:
        raise ValueError(f"period must be an int or {ndim} ints (x, y{', z' if ndim == 3 else ''}), got {period!r}")
    out = []
    for p in items:
        if isinstance(p, bool) or not isinstance(p, numbers.Integral):
            if isinstance(p, numbers.Real) and float(p).is_integer() and p > 0:
                p = int(p)
            else:
                raise ValueError(f"period must be a positive integer number of lattice cells, got {period!r}")
        if p < 1:
            raise ValueError(f"period must be a positive integer number of lattice cells, got {period!r}")
        out.append(int(p))
    return tuple(out)


def _check_offset(offset, ndim):
    if offset is None:
        return (0.0,) * ndim
    items = (offset,) * ndim if np.ndim(offset) == 0 else tuple(offset)
    if len(items) != ndim or not all(isinstance(o, numbers.Real) and np.isfinite(o) for o in items):
        raise ValueError(f"offset must be a number or {ndim} finite numbers (x, y[, z]), got {offset!r}")
    return tuple(float(o) for o in items)


def _permutation(rng):
    """Perlin's permutation table of 0..255, drawn from ``rng``, doubled to 512 entries."""
    perm = as_rng(rng).permutation(256)
    return np.concatenate([perm, perm]).astype(np.intp)


def _pixel_spacing(shape, frequency):
    """Lattice units per pixel: ``frequency`` cells across the longest axis (square cells)."""
    return float(frequency) / max(shape)


def band_limit_octaves(shape, frequency, lacunarity=2.0):
    """Number of octaves up to the band limit of a grid.

    Octave ``i`` has lattice spacing ``max(shape) / (frequency * lacunarity**i)``
    pixels; the sum stops at the last octave whose spacing is still at least
    one pixel (the slide "Turbulence Function": truncate when
    ``1 / 2^(k+1)`` is smaller than one pixel).

    Examples
    --------
    >>> band_limit_octaves((1024, 1024), 8)
    8
    >>> band_limit_octaves((64, 64), 64)
    1
    """
    cell = max(shape) / float(frequency)
    if cell < 1:
        return 1
    k = int(np.floor(np.log(cell) / np.log(lacunarity) + 1e-9))
    return k + 1


# --------------------------------------------------------------------------
# the lattice: gradients at lattice points
# --------------------------------------------------------------------------


def _wrap(indices, period):
    """Lattice index -> permutation index: wrap by the period, then by 256."""
    if period is not None:
        indices = np.mod(indices, period)
    return indices & 255


def _lattice_gradients(perm, lattice, period, dtype):
    """Gradient components at the lattice points of an outer product of axes.

    ``lattice`` lists integer coordinates per axis in (x, y[, z]) order; the
    result is one array per component (x, y[, z]), each of shape
    ``(len(z), len(y), len(x))`` (array axis order), with
    ``hash = P[P[P[x] + y] + z]`` (Perlin 2002; z = 0 in 2-D).
    """
    ndim = len(lattice)
    per = period or (None,) * ndim
    wrapped = [_wrap(np.asarray(ax, dtype=np.intp), p) for ax, p in zip(lattice, per)]
    h = np.take(perm, wrapped[0])  # P[x], shape (nx,)
    h = np.take(perm, h[None, :] + wrapped[1][:, None])  # P[P[x] + y], shape (ny, nx)
    if ndim == 3:
        h = np.take(perm, h[None, :, :] + wrapped[2][:, None, None])  # P[P[P[x] + y] + z]
    else:
        h = np.take(perm, h)  # P[P[P[x] + y] + 0]
    h &= 15
    table = _gradient_table(ndim)
    return [np.take(table[:, k].astype(dtype), h) for k in range(ndim)]


# --------------------------------------------------------------------------
# evaluation at arbitrary points (the direct form of the algorithm)
# --------------------------------------------------------------------------


def _noise_points(points, perm, period, fade, dtype, gradients=None):
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
# On a grid the corner sum of ``_noise_points`` factorises axis by axis. With
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
# (samples x 4) @ (4 x rest), see ``_contract``.


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


def _runs(cell):
    """``(cell, start, stop)`` for each run of consecutive samples in one cell."""
    edges = np.flatnonzero(np.diff(cell)) + 1
    starts = np.concatenate([[0], edges]).astype(int)
    stops = np.concatenate([edges, [len(cell)]]).astype(int)
    return [(int(cell[a]), int(a), int(b)) for a, b in zip(starts, stops)]


def _contract(stack, cell, coeffs, out):
    """``out[r] = sum_{c, ch} coeffs[r, c * nch + ch] * stack[cell[r] + c, ch]``.

    ``stack`` is (L, nch, *rest) C-contiguous, so ``stack[j:j + 2]`` is a
    (2 nch, rest) matrix and every run of samples in lattice cell ``j`` is one
    matrix product.
    """
    n = len(cell)
    lat, nch = stack.shape[:2]
    flat = stack.reshape(lat, nch, -1)
    rest = flat.shape[2]
    out2 = out.reshape(n, rest)
    for j, r0, r1 in _runs(cell):
        np.matmul(coeffs[r0:r1], flat[j : j + 2].reshape(2 * nch, rest), out=out2[r0:r1])
    return out


_BLAS_CONTROLLER = []


def _single_thread_blas():
    """Limit BLAS to one thread: the products here are small, and on a busy
    machine a multi-threaded BLAS waiting for its second thread was measured
    3x slower (105 ms vs 370 ms for 8-octave turbulence at 1024^2)."""
    if not _BLAS_CONTROLLER:
        try:
            import threadpoolctl  # a dependency of scikit-learn
        except ImportError:  # pragma: no cover
            _BLAS_CONTROLLER.append(None)
        else:
            _BLAS_CONTROLLER.append(threadpoolctl.ThreadpoolController())
    ctl = _BLAS_CONTROLLER[0]
    return contextlib.nullcontext() if ctl is None else ctl.limit(limits=1, user_api="blas")


def _noise_grid(shape, spacing, origin, perm, period, fade, dtype, out=None):
    with _single_thread_blas():
        return _noise_grid_impl(shape, spacing, origin, perm, period, fade, dtype, out)


def _noise_grid_impl(shape, spacing, origin, perm, period, fade, dtype, out=None):
    """Perlin noise on the grid ``x = origin + spacing * index`` (per axis).

    ``shape`` is in array order ((H, W) or (D, H, W)); ``origin`` in (x, y[, z])
    order. Writes into ``out`` (a C-contiguous array of ``shape``) if given.
    Equal to ``_noise_points`` at the grid's coordinates up to rounding.
    """
    ndim = len(shape)
    sizes_xyz = shape[::-1]
    axes = []
    for a in range(ndim):
        coords = origin[a] + spacing * np.arange(sizes_xyz[a], dtype=np.float64)
        axes.append(_axis_factors(coords, fade, dtype))
    lattice = [first + np.arange(int(rel[-1]) + 2) for rel, first, _ in axes]
    grads = _lattice_gradients(perm, lattice, period, dtype)  # per component (..., Ly, Lx)
    if out is None:
        out = np.empty(shape, dtype=dtype)
    (cx, _, fx), (cy, _, fy) = axes[0], axes[1]
    # contract x: gather the gradients of the left (i) and right (i + 1) corner per column
    left = [np.take(g, cx, axis=-1) for g in grads]
    right = [np.take(g, cx + 1, axis=-1) for g in grads]
    s = left[0] * fx[:, 1] + right[0] * fx[:, 3]
    v = [left[k] * fx[:, 0] + right[k] * fx[:, 2] for k in range(1, ndim)]
    if ndim == 2:
        # contract y: (rows x 4) @ [s_j; Vy_j; s_j+1; Vy_j+1]
        return _contract(np.stack([s, v[0]], axis=1), cy, fy, out)
    depth, height, width = shape
    lz = s.shape[0]
    # (Ly, ch, Lz, W) so the y contraction handles every lattice slice at once
    sy = np.ascontiguousarray(np.stack([s, v[0]], axis=0).transpose(2, 0, 1, 3))
    vz = np.ascontiguousarray(v[1].transpose(1, 0, 2)[:, None])
    planes = np.empty((2, height, lz, width), dtype=dtype)
    _contract(sy, cy, fy, planes[0])  # P
    _contract(vz, cy, np.ascontiguousarray(fy[:, [0, 2]]), planes[1])  # Qz
    # contract z: (slices x 4) @ [P_k; Qz_k; P_k+1; Qz_k+1]
    stack = np.ascontiguousarray(planes.transpose(2, 0, 1, 3))  # (Lz, 2, H, W)
    cz, _, fz = axes[2]
    return _contract(stack, cz, fz, out)


# --------------------------------------------------------------------------
# public function
# --------------------------------------------------------------------------


def perlin(shape=None, *, frequency=8, points=None, period=None, offset=None, fade="quintic",
           rng=None, dtype=np.float64):
    """Perlin gradient noise on a grid (image or volume) or at arbitrary points.

    Parameters
    ----------
    shape : int or tuple of int, optional
        ``(H, W)`` for an image or ``(D, H, W)`` for a volume (an int means a
        square image). Give either ``shape`` or ``points``.
    frequency : float, default 8
        Lattice cells across the longest axis of the grid (cells are square,
        so a 256 x 512 image with ``frequency=8`` has 4 x 8 cells). Ignored
        for ``points``, which are already in lattice units.
    points : array_like, shape (N, 2) or (N, 3), optional
        Coordinates in lattice units, columns ``(x, y[, z])``: the lecture's
        "evaluation of the function on the object surface" (mesh vertices,
        ray-surface intersections). Grid sample ``[row, col]`` (``[depth,
        row, col]``) lies at ``x = col * s``, ``y = row * s``, ``z = depth * s``
        with ``s = frequency / max(shape)``, plus ``offset``.
    period : int or tuple of int, optional
        Make the lattice wrap every ``period`` cells (per axis in (x, y[, z])
        order): the noise is then periodic. A grid spanning a whole number of
        periods tiles seamlessly, e.g. a square image with
        ``period=frequency``.
    offset : float or tuple of float, optional
        Translation of the grid in lattice units, (x, y[, z]) order.
    fade : {"quintic", "cubic"} or callable, default "quintic"
        Interpolation curve: Perlin 2002's ``6t^5 - 15t^4 + 10t^3`` or Perlin
        1985's cubic Hermite ``3t^2 - 2t^3``.
    rng : None, int or numpy.random.Generator
        Seeds the permutation table (which gradient sits at which lattice point).
    dtype : numpy.float32 or numpy.float64, default float64
        Precision of the computation and result; float32 is about twice as
        fast on large grids.

    Returns
    -------
    numpy.ndarray
        ``shape`` (grid) or ``(N,)`` (points), values in [-1, 1] (standard
        deviation about 0.31 in 2-D, 0.27 in 3-D), exactly 0 at lattice
        points.

    Raises
    ------
    ValueError
        If neither or both of ``shape`` and ``points`` are given, for a
        non-positive shape or frequency, a period that is not a positive
        integer, or an unknown fade.

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

    The noise is band-limited around the lattice frequency and its
    distribution over a region does not depend on where the region lies
    (translation invariance, the slide "Perlin's Noise"); pointwise, the
    variance is zero at lattice points and largest between them.

    References
    ----------
    .. [1] K. Perlin, "An image synthesizer", SIGGRAPH 1985.
       https://doi.org/10.1145/325165.325247
    .. [2] K. Perlin, "Improving noise", SIGGRAPH 2002.
       https://doi.org/10.1145/566654.566636

    Examples
    --------
    >>> from texsynth.procedural import perlin
    >>> img = perlin((32, 32), frequency=4, rng=0)
    >>> img.shape, bool(abs(img).max() <= 1)
    ((32, 32), True)
    >>> float(img[0, 0]), float(img[8, 8])       # lattice points (8 px per cell)
    (0.0, 0.0)
    >>> pts = perlin(points=[[0.5, 0.25], [1.0, 1.0]], rng=0)
    >>> float(pts[1])
    0.0
    >>> tile = perlin((16, 16), frequency=4, period=4, rng=1)
    >>> perlin((8, 8, 8), frequency=2, rng=0).shape
    (8, 8, 8)
    """
    fade_fn = _check_fade(fade)
    dt = _check_dtype(dtype)
    perm = _permutation(rng)
    if (shape is None) == (points is None):
        raise ValueError("give exactly one of shape (a grid) or points (lattice coordinates), "
                         f"got shape={shape!r} and points={'None' if points is None else 'an array'}")
    if points is not None:
        pts = _check_points(points)
        ndim = pts.shape[1]
        per = _check_period(period, ndim)
        pts = pts + np.asarray(_check_offset(offset, ndim))
        return _noise_points(pts, perm, per, fade_fn, dt)
    shape = _check_shape(shape)
    frequency = check_positive_float(frequency, "frequency")
    per = _check_period(period, len(shape))
    origin = _check_offset(offset, len(shape))
    return _noise_grid(shape, _pixel_spacing(shape, frequency), origin, perm, per, fade_fn, dt)
