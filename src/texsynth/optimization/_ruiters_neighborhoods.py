"""The interpolated neighbourhoods of patch-based texture interpolation (Ruiters, Schnabel and Klein 2010).

``InterpolateNeighborhoods`` of the paper's Pseudocode 1 (Sections 4.1 and
4.2), the set ``N'`` from which :func:`~texsynth.interpolate_textures`
synthesises: for every neighbourhood of each texture the most similar
neighbourhoods of the other one over colour and a distance-to-feature
channel (Section 4.1), the two patches' feature points matched by TPS-RPM
(:func:`texsynth.core.tps.tps_rpm`, eq. 1), each patch warped part of the
way towards the other, colour-adjusted and blended, and the best-aligned
fraction kept (Section 4.2)::

    InterpolateNeighborhoods(I1, I2, F1, F2, alpha, r, s)
      downsample I1, I2, F1, F2 by r
      for each neighbourhood N_i of I1 (and of I2):
        N_j = argmin ||W_C (N_i - N_j)||      (both directions)
        theta_12, theta_21 = TPS-RPM(features of N_i, features of N_j)
        N' += (1 - a) N_i(theta'_21(x)) + a N_j(theta'_12(x))
      keep the most similar half

The option groups :class:`Correspondences` and :class:`NeighborhoodSet`
hold the options of these two sections; :mod:`texsynth.optimization._ruiters`
holds the synthesis (Sections 4.3-4.5).

References
----------
.. [1] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
   interpolation", Computer Graphics Forum 29(4) (EGSR 2010), 1421-1429.
   :doi:`10.1111/j.1467-8659.2010.01739.x`
"""

from __future__ import annotations

import inspect
import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core._validate import (as_image, as_rng, check_group, check_in_range, check_positive_float,
                              check_positive_int, with_channels)
from ..core.search import (PatchIndex, Search, check_candidates, check_method, coherence_sets, patchmatch_features,
                           refuse_augment)
from ..core.neighborhood import all_patches
from ..core.tps import tps_rpm

__all__ = [
    "interpolate_neighborhoods", "Correspondences", "NeighborhoodSet", "edge_feature_map", "ridge_feature_map",
    # the synthesis of texsynth.optimization._ruiters builds on these
    "Inputs", "check_inputs", "stage_textures", "interpolated_set", "downsample",
]

# candidates="k-coherent": the size of the k-coherence sets of the correspondences (search.k="auto"), and the
# iterations over them after one PatchMatch iteration from random matches
_CORRESPONDENCE_SET = 4
_CORRESPONDENCE_ITERATIONS = 3


# --------------------------------------------------------------------------- option groups
@dataclass(frozen=True)
class Correspondences:
    """How corresponding neighbourhoods are found, aligned and compared (Ruiters et al. 2010, Sections 4.1-4.2).

    Examples
    --------
    >>> import texsynth
    >>> correspondences = texsynth.Correspondences(max_feature_points=12)  # cheaper TPS-RPM
    >>> correspondences.n_correspondences
    1

    An option group of :func:`~texsynth.interpolate_textures` and
    :func:`~texsynth.optimization.interpolate_neighborhoods`
    (``correspondences=Correspondences(...)``); on the command line its
    fields are flags (``--n-correspondences``, ``--distance-weight``, ...).

    Parameters
    ----------
    n_correspondences : int
        Corresponding neighbourhoods per neighbourhood: its nearest
        ``n_correspondences`` in the other texture, in both directions (1 in
        the paper).
    distance_weight : float
        Channel weight ``W_C`` of the distance channel (colour channels 1) in
        the correspondence search and the synthesis, at most 1e6.
    feature_weight : float
        Relative weight of the warped distance channels against the colour
        normalized cross-correlation in the similarity (in [0, 1]).
    max_feature_points : int
        Cap on the feature points per patch given to TPS-RPM (random
        subsample, default 24). Fewer points = cheaper matching but coarser
        alignment of thin features.
    rpm_options : dict, optional
        Options of :func:`texsynth.core.tps.tps_rpm`; defaults here anneal faster
        than Chui and Rangarajan's (``anneal_rate=0.8,
        iterations_per_temperature=3, sinkhorn_iterations=10``) and hold the
        affine part 1000 times stiffer (``affine_lambda_init=10``; theirs
        is 0.01, see Notes of :func:`~texsynth.interpolate_textures`).
    """

    n_correspondences: int = 1
    distance_weight: float = 1.0
    feature_weight: float = 0.5
    max_feature_points: int = 24
    rpm_options: object = None


@dataclass(frozen=True)
class NeighborhoodSet:
    """Which interpolated neighbourhoods make up ``N'``, and how many (Ruiters et al. 2010, Section 4.2).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.NeighborhoodSet(max_neighborhoods=256)
    NeighborhoodSet(keep_fraction=0.5, max_neighborhoods=256, max_set_size=16384)

    An option group of :func:`~texsynth.interpolate_textures` and
    :func:`~texsynth.optimization.interpolate_neighborhoods`
    (``neighborhood_set=NeighborhoodSet(...)``); on the command line its
    fields are flags (``--keep-fraction``, ``--max-neighborhoods``,
    ``--max-set-size``).

    Parameters
    ----------
    keep_fraction : float
        Fraction of interpolated neighbourhoods kept at ``alpha = 0.5``, the
        best by similarity (0.5 in the paper). Towards the ends the fraction
        rises linearly to 1 (``1 - (1 - keep_fraction) 2 min(alpha, 1 -
        alpha)``): a blend ghosts in proportion to the smaller weight, and
        at alpha = 0 or 1 the set is then all neighbourhoods of one input.
    max_neighborhoods : int
        Cap on the neighbourhoods of each texture that get a correspondence
        (a regular stride, default 1024 per texture and stage). The search
        itself is over every neighbourhood of the other texture; the cap
        bounds the number of TPS-RPM problems (at most ``2
        n_correspondences max_neighborhoods`` per stage). Each kept pair is
        reused shifted by up to the stride with the same warp (see
        ``max_set_size``), so the cap costs variety of the warps, not
        coverage of positions.
    max_set_size : int
        Cap on the size of ``N'`` per stage (all alphas together): the
        number of shifted copies per kept pair is reduced to stay below it.
        Larger sets cost search time in every iteration.
    """

    keep_fraction: float = 0.5
    max_neighborhoods: int = 1024
    max_set_size: int = 16384


# --------------------------------------------------------------------------- feature maps
def edge_feature_map(image, *, sigma=2.0):
    """Automatic binary feature map: Canny edges of the luminance.

    Ruiters et al. (Section 4.1) tried the compass operator and several edge
    detectors and found them "not very satisfactory" for many images; their
    results use hand-made feature maps. This is the weaker of the two
    automatic maps: the default of :func:`~texsynth.interpolate_textures` is
    :func:`ridge_feature_map`, which marks a mortar joint or groove as one
    line where Canny marks its two borders (or misses it at low contrast).
    Pass your own maps for best results.

    Parameters
    ----------
    image : array_like
        Grey or colour image.
    sigma : float
        Gaussian smoothing of the Canny detector, in pixels.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)

    Examples
    --------
    >>> img = np.zeros((16, 16)); img[:, 8:] = 1.0
    >>> edge_feature_map(img).any(axis=0).nonzero()[0].tolist()
    [7, 8]
    """
    from skimage.feature import canny

    img, _ = with_channels(as_image(image, "image"))
    grey = img[..., :3].mean(axis=-1) if img.shape[-1] >= 3 else img[..., 0]
    return canny(grey.astype(np.float64), sigma=check_positive_float(sigma, "sigma"))


def ridge_feature_map(image, *, sigmas=(1.0, 2.0), min_size=8):
    """Automatic binary feature map: centre lines of the image's ridges and valleys.

    The default of :func:`~texsynth.interpolate_textures`. Ruiters et al. (Section 4.1)
    draw feature maps by hand: the lines along which the texture's elements
    meet (mortar joints, cracks, grooves). Edge detectors mark the two
    borders of such a line, or only the strongest of them; this map marks the
    line itself: the Sato tubeness of the luminance for dark *and* light
    lines (the larger of the two responses, at the scales ``sigmas``),
    thresholded by Otsu's method, thinned to one-pixel lines, and stripped of
    pieces smaller than ``min_size`` pixels (speckle on stochastic textures).
    It finds the mortar grid of a brick wall whether the mortar is darker or
    lighter than the bricks, where Canny edges (:func:`edge_feature_map`)
    give doubled lines around light mortar and miss low-contrast dark joints.
    On stochastic textures (gravel, bumpy plaster) it marks a dense random
    network, as any automatic detector does; pass hand-made maps there.

    Parameters
    ----------
    image : array_like
        Grey or colour image.
    sigmas : sequence of float
        Scales of the ridge filter, in pixels (about half the line width).
    min_size : int
        Connected pieces with fewer pixels are dropped.

    Returns
    -------
    numpy.ndarray of bool, shape (H, W)

    Examples
    --------
    >>> img = np.ones((24, 24)); img[11, :] = 0.0  # a dark groove along row 11
    >>> f = ridge_feature_map(img)
    >>> rows = np.nonzero(f)[0]
    >>> bool(f.sum() >= 12 and np.all(np.abs(rows - 11) <= 1))
    True
    """
    from skimage.filters import sato, threshold_otsu
    from skimage.morphology import remove_small_objects, skeletonize

    img, _ = with_channels(as_image(image, "image"))
    grey = img[..., :3].mean(axis=-1) if img.shape[-1] >= 3 else img[..., 0]
    sig = [check_positive_float(v, "sigmas") for v in np.atleast_1d(sigmas)]
    grey = grey.astype(np.float64)
    tube = np.maximum(sato(grey, sigmas=sig, black_ridges=True, mode="wrap"),
                      sato(grey, sigmas=sig, black_ridges=False, mode="wrap"))
    if tube.max() <= 0:
        return np.zeros(grey.shape, bool)
    lines = skeletonize(tube > threshold_otsu(tube))
    return remove_small_objects(lines, max_size=check_positive_int(min_size, "min_size") - 1, connectivity=2)

def _feature_map(features, image, index):
    name = f"features[{index}]"
    if features is None:
        return ridge_feature_map(image)
    f = np.asarray(features)
    if f.ndim == 3 and f.shape[-1] == 1:
        f = f[..., 0]
    if f.shape != image.shape[:2]:
        raise ValueError(
            f"{name} has shape {f.shape} but its texture is {image.shape[:2]}; pass a binary map of the "
            f"texture's size (or features=None for the automatic ridge/valley maps of ridge_feature_map)"
        )
    if f.dtype != bool:
        f = as_image(f, name) > 0.5
    return f


def _distance_channel(feature, size):
    """Distance to the nearest feature pixel (Lefebvre and Hoppe 2006), scaled to [0, 1] by s/2."""
    if not feature.any():
        return np.ones(feature.shape)
    d = ndimage.distance_transform_edt(~feature)
    return np.minimum(d / (size / 2.0), 1.0)


def downsample(image, r, reduce=np.mean):
    """Resolution 1/r of Pseudocode 1: the mean (features: any) of r x r blocks, a remainder cropped."""
    from skimage.measure import block_reduce

    if r == 1:
        return image
    h, w = image.shape[0] // r * r, image.shape[1] // r * r
    return block_reduce(image[:h, :w], (r, r) + (1,) * (image.ndim - 2), reduce)


# --------------------------------------------------------------------------- Section 4.1, 4.2
@dataclass
class _Texture:
    """One input texture at one (r, s) stage: colour + distance channel, features, patch corners."""

    image: np.ndarray  # (H, W, C+1): colour then distance channel
    feature: np.ndarray  # (H, W) bool
    corners: np.ndarray  # (M, 2) top-left corners of the capped neighbourhood set
    mean: np.ndarray
    std: np.ndarray
    stride: int = 1  # spacing of the capped corners


def _prepare_texture(colour, feature, size, max_neighborhoods):
    # the distance channel is scaled to the colours' mean deviation, so that W_C = 1
    # weighs features like one colour channel (unscaled, its range [0, 1] dwarfs the
    # colour variation and the search matches mortar lines while ignoring colour)
    dist = _distance_channel(feature, size)
    dist = dist / max(dist.std(), 1e-6) * colour.reshape(-1, colour.shape[-1]).std(0).mean()
    img = np.concatenate([colour, dist[..., None]], axis=-1)
    ny, nx = colour.shape[0] - size + 1, colour.shape[1] - size + 1
    stride = max(1, int(np.ceil(np.sqrt(ny * nx / max_neighborhoods))))
    rr, cc = np.meshgrid(np.arange(0, ny, stride), np.arange(0, nx, stride), indexing="ij")
    corners = np.stack([rr.ravel(), cc.ravel()], 1)
    mean = colour.reshape(-1, colour.shape[-1]).mean(0)
    std = colour.reshape(-1, colour.shape[-1]).std(0) + 1e-6
    return _Texture(img, feature, corners, mean, std, stride)


def _correspondences(t1, t2, size, p, rng):
    """Pairs (corner in I1, corner in I2): the ``n_correspondences`` nearest in both directions (Section 4.1)."""
    channel_weights, k = p.channel_weights, p.n_correspondences
    pairs = []
    for src, dst, flip in ((t1, t2, False), (t2, t1, True)):
        if p.candidates == "k-coherent":
            other = _coherent_matches(src, dst, size, channel_weights, k, p.coherence_set, rng)
            mine = np.repeat(src.corners, k, axis=0)
            pairs.append(np.concatenate([other, mine], 1) if flip else np.concatenate([mine, other], 1))
            continue
        view = all_patches(dst.image, size)  # every neighbourhood of the other texture
        vecs = view.reshape(-1, size * size * view.shape[-1]).astype(np.float32)
        weights = np.tile(channel_weights, size * size)
        # with at most max_neighborhoods queries, exact search is the cheaper one up to 20000
        # neighbourhoods (profile "correspondence"); the paper's PCA + kd-tree above
        index = PatchIndex(vecs, weights=weights, method=p.method, profile="correspondence", rng=rng)
        q = all_patches(src.image, size)[src.corners[:, 0], src.corners[:, 1]]
        idx, _ = index.query(q.reshape(len(q), -1).astype(np.float32), k=k)
        other = np.stack(np.unravel_index(idx.ravel(), view.shape[:2]), 1)
        mine = np.repeat(src.corners, k, axis=0)
        pairs.append(np.concatenate([other, mine], 1) if flip else np.concatenate([mine, other], 1))
    pairs = np.unique(np.concatenate(pairs), axis=0)
    return pairs[:, :2], pairs[:, 2:]


def _coherent_matches(src, dst, size, channel_weights, k, set_size, rng):
    """The k nearest neighbourhoods of ``dst`` (top-left corners, ``(M k, 2)``) for the capped corners of
    ``src``, by k-coherent search: the queries lie on a grid, so a neighbour's match shifted by the offset
    to it is a candidate, offered with its k-coherence set of ``set_size`` (Tong et al. 2002), in
    PatchMatch's scan order; one PatchMatch iteration from random matches gives the search something to
    continue."""
    scale = np.sqrt(channel_weights)  # W_C as a scaling of the channels: the same weighted distance
    a, b = src.image * scale, dst.image * scale
    centres = src.corners + size // 2
    common = dict(centers=centres, exemplar_mask=None, pixel_weights=None, mode="valid", penalty=None, rng=rng,
                  k=k)
    field, _, _ = patchmatch_features(a, b, size, init=None, iterations=1, **common)
    sets = coherence_sets(b, size, set_size, rng=rng)
    field, _, _ = patchmatch_features(a, b, size, init=field, iterations=_CORRESPONDENCE_ITERATIONS, sets=sets,
                                      **common)
    return field.reshape(-1, 2) - size // 2


def _feature_points(feature, corners, size, max_points, rng):
    """Coordinates of the feature pixels of each patch, subsampled to ``max_points``: (B, m, 2), mask."""
    patches = all_patches(feature[..., None], size)[corners[:, 0], corners[:, 1], ..., 0]
    flat = patches.reshape(len(corners), -1)
    keys = rng.random(flat.shape)
    keys[~flat] = np.inf
    m = int(min(max_points, max(flat.sum(1).max(initial=0), 1)))
    order = np.argsort(keys, axis=1, kind="stable")[:, :m]
    valid = np.take_along_axis(flat, order, axis=1)
    points = np.stack([order // size, order % size], -1).astype(np.float64)
    return points, valid


def _warps(t1, t2, c1, c2, size, max_points, rng, rpm_options, margin=0):
    """theta_12 and theta_21 per pair by TPS-RPM, evaluated on the patch grid grown by ``margin``.

    Returns ``(fwd, bwd, grid, ok)`` with ``(B, s + 2 margin, s + 2 margin, 2)`` warps of
    patch-local coordinates; pairs with < 3 feature points keep the identity.
    """
    p1, v1 = _feature_points(t1.feature, c1, size, max_points, rng)
    p2, v2 = _feature_points(t2.feature, c2, size, max_points, rng)
    ok = (v1.sum(1) >= 3) & (v2.sum(1) >= 3)
    n = size + 2 * margin
    ax = np.arange(n, dtype=float) - margin
    grid = np.stack(np.meshgrid(ax, ax, indexing="ij"), -1).reshape(-1, 2)
    fwd = np.broadcast_to(grid, (len(c1),) + grid.shape).copy()
    bwd = fwd.copy()
    if ok.any():
        # Ruiters et al. Section 4.2: theta_12 and theta_21 from the same correspondences
        res = tps_rpm(p1[ok], p2[ok], x_weights=v1[ok], y_weights=v2[ok], **rpm_options)
        fwd[ok] = res.forward(np.broadcast_to(grid, (ok.sum(),) + grid.shape))
        bwd[ok] = res.backward(np.broadcast_to(grid, (ok.sum(),) + grid.shape))
    shape = (len(c1), n, n, 2)
    return fwd.reshape(shape), bwd.reshape(shape), grid.reshape(n, n, 2), ok


def _sample(image, corners, coords):
    """Cubic samples of ``image`` at patch-local ``coords`` (B, P, 2) offset by ``corners``.

    Cubic rather than bilinear: a warp moves most pixels by a fraction of a
    pixel, and bilinear sampling there is a small blur (the warped patches'
    sharpness at alpha = 0.5 rose from 0.070 to 0.086, see
    :func:`~texsynth.interpolate_textures`). The overshoot of the cubic spline is
    clipped to each channel's range.
    """
    rows = coords[..., 0] + corners[:, None, 0]
    cols = coords[..., 1] + corners[:, None, 1]
    out = np.empty(coords.shape[:2] + (image.shape[-1],))
    for ch in range(image.shape[-1]):
        out[..., ch] = ndimage.map_coordinates(image[..., ch], [rows, cols], order=3, mode="mirror")
    return np.clip(out, image.min(axis=(0, 1)), image.max(axis=(0, 1)))


def _blend_pairs(t1, t2, c1, c2, fwd, bwd, grid, alpha, feature_weight):
    """N'(x) = (1 - a) N1(theta'_21(x)) + a N2(theta'_12(x)) and its dissimilarity.

    ``fwd``, ``bwd`` and ``grid`` are ``(B, P, 2)`` patch-local coordinates.
    """
    th21 = alpha * bwd + (1.0 - alpha) * grid  # theta'_21 = a theta_21 + (1 - a) I
    th12 = (1.0 - alpha) * fwd + alpha * grid  # theta'_12 = (1 - a) theta_12 + a I
    n1 = _sample(t1.image, c1, th21)
    n2 = _sample(t2.image, c2, th12)
    # colour adjustment: means and deviations interpolated by alpha (Section 4.2)
    mean = (1 - alpha) * t1.mean + alpha * t2.mean
    std = (1 - alpha) * t1.std + alpha * t2.std
    n1[..., :-1] = (n1[..., :-1] - t1.mean) / t1.std * std + mean
    n2[..., :-1] = (n2[..., :-1] - t2.mean) / t2.std * std + mean
    blended = (1.0 - alpha) * n1 + alpha * n2
    # contrast-preserving blend: the average of two partly uncorrelated patches has less contrast
    # than either; restore the patch's deviation from its mean to the interpolated deviation of the
    # two warped patches (at most by 1 / sqrt((1 - a)^2 + a^2), the gain for uncorrelated patches)
    colour = blended[..., :-1]
    centre = colour.mean(1, keepdims=True)
    target = (1.0 - alpha) * _deviation(n1[..., :-1]) + alpha * _deviation(n2[..., :-1])
    gain = np.clip(target / np.maximum(_deviation(colour), 1e-12), 1.0, 1.0 / np.hypot(1.0 - alpha, alpha))
    blended[..., :-1] = centre + gain[:, None, None] * (colour - centre)
    # similarity: warped distance channels and normalized cross-correlation of the colours
    dist = np.sqrt(np.mean((n1[..., -1] - n2[..., -1]) ** 2, axis=1)) / max(float(t1.image[..., -1].std()), 1e-6)
    a = n1[..., :-1].reshape(len(n1), -1)
    b = n2[..., :-1].reshape(len(n2), -1)
    a = a - a.mean(1, keepdims=True)
    b = b - b.mean(1, keepdims=True)
    ncc = (a * b).sum(1) / np.maximum(np.sqrt((a * a).sum(1) * (b * b).sum(1)), 1e-12)
    dissimilarity = feature_weight * dist + (1.0 - feature_weight) * (1.0 - ncc) / 2.0
    return np.clip(blended, 0.0, None), dissimilarity


def _deviation(colour):
    """Root of the summed squared deviation of each patch ``(B, P, C)`` from its mean colour: (B,)."""
    return np.sqrt(((colour - colour.mean(1, keepdims=True)) ** 2).sum((1, 2)))


def _shifts(t1, t2, pairs, n_alphas, max_set_size):
    """Offsets (dr, dc) of the shifted copies of each kept pair (see :func:`interpolated_set`)."""
    stride = max(t1.stride, t2.stride)
    per_axis = int(np.clip(np.floor(np.sqrt(max_set_size / max(pairs * n_alphas, 1))), 1, stride))
    d = np.arange(per_axis) * stride // per_axis - stride // 2 if per_axis > 1 else np.zeros(1, int)
    dr, dc = np.meshgrid(d, d, indexing="ij")
    return np.stack([dr.ravel(), dc.ravel()], 1), stride // 2 + 1


def interpolated_set(t1, t2, size, alphas, params, rng, info=None):
    """InterpolateNeighborhoods of Pseudocode 1 for every alpha in ``alphas``: (M, s, s, C+1[+1]).

    The pairs come from capped corners (``max_neighborhoods``, a stride), so on their
    own they cover only one neighbourhood position in ``stride**2``: texture
    optimization from such a set cannot place an element at most offsets and
    breaks it up. Each kept pair is therefore also used shifted by up to the
    stride, ``(c1 + d, c2 + d)`` with the *same* warp evaluated at ``x + d``
    (the spatially coherent assignment the paper mentions in Section 4.4); at
    alpha = 0 this gives exactly the neighbourhoods of I1 around the kept pairs.
    ``max_set_size`` caps the result. ``params`` are :func:`check_inputs`'s; ``info`` (an
    :class:`~texsynth.optimization.InterpolationInfo`, optional) receives the timings and the number of pairs.
    """
    t0 = time.perf_counter()
    c1, c2 = _correspondences(t1, t2, size, params, rng)
    _add(info, "correspondences", t0)
    t0 = time.perf_counter()
    margin = max(t1.stride, t2.stride) // 2 + 1
    if params.colour_only:
        n = size + 2 * margin
        ax = np.arange(n, dtype=float) - margin
        grid = np.stack(np.meshgrid(ax, ax, indexing="ij"), -1)
        fwd = bwd = np.broadcast_to(grid, (len(c1),) + grid.shape)
    else:
        fwd, bwd, grid, _ = _warps(t1, t2, c1, c2, size, params.max_feature_points, rng, params.rpm, margin)
    _add(info, "tps_rpm", t0)
    t0 = time.perf_counter()
    win = (slice(None), slice(margin, margin + size), slice(margin, margin + size))
    flat = lambda w: w.reshape(w.shape[0], -1, 2)  # noqa: E731
    g = np.broadcast_to(grid, fwd.shape)
    ny1, nx1 = t1.image.shape[0] - size, t1.image.shape[1] - size
    ny2, nx2 = t2.image.shape[0] - size, t2.image.shape[1] - size
    out = []
    for alpha in alphas:
        blend, dis = _blend_pairs(t1, t2, c1, c2, flat(fwd[win]), flat(bwd[win]), flat(g[win]), alpha,
                                  params.feature_weight)
        # keep the best fraction (the paper's 50 %) at alpha = 0.5; the filter removes pairs whose
        # blend would ghost, and a blend ghosts in proportion to min(alpha, 1 - alpha): at the
        # ends N' is the whole neighbourhood set of I1 (resp. I2), as in texture optimization
        fraction = 1.0 - (1.0 - params.keep_fraction) * 2.0 * min(alpha, 1.0 - alpha)
        keep = np.flatnonzero(dis <= np.quantile(dis, fraction))
        offsets, _ = _shifts(t1, t2, len(keep), len(alphas), params.max_set_size)
        patches = []
        for dr, dc in offsets:
            k1, k2 = c1[keep] + [dr, dc], c2[keep] + [dr, dc]
            # a shifted copy must stay inside the texture(s) it takes pixels from (weight > 0);
            # warped samples that leave a texture are mirrored (map_coordinates)
            inside = np.ones(len(keep), bool)
            if alpha < 1.0:
                inside &= (k1 >= 0).all(1) & (k1[:, 0] <= ny1) & (k1[:, 1] <= nx1)
            if alpha > 0.0:
                inside &= (k2 >= 0).all(1) & (k2[:, 0] <= ny2) & (k2[:, 1] <= nx2)
            sel = keep[inside]
            if dr == 0 and dc == 0:  # the unshifted copy is the blend just computed
                patches.append(blend[sel])
                continue
            w = (sel, slice(margin + dr, margin + dr + size), slice(margin + dc, margin + dc + size))
            # sampled at the original corners: N1(c1 + theta'_21(x + d)), N2(c2 + theta'_12(x + d))
            p, _ = _blend_pairs(t1, t2, c1[sel], c2[sel], flat(fwd[w]), flat(bwd[w]), flat(g[w]), alpha,
                                params.feature_weight)
            patches.append(p)
        patches = np.concatenate(patches).reshape(-1, size, size, t1.image.shape[-1]).astype(np.float32)
        if len(alphas) > 1:
            patches = np.concatenate([patches, np.full(patches.shape[:-1] + (1,), alpha, np.float32)], -1)
        out.append(patches)
    if info is not None:
        info.pairs.append(len(c1))
    _add(info, "warping", t0)
    return np.concatenate(out)


def _add(info, key, t0):
    if info is not None:
        info.add(key, t0)

def stage_textures(p, r, size):
    """The two textures of one (r, s) stage (:class:`_Texture`): downsampled by ``r``, with distance channels."""
    out = []
    for img, feat in ((p.a, p.fa), (p.b, p.fb)):
        colour = downsample(img, r)
        if min(colour.shape[:2]) < size:
            raise ValueError(
                f"texture of shape {img.shape[:2]} downsampled by {r} is smaller than the neighbourhood size "
                f"{size}; pass larger textures or smaller stages=((r, s), ...)"
            )
        out.append(_prepare_texture(colour, downsample(feat, r, np.any), size, p.max_neighborhoods))
    return out


@dataclass(frozen=True)
class Inputs:
    """The checked inputs of an interpolation: the two textures, their feature maps, the settings of N'."""

    a: np.ndarray  # (H, W, C) I1
    b: np.ndarray  # I2
    grey: bool
    fa: np.ndarray  # feature maps F1, F2 (bool)
    fb: np.ndarray
    colour_only: bool  # a feature map is empty: identity warps
    channel_weights: np.ndarray  # W_C of the colour channels and the distance channel
    n_correspondences: int
    keep_fraction: float
    feature_weight: float
    max_feature_points: int
    max_neighborhoods: int
    max_set_size: int
    rpm: dict  # options of tps_rpm
    method: str  # search backend
    candidates: str  # "k-coherent": correspondences by k-coherent search
    coherence_set: int  # the size of their k-coherence sets


def check_inputs(a, b, features, correspondences, neighborhood_set, search):
    """The checked inputs of an interpolation (:class:`Inputs`): textures, feature maps, the settings of ``N'``."""
    corr = check_group(correspondences, Correspondences, "correspondences")
    nset = check_group(neighborhood_set, NeighborhoodSet, "neighborhood_set")
    search = check_group(search, Search, "search")
    refuse_augment(search.augment, "interpolate_textures", "its correspondences pair the neighbourhoods of a and b "
                   "as they are")
    a, grey_a = with_channels(as_image(a, "a", min_size=8))
    b, grey_b = with_channels(as_image(b, "b", min_size=8))
    if a.shape[-1] != b.shape[-1]:
        raise ValueError(f"a has {a.shape[-1]} channels and b has {b.shape[-1]}; pass two grey or two colour textures")
    if features is None:
        features = (None, None)
    elif isinstance(features, (str, bytes, np.ndarray)) or not hasattr(features, "__len__"):
        raise TypeError(f"features must be a pair (F1, F2) of binary maps or None, got {type(features).__name__}")
    elif len(features) != 2:
        raise ValueError(f"features must be a pair (F1, F2) of binary maps or None, got {len(features)} items")
    fa, fb = _feature_map(features[0], a, 0), _feature_map(features[1], b, 1)
    colour_only = not fa.any() or not fb.any()
    if colour_only:
        warnings.warn(
            "a feature map is empty: no feature points to align, falling back to colour-only correspondences "
            "(identity warps, i.e. blending of the most similar patches)",
            RuntimeWarning,
            stacklevel=3,
        )
    # (a weight of 1e6 already makes the distance channel all that counts; far beyond, float32 overflows)
    dw = check_positive_float(corr.distance_weight, "distance_weight", allow_zero=True, maximum=1e6)
    c = a.shape[-1]
    return Inputs(
        a=a, b=b, grey=grey_a and grey_b, fa=fa, fb=fb, colour_only=colour_only,
        channel_weights=np.array([1.0] * c + [0.0 if colour_only else dw], dtype=np.float64),
        n_correspondences=check_positive_int(corr.n_correspondences, "n_correspondences"),
        keep_fraction=check_in_range(nset.keep_fraction, "keep_fraction", 0.0, 1.0, low_open=True),
        feature_weight=check_in_range(corr.feature_weight, "feature_weight", 0.0, 1.0),
        max_feature_points=check_positive_int(corr.max_feature_points, "max_feature_points", 3),
        max_neighborhoods=check_positive_int(nset.max_neighborhoods, "max_neighborhoods"),
        max_set_size=check_positive_int(nset.max_set_size, "max_set_size"),
        rpm=_check_rpm_options(corr.rpm_options),
        method=check_method(search.method),
        candidates=check_candidates(search.resolved_candidates("all")),  # "auto": the paper's, every neighbourhood
        coherence_set=search.resolved_k(_CORRESPONDENCE_SET),
    )


def _check_rpm_options(rpm_options):
    """The TPS-RPM options: this module's defaults updated by the user's dict (names of :func:`tps_rpm`)."""
    if rpm_options is None:
        return dict(_RPM_DEFAULTS)
    if not isinstance(rpm_options, dict):
        raise TypeError(f"rpm_options must be a dict of tps_rpm options or None, got {type(rpm_options).__name__}")
    known = set(inspect.signature(tps_rpm).parameters) - {"X", "Y"}
    unknown = sorted(set(rpm_options) - known)
    if unknown:
        raise TypeError(f"rpm_options has unknown options {unknown}; tps_rpm takes {sorted(known)}")
    return dict(_RPM_DEFAULTS, **rpm_options)


# Faster-than-paper annealing for thousands of small point sets, and a stiffer affine part (the
# feature points of a patch lie along a few lines, which leave the affine part free across them);
# see Notes of texsynth.interpolate_textures.
_RPM_DEFAULTS = dict(anneal_rate=0.8, iterations_per_temperature=3, sinkhorn_iterations=10,
                     affine_lambda_init=10.0)


# --------------------------------------------------------------------------- public
def interpolate_neighborhoods(a, b, alpha, neighborhood_size, *, features=None, resolution=1,
                              correspondences=Correspondences(), neighborhood_set=NeighborhoodSet(),
                              search=Search(), rng=None):
    """The interpolated neighbourhood set ``N'`` for one (r, s) (Sections 4.1-4.2).

    ``neighborhood_size`` is ``s`` and ``resolution`` is ``r`` of a stage;
    ``alpha`` is a number. ``features`` and the option groups
    ``correspondences`` (:class:`Correspondences`), ``neighborhood_set``
    (:class:`NeighborhoodSet`) and ``search``
    (:class:`~texsynth.core.search.Search`) are those of
    :func:`~texsynth.interpolate_textures`. Returns ``(M, s, s, C + 1)``
    float32 patches: the colour channels then the interpolated distance
    channel.

    Examples
    --------
    >>> x = np.indices((24, 24)).sum(0) % 6 / 5.0
    >>> n = interpolate_neighborhoods(x, x.T, 0.5, 7, neighborhood_set=NeighborhoodSet(keep_fraction=0.8), rng=0)
    >>> n.shape[1:], n.dtype.name
    ((7, 7, 2), 'float32')
    """
    p = check_inputs(a, b, features, correspondences, neighborhood_set, search)
    alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
    rng = as_rng(rng)
    t1, t2 = stage_textures(p, resolution, neighborhood_size)
    return interpolated_set(t1, t2, neighborhood_size, [alpha], p, rng)
