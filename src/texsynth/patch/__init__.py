"""Patch-based synthesis: whole pieces of the exemplar pasted and joined.

- :func:`patchwork`, :func:`patchwork_video`, :func:`patchwork_transfer`:
  Harrison 2002, random Voronoi patches with invisible joins (images, looping
  video, texture transfer); :func:`voronoi_weights` draws the patch shapes.
- :func:`quilt`, :func:`quilt_transfer`: Efros & Freeman 2001, blocks joined
  along minimum-error boundary cuts, and texture transfer.
- :func:`patch_sampling`: Liang et al. 2001, patches chosen by their boundary
  zones, feathered.
"""

from ._patch_sampling import PatchSamplingInfo, patch_sampling
from ._patchwork import PatchworkInfo, patchwork, patchwork_transfer, patchwork_video, voronoi_weights
from ._quilting import QuiltInfo, QuiltTransferInfo, quilt, quilt_transfer

__all__ = ["patchwork", "patchwork_video", "patchwork_transfer", "voronoi_weights", "PatchworkInfo",
           "quilt", "quilt_transfer", "patch_sampling", "QuiltInfo", "QuiltTransferInfo", "PatchSamplingInfo"]
