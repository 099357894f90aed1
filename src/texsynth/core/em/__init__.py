"""Patch-energy synthesis as parts: the EM loop, its two steps and the terms of its energy.

Every method that minimises a patch energy (Kwatra et al. 2005's texture
optimization, its hole filling and guided synthesis, Ruiters et al. 2010's
interpolation) alternates two steps, and composes them from these parts:

The loops
    :func:`expectation_maximization` (Algorithm 1), :func:`irls_weights`
    (Section 3.1's robust weights) and :func:`coarse_to_fine` (Section 3.2's
    levels and sizes, recorded in a :class:`Record`).
The neighbourhoods
    :class:`ExemplarPatches` (the exemplar's searchable neighbourhoods of one
    level and size), :func:`patch_features`, :func:`feature_weights`,
    :func:`output_patches`, :func:`distances_at`; :class:`WarpedPatches` reads
    and writes them in the local frames of orientation and magnification fields.
The E-step
    :func:`e_step`: the weighted average of the matches (IRLS weights,
    constraint targets, extra votes), or with the gradient term the
    Poisson-like system (:func:`solve_gradient_system`); :class:`Average`
    composes it with the terms that vote (completeness, confidence,
    histograms, guides) as one stage's E-step.
The M-step forms
    :func:`nearest_step` (an index), :func:`field_step` (PatchMatch),
    :func:`constrained_step` (Algorithm 2's soft constraints),
    :func:`frame_step` (an animation frame's coherent candidates), with
    :func:`coherent_candidates`, :func:`random_candidates` and
    :class:`SearchMemo`. Every choice is made by :mod:`texsynth.core.search`.
The terms
    :class:`Occurrence` (occurrence penalty, copy limit), :class:`Completeness`
    (bidirectional similarity), :func:`confidence_weights` (Wexler et al.),
    :func:`touching_free` (hard constraints), :func:`histogram_groups` and
    :func:`match_channel` (histogram matching), :func:`robust_energy`.
The problem and the record
    :func:`prepare` and :class:`Problem` (the checked inputs, with
    :func:`with_guides`, :func:`with_fields`, :func:`with_margin`,
    :func:`pyramids`); :class:`StageInfo`, :class:`OptimizationInfo` and
    :class:`AnimationInfo`;
    :func:`source_map`, :func:`dominant_sources` and :func:`carried_field`
    (where each output pixel came from).
The options
    :class:`Schedule`, :class:`Terms`, :class:`Constraints`, :class:`Guides`
    and :class:`Fields`: the option groups of the methods built on these parts.

``docs/architecture.md`` shows a new EM method composed from them in 30 lines.

What the parts guarantee
------------------------
The energy actually minimised is the robust texture energy

.. math:: E(x, \\{z_p\\}) = \\sum_p \\left(\\rho_p + \\varepsilon^2\\right)^{r/2}
          + \\lambda E_c(x), \\qquad
          \\rho_p = \\|x_p - z_p\\|_g^2 + \\mu \\|D x_p - D z_p\\|_g^2

where ``‖·‖_g`` carries the Gaussian fall-off and ``ε`` (an RMS difference of
1e-3 per value, a quarter of an 8-bit grey level) keeps the IRLS weight
finite when ``x_p == z_p``. Because ``s -> (s + ε²)^{r/2}`` is concave for
``r <= 2``, its tangent at the current ``ρ_p`` is an upper bound: the IRLS
E-step (weights ``ω_p = (r/2)(ρ_p + ε²)^{(r-2)/2}``, the paper's
``||x_p - z_p||^{r-2}`` up to the constant ``r/2`` and the guard ``ε``)
minimises a majoriser that touches ``E`` at the current ``x``, so it cannot
raise ``E``; the M-step keeps the old ``z_p`` unless the search found one
strictly closer, so it cannot raise ``E`` either, even with an approximate
search backend, or when it skips the search of a neighbourhood that hardly
moved. Hence, for ``λ = 0`` (and with the occurrence penalty and the copy
limit off, their defaults), ``E`` never rises between two iterations of one
(level, size) stage beyond floating-point noise (the E-step with ``μ > 0``
is solved by preconditioned conjugate gradients to a relative residual of
1e-10, reached in 16 iterations (median; 30 at most) on the systems of a
256 x 256 synthesis). The modified M-step of Algorithm 2 ranks candidates
by ``||x_p - v||^2 + λ E_c(y)``, which is *not* ``E``; with constraints the
energy usually falls but is not guaranteed to. The optional completeness term
of the bidirectional similarity (``completeness_weight``) keeps the guarantee:
its matches ``p(j)`` are only ever replaced by closer ones and its votes join
the same weighted average.

References
----------
.. [1] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
   for example-based synthesis", ACM TOG 24(3), 2005, pp. 795-802.
   :doi:`10.1145/1073204.1073263`
"""

from ._loop import IRLS_EXPONENT, expectation_maximization, irls_weights
from ._patches import (BLOCK_VALUES, EPS_RMS, ExemplarPatches, difference_weights, distances_at, feature_weights,
                       output_patches, patch_features, unwrap_centers)
from ._fields import WarpedPatches
from ._estep import Average, e_step, grid_parts, solve_gradient_system
from ._mstep import (SearchMemo, coherent_candidates, constrained_step, field_step, frame_step, frame_terms,
                     nearest_step, random_candidates)
from ._terms import (WEXLER_CONFIDENCE, Completeness, Occurrence, confidence_weights, histogram_groups, match_channel,
                     nearest_label, robust_energy, touching_free)
from ._sources import carried_field, dominant_sources, extend_nearest, source_map
from ._problem import (MAX_WEIGHT, Problem, check_constraint_memory, check_constraint_weight, check_like, check_mask,
                       check_sizes, free_inside, level_sizes, prepare, pyramids, with_fields, with_guides, with_margin)
from ._record import AnimationInfo, OptimizationInfo, Record, StageInfo
from ._levels import Level, coarse_to_fine
from ._options import Animation, Constraints, Fields, Guides, Schedule, Terms

__all__ = [
    "expectation_maximization", "irls_weights", "IRLS_EXPONENT",
    "ExemplarPatches", "patch_features", "feature_weights", "difference_weights", "output_patches", "distances_at",
    "unwrap_centers", "EPS_RMS", "BLOCK_VALUES", "WarpedPatches",
    "e_step", "Average", "solve_gradient_system", "grid_parts",
    "nearest_step", "field_step", "constrained_step", "frame_step", "frame_terms", "SearchMemo",
    "coherent_candidates", "random_candidates",
    "Occurrence", "Completeness", "confidence_weights", "touching_free", "robust_energy", "nearest_label",
    "histogram_groups", "match_channel", "WEXLER_CONFIDENCE",
    "source_map", "dominant_sources", "carried_field", "extend_nearest",
    "Problem", "prepare", "with_guides", "with_fields", "with_margin", "free_inside", "pyramids", "level_sizes",
    "check_sizes", "check_mask", "check_like", "check_constraint_weight", "check_constraint_memory", "MAX_WEIGHT",
    "StageInfo", "OptimizationInfo", "AnimationInfo", "Record", "coarse_to_fine", "Level",
    "Schedule", "Terms", "Constraints", "Guides", "Fields", "Animation",
]
