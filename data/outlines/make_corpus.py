"""Rebuild the outline corpus (development time only; the JSON files are committed).

Needs, besides uniform2d: the geopandas 0.14.4 wheel (its ``geopandas/datasets``
ship Natural Earth's low-resolution countries and NYC's borough boundaries),
``pyshp`` to read their shapefiles, ``pyproj`` to project longitude/latitude, and
the ``triangle`` package (its example ``.poly`` files).  None of them is a
dependency of uniform2d::

    pip download --no-deps geopandas==0.14.4 pyshp pyproj -d dl
    (cd dl && unzip -q geopandas-0.14.4-py3-none-any.whl 'geopandas/datasets/*'
     && unzip -q geopandas/datasets/nybb_16a.zip -d nybb)
    # install pyshp and pyproj into a scratch environment, then
    python data/outlines/make_corpus.py dl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import uniform2d as u
from uniform2d.geometry import signed_area

HERE = Path(__file__).parent

#: Natural Earth countries: (name in the file, output stem); the largest part of each.
COUNTRIES = [
    ("Canada", "canada"), ("Antarctica", "antarctica"), ("Russia", "russia"),
    ("United States of America", "usa"), ("Greenland", "greenland"), ("Australia", "australia"),
    ("China", "china"), ("Brazil", "brazil"), ("Indonesia", "indonesia"), ("Norway", "norway"),
    ("Chile", "chile"), ("Argentina", "argentina"), ("Mexico", "mexico"), ("India", "india"),
    ("Italy", "italy"), ("Japan", "japan"), ("United Kingdom", "united_kingdom"),
    ("New Zealand", "new_zealand"), ("Madagascar", "madagascar"), ("Iceland", "iceland"),
    ("Greece", "greece"), ("Philippines", "philippines"), ("Turkey", "turkey"),
    ("Dem. Rep. Congo", "dr_congo"),
]
BOROUGHS = ["Staten Island", "Manhattan", "Bronx", "Brooklyn", "Queens"]
TRIANGLE = ["A", "face", "la", "double_hex", "square_circle_hole"]


def _rings(shape):
    parts = list(shape.parts) + [len(shape.points)]
    return [np.asarray(shape.points[a:b], dtype=np.float64) for a, b in zip(parts[:-1], parts[1:])]


def _largest(rings):
    """The largest outer ring (clockwise in a shapefile) and the holes inside it."""
    import shapely

    outers = [r for r in rings if signed_area(r) < 0]
    outer = max(outers, key=lambda r: abs(signed_area(r)))
    shell = shapely.Polygon(outer)
    holes = [r for r in rings if signed_area(r) > 0 and shell.contains(shapely.Polygon(r))]
    return outer, holes


def _clean(ring, digits):
    """Rounded, without repeated consecutive vertices (nor the closing one)."""
    r = np.round(ring, digits)
    keep = np.any(r != np.roll(r, 1, axis=0), axis=1)
    return r[keep]


def _write(stem, outer, holes, digits, meta):
    outer = _clean(outer, digits)
    holes = [_clean(h, digits) for h in holes]
    try:
        p = u.Polygon(outer, holes)
    except u.Uniform2dError:  # a pinch (Antarctica's pole) or a hole touching: made valid
        import shapely

        g = shapely.make_valid(shapely.Polygon(outer, holes))
        parts = [q for q in getattr(g, "geoms", [g]) if q.geom_type == "Polygon"]
        q = max(parts, key=lambda q: q.area)
        p = u.Polygon(_clean(np.asarray(q.exterior.coords)[:-1], digits),
                      [_clean(np.asarray(h.coords)[:-1], digits) for h in q.interiors])
    doc = {"outer": p.outer.tolist(), "holes": [h.tolist() for h in p.holes]}
    (HERE / f"{stem}.json").write_text(json.dumps(doc, separators=(",", ":")))
    meta.append((stem, len(p.vertices), p.n_holes))


def countries(dl: Path, meta):
    import pyproj
    import shapefile

    r = shapefile.Reader(str(dl / "geopandas/datasets/naturalearth_lowres/naturalearth_lowres.shp"))
    by_name = {rec[2]: shp for shp, rec in zip(r.shapes(), r.records())}
    for name, stem in COUNTRIES:
        outer, holes = _largest(_rings(by_name[name]))
        if name == "Norway":  # one outline kept in degrees, for the docs' projection example
            _write("norway_lonlat", outer, holes, 6, meta)
        if name == "Antarctica":
            crs = "EPSG:3031"  # south polar stereographic
        else:
            lon, lat = outer.mean(axis=0)
            crs = f"+proj=laea +lat_0={lat:.3f} +lon_0={lon:.3f} +datum=WGS84 +units=m"
        t = pyproj.Transformer.from_crs("EPSG:4326", crs, always_xy=True)
        proj = [np.c_[t.transform(r[:, 0], r[:, 1])] for r in [outer, *holes]]
        _write(stem, proj[0], proj[1:], 1, meta)


def boroughs(dl: Path, meta):
    import shapefile

    r = shapefile.Reader(str(dl / "nybb/nybb.shp"))
    for shp, rec in zip(r.shapes(), r.records()):
        if rec[1] in BOROUGHS:
            outer, holes = _largest(_rings(shp))
            _write("nyc_" + rec[1].lower().replace(" ", "_"), outer, holes, 2, meta)


def triangle_examples(meta):
    import triangle

    base = Path(triangle.__file__).parent / "data"
    for stem in TRIANGLE:
        p = u.read_polygon(base / f"{stem}.poly")
        doc = {"outer": p.outer.tolist(), "holes": [h.tolist() for h in p.holes]}
        if p.segments:
            doc["segments"] = [s.tolist() for s in p.segments]
        if len(p.points) and stem != "square_circle_hole":  # its points are a refined mesh's nodes
            doc["points"] = p.points.tolist()
        (HERE / f"triangle_{stem}.json").write_text(json.dumps(doc, separators=(",", ":")))
        meta.append((f"triangle_{stem}", len(p.vertices), p.n_holes))


if __name__ == "__main__":
    dl = Path(sys.argv[1])
    meta: list = []
    countries(dl, meta)
    boroughs(dl, meta)
    triangle_examples(meta)
    for stem, nv, nh in meta:
        print(f"{stem}: {nv} vertices, {nh} holes")
