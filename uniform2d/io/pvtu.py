"""ParaView's partitioned VTU: a ``.pvtu`` index and one ``.vtu`` file per piece.

A mesh made in parts (:mod:`uniform2d.partitioned`) is written piece by piece,
each piece by the worker that made it, so the whole mesh is never in one
process.  ``big.pvtu`` lists the pieces, which live in the directory ``big/``
beside it (``big/big_0000.vtu``, ...); every piece carries the global number of
each of its points as the point array ``GlobalPointIds`` (int64), so points on
the seams between pieces, which appear in both, can be told to be one.

The pieces are written into a temporary directory beside the index; only when
all exist is it renamed to ``big/`` and the index written (atomically): an
interrupted or failed run leaves no partial output, and an older output of the
same name stays whole until then.

Examples
--------
>>> import os, tempfile
>>> import numpy as np
>>> from uniform2d.io.pvtu import commit, piece_dir, read_pvtu, write_piece
>>> d = tempfile.mkdtemp()
>>> index = os.path.join(d, "sq.pvtu")
>>> tmp = piece_dir(index)
>>> P = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
>>> write_piece(tmp / "sq_0000.vtu", P[[0, 1, 2]], [[0, 1, 2]], [0, 1, 2])
>>> write_piece(tmp / "sq_0001.vtu", P[[0, 2, 3]], [[0, 1, 2]], [0, 2, 3])
>>> commit(index, tmp, ["sq_0000.vtu", "sq_0001.vtu"])
>>> points, triangles = read_pvtu(index)
>>> points.shape, triangles.tolist()
((4, 2), [[0, 1, 2], [0, 2, 3]])
"""

from __future__ import annotations

import os
import secrets
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .atomic import atomic_write
from .mesh_files import meshio_writer

__all__ = ["GLOBAL_IDS", "REGION", "commit", "piece_dir", "piece_name", "read_pvtu", "write_piece"]

#: The point array carrying every piece point's global number.
GLOBAL_IDS = "GlobalPointIds"

#: The cell array carrying every piece triangle's region (as in a gathered ``.vtu``).
REGION = "region"

_write_vtu = meshio_writer("vtu", pad_z=True, regions="region")


def piece_name(index, k: int) -> str:
    """The file name of piece ``k`` of the index ``index`` (``big_0003.vtu``)."""
    return f"{Path(index).stem}_{k:04d}.vtu"


def piece_dir(index) -> Path:
    """A new temporary directory beside ``index`` for its pieces (made here)."""
    index = Path(index)
    tmp = index.with_name(f".{index.stem}.pieces-{secrets.token_hex(4)}")
    tmp.mkdir()
    return tmp


def write_piece(path, points, triangles, global_ids, regions=None) -> None:
    """One piece: ``points`` (k, 2), ``triangles`` (m, 3) in piece numbering, the
    global number of every point, (k,) int64, and optionally the region of
    every triangle, (m,) int64 (the cell array ``region``)."""
    ids = np.asarray(global_ids, dtype=np.int64)
    _write_vtu(path, np.asarray(points, dtype=np.float64), np.asarray(triangles, dtype=np.int64),
               {GLOBAL_IDS: ids}, regions=regions)


def _index_xml(folder: str, names, regions: bool) -> bytes:
    root = ET.Element("VTKFile", type="PUnstructuredGrid", version="1.0", byte_order="LittleEndian")
    grid = ET.SubElement(root, "PUnstructuredGrid", GhostLevel="0")
    pd = ET.SubElement(grid, "PPointData", GlobalIds=GLOBAL_IDS)
    ET.SubElement(pd, "PDataArray", type="Int64", Name=GLOBAL_IDS, NumberOfComponents="1")
    if regions:
        cd = ET.SubElement(grid, "PCellData", Scalars=REGION)
        ET.SubElement(cd, "PDataArray", type="Int64", Name=REGION, NumberOfComponents="1")
    pts = ET.SubElement(grid, "PPoints")
    ET.SubElement(pts, "PDataArray", type="Float64", NumberOfComponents="3")
    for name in names:
        ET.SubElement(grid, "Piece", Source=f"{folder}/{name}")
    ET.indent(root)
    return b'<?xml version="1.0"?>\n' + ET.tostring(root) + b"\n"


def commit(index, tmp, names, regions: bool = False) -> None:
    """Move the pieces in ``tmp`` to their directory beside ``index`` and write the
    index listing ``names`` (in order; with ``regions``, they carry the cell
    array ``region``); an older directory of pieces is replaced."""
    index, tmp = Path(index), Path(tmp)
    final = index.with_name(index.stem)
    old = None
    if final.exists():
        old = index.with_name(f".{index.stem}.old-{secrets.token_hex(4)}")
        os.replace(final, old)
    os.replace(tmp, final)
    data = _index_xml(final.name, names, regions)

    def write(p):
        Path(p).write_bytes(data)

    atomic_write(index, write, extension=".pvtu")
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def read_pvtu(index) -> tuple[np.ndarray, np.ndarray]:
    """The whole mesh of a ``.pvtu``: ``points`` (N, 2) by global number and
    ``triangles`` (M, 3) in global numbering (pieces read with meshio)."""
    import meshio

    index = Path(index)
    root = ET.parse(index).getroot()
    pieces = [index.parent / p.get("Source") for p in root.iter("Piece")]
    meshes = [meshio.read(p) for p in pieces]
    n = 1 + max(int(m.point_data[GLOBAL_IDS].max()) for m in meshes)
    points = np.full((n, 2), np.nan)
    tris = []
    for m in meshes:
        ids = np.asarray(m.point_data[GLOBAL_IDS], dtype=np.int64)
        points[ids] = m.points[:, :2]
        tris.append(ids[m.cells_dict["triangle"]])
    return points, np.concatenate(tris)
