"""Patch-based texture interpolation (Ruiters, Schnabel and Klein 2010).

Interpolating two textures by blending the images ghosts every feature
(Figure 1a of the paper). Ruiters et al. instead interpolate the *MRF* of
the textures: for every neighbourhood of each texture they find the most
similar neighbourhood of the other one (Section 4.1), align the two patches'
features with a thin-plate-spline warp found by TPS-RPM point matching,
warp each patch part of the way and blend them (Section 4.2), keep the
best-aligned half of these interpolated neighbourhoods, and synthesise a new
texture from that set by texture optimization with irregular patch centres,
a relaxation of the pasted patches, a per-pixel mean-shift mode instead of
the mean, and one Portilla-Simoncelli step per iteration (Sections 4.3-4.5,
Pseudocode 1)::

    TextureInterpolation(I1, I2, F1, F2, alpha)
      add distance channel to I1 and I2
      initialise I with noise
      for each (r, s) in (2, 33), (2, 17), (1, 17):
        N' = InterpolateNeighborhoods(I1, I2, F1, F2, alpha, r, s)
        repeat N times:
          nearest neighbours in N' for irregular centres of I
          relax the neighbourhood centres
          update the pixels of I by mean shift
          one statistical synthesis step

A spatially varying interpolation (a transition strip, or any grey image of
alpha values) uses interpolated neighbourhoods for several alphas with alpha
as an extra channel that the synthesis matches to the user's map
(Section 4.5, Figures 4 and 7).

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
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import (as_array, as_float_array, as_image, as_rng, as_size, check_bool, check_in_range,
                              check_memory, check_positive_float, check_positive_int, restore_channels,
                              with_channels)
from ..core import search
from ..core.search import PatchIndex, check_candidates, coherence_sets, patchmatch_features, point_tree
from ..core.neighborhood import accumulate, all_patches, extract, gaussian_falloff, grid_centers
from ..core.em import expectation_maximization
from ..statistical import interpolate_statistics, ps_statistics, ps_step
from ..core.tps import tps_rpm

__all__ = [
    "interpolate_textures",
    "interpolate_neighborhoods",
    "edge_feature_map",
    "ridge_feature_map",
    "transition_alpha_map",
    "linear_blend",
    "InterpolationInfo",
]

_EPS = 1e-3  # ε² of the IRLS weights (texsynth.core.em.irls_weights): finite for perfect matches
# candidates="k-coherent": the size of the k-coherence sets of the correspondences, and the iterations over
# them after one PatchMatch iteration from random matches
_CORRESPONDENCE_SET = 4
_CORRESPONDENCE_ITERATIONS = 3


@dataclass
class InterpolationInfo:
    """Extra results of :func:`interpolate_textures`.

    Attributes
    ----------
    energy : numpy.ndarray
        Mean distance of the pasted neighbourhoods to the synthesized image:
        per (r, s) stage, after the stage's first search, then after each
        iteration; all stages in order.
    stage : numpy.ndarray of int
        The stage (index into ``stages``) of each energy value.
    pairs : list of int
        Corresponding neighbourhood pairs per (r, s) stage.
    kept : list of int
        Interpolated neighbourhoods kept in ``N'`` per stage (all alphas).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time per step of the method: ``"correspondences"``,
        ``"tps_rpm"``, ``"warping"`` (warp, blend, similarity filter),
        ``"synthesis"`` (searches, relaxation, mean shift) and
        ``"statistics"`` (Portilla-Simoncelli).
    colour_only : bool
        True when the feature maps were empty and the warps fell back to
        the identity.
    """

    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stage: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    pairs: list = field(default_factory=list)
    kept: list = field(default_factory=list)
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    colour_only: bool = False

    def add(self, key, t0):
        self.stage_seconds[key] = self.stage_seconds.get(key, 0.0) + time.perf_counter() - t0


# --------------------------------------------------------------------------- inputs
def edge_feature_map(image, *, sigma=2.0):
    """Automatic binary feature map: Canny edges of the luminance.

    Ruiters et al. (Section 4.1) tried the compass operator and several edge
    detectors and found them "not very satisfactory" for many images; their
    results use hand-made feature maps. This is the weaker of the two
    automatic maps: the default of :func:`interpolate_textures` is
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

    The default of :func:`interpolate_textures`. Ruiters et al. (Section 4.1)
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


def transition_alpha_map(size, *, start=0.0, stop=1.0):
    """A left-to-right ramp of alpha values for a transition strip (Figure 4).

    >>> transition_alpha_map((2, 5))[0].tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    h, w = as_size(size, "size")
    start = check_in_range(start, "start", 0.0, 1.0)
    stop = check_in_range(stop, "stop", 0.0, 1.0)
    check_memory(float(h) * w * 8, (h, w), what="the map")
    return np.broadcast_to(np.linspace(start, stop, w), (h, w)).copy()


def linear_blend(a, b, alpha):
    """Plain cross-fade ``(1 - alpha) a + alpha b`` (Figure 1a: ghosted features).

    ``alpha`` is a number in [0, 1] or an ``(H, W)`` map of them.

    >>> linear_blend(np.zeros((2, 2)), np.ones((2, 2)), 0.25).tolist()
    [[0.25, 0.25], [0.25, 0.25]]
    """
    a = as_image(a, "a")
    b = as_image(b, "b")
    if a.shape != b.shape:
        raise ValueError(f"a {a.shape} and b {b.shape} must have the same shape for a linear blend")
    if np.ndim(alpha) == 0:
        alpha = np.float64(check_in_range(alpha, "alpha", 0.0, 1.0))
    else:
        alpha = as_float_array(as_array(alpha, "alpha"), "alpha")  # a map: finite values in [0, 1]
        if alpha.shape != a.shape[:2]:
            raise ValueError(f"alpha map has shape {alpha.shape} but the images are {a.shape[:2]}; pass an "
                             f"(H, W) map of the images' size or one number")
        if a.ndim == 3:
            alpha = alpha[..., None]
    return (1.0 - alpha) * a + alpha * b


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


def _downsample(image, r, reduce=np.mean):
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


def _correspondences(t1, t2, size, channel_weights, k, rng, method="auto", candidates="all"):
    """Pairs (corner in I1, corner in I2): k nearest in both directions (Section 4.1)."""
    pairs = []
    for src, dst, flip in ((t1, t2, False), (t2, t1, True)):
        if candidates == "k-coherent":
            other = _coherent_matches(src, dst, size, channel_weights, k, rng)
            mine = np.repeat(src.corners, k, axis=0)
            pairs.append(np.concatenate([other, mine], 1) if flip else np.concatenate([mine, other], 1))
            continue
        view = all_patches(dst.image, size)  # every neighbourhood of the other texture
        vecs = view.reshape(-1, size * size * view.shape[-1]).astype(np.float32)
        weights = np.tile(channel_weights, size * size)
        # with at most max_neighborhoods queries, exact search is the cheaper one up to 20000
        # neighbourhoods (profile "correspondence"); the paper's PCA + kd-tree above
        index = PatchIndex(vecs, weights=weights, method=method, profile="correspondence", rng=rng)
        q = all_patches(src.image, size)[src.corners[:, 0], src.corners[:, 1]]
        idx, _ = index.query(q.reshape(len(q), -1).astype(np.float32), k=k)
        other = np.stack(np.unravel_index(idx.ravel(), view.shape[:2]), 1)
        mine = np.repeat(src.corners, k, axis=0)
        pairs.append(np.concatenate([other, mine], 1) if flip else np.concatenate([mine, other], 1))
    pairs = np.unique(np.concatenate(pairs), axis=0)
    return pairs[:, :2], pairs[:, 2:]


def _coherent_matches(src, dst, size, channel_weights, k, rng):
    """The k nearest neighbourhoods of ``dst`` (top-left corners, ``(M k, 2)``) for the capped corners of
    ``src``, by k-coherent search: the queries lie on a grid, so a neighbour's match shifted by the offset
    to it is a candidate, offered with its k-coherence set (Tong et al. 2002), in PatchMatch's scan order;
    one PatchMatch iteration from random matches gives the search something to continue."""
    scale = np.sqrt(channel_weights)  # W_C as a scaling of the channels: the same weighted distance
    a, b = src.image * scale, dst.image * scale
    centres = src.corners + size // 2
    common = dict(centers=centres, exemplar_mask=None, pixel_weights=None, mode="valid", penalty=None, rng=rng,
                  k=k)
    field, _ = patchmatch_features(a, b, size, init=None, iterations=1, **common)
    sets = coherence_sets(b, size, _CORRESPONDENCE_SET, rng=rng)
    field, _ = patchmatch_features(a, b, size, init=field, iterations=_CORRESPONDENCE_ITERATIONS, sets=sets,
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
    :func:`interpolate_textures`). The overshoot of the cubic spline is
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
    """Offsets (dr, dc) of the shifted copies of each kept pair (see :func:`_interpolated_set`)."""
    stride = max(t1.stride, t2.stride)
    per_axis = int(np.clip(np.floor(np.sqrt(max_set_size / max(pairs * n_alphas, 1))), 1, stride))
    d = np.arange(per_axis) * stride // per_axis - stride // 2 if per_axis > 1 else np.zeros(1, int)
    dr, dc = np.meshgrid(d, d, indexing="ij")
    return np.stack([dr.ravel(), dc.ravel()], 1), stride // 2 + 1


def _interpolated_set(t1, t2, size, alphas, params, rng, info):
    """InterpolateNeighborhoods of Pseudocode 1 for every alpha in ``alphas``: (M, s, s, C+1[+1]).

    The pairs come from capped corners (``max_neighborhoods``, a stride), so on their
    own they cover only one neighbourhood position in ``stride**2``: texture
    optimization from such a set cannot place an element at most offsets and
    breaks it up. Each kept pair is therefore also used shifted by up to the
    stride, ``(c1 + d, c2 + d)`` with the *same* warp evaluated at ``x + d``
    (the spatially coherent assignment the paper mentions in Section 4.4); at
    alpha = 0 this gives exactly the neighbourhoods of I1 around the kept pairs.
    ``max_set_size`` caps the result.
    """
    t0 = time.perf_counter()
    c1, c2 = _correspondences(t1, t2, size, params.channel_weights, params.k, rng, params.method, params.candidates)
    info.add("correspondences", t0)
    t0 = time.perf_counter()
    margin = max(t1.stride, t2.stride) // 2 + 1
    if params.colour_only:
        n = size + 2 * margin
        ax = np.arange(n, dtype=float) - margin
        grid = np.stack(np.meshgrid(ax, ax, indexing="ij"), -1)
        fwd = bwd = np.broadcast_to(grid, (len(c1),) + grid.shape)
    else:
        fwd, bwd, grid, _ = _warps(t1, t2, c1, c2, size, params.max_feature_points, rng, params.rpm, margin)
    info.add("tps_rpm", t0)
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
    info.pairs.append(len(c1))
    info.add("warping", t0)
    return np.concatenate(out)


def interpolate_neighborhoods(a, b, alpha, neighborhood_size, *, features=None, resolution=1, distance_weight=1.0,
                              k=1,
                              keep_fraction=0.5, feature_weight=0.5, max_feature_points=24,
                              max_neighborhoods=1024, max_set_size=16384, rpm_options=None, method="auto",
                              candidates="all", rng=None):
    """The interpolated neighbourhood set ``N'`` for one (r, s) (Sections 4.1-4.2).

    ``neighborhood_size`` is ``s`` and ``resolution`` is ``r`` of a stage;
    ``alpha`` is a number; the other parameters are those of
    :func:`interpolate_textures`. Returns ``(M, s, s, C + 1)`` float32
    patches: the colour channels then the interpolated distance channel.

    Examples
    --------
    >>> x = np.indices((24, 24)).sum(0) % 6 / 5.0
    >>> n = interpolate_neighborhoods(x, x.T, 0.5, 7, rng=0)
    >>> n.shape[1:], n.dtype.name
    ((7, 7, 2), 'float32')
    """
    p = _check_inputs(a, b, features=features, distance_weight=distance_weight, k=k, keep_fraction=keep_fraction,
                      feature_weight=feature_weight, max_feature_points=max_feature_points,
                      max_neighborhoods=max_neighborhoods, max_set_size=max_set_size, rpm_options=rpm_options,
                      method=method, candidates=candidates)
    alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
    rng = as_rng(rng)
    t1, t2 = _stage_textures(p, resolution, neighborhood_size)
    return _interpolated_set(t1, t2, neighborhood_size, [alpha], p, rng, InterpolationInfo())


def _stage_textures(p, r, size):
    out = []
    for img, feat in ((p.a, p.fa), (p.b, p.fb)):
        colour = _downsample(img, r)
        if min(colour.shape[:2]) < size:
            raise ValueError(
                f"texture of shape {img.shape[:2]} downsampled by {r} is smaller than the neighbourhood size "
                f"{size}; pass larger textures or smaller stages=((r, s), ...)"
            )
        out.append(_prepare_texture(colour, _downsample(feat, r, np.any), size, p.max_neighborhoods))
    return out


@dataclass(frozen=True)
class _Inputs:
    """The checked inputs of an interpolation: the two textures, their feature maps, the settings of N'."""

    a: np.ndarray  # (H, W, C) I1
    b: np.ndarray  # I2
    grey: bool
    fa: np.ndarray  # feature maps F1, F2 (bool)
    fb: np.ndarray
    colour_only: bool  # a feature map is empty: identity warps
    channel_weights: np.ndarray  # W_C of the colour channels and the distance channel
    k: int
    keep_fraction: float
    feature_weight: float
    max_feature_points: int
    max_neighborhoods: int
    max_set_size: int
    rpm: dict  # options of tps_rpm
    method: str  # search backend
    candidates: str = "all"  # "k-coherent": correspondences by k-coherent search


def _check_inputs(a, b, *, features, distance_weight, k, keep_fraction, feature_weight, max_feature_points,
                  max_neighborhoods, max_set_size, rpm_options, method, candidates="all"):
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
    dw = check_positive_float(distance_weight, "distance_weight", allow_zero=True, maximum=1e6)
    c = a.shape[-1]
    return _Inputs(
        a=a, b=b, grey=grey_a and grey_b, fa=fa, fb=fb, colour_only=colour_only,
        channel_weights=np.array([1.0] * c + [0.0 if colour_only else dw], dtype=np.float64),
        k=check_positive_int(k, "k"),
        keep_fraction=check_in_range(keep_fraction, "keep_fraction", 0.0, 1.0, low_open=True),
        feature_weight=check_in_range(feature_weight, "feature_weight", 0.0, 1.0),
        max_feature_points=check_positive_int(max_feature_points, "max_feature_points", 3),
        max_neighborhoods=check_positive_int(max_neighborhoods, "max_neighborhoods"),
        max_set_size=check_positive_int(max_set_size, "max_set_size"),
        rpm=_check_rpm_options(rpm_options),
        method=search.check_method(method),
        candidates=check_candidates(candidates),
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
# see Notes of interpolate_textures.
_RPM_DEFAULTS = dict(anneal_rate=0.8, iterations_per_temperature=3, sinkhorn_iterations=10,
                     affine_lambda_init=10.0)


# --------------------------------------------------------------------------- Sections 4.3-4.4
class _PatchSet:
    """The searchable set N' (flattened patches) with per-channel weights."""

    def __init__(self, patches, channel_weights, method, rng):
        self.patches = patches
        self.size = patches.shape[1]
        self.weights = np.tile(channel_weights, self.size * self.size)
        self.index = PatchIndex(patches.reshape(len(patches), -1), weights=self.weights, method=method, rng=rng)

    def query(self, x, centers):
        # float32 before the copy of the (many, overlapping) candidate neighbourhoods: half the bytes
        q = extract(x.astype(np.float32), centers, self.size, mode="wrap").reshape(len(centers), -1)
        idx, d2 = self.index.query(q, k=1)
        return idx[:, 0], d2[:, 0] / self.weights.sum()


def _bootstrap(patches, shape, spacing, rng):
    """Initial image: random neighbourhoods of ``N'`` on the regular grid, each pixel from its nearest centre.

    The paper initialises with noise; the nearest neighbourhoods of noise (or
    of an average of many random patches) are the flattest ones, and the
    synthesis collapses onto them (horizontal streaks, lost elements). A
    random tiling of ``N'`` (Kwatra et al.'s bootstrap, sharp fall-off
    ``sigma = spacing / 4``) is noise at the scale of the grid cells but keeps
    the patches' contrast.
    """
    centres = grid_centers(shape, patches.shape[1], spacing, mode="wrap")
    z = patches[rng.integers(0, len(patches), len(centres))].astype(np.float64)
    x, _ = accumulate(z, centres, shape, pixel_weights=gaussian_falloff(patches.shape[1], sigma=spacing / 4.0),
                      mode="wrap")
    return x


def _irregular_centres(x, nset, spacing, candidate_stride):
    """Within each cell of the regular grid, the centre whose best match has the lowest error (4.4)."""
    h, w = x.shape[:2]
    gy, gx = np.arange(0, h, spacing), np.arange(0, w, spacing)
    off = np.arange(0, spacing, candidate_stride)
    cell_r, cell_c, dr, dc = np.meshgrid(gy, gx, off, off, indexing="ij")
    cand = np.stack([(cell_r + dr) % h, (cell_c + dc) % w], -1).reshape(len(gy) * len(gx), -1, 2)
    idx, err = nset.query(x, cand.reshape(-1, 2))
    idx, err = idx.reshape(cand.shape[:2]), err.reshape(cand.shape[:2])
    best = np.argmin(err, axis=1)
    rows = np.arange(len(cand))
    return cand[rows, best], idx[rows, best], err[rows, best]


def _grid_neighbours(original, shape, count=8):
    """Indices of the ``count`` nearest other centres (periodic distance), shape (n, count)."""
    n = len(original)
    count = min(count, n - 1)
    if count < 1:
        return np.zeros((n, 0), int)
    pts = original.astype(np.float64)
    _, nb = point_tree(pts, period=shape).query(pts, k=count + 1)
    others = nb != np.arange(n)[:, None]
    others[others.sum(1) > count, -1] = False  # a duplicate position returned before the centre itself
    return nb[others].reshape(n, count)


def _relax(centres, z, weights, shape, radius, spring, max_sweeps):
    """Shift the pasted neighbourhoods to agree with their overlapping neighbours (Section 4.4).

    For every centre the shift within ``radius`` minimising the squared
    difference between its patch and the leave-one-out average of all other
    patches, plus ``spring * |displacement - mean displacement of its grid
    neighbours|^2`` (the spring term); repeated until no centre moves.

    Implementation: the weighted sums of all patches are read once per sweep
    in a window of ``s + 2 radius`` around each centre (every candidate shift
    is a slice of it), the centre's own contribution is subtracted in that
    frame, and the arithmetic is float32. After the first sweep only the
    centres whose window or grid neighbours saw a move are re-evaluated: the
    others' costs are unchanged, so they stay where they are (the result is
    that of re-evaluating every centre).
    """
    n, s, c = len(centres), z.shape[1], z.shape[-1]
    original = centres.copy()
    offsets = np.array([(dr, dc) for dr in range(-radius, radius + 1) for dc in range(-radius, radius + 1)])
    stay = len(offsets) // 2  # (0, 0)
    big = s + 2 * radius
    nbrs = _grid_neighbours(original, shape)
    z32 = z.astype(np.float32)
    w32 = weights.astype(np.float32)
    # the centre's own weighted patch and weight, zero-padded to the window frame
    own = np.zeros((n, big, big, c + 1), np.float32)
    own[:, radius : radius + s, radius : radius + s, :c] = z32 * w32[:, None, None, None]
    own[:, radius : radius + s, radius : radius + s, c] = w32[:, None, None]
    cost = np.zeros((n, len(offsets)))
    dirty = np.ones(n, bool)
    for _ in range(max_sweeps):
        total, wsum = accumulate(z, centres, shape, patch_weights=weights, mode="wrap")
        sums = np.concatenate([total * wsum[..., None], wsum[..., None]], -1).astype(np.float32)
        todo = np.flatnonzero(dirty)
        # wrap-pad first: the window may be larger than a small (coarse-level) image
        sums = np.pad(sums, ((big // 2, big - 1 - big // 2),) * 2 + ((0, 0),), mode="wrap")
        win = extract(sums, centres[todo] + big // 2, big, mode="valid")
        win -= own[todo]  # leave-one-out: everything but the centre's own patch
        zt = z32[todo]
        floor = 1e-4 * w32[todo, None, None, None]  # float32 rounding of the subtraction, far below any real overlap
        disp = centres - original
        mean_nbr = disp[nbrs].mean(1) if nbrs.shape[1] else np.zeros_like(disp)
        covered = bool(np.all(win[..., c:] > floor))  # the usual case: others overlap every pixel
        for j, (dr, dc) in enumerate(offsets):
            other = win[:, radius + dr : radius + dr + s, radius + dc : radius + dc + s]
            if covered:
                diff = other[..., :c] / other[..., c:] - zt
            else:  # a pixel only this patch covers does not count
                ok = other[..., c:] > floor
                diff = np.where(ok, other[..., :c] / np.where(ok, other[..., c:], 1.0), zt) - zt
            data = np.einsum("nijk,nijk->n", diff, diff) / z[0].size
            cost[todo, j] = data + spring * ((disp[todo] + (dr, dc) - mean_nbr[todo]) ** 2).sum(1)
        best = np.argmin(cost, axis=1)
        moved = cost[np.arange(n), best] < cost[:, stay] - 1e-12
        if not moved.any():
            break
        before = centres
        centres = (centres + offsets[best] * moved[:, None]) % np.array(shape)
        # re-evaluate the centres whose window reaches a moved patch (old or new place) or whose
        # grid neighbours moved (spring term)
        touched = np.zeros(shape, bool)
        touched[before[moved, 0], before[moved, 1]] = True
        touched[centres[moved, 0], centres[moved, 1]] = True
        touched = ndimage.maximum_filter(touched, size=2 * (s + radius) + 1, mode="wrap")
        dirty = touched[centres[:, 0], centres[:, 1]] | moved[nbrs].any(1)
    return centres


def _mean_shift_update(z, centres, weights, shape, bandwidth, iterations, n_colour, chunk=4096):
    """Per-pixel mode of the overlapping patch values (mean shift, Kopf et al. 2007).

    The values pasted on each pixel, weighted by the patch's IRLS weight and
    Kwatra et al.'s Gaussian fall-off, are gathered per pixel; the mean shift
    (Gaussian kernel of width ``bandwidth`` on the colour channels) starts at
    the value of highest kernel density among them and climbs to its mode.
    Started at the weighted mean instead, it climbed to the mode nearest the
    mean, which for two disagreeing groups of patches is the mean itself (a
    blur): see :func:`interpolate_textures`. ``iterations = 0`` returns the
    weighted mean (the Kwatra E-step). Pixels are processed ``chunk`` at a time.
    """
    g = gaussian_falloff(z.shape[1])  # Kwatra et al.'s Gaussian fall-off of each neighbourhood
    if iterations == 0:
        return accumulate(z, centres, shape, patch_weights=weights, pixel_weights=g, mode="wrap")[0]
    s, c = z.shape[1], z.shape[-1]
    h, w = shape
    rows = (centres[:, :1] - s // 2 + np.arange(s)) % h
    cols = (centres[:, 1:] - s // 2 + np.arange(s)) % w
    pixel = (rows[:, :, None] * w + cols[:, None, :]).ravel()
    order = np.argsort(pixel, kind="stable")
    pixel = pixel[order]
    count = np.bincount(pixel, minlength=h * w)
    slot = np.arange(len(pixel)) - (np.cumsum(count) - count)[pixel]
    values = np.zeros((h * w, count.max(), c), np.float32)  # the values pasted on each pixel, zero-padded
    wts = np.zeros((h * w, count.max()), np.float32)
    values[pixel, slot] = z.reshape(-1, c)[order]
    wts[pixel, slot] = (weights[:, None, None] * g).ravel()[order]
    scale = -0.5 / bandwidth**2
    x = np.zeros((h * w, c), np.float32)
    for lo in range(0, h * w, chunk):
        v, wt = values[lo : lo + chunk], wts[lo : lo + chunk]
        col = v[..., :n_colour]
        sq = (col**2).sum(-1)
        d2 = np.maximum(sq[:, :, None] + sq[:, None, :] - 2.0 * np.einsum("pkc,pjc->pkj", col, col), 0.0)
        density = np.einsum("pkj,pj->pk", np.exp(scale * d2), wt)
        density[wt == 0] = -1.0  # padding
        mode = v[np.arange(len(v)), density.argmax(1)]
        for _ in range(iterations):
            k = wt * np.exp(scale * ((col - mode[:, None, :n_colour]) ** 2).sum(-1))
            total = k.sum(1)[:, None]
            mode = np.where(total > 0, np.einsum("pk,pkc->pc", k, v) / np.maximum(total, 1e-30), mode)
        x[lo : lo + chunk] = mode
    return x.reshape(h, w, c).astype(np.float64)


# --------------------------------------------------------------------------- Section 4.5
class _Statistics:
    """Interpolated Portilla-Simoncelli statistics per alpha band at one resolution."""

    def __init__(self, c1, c2, alphas, shape):
        scales = int(min(4, np.floor(np.log2(min(min(shape), *c1.shape[:2], *c2.shape[:2]))) - 2))
        self.ok = scales >= 1
        if not self.ok:
            return
        s1 = ps_statistics(c1, scales=scales)
        s2 = ps_statistics(c2, scales=scales, color_basis=s1.color_basis)
        self.alphas = np.asarray(alphas, dtype=float)
        self.stats = [interpolate_statistics(s1, s2, float(al)) for al in self.alphas]

    def step(self, colour, alpha_map):
        if not self.ok:
            return colour
        colour = np.clip(colour, 0.0, 1.0)
        if len(self.stats) == 1:
            return ps_step(colour, self.stats[0])
        # Section 4.5: "the statistical synthesis independently for several equidistantly sampled
        # values of alpha, each time only on the relevant parts of the image according to the
        # distribution map. Then, the results are blended using alpha as blending weight." Band k
        # measures and imposes its statistics on the pixels nearest to its alpha (tent weight
        # w_k > 1/2) and its change is blended in with w_k (ps_step's fractional mask)
        change = np.zeros_like(colour)
        total = np.zeros(colour.shape[:2])
        spacing = self.alphas[1] - self.alphas[0]
        for al, st in zip(self.alphas, self.stats):
            w = np.maximum(0.0, 1.0 - np.abs(alpha_map - al) / spacing)
            if not np.any(w > 0.5):
                continue
            try:
                projected = ps_step(colour, st, mask=w)
            except ValueError:  # a region too thin for the autocorrelation window (small coarse images)
                projected = colour + w[..., None] * (ps_step(colour, st) - colour)  # the whole image's step
            change += projected - colour
            total += w
        return colour + change / np.maximum(total, 1e-12)[..., None]


# --------------------------------------------------------------------------- public
def interpolate_textures(a, b, alpha, *, size=None, features=None, stages=((2, 33), (2, 17), (1, 17)),
                         max_iterations=10, distance_weight=1.0, k=1, keep_fraction=0.5, feature_weight=0.5,
                         max_feature_points=24, max_neighborhoods=1024, max_set_size=16384, alpha_steps=20, alpha_weight=4.0,
                         statistics_bands=5, relative_grid_spacing=0.25, candidate_stride=2, relaxation_radius=2,
                         spring_weight=0.002, mean_shift_bandwidth=0.03, mean_shift_iterations=3,
                         tolerance=0.0, statistics_step=True, rpm_options=None, method="auto", candidates="all",
                         rng=None, progress=False, return_info=False):
    """Interpolate two textures by warping and blending their neighbourhoods (Ruiters et al. 2010).

    Parameters
    ----------
    a, b : array_like
        The textures ``I1`` and ``I2`` (grey or colour, same channels), at
        least as large as the largest neighbourhood at its resolution.
    alpha : float or array_like
        The interpolation amount in [0, 1] (0 gives ``a``, 1 gives ``b``), or
        a distribution map ``(H, W)`` of alpha values for a spatially varying
        texture (a transition strip, Figure 4, or any grey image, Figure 7);
        the output then has the map's size.
    size : int or (int, int), optional
        Output size for a scalar ``alpha``; default the size of ``a``.
    features : (array_like, array_like), optional
        Binary feature maps ``(F1, F2)`` of the two textures' sizes (the
        paper uses hand-made maps of edges, ridges, cracks). Default: the
        centre lines of ridges and valleys (:func:`ridge_feature_map`),
        which mark mortar joints and grooves as single lines; Canny edges
        (:func:`edge_feature_map`, the paper's "not very satisfactory"
        detector) are the alternative. An empty map falls back to
        colour-only correspondences with identity warps (with a warning).
    stages : sequence of (int, int)
        Coarse-to-fine ``(r, s)``: downsampling factor and neighbourhood size;
        the paper's default ``(2, 33), (2, 17), (1, 17)``, with ``(2, 49)``
        first for large regular features.
    max_iterations : int
        Synthesis iterations per stage (10 in the paper).
    distance_weight : float
        Channel weight ``W_C`` of the distance channel (colour channels 1) in
        the correspondence search and the synthesis, at most 1e6.
    k : int
        Corresponding neighbourhoods per neighbourhood (1 in the paper).
    keep_fraction : float
        Fraction of interpolated neighbourhoods kept at ``alpha = 0.5``, the
        best by similarity (0.5 in the paper). Towards the ends the fraction
        rises linearly to 1 (``1 - (1 - keep_fraction) 2 min(alpha, 1 -
        alpha)``): a blend ghosts in proportion to the smaller weight, and
        at alpha = 0 or 1 the set is then all neighbourhoods of one input.
    feature_weight : float
        Relative weight of the warped distance channels against the colour
        normalized cross-correlation in the similarity (in [0, 1]).
    max_feature_points : int
        Cap on the feature points per patch given to TPS-RPM (random
        subsample, default 24). Fewer points = cheaper matching but coarser
        alignment of thin features.
    max_neighborhoods : int
        Cap on the neighbourhoods of each texture that get a correspondence
        (a regular stride, default 1024 per texture and stage). The search
        itself is over every neighbourhood of the other texture; the cap
        bounds the number of TPS-RPM problems (at most ``2 k
        max_neighborhoods`` per stage). Each kept pair is reused shifted by
        up to the stride with the same warp (see ``max_set_size``), so the
        cap costs variety of the warps, not coverage of positions.
    max_set_size : int
        Cap on the size of ``N'`` per stage (all alphas together): the
        number of shifted copies per kept pair is reduced to stay below it.
        Larger sets cost search time in every iteration.
    alpha_steps : int
        Alphas (equidistant) with interpolated patches for a distribution
        map (20 in the paper).
    alpha_weight : float
        Weight of the alpha channel in the synthesis search: high values
        follow the distribution map exactly, low ones favour smooth
        transitions. At most 1e6.
    statistics_bands : int
        Alphas (equidistant) with their own statistical synthesis step for a
        distribution map, each run "only on the relevant parts of the image"
        (the pixels nearest to its alpha); the results are blended by alpha
        (Section 4.5).
    relative_grid_spacing : float
        Cell size of the irregular-centre grid as a fraction of ``s``
        (Kwatra et al.'s ``w/4``).
    candidate_stride : int
        Spacing of the candidate centres tried inside each cell; 1 tries
        every pixel as the paper does, 2 (default) a quarter of them.
    relaxation_radius : int
        Search radius of the relaxation step, in pixels.
    spring_weight : float
        Weight of the spring term keeping a centre's displacement near its
        neighbours' (per squared pixel, against mean squared colour error),
        at most 1e6.
    mean_shift_bandwidth : float
        Colour bandwidth of the per-pixel mean shift (Gaussian kernel on
        the colour distance, colours in [0, 1]; at most 100). Default 0.03: with 0.1 the
        kernel spans the disagreement of the overlapping patches and the
        mode is their mean (Notes).
    mean_shift_iterations : int
        Mean-shift steps per update (0 keeps the IRLS-weighted mean).
    tolerance : float or None
        Kwatra et al.'s stopping rule: a stage ends early at the first
        iteration whose energy (``info.energy``) is above ``(1 -
        tolerance)`` times the previous one; default 0.0, stop when the
        energy stops falling. ``None`` always runs ``max_iterations`` (the
        paper's fixed N = 10).
    statistics_step : bool
        Perform one Portilla-Simoncelli step with linearly interpolated
        statistics per iteration (Section 4.5); in the last stage it is
        weighted by ``2 min(alpha, 1 - alpha)`` (see Notes).
    method : {"auto", "exact", "kdtree", "tsvq"}
        Search backend (:mod:`texsynth.core.search`) of the correspondences
        (``"auto"``: exact up to 20000 neighbourhoods of the other texture,
        kd-tree above) and of the synthesis in ``N'`` (``"auto"``: exact up
        to a few thousand neighbourhoods, kd-tree above).
    candidates : {"all", "k-coherent"}
        How the correspondences (Section 4.1) are searched. ``"all"``
        (default, the paper): every neighbourhood of the other texture,
        through ``method``. ``"k-coherent"``: k-coherent search (Ashikhmin
        2001; Tong et al. 2002, :doi:`10.1145/566654.566634`, not at hand):
        the capped neighbourhoods lie on a grid, so a grid neighbour's match
        shifted by the offset to it is a candidate, offered with its
        k-coherence set of 4 (:func:`~texsynth.core.search.coherence_sets`),
        in PatchMatch's scan order, 3 iterations after one PatchMatch
        iteration from random matches (which gives the search something to
        continue); the ``k`` nearest found are kept. Approximate, and cheaper
        where the other texture has many neighbourhoods (see
        docs/methods/interpolation.md).
    rpm_options : dict, optional
        Options of :func:`texsynth.core.tps.tps_rpm`; defaults here anneal faster
        than Chui and Rangarajan's (``anneal_rate=0.8,
        iterations_per_temperature=3, sinkhorn_iterations=10``) and hold the
        affine part 1000 times stiffer (``affine_lambda_init=10``; theirs
        is 0.01, see Notes).
    rng : None, int or numpy.random.Generator
        Noise initialisation, feature subsampling, search indices.
    progress : bool or callable
        ``True`` shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return an :class:`InterpolationInfo`.

    Returns
    -------
    image : numpy.ndarray
        The interpolated texture, grey or colour like ``a``.
    info : InterpolationInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        For ``alpha`` outside [0, 1] (or a map with such values or not 2-D),
        feature maps of another size than their textures, textures smaller
        than a stage's neighbourhood, or other out-of-range options.

    Notes
    -----
    Correspondences use ``||W_C (N_i^(1) - N_j^(2))||_2`` over colour and
    distance channels (Section 4.1), searched in both directions through
    :mod:`texsynth.core.search` (profile ``"correspondence"``: exact up to
    20000 neighbourhoods of the other texture, the paper's PCA + kd-tree
    above); the synthesis searches ``N'`` with the default profile. Each pair
    is colour-adjusted to the alpha-interpolated means and deviations,
    TPS-RPM (eq. 1) gives ``theta_12`` and ``theta_21`` from the same
    correspondences, and

    .. math:: N'(x) = (1 - \\alpha) N_1(\\theta'_{21}(x)) + \\alpha N_2(\\theta'_{12}(x)),
              \\quad \\theta'_{12} = (1-\\alpha)\\theta_{12} + \\alpha I,\\;
              \\theta'_{21} = \\alpha\\theta_{21} + (1-\\alpha) I.

    The synthesis per iteration: irregular centres (best centre per grid
    cell), relaxation with a spring term, IRLS weights ``(rho + eps)^((r-2)/2)``
    with ``r = 0.8`` (Kwatra et al. 2005) and a per-pixel mean-shift mode
    (Kopf et al. 2007) started at the densest pasted value, then one
    Portilla-Simoncelli step with linearly interpolated statistics.

    Departures for speed, all options: TPS-RPM anneals faster than the
    authors' schedule (``rpm_options``), feature points and neighbourhoods
    are capped, candidate centres use a stride of 2, and a stage stops
    when its energy stops falling (``tolerance``). The distance channel is
    synthesized with the colour (so the output's features are matched too)
    and dropped at the end.

    Departures for quality, each measured on ``docs/methods/interpolation.md``:

    - the synthesis starts from a random tiling of ``N'`` rather than noise
      (the nearest neighbourhoods of noise are the flattest ones, and the
      result collapsed onto horizontal streaks);
    - the distance channel is scaled to the colours' deviation (unscaled it
      dominated the search and the colours averaged to grey);
    - each kept pair is reused at shifted positions (otherwise ``N'`` held
      one position in ``stride**2`` and elements broke up);
    - the keep fraction depends on alpha (above);
    - the overlapping patches carry Kwatra et al.'s Gaussian fall-off;
    - the Portilla-Simoncelli step comes *before* the patch step of each
      iteration (after it, as listed in Pseudocode 1, its colour fringes and
      broken lines stayed in the output), and in the last (r, s) stage it is
      weighted by ``2 min(alpha, 1 - alpha)`` (per pixel for a map): it
      restores the detail that blending removes, and at alpha = 0 and 1
      nothing is blended, so there the last stage is Kwatra et al.'s texture
      optimization on the input's own neighbourhoods while the coarser
      stages keep the full step, which prevents a collapse onto flat
      patches;
    - the affine part of TPS-RPM is regularised towards the identity with
      ``affine_lambda_init = 10`` instead of Chui and Rangarajan's 0.01: a
      patch's feature points lie along a few mortar lines or cracks, which
      leave the affine part free across them, and the warps squeezed patches
      across one axis into smeared swirls;
    - against blur: the warps sample with cubic splines (bilinear sampling at
      a warp's fractional positions is a blur); the blend of each pair keeps
      the contrast the colour adjustment intended (the average of two partly
      uncorrelated patches has less: its deviation from the patch mean is
      rescaled to ``(1 - a)`` times that of the warped ``N1`` plus ``a``
      times that of ``N2``, with a gain between 1 and ``1 / sqrt((1 - a)^2 +
      a^2)``, the observation behind Heitz and Neyret's variance-preserving
      blending); and the per-pixel mean shift starts at the densest of the
      pasted values with a bandwidth of 0.03 rather than at their mean with
      0.1, where the "mode" of disagreeing patches was their mean.

    The output is periodic.

    References
    ----------
    .. [1] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
       interpolation", EGSR 2010. :doi:`10.1111/j.1467-8659.2010.01739.x`
    .. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture
       optimization for example-based synthesis", SIGGRAPH 2005.
       :doi:`10.1145/1073204.1073263`
    .. [3] J. Kopf et al., "Solid texture synthesis from 2D exemplars",
       SIGGRAPH 2007. :doi:`10.1145/1276377.1276380`
    .. [4] H. Chui and A. Rangarajan, "A new algorithm for non-rigid point
       matching", CVPR 2000. :doi:`10.1109/CVPR.2000.854733`
    .. [5] J. Portilla and E. P. Simoncelli, "A parametric texture model
       based on joint statistics of complex wavelet coefficients", IJCV
       40(1), 2000. :doi:`10.1023/A:1026553619983`
    .. [6] E. Heitz and F. Neyret, "High-performance by-example noise using
       a histogram-preserving blending operator", HPG 2018.
       :doi:`10.1145/3233304`

    Examples
    --------
    >>> x = np.indices((24, 24)).sum(0) % 6 / 5.0
    >>> out = interpolate_textures(x, x.T, 0.5, stages=((1, 9),), max_iterations=1, statistics_step=False, rng=0)
    >>> out.shape
    (24, 24)
    """
    t_start = time.perf_counter()
    info = InterpolationInfo()
    stage_energies = []
    p = _check_inputs(a, b, features=features, distance_weight=distance_weight, k=k, keep_fraction=keep_fraction,
                      feature_weight=feature_weight, max_feature_points=max_feature_points,
                      max_neighborhoods=max_neighborhoods, max_set_size=max_set_size, rpm_options=rpm_options,
                      method=method, candidates=candidates)
    info.colour_only = p.colour_only
    rng = as_rng(rng)
    alpha_map = None
    if np.ndim(alpha) == 0:
        alpha = check_in_range(alpha, "alpha", 0.0, 1.0)
        out_shape = p.a.shape[:2] if size is None else as_size(size)
        alphas = [alpha]
    else:
        alpha_map = np.asarray(alpha, dtype=np.float64)
        if alpha_map.ndim != 2:
            raise ValueError(f"alpha must be a number or a 2-D distribution map (H, W), got shape {alpha_map.shape}")
        if size is not None and as_size(size) != alpha_map.shape:
            raise ValueError(f"alpha map has shape {alpha_map.shape} but size is {as_size(size)}; they must agree")
        if not np.all(np.isfinite(alpha_map)) or alpha_map.min() < 0 or alpha_map.max() > 1:
            raise ValueError(
                f"alpha map values must lie in [0, 1], got [{np.nanmin(alpha_map):.3g}, {np.nanmax(alpha_map):.3g}]"
            )
        out_shape = alpha_map.shape
        alphas = list(np.linspace(0.0, 1.0, check_positive_int(alpha_steps, "alpha_steps", 2)))
    # the per-pixel mean shift gathers the ~(1/relative_grid_spacing)^2 values pasted on every pixel
    # (float32, colour + distance + alpha channels), the relaxation a few image-sized sums
    check_memory(float(out_shape[0]) * out_shape[1] * (p.a.shape[-1] + 2) * 200, tuple(out_shape))
    stages = _check_stages(stages)
    max_iterations = check_positive_int(max_iterations, "max_iterations", maximum=MAX_ITERATIONS)
    # weights above 1e6 make their term all that counts, and far beyond they overflow float32
    alpha_weight = check_positive_float(alpha_weight, "alpha_weight", allow_zero=True, maximum=1e6)
    bands = check_positive_int(statistics_bands, "statistics_bands", 2)
    relative_grid_spacing = check_in_range(relative_grid_spacing, "relative_grid_spacing", 0.0, 1.0, low_open=True)
    candidate_stride = check_positive_int(candidate_stride, "candidate_stride")
    relaxation_radius = check_positive_int(relaxation_radius, "relaxation_radius", 0)
    if relaxation_radius >= min(s for _, s in stages):
        raise ValueError(f"relaxation_radius={relaxation_radius} lets a neighbourhood move past its own size; pass "
                         f"less than the smallest stage's neighbourhood size {min(s for _, s in stages)}")
    spring_weight = check_positive_float(spring_weight, "spring_weight", allow_zero=True, maximum=1e6)
    # colours lie in [0, 1]: a bandwidth of 100 already averages every colour
    bandwidth = check_positive_float(mean_shift_bandwidth, "mean_shift_bandwidth", maximum=100.0)
    ms_iterations = check_positive_int(mean_shift_iterations, "mean_shift_iterations", 0, MAX_ITERATIONS)
    if tolerance is not None:
        tolerance = check_in_range(tolerance, "tolerance", 0.0, 1.0)
    n_colour = p.a.shape[-1]
    channel_weights = p.channel_weights
    if alpha_map is not None:
        channel_weights = np.append(channel_weights, alpha_weight)
    with Progress(progress, len(stages) * max_iterations, "interpolate") as bar:
        x = None
        for stage, (r, s) in enumerate(stages):
            shape = (max(1, out_shape[0] // r), max(1, out_shape[1] // r))
            if min(shape) < s:
                raise ValueError(f"output {out_shape} at resolution 1/{r} is smaller than the neighbourhood {s}; "
                                 f"pass a larger size or smaller stages")
            t1, t2 = _stage_textures(p, r, s)
            patches = _interpolated_set(t1, t2, s, alphas, p, rng, info)
            info.kept.append(len(patches))
            t0 = time.perf_counter()
            nset = _PatchSet(patches, channel_weights, p.method, rng)
            amap = None if alpha_map is None else ndimage.zoom(alpha_map, (shape[0] / out_shape[0], shape[1] / out_shape[1]),
                                                               order=1)[: shape[0], : shape[1]]
            spacing = max(1, int(round(relative_grid_spacing * s)))
            if x is None:
                x = _bootstrap(patches[..., : n_colour + 1], shape, spacing, rng)
            elif x.shape[:2] != shape:
                x = ndimage.zoom(x, (shape[0] / x.shape[0], shape[1] / x.shape[1], 1), order=1)
            if amap is not None:
                x = np.concatenate([x[..., : n_colour + 1], amap[..., None]], -1)
            info.add("synthesis", t0)
            t0 = time.perf_counter()
            stats = _Statistics(_downsample(p.a, r), _downsample(p.b, r),
                                alphas if alpha_map is None else np.linspace(0, 1, bands), shape) if check_bool(
                    statistics_step, "statistics_step") else None
            info.add("statistics", t0)
            ps_weight = _statistics_weight(alphas[0] if amap is None else amap[..., None], stage == len(stages) - 1)

            def search(x, _previous):
                """M-step of Pseudocode 1: (PS step,) irregular centres and their nearest N' neighbourhoods."""
                if stats is not None and np.any(ps_weight > 0):
                    # Section 4.5, one Portilla-Simoncelli step per iteration, taken *before* the
                    # patch search: the step restores fine detail and contrast that the search then
                    # finds in N', and the patch update removes its colour fringes and broken
                    # features (taken after it, as listed in Pseudocode 1, they stay in the output)
                    t0 = time.perf_counter()
                    x = x.copy()
                    step = np.clip(stats.step(x[..., :n_colour], amap), 0.0, 1.0)
                    x[..., :n_colour] += ps_weight * (step - x[..., :n_colour])
                    info.add("statistics", t0)
                t0 = time.perf_counter()
                centres, idx, err = _irregular_centres(x, nset, spacing, min(candidate_stride, spacing))
                z = patches[idx].astype(np.float64)
                if amap is not None:
                    z[..., -1] = extract(x, centres, s, mode="wrap")[..., -1]  # the map is enforced, not replaced
                info.add("synthesis", t0)
                return (centres, z), err, True

            def update(state, weights, _iteration):
                """E-step: relaxation of the pasted neighbourhoods, then the per-pixel mean-shift mode."""
                t0 = time.perf_counter()
                centres, z = state
                if relaxation_radius > 0:
                    centres = _relax(centres, z, weights, shape, relaxation_radius, spring_weight, max_sweeps=5)
                x = _mean_shift_update(z, centres, weights, shape, bandwidth, ms_iterations, n_colour)
                x[..., :n_colour] = np.clip(x[..., :n_colour], 0.0, 1.0)
                info.add("synthesis", t0)
                return x

            energies = []

            def energy(err, _x):
                energies.append(float(err.mean()))
                return energies[-1]

            def report(iteration, value, stop):
                bar.advance({"stage": (r, s), "energy": value}, n=max_iterations - iteration if stop else 1)

            state, err, _ = search(x, None)
            x, *_ = expectation_maximization(
                x, state, err, update, search, energy, max_iterations=max_iterations,
                tolerance=tolerance, eps2=_EPS, on_iteration=report,
            )
            stage_energies.append(energies)
    if x.shape[:2] != out_shape:
        x = ndimage.zoom(x, (out_shape[0] / x.shape[0], out_shape[1] / x.shape[1], 1), order=1)
    out = np.clip(x[..., :n_colour], 0.0, 1.0).astype(p.a.dtype)
    out = restore_channels(out, p.grey)
    info.energy = np.concatenate([np.asarray(e, float) for e in stage_energies])
    info.stage = np.repeat(np.arange(len(stage_energies)), [len(e) for e in stage_energies])
    info.seconds = time.perf_counter() - t_start
    return (out, info) if return_info else out


def _statistics_weight(alpha, last):
    """Weight of the Portilla-Simoncelli step: 1, and ``2 min(alpha, 1 - alpha)`` in the last stage.

    The statistics step restores the detail that blending two warped patches
    removes, and blending removes it in proportion to ``min(alpha, 1 - alpha)``
    (the same factor sets the keep fraction, see :func:`_interpolated_set`).
    At alpha = 0 and 1 ``N'`` holds the input's own neighbourhoods and the
    last stage becomes Kwatra et al.'s texture optimization; the coarser
    stages keep the full step, which is what stops the synthesis collapsing
    onto flat patches (see Notes of :func:`interpolate_textures`).

    >>> float(_statistics_weight(0.25, True)), _statistics_weight(0.0, False)
    (0.5, 1.0)
    """
    return 2.0 * np.minimum(alpha, 1.0 - alpha) if last else 1.0


def _check_stages(stages):
    try:
        stages = [(int(r), int(s)) for r, s in stages]
    except (TypeError, ValueError):
        raise ValueError(f"stages must be a sequence of (r, s) pairs, got {stages!r}") from None
    if not stages or any(r < 1 or s < 3 for r, s in stages):
        raise ValueError(f"stages need r >= 1 and s >= 3, got {stages}")
    return stages
