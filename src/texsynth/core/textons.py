"""Texton masks and the feature-based warping and blending of two exemplars (Zhang et al. 2003).

The parts of Zhang, Zhou, Velho, Guo and Shum's progressively-variant textures [1]_ that the planar
method (:func:`texsynth.synthesize_controlled`) and the surface method
(:func:`texsynth.surface.progressive_surface`) share:

- :func:`find_textons`: a binary texton mask ``M`` of an exemplar (which pixels belong to a texture
  element);
- :func:`progressive_sample`: the 2-D progressively-variant sample ``(T, M, F)`` made from two
  homogeneous exemplars by feature-based warping and blending: across its width the transition
  function ``F`` runs from 0 (the first exemplar) to 1 (the second), and in between every element of
  one exemplar is moved towards its partner in the other and the two are cross-dissolved, so the
  elements change shape and place gradually instead of fading into each other where they are.

What could not be checked: the paper was not at hand (its published abstract and the lecture slides
that summarise it were). Its features are the texton masks' elements; the choices here (elements as
the masks' connected components, each reduced to its centroid and area, matched by nearest centroid on
the torus, moved and scaled about its centroid, the warp of every pixel that of its nearest element,
smoothed) are this implementation's reading of "feature-based warping and blending", which in the
paper may rest on user-drawn features and another warp (Beier and Neely's line features, say).

References
----------
.. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of progressively-variant
   textures on arbitrary surfaces", ACM TOG 22(3) (SIGGRAPH 2003), pp. 295-302.
   :doi:`10.1145/882262.882344`
"""

from __future__ import annotations

import numbers

import numpy as np

from ._validate import as_image, check_positive_float, check_positive_int, with_channels
from .fields import bilinear
from .search import is_auto, point_tree

__all__ = ["find_textons", "element_warp", "progressive_sample"]

#: Shares at which :func:`progressive_sample` computes the warps (linear in between).
_WARP_STEPS = 17


def find_textons(exemplar, *, sigma=1.0, threshold="auto"):
    """A binary texton mask of an exemplar: its blurred luminance, thresholded.

    Examples
    --------
    >>> import texsynth
    >>> brick = texsynth.data.load("brick")[:64, :64]
    >>> mask = texsynth.find_textons(brick)  # the mortar, the rarer phase
    >>> mask.shape, mask.dtype
    ((64, 64), dtype('bool'))

    What ``texton_mask="auto"`` of :func:`synthesize_controlled` uses; call
    it yourself to adjust the mask (or draw one) and pass the result.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture.
    sigma : float
        Width in pixels of the Gaussian blur before thresholding (default 1:
        removes pixel noise, keeps thin mortar lines and strokes). 0 is no
        blur.
    threshold : float or "auto"
        Luminance in [0, 1] that separates the two phases. ``"auto"``
        (default): Otsu's threshold of the blurred luminance (the two-cluster
        split that minimises the within-class variance, i.e. 1-D two-means).

    Returns
    -------
    numpy.ndarray of bool
        ``(h, w)``; True marks the rarer of the two phases (letters on
        paper, mortar between bricks, the gaps between pebbles). The
        polarity does not change a synthesis: the mask is compared by
        squared differences.

    Raises
    ------
    ValueError, TypeError
        For an invalid exemplar, a negative ``sigma`` or a ``threshold``
        outside [0, 1].

    Notes
    -----
    Zhang et al. [1]_ mark the texture elements of an exemplar by hand or
    with simple image segmentation; which segmentation they used could not
    be checked here. Luminance is the mean of the colour channels. The blur
    widens thin elements:

    >>> import numpy as np
    >>> image = np.zeros((8, 8)); image[2:4, 2:6] = 1.0
    >>> int(texsynth.find_textons(image, sigma=0).sum()), int(texsynth.find_textons(image).sum())
    (8, 12)

    References
    ----------
    .. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
       progressively-variant textures on arbitrary surfaces", SIGGRAPH 2003.
       :doi:`10.1145/882262.882344`
    """
    from scipy.ndimage import gaussian_filter
    from skimage.filters import threshold_otsu

    image, _ = with_channels(as_image(exemplar, "exemplar"))
    sigma = check_positive_float(sigma, "sigma", allow_zero=True)
    luminance = image[..., : min(3, image.shape[-1])].mean(axis=-1).astype(np.float64)
    if sigma > 0:
        luminance = gaussian_filter(luminance, sigma, mode="reflect")
    if is_auto(threshold):
        threshold = float(threshold_otsu(luminance)) if np.ptp(luminance) > 0 else float(luminance.max())
    elif not isinstance(threshold, numbers.Real) or isinstance(threshold, bool):
        raise TypeError(f"threshold must be a number in [0, 1] or 'auto' (Otsu), got {threshold!r}")
    elif not 0.0 <= float(threshold) <= 1.0:
        raise ValueError(f"threshold must lie in [0, 1] (a luminance), got {threshold}")
    mask = luminance > threshold
    return ~mask if mask.sum() * 2 > mask.size else mask


def element_warp(texton_mask, blend):
    """Feature-based warp of one texton mask's elements a share of the way onto their partners in another.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((16, 16), bool); a[2:5, 2:5] = True
    >>> b = np.zeros((16, 16), bool); b[6:9, 3:6] = True
    >>> u = element_warp((a, b), [0.0, 1.0])
    >>> u.shape, u[1, 7, 4].round(1).tolist()  # at share 1, pixel (7, 4) reads the element at (3, 3)
    ((2, 16, 16, 2), [-4.0, -1.0])

    The features are the elements: the connected components of each mask
    (toroidal images of one size), each with its centroid ``c`` and its
    area. Every element of ``mask`` is paired with the element of
    ``mask_b`` whose centroid is nearest on the torus, and at share ``F``
    it has moved by ``F d`` (``d`` the shortest toroidal vector between
    the centroids) and grown by ``s = 1 + F (sqrt(A_b / A) - 1)`` about its
    centroid, so at ``F = 1`` it covers its partner. Pixel ``x`` of the
    warped image reads the original at ``c + (x - c - F d) / s`` (``c``,
    ``d``, ``s`` of ``x``'s nearest element, inverse mapping); that
    displacement is smoothed by a Gaussian of sigma the elements' median
    radius, so that it is continuous between elements.

    Parameters
    ----------
    texton_mask : (numpy.ndarray, numpy.ndarray)
        ``(mask, mask_b)``: two ``(h, w)`` bool texton masks of the same
        size; ``mask``'s elements are warped onto ``mask_b``'s.
    blend : sequence of float
        The shares ``F`` in [0, 1] of the way.

    Returns
    -------
    numpy.ndarray
        ``(len(blend), h, w, 2)`` float: the (row, col) displacement ``u``;
        the warped image at ``x`` is the original at ``x + u(x)``.
    """
    from scipy.ndimage import center_of_mass, distance_transform_edt, gaussian_filter, label

    mask, mask_b = texton_mask
    shares = np.asarray(blend, np.float64)
    shape = np.array(mask.shape, float)
    labels, count = label(mask)
    labels_b, count_b = label(mask_b)
    if count == 0 or count_b == 0:
        return np.zeros((len(shares),) + mask.shape + (2,))
    centers = np.array(center_of_mass(mask, labels, range(1, count + 1))).reshape(-1, 2)
    centers_b = np.array(center_of_mass(mask_b, labels_b, range(1, count_b + 1))).reshape(-1, 2)
    areas, areas_b = np.bincount(labels.ravel())[1:], np.bincount(labels_b.ravel())[1:]
    _, partner = point_tree(centers_b % shape, period=shape).query(centers % shape)
    move = (centers_b[partner] - centers + shape / 2) % shape - shape / 2
    growth = np.sqrt(areas_b[partner] / areas)
    _, (rows, cols) = distance_transform_edt(labels == 0, return_indices=True)
    nearest = labels[rows, cols] - 1
    here = np.stack(np.mgrid[0:mask.shape[0], 0:mask.shape[1]], axis=-1).astype(np.float64)
    offset = (here - centers[nearest] + shape / 2) % shape - shape / 2  # x - c, toroidal
    radius = np.sqrt(np.median(areas) / np.pi)
    out = np.empty((len(shares),) + mask.shape + (2,))
    for i, share in enumerate(shares):
        scale = (1 + share * (growth[nearest] - 1))[..., None]
        u = offset * (1 / scale - 1) - share * move[nearest] / scale
        out[i] = np.stack([gaussian_filter(u[..., j], radius, mode="wrap") for j in range(2)], axis=-1)
    return out


def progressive_sample(exemplar, exemplar_b, texton_mask, *, width):
    """The 2-D progressively-variant sample ``(T, M, F)`` of two exemplars (Zhang et al. 2003).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((16, 16)); a[2:6, 2:6] = 1
    >>> b = np.zeros((16, 16)); b[8:14, 6:12] = 1
    >>> image, mask, blend = progressive_sample(a, b, (a > 0.5, b > 0.5), width=64)
    >>> image.shape, mask.shape, float(blend[0, 0]), float(blend[0, -1])
    ((16, 64, 1), (16, 64), 0.0, 1.0)

    Both exemplars are cut to their common size ``(h, w)`` and read as
    tiles (toroidally). Column ``c`` of the ``(h, width)`` sample has the
    transition value ``F = c / (width - 1)``; there the first exemplar is
    warped a share ``F`` of the way onto the second's elements and the
    second a share ``1 - F`` of the way back (:func:`element_warp`), and
    the two are blended with weights ``1 - F`` and ``F``:
    ``T = (1 - F) A(x + u_A) + F B(x + u_B)``, and the masks likewise,
    thresholded at 0.5. The warps are computed at :data:`_WARP_STEPS`
    shares and interpolated linearly between them.

    Parameters
    ----------
    exemplar, exemplar_b : array_like
        ``(h, w)`` or ``(h, w, C)`` textures with the same channels.
    texton_mask : (array_like, array_like)
        Their texton masks ``(mask, mask_b)`` (bool, e.g. from
        :func:`find_textons`), each of its exemplar's size.
    width : int
        Width of the sample in pixels (a few exemplar widths: the longer,
        the slower the variation across it).

    Returns
    -------
    image : numpy.ndarray
        ``(h, width, C)`` float64.
    mask : numpy.ndarray of bool
        ``(h, width)``, the blended texton mask.
    blend : numpy.ndarray
        ``(h, width)``, the transition function ``F`` in [0, 1].
    """
    a = with_channels(as_image(exemplar, "exemplar"))[0].astype(np.float64)
    b = with_channels(as_image(exemplar_b, "exemplar_b"))[0].astype(np.float64)
    width = check_positive_int(width, "width")
    if a.shape[-1] != b.shape[-1]:
        raise ValueError(f"exemplar_b has {b.shape[-1]} channels but exemplar has {a.shape[-1]}; pass exemplars "
                         "with the same channels")
    h, w = min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1])
    a, b = a[:h, :w], b[:h, :w]
    ma, mb = (np.asarray(m, bool)[:h, :w] for m in texton_mask)
    steps = np.linspace(0.0, 1.0, _WARP_STEPS)
    warp_a, warp_b = element_warp((ma, mb), steps), element_warp((mb, ma), 1 - steps)
    cols = np.arange(width)
    blend = cols / max(width - 1, 1)
    k = np.minimum((blend * (_WARP_STEPS - 1)).astype(np.intp), _WARP_STEPS - 2)
    t = (blend * (_WARP_STEPS - 1) - k)[None, :, None]
    tile = np.arange(h)[:, None], cols[None, :] % w
    here = np.stack(np.broadcast_arrays(np.arange(h)[:, None], cols[None, :]), axis=-1).astype(np.float64)
    at_a = here + (1 - t) * warp_a[k, tile[0], tile[1]] + t * warp_a[k + 1, tile[0], tile[1]]
    at_b = here + (1 - t) * warp_b[k, tile[0], tile[1]] + t * warp_b[k + 1, tile[0], tile[1]]
    share = blend[None, :, None]
    image = (1 - share) * bilinear(a, at_a, wrap=True)[0] + share * bilinear(b, at_b, wrap=True)[0]
    texton = ((1 - share) * bilinear(ma[..., None].astype(float), at_a, wrap=True)[0]
              + share * bilinear(mb[..., None].astype(float), at_b, wrap=True)[0])[..., 0] > 0.5
    return image, texton, np.array(np.broadcast_to(blend, (h, width)))
