"""Procedural textures: Perlin noise, turbulence, fBm, marble, wood and reaction-diffusion.

Functions of space rather than of an exemplar (the lecture slides "Procedural
Textures" to "Solid Textures"):

- :func:`perlin` -- Perlin gradient noise in 2-D and 3-D, on a grid (image or
  volume) or at arbitrary points, optionally periodic (tileable);
- :func:`turbulence` and :func:`fbm` -- sums of noise octaves, truncated at the
  band limit of the grid;
- :func:`marble` and :func:`wood` -- solid textures through a colour transfer
  function, as 2-D images or 3-D volumes;
- :func:`reaction_diffusion` (Turk 1991) and :func:`gray_scott` (Pearson
  1993) -- patterns grown by two reacting, diffusing chemicals.
"""

from ._noise import FADES, band_limit_octaves, perlin
from ._patterns import MARBLE_COLORS, WOOD_COLORS, apply_colormap, fbm, marble, turbulence, wood
from ._reaction_diffusion import (
    GRAY_SCOTT_PRESETS,
    RD_COLORS,
    TURK_PRESETS,
    GrayScottRates,
    ReactionDiffusionInfo,
    TurkRates,
    gray_scott,
    meinhardt_stripes,
    reaction_diffusion,
    stability_limit,
)

__all__ = [
    "perlin",
    "turbulence",
    "fbm",
    "marble",
    "wood",
    "reaction_diffusion",
    "gray_scott",
    "meinhardt_stripes",
    "apply_colormap",
    "band_limit_octaves",
    "stability_limit",
    "ReactionDiffusionInfo",
    "TurkRates",
    "GrayScottRates",
    "FADES",
    "MARBLE_COLORS",
    "WOOD_COLORS",
    "TURK_PRESETS",
    "GRAY_SCOTT_PRESETS",
    "RD_COLORS",
]
