"""Mesh files through meshio: readers and writers for one meshio format each.

:func:`meshio_reader` and :func:`meshio_writer` make the functions that the
registry (:mod:`uniform2d.io.registry`) lists for each meshio-backed extension.
A uniform2d mesh is planar: ``points (N, 2) float64`` and ``triangles (M, 3)
int``.  Formats that only store 3-D points get ``z = 0`` appended on writing
(``pad_z``) -- that also keeps meshio from printing its own warning about it --
and on reading a third coordinate must be zero (within 1e-12 of the extent).

meshio reports problems by printing to stderr; those messages are captured
during each call and passed on as logged warnings instead (the capture swaps
``sys.stderr`` for the duration of the call, as :func:`contextlib.redirect_stderr`
does).

Only triangle cells are read; ``vertex`` and ``line`` cells (boundary elements
written by Gmsh and friends) are skipped silently, other cell types with a
logged warning.

Examples
--------
>>> import os, tempfile
>>> from uniform2d.io.mesh_files import meshio_reader, meshio_writer
>>> path = os.path.join(tempfile.mkdtemp(), "tri.obj")
>>> meshio_writer("obj", pad_z=True)(path, [[0., 0.], [1., 0.], [0., 1.]], [[0, 1, 2]])
>>> points, triangles = meshio_reader("obj")(path)
>>> points.tolist(), triangles.tolist()
([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [[0, 1, 2]])
"""

from __future__ import annotations

import contextlib
import gzip
import io
import logging
import os
import re
import shutil
import tempfile
import zlib
from collections import Counter

import numpy as np

from ..errors import FileFormatError
from . import cells as _cells

__all__ = ["meshio_reader", "meshio_writer", "write_meshio", "check_planar_mesh"]

logger = logging.getLogger(__name__)

_SKIPPED_SILENTLY = {"vertex", "line", "line3"}


@contextlib.contextmanager
def _meshio_messages(path):
    """Turn whatever meshio prints during the block into logged warnings."""
    buffer = io.StringIO()
    try:
        with contextlib.redirect_stderr(buffer), contextlib.redirect_stdout(buffer):
            yield
    finally:
        text = " ".join(buffer.getvalue().split())
        if text:
            logger.warning("%s: meshio says: %s", path, text)


@contextlib.contextmanager
def _readable_name(path, extension):
    """A name meshio's reader understands for ``path``: the path itself; a
    lower-case link to it (some readers only know lower-case extensions); or,
    for a ``.gz`` extension, a decompressed copy."""
    name = str(path)
    if extension and extension.endswith(".gz") and name.lower().endswith(extension):
        # decompressed here: meshio's PERMAS reader does not read gzip at all
        with tempfile.TemporaryDirectory() as tmp:
            plain = os.path.join(tmp, "mesh" + extension[: -len(".gz")])
            try:
                with gzip.open(name, "rb") as src, open(plain, "wb") as dst:
                    shutil.copyfileobj(src, dst)
            except (OSError, EOFError, zlib.error) as exc:
                if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
                    raise
                raise FileFormatError(f"{path}: not a readable gzip file ({exc})") from None
            yield plain
        return
    if not extension or name.endswith(extension) or not name.lower().endswith(extension):
        yield name
        return
    with tempfile.TemporaryDirectory() as tmp:
        link = os.path.join(tmp, "mesh" + extension)
        try:
            os.symlink(os.path.abspath(name), link)
        except OSError:  # pragma: no cover - no symlinks (Windows without privilege)
            shutil.copyfile(name, link)
        yield link


def check_planar_mesh(path, points, triangles):
    """Return ``(points (N, 2) float64, triangles (M, 3) int64)`` read from `path`, checked.

    Raises :class:`~uniform2d.errors.FileFormatError` if the points are not planar
    (z = 0), not finite, or a triangle refers to a point that does not exist.
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise FileFormatError(f"{path}: points have shape {pts.shape}; expected (N, 2) or (N, 3)")
    if not np.isfinite(pts).all():
        raise FileFormatError(f"{path}: a point has a non-finite coordinate")
    if pts.shape[1] == 3:
        z = np.abs(pts[:, 2])
        extent = float(np.ptp(pts[:, :2], axis=0).max()) if len(pts) else 0.0
        if len(z) and z.max() > 1e-12 * max(extent, 1e-300):
            raise FileFormatError(
                f"{path}: the mesh is not planar (|z| up to {z.max():.6g}); "
                "uniform2d meshes lie in the plane z = 0"
            )
        pts = pts[:, :2]
    tri = np.asarray(triangles)
    if tri.size and not np.issubdtype(tri.dtype, np.integer):
        raise FileFormatError(f"{path}: triangle indices are not integers")
    tri = tri.astype(np.int64).reshape(-1, 3)
    if tri.size and (tri.min() < 0 or tri.max() >= len(pts)):
        bad = int(tri.max() if tri.max() >= len(pts) else tri.min())
        raise FileFormatError(
            f"{path}: a triangle refers to point {bad}, but there are {len(pts)} points"
        )
    return np.ascontiguousarray(pts), tri


def meshio_reader(file_format: str, extension: str | None = None, regions: str | None = None,
                  reader=None):
    """A reader ``path -> (points (N, 2), triangles (M, 3))`` for one meshio format.

    `file_format` names both meshio's format and its submodule (``"vtu"`` ->
    ``meshio.vtu.read``).  The submodule's reader is called directly:
    :func:`meshio.read` prints to stderr and calls ``sys.exit`` when a file does
    not parse, which a library must not do.  Some meshio readers look at the
    file name (``.meshb`` is binary) and only understand lower case; a file
    named ``MESH.MESHB`` is read through a temporary link named with the
    lower-case `extension`.  ``.gz`` files are decompressed here first (the
    PERMAS reader reads no gzip; see :func:`_readable_name`).  With
    ``regions=True`` the reader returns ``(points, triangles, regions)``, the
    regions read as style `regions` of :mod:`uniform2d.io.cells` says (None when
    the file has none, or the format stores none).  `reader` replaces meshio's
    (a function ``name -> meshio.Mesh``).
    """
    style = regions
    own = reader

    def read(path, regions=False):
        import meshio

        reader = own or getattr(meshio, file_format).read
        try:
            with _meshio_messages(path), _readable_name(path, extension) as name:
                mesh = reader(name)
        except (FileNotFoundError, PermissionError, IsADirectoryError):
            raise
        except Exception as exc:  # meshio raises all sorts of things on bad input
            raise FileFormatError(
                f"{path}: not a readable {file_format} file ({type(exc).__name__}: {exc})"
            ) from exc
        blocks = [c.data for c in mesh.cells if c.type == "triangle"]
        others = Counter(
            c.type for c in mesh.cells if c.type != "triangle" and c.type not in _SKIPPED_SILENTLY
        )
        if others:
            logger.warning(
                "%s: ignoring non-triangle cells (%s)",
                path,
                ", ".join(f"{n} blocks of {t}" for t, n in sorted(others.items())),
            )
        if not blocks:
            kinds = ", ".join(sorted({c.type for c in mesh.cells})) or "no cells at all"
            raise FileFormatError(f"{path}: contains no triangles ({kinds})")
        pts, tri = check_planar_mesh(path, mesh.points, np.concatenate(blocks))
        if not regions:
            return pts, tri
        return pts, tri, (_cells.from_meshio(path, style, mesh, len(tri)) if style else None)

    read.__name__ = f"read_{file_format}"
    read.__doc__ = f"Read a triangle mesh with meshio's {file_format!r} reader."
    return read


_STAMP = re.compile(rb"(Created by meshio v[^,\r\n]*), [^\r\n]*")


def _drop_timestamp(name: str) -> None:
    """Remove the time meshio writes into some headers (OBJ, PLY): same input, same bytes."""
    with open(name, "rb") as f:
        head = f.read(4096)
        if b"Created by meshio" not in head:
            return
        rest = f.read()
    with open(name, "wb") as f:
        f.write(_STAMP.sub(rb"\1", head, count=1) + rest)


def write_meshio(path, mesh, file_format: str, **options) -> None:
    """Write a :class:`meshio.Mesh` with meshio's `file_format` writer: its messages
    logged, no time stamp in the header, ``.gz`` names compressed here (with no
    name or time in the gzip header: same input, same bytes)."""
    import meshio

    name = str(path)
    gz = name.lower().endswith(".gz")
    plain = name[: -len(".gz")] if gz else name
    try:
        with _meshio_messages(path):
            meshio.write(plain, mesh, file_format=file_format, **options)
        _drop_timestamp(plain)
        if gz:
            with open(plain, "rb") as src, open(name, "wb") as raw:
                with gzip.GzipFile(filename="", mode="wb", fileobj=raw, mtime=0) as dst:
                    shutil.copyfileobj(src, dst)
    finally:
        if gz and os.path.exists(plain):
            os.unlink(plain)


def meshio_writer(file_format: str, *, pad_z: bool = False, int32: bool = False,
                  regions: str | None = None, **options):
    """A writer ``(path, points, triangles, point_data=None, *, regions=None,
    labels=None)`` for one meshio format.

    Parameters
    ----------
    file_format : str
        meshio's name of the format (``"vtu"``, ``"gmsh"``, ...).
    pad_z : bool
        Append ``z = 0`` to the points (for formats that store only 3-D points).
    int32 : bool
        Write the triangles as 32-bit integers (for formats without 64-bit ones).
    regions : str, optional
        How the format stores one region per triangle (a style of
        :mod:`uniform2d.io.cells`); None if it cannot.
    **options
        Passed on to meshio's writer (e.g. ``binary=False``).
    """

    style = regions

    def write(path, points, triangles, point_data=None, *, regions=None, labels=None):
        import meshio

        pts = np.asarray(points, dtype=np.float64)
        if pad_z:
            pts = np.column_stack([pts, np.zeros(len(pts))])
        tri = np.asarray(triangles, dtype=np.int32 if int32 else None)
        more = _cells.to_meshio(style, regions) if style and regions is not None else {}
        mesh = meshio.Mesh(
            pts,
            [("triangle", tri)],
            point_data={k: np.asarray(v) for k, v in (point_data or {}).items()},
            **more,
        )
        write_meshio(path, mesh, file_format, **options)

    write.__name__ = f"write_{file_format}"
    write.__doc__ = f"Write a triangle mesh with meshio's {file_format!r} writer."
    return write
