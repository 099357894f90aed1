"""Heeger-Bergen pyramid-based texture synthesis (Heeger & Bergen 1995).

A texture is described by first-order statistics only: the histogram of its
pixel values and the histogram of every sub-band of its steerable pyramid.
Synthesis starts from white noise and alternates histogram matching in the
image domain and in the pyramid domain (section 3 of the paper)::

    J <- noise;  J <- match(J, I)                          (initialisation)
    repeat `iterations` times:
        pyramid(J) -> (high-pass, oriented bands, low-pass)
        every sub-band of J <- match(sub-band of J, same sub-band of I)
        J <- reconstruct(pyramid(J));  J <- match(J, I)

This module follows the IPOL description of Briand, Vacher, Galerne & Rabin
(2014): the steerable pyramid is the FFT-based one (periodic output), colour
images are decorrelated by a principal component analysis of the exemplar's
colours and every component is synthesised independently, outputs may have
any size, and non-periodic exemplars are first replaced by the periodic
component of their periodic-plus-smooth decomposition (Moisan 2011), which
removes the spurious horizontal and vertical structures that the border
discontinuity adds to the spectrum.

Histogram matching ("match") is quantile matching: the values of the array
to modify keep their ranks and receive the reference's quantile function
sampled at their rank; arrays of different sizes are handled by linear
interpolation of the reference's sorted values (:func:`match_histogram`).

References
----------
.. [1] D. J. Heeger and J. R. Bergen, "Pyramid-based texture analysis/synthesis",
   SIGGRAPH 1995, 229-238. doi:10.1145/218380.218446
.. [2] T. Briand, J. Vacher, B. Galerne and J. Rabin, "The Heeger & Bergen pyramid
   based texture synthesis algorithm", Image Processing On Line 4 (2014), 276-299.
   doi:10.5201/ipol.2014.79
.. [3] L. Moisan, "Periodic plus smooth image decomposition", J. Math. Imaging Vis.
   39(2), 2011. doi:10.1007/s10851-010-0227-1
"""

from __future__ import annotations

import queue
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS
from ..core._validate import (as_image, as_rng, as_size, check_memory, check_positive_int, max_threads,
                              restore_channels, with_channels)
from ..core.color import color_pca
from ..core.histogram import match_histogram, match_to_targets, quantile_targets
from ..core.pyramid import SteerablePyramid, max_scales, periodic_smooth_decomposition

__all__ = ["heeger_bergen", "HeegerBergenInfo", "match_histogram"]

PERIODIC_EXEMPLAR = ("periodic+smooth", "mirror", "none")


# --------------------------------------------------------------------------- info and progress
@dataclass
class HeegerBergenInfo:
    """Diagnostics of :func:`heeger_bergen`.

    Attributes
    ----------
    band_names : list of str
        ``"highpass"``, ``"scale s orientation k"`` ..., ``"lowpass"``.
    band_distances : numpy.ndarray
        Shape ``(iterations + 1, len(band_names))``: 1-Wasserstein distance
        between each sub-band histogram of the output and the exemplar's,
        divided by the exemplar band's standard deviation and averaged over
        colour components. Row 0 is the histogram-matched noise that starts
        the synthesis, row ``i`` the output after iteration ``i``.
    color_basis : numpy.ndarray
        ``(C, C)`` principal axes of the exemplar's colours (columns); the
        identity up to sign for grey images.
    color_mean : numpy.ndarray
        ``(C,)`` mean colour of the exemplar.
    scales, orientations : int
    periodic_exemplar : str
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of each decorrelated colour component (``"component 0"``,
        ...; they run in parallel).
    """

    band_names: list
    band_distances: np.ndarray
    color_basis: np.ndarray
    color_mean: np.ndarray
    scales: int
    orientations: int
    periodic_exemplar: str
    extra: dict = field(default_factory=dict)
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


# --------------------------------------------------------------------------- the algorithm
def _analysis_image(component, periodic_exemplar):
    """The image whose pyramid is analysed (Briand et al. 2014, sec. 2.4)."""
    if periodic_exemplar == "periodic+smooth":
        return periodic_smooth_decomposition(component)[0]
    if periodic_exemplar == "mirror":
        doubled = np.concatenate([component, component[::-1]], axis=0)
        return np.concatenate([doubled, doubled[:, ::-1]], axis=1)
    return component


def _check_scales(scales, shape, what):
    most = max_scales(shape)
    if scales > most:
        need = 2 ** (scales + 2) if scales < 60 else float("inf")  # no trillion-bit integers in a message
        fix = f"pass scales <= {most} or " if most >= 1 else "pass "
        name = "size" if what == "output" else what
        raise ValueError(
            f"scales={scales} needs the {what} to be at least {need} pixels along each axis, but {name} is "
            f"{shape[0]}x{shape[1]}; {fix}a larger {name} (at least {need}x{need}; 1 scale needs 8x8)"
        )


def heeger_bergen(exemplar, size=None, *, scales=4, orientations=4, iterations=5,
                  periodic_exemplar="periodic+smooth", rng=None, progress=False, return_info=False):
    """Synthesise a texture by pyramid histogram matching (Heeger & Bergen 1995).

    Examples
    --------
    >>> import texsynth
    >>> exemplar = texsynth.data.load("metal")[:64, :64]
    >>> out, info = texsynth.heeger_bergen(exemplar, (48, 80), scales=2, iterations=2, rng=0, return_info=True)
    >>> out.shape, out.dtype
    ((48, 80), dtype('float64'))

    Starting from white noise, matches the histogram of the image and of
    every sub-band of its steerable pyramid to the exemplar's, again and
    again, so the output shares the exemplar's marginal statistics at every
    scale and orientation [1]_ (colour as Briand et al. [2]_).

    Parameters
    ----------
    exemplar : array_like
        Grey ``(H, W)`` or colour ``(H, W, C)`` texture (uint8, uint16 or
        float in [0, 1]).
    size : int or (int, int), optional
        Output ``(height, width)``; default the exemplar's size. Any size
        works (not only powers of two) as long as ``scales`` fits in it.
    scales : int
        Number of pyramid scales (the paper uses 4, with 4 orientations).
        Both the exemplar and the output need at least ``2^(scales+2)``
        pixels along each axis.
    orientations : int
        Number of orientations of the steerable pyramid (4 in the paper).
    iterations : int
        Number of analysis/synthesis loops. The paper and Briand et al. report
        that about 5 suffice; further iterations barely change the result.
    periodic_exemplar : {"periodic+smooth", "mirror", "none"}
        How the (generally non-periodic) exemplar is analysed by the periodic
        FFT pyramid:

        ``"periodic+smooth"`` (default, Briand et al. 2014)
            the periodic component of Moisan's decomposition: no border
            discontinuity, so no spurious horizontal/vertical frequencies;
        ``"mirror"`` (the original algorithm)
            the exemplar mirrored into a ``2H x 2W`` symmetric, periodic
            image; the reflections add a little symmetric structure;
        ``"none"``
            the exemplar as it is, wrapped around: the border jump puts a
            cross in its spectrum that the output imitates with horizontal and
            vertical streaks. Use it for exemplars that already tile.

        The image-domain histogram is always the exemplar's own.
    rng : None, int or numpy.random.Generator
        Seed of the initial white noise.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``
        after every iteration of every colour component with ``info =
        {"component", "iteration", "band_distance"}`` (the mean normalised
        distance of the sub-band histograms to the exemplar's).
    return_info : bool
        Also return a :class:`HeegerBergenInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channels, in [0, 1], the exemplar's
        float dtype. The output is periodic (it tiles seamlessly).
    info : HeegerBergenInfo
        Only if ``return_info=True``.

    Raises
    ------
    ValueError
        If ``scales`` does not fit in the exemplar or the output (the message
        gives the sizes that work), if ``iterations < 1``, for an unknown
        ``periodic_exemplar``, or for an exemplar with NaN/inf values.

    Notes
    -----
    Histogram matching of an array ``x`` to a reference ``y`` (the "match-
    Histogram" of the paper's fig. 3) is quantile matching: with ``F_y^{-1}``
    the reference's quantile function, the entry of rank ``k`` among ``n``
    becomes ``F_y^{-1}((k + 1/2) / n)``. It is applied to the image and to
    every sub-band of the steerable pyramid (high-pass residual, ``scales x
    orientations`` oriented bands, low-pass residual), with the pyramid of
    :class:`texsynth.core.pyramid.SteerablePyramid` (a tight frame, so
    reconstruction is exact). In the example above the sub-bands'
    histogram distances fell:

    >>> info.band_distances.shape  # (noise + 2 iterations) x (high-pass + 2x4 bands + low-pass)
    (3, 10)
    >>> bool(info.band_distances[-1].mean() < 0.2 * info.band_distances[0].mean())
    True

    Colour (Briand et al. 2014, sec. 3.3): with ``X`` the exemplar's
    mean-free colours and ``X^T X / N = V diag(l) V^T``, every component of
    ``X V`` is synthesised as a grey texture and the result is mapped back
    with ``V^T`` and the mean, then clipped to [0, 1].

    What it can and cannot do: stochastic, homogeneous textures (sand,
    gravel, metal, bark) come out well; anything with structure beyond
    marginal statistics (bricks, text, weaves, objects) does not: the
    histograms match, but edges do not line up and the structure dissolves
    into blobs (the "Failures" of Heeger & Bergen's paper).

    References
    ----------
    .. [1] D. J. Heeger and J. R. Bergen, "Pyramid-based texture analysis/
       synthesis", SIGGRAPH 1995. doi:10.1145/218380.218446
    .. [2] T. Briand, J. Vacher, B. Galerne and J. Rabin, "The Heeger & Bergen
       pyramid based texture synthesis algorithm", IPOL 4, 2014.
       doi:10.5201/ipol.2014.79
    """
    t_start = time.perf_counter()
    ex = as_image(exemplar, "exemplar")
    dtype = ex.dtype
    ex, grey = with_channels(ex.astype(np.float64, copy=False))
    shape = ex.shape[:2] if size is None else as_size(size)
    scales = check_positive_int(scales, "scales", minimum=1)
    orientations = check_positive_int(orientations, "orientations", minimum=1)
    iterations = check_positive_int(iterations, "iterations", minimum=1, maximum=MAX_ITERATIONS)
    if not isinstance(periodic_exemplar, str) or periodic_exemplar not in PERIODIC_EXEMPLAR:
        raise ValueError(f"periodic_exemplar must be one of {PERIODIC_EXEMPLAR}, got {periodic_exemplar!r}")
    _check_scales(scales, ex.shape[:2], "exemplar")
    _check_scales(scales, shape, "output")
    # per colour component in flight: the output's pyramid (about 4/3 of the image per orientation,
    # plus the high- and low-pass) and its complex FFTs
    check_memory(float(shape[0]) * shape[1] * min(ex.shape[-1], max_threads()) * 16 * (2 * scales * orientations + 8),
                 tuple(shape), also={"orientations": orientations})
    gen = as_rng(rng)

    # Colour decorrelation by PCA of the exemplar's colours (Briand et al. 2014, sec. 3.3).
    channels = ex.shape[-1]
    pixels = ex.reshape(-1, channels)
    mean, basis = color_pca(pixels)  # principal component first
    components = (basis.T @ (pixels - mean).T).reshape((channels,) + ex.shape[:2])  # (C, H, W), contiguous

    analysis_shape = _analysis_image(components[0], periodic_exemplar).shape
    pyr_ex = SteerablePyramid(analysis_shape, scales, orientations)
    pyr_out = pyr_ex if analysis_shape == shape else SteerablePyramid(shape, scales, orientations)
    names = (["highpass"] + [f"scale {s} orientation {k}" for s in range(scales) for k in range(orientations)]
             + ["lowpass"])
    n_out = shape[0] * shape[1]
    out_sizes = [int(np.prod(b)) for b in pyr_out.array_shapes()]
    noise = gen.standard_normal((channels,) + shape)
    measure = return_info or progress not in (False, None)
    if measure:  # one row of band distances per iteration
        check_memory(8.0 * (iterations + 1) * len(names), iterations, "iterations", "the band distances")
    def synthesize(c, advance):
        """One decorrelated component: the loop of Heeger & Bergen's Figure on its own pyramid."""
        t0 = time.perf_counter()
        distances = np.zeros((iterations + 1, len(names)))
        # Analysis: the exemplar's sorted values resampled to the output's sizes, once.
        pixel_targets = quantile_targets(np.sort(components[c].ravel()), n_out)
        ex_bands = pyr_ex.decompose(_analysis_image(components[c], periodic_exemplar)).arrays()
        band_targets = [quantile_targets(np.sort(b.ravel()), n) for b, n in zip(ex_bands, out_sizes)]
        band_scale = np.array([max(float(b.std()), 1e-12) for b in ex_bands])

        out, _ = match_to_targets(noise[c], pixel_targets, False)  # J <- match(noise, I)
        for it in range(iterations + 1):
            if it == iterations and not measure:
                break
            coeffs = pyr_out.decompose(out)  # pyramid(J)
            matched = [match_to_targets(a, t, measure) for a, t in zip(coeffs.arrays(), band_targets)]
            distance = np.array([d for _, d in matched]) / band_scale  # histograms of J before matching
            distances[it] = distance
            if it > 0:
                advance({"component": c, "iteration": it, "band_distance": float(distance.mean())})
            if it == iterations:
                break  # this decomposition only measured the final output
            # every sub-band of J <- match(sub-band of J, sub-band of I)
            bands = [m for m, _ in matched]
            coeffs.highpass, coeffs.lowpass = bands[0], bands[-1]
            coeffs.bands = [bands[1 + s * orientations : 1 + (s + 1) * orientations] for s in range(scales)]
            out, _ = match_to_targets(pyr_out.reconstruct(coeffs), pixel_targets, False)  # J <- match(J, I)
        return out, distances, time.perf_counter() - t0

    with Progress(progress, channels * iterations, "Heeger-Bergen") as bar:
        # The components are independent (that is what the PCA is for): they run on up to one
        # thread a core (max_threads: the user's thread limits apply), since sorting and FFTs release
        # the GIL (1.6x faster in colour on 2 cores).
        # Progress is reported from this thread only.
        done = queue.SimpleQueue()
        with ThreadPoolExecutor(max_workers=min(channels, max_threads())) as pool:
            jobs = [pool.submit(synthesize, c, done.put) for c in range(channels)]
            while not all(job.done() for job in jobs) or not done.empty():
                try:
                    bar.advance(done.get(timeout=0.05))
                except queue.Empty:
                    pass
            parts = [job.result() for job in jobs]  # re-raises a component's exception
    result = np.stack([out for out, _, _ in parts])
    distances = sum(d for _, d, _ in parts) / channels

    image = (basis @ result.reshape(channels, -1)).T + mean  # back to the exemplar's colour space
    image = np.clip(image.reshape(shape + (channels,)), 0.0, 1.0).astype(dtype, copy=False)
    image = restore_channels(image, grey)
    if not return_info:
        return image
    info = HeegerBergenInfo(names, distances, basis, mean, scales, orientations, periodic_exemplar,
                            seconds=time.perf_counter() - t_start,
                            stage_seconds={f"component {c}": t for c, (_, _, t) in enumerate(parts)})
    return image, info
