"""Reading and writing surface patches through trimesh.

Any format trimesh reads can be read (OBJ, PLY, STL, OFF, GLB, and the meshio
formats when meshio is installed); polygonal faces in a file are triangulated by
trimesh while reading.  Writing supports trimesh's mesh exporters
(:data:`WRITE_FORMATS`) and is atomic: the file is written to a temporary file in
the same directory and moved into place with :func:`os.replace`, so a reader never
sees a half-written file.
"""

from __future__ import annotations

import logging
import os
import tempfile
from pathlib import Path

import numpy as np

from uniform2d.errors import FileFormatError, UnsupportedFormatError

from .errors import InvalidPatchError
from .model import Model
from .patch import Patch

__all__ = ["read_patch", "read_model", "write_patch", "as_patch", "as_model", "WRITE_FORMATS"]

log = logging.getLogger(__name__)

#: File extensions :func:`write_patch` accepts.
WRITE_FORMATS = ("obj", "off", "ply", "stl", "glb", "inp")


def suffix(path: Path) -> str:
    """The file's format extension, lower case, without the dot (``stl_ascii``,
    ``vol.gz`` and such double extensions whole)."""
    name = path.name.lower()
    for double in ("stl_ascii", "dato.gz", "post.gz", "vol.gz"):
        if name.endswith("." + double):
            return double
    return path.suffix.lower().lstrip(".")


def read_patch(path) -> Patch:
    """Read a triangle mesh file and check it as a patch (a disk with holes).

    See :func:`read_model` for what is read; the checks are :class:`Patch`'s.
    """
    return Patch(*_load(path))


def read_model(path) -> Model:
    """Read a triangle mesh file and check it as a whole model.

    Parameters
    ----------
    path : str or os.PathLike
        Any mesh format trimesh can load.  Several meshes in one file (a scene) are
        concatenated, which the checks then refuse as several components.  Vertices
        with bit-identical coordinates are merged (STL stores every triangle
        separately); nothing else is changed.

    Returns
    -------
    Model

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    UnsupportedFormatError
        If trimesh cannot read files with this extension.
    FileFormatError
        If trimesh fails to parse the file.
    InvalidPatchError
        If the file holds no triangles or fails a check of :class:`Model`.
    """
    return Model(*_load(path))


def _load(path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of a mesh file, bit-identical duplicates merged."""
    import trimesh

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no such mesh file: {path}")
    ext = suffix(path)
    if ext not in trimesh.available_formats():
        raise UnsupportedFormatError(
            f"{path}: trimesh cannot read '.{ext}' files; use one of "
            "obj, ply, stl, off, glb (or another format listed by trimesh.available_formats())"
        )
    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds on bad content
        raise FileFormatError(f"{path}: trimesh could not read it ({exc})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise InvalidPatchError(
            f"{path}: not a triangle mesh (found {type(mesh).__name__} with no triangles); "
            "export the surface as triangles",
            "not_triangle_mesh",
        )
    V = np.asarray(mesh.vertices, dtype=np.float64)
    F = np.asarray(mesh.faces, dtype=np.int64)
    uniq, inv = np.unique(V, axis=0, return_inverse=True)
    if len(uniq) < len(V):
        log.info("%s: merging %d duplicated vertices", path, len(V) - len(uniq))
        # keep the first occurrence order so indices stay close to the file's
        first = np.full(len(uniq), len(V))
        np.minimum.at(first, inv.ravel(), np.arange(len(V)))
        rank = np.empty(len(uniq), dtype=np.int64)
        rank[np.argsort(first)] = np.arange(len(uniq))
        V = V[np.sort(first)]
        F = rank[inv.ravel()][F]
    return V, F


def _default_mode(path: Path) -> int:
    """The existing file's permissions, else what a plain open() would give."""
    try:
        return path.stat().st_mode & 0o777
    except FileNotFoundError:
        mask = os.umask(0)
        os.umask(mask)
        return 0o666 & ~mask


def _write_exact_text(fh, ext: str, V: np.ndarray, F: np.ndarray) -> None:
    """OBJ or OFF with every coordinate in shortest round-trip form (%.17g).

    trimesh's ``digits`` counts decimal places, not significant digits, so small
    coordinates would lose precision; these two formats are simple enough to write.
    """
    import io

    buf = io.StringIO()
    if ext == "off":
        buf.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(buf, V, fmt="%.17g")
        np.savetxt(buf, np.c_[np.full(len(F), 3), F], fmt="%d")
    else:
        np.savetxt(buf, V, fmt="v %.17g %.17g %.17g")
        np.savetxt(buf, F + 1, fmt="f %d %d %d")
    fh.write(buf.getvalue().encode("ascii"))


def write_patch(path, vertices, faces, *, element_type=None) -> Path:
    """Write a triangle mesh atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; the extension picks the format (:data:`WRITE_FORMATS`).
    vertices : array_like, shape (N, 3)
    faces : array_like, shape (M, 3)
    element_type : str, optional
        The Abaqus shell element type of an ``.inp`` file: ``S3`` (default) or
        ``S3R`` (:mod:`uniform2d.io.abaqus_file`).

    OBJ, OFF and Abaqus INP are written with 17 significant digits (coordinates
    read back exactly); PLY, STL and GLB store single precision (about 1e-7
    relative), and STL does not store shared vertices (they are merged on reading).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    UnsupportedFormatError
        If the extension is not in :data:`WRITE_FORMATS`.
    InvalidArgumentError
        If `element_type` is given for another format than ``.inp``, or is not
        a shell type.
    """
    import trimesh

    from uniform2d.errors import InvalidArgumentError
    from uniform2d.io.abaqus_file import element_type_for, write_abaqus

    path = Path(path)
    ext = suffix(path)
    if ext not in WRITE_FORMATS:
        raise UnsupportedFormatError(
            f"{path}: cannot write '.{ext}' files; use one of {', '.join(WRITE_FORMATS)}"
        )
    if element_type is not None and ext != "inp":
        raise InvalidArgumentError(f"{path}: an element type is written to .inp files only")
    element_type = element_type_for(3, element_type) if ext == "inp" else None
    V = np.asarray(vertices, dtype=np.float64)
    F = np.asarray(faces, dtype=np.int64)
    mesh = trimesh.Trimesh(V, F, process=False, validate=False)
    directory = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=f".{ext}", dir=directory)
    try:
        os.chmod(tmp, _default_mode(path))
        if ext == "inp":
            os.close(fd)
            write_abaqus(tmp, V, F, element_type=element_type)
        else:
            with os.fdopen(fd, "wb") as fh:
                if ext in ("obj", "off"):
                    _write_exact_text(fh, ext, V, F)
                else:
                    mesh.export(fh, file_type=ext)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


def as_patch(obj) -> Patch:
    """Convert a path, a ``(vertices, faces)`` pair, a trimesh or a :class:`Patch`.

    Parameters
    ----------
    obj : str, os.PathLike, tuple, trimesh.Trimesh or Patch
        A mesh file readable by trimesh, a ``(V, F)`` pair of array-likes, any
        object with ``vertices`` and ``faces`` attributes, or a Patch (returned as is).

    Returns
    -------
    Patch
    """
    if isinstance(obj, Patch):
        return obj
    return Patch(*_arrays(obj))


def as_model(obj) -> Model:
    """Convert a path, a ``(vertices, faces)`` pair, a trimesh, a :class:`Patch`
    or a :class:`Model` (returned as is) to a :class:`Model`."""
    if isinstance(obj, Model):
        return obj
    if isinstance(obj, Patch):
        return Model(obj.vertices, obj.faces)
    return Model(*_arrays(obj))


def _arrays(obj):
    if isinstance(obj, (str, os.PathLike)):
        return _load(obj)
    if hasattr(obj, "vertices") and hasattr(obj, "faces"):
        return obj.vertices, obj.faces
    if isinstance(obj, (tuple, list)) and len(obj) == 2:
        return obj[0], obj[1]
    raise InvalidPatchError(
        f"cannot read a patch from a {type(obj).__name__}; pass a mesh file path, a "
        "(vertices, faces) pair of arrays or a trimesh.Trimesh",
        "not_triangle_mesh",
    )
