"""Pixel-based synthesis: each output pixel chosen by matching its neighbourhood.

- :func:`synthesize_pixels`: Wei & Levoy 2000, multi-resolution, scanline or
  order-independent; with ``candidates="k-coherent"``, Ashikhmin's and Tong
  et al.'s k-coherent candidates.
- :func:`mix_textures`: Wei 2002, a mixture of several sources (eq. 1).
- :func:`synthesize_solid`: Wei 2002, a solid texture from 2-D views.
- :func:`efros_leung`: Efros & Leung 1999, non-parametric sampling grown
  pixel by pixel from a seed; hole filling.
- :func:`synthesize_controlled`: Zhang et al. 2003, texton masks, orientation
  and magnification fields, progressive variation between two exemplars.
- :func:`synthesize_btf`: Tong et al. 2002, a BTF (images under many lights)
  of any size through one k-coherent synthesis of its 3-D texton image.

Option groups: :class:`Neighborhood` (the multi-resolution neighbourhood of
the Wei-Levoy family and Zhang et al.), :class:`Sampling` (Efros-Leung's
sampling); the search is :class:`texsynth.core.search.Search`.
"""

from ._btf import BTFSynthesisInfo, synthesize_btf
from ._efros_leung import EfrosLeungInfo, Sampling, efros_leung
from ._options import ORDERS
from ._texton import ControlledSynthesisInfo, find_textons, synthesize_controlled
from ._wei_2002 import mix_textures, synthesize_solid
from ._wei_levoy import SHAPES, Neighborhood, PixelSynthesisInfo, synthesize_pixels

__all__ = ["synthesize_pixels", "mix_textures", "synthesize_solid", "efros_leung", "PixelSynthesisInfo",
           "EfrosLeungInfo", "ORDERS", "SHAPES", "synthesize_controlled", "find_textons", "ControlledSynthesisInfo",
           "Neighborhood", "Sampling", "synthesize_btf", "BTFSynthesisInfo"]
