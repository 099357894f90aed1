"""Optimization-based synthesis: minimise a patch energy by the EM loop of :mod:`texsynth.core.em`.

- :func:`optimize_texture`, :func:`animate_texture`: Kwatra et al. 2005,
  texture optimization (constraints, hole filling) and flow-guided animation.
  Their options come in groups: :class:`~texsynth.core.em.Schedule`,
  :class:`~texsynth.core.em.Terms`, :class:`~texsynth.core.search.Search`,
  :class:`~texsynth.core.em.Constraints`, :class:`~texsynth.core.em.Guides`,
  :class:`~texsynth.core.em.Fields` (importable from here too) and
  :class:`~texsynth.core.em.Animation`; their results are :class:`~texsynth.core.em.OptimizationInfo`
  and :class:`~texsynth.core.em.AnimationInfo`.
- :func:`interpolate_textures`: Ruiters et al. 2010, patch-based texture
  interpolation (with :func:`interpolate_neighborhoods`, the feature maps
  :func:`ridge_feature_map` and :func:`edge_feature_map`, the baseline
  :func:`linear_blend` and :func:`transition_alpha_map`). Its options come
  in groups: :class:`InterpolationSchedule`, :class:`Correspondences`,
  :class:`NeighborhoodSet`, :class:`InterpolationUpdate`,
  :class:`VaryingAlpha` and :class:`Search`.
- :func:`inpaint`, :func:`uncrop`: image completion by texture optimization
  with hard constraints (hole filling with a sampling area; extending an
  image beyond its borders); :func:`make_tileable`: re-synthesise a band
  along a photo's edges so that it tiles seamlessly.
- :func:`feature_aligned_texture`: after Xu et al. 2009, a texture along drawn
  curves, its feature lines (edges) laid on them (with :func:`curve_orientation`).
"""

from ..core._lazy import attach
from ..core.em import (Animation, AnimationInfo, Constraints, Fields, Guides, OptimizationInfo, Schedule,  # noqa: F401
                       StageInfo, Terms)  # the option groups and results, importable from here too
from ..core.search import Search  # noqa: F401
from ._kwatra import animate_texture, optimize_texture
from ._completion import inpaint, make_tileable, uncrop

# Ruiters et al. load on first use: their module imports the statistical family (0.1 s), which
# texture optimization does not need
_RUITERS = ("interpolate_textures", "interpolate_neighborhoods", "ridge_feature_map", "edge_feature_map",
            "linear_blend", "transition_alpha_map", "InterpolationInfo", "InterpolationSchedule", "Correspondences",
            "NeighborhoodSet", "InterpolationUpdate", "VaryingAlpha")
# the feature-aligned planar form reads Ruiters' edge feature map: loaded on first use too
_FEATURE_ALIGNED = ("feature_aligned_texture", "curve_orientation", "FeatureTextureInfo")
__getattr__ = attach(__name__, names={**{name: "._ruiters" for name in _RUITERS},
                                      **{name: "._feature_aligned" for name in _FEATURE_ALIGNED}})[0]

__all__ = [
    "optimize_texture", "animate_texture", "inpaint", "uncrop",
    "make_tileable",
    "interpolate_textures", "interpolate_neighborhoods", "ridge_feature_map", "edge_feature_map",
    "linear_blend", "transition_alpha_map", "InterpolationInfo", "InterpolationSchedule", "Correspondences",
    "NeighborhoodSet", "InterpolationUpdate", "VaryingAlpha", *_FEATURE_ALIGNED,
]


def __dir__():
    return sorted(set(globals()) | set(_RUITERS) | set(_FEATURE_ALIGNED))
