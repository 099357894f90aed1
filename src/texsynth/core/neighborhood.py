"""Neighbourhoods: patch extraction, shapes, fall-off weights and scatter-average.

This is the shared layer every patch- and pixel-based algorithm stands on.
Images here are channels-last ``(H, W, C)`` float arrays (public functions
convert user input to float in [0, 1] and add a channel axis to grey
images first; docs/conventions.md).

Positions are patch *centres* ``(row, col)``; a patch of size ``(h, w)``
centred at ``(r, c)`` covers rows ``r - h//2 ... r - h//2 + h - 1`` (for even
sizes the centre is the lower-right of the middle four pixels).

Boundary modes
--------------
``"valid"``
    Every patch lies inside the image; centres outside that range raise.
``"wrap"``
    Toroidal indexing (tileable output, FFT-consistent).
``"reflect"``
    Mirror about the edge pixels (``numpy.pad(mode="reflect")``).

The inverse of extraction is :func:`accumulate`, which adds weighted patches
back into an image and divides by the summed weights: the E-step of texture
optimization (Kwatra et al. 2005, eq. 1 minimised over x) and the blend of
patch-based methods.
"""

from __future__ import annotations

import numbers
import reprlib

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from ._parallel import parallel_for
from ._validate import as_size, check_choice, check_memory, check_positive_float, is_auto, max_threads

__all__ = [
    "MODES",
    "patch_shape",
    "all_patches",
    "patches_within",
    "grid_axes",
    "grid_cells",
    "extract",
    "accumulate",
    "PatchSum",
    "grid_centers",
    "gaussian_falloff",
    "causal_mask",
    "SHAPES",
    "footprint",
    "causal_parts",
    "mask_offsets",
    "wavefronts",
    "multilevel_vectors",
    "plane_vectors",
]

MODES = ("valid", "wrap", "reflect")
#: Footprints of a neighbourhood inside its ``(h, w)`` box: the whole box, or the inscribed disc (ellipse).
SHAPES = ("square", "disc")
# PatchSum adds a grid's patches on several threads from this many values on (below, a thread costs more
# than it saves)
_THREADED_VALUES = 2**20
# plane_vectors gathers the neighbourhoods of this many slices at once (bounds its temporaries)
_SLICE_CHUNK = 8


def patch_shape(patch_size, name="patch_size"):
    """Normalise a patch size: an int means square.

    >>> patch_shape(5), patch_shape((3, 4))
    ((5, 5), (3, 4))
    """
    if isinstance(patch_size, numbers.Integral) and not isinstance(patch_size, bool):
        patch_size = (int(patch_size), int(patch_size))
    try:
        h, w = patch_size
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an int or a pair (height, width), got {patch_size!r}") from None
    if not all(isinstance(s, numbers.Integral) and not isinstance(s, bool) for s in (h, w)):
        raise TypeError(f"{name} must hold integers, got {patch_size!r}")
    if h < 1 or w < 1:
        raise ValueError(f"{name} must be positive, got ({h}, {w})")
    return int(h), int(w)


def _check_fits(image_shape, size, name="patch_size"):
    h, w = size
    if h > image_shape[0] or w > image_shape[1]:
        raise ValueError(
            f"{name} ({h}, {w}) is larger than the image ({image_shape[0]}, {image_shape[1]}); "
            f"pass a smaller {name} or a larger image"
        )


def _check_channels_last(image, name="image"):
    if not isinstance(image, np.ndarray) or image.ndim != 3:
        shape = getattr(image, "shape", None)
        raise ValueError(
            f"{name} must be a channels-last array (H, W, C), got shape {shape}; "
            "add a channel axis with image[..., None]"
        )


def _index(coords, length, mode, name):
    """Map integer coordinates to valid indices along one axis."""
    if mode == "wrap":
        return np.mod(coords, length)
    if mode == "reflect":
        if length == 1:
            return np.zeros_like(coords)
        period = 2 * (length - 1)
        folded = np.mod(coords, period)
        return np.where(folded < length, folded, period - folded)
    if coords.size and (coords.min() < 0 or coords.max() >= length):
        raise ValueError(
            f"{name} reach outside the image (axis length {length}) in mode='valid'; "
            "move the centres inside or use mode='wrap' or 'reflect'"
        )
    return coords


def _patch_coords(centers, size, shape, mode):
    """Row and column indices ``(N, h)`` and ``(N, w)`` of patches at ``centers``."""
    centers = np.asarray(centers)
    if centers.ndim != 2 or centers.shape[1] != 2 or not np.issubdtype(centers.dtype, np.integer):
        raise ValueError(
            f"centers must be an integer array of shape (N, 2) holding (row, col), "
            f"got dtype {centers.dtype} and shape {centers.shape}"
        )
    h, w = size
    rows = centers[:, :1] - h // 2 + np.arange(h)
    cols = centers[:, 1:] - w // 2 + np.arange(w)
    return _index(rows, shape[0], mode, "patches"), _index(cols, shape[1], mode, "patches")


def patches_within(mask, patch_size):
    """Which patches lie wholly on the True pixels of a mask: ``(H - h + 1, W - w + 1)`` bool by top-left corner.

    One summed-area table of the False pixels, so the cost does not grow with the patch size (a
    minimum over every window of :func:`all_patches` reads ``h w`` values per patch).

    Parameters
    ----------
    mask : array_like of bool
        ``(H, W)``; True where a patch may lie.
    patch_size : int or (int, int)

    Examples
    --------
    >>> m = np.ones((4, 5), bool); m[1, 3] = False
    >>> patches_within(m, 2).astype(int).tolist()
    [[1, 1, 0, 0], [1, 1, 0, 0], [1, 1, 1, 1]]
    """
    h, w = patch_shape(patch_size)
    m = np.asarray(mask, dtype=bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be a 2-D (H, W) array of bool, got shape {m.shape}")
    bad = np.zeros((m.shape[0] + 1, m.shape[1] + 1), dtype=np.int64)
    bad[1:, 1:] = np.cumsum(np.cumsum(~m, axis=0), axis=1)
    return (bad[h:, w:] - bad[:-h, w:] - bad[h:, :-w] + bad[:-h, :-w]) == 0


def all_patches(image, patch_size, *, mode="valid"):
    """Every patch of an image, as a read-only view (no copy).

    Parameters
    ----------
    image : numpy.ndarray
        ``(H, W, C)``.
    patch_size : int or (int, int)
        Patch size ``(h, w)``.
    mode : {"valid", "wrap", "reflect"}
        ``"valid"`` gives ``(H - h + 1, W - w + 1)`` patches, indexed by their
        top-left corner. ``"wrap"`` and ``"reflect"`` give ``(H, W)`` patches,
        the one at ``[i, j]`` centred at pixel ``(i, j)`` (the image is padded
        first, so those two modes copy the image once).

    Returns
    -------
    numpy.ndarray
        View of shape ``(Ny, Nx, h, w, C)``.

    Examples
    --------
    >>> img = np.arange(12.0).reshape(3, 4, 1)
    >>> all_patches(img, 2).shape
    (2, 3, 2, 2, 1)
    >>> all_patches(img, 3, mode="wrap")[0, 0, :, :, 0]
    array([[11.,  8.,  9.],
           [ 3.,  0.,  1.],
           [ 7.,  4.,  5.]])
    """
    _check_channels_last(image)
    check_choice(mode, "mode", MODES)
    h, w = patch_shape(patch_size)
    _check_fits(image.shape, (h, w))
    if mode != "valid":
        pads = ((h // 2, h - 1 - h // 2), (w // 2, w - 1 - w // 2), (0, 0))
        image = np.pad(image, pads, mode=mode)
    view = sliding_window_view(image, (h, w), axis=(0, 1))  # (Ny, Nx, C, h, w)
    return np.moveaxis(view, 2, -1)


def extract(image, centers, patch_size, *, mode="wrap"):
    """Copy the patches centred at arbitrary positions.

    Parameters
    ----------
    image : numpy.ndarray
        ``(H, W, C)``.
    centers : array_like of int, shape (N, 2)
        Patch centres ``(row, col)``: a regular sparse grid
        (:func:`grid_centers`) or any irregular positions.
    patch_size : int or (int, int)
        Patch size.
    mode : {"wrap", "reflect", "valid"}
        Boundary handling; ``"valid"`` raises if a patch leaves the image.

    Returns
    -------
    numpy.ndarray
        ``(N, h, w, C)``.

    Examples
    --------
    >>> img = np.arange(16.0).reshape(4, 4, 1)
    >>> extract(img, [[0, 0]], 2, mode="wrap")[0, :, :, 0]
    array([[15., 12.],
           [ 3.,  0.]])
    """
    _check_channels_last(image)
    check_choice(mode, "mode", MODES)
    patch_size = patch_shape(patch_size)
    _check_fits(image.shape, patch_size)
    rows, cols = _patch_coords(centers, patch_size, image.shape, mode)
    return image[rows[:, :, None], cols[:, None, :]]


def accumulate(patches, centers, shape, *, patch_weights=None, pixel_weights=None, mode="wrap"):
    """Weighted average of overlapping patches: the inverse of :func:`extract`.

    Computes, for every pixel ``x``,
    ``out(x) = sum_p a_p b(x - p) z_p(x) / sum_p a_p b(x - p)``
    where ``a_p`` are the per-patch weights (e.g. IRLS weights) and ``b`` the
    per-pixel weights (e.g. a Gaussian fall-off). This is the closed-form
    minimiser of the texture energy over the output (Kwatra et al. 2005, the
    E-step of Algorithm 1). One :class:`PatchSum` with all the patches added
    at once; add them in parts with :class:`PatchSum` to bound the memory.

    Parameters
    ----------
    patches : numpy.ndarray
        ``(N, h, w, C)``. Integer or bool patches are averaged in float64, in
        their own units (no scaling to [0, 1]).
    centers : array_like of int, shape (N, 2)
        Where each patch is centred.
    shape : (int, int)
        Spatial shape ``(H, W)`` of the output.
    patch_weights : array_like, shape (N,), optional
        Non-negative weight per patch.
    pixel_weights : array_like, shape (h, w) or (N, h, w), optional
        Non-negative weight per patch pixel.
    mode : {"wrap", "reflect", "valid"}
        Must match the extraction mode; ``"reflect"`` adds an outside pixel
        to its mirror image (the adjoint of reflect extraction).

    Returns
    -------
    image : numpy.ndarray
        ``(H, W, C)``, float32 for float32 patches, float64 otherwise; pixels
        that no patch covers (zero total weight) are 0.
    weight : numpy.ndarray
        ``(H, W)`` total weight per pixel.

    Examples
    --------
    Extracting every patch and averaging them back reproduces the image:

    >>> img = np.random.default_rng(0).random((5, 6, 2))
    >>> centers = np.argwhere(np.ones((5, 6), bool))
    >>> out, weight = accumulate(extract(img, centers, 3), centers, (5, 6))
    >>> bool(np.allclose(out, img)), float(weight.min())
    (True, 9.0)
    """
    patches = _as_patches(patches)
    acc = PatchSum(shape, patches.shape[-1], mode=mode)
    acc.add(patches, centers, patch_weights=patch_weights, pixel_weights=pixel_weights)
    return acc.average(patches.dtype)


def _as_patches(patches):
    patches = np.asarray(patches)
    if patches.ndim != 4:
        raise ValueError(f"patches must have shape (N, h, w, C), got {patches.shape}")
    if not np.issubdtype(patches.dtype, np.floating):  # an average of integers is not an integer
        patches = patches.astype(np.float64)
    return patches


def _as_weights(weights, name):
    try:
        return np.asarray(weights, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an array of non-negative numbers, got {reprlib.repr(weights)}") from None


class PatchSum:
    """Weighted sums of patches added into an image, part by part; :meth:`average` divides.

    The running sums ``sum_p a_p b(x - p) z_p(x)`` and ``sum_p a_p b(x - p)``
    of :func:`accumulate`, kept in float64, so a caller can add the patches
    of a large grid a few rows at a time (the memory then grows with the
    output, not with the number of patches times their size).

    Patches whose centres form a rectilinear grid (every combination of some
    rows and some columns, in row-major order, as :func:`grid_centers` and
    its row-major slices give) are added without index arrays: the grid's
    rows and columns are split into phases whose patches do not overlap, and
    each phase's patches are laid side by side and added as one block. Any
    other centres, and ``"reflect"`` mode (where a patch may fold onto
    itself), are added with ``numpy.bincount``.

    Parameters
    ----------
    shape : (int, int)
        Spatial shape ``(H, W)`` of the image.
    channels : int
        Channels ``C`` of the patches.
    mode : {"wrap", "reflect", "valid"}
        As :func:`accumulate`.

    Examples
    --------
    >>> img = np.random.default_rng(0).random((8, 9, 3))
    >>> centers = grid_centers((8, 9), 4, 2, mode="valid")
    >>> acc = PatchSum((8, 9), 3, mode="valid")
    >>> for part in np.array_split(np.arange(len(centers)), 3):
    ...     acc.add(extract(img, centers[part], 4, mode="valid"), centers[part])
    >>> bool(np.allclose(acc.average()[0], img))
    True
    """

    def __init__(self, shape, channels, *, mode="wrap"):
        check_choice(mode, "mode", MODES)
        self.shape = height, width = as_size(shape, "shape")
        self.mode = mode
        check_memory(float(height) * width * (channels + 1) * 8 * 2, (height, width), "shape", "the accumulated image")
        self.sums = np.zeros((height, width, channels))
        self.total = np.zeros((height, width))

    def add(self, patches, centers, *, patch_weights=None, pixel_weights=None):
        """Add ``patches`` ``(N, h, w, C)`` centred at ``centers``, weighted as in :func:`accumulate`."""
        patches = _as_patches(patches)
        n, h, w, c = patches.shape
        if c != self.sums.shape[-1]:
            raise ValueError(f"patches have {c} channels but this sum holds {self.sums.shape[-1]}")
        rows, cols = _patch_coords(centers, (h, w), self.shape, self.mode)
        if rows.shape[0] != n:
            raise ValueError(f"centers holds {rows.shape[0]} positions but patches holds {n}; pass one centre per patch")
        pw = np.ones((1, h, w))
        if pixel_weights is not None:
            pw = _as_weights(pixel_weights, "pixel_weights")
            if pw.shape not in {(h, w), (n, h, w)}:
                raise ValueError(f"pixel_weights must have shape ({h}, {w}) or ({n}, {h}, {w}), got {pw.shape}")
            pw = pw.reshape((-1, h, w))
        aw = np.ones(n)
        if patch_weights is not None:
            aw = _as_weights(patch_weights, "patch_weights")
            if aw.shape != (n,):
                raise ValueError(f"patch_weights must have shape ({n},), got {aw.shape}")
        for name, wt in (("pixel_weights", pw), ("patch_weights", aw)):
            if wt.size and not (np.isfinite(wt).all() and wt.min() >= 0):
                raise ValueError(f"{name} must be finite and non-negative; "
                                 "replace NaN or negative weights (e.g. np.nan_to_num, np.clip)")
        if n == 0:
            return
        grid = self._grid(np.asarray(centers), (h, w)) if self.mode != "reflect" else None
        if grid is None:
            self._scatter(patches, rows, cols, aw, pw)
        else:
            self._blocks(patches, grid, aw, pw)

    def average(self, dtype=np.float64):
        """The weighted average ``(H, W, C)`` (0 where nothing was added) and the total weight ``(H, W)``."""
        out = np.zeros_like(self.sums)
        np.divide(self.sums, self.total[..., None], out=out, where=self.total[..., None] > 0)
        return out.astype(dtype, copy=False), self.total

    def _scatter(self, patches, rows, cols, aw, pw):
        n, h, w, c = patches.shape
        height, width = self.shape
        weight = aw[:, None, None] * pw
        flat = (rows[:, :, None] * width + cols[:, None, :]).ravel()
        weight = np.broadcast_to(weight, (n, h, w)).ravel()
        self.total += np.bincount(flat, weights=weight, minlength=height * width).reshape(height, width)
        weighted = (patches.reshape(-1, c) * weight[:, None])
        for k in range(c):
            self.sums[..., k] += np.bincount(flat, weights=weighted[:, k], minlength=height * width).reshape(height,
                                                                                                              width)

    def _grid(self, centers, size):
        """The grid's rows and columns and their non-overlapping phases, or None if ``centers`` is no grid."""
        axes = grid_axes(centers[:, 0], centers[:, 1])
        if axes is None:
            return None
        r, c = axes
        phases = [_phases(r, size[0], self.shape[0], self.mode), _phases(c, size[1], self.shape[1], self.mode)]
        if phases[0] is None or phases[1] is None:
            return None
        return r, c, phases

    def _blocks(self, patches, grid, aw, pw):
        n, h, w, ch = patches.shape
        r, c, (rphases, cphases) = grid
        nr, nc = r.shape[0], c.shape[0]
        z = patches.reshape(nr, nc, h, w, ch)
        a = aw.reshape(nr, nc)
        b = pw.reshape((nr, nc, h, w) if pw.shape[0] == n else (1, 1, h, w))
        # a phase's patches do not overlap, so its grid rows can be added by several threads at once, each
        # into its own rows of the image (the same additions in the same order: the same sums, bit for bit)
        threads = max_threads() if patches.size >= _THREADED_VALUES else 1

        def add_rows(ri, ci, cols):
            rows = _index((r[ri, None] - h // 2 + np.arange(h)).ravel(), self.shape[0], self.mode, "patches")
            sel = np.ix_(ri, ci)
            wt = a[sel][:, :, None, None] * (b[sel] if b.shape[0] > 1 else b)
            wt = wt.transpose(0, 2, 1, 3).reshape(rows.shape[0], cols.shape[0])
            # weighted in float64 like the total: in a float32 block a tiny weight (Wexler's confidence far from
            # the known pixels, 1.3^-d) underflows to 0 while the total keeps it, which averaged pixels to black
            block = z[sel].transpose(0, 2, 1, 3, 4).reshape(rows.shape[0], cols.shape[0], ch) * wt[..., None]
            for at, part in _spans(rows, cols, self.shape):
                self.total[at] += wt[part]
                self.sums[at] += block[part]

        for ri in rphases:
            parts = np.array_split(ri, min(threads, ri.shape[0]))
            for ci in cphases:
                cols = _index((c[ci, None] - w // 2 + np.arange(w)).ravel(), self.shape[1], self.mode, "patches")
                parallel_for(lambda i: add_rows(parts[i], ci, cols), len(parts), threads)


def grid_axes(rows, cols):
    """The grid's rows and columns if the points ``(rows, cols)`` are every combination of them in
    row-major order (as :func:`grid_centers` gives them), else None.

    Examples
    --------
    >>> [a.tolist() for a in grid_axes(np.array([0, 0, 5, 5]), np.array([1, 3, 1, 3]))]
    [[0, 5], [1, 3]]
    >>> grid_axes(np.array([0, 5]), np.array([1, 3])) is None
    True
    """
    r, c = np.unique(rows), np.unique(cols)
    if r.shape[0] * c.shape[0] != rows.shape[0]:
        return None
    if not (np.array_equal(rows, np.repeat(r, c.shape[0])) and np.array_equal(cols, np.tile(c, r.shape[0]))):
        return None
    return r, c


def grid_cells(centers):
    """The centres ``(N, 2)`` on the grid of their distinct rows and columns: ``(cells, gi, gj)``.

    ``cells`` ``(rows, cols)`` holds each centre's index at its cell and -1 at
    cells no centre takes (a part of a grid, e.g. the neighbourhoods near a
    hole); centre ``n`` sits at ``cells[gi[n], gj[n]]`` unless another centre
    repeats its position (the later one is kept).

    Examples
    --------
    >>> cells, gi, gj = grid_cells(np.array([[0, 1], [0, 3], [5, 3]]))
    >>> cells.tolist(), gi.tolist(), gj.tolist()
    ([[0, 1], [-1, 2]], [0, 0, 1], [0, 1, 1])
    """
    rows, gi = np.unique(centers[:, 0], return_inverse=True)
    cols, gj = np.unique(centers[:, 1], return_inverse=True)
    gi, gj = gi.ravel(), gj.ravel()
    cells = np.full((rows.shape[0], cols.shape[0]), -1, dtype=np.int64)
    cells[gi, gj] = np.arange(centers.shape[0])
    return cells, gi, gj


def _spans(rows, cols, shape):
    """Pairs (where in the image, which part of the block) that add a block at ``rows x cols``.

    Runs of consecutive indices (also across a wrapped edge) become slices, at
    most two per axis; any other axis keeps its index array.
    """
    per_axis = []
    for idx, extent in zip((rows, cols), shape):
        n = idx.shape[0]
        start = int(idx[0])
        if n <= extent and np.array_equal((idx - start) % extent, np.arange(n)):
            head = min(n, extent - start)
            pieces = [(slice(start, start + head), slice(0, head))]
            if head < n:
                pieces.append((slice(0, n - head), slice(head, n)))
        else:
            pieces = [(idx, slice(None))]
        per_axis.append(pieces)
    for (r_at, r_part) in per_axis[0]:
        for (c_at, c_part) in per_axis[1]:
            if isinstance(r_at, slice) and isinstance(c_at, slice):
                yield (r_at, c_at), (r_part, c_part)
            else:  # index arrays on both axes
                yield np.ix_(np.arange(shape[0])[r_at], np.arange(shape[1])[c_at]), (r_part, c_part)


def _phases(coords, length, extent, mode):
    """Split sorted grid coordinates into groups whose patches (``length`` long) do not overlap.

    Greedy: each coordinate joins the first group whose last patch ends before
    it starts (and, wrapping, whose first patch starts after it ends). None if
    a patch overlaps itself (longer than a wrapped axis).
    """
    if mode == "wrap" and length > extent:
        return None
    groups = []
    for i, x in enumerate(coords.tolist()):
        for g in groups:
            if x - coords[g[-1]] >= length and (mode != "wrap" or coords[g[0]] + extent - x >= length):
                g.append(i)
                break
        else:
            groups.append([i])
    return [np.asarray(g) for g in groups]


def grid_centers(shape, patch_size, grid_spacing, *, mode="wrap"):
    """Centres of a regular grid of patches that covers every pixel.

    Parameters
    ----------
    shape : (int, int)
        Image shape ``(H, W)``.
    patch_size : int or (int, int)
        Patch size; the grid must not leave gaps, so ``spacing <= size``.
    grid_spacing : int or (int, int)
        Distance between neighbouring centres (Kwatra et al. 2005 use w/4).
    mode : {"wrap", "reflect", "valid"}
        ``"valid"`` keeps every patch inside the image and adds a last row
        and column of centres flush with the far edges, so the border is
        covered.

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` int64 centres in row-major order.

    Examples
    --------
    >>> grid_centers((8, 8), 4, 2, mode="valid")[:3].tolist()
    [[2, 2], [2, 4], [2, 6]]
    """
    check_choice(mode, "mode", MODES)
    shape = as_size(shape, "shape")
    patch_size = patch_shape(patch_size)
    step = patch_shape(grid_spacing, "grid_spacing")
    check_memory(16.0 * (shape[0] / step[0] + 2) * (shape[1] / step[1] + 2), shape, "shape", "the grid's centres")
    axes = []
    for length, s, d in zip(shape, patch_size, step):
        if d > s:
            raise ValueError(f"grid_spacing {step} is larger than patch_size {patch_size}; the grid would leave gaps")
        if mode == "valid":
            if s > length:
                raise ValueError(f"patch_size {patch_size} is larger than the image {tuple(shape)}; pass a smaller patch_size")
            first, last = s // 2, length - s + s // 2
            coords = np.arange(first, last + 1, d)
            if coords[-1] != last:
                coords = np.append(coords, last)
        else:
            coords = np.arange(0, length, d)
        axes.append(coords)
    rr, cc = np.meshgrid(*axes, indexing="ij")
    return np.stack([rr.ravel(), cc.ravel()], axis=1).astype(np.int64)


def gaussian_falloff(patch_size, sigma="auto"):
    """Gaussian weights over a patch, 1 at the centre.

    Parameters
    ----------
    patch_size : int or (int, int)
    sigma : float or "auto"
        Standard deviation in pixels. ``"auto"`` (default): ``max(h, w) / 4``, so the
        weight at the middle of an edge is ``exp(-2) ~ 0.14``.

    Returns
    -------
    numpy.ndarray
        ``(h, w)``.

    Examples
    --------
    >>> g = gaussian_falloff(5)
    >>> float(g[2, 2]), bool(g[0, 0] < g[0, 2] < g[2, 2])
    (1.0, True)
    """
    h, w = patch_shape(patch_size)
    check_memory(24.0 * h * w, (h, w), "patch_size", "the mask")
    sigma = max(h, w) / 4.0 if is_auto(sigma) else check_positive_float(sigma, "sigma")
    y = np.arange(h) - h // 2
    x = np.arange(w) - w // 2
    r2 = (y[:, None] ** 2 + x[None, :] ** 2) / 2.0
    return np.exp(-(r2 / sigma) / sigma)  # (divided twice: sigma**2 overflows for sigma above 1e154)


def causal_mask(patch_size):
    """The causal (L-shaped) neighbourhood of scanline synthesis.

    True for the pixels already synthesised when the centre is visited in
    scanline order: every row above the centre, and the pixels left of it in
    its row (Wei & Levoy 2000, Figure 2). The centre itself is excluded.

    Examples
    --------
    >>> causal_mask(3).astype(int)
    array([[1, 1, 1],
           [1, 0, 0],
           [0, 0, 0]])
    """
    h, w = patch_shape(patch_size)
    check_memory(1.0 * h * w, (h, w), "patch_size", "the mask")
    mask = np.zeros((h, w), dtype=bool)
    mask[: h // 2] = True
    mask[h // 2, : w // 2] = True
    return mask


def footprint(patch_size, shape="square"):
    """The pixels of an ``(h, w)`` neighbourhood box that its footprint keeps.

    ``"square"``: the whole box (Wei & Levoy 2000). ``"disc"``: the ellipse
    inscribed in the box, ``(dy / (h/2))^2 + (dx / (w/2))^2 <= 1`` (a disc
    when ``h == w``; 3x3 keeps all 9 pixels, 5x5 drops the 4 corners, 21
    left), which compares the same distance in every direction.

    Examples
    --------
    >>> footprint(5, "disc").astype(int)
    array([[0, 1, 1, 1, 0],
           [1, 1, 1, 1, 1],
           [1, 1, 1, 1, 1],
           [1, 1, 1, 1, 1],
           [0, 1, 1, 1, 0]])
    """
    h, w = patch_shape(patch_size)
    check_memory(1.0 * h * w, (h, w), "patch_size", "the mask")
    check_choice(shape, "shape", SHAPES)
    if shape == "square":
        return np.ones((h, w), bool)
    dy = (np.arange(h) - h // 2) / (h / 2)
    dx = (np.arange(w) - w // 2) / (w / 2)
    return dy[:, None] ** 2 + dx[None, :] ** 2 <= 1.0


def causal_parts(patch_size, shape="square"):
    """The parts of a neighbourhood that scanline synthesis tells apart, inside its :func:`footprint`.

    Returns ``(above, left, full)``, boolean ``(h, w)`` masks: the causal
    rows above the centre (known for a whole scanline at once), the causal
    pixels left of the centre in its row (known one at a time; every
    footprint keeps the whole centre row, so these are always the ``w // 2``
    pixels left of it) and the full non-causal neighbourhood without its
    centre. ``above | left`` is the footprint's part of :func:`causal_mask`.

    Examples
    --------
    >>> above, left, full = causal_parts(3)
    >>> int(above.sum()), int(left.sum()), int(full.sum())
    (3, 1, 8)
    """
    h, w = patch_shape(patch_size)
    foot = footprint((h, w), shape)
    above = np.zeros((h, w), bool)
    above[: h // 2] = True
    left = causal_mask((h, w)) & ~above & foot
    full = foot.copy()
    full[h // 2, w // 2] = False
    return above & foot, left, full


def mask_offsets(mask):
    """``(row, col)`` offsets from the centre ``(h // 2, w // 2)`` of the True pixels of a neighbourhood mask.

    Examples
    --------
    >>> mask_offsets(causal_mask(3)).tolist()
    [[-1, -1], [-1, 0], [-1, 1], [0, -1]]
    """
    mask = np.asarray(mask, dtype=bool)
    h, w = mask.shape
    return np.argwhere(mask) - [h // 2, w // 2]


def wavefronts(height, width, step):
    """Pixels (flat indices) grouped by wavefront ``j + step * i`` of the scanline order, and the groups' bounds.

    With ``step = w // 2 + 1`` every causal neighbour of pixel ``(i, j)`` in
    an ``(h, w)`` box (rows above within ``w // 2`` columns, pixels to its
    left) lies on an earlier wavefront and every other pixel of its box on a
    later one, so the pixels of one wavefront can be synthesised together
    with the result of the scanline order. Wavefront ``t`` holds the pixels
    ``order[bounds[t]:bounds[t + 1]]``.

    Examples
    --------
    >>> order, bounds = wavefronts(2, 3, 2)
    >>> [order[bounds[t]:bounds[t + 1]].tolist() for t in range(len(bounds) - 1)]
    [[0], [1], [2, 3], [4], [5]]
    """
    t = (np.arange(width)[None, :] + step * np.arange(height)[:, None]).ravel()
    order = np.argsort(t, kind="stable")
    return order, np.searchsorted(t[order], np.arange(t.max() + 2))


def multilevel_vectors(image, parent, centers, patch_size, parent_size, *, mode="wrap", mask=None, parent_mask=None):
    """Neighbourhood vectors that join this pyramid level with its parent.

    The vector of a pixel is its (optionally masked, e.g. causal) neighbourhood
    at this level followed by the (optionally masked) neighbourhood of the
    corresponding pixel ``center // 2`` at the next coarser level (Wei & Levoy
    2000, Section 3.2; Kwatra et al. 2005, Section 3.2).

    Parameters
    ----------
    image, parent : numpy.ndarray
        ``(H, W, C)`` and ``(ceil(H/2), ceil(W/2), C)`` (or any coarser level
        whose pixel ``(i // 2, j // 2)`` lies under ``(i, j)``). ``parent``
        None: this level's neighbourhood alone (the coarsest level).
    centers : array_like of int, shape (N, 2)
    patch_size, parent_size : int or (int, int)
    mode : {"wrap", "reflect", "valid"}
    mask : numpy.ndarray of bool, shape size, optional
        Which pixels of this level's neighbourhood to keep.
    parent_mask : numpy.ndarray of bool, shape parent_size, optional
        Which pixels of the parent's neighbourhood to keep (default all).

    Returns
    -------
    numpy.ndarray
        ``(N, n_here * C + n_parent * C)``.

    Examples
    --------
    >>> img, par = np.zeros((8, 8, 1)), np.ones((4, 4, 1))
    >>> v = multilevel_vectors(img, par, [[4, 4]], 5, 3, mask=causal_mask(5))
    >>> v.shape, float(v.sum())
    ((1, 21), 9.0)
    >>> multilevel_vectors(img, par, [[4, 4]], 5, 3, mask=causal_mask(5), parent_mask=footprint(3, "disc")).shape
    (1, 21)
    >>> multilevel_vectors(img, None, [[4, 4]], 5, 3, mask=causal_mask(5)).shape
    (1, 12)
    """
    centers = np.asarray(centers)
    here = extract(image, centers, patch_size, mode=mode)
    if mask is not None:
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != patch_shape(patch_size):
            raise ValueError(f"mask must have shape {patch_shape(patch_size)}, got {mask.shape}")
        here = here[:, mask]
    if parent is None:
        return here.reshape(len(centers), -1)
    coarse = extract(parent, centers // 2, parent_size, mode=mode)
    if parent_mask is not None:
        parent_mask = np.asarray(parent_mask, dtype=bool)
        if parent_mask.shape != patch_shape(parent_size):
            raise ValueError(f"parent_mask must have shape {patch_shape(parent_size)}, got {parent_mask.shape}")
        coarse = coarse[:, parent_mask]
    return np.concatenate([here.reshape(len(centers), -1), coarse.reshape(len(centers), -1)], axis=1)


def plane_vectors(volume, parent, axis, patch_size, parent_size, *, mask=None, parent_mask=None):
    """Multi-level neighbourhood vectors of every voxel of a volume, in the plane perpendicular to ``axis``.

    The 3-D counterpart of :func:`multilevel_vectors` at every position,
    toroidal: the neighbourhood of voxel ``v`` is the ``patch_size`` window
    (its ``mask`` pixels) of the slice through ``v`` across ``axis``, joined
    to the ``parent_size`` window (its ``parent_mask`` pixels) around the
    voxel ``v // 2`` of ``parent`` in its slice across ``axis`` (Wei's solid
    textures: the view along axis ``a`` constrains the slices across ``a``).
    The slices are stacked as channels, so the 2-D extraction handles a few
    of them at once.

    Parameters
    ----------
    volume, parent : numpy.ndarray
        ``(D, H, W, C)`` and its coarser level ``(ceil(D/2), ceil(H/2),
        ceil(W/2), C)``, or None (this level alone).
    axis : {0, 1, 2}
        The axis across which the neighbourhoods lie: 0 takes the windows of
        ``volume[d]`` (rows H, columns W), 1 those of ``volume[:, h]`` (rows
        D, columns W), 2 those of ``volume[:, :, w]`` (rows D, columns H).
    patch_size, parent_size : int or (int, int)
    mask, parent_mask : numpy.ndarray of bool, optional
        Which pixels of each window to keep (default all).

    Returns
    -------
    numpy.ndarray
        ``(D * H * W, n_here * C + n_parent * C)``, one row per voxel in C
        order.

    Examples
    --------
    >>> vol = np.arange(4 * 4 * 4, dtype=float).reshape(4, 4, 4, 1)
    >>> v = plane_vectors(vol, None, 0, 3, 1)
    >>> v.shape, bool(np.array_equal(v[5], vol[0, :3, :3, 0].ravel()))
    ((64, 9), True)
    """
    size = patch_shape(patch_size)
    mask = np.ones(size, bool) if mask is None else np.asarray(mask, dtype=bool)
    vol = np.moveaxis(volume, axis, 2)  # (P0, P1, S, C): plane axes first
    p0, p1, s, c = vol.shape
    pvol = None
    if parent is not None:  # parent voxel of (i, j, k) is (i//2, j//2, k//2)
        pvol = np.repeat(np.moveaxis(parent, axis, 2), 2, axis=2)[:, :, :s]
    centers = np.argwhere(np.ones((p0, p1), bool))
    n_here = int(mask.sum())
    result = None
    for s0 in range(0, s, _SLICE_CHUNK):
        chunk = slice(s0, min(s, s0 + _SLICE_CHUNK))
        ns = chunk.stop - chunk.start
        img = vol[:, :, chunk].reshape(p0, p1, ns * c)
        pim = None if pvol is None else pvol[:, :, chunk].reshape(pvol.shape[0], pvol.shape[1], ns * c)
        v = multilevel_vectors(img, pim, centers, size, parent_size, mode="wrap", mask=mask, parent_mask=parent_mask)
        parts = [v[:, : n_here * ns * c].reshape(p0 * p1, n_here, ns, c)]
        if pim is not None:
            parts.append(v[:, n_here * ns * c :].reshape(p0 * p1, -1, ns, c))
        # (P0*P1, ns, n, C) -> one row per voxel, vector = [here..., parent...]
        v = np.concatenate([np.swapaxes(q, 1, 2).reshape(p0 * p1, ns, -1) for q in parts], axis=2)
        if result is None:
            result = np.empty((p0, p1, s, v.shape[-1]), dtype=volume.dtype)
        result[:, :, chunk] = v.reshape(p0, p1, ns, -1)
    return np.moveaxis(result, 2, axis).reshape(-1, result.shape[-1])
