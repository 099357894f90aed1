"""Cohen, Shade, Hiller & Deussen's Wang tiles: a few texture tiles with coloured edges, tiled at random.

A Wang tile is a square whose four edges carry colours; tiles are laid edge to
edge so that touching edges have the same colour (Cohen et al. 2003,
Section 2). A small set of tiles then covers any area without periodic
repetition, one tile at a time.

The tiles are filled with texture as the paper does (Section 3.2), by
quilting with diamonds:

1. for every edge colour one *diamond* of the exemplar is chosen: a square
   sample rotated by 45 degrees, centred on the edge, half in the tile on each
   side of it;
2. a tile with edge colours ``(N, E, S, W)`` is covered by the four diamonds of
   its edges; they overlap along the tile's two diagonals, and each pair is
   joined along a minimum-error boundary cut through its overlap
   (:func:`texsynth.core.seams.minimum_error_boundary`, the cut of image
   quilting), so that every pixel on an edge comes from that edge's diamond.

Two tiles that share an edge colour therefore show, across that edge, the two
halves of one and the same diamond: the join is the exemplar itself, pixel
for pixel, and only the cuts inside the tiles are seams. The tiling
(Section 4) is stochastic and sequential, in scanline order: each tile is
drawn uniformly among those whose north and west colours match the south
colour of the tile above and the east colour of the tile to the left. The
tile set holds, for every (north, west) pair of colours, two tiles that
differ in both their south and east colours, so there is always a choice:
``2 K^2`` tiles for ``K`` colours per direction (8 for the paper's 2).

The cut along a diagonal is the dynamic programme of quilting run on the
tile's rows after a shear (``x' = x - y`` for the main diagonal), so a step of
one sheared column per row follows the diagonal; it is pinned to the tile's
corners, so that no pixel of an edge but the corner pixels comes from another
diamond.

What could not be checked against the paper's text (it was not at hand;
the construction follows its published description, public implementations
and secondary summaries): the size of the
diamonds' overlap (here ``overlap``, default a third of the tile), how the
samples are chosen (here the first at random and each later one among those
that match the ones chosen within quilting's tolerance; ``error_tolerance=None``
draws all at random), which (south, east)
pairs the two tiles of a (north, west) pair get (here ``(W, N)`` and
``(W + 1, N + 1)`` modulo ``K``, so every (south, east) pair appears equally
often), and the section numbers. The cut is computed on the sheared grid
rather than on a 45-degree rotation of the exemplar (which would resample it).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_memory,
    check_positive_float,
    check_positive_int,
    with_channels,
)
from ..core.search import is_auto
from ..core.seams import minimum_error_boundary

__all__ = ["WangTileSet", "WangTilesInfo", "WangTilingInfo", "wang_texture", "wang_tiles", "wang_tiling"]

NORTH, EAST, SOUTH, WEST = 0, 1, 2, 3
OVERLAP_FRACTION = 1 / 3  # the band of the cuts: a third of the tile (measured: a sixth leaves bricks broken)
ERROR_TOLERANCE = 0.1  # samples within 10 % of the best match qualify (quilting's rule)
CANDIDATES = 8  # sets of samples tried; the one whose cuts cost least is kept (bricks: visibly fewer breaks)


@dataclass
class WangTileSet:
    """A set of Wang tiles: the images and the colours of their edges.

    Attributes
    ----------
    tiles : numpy.ndarray
        ``(n, T, T)`` grey or ``(n, T, T, C)``: the tile images.
    edges : numpy.ndarray
        ``(n, 4)`` int: each tile's edge colours in the order north, east,
        south, west. North and south colours (horizontal edges) and east and
        west colours (vertical edges) are separate sets, ``0 .. colors - 1``.
    colors : int
        Colours per direction.
    coordinates : numpy.ndarray or None
        ``(n, T, T, 2)`` int: the exemplar pixel ``(row, col)`` each tile
        pixel was copied from (None for a set made by hand). Tilings made
        from the set carry it into their ``info.coordinates``.
    """

    tiles: np.ndarray
    edges: np.ndarray
    colors: int
    coordinates: np.ndarray | None = None

    @property
    def tile(self):
        """The tiles' side ``T`` in pixels."""
        return int(self.tiles.shape[1])

    def __len__(self):
        return int(self.tiles.shape[0])


@dataclass
class WangTilesInfo:
    """How :func:`wang_tiles` made its tiles.

    Attributes
    ----------
    samples : numpy.ndarray
        ``(2, colors, 2)`` int: the top-left exemplar pixel of each colour's
        sample, ``samples[0]`` for the horizontal-edge (north/south) colours
        (blocks of ``2a x T``), ``samples[1]`` for the vertical-edge (east/west)
        colours (``T x 2a``), with ``a = T // 2 + overlap // 2 + 1``.
    labels : numpy.ndarray
        ``(n, T, T)`` uint8: which edge's diamond each tile pixel comes from
        (0 north, 1 east, 2 south, 3 west).
    seam_costs : numpy.ndarray
        ``(n, 2)``: the error along each tile's two cuts (main diagonal,
        anti-diagonal), the sum of squared differences of the two diamonds
        on the cut's pixels.
    set_costs : numpy.ndarray
        ``(n_candidates,)``: the total cut error of every set of samples
        tried; the kept set has the least.
    overlap : int
        Width of the band around each diagonal in which the cuts may run.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"checks"`` (input checks and the exemplar's Fourier transforms),
        ``"samples"`` and ``"tiles"``, over all the candidate sets.
    """

    samples: np.ndarray
    labels: np.ndarray
    seam_costs: np.ndarray
    set_costs: np.ndarray
    overlap: int
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


@dataclass
class WangTilingInfo:
    """What :func:`wang_tiling` (or :func:`wang_texture`) laid.

    Attributes
    ----------
    indices : numpy.ndarray
        ``(rows, columns)`` int: the tile at each place of the grid, in tiles
        (the last row and column may be cropped by ``size``).
    tiles : WangTileSet
        The tile set used.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"choice"`` (the scanline choice of tiles), ``"assembly"`` (copying
        them into the output) and, from :func:`wang_texture`, ``"tiles"``.
    coordinates : numpy.ndarray or None
        ``(H, W, 2)`` int, the exemplar pixel ``(row, col)`` each output pixel
        was copied from (the source-coordinate map of ``docs/conventions.md``;
        :func:`texsynth.apply_coordinates` renders other channels through it);
        None if the tile set has no ``coordinates``.
    weights : None
        Every pixel is a copy.
    """

    indices: np.ndarray
    tiles: WangTileSet
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None


# --------------------------------------------------------------------------
# Section 2: a complete tile set


def tile_edges(colors):
    """Edge colours ``(N, E, S, W)`` of the ``2 K^2`` tiles: two tiles for every (north, west) pair.

    The two tiles of the pair ``(n, w)`` have ``(S, E) = (w, n)`` and ``(w + 1, n + 1)`` modulo ``K``: they
    differ in both, so the scanline tiling always has two choices, and every (south, east) pair is used by
    exactly two tiles, so no colour is favoured.

    >>> tile_edges(2).tolist()[:4]
    [[0, 0, 0, 0], [0, 1, 1, 0], [0, 0, 1, 1], [0, 1, 0, 1]]
    """
    k = colors
    edges = []
    for n in range(k):
        for w in range(k):
            edges.append((n, n, w, w))  # (N, E, S, W) with E = n, S = w
            edges.append((n, (n + 1) % k, (w + 1) % k, w))
    return np.array(edges, dtype=np.int64)


# --------------------------------------------------------------------------
# Section 3.2: quilting with diamonds


def _diamond_layers(samples_h, samples_v, edge, T, a, channels):
    """The four diamonds of a tile's edges over the tile, ``(4, T, T, C)`` (N, E, S, W; zero outside their half)."""
    n, e, s, w = edge
    layers = np.zeros((4, T, T, channels))
    rows = min(a, T)
    layers[NORTH, :rows] = samples_h[n][a:a + rows]  # the lower half of the north edge's diamond
    layers[SOUTH, T - rows:] = samples_h[s][a - rows:a]  # the upper half of the south edge's diamond
    layers[WEST, :, :rows] = samples_v[w][:, a:a + rows]
    layers[EAST, :, T - rows:] = samples_v[e][:, a - rows:a]
    return layers


def _diagonal_cut(first, second, m, anti):
    """The minimum-error cut along a tile's main diagonal (or anti-diagonal), pinned to its corners.

    ``first`` and ``second`` are the error surfaces ``||A - B||^2`` of the diamonds that meet along the upper
    and lower half of the diagonal. The band of ``2m + 1`` pixels around the diagonal is sheared into a strip
    (``x' = x - y``, or ``x + y - (T - 1)``) where the DP of quilting's cut runs, one pixel per row.
    Returns the cut's column in every row and its error.
    """
    T = first.shape[0]
    y = np.arange(T)
    offsets = np.arange(-m, m + 1)
    base = (T - 1 - y) if anti else y  # the diagonal's column in each row
    cols = base[:, None] + offsets[None, :]
    if anti:  # x <= T - 1 below the first row, x >= 1 above the last
        lo, hi = np.maximum(-m, y - T + 2), np.minimum(m, y)
    else:  # x >= 1 below the first row, x <= T - 1 above the last
        lo, hi = np.maximum(-m, 1 - y), np.minimum(m, T - 1 - y)
    lo[[0, -1]] = hi[[0, -1]] = 0  # pinned to the corners
    allowed = (offsets[None, :] >= lo[:, None]) & (offsets[None, :] <= hi[:, None])
    upper = (y < T / 2)[:, None]
    safe = np.clip(cols, 0, T - 1)
    error = np.where(upper, first[y[:, None], safe], second[y[:, None], safe])
    strip = np.where(allowed, error, 0.0)
    big = strip.sum() + 1.0  # more than any path through allowed pixels only
    strip[~allowed] = big
    seam = minimum_error_boundary(strip)
    return base + offsets[seam], float(strip[y, seam].sum())


def _tile_coordinates(samples, edges, labels, T, a):
    """``(n, T, T, 2)``: the exemplar pixel of every tile pixel, from its diamond's sample (:func:`_frame`)."""
    y, x = np.indices((T, T))
    out = np.zeros(labels.shape + (2,), dtype=np.int64)
    for i, edge in enumerate(edges):
        for side in (NORTH, EAST, SOUTH, WEST):
            here = labels[i] == side
            origin = samples[0 if side in (NORTH, SOUTH) else 1][edge[side]]
            u, v = _frame(side, y[here], x[here], T, a)
            out[i][here] = np.stack([origin[0] + u, origin[1] + v], -1)
    return out


def _make_tile(layers, m, cut):
    """Label every tile pixel with one diamond along the two cuts, and compose the tile."""
    T = layers.shape[1]
    if cut and m > 0:
        def sq(i, j):
            return ((layers[i] - layers[j]) ** 2).sum(-1)

        cut1, cost1 = _diagonal_cut(sq(WEST, NORTH), sq(SOUTH, EAST), m, anti=False)
        cut2, cost2 = _diagonal_cut(sq(NORTH, EAST), sq(WEST, SOUTH), m, anti=True)
    else:
        y = np.arange(T)
        cut1, cut2 = y, T - 1 - y
        cost1 = cost2 = 0.0
    x = np.arange(T)[None, :]
    upper_right = x >= cut1[:, None]  # the north/east side of the main diagonal's cut
    lower_right = x >= cut2[:, None]  # the east/south side of the anti-diagonal's cut
    labels = np.where(upper_right, np.where(lower_right, EAST, NORTH), np.where(lower_right, SOUTH, WEST))
    labels = labels.astype(np.uint8)
    tile = np.take_along_axis(layers, labels[None, :, :, None].astype(np.intp), axis=0)[0]
    return tile, labels, (cost1, cost2)


# Where the diamonds meet: the band around each half-diagonal, and which two edges' diamonds meet there
_MEETINGS = (("main", "upper", NORTH, WEST), ("anti", "upper", NORTH, EAST),
             ("anti", "lower", SOUTH, WEST), ("main", "lower", SOUTH, EAST))


def _band(T, m, diagonal, half):
    """Tile pixels ``(y, x)`` within ``m`` columns of a half-diagonal."""
    y, x = np.mgrid[:T, :T]
    line = y if diagonal == "main" else T - 1 - y
    rows = y < T / 2 if half == "upper" else y >= T / 2
    return np.nonzero(rows & (np.abs(x - line) <= m))


def _frame(edge, y, x, T, a):
    """Where tile pixel ``(y, x)`` lies in the sample of the diamond of ``edge`` (and whether it is inside it)."""
    if edge == NORTH:
        u, v = y + a, x
    elif edge == SOUTH:
        u, v = y - T + a, x
    elif edge == WEST:
        u, v = y, x + a
    else:
        u, v = y, x - T + a
    return u, v


def _choose_samples(exf, T, a, m, k, error_tolerance, gen, searches=None):
    """Top-left corners of the samples: ``(2, k, 2)``, horizontal-edge colours then vertical-edge ones.

    ``error_tolerance=None`` draws them uniformly. Otherwise the first is drawn and each later one (north/south
    and east/west colours in turn) is drawn among the exemplar positions whose squared difference with the
    samples already chosen, over the bands where their diamonds meet in the tiles, is within ``(1 +
    error_tolerance)`` of the least (quilting's rule, Section 2.1 of Efros & Freeman 2001), away from the
    samples of its own direction. Every pair of colours meets in the set (all four ways), so all four bands
    count.
    """
    from ..core.search import within_tolerance

    H, W = exf.shape[:2]
    shapes = ((2 * a, T), (T, 2 * a))  # horizontal-edge (north/south) samples, vertical-edge (east/west) ones
    samples = np.zeros((2, k, 2), dtype=np.int64)
    if error_tolerance is None:
        for d, (h, w) in enumerate(shapes):
            samples[d, :, 0] = gen.integers(0, H - h + 1, k)
            samples[d, :, 1] = gen.integers(0, W - w + 1, k)
        return samples
    bands = {(diag, half): _band(T, m, diag, half) for diag, half, _, _ in _MEETINGS}
    chosen = [[], []]
    for step in range(2 * k):
        d = step % 2  # 0: a north/south colour, 1: an east/west one
        h, w = shapes[d]
        search = searches[d]
        total = np.zeros(search.shape)
        for r0, c0 in chosen[1 - d]:
            other = exf[r0:r0 + shapes[1 - d][0], c0:c0 + shapes[1 - d][1]]
            for diag, half, horizontal_edge, vertical_edge in _MEETINGS:
                mine, theirs = (horizontal_edge, vertical_edge) if d == 0 else (vertical_edge, horizontal_edge)
                y, x = bands[diag, half]
                u, v = _frame(mine, y, x, T, a)
                uo, vo = _frame(theirs, y, x, T, a)
                inside = (u >= 0) & (u < h) & (v >= 0) & (v < w) & (uo >= 0) & (uo < other.shape[0]) & \
                         (vo >= 0) & (vo < other.shape[1])
                template, mask = np.zeros((h, w, exf.shape[2])), np.zeros((h, w))
                template[u[inside], v[inside]] = other[uo[inside], vo[inside]]
                mask[u[inside], v[inside]] = 1.0
                total += search.sq_distances(template, mask)
        near = np.zeros(search.shape, dtype=bool)
        for r0, c0 in chosen[d]:  # not the same sample as another colour's
            near[max(0, r0 - T // 2):r0 + T // 2 + 1, max(0, c0 - T // 2):c0 + T // 2 + 1] = True
        if not near.all():
            total[near] = np.inf
        if chosen[1 - d]:
            pick = within_tolerance(total, error_tolerance)  # (inf: excluded)
            flat = int(pick[gen.integers(pick.size)])
        else:
            flat = int(gen.choice(np.flatnonzero(np.isfinite(total))))
        position = divmod(flat, search.shape[1])
        chosen[d].append(position)
        samples[d, len(chosen[d]) - 1] = position
    return samples


# --------------------------------------------------------------------------
# Checks


def _check_tile(tile, shape):
    shortest = min(shape)
    if is_auto(tile):
        if shortest < 8:
            raise ValueError(f"exemplar is {shape[0]}x{shape[1]}; Wang tiles need an exemplar of at least 8 x 8 "
                             "pixels (tiles of 4 and their samples)")
        return (shortest - 2) // 2
    T = check_positive_int(tile, "tile", minimum=4)
    if T + 4 > shortest:
        raise ValueError(f"tile {T} needs diamonds of about {T + 4} pixels or more, larger than the exemplar "
                         f"({shape[0]}x{shape[1]}); pass tile <= {max(4, (shortest - 2) // 2)} or a larger exemplar")
    return T


def _check_overlap(overlap, T, shape):
    if is_auto(overlap):
        overlap = max(2, round(T * OVERLAP_FRACTION))
        overlap = min(overlap, T // 2, min(shape) - T - 3)
        return max(0, overlap)
    o = check_positive_int(overlap, "overlap", minimum=0)
    if o > T // 2:
        raise ValueError(f"overlap {o} must be at most half the tile ({T // 2}); the default is a third "
                         f"({max(2, round(T * OVERLAP_FRACTION))})")
    if T + 2 * (o // 2) + 2 > min(shape):
        raise ValueError(f"tile {T} with overlap {o} needs diamonds of {T + 2 * (o // 2) + 2} pixels, larger than "
                         f"the exemplar ({shape[0]}x{shape[1]}); pass a smaller overlap or tile")
    return o


def _check_colors(colors):
    k = check_positive_int(colors, "colors", minimum=2)
    return k


# --------------------------------------------------------------------------
# The tiles, the tiling, and both at once


#: Most sets of samples ``wang_tiles`` draws: a thousand sets of 8 tiles of 128 px take about a minute.
_MAX_CANDIDATES = 1000


def wang_tiles(exemplar, tile="auto", *, colors=2, overlap="auto", error_tolerance=ERROR_TOLERANCE,
               n_candidates=CANDIDATES,
               cut=True, rng=None, return_info=False, progress=False):
    """Make a set of Wang tiles from an exemplar by quilting with diamonds (Cohen et al. 2003).

    Examples
    --------
    >>> import texsynth
    >>> brick = texsynth.data.load("brick")[:96, :96]
    >>> tiles = texsynth.wang_tiles(brick, 32, rng=0)
    >>> tiles.tiles.shape, tiles.edges.shape, tiles.tile
    ((8, 32, 32, 3), (8, 4), 32)

    Every tile is quilted from exemplar samples, one per edge colour, each
    shown as a diamond around the edge's midpoint and joined to the others
    along minimum-error cuts, so any two tiles whose shared edge has one
    colour continue each other across it [1]_ [2]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture: ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    tile : int or "auto"
        Side ``T`` of the square tiles, in pixels (at least 4). Each colour's
        sample needs ``T + overlap + 2`` pixels of the exemplar. ``"auto"``
        (default): about half the exemplar's shorter side.
    colors : int
        Edge colours per direction ``K`` (at least 2). The set has ``2 K^2``
        tiles: the paper's minimal complete set of 8 for ``K = 2``.
    overlap : int or "auto"
        Width of the band around each diagonal in which the diamonds overlap
        and the cut may run. ``"auto"`` (default): a third of the tile (a sixth, quilting's
        ``B / 6``, left brick courses broken along the diagonals on the
        photographs tried); 0 joins the diamonds along the straight diagonals.
    error_tolerance : float or None
        How the samples are chosen. A number: the first at random, each later
        one among the exemplar positions whose squared difference with the
        samples already chosen, where their diamonds meet in the tiles, is
        within ``(1 + error_tolerance)`` of the least (image quilting's rule
        and value, 0.1), away from the samples of the same direction. None:
        all uniformly at random (the paper's description as far as it could
        be checked; structured textures then break along the cuts).
    n_candidates : int
        Sets of samples drawn (each as ``error_tolerance`` says); the set
        whose tiles' cuts have the least total error is kept. Default 8
        (about 0.05 s a set for 128 px tiles); 1 keeps the first draw.
    cut : bool
        Join the diamonds along minimum-error boundary cuts (True, the paper's
        method); False joins them along the straight diagonals (a baseline).
    rng : None, int or numpy.random.Generator
        Random source for the choice of samples.
    return_info : bool
        Also return a :class:`WangTilesInfo` (samples, labels, seam errors).
    progress : bool or callable
        Report progress per tile.

    Returns
    -------
    tiles : WangTileSet
        ``tiles.tiles`` is ``(2 K^2, T, T[, C])`` with the exemplar's channel
        layout (float32 for float32 input, float64 otherwise);
        ``tiles.edges`` the colours (north, east, south, west) of each.
    info : WangTilesInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If the tile (with its overlap) does not fit in the exemplar, for
        fewer than 2 colours, or if the set would not fit in memory.

    Notes
    -----

    With ``a = T // 2 + overlap // 2 + 1``, each north/south colour ``c``
    has a sample ``H_c`` of ``2a x T`` exemplar pixels and each east/west
    colour a sample ``V_c`` of ``T x 2a``. A tile whose north edge is ``c``
    shows ``H_c``'s lower half from its first row down, one whose south
    edge is ``c`` its upper half ending at its last row; east and west
    likewise. So across a shared edge, the two tiles' rows ``T - 1`` and
    ``0`` are rows ``a - 1`` and ``a`` of one exemplar sample. Of each
    sample a tile uses the diamond ``|dx| + |dy| <= T / 2 + overlap / 2``
    around its edge's midpoint.

    The diamonds of the north and west edges meet along the upper half of
    the main diagonal, east and south along its lower half; north and east
    along the upper half of the anti-diagonal, west and south along its
    lower half. Each diagonal gets one minimum-error boundary cut through
    the error surface ``e = ||A - B||^2`` of the pair meeting there, the
    dynamic programme of image quilting (Efros & Freeman 2001) on the
    sheared band, pinned to the tile's corners. A pixel belongs to the
    diamond on its side of both cuts, so every edge pixel except the four
    corner pixels comes from its edge's diamond.

    The tiles cannot hide what their samples show: a conspicuous element
    in a sample appears on every tile with that edge colour (repetition at
    the scale of the tiles), and where four tiles meet at a corner the
    edge colours do not constrain the diagonal neighbours (the "corner
    problem"). Textures whose structure is larger than about a quarter of
    the tile cannot be joined well along the cuts.

    References
    ----------
    .. [1] M. F. Cohen, J. Shade, S. Hiller and O. Deussen, "Wang tiles for
       image and texture generation", ACM TOG 22(3) (SIGGRAPH 2003),
       pp. 287-294. :doi:`10.1145/882262.882265`
    .. [2] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001. :doi:`10.1145/383259.383296`
    """
    started = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey = with_channels(image)
    T = _check_tile(tile, ex.shape[:2])
    k = _check_colors(colors)
    o = _check_overlap(overlap, T, ex.shape[:2])
    cut = check_bool(cut, "cut")
    n_sets = check_positive_int(n_candidates, "n_candidates")
    if n_sets > _MAX_CANDIDATES:  # each set makes every tile once: more buys nothing visible and takes hours
        raise ValueError(f"n_candidates must be at most {_MAX_CANDIDATES} (each set of samples makes all the tiles "
                         f"once), got {n_sets}; the default is {CANDIDATES}")
    tolerance = None if error_tolerance is None else check_positive_float(error_tolerance, "error_tolerance",
                                                                          allow_zero=True, maximum=1e6)
    n = 2 * k * k
    check_memory(float(n) * T * T * (ex.shape[2] * 8 + 1) + 4.0 * T * T * ex.shape[2] * 8 * 3, k, "colors",
                 f"{n} tiles of {T} x {T}", also={"tile": T})
    gen = as_rng(rng)
    m = o // 2
    a = T // 2 + m + 1
    exf = ex.astype(np.float64)
    edges = tile_edges(k)
    searches = None
    if tolerance is not None:  # every exemplar position scored at once by FFT correlation (quilting's search)
        from ..core.search import WindowSearch

        searches = [WindowSearch(exf, shape) for shape in ((2 * a, T), (T, 2 * a))]
    t_samples = t_tiles = 0.0
    best, set_costs = None, []
    with Progress(progress, n * n_sets, "wang tiles") as bar:
        for _ in range(n_sets):
            # Section 3.2: one sample (the diamond's bounding box) per colour, then the tiles
            t0 = time.perf_counter()
            samples = _choose_samples(exf, T, a, m, k, tolerance, gen, searches)
            samples_h = [exf[r:r + 2 * a, c:c + T] for r, c in samples[0]]
            samples_v = [exf[r:r + T, c:c + 2 * a] for r, c in samples[1]]
            t1 = time.perf_counter()
            tiles = np.empty((n, T, T, ex.shape[2]), dtype=image.dtype)
            labels = np.empty((n, T, T), dtype=np.uint8)
            costs = np.zeros((n, 2))
            for i, edge in enumerate(edges):
                layers = _diamond_layers(samples_h, samples_v, edge, T, a, ex.shape[2])
                tiles[i], labels[i], costs[i] = _make_tile(layers, m, cut)
                bar.advance()
            t_samples, t_tiles = t_samples + t1 - t0, t_tiles + time.perf_counter() - t1
            set_costs.append(float(costs.sum()))
            if best is None or set_costs[-1] < best[0]:  # the set whose cuts cost least
                best = (set_costs[-1], samples, tiles, labels, costs)
    _, samples, tiles, labels, costs = best
    result = WangTileSet(tiles=np.ascontiguousarray(tiles[..., 0]) if grey else tiles, edges=edges, colors=k,
                         coordinates=_tile_coordinates(samples, edges, labels, T, a))
    if not return_info:
        return result
    total = time.perf_counter() - started
    return result, WangTilesInfo(samples=samples, labels=labels, seam_costs=costs, set_costs=np.array(set_costs),
                                 overlap=o, seconds=total,
                                 stage_seconds={"checks": total - t_samples - t_tiles, "samples": t_samples,
                                                "tiles": t_tiles})


def _check_tile_set(tiles):
    if not isinstance(tiles, WangTileSet):
        raise TypeError(f"tiles must be a WangTileSet (from texsynth.wang_tiles), got {type(tiles).__name__}")
    edges = np.asarray(tiles.edges)
    if tiles.tiles.ndim not in (3, 4) or edges.shape != (tiles.tiles.shape[0], 4) or tiles.tiles.shape[0] == 0:
        raise ValueError(f"tiles holds {tiles.tiles.shape} images and {edges.shape} edges; it needs (n, T, T[, C]) "
                         "images and (n, 4) edge colours")
    return edges


def wang_tiling(tiles, size, *, tileable=False, rng=None, return_info=False):
    """Cover an image of any size with Wang tiles, chosen at random in scanline order (Cohen et al. 2003).

    Examples
    --------
    >>> import texsynth
    >>> tiles = texsynth.wang_tiles(texsynth.data.load("bread")[:96, :96], 32, rng=0)
    >>> out, info = texsynth.wang_tiling(tiles, (100, 70), rng=0, return_info=True)
    >>> out.shape, info.indices.shape
    ((100, 70, 3), (4, 3))

    Each tile is drawn at random among those whose north and west edge
    colours match the tiles above and to the left (Section 4), so the
    tiling never repeats in a regular way; a tile set is reused for any
    number of outputs [1]_.

    Parameters
    ----------
    tiles : WangTileSet
        A tile set from :func:`wang_tiles`.
    size : int or (int, int)
        Output size ``(height, width)``; the last row and column of tiles are
        cropped if it is not a multiple of the tile.
    tileable : bool
        A toroidal tiling, so the output tiles seamlessly: the last column's
        east colours are the first column's west colours, the last row's
        south colours the first row's north colours, so the wrap-around
        edges are ordinary tile edges of matching colours. Needs a ``size``
        of at least two whole tiles in each direction (a multiple of the
        tile: a cropped tile would break the wrap) and a set of two colours
        per direction: see Notes.
    rng : None, int or numpy.random.Generator
        Random source for the choice of tiles.
    return_info : bool
        Also return a :class:`WangTilingInfo` with the map of tile indices.

    Returns
    -------
    image : numpy.ndarray
        ``size``, the tiles' channel layout and dtype.
    info : WangTilingInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If the set has no tile for a (north, west) pair that the tiling
        meets (or, tileable, for the colours the wrap fixes), the output
        would not fit in memory, or ``tileable`` with a size that is not a
        multiple of at least two tiles.
    TypeError
        If ``tiles`` is not a :class:`WangTileSet`.

    Notes
    -----

    *Tileable.* The last tile of a row must also match the row's first
    tile on its east edge, the tiles of the last row the first row on
    their south edges. With :func:`tile_edges`' set of two colours this
    never fails: its two tiles of each (north, west) pair differ in east
    and in south colour, so the last column and the last row have exactly
    one tile each, and every tile has ``N + W = S + E`` (mod 2), which,
    summed over the torus, makes the corner's four constraints agree. With
    more colours a scanline choice can reach an east or south colour that
    no tile of its (north, west) pair has, so ``wang_texture`` refuses
    ``tileable`` with ``colors > 2``.

    Section 4 of the paper: the tiles are placed row by row, left to right;
    each is drawn uniformly among the tiles whose north colour is the south
    colour of the tile above and whose west colour is the east colour of the
    tile to the left (the first row and column have one constraint, the
    first tile none). The tiles are then copied into the output one row of
    tiles at a time, a gather of the row's tiles into a view of the output
    (``benchmarks/bench_wang_tiles.py``: a 4096 x 4096 colour output in well
    under a second, most of it the operating system mapping the output's
    memory).

    References
    ----------
    .. [1] M. F. Cohen, J. Shade, S. Hiller and O. Deussen, "Wang tiles for
       image and texture generation", ACM TOG 22(3) (SIGGRAPH 2003),
       pp. 287-294. :doi:`10.1145/882262.882265`
    """
    started = time.perf_counter()
    edges = _check_tile_set(tiles)
    size = as_size(size)
    images = tiles.tiles
    T = images.shape[1]
    channels = images.shape[3] if images.ndim == 4 else 1
    n_rows, n_cols = math.ceil(size[0] / T), math.ceil(size[1] / T)
    if check_bool(tileable, "tileable") and (size[0] % T or size[1] % T or min(n_rows, n_cols) < 2):
        raise ValueError(f"a tileable tiling needs a size that is a multiple of the tile ({T}) with at least two "
                         f"tiles in each direction, got {size}; pass e.g. size="
                         f"{(max(2, round(size[0] / T)) * T, max(2, round(size[1] / T)) * T)}")
    check_memory(float(size[0]) * size[1] * channels * images.dtype.itemsize + 8.0 * n_rows * n_cols, size, "size")
    gen = as_rng(rng)
    # Section 4: the scanline choice, each tile among those matching the tile above and the tile to the left
    options = {}
    for north in range(-1, int(edges[:, NORTH].max()) + 1):
        for west in range(-1, int(edges[:, WEST].max()) + 1):
            ok = np.ones(len(edges), dtype=bool)
            if north >= 0:
                ok &= edges[:, NORTH] == north
            if west >= 0:
                ok &= edges[:, WEST] == west
            options[north, west] = np.flatnonzero(ok)
    draws = gen.random((n_rows, n_cols))
    indices = np.empty((n_rows, n_cols), dtype=np.int64)
    south, east = edges[:, SOUTH].tolist(), edges[:, EAST].tolist()
    for r in range(n_rows):
        for c in range(n_cols):
            north = south[indices[r - 1, c]] if r else -1
            west = east[indices[r, c - 1]] if c else -1
            choice = options.get((north, west))
            if choice is None or choice.size == 0:
                raise ValueError(f"tiles has no tile with north colour {north} and west colour {west}; a set needs "
                                 "at least one tile for every pair (wang_tiles makes two)")
            if tileable and (r == n_rows - 1 or c == n_cols - 1):  # the wrap: match the first column and row too
                wraps = np.ones(choice.size, bool)
                if c == n_cols - 1:
                    wraps &= edges[choice, EAST] == edges[indices[r, 0], WEST]
                if r == n_rows - 1:
                    wraps &= edges[choice, SOUTH] == edges[indices[0, c], NORTH]
                choice = choice[wraps]
                if choice.size == 0:
                    raise ValueError(f"tiles has no tile for the wrap at tile ({r}, {c}) of a tileable tiling; a set "
                                     "of two colours per direction always has one (wang_tiles(..., colors=2))")
            indices[r, c] = choice[int(draws[r, c] * choice.size)]
    t_choice = time.perf_counter() - started
    out = np.empty(size + images.shape[3:], dtype=images.dtype)
    whole = size[1] // T  # tiles that fit whole across
    for r in range(n_rows):  # one row of tiles at a time: no temporary of the output's size
        rows = min(T, size[0] - r * T)
        if whole:
            band = out[r * T:r * T + rows, :whole * T]
            band.shape = (rows, whole, T) + images.shape[3:]  # a view (assigning .shape never copies)
            band[...] = images[indices[r, :whole], :rows].swapaxes(0, 1)
        if whole < n_cols:  # the cropped last column
            out[r * T:r * T + rows, whole * T:] = images[indices[r, whole], :rows, :size[1] - whole * T]
    if not return_info:
        return out
    coordinates = None
    if tiles.coordinates is not None:  # the same gather as the images: (rows, T, columns, T, 2), cropped
        grid = np.asarray(tiles.coordinates)[indices].swapaxes(1, 2)
        coordinates = grid.reshape(n_rows * T, n_cols * T, 2)[: size[0], : size[1]].copy()
    total = time.perf_counter() - started
    return out, WangTilingInfo(indices=indices, tiles=tiles, seconds=total,
                               stage_seconds={"choice": t_choice, "assembly": total - t_choice},
                               coordinates=coordinates)


def wang_texture(exemplar, size, *, tile="auto", colors=2, overlap="auto", error_tolerance=ERROR_TOLERANCE,
                 n_candidates=CANDIDATES, cut=True, tileable=False, rng=None, return_info=False, progress=False):
    """Synthesise a texture of any size with Wang tiles: a tile set, then a random tiling (Cohen et al. 2003).

    Examples
    --------
    >>> import texsynth
    >>> brick = texsynth.data.load("brick")[:96, :96]
    >>> texsynth.wang_texture(brick, 200, tile=32, rng=0).shape
    (200, 200, 3)

    The same as ``wang_tiling(wang_tiles(exemplar, tile, ...), size)`` with one random source for both
    (:func:`wang_tiles`, :func:`wang_tiling`): a small set of tiles quilted
    from the exemplar, whose matching edge colours let a random tiling of
    any size join without seams [1]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture: ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    size : int or (int, int)
        Output size ``(height, width)``.
    tile, colors, overlap, error_tolerance, n_candidates, cut :
        As in :func:`wang_tiles`.
    tileable : bool
        Output that tiles seamlessly (a toroidal tiling, see
        :func:`wang_tiling`): ``size`` a multiple of the tile, at least two
        tiles each way, and ``colors=2``.
    rng : None, int or numpy.random.Generator
        Random source for the samples and the tiling.
    return_info : bool
        Also return a :class:`WangTilingInfo` (the tile set and the map of
        tile indices).
    progress : bool or callable
        Report progress per tile made.

    Returns
    -------
    image : numpy.ndarray
        ``size``, the exemplar's channel layout; float32 for float32 input,
        float64 otherwise.
    info : WangTilingInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        As :func:`wang_tiles` and :func:`wang_tiling`.

    References
    ----------
    .. [1] M. F. Cohen, J. Shade, S. Hiller and O. Deussen, "Wang tiles for
       image and texture generation", ACM TOG 22(3) (SIGGRAPH 2003),
       pp. 287-294. :doi:`10.1145/882262.882265`
    """
    started = time.perf_counter()
    size = as_size(size)
    if check_bool(tileable, "tileable") and colors != 2:
        raise ValueError(f"tileable=True needs colors=2, got colors={colors!r}: with more colours a random tiling "
                         "cannot always close around the torus (see wang_tiling's Notes)")
    gen = as_rng(rng)
    tiles = wang_tiles(exemplar, tile, colors=colors, overlap=overlap, error_tolerance=error_tolerance,
                       n_candidates=n_candidates, cut=cut, rng=gen, progress=progress)
    t_tiles = time.perf_counter() - started
    out, info = wang_tiling(tiles, size, tileable=tileable, rng=gen, return_info=True)
    if not return_info:
        return out
    info.stage_seconds = {"tiles": t_tiles, **info.stage_seconds}
    info.seconds = time.perf_counter() - started
    return out, info
