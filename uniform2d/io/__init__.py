"""File input and output: polygons in, meshes out, chosen by file extension.

>>> from uniform2d.io import read_polygon, write_mesh, polygon_formats, mesh_formats

Polygon files (:func:`read_polygon`, :func:`write_polygon`): ``.json`` (our own
format), ``.geojson``, ``.wkt``, Triangle's ``.poly`` and ``.dxf``, with interior
segments, fixed points and region labels (:mod:`uniform2d.io.constrained_files`).
Meshes carry their regions as cell data where the format has it
(:mod:`uniform2d.io.cells`).  Mesh files
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
