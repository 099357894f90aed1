"""Feature-aligned texture synthesis in the plane (after Xu et al. 2009's feature-aligned shape texturing).

The planar form of Xu et al.'s method [1]_ (:mod:`texsynth.surface._feature_aligned` is the surface one):
the user draws curves as a line image, and the texture is synthesised so that its direction follows the
curves and the exemplar's own feature lines lie on them:

1. **The exemplar's feature lines**: its edge map (:func:`edge_feature_map`, Canny), or its ridge lines
   (:func:`ridge_feature_map`), or a map the user gives; their dominant direction ``theta_f``
   (:func:`texsynth.metrics.dominant_orientation`).
2. **The curves' orientation**: at every curve pixel the direction of the line, from the structure tensor
   of the curve image (Gaussian derivatives of 1 pixel, averaged over 2 pixels), as a doubled angle ``w =
   exp(2 i phi)`` (a line has no sign, so no orientation has to be chosen).
3. **A field constrained by the curves**: ``w`` held at the curve pixels and harmonic elsewhere (the
   smoothest field: a sparse Laplace system over the free pixels), ``phi = arg(w) / 2``. The texture is
   turned by ``phi - theta_f`` at every pixel, so the exemplar's feature direction runs along the curves
   (the ``orientation`` field of :class:`texsynth.core.em.Fields`).
4. **Texture optimisation with the feature term** (Kwatra et al. 2005's EM, composed through
   :func:`~texsynth.optimize_texture` with :class:`texsynth.core.em.Guides` and
   :class:`texsynth.core.em.Fields`, no option of its own): ``E = sum_p ||x_p - z_p||^r + w_F ||g_p -
   f(z_p)||^2``, where ``f = exp(-d^2 / 2 sigma^2)`` of the distance ``d`` to the exemplar's nearest feature
   line is an extra exemplar channel and ``g = m + (1 - m) exp(-d_c^2 / 2 sigma^2)`` of the distance
   ``d_c`` to the nearest curve the output's given channel (``m`` the mean of ``f``: far from the curves
   every exemplar neighbourhood is about equally far from it, so the term leaves the texture free there),
   ``sigma`` 2 pixels. Neighbourhoods near a curve so prefer exemplar neighbourhoods with a feature line
   where the curve is: the paper's feature-alignment term, as a guide channel.

What could not be checked: the paper was not at hand (its published description and the lecture slides on
its curve orientation and vector field were); it works on surfaces, and its planar form here, the doubled
angle field, the harmonic fill, the guide-channel form of its feature term and every constant are this
implementation's reading.

References
----------
.. [1] K. Xu, D. Cohen-Or, T. Ju, L. Liu, H. Zhang, S. Zhou and Y. Xiong, "Feature-aligned shape
   texturing", ACM TOG 28(5) (SIGGRAPH Asia 2009), article 108. :doi:`10.1145/1618452.1618454`
.. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for example-based synthesis",
   ACM TOG 24(3), 2005, pp. 795-802. :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np
import scipy.ndimage
import scipy.sparse
import scipy.sparse.linalg

from ..core._validate import as_array, as_image, check_memory, check_positive_float, is_auto, with_channels
from ..core.em import Fields, Guides, Schedule
from ..core.search import Search
from ..metrics import dominant_orientation
from ._kwatra import optimize_texture
from ._ruiters_neighborhoods import edge_feature_map, ridge_feature_map

__all__ = ["feature_aligned_texture", "FeatureTextureInfo", "curve_orientation"]

#: The exemplar's feature lines when not given as a map.
EXEMPLAR_FEATURES = ("edges", "ridges")
_SIGMA = 2.0          # width of the feature channels, pixels
_TENSOR = (1.0, 2.0)  # the curve image's structure tensor: derivative and averaging sigmas, pixels
_FIELD_BYTES = 600    # per pixel: the curve image's tensor and the Laplace system with its sparse LU factor


@dataclass
class FeatureTextureInfo:
    """Extra results of :func:`feature_aligned_texture`.

    Attributes
    ----------
    orientation : numpy.ndarray
        ``(H, W)`` radians: the curves' direction ``phi`` at every pixel (step 3), counter-clockwise as shown.
    exemplar_features : numpy.ndarray of bool
        ``(h, w)`` the exemplar's feature lines (step 1).
    feature_angle : float
        Degrees, their dominant direction ``theta_f``.
    output_guide : numpy.ndarray
        ``(H, W)`` the feature channel ``g`` the output's neighbourhoods were matched with.
    optimization : texsynth.core.em.OptimizationInfo
        The texture optimisation's own info (energy per iteration, stages, sources).
    energy, stage : numpy.ndarray
        The optimisation's energies and their stages (as ``optimization``'s).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"field"`` and ``"optimization"``.
    """

    orientation: np.ndarray | None = None
    exemplar_features: np.ndarray | None = None
    feature_angle: float = 0.0
    output_guide: np.ndarray | None = None
    optimization: object = None
    energy: np.ndarray | None = None
    stage: np.ndarray | None = None
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


def _curve_image(curves):
    arr = as_array(curves, "curves")
    if arr.ndim == 3 and 1 <= arr.shape[2] <= 4:  # a drawing saved in colour: its colour channels averaged
        scale = 255.0 if arr.dtype == np.uint8 else 1.0
        arr = arr[..., : 3 if arr.shape[2] >= 3 else 1].astype(np.float64).mean(axis=2) / scale
    if arr.ndim != 2:
        raise ValueError(f"curves must be a line image (H, W) or (H, W, C), white on the curves, got shape "
                         f"{arr.shape}")
    # the Laplace system of the orientation field: about 5 nonzeros per pixel, and its factor a few times that
    check_memory(float(arr.size) * _FIELD_BYTES, arr.shape, "curves.shape", "the curves' orientation field")
    if arr.dtype == bool:
        mask = np.asarray(arr)
    else:
        values = arr.astype(np.float64)
        if not np.isfinite(values).all():
            raise ValueError("curves has NaN or infinite values; pass a bool or 0/1 line image")
        mask = values / 255.0 > 0.5 if arr.dtype == np.uint8 else values > 0.5
    if not mask.any():
        raise ValueError("curves has no curve pixel (nothing above 0.5); draw the curves in white on black")
    return mask


def curve_orientation(curves):
    """The direction of a line image's curves, carried over the whole image (steps 2-3).

    Examples
    --------
    >>> import numpy as np
    >>> curves = np.zeros((40, 40), bool); curves[20, 5:35] = True   # one horizontal line
    >>> phi = curve_orientation(curves)
    >>> bool(np.allclose(np.sin(phi), 0, atol=0.05))                  # horizontal everywhere
    True

    Parameters
    ----------
    curves : array_like
        ``(H, W)`` line image, True (or > 0.5) on the curves.

    Returns
    -------
    numpy.ndarray
        ``(H, W)`` radians in (-pi/2, pi/2], counter-clockwise from the
        horizontal as the image is shown: the curves' direction at the curve
        pixels (structure tensor of the line image), the harmonic
        interpolation of its doubled angle elsewhere.
    """
    mask = _curve_image(curves)
    image = mask.astype(np.float64)
    d, avg = _TENSOR
    g_col = scipy.ndimage.gaussian_filter(image, d, order=(0, 1))
    g_up = -scipy.ndimage.gaussian_filter(image, d, order=(1, 0))     # y up, as the image is shown
    jxx, jyy, jxy = (scipy.ndimage.gaussian_filter(a, avg) for a in (g_col * g_col, g_up * g_up, g_col * g_up))
    # the gradient's doubled angle is (jxx - jyy, 2 jxy); the line runs across it: turned by 180 degrees
    w = -((jxx - jyy) + 2j * jxy)
    w = w / np.maximum(np.abs(w), 1e-12)
    h, wd = mask.shape
    n = h * wd
    index = np.arange(n).reshape(h, wd)
    # the grid Laplacian: 4 neighbours
    a = np.concatenate([index[:, :-1].ravel(), index[:-1, :].ravel()])
    b = np.concatenate([index[:, 1:].ravel(), index[1:, :].ravel()])
    degree = np.bincount(np.concatenate([a, b]), minlength=n).astype(np.float64)
    laplacian = (scipy.sparse.diags(degree) - scipy.sparse.csr_matrix(
        (np.ones(2 * len(a)), (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(n, n))).tocsr()
    fixed = mask.ravel()
    z = np.where(fixed, w.ravel(), 0.0)
    free = ~fixed
    if free.any():
        system = laplacian[free][:, free].tocsc()
        rhs = -(laplacian[free][:, fixed] @ z[fixed])
        z[free] = (scipy.sparse.linalg.spsolve(system, rhs.real) + 1j * scipy.sparse.linalg.spsolve(system, rhs.imag))
    return np.angle(z.reshape(h, wd)) / 2.0


def _exemplar_features(exemplar_features, image):
    if isinstance(exemplar_features, str):
        if exemplar_features == "edges" or is_auto(exemplar_features):
            return edge_feature_map(image)
        if exemplar_features == "ridges":
            return ridge_feature_map(image)
        raise ValueError(f"exemplar_features must be 'edges', 'ridges' or a bool map of the exemplar's size, got "
                         f"{exemplar_features!r}")
    arr = as_array(exemplar_features, "exemplar_features")
    if arr.shape != image.shape[:2]:
        raise ValueError(f"exemplar_features must have the exemplar's size {image.shape[:2]}, got shape {arr.shape}; "
                         "pass a bool map of its feature lines, 'edges' or 'ridges'")
    if not np.isfinite(arr.astype(np.float64)).all():
        raise ValueError("exemplar_features has NaN or infinite values; pass a map of 0/1 or bool")
    return arr.astype(np.float64) > 0.5


def _feature(distance):
    return np.exp(-0.5 * (distance / _SIGMA) ** 2)


def feature_aligned_texture(exemplar, curves, *, exemplar_features="edges", alignment_weight=4.0,
                            schedule=Schedule(), search=Search(), rng=None, progress=False, return_info=False):
    """Synthesise a texture whose direction follows drawn curves and whose feature lines lie on them.

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> from texsynth.optimization import feature_aligned_texture
    >>> stripes = np.tile((np.arange(32) % 8 < 4)[:, None], (1, 32)).astype(float)
    >>> curves = np.zeros((48, 48), bool); curves[5:43, 24] = True        # one vertical line
    >>> out = feature_aligned_texture(stripes, curves, rng=0,
    ...                               schedule=texsynth.Schedule(neighborhood_sizes=(8,), levels=1, max_iterations=2))
    >>> out.shape
    (48, 48)

    The planar form of Xu et al.'s feature-aligned texturing [1]_: the
    curves' direction is carried over the image as a smooth field, the
    texture is turned along it, and a feature channel pulls the
    exemplar's feature lines onto the curves, in texture optimisation
    (Kwatra et al. [2]_; module notes: the steps and what could not be
    checked).

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    curves : array_like
        ``(H, W)`` line image, True (or > 0.5; uint8 > 127) on the curves
        (a colour drawing ``(H, W, C)``: its colour channels averaged): its
        size is the output's.
    exemplar_features : {"edges", "ridges"} or array_like
        The exemplar's feature lines: its Canny edges
        (:func:`~texsynth.optimization._ruiters_neighborhoods.edge_feature_map`,
        default), its ridge and valley lines (``ridge_feature_map``), or a
        bool map of its size.
    alignment_weight : float
        ``w_F``, the feature channel's weight against the colours (the
        ``guide_weight`` of :class:`texsynth.core.em.Guides`; 0: the field
        alone aligns the texture). Default 4: on a planks exemplar the
        joints covered 25 % of the curves' pixels with 1 and 45 % with 4
        (15 % of the image; docs/methods/feature_aligned.md).
    schedule, search
        The texture optimisation's stages and search, as in
        :func:`~texsynth.optimize_texture` (its ``"default"`` preset). The
        orientation field makes its M-step the index (PatchMatch compares
        unrotated patches).
    rng : None, int or numpy.random.Generator
        Seeds the optimisation. Same seed, same image.
    progress : bool or callable
        As in :func:`~texsynth.optimize_texture`.
    return_info : bool
        Also return a :class:`FeatureTextureInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``(H, W)`` or ``(H, W, C)``, the exemplar's layout.
    info : FeatureTextureInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid exemplar, a curve image that is not 2-D or has no
        curve, a feature map of another size, a negative ``alignment_weight``,
        or any error of :func:`~texsynth.optimize_texture`'s options.

    References
    ----------
    .. [1] K. Xu, D. Cohen-Or, T. Ju, L. Liu, H. Zhang, S. Zhou and Y. Xiong,
       "Feature-aligned shape texturing", ACM TOG 28(5) (SIGGRAPH Asia
       2009), article 108. :doi:`10.1145/1618452.1618454`
    .. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
       for example-based synthesis", ACM TOG 24(3), 2005, pp. 795-802.
       :doi:`10.1145/1073204.1073263`
    """
    start = time.perf_counter()
    image = with_channels(as_image(exemplar, "exemplar"))[0]
    mask = _curve_image(curves)
    alignment_weight = check_positive_float(alignment_weight, "alignment_weight", allow_zero=True, maximum=1e6)
    features = _exemplar_features(exemplar_features, image)
    info = FeatureTextureInfo(exemplar_features=features)
    t0 = time.perf_counter()
    if features.any():  # the direction of the exemplar's feature lines, in [0, 180)
        info.feature_angle = dominant_orientation(features.astype(np.float64), levels=1)[0] % 180.0
    info.orientation = curve_orientation(mask)
    turn = info.orientation - np.radians(info.feature_angle)
    f = _feature(scipy.ndimage.distance_transform_edt(~features)) if features.any() else np.zeros(features.shape)
    mean = float(f.mean())
    info.output_guide = mean + (1.0 - mean) * _feature(scipy.ndimage.distance_transform_edt(~mask))
    info.stage_seconds["field"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    out, opt = optimize_texture(exemplar, mask.shape, schedule=schedule, search=search,
                                guides=Guides(exemplar_guide=f, output_guide=info.output_guide,
                                              guide_weight=alignment_weight),
                                fields=Fields(orientation=turn), rng=rng, progress=progress, return_info=True)
    info.stage_seconds["optimization"] = time.perf_counter() - t0
    info.optimization, info.energy, info.stage = opt, opt.energy, opt.stage
    info.seconds = time.perf_counter() - start
    return (out, info) if return_info else out
