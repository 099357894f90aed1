"""Optimal seams between overlapping images: minimum-error boundary cuts and grid min-cuts.

Patch-based methods paste a new piece of texture ``B`` over an output ``A``
that already covers part of it, and hide the join by choosing *where* in the
overlap each pixel stops coming from ``A`` and starts coming from ``B``: along
a seam where the two agree. This module finds such seams two ways.

Minimum-error boundary cut (Efros & Freeman 2001, Section 2.1)
--------------------------------------------------------------
For a vertical overlap strip with error surface ``e_ij = ||A_ij - B_ij||^2``
the cheapest 8-connected path from the top row to the bottom row (one pixel
per row, moving at most one column between rows) follows from the cumulative
minimum error

.. math:: E_{i,j} = e_{i,j} + \\min(E_{i-1,j-1},\\, E_{i-1,j},\\, E_{i-1,j+1})

by tracing back from the smallest ``E`` of the last row. The same dynamic
programme is seam carving's (Avidan & Shamir 2007, eq. 4 with an energy map for
``e``). :func:`cumulative_cost` computes ``E``, :func:`backtrack` traces a seam
through it, :func:`minimum_error_boundary` does both, and :func:`seam_mask`
marks the pixels on one side of a seam. ``direction="horizontal"`` runs every
one of them left to right (on the transposed array).

Graph cut (Kwatra, Schödl, Essa, Turk & Bobick 2003, Section 3)
-----------------------------------------------------------------
:func:`graph_cut` labels every pixel of a 2-D overlap ``A`` (old) or ``B``
(new) (or every voxel of a 3-D one, ``spatial_dims=3``: the paper's video
synthesis, Section 5, with 6-connected voxels and seams that are surfaces in
space and time) by a minimum cut of the 4-connected grid graph whose arc between
neighbours ``s`` and ``t`` costs the matching quality cost
``M(s, t, A, B) = ||A(s) - B(s)|| + ||A(t) - B(t)||`` (:func:`matching_cost`;
the paper's gradient-normalised ``M'`` is :func:`gradient_matching_cost`),
with pixels that must stay old tied to the source terminal ``A`` and pixels
that must come from the new patch tied to the sink terminal ``B`` by infinite
arcs. Where two neighbours of the old output came from different old patches
``A_s`` and ``A_t`` an old seam runs between them; a *seam node* replaces
their arc (the paper's Section 3, "Accounting for old seams") with three:
``s``-seam ``M(s, t, A_s, B)``, seam-``t`` ``M(s, t, B, A_t)`` and seam-``B``
``M(s, t, A_s, A_t)``, the old seam's own cost. A cut through the seam-``B``
arc keeps the old seam, one through a pixel arc replaces it by a new seam, and
a cut through neither removes it, so the new cut pays for old seams it keeps
and no more; when ``M`` obeys the triangle inequality (any norm does) at most
one of the three arcs is cut.

The maximum flow is :func:`scipy.sparse.csgraph.maximum_flow` (Dinic), which
takes integer capacities only; how they are scaled and what that costs is in
the notes of :func:`graph_cut`.

References
----------
.. [1] A. A. Efros and W. T. Freeman, "Image quilting for texture synthesis
   and transfer", SIGGRAPH 2001, pp. 341-346. :doi:`10.1145/383259.383296`
.. [2] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
   textures: image and video synthesis using graph cuts", ACM TOG 22(3)
   (SIGGRAPH 2003), pp. 277-286. :doi:`10.1145/882262.882264`
.. [3] S. Avidan and A. Shamir, "Seam carving for content-aware image
   resizing", ACM TOG 26(3) (SIGGRAPH 2007). :doi:`10.1145/1275808.1276390`
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ._validate import check_memory, check_positive_int

__all__ = [
    "DIRECTIONS",
    "backtrack",
    "cumulative_cost",
    "GRADIENT_EPSILON",
    "gradient_matching_cost",
    "graph_cut",
    "matching_cost",
    "minimum_error_boundary",
    "poisson_blend",
    "BLEND_SMOOTHING",
    "seam_mask",
    "EDGE_COSTS",
    "edge_cost_function",
]

#: Values of ``direction``: a vertical seam runs top to bottom (one column per
#: row), a horizontal seam left to right (one row per column).
DIRECTIONS = ("vertical", "horizontal")

# Integer capacities of the max-flow: every finite capacity is scaled so that
# their sum is this (scipy's maximum_flow computes in int32, and silently wraps
# larger values), leaving room below 2**31 - 1 for the "infinite" constraint arcs.
_CAPACITY_SUM = 2**30
_INT32_MAX = 2**31 - 1
# bytes per pixel of the graph: 2 x 4 plain arcs, a seam node's 5 arcs, terminal
# arcs, csr indices and data, the flow and the residual graph (measured ~180)
_GRAPH_BYTES_PER_PIXEL = 256
# poisson_blend's memory: per blended pixel, the sparse system, its LU factors (a band's fill-in) and the
# right-hand sides; per image pixel, the distance transform and the image-sized index and smoothing layers.
# Peak growth measured 52, 225 and 722 MiB for the 32-px band round a 256, 1024 and 3000 px square centred in
# 512, 2048 and 4096 px images (36,000-387,000 band pixels): at most 2 kB per band pixel, all counted
_BLEND_BYTES_PER_PIXEL = 2048
_BLEND_BYTES_PER_IMAGE_PIXEL = 64
#: Sigma in pixels of the Gaussian along the border that smooths a fill's mismatch before
#: :func:`poisson_blend` removes it: on seven photographs (``benchmarks/bench_completion.py``'s fills) 2 px
#: left the most seams and 8 px the most real edges smeared; 4 px kept boundary seams near the texture's own
#: (1.07 mean) with fewer pixels changed by more than 0.3 than without smoothing (docs/methods/completion.md)
BLEND_SMOOTHING = 4.0
# a border tie is trusted by exp(-(step / tau)^2), the steepest step within _BLEND_LINE_DEPTH pixels behind the
# border against tau = _BLEND_TRUST_STEPS times the texture's median step: a mortar line along a hole's rim made a
# dark spot without it (docs/methods/completion.md)
_BLEND_LINE_DEPTH = 2
_BLEND_TRUST_STEPS = 4.0


# --------------------------------------------------------------------------- checks


def _check_direction(direction):
    if direction not in DIRECTIONS:
        raise ValueError(f"direction must be 'vertical' or 'horizontal', got {direction!r}")
    return direction


def _as_cost_array(cost, name="cost"):
    """A 2-D finite real array as float64."""
    arr = np.asarray(cost)
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == np.bool_) \
            or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 2-D array (rows, columns), got shape {arr.shape}")
    arr = arr.astype(np.float64, copy=False)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; pass finite costs (e.g. np.nan_to_num)")
    return arr


# --------------------------------------------------------------------------- minimum-error boundary cut


def cumulative_cost(cost, *, direction="vertical", step_costs=None):
    """The cumulative minimum error ``E`` of the minimum-error boundary cut.

    Parameters
    ----------
    cost : array_like, shape (h, w)
        The error ``e`` of every pixel: the squared difference of two
        overlapping images (quilting) or an energy map (seam carving).
    direction : {"vertical", "horizontal"}
        ``"vertical"``: seams run from the top row to the bottom row;
        ``"horizontal"``: from the left column to the right column.
    step_costs : (array_like or None, array_like or None, array_like or None), optional
        Costs of the three steps into a pixel, each of shape ``(h, w)``
        (None: 0): from the pixel above-left, above, and above-right
        (``(i-1, j-1)``, ``(i-1, j)``, ``(i-1, j+1)``) for vertical seams;
        from ``(i-1, j-1)``, ``(i, j-1)``, ``(i+1, j-1)`` for horizontal
        ones. The first row's (column's) values are not used. Seam carving's
        forward energy (Rubinstein, Shamir & Avidan 2008) is a pixel cost
        plus such step costs.

    Returns
    -------
    numpy.ndarray, shape (h, w), float64
        ``E[i, j]``, the cost of the cheapest seam from the first row to pixel
        ``(i, j)`` (first column, for horizontal seams), pixel ``(i, j)``
        included.

    Notes
    -----
    Efros & Freeman 2001, Section 2.1:

    .. math:: E_{i,j} = e_{i,j} + \\min(E_{i-1,j-1},\\, E_{i-1,j},\\, E_{i-1,j+1}),
              \\qquad E_{0,j} = e_{0,j}.

    With ``step_costs = (C_L, C_U, C_R)`` each term of the minimum carries
    its step's cost: ``min(E_{i-1,j-1} + C_L(i,j), E_{i-1,j} + C_U(i,j),
    E_{i-1,j+1} + C_R(i,j))``.

    One vectorized step per row (each row needs the one above, so the loop
    over rows is sequential).

    Examples
    --------
    >>> e = np.array([[1.0, 5.0, 1.0], [5.0, 1.0, 5.0], [1.0, 5.0, 9.0]])
    >>> cumulative_cost(e)
    array([[ 1.,  5.,  1.],
           [ 6.,  2.,  6.],
           [ 3.,  7., 11.]])
    """
    e = _as_cost_array(cost)
    steps = _as_step_costs(step_costs, e.shape)
    if _check_direction(direction) == "horizontal":
        return cumulative_cost(e.T, step_costs=None if steps is None else [_t(c) for c in steps]).T
    h, w = e.shape
    out = np.empty_like(e)
    out[0] = e[0]
    above = np.full(w + 2, np.inf)  # E of the row above, with +inf beyond both ends
    if steps is None:
        for i in range(1, h):
            above[1:-1] = out[i - 1]
            row = out[i]
            np.minimum(above[:-2], above[2:], out=row)  # min(E[i-1, j-1], E[i-1, j+1])
            np.minimum(row, above[1:-1], out=row)  # ... and E[i-1, j]
            row += e[i]
        return out
    left, up, right = steps
    for i in range(1, h):
        above[1:-1] = out[i - 1]
        row = out[i]
        candidates = [above[:-2] if left is None else above[:-2] + left[i],
                      above[1:-1] if up is None else above[1:-1] + up[i],
                      above[2:] if right is None else above[2:] + right[i]]
        np.minimum(candidates[0], candidates[2], out=row)
        np.minimum(row, candidates[1], out=row)
        row += e[i]
    return out


def _t(array):
    return None if array is None else array.T


def _as_step_costs(step_costs, shape):
    """``step_costs`` as three float64 arrays of ``shape`` (or None), or None."""
    if step_costs is None:
        return None
    try:
        parts = list(step_costs)
    except TypeError:
        raise TypeError("step_costs must be a triple (left, up, right) of arrays or None") from None
    if len(parts) != 3:
        raise ValueError(f"step_costs must hold 3 entries (left, up, right), got {len(parts)}")
    out = []
    for name, part in zip(("left", "up", "right"), parts):
        if part is None:
            out.append(None)
            continue
        arr = _as_cost_array(part, f"step_costs' {name}")
        if arr.shape != shape:
            raise ValueError(f"step_costs' {name} has shape {arr.shape}; it needs the cost's shape {shape}")
        out.append(arr)
    return out


def backtrack(cumulative, *, direction="vertical", step_costs=None):
    """Trace the cheapest seam back through a cumulative cost map.

    Parameters
    ----------
    cumulative : array_like, shape (h, w)
        ``E`` from :func:`cumulative_cost` (or any map built by the same
        recurrence).
    direction : {"vertical", "horizontal"}
        As the map was built.
    step_costs : (array_like or None, array_like or None, array_like or None), optional
        The step costs the map was built with (see :func:`cumulative_cost`).

    Returns
    -------
    numpy.ndarray of intp
        The seam: for a vertical seam its column in each of the ``h`` rows,
        for a horizontal seam its row in each of the ``w`` columns.
        Neighbouring entries differ by at most 1.

    Notes
    -----
    The seam ends at the smallest ``E`` of the last row (the lowest column on
    ties) and steps to whichever of the three pixels above has the smallest
    ``E``, preferring straight up on ties, so a flat cost gives a straight seam.

    Examples
    --------
    >>> backtrack(cumulative_cost(np.array([[1.0, 5.0, 1.0], [5.0, 1.0, 5.0], [1.0, 5.0, 9.0]])))
    array([0, 1, 0])
    """
    E = _as_cost_array(cumulative, "cumulative")
    steps = _as_step_costs(step_costs, E.shape)
    if _check_direction(direction) == "horizontal":
        E = E.T
        steps = None if steps is None else [_t(c) for c in steps]
    h, w = E.shape
    seam = np.empty(h, dtype=np.intp)
    j = int(np.argmin(E[-1]))
    seam[-1] = j
    if steps is None:
        for i in range(h - 2, -1, -1):
            row = E[i]
            best = j
            if j > 0 and row[j - 1] < row[best]:
                best = j - 1
            if j + 1 < w and row[j + 1] < row[best]:
                best = j + 1
            seam[i] = j = best
        return seam
    left, up, right = steps
    for i in range(h - 2, -1, -1):  # the step into (i + 1, j) from (i, j - 1), (i, j) or (i, j + 1)
        row = E[i]
        best, value = j, row[j] + (0.0 if up is None else up[i + 1, j])
        if j > 0:
            candidate = row[j - 1] + (0.0 if left is None else left[i + 1, j])
            if candidate < value:
                best, value = j - 1, candidate
        if j + 1 < w:
            candidate = row[j + 1] + (0.0 if right is None else right[i + 1, j])
            if candidate < value:
                best = j + 1
        seam[i] = j = best
    return seam


def minimum_error_boundary(cost, *, direction="vertical", step_costs=None):
    """The minimum-cost 8-connected seam through an error surface (Efros & Freeman 2001, Section 2.1).

    Parameters
    ----------
    cost : array_like, shape (h, w)
        Error of every pixel of the overlap, e.g. ``((old - new) ** 2).sum(-1)``.
    direction : {"vertical", "horizontal"}
        ``"vertical"``: the seam crosses the strip from top to bottom (a left
        or right overlap); ``"horizontal"``: from left to right (a top or
        bottom overlap).
    step_costs : (array_like or None, array_like or None, array_like or None), optional
        Costs of the three steps into each pixel (see :func:`cumulative_cost`);
        default none.

    Returns
    -------
    numpy.ndarray of intp
        The seam's column in each row (vertical) or row in each column
        (horizontal). No other such path has a smaller total cost.

    Raises
    ------
    ValueError, TypeError
        If ``cost`` is not a finite 2-D real array, or ``direction`` is unknown.

    Notes
    -----
    ``backtrack(cumulative_cost(cost))``: the dynamic programme of eq. (Section
    2.1) ``E_ij = e_ij + min(E_{i-1,j-1}, E_{i-1,j}, E_{i-1,j+1})``, O(h w).
    scikit-image's :class:`skimage.graph.MCP` finds the same path when its
    moves are limited to the three pixels below (``offsets=[(1, -1), (1, 0),
    (1, 1)]``; with its default moves, as in ``route_through_array``, a path
    may also run sideways and is no seam). ``benchmarks/bench_quilting.py``
    measures MCP 1.7 times slower on quilting's 64 x 11 strips and about 50
    times slower on a 512 x 512 energy map, so the programme is written here.

    Examples
    --------
    The seam follows the valley of low error:

    >>> e = np.ones((4, 5)); e[[0, 1, 2, 3], [3, 2, 2, 1]] = 0
    >>> minimum_error_boundary(e)
    array([3, 2, 2, 1])
    >>> minimum_error_boundary(e.T, direction="horizontal")
    array([3, 2, 2, 1])
    """
    return backtrack(cumulative_cost(cost, direction=direction, step_costs=step_costs), direction=direction,
                     step_costs=step_costs)


def seam_mask(seam, shape, *, direction="vertical"):
    """The pixels before a seam: left of a vertical seam, above a horizontal one.

    Parameters
    ----------
    seam : array_like of int
        A vertical seam's column in each row (``shape[0]`` entries) or a
        horizontal seam's row in each column (``shape[1]`` entries).
    shape : (int, int)
        ``(h, w)`` of the strip.
    direction : {"vertical", "horizontal"}

    Returns
    -------
    numpy.ndarray of bool, shape (h, w)
        True strictly before the seam (``j < seam[i]``, or ``i < seam[j]``);
        the seam's own pixels and everything after it are False. ``~mask``
        is the side from the seam on; ``seam_mask(seam + 1, ...)`` includes
        the seam.

    Examples
    --------
    >>> seam_mask([1, 2], (2, 3)).astype(int)
    array([[1, 0, 0],
           [1, 1, 0]])
    """
    direction = _check_direction(direction)
    h, w = int(shape[0]), int(shape[1])
    length, across = (h, w) if direction == "vertical" else (w, h)
    seam = np.asarray(seam)
    if seam.shape != (length,) or not np.issubdtype(seam.dtype, np.integer):
        raise ValueError(f"seam must hold {length} integers (one per {'row' if direction == 'vertical' else 'column'}) "
                         f"for shape {(h, w)} and direction {direction!r}, got dtype {seam.dtype} shape {seam.shape}")
    if seam.min() < 0 or seam.max() > across:
        raise ValueError(f"seam values must lie in 0..{across}, got {seam.min()}..{seam.max()}")
    mask = np.arange(across)[None, :] < seam[:, None]
    return mask if direction == "vertical" else mask.T


# --------------------------------------------------------------------------- graph cut


def matching_cost(a_s, a_t, b_s, b_t):
    """Kwatra et al.'s matching quality cost ``M(s, t, A, B) = ||A(s) - B(s)|| + ||A(t) - B(t)||``.

    Parameters
    ----------
    a_s, a_t, b_s, b_t : numpy.ndarray, shape (n, C)
        The values of images ``A`` and ``B`` at the two pixels ``s`` and
        ``t`` of ``n`` neighbouring pairs.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The cost of a seam between ``s`` and ``t`` that takes ``s`` from
        ``A`` and ``t`` from ``B`` (or the reverse): the Euclidean norm over
        the channels, not its square, so it obeys the triangle inequality
        that the old-seam construction of :func:`graph_cut` needs.

    Examples
    --------
    >>> matching_cost(np.array([[0.0]]), np.array([[1.0]]), np.array([[0.5]]), np.array([[1.0]]))
    array([0.5])
    """
    return np.sqrt(((a_s - b_s) ** 2).sum(-1)) + np.sqrt(((a_t - b_t) ** 2).sum(-1))


#: ``ε`` added to the gradient terms of :func:`gradient_matching_cost` (values in [0, 1]): it keeps the cost
#: finite where both images are flat, and there makes a seam about ``M / ε`` dear (not in the paper).
GRADIENT_EPSILON = 0.01


def gradient_matching_cost(a_s, a_t, b_s, b_t):
    """Kwatra et al.'s gradient-normalised matching cost ``M'``: seams are cheaper where the images vary.

    Parameters
    ----------
    a_s, a_t, b_s, b_t : numpy.ndarray, shape (n, C)
        The values of images ``A`` and ``B`` at the two pixels ``s`` and
        ``t`` of ``n`` neighbouring pairs (values in [0, 1]).

    Returns
    -------
    numpy.ndarray, shape (n,)
        ``M(s, t, A, B)`` of :func:`matching_cost` divided by the gradients
        of both images along the pair's direction, finite and >= 0.

    Notes
    -----
    The paper's Section 3 ("Cost function"):

    .. math:: M'(s, t, A, B) = \\frac{\\|A(s) - B(s)\\| + \\|A(t) - B(t)\\|}
              {\\|G^d_A(s)\\| + \\|G^d_A(t)\\| + \\|G^d_B(s)\\| + \\|G^d_B(t)\\|}

    with ``G^d`` the gradient along the direction ``d`` of the arc
    ``s``-``t``. Here the gradient at both ends of the arc is the finite
    difference along it, ``G^d_A(s) = G^d_A(t) = A(t) - A(s)``, so ``M'``
    needs the four values an edge cost receives and nothing else (the
    paper's discretisation of ``G^d`` could not be checked), and
    :data:`GRADIENT_EPSILON` is added to the denominator so that flat
    regions give a large finite cost instead of a division by zero. ``M'``
    does not obey the triangle inequality, so with old seams the cut is the
    minimum of the graph but a seam node may charge a little more or less
    than the seams it stands for (see :func:`graph_cut`).

    Examples
    --------
    The same mismatch costs less across an edge of the images than in a flat region:

    >>> flat, edge = np.array([[0.5]]), np.array([[1.0]])
    >>> float(gradient_matching_cost(flat, flat, flat + 0.1, flat + 0.1)[0])  # 0.2 / 0.01
    20.0
    >>> round(float(gradient_matching_cost(flat, edge, flat + 0.1, edge + 0.1)[0]), 4)  # 0.2 / 2.01
    0.0995
    """
    gradients = 2.0 * (np.sqrt(((a_t - a_s) ** 2).sum(-1)) + np.sqrt(((b_t - b_s) ** 2).sum(-1)))
    return matching_cost(a_s, a_t, b_s, b_t) / (gradients + GRADIENT_EPSILON)


#: The seam costs a graph cut's ``edge_cost`` may name: the paper's ``M`` and its gradient-normalised ``M'``.
EDGE_COSTS = {"plain": matching_cost, "gradient": gradient_matching_cost}


def edge_cost_function(edge_cost):
    """``edge_cost`` as a function: ``"plain"`` (Kwatra et al.'s ``M``), ``"gradient"`` (``M'``) or a callable
    ``edge_cost(a_s, a_t, b_s, b_t)`` itself; a ValueError naming ``edge_cost`` otherwise."""
    if callable(edge_cost):
        return edge_cost
    if isinstance(edge_cost, str) and edge_cost in EDGE_COSTS:
        return EDGE_COSTS[edge_cost]
    raise ValueError(f"edge_cost must be 'plain' (the paper's M), 'gradient' (its gradient-normalised M') or a "
                     f"callable edge_cost(a_s, a_t, b_s, b_t), got {edge_cost!r}")


def _as_values(image, name, spatial_dims=2):
    """A finite real image (volume) as float64 ``(H, W, C)`` (``(T, H, W, C)`` with ``spatial_dims=3``)."""
    arr = np.asarray(image)
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == np.bool_) \
            or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim not in (spatial_dims, spatial_dims + 1) or arr.size == 0:
        axes = "(H, W)" if spatial_dims == 2 else "(T, H, W)" if spatial_dims == 3 else f"{spatial_dims} axes"
        raise ValueError(f"{name} must have shape {axes} or {axes[:-1]}, C), got {arr.shape}")
    arr = arr.astype(np.float64, copy=False)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) first")
    return arr if arr.ndim == spatial_dims + 1 else arr[..., None]


def _as_mask(mask, shape, name, default):
    if mask is None:
        return np.full(shape, default)
    arr = np.asarray(mask)
    if arr.shape != shape or arr.dtype != np.bool_:
        raise ValueError(f"{name} must be a bool array of shape {shape} (one value per pixel of the image), "
                         f"got dtype {arr.dtype} shape {arr.shape}")
    return arr


def check_disjoint(first, second, names, fix):
    """Refuse two constraint masks that share a pixel, naming both, the first shared pixel and ``fix``."""
    both = first & second
    if both.any():
        where = np.argwhere(both)[0]
        at = (f"row {where[0]}, column {where[1]}" if where.size == 2
              else "frame {}, row {}, column {}".format(*where) if where.size == 3 else f"index {tuple(where)}")
        raise ValueError(f"{names[0]} and {names[1]} both hold {int(both.sum())} pixels (the first at {at}); {fix}")


def _neighbour_pairs(mask):
    """Flat indices ``(s, t)`` of grid neighbours (4 in 2-D, 6 in 3-D) that both lie in ``mask``.

    The pairs along the last axis first (right neighbours), then along each earlier axis in turn (down, then,
    in a volume, the next frame).
    """
    flat = np.arange(mask.size).reshape(mask.shape)
    s, t = [], []
    for axis in range(mask.ndim - 1, -1, -1):
        lo = tuple(slice(None, -1) if a == axis else slice(None) for a in range(mask.ndim))
        hi = tuple(slice(1, None) if a == axis else slice(None) for a in range(mask.ndim))
        both = mask[lo] & mask[hi]
        s.append(flat[lo][both])
        t.append(flat[hi][both])
    return np.concatenate(s), np.concatenate(t)


def _edge_costs(edge_cost, a_s, a_t, b_s, b_t):
    values = np.asarray(edge_cost(a_s, a_t, b_s, b_t), dtype=np.float64)
    if values.shape != (a_s.shape[0],):
        raise ValueError(f"edge_cost must return one cost per pair, shape ({a_s.shape[0]},), got {values.shape}")
    if not (np.all(np.isfinite(values)) and (values.size == 0 or values.min() >= 0)):
        raise ValueError("edge_cost returned negative, NaN or infinite costs; a cut needs finite costs >= 0")
    return values


def graph_cut(old, new, *, mask=None, old_mask=None, new_mask=None, labels=None, patches=None,
              edge_cost=matching_cost, spatial_dims=2):
    """The minimum-cost seam between an old image and a new patch over an overlap (Kwatra et al. 2003).

    The overlap is 2-D (images, 4-connected) or, with ``spatial_dims=3``, a
    volume (video, 6-connected: the paper's Section 5, where the seams are
    surfaces in space and time). Below, ``(H, W)`` stands for the grid's shape,
    ``(T, H, W)`` for a volume.

    Parameters
    ----------
    old : array_like, shape (H, W) or (H, W, C)
        The output as it is (Kwatra's ``A``) over the overlap's bounding box.
        Any finite real values (colours, features). With ``spatial_dims=3``:
        ``(T, H, W)`` or ``(T, H, W, C)``.
    new : array_like, same shape as ``old``
        The new patch ``B`` over the same pixels.
    mask : array_like of bool, shape (H, W), optional
        The overlap: the pixels that are nodes of the graph (default every
        pixel). Pixels outside it are not cut and come back False.
    old_mask : array_like of bool, shape (H, W), optional
        Pixels that must keep the old value: tied to the source terminal
        ``A`` by infinite arcs. For patch fitting, the overlap's pixels next
        to pixels that only the old output covers; for a patch placed over
        covered output (the paper's "surrounded regions"), the border of the
        patch.
    new_mask : array_like of bool, shape (H, W), optional
        Pixels that must take the new patch: tied to the sink terminal ``B``.
        For patch fitting, the overlap's pixels next to pixels only the new
        patch covers; for interactive merging, what the user marked.
    labels : array_like of int, shape (H, W), optional
        Which old patch each pixel of ``old`` came from (indices into
        ``patches``). Where two neighbours in ``mask`` have different labels
        an old seam runs between them and gets a seam node. Needs ``patches``.
    patches : array_like, shape (K, H, W[, C]), optional
        The old patches' values over the same pixels (``patches[k]`` is what
        old patch ``k`` shows everywhere, including where another patch won),
        so that ``old`` equals ``patches[labels]`` on ``mask``.
    edge_cost : callable
        ``edge_cost(a_s, a_t, b_s, b_t) -> costs``: the cost of a seam between
        neighbours ``s`` and ``t`` with ``s`` from image ``A`` and ``t`` from
        ``B``, for arrays of pairs ``(n, C)``; finite and >= 0. Default
        :func:`matching_cost`, the paper's ``M`` (Section 3). A cost that
        breaks the triangle inequality (the paper's gradient-normalised ``M'``
        can) still gives the minimum cut of the graph, but the seam nodes then
        no longer charge exactly the cost of the seams the labelling makes.
    spatial_dims : int
        2 for images (the default), 3 for volumes and videos ``(T, H, W[, C])``,
        whose voxels are joined to their 6 neighbours (along time, rows and
        columns). The masks, ``labels`` and ``patches`` then carry the same
        three grid axes.

    Returns
    -------
    new_side : numpy.ndarray of bool, shape (H, W)
        True where the pixel takes the new patch (False outside ``mask``).
    cut_cost : float
        The cost of the seams of that labelling: ``M`` of every neighbouring
        pair with one pixel on each side, plus, per old seam, the cheapest
        of its seam node's arcs that the labelling cuts (``M(s, t, A_s, A_t)``
        if both pixels stay old and the old seam remains).

    Raises
    ------
    ValueError, TypeError
        For images of different shapes or with non-finite values, masks of
        the wrong shape or dtype, a pixel in both ``old_mask`` and
        ``new_mask``, constraints outside ``mask``, ``labels`` without
        ``patches`` (or the reverse), labels out of range, an ``old`` that
        is not ``patches[labels]``, or costs that are negative or not finite.

    Notes
    -----
    *The graph.* One node per pixel of ``mask``, one arc per pair of
    4-neighbours (6-neighbours in a volume) weighted ``M(s, t, A, B)`` (both directions), and one seam
    node per old seam: arcs ``s``-seam ``M(s, t, A_s, B)``, seam-``t``
    ``M(s, t, B, A_t)``, seam-sink ``M(s, t, A_s, A_t)``. The source is the
    old output ``A``, the sink the new patch ``B``. The pixels reachable from
    the source in the residual graph of a maximum flow keep the old value;
    the rest take the new patch (of several minimum cuts, the one with the
    fewest old pixels).

    *Integer capacities.* :func:`scipy.sparse.csgraph.maximum_flow` needs
    integer capacities and computes in 32-bit integers. Every finite cost
    ``c`` becomes ``round(c * 2**30 / S)`` with ``S`` the sum of all finite
    costs of the graph, so no flow can exceed 2**30; the constraint arcs get
    the sum of the scaled capacities plus one, more than any cut of finite
    arcs. Rounding moves each capacity by at most ``S / 2**31``: costs below
    that become 0, and the labelling found is optimal for the rounded costs,
    so its true cost exceeds the minimum by at most ``n_arcs * S / 2**30``
    (relative to the total cost ``S``: under 1e-4 for a million arcs; exact
    on the tests' small grids). ``cut_cost`` is evaluated from the labelling
    in float64, not from the integer flow.

    Memory grows as about 256 bytes per pixel of the overlap; a size that
    does not fit is refused before the graph is built. Dinic's algorithm is
    worst-case O(V^2 E); measured on random colour images (a hard case: no
    cheap seam), a 128 x 128 overlap takes 0.2 s and a 256 x 256 one about
    3 s (``benchmarks/bench_quilting.py``).

    References
    ----------
    .. [1] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
       textures: image and video synthesis using graph cuts", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 277-286. :doi:`10.1145/882262.882264`
    .. [2] Y. Boykov, O. Veksler and R. Zabih, "Fast approximate energy
       minimization via graph cuts", ICCV 1999 (the paper's max-flow code).

    Examples
    --------
    Two flat images that agree only in column 2: the seam runs there.

    >>> old = np.zeros((3, 5)); new = np.ones((3, 5)); old[:, 2] = new[:, 2] = 0.5
    >>> left = np.zeros((3, 5), bool); left[:, 0] = True
    >>> right = np.zeros((3, 5), bool); right[:, 4] = True
    >>> side, cost = graph_cut(old, new, old_mask=left, new_mask=right)
    >>> side.astype(int)
    array([[0, 0, 1, 1, 1],
           [0, 0, 1, 1, 1],
           [0, 0, 1, 1, 1]])
    >>> round(cost, 6)  # three rows of M = |0 - 1| + |0.5 - 0.5|
    3.0
    """
    from scipy.sparse import csr_array
    from scipy.sparse.csgraph import breadth_first_order, maximum_flow

    if spatial_dims not in (2, 3) or isinstance(spatial_dims, bool):
        raise ValueError(f"spatial_dims must be 2 (images) or 3 (volumes and videos), got {spatial_dims!r}")
    nd = int(spatial_dims)
    a = _as_values(old, "old", nd)
    b = _as_values(new, "new", nd)
    if a.shape != b.shape:
        raise ValueError(f"old and new must have the same shape, got {a.shape[:nd]} x {a.shape[nd]} channels and "
                         f"{b.shape[:nd]} x {b.shape[nd]} channels; crop both to the overlap's bounding box")
    shape = a.shape[:nd]
    region = _as_mask(mask, shape, "mask", True)
    keep_old = _as_mask(old_mask, shape, "old_mask", False)
    take_new = _as_mask(new_mask, shape, "new_mask", False)
    check_disjoint(keep_old, take_new, ("old_mask", "new_mask"), "a pixel can be constrained to one side only")
    for name, constraint in (("old_mask", keep_old), ("new_mask", take_new)):
        if (constraint & ~region).any():
            raise ValueError(f"{name} holds {int((constraint & ~region).sum())} pixels outside mask; "
                             f"constrain only pixels of the overlap (pass {name} & mask)")
    if (labels is None) != (patches is None):
        raise ValueError("labels and patches go together: labels says which of patches each old pixel came "
                         "from; pass both, or neither for a cut without old seams")
    n_pix = int(region.sum())
    check_memory(float(_GRAPH_BYTES_PER_PIXEL) * max(n_pix, 1), shape, "old", "the graph of the cut")
    flat_a, flat_b = a.reshape(-1, a.shape[nd]), b.reshape(-1, b.shape[nd])
    s, t = _neighbour_pairs(region)

    seam = np.zeros(s.shape[0], dtype=bool)
    if labels is not None:
        lab, layers = _check_labels(labels, patches, a, region)
        seam = lab[s] != lab[t]
    plain = _edge_costs(edge_cost, flat_a[s[~seam]], flat_a[t[~seam]], flat_b[s[~seam]], flat_b[t[~seam]])
    if seam.any():
        ss, ts = s[seam], t[seam]
        as_s, as_t = layers[lab[ss], ss], layers[lab[ss], ts]  # A_s at s and at t
        at_s, at_t = layers[lab[ts], ss], layers[lab[ts], ts]  # A_t at s and at t
        to_seam = _edge_costs(edge_cost, as_s, as_t, flat_b[ss], flat_b[ts])  # M(s, t, A_s, B)
        from_seam = _edge_costs(edge_cost, flat_b[ss], flat_b[ts], at_s, at_t)  # M(s, t, B, A_t)
        old_seam = _edge_costs(edge_cost, as_s, as_t, at_s, at_t)  # M(s, t, A_s, A_t)
    else:
        ss = ts = np.zeros(0, dtype=np.intp)
        to_seam = from_seam = old_seam = np.zeros(0)

    # nodes: the pixels of the region, then the seam nodes, then the source A and the sink B
    node = np.full(int(np.prod(shape)), -1, dtype=np.int64)
    node[region.ravel()] = np.arange(n_pix)
    n_seam = ss.shape[0]
    seam_node = n_pix + np.arange(n_seam)
    source, sink = n_pix + n_seam, n_pix + n_seam + 1
    finite = np.concatenate([plain, to_seam, from_seam, old_seam])
    scale = _CAPACITY_SUM / finite.sum() if finite.sum() > 0 else 1.0
    plain_i, to_i, from_i, old_i = np.split(np.rint(finite * scale).astype(np.int64),
                                            np.cumsum([plain.size, n_seam, n_seam]))
    infinite = int(plain_i.sum() + to_i.sum() + from_i.sum() + old_i.sum()) + 1
    if infinite > _INT32_MAX:  # pragma: no cover - needs about 2**31 arcs, far beyond check_memory
        raise ValueError("the graph has too many arcs for 32-bit capacities; cut a smaller overlap")
    ps, pt = node[s[~seam]], node[t[~seam]]
    ns, nt = node[ss], node[ts]
    old_nodes, new_nodes = node[keep_old.ravel()], node[take_new.ravel()]
    tails = np.concatenate([ps, pt, ns, seam_node, seam_node, nt, seam_node,
                            np.full(old_nodes.size, source), new_nodes])
    heads = np.concatenate([pt, ps, seam_node, ns, nt, seam_node, np.full(n_seam, sink),
                            old_nodes, np.full(new_nodes.size, sink)])
    caps = np.concatenate([plain_i, plain_i, to_i, to_i, from_i, from_i, old_i,
                           np.full(old_nodes.size + new_nodes.size, infinite)])
    n_nodes = n_pix + n_seam + 2
    graph = csr_array((caps.astype(np.int32), (tails, heads)), shape=(n_nodes, n_nodes))
    flow = maximum_flow(graph, source, sink).flow
    residual = (graph - flow).tocsr()
    residual.data[residual.data < 0] = 0
    residual.eliminate_zeros()
    reached = np.zeros(n_nodes, dtype=bool)
    reached[breadth_first_order(residual, source, directed=True, return_predecessors=False)] = True

    new_side = np.zeros(shape, dtype=bool)
    new_side[region] = ~reached[:n_pix]
    flat_new = new_side.ravel()
    cost = float(plain[flat_new[s[~seam]] != flat_new[t[~seam]]].sum())
    if n_seam:  # each seam node on whichever side cuts less (the cut puts it there)
        s_new, t_new = flat_new[ss], flat_new[ts]
        node_old = to_seam * s_new + from_seam * t_new + old_seam
        node_new = to_seam * ~s_new + from_seam * ~t_new
        cost += float(np.minimum(node_old, node_new).sum())
    return new_side, cost


def _check_labels(labels, patches, old, region):
    """``labels`` flattened and ``patches`` as ``(K, H*W, C)``; refuses labels and patches that do not make ``old``."""
    nd = old.ndim - 1
    lab = np.asarray(labels)
    if lab.shape != old.shape[:nd] or not np.issubdtype(lab.dtype, np.integer):
        raise ValueError(f"labels must be an integer array of shape {old.shape[:nd]}, got dtype {lab.dtype} "
                         f"shape {lab.shape}")
    layers = np.asarray(patches, dtype=np.float64)
    if layers.ndim == nd + 1:
        layers = layers[..., None]
    if layers.ndim != nd + 2 or layers.shape[1:] != old.shape:
        raise ValueError(f"patches must have shape (K, {', '.join(str(n) for n in old.shape)}) "
                         f"(K old patches over old's pixels), got {layers.shape}")
    if not np.all(np.isfinite(layers)):
        raise ValueError("patches contains NaN or infinite values; give every patch a value at every pixel")
    used = lab[region]
    if used.size and (used.min() < 0 or used.max() >= layers.shape[0]):
        raise ValueError(f"labels must lie in 0..{layers.shape[0] - 1} (one per patch) on mask, "
                         f"got {used.min()}..{used.max()}")
    lab = np.where(region, lab, 0).ravel()
    layers = layers.reshape(layers.shape[0], -1, layers.shape[-1])
    made = layers[lab, np.arange(lab.size)]
    differ = region.ravel() & ~np.all(made == old.reshape(-1, old.shape[-1]), axis=1)
    if differ.any():
        raise ValueError(f"old differs from patches[labels] at {int(differ.sum())} pixels of mask; old must be "
                         "the image that the labelled patches make")
    return lab, layers


# --------------------------------------------------------------------------- gradient-domain blending


def poisson_blend(image, mask, *, blend_width=32, sample_mask=None):
    """Blend the pixels within ``blend_width`` of the known ones (``mask``) into them in the gradient domain.

    A fill made apart from the pixels around it (a hole's, an uncrop's border)
    meets them with steps in colour where one copy of the texture is lighter or
    darker than the image beside it. Pérez, Gangnet & Blake's seamless
    cloning [4]_ keeps the fill's gradients and moves its values to meet the
    border: the result is the fill plus a *membrane*, the harmonic function
    ``c`` (``Δc = 0``, their eq. 7 with the fill's own gradients as guidance)
    that takes the fill's mismatch to the known pixels at the border (the
    membrane view of Farbman et al. [5]_). Here:

    - the mismatch of a free pixel ``p`` is its mean difference ``g_q - g_p``
      to its known 4-neighbours ``q``;
    - it is *smoothed along the border* (a Gaussian of sigma
      :data:`BLEND_SMOOTHING` pixels over the border pixels), so a copy that is
      darker than the image over a stretch of the border is lifted, while the
      steps of the texture itself, which change from pixel to pixel along the
      border (a stone's edge crossing it), are not smeared into it;
    - each border pixel counts in that mean by how smooth both sides are just
      behind the border, ``exp(-(s / tau)^2)`` with ``s`` the steepest step
      between neighbouring pixels of one side within 2 pixels of the border and
      ``tau`` four times the known pixels' median step: a short stretch of a
      line of the texture that runs *along* the border (a mortar joint just
      inside a hole's rim) is outweighed by the smooth border beside it instead
      of looking like an offset and being shaded away (a line along the whole
      width of the smoothing is not: there nothing outweighs it);
    - only the free pixels within ``blend_width`` (Euclidean distance) of the
      known ones move: ``c`` is 0 at the band's far edge, so the correction
      fades across the band, and the rest of the fill and every known pixel
      keep their values bit for bit.

    The smoothing and the band are this implementation's choices (the paper
    solves over the whole region with the pixel-wise mismatch, which here
    made the border smoother than the texture and smeared real edges at it
    into shadows: docs/methods/completion.md).
    ``sample_mask`` limits the known pixels the fill is blended into to those
    it was copied from (a fill copied from one texture is not pulled towards
    the colours of another beside it): the band is measured from them, and the
    border with the other known pixels is left free (no equation ties the fill
    to them).

    Parameters
    ----------
    image : array_like
        ``(H, W)`` or ``(H, W, C)``: the known pixels and the fill.
    mask : array_like of bool
        ``(H, W)``: True at the known pixels, which keep their values.
    blend_width : int
        Width in pixels of the band of free pixels that is blended (0: none).
    sample_mask : array_like of bool, optional
        ``(H, W)``: the known pixels the fill was copied from and is blended
        into; default all.

    Returns
    -------
    numpy.ndarray
        float64, the shape of ``image``, its values clipped to the range ``image`` had.

    References
    ----------
    .. [4] P. Pérez, M. Gangnet and A. Blake, "Poisson image editing", ACM TOG
       22(3) (SIGGRAPH 2003), pp. 313-318. :doi:`10.1145/882262.882269`
    .. [5] Z. Farbman, G. Hoffer, Y. Lipman, D. Cohen-Or and D. Lischinski,
       "Coordinates for instant image cloning", ACM TOG 28(3) (SIGGRAPH 2009).
       :doi:`10.1145/1531326.1531373` (not at hand: the membrane view is as its
       abstract states it)

    Examples
    --------
    >>> flat = np.full((4, 8), 0.25)
    >>> known = np.zeros((4, 8), bool); known[:, :4] = True
    >>> stepped = flat + 0.5 * ~known          # the fill 0.5 too bright
    >>> bool(np.allclose(poisson_blend(stepped, known, blend_width=8), flat))
    True
    """
    g = _as_values(image, "image")
    h, w = g.shape[:2]
    known = _as_mask(mask, (h, w), "mask", True)
    blend_width = check_positive_int(blend_width, "blend_width", 0)
    anchor = known if sample_mask is None else _as_mask(sample_mask, (h, w), "sample_mask", False) & known
    out = g.copy()
    if blend_width == 0 or known.all() or not anchor.any():
        return out[..., 0] if np.ndim(image) == 2 else out
    # the texture's own step: the median difference of horizontally neighbouring known pixels
    steps = np.abs(np.diff(g, axis=1)).max(axis=-1)[anchor[:, 1:] & anchor[:, :-1]]
    tau = _BLEND_TRUST_STEPS * float(np.median(steps)) if steps.size else 0.0
    band = ~known & (ndimage.distance_transform_edt(~anchor) <= blend_width)
    n = int(band.sum())
    check_memory(float(n) * _BLEND_BYTES_PER_PIXEL + float(h) * w * _BLEND_BYTES_PER_IMAGE_PIXEL, (h, w), "image",
                 "the gradient-domain blend")
    index = np.full((h, w), -1, dtype=np.int64)
    index[band] = np.arange(n)
    pr, pc = np.nonzero(band)
    mismatch, ties, trust = np.zeros((n, g.shape[2])), np.zeros(n), np.zeros(n)
    rows, cols, degree = [], [], np.zeros(n)
    for dr, dc in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        qr, qc = pr + dr, pc + dc
        inside = (qr >= 0) & (qr < h) & (qc >= 0) & (qc < w)
        inside[inside] = ~(known & ~anchor)[qr[inside], qc[inside]]  # no tie to the known pixels left out
        p, sr, sc, qr, qc = index[pr, pc][inside], pr[inside], pc[inside], qr[inside], qc[inside]
        degree += np.bincount(p, minlength=n)
        free = band[qr, qc]
        rows.append(p[free])
        cols.append(index[qr[free], qc[free]])
        edge = anchor[qr, qc]
        weight = _line_trust(g, known, (sr[edge], sc[edge]), (qr[edge], qc[edge]), (dr, dc), tau)
        np.add.at(mismatch, p[edge], weight[:, None] * (g[qr[edge], qc[edge]] - g[sr[edge], sc[edge]]))
        np.add.at(trust, p[edge], weight)
        np.add.at(ties, p[edge], 1)
    border = ties > 0
    # the mismatch smoothed along the border: a Gaussian-weighted mean over the nearby border pixels, each
    # counted by how little a line of the texture runs along the border there
    on_border = np.zeros((h, w))
    on_border[pr[border], pc[border]] = trust[border]
    weight = np.maximum(ndimage.gaussian_filter(on_border, BLEND_SMOOTHING)[pr[border], pc[border]], 1e-12)
    for k in range(g.shape[2]):
        layer = np.zeros((h, w))
        layer[pr[border], pc[border]] = mismatch[border, k]
        mismatch[border, k] = ndimage.gaussian_filter(layer, BLEND_SMOOTHING)[pr[border], pc[border]] / weight
    # the membrane: Laplace's equation in the band, each tie to a known pixel pulling towards the mismatch
    from scipy.sparse import csc_matrix  # here: importing scipy.sparse.linalg takes 50 ms, and only blends need it
    from scipy.sparse.linalg import splu

    system = csc_matrix(
        (np.concatenate([-np.ones(sum(r.shape[0] for r in rows)), degree]),
         (np.concatenate(rows + [np.arange(n)]), np.concatenate(cols + [np.arange(n)]))), shape=(n, n))
    out[pr, pc] += splu(system).solve(mismatch * ties[:, None])
    np.clip(out, g.min(axis=(0, 1)), g.max(axis=(0, 1)), out=out)  # (a photograph's fill stays in [0, 1])
    return out[..., 0] if np.ndim(image) == 2 else out


def _line_trust(g, known, free, fixed, d, tau):
    """How far a border tie's mismatch is a colour offset rather than a line of the texture along the border.

    For the free pixels ``free`` and their known neighbours ``fixed`` one step ``d`` away, the steepest step
    between neighbouring pixels of one side within :data:`_BLEND_LINE_DEPTH` pixels behind the border (into the
    known pixels past ``fixed``, into the fill behind ``free``); the weight ``exp(-(step / tau)^2)`` is near 1
    where both sides are smooth there and near 0 where a line (a mortar joint, a stone's rim) runs beside it.
    """
    h, w = known.shape
    (fr, fc), (kr, kc), (dr, dc) = free, fixed, d
    steep = np.zeros(fr.shape[0])
    for k in range(1, _BLEND_LINE_DEPTH + 1):
        for ar, ac, br, bc in ((kr + (k - 1) * dr, kc + (k - 1) * dc, kr + k * dr, kc + k * dc),
                               (fr - (k - 1) * dr, fc - (k - 1) * dc, fr - k * dr, fc - k * dc)):
            inside = (ar >= 0) & (ar < h) & (ac >= 0) & (ac < w) & (br >= 0) & (br < h) & (bc >= 0) & (bc < w)
            ar, ac, br, bc = (np.clip(v, 0, m - 1) for v, m in ((ar, h), (ac, w), (br, h), (bc, w)))
            one_side = inside & (known[ar, ac] == known[br, bc])
            steep = np.maximum(steep, np.abs(g[ar, ac] - g[br, bc]).max(axis=-1) * one_side)
    return np.exp(-(steep / max(tau, 1e-12)) ** 2)
