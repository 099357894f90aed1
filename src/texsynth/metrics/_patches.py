"""The patch and statistics metrics of :mod:`texsynth.metrics` (coherence, completeness, copying, histogram,
spectrum), their random baselines and the reports that compare an output with them."""

from __future__ import annotations

import copy
import hashlib
import numbers
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..core._validate import (
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_memory,
    check_positive_float,
    check_positive_int,
    with_channels,
)
from ..core.search import PatchIndex, is_auto, nearest_candidates
from ..core.neighborhood import all_patches, patch_shape

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
    queries, corners, grid = _grid_vectors(out, size, stride)
    vectors = all_patches(ex, size, mode="valid").reshape(-1, queries.shape[1])
    idx, dist = _nearest_distances(queries, vectors, method, rng)
    return _largest_copy(idx, dist, corners, grid, out.shape, ex.shape, size, value_tolerance)


def _largest_copy(idx, dist, corners, grid, out_shape, ex_shape, size, value_tolerance):
    """The copied fraction of :func:`verbatim_copy` from each grid neighbourhood's nearest exemplar
    neighbourhood (flat index ``idx`` among the exemplar's valid ones, squared distance ``dist``)."""
    ny, nx = grid
    h, w = size
    ex_nx = ex_shape[1] - w + 1
    copied = dist / (h * w * out_shape[2]) <= value_tolerance**2
    offset = np.stack([idx // ex_nx, idx % ex_nx], -1) - corners
    key = (offset[:, 0] * (out_shape[1] + ex_shape[1] + 1) + offset[:, 1]).reshape(ny, nx)
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
    covered = np.zeros(out_shape[:2], dtype=bool)
    covered[members[:, 0, None, None] + np.arange(h)[:, None], members[:, 1, None, None] + np.arange(w)] = True
    return float(covered.sum() / (ex_shape[0] * ex_shape[1]))


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
    # np.quantile(..., q, axis=0, method="inverted_cdf"), its index rule spelled out: one sort instead of a
    # partition around each of the h * w quantiles (8 s for a 256² exemplar at 256², here 10 ms)
    flat = ex.reshape(-1, ex.shape[-1])
    virtual = flat.shape[0] * q - 1
    below = np.floor(virtual)
    index = np.maximum(np.where(virtual - below == 0, below, below + 1), 0).astype(np.intp)
    values = np.sort(flat, axis=0)[index]
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
        """A plain-text table: one row per metric, one column per image ("-" where one was not measured)."""
        names = list(self.values)
        cols = ["output"] + list(self.reference)
        lines = [f"{'metric':<20}" + "".join(f"{c:>12}" for c in cols)]
        for n in names:
            row = [self.values[n]] + [self.reference[c].get(n) for c in self.reference]
            lines.append(f"{n:<20}" + "".join(f"{'-':>12}" if v is None else f"{v:>12.5f}" for v in row))
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


# The report of texsynth.testing.assert_texture_like: only the metrics its verdict uses, each search on at
# most _VERDICT_GRID neighbourhoods of the metric's own grid. Up to that many the values are texture_report's;
# above, each patch metric's mean over its grid is estimated from a stratified random sample of the grid (one
# neighbourhood per cell of about equal numbers of grid points, weighted by the points it stands for):
# unbiased whatever the image's structure, where a coarser regular grid could fall in step with a synthesis'
# blocks and miss every seam. docs/metrics.md ("How assert_texture_like measures") gives the agreement
# measured on real textures.
_VERDICT_GRID = 1024
# the noise baseline's energy, when sampled: histogram-matched white noise is the same everywhere, so 256
# neighbourhoods estimate its mean within 1.5 % (measured on 6 textures; its completeness, whose queries are
# the exemplar's varied neighbourhoods, needs the full sample: 10 % off with 256)
_NOISE_GRID = 256
# values (neighbourhoods x values per neighbourhood) per block of exact search: bounds the memory whatever
# the image sizes (32 MiB of float64)
_BLOCK_VALUES = 2**22
_COPY_STRIDE = 2  # verbatim_copy's default grid
_VERDICT_BASELINES = {}  # (exemplar digest, shape, dtype, output size, patch size, seed) -> baselines' metrics
_VERDICT_BASELINES_KEPT = 16


@dataclass
class _Sample:
    """Neighbourhoods of a grid: ``corners`` (n, 2), the grid points each stands for (``weights``, None when
    it is the whole grid), the sample's ``cells`` (rows, columns) and the cells' first pixels (``edges_y``,
    ``edges_x``, one more than cells: the last is past the end)."""

    corners: np.ndarray
    weights: np.ndarray | None
    cells: tuple
    edges_y: np.ndarray
    edges_x: np.ndarray


def _grid_sample(shape, size, stride, most=None):
    """The grid of valid neighbourhoods of ``stride``: whole if it holds at most ``most`` (default
    ``_VERDICT_GRID``), else one neighbourhood drawn from each of at most ``most`` cells of about equal
    numbers of grid points. The draw is fixed (seed 0): the same images give the same values.

    >>> _grid_sample((20, 20), (8, 8), 2).cells, _grid_sample((256, 256), (8, 8), 2).cells
    ((7, 7), (32, 32))
    """
    most = _VERDICT_GRID if most is None else most
    gy, gx = -(-(shape[0] - size[0] + 1) // stride), -(-(shape[1] - size[1] + 1) // stride)
    if gy * gx <= most:
        cy, cx = gy, gx
    else:
        cy = int(max(1, min(gy, round(np.sqrt(most * gy / gx)))))
        cx = int(max(1, min(gx, most // cy)))
    edges_y, edges_x = np.arange(cy + 1) * gy // cy, np.arange(cx + 1) * gx // cx  # in grid points
    if (cy, cx) == (gy, gx):
        corners = np.stack(np.meshgrid(edges_y[:-1], edges_x[:-1], indexing="ij"), -1).reshape(-1, 2) * stride
        return _Sample(corners, None, (cy, cx), edges_y * stride, edges_x * stride)
    across_y, across_x = np.diff(edges_y)[:, None], np.diff(edges_x)[None, :]
    gen = np.random.default_rng(0)
    iy = edges_y[:-1, None] + gen.integers(0, across_y, size=(cy, cx))
    ix = edges_x[None, :-1] + gen.integers(0, across_x, size=(cy, cx))
    corners = np.stack([iy, ix], -1).reshape(-1, 2) * stride
    return _Sample(corners, (across_y * across_x).ravel(), (cy, cx), edges_y * stride, edges_x * stride)


def _sample_vectors(image, size, sample):
    view = all_patches(image, size, mode="valid")
    return view[sample.corners[:, 0], sample.corners[:, 1]].reshape(len(sample.corners), -1)


def _sample_mean(dist, dim, sample, where=None):
    """The grid's mean distance per value from the sample's distances (``where``: the sampled neighbourhoods
    ``dist`` belongs to; the others are 0)."""
    if where is None and sample.weights is None:
        return float(dist.mean(dtype=np.float64) / dim)  # as texture_energy computes it
    weights = np.ones(len(sample.corners)) if sample.weights is None else sample.weights
    chosen = weights if where is None else weights[where]
    return float(np.dot(dist.astype(np.float64), chosen) / (weights.sum() * dim))


def _nearest_in(image, size, queries, dtype=None):
    """Each query's exact nearest valid neighbourhood of ``image``: flat indices and squared distances.

    The candidates are indexed a block of rows at a time (memory bounded by ``_BLOCK_VALUES``); a later
    block wins only if strictly nearer, so ties go to the lowest index as in one search over all of them.
    ``dtype`` (e.g. float32) is the precision of the search, by default the queries'.
    """
    view = all_patches(image, size, mode="valid")
    ny, nx = view.shape[:2]
    dim = queries.shape[1]
    dtype = queries.dtype if dtype is None else np.dtype(dtype)
    queries = queries.astype(dtype, copy=False)
    rows = max(1, _BLOCK_VALUES // (nx * dim))
    best_i = np.zeros(len(queries), dtype=np.int64)
    best_d = np.full(len(queries), np.inf, dtype=dtype)
    for top in range(0, ny, rows):
        vectors = np.array(view[top:top + rows], dtype=dtype).reshape(-1, dim)
        idx, dist = _nearest_distances(queries, vectors, "exact", None)
        better = dist < best_d
        best_i[better] = idx[better] + top * nx
        best_d[better] = dist[better]
    return best_i, best_d


def _copy_from_seeds(out, ex, size, seeds, sample, value_tolerance=0.02):
    """:func:`verbatim_copy` on its stride-2 grid, each neighbourhood's nearest searched among the seeds' offsets.

    ``seeds`` holds the exact nearest exemplar neighbourhood (flat indices, squared distances) of the
    output neighbourhoods of ``sample``. Each stride-2 neighbourhood is compared with the exemplar
    neighbourhoods at the offsets of the copied seeds of the 4 x 4 sample cells around it (about two
    cells each way), and the nearest of those (ties: the lowest index) stands for its nearest: a copied
    region that holds a seed is found whole, as the exact search finds it, unless the exemplar holds
    another neighbourhood within ``value_tolerance`` of the copied one (a flat area).
    """
    dim = size[0] * size[1] * out.shape[2]
    ex_view, out_view = all_patches(ex, size, mode="valid"), all_patches(out, size, mode="valid")
    eny, enx = ex_view.shape[:2]
    seed_idx, seed_dist = seeds
    cy, cx = sample.cells
    copied = (seed_dist / dim <= value_tolerance**2).reshape(cy, cx)
    offset_y = (seed_idx // enx - sample.corners[:, 0]).reshape(cy, cx)
    offset_x = (seed_idx % enx - sample.corners[:, 1]).reshape(cy, cx)
    fy = np.arange(0, out_view.shape[0], _COPY_STRIDE)
    fx = np.arange(0, out_view.shape[1], _COPY_STRIDE)
    around = np.arange(-1, 3)
    near_y = np.searchsorted(sample.edges_y, fy, side="right")[:, None] - 1 + around
    near_x = np.searchsorted(sample.edges_x, fx, side="right")[:, None] - 1 + around
    inside_y, inside_x = (near_y >= 0) & (near_y < cy), (near_x >= 0) & (near_x < cx)
    near_y, near_x = np.clip(near_y, 0, cy - 1), np.clip(near_x, 0, cx - 1)
    none = eny * enx  # past every flat index: "no candidate", sorts last
    fine_i = np.zeros(fy.size * fx.size, dtype=np.int64)
    fine_d = np.full(fy.size * fx.size, np.inf, dtype=out.dtype)
    k = around.size**2
    rows = max(1, _BLOCK_VALUES // (fx.size * k * dim))
    for top in range(0, fy.size, rows):
        sy, sx = near_y[top:top + rows, None, :, None], near_x[None, :, None, :]
        usable = copied[sy, sx] & inside_y[top:top + rows, None, :, None] & inside_x[None, :, None, :]
        ty = fy[top:top + rows, None, None, None] + offset_y[sy, sx]
        tx = fx[None, :, None, None] + offset_x[sy, sx]
        usable &= (ty >= 0) & (ty < eny) & (tx >= 0) & (tx < enx)
        pool = np.sort(np.where(usable, ty * enx + tx, none).reshape(-1, k), axis=1)
        found = np.flatnonzero(pool[:, 0] < none)
        if not found.size:
            continue
        # lowest index first, empty places repeat it: nearest_candidates keeps the first of equals
        pool = pool[found]
        pool = np.where(pool < none, pool, pool[:, :1])
        at = found + top * fx.size
        queries = out_view[fy[at // fx.size], fx[at % fx.size]].reshape(-1, dim)
        choice, dist = nearest_candidates(queries, ex_view[pool // enx, pool % enx].reshape(len(at), k, dim))
        fine_i[at] = pool[np.arange(len(at)), choice]
        fine_d[at] = dist
    corners = np.stack(np.meshgrid(fy, fx, indexing="ij"), -1).reshape(-1, 2)
    return _largest_copy(fine_i, fine_d, corners, (fy.size, fx.size), out.shape, ex.shape, size, value_tolerance)


def verdict_report(output, exemplar, *, patch_size=8, rng=0):
    """The metrics :func:`texsynth.testing.assert_texture_like` judges by, each from at most ``_VERDICT_GRID``
    neighbourhoods.

    Returns ``(report, sampled)``: a :class:`TextureReport` with the output's five metrics and the
    noise and tiled baselines' energy, completeness, histogram and spectrum (not their verbatim copy;
    no mosaic), and ``{"energy": (n, of), "completeness": (n, of)}``, the neighbourhoods searched of
    those of the metric's grid (the output's, the exemplar's). While a grid holds at most
    ``_VERDICT_GRID`` neighbourhoods it is searched whole, in the images' precision, and the value is
    :func:`texture_report`'s (up to the rounding of a sum in another order); above, its mean is
    estimated from a stratified sample (:func:`_grid_sample`) searched in float32 (distances to
    about 1e-6, 1.3-2x faster), of ``_NOISE_GRID`` neighbourhoods for the noise's energy. The
    verbatim copy is measured on its whole stride-2 grid:
    by an exact search while that holds at most ``_VERDICT_GRID`` neighbourhoods (shared with the
    energy's when the grids are one), else from the energy's sample as seeds (:func:`_copy_from_seeds`).

    Exact shortcuts, not approximations: the tiled exemplar's neighbourhoods that cross no seam are
    exemplar neighbourhoods (distance 0), so only the crossing ones are searched, and when the
    output is at least as large as the exemplar the tiled exemplar holds every exemplar
    neighbourhood (completeness 0). The exemplar's neighbourhoods are searched once for the
    output's, the noise's and the tiled exemplar's queries together, and the baselines' metrics
    of an int seed are kept for the 16 most recent exemplars and sizes.

    >>> ex = np.random.default_rng(1).random((20, 20))
    >>> report, sampled = verdict_report(ex, ex, patch_size=4)
    >>> sorted(report.reference), sampled
    (['noise', 'tiled'], {'energy': (289, 289), 'completeness': (289, 289)})
    """
    out, ex = _pair(output, exemplar)
    size = _check_patch(ex, patch_size, "the exemplar")
    _check_patch(out, size, "the output")
    seed = int(rng) if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) else None
    gen = as_rng(rng)
    h, w = size
    dim = h * w * ex.shape[-1]
    default = max(1, h // 4)  # texture_energy's and completeness's "auto" stride
    energy_sample = _grid_sample(out.shape, size, default)
    complete_sample = _grid_sample(ex.shape, size, default)
    energy_dtype = None if energy_sample.weights is None else np.float32
    complete_dtype = None if complete_sample.weights is None else np.float32
    queries = _sample_vectors(out, size, energy_sample)
    ex_queries = _sample_vectors(ex, size, complete_sample)

    key = None if seed is None else (hashlib.sha256(ex.tobytes()).hexdigest(), ex.shape, ex.dtype.str,
                                     out.shape[:2], size, seed)
    reference = _VERDICT_BASELINES.get(key) if key is not None else None
    if reference is None:
        noise = noise_baseline(ex, out.shape[:2], rng=gen)
        tiled = tiled_baseline(ex, out.shape[:2])
        # tiled[y, x] = ex[y % H, x % W]: a neighbourhood that crosses no seam is the exemplar's own
        corners = energy_sample.corners
        crossing = ((corners[:, 0] % ex.shape[0]) + h > ex.shape[0]) | ((corners[:, 1] % ex.shape[1]) + w > ex.shape[1])
        noise_sample = energy_sample if energy_sample.weights is None else _grid_sample(
            out.shape, size, default, most=_NOISE_GRID)
        noise_queries = _sample_vectors(noise, size, noise_sample)
        searched = np.concatenate([queries, noise_queries, _sample_vectors(tiled, size, energy_sample)[crossing]])
        idx, dist = _nearest_in(ex, size, searched, energy_dtype)
        idx = idx[:len(queries)]
        dist, noise_dist, tiled_dist = np.split(dist, [len(queries), len(queries) + len(noise_queries)])
        if out.shape[0] >= ex.shape[0] and out.shape[1] >= ex.shape[1]:
            tiled_complete = 0.0  # tiled[:H, :W] is the exemplar
        else:
            tiled_complete = _sample_mean(_nearest_in(tiled, size, ex_queries, complete_dtype)[1], dim, complete_sample)
        noise_complete = _nearest_in(noise, size, ex_queries, complete_dtype)[1]
        reference = {
            "noise": {"energy": _sample_mean(noise_dist, dim, noise_sample),
                      "completeness": _sample_mean(noise_complete, dim, complete_sample),
                      "histogram": histogram_distance(noise, ex), "spectrum": spectrum_distance(noise, ex)},
            "tiled": {"energy": _sample_mean(tiled_dist, dim, energy_sample, where=crossing),
                      "completeness": tiled_complete,
                      "histogram": histogram_distance(tiled, ex), "spectrum": spectrum_distance(tiled, ex)},
        }
        if key is not None:
            _VERDICT_BASELINES[key] = reference
            while len(_VERDICT_BASELINES) > _VERDICT_BASELINES_KEPT:
                _VERDICT_BASELINES.pop(next(iter(_VERDICT_BASELINES)))  # the oldest
    else:
        idx, dist = _nearest_in(ex, size, queries, energy_dtype)

    if energy_sample.weights is None and default == _COPY_STRIDE:  # the verbatim copy's grid: the energy's search
        copied = _largest_copy(idx, dist, energy_sample.corners, energy_sample.cells, out.shape, ex.shape, size, 0.02)
    else:
        copy_sample = _grid_sample(out.shape, size, _COPY_STRIDE)
        if copy_sample.weights is None:  # a small grid: searched whole
            copy_idx, copy_dist = _nearest_in(ex, size, _sample_vectors(out, size, copy_sample))
            copied = _largest_copy(copy_idx, copy_dist, copy_sample.corners, copy_sample.cells, out.shape, ex.shape,
                                   size, 0.02)
        else:
            copied = _copy_from_seeds(out, ex, size, (idx, dist), energy_sample)
    values = {
        "energy": _sample_mean(dist, dim, energy_sample),
        "completeness": _sample_mean(_nearest_in(out, size, ex_queries, complete_dtype)[1], dim, complete_sample),
        "verbatim_copy": copied,
        "histogram": histogram_distance(out, ex),
        "spectrum": spectrum_distance(out, ex),
    }
    sampled = {name: (len(sample.corners), len(sample.corners) if sample.weights is None else int(sample.weights.sum()))
               for name, sample in (("energy", energy_sample), ("completeness", complete_sample))}
    return TextureReport(values=values, reference=copy.deepcopy(reference)), sampled
