"""Texture synthesis on surfaces: triangle meshes, their files and previews.

- :class:`Mesh`, :func:`as_mesh`: the triangle mesh every surface method
  works on (per-vertex colours or a uv-mapped texture) and its checks.
- :func:`sphere`, :func:`torus`, :func:`bumpy`: test surfaces;
  :func:`scanned_mesh`: a real scan (the Stanford Bunny, ``texsynth[mesh]``).
- :func:`read_mesh`, :func:`write_mesh`: OBJ (with MTL and texture) and PLY
  in numpy, other formats through trimesh (``texsynth[mesh]``).
- :func:`render_mesh`: a z-buffer preview from a few viewpoints.
- :func:`retile`: Turk's evenly spaced retiling; :func:`tangent_field`:
  the orientation (user, random or relaxed, 2-/4-fold symmetric).
- :func:`synthesize_surface`: vertex synthesis over a mesh hierarchy
  (Turk 2001; Wei & Levoy 2001), its options grouped in
  :class:`SurfaceSchedule` and :class:`~texsynth.core.search.Search`; :func:`lapped_textures`: Praun et al.'s
  pasted splotches, baked into a texture atlas.
- :func:`synthesize_btf_surface`, :func:`render_btf_surface`: Tong et al. 2002, a BTF over a mesh
  as a surface texton map (a sample position per vertex), rendered for any light and view.
- :func:`feature_aligned_surface`: Xu et al. 2009, a texture along the mesh's
  salient curves (:func:`salient_curves`: ridges, valleys) or the user's, the
  exemplar's feature lines laid on them; :func:`curve_alignment` measures it.
- :func:`progressive_surface`: progressively-variant textures (Zhang et al. 2003): a texton
  mask, then the texture, varying between two exemplars along a per-vertex transition function.
"""

from ._mesh import Mesh
from ._meshio import as_mesh, read_mesh, write_mesh
from ._render import PROJECTIONS, render_mesh
from ._shapes import SCANNED_MESHES, bumpy, scanned_mesh, sphere, torus
from ._retile import retile
from ._field import tangent_field
from ._vertex_synthesis import SurfaceSchedule, SurfaceSynthesisInfo, synthesize_surface
from ._lapped import LappedInfo, default_splotch, lapped_textures
from ._progressive_surface import ProgressiveSurfaceInfo, progressive_surface
from ._feature_aligned import (FeatureAlignedInfo, SalientCurves, curve_alignment, feature_aligned_surface,
                               salient_curves)
from ._btf import BTFSurface, BTFSurfaceInfo, render_btf_surface, synthesize_btf_surface

__all__ = ["Mesh", "as_mesh", "read_mesh", "write_mesh", "render_mesh", "PROJECTIONS", "sphere", "torus", "bumpy",
           "scanned_mesh", "SCANNED_MESHES", "retile", "tangent_field", "synthesize_surface", "SurfaceSchedule", "SurfaceSynthesisInfo",
           "lapped_textures", "LappedInfo", "default_splotch", "progressive_surface", "ProgressiveSurfaceInfo",
           "synthesize_btf_surface", "render_btf_surface", "BTFSurface", "BTFSurfaceInfo", "feature_aligned_surface",
           "salient_curves", "curve_alignment", "SalientCurves", "FeatureAlignedInfo"]
