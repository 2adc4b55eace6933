"""Readers and writers of polygon files, one pair per format.

(Longer than most modules on purpose: five short reader/writer pairs share one
set of error and number-formatting helpers, and each format is one marked
section below; splitting them would scatter those helpers.)

These read and write the rings; :mod:`uniform2d.io.constrained_files` and
:mod:`uniform2d.io.pslg_files` extend them with interior segments, fixed points
and region labels, and are what the registry lists.  The functions here do the
ring work behind :func:`uniform2d.io.read_polygon` and
:func:`uniform2d.io.write_polygon`, which pick one of them by the file's
extension (see :mod:`uniform2d.io.registry`).  Readers take a path to an
existing file and return a :class:`uniform2d.Polygon`; writers take a path and a
polygon and write the whole file (atomicity is added by the caller).

Formats
-------
``.json``
    uniform2d's own format, ``{"outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}``;
    ``"holes"`` is optional, rings may be given closed or open, in either
    orientation, and other keys (``"units"``, ``"description"``, ...) are
    ignored.  A JSON file with a ``"type"`` member is read as GeoJSON.
``.geojson``
    A GeoJSON ``Polygon`` geometry, a ``Feature`` holding one, or a
    ``FeatureCollection`` (or ``GeometryCollection``) with exactly one polygon.
    A ``MultiPolygon`` with a single part is accepted; with more parts it is an
    error, as uniform2d meshes one polygon at a time.  A third (z) coordinate
    is ignored.  Written as a FeatureCollection with one Feature, exterior ring
    counter-clockwise and holes clockwise (RFC 7946).
``.wkt``
    One Well-Known-Text ``POLYGON`` (a one-part ``MULTIPOLYGON`` is accepted).
``.poly``
    Triangle's planar straight-line graph format: a vertex section, a segment
    section and a hole section (see https://www.cs.cmu.edu/~quake/triangle.poly.html).
    The segments must form closed rings; the ring that contains the others is
    the outer ring and every other ring must hold at least one hole point (a
    ring without one would bound an interior region in Triangle, which
    uniform2d does not model).  ``#`` starts a comment; vertices are numbered
    from 0 or 1, as given by the first vertex; a vertex count of 0 means the
    vertices are in the ``.node`` file of the same name.
``.dxf``
    Closed ``LWPOLYLINE`` and 2-D/3-D ``POLYLINE`` entities in modelspace (read
    with ezdxf).  The ring with the largest area is the outer ring, the others
    are its holes.  Arc segments (bulges) are replaced by their chords, with a
    logged warning.  Written as LWPOLYLINEs on layers ``OUTER`` and ``HOLES``.

Errors
------
A file whose content is not a usable polygon raises
:class:`~uniform2d.errors.FileFormatError` naming the file and what is wrong;
a well-formed file describing an invalid polygon raises the
:class:`~uniform2d.errors.InvalidPolygonError` of :class:`~uniform2d.Polygon`,
with the file name in front of its message.

Examples
--------
>>> import os, tempfile
>>> from uniform2d import Polygon
>>> from uniform2d.io.polygon_files import read_wkt, write_wkt
>>> path = os.path.join(tempfile.mkdtemp(), "square.wkt")
>>> write_wkt(path, Polygon([(0, 0), (2, 0), (2, 2), (0, 2)]))
>>> print(open(path).read().strip())
POLYGON ((0.0 0.0, 2.0 0.0, 2.0 2.0, 0.0 2.0, 0.0 0.0))
>>> read_wkt(path).area
4.0
"""

from __future__ import annotations

import json
import logging
import re
from collections import Counter
from pathlib import Path

import numpy as np
import shapely
import shapely.wkt

from ..errors import FileFormatError, InvalidPolygonError
from ..geometry import signed_area
from ..polygon import Polygon

__all__ = [
    "read_json",
    "write_json",
    "read_geojson",
    "write_geojson",
    "read_wkt",
    "write_wkt",
    "read_poly",
    "write_poly",
    "read_dxf",
    "write_dxf",
]

logger = logging.getLogger(__name__)

_OUR_JSON = '{"outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}'


# -- shared helpers ----------------------------------------------------------------
def _fail(path, message: str):
    raise FileFormatError(f"{path}: {message}")


def _short(obj, limit: int = 60) -> str:
    text = json.dumps(obj) if not isinstance(obj, str) else repr(obj)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _num(x: float) -> str:
    """Shortest text that reads back as exactly the same float."""
    return repr(float(x))


def _read_text(path) -> str:
    try:
        with open(path, encoding="utf-8-sig") as f:
            return f.read()
    except UnicodeDecodeError as exc:
        _fail(path, f"not a UTF-8 text file ({exc.reason} at byte {exc.start})")


def _make_polygon(path, outer, holes, labels=None, **constraints) -> Polygon:
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


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _json_ring(path, obj, where: str, *, geojson: bool) -> np.ndarray:
    """A JSON list of positions -> (k, 2) float64, with precise complaints."""
    want = "[x, y] (or [x, y, z])" if geojson else "[x, y]"
    if not isinstance(obj, list):
        _fail(path, f"{where} must be a list of {want} positions, got {_short(obj)}")
    out = np.empty((len(obj), 2), dtype=np.float64)
    dropped_z = False
    for i, p in enumerate(obj):
        if isinstance(p, list) and p and all(isinstance(q, list) for q in p):
            _fail(
                path,
                f"{where}[{i}] is a list of lists, but a position [x, y] was expected "
                "(one level of nesting too many?)",
            )
        if not isinstance(p, list) or not (len(p) >= 2 if geojson else len(p) == 2):
            _fail(path, f"{where}[{i}] must be a position {want}, got {_short(p)}")
        for c in p[:2]:
            if not _is_number(c):
                _fail(
                    path,
                    f"{where}[{i}] has an unreadable number {_short(c)}; "
                    "coordinates must be JSON numbers (not strings or booleans)",
                )
        out[i] = p[0], p[1]
        dropped_z |= len(p) > 2 and _is_number(p[2]) and p[2] != 0
    if dropped_z:
        logger.warning("%s: %s has z coordinates; they are ignored", path, where)
    return out


def _load_json(path):
    text = _read_text(path)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        _fail(path, f"invalid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}")
    except RecursionError:
        _fail(path, "invalid JSON: nested too deeply to be a polygon or a mesh")


# -- .json (our format) -------------------------------------------------------------
def read_json(path) -> Polygon:
    """Read uniform2d's JSON polygon format (or GeoJSON, if the object has a "type")."""
    data = _load_json(path)
    if isinstance(data, dict) and "type" in data:
        logger.info("%s: has a 'type' member, reading it as GeoJSON", path)
        return _polygon_from_geojson(path, data)
    return _make_polygon(path, *_json_rings(path, data))


def _json_rings(path, data):
    """(outer, holes) of uniform2d's JSON polygon object."""
    if not isinstance(data, dict):
        _fail(path, f"expected a JSON object {_OUR_JSON}, got a JSON {type(data).__name__}")
    if "outer" not in data:
        if "nodes" in data and ("triangles" in data or "members" in data):
            _fail(
                path,
                "this is a uniform2d truss mesh, not a polygon; read it with "
                "uniform2d.io.read_mesh (truss meshes use the extension .truss.json)",
            )
        keys = ", ".join(repr(k) for k in list(data)[:8]) or "none"
        _fail(path, f'missing the "outer" key (keys found: {keys}); expected {_OUR_JSON}')
    outer = _json_ring(path, data["outer"], '"outer"', geojson=False)
    holes = data.get("holes", [])
    if holes is None:
        holes = []
    if not isinstance(holes, list):
        _fail(path, f'"holes" must be a list of rings, got {_short(holes)}')
    if holes and isinstance(holes[0], list) and holes[0] and _is_number(holes[0][0]):
        _fail(
            path,
            '"holes" must be a list of rings, but it looks like a single ring '
            "(a list of [x, y]); wrap it as [[[x, y], ...]]",
        )
    rings = [_json_ring(path, h, f'"holes"[{i}]', geojson=False) for i, h in enumerate(holes)]
    extra = sorted(set(data) - {"outer", "holes", "segments", "points", "regions"})
    if extra:
        logger.debug("%s: ignoring keys %s", path, extra)
    return outer, rings


def _json_ring_text(ring, indent: str, close: bool = False) -> str:
    pts = list(ring) + ([ring[0]] if close else [])
    body = ",\n".join(f"{indent}  [{_num(x)}, {_num(y)}]" for x, y in pts)
    return f"[\n{body}\n{indent}]"


def write_json(path, polygon: Polygon) -> None:
    """Write uniform2d's JSON polygon format, one vertex per line, exact floats."""
    outer = _json_ring_text(polygon.outer, "  ")
    holes = ",\n".join("    " + _json_ring_text(h, "    ") for h in polygon.holes)
    holes = f"[\n{holes}\n  ]" if polygon.holes else "[]"
    with open(path, "w", encoding="utf-8") as f:
        f.write(f'{{\n  "outer": {outer},\n  "holes": {holes}\n}}\n')


# -- .geojson -----------------------------------------------------------------------
_POLYGONAL = ("Polygon", "MultiPolygon")


def _multipolygon_error(path, n_parts: int):
    _fail(
        path,
        f"contains a MultiPolygon with {n_parts} parts; uniform2d meshes one polygon "
        f"at a time: split it into {n_parts} files with one Polygon each and mesh "
        "them separately",
    )


def _geojson_polygon_coords(path, data):
    """Find the one polygon in a GeoJSON object; return its coordinates member."""
    if not isinstance(data, dict):
        _fail(path, f"expected a GeoJSON object, got a JSON {type(data).__name__}")
    kind = data.get("type")
    if kind == "Feature":
        geom = data.get("geometry")
        if geom is None:
            _fail(path, "the Feature has no geometry (null); give it a Polygon geometry")
        return _geojson_polygon_coords(path, geom)
    if kind in ("FeatureCollection", "GeometryCollection"):
        member = "features" if kind == "FeatureCollection" else "geometries"
        items = data.get(member)
        if not isinstance(items, list):
            _fail(path, f'the {kind} has no "{member}" list')
        for i, item in enumerate(items):
            if not isinstance(item, dict):
                what = "Feature" if kind == "FeatureCollection" else "geometry"
                _fail(path, f'{member}[{i}] is {_short(item)}, not a GeoJSON {what} object')
        if kind == "FeatureCollection":
            items = [item.get("geometry") for item in items]
        geoms = [g for g in items if isinstance(g, dict)]
        polys = [g for g in geoms if g.get("type") in _POLYGONAL]
        others = Counter(str(g.get("type")) for g in geoms if g.get("type") not in _POLYGONAL)
        if len(polys) != 1:
            found = ", ".join(f"{n} {t}" for t, n in sorted(others.items())) or "nothing else"
            if not polys:
                _fail(path, f"the {kind} contains no Polygon (found {found}); it needs exactly one")
            _fail(
                path,
                f"the {kind} contains {len(polys)} polygons; uniform2d meshes one polygon "
                "at a time: keep one, or split them into separate files",
            )
        if others:
            logger.warning(
                "%s: ignoring %s in the %s; only its Polygon is read",
                path,
                ", ".join(f"{n} {t}" for t, n in sorted(others.items())),
                kind,
            )
        return _geojson_polygon_coords(path, polys[0])
    if kind == "Polygon":
        coords = data.get("coordinates")
        if not isinstance(coords, list) or not coords:
            _fail(path, 'the Polygon needs "coordinates": a non-empty list of rings')
        return coords
    if kind == "MultiPolygon":
        coords = data.get("coordinates")
        if not isinstance(coords, list) or not coords:
            _fail(path, 'the MultiPolygon needs "coordinates": a non-empty list of polygons')
        if len(coords) != 1:
            _multipolygon_error(path, len(coords))
        logger.info("%s: reading a one-part MultiPolygon as a Polygon", path)
        return _geojson_polygon_coords(path, {"type": "Polygon", "coordinates": coords[0]})
    if kind in ("Point", "MultiPoint", "LineString", "MultiLineString"):
        _fail(
            path,
            f"contains a {kind}; expected a Polygon (or a Feature or FeatureCollection "
            "holding one). A closed outline must be a Polygon, not a LineString",
        )
    _fail(
        path,
        f"unknown GeoJSON type {_short(kind)}; expected a Polygon, Feature or FeatureCollection",
    )


def _polygon_from_geojson(path, data) -> Polygon:
    coords = _geojson_polygon_coords(path, data)
    if coords and isinstance(coords[0], list) and coords[0] and _is_number(coords[0][0]):
        _fail(
            path,
            '"coordinates" of a Polygon is a list of rings (outer first); it looks like a '
            "single ring: wrap it as [[[x, y], ...]]",
        )
    rings = [
        _json_ring(path, r, "the outer ring" if i == 0 else f"hole ring {i - 1}", geojson=True)
        for i, r in enumerate(coords)
    ]
    return _make_polygon(path, rings[0], rings[1:])


def read_geojson(path) -> Polygon:
    """Read a GeoJSON Polygon (bare, in a Feature, or the one in a FeatureCollection)."""
    return _polygon_from_geojson(path, _load_json(path))


def write_geojson(path, polygon: Polygon) -> None:
    """Write a FeatureCollection with one Polygon Feature (RFC 7946 orientation)."""
    rings = ",\n".join(
        "          " + _json_ring_text(r, "          ", close=True) for r in polygon.rings
    )
    text = (
        '{\n  "type": "FeatureCollection",\n  "features": [\n    {\n'
        '      "type": "Feature",\n      "properties": {},\n'
        '      "geometry": {\n        "type": "Polygon",\n'
        f'        "coordinates": [\n{rings}\n        ]\n      }}\n    }}\n  ]\n}}\n'
    )
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


# -- .wkt ---------------------------------------------------------------------------
def read_wkt(path) -> Polygon:
    """Read one WKT POLYGON (a one-part MULTIPOLYGON is accepted)."""
    text = _read_text(path).strip()
    if not text:
        _fail(path, "the file is empty; expected a WKT POLYGON ((x y, ...), ...)")
    try:
        geom = shapely.wkt.loads(text)
    except NotImplementedError as exc:  # e.g. CURVEPOLYGON: curved geometry
        _fail(path, f"unsupported WKT geometry ({exc}); give a POLYGON with straight edges")
    except shapely.errors.ShapelyError as exc:
        _fail(path, f"not valid WKT ({exc})")
    if geom.geom_type == "MultiPolygon":
        if geom.is_empty:
            _fail(path, "contains an empty MULTIPOLYGON; give one POLYGON with its coordinates")
        if len(geom.geoms) != 1:
            _multipolygon_error(path, len(geom.geoms))
        logger.info("%s: reading a one-part MULTIPOLYGON as a POLYGON", path)
        geom = geom.geoms[0]
    if geom.geom_type != "Polygon":
        _fail(path, f"contains a {geom.geom_type}; expected a POLYGON")
    if geom.is_empty:
        _fail(path, "contains an empty POLYGON")
    if geom.has_z:
        logger.warning("%s: z coordinates are ignored", path)
    return _make_polygon(
        path,
        np.asarray(geom.exterior.coords)[:, :2],
        [np.asarray(h.coords)[:, :2] for h in geom.interiors],
    )


def write_wkt(path, polygon: Polygon) -> None:
    """Write one WKT POLYGON with closed rings and exact (shortest round-trip) floats."""
    rings = []
    for r in polygon.rings:
        pts = list(r) + [r[0]]
        rings.append("(" + ", ".join(f"{_num(x)} {_num(y)}" for x, y in pts) + ")")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"POLYGON ({', '.join(rings)})\n")


# -- .poly (Triangle) ---------------------------------------------------------------
class _PolyLines:
    """Non-empty, comment-free lines of a .poly/.node file, with line numbers."""

    def __init__(self, path, text: str):
        self.path = path
        self.lines = []
        for n, line in enumerate(text.splitlines(), start=1):
            tokens = line.split("#", 1)[0].split()
            if tokens:
                self.lines.append((n, tokens))
        self.i = 0

    def next(self, what: str, *, optional: bool = False):
        if self.i >= len(self.lines):
            if optional:
                return None, None
            _fail(self.path, f"the file ends before {what}")
        n, tokens = self.lines[self.i]
        self.i += 1
        return n, tokens

    def number(self, n: int, tokens, k: int, what: str, kind=float):
        if k >= len(tokens):
            _fail(self.path, f"line {n}: missing {what}")
        try:
            if kind is int:
                value = float(tokens[k])
                if not value.is_integer():
                    raise ValueError
                return int(value)
            return float(tokens[k])
        except ValueError:
            _fail(self.path, f"line {n}: unreadable {what} {tokens[k]!r}")


def _read_vertices(lines: _PolyLines, count_line=None):
    """Read a vertex section (header + lines); return (xy array, base, numbers)."""
    n, tokens = count_line if count_line else lines.next("the vertex count")
    nv = lines.number(n, tokens, 0, "vertex count", int)
    dim = lines.number(n, tokens, 1, "dimension", int) if len(tokens) > 1 else 2
    if dim != 2:
        _fail(lines.path, f"line {n}: dimension is {dim}; a .poly polygon must be 2-D")
    if nv < 0:
        _fail(lines.path, f"line {n}: negative vertex count {nv}")
    left = len(lines.lines) - lines.i
    if nv > left:  # before allocating: a corrupt count must not look like a memory problem
        _fail(lines.path, f"line {n}: the header counts {nv} vertices, but only {left} lines follow")
    xy = np.empty((nv, 2), dtype=np.float64)
    base = 0
    for k in range(nv):
        n, tokens = lines.next(f"vertex {k + 1} of {nv}")
        vid = lines.number(n, tokens, 0, "vertex number", int)
        if k == 0:
            base = vid
            if base not in (0, 1):
                _fail(
                    lines.path, f"line {n}: the first vertex is numbered {vid}; number from 0 or 1"
                )
        elif vid != base + k:
            _fail(
                lines.path,
                f"line {n}: vertex number {vid}, expected {base + k} "
                "(vertices must be numbered consecutively)",
            )
        xy[k, 0] = lines.number(n, tokens, 1, "x coordinate")
        xy[k, 1] = lines.number(n, tokens, 2, "y coordinate")
    return xy, base


def _check_segments(path, segments, base: int) -> None:
    """No segment joins a vertex to itself, no two join the same vertices."""
    seen = {}
    for sid, a, b in segments:
        if a == b:
            _fail(path, f"segment {sid} joins vertex {a + base} to itself")
        key = (min(a, b), max(a, b))
        if key in seen:
            _fail(
                path,
                f"segments {seen[key]} and {sid} both join vertices {key[0] + base} and "
                f"{key[1] + base}; remove the duplicate",
            )
        seen[key] = sid


def _walk_rings(path, nv: int, segments, base: int):
    """Split segments (list of (segment number, a, b), 0-based) into closed rings."""
    _check_segments(path, segments, base)
    adj = [[] for _ in range(nv)]
    for sid, a, b in segments:
        adj[a].append((b, sid))
        adj[b].append((a, sid))
    for v, nbrs in enumerate(adj):
        if len(nbrs) == 1:
            _fail(
                path,
                f"segment {nbrs[0][1]} ends at vertex {v + base}, where no other segment "
                "continues (a dangling segment); segments must form closed rings",
            )
        if len(nbrs) > 2:
            _fail(
                path,
                f"vertex {v + base} is the end of {len(nbrs)} segments "
                f"({', '.join(str(s) for _, s in nbrs)}); rings must not branch or touch",
            )
    unused = [v + base for v in range(nv) if not adj[v]]
    if unused:
        logger.warning(
            "%s: %d vertices are on no segment and are ignored (first: %s)",
            path,
            len(unused),
            ", ".join(map(str, unused[:5])),
        )
    visited = np.zeros(nv, dtype=bool)
    rings = []
    for start in range(nv):
        if visited[start] or not adj[start]:
            continue
        ring = [start]
        visited[start] = True
        prev, cur = start, adj[start][0][0]
        while cur != start:
            ring.append(cur)
            visited[cur] = True
            a, b = adj[cur]
            nxt = a[0] if a[0] != prev else b[0]
            prev, cur = cur, nxt
        rings.append(ring)
    return rings


def read_poly(path) -> Polygon:
    """Read a Triangle .poly file whose segments form one outer ring and hole rings."""
    path = Path(path)
    lines, xy, base, segments, holes_xy = _poly_sections(path)
    if lines.next("", optional=True)[0] is not None:
        logger.debug("%s: ignoring the regional attributes section", path)
    return _poly_ring_polygon(path, xy, base, segments, holes_xy)


def _poly_sections(path):
    """(lines, vertices, base, segments, hole points) of a .poly file, ``lines``
    left at the regional attributes section."""
    lines = _PolyLines(path, _read_text(path))
    n, tokens = lines.next("the vertex count")
    nv = lines.number(n, tokens, 0, "vertex count", int)
    if nv == 0:
        node = path.with_suffix(".node")
        if not node.is_file():
            _fail(path, f"has 0 vertices, so they must be in '{node}', which does not exist")
        xy, base = _read_vertices(_PolyLines(node, _read_text(node)))
    else:
        xy, base = _read_vertices(lines, (n, tokens))
    nv = len(xy)

    n, tokens = lines.next("the segment count")
    ns = lines.number(n, tokens, 0, "segment count", int)
    segments = []
    for k in range(ns):
        n, tokens = lines.next(f"segment {k + 1} of {ns}")
        sid = lines.number(n, tokens, 0, "segment number", int)
        ends = []
        for j in (1, 2):
            v = lines.number(n, tokens, j, "segment endpoint", int)
            if not base <= v < base + nv:
                _fail(
                    path,
                    f"line {n}: segment {sid} refers to vertex {v}, but vertices are "
                    f"numbered {base}..{base + nv - 1}",
                )
            ends.append(v - base)
        segments.append((sid, ends[0], ends[1]))
    if not segments:
        _fail(path, "has no segments; the rings of the polygon must be given as segments")

    n, tokens = lines.next("the hole count", optional=True)
    holes_xy = []
    if n is not None:
        nh = lines.number(n, tokens, 0, "hole count", int)
        if nh < 0:
            _fail(path, f"line {n}: negative hole count {nh}; give 0 or the number of hole points")
        for k in range(nh):
            n, tokens = lines.next(f"hole point {k + 1} of {nh}")
            hid = lines.number(n, tokens, 0, "hole number", int)
            holes_xy.append(
                (hid, lines.number(n, tokens, 1, "hole x"), lines.number(n, tokens, 2, "hole y"))
            )
    return lines, xy, base, segments, holes_xy


def _poly_ring_polygon(path, xy, base, segments, holes_xy) -> Polygon:
    """The polygon of .poly segments that form closed rings only."""
    nv = len(xy)
    rings = _walk_rings(path, nv, segments, base)
    areas = [abs(shapely.Polygon(xy[r]).area) for r in rings]
    outer_i = int(np.argmax(areas))
    order = [outer_i] + [i for i in range(len(rings)) if i != outer_i]

    def label(ring):
        return f"the ring through vertices {ring[0] + base}, {ring[1] + base}, ..."

    labels = [label(rings[i]) for i in order]
    polygon = _make_polygon(path, xy[rings[outer_i]], [xy[rings[i]] for i in order[1:]], labels)

    hole_shapes = [shapely.Polygon(h) for h in polygon.holes]
    has_point = [False] * len(hole_shapes)
    for hid, hx, hy in holes_xy:
        pt = shapely.Point(hx, hy)
        inside = [k for k, h in enumerate(hole_shapes) if h.contains(pt)]
        if not inside:
            _fail(
                path,
                f"hole point {hid} ({hx:.17g}, {hy:.17g}) is not inside any hole ring; "
                "move it into the hole it marks, or remove it",
            )
        has_point[inside[0]] = True
    for k, ok in enumerate(has_point):
        if not ok:
            _fail(
                path,
                f"{labels[k + 1]} lies inside the outer ring but has no hole point; in "
                "Triangle it would bound an interior region, which uniform2d does not "
                "support: add a hole point inside it to make it a hole",
            )
    return polygon


def write_poly(path, polygon: Polygon) -> None:
    """Write a Triangle .poly file (vertices numbered from 1, one hole point per hole)."""
    out = [
        f"# uniform2d polygon: outer ring and {polygon.n_holes} hole(s), Triangle .poly format",
        f"{len(polygon.vertices)} 2 0 0",
    ]
    out += [f"{k + 1} {_num(x)} {_num(y)}" for k, (x, y) in enumerate(polygon.vertices)]
    segs = []
    for r in range(len(polygon.rings)):
        a, b = int(polygon.ring_offsets[r]), int(polygon.ring_offsets[r + 1])
        for v in range(a, b):
            segs.append((v + 1, (v + 1 - a) % (b - a) + a + 1))
    out.append(f"{len(segs)} 0")
    out += [f"{k + 1} {i} {j}" for k, (i, j) in enumerate(segs)]
    out.append(f"{polygon.n_holes}")
    for k, h in enumerate(polygon.holes):
        p = shapely.Polygon(h).point_on_surface()
        out.append(f"{k + 1} {_num(p.x)} {_num(p.y)}")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


# -- .dxf ---------------------------------------------------------------------------
_GEOMETRY_ENTITIES = {"LINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE", "INSERT", "HATCH"}


def _open_dxf(path):
    """The ezdxf document of the file; a file ezdxf cannot read is an InvalidPolygonError."""
    import ezdxf

    try:
        return ezdxf.readfile(path)
    except ezdxf.DXFError as exc:
        _fail(path, f"not a readable DXF file ({exc})")
    except (FileNotFoundError, PermissionError, IsADirectoryError):
        raise
    except (OSError, UnicodeDecodeError) as exc:
        _fail(path, f"not a readable DXF file ({exc})")
    except (StopIteration, EOFError, IndexError, ValueError) as exc:  # truncated files
        _fail(path, f"not a readable DXF file (truncated or malformed: {type(exc).__name__})")


def _dxf_polyline(e):
    """(points, closed, has bulges) of a 2-D/3-D polyline entity, None for any other."""
    kind = e.dxftype()
    if kind == "LWPOLYLINE":
        pts = [tuple(v) for v in e.vertices_in_wcs()]
        return pts, bool(e.closed), any(b != 0 for (b,) in e.get_points("b"))
    if kind == "POLYLINE" and (e.is_2d_polyline or e.is_3d_polyline):
        pts = [tuple(v) for v in e.points_in_wcs()]
        return pts, bool(e.is_closed), any(v.dxf.get("bulge", 0) != 0 for v in e.vertices)
    return None


def _dxf_ring(path, name: str, pts, closed: bool, bulged: bool) -> np.ndarray:
    """One polyline's ring (x, y); an open one is an error unless it ends where it starts."""
    xy = np.asarray(pts, dtype=np.float64).reshape(-1, 3)[:, :2]
    if not closed:
        if len(xy) >= 4 and np.array_equal(xy[0], xy[-1]):
            logger.info("%s: %s ends where it starts; read as closed", path, name)
        else:
            _fail(
                path,
                f"{name} is open; close it (set its 'closed' flag in CAD) or delete it: "
                "every polyline must be the outline or a hole",
            )
    if bulged:
        logger.warning(
            "%s: %s has arc segments (bulges); they are read as straight chords. "
            "Approximate arcs by short segments in CAD if the curvature matters",
            path,
            name,
        )
    return xy


def _dxf_rings(path, doc):
    """The rings of the modelspace's polylines and their labels, in file order."""
    rings, labels, ignored = [], [], Counter()
    for e in doc.modelspace():
        poly = _dxf_polyline(e)
        if poly is None:
            ignored[e.dxftype()] += 1
            continue
        name = f"polyline #{len(rings) + 1} (handle {e.dxf.handle}, layer {e.dxf.get('layer', '0')})"
        rings.append(_dxf_ring(path, name, *poly))
        labels.append(name)
    geometric = {k: n for k, n in ignored.items() if k in _GEOMETRY_ENTITIES}
    if geometric:
        logger.warning(
            "%s: ignoring %s; uniform2d reads only closed LWPOLYLINE/POLYLINE entities "
            "(convert circles, arcs and lines to closed polylines)",
            path,
            ", ".join(f"{n} {k}" for k, n in sorted(geometric.items())),
        )
    if not rings:
        found = ", ".join(f"{n} {k}" for k, n in sorted(ignored.items())) or "nothing"
        _fail(
            path,
            f"no closed polylines in modelspace (found {found}); draw the outline and the "
            "holes as closed LWPOLYLINE or POLYLINE entities",
        )
    return rings, labels


def read_dxf(path) -> Polygon:
    """Read closed polylines from a DXF modelspace: the largest is outer, the rest holes."""
    rings, labels = _dxf_rings(path, _open_dxf(path))
    outer_i = int(np.argmax([abs(signed_area(r)) for r in rings]))
    order = [outer_i] + [i for i in range(len(rings)) if i != outer_i]
    outer_shape = shapely.Polygon(rings[outer_i]) if len(rings[outer_i]) >= 3 else None
    for i in order[1:]:
        if outer_shape is not None and len(rings[i]) >= 3 and outer_shape.disjoint(
            shapely.Polygon(rings[i])
        ):
            raise InvalidPolygonError(
                f"{path}: {labels[i]} lies outside the outer ring ({labels[outer_i]}, the "
                "largest); uniform2d meshes one polygon at a time: put each part in its own "
                "file"
            )
    return _make_polygon(
        path, rings[outer_i], [rings[i] for i in order[1:]], [labels[i] for i in order]
    )


def write_dxf(path, polygon: Polygon) -> None:
    """Write the rings as closed LWPOLYLINEs (layer OUTER, then layer HOLES)."""
    import ezdxf

    # ezdxf stamps the time and random GUIDs into every file unless told to write
    # its fixed ones (when the document is made and when it is saved): same
    # polygon, same bytes
    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2010")
        doc.layers.add("OUTER", color=7)
        doc.layers.add("HOLES", color=1)
        msp = doc.modelspace()
        for k, ring in enumerate(polygon.rings):
            msp.add_lwpolyline(
                [(float(x), float(y)) for x, y in ring],
                close=True,
                dxfattribs={"layer": "OUTER" if k == 0 else "HOLES"},
            )
        doc.saveas(path)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed
