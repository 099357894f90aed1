"""Near-regular texture synthesis: whole cells of the exemplar's lattice placed on the output's lattice.

After Liu, Lin & Hays (SIGGRAPH 2004), who model a near-regular texture as a
regular congruent tiling (a lattice of two period vectors) deformed in
geometry, lighting and colour. A texture of square stone tiles in a grid, a
parquet, a wall of bricks: the general methods (image quilting, patch-based
sampling, graph cuts) place their blocks wherever the overlap error is
smallest, so tiles of the 4x enlargement come out fragmented, stacked in
columns, or of varied sizes. Placing whole cells of the lattice on a lattice
of the same period keeps the grid.

1. **The lattice** (``lattice="auto"``): axis-aligned grids are found from
   their full-length lines (grout, mortar): the row-mean and column-mean
   luminance profiles dip below their running median (31 px) where a line
   runs across; the dips (``scipy.signal.find_peaks`` on
   ``(median - profile) / std``, height 0.6) of each axis give the period
   (from the median spacing of the strong dips, refined by a least-squares
   fit of the dips to ``origin + k period``) and the origin (a line's
   position). Dark lines are tried first, then bright ones; a lattice must
   have at least two lines per axis and a line near three quarters of its
   predicted positions. Failing that, :func:`texsynth.metrics.lattice`'s
   period vectors are used when they are axis-aligned (the origin at the
   darkest phase of the profiles folded on the period).
2. **Cells**: the output is a grid of cells of the period; each is a block of
   the exemplar of ``(cell + O)`` pixels whose top-left corner is a lattice
   point shifted by ``-O/2``, so the overlap bands lie on the lines, where a
   seam is invisible. Candidates are all lattice cells of the exemplar (a cell
   may reach a few pixels past its border: its margin is mirrored there and
   the cuts prefer real pixels), and for square cells their eight dihedral
   transforms (flips and quarter turns) against repetition.
3. **Placement**: in raster order as image quilting's
   (:func:`texsynth.patch.quilt`): every candidate's overlap error with what
   the output already shows (:func:`texsynth.core.search.candidate_sq_distances`
   over the known band), one drawn uniformly among those within
   ``(1 + error_tolerance)`` of the best, pasted along the minimum-error
   boundary cuts (:func:`texsynth.core.seams.minimum_error_boundary`). Added
   here: a cell is not drawn beside a copy of itself (left or above) while
   another qualifies. The block grid (two of quilting's ``Grid`` axes, one
   step per axis), its raster loop (``paste_blocks``) and the records
   (``quilt_info``) are image quilting's.

What could not be checked against the paper (its text was not at hand; the
description follows its published abstract): Liu et al. extract the lattice
with the user's help and model the deviations from it as geometric, lighting
and colour *deformation fields*, which they analyse, synthesise and
manipulate; here the lattice is automatic, axis-aligned and undeformed, and
the deviations are whatever the pasted cells carry. Their synthesis procedure,
equations and parameters were not checked; this is image quilting restricted
to the lattice, with quilting's defaults.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..core._validate import (
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_memory,
    check_positive_int,
    with_channels,
)
from ..core.search import augmentations, candidate_sq_distances, check_augment, is_auto, within_tolerance
from ._quilting import (
    ERROR_TOLERANCE,
    Grid,
    QuiltInfo,
    check_canvas_memory,
    check_tolerance,
    cut_through,
    finish,
    paste_blocks,
    quilt_info,
)

__all__ = ["NearRegularInfo", "near_regular_texture"]

MEDIAN_WINDOW = 31  # pixels: the running median the profiles' dips are measured from
DIP_HEIGHT = 0.6  # a dip: this many standard deviations of the profile below its running median
STRONG_DIP = 0.4  # the dips that make the lattice: at least this fraction of the deepest one
LINES_FOUND = 0.75  # a lattice has a line near at least this fraction of its predicted positions
OVERLAP_FRACTION = 1 / 6  # overlap "auto": a sixth of the cell, as image quilting's of the block
SQUARE_TOLERANCE = 0.03  # cells are square when their sides differ by at most 3 % (or 2 px)


@dataclass
class NearRegularInfo(QuiltInfo):
    """What :func:`near_regular_texture` found and chose: :class:`~texsynth.patch.QuiltInfo` and the lattice.

    Attributes
    ----------
    lattice : tuple of float
        ``(period_rows, period_cols, origin_row, origin_col)`` of the exemplar's lattice, in pixels:
        lines at rows ``origin_row + k period_rows`` and columns ``origin_col + k period_cols``.
    found_by : str
        ``"dark lines"``, ``"bright lines"``, ``"autocorrelation"`` (``texsynth.metrics.lattice``) or
        ``"given"``.
    cells : tuple of int
        ``(rows, cols)``: how many periods one block spans along each axis (more than one along the
        shorter period of an oblong lattice, so the blocks stay about square).
    steps : tuple of int
        The output grid's step along rows and columns (the cells' size).
    augment : str
        The transforms the candidates were drawn from (``"none"`` or ``"both"``, ...).
    n_candidates : int
        How many candidate blocks (lattice cells times transforms).
    transforms : numpy.ndarray
        ``(n,)`` int: the transform of each pasted block, an index into
        :func:`texsynth.core.search.augmentations` of ``augment`` (0: the exemplar as it is).
    cell_indices : numpy.ndarray
        ``(n,)`` int: which lattice cell of the exemplar each block shows (row-major over its cells,
        whatever the transform). No block shows the cell of its left or upper neighbour unless the
        exemplar holds too few cells for that.

    The corners, sources, errors, ``coordinates`` and timings are :class:`~texsynth.patch.QuiltInfo`'s:
    ``corners`` in output pixels (the block's top-left may lie above or left of the output: negative),
    ``sources`` the exemplar pixel each block's top-left pixel shows.
    """

    lattice: tuple = ()
    found_by: str = ""
    cells: tuple = ()
    steps: tuple = ()
    augment: str = "none"
    n_candidates: int = 0
    transforms: np.ndarray | None = None
    cell_indices: np.ndarray | None = None


# --------------------------------------------------------------------------
# 1. The lattice


def luminance(image):
    """The mean of the colour channels (alpha left out), as the structure metrics measure it."""
    channels = image.shape[2]
    return image[..., : 3 if channels >= 3 else 1].mean(-1)


def axis_lattice(profile, sign, min_distance):
    """``(period, origin, share)`` of one axis from its profile's dips (``sign`` 1: dark lines, -1: bright; share:
    of the lines the lattice predicts inside the profile, those found), or None when fewer than two strong dips
    or the dips do not fall on one period."""
    from scipy.ndimage import median_filter
    from scipy.signal import find_peaks

    spread = float(profile.std())
    if spread <= 1e-12 or len(profile) < 8:
        return None
    depth = sign * (median_filter(profile, MEDIAN_WINDOW, mode="reflect") - profile) / spread
    peaks, props = find_peaks(depth, height=DIP_HEIGHT, distance=min_distance)
    if len(peaks) < 2:
        return None
    dips, heights, whole = _dips(depth, peaks, props["peak_heights"])
    is_strong = heights >= STRONG_DIP * heights.max()
    strong = dips[is_strong]
    if len(strong) < 2:
        return None
    if np.sum(is_strong & whole) >= 2:  # lines cut by the border are placed less exactly: fit the others
        strong = dips[is_strong & whole]
    rough = float(np.median(np.diff(strong)))
    if rough < 4:
        return None
    k = np.round((strong - strong[0]) / rough)
    if len(np.unique(k)) < 2:
        return None
    design = np.stack([np.ones_like(k), k], axis=1)
    (start, period), *_ = np.linalg.lstsq(design, strong.astype(np.float64), rcond=None)
    if not 4 <= period <= len(profile) - 1:
        return None
    tolerance = max(2.0, 0.08 * period)
    if np.max(np.abs(start + k * period - strong)) > tolerance:
        return None
    origin = start % period
    predicted = origin + period * np.arange(math.ceil((len(profile) - origin) / period))
    predicted = predicted[(predicted >= 2) & (predicted <= len(profile) - 3)]  # the median reflects at the ends
    near = np.abs(dips[None, :] - predicted[:, None]).min(axis=1) <= tolerance if len(predicted) else [1.0]
    if np.mean(near) < LINES_FOUND:
        return None
    return float(period), float(origin), float(np.mean(near))


def _dips(depth, peaks, heights):
    """``(positions, heights, whole)`` of the lines, to a fraction of a pixel: each dip is the run of the profile
    deeper than half its deepest value around a peak (peaks in one run are one line), positioned at the run's
    centroid; where the run reaches the profile's end (not ``whole``), at its deepest pixel."""
    found = {}
    for peak, height in sorted(zip(peaks.tolist(), heights.tolist()), key=lambda x: -x[1]):
        half = height / 2
        left = right = peak
        while left > 0 and depth[left - 1] > half:
            left -= 1
        while right < len(depth) - 1 and depth[right + 1] > half:
            right += 1
        if any(l <= peak <= r for l, r in found):
            continue  # a lesser peak of a line already found
        if left == 0 or right == len(depth) - 1:
            found[(left, right)] = (float(peak), height, False)
            continue
        weights = depth[left:right + 1] - half
        found[(left, right)] = (float(np.arange(left, right + 1) @ weights / weights.sum()), height, True)
    ordered = sorted(found.values())
    return (np.array([p for p, _, _ in ordered]), np.array([h for _, h, _ in ordered]),
            np.array([i for _, _, i in ordered], dtype=bool))


def _lines_lattice(grey):
    """``(lattice, found_by, shares)`` from full-length dark (else bright) lines along both axes, or None."""
    min_distance = 3  # peaks closer than this are one line (and so are those of one dip: _dips)
    for sign, name in ((1, "dark lines"), (-1, "bright lines")):
        rows = axis_lattice(grey.mean(axis=1), sign, min_distance)
        cols = axis_lattice(grey.mean(axis=0), sign, min_distance)
        if rows is not None and cols is not None:
            return (rows[0], cols[0], rows[1], cols[1]), name, (rows[2], cols[2])
    return None


def _folded_origin(profile, period):
    """The darkest phase of a profile folded on ``period``: where a lattice without lines has its origin."""
    p = int(round(period))
    n = len(profile) // p * p
    return float(np.argmin(profile[:n].reshape(-1, p).mean(axis=0))) if n else 0.0


def _autocorrelation_lattice(image, grey):
    """The lattice of :func:`texsynth.metrics.lattice` if its period vectors are axis-aligned, else None."""
    from ..metrics import lattice as metrics_lattice

    vectors = metrics_lattice(image).vectors.tolist()
    rows = [abs(v[0]) for v in vectors if v[1] == 0 and v[0] != 0]
    cols = [abs(v[1]) for v in vectors if v[0] == 0 and v[1] != 0]
    if not rows or not cols:
        return None
    py, px = float(rows[0]), float(cols[0])
    return (py, px, _folded_origin(grey.mean(axis=1), py), _folded_origin(grey.mean(axis=0), px)), "autocorrelation"


def find_lattice(image):
    """``(lattice, found_by)``: the axis-aligned lattice ``(period_rows, period_cols, origin_row, origin_col)``
    of a channels-last image, or a ValueError naming ``lattice`` when there is none."""
    grey = luminance(image)
    found = _lines_lattice(grey)
    if found is not None:
        return tuple(round(v, 2) for v in found[0]), found[1]
    found = _autocorrelation_lattice(image, grey)
    if found is not None:
        return found
    h, w = grey.shape
    raise ValueError(
        f"lattice='auto' found no lattice in the {h}x{w} exemplar: no axis-aligned grid of at least two "
        f"full-length dark or bright lines per axis, and no axis-aligned period vectors in its autocorrelation "
        f"(texsynth.metrics.lattice); use texsynth.quilt for a texture without a regular grid, a crop that holds "
        f"at least two lines per axis, or pass lattice=(period_rows, period_cols, origin_row, origin_col) "
        f"explicitly"
    )


def _check_lattice(lattice, shape):
    """A given lattice ``(period_rows, period_cols, origin_row, origin_col)`` as floats, origins modulo the periods."""
    h, w = shape
    try:
        values = tuple(lattice)
    except TypeError:
        raise TypeError(f"lattice must be 'auto' or (period_rows, period_cols, origin_row, origin_col) in pixels, "
                        f"got {type(lattice).__name__} {lattice!r}") from None
    if len(values) != 4 or not all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
                                   for v in values):
        raise ValueError(f"lattice must be 'auto' or four numbers (period_rows, period_cols, origin_row, "
                         f"origin_col) in pixels, got {lattice!r}")
    py, px, oy, ox = (float(v) for v in values)
    if not all(math.isfinite(v) for v in (py, px, oy, ox)):
        raise ValueError(f"lattice must hold finite numbers, got {lattice!r}")
    if not (2 <= py <= h and 2 <= px <= w):
        raise ValueError(f"lattice's periods ({py:g}, {px:g}) must lie between 2 pixels and the exemplar's sides "
                         f"({h}, {w}); pass lattice='auto' or periods the exemplar holds")
    return (py, px, oy % py, ox % px)


def _is_square(a, b):
    return abs(a - b) <= max(2.0, SQUARE_TOLERANCE * max(a, b))


# --------------------------------------------------------------------------
# 2. Cells: the candidate blocks


def _cells_per_block(py, px):
    """How many periods a block spans along rows and columns, so that an oblong cell makes an about square block."""
    if _is_square(py, px):
        return 1, 1
    return (max(1, round(px / py)), 1) if py < px else (1, max(1, round(py / px)))


def _lattice_lines(length, period, origin, span):
    """Integer positions of the lattice lines that start a cell of ``span`` periods inside ``length`` pixels (a
    line may lie a few pixels outside: the crop cut through it)."""
    slack = max(2.0, 0.1 * period)
    first = math.ceil((-slack - origin) / period)
    lines = origin + period * np.arange(first, first + math.ceil((length + 2 * slack) / period) + 1)
    keep = (lines >= -slack) & (lines + span * period <= length - 1 + slack)
    return np.round(lines[keep]).astype(np.int64)


class _Candidates:
    """The candidate blocks: every lattice cell of the exemplar, in each transform, ``B x B`` with its lines at
    ``(a, a)``; laid side by side (``image``, with a last channel 1 on real pixels and 0 on mirrored margins),
    as vectors for the search (``vectors``), and with the exemplar pixel each of their pixels shows (``origin``)."""

    def __init__(self, ex, lattice, cells, block, margin, augment):
        py, px, oy, ox = lattice
        h, w, channels = ex.shape
        B, a = block, margin
        span = (int(round(cells[0] * py)), int(round(cells[1] * px)))
        rows = _lattice_lines(h, py, oy, cells[0])
        cols = _lattice_lines(w, px, ox, cells[1])
        transforms = augmentations(augment)
        self.n = len(rows) * len(cols) * len(transforms)
        self.lines = (rows, cols)
        if not len(rows) or not len(cols):
            raise ValueError(
                f"lattice {tuple(round(v, 1) for v in lattice)} has no whole cell of {span[0]}x{span[1]} px in the "
                f"{h}x{w} exemplar; pass a lattice whose periods and origin fit it, or a larger exemplar")
        check_memory(8.0 * self.n * B * B * (2 * channels + 4), (h, w), "exemplar", "the candidate blocks",
                     also={"lattice": tuple(round(v, 1) for v in lattice)})
        pad = B + int(math.ceil(max(0.1 * py, 0.1 * px, 2.0))) + 1
        padded = np.pad(np.concatenate([ex, np.ones((h, w, 1))], axis=2), ((pad, pad), (pad, pad), (0, 0)),
                        mode="symmetric")
        padded[..., -1] = 0.0
        padded[pad:pad + h, pad:pad + w, -1] = 1.0
        where = np.pad(np.indices((h, w)).transpose(1, 2, 0), ((pad, pad), (pad, pad), (0, 0)), mode="symmetric")
        blocks = np.empty((self.n, B, B, channels + 1))
        origin = np.empty((self.n, B, B, 2), np.int64)
        self.transform = np.empty(self.n, np.int64)
        self.cell = np.empty(self.n, np.int64)  # which lattice cell (whatever its transform)
        k = 0
        for t, transform in enumerate(transforms):
            # the cell's top-left corner before the transform: the source of the transformed cell's corners
            turned = transform.shape(span)
            local = transform.origin((B, B))
            corners = local[[a, a, a + turned[0], a + turned[0]], [a, a + turned[1], a, a + turned[1]]]
            u, v = corners.min(axis=0)
            for r in rows:
                for c in cols:
                    top, left = r - u + pad, c - v + pad
                    blocks[k] = transform.apply(padded[top:top + B, left:left + B])
                    origin[k] = transform.apply(where[top:top + B, left:left + B])
                    self.transform[k] = t
                    self.cell[k] = k % (len(rows) * len(cols))
                    k += 1
        self.block = B
        self.real = blocks[..., -1] > 0.5
        self.common = self.real.all(axis=0)  # compared where every candidate shows real pixels
        self.image = blocks.transpose(1, 0, 2, 3).reshape(B, self.n * B, channels + 1)
        self.origin = origin.transpose(1, 0, 2, 3).reshape(B, self.n * B, 2)
        self.vectors = np.ascontiguousarray(blocks[..., :channels]).reshape(self.n, -1)
        self.channels = channels

    def to_exemplar(self, coordinates):
        """Positions in :attr:`image` (``(..., 2)``) as the exemplar pixels they show."""
        c = np.asarray(coordinates)
        return self.origin[c[..., 0], c[..., 1]]


# --------------------------------------------------------------------------
# 3. Placement: the quilting rule on the candidates, cuts that keep real pixels


def _lattice_grid(size, block, steps, tileable):
    """Image quilting's :class:`Grid` with a step of its own along each axis: the rows of one grid, the columns
    of another."""
    rows = Grid(size, block, block - steps[0], tileable)
    cols = Grid(size, block, block - steps[1], tileable)
    rows.cols, rows.canvas_w = cols.cols, cols.canvas_w
    rows.canvas_shape = (rows.canvas_h, rows.canvas_w)
    rows.n_blocks = len(rows.rows) * len(rows.cols)
    return rows


def _lattice_cut(old, new, known):
    """Which pixels the new block takes: the minimum-error boundary cut through each known strip (Efros &
    Freeman's, as :func:`texsynth.patch.quilt` cuts), where the error of a pixel that either side shows only
    in a mirrored margin is prohibitive, so the seam runs on real pixels; then real pixels win over mirrored
    ones wherever the two sides differ in that."""
    e = ((old[..., :-1] - new[..., :-1]) ** 2).sum(-1)
    new_real = new[..., -1] > 0.5
    old_real = (old[..., -1] > 0.5) | ~known
    e = e + (e.size * old.shape[2] + 1.0) * ~(new_real & old_real)
    take = cut_through(e, known)
    take[new_real & ~old_real] = True
    take[~new_real & old_real & known] = False
    return take


def _check_overlap(overlap, cell):
    if is_auto(overlap):
        return max(2, int(round(min(cell) * OVERLAP_FRACTION)))
    o = check_positive_int(overlap, "overlap", minimum=2)  # the cut runs in a band of at least 2 px, one per side
    if o >= min(cell):
        raise ValueError(f"overlap {o} must be smaller than the lattice's cell {cell[0]}x{cell[1]} px (a sixth of "
                         f"it, {max(2, round(min(cell) * OVERLAP_FRACTION))}, is the default); pass a smaller overlap")
    return o


def _choose_augment(augment, grey, lattice, cells, lines):
    """``augment`` checked; ``"auto"``: all eight symmetries for square cells framed by lines along both axes
    (whatever a cell holds, the lines around it look the same turned or flipped), else none."""
    square = cells == (1, 1) and _is_square(lattice[0], lattice[1])
    if is_auto(augment):
        if not square:
            return "none"
        if lines is None:
            lines = _lines_lattice(grey)
        return "both" if lines is not None else "none"
    augment = check_augment(augment)
    if augment in ("rotations", "both") and not square:
        raise ValueError(f"augment={augment!r} turns the cells a quarter turn, but the lattice's cells "
                         f"({lattice[0]:.1f} x {lattice[1]:.1f} px) are not square; pass augment='flips' or 'none'")
    return augment


def _check_tileable_size(size, steps):
    """Tileable output needs whole cells along each axis (a step at most 3 % or 1 px short of the cell's)."""
    for length, step, axis in zip(size, steps, ("height", "width")):
        n = max(2, math.ceil(length / step))
        if step - length / n > max(1.0, SQUARE_TOLERANCE * step):
            fit = [k * step for k in (math.floor(length / step), math.ceil(length / step)) if k >= 2]
            raise ValueError(
                f"tileable=True needs a size of whole lattice cells, but the {axis} {length} holds "
                f"{length / step:.2f} cells of {step} px; pass a {axis} of {' or '.join(map(str, fit))}")


def near_regular_texture(exemplar, size, *, lattice="auto", overlap="auto", error_tolerance=ERROR_TOLERANCE,
                         augment="auto", tileable=False, rng=None, return_info=False, progress=False):
    """Synthesise a near-regular texture (tiles, parquet, bricks) by placing whole cells of its lattice on a lattice.

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> rng = np.random.default_rng(0)
    >>> rows, cols = np.mgrid[:96, :96]
    >>> tiles = rng.uniform(0.4, 0.9, (4, 4))[rows // 24, cols // 24]        # tiles of 24 px ...
    >>> tiles[(rows % 24 < 3) | (cols % 24 < 3)] = 0.1                       # ... with dark grout lines
    >>> out, info = texsynth.near_regular_texture(tiles, 200, rng=0, return_info=True)
    >>> out.shape, info.lattice, info.found_by
    ((200, 200), (24.0, 24.0, 1.0, 1.0), 'dark lines')

    Finds the exemplar's lattice (the period and position of its grout or
    mortar lines), cuts it into cells, and covers the output with those cells
    on a lattice of the same period, in raster order, each drawn among the
    cells that continue the output best in the bands they share, and joined
    to it along minimum-error cuts that run on the lines [1]_. The grid stays
    whole at any enlargement, where image quilting, patch-based sampling and
    graph cuts scatter or stack the tiles.

    Parameters
    ----------
    exemplar : array_like
        A near-regular texture: ``(H, W)`` grey or ``(H, W, C)``; any
        accepted dtype. It must hold at least one whole cell of its lattice
        (two lines along each axis for ``lattice="auto"``).
    size : int or (int, int)
        Output size ``(height, width)``.
    lattice : "auto" or (float, float, float, float)
        The exemplar's grid, ``(period_rows, period_cols, origin_row,
        origin_col)`` in pixels, or ``"auto"`` (default) to find it. The
        lines of the grid run along rows ``origin_row + k period_rows`` and
        columns ``origin_col + k period_cols``. ``"auto"`` finds
        them from the dips of the row and column mean luminance (dark lines,
        else bright ones), else from the axis-aligned period vectors of
        :func:`texsynth.metrics.lattice`; ``info.lattice`` says what was
        found. Periods between 2 pixels and the exemplar's sides; origins are
        taken modulo the periods.
    overlap : int or "auto"
        Width ``O`` of the bands, centred on the lines, in which neighbouring
        cells overlap, are matched and are cut. ``"auto"`` (default): a sixth
        of the cell (image quilting's ratio), at least 2. Smaller than the cell.
    error_tolerance : float
        A cell qualifies if its overlap error is at most ``(1 +
        error_tolerance)`` times the best cell's (image quilting's 0.1); one of
        them is drawn uniformly. Must be >= 0.
    augment : {"auto", "none", "flips", "rotations", "both"}
        Also draw the cells' mirror images (``"flips"``), quarter turns
        (``"rotations"``, square cells only) or all eight symmetries of the
        square (``"both"``), against visible repetition when the exemplar
        holds few cells. ``"auto"`` (default): ``"both"`` when the cells are
        square and framed by full-length lines along both axes (the lines
        around a cell look the same turned or flipped, whatever it holds),
        else ``"none"``. Pass ``"none"`` to keep the exemplar's orientation
        (a light from one side, wood grain that must run one way).
    tileable : bool
        Make the output tile seamlessly (the grid wraps round, as
        :func:`~texsynth.patch.quilt`'s): needs a ``size`` of whole cells
        along each axis (the message names the sizes that fit).
    rng : None, int or numpy.random.Generator
        Random source for the choice of cells; an int seed reproduces the
        output bit for bit.
    return_info : bool
        Also return a :class:`NearRegularInfo`: the lattice, each block's
        position, source, transform and error, and the source-coordinate map
        (``info.coordinates``, for :func:`texsynth.apply_coordinates`).
    progress : bool or callable
        Report progress per cell (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    image : numpy.ndarray
        ``(height, width)`` or ``(height, width, C)``, the exemplar's channel
        layout; float32 for float32 input, float64 otherwise.
    info : NearRegularInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If ``lattice="auto"`` finds no lattice (use :func:`texsynth.quilt`,
        or pass the lattice), a given lattice is not four numbers with
        periods that fit the exemplar, the exemplar holds no whole cell,
        ``overlap`` is not smaller than the cell, ``error_tolerance < 0``,
        ``augment`` turns oblong cells, a tileable ``size`` is not whole
        cells, or the output would not fit in memory.
    TypeError
        For a ``lattice``, ``overlap``, ``tileable`` or ``rng`` of the wrong type.

    Notes
    -----
    With periods ``(p_y, p_x)`` and origin ``(o_y, o_x)``, the candidate
    blocks are the square pieces of the exemplar of ``B = max(p_y, p_x) + O``
    pixels (the blocks of :func:`~texsynth.patch.quilt`'s grid) whose
    top-left pixel is ``(o_y + i p_y - O/2, o_x + j p_x - O/2)``, in each
    transform of ``augment``; for oblong cells a block spans several periods
    along the shorter one. The output grid steps by ``(p_y, p_x)``, so every
    band where two blocks overlap is centred on a line. Each block is the
    quilting rule's choice among the candidates ``b``,

    .. math:: \\varepsilon(b) = \\sum_{x \\in \\Omega} \\|b(x) - o(x)\\|^2, \\qquad
              \\varepsilon(b) \\le (1 + \\text{error\\_tolerance}) \\min_b \\varepsilon(b),

    over the known band ``Ω`` (the pixels every candidate shows from inside
    the exemplar), joined along the minimum-error boundary cuts
    ``E_ij = e_ij + min(E_{i-1,j-1}, E_{i-1,j}, E_{i-1,j+1})`` through it.
    A cell cut by the exemplar's border (a 2 x 2-tile crop whose lines lie
    at its edges) is still a candidate: its missing margin is mirrored, and
    the cuts keep the real pixels of the other side there.

    Liu et al. [1]_ model a near-regular texture as a regular lattice
    deformed by geometric, lighting and colour fields, extracted with the
    user's help, and synthesise and manipulate those fields. Not checked
    against the paper's text (not at hand; its published abstract and
    descriptions were): the lattice here is automatic, axis-aligned (two
    perpendicular period vectors, no shear: a running bond's half-brick shift
    is left to the overlap error), and undeformed: no deformation field is
    estimated, each cell keeps the deformation it had in the exemplar.
    Fails on photographs in perspective (the period changes across the
    image), irregular grids (crazy paving, random ashlar), turned grids, and
    crops with fewer than two lines per axis.

    References
    ----------
    .. [1] Y. Liu, W.-C. Lin and J. Hays, "Near-regular texture analysis and
       manipulation", ACM Transactions on Graphics 23(3) (SIGGRAPH 2004),
       pp. 368-376. :doi:`10.1145/1015706.1015731`
    """
    started = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey_input = with_channels(image)
    ex64 = ex.astype(np.float64)
    size = as_size(size)
    tileable = check_bool(tileable, "tileable")
    tolerance = check_tolerance(error_tolerance)
    gen = as_rng(rng)
    grey = luminance(ex64)
    lines = None  # the grid of lines, when lattice="auto" found one
    if is_auto(lattice):
        found, found_by = find_lattice(ex64)
        lines = found if found_by.endswith("lines") else None
    elif isinstance(lattice, str):
        raise ValueError(f"lattice must be 'auto' or (period_rows, period_cols, origin_row, origin_col), "
                         f"got {lattice!r}")
    else:
        found, found_by = _check_lattice(lattice, ex.shape[:2]), "given"
    py, px = found[:2]
    cells = _cells_per_block(py, px)
    steps = (int(round(cells[0] * py)), int(round(cells[1] * px)))
    O = _check_overlap(overlap, steps)
    augment = _choose_augment(augment, grey, found, cells, lines)
    B = max(steps) + O
    if tileable:
        _check_tileable_size(size, steps)
    # plain output: the canvas reaches one overlap beyond the output on every side (the first and last
    # blocks' outer margins may be mirrored pixels that no later block covers)
    lead = 0 if tileable else B - min(steps)
    canvas_size = size if tileable else (size[0] + 2 * lead + 1, size[1] + 2 * lead + 1)
    grid = _lattice_grid(canvas_size, B, steps, tileable)
    check_canvas_memory(grid, ex.shape[2] + 1, ex.shape[:2], value=size)
    found_at = time.perf_counter()
    candidates = _Candidates(ex64, found, cells, B, O // 2, augment)
    C = candidates.channels
    built_at = time.perf_counter()
    every = np.arange(candidates.n)[None, :]
    n_rows, n_cols = len(grid.rows), len(grid.cols)
    picked = []  # the candidate of each block so far, in raster order

    def neighbour_cells():
        """The cells of the blocks already placed beside this one (left, above; round the border when tileable)."""
        i = len(picked)
        r, c = divmod(i, n_cols)
        near = [i - 1] if c else []
        near += [i - n_cols] if r else []
        if tileable:
            near += [i - c] if c == n_cols - 1 and c else []
            near += [c] if r == n_rows - 1 and r else []
        return np.unique(candidates.cell[[picked[j] for j in near]]) if near else np.zeros(0, np.int64)

    def choose(window, region, known):
        if not known.any():
            k = int(gen.integers(candidates.n))
            picked.append(k)
            return 0, k * B, 0.0, 0.0, candidates.n
        mask = known & (region[..., -1] > 0.5) & candidates.common
        weights = np.repeat(mask[..., None], C, axis=2).reshape(1, -1).astype(np.float64)
        d = candidate_sq_distances(region[..., :C].reshape(1, -1), every, candidates.vectors, weights)[0]
        repeats = np.isin(candidates.cell, neighbour_cells())
        if not repeats.all():  # a cell beside a copy of itself: the repetition a few cells would show
            d[repeats] = np.inf
        chosen = within_tolerance(d, tolerance)
        k = int(chosen[gen.integers(chosen.size)])
        picked.append(k)
        return 0, k * B, float(d[k]), float(d[np.isfinite(d)].min()), int(chosen.size)

    canvas, records, searching, sources = paste_blocks(candidates.image, grid, choose, _lattice_cut, progress,
                                                       "near-regular", return_info)
    out = finish(canvas[lead:, lead:, :C], size, image.dtype, grey_input)
    if not return_info:
        return out
    q = quilt_info(grid, records, O, built_at, searching, sources, (size[0] + lead, size[1] + lead))
    blocks_k = q.sources[:, 1] // B
    seconds = time.perf_counter() - started
    return out, NearRegularInfo(
        corners=q.corners - lead, sources=candidates.to_exemplar(q.sources), errors=q.errors,
        best_errors=q.best_errors, candidates=q.candidates, block=B, overlap=O, seconds=seconds,
        stage_seconds={"lattice": found_at - started, "candidates": built_at - found_at, **q.stage_seconds},
        coordinates=candidates.to_exemplar(q.coordinates[lead:, lead:]), weights=None,
        lattice=tuple(float(v) for v in found), found_by=found_by, cells=cells, steps=steps, augment=augment,
        n_candidates=candidates.n, transforms=candidates.transform[blocks_k], cell_indices=candidates.cell[blocks_k])
