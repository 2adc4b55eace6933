"""File input and output: polygons in, meshes out, chosen by file extension.

>>> from uniform2d.io import read_polygon, write_mesh, polygon_formats, mesh_formats

Polygon files (:func:`read_polygon`, :func:`write_polygon`), one module per
format that reads and writes everything the format carries (rings, interior
segments, fixed points and region labels): ``.json`` (our own format,
:mod:`~uniform2d.io.json_file`), ``.geojson`` (:mod:`~uniform2d.io.geojson_file`),
``.wkt`` (:mod:`~uniform2d.io.wkt_file`), Triangle's ``.poly``
(:mod:`~uniform2d.io.poly_file`) and ``.dxf`` (:mod:`~uniform2d.io.dxf_file`);
what they share is :mod:`uniform2d.io.common`.
Meshes carry their regions as cell data where the format has it
(:mod:`uniform2d.io.cells`); ``.msh``, ``.inp``, ``.vtu`` and ``.vtk`` also
carry the named sets of :mod:`uniform2d.io.mesh_sets` (regions, rings,
segments, fixed points), written by :mod:`~uniform2d.io.gmsh_file`,
:mod:`~uniform2d.io.abaqus_file` and :mod:`~uniform2d.io.vtk_file`.  Mesh files
(:func:`write_mesh`, :func:`read_mesh`): meshio formats (``.vtu``, ``.msh``,
``.obj``, ...) and two truss formats for structural design, ``.csv`` and
``.truss.json`` (see :mod:`uniform2d.io.truss`).  The single list of formats is
:mod:`uniform2d.io.registry`.
"""

from .readwrite import read_mesh, read_polygon, write_mesh, write_polygon
from .registry import mesh_formats, polygon_formats

__all__ = [
    "read_polygon",
    "write_polygon",
    "read_mesh",
    "write_mesh",
    "polygon_formats",
    "mesh_formats",
]
