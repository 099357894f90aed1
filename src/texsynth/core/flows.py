"""Two-dimensional flow fields and warping along them.

Flow-guided texture synthesis (Kwatra et al. 2005, Section 4.1) animates a
texture along a sequence of flow fields ``f_1 .. f_{L-1}``, where ``f_i``
says where each pixel of frame ``i`` goes in frame ``i + 1``. This module
builds the kinds of flow the paper shows (Figure 6: sink, source, vortex /
rotation, translation), turns a user array or a callable of time into a
validated flow sequence, and warps images along a flow.

Conventions
-----------
A flow is a float array of shape ``(H, W, 2)``: the displacement
``(d_row, d_col)`` in pixels per frame of the pixel at ``(row, col)``, so the
paper's ``f_i(p) = p + flow[p]``. Rows grow downwards, as in the images;
a positive angle turns counter-clockwise *on screen*.

A flow sequence is ``(L - 1, H, W, 2)``: one flow per frame transition.

Warping is *backward* (semi-Lagrangian): the value of output pixel ``q`` is
read from the input at the point ``p`` with ``p + flow(p) = q``, found by a
few fixed-point iterations ``p <- q - flow(p)`` starting at ``p = q``
(``scipy.ndimage.map_coordinates`` interpolates both the image and the
flow). Backward warping never leaves gaps between pixels, but pixels whose
source lies outside the image have no value: :func:`warp` reports them
(``return_valid=True``) and fills them with ``cval`` in ``mode="constant"``.

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
   for example-based synthesis", ACM Transactions on Graphics (SIGGRAPH
   2005) 24(3), pp. 795-802. :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import numbers
import reprlib

import numpy as np
from scipy import ndimage

from ._validate import (as_image, as_size, check_choice, check_memory, check_positive_int, restore_channels,
                        with_channels)

__all__ = [
    "translation",
    "rotation",
    "vortex",
    "sink",
    "source",
    "flow_sequence",
    "check_flow",
    "warp",
    "warp_coordinates",
    "estimate_flows",
    "WARP_MODES",
    "FLOW_METHODS",
]

#: Optical-flow estimators of :func:`estimate_flows` (scikit-image's).
FLOW_METHODS = ("tvl1", "ilk")

#: Boundary modes of :func:`warp` (and the scipy.ndimage mode each maps to).
WARP_MODES = {"constant": "grid-constant", "wrap": "grid-wrap", "reflect": "reflect", "nearest": "nearest"}


def _field_size(size):
    """``size`` checked, and refused before allocation if a field's arrays (coordinates and the
    (H, W, 2) flow, float64) cannot fit."""
    h, w = as_size(size, "size")
    check_memory(float(h) * w * 8 * 8, (h, w), what="the flow field")
    return h, w


def _grid(size, center):
    """Pixel coordinates relative to ``center`` (default: the image centre)."""
    h, w = _field_size(size)
    if center is None:
        center = ((h - 1) / 2.0, (w - 1) / 2.0)
    try:
        cy, cx = (float(c) for c in center)
    except (TypeError, ValueError):
        raise TypeError(f"center must be a pair (row, col) of numbers, got {center!r}") from None
    rows, cols = np.meshgrid(np.arange(h, dtype=np.float64) - cy, np.arange(w, dtype=np.float64) - cx, indexing="ij")
    return rows, cols


def _real(value, name):
    if not isinstance(value, numbers.Real) or isinstance(value, bool) or not np.isfinite(value):
        raise ValueError(f"{name} must be a finite real number, got {value!r}")
    return float(value)


def translation(size, velocity):
    """Uniform translation: every pixel moves by ``velocity`` per frame.

    Parameters
    ----------
    size : int or (int, int)
        Frame size ``(H, W)``.
    velocity : (float, float)
        Displacement ``(d_row, d_col)`` in pixels per frame.

    Returns
    -------
    numpy.ndarray
        ``(H, W, 2)`` flow.

    Examples
    --------
    >>> translation((2, 3), (0.0, 1.5))[1, 2].tolist()
    [0.0, 1.5]
    """
    h, w = _field_size(size)
    try:
        pair = tuple(velocity)
    except TypeError:
        raise TypeError(f"velocity must be a pair (d_row, d_col), got {velocity!r}") from None
    if len(pair) != 2:
        raise ValueError(f"velocity must be a pair (d_row, d_col), got {reprlib.repr(velocity)}")
    dy, dx = (_real(v, "velocity") for v in pair)
    flow = np.empty((h, w, 2))
    flow[..., 0], flow[..., 1] = dy, dx
    return flow


def rotation(size, angle, *, center=None):
    """Rigid rotation by ``angle`` radians per frame about ``center``.

    The rotational flow of Kwatra et al. 2005, Figure 7. The displacement is
    exact for a rigid rotation, ``f(p) = R (p - c) + c - p``, so points on
    a circle stay on it.

    Parameters
    ----------
    size : int or (int, int)
    angle : float
        Radians per frame, counter-clockwise on screen for ``angle > 0``.
    center : (float, float), optional
        Default: the image centre.

    Returns
    -------
    numpy.ndarray
        ``(H, W, 2)`` flow.

    Examples
    --------
    >>> f = rotation((5, 5), np.pi / 2)
    >>> np.round(f[2, 4], 6).tolist()  # the point right of the centre goes to the top
    [-2.0, -2.0]
    """
    angle = _real(angle, "angle")
    y, x = _grid(size, center)
    c, s = np.cos(angle), np.sin(angle)
    # counter-clockwise on screen: with rows pointing down, (x, -y) turns by +angle
    new_x = c * x + s * y
    new_y = -s * x + c * y
    return np.stack([new_y - y, new_x - x], axis=-1)


def vortex(size, speed, *, center=None, radius=None):
    """A Rankine vortex: swirl that turns fastest at ``radius``.

    Tangential speed ``speed * r / radius`` inside the core ``r < radius``
    (rigid rotation) and ``speed * radius / r`` outside (irrotational), the
    classic model of a whirlpool.

    Parameters
    ----------
    size : int or (int, int)
    speed : float
        Largest tangential speed in pixels per frame (at ``r = radius``);
        positive turns counter-clockwise on screen.
    center : (float, float), optional
        Default: the image centre.
    radius : float, optional
        Core radius in pixels; default a quarter of the smaller side.

    Returns
    -------
    numpy.ndarray
        ``(H, W, 2)`` flow.

    Examples
    --------
    >>> f = vortex((9, 9), 1.0, radius=2.0)
    >>> float(np.hypot(*f[4, 6])), float(np.hypot(*f[4, 8]))
    (1.0, 0.5)
    """
    speed = _real(speed, "speed")
    y, x = _grid(size, center)
    if radius is None:
        radius = min(_field_size(size)) / 4.0
    radius = _real(radius, "radius")
    if radius <= 0:
        raise ValueError(f"radius must be > 0 pixels, got {radius}")
    r = np.hypot(y, x)
    profile = np.where(r < radius, r / radius, radius / np.maximum(r, radius))
    tangential = speed * profile / np.maximum(r, 1e-12)
    # counter-clockwise on screen: the tangent of (row, col) = (y, x) is (-x, y)
    return np.stack([-x * tangential, y * tangential], axis=-1)


def _radial(shape, speed, center, sign):
    speed = _real(speed, "speed")
    if speed < 0:
        raise ValueError(f"speed must be >= 0 pixels per frame, got {speed}")
    y, x = _grid(shape, center)
    r = np.hypot(y, x)
    # constant speed along the radius; a sink stops at the centre instead of overshooting
    step = np.minimum(speed, r) if sign < 0 else np.full_like(r, speed)
    scale = sign * step / np.maximum(r, 1e-12)
    return np.stack([y * scale, x * scale], axis=-1)


def sink(size, speed, *, center=None):
    """Radial inflow at ``speed`` pixels per frame towards ``center``.

    The flow of Kwatra et al. 2005, Figure 1: texture drains into the
    centre. Pixels closer than ``speed`` to the centre move onto it.

    Examples
    --------
    >>> f = sink((5, 5), 1.0)
    >>> f[2, 0].tolist(), f[2, 2].tolist()
    ([0.0, 1.0], [0.0, 0.0])
    """
    return _radial(size, speed, center, -1.0)


def source(size, speed, *, center=None):
    """Radial outflow at ``speed`` pixels per frame away from ``center``.

    Examples
    --------
    >>> source((5, 5), 2.0)[0, 2].tolist()
    [-2.0, 0.0]
    """
    return _radial(size, speed, center, 1.0)


def check_flow(flow, shape=None, name="flow"):
    """Validate one flow field: a finite float array ``(H, W, 2)``.

    Parameters
    ----------
    flow : array_like
    shape : (int, int), optional
        Required spatial shape.
    name : str
        Parameter name for messages.

    Returns
    -------
    numpy.ndarray
        float64 copy.

    Examples
    --------
    >>> check_flow(np.zeros((2, 3, 2))).shape
    (2, 3, 2)
    >>> check_flow(np.zeros((2, 3)))
    Traceback (most recent call last):
    ...
    ValueError: flow must have shape (H, W, 2) holding (d_row, d_col) per pixel, got shape (2, 3)
    """
    arr = np.asarray(flow)
    if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim != 3 or arr.shape[-1] != 2:
        raise ValueError(f"{name} must have shape (H, W, 2) holding (d_row, d_col) per pixel, got shape {arr.shape}")
    if shape is not None and tuple(arr.shape[:2]) != tuple(shape):
        raise ValueError(f"{name} has spatial shape {arr.shape[:2]} but the frames are {tuple(shape)}; pass flows of the frame size")
    arr = arr.astype(np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; pass finite displacements")
    return arr


def flow_sequence(flows, n_frames=None, *, shape=None):
    """Turn a flow description into a validated sequence ``(L - 1, H, W, 2)``.

    Parameters
    ----------
    flows : array_like or callable
        One of

        - ``(H, W, 2)``: a stationary flow, used for every transition
          (``n_frames`` required);
        - ``(L - 1, H, W, 2)``: one flow per transition (time-varying flow);
        - a callable ``flows(i) -> (H, W, 2)`` for ``i = 0 .. L - 2``
          (``n_frames`` required), the flow from frame ``i`` to ``i + 1``.
    n_frames : int, optional
        Number of frames ``L`` (at least 2). Must agree with an array of
        shape ``(L - 1, H, W, 2)`` if both are given.
    shape : (int, int), optional
        Required frame size.

    Returns
    -------
    numpy.ndarray
        ``(L - 1, H, W, 2)`` float64.

    Raises
    ------
    ValueError
        For a wrong shape, NaN, a missing or inconsistent ``n_frames``.

    Examples
    --------
    >>> flow_sequence(translation((4, 4), (0, 1)), n_frames=3).shape
    (2, 4, 4, 2)
    >>> flow_sequence(lambda i: rotation((4, 4), 0.1 * i), n_frames=4).shape
    (3, 4, 4, 2)
    """
    if n_frames is not None:
        n_frames = check_positive_int(n_frames, "n_frames", minimum=2)
    if callable(flows):
        if n_frames is None:
            raise ValueError("n_frames is required when flows is a callable of time; pass n_frames=L (the number of frames)")
        seq = [check_flow(flows(i), shape, name=f"flows({i})") for i in range(n_frames - 1)]
        first = seq[0].shape
        for i, f in enumerate(seq):
            if f.shape != first:
                raise ValueError(f"flows({i}) has shape {f.shape} but flows(0) has {first}; every flow must have the frame size")
        return np.stack(seq)
    arr = np.asarray(flows)
    if arr.ndim == 3:
        if n_frames is None:
            raise ValueError("n_frames is required with a single (H, W, 2) flow; pass n_frames=L, or a (L-1, H, W, 2) sequence")
        one = check_flow(arr, shape, "flows")
        check_memory(float(one.nbytes) * (n_frames - 1), n_frames, "n_frames", "the flow of every frame")
        return np.broadcast_to(one, (n_frames - 1,) + one.shape).copy()
    if arr.ndim != 4 or arr.shape[-1] != 2:
        raise ValueError(
            f"flows must have shape (H, W, 2) or (L-1, H, W, 2), or be a callable of time, got shape {arr.shape}"
        )
    if n_frames is not None and arr.shape[0] != n_frames - 1:
        raise ValueError(f"flows holds {arr.shape[0]} flows, so {arr.shape[0] + 1} frames, but n_frames={n_frames}; pass {n_frames - 1} flows")
    return np.stack([check_flow(f, shape, f"flows[{i}]") for i, f in enumerate(arr)])


def warp(image, flow, *, mode="constant", cval=0.0, spline_order=1, iterations=3, return_valid=False):
    """Move an image's content along a flow for one frame (backward warping).

    Parameters
    ----------
    image : array_like
        ``(H, W)`` or ``(H, W, C)``, any accepted image dtype.
    flow : array_like
        ``(H, W, 2)`` displacement ``(d_row, d_col)`` per pixel of ``image``.
    mode : {"constant", "wrap", "reflect", "nearest"}
        Where a source point outside the image reads from: ``cval``
        ("constant", leaves holes), the opposite edge ("wrap", for tileable
        textures), the mirror image, or the nearest edge pixel.
    cval : float
        Fill value for ``mode="constant"``.
    spline_order : int
        Spline order of the interpolation (0 = nearest, 1 = bilinear, 3 =
        cubic; the result is clipped to [0, 1]).
    iterations : int
        Fixed-point iterations that invert the flow: the source of ``q`` is
        the point ``p`` with ``p + flow(p) = q``. 1 gives the plain
        semi-Lagrangian ``p = q - flow(q)``.
    return_valid : bool
        Also return a boolean ``(H, W)`` map: True where the source point lies
        inside the image (always True for "wrap").

    Returns
    -------
    warped : numpy.ndarray
        Same shape and layout as ``image``.
    valid : numpy.ndarray of bool
        Only with ``return_valid=True``.

    Examples
    --------
    >>> img = np.zeros((4, 5)); img[1, 1] = 1.0
    >>> out = warp(img, translation((4, 5), (1, 2)))
    >>> [int(i) for i in np.argwhere(out > 0.5)[0]]
    [2, 3]
    >>> _, valid = warp(img, translation((4, 5), (0, 2)), return_valid=True)
    >>> valid[0].tolist()
    [False, False, True, True, True]
    """
    img, grey = with_channels(as_image(image, "image"))
    h, w = img.shape[:2]
    flow = check_flow(flow, (h, w))
    check_choice(mode, "mode", WARP_MODES)
    spline_order = check_positive_int(spline_order, "spline_order", minimum=0)
    if spline_order > 5:
        raise ValueError(f"spline_order must be in 0..5, got {spline_order}")
    iterations = check_positive_int(iterations, "iterations")
    cval = _real(cval, "cval")
    src = _source_points(flow, mode, iterations)
    out = np.stack(
        [ndimage.map_coordinates(img[..., k], src, order=spline_order, mode=WARP_MODES[mode], cval=cval)
         for k in range(img.shape[-1])],
        axis=-1,
    )
    np.clip(out, 0.0, 1.0, out=out)
    out = restore_channels(out.astype(img.dtype, copy=False), grey)
    return (out, _inside(src, mode)) if return_valid else out


def _source_points(flow, mode, iterations):
    """``(2, H, W)`` backward sources ``p`` of every pixel ``q``: ``p + flow(p) = q``."""
    h, w = flow.shape[:2]
    flow_mode = "grid-wrap" if mode == "wrap" else "nearest"
    q = np.stack(np.meshgrid(np.arange(h, dtype=np.float64), np.arange(w, dtype=np.float64), indexing="ij"))
    src = q - flow.transpose(2, 0, 1)
    for _ in range(iterations - 1):
        # fixed point of p = q - flow(p): invert the forward displacement
        fp = np.stack([ndimage.map_coordinates(flow[..., k], src, order=1, mode=flow_mode) for k in range(2)])
        src = q - fp
    return src


def _inside(src, mode):
    """True where a source point lies inside the image (always for "wrap")."""
    h, w = src.shape[1:]
    if mode == "wrap":
        return np.ones((h, w), dtype=bool)
    tol = 1e-9
    return (src[0] >= -tol) & (src[0] <= h - 1 + tol) & (src[1] >= -tol) & (src[1] <= w - 1 + tol)


def warp_coordinates(coords, flow, *, mode="nearest", iterations=3, return_valid=False):
    """Move a dense correspondence field along a flow without blurring it.

    ``coords[q]`` is a position in another image (e.g. the exemplar pixel a
    synthesised pixel was copied from). Warping it like an image would
    average the positions of unrelated neighbours across every seam, so each
    output pixel instead takes the correspondence of the pixel nearest to its
    backward source ``p`` and moves it by the sub-pixel remainder:
    ``out[q] = coords[round(p)] + (p - round(p))``. Inside a coherent patch
    (a locally translated copy) this is exact; across a seam it picks one
    side. Reading the other image at the warped positions then costs one
    interpolation in total, however many frames the field was carried along,
    while warping colours frame after frame blurs them again at every frame.

    Parameters
    ----------
    coords : array_like
        ``(H, W, 2)`` positions ``(row, col)``, any real values.
    flow : array_like
        ``(H, W, 2)`` displacement ``(d_row, d_col)`` per pixel.
    mode : {"constant", "wrap", "reflect", "nearest"}
        Where a source point outside the field reads from: "wrap" the
        opposite edge, otherwise the nearest edge pixel (report those
        pixels with ``return_valid=True``).
    iterations : int
        Fixed-point iterations inverting the flow, as in :func:`warp`.
    return_valid : bool
        Also return the boolean ``(H, W)`` map of pixels whose source lies
        inside the field.

    Returns
    -------
    warped : numpy.ndarray
        ``(H, W, 2)`` float64 positions.
    valid : numpy.ndarray of bool
        Only with ``return_valid=True``.

    Examples
    --------
    >>> rows, cols = np.meshgrid(np.arange(4.0), np.arange(5.0), indexing="ij")
    >>> coords = np.stack([rows + 10, cols + 20], axis=-1)  # a copy from (10, 20) on
    >>> out = warp_coordinates(coords, translation((4, 5), (0.0, 1.5)))
    >>> out[2, 3].tolist()  # pixel (2, 3) came from (2, 1.5): position (12, 21.5)
    [12.0, 21.5]
    """
    coords = check_flow(coords, name="coords")
    h, w = coords.shape[:2]
    flow = check_flow(flow, (h, w))
    check_choice(mode, "mode", WARP_MODES)
    iterations = check_positive_int(iterations, "iterations")
    src = _source_points(flow, mode, iterations)
    near = np.rint(src).astype(np.int64)
    if mode == "wrap":
        rows, cols = near[0] % h, near[1] % w
    else:
        rows, cols = np.clip(near[0], 0, h - 1), np.clip(near[1], 0, w - 1)
    # the remainder p - round(p); a source outside the field continues the edge pixel's copy
    rem = src - (near if mode == "wrap" else np.stack([rows, cols]))
    out = coords[rows, cols] + rem.transpose(1, 2, 0)
    return (out, _inside(src, mode)) if return_valid else out


def estimate_flows(frames, *, estimator="tvl1"):
    """Dense optical flow between consecutive frames, as a flow sequence of this module.

    Flow ``i`` says where each pixel of frame ``i`` is in frame ``i + 1``
    (``frames[i][p] ≈ frames[i + 1][p + flows[i][p]]``), the convention of
    :func:`warp` and :func:`flow_sequence`. Colour frames are compared by
    their luminance (``skimage.color.rgb2gray``; other channel counts by
    their mean).

    Parameters
    ----------
    frames : array_like
        ``(T, H, W)`` or ``(T, H, W, C)``, ``T >= 2``.
    estimator : {"tvl1", "ilk"}
        ``"tvl1"``: TV-L1 (``skimage.registration.optical_flow_tvl1``, Zach,
        Pock & Bischof 2007), smooth and robust; ``"ilk"``: iterative
        Lucas-Kanade (``optical_flow_ilk``), about twice as fast, noisier.

    Returns
    -------
    numpy.ndarray
        ``(T - 1, H, W, 2)`` float64 displacements ``(d_row, d_col)``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> from scipy import ndimage
    >>> image = ndimage.gaussian_filter(rng.random((40, 40)), 2)
    >>> frames = np.stack([image, np.roll(image, 1, axis=1)])  # one pixel to the right
    >>> flow = estimate_flows(frames)
    >>> round(float(np.median(flow[0, ..., 1])), 1), round(float(np.median(flow[0, ..., 0])), 1)
    (1.0, 0.0)
    """
    from skimage.registration import optical_flow_ilk, optical_flow_tvl1

    video = as_image(frames, "frames", spatial_dims=3)
    if video.shape[0] < 2:
        raise ValueError(f"frames holds {video.shape[0]} frame; pass at least 2 frames to estimate a flow")
    estimator = check_choice(estimator, "estimator", FLOW_METHODS)
    check_memory(float(video.shape[0]) * video.shape[1] * video.shape[2] * 2 * 8 * 2, video.shape[:3], "frames",
                 "the flows")
    if video.ndim == 4 and video.shape[-1] >= 3:
        from skimage.color import rgb2gray

        grey = np.stack([rgb2gray(f[..., :3]) for f in video])
    else:
        grey = video if video.ndim == 3 else video.mean(axis=-1)
    estimate = optical_flow_tvl1 if estimator == "tvl1" else optical_flow_ilk
    out = np.empty((video.shape[0] - 1,) + video.shape[1:3] + (2,))
    for i in range(video.shape[0] - 1):
        # skimage: reference[p] ≈ moving[p + flow[p]], so frame i as the reference gives the forward flow
        out[i] = np.moveaxis(estimate(grey[i].astype(np.float64), grey[i + 1].astype(np.float64)), 0, -1)
    return out
