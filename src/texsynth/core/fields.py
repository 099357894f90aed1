"""Orientation and magnification fields over an output, and bilinear sampling in local frames.

Zhang et al. 2003 [1]_ control a synthesis with an orientation field
``theta`` and a magnification field ``S`` over the output ("local size control" and
"vector field control" of the lecture's *Synthesis with Local Size/Vector
Field Control*): the neighbourhood of output pixel ``p`` is read at
``p + S(p) R(theta(p)) d`` for every footprint offset ``d``, so the exemplar
appears turned by ``theta`` and magnified by ``S`` there. This module holds
what every method that takes such fields shares:

- :func:`as_field`: a field given as a number, an array of the output's size
  or a callable ``(rows, cols) -> values``, checked;
- :func:`level_field`: the field at a pyramid level;
- :func:`frames`: the per-pixel matrix ``A = S R(theta)`` and its inverse;
- :func:`taps` and :func:`bilinear`: bilinear samples at float positions
  (toroidal or clamped), and :func:`splat`, their adjoint: values added
  back at float positions with the same bilinear weights (:func:`sample`
  and :func:`scatter` do the same from taps computed once).

References
----------
.. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
   progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
   (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344`
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = ["MAGNIFICATION_RANGE", "as_field", "level_field", "frames", "taps", "bilinear", "sample", "splat",
           "scatter"]

#: The magnification factors a field may hold.
MAGNIFICATION_RANGE = (1e-3, 1e3)


def as_field(value, size, name, *, positive=False):
    """A field over the output: None, a number, an array of the output size, or a callable (rows, cols).

    Parameters
    ----------
    value : None, float, array_like or callable
        A number (everywhere), an ``(H, W)`` (or ``(H, W, 1)``) array, or a
        callable ``value(rows, cols)`` of float arrays of output pixel
        coordinates returning the values (broadcast to ``size``).
    size : (int, int)
        The output's ``(H, W)``.
    name : str
        The parameter's name, for the error messages.
    positive : bool
        A magnification factor: every value must lie in :data:`MAGNIFICATION_RANGE`.

    Returns
    -------
    numpy.ndarray or None
        ``(H, W)`` float64, None for None.

    Raises
    ------
    ValueError, TypeError
        For another shape than ``size``, NaN or infinite values, a callable
        that fails on arrays, or (``positive``) values outside
        :data:`MAGNIFICATION_RANGE`; each message names ``name`` and the fix.

    Examples
    --------
    >>> as_field(lambda r, c: 1 + c / 2, (2, 3), "magnification", positive=True)[0].tolist()
    [1.0, 1.5, 2.0]
    >>> as_field(0.0, (2, 3), "magnification", positive=True)
    Traceback (most recent call last):
    ...
    ValueError: magnification must be positive everywhere (a factor: 2 doubles the elements), got a minimum of 0
    """
    if value is None:
        return None
    if callable(value):
        rows, cols = np.meshgrid(np.arange(size[0], dtype=float), np.arange(size[1], dtype=float), indexing="ij")
        try:
            arr = np.asarray(value(rows, cols), dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{name}(rows, cols) must return numbers for arrays of rows and columns of the "
                             f"output; it raised {type(exc).__name__}: {exc}") from exc
        what = f"{name}(rows, cols)"
        try:
            arr = np.broadcast_to(arr, size)
        except ValueError:
            raise ValueError(f"{what} returned shape {arr.shape}; it must return one value per output pixel, "
                             f"shape {tuple(size)}") from None
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        what = name
        arr = np.full(size, float(value))
    else:
        what = name
        arr = np.asarray(value)
        if arr.dtype == object or arr.dtype == bool or not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
            raise TypeError(f"{name} must be a number, an array of the output size {tuple(size)} or a callable "
                            f"(rows, cols) -> values, got {type(value).__name__} of dtype {arr.dtype}")
        if arr.ndim == 3 and arr.shape[-1] == 1:
            arr = arr[..., 0]
        if arr.shape != tuple(size):
            raise ValueError(f"{name} has shape {arr.shape} but the output size is {tuple(size)}; pass one "
                             f"value per output pixel, a number, or a callable (rows, cols) -> values")
        arr = arr.astype(np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{what} contains NaN or infinite values")
    if positive and arr.min() <= 0:
        raise ValueError(f"{what} must be positive everywhere (a factor: 2 doubles the elements), got a minimum "
                         f"of {arr.min():.4g}")
    low, high = MAGNIFICATION_RANGE
    if positive and (arr.min() < low or arr.max() > high):
        raise ValueError(f"{what} must lie in [{low:g}, {high:g}] (a texture magnified or "
                         f"shrunk more shows one pixel or nothing), got values in [{arr.min():.4g}, {arr.max():.4g}]")
    return arr


def level_field(output_field, level, shape):
    """The field at a pyramid level: pixel ``p`` of the level lies over output pixel ``2^level p``.

    ``output_field`` is an ``(H, W)`` field of the output's size (as :func:`as_field` gives it),
    ``shape`` the level's ``(h, w)``.

    Examples
    --------
    >>> level_field(np.arange(16.0).reshape(4, 4), 1, (2, 2)).tolist()
    [[0.0, 2.0], [8.0, 10.0]]
    """
    step = 2**level
    return np.ascontiguousarray(output_field[::step, ::step][: shape[0], : shape[1]])


def frames(orientation, magnification):
    """Per pixel the matrix ``A = S R(orientation)`` (exemplar offsets to output offsets) and its inverse.

    ``orientation`` and ``magnification`` (``S``) are arrays of one shape (angles in radians, factors).
    ``R(orientation)`` turns the texture counter-clockwise as the image is shown
    (rows down): the exemplar's rightward offset ``(0, 1)`` becomes
    ``(-sin, cos)``, upward for 90 degrees. Returns ``(A, A^-1)``, each ``(N, 2, 2)``.

    Examples
    --------
    >>> a, inverse = frames(np.array([np.pi / 2]), np.array([2.0]))
    >>> np.round(a[0] @ [0.0, 1.0], 6).tolist()  # rightward becomes upward, twice as long
    [-2.0, 0.0]
    """
    cos, sin = np.cos(orientation), np.sin(orientation)
    a = np.stack([np.stack([cos, -sin], -1), np.stack([sin, cos], -1)], -2) * magnification[..., None, None]
    inverse = np.stack([np.stack([cos, sin], -1), np.stack([-sin, cos], -1)], -2) / magnification[..., None, None]
    return a.reshape(-1, 2, 2), inverse.reshape(-1, 2, 2)


def taps(positions, height, width, wrap):
    """Flat indices ``(..., 4)`` and weights of the bilinear taps of float (row, col) ``positions`` ``(..., 2)``.

    On an image of ``height x width`` pixels: toroidal with ``wrap``, else positions clamped to it.

    Examples
    --------
    >>> index, weight = taps(np.array([[0.5, 1.0]]), 2, 3, wrap=False)
    >>> index.tolist(), weight.tolist()
    ([[1, 2, 4, 5]], [[0.5, 0.0, 0.5, 0.0]])
    """
    h, w = height, width
    if wrap:
        r, col = positions[..., 0], positions[..., 1]
    else:
        r, col = np.clip(positions[..., 0], 0, h - 1), np.clip(positions[..., 1], 0, w - 1)
    r0, c0 = np.floor(r), np.floor(col)
    fr, fc = r - r0, col - c0
    r0, c0 = r0.astype(np.intp), c0.astype(np.intp)
    if wrap:
        r0, c0 = r0 % h, c0 % w
        r1, c1 = (r0 + 1) % h, (c0 + 1) % w
    else:
        r1, c1 = np.minimum(r0 + 1, h - 1), np.minimum(c0 + 1, w - 1)
    index = np.stack([r0 * w + c0, r0 * w + c1, r1 * w + c0, r1 * w + c1], -1)
    weight = np.stack([(1 - fr) * (1 - fc), (1 - fr) * fc, fr * (1 - fc), fr * fc], -1)
    return index, weight


def bilinear(image, positions, *, wrap, done=None, spread=None):
    """Bilinear samples of an ``(h, w, C)`` image at float (row, col) ``positions`` ``(..., 2)``.

    ``wrap``: toroidal (the output); otherwise positions are clamped to the
    image (the exemplar). With ``done`` (a flat bool per pixel) only done
    pixels count: the value is their weighted mean and ``known`` their share
    of the bilinear weight (0 where none is done). With ``spread`` (``(...)``
    half-widths, in pixels) each value is the mean of the bilinear samples at
    ``positions - spread`` and ``positions + spread`` along both axes: a tent filter that
    also sees the pixels between the samples of a magnified footprint. Returns ``(value, known)``.

    Examples
    --------
    >>> image = np.arange(6.0).reshape(2, 3, 1)
    >>> bilinear(image, np.array([[0.5, 1.0]]), wrap=False)[0].tolist()
    [[2.5]]
    """
    h, w, c = image.shape
    if spread is None:
        index, weight = taps(positions, h, w, wrap)
    else:
        shift = spread[..., None]
        i1, w1 = taps(positions - shift, h, w, wrap)
        i2, w2 = taps(positions + shift, h, w, wrap)
        index, weight = np.concatenate([i1, i2], -1), np.concatenate([w1, w2], -1) / 2
    return sample(image, index, weight, done=done)


def sample(image, tap_indices, tap_weights, *, done=None):
    """:func:`bilinear` from its taps: the sums of ``image``'s flat pixels ``tap_indices`` ``(..., K)``
    weighted by ``tap_weights`` ``(..., K)`` (both as :func:`taps` gives them).

    For taps computed once and sampled many times (the neighbourhoods of an
    EM loop); ``done`` as in :func:`bilinear`. Returns ``(value, known)``.

    Examples
    --------
    >>> image = np.arange(6.0).reshape(2, 3, 1)
    >>> sample(image, *taps(np.array([[0.5, 1.0]]), 2, 3, wrap=False))[0].tolist()
    [[2.5]]
    """
    h, w, c = image.shape
    weight = tap_weights
    if done is not None:
        weight = weight * done[tap_indices]
    weight = weight.astype(image.dtype, copy=False)
    values = image.reshape(h * w, c)[tap_indices]
    known = weight.sum(-1)
    value = np.einsum("...k,...kc->...c", weight, values)
    if done is not None:
        value /= np.maximum(known, 1e-12)[..., None]
    return value, known


def splat(values, positions, weights, shape, *, wrap):
    """Add ``values`` ``(..., C)`` at float (row, col) ``positions`` ``(..., 2)`` into an ``(H, W)`` image: the adjoint of :func:`bilinear`.

    Each value is spread over the four pixels around its position with the
    bilinear weights of :func:`taps` times its own ``weights`` ``(...)``
    (toroidal with ``wrap``, else positions clamped to the image as
    :func:`bilinear` clamps them). Returns the weighted sums ``(H, W, C)``
    and the summed weights ``(H, W)`` (float64), whose ratio is the weighted
    average of the values that reach each pixel.

    Examples
    --------
    >>> sums, total = splat(np.array([[4.0]]), np.array([[0.5, 0.0]]), np.array([1.0]), (2, 2), wrap=False)
    >>> sums[..., 0].tolist(), total.tolist()
    ([[2.0, 0.0], [2.0, 0.0]], [[0.5, 0.0], [0.5, 0.0]])
    """
    index, tap = taps(positions, shape[0], shape[1], wrap)
    return scatter(values, index, tap * np.asarray(weights, np.float64)[..., None], shape)


def scatter(values, tap_indices, tap_weights, shape):
    """:func:`splat` from taps: ``values`` ``(..., C)`` added to the flat pixels ``tap_indices`` ``(..., K)`` with
    ``tap_weights`` ``(..., K)``. Returns the weighted sums ``(H, W, C)`` and the summed weights ``(H, W)``.

    Examples
    --------
    >>> sums, total = scatter(np.array([[4.0]]), np.array([[0, 3]]), np.array([[0.25, 0.75]]), (2, 2))
    >>> sums[..., 0].tolist(), total.tolist()
    ([[1.0, 0.0], [0.0, 3.0]], [[0.25, 0.0], [0.0, 0.75]])
    """
    h, w = shape
    index = tap_indices.reshape(-1)
    weight = tap_weights
    total = np.bincount(index, weight.reshape(-1), minlength=h * w).reshape(h, w)
    sums = [np.bincount(index, (weight * values[..., c, None]).reshape(-1), minlength=h * w)
            for c in range(values.shape[-1])]
    return np.stack(sums, -1).reshape(h, w, -1), total
