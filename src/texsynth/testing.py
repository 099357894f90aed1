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

Structure
---------
Four checks of the exemplar's large-scale structure use the structure metrics
of :mod:`texsynth.metrics` (on the luminance), each bounded by its module
threshold by default:

- induced lattice (:func:`~texsynth.metrics.induced_lattice`): fails above
  ``max_induced_lattice``, at any size (it sees repetitions at offsets up to
  5/8 of the output's sides: under about 1.6 times the exemplar's side, not a
  repetition at the exemplar's size, which the verbatim copy catches);
- orientation (:func:`~texsynth.metrics.orientation_distance`, degrees): fails
  above ``max_orientation`` *and* above half the noise baseline's own distance;
- lattice kept (:func:`~texsynth.metrics.lattice_kept`): fails below
  ``min_lattice_kept``, checked only when the exemplar has period vectors
  (:func:`~texsynth.metrics.lattice`);
- element integrity (:func:`~texsynth.metrics.element_integrity`): fails below
  ``min_element_integrity``, checked only when the noise baseline scores below
  that bound on this exemplar (where noise passes, the check tells nothing).

The last three are made only in the regime their thresholds were calibrated
in: an exemplar of at least 128 px on its smaller side and an output at least
twice its size on each side. Below it they judge sampling noise (other crops of
the same photographs fail them; ``docs/metrics.md``), and they are skipped. The
report's ``notes`` say how each check was judged, or why it was skipped.

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
The structure checks add about 0.1 s (0.05 s with the exemplar's side cached).
"""

from __future__ import annotations

import copy
import hashlib
import math
import numbers
from dataclasses import dataclass, field

from .core._validate import as_image, as_rng
from .metrics import (
    ELEMENT_INTEGRITY_THRESHOLD,
    INDUCED_LATTICE_THRESHOLD,
    LATTICE_KEPT_THRESHOLD,
    ORIENTATION_THRESHOLD,
    TextureReport,
    element_integrity,
    induced_lattice,
    lattice,
    lattice_kept,
    noise_baseline,
    orientation_distance,
    tiled_baseline,
    verdict_report,
)

__all__ = ["TextureAssertionError", "TextureVerdict", "assert_texture_like", "relative_scores"]


@dataclass
class TextureVerdict(TextureReport):
    """The report of :func:`assert_texture_like`: a :class:`~texsynth.metrics.TextureReport` with notes.

    Attributes
    ----------
    values : dict
        The output's metrics: ``energy``, ``completeness``, ``verbatim_copy``, ``histogram``,
        ``spectrum``, and the structure checks' ``orientation``, ``induced_lattice``,
        ``lattice_kept``, ``element_integrity`` (None for a check switched off or skipped).
    reference : dict
        The baselines' metrics: ``reference["noise"]`` and ``reference["tiled"]`` (the patch metrics
        but the verbatim copy; the noise's ``orientation`` and ``element_integrity``, the tiled
        exemplar's ``induced_lattice``, where measured).
    notes : dict
        For each structure check, how it was judged or why it was skipped (one sentence).
    failed : list
        The names of the checks out of bounds (``values``' names): empty when the assertion passed.
    """

    notes: dict = field(default_factory=dict)
    failed: list = field(default_factory=list)

    def table(self):
        """The metrics' table, then the structure checks' notes."""
        lines = [super().table()]
        lines += [f"{name}: {note}" for name, note in self.notes.items()]
        return "\n".join(lines)


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


def _check_lower_bound(value, name):
    """A lower bound of a score in [0, 1] is a real number in [0, 1]; 0 switches its check off."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise TypeError(f"{name} must be a number in [0, 1] (or 0 for no bound), got {value!r}")
    value = float(value)
    if not 0 <= value <= 1:  # NaN too
        raise ValueError(f"{name} must be a number in [0, 1] (a lower bound; 0 switches the check off), got {value}")
    return value


# The exemplar's side of the structure checks for an int rng: the exemplar's lattice, and the noise baseline's
# orientation and element scores and the tiled exemplar's induced lattice at the output's size, filled as the
# checks need them. (exemplar digest, shape, dtype, output size, seed) -> {name: value}
_STRUCTURE_BASELINES = {}
_STRUCTURE_BASELINES_KEPT = 16
_STRUCTURE = ("orientation", "induced_lattice", "lattice_kept", "element_integrity")
_MIN_SIDE = 8  # the structure metrics' smallest image side
# The regime the orientation, lattice-kept and element thresholds were calibrated in (benchmarks/
# calibrate_structure.py): exemplars of 128 px (96 x 128 for the wood), outputs twice their size. Below it they
# judge sampling noise: other crops of the same photographs (a perfect synthesis' stand-in) fail the orientation
# 2 times in 33 with 128 px exemplars, 5 in 34 with 96 px and 10 in 41 with 64 px, 64 px exemplars show period
# vectors their photographs lack, and an output of less than twice the exemplar holds one window of
# element_integrity's frame: an exact half-size crop of the exemplar fails it (docs/metrics.md, "Structure
# checks of assert_texture_like").
_CALIBRATED_SIDE = 128
_CALIBRATED_FACTOR = 2


def _calibrated(out, ex):
    """Why the size-sensitive checks cannot be made on these sizes (a sentence), or None when they can."""
    (oh, ow), (eh, ew) = out.shape[:2], ex.shape[:2]
    if min(eh, ew) >= _CALIBRATED_SIDE and oh >= _CALIBRATED_FACTOR * eh and ow >= _CALIBRATED_FACTOR * ew:
        return None
    return (f"skipped: its threshold holds for exemplars of at least {_CALIBRATED_SIDE} px and outputs at least "
            f"{_CALIBRATED_FACTOR} times their size (its calibration), not a {eh}x{ew} exemplar with a {oh}x{ow} "
            "output: these hold too few coarse orientations, periods or elements for it")


def _structure(out, ex, bounds, seed, noise_rng):
    """The structure checks: ``(values, reference, notes, failed)``; ``values[name]`` None where off or skipped.

    ``seed`` is the int seed of the noise baseline (its figures cached), else None and ``noise_rng`` a
    generator in the state the patch metrics' noise was drawn from (the same noise)."""
    values = dict.fromkeys(_STRUCTURE)
    reference = {"noise": {}, "tiled": {}}
    notes, failed = {}, []
    for name in _STRUCTURE:
        if bounds[name] in (math.inf, 0.0):
            notes[name] = f"switched off ({_BOUND_NAMES[name]}={bounds[name]:g})"
    if min(*out.shape[:2], *ex.shape[:2]) < _MIN_SIDE:
        for name in _STRUCTURE:
            notes.setdefault(name, f"skipped: the structure metrics need sides of at least {_MIN_SIDE} px (output "
                                   f"{out.shape[0]}x{out.shape[1]}, exemplar {ex.shape[0]}x{ex.shape[1]})")
    outside = _calibrated(out, ex)
    if outside is not None:
        for name in ("orientation", "lattice_kept", "element_integrity"):
            notes.setdefault(name, outside)
    active = [name for name in _STRUCTURE if name not in notes]
    if not active:
        return values, reference, {name: notes[name] for name in _STRUCTURE}, failed

    key = None
    if seed is not None:
        key = (hashlib.sha256(ex.tobytes()).hexdigest(), ex.shape, ex.dtype.str, out.shape[:2], seed)
    cached = _STRUCTURE_BASELINES.get(key, {}) if key is not None else {}
    made = {}

    def side(name, compute):
        """A figure of the exemplar's side: cached for an int seed."""
        if name not in cached:
            cached[name] = compute()
        return cached[name]

    def noise():
        if "image" not in made:
            made["image"] = noise_baseline(ex, out.shape[:2], rng=seed if seed is not None else noise_rng)
        return made["image"]

    if "orientation" in active:
        value = orientation_distance(out, ex)
        noise_value = side("noise orientation", lambda: orientation_distance(noise(), ex))
        values["orientation"], reference["noise"]["orientation"] = value, noise_value
        notes["orientation"] = (f"degrees; noise {noise_value:.2f}: fails above {bounds['orientation']:g} and "
                                f"above half the noise's, {0.5 * noise_value:.2f}")
        if value > bounds["orientation"] and value > 0.5 * noise_value:
            failed.append("orientation")

    if "induced_lattice" in active:
        value = induced_lattice(out, ex)
        tiled = side("tiled induced_lattice", lambda: induced_lattice(tiled_baseline(ex, out.shape[:2]), ex))
        values["induced_lattice"], reference["tiled"]["induced_lattice"] = value, tiled
        # the output's autocorrelation reaches 5/8 of each side; a peak on its edge does not count
        seen = (5 * out.shape[0] // 8 - 1, 5 * out.shape[1] // 8 - 1)
        notes["induced_lattice"] = f"the tiled exemplar {tiled:.2f}; offsets up to {seen[0]}x{seen[1]} px seen"
        if ex.shape[0] > seen[0] and ex.shape[1] > seen[1]:
            notes["induced_lattice"] += (
                f", not the exemplar's size {ex.shape[0]}x{ex.shape[1]}: a tiled copy's repetition is beyond them "
                "(an output of about 1.6 times the exemplar's sides shows it; the verbatim copy fails a tiled copy)")
        if not value <= bounds["induced_lattice"]:
            failed.append("induced_lattice")

    if "lattice_kept" in active:
        found = side("lattice", lambda: lattice(ex))
        vectors = found.vectors.tolist()
        # lattice_kept's reach: the output's autocorrelation, 5/8 of each side, must hold each vector with its
        # tolerance (1 px or 5 % of its length); an output twice the exemplar always does
        reach = (5 * out.shape[0] // 8, 5 * out.shape[1] // 8)
        if not vectors:
            notes["lattice_kept"] = "skipped: the exemplar has no lattice (no period vector), nothing to keep"
        elif any(abs(vy) + max(1, round(0.05 * math.hypot(vy, vx))) > reach[0]
                 or abs(vx) + max(1, round(0.05 * math.hypot(vy, vx))) > reach[1] for vy, vx in vectors):
            notes["lattice_kept"] = (f"skipped: the output ({out.shape[0]}x{out.shape[1]}) is too small to show the "
                                     f"exemplar's period vectors {vectors}")
        else:
            value = lattice_kept(out, ex)
            values["lattice_kept"] = value
            strengths = ", ".join(f"{v:.2f}" for v in found.strengths.tolist())
            notes["lattice_kept"] = f"at the exemplar's period vectors {vectors} (strengths {strengths})"
            if not value >= bounds["lattice_kept"]:
                failed.append("lattice_kept")

    if "element_integrity" in active:
        def noise_elements():
            try:
                return element_integrity(noise(), ex)
            except ValueError as error:  # the images are checked: the exemplar has no element
                return str(error)

        noise_value = side("noise element_integrity", noise_elements)
        bound = bounds["element_integrity"]
        if isinstance(noise_value, str):
            notes["element_integrity"] = f"skipped: {noise_value}"
        elif noise_value >= bound:
            reference["noise"]["element_integrity"] = noise_value
            notes["element_integrity"] = (f"skipped: the noise baseline scores {noise_value:.2f} on this exemplar, "
                                          f"not below the bound {bound:g}: the check would not tell noise from "
                                          "whole elements")
        else:
            value = element_integrity(out, ex)
            values["element_integrity"], reference["noise"]["element_integrity"] = value, noise_value
            notes["element_integrity"] = f"noise {noise_value:.2f}"
            if not value >= bound:
                failed.append("element_integrity")

    if key is not None:
        _STRUCTURE_BASELINES.pop(key, None)
        _STRUCTURE_BASELINES[key] = cached  # the most recent last
        while len(_STRUCTURE_BASELINES) > _STRUCTURE_BASELINES_KEPT:
            _STRUCTURE_BASELINES.pop(next(iter(_STRUCTURE_BASELINES)))  # the oldest
    return values, reference, {name: notes[name] for name in _STRUCTURE}, failed


_BOUND_NAMES = {"energy": "max_energy", "completeness": "max_completeness", "spectrum": "max_spectrum",
                "verbatim_copy": "max_copy", "orientation": "max_orientation",
                "induced_lattice": "max_induced_lattice", "lattice_kept": "min_lattice_kept",
                "element_integrity": "min_element_integrity"}


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
                        max_spectrum=0.6, max_copy=0.5, max_orientation=ORIENTATION_THRESHOLD,
                        max_induced_lattice=INDUCED_LATTICE_THRESHOLD, min_lattice_kept=LATTICE_KEPT_THRESHOLD,
                        min_element_integrity=ELEMENT_INTEGRITY_THRESHOLD, rng=0):
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
    max_orientation : float
        Degrees of :func:`~texsynth.metrics.orientation_distance` (default
        ``ORIENTATION_THRESHOLD``, 10): the output fails above it *and* above
        half the noise baseline's distance. >= 0; ``float("inf")``: off.
    max_induced_lattice : float
        Upper bound on :func:`~texsynth.metrics.induced_lattice` (default
        ``INDUCED_LATTICE_THRESHOLD``, 0.3): a lattice the exemplar lacks.
        >= 0; ``float("inf")``: off.
    min_lattice_kept : float
        Lower bound on :func:`~texsynth.metrics.lattice_kept` (default
        ``LATTICE_KEPT_THRESHOLD``, 0.4), checked when the exemplar has
        period vectors. In [0, 1]; 0: off.
    min_element_integrity : float
        Lower bound on :func:`~texsynth.metrics.element_integrity` (default
        ``ELEMENT_INTEGRITY_THRESHOLD``, 0.4), checked when the noise
        baseline scores below it on this exemplar. In [0, 1]; 0: off.

        The orientation, lattice-kept and element checks are made only for
        an exemplar of at least 128 px on its smaller side and an output at
        least twice its size on each side (their thresholds' calibration);
        the induced lattice at any size.
    rng : None, int or numpy.random.Generator
        Seed of the noise baseline. Fixed (0) by default rather than the
        library's usual None, so the assertion is deterministic: the same
        output passes or fails the same way in every run.

    Returns
    -------
    TextureVerdict
        A :class:`~texsynth.metrics.TextureReport` of the metrics judged, for
        logging: the output's (energy, completeness, verbatim copy,
        histogram, spectrum, and the four structure values, None where a
        check was off or skipped) and the noise and tiled baselines' (all but
        the verbatim copy; the noise's orientation and element integrity, the
        tiled exemplar's induced lattice), with ``notes`` saying how each
        structure check was judged or why it was skipped, and ``failed``
        (empty: it passed). Pass it to :func:`relative_scores` for the
        scores.

    Raises
    ------
    TextureAssertionError
        Listing every metric with its score and bound, failing ones marked,
        the structure checks with their baselines' figures and notes, and the
        grid strides measured on.
    TypeError, ValueError
        For bad arguments (checked before anything is computed): a bound that
        is not a number >= 0 (NaN, negative, a bool or a string), a lower
        bound outside [0, 1], and bad images, ``patch_size`` or ``rng`` as in
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

    The structure checks (module notes) are the metrics' own, on the whole
    images. The induced lattice sees repetitions at offsets up to 5/8 of the
    output's sides: in an output less than about 1.6 times the exemplar's
    side it cannot see a repetition at the exemplar's size (a tiled copy;
    the verbatim copy fails that), only shorter ones, and the note says so.
    The other three are skipped, with a note, outside the regime of their
    calibration (an exemplar under 128 px, an output under twice its size),
    where other crops of the same photographs fail them (``docs/metrics.md``,
    "Structure checks of assert_texture_like"); all four when a side is
    below 8 px.

    The baselines' figures of an int ``rng`` (the patch metrics, the
    exemplar's lattice, the noise's orientation and element integrity, the
    tiled exemplar's induced lattice) are kept for the 16 most recent
    exemplars and sizes, so asserting several outputs of one exemplar
    measures them once. ``docs/metrics.md`` gives the timings and the
    agreement measured.
    """
    bounds = {"energy": _check_bound(max_energy, "max_energy"),
              "completeness": _check_bound(max_completeness, "max_completeness"),
              "spectrum": _check_bound(max_spectrum, "max_spectrum"),
              "verbatim_copy": _check_bound(max_copy, "max_copy"),
              "orientation": _check_bound(max_orientation, "max_orientation"),
              "induced_lattice": _check_bound(max_induced_lattice, "max_induced_lattice"),
              "lattice_kept": _check_lower_bound(min_lattice_kept, "min_lattice_kept"),
              "element_integrity": _check_lower_bound(min_element_integrity, "min_element_integrity")}
    out, ex = as_image(output, "output"), as_image(exemplar, "exemplar")  # a file is read once
    seed = int(rng) if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) else None
    noise_rng = None
    if seed is None:  # the structure checks' noise is the patch metrics': drawn from a copy of the generator
        rng = as_rng(rng)
        noise_rng = copy.deepcopy(rng)
    report, sampled = verdict_report(out, ex, patch_size=patch_size, rng=rng)
    scores = relative_scores(report)
    failed = [name for name in _METRICS if not scores[name] <= bounds[name]]
    values, reference, notes, structure_failed = _structure(out, ex, bounds, seed, noise_rng)
    failed += structure_failed
    report = TextureVerdict(values={**report.values, **values},
                            reference={base: {**report.reference[base], **reference[base]}
                                       for base in report.reference},
                            notes=notes, failed=failed)
    if failed:
        lines = [f"output does not look like the exemplar ({', '.join(failed)} out of bounds):"]
        for name in _METRICS:
            mark = "FAIL" if name in failed else "ok"
            lines.append(f"  {mark:>4}  {name:<17} score {scores[name]:8.4f}  bound <= {bounds[name]:8.4f}  "
                         f"(raw {report.values[name]:.5f})")
        for name in _STRUCTURE:
            value = values[name]
            if value is None:
                lines.append(f"  {'-':>4}  {name:<17} {notes[name]}")
                continue
            mark = "FAIL" if name in failed else "ok"
            sign = ">=" if name in ("lattice_kept", "element_integrity") else "<="
            lines.append(f"  {mark:>4}  {name:<17} value {value:8.4f}  bound {sign} {bounds[name]:8.4f}  "
                         f"({notes[name]})")
        (n_out, of_out), (n_ex, of_ex) = sampled["energy"], sampled["completeness"]
        lines.append(f"searched {n_out} of the output's {of_out} grid neighbourhoods and {n_ex} of the exemplar's "
                     f"{of_ex}; baselines:\n" + TextureReport.table(report))
        raise TextureAssertionError("\n".join(lines), report)
    return report
