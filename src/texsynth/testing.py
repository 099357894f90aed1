"""Assertion helpers for reference comparisons in your own pytest suites.

"Does this output still look like that exemplar, with no pasted copy, at this
quality?" :func:`assert_texture_like` answers with the metrics of
:mod:`texsynth.metrics`, each bounded *relative to baselines computed from the
exemplar itself* (histogram-matched noise, a random-block mosaic and the tiled
exemplar), so the same thresholds make sense for any texture.

Scores
------
For coherence (texture energy) and completeness the score places the output
on the scale from the tiled exemplar (score 0, the best any synthesis can do)
to histogram-matched noise (score 1, no structure at all)::

    score = (metric(output) - metric(tiled)) / (metric(noise) - metric(tiled))

The spectrum score is ``spectrum_distance(output) / spectrum_distance(noise)``
(white noise has a flat spectrum, so it is the natural "knows nothing" case).
Copying is bounded directly: the largest single-offset copied region as a
fraction of the exemplar's area.

The default bounds come from the calibration table in ``docs/metrics.md``
(11 real textures): noise scores 1 by construction; random-block mosaics,
coherent inside their blocks but with seams between them, score 0.11-0.29 on
energy, 0.04-0.25 on completeness and 0.15-0.42 on the spectrum, and copy
0.06-0.10 of the exemplar. The defaults (0.5, 0.5, 0.6 and a copy of at most
half the exemplar) therefore pass anything at least about as good as a
mosaic and fail noise, blur and pasted copies of the whole exemplar.

Speed
-----
:func:`assert_texture_like` measures only what its verdict uses (the output,
the noise and the tiled exemplar; no mosaic), and each nearest-neighbour
search on at most 1024 neighbourhoods: the metrics' default grids while they
fit (images up to about 70 px for ``patch_size=8``: then every value is
:func:`~texsynth.metrics.texture_report`'s), a stratified random sample of
them above. A 256² colour output takes 1-2.5 s on 2 cores (from a 128² or a
256² exemplar; ``benchmarks/bench_testing.py``), against 23-29 s and 161 s
before, with the same verdicts on 72 calibration cases;
:func:`~texsynth.metrics.texture_report` still computes every metric in full.
"""

from __future__ import annotations

import math
import numbers

from .metrics import TextureReport, verdict_report

__all__ = ["TextureAssertionError", "assert_texture_like", "relative_scores"]


class TextureAssertionError(AssertionError):
    """Raised by :func:`assert_texture_like`; the message lists every metric and bound."""

    def __init__(self, message, report=None):
        super().__init__(message)
        self.report = report


def _scale(value, best, worst):
    span = worst - best
    return (value - best) / span if span > 0 else float("inf") if value > best else 0.0


_METRICS = ("energy", "completeness", "spectrum", "verbatim_copy")


def _check_report(report):
    if not isinstance(report, TextureReport):
        raise TypeError(
            f"report must be a texsynth.metrics.TextureReport (from texture_report(output, exemplar)), "
            f"got {type(report).__name__}"
        )
    missing = [name for name in _METRICS if name not in report.values]
    if missing:
        raise ValueError(f"report.values lacks {missing}; compute the report with texture_report(output, exemplar)")
    for baseline in ("tiled", "noise"):
        if baseline not in report.reference:
            raise ValueError(
                f"report has no {baseline!r} baseline (reference holds {sorted(report.reference)}); "
                "compute it with texture_report(output, exemplar, with_baselines=True)"
            )
        lacking = [name for name in ("energy", "completeness", "spectrum") if name not in report.reference[baseline]]
        if lacking:
            raise ValueError(f"report.reference[{baseline!r}] lacks {lacking}; compute it with texture_report")


def _check_bound(value, name):
    """A bound is a real number >= 0; +inf switches its check off."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise TypeError(f"{name} must be a number >= 0 (or float('inf') for no bound), got {value!r}")
    value = float(value)
    if math.isnan(value) or value < 0:
        raise ValueError(
            f"{name} must be a number >= 0 (an upper bound; float('inf') switches the check off), got {value}"
        )
    return value


def relative_scores(report):
    """Baseline-relative scores of a :class:`~texsynth.metrics.TextureReport`.

    Parameters
    ----------
    report : texsynth.metrics.TextureReport
        From :func:`~texsynth.metrics.texture_report` with its baselines
        (``with_baselines=True``, the default).

    Returns
    -------
    dict
        ``energy``, ``completeness`` and ``spectrum`` scores (0 = as good as the
        tiled exemplar, 1 = as bad as noise) and the raw ``verbatim_copy``.

    Raises
    ------
    TypeError
        If ``report`` is not a TextureReport.
    ValueError
        If it lacks a metric or the tiled and noise baselines.

    Examples
    --------
    >>> from texsynth.metrics import texture_report
    >>> ex = np.random.default_rng(0).random((20, 20))
    >>> scores = relative_scores(texture_report(ex, ex, patch_size=4))
    >>> scores["energy"], scores["spectrum"]
    (0.0, 0.0)
    """
    _check_report(report)
    ref = report.reference
    return {
        "energy": _scale(report.values["energy"], ref["tiled"]["energy"], ref["noise"]["energy"]),
        "completeness": _scale(report.values["completeness"], ref["tiled"]["completeness"],
                               ref["noise"]["completeness"]),
        "spectrum": _scale(report.values["spectrum"], 0.0, ref["noise"]["spectrum"]),
        "verbatim_copy": report.values["verbatim_copy"],
    }


def assert_texture_like(output, exemplar, *, patch_size=8, max_energy=0.5, max_completeness=0.5,
                        max_spectrum=0.6, max_copy=0.5, rng=0):
    """Assert that ``output`` is a plausible synthesis of ``exemplar``.

    Examples
    --------
    >>> import numpy as np
    >>> from texsynth import data, quilt
    >>> ex = data.load("bread")
    >>> report = assert_texture_like(quilt(ex, 128, rng=0), ex)  # passes (about 0.5 s)
    >>> noise = np.random.default_rng(0).random((128, 128, 3))
    >>> assert_texture_like(noise, ex)  # white noise: fails
    Traceback (most recent call last):
    ...
    texsynth.testing.TextureAssertionError: output does not look like the exemplar ...

    Parameters
    ----------
    output, exemplar : array_like
        Images with the same number of channels.
    patch_size : int
        Neighbourhood size of the metrics; about the size of the texture's
        elements.
    max_energy, max_completeness, max_spectrum : float
        Upper bounds on the baseline-relative scores (see the module notes):
        0 is the tiled exemplar, 1 is histogram-matched noise. Numbers >= 0;
        ``float("inf")`` switches a check off.
    max_copy : float
        Upper bound on the largest verbatim-copied region, as a fraction of
        the exemplar's area (>= 0; ``float("inf")`` switches it off).
    rng : None, int or numpy.random.Generator
        Seed of the noise baseline. Fixed (0) by default rather than the
        library's usual None, so the assertion is deterministic: the same
        output passes or fails the same way in every run.

    Returns
    -------
    texsynth.metrics.TextureReport
        The metrics judged, for logging: the output's (energy, completeness,
        verbatim copy, histogram, spectrum) and the noise and tiled
        baselines' (all but the verbatim copy). Pass it to
        :func:`relative_scores` for the scores.

    Raises
    ------
    TextureAssertionError
        Listing every metric with its score and bound, failing ones marked,
        and the grid strides measured on.
    TypeError, ValueError
        For bad arguments (checked before anything is computed): a bound that
        is not a number >= 0 (NaN, negative, a bool or a string), and bad
        images, ``patch_size`` or ``rng`` as in
        :func:`~texsynth.metrics.texture_report`.

    Notes
    -----
    The metrics are those of :func:`~texsynth.metrics.texture_report`, with
    each nearest-neighbour search on at most 1024 neighbourhoods:

    - energy and completeness: the mean over the default grid (a
      neighbourhood every ``patch_size // 4`` pixels) while it holds at most
      1024 of them (images up to about 70 px for ``patch_size=8``: the values
      are then ``texture_report``'s); above, the grid is cut into 1024 cells
      and one neighbourhood drawn from each (a fixed draw) stands for its
      cell, an unbiased estimate of the same mean, searched in float32; 256
      for the noise's energy. On 72 calibration cases the energy and
      completeness scores stay within 0.015 of the full computation's, the
      copied fraction within 0.03, and every verdict is the same
      (``tests/test_testing.py`` checks it with a margin).
    - verbatim copy: on its whole stride-2 grid, as
      :func:`~texsynth.metrics.verbatim_copy`; above 1024 neighbourhoods
      the exact search of the energy's sample gives the copied seeds, and
      each stride-2 neighbourhood is compared with the exemplar at the
      offsets of the seeds around it: a copied region is found whole.
    - the tiled exemplar's energy searches only its neighbourhoods across a
      seam (the others are exemplar neighbourhoods, distance 0), and its
      completeness is 0 when the output is at least as large as the
      exemplar: both exact.

    The baselines' metrics of an int ``rng`` are kept for the 16 most recent
    exemplars and sizes, so asserting several outputs of one exemplar
    measures them once. ``docs/metrics.md`` gives the timings and the
    agreement measured.
    """
    bounds = {"energy": _check_bound(max_energy, "max_energy"),
              "completeness": _check_bound(max_completeness, "max_completeness"),
              "spectrum": _check_bound(max_spectrum, "max_spectrum"),
              "verbatim_copy": _check_bound(max_copy, "max_copy")}
    report, sampled = verdict_report(output, exemplar, patch_size=patch_size, rng=rng)
    scores = relative_scores(report)
    failed = [name for name in bounds if not scores[name] <= bounds[name]]
    if failed:
        lines = [f"output does not look like the exemplar ({', '.join(failed)} out of bounds):"]
        for name, bound in bounds.items():
            mark = "FAIL" if name in failed else "ok"
            lines.append(f"  {mark:>4}  {name:<14} score {scores[name]:8.4f}  bound {bound:8.4f}  "
                         f"(raw {report.values[name]:.5f})")
        (n_out, of_out), (n_ex, of_ex) = sampled["energy"], sampled["completeness"]
        lines.append(f"searched {n_out} of the output's {of_out} grid neighbourhoods and {n_ex} of the exemplar's "
                     f"{of_ex}; baselines:\n" + report.table())
        raise TextureAssertionError("\n".join(lines), report)
    return report
