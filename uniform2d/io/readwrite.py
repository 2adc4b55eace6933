"""Read and write polygons and meshes, the format chosen by the file's extension.

The extension is looked up in the registry (:mod:`uniform2d.io.registry`);
:func:`polygon_formats` and :func:`mesh_formats` list what is supported.  Every
write is atomic: the file appears complete or not at all, and an existing file
is only replaced once the new one has been written successfully.

Examples
--------
>>> import os, tempfile
>>> from uniform2d import Polygon
>>> from uniform2d.io import read_polygon, write_polygon, read_mesh, write_mesh
>>> d = tempfile.mkdtemp()
>>> square = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], [[(0.4, 0.4), (0.6, 0.4), (0.5, 0.6)]])
>>> write_polygon(os.path.join(d, "square.geojson"), square)
>>> read_polygon(os.path.join(d, "square.geojson")) == square
True
>>> points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
>>> triangles = [[0, 1, 2], [0, 2, 3]]
>>> write_mesh(os.path.join(d, "square.vtu"), points, triangles)
>>> p, t = read_mesh(os.path.join(d, "square.vtu"))
>>> p.shape, p.dtype, t.tolist()
((4, 2), dtype('float64'), [[0, 1, 2], [0, 2, 3]])
"""

from __future__ import annotations

import errno
import logging
from pathlib import Path

import numpy as np

from ..errors import ArgumentTypeError, InvalidArgumentError
from ..polygon import Polygon
from .atomic import atomic_write
from .registry import find_mesh_format, find_polygon_format

__all__ = ["read_polygon", "write_polygon", "read_mesh", "write_mesh"]

logger = logging.getLogger(__name__)


def _existing_file(path, what: str) -> Path:
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(errno.ENOENT, f"{what} file not found", str(p))
    if p.is_dir():
        raise IsADirectoryError(errno.EISDIR, f"expected a {what} file, got a directory", str(p))
    return p


def read_polygon(path) -> Polygon:
    """Read a polygon file.

    Parameters
    ----------
    path : str or os.PathLike
        A file with one of the extensions of :func:`polygon_formats`.

    Returns
    -------
    Polygon

    Raises
    ------
    UnsupportedFormatError
        If the extension is not a polygon format.
    FileNotFoundError
        If the file does not exist.
    FileFormatError
        If the file's content is not a usable polygon (the message says why).
    InvalidPolygonError
        If the file describes an invalid polygon (the file name precedes the reason).
    """
    fmt = find_polygon_format(path, "read")
    p = _existing_file(path, "polygon")
    # NaN, inf or huge coordinates would make numpy and shapely warn on the way to
    # the polygon's own checks, which then say what is wrong in one message
    with np.errstate(all="ignore"):
        polygon = fmt.reader(p)
    logger.debug("read %r from %s", polygon, p)
    return polygon


def write_polygon(path, polygon: Polygon) -> None:
    """Write a polygon to a file, in the format given by the extension.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its extension is one of :func:`polygon_formats`.
    polygon : Polygon

    Raises
    ------
    UnsupportedFormatError
        If the extension is not a polygon format.
    """
    fmt = find_polygon_format(path, "write")
    if not isinstance(polygon, Polygon):
        raise ArgumentTypeError(
            f"write_polygon expects a uniform2d.Polygon, got {type(polygon).__name__}; "
            "build one with Polygon(outer, holes)"
        )
    atomic_write(path, lambda tmp: fmt.writer(tmp, polygon), extension=fmt.extension)


def read_mesh(path, *, regions: bool = False):
    """Read a triangle mesh file.

    Parameters
    ----------
    path : str or os.PathLike
        A file with one of the extensions of :func:`mesh_formats`.
    regions : bool
        Also return the region of every triangle (see :func:`write_mesh`).

    Returns
    -------
    points : ndarray, shape (N, 2), float64
    triangles : ndarray, shape (M, 3), int64
        Only the triangle cells of the file; other cells are skipped.
    regions : ndarray, shape (M,), int64, or None
        Only with ``regions=True``: the region of each triangle, None if the
        file stores none.

    Raises
    ------
    UnsupportedFormatError
        If the extension is not a mesh format.
    FileNotFoundError
        If the file does not exist.
    FileFormatError
        If the file cannot be read as a planar triangle mesh.
    """
    fmt = find_mesh_format(path, "read")
    p = _existing_file(path, "mesh")
    if not regions:
        return fmt.reader(p)
    if not fmt.regions:
        return (*fmt.reader(p), None)
    return fmt.reader(p, regions=True)


def _as_mesh(points, triangles, point_data):
    try:
        pts = np.array(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(f"points must be an (N, 2) array of numbers ({exc})") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InvalidArgumentError(f"points must have shape (N, 2), got {pts.shape}")
    if not np.isfinite(pts).all():
        raise InvalidArgumentError("points contain a non-finite coordinate (NaN or inf)")
    tri = np.array(triangles)
    if tri.size == 0 or tri.ndim != 2 or tri.shape[1] != 3:
        raise InvalidArgumentError(f"triangles must have shape (M, 3) with M >= 1, got {tri.shape}")
    if not np.issubdtype(tri.dtype, np.integer):
        raise InvalidArgumentError(
            f"triangles must be integer point indices, got dtype {tri.dtype}"
        )
    tri = tri.astype(np.int64)
    if tri.min() < 0 or tri.max() >= len(pts):
        raise InvalidArgumentError(
            f"triangles refer to points {tri.min()}..{tri.max()}, but there are {len(pts)} points"
        )
    data = {}
    for name, values in (point_data or {}).items():
        arr = np.array(values)
        if arr.ndim == 0 or len(arr) != len(pts):
            raise InvalidArgumentError(
                f"point data {name!r} must have one entry per point ({len(pts)}), "
                f"got shape {arr.shape}"
            )
        data[str(name)] = arr
    return pts, tri, data


def _as_members(members, n_pts: int, name: str):
    if members is None:
        return None
    edges, ids = (np.asarray(a, dtype=np.int64) for a in members)
    if edges.ndim != 2 or edges.shape[1:] != (2,) or ids.shape != (len(edges),) or (
            edges.size and (edges.min() < 0 or edges.max() >= n_pts)) or (
            ids.size and ids.min() < 0):
        raise InvalidArgumentError(
            f"{name} must be (edges (K, 2) point indices, ids (K,) from 0), "
            f"got shapes {edges.shape} and {ids.shape}")
    return edges, ids


def _as_fixed(fixed, n_pts: int):
    if fixed is None:
        return None
    f = np.asarray(fixed)
    if f.ndim != 1 or (f.size and (not np.issubdtype(f.dtype, np.integer) or f.min() < 0
                                   or f.max() >= n_pts)):
        raise InvalidArgumentError(
            f"fixed_points must be (F,) point indices in 0..{n_pts - 1}, got shape {f.shape} "
            f"and dtype {f.dtype}")
    return f.astype(np.int64)


def _as_regions(regions, labels, members, n_tri: int, n_pts: int):
    if regions is None:
        if labels is not None:
            raise InvalidArgumentError("region_labels given without regions")
        reg = None
    else:
        reg = np.array(regions)
        if reg.shape != (n_tri,) or not np.issubdtype(reg.dtype, np.integer) or (
                n_tri and reg.min() < 0):
            raise InvalidArgumentError(
                f"regions must be one non-negative integer per triangle ({n_tri}), "
                f"got shape {reg.shape} and dtype {reg.dtype}")
        reg = reg.astype(np.int64)
        if labels is not None and len(labels) <= int(reg.max()):
            raise InvalidArgumentError(
                f"region_labels has {len(labels)} entries, but the regions go up to {int(reg.max())}")
    return reg, labels, _as_members(members, n_pts, "segment_members")


def write_mesh(path, points, triangles, *, point_data=None, regions=None, region_labels=None,
               segment_members=None, ring_members=None, fixed_points=None,
               element_type=None) -> None:
    """Write a triangle mesh, in the format given by the extension.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its extension is one of :func:`mesh_formats`.
    points : array_like, shape (N, 2)
    triangles : array_like of int, shape (M, 3)
    point_data : dict of str to array_like, optional
        Values per point (first axis of length N).  Formats that cannot store
        them drop them with a logged warning.
    regions : array_like of int, shape (M,), optional
        The region of every triangle (:attr:`uniform2d.Mesh.regions`), written
        as cell data where the format has it (see :mod:`uniform2d.io.cells`;
        formats without drop them with a logged warning).
    region_labels : sequence, optional
        The label of each region (None for none): Gmsh physical names, Abaqus
        element set names, truss files.
    segment_members : (edges (K, 2), ids (K,)), optional
        Mesh edges on the polygon's segments and their segment
        (:attr:`uniform2d.Mesh.segment_members`): the truss formats mark those
        members with their segment; formats with named sets
        (:mod:`uniform2d.io.mesh_sets`) a set per segment.
    ring_members : (edges (K, 2), ids (K,)), optional
        Mesh edges on the polygon's rings and their ring, 0 the outer one
        (:attr:`uniform2d.Mesh.ring_members`): a set per ring in formats with
        named sets (``.msh``, ``.inp``, ``.vtu``, ``.vtk``), ignored by others.
    fixed_points : array_like of int, shape (F,), optional
        The point of each fixed point of the polygon (``polygon.fixed``): a set
        per point in formats with named sets, ignored by others.
    element_type : str, optional
        The element type of formats that declare one: ``.inp`` takes ``CPS3``
        (plane stress, default), ``CPE3`` (plane strain) or ``CAX3``
        (axisymmetric).

    Raises
    ------
    UnsupportedFormatError
        If the extension is not a mesh format.
    ValueError
        If the arrays do not describe a triangle mesh.

    Notes
    -----
    The inputs are copied, never modified.  The file is written atomically.
    """
    fmt = find_mesh_format(path, "write")
    pts, tri, data = _as_mesh(points, triangles, point_data)
    reg, labels, members = _as_regions(regions, region_labels, segment_members, len(tri), len(pts))
    rings = _as_members(ring_members, len(pts), "ring_members")
    fixed = _as_fixed(fixed_points, len(pts))
    if element_type is not None and str(element_type).upper() not in fmt.element_types:
        hint = (f"use one of {', '.join(fmt.element_types)}" if fmt.element_types else
                f"the {fmt.extension} format declares no element type")
        raise InvalidArgumentError(f"{path}: element type {element_type!r} not available; {hint}")
    if data and not fmt.point_data:
        logger.warning(
            "%s: the %s format does not store point data; dropping %s",
            path,
            fmt.extension,
            ", ".join(data),
        )
        data = {}
    if reg is not None and not fmt.regions:
        logger.warning("%s: the %s format does not store regions; dropping them", path,
                       fmt.extension)
        reg = labels = None
    more = {} if reg is None else {"regions": reg, "labels": labels}
    if members is not None and (fmt.members or fmt.sets):
        more["segment_members"] = members
    if fmt.sets:
        more.update(ring_members=rings, fixed_points=fixed)
    if element_type is not None:
        more["element_type"] = str(element_type).upper()
    atomic_write(path, lambda tmp: fmt.writer(tmp, pts, tri, data, **more),
                 extension=fmt.extension)
