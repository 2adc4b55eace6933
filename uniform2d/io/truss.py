"""Truss files: a triangle mesh as nodes and members (bars), for structural design.

A uniform triangular mesh of a plate or panel is also a truss layout: the mesh
points are the nodes (joints), every triangle edge is a member (bar), and the
near-equal member lengths are what make the layout economical to fabricate.
Two formats carry the same content; both are written with shortest exact
float text, so a write/read round trip is lossless.

Members are the unique undirected edges of the triangles, each listed once with
its lower-numbered node first (``i < j``), sorted by ``(i, j)``.  Lengths are
Euclidean, in the units of the coordinates (uniform2d does not change units).

CSV (``.csv``)
--------------
One comma-separated file with a header row and one row per object, so it can be
opened in a spreadsheet and filtered by the ``kind`` column::

    kind,id,x,y,i,j,k,length
    node,1,0.0,0.0,,,,
    node,2,4.0,0.0,,,,
    node,3,2.0,3.0,,,,
    member,1,,,1,2,,4.0
    member,2,,,1,3,,3.605551275463989
    member,3,,,2,3,,3.605551275463989
    triangle,1,,,1,2,3,

===========  ======================================================================
column       meaning
===========  ======================================================================
``kind``     ``node``, ``member`` or ``triangle``; rows come in that order
``id``       number of the object within its kind, counted from **1** (the usual
             convention of structural analysis programs)
``x, y``     node coordinates (node rows only)
``i, j``     node ids of the member's ends (member rows), ``i < j``
``i, j, k``  node ids of the triangle's corners, counter-clockwise if the mesh
             is (triangle rows); triangles are kept so the file is a full mesh
``length``   member length (member rows only)
===========  ======================================================================

A mesh of a polygon with segments or regions (:attr:`uniform2d.Mesh.regions`)
gets three more columns after ``length``: ``segment`` on member rows (the
number of the polygon segment the member lies on; empty for other members),
``region`` and ``label`` on triangle rows (the triangle's region and its label
if any).  Every number in the file counts from **1**, these two columns too:
segment 1 is ``Polygon.segments[0]``, region 1 is region 0 of
:attr:`uniform2d.Mesh.regions` (files written before uniform2d counted both
from 0; a ``region`` column holding a 0 is read that way).
Point data (one value per node, e.g. an insertion weight) is appended as extra
columns after those, named after the data, filled on node rows only.
Reading maps node ids to rows, so ids need not be contiguous, but they must be
unique; lines starting with ``#`` are skipped.

JSON (``.truss.json``)
----------------------
One JSON object, indices counted from **0** (positions in the ``nodes`` list)::

    {
      "format": "uniform2d-truss",
      "version": 1,
      "nodes": [[x, y], ...],
      "members": [[i, j], ...],
      "lengths": [l, ...],
      "triangles": [[a, b, c], ...],
      "member_segments": [s, ...],
      "regions": [r, ...],
      "region_labels": [label, ...],
      "point_data": {"name": [...], ...}
    }

``member_segments`` (the segment of each member, -1 for none), ``regions``
(one per triangle), ``region_labels`` (one per region, null for none) and
``point_data`` are present only when the mesh has them.  The compound extension
``.truss.json`` keeps these files apart from ``.json`` polygon files.

Examples
--------
>>> import numpy as np
>>> from uniform2d.io.truss import members
>>> tri = np.array([[0, 1, 2], [0, 2, 3]])
>>> i_j, lengths = members(np.array([[0., 0.], [4., 0.], [4., 3.], [0., 3.]]), tri)
>>> i_j.tolist()
[[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
>>> lengths.tolist()
[4.0, 5.0, 3.0, 3.0, 4.0]

The CSV example above, written by :func:`uniform2d.io.write_mesh`:

>>> import os, tempfile
>>> from uniform2d.io import write_mesh
>>> path = os.path.join(tempfile.mkdtemp(), "roof.csv")
>>> write_mesh(path, [[0, 0], [4, 0], [2, 3]], [[0, 1, 2]])
>>> print(open(path).read())
kind,id,x,y,i,j,k,length
node,1,0.0,0.0,,,,
node,2,4.0,0.0,,,,
node,3,2.0,3.0,,,,
member,1,,,1,2,,4.0
member,2,,,1,3,,3.605551275463989
member,3,,,2,3,,3.605551275463989
triangle,1,,,1,2,3,
<BLANKLINE>
"""

from __future__ import annotations

import csv
import json

import numpy as np

from ..errors import FileFormatError, InvalidArgumentError

__all__ = ["members", "read_truss_csv", "write_truss_csv", "read_truss_json", "write_truss_json"]

CSV_COLUMNS = ("kind", "id", "x", "y", "i", "j", "k", "length")
REGION_COLUMNS = ("segment", "region", "label")
JSON_FORMAT_NAME = "uniform2d-truss"
JSON_VERSION = 1


def _fail(path, message: str):
    raise FileFormatError(f"{path}: {message}")


def _num(x) -> str:
    return repr(float(x))


def members(points, triangles):
    """Unique undirected edges of a triangle mesh and their lengths.

    Parameters
    ----------
    points : array_like, shape (N, 2)
    triangles : array_like of int, shape (M, 3)

    Returns
    -------
    ij : ndarray of int64, shape (E, 2)
        Each edge once, ``i < j``, sorted lexicographically.
    lengths : ndarray of float64, shape (E,)
    """
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    e = tri[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    ij = np.unique(np.sort(e, axis=1), axis=0)
    lengths = np.hypot(*(pts[ij[:, 1]] - pts[ij[:, 0]]).T)
    return ij, lengths


def member_segments(ij: np.ndarray, members) -> np.ndarray:
    """The segment of every member of ``ij`` (-1 for none), from ``(edges, ids)``."""
    out = np.full(len(ij), -1, np.int64)
    if members is None or not len(members[0]):
        return out
    edges = np.sort(np.asarray(members[0], dtype=np.int64), axis=1)
    n = int(max(ij.max(initial=0), edges.max(initial=0))) + 1
    pos = np.searchsorted(ij[:, 0] * n + ij[:, 1], edges[:, 0] * n + edges[:, 1])
    out[pos] = members[1]
    return out


# -- CSV ----------------------------------------------------------------------------
def write_truss_csv(path, points, triangles, point_data=None, *, regions=None, labels=None,
                    segment_members=None) -> None:
    """Write the one-file CSV truss layout described in the module docstring."""
    point_data = point_data or {}
    for name, values in point_data.items():
        if np.ndim(values) != 1:
            raise InvalidArgumentError(
                f"point data {name!r} has shape {np.shape(values)}; the CSV truss format "
                "stores one value per node (shape (N,)): split it into several arrays or "
                "use .truss.json"
            )
        if name in CSV_COLUMNS + REGION_COLUMNS:
            raise InvalidArgumentError(
                f"point data name {name!r} clashes with a CSV column; rename it"
            )
    ij, lengths = members(points, triangles)
    names = list(point_data)
    columns = [np.asarray(point_data[n]) for n in names]
    blank = [""] * len(names)
    tagged = regions is not None or segment_members is not None
    seg = member_segments(ij, segment_members)
    with open(path, "w", encoding="utf-8", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(list(CSV_COLUMNS) + (list(REGION_COLUMNS) if tagged else []) + names)
        pad = ["", "", ""] if tagged else []
        for n, (x, y) in enumerate(points):
            extra = [_cell(c[n]) for c in columns]
            w.writerow(["node", n + 1, _num(x), _num(y), "", "", "", ""] + pad + extra)
        for m, ((i, j), length) in enumerate(zip(ij, lengths)):
            tag = [str(seg[m] + 1) if seg[m] >= 0 else "", "", ""] if tagged else []
            w.writerow(["member", m + 1, "", "", i + 1, j + 1, "", _num(length)] + tag + blank)
        for t, (a, b, c) in enumerate(triangles):
            tag = []
            if tagged:
                r = int(regions[t]) if regions is not None else None
                lab = labels[r] if labels is not None and r is not None else None
                tag = ["", "" if r is None else str(r + 1), "" if lab is None else _cell(lab)]
            w.writerow(["triangle", t + 1, "", "", a + 1, b + 1, c + 1, ""] + tag + blank)


def _cell(v) -> str:
    v = v.item() if hasattr(v, "item") else v
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _csv_table(path):
    """The rows of a CSV truss file after its header, as (line number, cells), and
    the column of every field the header names."""
    try:
        with open(path, encoding="utf-8-sig", newline="") as f:
            rows = [
                (n, row)
                for n, row in enumerate(csv.reader(f), start=1)
                if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")
            ]
    except UnicodeDecodeError as exc:
        _fail(path, f"not a UTF-8 text file ({exc.reason} at byte {exc.start})")
    except csv.Error as exc:
        _fail(path, f"not a readable CSV file ({exc})")
    if not rows:
        _fail(path, f"the file is empty; expected the header {','.join(CSV_COLUMNS)}")
    n, header = rows[0]
    header = [c.strip().lower() for c in header]
    if tuple(header[: len(CSV_COLUMNS)]) != CSV_COLUMNS:
        semicolons = len(header) == 1 and ";" in header[0]
        hint = " (the separator must be a comma, not ';')" if semicolons else ""
        _fail(
            path,
            f"line {n}: the header must start with {','.join(CSV_COLUMNS)}{hint}, "
            f"got {','.join(header)[:80]}",
        )
    col = {name: c for c, name in enumerate(CSV_COLUMNS)}
    if "region" in header:
        col["region"] = header.index("region")
    return rows[1:], col


def _csv_field(path, col, n, row, name, kind):
    """The value of field ``name`` (a finite float, or an int) in row ``row`` of line ``n``."""
    c = col[name]
    text = row[c].strip() if c < len(row) else ""
    if not text:
        _fail(path, f"line {n}: {row[0].strip()} row without a value in column {name!r}")
    try:
        value = float(text)
        if kind is int:
            if not value.is_integer():
                raise ValueError
            return int(value)
        if not np.isfinite(value):
            raise ValueError
        return value
    except ValueError:
        _fail(path, f"line {n}: unreadable {name} {text!r}")


def read_truss_csv(path, regions=False):
    """Read a CSV truss file; returns ``(points (N, 2) float64, triangles (M, 3) int64)``,
    and with ``regions`` the region of each triangle (None if the file has no
    ``region`` column)."""
    rows, col = _csv_table(path)

    def field(n, row, name, kind):
        return _csv_field(path, col, n, row, name, kind)

    node_ids, xy, tri_rows, member_rows, region_rows = {}, [], [], [], []
    for n, row in rows:
        kind = row[0].strip().lower()
        if kind == "node":
            nid = field(n, row, "id", int)
            if nid in node_ids:
                _fail(path, f"line {n}: node id {nid} appears twice")
            node_ids[nid] = len(xy)
            xy.append((field(n, row, "x", float), field(n, row, "y", float)))
        elif kind == "member":
            member_rows.append((n, field(n, row, "i", int), field(n, row, "j", int)))
        elif kind == "triangle":
            tri_rows.append(
                (n, field(n, row, "i", int), field(n, row, "j", int), field(n, row, "k", int))
            )
            if regions and "region" in col:
                region_rows.append(field(n, row, "region", int))
        else:
            _fail(path, f"line {n}: unknown kind {row[0].strip()!r}; use node, member or triangle")
    if not xy:
        _fail(path, "has no node rows")
    if not tri_rows:
        _fail(
            path,
            "has no triangle rows; a mesh needs them (members alone do not define the "
            "triangles unambiguously)",
        )

    def index(n, nid):
        if nid not in node_ids:
            _fail(path, f"line {n}: refers to node {nid}, which has no node row")
        return node_ids[nid]

    for n, i, j in member_rows:
        index(n, i), index(n, j)
    triangles = np.array(
        [[index(n, a), index(n, b), index(n, c)] for n, a, b, c in tri_rows], dtype=np.int64
    )
    if not regions:
        return np.array(xy, dtype=np.float64), triangles
    reg = np.array(region_rows, dtype=np.int64) if "region" in col else None
    if reg is not None and reg.size:
        if reg.min() < 0:
            _fail(path, "a triangle has a negative region; regions count from 1")
        reg = reg - (reg.min() > 0)  # from 1; a file counting from 0 holds a 0
    return np.array(xy, dtype=np.float64), triangles, reg


# -- JSON ---------------------------------------------------------------------------
def _rows(array, fmt) -> str:
    return ",\n".join("    [" + ", ".join(fmt(v) for v in row) + "]" for row in array)


def write_truss_json(path, points, triangles, point_data=None, *, regions=None, labels=None,
                     segment_members=None) -> None:
    """Write the ``.truss.json`` layout described in the module docstring."""
    ij, lengths = members(points, triangles)
    seg = member_segments(ij, segment_members)
    parts = [
        f'  "format": "{JSON_FORMAT_NAME}"',
        f'  "version": {JSON_VERSION}',
        '  "nodes": [\n' + _rows(points, _num) + "\n  ]",
        '  "members": [\n' + _rows(ij, str) + "\n  ]",
        '  "lengths": [' + ", ".join(_num(v) for v in lengths) + "]",
        '  "triangles": [\n' + _rows(triangles, str) + "\n  ]",
    ]
    if segment_members is not None:
        parts.append('  "member_segments": [' + ", ".join(map(str, seg.tolist())) + "]")
    if regions is not None:
        parts.append('  "regions": [' + ", ".join(str(int(r)) for r in regions) + "]")
        if labels is not None:
            parts.append('  "region_labels": ' + json.dumps(list(labels)))
    if point_data:
        data = {name: np.asarray(v).tolist() for name, v in point_data.items()}
        parts.append('  "point_data": ' + json.dumps(data))
    with open(path, "w", encoding="utf-8") as f:
        f.write("{\n" + ",\n".join(parts) + "\n}\n")


def _int_table(path, data, key, width, n_nodes):
    value = data.get(key)
    try:
        arr = np.array(value)
        if arr.size == 0:
            arr = arr.reshape(0, width)
        if arr.ndim != 2 or arr.shape[1] != width or not (
            np.issubdtype(arr.dtype, np.integer) and arr.dtype != np.bool_
        ):
            raise ValueError
    except (ValueError, TypeError):
        _fail(path, f'"{key}" must be a list of [{", ".join("ijk"[:width])}] integer node indices')
    if arr.size and (arr.min() < 0 or arr.max() >= n_nodes):
        _fail(
            path,
            f'"{key}" refers to node {int(arr.max() if arr.max() >= n_nodes else arr.min())}; '
            f"nodes are indexed 0..{n_nodes - 1}",
        )
    return arr.astype(np.int64)


def read_truss_json(path, regions=False):
    """Read a ``.truss.json`` file; returns ``(points (N, 2) float64, triangles (M, 3) int64)``,
    and with ``regions`` the region of each triangle (None if the file has none)."""
    try:
        with open(path, encoding="utf-8-sig") as f:
            data = json.load(f)
    except UnicodeDecodeError as exc:
        _fail(path, f"not a UTF-8 text file ({exc.reason} at byte {exc.start})")
    except json.JSONDecodeError as exc:
        _fail(path, f"invalid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}")
    except RecursionError:
        _fail(path, "invalid JSON: nested too deeply to be a truss mesh")
    if not isinstance(data, dict):
        _fail(path, "expected a JSON object with \"nodes\" and \"triangles\"")
    if "outer" in data:
        _fail(path, "this is a polygon file, not a truss mesh; read it with read_polygon")
    for key in ("nodes", "triangles"):
        if key not in data:
            _fail(path, f'missing the "{key}" key')
    if data.get("format", JSON_FORMAT_NAME) != JSON_FORMAT_NAME:
        _fail(path, f'"format" is {data["format"]!r}, expected {JSON_FORMAT_NAME!r}')
    nodes = data["nodes"]
    ok = isinstance(nodes, list) and all(
        isinstance(p, list)
        and len(p) == 2
        and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in p)
        for p in nodes
    )
    if not ok or not nodes:
        _fail(path, '"nodes" must be a non-empty list of [x, y] number pairs')
    points = np.array(nodes, dtype=np.float64).reshape(-1, 2)
    if not np.isfinite(points).all():
        _fail(path, '"nodes" has a non-finite coordinate')
    triangles = _int_table(path, data, "triangles", 3, len(points))
    if "members" in data:
        _int_table(path, data, "members", 2, len(points))
    if not regions:
        return points, triangles
    if "regions" not in data:
        return points, triangles, None
    reg = data["regions"]
    if not (isinstance(reg, list) and len(reg) == len(triangles) and all(
            isinstance(r, int) and not isinstance(r, bool) and r >= 0 for r in reg)):
        _fail(path, '"regions" must list one non-negative integer per triangle')
    return points, triangles, np.array(reg, dtype=np.int64)
