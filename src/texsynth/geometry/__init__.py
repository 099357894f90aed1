"""Geometry synthesis by example: surfaces and volumes made from an example shape.

- :func:`synthesize_geometry`: after Lagae, Dumont & Dutré 2005, the example as a signed distance
  volume, quilted block by block (3-D minimum cuts) into a larger one, optionally copying the example's
  own separate elements whole; :func:`sdf_to_mesh` turns a distance volume into a watertight triangle
  mesh (marching cubes) that :func:`texsynth.render_mesh` and :func:`texsynth.write_mesh` take;
  :func:`mesh_to_sdf` the other way: a closed mesh (an OBJ or PLY file's) as a distance volume.
- :func:`geometry_analogies`: after Bhat, Ingram & Turk 2004, image analogies for volumes: a plain model ``a``,
  the same with a geometric texture ``a_prime`` (grooves, pits, spikes, a dilation) and a new plain model ``b``
  give ``b_prime``, the texture laid along a vector field on ``b`` (neighbourhoods sampled in the field's
  frames, voxels visited along the field).
- :func:`mesh_quilting`: after Zhou et al. 2006, a swatch of separate elements (a mesh, one connected
  component per element) quilted over a surface inside a thin shell: patches matched by their elements'
  centres in the overlap, whole elements kept, each bent into the shell, colliding ones dropped.
"""

from ._lagae import GeometryInfo, as_distance_field, sdf_to_mesh, synthesize_geometry
from ._voxelize import mesh_to_sdf
from ._mesh_quilting import QUILT_PLACEMENTS, MeshQuiltingInfo, mesh_quilting
from ._geometry_analogies import AnalogiesInfo, geometry_analogies

__all__ = ["synthesize_geometry", "sdf_to_mesh", "mesh_to_sdf", "as_distance_field", "GeometryInfo",
           "mesh_quilting", "MeshQuiltingInfo", "QUILT_PLACEMENTS", "geometry_analogies", "AnalogiesInfo"]
