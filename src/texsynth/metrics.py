"""Quality metrics for synthesised textures, and the baselines that calibrate them.

A synthesis is judged against its exemplar on four axes:

coherence (:func:`texture_energy`)
    How far each output neighbourhood is from its nearest exemplar
    neighbourhood: Kwatra et al. 2005, eq. 1, normalised per value. Low means
    every part of the output looks like some part of the exemplar.
completeness (:func:`completeness`)
    How far each exemplar neighbourhood is from its nearest output
    neighbourhood (the other half of the bidirectional similarity of Simakov
    et al. 2008). Low means the output shows everything the exemplar has.
copying (:func:`verbatim_copy`)
    The largest output region copied from the exemplar with one single
    offset, as a fraction of the exemplar's area. A tiled exemplar scores
    about 1; a good synthesis well below 0.5.
statistics (:func:`histogram_distance`, :func:`spectrum_distance`)
    Per-channel Wasserstein distance of the value histograms, and distance of
    the radially averaged log power spectra.

Raw numbers mean little on their own; :func:`baselines` makes three reference
images from the exemplar - histogram-matched white noise (worst coherence),
a random-block mosaic (what naive patch pasting gives) and the tiled exemplar
(best coherence, worst copying) - and :func:`texture_report` scores an output
against them. ``docs/metrics.md`` holds the calibration table on real textures.
"""

from __future__ import annotations

import copy
import hashlib
import numbers
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .core._validate import (
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_memory,
    check_positive_float,
    check_positive_int,
    with_channels,
)
from .core.search import PatchIndex, is_auto
from .core.neighborhood import all_patches, patch_shape

__all__ = [
    "texture_energy",
    "completeness",
    "verbatim_copy",
    "histogram_distance",
    "spectrum_distance",
    "noise_baseline",
    "mosaic_baseline",
    "tiled_baseline",
    "baselines",
    "TextureReport",
    "texture_report",
]


def _pair(output, exemplar):
    out, _ = with_channels(as_image(output, "output"))
    ex, _ = with_channels(as_image(exemplar, "exemplar"))
    if out.shape[-1] != ex.shape[-1]:
        raise ValueError(
            f"output has {out.shape[-1]} channels but exemplar has {ex.shape[-1]}; compare images with the same channels"
        )
    return out, ex


def _grid_vectors(image, size, stride):
    """Valid patches on a grid with the given stride, flattened, with their top-left corners."""
    view = all_patches(image, size, mode="valid")[::stride, ::stride]
    ny, nx = view.shape[:2]
    corners = np.stack(np.meshgrid(np.arange(ny) * stride, np.arange(nx) * stride, indexing="ij"), -1)
    return view.reshape(ny * nx, -1), corners.reshape(-1, 2), (ny, nx)


def _nearest_distances(queries, vectors, method, rng):
    index = PatchIndex(vectors, method=method, rng=rng)
    idx, dist = index.query(queries, k=1)
    return idx[:, 0], dist[:, 0]


def _check_patch(image, size, name):
    h, w = patch_shape(size, "patch_size")
    if h > image.shape[0] or w > image.shape[1]:
        raise ValueError(
            f"patch_size ({h}, {w}) is larger than {name} {image.shape[:2]}; pass a smaller patch_size"
        )
    return h, w


def _mean_nearest_distance(queries_image, candidates_image, queries_name, candidates_name, patch_size, stride,
                           method, rng):
    """Mean squared distance per value of the grid neighbourhoods of one image to their nearest in the other.

    The names are those of the user's arguments, so a size error names the image that is too small.
    """
    size = _check_patch(candidates_image, patch_size, candidates_name)
    _check_patch(queries_image, size, queries_name)
    stride = max(1, size[0] // 4) if is_auto(stride) else check_positive_int(stride, "stride")
    queries, _, _ = _grid_vectors(queries_image, size, stride)
    vectors = all_patches(candidates_image, size, mode="valid").reshape(-1, queries.shape[1])
    _, dist = _nearest_distances(queries, vectors, method, rng)
    return float(dist.mean() / queries.shape[1])


def texture_energy(output, exemplar, *, patch_size=8, stride="auto", method="exact", rng=None):
    """Coherence: mean distance of output neighbourhoods to their nearest exemplar neighbourhood.

    Parameters
    ----------
    output, exemplar : array_like
        Images with the same number of channels (any sizes).
    patch_size : int or (int, int)
        Neighbourhood size ``w``.
    stride : int or "auto"
        Spacing of the output neighbourhoods; ``"auto"`` (default): ``patch_size // 4``
        (the sparse grid of Kwatra et al. 2005). Every exemplar neighbourhood
        is a candidate.
    method : str
        Nearest-neighbour backend (see :class:`texsynth.core.search.PatchIndex`);
        ``"exact"`` by default so the metric is a reference.
    rng : None, int or numpy.random.Generator
        Seeds the approximate backends (``method="kdtree"``, ``"tsvq"``, or
        ``"auto"`` when it picks one of them); pass an int there for a
        reproducible value. The exact default does not use it: the metric is
        the same whatever ``rng``.

    Returns
    -------
    float
        ``E_t / (number of neighbourhoods * values per neighbourhood)`` with
        ``E_t = sum_p ||x_p - z_p||^2`` (Kwatra et al. 2005, eq. 1): the mean
        squared difference per pixel and channel, in [0, 1].

    Raises
    ------
    TypeError
        For images that are not arrays (None, strings) or of an unsupported
        dtype, and non-integer ``patch_size`` or ``stride``.
    ValueError
        For images with NaN, infinity or values outside [0, 1], different
        channel counts, a ``patch_size`` larger than either image, a
        ``stride`` below 1 or an unknown ``method``.

    Examples
    --------
    >>> ex = np.random.default_rng(0).random((16, 16))
    >>> texture_energy(ex, ex, patch_size=4)
    0.0
    """
    out, ex = _pair(output, exemplar)
    return _mean_nearest_distance(out, ex, "the output", "the exemplar", patch_size, stride, method, rng)


def completeness(output, exemplar, *, patch_size=8, stride="auto", method="exact", rng=None):
    """Completeness: mean distance of exemplar neighbourhoods to their nearest output neighbourhood.

    The second term of the bidirectional similarity of Simakov et al. 2008
    (doi:10.1109/CVPR.2008.4587842), normalised per value like
    :func:`texture_energy`. Parameters are the same, with the roles of the two
    images exchanged (``stride`` spaces the exemplar neighbourhoods). As
    there, ``rng`` only matters for an approximate ``method``.

    Examples
    --------
    >>> ex = np.random.default_rng(0).random((16, 16))
    >>> completeness(ex, ex, patch_size=4)
    0.0
    """
    out, ex = _pair(output, exemplar)
    return _mean_nearest_distance(ex, out, "the exemplar", "the output", patch_size, stride, method, rng)


def verbatim_copy(output, exemplar, *, patch_size=8, stride=2, value_tolerance=0.02, method="exact", rng=None):
    """Largest output region copied from the exemplar with a single offset.

    Every output neighbourhood on a grid of the given stride is matched to its
    nearest exemplar neighbourhood. A neighbourhood counts as *copied* when
    its RMS difference to that match is at most ``value_tolerance``. Neighbouring
    copied neighbourhoods with the same offset (exemplar position minus
    output position) form one copied region; the region's area is the union
    of its neighbourhoods' pixels.

    Parameters
    ----------
    output, exemplar : array_like
    patch_size : int or (int, int)
    stride : int
        Grid spacing of the output neighbourhoods (1 is exact and slow).
    value_tolerance : float
        RMS difference (in [0, 1] units) below which a neighbourhood is a copy.
    method : str
        Nearest-neighbour backend; ``"exact"`` by default.
    rng : None, int or numpy.random.Generator
        Seeds an approximate ``method`` only (see :func:`texture_energy`).

    Returns
    -------
    float
        Area of the largest copied region divided by the exemplar's area.
        A tiled exemplar gives about 1, a fresh synthesis close to 0.

    Examples
    --------
    >>> ex = np.random.default_rng(0).random((16, 16))
    >>> round(verbatim_copy(np.tile(ex, (2, 2)), ex, patch_size=4), 2)
    1.0
    """
    out, ex = _pair(output, exemplar)
    size = _check_patch(ex, patch_size, "the exemplar")
    _check_patch(out, size, "the output")
    stride = check_positive_int(stride, "stride")
    value_tolerance = check_positive_float(value_tolerance, "value_tolerance")
    queries, corners, (ny, nx) = _grid_vectors(out, size, stride)
    vectors = all_patches(ex, size, mode="valid")
    ex_nx = vectors.shape[1]
    vectors = vectors.reshape(-1, queries.shape[1])
    idx, dist = _nearest_distances(queries, vectors, method, rng)
    copied = dist / queries.shape[1] <= value_tolerance**2
    offset = np.stack([idx // ex_nx, idx % ex_nx], -1) - corners
    key = (offset[:, 0] * (out.shape[1] + ex.shape[1] + 1) + offset[:, 1]).reshape(ny, nx)
    copied = copied.reshape(ny, nx)
    node = np.arange(ny * nx).reshape(ny, nx)
    edges = []
    for a, b in (((slice(None), slice(0, -1)), (slice(None), slice(1, None))),
                 ((slice(0, -1), slice(None)), (slice(1, None), slice(None)))):
        same = copied[a] & copied[b] & (key[a] == key[b])
        edges.append((node[a][same], node[b][same]))
    rows = np.concatenate([e[0] for e in edges])
    cols = np.concatenate([e[1] for e in edges])
    graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(ny * nx, ny * nx))
    _, labels = connected_components(graph, directed=False)
    if not copied.any():
        return 0.0
    labels = labels.reshape(ny, nx)
    counts = np.bincount(labels[copied])
    largest = np.argmax(counts)
    members = corners.reshape(ny, nx, 2)[copied & (labels == largest)]
    covered = np.zeros(out.shape[:2], dtype=bool)
    h, w = size
    covered[members[:, 0, None, None] + np.arange(h)[:, None], members[:, 1, None, None] + np.arange(w)] = True
    return float(covered.sum() / (ex.shape[0] * ex.shape[1]))


def histogram_distance(output, exemplar):
    """Mean over channels of the 1-D Wasserstein distance between value histograms.

    Computed from 256 quantiles of each image, so images of different sizes
    compare fairly. In [0, 1] units.

    Examples
    --------
    >>> a = np.linspace(0, 1, 100).reshape(10, 10)
    >>> histogram_distance(a, a), round(histogram_distance(a, a * 0.5), 3)
    (0.0, 0.25)
    """
    out, ex = _pair(output, exemplar)
    q = (np.arange(256) + 0.5) / 256
    qo = np.quantile(out.reshape(-1, out.shape[-1]), q, axis=0)
    qe = np.quantile(ex.reshape(-1, ex.shape[-1]), q, axis=0)
    return float(np.abs(qo - qe).mean())


def _radial_log_spectrum(image, bins):
    """Radially averaged log power spectrum of the mean-free luminance, on frequency bins in cycles/pixel."""
    grey = image.mean(axis=-1)
    grey = grey - grey.mean()
    power = np.abs(np.fft.fft2(grey)) ** 2 / grey.size
    fy = np.fft.fftfreq(grey.shape[0])[:, None]
    fx = np.fft.fftfreq(grey.shape[1])[None, :]
    radius = np.hypot(fy, fx).ravel()
    which = np.digitize(radius, bins) - 1
    valid = (which >= 0) & (which < len(bins) - 1)
    sums = np.bincount(which[valid], weights=power.ravel()[valid], minlength=len(bins) - 1)
    counts = np.bincount(which[valid], minlength=len(bins) - 1)
    return np.log10(sums / np.maximum(counts, 1) + 1e-12), counts > 0


def spectrum_distance(output, exemplar, *, bins=24, max_wavelength=None, min_wavelength=None):
    """Mean absolute difference of radially averaged log10 power spectra.

    Frequencies are binned in cycles per pixel (from 1/min-size to 0.5), so
    images of different sizes compare. 1.0 means the spectra differ by a
    factor of 10 on average. ``min_wavelength`` keeps only the long
    wavelengths, the large-scale structure (the arrangement of bricks, the
    spacing of stones) that a synthesis loses when it repeats a small part
    of the exemplar or breaks its elements.

    Parameters
    ----------
    output, exemplar : array_like
        Images with the same number of channels, every side at least 2
        pixels (a side of 1 pixel has no frequency above 0); 16 pixels or
        more for a meaningful spectrum.
    bins : int
        Number of logarithmically spaced frequency bands, >= 2.
    max_wavelength, min_wavelength : float, optional
        Pixels: compare only the bands whose wavelengths lie between them
        (default: from the smaller side of the smaller image down to 2
        pixels). E.g. ``min_wavelength=32`` for the structure above 32 px.

    Returns
    -------
    float
        Mean over the bands that hold frequencies of both images.

    Raises
    ------
    ValueError
        If a side of either image is shorter than 2 pixels, or the two
        images share no frequency band (tiny images of different sizes, or
        too many ``bins``).

    Examples
    --------
    >>> ex = np.random.default_rng(0).random((32, 32))
    >>> spectrum_distance(ex, ex)
    0.0
    """
    out, ex = _pair(output, exemplar)
    bins = check_positive_int(bins, "bins", minimum=2)
    for name, image in (("output", out), ("exemplar", ex)):
        if min(image.shape[:2]) < 2:
            raise ValueError(
                f"spectrum_distance needs images of at least 2x2 pixels (a side of 1 pixel has no frequency "
                f"above 0), but {name} is {image.shape[0]}x{image.shape[1]}; pass a larger {name}"
            )
    low = 1.0 / min(out.shape[0], out.shape[1], ex.shape[0], ex.shape[1])
    high = 0.5 * np.sqrt(2)
    if max_wavelength is not None:
        low = max(low, 1.0 / check_positive_float(max_wavelength, "max_wavelength"))
    if min_wavelength is not None:
        high = min(high, 1.0 / check_positive_float(min_wavelength, "min_wavelength"))
    if not high > low:
        raise ValueError(f"min_wavelength ({min_wavelength}) must be below max_wavelength and the images' size "
                         f"({1.0 / low:g} px); pass a smaller min_wavelength")
    edges = np.geomspace(low, high, bins + 1)
    so, ko = _radial_log_spectrum(out, edges)
    se, ke = _radial_log_spectrum(ex, edges)
    both = ko & ke
    if not both.any():
        raise ValueError(
            f"output ({out.shape[0]}x{out.shape[1]}) and exemplar ({ex.shape[0]}x{ex.shape[1]}) share no "
            f"frequency band of the {bins} bins; pass fewer bins or larger images"
        )
    return float(np.abs(so[both] - se[both]).mean())


def noise_baseline(exemplar, size, *, rng=None):
    """White noise with each channel's histogram matched to the exemplar's.

    The worst-coherence baseline: right values, no structure.

    >>> noise_baseline(np.zeros((4, 4)), (2, 3), rng=0).shape
    (2, 3)
    """
    ex, grey = with_channels(as_image(exemplar, "exemplar"))
    h, w = as_size(size)
    check_memory(float(h) * w * ex.shape[-1] * 8 * 4, (h, w), what="the baseline")
    gen = as_rng(rng)
    order = np.argsort(gen.random((h * w, ex.shape[-1])), axis=0)
    q = (np.arange(h * w) + 0.5) / (h * w)
    values = np.quantile(ex.reshape(-1, ex.shape[-1]), q, axis=0, method="inverted_cdf")
    out = np.empty_like(values)
    np.put_along_axis(out, order, values, axis=0)
    out = out.reshape(h, w, -1).astype(ex.dtype)
    return out[..., 0] if grey else out


def mosaic_baseline(exemplar, size, *, block="auto", rng=None):
    """Random exemplar blocks pasted edge to edge on a grid, without blending.

    What naive patch pasting gives: coherent inside blocks, seams between
    them. ``block="auto"`` (default) is a quarter of the exemplar's smaller side
    (at least 2 pixels, at most the exemplar's smaller side).

    >>> mosaic_baseline(np.zeros((8, 8, 3)), 5, rng=0).shape
    (5, 5, 3)
    """
    ex, grey = with_channels(as_image(exemplar, "exemplar"))
    h, w = as_size(size)
    check_memory(float(h) * w * ex.shape[-1] * 8 * 4, (h, w), what="the baseline")
    b = min(max(2, min(ex.shape[:2]) // 4), min(ex.shape[:2])) if is_auto(block) else check_positive_int(block, "block")
    if b > min(ex.shape[:2]):
        raise ValueError(f"block {b} is larger than the exemplar {ex.shape[:2]}; pass a smaller block")
    gen = as_rng(rng)
    ny, nx = -(-h // b), -(-w // b)
    tops = gen.integers(0, ex.shape[0] - b + 1, size=ny * nx)
    lefts = gen.integers(0, ex.shape[1] - b + 1, size=ny * nx)
    r = np.arange(b)
    blocks = ex[(tops[:, None] + r)[:, :, None], (lefts[:, None] + r)[:, None, :]]
    out = blocks.reshape(ny, nx, b, b, -1).transpose(0, 2, 1, 3, 4).reshape(ny * b, nx * b, -1)[:h, :w]
    return out[..., 0] if grey else out


def tiled_baseline(exemplar, size):
    """The exemplar repeated (periodically) to the output size: best coherence, worst copying.

    >>> tiled_baseline(np.eye(2), (3, 3)).tolist()
    [[1.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]
    """
    ex, grey = with_channels(as_image(exemplar, "exemplar"))
    h, w = as_size(size)
    check_memory(float(h) * w * ex.shape[-1] * 8 * 4, (h, w), what="the baseline")
    out = np.pad(ex, ((0, max(0, h - ex.shape[0])), (0, max(0, w - ex.shape[1])), (0, 0)), mode="wrap")[:h, :w]
    return out[..., 0] if grey else out


def baselines(exemplar, size, *, rng=0):
    """The three reference images for an output of the given size.

    Parameters
    ----------
    exemplar : array_like
    size : int or (int, int)
        ``(height, width)`` of the baselines; an int means square.
    rng : None, int or numpy.random.Generator
        Seeds the noise and the mosaic. The default is the fixed seed 0, not
        the library's usual None: the baselines are the reference scale of
        :func:`texture_report` and :func:`texsynth.testing.assert_texture_like`,
        and a reference that changed from run to run would make the same
        output pass one run and fail the next. Pass None for fresh baselines.

    Returns
    -------
    dict
        ``{"noise": ..., "mosaic": ..., "tiled": ...}``.

    Examples
    --------
    >>> sorted(baselines(np.zeros((8, 8)), 6))
    ['mosaic', 'noise', 'tiled']
    """
    gen = as_rng(rng)
    return {
        "noise": noise_baseline(exemplar, size, rng=gen),
        "mosaic": mosaic_baseline(exemplar, size, rng=gen),
        "tiled": tiled_baseline(exemplar, size),
    }


@dataclass
class TextureReport:
    """All metrics of one output, next to the same metrics of the baselines.

    ``values[name]`` holds the output's metric, ``reference[baseline][name]``
    the baselines' (``baseline`` in ``"noise"``, ``"mosaic"``, ``"tiled"``).
    """

    values: dict
    reference: dict = field(default_factory=dict)

    def table(self):
        """A plain-text table: one row per metric, one column per image."""
        names = list(self.values)
        cols = ["output"] + list(self.reference)
        lines = [f"{'metric':<20}" + "".join(f"{c:>12}" for c in cols)]
        for n in names:
            row = [self.values[n]] + [self.reference[c][n] for c in self.reference]
            lines.append(f"{n:<20}" + "".join(f"{v:>12.5f}" for v in row))
        return "\n".join(lines)


def texture_report(output, exemplar, *, patch_size=8, with_baselines=True, rng=0):
    """Compute every metric for ``output`` (and, by default, for the baselines).

    Parameters
    ----------
    output, exemplar : array_like
        Images with the same number of channels, every side at least
        ``patch_size`` (and 2) pixels.
    patch_size : int or (int, int)
        Neighbourhood size of the patch metrics.
    with_baselines : bool
        Also score the three :func:`baselines` (made at the output's size),
        as :func:`texsynth.testing.relative_scores` needs.
    rng : None, int or numpy.random.Generator
        Seed of the baselines; the fixed default 0 keeps a report
        reproducible (see :func:`baselines`). The metrics themselves are
        exact and use no randomness. With an int seed the baselines'
        metrics are kept for the 16 most recent exemplars and sizes, so
        scoring several outputs of one exemplar measures them once.

    Returns
    -------
    TextureReport

    Examples
    --------
    >>> ex = np.random.default_rng(1).random((20, 20))
    >>> r = texture_report(ex, ex, patch_size=4)
    >>> sorted(r.values), sorted(r.reference)
    (['completeness', 'energy', 'histogram', 'spectrum', 'verbatim_copy'], ['mosaic', 'noise', 'tiled'])
    """
    out, ex = _pair(output, exemplar)
    with_baselines = check_bool(with_baselines, "with_baselines")
    seed = int(rng) if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) else None
    rng = as_rng(rng)  # checked even without baselines; a Generator passes through unchanged

    def measure(image):
        return {
            "energy": texture_energy(image, ex, patch_size=patch_size),
            "completeness": completeness(image, ex, patch_size=patch_size),
            "verbatim_copy": verbatim_copy(image, ex, patch_size=patch_size),
            "histogram": histogram_distance(image, ex),
            "spectrum": spectrum_distance(image, ex),
        }

    reference = {}
    if with_baselines:
        # the baselines of an int seed are the same at every call: scoring several outputs of one
        # exemplar (methods side by side, a test's seeds) measures them once
        key = None if seed is None else (hashlib.sha256(ex.tobytes()).hexdigest(), ex.shape, ex.dtype.str,
                                         out.shape[:2], patch_size, seed)
        reference = _BASELINE_METRICS.get(key) if key is not None else None
        if reference is None:
            reference = {name: measure(img) for name, img in baselines(ex, out.shape[:2], rng=rng).items()}
            if key is not None:
                _BASELINE_METRICS[key] = reference
                while len(_BASELINE_METRICS) > _BASELINE_METRICS_KEPT:
                    _BASELINE_METRICS.pop(next(iter(_BASELINE_METRICS)))  # the oldest
        reference = copy.deepcopy(reference)
    return TextureReport(values=measure(out), reference=reference)


_BASELINE_METRICS = {}  # (exemplar digest, shape, dtype, output size, patch_size, seed) -> the baselines' metrics
_BASELINE_METRICS_KEPT = 16
