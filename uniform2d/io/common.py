"""What the polygon file formats share: errors, exact numbers, JSON positions, polygons.

Each format module (:mod:`~uniform2d.io.json_file`, :mod:`~uniform2d.io.geojson_file`,
:mod:`~uniform2d.io.wkt_file`, :mod:`~uniform2d.io.poly_file`,
:mod:`~uniform2d.io.dxf_file`) reads and writes everything its format carries
with these: :func:`fail` raises the :class:`~uniform2d.errors.FileFormatError`
naming the file, :func:`num` writes a float that reads back exactly,
:func:`json_ring` reads a JSON list of positions with precise complaints,
:func:`make_polygon` builds the :class:`~uniform2d.Polygon` with the file name
(and ring labels) in its errors, and :func:`zone_seeds` labels the regions
inside a file's zones.

Errors
------
A file whose content is not a usable polygon raises
:class:`~uniform2d.errors.FileFormatError` naming the file and what is wrong;
a well-formed file describing an invalid polygon raises the
:class:`~uniform2d.errors.InvalidPolygonError` (or
:class:`~uniform2d.errors.InvalidConstraintError`) of :class:`~uniform2d.Polygon`,
with the file name in front of its message.
"""

from __future__ import annotations

import json
import logging
import numbers
import re

import numpy as np

from ..errors import FileFormatError, InvalidPolygonError
from ..polygon import Polygon

__all__ = ["fail", "short", "num", "read_text", "load_json", "is_number", "json_ring",
           "json_ring_text", "label_ok", "label_json", "make_polygon", "multipolygon_error",
           "zone_seeds"]

logger = logging.getLogger(__name__)


# -- text and numbers ------------------------------------------------------------------
def fail(path, message: str):
    raise FileFormatError(f"{path}: {message}")


def short(obj, limit: int = 60) -> str:
    text = json.dumps(obj) if not isinstance(obj, str) else repr(obj)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def num(x: float) -> str:
    """Shortest text that reads back as exactly the same float."""
    return repr(float(x))


def read_text(path) -> str:
    try:
        with open(path, encoding="utf-8-sig") as f:
            return f.read()
    except UnicodeDecodeError as exc:
        fail(path, f"not a UTF-8 text file ({exc.reason} at byte {exc.start})")


def load_json(path):
    text = read_text(path)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        fail(path, f"invalid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}")
    except RecursionError:
        fail(path, "invalid JSON: nested too deeply to be a polygon or a mesh")


# -- JSON positions and labels ---------------------------------------------------------
def is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def json_ring(path, obj, where: str, *, geojson: bool) -> np.ndarray:
    """A JSON list of positions -> (k, 2) float64, with precise complaints."""
    want = "[x, y] (or [x, y, z])" if geojson else "[x, y]"
    if not isinstance(obj, list):
        fail(path, f"{where} must be a list of {want} positions, got {short(obj)}")
    out = np.empty((len(obj), 2), dtype=np.float64)
    dropped_z = False
    for i, p in enumerate(obj):
        if isinstance(p, list) and p and all(isinstance(q, list) for q in p):
            fail(
                path,
                f"{where}[{i}] is a list of lists, but a position [x, y] was expected "
                "(one level of nesting too many?)",
            )
        if not isinstance(p, list) or not (len(p) >= 2 if geojson else len(p) == 2):
            fail(path, f"{where}[{i}] must be a position {want}, got {short(p)}")
        for c in p[:2]:
            if not is_number(c):
                fail(
                    path,
                    f"{where}[{i}] has an unreadable number {short(c)}; "
                    "coordinates must be JSON numbers (not strings or booleans)",
                )
        out[i] = p[0], p[1]
        dropped_z |= len(p) > 2 and is_number(p[2]) and p[2] != 0
    if dropped_z:
        logger.warning("%s: %s has z coordinates; they are ignored", path, where)
    return out


def json_ring_text(ring, indent: str, close: bool = False) -> str:
    pts = list(ring) + ([ring[0]] if close else [])
    body = ",\n".join(f"{indent}  [{num(x)}, {num(y)}]" for x, y in pts)
    return f"[\n{body}\n{indent}]"


def label_ok(label) -> bool:
    return isinstance(label, str) or (isinstance(label, numbers.Real) and not isinstance(label, bool))


def label_json(label) -> str:
    """A region label as JSON text."""
    return json.dumps(label)


# -- polygons from files ---------------------------------------------------------------
def make_polygon(path, outer, holes, labels=None, **constraints) -> Polygon:
    """Build the Polygon (with ``constraints``: segments, points, regions), putting
    the file name (and ring labels) into its errors."""
    try:
        return Polygon(outer, holes, **constraints)
    except InvalidPolygonError as exc:
        message = str(exc)
        if labels:
            named = [f"outer ring = {labels[0]}"] if message.startswith("outer ring") else []
            found = re.findall(r"\bholes? (\d+)(?: and (\d+))?", message)
            for i in sorted({int(m) for pair in found for m in pair if m}):
                if i + 1 < len(labels):
                    named.append(f"hole {i} = {labels[i + 1]}")
            if named:
                message += f" ({'; '.join(named)})"
        raise type(exc)(f"{path}: {message}") from exc


def multipolygon_error(path, n_parts: int):
    fail(
        path,
        f"contains a MultiPolygon with {n_parts} parts; uniform2d meshes one polygon "
        f"at a time: split it into {n_parts} files with one Polygon each and mesh "
        "them separately",
    )


def zone_seeds(path, outer, holes, segments, points, zones, seeds):
    """Region seeds for ``zones`` [(shapely.Polygon, label)]: every region inside a
    zone, and inside no smaller one, is labelled with that zone's label, unless an
    explicit seed in ``seeds`` already labels it."""
    if not any(label is not None for _, label in zones):
        return seeds
    bare = make_polygon(path, outer, holes, segments=segments, points=points)
    regions = bare.regions
    taken = {regions.locate(x, y) for x, y, _ in seeds}
    order = sorted(zones, key=lambda z: z[0].area)
    out = list(seeds)
    for r, face in enumerate(regions.faces):
        if r in taken:
            continue
        inside = face.representative_point()
        hit = next((label for z, label in order if z.contains(inside)), None)
        if hit is not None:
            out.append((inside.x, inside.y, hit))
    return out
