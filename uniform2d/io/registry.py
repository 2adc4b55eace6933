"""The one registry of file formats: which extension is read or written by what.

Two tables, both keyed by lower-case extension:

* :data:`POLYGON_FORMATS` -- polygon files, each with a reader returning a
  :class:`uniform2d.Polygon` and a writer;
* :data:`MESH_FORMATS` -- triangle mesh files, each with a writer taking
  ``(path, points, triangles, point_data)`` and a reader returning
  ``(points, triangles)``.

Extensions may be compound (``.truss.json``, ``.vol.gz``); a file name is
matched against the longest registered extension it ends with, ignoring case.
Everything that lists formats -- :func:`polygon_formats`, :func:`mesh_formats`,
the error for an unknown extension, the command line's help -- reads these
tables, so a format is added in exactly one place.

Mesh formats were kept only if meshio 5.3.5 round-trips points (x, y) and
triangles of a 2-D mesh exactly here.  Left out: ``.stl`` (no shared vertices,
float32), Nastran ``.bdf/.nas/.fem`` (fixed-width fields lose digits),
``.xdmf``/``.med``/``.cgns``/``.h5m`` (need h5py), Exodus ``.e/.exo`` (need
netCDF4), DOLFIN ``.xml`` (meshio prints a deprecation warning on every use),
``.ugrid``/``.f3grid``/``.wkt``/TetGen ``.node/.ele`` (fail on triangle meshes) and
``.svg`` (write only).

Examples
--------
>>> from uniform2d.io import polygon_formats, mesh_formats
>>> list(polygon_formats())
['.json', '.geojson', '.wkt', '.poly', '.dxf']
>>> mesh_formats()[".csv"]
'truss: nodes, members (with lengths) and triangles in one CSV table'
>>> find_mesh_format("Panel.Truss.JSON").extension
'.truss.json'
>>> find_polygon_format("plate.step")
Traceback (most recent call last):
    ...
uniform2d.errors.UnsupportedFormatError: cannot read a polygon from 'plate.step': unknown extension '.step'; polygon extensions: .json, .geojson, .wkt, .poly, .dxf
"""

from __future__ import annotations

from pathlib import Path

from ..errors import UnsupportedFormatError
from . import (
    abaqus_file,
    dxf_file,
    geojson_file,
    gmsh_file,
    json_file,
    poly_file,
    wkt_file,
)
from . import truss as _truss
from .fileformat import FileFormat
from .mesh_files import meshio_reader, meshio_writer
from .vtk_file import vtk_writer

__all__ = [
    "MESH_FORMATS",
    "POLYGON_FORMATS",
    "find_mesh_format",
    "find_polygon_format",
    "match_format",
    "mesh_formats",
    "polygon_formats",
]


def _table(*formats: FileFormat) -> dict[str, FileFormat]:
    return {f.extension: f for f in formats}


#: Each polygon format module declares its own entry (its ``FORMAT``), in this order.
POLYGON_FORMATS: dict[str, FileFormat] = _table(
    json_file.FORMAT, geojson_file.FORMAT, wkt_file.FORMAT, poly_file.FORMAT, dxf_file.FORMAT,
)


def _meshio(ext, description, name, *, pad_z=False, int32=False, point_data=False,
            regions=None, writer=None, reader=None, sets=False, element_types=(), **options):
    return FileFormat(
        ext,
        description + ("; stored as 3-D points with z = 0" if pad_z else ""),
        meshio_reader(name, ext, regions, reader),
        writer or meshio_writer(name, pad_z=pad_z, int32=int32, regions=regions, **options),
        point_data,
        regions is not None,
        sets=sets,
        element_types=element_types,
    )


MESH_FORMATS: dict[str, FileFormat] = _table(
    _meshio(".vtu", "VTK XML unstructured grid (ParaView), with named sets", "vtu", pad_z=True,
            point_data=True, regions="region", writer=vtk_writer("vtu"), sets=True),
    _meshio(".vtk", "legacy VTK (ParaView, VisIt), with the sets' cells", "vtk", pad_z=True,
            point_data=True, regions="region", writer=vtk_writer("vtk"), sets=True),
    _meshio(".msh", "Gmsh 4.1, ASCII, with named physical groups", "gmsh", regions="gmsh",
            writer=gmsh_file.write_gmsh, sets=True),
    _meshio(".obj", "Wavefront OBJ", "obj", pad_z=True),
    _meshio(".ply", "Stanford PLY", "ply", pad_z=True, int32=True, point_data=True),
    _meshio(".off", "Geomview OFF", "off", pad_z=True),
    _meshio(".inp", "Abaqus input file (CPS3, CPE3 or CAX3 elements), with named sets", "abaqus",
            regions="abaqus", writer=abaqus_file.write_abaqus, reader=abaqus_file.read_abaqus_text,
            sets=True, element_types=abaqus_file.PLANAR_TYPES),
    _meshio(".mesh", "Medit / INRIA mesh, ASCII", "medit", regions="medit"),
    _meshio(".meshb", "Medit / INRIA mesh, binary", "medit", regions="medit"),
    _meshio(".su2", "SU2 native mesh", "su2"),
    _meshio(".vol", "Netgen mesh", "netgen", regions="netgen"),
    _meshio(".vol.gz", "Netgen mesh, gzip-compressed", "netgen", regions="netgen"),
    _meshio(".tec", "Tecplot ASCII", "tecplot", point_data=True, regions="region"),
    _meshio(".avs", "AVS-UCD", "avsucd", pad_z=True, regions="avsucd"),
    _meshio(".mdpa", "Kratos Multiphysics model part", "mdpa", pad_z=True),
    _meshio(".dato", "PERMAS input", "permas", pad_z=True),
    _meshio(".dato.gz", "PERMAS input, gzip-compressed", "permas", pad_z=True),
    FileFormat(
        ".csv",
        "truss: nodes, members (with lengths) and triangles in one CSV table",
        _truss.read_truss_csv,
        _truss.write_truss_csv,
        point_data=True,
        regions=True,
        members=True,
    ),
    FileFormat(
        ".truss.json",
        "truss: JSON with nodes, members, lengths and triangles",
        _truss.read_truss_json,
        _truss.write_truss_json,
        point_data=True,
        regions=True,
        members=True,
    ),
)


def polygon_formats() -> dict[str, str]:
    """Polygon file extensions (read and write) and their descriptions."""
    return {ext: f.description for ext, f in POLYGON_FORMATS.items()}


def mesh_formats() -> dict[str, str]:
    """Mesh file extensions (read and write) and their descriptions."""
    return {ext: f.description for ext, f in MESH_FORMATS.items()}


def match_format(path, table: dict[str, FileFormat]) -> FileFormat | None:
    """The format of ``table`` whose extension ends ``path``'s name (the longest
    one, so ``.vol.gz`` beats ``.gz``), or None."""
    name = Path(path).name.lower()
    best = None
    for ext, fmt in table.items():
        longer = best is None or len(ext) > len(best.extension)
        if name.endswith(ext) and len(name) > len(ext) and longer:
            best = fmt
    return best


def _unsupported(path, kind: str, action: str) -> UnsupportedFormatError:
    table, other, other_kind = (
        (POLYGON_FORMATS, MESH_FORMATS, "mesh")
        if kind == "polygon"
        else (MESH_FORMATS, POLYGON_FORMATS, "polygon")
    )
    verb = f"read a {kind} from" if action == "read" else f"write a {kind} to"
    suffix = Path(path).suffix
    found = f"unknown extension '{suffix}'" if suffix else "the file name has no extension"
    message = f"cannot {verb} '{path}': {found}; {kind} extensions: {', '.join(table)}"
    hit = match_format(path, other)
    if hit is not None:
        message += f" ('{hit.extension}' is a {other_kind} format: use {action}_{other_kind})"
    return UnsupportedFormatError(message)


def find_polygon_format(path, action: str = "read") -> FileFormat:
    """The polygon format for `path`'s extension (`action` is "read" or "write").

    Raises
    ------
    UnsupportedFormatError
        If no polygon format matches; the message lists the supported extensions.
    """
    return _find(path, "polygon", action)


def find_mesh_format(path, action: str = "write") -> FileFormat:
    """The mesh format for `path`'s extension (`action` is "read" or "write").

    Raises
    ------
    UnsupportedFormatError
        If no mesh format matches; the message lists the supported extensions.
    """
    return _find(path, "mesh", action)


def _find(path, kind: str, action: str) -> FileFormat:
    fmt = match_format(path, POLYGON_FORMATS if kind == "polygon" else MESH_FORMATS)
    if fmt is None:
        raise _unsupported(path, kind, action)
    return fmt
