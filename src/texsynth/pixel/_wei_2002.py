"""Wei's texture synthesis from multiple sources: texture mixtures and solid textures from 2-D views.

Wei [1]_ extends Wei & Levoy 2000 [2]_ (:mod:`texsynth.pixel._wei_levoy`) to
several sources: every source ``i`` has a weight image ``w_i`` of the output's
size and its own neighbourhood ``N_i``, and each output pixel ``p`` minimises

.. math:: E(p, \\{p_i\\}) = \\sum_i w_i \\left(\\|p - p_i\\|^2
          + \\|N_i(p) - N_i(p_i)\\|^2\\right)                  \\quad (1)

With one source eq. 1 is minimised directly: the ``p_i`` of nearest
neighbourhood, ``p = p_i`` (Wei & Levoy 2000). With several, by alternation:
fix ``p``, choose each ``p_i`` minimising its term; fix the ``p_i``, set ``p``
to their weighted average; both steps never raise E; stop when E stops
falling ("1 to 4 iterations are sufficient"). This module is that
alternation (:func:`_alternate_pixel` and its vectorized forms, which the
Wei-Levoy engine calls through a :class:`~texsynth.pixel._wei_levoy.Mixture`)
and the paper's two specialisations:

:func:`mix_textures`
    Texture mixtures: the weight images say how the sources mix (equal
    weights: a uniform mixture; a ramp: one texture turning into another).
:func:`synthesize_solid`
    Solid textures: the sources are 2-D views of a solid along the volume
    axes; the neighbourhood of a voxel for the view along axis ``a`` lies in
    the plane perpendicular to ``a``.

References
----------
.. [1] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
   Sketches & Applications. :doi:`10.1145/965400.965507`
.. [2] L.-Y. Wei and M. Levoy, "Fast texture synthesis using tree-structured
   vector quantization", SIGGRAPH 2000, pp. 479-488.
   :doi:`10.1145/344779.345009`
.. [3] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
   Stanford University Technical Report TR-2002-01, 2002.
"""

from __future__ import annotations

import numbers
import os

import numpy as np

from ..core._validate import as_rng, as_size, check_bool, check_choice, check_group, restore_channels
from ..core.search import Search, is_auto, lowest_cost, refuse_augment
from ._augment import augmented_source, to_exemplar
from ._options import check_candidate_options, check_order_method, check_output_memory, search_options
from ._wei_levoy import SHAPES, Mixture, Neighborhood, average_picks, prepare_sources, synthesize_levels

__all__ = ["mix_textures", "synthesize_solid"]

# Relative tolerance of "E stops falling" (eq. 1 alternation).
_STOP_TOLERANCE = 1e-9
# Working precision of solid synthesis (the output keeps the views' dtype).
_SOLID_DTYPE = np.float32


# --------------------------------------------------------------------------- #
# eq. 1 by alternation (Wei 2002, Sec. 2)
# --------------------------------------------------------------------------- #
def _average(weights, pixels, chosen):
    """p = sum_i a_i p_i (sum a_i = 1) and the energy of eq. 1 at that p."""
    picks = [c[k] for c, (k, _) in zip(pixels, chosen)]
    p = weights[0] * picks[0]
    for a, q in zip(weights[1:], picks[1:]):
        p = p + a * q
    energy = 0.0
    for a, q, (_, nd) in zip(weights, picks, chosen):
        energy += a * (float(((p - q) ** 2).sum()) + float(nd))
    return p, energy


def _alternate_pixel(weights, pixels, direct, choose, iterations):
    """Eq. 1 at one pixel by Wei's alternation: ``(p, E, picks, steps)`` (see :class:`Mixture`).

    Wei's alternation needs a starting p; start from each source's own
    direct solution (its p_i of nearest neighbourhood) and keep the end of
    lowest E.
    """
    n_iter = 0
    best = None
    for start in range(len(weights)):
        p = pixels[start][direct(start)]
        energy, n, ks = np.inf, 0, None
        for _ in range(iterations):
            # fix p, choose each p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2 (one term of eq. 1)
            chosen = [choose(i, p) for i in range(len(weights))]
            # fix {p_i}, p = weighted average (minimises eq. 1 over p)
            p_new, e_new = _average(weights, pixels, chosen)
            n += 1
            if not e_new < energy * (1.0 - _STOP_TOLERANCE):  # E stopped falling
                break
            p, energy, ks = p_new, e_new, [k for k, _ in chosen]
        n_iter += n
        if best is None or energy < best[1]:
            best = (p, energy, ks)
    return best[0], best[1], best[2], n_iter


def _alternate_candidates(a, nds, colours, iterations):
    """Eq. 1 for ``M`` pixels over each source's own candidates: ``(p, E, picks, steps)``.

    ``a`` ``(S, M)`` the weights (sum 1 per pixel), ``nds[i]`` ``(M, K_i)``
    the neighbourhood distances to source ``i``'s candidates (``inf`` for a
    repeat), ``colours[i]`` ``(M, K_i, C)`` their pixels. As in the full
    search (:func:`_alternate_pixel`): from each source's direct solution (its
    nearest neighbourhood), fix ``p`` and choose each ``p_i`` minimising
    ``||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2``, set ``p`` to the weighted
    average, until E stops falling or ``iterations`` steps; keep the start of
    lowest E. A source of weight 0 at a pixel keeps its nearest
    neighbourhood (its map continues from there).
    """
    m = a.shape[1]
    direct = [lowest_cost(nd)[0] for nd in nds]

    def blend(r, ks):
        """p = sum_i a_i p_i at pixels ``r`` with picks ``ks``, and E there."""
        picked = [col[r, k] for col, k in zip(colours, ks)]
        p = sum(a[i, r, None] * c for i, c in enumerate(picked))
        e = sum(a[i, r] * (((p - c) ** 2).sum(axis=1) + nds[i][r, k]) for i, (c, k) in enumerate(zip(picked, ks)))
        return p, e

    best_p = np.zeros((m, colours[0].shape[-1]))  # every pixel has a source of weight > 0: all are set below
    best_e = np.full(m, np.inf)
    best_k = [k.copy() for k in direct]
    steps = np.zeros(m)
    for start in range(len(nds)):
        sel = np.flatnonzero(a[start] > 0)
        p = colours[start][sel, direct[start][sel]]
        e = np.full(len(sel), np.inf)
        ks = [k[sel].copy() for k in direct]
        todo = np.arange(len(sel))
        for _ in range(iterations):
            r = sel[todo]
            new = [np.where(a[i, r] > 0, lowest_cost(nd[r], ((col[r] - p[todo, None]) ** 2).sum(axis=2))[0],
                            direct[i][r]) for i, (nd, col) in enumerate(zip(nds, colours))]
            p_new, e_new = blend(r, new)
            steps[r] += 1
            better = e_new < e[todo] * (1.0 - _STOP_TOLERANCE)  # E still falling
            if not better.any():
                break
            todo, p_new, e_new = todo[better], p_new[better], e_new[better]
            p[todo], e[todo] = p_new, e_new
            for i in range(len(ks)):
                ks[i][todo] = new[i][better]
        win = e < best_e[sel]
        best_p[sel[win]], best_e[sel[win]] = p[win], e[win]
        for i in range(len(ks)):
            best_k[i][sel[win]] = ks[i][win]
    return best_p, best_e, best_k, steps


def _alternate_everywhere(previous, pixels, a_flat, ks, nds, multi, iterations, choose, for_each, result):
    """Eq. 1 at the pixels ``multi`` (several sources) at once, as :func:`_alternate_pixel`; updates ``result``.

    ``result = (p, E, steps, picks)`` holds every pixel's values, the
    sources' direct solutions (``ks``, ``nds``) already averaged. Wei's
    alternation from each source's direct solution, keeping the lowest E;
    a volume (``previous``, the last pass, not None: every voxel has all
    views) starts once, from the previous pass.
    """
    p, energy, n_iter, final = result
    energy[multi] = np.inf
    n_iter[multi] = 0
    starts = [(None, None, None)] if previous is not None else list(zip(pixels, a_flat, ks))
    for start_pixels, start_a, start_k in starts:
        sel = multi if start_pixels is None else multi[start_a[multi] > 0]
        cur_p = previous[sel].copy() if start_pixels is None else start_pixels[start_k[sel]]
        cur_e = np.full(len(sel), np.inf)
        cur_k = [k[sel] for k in ks]
        cur_nd = [nd[sel] for nd in nds]
        todo = np.arange(len(sel))
        for step in range(iterations):
            # fix p, choose each p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2
            new_k = [k.copy() for k in cur_k]
            new_nd = [nd.copy() for nd in cur_nd]

            def one(i):
                m = todo[a_flat[i][sel[todo]] > 0]
                new_k[i][m], new_nd[i][m] = choose(i, sel[m], cur_p[m])

            for_each(one)
            # fix {p_i}, p = weighted average
            p_new, e_new = average_picks(pixels, a_flat, [k[todo] for k in new_k], [d[todo] for d in new_nd],
                                         sel[todo])
            n_iter[sel[todo]] += 1
            better = e_new < cur_e[todo] * (1.0 - _STOP_TOLERANCE)  # E still falling
            if not better.any():
                break
            todo = todo[better]
            # where p did not move, the next step would choose the same p_i and
            # find E unchanged (the stop rule): count that step, skip its search
            moved = np.any(p_new[better] != cur_p[todo], axis=1)
            cur_p[todo], cur_e[todo] = p_new[better], e_new[better]
            for i in range(len(pixels)):
                cur_k[i][todo], cur_nd[i][todo] = new_k[i][todo], new_nd[i][todo]
            if step + 1 < iterations:
                n_iter[sel[todo[~moved]]] += 1
            todo = todo[moved]
            if todo.size == 0:
                break
        win = cur_e < energy[sel]
        p[sel[win]], energy[sel[win]] = cur_p[win], cur_e[win]
        for i in range(len(pixels)):
            final[i][sel[win]] = cur_k[i][win]


#: Wei's alternation, as the Wei-Levoy engine calls it where a pixel has several sources.
_EQ1 = Mixture(pixel=_alternate_pixel, candidates=_alternate_candidates, everywhere=_alternate_everywhere)


# --------------------------------------------------------------------------- #
# the sources' options
# --------------------------------------------------------------------------- #
def _is_int(v):
    return isinstance(v, numbers.Integral) and not isinstance(v, bool)


def _is_pair(v):
    return isinstance(v, (tuple, list, np.ndarray)) and len(v) == 2 and all(_is_int(x) for x in v)


def _per_source(value, n, name):
    """Neighbourhood sizes: one setting for every source, or a list with one per source.

    ``"auto"`` or an int is the same for every source. A list (or a tuple whose
    entries are not all integers, or whose length is the number of sources
    other than two) holds one entry per source, each an int or an ``(h, w)``
    pair. A tuple or array of two integers is one ``(h, w)`` rectangle for
    every source, except with exactly two sources, where ``(5, 9)`` could
    also mean 5x5 and 9x9: that raises, naming both spellings.
    """
    if is_auto(value) or _is_int(value):
        return [value] * n
    if isinstance(value, str) or not hasattr(value, "__len__"):
        raise TypeError(f"{name} must be an int, an (h, w) pair or a list with one per source, got {value!r}")
    if not isinstance(value, list) and _is_pair(value):
        h, w = (int(v) for v in value)
        if n == 2:
            raise ValueError(
                f"{name}=({h}, {w}) is ambiguous with two sources: pass a list with one entry per source, "
                f"[{h}, {w}] for {h}x{h} and {w}x{w}, or [({h}, {w}), ({h}, {w})] for one {h}x{w} rectangle for both"
            )
        return [(h, w)] * n
    values = list(value)
    if len(values) != n:
        one = "source" if n == 1 else "sources"
        raise ValueError(
            f"{name} holds {len(values)} entries but there {'is' if n == 1 else 'are'} {n} {one}; pass a list "
            f"with one entry per source (an int or an (h, w) pair each, e.g. {[5] * n!r}) or a single int"
        )
    for i, v in enumerate(values):
        if not (is_auto(v) or _is_int(v) or _is_pair(v)):
            raise TypeError(f"{name}[{i}] must be an int or an (h, w) pair of ints, got {v!r}")
    return [v if is_auto(v) or _is_int(v) else tuple(int(x) for x in v) for v in values]


def _per_source_shape(value, n, name):
    """Neighbourhood footprints: one name for every source, or a list with one per source."""
    values = [value] * n if isinstance(value, str) else value
    if not isinstance(values, (list, tuple)):
        raise TypeError(
            f"{name} must be one of {', '.join(map(repr, SHAPES))} or a list with one per source, got {value!r}"
        )
    values = list(values)
    if len(values) != n:
        raise ValueError(
            f"{name} holds {len(values)} entries but there are {n} sources; pass one shape "
            f"({' or '.join(map(repr, SHAPES))}) per source or a single one"
        )
    per_source = n > 1 and not isinstance(value, str)
    return [check_choice(v, f"{name}[{i}]" if per_source else name, SHAPES) for i, v in enumerate(values)]



def _check_weights(weights, n, size):
    """Weight images of the output size (a scalar means constant), non-negative, never all zero."""
    if weights is None:
        return [1.0] * n
    if isinstance(weights, np.ndarray) and weights.ndim == 3 and weights.shape[0] == n:
        weights = list(weights)
    if isinstance(weights, numbers.Real) or (isinstance(weights, np.ndarray) and weights.ndim < 3 and n > 1 and weights.ndim != 1):
        raise ValueError(
            f"weights must hold one weight (a number or a {size[0]}x{size[1]} image) per source, "
            f"i.e. a list of {n}, got {np.asarray(weights).shape if hasattr(weights, 'shape') else weights!r}"
        )
    weights = list(weights)
    if len(weights) != n:
        raise ValueError(f"weights holds {len(weights)} entries but there are {n} sources; pass one weight per source")
    result = []
    for i, w in enumerate(weights):
        arr = np.asarray(w)
        if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
            raise TypeError(f"weights[{i}] must be a real number or array, got dtype {arr.dtype}")
        arr = arr.astype(np.float64)
        if arr.ndim != 0 and arr.shape != tuple(size):
            raise ValueError(
                f"weights[{i}] has shape {arr.shape} but the output size is {tuple(size)}; "
                f"pass a number or a weight image of shape {tuple(size)}"
            )
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"weights[{i}] contains NaN or infinite values")
        if arr.size and arr.min() < 0:
            raise ValueError(f"weights[{i}] has negative values (min {arr.min():.4g}); weights must be >= 0")
        result.append(arr)
    total = sum(np.broadcast_to(w, size) for w in result)
    if np.any(total <= 0):
        bad = tuple(int(v) for v in np.argwhere(total <= 0)[0])
        raise ValueError(
            f"weights are all zero at pixel {bad} (and {int(np.sum(total <= 0)) - 1} others); "
            "every output pixel needs a positive weight for at least one source"
        )
    return result



def mix_textures(
    sources,
    size,
    *,
    weights=None,
    neighborhood=Neighborhood(),
    max_iterations=4,
    order="scanline",
    search=Search(),
    passes=2,
    tileable=False,
    rng=None,
    progress=False,
    return_info=False,
):
    """Texture mixture from several sources (Wei 2002, eq. 1).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> a, b = texsynth.data.load("bread")[:24, :24], texsynth.data.load("wood")[:24, :24]
    >>> ramp = np.tile(np.linspace(0, 1, 20), (20, 1))  # bread on the left, wood on the right
    >>> out = texsynth.mix_textures([a, b], 20, weights=[1 - ramp, ramp], rng=0,
    ...                             neighborhood=texsynth.Neighborhood(levels=2))
    >>> out.shape
    (20, 20, 3)

    Every output pixel ``p`` takes from each source ``i`` the pixel ``p_i``
    whose neighbourhood matches its own and becomes their weighted average;
    the two steps alternate to minimise eq. 1, so the output mixes the
    sources' textures in the proportions ``weights`` gives [1]_.

    Parameters
    ----------
    sources : sequence of array_like
        Exemplars ``(h_i, w_i[, C])``, all with the same channels (sizes may
        differ).
    size : int or (int, int)
        Output ``(height, width)``.
    weights : sequence, optional
        One weight per source: a number (constant) or a weight image of the
        output size; non-negative, with a positive sum at every pixel.
        Default: equal weighting (a uniform mixture). A ramp
        ``np.linspace(0, 1, width)`` for one source and its complement for
        the other turns one texture into the other from left to right.
    neighborhood : Neighborhood
        ``N_i`` at each level and at the parent level, and the pyramid
        levels (:class:`~texsynth.pixel.Neighborhood`): each field is one
        setting for every source or a list with one per source, because
        sources differ in texon size (Wei 2002, Sec. 2), e.g.
        ``Neighborhood(neighborhood_size=[5, 9])`` (default 5x5 squares,
        3x3 parents, 3 levels, as :func:`~texsynth.synthesize_pixels`). See
        Notes for the shapes.
    max_iterations : int
        Most alternation steps of eq. 1 per pixel (default 4: the paper found
        1 to 4 enough). Stops earlier when E stops falling.
    tileable : bool
        Make the output tile seamlessly, as :func:`synthesize_pixels` does:
        in scanline order a pixel where some source's causal window wraps
        compares, for every source, the wrapped pixels synthesised before it
        (exact search), and eq. 1 alternates over those distances. In
        independent order the output tiles either way; True changes nothing
        there. Weight images should then wrap too (a left-to-right ramp
        meets its other end at the seam).
    search : Search
        How each source's ``p_i`` is searched
        (:class:`~texsynth.core.search.Search`): ``method`` and ``k`` as in
        :func:`~texsynth.synthesize_pixels`. ``candidates="all"`` (or
        ``"auto"``, the paper's): each ``p_i`` among all of source ``i``'s
        neighbourhoods. ``"k-coherent"``: among the k-coherent candidates of
        its own source map only, as :func:`~texsynth.synthesize_pixels`
        chooses them (Ashikhmin 2001; Tong et al. 2002): each source keeps
        the map of where its ``p_i`` came from, and eq. 1 alternates over the
        candidates that map's neighbours suggest (their neighbourhood
        distances computed once per pixel). Scanline order only; not with
        ``tileable=True``. ``augment``: each source's flipped or rotated
        copies are its candidates too (with ``candidates="all"``).
    order, passes, rng, progress, return_info
        As in :func:`~texsynth.synthesize_pixels`.

    Returns
    -------
    image : numpy.ndarray
        The mixture, ``size`` with the sources' channel layout; toroidal
        (seamless when tiled with ``tileable=True`` or in independent
        order).
    info : PixelSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For weights of the wrong shape, negative weights, all weights zero at
        a pixel, sources with different channel counts, a neighbourhood
        larger than its source, ``neighborhood_size``, ``neighborhood_shape``
        or ``parent_size`` of the wrong length or ambiguous (a tuple of two
        ints with two sources), or an invalid option.

    Notes
    -----
    For each output pixel ``p`` the algorithm minimises (Wei 2002, eq. 1)

    .. math:: E(p, \\{p_i\\}) = \\sum_i w_i \\left(\\|p - p_i\\|^2
              + \\|N_i(p) - N_i(p_i)\\|^2\\right)

    First each ``p_i`` minimises its neighbourhood term (``p`` is not known
    yet); then ``p`` is set to the weighted average of the ``p_i``; then,
    with ``p`` fixed, each ``p_i`` minimises its whole term, and so on. Both
    steps never raise E; the loop stops when E stops falling or after
    ``max_iterations`` steps. The weights are normalised to sum 1 at each pixel,
    which does not move the minimum. With one source the first step is
    Wei & Levoy 2000 and later steps keep it, so the result equals
    :func:`synthesize_pixels` bit for bit.

    Neighbourhood shape: Wei gives each source "a neighborhood parameter,
    defining the size and shape of the neighborhood" [1]_ without listing
    shapes; Wei & Levoy 2000 use square boxes (the causal L-shaped half in
    scanline order) [2]_. A box reaches sqrt(2) times farther along its
    diagonals than along its axes, so for isotropic (stochastic) textures
    ``"disc"`` compares the same distance in every direction, with about
    pi/4 of the values (5x5: 21 of 25, 9x9: 69 of 81). A rectangular
    ``(h, w)`` box suits elongated texons (bricks). 3x3 discs keep all 9
    pixels, so they equal 3x3 squares. The shape is this library's option,

    not a setting the paper reports. The neighbourhood term of eq. 1 sums
    over the pixels of ``N_i``, so at equal weights a source with a larger
    neighbourhood counts more (a ramp turns later); divide ``w_i`` by the
    pixel count of ``N_i`` to balance them. One setting per source, and a
    pair that is ambiguous with two sources:

    >>> per_source = texsynth.Neighborhood(neighborhood_size=[3, (5, 7)], neighborhood_shape=["square", "disc"],
    ...                                    levels=2)
    >>> out = texsynth.mix_textures([a, b], 20, neighborhood=per_source, rng=0)
    >>> ambiguous = texsynth.Neighborhood(neighborhood_size=(3, 5))
    >>> texsynth.mix_textures([a, b], 20, neighborhood=ambiguous)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: neighborhood_size=(3, 5) is ambiguous with two sources: ... [3, 5] ... or [(3, 5), (3, 5)] ...

    References
    ----------
    .. [1] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
       Sketches & Applications. :doi:`10.1145/965400.965507`
    .. [2] L.-Y. Wei and M. Levoy, "Fast texture synthesis using
       tree-structured vector quantization", SIGGRAPH 2000.
       :doi:`10.1145/344779.345009`
    """
    if isinstance(sources, (str, os.PathLike)):
        raise TypeError(f"sources: got the single file name {str(sources)!r}; pass a list of images or files, "
                        "e.g. ['a.png', 'b.png']")
    if isinstance(sources, np.ndarray) or not hasattr(sources, "__len__") or len(sources) == 0:
        raise ValueError("sources must be a non-empty list of exemplar images, e.g. [a, b]")
    n = len(sources)
    size = as_size(size)
    nb = check_group(neighborhood, Neighborhood, "neighborhood")
    method, candidates, k = search_options(search)
    check_order_method(order, method, passes, max_iterations)
    tileable = check_bool(tileable, "tileable")
    k = check_candidate_options(candidates, k, order, tileable)
    rng = as_rng(rng)
    sizes = _per_source(nb.neighborhood_size, n, "neighborhood_size")
    psizes = _per_source(nb.parent_size, n, "parent_size")
    shapes = _per_source_shape(nb.neighborhood_shape, n, "neighborhood_shape")
    names = [f"sources[{i}]" for i in range(n)]
    srcs, channels, dtype, grey = prepare_sources(
        sources, names, sizes, psizes, [None] * n, nb.levels, "neighborhood_size", shapes=shapes
    )
    srcs = [augmented_source(s, search.augment, nb.levels, candidates) for s in srcs]  # the exemplars' copies too
    check_output_memory(srcs, size, channels, dtype, order)  # before the weight images are summed at the output size
    for src, w in zip(srcs, _check_weights(weights, n, size)):
        src.weights = w
    out, info = synthesize_levels(
        srcs, size, channels, dtype, levels=nb.levels, order=order, method=method, iterations=max_iterations,
        passes=passes, rng=rng, progress=progress, desc="Wei mixture", candidates=candidates, k=k,
        tileable=tileable and order == "scanline", mixture=_EQ1,
    )
    info.coordinates = to_exemplar(srcs, info.coordinates, info.source_index)
    out = restore_channels(out, grey)
    return (out, info) if return_info else out


def synthesize_solid(
    views,
    size,
    *,
    axes="auto",
    neighborhood=Neighborhood(),
    max_iterations=2,
    passes=2,
    search=Search(),
    rng=None,
    progress=False,
    return_info=False,
):
    """Solid texture from 2-D views along the volume axes (Wei 2002).

    Examples
    --------
    >>> import texsynth
    >>> bread = texsynth.data.load("bread")[:24, :24]
    >>> volume = texsynth.synthesize_solid(bread, 8, neighborhood=texsynth.Neighborhood(levels=1), passes=1, rng=0)
    >>> volume.shape
    (8, 8, 8, 3)

    A volume whose slices across each view's axis look like that view:
    every view is one source of Wei's multi-source energy (eq. 1), with its
    neighbourhoods in the plane perpendicular to its axis [1]_.

    Parameters
    ----------
    views : array_like or sequence of array_like
        One image (used as the view along all three axes) or a list of 1 to 3
        images with the same channels. ``views[k]`` is what the solid looks
        like when cut perpendicular to ``axes[k]``.
    size : int or (int, int, int)
        Output ``(depth, height, width)``.
    axes : sequence of int or "auto"
        Volume axis of each view: 0 (z: the slice ``volume[d]`` has rows H,
        columns W), 1 (y: ``volume[:, h]`` has rows D, columns W) or 2 (x:
        ``volume[:, :, w]`` has rows D, columns H). ``"auto"`` (default):
        ``(0, 1, 2)`` for one view (repeated) or three views, ``(0, 1)`` for
        two.
    neighborhood : Neighborhood
        As in :func:`~texsynth.synthesize_pixels`
        (:class:`~texsynth.pixel.Neighborhood`; one setting for every view;
        each view's neighbourhood lies in the plane perpendicular to its
        axis).
    max_iterations : int
        Most alternation steps of eq. 1 per voxel and pass (default 2).
    passes : int
        Passes per level of the order-independent update (default 2).
    search : Search
        The search (:class:`~texsynth.core.search.Search`): ``method``, the
        backend; ``"auto"``: exact for small volumes, kd-tree (4 re-ranked
        candidates, profile ``"solid"``) for large ones. ``"tsvq"`` is Wei &
        Levoy's tree-structured vector quantization (faster, less exact; see
        Notes). Every voxel is compared with all candidates
        (``candidates`` ``"all"`` or ``"auto"``; ``k`` is not used; no
        ``augment``: each view fixes the orientation in its plane).
    rng, progress, return_info
        As in :func:`synthesize_pixels`.

    Returns
    -------
    volume : numpy.ndarray
        ``(D, H, W)`` or ``(D, H, W, C)`` following the views' layout;
        toroidal along every axis.
    info : PixelSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For views with mismatched channels, more than 3 views, repeated or
        invalid axes, a neighbourhood larger than a view, bad options.

    Notes
    -----

    Every view is one source of eq. 1 (equal weights); the neighbourhood
    ``N_a`` of a voxel for the view along axis ``a`` is the square in the
    plane perpendicular to ``a`` (and its parent one level coarser, in the
    same plane), so each view constrains what the slices across its axis
    look like. Wei synthesised the volume in scanline order; here voxels
    are updated in the order-independent way (Wei & Levoy 2002: non-causal
    neighbourhoods, all voxels per pass), which vectorizes over the volume.
    The output pyramid is a 3-D Gaussian pyramid of noise.

    No source-coordinate map (``info.coordinates`` is None): each voxel is
    the average of one pixel of every view (eq. 1), so a map would be
    ``(D, H, W, 3, 2)`` plus the view of each slot, 48 bytes a voxel (800
    MB for 256^3), and it would render only channels that mean the same in
    every view. A tangent-space normal map is expressed in its view's own
    plane, and the three views' planes differ, so averaging their normals
    gives no normal of the solid; a height map is a height above one
    view's plane, not a property of a voxel. Colour and roughness alone
    would survive, and for them one can synthesise a solid of those
    channels stacked with the colour (``views`` with more channels).

    Speed: a view given once for several axes builds each search index once;
    the alternation of eq. 1 starts from the previous pass's voxel (the
    direct per-view search is skipped); volumes and their neighbourhood
    vectors are float32 inside (the output keeps the views' dtype); kd-tree
    search re-ranks 4 candidates, the views' searches run in threads
    (``docs/methods/wei_2002.md`` has the times and the quality of each
    backend).

    References
    ----------
    .. [1] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
       Sketches & Applications. :doi:`10.1145/965400.965507`
    .. [2] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
       Stanford University Technical Report TR-2002-01, 2002.
    """
    size = as_size(size, "size", ndim=3)
    nb = check_group(neighborhood, Neighborhood, "neighborhood")
    method, candidates, _ = search_options(search)
    refuse_augment(search.augment, "synthesize_solid", "each view fixes the texture's orientation in its plane")
    if candidates != "all" or not is_auto(search.k):
        raise ValueError(f"synthesize_solid compares every voxel with all candidates; pass search=Search(method=...) "
                         f"with candidates='all' and k='auto', got candidates={candidates!r}, k={search.k!r}")
    check_order_method("independent", method, passes, max_iterations)
    rng = as_rng(rng)
    alone = isinstance(views, np.ndarray) or not isinstance(views, (list, tuple))  # one view, not in a list
    views = [views] if alone else list(views)
    if not 1 <= len(views) <= 3:
        raise ValueError(f"views must hold 1 to 3 images (one per axis), got {len(views)}")
    if is_auto(axes):
        axes = (0, 1, 2) if len(views) in (1, 3) else (0, 1)
    if isinstance(axes, (str, bytes)) or not hasattr(axes, "__len__"):
        raise TypeError(f"axes must be 'auto' or a sequence of volume axes (0, 1 or 2), one per view, got {axes!r}")
    axes = tuple(axes)
    if len(views) == 1 and len(axes) > 1:
        views = views * len(axes)
    if len(axes) != len(views) or not all(isinstance(a, numbers.Integral) and 0 <= a <= 2 for a in axes) or len(
        set(axes)
    ) != len(axes):
        raise ValueError(f"axes must name a distinct volume axis (0, 1 or 2) for each of the {len(views)} views, got {axes!r}")
    n = len(views)
    names = ["views"] * n if alone else [f"views[{i}]" for i in range(n)]
    # float32 work: the volume's neighbourhood vectors are the bulk of the
    # memory traffic (64^3 voxels x 3 views x ~100 values); voxels are averages
    # of exemplar pixels, so 1e-7 rounding is far below any visible change.
    srcs, channels, dtype, grey = prepare_sources(
        views, names, [nb.neighborhood_size] * n, [nb.parent_size] * n, list(axes), nb.levels, "neighborhood_size",
        work_dtype=_SOLID_DTYPE, shapes=[check_choice(nb.neighborhood_shape, "neighborhood_shape", SHAPES)] * n,
    )
    for src in srcs:
        src.weights = 1.0
    out, info = synthesize_levels(
        srcs, size, channels, _SOLID_DTYPE, levels=nb.levels, order="independent", method=method,
        iterations=max_iterations, passes=passes, rng=rng, progress=progress, desc="Wei solid", mixture=_EQ1,
    )
    out = restore_channels(out.astype(dtype, copy=False), grey)
    return (out, info) if return_info else out
