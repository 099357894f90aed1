"""Patch-based synthesis: whole pieces of the exemplar pasted and joined.

- :func:`patchwork`, :func:`patchwork_video`, :func:`patchwork_transfer`:
  Harrison 2002, random Voronoi patches with invisible joins (images, looping
  video, texture transfer); :func:`voronoi_weights` draws the patch shapes.
"""

from ._patchwork import PatchworkInfo, patchwork, patchwork_transfer, patchwork_video, voronoi_weights

__all__ = ["patchwork", "patchwork_video", "patchwork_transfer", "voronoi_weights", "PatchworkInfo"]
