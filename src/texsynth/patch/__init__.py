"""Patch-based synthesis: whole pieces of the exemplar pasted and joined.

- :func:`patchwork`, :func:`patchwork_video`, :func:`patchwork_transfer`:
  Harrison 2002, random Voronoi patches with invisible joins (images, looping
  video, texture transfer); :func:`voronoi_weights` draws the patch shapes.
- :func:`quilt`, :func:`quilt_transfer`: Efros & Freeman 2001, blocks joined
  along minimum-error boundary cuts, and texture transfer.
- :func:`patch_sampling`: Liang et al. 2001, patches chosen by their boundary
  zones, feathered.
- :func:`graphcut_texture`, :func:`graphcut_merge`: Kwatra et al. 2003, patches
  joined along graph min-cuts with refinement, and interactive merging.
- :func:`carve_seams`: Avidan & Shamir 2007, content-aware resizing and object
  removal by removing and inserting seams of least energy.
- :func:`wang_tiles`, :func:`wang_tiling`, :func:`wang_texture`: Cohen et al.
  2003, a set of tiles with coloured edges quilted from diamonds, tiled at random.
- :func:`near_regular_texture`: after Liu, Lin & Hays 2004, whole cells of the
  exemplar's lattice (tiles, parquet, bricks) placed on the output's lattice.
"""

from ._graphcut import GraphcutInfo, GraphcutMergeInfo, graphcut_merge, graphcut_texture
from ._near_regular import NearRegularInfo, find_lattice, near_regular_texture
from ._patch_sampling import PatchSamplingInfo, patch_sampling
from ._patchwork import PatchworkInfo, patchwork, voronoi_weights
from ._patchwork_transfer import patchwork_transfer
from ._patchwork_video import patchwork_video
from ._quilting import QuiltInfo, QuiltTransferInfo, quilt, quilt_transfer
from ._seam_carving import SeamCarvingInfo, carve_seams
from ._wang_tiles import WangTileSet, WangTilesInfo, WangTilingInfo, wang_texture, wang_tiles, wang_tiling

__all__ = ["patchwork", "patchwork_video", "patchwork_transfer", "voronoi_weights", "PatchworkInfo",
           "quilt", "quilt_transfer", "patch_sampling", "QuiltInfo", "QuiltTransferInfo", "PatchSamplingInfo",
           "graphcut_texture", "graphcut_merge", "GraphcutInfo", "GraphcutMergeInfo",
           "carve_seams", "SeamCarvingInfo", "wang_tiles", "wang_tiling", "wang_texture", "WangTileSet",
           "WangTilesInfo", "WangTilingInfo", "near_regular_texture", "NearRegularInfo",
           "find_lattice"]
