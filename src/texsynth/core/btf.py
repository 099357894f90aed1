"""Bidirectional texture functions (BTFs) and their 3-D textons (Leung & Malik 2001; Tong et al. 2002).

A BTF sample [2]_ is a stack of images of one patch of surface, each taken
under its own light direction (and view direction): :class:`BTF` holds the
stack and the directions, :func:`as_btf` checks one. Tong et al. [2]_
synthesise a BTF as a 2-D texture of *3-D textons* (Leung & Malik [1]_):

1. every image is filtered with the Leung-Malik filter bank
   (:func:`leung_malik_filters`: 48 filters, first and second derivatives of
   elongated Gaussians at 3 scales and 6 orientations, 8 Laplacians of
   Gaussians, 4 Gaussians) and the responses of all images are concatenated
   into one long vector per pixel (:func:`filter_responses`);
2. the vectors are clustered by k-means (scikit-learn's ``KMeans``); the
   cluster centres are the textons, and every pixel is labelled with its
   nearest one (:func:`btf_textons`). For speed, with more than 8 images
   k-means runs on the vectors' 48 leading principal axes
   (``randomized_svd``; 98% of the responses' energy on the 64-light
   ``stones`` sample, and the same k-means energy in the full space as
   k-means run there, in a fraction of the time:
   ``benchmarks/bench_btf.py``), and the textons are then the means of
   each cluster's full vectors;
3. neighbourhoods of texton labels are compared through the textons' dot
   products ``G_ab = <t_a, t_b>`` (Tong et al.'s precomputed table): the high
   dimensional centres are dropped once ``G`` is known, and
   ``||t_a - t_b||^2 = G_aa + G_bb - 2 G_ab``.

Here the table is used through an embedding (:func:`texton_embedding`): the
eigen-decomposition of the centred Gram matrix ``J G J`` (classical scaling)
gives points ``y_a`` with ``||y_a - y_b|| = ||t_a - t_b||`` exactly when all
positive eigenvalues are kept, so an image of texton labels becomes an image
of ``y`` (:meth:`Textons.image`) that the shared search layer and the pixel
and surface syntheses match like any exemplar. Those take at most 4
channels, so the families keep the 4 leading axes, which keep
:attr:`Textons.image`'s reported share of the squared distances (an
approximation of the paper's exact table; stated where it is used).

A BTF is rendered for any light and view (:func:`render_btf`,
:func:`sample_btf`) by blending the images of the nearest measured
directions, weighted by inverse distance between direction pairs.

What could not be checked: the paper was not at hand; this module follows
its published description (the abstract and talk slides). The number of
textons (default 64 here), the filter bank's exact scales (Leung & Malik's
"small" bank, LMS, is used), whether responses are normalised before
clustering (they are not here) and how the paper interpolates between
measured directions could not be checked.

References
----------
.. [1] T. Leung and J. Malik, "Representing and recognizing the visual
   appearance of materials using three-dimensional textons", IJCV 43(1),
   2001, pp. 29-44. :doi:`10.1023/A:1011126920638`
.. [2] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
   "Synthesis of bidirectional texture functions on arbitrary surfaces",
   SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np
import scipy.fft as sfft

from ._validate import as_array, as_float_array, as_rng, check_memory, check_positive_int
from .search import PatchIndex

__all__ = ["BTF", "as_btf", "leung_malik_filters", "filter_responses", "btf_textons", "Textons",
           "texton_embedding", "texton_image", "TEXTON_CHANNELS", "render_btf", "sample_btf", "direction_weights"]

_TOP = (0.0, 0.0, 1.0)
_NEAREST_DIRECTIONS = 3    # measured directions blended by render_btf / sample_btf
_PRINCIPAL_AXES = 48      # k-means runs on the responses' leading principal axes (module notes)
#: Axes of the texton coordinates a synthesis matches (the pixel and surface syntheses take at most 4 channels).
TEXTON_CHANNELS = 4


@dataclass(frozen=True, eq=False)
class BTF:
    """A BTF sample: images of one surface patch under many light (and view) directions.

    Examples
    --------
    >>> import numpy as np
    >>> from texsynth.core.btf import BTF
    >>> b = BTF(np.zeros((2, 8, 8)), lights=[(0, 0, 1), (1, 0, 1)])
    >>> b.images.shape, b.lights.round(3).tolist()[1], b.views.tolist()[0]
    ((2, 8, 8), [0.707, 0.0, 0.707], [0.0, 0.0, 1.0])

    Parameters
    ----------
    images : array_like
        ``(M, H, W)`` grey images in [0, 1] (any accepted dtype, as an image).
    lights : array_like
        ``(M, 3)`` direction towards the light of each image, in the sample's
        frame: x along the columns, y up the rows (towards row 0), z out of
        the surface. Normalised to unit length.
    views : array_like, optional
        ``(M, 3)`` direction towards the viewer of each image, same frame.
        None: every image seen from straight above, ``(0, 0, 1)``.
    """

    images: np.ndarray
    lights: np.ndarray
    views: np.ndarray | None = None

    def __post_init__(self):
        images = as_array(self.images, "btf.images")
        if images.ndim != 3 or min(images.shape) < 1:
            raise ValueError(f"btf.images must have shape (M, H, W): M grey images of one size, got shape "
                             f"{images.shape}")
        images = as_float_array(images, "btf.images")
        m = images.shape[0]
        object.__setattr__(self, "images", images)
        object.__setattr__(self, "lights", _directions(self.lights, m, "btf.lights"))
        views = np.tile(_TOP, (m, 1)) if self.views is None else self.views
        object.__setattr__(self, "views", _directions(views, m, "btf.views"))

    @property
    def shape(self):
        """``(H, W)``: the size of every image."""
        return self.images.shape[1:]

    def __len__(self):
        return self.images.shape[0]

    def __repr__(self):
        return f"BTF({len(self)} images of {self.shape[0]}x{self.shape[1]})"


def _directions(value, m, name):
    d = as_array(value, name).astype(np.float64)
    if d.shape != (m, 3):
        raise ValueError(f"{name} must have shape ({m}, 3): one direction per image, got shape {d.shape}")
    norm = np.linalg.norm(d, axis=1, keepdims=True)
    if np.any(norm == 0):
        raise ValueError(f"{name} has a zero vector; give a direction (x, y, z) of nonzero length per image")
    return d / norm


def as_btf(value, name="btf"):
    """``value`` if it is a :class:`BTF`, else a TypeError naming ``name`` and the fix.

    >>> as_btf(np.zeros((2, 4, 4)))
    Traceback (most recent call last):
    ...
    TypeError: btf must be a texsynth.core.btf.BTF (images and light directions: texsynth.data.btf(...)), got ndarray
    """
    if isinstance(value, BTF):
        return value
    raise TypeError(f"{name} must be a texsynth.core.btf.BTF (images and light directions: "
                    f"texsynth.data.btf(...)), got {type(value).__name__}")


def _gauss1d(sigma, order, x):
    """A 1-D Gaussian of ``sigma`` at ``x`` or its first or second derivative (Leung & Malik's ``gauss1d``)."""
    g = np.exp(-x * x / (2 * sigma * sigma)) / np.sqrt(2 * np.pi * sigma * sigma)
    if order == 1:
        return -g * x / sigma**2
    if order == 2:
        return g * (x * x - sigma**2) / sigma**4
    return g


def _normalise(f):
    """Zero mean, unit L1 norm (the bank's ``normalise``)."""
    f = f - f.mean()
    return f / np.abs(f).sum()


def leung_malik_filters(size=49):
    """The Leung-Malik filter bank (the "small" LMS bank of Leung & Malik 2001): 48 filters.

    Examples
    --------
    >>> from texsynth.core.btf import leung_malik_filters
    >>> bank = leung_malik_filters(15)
    >>> bank.shape, bool(abs(bank.sum(axis=(1, 2))).max() < 1e-12)
    ((48, 15, 15), True)

    Parameters
    ----------
    size : int
        The side of every filter, odd (default 49, the bank's support).

    Returns
    -------
    numpy.ndarray
        ``(48, size, size)`` float64: 36 oriented filters (first, then second
        derivative of a Gaussian elongated 3:1 across its direction, at
        scales ``sigma = sqrt(2), 2, 2 sqrt(2)`` and 6 orientations, 30 degrees
        apart), 8 Laplacians of Gaussians (``sigma = sqrt(2)^i`` and
        ``3 sqrt(2)^i``, ``i = 1..4``) and 4 Gaussians (``sqrt(2)^i``); each
        of zero mean and unit L1 norm.
    """
    size = check_positive_int(size, "size", minimum=3)
    if size % 2 == 0:
        raise ValueError(f"size must be odd (a filter centred on a pixel), got {size}; pass {size + 1}")
    half = size // 2
    y, x = np.mgrid[-half:half + 1, -half:half + 1].astype(np.float64)
    scales = np.sqrt(2.0) ** np.arange(1, 5)
    bank = []
    for order in (1, 2):
        for s in scales[:3]:
            for angle in np.arange(6) * np.pi / 6:
                u = np.cos(angle) * x + np.sin(angle) * y     # along the filter
                v = -np.sin(angle) * x + np.cos(angle) * y    # across it: the derivative's axis
                bank.append(_normalise(_gauss1d(3 * s, 0, u) * _gauss1d(s, order, v)))
    for s in np.concatenate([scales, 3 * scales]):
        bank.append(_normalise(_gauss1d(s, 2, x) * _gauss1d(s, 0, y) + _gauss1d(s, 0, x) * _gauss1d(s, 2, y)))
    for s in scales:
        bank.append(_normalise(_gauss1d(s, 0, x) * _gauss1d(s, 0, y)))
    return np.stack(bank)


def filter_responses(images, filters):
    """Every filter's response at every pixel of every image, concatenated per pixel (Leung & Malik's vectors).

    Examples
    --------
    >>> from texsynth.core.btf import filter_responses, leung_malik_filters
    >>> filter_responses(np.random.default_rng(0).random((3, 20, 24)), leung_malik_filters(9)).shape
    (20, 24, 144)

    Parameters
    ----------
    images : numpy.ndarray
        ``(M, H, W)`` float images.
    filters : numpy.ndarray
        ``(F, h, w)`` odd-sized filters.

    Returns
    -------
    numpy.ndarray
        ``(H, W, F * M)`` float32: entry ``f * M + m`` is filter ``f``'s
        response on image ``m`` (a convolution, the images extended by
        reflection at their edges).
    """
    m, h, w = images.shape
    f, fh, fw = filters.shape
    ph, pw = fh // 2, fw // 2
    padded = np.pad(images, ((0, 0), (ph, ph), (pw, pw)), mode="reflect")
    shape = [sfft.next_fast_len(n, True) for n in (h + 2 * ph, w + 2 * pw)]
    spectra = sfft.rfft2(padded, shape)
    out = np.empty((h, w, f, m), np.float32)
    for j in range(f):  # one filter at a time: memory of one stack of spectra, not F of them
        conv = sfft.irfft2(spectra * sfft.rfft2(filters[j], shape), shape)
        out[:, :, j, :] = conv[:, 2 * ph:2 * ph + h, 2 * pw:2 * pw + w].transpose(1, 2, 0)
    return out.reshape(h, w, f * m)


@dataclass
class Textons:
    """3-D textons of a BTF sample (:func:`btf_textons`): each pixel's label and the textons' dot products.

    Attributes
    ----------
    labels : numpy.ndarray of int64
        ``(H, W)`` the texton of each pixel of the sample.
    gram : numpy.ndarray
        ``(n_textons, n_textons)`` float64 dot products ``<t_a, t_b>`` of the
        textons (the cluster centres, which are not kept).
    counts : numpy.ndarray of int64
        ``(n_textons,)`` pixels labelled with each texton.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"filters"``, ``"principal axes"``, ``"k-means"`` and ``"gram"``.
    """

    labels: np.ndarray
    gram: np.ndarray
    counts: np.ndarray
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)

    def image(self, n_components=4):
        """The sample as an image of texton coordinates in [0, 1] (:func:`texton_embedding`).

        Returns ``(image, kept)``: ``(H, W, n_components)`` coordinates of each
        pixel's texton, all axes scaled by one factor (so distances keep their
        ratios), and the share of the sum of squared texton distances the
        ``n_components`` leading axes keep (1.0: exact).
        """
        points, kept = texton_embedding(self.gram, n_components)
        low, high = points.min(), points.max()
        scaled = (points - low) / (high - low) if high > low else np.zeros_like(points)
        return scaled[self.labels], kept


def btf_textons(btf, n_textons=64, *, filter_size=49, rng=None):
    """3-D textons of a BTF sample: filter-bank responses of all images, clustered by k-means.

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.core.btf import btf_textons
    >>> t = btf_textons(texsynth.data.btf("stones", 32, n_lights=8), 8, filter_size=15, rng=0)
    >>> t.labels.shape, t.gram.shape, int(t.counts.sum())
    ((32, 32), (8, 8), 1024)

    Steps 1-3 of the module notes: the Leung-Malik responses of every image
    (:func:`filter_responses`), concatenated per pixel, are clustered into
    ``n_textons`` textons by k-means on their 48 leading principal axes
    (with more than 8 images; on the vectors themselves otherwise);
    each pixel is labelled with its cluster, the textons are the clusters'
    mean full responses, and they are kept only as their dot-product matrix.

    Parameters
    ----------
    btf : BTF
        The sample.
    n_textons : int
        Number of textons (clusters), at least 2 and at most the sample's
        pixels. Default 64 (the paper's count could not be checked).
    filter_size : int
        The side of the filters (:func:`leung_malik_filters`; default 49).
    rng : None, int or numpy.random.Generator
        Seeds the principal axes and k-means. Same seed, same textons.

    Returns
    -------
    Textons

    Raises
    ------
    TypeError, ValueError
        For a ``btf`` that is not a :class:`BTF`, a bad ``n_textons`` or
        ``filter_size``, or a sample whose responses (``H * W * 48 * M``
        float32, about twice) need more memory than is available.
    """
    start = time.perf_counter()
    btf = as_btf(btf)
    h, w = btf.shape
    n_textons = check_positive_int(n_textons, "n_textons", minimum=2, maximum=h * w)
    filters = leung_malik_filters(filter_size)
    dim = len(filters) * len(btf)
    check_memory(2.2 * h * w * dim * 4 + 4.0 * n_textons * h * w, (len(btf), h, w), "btf",
                 "the filter responses of every image")
    seed = int(as_rng(rng).integers(2**31 - 1))
    responses = filter_responses(btf.images, filters).reshape(h * w, dim)
    stages = {"filters": time.perf_counter() - start}
    from sklearn.cluster import KMeans  # scikit-learn loads in ~1 s: only when textons are made
    from sklearn.utils.extmath import randomized_svd

    if dim > 8 * _PRINCIPAL_AXES:
        _, _, axes = randomized_svd(responses, min(_PRINCIPAL_AXES, h * w), n_iter=2, random_state=seed)
        reduced = responses @ axes.T
    else:  # few images: k-means on the responses themselves
        reduced = responses
    stages["principal axes"] = time.perf_counter() - start - stages["filters"]
    labels = KMeans(n_clusters=n_textons, n_init=1, random_state=seed).fit(reduced).labels_.astype(np.int64)
    stages["k-means"] = time.perf_counter() - start - sum(stages.values())
    counts = np.bincount(labels, minlength=n_textons)
    members = np.zeros((n_textons, h * w), np.float32)
    members[labels, np.arange(h * w)] = 1.0
    centres = (members @ responses).astype(np.float64) / np.maximum(counts, 1)[:, None]  # the full textons
    gram = centres @ centres.T
    stages["gram"] = time.perf_counter() - start - sum(stages.values())
    labels = labels.reshape(h, w)
    return Textons(labels, gram, counts, time.perf_counter() - start, stages)


def texton_image(btf, textons="auto", n_textons=64, *, rng=None):
    """A BTF sample's textons and the image of texton coordinates a synthesis matches (steps 1-3).

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.core.btf import texton_image
    >>> t, image, share = texton_image(texsynth.data.btf("stones", 32, n_lights=8), n_textons=8, rng=0)
    >>> image.shape, 0 < share <= 1
    ((32, 32, 4), True)

    Parameters
    ----------
    btf : BTF
    textons : Textons or "auto"
        Textons made before for this sample (:func:`btf_textons`); ``"auto"``:
        made here.
    n_textons : int
        With ``textons="auto"``: how many.
    rng : None, int or numpy.random.Generator
        Seeds k-means.

    Returns
    -------
    textons : Textons
    image : numpy.ndarray
        ``(h, w, TEXTON_CHANNELS)`` in [0, 1] (:meth:`Textons.image`).
    share : float
        The share of the texton distances the axes keep.
    """
    btf = as_btf(btf)
    if isinstance(textons, str) and textons == "auto":
        textons = btf_textons(btf, n_textons, rng=rng)
    elif not isinstance(textons, Textons):
        raise TypeError(f"textons must be 'auto' or a texsynth.core.btf.Textons (btf_textons(btf)), got "
                        f"{type(textons).__name__}")
    elif textons.labels.shape != btf.shape:
        raise ValueError(f"textons label a {textons.labels.shape} sample but btf's images are {btf.shape}; "
                         f"make them with btf_textons(btf)")
    image, share = textons.image(TEXTON_CHANNELS)
    return textons, image, share


def texton_embedding(gram, n_components=None):
    """Points whose distances are the textons' distances, from their dot products (classical scaling).

    Examples
    --------
    >>> from texsynth.core.btf import texton_embedding
    >>> t = np.random.default_rng(0).normal(size=(5, 40))
    >>> y, kept = texton_embedding(t @ t.T)
    >>> d_t = ((t[:, None] - t[None]) ** 2).sum(-1)
    >>> d_y = ((y[:, None] - y[None]) ** 2).sum(-1)
    >>> bool(np.allclose(d_t, d_y)), kept
    (True, 1.0)

    ``||t_a - t_b||^2 = G_aa + G_bb - 2 G_ab`` for the Gram matrix ``G``;
    centring it (``B = J G J``, ``J = I - 11^T / n``) leaves those distances
    unchanged, and ``B = V diag(lambda) V^T`` gives the points
    ``Y = V sqrt(lambda)``, exact with every positive eigenvalue.

    Parameters
    ----------
    gram : array_like
        ``(n, n)`` symmetric dot products.
    n_components : int, optional
        Keep only the leading axes (largest eigenvalues). None: all with a
        positive eigenvalue (exact).

    Returns
    -------
    points : numpy.ndarray
        ``(n, d)`` float64.
    kept : float
        The share of ``sum_ab ||t_a - t_b||^2`` (the sum of the eigenvalues)
        the kept axes reproduce; 1.0 when exact.
    """
    g = as_array(gram, "gram").astype(np.float64)
    if g.ndim != 2 or g.shape[0] != g.shape[1] or g.shape[0] < 1:
        raise ValueError(f"gram must be a square (n, n) matrix of dot products, got shape {g.shape}")
    n = g.shape[0]
    b = g - g.mean(0, keepdims=True) - g.mean(1, keepdims=True) + g.mean()
    values, vectors = np.linalg.eigh((b + b.T) / 2)
    order = np.argsort(values)[::-1]
    values, vectors = np.clip(values[order], 0, None), vectors[:, order]
    total = values.sum()
    positive = int(np.count_nonzero(values > total * 1e-12)) if total > 0 else 0
    want = positive if n_components is None else check_positive_int(n_components, "n_components")
    d = min(want, n)
    points = np.pad(vectors[:, :d] * np.sqrt(values[:d]), ((0, 0), (0, want - d)))  # zero axes beyond n
    return points, float(values[:d].sum() / total) if total > 0 else 1.0


def direction_weights(btf, lights, views=None):
    """The measured images that render each light (and view) direction, and their blend weights.

    The :data:`_NEAREST_DIRECTIONS` images whose (light, view) pairs are
    nearest to the query's (through :class:`~texsynth.core.search.PatchIndex`),
    weighted by inverse distance (an exact hit takes all the weight); a light
    below the surface (``z <= 0``) gets weight 0 (unlit).

    Parameters
    ----------
    btf : BTF
    lights : array_like
        ``(3,)`` or ``(Q, 3)`` directions towards the light, in the sample's frame.
    views : array_like, optional
        The same for the viewer; None: from above.

    Returns
    -------
    indices : numpy.ndarray of int64
        ``(Q, k)`` image indices.
    weights : numpy.ndarray
        ``(Q, k)`` summing to 1 (0 for lights below the surface).
    """
    btf = as_btf(btf)
    lights = _query_directions(lights, "lights")
    views = np.tile(_TOP, (len(lights), 1)) if views is None else _query_directions(views, "views")
    if len(views) == 1 and len(lights) > 1:
        views = np.repeat(views, len(lights), axis=0)
    if len(views) != len(lights):
        raise ValueError(f"views must be one direction or one per light ({len(lights)}), got {len(views)}")
    k = min(_NEAREST_DIRECTIONS, len(btf))
    index = PatchIndex(np.concatenate([btf.lights, btf.views], axis=1), method="exact")
    indices, d2 = index.query(np.concatenate([lights, views], axis=1), k=k)
    distance = np.sqrt(np.maximum(d2, 0.0))
    exact = distance[:, :1] < 1e-9                         # a measured direction: its image alone
    inverse = np.where(exact, (np.arange(k) == 0).astype(np.float64), 1.0 / np.maximum(distance, 1e-9))
    weights = inverse / inverse.sum(axis=1, keepdims=True)
    weights[lights[:, 2] <= 0] = 0.0
    return indices.astype(np.int64), weights


def _query_directions(value, name):
    d = as_array(value, name).astype(np.float64)
    d = d[None] if d.ndim == 1 else d
    if d.ndim != 2 or d.shape[1] != 3:
        raise ValueError(f"{name} must be a direction (x, y, z) or an (N, 3) array of them, got shape {d.shape}")
    norm = np.linalg.norm(d, axis=1, keepdims=True)
    if np.any(norm == 0):
        raise ValueError(f"{name} has a zero vector; give directions of nonzero length")
    return d / norm


def render_btf(btf, light, view=None):
    """The BTF's image for any light (and view) direction: its nearest measured images, blended.

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.core.btf import render_btf
    >>> sample = texsynth.data.btf("stones", 32, n_lights=8)
    >>> bool(np.allclose(render_btf(sample, sample.lights[3]), sample.images[3]))
    True

    Parameters
    ----------
    btf : BTF
    light : array_like
        ``(3,)`` direction towards the light (x along the columns, y up the
        rows, z out of the surface).
    view : array_like, optional
        ``(3,)`` direction towards the viewer; None: from above.

    Returns
    -------
    numpy.ndarray
        ``(H, W)`` image (:func:`direction_weights` says how it is blended).
    """
    indices, weights = direction_weights(btf, light, view)
    return np.tensordot(weights[0], btf.images[indices[0]], axes=1)


def sample_btf(btf, positions, lights, views=None):
    """The BTF at sample pixels, each under its own light (and view) direction (a surface's local frames).

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.core.btf import sample_btf
    >>> sample = texsynth.data.btf("stones", 32, n_lights=8)
    >>> float(sample_btf(sample, [[4, 5]], sample.lights[2])[0]) == float(sample.images[2, 4, 5])
    True

    Parameters
    ----------
    btf : BTF
    positions : array_like of int
        ``(N, 2)`` sample pixels ``(row, col)``.
    lights : array_like
        ``(3,)`` or ``(N, 3)`` directions towards the light, each in the
        sample's frame at its point.
    views : array_like, optional
        The same for the viewer; None: from above.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` values.
    """
    btf = as_btf(btf)
    pos = np.asarray(positions)
    if pos.ndim != 2 or pos.shape[1] != 2 or not np.issubdtype(pos.dtype, np.integer):
        raise ValueError(f"positions must be an (N, 2) integer array of (row, col), got {pos.dtype} {pos.shape}")
    h, w = btf.shape
    if len(pos) and (pos.min() < 0 or pos[:, 0].max() >= h or pos[:, 1].max() >= w):
        raise ValueError(f"positions must lie inside the sample's {h}x{w} pixels")
    indices, weights = direction_weights(btf, lights, views)
    if len(indices) == 1:
        indices, weights = np.repeat(indices, len(pos), 0), np.repeat(weights, len(pos), 0)
    if len(indices) != len(pos):
        raise ValueError(f"lights must be one direction or one per position ({len(pos)}), got {len(indices)}")
    values = btf.images[indices, pos[:, 0, None], pos[:, 1, None]]
    return (values * weights).sum(axis=1)
