"""Harrison's patchwork texture transfer: a pattern image rendered in a texture (Harrison 2002, Section 5).

The output has the pattern's size; its Voronoi cells (:mod:`texsynth.patch._patchwork`)
copy texture patches chosen to match the pattern around each ``p_i``, and are
joined with eq. 7, which blends the local patch averages ``a_i`` so the output
follows the pattern's light and dark regions. With a video texture the cells
play the intermediate sequences of Section 4 (:mod:`texsynth.patch._patchwork_video`).
Symbols as in :mod:`texsynth.patch._patchwork` (the paper's Table 1).

References
----------
.. [1] P. Harrison, "Patchwork texture synthesis", Technical report,
   Monash University, 2002, Section 5.
"""

from __future__ import annotations

import time

import numpy as np

from ..core._progress import Progress
from ..core._validate import as_image, as_rng, check_bool, check_memory, check_positive_int, with_channels
from ..core.neighborhood import extract
from ..core.search import is_auto, nearest_candidates
from ._patchwork import (Geometry, blend, check_grid_spacing, check_neighbors, check_output_memory, check_sharpness,
                         draw_sources, finish_output, padded_flat, patchwork_info, run_bands)
from ._patchwork_video import check_video, resolve_frame_spacing, synthesize_video

__all__ = ["patchwork_transfer", "prescale_pattern"]


# --------------------------------------------------------------------------
# Section 5: texture transfer


def prescale_pattern(pattern, texture):
    """Rescale the pattern to the texture's mean colour and colour range (the paper's pre-processing)."""
    axes = tuple(range(pattern.ndim - 1))
    p_mean, t_mean = pattern.mean(axes), texture.mean(axes)
    p_range = pattern.max(axes) - pattern.min(axes)
    t_range = texture.max(axes) - texture.min(axes)
    gain = np.where(p_range > 0, t_range / np.where(p_range > 0, p_range, 1), 1.0)
    return (pattern - p_mean) * gain + t_mean


def _match_sources(geom, pattern, texture, n_candidates, patch, gen, progress):
    """Section 5: each q_i minimises the SSD between the pattern around p_i and the texture around q_i.

    Only ``n_candidates`` random positions (inside the allowed range of
    ``_source_bounds`` of :mod:`texsynth.patch._patchwork`) are tried per point. Returns ``q`` (rows, cols)
    and the local averages ``a_i`` of the chosen texture patches.
    """
    ny, nx = geom.grid_shape
    n = ny * nx
    cy = draw_sources(*geom.bounds_y, gen, n_candidates).reshape(n, n_candidates).astype(np.intp)
    cx = draw_sources(*geom.bounds_x, gen, n_candidates).reshape(n, n_candidates).astype(np.intp)
    centers = np.stack([(geom.py - 0.5).ravel(), (geom.px - 0.5).ravel()], 1).astype(np.intp)
    target = extract(pattern, centers, patch, mode="reflect").reshape(n, -1)
    values = target.shape[1]
    chunk = max(1, (1 << 22) // (n_candidates * values))  # about 16 MB of candidate patches at a time
    best = np.empty(n, np.intp)
    means = np.empty((n, texture.shape[-1]), np.float64)
    steps = range(0, n, chunk)
    bar = Progress(progress, len(steps), "patchwork_transfer: matching")
    for start in steps:
        sl = slice(start, min(n, start + chunk))
        k = sl.stop - sl.start
        cand = np.stack([cy[sl].ravel(), cx[sl].ravel()], 1)
        patches = extract(texture, cand, patch, mode="reflect").reshape(k, n_candidates, -1)
        choice, _ = nearest_candidates(target[sl], patches)  # the SSD of eq. 7's matching
        best[sl] = choice
        chosen = patches[np.arange(k), choice].reshape(k, -1, texture.shape[-1])
        means[sl] = chosen.mean(1)  # local average a_i of the patch
        bar.advance({"points": sl.stop})
    bar.close()
    rows = np.arange(n)
    qy = cy[rows, best].reshape(ny, nx) + 0.5
    qx = cx[rows, best].reshape(ny, nx) + 0.5
    return qy, qx, means.astype(np.float32)


def patchwork_transfer(
    texture,
    pattern,
    *,
    grid_spacing=16,
    sharpness=2,
    n_candidates=64,
    neighborhood_size="auto",
    prescale=True,
    n_frames=None,
    frame_spacing="auto",
    neighbors=4,
    rng=None,
    return_info=False,
    progress=False,
):
    """Texture transfer: render a pattern image in a texture (Harrison 2002, Section 5).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> metal = texsynth.data.load("metal")
    >>> pattern = np.zeros((48, 48)); pattern[12:36, 12:36] = 1.0  # a bright square
    >>> out = texsynth.patchwork_transfer(metal, pattern, grid_spacing=8, n_candidates=16, rng=0)
    >>> out.shape, bool(out[16:32, 16:32].mean() > out[:8].mean())
    ((48, 48), True)

    The output has the pattern's size. Its Voronoi cells copy texture patches
    chosen, among ``n_candidates`` random positions per cell, to best match the
    pattern around each ``p_i`` (sum of squared differences), and are joined
    with eq. 7, which blends the local patch averages ``a_i`` so the output
    follows the pattern's light and dark regions [1]_.

    Parameters
    ----------
    texture : array_like
        Texture ``I``: an image ``(H, W[, C])``, or with ``n_frames`` a video
        ``(T, H, W[, C])`` (the pattern is then matched against the average
        frame ``A(x)`` and the video method of Section 4 animates the result).
    pattern : array_like
        Pattern ``P`` ``(h, w[, C])`` with the same number of channels as the
        texture (for a grey pattern and a colour texture, repeat it:
        ``np.repeat(pattern[..., None], 3, axis=-1)``).
    grid_spacing : int
        Spacing of the points ``p_i`` (paper, Figure 8: 16).
    sharpness : float
        ``f`` of eq. 1 (paper, Figure 8: 2).
    n_candidates : int
        Size of the random subset of texture positions tried for each ``q_i``
        (the paper's remedy against one texture area repeated everywhere; it
        gives no number).
    neighborhood_size : int or "auto"
        Side of the square patches compared around ``p_i`` and ``q_i`` and
        averaged for ``a_i``; ``"auto"`` (default): ``grid_spacing``.
    prescale : bool
        Rescale the pattern to the texture's mean colour and colour range
        before matching (the paper's pre-processing; default True).
    n_frames : int, optional
        Output a video of this many frames (``texture`` is then a video).
    frame_spacing : int or "auto"
        Video only, see :func:`~texsynth.patch.patchwork_video`.
    neighbors : int
        Block size of the neighbour bound, see :func:`~texsynth.patch.patchwork`.
    rng : None, int or numpy.random.Generator
        Random source.
    return_info : bool
        Also return a :class:`~texsynth.patch.PatchworkInfo` (with ``local_means`` = ``a_i``).
    progress : bool or callable
        Report progress of the matching.

    Returns
    -------
    image : numpy.ndarray
        ``(h, w[, C])``, or ``(n_frames, h, w[, C])`` for video.
    info : PatchworkInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If the texture and the pattern have different numbers of channels,
        ``grid_spacing`` or ``neighborhood_size`` exceed the texture, ``sharpness <=
        0``, or a video texture has fewer than 2 frames.

    Notes
    -----

    Eq. 7:

    .. math:: O(x) = \\frac{\\sum_i (I(x - p_i + q_i) - a_i) w_i(x)}
              {\\sqrt{\\sum_i w_i(x)^2}} + \\frac{\\sum_i a_i w_i(x)}{\\sum_i w_i(x)}

    As in :func:`~texsynth.patch.patchwork`, the sums run over the ``m x m`` block of cells
    around ``x`` with each ``w_i(x)`` multiplied by the window ``phi_i(x)``
    that tapers it to 0 at the edge of that block (a departure from the
    paper's plain omission of small terms, see the module notes). Transfer
    needs it most: at its default ``f = 2`` the weights fall off slowly and
    the second term uses their first power, so the plain cut left faint
    straight seams every ``grid_spacing`` pixels in flat areas. The ``q_i``
    are chosen exactly as without it.

    No source-coordinate map (``info.coordinates`` is None): the local
    means ``a_i`` of eq. 7 are averages over each cell's whole
    ``neighborhood_size`` square of texture, so rendering another channel
    exactly would need every pixel of those squares in every output pixel's
    map (256 slots per cell at the default 16, with eq. 7's two
    normalisations), not the few pixels per output pixel of a map; a map of
    the ``x - p_i + q_i`` alone with the channel's global mean in place of
    ``a_i`` would not follow the pattern. To carry other channels through a
    transfer, stack them as extra channels of ``texture`` (and of
    ``pattern``, e.g. the pattern itself or a constant, which then also
    weighs in the matching).

    References
    ----------
    .. [1] P. Harrison, "Patchwork texture synthesis", Technical report,
       Monash University, 2002, Section 5.
    """
    start = time.perf_counter()
    is_video = n_frames is not None
    if is_video:
        source = check_video(texture, "texture")
        tex, grey = with_channels(source, spatial_dims=3)
        N = check_positive_int(n_frames, "n_frames")
        spacing = resolve_frame_spacing(frame_spacing, tex.shape[0], N)
        reference = tex.astype(np.float32).mean(0)  # A(x): the pattern is matched against the average frame
    else:
        source = as_image(texture, "texture")
        tex, grey = with_channels(source)
        reference = tex.astype(np.float32)
    pat, pat_grey = with_channels(as_image(pattern, "pattern"))
    if pat.shape[-1] != reference.shape[-1]:
        hint = " (repeat a grey pattern: np.repeat(pattern[..., None], 3, axis=-1))" if pat.shape[-1] == 1 else ""
        if is_video:
            hint += f"; with n_frames={n_frames}, texture is read as a video (T, H, W[, C])"
        raise ValueError(
            f"pattern has {pat.shape[-1]} channel(s) but texture has {reference.shape[-1]}; "
            f"pass images with the same number of channels{hint}"
        )
    f = check_sharpness(sharpness)
    m = check_neighbors(neighbors)
    s = check_grid_spacing(grid_spacing, reference.shape[:2], f, m, "texture")
    K = check_positive_int(n_candidates, "n_candidates")
    # the candidates of a chunk of grid points are compared at once; every point keeps its K positions
    check_memory(8.0 * K * (pat.shape[0] / s + 2) * (pat.shape[1] / s + 2) * 3, K, "n_candidates",
                 "the candidate positions")
    patch = s if is_auto(neighborhood_size) else check_positive_int(neighborhood_size, "neighborhood_size")
    if patch > min(reference.shape[:2]) or patch > min(pat.shape[:2]):
        raise ValueError(
            f"patch_size {patch} is larger than the texture {reference.shape[:2]} or the pattern "
            f"{pat.shape[:2]}; pass a smaller neighborhood_size"
        )
    gen = as_rng(rng)
    H, W = pat.shape[:2]
    check_output_memory((H, W), reference.shape[-1], s, frames=N if is_video else 1, cells=return_info)
    geom = Geometry((H, W), reference.shape[:2], s, f, m, False, gen, choose_q=False)
    target = pat.astype(np.float32)
    if check_bool(prescale, "prescale"):
        target = prescale_pattern(target, reference)
    qy, qx, local = _match_sources(geom, target, reference, K, patch, gen, progress)
    matched = time.perf_counter()
    geom.set_sources(qy, qx)

    if is_video:
        out, cells, seq, _ = synthesize_video(geom, tex, N, spacing, gen, local, False, "patchwork_transfer")
        extra = {"frame_keys": seq.keys[:, :-1], "frame_sources": seq.sources[:, :-1]}
    else:
        C = reference.shape[-1]
        pads = geom.pad()
        table, width = padded_flat(reference, pads)
        out = np.empty((H, W, C), np.float32)

        def compose(band, parts):
            blended = blend(parts, lambda n, ids, flat: table.take(flat, axis=0), C, local)
            idx, rows = geom.to_output(band, blended)
            out[idx] = rows

        cells = run_bands(geom, width, pads, return_info, compose, False, "patchwork_transfer")
        extra = {}
    result, clipped = finish_output(out, source.dtype, grey)
    if return_info:
        return result, patchwork_info(geom, cells, clipped, start, matched, local_means=local, **extra)
    return result
