"""Triangle ``.poly`` and DXF files with interior segments, points and labels.

These extend the ``.poly`` and ``.dxf`` readers and writers of
:mod:`uniform2d.io.polygon_files` (see :mod:`uniform2d.io.constrained_files`
for what each format holds).  A file in the older subset -- rings only, every
inner ring around a hole point, no regional attributes -- is read exactly as
there, with the same messages.

``.poly``: the faces the segments enclose are found with
:func:`shapely.polygonize`; those holding a hole point are holes (Triangle eats
them), the rest make the domain, whose boundary gives the rings.  The other
segments are chained into polylines through the vertices where exactly two of
them meet and nothing else does; vertices on no segment are fixed points
(those outside the domain are dropped with a warning, as Triangle drops them).
"""

from __future__ import annotations

import logging
from collections import Counter
from pathlib import Path

import numpy as np
import shapely

from ..polygon import Polygon
from . import polygon_files as _pf
from .constrained_files import zone_seeds
from .polygon_files import _fail, _num

__all__ = ["read_poly", "write_poly", "read_dxf", "write_dxf"]

logger = logging.getLogger(__name__)


# -- .poly ---------------------------------------------------------------------------
def _poly_attributes(path, lines) -> list:
    """The regional attributes section: [(x, y, attribute), ...]."""
    n, tokens = lines.next("", optional=True)
    if n is None:
        return []
    count = lines.number(n, tokens, 0, "regional attribute count", int)
    if count < 0:
        _fail(path, f"line {n}: negative regional attribute count {count}")
    out = []
    for k in range(count):
        n, tokens = lines.next(f"regional attribute {k + 1} of {count}")
        x = lines.number(n, tokens, 1, "region x")
        y = lines.number(n, tokens, 2, "region y")
        if len(tokens) < 4:
            continue  # an area constraint alone labels nothing
        a = lines.number(n, tokens, 3, "regional attribute")
        out.append((x, y, int(a) if float(a).is_integer() else a))
    return out


def _rings_only(path, xy, base, segments, holes_xy) -> bool:
    """Whether the file is in the rings-and-holes subset of the older reader."""
    deg = Counter()
    for _, a, b in segments:
        deg[a] += 1
        deg[b] += 1
    if len(deg) != len(xy) or any(d != 2 for d in deg.values()) or any(a == b for _, a, b in segments):
        return False
    try:
        rings = _pf._walk_rings(path, len(xy), segments, base)
    except _pf.FileFormatError:
        return True  # let the older reader say what is wrong
    shapes = [shapely.Polygon(xy[r]) for r in rings]
    outer = int(np.argmax([s.area for s in shapes]))
    pts = [shapely.Point(hx, hy) for _, hx, hy in holes_xy]
    return all(any(s.contains(p) for p in pts) for k, s in enumerate(shapes) if k != outer)


def _domain(path, xy, edges, holes_xy):
    """The shapely Polygon the segments enclose, less the faces around hole points."""
    faces = list(shapely.polygonize(shapely.linestrings(xy[edges])).geoms)
    if not faces:
        _fail(path, "the segments enclose no area; the outline must be a closed chain of segments")
    is_hole = [False] * len(faces)
    for hid, hx, hy in holes_xy:
        hit = [k for k, f in enumerate(faces) if f.contains(shapely.Point(hx, hy))]
        if not hit:
            _fail(path, f"hole point {hid} ({hx:.17g}, {hy:.17g}) is not inside any area the "
                        "segments enclose; move it into the hole it marks, or remove it")
        is_hole[hit[0]] = True
    kept = [f for f, h in zip(faces, is_hole) if not h]
    if not kept:
        _fail(path, "every area the segments enclose holds a hole point; nothing is left to mesh")
    domain = shapely.union_all(kept)
    if domain.geom_type != "Polygon":
        _fail(path, f"the segments enclose {len(domain.geoms)} separate areas; uniform2d meshes "
                    "one polygon at a time: put each in its own file")
    return domain


def _chains(edges: list, stops: set) -> list[list[int]]:
    """Maximal vertex paths of ``edges`` through vertices of degree 2 not in ``stops``."""
    adj = {}
    for k, (a, b) in enumerate(edges):
        adj.setdefault(a, []).append((b, k))
        adj.setdefault(b, []).append((a, k))
    stop = set(stops) | {v for v, n in adj.items() if len(n) != 2}
    used = [False] * len(edges)
    out = []
    for start in sorted(stop & set(adj)) + sorted(adj):
        for nxt, k in adj[start]:
            if used[k]:
                continue
            chain, prev, cur = [start], start, nxt
            used[k] = True
            while True:
                chain.append(cur)
                if cur in stop or cur == start:
                    break
                (n1, k1), (n2, k2) = adj[cur]
                nxt, kk = (n2, k2) if used[k1] else (n1, k1)
                if used[kk]:
                    break
                used[kk] = True
                prev, cur = cur, nxt
            out.append(chain)
    return out


def read_poly(path) -> Polygon:
    """Read a Triangle .poly file: rings, holes, interior segments, free vertices
    (fixed points) and regional attributes (labels)."""
    path = Path(path)
    lines, xy, base, segments, holes_xy = _pf._poly_sections(path)
    seeds = _poly_attributes(path, lines)
    if not seeds and _rings_only(path, xy, base, segments, holes_xy):
        return _pf._poly_ring_polygon(path, xy, base, segments, holes_xy)
    _pf._check_segments(path, segments, base)
    edges = np.array([(a, b) for _, a, b in segments], dtype=np.int64)
    domain = _domain(path, xy, edges, holes_xy)
    first = {}
    for i, p in enumerate(map(tuple, xy)):
        first.setdefault(p, i)

    def ring(coords):  # starting at its first vertex in the file, as written
        r = np.asarray(coords)[:-1]
        return np.roll(r, -int(np.argmin([first[tuple(p)] for p in r])), axis=0)

    outer = ring(domain.exterior.coords)
    holes = [ring(h.coords) for h in domain.interiors]
    on_ring = set()
    for r in (outer, *holes):
        t = [tuple(p) for p in r]
        on_ring |= {frozenset((t[i], t[(i + 1) % len(t)])) for i in range(len(t))}
    inner, dropped = [], 0
    shapely.prepare(domain)
    for a, b in edges.tolist():
        if frozenset((tuple(xy[a]), tuple(xy[b]))) in on_ring:
            continue
        if domain.covers(shapely.Point((xy[a] + xy[b]) / 2)):
            inner.append((a, b))
        else:
            dropped += 1
    ring_pts = {tuple(p) for r in (outer, *holes) for p in r}
    ring_vertex = {i for i in range(len(xy)) if tuple(xy[i]) in ring_pts}
    chains = [xy[c] for c in _chains(inner, ring_vertex)]
    free = sorted(set(range(len(xy))) - set(edges.ravel().tolist()))
    fixed = [i for i in free if domain.covers(shapely.Point(xy[i]))]
    if dropped or len(fixed) < len(free):
        logger.warning("%s: dropping %d segments and %d vertices outside the polygon or in its "
                       "holes (as Triangle does)", path, dropped, len(free) - len(fixed))
    return _pf._make_polygon(path, outer, holes, segments=chains,
                             points=xy[fixed].reshape(-1, 2), regions=seeds)


def write_poly(path, polygon: Polygon) -> None:
    """Write a Triangle .poly file: every vertex, the ring edges and segment pieces
    as segments, a hole point per hole and the numeric region labels as regional
    attributes (text labels are dropped with a warning)."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _pf.write_poly(path, polygon)
    V = polygon.vertices
    out = [f"# uniform2d polygon: {polygon.n_holes} hole(s), {len(polygon.segments)} segment(s), "
           f"{len(polygon.points)} fixed point(s); Triangle .poly format",
           f"{len(V)} 2 0 0"]
    out += [f"{k + 1} {_num(x)} {_num(y)}" for k, (x, y) in enumerate(V)]
    edges = polygon.constraint_edges
    out.append(f"{len(edges)} 0")
    out += [f"{k + 1} {i + 1} {j + 1}" for k, (i, j) in enumerate(edges.tolist())]
    out.append(f"{polygon.n_holes}")
    for k, h in enumerate(polygon.holes):
        p = shapely.Polygon(h).point_on_surface()
        out.append(f"{k + 1} {_num(p.x)} {_num(p.y)}")
    numeric = [(x, y, lab) for x, y, lab in polygon.region_seeds if not isinstance(lab, str)]
    if len(numeric) < len(polygon.region_seeds):
        logger.warning("%s: .poly regional attributes are numbers; dropping %d text labels",
                       path, len(polygon.region_seeds) - len(numeric))
    out.append(f"{len(numeric)}")
    out += [f"{k + 1} {_num(x)} {_num(y)} {lab!r} 0" for k, (x, y, lab) in enumerate(numeric)]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


# -- .dxf ----------------------------------------------------------------------------
def _text(e) -> str | None:
    kind = e.dxftype()
    if kind == "TEXT":
        return e.dxf.text
    if kind == "MTEXT":
        return e.plain_text()
    return None


def _dxf_entities(path, doc):
    """Rings (with names), zones, segments, points and seeds of a modelspace."""
    rings, names, zones, segments, points, seeds, ignored = [], [], [], [], [], [], Counter()
    for e in doc.modelspace():
        kind, layer = e.dxftype(), str(e.dxf.get("layer", "0"))
        poly = _pf._dxf_polyline(e)
        if poly is not None:
            pts, closed, bulged = poly
            xy = np.asarray(pts, dtype=np.float64).reshape(-1, 3)[:, :2]
            ends_at_start = len(xy) >= 4 and np.array_equal(xy[0], xy[-1])
            name = f"polyline (handle {e.dxf.handle}, layer {layer})"
            if bulged:
                logger.warning("%s: %s has arc segments (bulges); they are read as straight "
                               "chords", path, name)
            kind_of = layer.upper()
            if (closed or ends_at_start) and kind_of.startswith(("ZONE", "SEGMENT")):
                ring = xy[:-1] if ends_at_start else xy
                segments.append(np.vstack([ring, ring[:1]]))
                if kind_of.startswith("ZONE") and len(ring) >= 3:
                    zones.append((shapely.Polygon(ring), layer))
            elif closed or ends_at_start:
                rings.append(_pf._dxf_ring(path, name, pts, closed, False))
                names.append(name)
            else:
                segments.append(xy)
        elif kind == "LINE":
            segments.append(np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)]))
        elif kind == "POINT":
            points.append(np.array([e.dxf.location.x, e.dxf.location.y]))
        elif _text(e) is not None:
            x, y = float(e.dxf.insert.x), float(e.dxf.insert.y)
            seeds.append((x, y, _text(e)))
        else:
            ignored[kind] += 1
    if ignored:
        logger.warning("%s: ignoring %s", path, ", ".join(f"{n} {k}" for k, n in sorted(ignored.items())))
    return rings, names, zones, segments, points, seeds


def read_dxf(path) -> Polygon:
    """Read a DXF modelspace: closed polylines as the outline and holes (on a
    ZONE* or SEGMENT* layer: closed segments), open LINE/LWPOLYLINE/POLYLINE as
    segments, POINT as fixed points, TEXT/MTEXT and ZONE* layers as labels."""
    doc = _pf._open_dxf(path)
    rings, names, zones, segments, points, seeds = _dxf_entities(path, doc)
    if not (segments or points or seeds):
        return _pf.read_dxf(path)
    if not rings:
        found = Counter(e.dxftype() for e in doc.modelspace())
        _fail(path, "no closed polylines in modelspace (found "
                    + ", ".join(f"{n} {k}" for k, n in sorted(found.items()))
                    + "); draw the outline as a closed LWPOLYLINE or POLYLINE")
    outer = int(np.argmax([abs(shapely.Polygon(r).area) if len(r) >= 3 else 0.0 for r in rings]))
    holes = [r for k, r in enumerate(rings) if k != outer]
    pts = np.array(points, dtype=np.float64).reshape(-1, 2)
    seeds = zone_seeds(path, rings[outer], holes, segments, pts, zones, seeds)
    return _pf._make_polygon(path, rings[outer], holes,
                             [names[outer]] + [n for k, n in enumerate(names) if k != outer],
                             segments=segments, points=pts, regions=seeds)


def write_dxf(path, polygon: Polygon) -> None:
    """Write the rings (layers OUTER, HOLES), segments as LWPOLYLINEs (SEGMENTS,
    closed ones closed), fixed points as POINTs (POINTS) and labels as TEXT
    (REGIONS); labels read back as text."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _pf.write_dxf(path, polygon)
    import ezdxf

    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2010")
        for name, colour in (("OUTER", 7), ("HOLES", 1), ("SEGMENTS", 3), ("POINTS", 5),
                             ("REGIONS", 4)):
            doc.layers.add(name, color=colour)
        msp = doc.modelspace()
        for k, ring in enumerate(polygon.rings):
            msp.add_lwpolyline([(float(x), float(y)) for x, y in ring], close=True,
                               dxfattribs={"layer": "OUTER" if k == 0 else "HOLES"})
        for s in polygon.segments:
            closed = len(s) > 3 and np.array_equal(s[0], s[-1])
            pts = s[:-1] if closed else s
            msp.add_lwpolyline([(float(x), float(y)) for x, y in pts], close=closed,
                               dxfattribs={"layer": "SEGMENTS"})
        for x, y in polygon.points:
            msp.add_point((float(x), float(y)), dxfattribs={"layer": "POINTS"})
        for x, y, label in polygon.region_seeds:
            msp.add_text(str(label), dxfattribs={"layer": "REGIONS", "insert": (x, y)})
        doc.saveas(path)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed
