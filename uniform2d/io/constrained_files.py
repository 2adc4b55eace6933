"""Polygon files with interior segments, fixed points and region labels.

The readers and writers here extend those of :mod:`uniform2d.io.polygon_files`
(which read and write the rings) with the constraints of a
:class:`~uniform2d.Polygon`; a file without constraints reads and writes exactly
as there.

``.json``
    Three optional keys beside ``"outer"`` and ``"holes"``: ``"segments"``, a
    list of polylines ``[[x, y], ...]`` (closed if the last point repeats the
    first), ``"points"``, a list of ``[x, y]``, and ``"regions"``, a list of
    ``[x, y, label]`` seeds (label a string or a number).
``.geojson``
    A FeatureCollection (or GeometryCollection): the one Polygon containing the
    others is the domain; ``LineString`` and ``MultiLineString`` features are
    segments; ``Point`` and ``MultiPoint`` features are fixed points, except a
    Point whose properties have a ``"label"``, which labels the region around
    it.  Any other Polygon feature is a *zone*: its outline becomes a closed
    segment and, if its properties have a ``"label"``, the regions inside it
    (not inside a smaller zone) get that label.
``.wkt``
    A ``GEOMETRYCOLLECTION`` of one ``POLYGON`` and ``LINESTRING``,
    ``MULTILINESTRING``, ``POINT`` and ``MULTIPOINT`` members (WKT has no labels).
``.poly``
    Triangle's format in full: the segments form the outer ring, the hole rings
    (those around a hole point) and interior segments; vertices on no segment
    are fixed points; the regional attributes section labels regions with its
    attribute numbers.
``.dxf``
    Closed polylines are the outline (the largest) and holes, as before, except
    those on a layer whose name starts with ``ZONE`` (any case): they are zones
    as in GeoJSON, labelled with their layer name.  Open ``LINE``,
    ``LWPOLYLINE`` and ``POLYLINE`` entities are segments, ``POINT`` entities
    fixed points, ``TEXT`` and ``MTEXT`` entities label the region around their
    insertion point with their text.  Written on layers ``OUTER``, ``HOLES``,
    ``SEGMENTS``, ``POINTS`` and ``REGIONS``.

Errors are those of :mod:`uniform2d.io.polygon_files`:
:class:`~uniform2d.errors.FileFormatError` for unusable content, the
polygon's own :class:`~uniform2d.errors.InvalidConstraintError` (file name in
front) for constraints that cross, overlap or lie outside.
"""

from __future__ import annotations

import logging
import numbers

import numpy as np
import shapely
import shapely.wkt

from ..polygon import Polygon
from . import polygon_files as _pf
from .polygon_files import _fail, _is_number, _json_ring, _json_ring_text, _load_json, _num, _short

__all__ = ["read_json", "write_json", "read_geojson", "write_geojson", "read_wkt", "write_wkt",
           "zone_seeds"]

logger = logging.getLogger(__name__)


def _label_ok(label) -> bool:
    return isinstance(label, str) or (isinstance(label, numbers.Real) and not isinstance(label, bool))


def zone_seeds(path, outer, holes, segments, points, zones, seeds):
    """Region seeds for ``zones`` [(shapely.Polygon, label)]: every region inside a
    zone, and inside no smaller one, is labelled with that zone's label, unless an
    explicit seed in ``seeds`` already labels it."""
    if not any(label is not None for _, label in zones):
        return seeds
    bare = _pf._make_polygon(path, outer, holes, segments=segments, points=points)
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


# -- .json ---------------------------------------------------------------------------
def _json_constraints(path, data) -> dict:
    segs = data.get("segments") or []
    pts = data.get("points") or []
    regs = data.get("regions") or []
    for key, value in (("segments", segs), ("points", pts), ("regions", regs)):
        if not isinstance(value, list):
            _fail(path, f'"{key}" must be a list, got {_short(value)}')
    if segs and isinstance(segs[0], list) and segs[0] and _is_number(segs[0][0]):
        _fail(path, '"segments" must be a list of polylines, but it looks like a single one '
                    "(a list of [x, y]); wrap it as [[[x, y], ...]]")
    segments = [_json_ring(path, s, f'"segments"[{i}]', geojson=False) for i, s in enumerate(segs)]
    points = _json_ring(path, pts, '"points"', geojson=False)
    seeds = []
    for i, s in enumerate(regs):
        if not (isinstance(s, list) and len(s) == 3 and _is_number(s[0]) and _is_number(s[1])
                and _label_ok(s[2])):
            _fail(path, f'"regions"[{i}] must be [x, y, label] with a string or number label, '
                        f"got {_short(s)}")
        seeds.append((s[0], s[1], s[2]))
    return {"segments": segments, "points": points, "regions": seeds}


def read_json(path) -> Polygon:
    """Read uniform2d's JSON polygon format with its constraint keys (or GeoJSON)."""
    data = _load_json(path)
    if isinstance(data, dict) and "type" in data:
        logger.info("%s: has a 'type' member, reading it as GeoJSON", path)
        return _polygon_from_geojson(path, data)
    outer, holes = _pf._json_rings(path, data)
    return _pf._make_polygon(path, outer, holes, **_json_constraints(path, data))


def _label_json(label) -> str:
    import json

    return json.dumps(label)


def write_json(path, polygon: Polygon) -> None:
    """Write uniform2d's JSON polygon format, with the constraint keys if any."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _pf.write_json(path, polygon)
    outer = _json_ring_text(polygon.outer, "  ")
    holes = ",\n".join("    " + _json_ring_text(h, "    ") for h in polygon.holes)
    holes = f"[\n{holes}\n  ]" if polygon.holes else "[]"
    segs = ",\n".join("    " + _json_ring_text(s, "    ") for s in polygon.segments)
    pts = ",\n".join(f"    [{_num(x)}, {_num(y)}]" for x, y in polygon.points)
    regs = ",\n".join(f"    [{_num(x)}, {_num(y)}, {_label_json(lab)}]"
                      for x, y, lab in polygon.region_seeds)
    parts = [f'  "outer": {outer}', f'  "holes": {holes}']
    for key, body in (("segments", segs), ("points", pts), ("regions", regs)):
        parts.append(f'  "{key}": ' + (f"[\n{body}\n  ]" if body else "[]"))
    with open(path, "w", encoding="utf-8") as f:
        f.write("{\n" + ",\n".join(parts) + "\n}\n")


# -- .geojson ------------------------------------------------------------------------
_LINES = ("LineString", "MultiLineString")
_POINTS = ("Point", "MultiPoint")
_POLYS = ("Polygon", "MultiPolygon")


def _geo_items(path, data) -> list:
    """(geometry, properties, where) of every geometry in a GeoJSON object."""
    if not isinstance(data, dict):
        _fail(path, f"expected a GeoJSON object, got a JSON {type(data).__name__}")
    kind = data.get("type")
    if kind == "FeatureCollection" and isinstance(data.get("features"), list):
        out = []
        for i, f in enumerate(data["features"]):
            if not isinstance(f, dict):
                _fail(path, f"features[{i}] is {_short(f)}, not a GeoJSON Feature object")
            props = f.get("properties") if isinstance(f.get("properties"), dict) else {}
            if isinstance(f.get("geometry"), dict):
                out.append((f["geometry"], props, f"features[{i}]"))
        return out
    if kind == "GeometryCollection" and isinstance(data.get("geometries"), list):
        return [(g, {}, f"geometries[{i}]") for i, g in enumerate(data["geometries"])
                if isinstance(g, dict)]
    if kind == "Feature" and isinstance(data.get("geometry"), dict):
        props = data.get("properties") if isinstance(data.get("properties"), dict) else {}
        return [(data["geometry"], props, "the Feature")]
    return [(data, {}, "the geometry")]


def _coords(path, g, where):
    c = g.get("coordinates")
    if not isinstance(c, list) or not c:
        _fail(path, f'{where}: the {g.get("type")} needs non-empty "coordinates"')
    return c


def _geo_polygon(path, g, where):
    c = _coords(path, g, where)
    if g["type"] == "MultiPolygon":
        if len(c) != 1:
            _pf._multipolygon_error(path, len(c))
        c = c[0]
    if not isinstance(c, list) or not c or not isinstance(c[0], list) or (c[0] and _is_number(c[0][0])):
        _fail(path, f"{where}: the Polygon's coordinates must be a list of rings [[[x, y], ...], ...]")
    return [_json_ring(path, r, f"{where} ring {k}", geojson=True) for k, r in enumerate(c)]


def _split_geojson(path, items):
    polys, segments, points, seeds = [], [], [], []
    for g, props, where in items:
        kind = g.get("type")
        label = props.get("label")
        if label is not None and not _label_ok(label):
            _fail(path, f'{where}: the "label" property {_short(label)} is not a string or number')
        if kind in _POLYS:
            polys.append((_geo_polygon(path, g, where), label, where))
        elif kind == "LineString":
            segments.append(_json_ring(path, _coords(path, g, where), where, geojson=True))
        elif kind == "MultiLineString":
            segments += [_json_ring(path, c, f"{where} line {k}", geojson=True)
                         for k, c in enumerate(_coords(path, g, where))]
        elif kind in _POINTS:
            c = _coords(path, g, where)
            xy = _json_ring(path, [c] if kind == "Point" else c, where, geojson=True)
            if label is not None:
                seeds += [(x, y, label) for x, y in xy]
            else:
                points += list(xy)
        else:
            logger.warning("%s: ignoring %s, a %s", path, where, _short(kind))
    return polys, segments, points, seeds


def _polygon_from_geojson(path, data) -> Polygon:
    items = _geo_items(path, data)
    kinds = [g.get("type") for g, _, _ in items]
    if not any(k in _LINES + _POINTS for k in kinds) and sum(k in _POLYS for k in kinds) <= 1:
        return _pf._polygon_from_geojson(path, data)
    polys, segments, points, seeds = _split_geojson(path, items)
    if not polys:
        return _pf._polygon_from_geojson(path, data)
    main = int(np.argmax([abs(shapely.Polygon(p[0][0]).area) if len(p[0][0]) >= 3 else 0.0
                          for p in polys]))
    rings, label, _ = polys[main]
    outline = shapely.Polygon(rings[0]) if len(rings[0]) >= 3 else None
    zones = []
    for k, (zr, zlabel, where) in enumerate(polys):
        if k == main:
            continue
        if outline is not None and len(zr[0]) >= 3 and not outline.covers(shapely.Polygon(zr[0])):
            _fail(path, f"contains {len(polys)} polygons and {where} is not inside the largest "
                        f"({polys[main][2]}); uniform2d meshes one polygon at a time: keep one, "
                        "or split them into separate files (a Polygon inside the outline is "
                        "read as a zone)")
        segments += [np.vstack([r, r[:1]]) if not np.array_equal(r[0], r[-1]) else r for r in zr]
        if len(zr[0]) >= 3:
            zones.append((shapely.Polygon(zr[0]), zlabel))
    if label is not None:
        logger.info("%s: the outline's label is not used; label regions with Points", path)
    pts = np.array(points, dtype=np.float64).reshape(-1, 2)
    seeds = zone_seeds(path, rings[0], rings[1:], segments, pts, zones, seeds)
    return _pf._make_polygon(path, rings[0], rings[1:], segments=segments, points=pts,
                             regions=seeds)


def read_geojson(path) -> Polygon:
    """Read a GeoJSON polygon, with segments, points and labels from a collection."""
    return _polygon_from_geojson(path, _load_json(path))


def _feature(geometry: str, props: str) -> str:
    return f'    {{"type": "Feature", "properties": {props}, "geometry": {geometry}}}'


def write_geojson(path, polygon: Polygon) -> None:
    """Write a FeatureCollection: the Polygon, then a LineString per segment, a Point
    per fixed point and a labelled Point per region seed."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _pf.write_geojson(path, polygon)

    def line(ring, close=False):
        pts = list(ring) + ([ring[0]] if close else [])
        return "[" + ", ".join(f"[{_num(x)}, {_num(y)}]" for x, y in pts) + "]"

    rings = ", ".join(line(r, close=True) for r in polygon.rings)
    feats = [_feature(f'{{"type": "Polygon", "coordinates": [{rings}]}}', "{}")]
    feats += [_feature(f'{{"type": "LineString", "coordinates": {line(s)}}}', f'{{"segment": {i}}}')
              for i, s in enumerate(polygon.segments)]
    feats += [_feature(f'{{"type": "Point", "coordinates": [{_num(x)}, {_num(y)}]}}',
                       f'{{"point": {i}}}') for i, (x, y) in enumerate(polygon.points)]
    feats += [_feature(f'{{"type": "Point", "coordinates": [{_num(x)}, {_num(y)}]}}',
                       f'{{"label": {_label_json(lab)}}}') for x, y, lab in polygon.region_seeds]
    with open(path, "w", encoding="utf-8") as f:
        f.write('{"type": "FeatureCollection", "features": [\n' + ",\n".join(feats) + "\n]}\n")


# -- .wkt ----------------------------------------------------------------------------
def read_wkt(path) -> Polygon:
    """Read a WKT POLYGON, or a GEOMETRYCOLLECTION of one POLYGON with LINESTRINGs
    (segments) and POINTs (fixed points)."""
    text = _pf._read_text(path).strip()
    if not text.upper().startswith("GEOMETRYCOLLECTION"):
        return _pf.read_wkt(path)
    try:
        geom = shapely.wkt.loads(text)
    except shapely.errors.ShapelyError as exc:
        _fail(path, f"not valid WKT ({exc})")
    polys, segments, points = [], [], []
    for k, g in enumerate(geom.geoms):
        if g.geom_type == "Polygon" and not g.is_empty:
            polys.append(g)
        elif g.geom_type in ("LineString", "MultiLineString"):
            parts = [g] if g.geom_type == "LineString" else list(g.geoms)
            segments += [np.asarray(p.coords)[:, :2] for p in parts if not p.is_empty]
        elif g.geom_type in ("Point", "MultiPoint"):
            points += [np.asarray(p.coords)[0, :2] for p in getattr(g, "geoms", [g])
                       if not p.is_empty]
        else:
            _fail(path, f"member {k} of the GEOMETRYCOLLECTION is a {g.geom_type}; expected one "
                        "POLYGON with LINESTRING, MULTILINESTRING, POINT or MULTIPOINT members")
    if len(polys) != 1:
        _fail(path, f"the GEOMETRYCOLLECTION holds {len(polys)} non-empty POLYGONs; it needs "
                    "exactly one (the outline with its holes)")
    p = polys[0]
    return _pf._make_polygon(
        path, np.asarray(p.exterior.coords)[:, :2], [np.asarray(h.coords)[:, :2] for h in p.interiors],
        segments=segments, points=np.array(points, dtype=np.float64).reshape(-1, 2))


def write_wkt(path, polygon: Polygon) -> None:
    """Write a WKT POLYGON, or a GEOMETRYCOLLECTION with the segments and points
    (WKT holds no region labels: they are dropped with a warning)."""
    if polygon.region_seeds:
        logger.warning("%s: WKT has no labels; dropping the %d region labels", path,
                       len(polygon.region_seeds))
    if not polygon.has_constraints:
        return _pf.write_wkt(path, polygon)

    def seq(pts, close=False):
        pts = list(pts) + ([pts[0]] if close else [])
        return "(" + ", ".join(f"{_num(x)} {_num(y)}" for x, y in pts) + ")"

    parts = ["POLYGON (" + ", ".join(seq(r, close=True) for r in polygon.rings) + ")"]
    parts += [f"LINESTRING {seq(s)}" for s in polygon.segments]
    parts += [f"POINT ({_num(x)} {_num(y)})" for x, y in polygon.points]
    with open(path, "w", encoding="utf-8") as f:
        f.write("GEOMETRYCOLLECTION (" + ", ".join(parts) + ")\n")
