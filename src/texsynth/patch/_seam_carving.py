"""Avidan & Shamir's seam carving: content-aware resizing by removing and inserting seams of low energy.

A *vertical seam* is an 8-connected path of pixels from the top row to the
bottom row, one pixel per row (``|x(i) - x(i-1)| <= 1``); a horizontal seam
likewise from left to right, one pixel per column. Removing a seam narrows
(lowers) the image by one pixel and keeps the rest of the image intact; the
seam removed is the one of least energy (Avidan & Shamir 2007, Section 3):

1. the energy of every pixel is the gradient magnitude
   ``e1(I) = |dI/dx| + |dI/dy|`` (the paper's eq. 1), summed over channels;
2. the optimal seam minimises ``E(s) = sum_i e(I(s_i))`` (eq. 4) and is found
   by dynamic programming, ``M(i, j) = e(i, j) + min(M(i-1, j-1), M(i-1, j),
   M(i-1, j+1))``, then traced back from the smallest entry of the last row
   (:func:`texsynth.core.seams.cumulative_cost` and
   :func:`~texsynth.core.seams.backtrack`, which quilting's boundary cut uses too);
3. for resizing in both directions, the order of vertical and horizontal
   seams is the one of least total energy, found by dynamic programming over
   the *transport map* ``T(r, c)`` (Section 4.3);
4. enlarging inserts the ``k`` seams that removal would take first, each
   duplicated (Section 4.2), and object removal gives masked pixels a strongly
   negative energy (protected ones a strongly positive one) and removes seams
   until no masked pixel is left, then inserts seams to restore the size
   (Section 4.6).

The energy is kept between seams and recomputed only where the removed seam
changed it (two pixels per row), so a seam costs one DP and one copy of the
image. The *forward energy* of Rubinstein, Shamir & Avidan 2008 (the cost of
the new edges a removal creates) is an option.

What could not be checked against the paper's text (it was not at hand;
the steps follow its published description, a slide deck of the paper and
public implementations): the discretisation of the gradient (here
central differences with replicated borders, halved), the exact form of the
transport-map recurrence (an internally consistent form is used), the
averaging rule of inserted seams (here: the seam pixel stays and a new pixel,
the mean of it and its right or lower neighbour, follows it), the fraction of
the size by which one insertion step may enlarge (here at most half), the
magnitude of the mask energies, and the paper's section numbers.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (
    as_array,
    as_image,
    as_size,
    check_bool,
    check_memory,
    restore_channels,
    with_channels,
)
from ..core.coordinates import compact_slots
from ..core.seams import backtrack, cumulative_cost

__all__ = ["SeamCarvingInfo", "carve_seams"]

ENERGIES = ("backward", "forward")
ORDERS = ("optimal", "alternate", "vertical-first", "horizontal-first")
ENLARGE_STEP = 0.5  # one insertion step adds at most half of the current width (height); larger ones repeat
_AXIS = {"vertical": 1, "horizontal": 0}  # the axis a seam removes a pixel along


@dataclass
class SeamCarvingInfo:
    """What :func:`carve_seams` did.

    Attributes
    ----------
    seams : list of (str, numpy.ndarray)
        The seams removed, in order: ``("vertical", columns)`` (one column per
        row) or ``("horizontal", rows)`` (one row per column), each in the
        coordinates of the image it was removed from.
    costs : numpy.ndarray
        The energy ``E(s)`` of each removed seam, as minimised (mask energies
        included).
    n_removed, n_inserted : (int, int)
        Rows and columns removed (horizontal and vertical seams), and inserted.
    source : numpy.ndarray
        ``(H', W', 2)`` int: the input pixel ``(row, column)`` that each output
        pixel shows (an inserted pixel: the seam pixel it duplicates).
    inserted : numpy.ndarray
        ``(H', W')`` bool: the pixels that insertion added.
    removal_size : (int, int)
        The size after object removal, before any seams were inserted or
        removed to reach ``size`` (the input's size without ``remove_mask``).
    order : str
        The order of the seams removed to reach ``size``.
    transport_map : numpy.ndarray or None
        ``order="optimal"``: ``T(r, c)``, the least total energy of removing
        ``r`` rows and ``c`` columns (Section 4.3).
    coordinates : numpy.ndarray
        The source-coordinate map of ``docs/conventions.md``, which
        :func:`texsynth.apply_coordinates` renders other channels of the
        image through (a height or normal map resized like the photo).
        Seams removed only: ``(H', W', 2)``, equal to ``source``, every
        pixel a copy. Seams inserted: ``(H', W', K, 2)``, the input pixels
        each output pixel averages, largest weight first (an inserted pixel
        is the mean of two, which may themselves be inserted ones; the
        shares of one input pixel are added up, so ``K`` stays small: 2
        for insertion in one direction, 4 in both, in our measurements).
    weights : numpy.ndarray or None
        None after removal only; with inserted seams ``(H', W', K)``, the
        weights of ``coordinates`` (sums of powers of 1/2, summing to 1).
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"object removal"``, ``"order"`` (the transport map), ``"removal"``,
        ``"insertion"``: the stages that ran.
    """

    seams: list
    costs: np.ndarray
    n_removed: tuple
    n_inserted: tuple
    source: np.ndarray
    inserted: np.ndarray
    removal_size: tuple
    order: str
    transport_map: np.ndarray | None = None
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


# --------------------------------------------------------------------------
# Eq. 1: the gradient-magnitude energy, everywhere and at given pixels


def _abs_diff(a, b):
    """``sum_c |a - b|`` over the last axis, channel by channel (3 times faster than ``.sum(-1)`` over 3)."""
    out = np.abs(a[..., 0] - b[..., 0]).astype(np.float64, copy=False)
    for c in range(1, a.shape[-1]):
        out += np.abs(a[..., c] - b[..., c])
    return out


def gradient_energy(image):
    """``e1 = (|I(x+1) - I(x-1)| + |I(y+1) - I(y-1)|) / 2`` summed over channels, borders replicated."""
    p = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
    return (_abs_diff(p[1:-1, 2:], p[1:-1, :-2]) + _abs_diff(p[2:, 1:-1], p[:-2, 1:-1])) / 2


def _energy_at(image, rows, cols):
    """:func:`gradient_energy` at the pixels ``(rows, cols)`` only (the same arithmetic, bit for bit)."""
    h, w = image.shape[:2]
    left, right = np.maximum(cols - 1, 0), np.minimum(cols + 1, w - 1)
    up, down = np.maximum(rows - 1, 0), np.minimum(rows + 1, h - 1)
    return (_abs_diff(image[rows, right], image[rows, left]) + _abs_diff(image[down, cols], image[up, cols])) / 2


def _forward_costs(image):
    """Rubinstein et al. 2008's forward energy for vertical seams: the pixel cost ``C_U`` and the side steps.

    Removing pixel ``(i, j)`` joins ``(i, j-1)`` and ``(i, j+1)``: ``C_U = |I(i,j+1) - I(i,j-1)|``; a seam
    coming from the upper left also joins ``(i-1, j)`` and ``(i, j-1)`` (``C_L = C_U + |I(i-1,j) - I(i,j-1)|``),
    from the upper right ``(i-1, j)`` and ``(i, j+1)`` (``C_R``). ``C_U`` is common to the three steps and is
    returned as the pixel cost; the side steps return only their extra term.
    """
    p = np.pad(image, ((0, 0), (1, 1), (0, 0)), mode="edge")
    left, right = p[:, :-2], p[:, 2:]
    cu = _abs_diff(right, left)
    cl, cr = np.zeros_like(cu), np.zeros_like(cu)
    cl[1:] = _abs_diff(image[:-1], left[1:])
    cr[1:] = _abs_diff(image[:-1], right[1:])
    return cu, cl, cr


# --------------------------------------------------------------------------
# An image being carved, with what travels along with it


def _remove_along(array, seam, axis):
    """``array`` without one pixel per row (``axis=1``, a vertical seam) or per column (``axis=0``).

    Each pixel's values are moved as one opaque item (a numpy void view): 5-10 times faster than
    ``take_along_axis`` over the channels.
    """
    a = np.ascontiguousarray(array)
    h, w = a.shape[:2]
    tail = a.shape[2:]
    items = a.reshape(h, w, -1).view(np.dtype((np.void, a.dtype.itemsize * int(np.prod(tail, dtype=int)))))
    items = items.reshape(h, w)
    if axis == 1:
        keep = np.ones((h, w), dtype=bool)
        keep[np.arange(h), seam] = False
        out = items[keep].reshape(h, w - 1)
    else:
        out = items[:-1].copy()
        np.copyto(out, items[1:], where=np.arange(h - 1)[:, None] >= seam[None, :])
    return out.view(a.dtype).reshape(out.shape + tail)


class _Carver:
    """The image, its energy, the mask energy and the source positions, carried through removals."""

    def __init__(self, image, bias, energy, source=None, inserted=None, removing=None):
        self.image, self.bias, self.kind = image, bias, energy
        self.source, self.inserted, self.removing = source, inserted, removing
        self.blend = None  # (coordinates (H, W, K, 2), weights (H, W, K)) of every pixel, once insertion blends
        self.energy = self._full_energy() if energy == "backward" or callable(energy) else None

    @property
    def shape(self):
        return self.image.shape[:2]

    def _full_energy(self):
        if callable(self.kind):
            e = _custom_energy(self.kind, self.image)
        else:
            e = gradient_energy(self.image)
        return e if self.bias is None else e + self.bias

    def seam(self, direction):
        """The optimal seam (eq. 4 by dynamic programming) and its energy."""
        transpose = direction == "horizontal"  # a horizontal seam is a vertical one of the transposed image
        steps = None
        if self.kind == "forward":
            image = np.ascontiguousarray(self.image.transpose(1, 0, 2)) if transpose else self.image
            cost, cl, cr = _forward_costs(image)
            if self.bias is not None:
                cost += self.bias.T if transpose else self.bias
            steps = (cl, None, cr)
        else:
            # (the DP runs along rows: a contiguous copy is 5 times faster than a transposed view)
            cost = np.ascontiguousarray(self.energy.T) if transpose else self.energy
        m = cumulative_cost(cost, step_costs=steps)  # M(i,j) = e(i,j) + min(M(i-1,j-1), M(i-1,j), M(i-1,j+1))
        seam = backtrack(m, step_costs=steps)
        return seam, float(m[-1, seam[-1]])

    def removed(self, direction, seam):
        """A new carver without the seam; the energy is recomputed only next to it."""
        axis = _AXIS[direction]
        out = _Carver.__new__(_Carver)
        out.kind, out.blend = self.kind, None  # (seams are removed before any is inserted)
        out.image = _remove_along(self.image, seam, axis)
        for name in ("bias", "source", "inserted", "removing"):
            value = getattr(self, name)
            setattr(out, name, None if value is None else _remove_along(value, seam, axis))
        if self.energy is None:
            out.energy = None
        elif callable(self.kind):
            out.energy = out._full_energy()
        else:
            energy = _remove_along(self.energy, seam, axis)
            # the pixels whose neighbours changed: the two beside the seam in each row (column)
            along = np.arange(seam.size)
            near = np.concatenate([seam - 1, seam])
            near = np.clip(near, 0, out.shape[axis] - 1)
            lines = np.concatenate([along, along])
            rows, cols = (lines, near) if axis == 1 else (near, lines)
            values = _energy_at(out.image, rows, cols)
            if out.bias is not None:
                values = values + out.bias[rows, cols]
            energy[rows, cols] = values
            out.energy = energy
        return out

    def inserted_seams(self, direction, k, on_seam=None):
        """Enlarge by ``k`` seams: find the ``k`` that removal would take, then duplicate each (Section 4.2)."""
        axis = _AXIS[direction]
        copy = _Carver(self.image, self.bias, self.kind)
        n_lines = self.shape[1 - axis]
        position = np.broadcast_to(np.arange(self.shape[axis]), (n_lines, self.shape[axis]))
        copy.source = np.ascontiguousarray(position if axis == 1 else position.T)[..., None]
        chosen = np.empty((k, n_lines), dtype=np.intp)
        for t in range(k):
            seam, _ = copy.seam(direction)
            along = np.arange(n_lines)
            chosen[t] = copy.source[along, seam, 0] if axis == 1 else copy.source[seam, along, 0]
            if t < k - 1:
                copy = copy.removed(direction, seam)
            if on_seam is not None:
                on_seam()
        return self._duplicate(chosen, axis)

    def _duplicate(self, chosen, axis):
        """Insert after each chosen pixel a new one, the mean of it and its next neighbour."""
        out = _Carver.__new__(_Carver)
        out.kind = self.kind
        flip = (lambda a: a) if axis == 1 else (lambda a: None if a is None else a.swapaxes(0, 1))
        image = flip(self.image)
        h, w = image.shape[:2]
        k = chosen.shape[0]
        dup = np.zeros((h, w), dtype=bool)
        dup[np.arange(h)[None, :], chosen] = True
        after = np.cumsum(dup, axis=1)  # duplicates at or before each pixel
        rows = np.arange(h)[:, None]
        keep_at = np.arange(w)[None, :] + after - dup  # where each pixel goes
        new_at = keep_at + 1  # where its duplicate goes
        r_dup, c_dup = np.nonzero(dup)
        nxt = np.minimum(c_dup + 1, w - 1)

        def spread(values, duplicate_values):
            result = np.empty((h, w + k) + values.shape[2:], dtype=values.dtype)
            result[rows, keep_at] = values
            result[r_dup, new_at[r_dup, c_dup]] = duplicate_values
            return result

        def back(a):
            return a if axis == 1 else np.ascontiguousarray(a.swapaxes(0, 1))

        out.image = back(spread(image, (image[r_dup, c_dup] + image[r_dup, nxt]) / 2))
        for name in ("bias", "source"):
            value = flip(getattr(self, name))
            setattr(out, name, None if value is None else back(spread(value, value[r_dup, c_dup])))
        out.blend = None
        if self.blend is not None:  # the new pixel's sources: half of each of the two it averages
            coords, weights = (flip(a) for a in self.blend)
            both, halves = _merged(np.concatenate([coords[r_dup, c_dup], coords[r_dup, nxt]], axis=1),
                                   np.concatenate([weights[r_dup, c_dup], weights[r_dup, nxt]], axis=1) / 2)
            coords = np.concatenate([coords, np.zeros_like(coords)], axis=2)  # 2K slots for every pixel
            weights = np.concatenate([weights, np.zeros_like(weights)], axis=2)
            out.blend = compact_slots(back(spread(coords, both)), back(spread(weights, halves)))
        inserted = flip(self.inserted)
        out.inserted = back(spread(inserted, np.ones(r_dup.size, dtype=bool)))
        removing = flip(self.removing)
        out.removing = None if removing is None else back(spread(removing, removing[r_dup, c_dup]))
        out.energy = out._full_energy() if out.kind == "backward" or callable(out.kind) else None
        return out


def _merged(coords, weights):
    """Blend slots ``(n, K, 2)``, ``(n, K)`` with the weights of equal coordinates summed into one slot (the
    others 0): the two pixels an inserted one averages often share sources, and unmerged, the slots
    would double with every insertion step."""
    codes = coords[..., 0] * (int(coords[..., 1].max()) + 1) + coords[..., 1]
    order = np.argsort(codes, axis=1, kind="stable")
    codes = np.take_along_axis(codes, order, axis=1)
    coords = np.take_along_axis(coords, order[..., None], axis=1)
    weights = np.take_along_axis(weights, order, axis=1).copy()
    for k in range(codes.shape[1] - 1, 0, -1):  # right to left: runs of equal codes add up in their first slot
        same = codes[:, k] == codes[:, k - 1]
        weights[same, k - 1] += weights[same, k]
        weights[same, k] = 0
    return coords, weights


def _custom_energy(energy, image):
    values = np.asarray(energy(image), dtype=np.float64)
    if values.shape != image.shape[:2] or not np.all(np.isfinite(values)):
        raise ValueError(f"energy(image) must return a finite map of the image's shape {image.shape[:2]}, got "
                         f"shape {values.shape}{'' if values.shape != image.shape[:2] else ' with NaN or inf'}")
    return values


# --------------------------------------------------------------------------
# Section 4.3: the order of vertical and horizontal seams


def _sequence(order, n_rows, n_cols):
    """The directions of ``n_rows`` horizontal and ``n_cols`` vertical seams in a fixed order."""
    v, h = ["vertical"] * n_cols, ["horizontal"] * n_rows
    if order == "vertical-first":
        return v + h
    if order == "horizontal-first":
        return h + v
    out = []  # alternate, starting with the direction that has more seams to remove
    first, second = (v, h) if n_cols >= n_rows else (h, v)
    for i in range(max(len(first), len(second))):
        out += first[i:i + 1] + second[i:i + 1]
    return out


def _transport_map(state, n_rows, n_cols, bar):
    """The optimal order (Section 4.3) by dynamic programming over ``T(r, c)``.

    ``T(r, c) = min(T(r-1, c) + E(s_y(I_{r-1,c})), T(r, c-1) + E(s_x(I_{r,c-1})))``, ``T(0, 0) = 0``, where
    ``I_{r,c}`` is the image reached with ``r`` rows and ``c`` columns removed along the better of its two
    predecessors. Only one line of images is kept: the ones of the previous ``r``.
    Returns the directions in removal order and ``T``.
    """
    T = np.zeros((n_rows + 1, n_cols + 1))
    horizontal = np.zeros((n_rows + 1, n_cols + 1), dtype=bool)  # reached by removing a row
    line = [state]
    for c in range(1, n_cols + 1):
        seam, cost = line[-1].seam("vertical")
        line.append(line[-1].removed("vertical", seam))
        T[0, c] = T[0, c - 1] + cost
        bar.advance()
    for r in range(1, n_rows + 1):
        seam, cost = line[0].seam("horizontal")
        line[0] = line[0].removed("horizontal", seam)
        T[r, 0], horizontal[r, 0] = T[r - 1, 0] + cost, True
        bar.advance()
        for c in range(1, n_cols + 1):
            up, left = line[c], line[c - 1]  # I_{r-1,c} and I_{r,c-1}
            h_seam, h_cost = up.seam("horizontal")
            v_seam, v_cost = left.seam("vertical")
            if T[r - 1, c] + h_cost <= T[r, c - 1] + v_cost:
                T[r, c], horizontal[r, c] = T[r - 1, c] + h_cost, True
                line[c] = up.removed("horizontal", h_seam)
            else:
                T[r, c] = T[r, c - 1] + v_cost
                line[c] = left.removed("vertical", v_seam)
            bar.advance()
    directions, r, c = [], n_rows, n_cols
    while r or c:
        if horizontal[r, c]:
            directions.append("horizontal")
            r -= 1
        else:
            directions.append("vertical")
            c -= 1
    return directions[::-1], T


# --------------------------------------------------------------------------
# Checks


def _check_energy(energy):
    if callable(energy):
        return energy
    if not isinstance(energy, str) or energy not in ENERGIES:
        raise ValueError(f"energy must be 'backward' (the paper's e1), 'forward' (Rubinstein et al. 2008) or a "
                         f"callable image -> (H, W) energy map, got {energy!r}")
    return energy


def _check_order(order):
    if not isinstance(order, str) or order not in ORDERS:
        raise ValueError(f"order must be one of {', '.join(repr(o) for o in ORDERS)}, got {order!r}")
    return order


def _as_mask(mask, shape, name):
    if mask is None:
        return None
    arr = as_array(mask, name)
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == np.bool_) \
            or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(f"{name} must be a bool (or 0/1) array of the image's shape {shape}, got dtype {arr.dtype}")
    if arr.shape != shape:
        raise ValueError(f"{name} must have the image's shape {shape} (one value per pixel), got {arr.shape}")
    if arr.dtype != np.bool_:
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} contains NaN or infinite values; pass a bool mask")
        arr = arr > 0.5
    return arr


def _check_memory(shape, target, channels, itemsize, n_line):
    """The images of a run (input, output and a few of their size) and the transport map's line of images."""
    pixels = float(max(shape[0], target[0])) * max(shape[1], target[1])
    per_pixel = channels * itemsize * 4 + 8 * 6 + 16 * 2
    line = float(shape[0]) * shape[1] * (channels * itemsize + 8 * 2) * n_line
    check_memory(pixels * per_pixel + line, target, "size", "the carved image" +
                 (f" and the transport map's line of {n_line} images (order='alternate' needs none)"
                  if n_line > 1 else ""), also={"order": "'optimal'"} if n_line > 1 else None)


# --------------------------------------------------------------------------
# The method


def carve_seams(image, size=None, *, energy="backward", order="optimal", enlarge=True, remove_mask=None,
                protect_mask=None, return_info=False, progress=False):
    """Resize an image by seam carving: remove or insert seams of least energy (Avidan & Shamir 2007).

    Examples
    --------
    >>> import texsynth
    >>> photo = texsynth.data.load("wood")[:64, :64]
    >>> out, info = texsynth.carve_seams(photo, (56, 48), return_info=True)
    >>> out.shape, info.n_removed, len(info.seams)
    ((56, 48, 3), (8, 16), 24)
    >>> texsynth.carve_seams(photo, (64, 80)).shape  # 16 columns inserted
    (64, 80, 3)

    Removes (or inserts) one 8-connected path of pixels across the image at
    a time, the one of least energy (eq. 1), found by dynamic programming,
    so the image changes size where its content is least noticeable [1]_.

    Parameters
    ----------
    image : array_like
        ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    size : int or (int, int), optional
        Output size ``(height, width)``. Smaller than the image: seams are
        removed; larger: seams are inserted (with ``enlarge=True``). Default
        None: the image's own size (with ``remove_mask``: object removal,
        then seams inserted to restore the size).
    energy : {"backward", "forward"} or callable
        ``"backward"``: the paper's gradient magnitude ``e1 = |dI/dx| +
        |dI/dy|`` (eq. 1), summed over channels. ``"forward"``: the forward
        energy of Rubinstein, Shamir & Avidan 2008, the intensity jumps that a
        removal creates between the pixels it brings together (fewer broken
        straight edges; about twice as slow). A callable ``energy(image) ->
        (H, W)`` map is recomputed on the whole image after every seam.
    order : {"optimal", "alternate", "vertical-first", "horizontal-first"}
        When both height and width shrink: ``"optimal"`` removes the rows and
        columns in the order of least total energy, the paper's transport-map
        dynamic programme (Section 4.3; it finds ``(r + 1)(c + 1)`` pairs of
        seams for ``r`` rows and ``c`` columns, so it is slow for large
        ``r c``); ``"alternate"`` alternates vertical and horizontal seams
        (one seam each); the others remove all of one direction first.
        Inserted seams are always vertical first.
    enlarge : bool
        Allow inserting seams (Section 4.2). False refuses a ``size`` larger
        than the image and, with ``remove_mask``, leaves the image as small
        as object removal made it (or smaller, if ``size`` asks for it).
    remove_mask : array_like of bool, shape (H, W), optional
        Object removal: pixels to remove. They get a strongly negative
        energy, and seams (vertical if the object is narrower than tall,
        else horizontal) are removed until no masked pixel is left.
    protect_mask : array_like of bool, shape (H, W), optional
        Pixels to keep: a strongly positive energy keeps seams out of them
        (unless every seam must cross them).
    return_info : bool
        Also return a :class:`SeamCarvingInfo` (the seams, their energies, the
        source of every output pixel).
    progress : bool or callable
        Report progress per seam (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    image : numpy.ndarray
        ``size``, the input's channel layout; float32 for float32 input,
        float64 otherwise.
    info : SeamCarvingInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If ``size`` is larger than the image and ``enlarge=False``; for masks
        of the wrong shape or overlapping; if the object cannot be removed
        without crossing ``protect_mask``; if the work would not fit in memory.
    TypeError
        For arguments of the wrong type.

    Notes
    -----

    The energy (eq. 1) is

    .. math:: e_1(I) = \\left|\\frac{\\partial I}{\\partial x}\\right| + \\left|\\frac{\\partial I}{\\partial y}\\right|

    (central differences, halved, borders replicated; summed over channels),
    and the optimal vertical seam minimises ``E(s) = sum_i e(I(s_i))`` over
    8-connected paths with one pixel per row, by the dynamic programme

    .. math:: M(i, j) = e(i, j) + \\min(M(i-1, j-1),\\, M(i-1, j),\\, M(i-1, j+1))

    traced back from the smallest ``M`` of the last row
    (:mod:`texsynth.core.seams`). After a removal only the energy of the two
    pixels beside the seam in each row is recomputed (a pixel's ``e1`` depends
    on its four neighbours only).

    *Forward energy* (Rubinstein et al. 2008, eq. 5) adds to ``M`` the jumps
    between the pixels a removal makes neighbours: ``C_U = |I(i, j+1) -
    I(i, j-1)|`` for every step, plus ``|I(i-1, j) - I(i, j-1)|`` from the
    upper left and ``|I(i-1, j) - I(i, j+1)|`` from the upper right.

    *Optimal order* (Section 4.3): with ``T(r, c)`` the least energy of
    removing ``r`` rows and ``c`` columns,

    .. math:: T(r, c) = \\min\\big(T(r-1, c) + E(s^y(I_{r-1,c})),\\; T(r, c-1) + E(s^x(I_{r,c-1}))\\big)

    and the order is traced back from ``T(r, c)``; only the images of one
    line of ``T`` are kept.

    *Enlarging* by ``k`` (Section 4.2): the ``k`` seams that removal would
    take are found on a copy, and each of their pixels in the original is
    followed by a new pixel, the mean of it and its right (lower) neighbour
    (the original pixels are untouched, so removing the inserted pixels gives
    the input back exactly). An enlargement of more than half the width is
    done in steps of at most half.

    *Object removal* (Section 4.6): masked pixels get the energy ``-L`` and
    protected ones ``+L``, with ``L`` more than any seam's energy, so a seam
    takes as many masked pixels as it can and avoids protected ones.

    Seam carving works where an image has regions of low energy (sky, water,
    walls) between its objects; it bends straight lines and squeezes objects
    once those regions are used up, and faces and regular structures (rows of
    windows) show it first; protect them with ``protect_mask``.

    References
    ----------
    .. [1] S. Avidan and A. Shamir, "Seam carving for content-aware image
       resizing", ACM TOG 26(3) (SIGGRAPH 2007), article 10.
       :doi:`10.1145/1275808.1276390`
    .. [2] M. Rubinstein, A. Shamir and S. Avidan, "Improved seam carving for
       video retargeting", ACM TOG 27(3) (SIGGRAPH 2008), article 16.
       :doi:`10.1145/1360612.1360615`
    """
    started = time.perf_counter()
    img = as_image(image, "image")
    x, grey = with_channels(img)
    shape = x.shape[:2]
    target = shape if size is None else as_size(size)
    energy = _check_energy(energy)
    order = _check_order(order)
    enlarge = check_bool(enlarge, "enlarge")
    remove = _as_mask(remove_mask, shape, "remove_mask")
    protect = _as_mask(protect_mask, shape, "protect_mask")
    if remove is not None and protect is not None and (remove & protect).any():
        raise ValueError(f"remove_mask and protect_mask share {int((remove & protect).sum())} pixels; a pixel "
                         "can be removed or protected, not both")
    if not enlarge and (target[0] > shape[0] or target[1] > shape[1]):
        raise ValueError(f"size {target} is larger than the image ({shape[0]}, {shape[1]}) in "
                         f"{'height' if target[0] > shape[0] else 'width'}, and enlarge=False forbids inserting "
                         f"seams; pass enlarge=True or a size of at most ({shape[0]}, {shape[1]})")
    rows_out, cols_out = max(0, shape[0] - target[0]), max(0, shape[1] - target[1])
    n_line = min(rows_out, cols_out) + 1 if order == "optimal" and remove is None else 1
    _check_memory(shape, target, x.shape[2], x.dtype.itemsize, n_line)

    bias = None
    if remove is not None or protect is not None:
        # L: more than any seam's energy (e1 <= C per pixel, forward steps <= 2C), so masks dominate
        if callable(energy):
            top = float(_custom_energy(energy, x).max(initial=0.0))
        else:
            top = 2.0 * x.shape[2]
        big = (max(top, 2.0 * x.shape[2]) + 1.0) * max(shape) * 2.0 + 1.0
        bias = np.zeros(shape)
        if remove is not None:
            bias[remove] = -big
        if protect is not None:
            bias[protect] = big
    source = np.stack(np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij"), -1)
    state = _Carver(x, bias, energy, source=source, inserted=np.zeros(shape, dtype=bool), removing=remove)
    seams, costs, stages = [], [], {}
    n_removed, n_inserted = [0, 0], [0, 0]

    def remove_one(direction, bar):
        nonlocal state
        seam, cost = state.seam(direction)
        seams.append((direction, seam))
        costs.append(cost)
        state = state.removed(direction, seam)
        n_removed[_AXIS[direction]] += 1
        bar.advance()

    # Section 4.6: object removal
    if remove is not None and remove.any():
        t0 = time.perf_counter()
        rows_hit, cols_hit = np.nonzero(remove.any(axis=1))[0], np.nonzero(remove.any(axis=0))[0]
        direction = "vertical" if np.ptp(cols_hit) <= np.ptp(rows_hit) else "horizontal"
        left = int(remove.sum())
        with Progress(progress, left, "object removal") as bar:
            while left:
                before = left
                if state.shape[_AXIS[direction]] <= 1:
                    break
                remove_one(direction, bar)
                left = int(state.removing.sum())
                if left == before:
                    raise ValueError("remove_mask cannot be removed: every seam through it crosses protect_mask; "
                                     "protect fewer pixels or remove a smaller region")
        if left:
            raise ValueError("remove_mask covers a whole row and column; remove a smaller region")
        stages["object removal"] = time.perf_counter() - t0
        if not enlarge:  # nothing is inserted: the size after removal bounds the output
            target = (min(target[0], state.shape[0]), min(target[1], state.shape[1]))
    removal_size = tuple(int(s) for s in state.shape)
    if state.bias is not None and state.removing is not None:
        state.bias = np.where(state.removing, 0.0, state.bias)  # nothing left to remove
    state.removing = None

    # shrinking: the order of rows and columns
    rows_out, cols_out = max(0, state.shape[0] - target[0]), max(0, state.shape[1] - target[1])
    rows_in, cols_in = max(0, target[0] - state.shape[0]), max(0, target[1] - state.shape[1])
    T = None
    if rows_out or cols_out:
        if order == "optimal" and rows_out and cols_out:
            t0 = time.perf_counter()
            n_line = min(rows_out, cols_out) + 1
            _check_memory(state.shape, target, x.shape[2], x.dtype.itemsize, n_line)
            planner = _Carver(state.image, state.bias, energy)
            with Progress(progress, (rows_out + 1) * (cols_out + 1) - 1, "seam order") as bar:
                directions, T = _transport_map(planner, rows_out, cols_out, bar)
            stages["order"] = time.perf_counter() - t0
        else:
            directions = _sequence(order if order != "optimal" else "vertical-first", rows_out, cols_out)
        t0 = time.perf_counter()
        with Progress(progress, len(directions), "seam removal") as bar:
            for direction in directions:
                remove_one(direction, bar)
        stages["removal"] = time.perf_counter() - t0

    # Section 4.2: enlarging, vertical seams first
    if rows_in or cols_in:
        t0 = time.perf_counter()
        if return_info:  # every pixel a copy of weight 1 until insertion averages two
            state.blend = (state.source[:, :, None, :].copy(), np.ones(state.shape + (1,)))
        with Progress(progress, rows_in + cols_in, "seam insertion") as bar:
            for direction, count in (("vertical", cols_in), ("horizontal", rows_in)):
                axis = _AXIS[direction]
                while count:
                    k = min(count, max(1, int(state.shape[axis] * ENLARGE_STEP)))
                    state = state.inserted_seams(direction, k, on_seam=bar.advance)
                    count -= k
                    n_inserted[axis] += k
        stages["insertion"] = time.perf_counter() - t0

    out = restore_channels(state.image.astype(img.dtype, copy=False), grey)
    if not return_info:
        return out
    total = time.perf_counter() - started
    info = SeamCarvingInfo(seams=seams, costs=np.asarray(costs, dtype=np.float64), n_removed=tuple(n_removed),
                           n_inserted=tuple(n_inserted), source=state.source, inserted=state.inserted,
                           removal_size=removal_size, order=order, transport_map=T, seconds=total,
                           stage_seconds=stages)
    if state.blend is None:  # removal only: every pixel is a copy
        info.coordinates = state.source
    else:
        info.coordinates, info.weights = state.blend
    return out, info
