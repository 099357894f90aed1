"""Image completion by texture optimization: hole filling with a sample mask, and uncrop.

Kwatra et al. [1]_ (Section 4) fill a hole by texture optimization with the
known pixels as constraints and the rest of the image as the exemplar. The
two functions here are that application, at the sizes photographs have:

:func:`inpaint`
    Fill the pixels of ``hole`` from the image's other pixels, or only from
    those ``sample_mask`` allows (resynthesizer's "heal selection" with a
    sampling area, Embark's sample masks).
:func:`uncrop`
    Extend an image beyond its borders: the image is placed in a larger
    canvas and everything around it is synthesised from it (resynthesizer's
    "Uncrop", outpainting).
:func:`make_tileable`
    Make an existing photo tile seamlessly: a band along its edges is
    re-synthesised on a toroidal canvas (the top meets the bottom, the left
    the right), the interior is kept.

All three run :func:`texsynth.optimize_texture` with hard constraints
(``constraint_weight=inf``): the known pixels are the target, every E-step
puts them back, so the M-step is the plain nearest-neighbour search and runs
with PatchMatch on large stages. That is the form of Wexler, Shechtman &
Irani's space-time completion [2]_ and of PatchMatch's hole filling [3]_;
Kwatra et al.'s soft constraint with a large λ (Algorithm 2) reaches the
same fixed point but queries an index of every image neighbourhood for every
constrained neighbourhood, which at 512² needs tens of GiB. Under hard
constraints only the neighbourhoods near the unknown pixels take part (the
others vote only for pixels that are put back), so a hole costs time in
proportion to its size, not the image's: a disc of radius 80 in a 512²
photograph 1.1-1.7 s, against 5.0-7.5 s with every neighbourhood
(``benchmarks/bench_completion.py``).

:func:`inpaint` and :func:`uncrop` also weigh each neighbourhood in the E-step by Wexler et
al.'s confidence (``confidence=1.3``: a filled pixel at distance ``d`` from the known ones counts
``1.3^-d``), so that near the boundary the neighbourhoods lying on known pixels decide: their
seams fell from 1.65 to 1.02 (bricks) and 4.20 to 3.15 (pebbles) on uncrop
(``benchmarks/bench_completion.py``). :func:`make_tileable` does not: the two sides of its band
meet in the middle, and the confidence made that meeting a seam (2x2 tiling seam 0.66-0.98 without,
1.31-1.74 with).

The fill is then blended into the image in the gradient domain (``blend_width=32``,
:func:`texsynth.core.seams.poisson_blend`: the membrane of Pérez, Gangnet & Blake's seamless
cloning [4]_ over a band 32 px wide, from the fill's colour mismatch smoothed along the border):
where a copy of the texture meets the image lighter or darker than it, the step goes and the
fill's texture stays (docs/methods/completion.md). The fill is blended only into the known pixels
it may copy from (``sample_mask``), so a hole between two textures is not pulled towards the one
it does not copy. ``blend_width=0`` keeps the fill as synthesised (exemplar pixels, as
``info.coordinates`` maps them).

Choices, with reasons: the completeness term and the copy limit of the
default preset are off (the known part of the image *is* a verbatim copy of
the exemplar); its histogram matching is on for the unknown pixels (their
colours get the sampling area's histogram after every E-step: without it an
uncropped border washes out into flat colour, as large enlargements do);
neighbourhood
sizes and levels follow the image's feature scale as in the default preset,
with the sizes halved on down to 8 pixels (the preset stops at a quarter of
the largest, 16 for 64: a last stage of small neighbourhoods joins the fill
to the known pixels: 6-24 % lower boundary seams on seven photographs)
and at least enough levels that the coarsest sees the hole narrower than its
largest neighbourhood (otherwise nothing carries structure across the hole:
``docs/methods/kwatra.md``, hole filling); the output equals the input
outside the hole, bit for bit.

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for
   example-based synthesis", SIGGRAPH 2005. :doi:`10.1145/1073204.1073263`
.. [2] Y. Wexler, E. Shechtman and M. Irani, "Space-time completion of video",
   IEEE TPAMI 29(3), 2007. :doi:`10.1109/TPAMI.2007.60`
.. [3] C. Barnes, E. Shechtman, A. Finkelstein and D. B. Goldman,
   "PatchMatch: a randomized correspondence algorithm for structural image
   editing", SIGGRAPH 2009. :doi:`10.1145/1531326.1531330`
.. [4] P. Pérez, M. Gangnet and A. Blake, "Poisson image editing", SIGGRAPH
   2003. :doi:`10.1145/882262.882269`
"""

from __future__ import annotations

import math
import os
import warnings

import numpy as np

from ..core._validate import as_image, as_size, check_memory, check_positive_int, with_channels
from ..core.neighborhood import patches_within
from ..core.seams import poisson_blend
from ..core.em import WEXLER_CONFIDENCE, Constraints, Schedule, Terms, check_mask, check_sizes
from ..core.search import Search, is_auto
from ..core.scale import scale_schedule
from ._kwatra import optimize_texture

__all__ = ["inpaint", "uncrop", "make_tileable"]

#: The terms the completion functions pass to :func:`~texsynth.optimize_texture`: the fill continues the known
#: pixels (hard constraints), with neither the completeness term nor the copy limit, its histogram the image's.
_TERMS = Terms(completeness_weight=0.0, copy_limit=None, histogram_matching=True)
#: "auto" neighbourhood sizes end at this one (the default preset's end at a quarter of the largest, 16 for 64):
#: on seven photographs (``benchmarks/bench_completion.py``, its four and ``--photos tiles_1 cobblestones_2
#: bark_1``) the 8-px stage lowered the boundary seam of every fill whose schedule it changed, 11 of 14, by 6-24 %
#: (docs/methods/completion.md)
_SMALLEST = 8
#: The band of the fill blended into the known pixels (``blend_width``): on seven photographs
#: (``benchmarks/bench_completion.py``'s hole and uncrop, seeds 0-1) the boundary seam fell from 1.47 to
#: 1.14 (holes) and from 1.54 to 1.11 (uncrops), the sharpness unchanged. A band of 16 px gave the seams of
#: 32 px in a first version (the fill held level with the image across the border); the wider band spreads
#: the correction more gently (docs/methods/completion.md)
BLEND_WIDTH = 32


def _sizes(exemplar, shape, neighborhood_sizes):
    """The neighbourhood sizes, checked against the image. "auto": the default preset's, halved on down
    to 8 pixels (a last stage of small neighbourhoods joins the fill to the known pixels)."""
    if is_auto(neighborhood_sizes):
        sizes = scale_schedule(exemplar, shape)[0]
        while sizes[-1] > _SMALLEST:
            sizes += (sizes[-1] // 2,)
    else:
        sizes = check_sizes(neighborhood_sizes)
    if min(sizes) > min(exemplar.shape[:2]):
        raise ValueError(f"the image is {exemplar.shape[0]}x{exemplar.shape[1]} but the smallest neighborhood is "
                         f"{min(sizes)}; pass neighborhood_sizes no larger than {min(exemplar.shape[:2])}")
    return sizes


def _schedule(exemplar, shape, hole, neighborhood_sizes, levels):
    """Sizes and levels: the default preset's, with levels enough for the coarsest to span the hole."""
    sizes = _sizes(exemplar, shape, neighborhood_sizes)
    auto_levels = scale_schedule(exemplar, shape)[1]
    if not is_auto(levels):
        return sizes, check_positive_int(levels, "levels")
    rows, cols = np.nonzero(hole)
    span = max(rows.max() - rows.min() + 1, cols.max() - cols.min() + 1)
    # the hole at level L is span / 2^L wide; the largest neighbourhood should cover it, and the
    # coarsest exemplar should still hold the smallest neighbourhood
    wanted = max(auto_levels, 1 + math.ceil(math.log2(max(span / max(sizes), 1))))
    return sizes, min(wanted, 1 + int(math.log2(max(1, min(exemplar.shape[:2]) // min(sizes)))))


def _hole(hole, channels, grey):
    """``inpaint``'s hole as an ``(H, W)`` bool map: a map or an image file (white, > 0.5 = fill), or "alpha"
    (every pixel that is not opaque: alpha < 1)."""
    shape = channels.shape[:2]
    if isinstance(hole, str) and hole == "alpha":
        if grey or channels.shape[-1] not in (2, 4):
            layout = "grey" if grey or channels.shape[-1] == 1 else f"{channels.shape[-1]} channels"
            raise ValueError(f"hole='alpha' takes the hole from the image's alpha channel (alpha < 1 = fill), but "
                             f"the image has none ({layout}); pass an RGBA or grey + alpha image, or a hole map")
        return channels[..., -1] < 1.0
    if isinstance(hole, (str, os.PathLike)):  # a file: grey, or colour channels averaged, alpha ignored
        if isinstance(hole, str) and not os.path.exists(hole):
            raise ValueError(f"hole must be an (H, W) map, an image file or 'alpha', got {hole!r} (no such file)")
        picture = as_image(hole, "hole")
        if picture.ndim == 3:
            picture = picture[..., 0] if picture.shape[-1] <= 2 else picture[..., :3].mean(axis=-1)
        hole = picture
    return check_mask(hole, shape, "hole") > 0.5


def _check_sources(allowed, smallest, name):
    """Refuse a sampling area with no whole neighbourhood of the smallest size."""
    if not patches_within(allowed > 0.5, smallest).any():
        raise ValueError(
            f"{name} leaves no {smallest}x{smallest} block of pixels to copy from; allow a larger sampling area "
            f"or pass smaller neighborhood_sizes"
        )


def _complete(exemplar, target, known, allowed, sizes, levels, grey, return_info, *, max_iterations, method, rng,
              progress, tileable=False, origin=(0, 0), blend_width=0, confidence=None):
    """Texture optimization with the ``known`` pixels of ``target`` as hard constraints; those pixels
    pasted back bit for bit, the fill within ``blend_width`` of them blended into them in the gradient
    domain, the exemplar's channel layout restored. The known pixels are the exemplar's own, placed at
    ``origin``: the source-coordinate map says so for them."""
    hard = Constraints(mask=known, target=target, constraint_weight=np.inf, confidence=confidence,
                       exemplar_mask=allowed)
    out, info = optimize_texture(exemplar, known.shape, schedule=Schedule(sizes, levels, max_iterations=max_iterations),
                                 terms=_TERMS, search=Search(method=method), constraints=hard, tileable=tileable,
                                 rng=rng, progress=progress, return_info=True)
    out[known] = target[known]
    if blend_width:  # into the known pixels the fill may copy from (not a texture beside them)
        sources = np.zeros(known.shape, bool)
        sources[origin[0] : origin[0] + allowed.shape[0], origin[1] : origin[1] + allowed.shape[1]] = allowed
        # the blend keeps every known pixel bit for bit (its clip is to the image's own range)
        out = poisson_blend(out, known, blend_width=blend_width, sample_mask=sources).astype(out.dtype, copy=False)
    rows, cols = np.nonzero(known)
    info.coordinates[rows, cols] = np.stack([rows - origin[0], cols - origin[1]], axis=1)
    out = out[..., 0] if grey else out
    return (out, info) if return_info else out


def inpaint(image, hole, *, sample_mask=None, neighborhood_sizes="auto", levels="auto", max_iterations=5,
            blend_width=BLEND_WIDTH, method="auto", rng=None, progress=False, return_info=False):
    """Fill a hole of an image with texture taken from the rest of it (Kwatra et al. 2005, Section 4).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> image = texsynth.data.load("bread")[:48, :48]
    >>> hole = np.zeros((48, 48), bool); hole[18:30, 18:30] = True
    >>> out = texsynth.inpaint(image, hole, neighborhood_sizes=(8,), levels=1, max_iterations=2, rng=0)
    >>> bool(np.array_equal(out[~hole], image[~hole]))
    True

    Texture optimization (Kwatra et al. 2005, Section 4 [1]_) with the known
    pixels as hard constraints and the rest of the image as the exemplar, the
    form of Wexler et al.'s space-time completion [2]_; the fill is then
    blended into the image in the gradient domain (``blend_width``).

    Parameters
    ----------
    image : array_like, str or os.PathLike
        ``(H, W)`` or ``(H, W, C)`` image with a hole (the values inside the
        hole are ignored), or its file.
    hole : array_like, str, os.PathLike or "alpha"
        Where to fill: an image file or an ``(H, W)`` map, white (> 0.5,
        True) = fill. A file's colour channels are averaged and its alpha
        channel ignored. ``"alpha"``: the hole is the image's own
        transparency (an RGBA or grey + alpha image): every pixel that is
        not opaque (alpha < 1) is filled from the opaque ones, and the image
        is then laid over the fill by its alpha (Porter-Duff *over*), so a
        soft, feathered edge blends into the fill and the result is opaque
        wherever the fill is (GIMP's heal-transparency). A hole
        over more than half of the image gives a UserWarning: a mask drawn
        the other way round (black = fill, as Embark's) is inverted with
        ``~hole`` (``--invert-mask`` on the command line).
    sample_mask : array_like of bool, optional
        Where pixels may be copied into the hole (the sampling area): an
        ``(H, W)`` map, white (> 0.5, True) = may be copied; default every
        pixel outside the hole. Pixels of the hole are never copied.
    neighborhood_sizes : sequence of int or "auto"
        As in :func:`~texsynth.optimize_texture`, but ``"auto"`` is the
        default preset's sizes (from the image's feature scale) halved on
        down to 8 pixels.
    levels : int or "auto"
        As in :func:`~texsynth.optimize_texture`, but ``"auto"`` gives
        levels enough that the coarsest level sees the hole no wider than
        the largest neighbourhood.
    blend_width : int
        Width in pixels of the band of filled pixels that is blended into
        the known ones in the gradient domain (Pérez et al. 2003's seamless
        cloning, :func:`texsynth.core.seams.poisson_blend`): the fill keeps
        its texture and loses the step in colour where it meets the image.
        Default 32; 0 leaves the fill as the synthesis made it (exemplar
        pixels, as ``info.coordinates`` maps them).
    max_iterations, method, rng, progress
        As in :func:`~texsynth.optimize_texture`.
    return_info : bool
        Also return the :class:`~texsynth.optimization.OptimizationInfo`.

    Returns
    -------
    image : numpy.ndarray
        The image with the hole filled; every pixel outside the hole is the
        input's, bit for bit.
    info : OptimizationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For a ``hole`` or ``sample_mask`` of another shape, a hole with no
        pixel or with no known pixel around it, ``hole="alpha"`` for an
        image without an alpha channel, a sampling area without a whole
        neighbourhood, and the errors of :func:`~texsynth.optimize_texture`.

    Warns
    -----
    UserWarning
        When the hole covers more than half of the image, naming its share.

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for
       example-based synthesis", SIGGRAPH 2005. :doi:`10.1145/1073204.1073263`
    .. [2] Y. Wexler, E. Shechtman and M. Irani, "Space-time completion of video",
       IEEE TPAMI 29(3), 2007. :doi:`10.1109/TPAMI.2007.60`
    """
    img = as_image(image, "image")
    channels, grey = with_channels(img)
    shape = channels.shape[:2]
    transparency = isinstance(hole, str) and hole == "alpha"
    hole = _hole(hole, channels, grey)
    share = float(hole.mean())
    if 0.5 < share < 1.0:
        warnings.warn(f"the hole covers {100 * share:.0f} % of the image (white, True = fill); if white marks what "
                      f"to keep, invert it: ~hole (on the command line --invert-mask)", UserWarning, stacklevel=2)
    if not hole.any():
        raise ValueError("hole marks no pixel; pass a boolean (H, W) mask that is True where pixels are to be filled")
    if hole.all():
        raise ValueError("hole covers the whole image, so nothing is known to fill it from; leave some pixels "
                         "outside the hole (or use texsynth.optimize_texture to synthesise from an exemplar)")
    allowed = ~hole if sample_mask is None else ~hole & (check_mask(sample_mask, shape, "sample_mask") > 0.5)
    sizes, levels = _schedule(channels, shape, hole, neighborhood_sizes, levels)
    _check_sources(allowed, min(sizes), "sample_mask" if sample_mask is not None else "hole")
    out, info = _complete(channels, channels, ~hole, allowed, sizes, levels, grey, True,
                          blend_width=check_positive_int(blend_width, "blend_width", 0), confidence=WEXLER_CONFIDENCE,
                          max_iterations=max_iterations, method=method, rng=rng, progress=progress)
    if transparency:  # the image laid over its fill: a soft edge blends into the fill, and the result is opaque
        out = _over(channels, out)
    return (out, info) if return_info else out


def _over(image, fill):
    """``image`` composited over ``fill`` by its alpha (the last channel, straight, not premultiplied): Porter and
    Duff's *over*, :doi:`10.1145/964965.808606`. Opaque pixels of ``image`` are kept bit for bit."""
    a, b = image[..., -1:], fill[..., -1:]
    alpha = a + (1 - a) * b
    colour = a * image[..., :-1] + (1 - a) * b * fill[..., :-1]
    colour = np.divide(colour, alpha, out=fill[..., :-1].astype(colour.dtype), where=alpha > 0)
    return np.concatenate([colour, alpha], axis=-1).astype(fill.dtype, copy=False)


def uncrop(image, size, *, position="center", sample_mask=None, neighborhood_sizes="auto", levels="auto",
           max_iterations=5, blend_width=BLEND_WIDTH, method="auto", rng=None, progress=False, return_info=False):
    """Extend an image beyond its borders with texture taken from it (uncrop, outpainting).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> image = texsynth.data.load("bread")[:32, :32]
    >>> out = texsynth.uncrop(image, 48, neighborhood_sizes=(8,), levels=1, max_iterations=2, rng=0)
    >>> out.shape, bool(np.array_equal(out[8:40, 8:40], image))
    ((48, 48, 3), True)

    The image is placed in a canvas of ``size`` and everything around it is
    synthesised from it, as :func:`inpaint` fills a hole: texture
    optimization (Kwatra et al. 2005, Section 4 [1]_) with the image as hard
    constraints (resynthesizer's "Uncrop").

    Parameters
    ----------
    image : array_like
        ``(h, w)`` or ``(h, w, C)``.
    size : int or (int, int)
        ``(H, W)`` of the result, at least the image's size and larger on
        at least one side.
    position : "center" or (int, int)
        Where the image's top-left pixel lands in the result: centred
        (default), or ``(row, col)`` (``(0, 0)``: extend to the bottom and
        right only).
    sample_mask : array_like of bool, optional
        Where the image's pixels may be copied: an ``(h, w)`` map, white
        (> 0.5, True) = may be copied; default all.
    neighborhood_sizes, levels, max_iterations, blend_width, method, rng, progress, return_info
        As in :func:`inpaint`.

    Returns
    -------
    image : numpy.ndarray
        ``size``, with the input unchanged at ``position``.
    info : OptimizationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For a ``size`` smaller than the image, a ``position`` that does not
        keep the image inside, a ``sample_mask`` of another shape or without a
        whole neighbourhood, and the errors of
        :func:`~texsynth.optimize_texture`.

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for
       example-based synthesis", SIGGRAPH 2005. :doi:`10.1145/1073204.1073263`
    """
    img = as_image(image, "image")
    channels, grey = with_channels(img)
    h, w = channels.shape[:2]
    shape = as_size(size)
    if shape[0] < h or shape[1] < w:
        raise ValueError(f"size {shape} is smaller than the image ({h}, {w}); pass a size at least the image's "
                         f"(to make it smaller, crop it)")
    if shape == (h, w):
        raise ValueError(f"size {shape} is the image's size: nothing to fill; pass a size larger than the image "
                         f"({h}, {w}) on at least one side")
    if isinstance(position, str) and position == "center":
        top, left = (shape[0] - h) // 2, (shape[1] - w) // 2
    else:
        try:
            top, left = (int(v) for v in position)
        except (TypeError, ValueError):
            raise TypeError(f"position must be 'center' or (row, col), got {position!r}") from None
        if not (0 <= top <= shape[0] - h and 0 <= left <= shape[1] - w):
            raise ValueError(f"position {(top, left)} puts the {h}x{w} image outside the {shape} result; pass "
                             f"0 <= row <= {shape[0] - h} and 0 <= col <= {shape[1] - w}, or 'center'")
    allowed = np.ones((h, w), bool) if sample_mask is None else check_mask(sample_mask, (h, w), "sample_mask") > 0.5
    sizes = _sizes(channels, shape, neighborhood_sizes)
    # held at once until optimize_texture checks its own arrays: here the canvas and its mask (a byte a pixel);
    # there the target's two copies (its conversion, then astype) and the mask's two float64 ones, then both
    # again on its canvas, up to half the largest neighbourhood larger (its margin); and per exemplar pixel,
    # two copies, the valid mask and the Fourier transforms of the feature scale (80 + 8 C bytes)
    margin, c, item = sizes[0] // 2, channels.shape[-1], channels.itemsize
    check_memory(float(shape[0] + margin) * (shape[1] + margin) * (3 * c * item + 17)
                 + float(h) * w * (2 * c * item + 8 * c + 96), shape)
    canvas = np.zeros(shape + (channels.shape[-1],), channels.dtype)
    canvas[top : top + h, left : left + w] = channels
    known = np.zeros(shape, bool)
    known[top : top + h, left : left + w] = True
    sizes, levels = _schedule(channels, shape, ~known, sizes, levels)
    _check_sources(allowed, min(sizes), "sample_mask")
    return _complete(channels, canvas, known, allowed, sizes, levels, grey, return_info, origin=(top, left),
                     blend_width=check_positive_int(blend_width, "blend_width", 0), confidence=WEXLER_CONFIDENCE,
                     max_iterations=max_iterations, method=method, rng=rng, progress=progress)


def make_tileable(image, *, band="auto", neighborhood_sizes="auto", levels="auto", max_iterations=5,
                  method="auto", rng=None, progress=False, return_info=False):
    """Make a photo tile seamlessly by re-synthesising a band along its edges (its interior is kept).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> image = texsynth.data.load("bread")[:48, :48]
    >>> out = texsynth.make_tileable(image, band=8, neighborhood_sizes=(8,), levels=1, max_iterations=2, rng=0)
    >>> bool(np.array_equal(out[8:-8, 8:-8], image[8:-8, 8:-8]))
    True

    The pixels within ``band`` of the image's edges are unknown, the rest
    are hard constraints, and the whole image is the exemplar of a
    *tileable* (toroidal) texture optimization [1]_: the band is filled so that
    its neighbourhoods, which wrap round from the right edge to the left and
    from the bottom to the top, look like neighbourhoods of the photo. The
    result's opposite edges meet without a seam, so it can be repeated
    (``np.tile(out, (2, 2, 1))``).

    Parameters
    ----------
    image : array_like
        ``(H, W)`` or ``(H, W, C)``.
    band : "auto" or int
        Width in pixels of the re-synthesised border (the same on all four
        sides; the seam region across each wrap-around edge is twice as
        wide). ``"auto"``: an eighth of the smaller side, and at least the
        smallest neighbourhood size, so that every neighbourhood that crosses
        an edge has unknown pixels to move (narrower, and the two edges'
        pixels would be fixed face to face with nothing between them to
        mend the seam); wider bands change more of the photo for no better
        seam.
    neighborhood_sizes, levels, max_iterations, method, rng, progress, return_info
        As in :func:`inpaint`.

    Returns
    -------
    image : numpy.ndarray
        The same shape; the pixels at least ``band`` from every edge are the
        input's, bit for bit.
    info : OptimizationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For a ``band`` that is not a positive int or "auto", an image too
        small for the band (it must leave an interior at least as large as
        the smallest neighbourhood), and the errors of
        :func:`~texsynth.optimize_texture`.

    References
    ----------
    .. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for
       example-based synthesis", SIGGRAPH 2005. :doi:`10.1145/1073204.1073263`
    """
    img = as_image(image, "image")
    channels, grey = with_channels(img)
    h, w = shape = channels.shape[:2]
    smallest = min(_sizes(channels, shape, neighborhood_sizes))
    if isinstance(band, str) and band == "auto":
        band = max(min(h, w) // 8, smallest)
    elif isinstance(band, str):
        raise ValueError(f"band must be 'auto' or a positive int, got {band!r}")
    else:
        band = check_positive_int(band, "band")
    if min(h, w) - 2 * band < smallest:
        raise ValueError(
            f"the image is {h}x{w}, too small for band {band}: the kept interior must be at least the smallest "
            f"neighborhood ({smallest}) wide; pass a smaller band (at most {max((min(h, w) - smallest) // 2, 0)}) "
            f"or a larger image"
        )
    known = np.zeros(shape, bool)
    known[band : h - band, band : w - band] = True
    # the hole is a frame; on the torus it is a cross of width 2*band through the wrapped edges
    cross = np.zeros(shape, bool)
    cross[: 2 * band, : 2 * band] = True
    sizes, levels = _schedule(channels, shape, cross, neighborhood_sizes, levels)
    return _complete(channels, channels, known, np.ones(shape, bool), sizes, levels, grey, return_info,
                     tileable=True, max_iterations=max_iterations, method=method, rng=rng, progress=progress)
