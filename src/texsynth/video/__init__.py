"""Dynamic textures and video: synthesis that learns from a clip.

- :func:`dynamic_texture`, :func:`learn_dynamic_texture`: Doretto, Chiuso, Wu & Soatto 2003, a linear
  dynamical system identified in closed form, which then plays new frames for ever.
- :func:`video_texture`: Schödl, Szeliski, Salesin & Essa 2000, the clip's own frames replayed with
  jumps where two frames are alike: an endless sequence, or a seamless loop of a requested length.
- :func:`graphcut_video`: Kwatra, Schödl, Essa, Turk & Bobick 2003, Section 5: spatio-temporal patches
  of the clip joined along 3-D minimum cuts (the 2-D graph-cut textures' seam code), longer, larger or
  looping.
- :func:`stylize_video`: in the spirit of Jamriška et al. 2019 (ebsynth): every frame painted in the
  style of painted keyframes by guided synthesis on the EM core, coherent in time along the frames'
  motion, blended between keyframes.

Clips are ``(T, H, W[, C])``; :func:`texsynth.data.clip` makes simulated ones.
"""

from ._doretto import DynamicTexture, DynamicTextureInfo, dynamic_texture, learn_dynamic_texture
from ._graphcut_video import GraphcutVideoInfo, graphcut_video
from ._jamriska import StylizeInfo, stylize_video
from ._schodl import VideoTextureInfo, video_texture

__all__ = ["dynamic_texture", "learn_dynamic_texture", "DynamicTexture", "DynamicTextureInfo",
           "video_texture", "VideoTextureInfo", "graphcut_video", "GraphcutVideoInfo", "stylize_video", "StylizeInfo"]
