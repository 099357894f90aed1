"""Nearest-neighbour search: the one place in texsynth where a neighbour is chosen.

Every neighbourhood-matching algorithm asks the same question, *which exemplar
neighbourhood is closest to this one?*, and asks it here:

:class:`PatchIndex`
    ``PatchIndex(vectors, weights=None, method="auto").query(queries, k)``
    gives the k nearest vectors and their exact (weighted) squared distances,
    ties broken by the lowest index, whatever the backend.
:class:`SequentialExact`
    Exact search for queries whose vectors become known in parts (scanline
    synthesis: the rows above first, the pixels to the left one at a time).
:class:`SubsetExact`
    Exact search over the dimensions a query knows, when few such subsets
    recur (a tileable scanline synthesis's wrapped windows).
:func:`nearest_candidates`
    The nearest of each query's own candidate list (coherent candidates,
    random subsets); :func:`candidate_sq_distances` the distances to all of
    them, for a choice that weighs other terms too (a mixture's eq. 1).
:func:`lowest_cost`
    The choice among each query's candidates by a cost the method computed
    (distance plus another energy term: constrained re-ranking, wrap search,
    a mixture's alternation), ties broken as asked.
:func:`sq_distances`
    Weighted squared distances of given pairs (a query and its match).
:class:`MaskedIndex`
    Queries known only in part (a window with unknown pixels): masked
    distances by BLAS, blocks known whole compared on their own (exactly,
    or in PCA with ``method="pca"``); ``near_best`` picks among the vectors
    within ``(1 + error_tolerance)`` of the nearest (Efros-Leung).
:func:`masked_sq_distances`
    The same masked distances, one-shot.
:class:`WindowSearch`
    Masked squared distances of a template to every window of an image, by
    FFT (quilting, patch-based sampling); :func:`within_tolerance` and
    :func:`within_radius` turn them into candidate sets.
:class:`TemplateSearch`
    The same with the roles exchanged: a fixed template placed over every
    position of a partly known image (graph-cut textures' whole input).
:func:`patchmatch`
    For every patch of an image, the k nearest patches of an exemplar
    (PatchMatch): fields on grids, warm-started, with masks and wrap;
    :func:`patchmatch_features` the same for feature arrays the caller has
    checked (any channels and values: an EM loop's M-step).
:func:`nearest_field`
    The same question of any backend: ``method="exact"``, ``"kdtree"``,
    ``"tsvq"`` or ``"patchmatch"``.
:class:`Search`
    The options of a synthesis's search, one group (``search=Search(method=...,
    candidates=..., k=..., augment=...)``); :func:`is_auto` tells the preset's ``"auto"``.
:func:`augmented_set`
    The exemplar's flipped and rotated copies (``Search(augment=...)``);
    :class:`ExemplarAtlas` lays them out as one image that a method searches
    as its exemplar, and maps a match back to the exemplar pixel it shows.
:class:`KCoherence`
    k-coherent candidates (Ashikhmin 2001, Tong et al. 2002): where the
    neighbours' copies continue, and what resembles those positions;
    :func:`neighbor_sources` reads the neighbours' sources from a field.

Distances are ``sum_d w_d (q_d - v_d)^2``, implemented by scaling both sides
by ``sqrt(w)`` once, so every backend works on plain Euclidean vectors.

Backends and profiles
---------------------
A backend is one module that registers itself (:func:`register`):
``"exact"`` (chunked BLAS, memory-bounded, exact re-ranking), ``"kdtree"``
(PCA + kd-tree candidates, re-ranked exactly) and ``"tsvq"`` (tree-structured
vector quantization, Wei & Levoy 2000). ``method="auto"`` is resolved by the
rule of a named :data:`PROFILES` entry, which also holds each algorithm's
measured tuning; :func:`use` makes ``"auto"`` mean one backend everywhere.

>>> rng = np.random.default_rng(0)
>>> vectors = rng.random((200, 12))
>>> index = PatchIndex(vectors, method="exact")
>>> idx, d2 = index.query(vectors[:3] + 0.001, k=2)
>>> idx[:, 0].tolist()
[0, 1, 2]
"""

from . import _exact, _kdtree, _tsvq  # noqa: F401  (each registers its backend)
from ._common import sq_distances
from ._exact import SequentialExact, SubsetExact, candidate_sq_distances, exact_chunk_rows, nearest_candidates
from ._index import PatchIndex, nearest
from ._kdtree import point_tree
from ._masked import MASKED_METHODS, MaskedIndex, masked_sq_distances
from ._template import TemplateSearch, WindowSearch, within_radius, within_tolerance
from ._coherent import CANDIDATES, COHERENT_MODES, KCoherence, check_candidates, coherence_sets, neighbor_sources
from ._patchmatch import (
    FIELD_METHODS,
    FIELD_MIN_VALUES,
    check_field_method,
    nearest_field,
    patchmatch,
    patchmatch_features,
    project_patches,
    resolve_field,
)
from ._augment import (AUGMENT_METHODS, AUGMENTS, ExemplarAtlas, Transform, augmentations, augmented_set, check_augment,
                       refuse_augment, window_search)
from ._options import Search, is_auto
from ._rescore import lowest_cost
from ._registry import BACKENDS, PROFILES, Profile, check_method, register, resolve, use
from ._registry import methods as _methods

#: Valid values of ``method``: ``"auto"`` and the registered backends.
METHODS = _methods()

__all__ = [
    "PatchIndex", "nearest", "point_tree", "SequentialExact", "SubsetExact", "nearest_candidates", "candidate_sq_distances", "sq_distances",
    "MaskedIndex", "masked_sq_distances", "MASKED_METHODS", "WindowSearch", "TemplateSearch", "within_tolerance", "within_radius",
    "KCoherence", "neighbor_sources", "coherence_sets", "check_candidates", "COHERENT_MODES", "CANDIDATES", "patchmatch", "patchmatch_features", "nearest_field", "project_patches", "FIELD_METHODS", "FIELD_MIN_VALUES", "check_field_method", "resolve_field",
    "Search", "is_auto", "AUGMENTS", "AUGMENT_METHODS", "ExemplarAtlas", "Transform", "augmentations", "augmented_set", "check_augment", "refuse_augment", "window_search", "lowest_cost", "METHODS", "BACKENDS", "PROFILES", "Profile", "register", "resolve", "use", "check_method", "exact_chunk_rows",
]
