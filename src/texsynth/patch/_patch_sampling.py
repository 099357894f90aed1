"""Liang et al.'s patch-based sampling: patches chosen by their boundary zones, pasted and feathered.

Liang, Liu, Xu, Guo & Shum (2001) synthesise a texture from whole patches
``B_k`` of the exemplar (``w_B x w_B``), pasted in scanline order with a step
of ``w_B - w_E`` so that each overlaps the patches pasted before it by a
*boundary zone* of width ``w_E``. Each patch is a sample of the local
conditional MRF density, estimated non-parametrically from the boundary zones:

1. ``E_out``, the output's boundary zone at the new position (the band shared
   with the patch to the left, the one above, or both);
2. ``Ψ_B = {B : d(E_B, E_out) < d_max}``, every exemplar patch whose boundary
   zone ``E_B`` is close to it, with ``d`` the root-mean-square difference
   over the zone's ``A`` pixels and the relative tolerance
   ``d_max = ε [1/A Σ_i (p_out^i)^2]^{1/2}`` (``ε = 0.2``);
3. one patch of ``Ψ_B`` drawn uniformly, or the closest patch if ``Ψ_B`` is
   empty; the boundary zones are blended by feathering.

The paper makes the search real-time with an optimised kd-tree over
PCA-reduced boundary-zone vectors and a quad-tree pyramid. Here the distance
of *every* exemplar patch is computed exactly, at once, by the shared
template search (:class:`texsynth.core.search.WindowSearch`, FFT
correlation), so ``Ψ_B`` is the paper's set itself rather than an
approximation of it; see ``docs/methods/patch_sampling.md`` for why (speed and
memory measured in ``benchmarks/bench_quilting.py``). The block grid and its
raster loop are image quilting's (:mod:`texsynth.patch._quilting`).

Not checked against the paper's text (it was not at hand; this follows its
published description: abstract, lecture slides, secondary summaries):
the exact normalisation of ``d`` and ``d_max`` (here over pixels and
channels), the default boundary zone ``w_E = w_B / 6`` and ``ε = 0.2`` as the
paper's own values, and the feathering weights (here linear in the distance
to the patch border, ``w(d) = d``, as quoted from the paper's slides).
"""

from __future__ import annotations

import time

import numpy as np

from ..core._validate import as_image, as_rng, as_size, check_bool, with_channels
from ..core.search import window_search, within_radius
from ._quilting import (
    Grid,
    QuiltInfo,
    augmented_info,
    check_block,
    check_canvas_memory,
    check_overlap,
    check_tolerance,
    finish,
    overlap_widths,
    paste_blocks,
    quilt_info,
)

__all__ = ["PatchSamplingInfo", "patch_sampling"]

EPSILON = 0.2  # the relative matching error ε of d_max


class PatchSamplingInfo(QuiltInfo):
    """What :func:`patch_sampling` chose, patch by patch in scanline order.

    The fields of :class:`~texsynth.patch.QuiltInfo`, with ``errors`` and
    ``best_errors`` the boundary-zone distance ``d`` (root-mean-square over the
    zone's pixels and channels) of the chosen and of the closest patch, and
    ``candidates`` the size of ``Ψ_B`` (1 when it was empty and the closest
    patch was taken). ``overlap`` is the boundary zone's width ``w_E``.
    ``coordinates`` ``(H, W, K, 2)`` and ``weights`` ``(H, W, K)`` are the
    feathered blend of every pixel (``K`` up to 4 where the zones of four
    patches cross; weight 1 in a patch's interior).
    """


def feather_weights(known):
    """Weight of the new patch at every pixel of a block: linear ramps across its boundary zones.

    Across a zone of width ``w`` the new patch's weight rises as ``(j + 1) / (w
    + 1)`` with the distance ``j + 1`` from its border (the old patch's weight
    falling as its own distance to its border), the feathering ``w(d) = d`` of
    the paper; where two zones cross (the corner of an L-shaped zone) the
    ramps multiply. 1 outside the zones.
    """
    h, w = known.shape
    left, top, right, bottom = overlap_widths(known)

    def ramp(n, start, end):
        r = np.ones(n)
        if start:
            r[:start] = np.arange(1, start + 1) / (start + 1)
        if end:
            r[n - end:] *= np.arange(end, 0, -1) / (end + 1)
        return r

    return ramp(h, top, bottom)[:, None] * ramp(w, left, right)[None, :]


def patch_sampling(exemplar, size, *, block="auto", overlap="auto", error_tolerance=EPSILON, tileable=False,
                   augment="none", rng=None, return_info=False, progress=False):
    """Synthesise a texture by patch-based sampling (Liang et al. 2001).

    Examples
    --------
    >>> import texsynth
    >>> bread = texsynth.data.load("bread")[:96, :96]
    >>> out, info = texsynth.patch_sampling(bread, 128, block=32, rng=0, return_info=True)
    >>> out.shape, info.overlap, int(info.candidates.min()) >= 1
    ((128, 128, 3), 5, True)

    Pastes square patches of the exemplar in scanline order, each drawn at
    random among those whose boundary zone matches the output's within a
    tolerance, and feathers the boundary zones where patches overlap [1]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture: ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    size : int or (int, int)
        Output size ``(height, width)``; any size.
    block : int or "auto"
        Patch side ``w_B`` in pixels, about the size of the texture's
        elements. ``"auto"`` (default): a quarter of the exemplar's shorter side; at most
        the exemplar's shorter side.
    overlap : int or "auto"
        Width ``w_E`` of the boundary zone. ``"auto"`` (default): ``w_B / 6``, rounded; must
        be smaller than ``block``. 0 pastes random patches side by side.
    error_tolerance : float
        The relative matching error ``ε`` of ``d_max`` (default 0.2): a patch
        qualifies if its boundary-zone distance is below ``ε`` times the
        root-mean-square value of the output's boundary zone. 0 takes the
        closest patch. Must be >= 0.
    tileable : bool
        Make the output tile seamlessly: the patch grid wraps around, so the
        last patches of a row (column) also match and blend with the first.
    augment : {"none", "flips", "rotations", "both"}
        Also paste patches of the exemplar's mirror images (``"flips"``),
        quarter turns (``"rotations"``) or both, each patch from one copy,
        as ``Search(augment=...)`` does for the neighbourhood-matching
        methods (:func:`~texsynth.core.search.augmented_set`). Default
        ``"none"``. ``info.sources`` and ``info.coordinates`` still point
        into the exemplar (a source: the exemplar pixel that the patch's
        top-left pixel shows).
    rng : None, int or numpy.random.Generator
        Random source for the choice of patches; an int seed reproduces the
        output bit for bit.
    return_info : bool
        Also return a :class:`PatchSamplingInfo`.
    progress : bool or callable
        Report progress per patch (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    image : numpy.ndarray
        ``(height, width)`` or ``(height, width, C)``, the exemplar's channel
        layout; float32 for float32 input, float64 otherwise.
    info : PatchSamplingInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If ``block`` is larger than the exemplar, ``overlap >= block``,
        ``error_tolerance < 0``, or a tileable ``size`` is too small for the
        block; if the output would not fit in memory.

    Notes
    -----

    The boundary-zone distance of an exemplar patch ``B`` and the output's
    zone ``E_out`` of ``A`` pixels (``C`` channels) is

    .. math:: d(E_B, E_{out}) = \\Big[\\frac{1}{A C} \\sum_{i=1}^{A} \\|p_B^i - p_{out}^i\\|^2\\Big]^{1/2},
       \\qquad d_{max} = \\varepsilon \\Big[\\frac{1}{A C} \\sum_{i=1}^{A} \\|p_{out}^i\\|^2\\Big]^{1/2}

    and the patch is drawn uniformly from ``Ψ_B = {B : d < d_max}`` (the
    closest patch if it is empty). Every patch's ``d`` is computed exactly by
    FFT correlation; the paper's kd-tree, PCA and quad-tree pyramid
    approximate the same search to make it fast in 2001. The new patch's
    weight across each boundary zone of width ``w`` rises linearly, ``(j +
    1) / (w + 1)`` at ``j`` pixels from its border (feathering with ``w(d) =
    d``); the ramps of the two zones multiply in an L-shaped zone's corner.

    The method avoids the "growing garbage" of pixel-based sampling
    (Efros & Leung) because every patch is a whole, coherent piece of the
    exemplar. Feathering blurs the boundary zones a little where the patches
    disagree (Efros & Freeman's minimum-error cut, :func:`quilt`, avoids
    that); the patches follow a visible grid when ``ε`` is large on
    structured textures, and texture elements larger than the patch break.

    References
    ----------
    .. [1] L. Liang, C. Liu, Y.-Q. Xu, B. Guo and H.-Y. Shum, "Real-time
       texture synthesis by patch-based sampling", ACM Transactions on
       Graphics 20(3), 2001, pp. 127-150. :doi:`10.1145/501786.501787`
    """
    started = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey = with_channels(image)
    size = as_size(size)
    B = check_block(block, ex.shape[:2])
    w_E = check_overlap(overlap, B)
    epsilon = check_tolerance(error_tolerance, paper=EPSILON)
    grid = Grid(size, B, w_E, check_bool(tileable, "tileable"))
    gen = as_rng(rng)
    check_canvas_memory(grid, ex.shape[2], ex.shape[:2], value=size)
    search, atlas = window_search(ex.astype(np.float64), (B, B), augment)  # atlas: the exemplar's copies too
    exf = search.image

    def choose(window, region, known):
        if not known.any():  # the first patch: any
            top, left = search.draw(gen)
            return top, left, 0.0, 0.0, search.n_positions
        d2 = search.sq_distances(region, known)  # A C d(E_B, E_out)^2 for every patch B
        values = known.sum() * ex.shape[2]  # A C
        zone_energy = float(np.einsum("ij,ijc,ijc->", known, region, region))  # A C (d_max / ε)^2
        chosen = within_radius(d2, epsilon**2 * zone_energy)  # Ψ_B, or the closest patch
        k = int(chosen[gen.integers(chosen.size)])
        top, left = divmod(k, search.shape[1])
        return top, left, float(np.sqrt(d2.flat[k] / values)), float(np.sqrt(d2.min() / values)), int(chosen.size)

    def join(region, new, known):
        return feather_weights(known)

    canvas, records, searching, sources = paste_blocks(exf, grid, choose, join, progress, "patch sampling",
                                                       return_info)
    out = finish(canvas, size, image.dtype, grey)
    if return_info:
        info = augmented_info(quilt_info(grid, records, w_E, started, searching, sources, size), atlas)
        return out, PatchSamplingInfo(**vars(info))
    return out
