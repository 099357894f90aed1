"""texsynth: example-based texture synthesis on one shared numpy layer.

The algorithms are functions at the top level (``texsynth.heeger_bergen``, ...);
the shared layer and the tools are submodules: :mod:`texsynth.neighborhood`,
:mod:`texsynth.pyramid`, :mod:`texsynth.nearest`, :mod:`texsynth.metrics`,
:mod:`texsynth.testing`, :mod:`texsynth.io`, :mod:`texsynth.data`.
"""

from . import data, flows, io, metrics, nearest, neighborhood, procedural, pyramid, testing, tps
from .heeger_bergen import heeger_bergen
from .interpolation import edge_feature_map, interpolate_textures, linear_blend, ridge_feature_map
from .multisource import mix_textures, synthesize_pixels, synthesize_solid
from .optimization import animate_texture, optimize_texture
from .portilla_simoncelli import interpolate_statistics, portilla_simoncelli, ps_statistics, ps_step
from .patchwork import patchwork, patchwork_transfer, patchwork_video

__version__ = "0.1.0"

__all__ = [
    "synthesize_pixels",
    "mix_textures",
    "synthesize_solid",
    "optimize_texture",
    "animate_texture",
    "heeger_bergen",
    "interpolate_textures",
    "ridge_feature_map",
    "edge_feature_map",
    "linear_blend",
    "portilla_simoncelli",
    "ps_statistics",
    "ps_step",
    "interpolate_statistics",
    "patchwork",
    "patchwork_video",
    "patchwork_transfer",
    "data",
    "flows",
    "io",
    "metrics",
    "nearest",
    "neighborhood",
    "procedural",
    "pyramid",
    "testing",
    "tps",
    "__version__",
]
