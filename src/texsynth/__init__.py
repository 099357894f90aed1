"""texsynth: example-based texture synthesis on one shared numpy layer.

``texsynth.synthesize(exemplar, size)`` is the front door: it analyses the
exemplar and runs the method that suits it. The algorithms are functions at
the top level (``texsynth.optimize_texture``, ``texsynth.patchwork``, ...;
``print(texsynth.methods())`` lists them, one line each), each implemented in
its family:

=============================  ====================================================
:mod:`texsynth.pixel`          pixel-based: Wei-Levoy, Wei's mixtures and solids, Efros-Leung, Zhang et al.
:mod:`texsynth.patch`          patch-based: Harrison's patchwork, image quilting, patch-based sampling, graph cuts, seam carving, Wang tiles
:mod:`texsynth.optimization`   optimization-based: Kwatra, Ruiters
:mod:`texsynth.statistical`    statistical: Heeger-Bergen, Portilla-Simoncelli, random phase noise, tiling and blending
:mod:`texsynth.procedural`     procedural: Perlin noise, marble, reaction-diffusion
:mod:`texsynth.surface`        on surfaces: meshes, their files and previews
:mod:`texsynth.geometry`       geometry by example: distance-field synthesis (Lagae et al.)
:mod:`texsynth.video`          dynamic textures and video: Doretto et al., Schödl et al., Kwatra et al., Jamriška et al.
:mod:`texsynth.core`           the shared layer: neighbourhoods, pyramids, search, EM
=============================  ====================================================

and the tools :mod:`texsynth.metrics`, :mod:`texsynth.testing`,
:mod:`texsynth.io` and :mod:`texsynth.data`. Everything loads on first use,
so ``import texsynth`` is fast.
"""

from .core._lazy import attach
from .core._version import __version__

__getattr__, __dir__, __all__ = attach(
    __name__,
    submodules=["pixel", "patch", "optimization", "statistical", "procedural", "surface", "video", "geometry", "core",
                "metrics", "testing", "io", "data"],
    names={
        **dict.fromkeys(["synthesize_pixels", "mix_textures", "synthesize_solid", "efros_leung",
                         "synthesize_controlled", "find_textons", "Neighborhood", "Sampling"], ".pixel"),
        **dict.fromkeys(["patchwork", "patchwork_video", "patchwork_transfer", "quilt", "quilt_transfer",
                        "patch_sampling", "graphcut_texture", "graphcut_merge", "carve_seams", "wang_texture",
                        "wang_tiles", "wang_tiling", "near_regular_texture"], ".patch"),
        **dict.fromkeys(["optimize_texture", "animate_texture", "inpaint", "uncrop", "interpolate_textures",
                         "make_tileable", "ridge_feature_map",
                         "edge_feature_map", "linear_blend", "InterpolationSchedule", "Correspondences",
                         "NeighborhoodSet", "InterpolationUpdate", "VaryingAlpha", "feature_aligned_texture"],
                        ".optimization"),
        **dict.fromkeys(["heeger_bergen", "portilla_simoncelli", "ps_statistics", "ps_step",
                         "interpolate_statistics", "random_phase_noise", "tile_and_blend", "tile_and_blend_at"],
                        ".statistical"),
        **dict.fromkeys(["read_mesh", "write_mesh", "render_mesh", "synthesize_surface", "SurfaceSchedule",
                         "lapped_textures", "progressive_surface", "feature_aligned_surface"], ".surface"),
        **dict.fromkeys(["dynamic_texture", "learn_dynamic_texture", "video_texture", "graphcut_video", "stylize_video"], ".video"),
        **dict.fromkeys(["Schedule", "Terms", "Constraints", "Guides", "Fields", "Animation"], ".core.em"),
        "Search": ".core.search",
        "apply_coordinates": ".core.coordinates",
        "batch": "._batch",
        **dict.fromkeys(["synthesize", "analyze_exemplar", "choose_method"], "._synthesize"),
        "methods": ".registry",
    },
)
__all__.append("__version__")

