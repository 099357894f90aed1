"""Procedural textures: Perlin noise, turbulence, marble, wood, reaction-diffusion."""
from .noise import perlin, band_limit_octaves
from .patterns import turbulence, fbm, marble, wood, apply_colormap, MARBLE_COLORS, WOOD_COLORS
from .reaction_diffusion import reaction_diffusion, gray_scott, TURK_PRESETS, GRAY_SCOTT_PRESETS, ReactionDiffusionInfo, stability_limit
