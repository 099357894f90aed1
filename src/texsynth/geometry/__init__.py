"""Geometry synthesis by example: surfaces and volumes made from an example shape.

- :func:`synthesize_geometry`: after Lagae, Dumont & Dutré 2005, the example as a signed distance
  volume, quilted block by block (3-D minimum cuts) into a larger one, optionally copying the example's
  own separate elements whole; :func:`sdf_to_mesh` turns a distance volume into a watertight triangle
  mesh (marching cubes) that :func:`texsynth.render_mesh` and :func:`texsynth.write_mesh` take.
"""

from ._lagae import GeometryInfo, as_distance_field, sdf_to_mesh, synthesize_geometry

__all__ = ["synthesize_geometry", "sdf_to_mesh", "as_distance_field", "GeometryInfo"]
