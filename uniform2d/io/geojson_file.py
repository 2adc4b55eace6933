"""GeoJSON polygon files, ``.geojson``.

A GeoJSON ``Polygon`` geometry, a ``Feature`` holding one, or a
``FeatureCollection`` (or ``GeometryCollection``): the one Polygon containing
the others is the domain.  A ``MultiPolygon`` with a single part is accepted;
with more parts it is an error, as uniform2d meshes one polygon at a time.  A
third (z) coordinate is ignored.  In a collection, ``LineString`` and
``MultiLineString`` features are segments; ``Point`` and ``MultiPoint``
features are fixed points, except a Point whose properties have a ``"label"``,
which labels the region around it.  Any other Polygon feature is a *zone*: its
outline becomes a closed segment and, if its properties have a ``"label"``, the
regions inside it (not inside a smaller zone) get that label.

Written as a FeatureCollection, exterior ring counter-clockwise and holes
clockwise (RFC 7946): one Polygon Feature, then a LineString per segment, a
Point per fixed point and a labelled Point per region seed.
"""

from __future__ import annotations

import logging
from collections import Counter

import numpy as np
import shapely

from ..polygon import Polygon
from .common import (fail, is_number, json_ring, json_ring_text, label_json, label_ok, load_json,
                     make_polygon, multipolygon_error, num, short, zone_seeds)
from .fileformat import FileFormat

__all__ = ["read_geojson", "write_geojson", "polygon_from_geojson", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    "GeoJSON Polygon, Feature, or FeatureCollection with one polygon (and LineString "
    "segments, Point fixed points, labelled Points and zone Polygons)"
)

# -- one polygon ------------------------------------------------------------------------
_POLYGONAL = ("Polygon", "MultiPolygon")


def _geojson_polygon_coords(path, data):
    """Find the one polygon in a GeoJSON object; return its coordinates member."""
    if not isinstance(data, dict):
        fail(path, f"expected a GeoJSON object, got a JSON {type(data).__name__}")
    kind = data.get("type")
    if kind == "Feature":
        geom = data.get("geometry")
        if geom is None:
            fail(path, "the Feature has no geometry (null); give it a Polygon geometry")
        return _geojson_polygon_coords(path, geom)
    if kind in ("FeatureCollection", "GeometryCollection"):
        member = "features" if kind == "FeatureCollection" else "geometries"
        items = data.get(member)
        if not isinstance(items, list):
            fail(path, f'the {kind} has no "{member}" list')
        for i, item in enumerate(items):
            if not isinstance(item, dict):
                what = "Feature" if kind == "FeatureCollection" else "geometry"
                fail(path, f'{member}[{i}] is {short(item)}, not a GeoJSON {what} object')
        if kind == "FeatureCollection":
            items = [item.get("geometry") for item in items]
        geoms = [g for g in items if isinstance(g, dict)]
        polys = [g for g in geoms if g.get("type") in _POLYGONAL]
        others = Counter(str(g.get("type")) for g in geoms if g.get("type") not in _POLYGONAL)
        if len(polys) != 1:
            found = ", ".join(f"{n} {t}" for t, n in sorted(others.items())) or "nothing else"
            if not polys:
                fail(path, f"the {kind} contains no Polygon (found {found}); it needs exactly one")
            fail(
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
            fail(path, 'the Polygon needs "coordinates": a non-empty list of rings')
        return coords
    if kind == "MultiPolygon":
        coords = data.get("coordinates")
        if not isinstance(coords, list) or not coords:
            fail(path, 'the MultiPolygon needs "coordinates": a non-empty list of polygons')
        if len(coords) != 1:
            multipolygon_error(path, len(coords))
        if not isinstance(coords[0], list) or not coords[0]:
            fail(path, f"the MultiPolygon's only polygon is {short(coords[0])}; it must be a "
                       "non-empty list of rings [[[x, y], ...], ...] (outer ring first)")
        logger.info("%s: reading a one-part MultiPolygon as a Polygon", path)
        return _geojson_polygon_coords(path, {"type": "Polygon", "coordinates": coords[0]})
    if kind in ("Point", "MultiPoint", "LineString", "MultiLineString"):
        fail(
            path,
            f"contains a {kind}; expected a Polygon (or a Feature or FeatureCollection "
            "holding one). A closed outline must be a Polygon, not a LineString",
        )
    fail(
        path,
        f"unknown GeoJSON type {short(kind)}; expected a Polygon, Feature or FeatureCollection",
    )


def _one_polygon(path, data) -> Polygon:
    coords = _geojson_polygon_coords(path, data)
    if coords and isinstance(coords[0], list) and coords[0] and is_number(coords[0][0]):
        fail(
            path,
            '"coordinates" of a Polygon is a list of rings (outer first); it looks like a '
            "single ring: wrap it as [[[x, y], ...]]",
        )
    rings = [
        json_ring(path, r, "the outer ring" if i == 0 else f"hole ring {i - 1}", geojson=True)
        for i, r in enumerate(coords)
    ]
    return make_polygon(path, rings[0], rings[1:])


# -- a collection with segments, points and labels ------------------------------------
_LINES = ("LineString", "MultiLineString")
_POINTS = ("Point", "MultiPoint")
_POLYS = ("Polygon", "MultiPolygon")


def _geo_items(path, data) -> list:
    """(geometry, properties, where) of every geometry in a GeoJSON object."""
    if not isinstance(data, dict):
        fail(path, f"expected a GeoJSON object, got a JSON {type(data).__name__}")
    kind = data.get("type")
    if kind == "FeatureCollection" and isinstance(data.get("features"), list):
        out = []
        for i, f in enumerate(data["features"]):
            if not isinstance(f, dict):
                fail(path, f"features[{i}] is {short(f)}, not a GeoJSON Feature object")
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
        fail(path, f'{where}: the {g.get("type")} needs non-empty "coordinates"')
    return c


def _geo_polygon(path, g, where):
    c = _coords(path, g, where)
    if g["type"] == "MultiPolygon":
        if len(c) != 1:
            multipolygon_error(path, len(c))
        c = c[0]
    if not isinstance(c, list) or not c or not isinstance(c[0], list) or (c[0] and is_number(c[0][0])):
        fail(path, f"{where}: the Polygon's coordinates must be a list of rings [[[x, y], ...], ...]")
    return [json_ring(path, r, f"{where} ring {k}", geojson=True) for k, r in enumerate(c)]


def _split_geojson(path, items):
    polys, segments, points, seeds = [], [], [], []
    for g, props, where in items:
        kind = g.get("type")
        label = props.get("label")
        if label is not None and not label_ok(label):
            fail(path, f'{where}: the "label" property {short(label)} is not a string or number')
        if kind in _POLYS:
            polys.append((_geo_polygon(path, g, where), label, where))
        elif kind == "LineString":
            segments.append(json_ring(path, _coords(path, g, where), where, geojson=True))
        elif kind == "MultiLineString":
            segments += [json_ring(path, c, f"{where} line {k}", geojson=True)
                         for k, c in enumerate(_coords(path, g, where))]
        elif kind in _POINTS:
            c = _coords(path, g, where)
            xy = json_ring(path, [c] if kind == "Point" else c, where, geojson=True)
            if label is not None:
                seeds += [(x, y, label) for x, y in xy]
            else:
                points += list(xy)
        else:
            logger.warning("%s: ignoring %s, a %s", path, where, short(kind))
    return polys, segments, points, seeds


def polygon_from_geojson(path, data) -> Polygon:
    """The polygon of a parsed GeoJSON object ``data`` read from ``path``."""
    items = _geo_items(path, data)
    kinds = [g.get("type") for g, _, _ in items]
    if not any(k in _LINES + _POINTS for k in kinds) and sum(k in _POLYS for k in kinds) <= 1:
        return _one_polygon(path, data)
    polys, segments, points, seeds = _split_geojson(path, items)
    if not polys:
        return _one_polygon(path, data)
    main = int(np.argmax([abs(shapely.Polygon(p[0][0]).area) if len(p[0][0]) >= 3 else 0.0
                          for p in polys]))
    rings, label, _ = polys[main]
    outline = shapely.Polygon(rings[0]) if len(rings[0]) >= 3 else None
    zones = []
    for k, (zr, zlabel, where) in enumerate(polys):
        if k == main:
            continue
        if outline is not None and len(zr[0]) >= 3 and not outline.covers(shapely.Polygon(zr[0])):
            fail(path, f"contains {len(polys)} polygons and {where} is not inside the largest "
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
    return make_polygon(path, rings[0], rings[1:], segments=segments, points=pts,
                             regions=seeds)


def read_geojson(path) -> Polygon:
    """Read a GeoJSON polygon, with segments, points and labels from a collection."""
    return polygon_from_geojson(path, load_json(path))


def _write_rings(path, polygon: Polygon) -> None:
    """Write a FeatureCollection with one Polygon Feature (RFC 7946 orientation)."""
    rings = ",\n".join(
        "          " + json_ring_text(r, "          ", close=True) for r in polygon.rings
    )
    text = (
        '{\n  "type": "FeatureCollection",\n  "features": [\n    {\n'
        '      "type": "Feature",\n      "properties": {},\n'
        '      "geometry": {\n        "type": "Polygon",\n'
        f'        "coordinates": [\n{rings}\n        ]\n      }}\n    }}\n  ]\n}}\n'
    )
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def _feature(geometry: str, props: str) -> str:
    return f'    {{"type": "Feature", "properties": {props}, "geometry": {geometry}}}'


def write_geojson(path, polygon: Polygon) -> None:
    """Write a FeatureCollection: the Polygon, then a LineString per segment, a Point
    per fixed point and a labelled Point per region seed."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _write_rings(path, polygon)

    def line(ring, close=False):
        pts = list(ring) + ([ring[0]] if close else [])
        return "[" + ", ".join(f"[{num(x)}, {num(y)}]" for x, y in pts) + "]"

    rings = ", ".join(line(r, close=True) for r in polygon.rings)
    feats = [_feature(f'{{"type": "Polygon", "coordinates": [{rings}]}}', "{}")]
    feats += [_feature(f'{{"type": "LineString", "coordinates": {line(s)}}}', f'{{"segment": {i}}}')
              for i, s in enumerate(polygon.segments)]
    feats += [_feature(f'{{"type": "Point", "coordinates": [{num(x)}, {num(y)}]}}',
                       f'{{"point": {i}}}') for i, (x, y) in enumerate(polygon.points)]
    feats += [_feature(f'{{"type": "Point", "coordinates": [{num(x)}, {num(y)}]}}',
                       f'{{"label": {label_json(lab)}}}') for x, y, lab in polygon.region_seeds]
    with open(path, "w", encoding="utf-8") as f:
        f.write('{"type": "FeatureCollection", "features": [\n' + ",\n".join(feats) + "\n]}\n")


#: This module's entry in :data:`uniform2d.io.registry.POLYGON_FORMATS`.
FORMAT = FileFormat(".geojson", DESCRIPTION, read_geojson, write_geojson)
