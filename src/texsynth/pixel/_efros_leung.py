"""Efros-Leung non-parametric sampling: a texture grown pixel by pixel from a seed.

Efros & Leung (ICCV 1999) [1]_ model a texture as a Markov random field: the
value of a pixel, given its square window, is independent of the rest of the
image. Instead of estimating that conditional distribution, they sample it
directly: find every exemplar window that looks like the pixel's window where
the window is already known, and copy the centre of one of them. Steps:

1. Seed: a random 3x3 patch of the exemplar at the centre of the output
   (in hole filling, the known pixels are the seed).
2. Each pass takes the unfilled pixels that touch a filled one (one layer of
   the growing region), in random order sorted by decreasing number of known
   pixels in their window: "the texture grows in layers".
3. For each pixel, the known part of its ``w x w`` window ``T`` (mask ``M``)
   is compared with every exemplar window ``I_q`` by the Gaussian-weighted SSD
   normalised by the weight of the known pixels,

   .. math:: d(p, q) = \\frac{\\sum_u G_\\sigma(u) M(u) \\|T(u) - I_q(u)\\|^2}
                            {C \\sum_u G_\\sigma(u) M(u)}, \\qquad \\sigma = w / 6.4,

   (``C`` channels: the error is per value, so its threshold means the same
   in grey and colour).
4. Candidates: ``{q : d(p, q) <= (1 + ε) d_min(p)}``, ``ε = 0.1``
   (``error_tolerance``, the name image quilting gives the same rule);
   one is picked uniformly at random and its centre pixel copied.
5. MaxErrThreshold (the authors' pseudo-code [2]_): a pick is accepted only if
   its error is below ``max_error`` (0.3); if a whole pass accepts nothing,
   the threshold rises by 10 %.

The search is exhaustive (every exemplar window, every pixel): the masked
distances of a batch of pixels are one matrix product against the exemplar's
windows, the two products of ``sum M G (T - I)^2 = sum M G T^2 - 2 (M G T).I
+ (M G).I^2`` stacked (:class:`texsynth.core.search.MaskedIndex`). The pixels of one pass are
processed in *batches* chosen so that the result is the pseudo-code's, one
pixel at a time, in the pass's order: a pixel goes into the batch after the
latest earlier pixel of the pass that lies in its window, so it sees exactly
the pixels that were filled before it in the sequential order (and none
after). A pixel that knows a whole half-window (or quadrant) of its window
compares it on its own, at half the cost; ``search=Search(method="pca")``
compares it in a truncated PCA basis, the acceleration of the IPOL
implementation [3]_.

References
----------
.. [1] A. A. Efros and T. K. Leung, "Texture synthesis by non-parametric
   sampling", ICCV 1999, vol. 2, pp. 1033-1038.
   :doi:`10.1109/ICCV.1999.790383`
.. [2] A. A. Efros, "Efros-Leung algorithm: pseudo-code",
   https://people.eecs.berkeley.edu/~efros/research/NPS/alg.html
.. [3] C. Aguerrebere, Y. Gousseau and G. Tartavel, "Exemplar-based texture
   synthesis: the Efros-Leung algorithm", Image Processing On Line 3 (2013),
   pp. 223-241. :doi:`10.5201/ipol.2013.59`
"""

from __future__ import annotations

import numbers
import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ..core._progress import Progress
from ..core._validate import one_blas_thread
from ..core._validate import (
    as_binary_map,
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_group,
    check_memory,
    check_positive_float,
    restore_channels,
    with_channels,
)
from ..core.neighborhood import all_patches, gaussian_falloff, patches_within
from ..core.search import MASKED_METHODS, ExemplarAtlas, MaskedIndex, Search, is_auto

__all__ = ["EfrosLeungInfo", "Sampling", "efros_leung"]

#: sigma of the Gaussian weights is the window width over this (the pseudo-code's constants; IPOL too)
_SIGMA_DIVISOR = 6.4
#: a pass that fills nothing multiplies the error threshold by this (the pseudo-code's MaxErrThreshold * 1.1)
_THRESHOLD_GROWTH = 1.1
#: side of the seed patch (the paper's 3x3)
_SEED = 3


@dataclass
class EfrosLeungInfo:
    """Extra results of :func:`efros_leung`.

    Attributes
    ----------
    source : numpy.ndarray of int, shape (H, W, 2)
        The exemplar pixel ``(row, col)`` each output pixel was copied from
        (the centre of the chosen window, or the seed's pixel); ``-1`` for
        pixels given by ``target``. Shows verbatim copying: smooth runs of
        source positions are copied regions. Also ``coordinates`` (the name
        every method's info shares; ``weights`` is None).
    error : numpy.ndarray, shape (H, W)
        The normalised error ``d(p, q)`` of the window each pixel was copied
        from; NaN for the seed and given pixels.
    n_candidates : numpy.ndarray of int, shape (H, W)
        Size of each pixel's candidate set ``{q : d <= (1 + ε) d_min}``
        (0 for the seed and given pixels): 1 means a forced choice.
    layer : numpy.ndarray of int, shape (H, W)
        The pass that filled each pixel (0: seed or given).
    passes : int
        Growth passes run.
    batches : int
        Batches of pixels searched together (matrix products).
    max_error : float or None
        The error threshold at the end (``None`` if it was switched off).
    neighborhood_size : int
    sigma : float
    method : str
        ``"exact"`` or ``"pca"``.
    n_components : list of int
        The PCA dimension of each half-window and quadrant (``method="pca"``).
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``{"index": ..., "growth": ...}``: building the exemplar's window
        matrix (and PCA), and growing the output.
    """

    source: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2), int))
    error: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    n_candidates: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), int))
    layer: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), int))
    passes: int = 0
    batches: int = 0
    max_error: float | None = 0.3
    neighborhood_size: int = 11
    sigma: float = 11 / _SIGMA_DIVISOR
    method: str = "exact"
    n_components: list = field(default_factory=list)
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)

    @property
    def coordinates(self):
        """``source`` under the name every method's info shares: the source-coordinate map
        (``docs/conventions.md``) that :func:`texsynth.apply_coordinates` renders other channels through."""
        return self.source

    @property
    def weights(self):
        """None: every pixel is a copy."""
        return None


@dataclass(frozen=True)
class Sampling:
    """How Efros & Leung sample a pixel from the windows that match its own (their Sec. 2.1 and pseudo-code).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.Sampling(error_tolerance=0.2)
    Sampling(error_tolerance=0.2, max_error=0.3, sigma='auto')
    >>> texsynth.Sampling(error_tolerance=-1)
    Traceback (most recent call last):
    ...
    ValueError: error_tolerance must be a finite number >= 0, got -1.0

    The Gaussian weighting of the window distance, the tolerance that makes
    the candidate set, and the error a pick must stay below. An option
    group of :func:`efros_leung` (``sampling=Sampling(...)``); on the
    command line its fields are the flags ``--error-tolerance``,
    ``--max-error`` and ``--sigma``.

    Parameters
    ----------
    error_tolerance : float
        How much worse than the best window a candidate may be, as a
        fraction (default 0.1, the paper's). It is the paper's ``ε >= 0``:
        the candidates are the windows with ``d <= (1 + ε) d_min``. 0 keeps only the
        best match (and exact ties).
    max_error : float or None
        The pseudo-code's MaxErrThreshold (default 0.3): a pick whose error
        ``d`` (per value, intensities in [0, 1]) is not below it is left
        unfilled for a later pass; when a whole pass fills nothing the
        threshold rises by 10 %. None accepts every pick (the IPOL
        implementation).
    sigma : float or "auto"
        Width in pixels of the Gaussian weights of a window (``G_σ``). ``"auto"``
        (default): ``w / 6.4`` for the window width ``w``.
    """

    error_tolerance: float = 0.1
    max_error: object = 0.3
    sigma: object = "auto"

    def __post_init__(self):
        check_positive_float(self.error_tolerance, "error_tolerance", allow_zero=True, maximum=1e6)
        _check_max_error(self.max_error)
        if not is_auto(self.sigma):
            check_positive_float(self.sigma, "sigma")


# --------------------------------------------------------------------------- #
# validation
# --------------------------------------------------------------------------- #
def _check_window(neighborhood_size, exemplar_shape):
    w = neighborhood_size
    if not isinstance(w, numbers.Integral) or isinstance(w, bool):
        raise TypeError(f"neighborhood_size must be an odd integer >= 3 (the side of the square window), got {w!r}")
    w = int(w)
    if w < 3:
        raise ValueError(f"neighborhood_size must be an odd integer >= 3, got {w}; the paper's windows are 5 to 25")
    if w % 2 == 0:
        raise ValueError(f"neighborhood_size must be odd (the window is centred on the pixel), got {w}; "
                         f"pass {w - 1} or {w + 1}")
    h, wd = exemplar_shape
    if w > min(h, wd):
        raise ValueError(f"exemplar is {h}x{wd} but neighborhood_size={w} needs at least {w}x{w}; "
                         f"pass neighborhood_size <= {min(h, wd) - (1 - min(h, wd) % 2)} or a larger exemplar")
    return w


def _check_map(array, shape, name):
    """A binary (H, W) map: bool, or numbers that are all 0 or 1."""
    return as_binary_map(array, shape, name)


def _check_constraints(target, mask, size, channels, seed_center):
    """Known output pixels from ``target``/``mask`` (hole filling), or None for synthesis from a seed."""
    if target is None and mask is None:
        return None, None
    if target is None:
        raise ValueError("mask was given without target; pass target=image holding the known values")
    if mask is None:
        raise ValueError("target was given without mask, so every pixel would be known and nothing synthesised; "
                         "pass mask=known (True where target is known, False in the hole)")
    values, _ = with_channels(as_image(target, "target"))
    if values.shape[:2] != tuple(size) or values.shape[-1] != channels:
        want = tuple(size) + ((channels,) if channels > 1 else ())
        raise ValueError(f"target must have the output's shape {want} (channels as the exemplar), "
                         f"got shape {np.shape(target)}")
    known = _check_map(mask, size, "mask")
    if not known.any():
        raise ValueError("mask marks no known pixel; pass mask=None (and no target) to grow the output from a seed")
    if not is_auto(seed_center):
        raise ValueError("seed_center is for synthesis from a seed; with mask, the known pixels are the seed: "
                         "leave seed_center='auto'")
    return values, known


def _check_seed_center(seed_center, size):
    if is_auto(seed_center):
        return size[0] // 2, size[1] // 2
    try:
        r, c = seed_center
    except (TypeError, ValueError):
        raise TypeError(f"seed_center must be a pair (row, col) of ints, got {seed_center!r}") from None
    if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in (r, c)):
        raise TypeError(f"seed_center must be a pair (row, col) of ints, got {seed_center!r}")
    if not (0 <= r < size[0] and 0 <= c < size[1]):
        raise ValueError(f"seed_center={tuple(seed_center)} lies outside the output of size {tuple(size)}; "
                         f"pass a (row, col) with 0 <= row < {size[0]} and 0 <= col < {size[1]}")
    return int(r), int(c)


def _check_max_error(max_error):
    if max_error is None:
        return None
    return check_positive_float(max_error, "max_error")


# --------------------------------------------------------------------------- #
# the exemplar's windows
# --------------------------------------------------------------------------- #
def _blocks(w, channels):
    """Dimensions a growing pixel often knows whole: the four half-windows, then the four quadrants.

    A pixel on a side of the grown region knows the half-window towards it,
    one at a corner the quadrant; each is compared on its own (in PCA, the
    IPOL acceleration [3]_), the rest of the known pixels by the masked product.
    """
    t = w // 2
    dims = np.arange(w * w * channels).reshape(w, w, channels)
    halves = [dims[:t], dims[t + 1:], dims[:, :t], dims[:, t + 1:]]
    quadrants = [dims[:t, :t], dims[:t, t + 1:], dims[t + 1:, :t], dims[t + 1:, t + 1:]]
    return [b.ravel() for b in halves + quadrants]


def _exemplar_windows(ex, allowed, w):
    """Every window that lies inside the exemplar and on allowed pixels: vectors ``(N, w*w*C)`` and centres."""
    t = w // 2
    inside = patches_within(allowed, w)  # one flag per window, by its top-left corner
    corners = np.argwhere(inside)
    if corners.shape[0] == 0:
        raise ValueError(f"exemplar_mask leaves no {w}x{w} window of the exemplar whose pixels are all allowed; "
                         "pass a smaller neighborhood_size or allow more pixels")
    vectors = all_patches(ex, w)[inside].reshape(corners.shape[0], -1)
    return vectors, corners + t


# --------------------------------------------------------------------------- #
# growth
# --------------------------------------------------------------------------- #
def _window_counts(known, w):
    """Known pixels in the window of every output pixel (a summed-area table of the padded ``known``)."""
    s = np.zeros((known.shape[0] + 1, known.shape[1] + 1), np.int32)
    np.cumsum(np.cumsum(known, axis=0, dtype=np.int32), axis=1, out=s[1:, 1:])
    return s[w:, w:] - s[:-w, w:] - s[w:, :-w] + s[:-w, :-w]


def _batches(rows, cols, shape, w, size=None):
    """Batch number of each pixel of a pass, in pass order: one more than the latest earlier pixel in its window.

    Pixels of one batch lie outside each other's windows, and each sees exactly
    the pixels before it in the pass order: batch by batch is one at a time.
    ``size``: the output's, for toroidal windows (None: windows end at the border).
    """
    t = w // 2
    out = np.empty(len(rows), np.int32)
    if size is not None:  # toroidal: the window of (r, c) wraps
        latest = np.zeros(size, np.int32)
        around = np.arange(-t, t + 1)
        for i, (r, c) in enumerate(zip(rows.tolist(), cols.tolist())):
            out[i] = latest[np.ix_((r + around) % size[0], (c + around) % size[1])].max() + 1
            latest[r, c] = out[i]
        return out
    latest = np.zeros(shape, np.int32)  # padded coordinates: the window of (r, c) is latest[r:r+w, c:c+w]
    for i, (r, c) in enumerate(zip(rows.tolist(), cols.tolist())):
        out[i] = latest[r:r + w, c:c + w].max() + 1
        latest[r + t, c + t] = out[i]
    return out


class _Canvas:
    """The output padded by half a window of unknown pixels, with what the info reports per pixel.

    ``tileable``: the padding holds copies of the opposite side (written with every pixel), so every window
    is toroidal."""

    def __init__(self, size, channels, dtype, w, tileable=False):
        t = w // 2
        h, wd = size
        self.w, self.t, self.size, self.tileable = w, t, (h, wd), tileable
        self.image = np.zeros((h + 2 * t, wd + 2 * t, channels), dtype)
        self.known = np.zeros((h + 2 * t, wd + 2 * t), bool)
        self.inner = (slice(t, t + h), slice(t, t + wd))
        self.windows = all_patches(self.image, w)  # views: they follow every write
        self.known_windows = all_patches(self.known[..., None], w)
        self.source = np.full((h, wd, 2), -1, np.int64)
        self.error = np.full((h, wd), np.nan)
        self.n_candidates = np.zeros((h, wd), np.int64)
        self.layer = np.zeros((h, wd), np.int64)

    def set(self, rows, cols, values):
        """Write known values at output pixels ``(rows, cols)`` (and at their copies in a toroidal padding)."""
        (h, wd) = self.size
        shifts = [(dr, dc) for dr in (-h, 0, h) for dc in (-wd, 0, wd)] if self.tileable else [(0, 0)]
        for dr, dc in shifts:
            pr, pc = rows + self.t + dr, cols + self.t + dc
            on = (pr >= 0) & (pr < self.known.shape[0]) & (pc >= 0) & (pc < self.known.shape[1])
            self.image[pr[on], pc[on]] = values[on]
            self.known[pr[on], pc[on]] = True

    def layer_pixels(self):
        """The unfilled pixels touching a filled one (8-neighbours) and their known pixels per window."""
        inner = self.known[self.inner]
        if self.tileable:  # the padding's copies are the wrapped neighbours
            front = ndimage.binary_dilation(self.known, np.ones((3, 3), bool))[self.inner] & ~inner
        else:
            front = ndimage.binary_dilation(inner, np.ones((3, 3), bool)) & ~inner
        rows, cols = np.nonzero(front)
        return rows, cols, _window_counts(self.known, self.w)[rows, cols]


@dataclass(frozen=True)
class _Search:
    """What every pixel is matched against: the exemplar's windows, their centres, the weights and ε."""

    index: MaskedIndex
    exemplar: np.ndarray  # (h, w, C)
    centers: np.ndarray  # (N, 2) exemplar pixel at the centre of each indexed window
    gauss: np.ndarray  # (w, w) G_sigma
    error_tolerance: float


def _fill(canvas, search, rows, cols, u, threshold, layer):
    """Fill one batch (none in another's window); returns how many were accepted."""
    m, channels = rows.size, search.exemplar.shape[-1]
    queries = canvas.windows[rows, cols].reshape(m, -1)
    known = canvas.known_windows[rows, cols]  # (m, w, w, 1)
    mask = np.broadcast_to(known, known.shape[:3] + (channels,)).reshape(m, -1)
    idx, d2, _, count = search.index.near_best(queries, mask, search.error_tolerance, u)
    error = d2 / (channels * np.einsum("mij,ij->m", known[..., 0], search.gauss))
    ok = slice(None) if threshold is None else error < threshold
    rows, cols, idx = rows[ok], cols[ok], idx[ok]
    src = search.centers[idx]
    canvas.set(rows, cols, search.exemplar[src[:, 0], src[:, 1]])
    canvas.source[rows, cols] = src
    canvas.error[rows, cols] = error[ok]
    canvas.n_candidates[rows, cols] = count[ok]
    canvas.layer[rows, cols] = layer
    return rows.size


def _grow(canvas, search, max_error, rng, bar):
    """The pseudo-code's GrowImage: passes over the layer of unfilled pixels until the output is full."""
    threshold, passes, batches = max_error, 0, 0
    while True:
        rows, cols, counts = canvas.layer_pixels()
        if rows.size == 0:
            return threshold, passes, batches
        passes += 1
        # randomly permuted, then sorted by decreasing number of known pixels in the window
        perm = rng.permutation(rows.size)
        order = perm[np.argsort(-counts[perm], kind="stable")]
        rows, cols = rows[order], cols[order]
        u = rng.random(rows.size)  # the random pick of each pixel, in pass order
        batch = _batches(rows, cols, canvas.known.shape, canvas.w, canvas.size if canvas.tileable else None)
        filled = 0
        for b in range(1, int(batch.max()) + 1):
            sel = batch == b
            filled += _fill(canvas, search, rows[sel], cols[sel], u[sel], threshold, passes)
        batches += int(batch.max())
        if filled == 0:  # no pixel of the pass was good enough: accept worse matches
            threshold *= _THRESHOLD_GROWTH
        bar.advance({"pass": passes} if threshold is None else {"pass": passes, "max_error": threshold}, n=filled)


def _plant_seed(canvas, exemplar, allowed, center, rng):
    """A random 3x3 patch of the exemplar (allowed pixels only) centred at ``center``, clipped to the output."""
    corners = np.argwhere(patches_within(allowed, _SEED))
    if corners.shape[0] == 0:
        raise ValueError("exemplar_mask leaves no 3x3 patch of allowed exemplar pixels for the seed; allow more pixels")
    top = corners[rng.integers(corners.shape[0])]
    d = np.arange(_SEED) - _SEED // 2
    rows, cols = (a.ravel() for a in np.meshgrid(center[0] + d, center[1] + d, indexing="ij"))
    src = np.stack([rows - center[0], cols - center[1]], axis=1) + top + _SEED // 2
    inside = (rows >= 0) & (rows < canvas.source.shape[0]) & (cols >= 0) & (cols < canvas.source.shape[1])
    rows, cols, src = rows[inside], cols[inside], src[inside]
    canvas.set(rows, cols, exemplar[src[:, 0], src[:, 1]])
    canvas.source[rows, cols] = src


def _check_memory(ex_shape, channels, itemsize, w, size):
    n = (ex_shape[0] - w + 1) * (ex_shape[1] - w + 1)
    dim = w * w * channels
    # the windows (1), the stacked [v | v^2] (2), the half-windows (2) and quadrants (1), exact or fewer in PCA
    per_vector = dim * itemsize * 6
    check_memory(float(n) * per_vector, w, "neighborhood_size", "the exemplar's windows",
                 also={"exemplar": f"{ex_shape[0]}x{ex_shape[1]}"})
    t = w // 2
    per_pixel = channels * itemsize + 1 + 4 + 16 + 8 + 8 + 8 + 16  # image, known, counts, source, error, ...
    check_memory(float(size[0] + 2 * t) * (size[1] + 2 * t) * per_pixel, size)


# --------------------------------------------------------------------------- #
# public
# --------------------------------------------------------------------------- #
def efros_leung(exemplar, size, *, neighborhood_size=11, sampling=Sampling(), seed_center="auto", mask=None,
                target=None, exemplar_mask=None, search=Search(), tileable=False, rng=None, progress=False,
                return_info=False):
    """Efros-Leung texture synthesis by non-parametric sampling: grow the output pixel by pixel.

    Examples
    --------
    >>> import texsynth
    >>> exemplar = texsynth.data.load("bread")[:20, :20]
    >>> out = texsynth.efros_leung(exemplar, 16, neighborhood_size=5, rng=0)
    >>> out.shape, out.dtype
    ((16, 16, 3), dtype('float64'))

    Grows the output pixel by pixel from a 3x3 seed: each pixel at the
    growth front copies the centre of an exemplar window drawn at random
    among those that match its known neighbours (Gaussian-weighted) within
    a tolerance of the best match [1]_.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` grey or ``(h, w, C)`` sample texture, any accepted dtype.
    size : int or (int, int)
        Output ``(height, width)``.
    neighborhood_size : int
        The window width ``w``, odd, >= 3: the paper's one parameter, "the
        scale of the largest regular feature" of the texture. Small windows
        give random outputs that keep only small-scale structure; large ones
        copy bigger regions (the paper's Figure 2: 5, 11, 15, 23). Default 11.
    sampling : Sampling
        How a pixel is sampled from the matching windows (:class:`Sampling`):
        the candidates within ``error_tolerance`` (ε = 0.1) of the best, the
        MaxErrThreshold ``max_error`` (0.3) and the Gaussian ``sigma``
        (``w / 6.4``), the paper's and its pseudo-code's values.
    seed_center : (int, int) or "auto"
        Output pixel ``(row, col)`` at which the 3x3 seed is placed (clipped
        to the output at its borders). ``"auto"`` (default): the centre, as
        in the paper. Not with ``mask``: then the known pixels are the seed.
    mask : array_like of bool, optional
        Hole filling: white (True) where ``target`` is known (kept
        unchanged), black (False) in the hole (synthesised); ``(H, W)``.
        Requires ``target``.
    target : array_like, optional
        ``(H, W[, C])`` the image with the hole, as the exemplar's channels.
    exemplar_mask : array_like of bool, optional
        ``(h, w)`` exemplar pixels that may be copied: windows touching a
        False pixel are never used (e.g. the hole, when the exemplar is the
        image being filled).
    search : Search
        The masked search (:class:`~texsynth.core.search.Search`), whose
        ``method`` is :class:`~texsynth.core.search.MaskedIndex`'s:
        ``"exact"`` (and ``"auto"``, default): every masked distance
        computed in full. ``"pca"``: a pixel that knows a whole half-window
        (or quadrant) compares it in a PCA basis keeping 99 % of its
        variance, the rest exactly: the IPOL acceleration [3]_, 1.6x faster,
        visually alike (see Notes). Every exemplar window is a candidate
        (``candidates`` ``"all"`` or ``"auto"``; ``k`` is not used).
        ``augment``: the windows of the exemplar's flipped or rotated copies
        are candidates too (``source`` still points into the exemplar).
    tileable : bool
        Toroidal output: a window that crosses the output's border continues
        on the opposite side (the known pixels there count, the growth front
        wraps), so the output tiles seamlessly. Needs an output at least
        ``neighborhood_size`` in both directions. Default False: positions
        outside the output are unknown, as in the paper.
    rng : None, int or numpy.random.Generator
        Seeds the seed patch, the order of each pass and the random picks.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``
        with step counted in filled pixels.
    return_info : bool
        Also return an :class:`EfrosLeungInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channel layout and dtype. Every pixel is
        a copy of an exemplar pixel (or of ``target`` where ``mask``).
    info : EfrosLeungInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an even, non-positive or too large ``neighborhood_size``, a
        negative ``error_tolerance``, a ``seed_center`` outside the output, a
        ``mask``/``target`` of another shape than the output, a non-binary
        mask, NaN or infinite values, or an exemplar or output that does not
        fit in memory (checked before anything is allocated).

    Notes
    -----
    Candidate windows lie wholly inside the exemplar (and on
    ``exemplar_mask``); the output is not periodic unless ``tileable``:
    window positions outside it count as unknown.

    *Order.* Each pass is the pseudo-code's [2]_ list: the unfilled pixels
    with a filled 8-neighbour, randomly permuted, then sorted by decreasing
    number of known pixels in their ``w x w`` window (the pseudo-code says
    "filled neighbor pixels"; counting over the window is this
    implementation's reading). The list is processed in batches that give
    exactly the one-at-a-time result (see the module notes); a pixel whose
    pick is rejected by ``max_error`` stays unknown for the rest of the pass.

    *What could not be checked against the paper text.* The paper itself was
    not at hand: σ = w/6.4, MaxErrThreshold = 0.3 and its 10 % growth come
    from the authors' pseudo-code page [2]_ (σ = w/6.4 is also the IPOL
    code's); the paper's own choice may weight the random pick by the
    distance, where this implementation (like the pseudo-code and IPOL)
    picks uniformly; the error is normalised per value (divided by the
    number of channels) so that 0.3 means the same in grey and colour,
    which the pseudo-code (grey) does not need to say.

    Cost: every pixel is compared with every exemplar window,
    ``O(H W h w w²)``: 2.5 s (PCA 1.6 s) for 64² -> 128² colour with
    w = 11 (``benchmarks/bench_efros_leung.py``). The products are small, so
    they run on one BLAS thread.

    The default :class:`Sampling` is the paper's (``error_tolerance=0.1``),
    and a seed reproduces the output:

    >>> sampling = texsynth.Sampling(error_tolerance=0.1)
    >>> bool(np.array_equal(out, texsynth.efros_leung(exemplar, 16, neighborhood_size=5, sampling=sampling, rng=0)))
    True

    Hole filling: the known pixels stay, the hole is grown from its rim.

    >>> import numpy as np
    >>> image = texsynth.data.load("bread")[:24, :24]
    >>> known = np.ones((24, 24), bool)
    >>> known[8:16, 8:16] = False
    >>> filled = texsynth.efros_leung(image, (24, 24), neighborhood_size=5, target=image, mask=known,
    ...                               exemplar_mask=known, rng=0)
    >>> bool(np.array_equal(filled[known], image[known]))
    True

    References
    ----------
    .. [1] A. A. Efros and T. K. Leung, "Texture synthesis by non-parametric
       sampling", ICCV 1999, vol. 2, pp. 1033-1038.
       :doi:`10.1109/ICCV.1999.790383`
    .. [2] A. A. Efros, "Efros-Leung algorithm" (pseudo-code),
       https://people.eecs.berkeley.edu/~efros/research/NPS/alg.html
    .. [3] C. Aguerrebere, Y. Gousseau and G. Tartavel, "Exemplar-based
       texture synthesis: the Efros-Leung algorithm", Image Processing On
       Line 3 (2013), pp. 223-241. :doi:`10.5201/ipol.2013.59`
    """
    start = time.perf_counter()
    ex, grey = with_channels(as_image(exemplar, "exemplar"))
    size = as_size(size)
    w = _check_window(neighborhood_size, ex.shape[:2])
    sampling = check_group(sampling, Sampling, "sampling")
    error_tolerance, max_error = sampling.error_tolerance, _check_max_error(sampling.max_error)
    sigma = w / _SIGMA_DIVISOR if is_auto(sampling.sigma) else check_positive_float(sampling.sigma, "sigma")
    search = check_group(search, Search, "search")
    method = search.method
    if not isinstance(method, str) or method not in MASKED_METHODS:
        raise ValueError(f"method must be one of {', '.join(map(repr, MASKED_METHODS))}, got {method!r}")
    if search.resolved_candidates("all") != "all" or not is_auto(search.k):
        raise ValueError(f"efros_leung compares every exemplar window (its candidates are those within "
                         f"error_tolerance of the best); pass search=Search(method=...) with candidates='all' and "
                         f"k='auto', got candidates={search.candidates!r}, k={search.k!r}")
    method = "exact" if method == "auto" else method
    channels = ex.shape[-1]
    values, known = _check_constraints(target, mask, size, channels, seed_center)
    center = _check_seed_center(seed_center, size) if known is None else None
    if check_bool(tileable, "tileable") and min(size) < w:
        raise ValueError(f"tileable output of size {tuple(size)} is smaller than the {w}x{w} window, which would "
                         f"wrap onto itself; pass a size of at least {w} or a smaller neighborhood_size")
    allowed = np.ones(ex.shape[:2], bool) if exemplar_mask is None else _check_map(exemplar_mask, ex.shape[:2],
                                                                                  "exemplar_mask")
    atlas = None if search.augment == "none" else ExemplarAtlas(ex.shape[:2], search.augment)
    if atlas is not None:  # Search(augment=...): the windows of the exemplar's flipped and rotated copies too
        ex, allowed = atlas.apply(ex, valid=allowed)
    rng = as_rng(rng)
    _check_memory(ex.shape[:2], channels, ex.itemsize, w, size)

    # one BLAS thread: the products have a few rows each (one batch of a pass, split by block), where a
    # second thread gains little and, on a machine whose other core is busy, loses much: 64^2 -> 128^2 colour
    # took 3.3 s on one thread and 2.3-28 s on two with one core taken by another process (also the PCA build)
    with one_blas_thread():
        vectors, centers = _exemplar_windows(ex, allowed, w)
        gauss = gaussian_falloff(w, sigma).astype(ex.dtype)
        index = MaskedIndex(vectors, weights=np.repeat(gauss.ravel(), channels), method=method,
                            blocks=_blocks(w, channels), rng=rng)
        windows = _Search(index, ex, centers, gauss, error_tolerance)
        t_index = time.perf_counter()
        canvas = _Canvas(size, channels, ex.dtype, w, tileable)
        if known is None:
            _plant_seed(canvas, ex, allowed, center, rng)
        else:
            rows, cols = np.nonzero(known)
            canvas.set(rows, cols, values[rows, cols])
        todo = int(size[0] * size[1] - canvas.known.sum())
        with Progress(progress, todo, "Efros-Leung") as bar:
            threshold, passes, batches = _grow(canvas, windows, max_error, rng, bar)
    out = restore_channels(canvas.image[canvas.inner].copy(), grey)
    if not return_info:
        return out
    now = time.perf_counter()
    source = canvas.source if atlas is None else np.where(  # augmented: the exemplar pixels the copies show
        canvas.source >= 0, atlas.to_exemplar(np.maximum(canvas.source, 0)), -1)
    info = EfrosLeungInfo(source=source, error=canvas.error, n_candidates=canvas.n_candidates,
                          layer=canvas.layer, passes=passes, batches=batches, max_error=threshold,
                          neighborhood_size=w, sigma=sigma, method=method, n_components=index.n_components,
                          seconds=now - start, stage_seconds={"index": t_index - start, "growth": now - t_index})
    return out, info
