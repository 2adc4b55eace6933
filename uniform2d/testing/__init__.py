"""Tools for testing code that makes or uses triangle meshes of polygons.

uniform2d's own tests use them, and so can yours (as ``numpy.testing`` and
``shapely.testing`` serve their users):

* :func:`check_mesh` -- an independent check that a mesh is a valid (constrained
  Delaunay) triangulation of a :class:`~uniform2d.Polygon`: it shares no code
  with the mesher, rebuilds the adjacency with numpy and decides the signs in
  floating point with an error bound, exactly where that bound is not met
  (:mod:`uniform2d.testing.checks`);
* random polygons fully described by a seed: reasonable ones
  (:mod:`uniform2d.testing.polygons`) and the shapes that break meshers, at every
  scale, with and without interior constraints (:mod:`uniform2d.testing.fuzz`).
"""

from .checks import check_mesh, edge_table, non_delaunay_edges, orientations, segment_chains

__all__ = ["check_mesh", "edge_table", "non_delaunay_edges", "orientations", "segment_chains"]
