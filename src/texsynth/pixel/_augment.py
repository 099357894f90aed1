"""Exemplar augmentation in Wei-Levoy pixel synthesis: ``Search(augment=...)`` of :func:`~texsynth.synthesize_pixels`
and :func:`~texsynth.mix_textures`.

The exemplar's flipped and rotated copies (:class:`~texsynth.core.search.ExemplarAtlas`) each get their
own Gaussian pyramid, laid out side by side at every level; a source holding that atlas as its pyramid
offers, at each level, the candidate pixels of every copy, found as for an exemplar of its own (the
neighbourhood and its parent's inside the copy). The engine then searches them all at once, as it would
one exemplar, and the source-coordinate map is mapped back to the exemplar's pixels.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.pyramid import gaussian_pyramid
from ..core.search import ExemplarAtlas, check_augment

__all__ = ["augmented_source", "to_exemplar"]


def augmented_source(source, augment, levels, candidates="all"):
    """``source`` (a :class:`~texsynth.pixel._wei_levoy.Source` of one exemplar) with its pyramid replaced by
    the atlas of its ``augment`` copies' pyramids; ``source`` itself for ``augment="none"``."""
    if check_augment(augment) == "none":
        return source
    if candidates == "k-coherent":
        raise ValueError(f"augment={augment!r} does not combine with candidates='k-coherent' (its candidates "
                         f"continue copies on the grid of one exemplar); pass candidates='all' or augment='none'")
    image = source.pyramid[0]
    atlas = ExemplarAtlas(image.shape[:2], augment, levels=levels)
    pyramid = atlas.pyramid(image, levels, lambda copy, n: [np.asarray(level, dtype=image.dtype)
                                                            for level in gaussian_pyramid(copy, n)])
    return dataclasses.replace(source, pyramid=pyramid, atlas=atlas)


def to_exemplar(sources, coordinates, source_index=None):
    """A source-coordinate map into the sources' pyramids (their atlases) as one into the exemplars themselves
    (unchanged without an atlas); ``source_index`` (several sources) says which source each slot points into."""
    if coordinates is None or all(s.atlas is None for s in sources):
        return coordinates
    if source_index is None:
        return sources[0].atlas.to_exemplar(coordinates)
    out = coordinates.copy()
    for i, src in enumerate(sources):
        at = source_index == i
        if src.atlas is not None and at.any():
            out[at] = src.atlas.to_exemplar(coordinates[at])
    return out
