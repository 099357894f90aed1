"""The search options that every synthesis shares, as one group: ``search=Search(...)``."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

from .._validate import is_auto
from ._augment import check_augment
from ._coherent import check_candidates

__all__ = ["Search", "is_auto"]


@dataclass(frozen=True)
class Search:
    """How a synthesis finds, for each of its neighbourhoods, the nearest exemplar neighbourhood.

    Examples
    --------
    >>> import texsynth
    >>> texsynth.Search(candidates="k-coherent", k=2)
    Search(method='auto', candidates='k-coherent', k=2, augment='none')
    >>> texsynth.Search(augment="rotations").augment
    'rotations'

    One group of options, passed as ``search=Search(...)`` to every method
    that searches (:func:`~texsynth.optimize_texture`,
    :func:`~texsynth.synthesize_pixels`, ...). On the command line its
    fields are the flags ``--method``, ``--candidates``, ``--k`` and ``--augment``.

    Parameters
    ----------
    method : str
        The nearest-neighbour backend: ``"exact"``, ``"kdtree"``,
        ``"tsvq"``, or ``"patchmatch"`` where the method searches fields;
        ``"auto"`` (default): the method's measured choice per stage. The
        names are listed in :data:`texsynth.core.search.METHODS` and
        :data:`~texsynth.core.search.FIELD_METHODS`.
    candidates : {"all", "k-coherent", "auto"}
        Which exemplar neighbourhoods a query is compared with: all of them,
        through ``method`` (default), or the k-coherent candidates of its
        neighbours' sources (Ashikhmin 2001; Tong et al. 2002 [1]_). ``"auto"``:
        the method's preset chooses (:func:`~texsynth.synthesize_surface`);
        a method without a preset for it refuses it or reads it as ``"all"``.
    k : int or "auto"
        The size of the k-coherence sets with ``candidates="k-coherent"``:
        the neighbourhood itself and ``k - 1`` similar ones (1: Ashikhmin's
        continuations only). ``"auto"`` (default): the method's own default.
    augment : {"none", "flips", "rotations", "both"}
        Also draw from flipped or rotated copies of the exemplar:
        ``"flips"`` its left-right and up-down mirror images,
        ``"rotations"`` its quarter turns (90, 180, 270 degrees), ``"both"``
        all eight symmetries of the square; ``"none"`` (default): the
        exemplar as it is. It helps a texture of few elements that occur in
        any orientation and harms a directional one
        (``docs/methods/search.md``). The source-coordinate map still points
        into the exemplar itself
        (:func:`~texsynth.core.search.augmented_set`). Taken by
        :func:`~texsynth.optimize_texture`,
        :func:`~texsynth.synthesize_pixels`, :func:`~texsynth.mix_textures`
        (not with ``candidates="k-coherent"``) and
        :func:`~texsynth.efros_leung`; the other methods refuse it
        (:func:`~texsynth.quilt` and :func:`~texsynth.patch_sampling` take
        ``augment=`` as an option of their own).

    References
    ----------
    .. [1] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       ACM TOG 21(3) (SIGGRAPH 2002), pp. 665-672.
       :doi:`10.1145/566654.566634` (not at hand: the k-coherence sets as
       :mod:`texsynth.core.search` describes them; their use in texture
       optimization's M-step is ours).
    """

    method: str = "auto"
    candidates: str = "all"
    k: object = "auto"
    augment: str = "none"

    def __post_init__(self):
        check_augment(self.augment)
        if not isinstance(self.method, str):
            raise TypeError(f"method must be a backend name such as 'auto' or 'exact', got {self.method!r}")
        if not is_auto(self.candidates):
            check_candidates(self.candidates)
        if not is_auto(self.k) and (not isinstance(self.k, numbers.Integral) or isinstance(self.k, bool)
                                    or self.k < 1):
            raise ValueError(f"k must be 'auto' or an integer >= 1 (the size of the k-coherence sets), "
                             f"got {self.k!r}")

    def resolved_k(self, default):
        """``k``, or the method's ``default`` where it is ``"auto"``."""
        return default if is_auto(self.k) else int(self.k)

    def resolved_candidates(self, default):
        """``candidates``, or the method's ``default`` where it is ``"auto"``."""
        return default if is_auto(self.candidates) else self.candidates
