"""Well-Known Text polygon files, ``.wkt``.

One ``POLYGON`` (a one-part ``MULTIPOLYGON`` is accepted), or a
``GEOMETRYCOLLECTION`` of one ``POLYGON`` and ``LINESTRING``,
``MULTILINESTRING``, ``POINT`` and ``MULTIPOINT`` members (segments and fixed
points; WKT has no labels, so region labels are dropped with a warning).

Examples
--------
>>> import os, tempfile
>>> from uniform2d import Polygon
>>> from uniform2d.io.wkt_file import read_wkt, write_wkt
>>> path = os.path.join(tempfile.mkdtemp(), "square.wkt")
>>> write_wkt(path, Polygon([(0, 0), (2, 0), (2, 2), (0, 2)]))
>>> print(open(path).read().strip())
POLYGON ((0.0 0.0, 2.0 0.0, 2.0 2.0, 0.0 2.0, 0.0 0.0))
>>> read_wkt(path).area
4.0
"""

from __future__ import annotations

import logging

import numpy as np
import shapely
import shapely.wkt

from ..polygon import Polygon
from .common import fail, make_polygon, multipolygon_error, num, read_text
from .fileformat import FileFormat

__all__ = ["read_wkt", "write_wkt", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    "Well-Known Text POLYGON, or GEOMETRYCOLLECTION with LINESTRING segments and POINTs"
)

def _read_polygon(path) -> Polygon:
    """Read one WKT POLYGON (a one-part MULTIPOLYGON is accepted)."""
    text = read_text(path).strip()
    if not text:
        fail(path, "the file is empty; expected a WKT POLYGON ((x y, ...), ...)")
    try:
        geom = shapely.wkt.loads(text)
    except NotImplementedError as exc:  # e.g. CURVEPOLYGON: curved geometry
        fail(path, f"unsupported WKT geometry ({exc}); give a POLYGON with straight edges")
    except shapely.errors.ShapelyError as exc:
        fail(path, f"not valid WKT ({exc})")
    if geom.geom_type == "MultiPolygon":
        if geom.is_empty:
            fail(path, "contains an empty MULTIPOLYGON: there is no polygon to mesh; give one "
                       "POLYGON ((x y, ...)) with the outline's coordinates (export the shape "
                       "again if it was meant to have some)")
        if len(geom.geoms) != 1:
            multipolygon_error(path, len(geom.geoms))
        logger.info("%s: reading a one-part MULTIPOLYGON as a POLYGON", path)
        geom = geom.geoms[0]
    if geom.geom_type != "Polygon":
        fail(path, f"contains a {geom.geom_type}; expected a POLYGON")
    if geom.is_empty:
        fail(path, "contains an empty POLYGON: there is no polygon to mesh; give the "
                   "outline's coordinates, POLYGON ((x y, ...))")
    if geom.has_z:
        logger.warning("%s: z coordinates are ignored", path)
    return make_polygon(
        path,
        np.asarray(geom.exterior.coords)[:, :2],
        [np.asarray(h.coords)[:, :2] for h in geom.interiors],
    )


def read_wkt(path) -> Polygon:
    """Read a WKT POLYGON, or a GEOMETRYCOLLECTION of one POLYGON with LINESTRINGs
    (segments) and POINTs (fixed points)."""
    text = read_text(path).strip()
    if not text.upper().startswith("GEOMETRYCOLLECTION"):
        return _read_polygon(path)
    try:
        geom = shapely.wkt.loads(text)
    except shapely.errors.ShapelyError as exc:
        fail(path, f"not valid WKT ({exc})")
    polys, segments, points = [], [], []
    for k, g in enumerate(geom.geoms):
        if g.geom_type == "MultiPolygon" and len(g.geoms) == 1:
            g = g.geoms[0]  # a one-part MULTIPOLYGON, as at the top level
        if g.geom_type == "Polygon" and not g.is_empty:
            polys.append(g)
        elif g.geom_type in ("LineString", "MultiLineString"):
            parts = [g] if g.geom_type == "LineString" else list(g.geoms)
            segments += [np.asarray(p.coords)[:, :2] for p in parts if not p.is_empty]
        elif g.geom_type in ("Point", "MultiPoint"):
            points += [np.asarray(p.coords)[0, :2] for p in getattr(g, "geoms", [g])
                       if not p.is_empty]
        elif g.geom_type == "MultiPolygon" and len(g.geoms) > 1:
            multipolygon_error(path, len(g.geoms))
        elif not (g.geom_type in ("Polygon", "MultiPolygon") and g.is_empty):
            fail(path, f"member {k} of the GEOMETRYCOLLECTION is a {g.geom_type}; expected one "
                        "POLYGON with LINESTRING, MULTILINESTRING, POINT or MULTIPOINT members")
    if len(polys) != 1:
        fail(path, f"the GEOMETRYCOLLECTION holds {len(polys)} non-empty POLYGONs; it needs "
                    "exactly one (the outline with its holes)")
    p = polys[0]
    return make_polygon(
        path, np.asarray(p.exterior.coords)[:, :2], [np.asarray(h.coords)[:, :2] for h in p.interiors],
        segments=segments, points=np.array(points, dtype=np.float64).reshape(-1, 2))


def _write_polygon(path, polygon: Polygon) -> None:
    """Write one WKT POLYGON with closed rings and exact (shortest round-trip) floats."""
    rings = []
    for r in polygon.rings:
        pts = list(r) + [r[0]]
        rings.append("(" + ", ".join(f"{num(x)} {num(y)}" for x, y in pts) + ")")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"POLYGON ({', '.join(rings)})\n")


def write_wkt(path, polygon: Polygon) -> None:
    """Write a WKT POLYGON, or a GEOMETRYCOLLECTION with the segments and points
    (WKT holds no region labels: they are dropped with a warning)."""
    if polygon.region_seeds:
        logger.warning("%s: WKT has no labels; dropping the %d region labels", path,
                       len(polygon.region_seeds))
    if not polygon.has_constraints:
        return _write_polygon(path, polygon)

    def seq(pts, close=False):
        pts = list(pts) + ([pts[0]] if close else [])
        return "(" + ", ".join(f"{num(x)} {num(y)}" for x, y in pts) + ")"

    parts = ["POLYGON (" + ", ".join(seq(r, close=True) for r in polygon.rings) + ")"]
    parts += [f"LINESTRING {seq(s)}" for s in polygon.segments]
    parts += [f"POINT ({num(x)} {num(y)})" for x, y in polygon.points]
    with open(path, "w", encoding="utf-8") as f:
        f.write("GEOMETRYCOLLECTION (" + ", ".join(parts) + ")\n")


#: This module's entry in :data:`uniform2d.io.registry.POLYGON_FORMATS`.
FORMAT = FileFormat(".wkt", DESCRIPTION, read_wkt, write_wkt)
