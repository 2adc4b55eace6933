"""Triangle's planar straight-line graph files, ``.poly``.

A vertex section, a segment section, a hole section and a regional attributes
section (see https://www.cs.cmu.edu/~quake/triangle.poly.html).  ``#`` starts a
comment; vertices are numbered from 0 or 1, as given by the first vertex; a
vertex count of 0 means the vertices are in the ``.node`` file of the same name.

The segments form the outer ring, the hole rings (those around a hole point)
and interior segments; vertices on no segment are fixed points; the regional
attributes label regions with their attribute numbers.  The faces the segments
enclose are found with :func:`shapely.polygonize`; those holding a hole point
are holes (Triangle eats them), the rest make the domain, whose boundary gives
the rings.  The other segments are chained into polylines through the vertices
where exactly two of them meet and nothing else does; vertices outside the
domain are dropped with a warning, as Triangle drops them.

A file of closed rings only, every inner ring around a hole point and no
regional attributes, is read ring by ring, with messages that name the rings
(a ring without a hole point would bound an interior region in Triangle).
"""

from __future__ import annotations

import logging
from collections import Counter
from pathlib import Path

import numpy as np
import shapely

from ..errors import FileFormatError
from ..polygon import Polygon
from .common import fail, make_polygon, num, read_text
from .fileformat import FileFormat

__all__ = ["read_poly", "write_poly", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    "Triangle .poly: vertices, segments (rings and interior), hole points, regional attributes"
)


# -- the sections of a file ------------------------------------------------------------
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
            fail(self.path, f"the file ends before {what}")
        n, tokens = self.lines[self.i]
        self.i += 1
        return n, tokens

    def number(self, n: int, tokens, k: int, what: str, kind=float):
        if k >= len(tokens):
            fail(self.path, f"line {n}: missing {what}")
        try:
            if kind is int:
                value = float(tokens[k])
                if not value.is_integer():
                    raise ValueError
                return int(value)
            return float(tokens[k])
        except ValueError:
            fail(self.path, f"line {n}: unreadable {what} {tokens[k]!r}")

    def count(self, n: int, tokens, what: str, of: str) -> int:
        """The non-negative count ``what`` (of ``of``) that starts line ``n``."""
        value = self.number(n, tokens, 0, what, int)
        if value < 0:
            fail(self.path, f"line {n}: negative {what} {value}; a count cannot be negative: "
                            f"give 0 or the number of {of} that follow")
        return value


def _read_vertices(lines: _PolyLines, count_line=None):
    """Read a vertex section (header + lines); return (xy array, base, numbers)."""
    n, tokens = count_line if count_line else lines.next("the vertex count")
    nv = lines.count(n, tokens, "vertex count", "vertex lines")
    dim = lines.number(n, tokens, 1, "dimension", int) if len(tokens) > 1 else 2
    if dim != 2:
        fail(lines.path, f"line {n}: dimension is {dim}; a .poly polygon must be 2-D")
    left = len(lines.lines) - lines.i
    if nv > left:  # before allocating: a corrupt count must not look like a memory problem
        fail(lines.path, f"line {n}: the header counts {nv} vertices, but only {left} lines follow")
    xy = np.empty((nv, 2), dtype=np.float64)
    base = 0
    for k in range(nv):
        n, tokens = lines.next(f"vertex {k + 1} of {nv}")
        vid = lines.number(n, tokens, 0, "vertex number", int)
        if k == 0:
            base = vid
            if base not in (0, 1):
                fail(
                    lines.path, f"line {n}: the first vertex is numbered {vid}; number from 0 or 1"
                )
        elif vid != base + k:
            fail(
                lines.path,
                f"line {n}: vertex number {vid}, expected {base + k} "
                "(vertices must be numbered consecutively)",
            )
        xy[k, 0] = lines.number(n, tokens, 1, "x coordinate")
        xy[k, 1] = lines.number(n, tokens, 2, "y coordinate")
    return xy, base


def _poly_sections(path):
    """(lines, vertices, base, segments, hole points) of a .poly file, ``lines``
    left at the regional attributes section."""
    lines = _PolyLines(path, read_text(path))
    n, tokens = lines.next("the vertex count")
    nv = lines.count(n, tokens, "vertex count", "vertex lines")
    if nv == 0:
        node = path.with_suffix(".node")
        if not node.is_file():
            fail(path, f"has 0 vertices, so they must be in '{node}', which does not exist")
        xy, base = _read_vertices(_PolyLines(node, read_text(node)))
    else:
        xy, base = _read_vertices(lines, (n, tokens))
    nv = len(xy)

    n, tokens = lines.next("the segment count")
    ns = lines.count(n, tokens, "segment count", "segment lines")
    segments = []
    for k in range(ns):
        n, tokens = lines.next(f"segment {k + 1} of {ns}")
        sid = lines.number(n, tokens, 0, "segment number", int)
        ends = []
        for j in (1, 2):
            v = lines.number(n, tokens, j, "segment endpoint", int)
            if not base <= v < base + nv:
                fail(
                    path,
                    f"line {n}: segment {sid} refers to vertex {v}, but vertices are "
                    f"numbered {base}..{base + nv - 1}",
                )
            ends.append(v - base)
        segments.append((sid, ends[0], ends[1]))
    if not segments:
        fail(path, "has no segments; the rings of the polygon must be given as segments")

    n, tokens = lines.next("the hole count", optional=True)
    holes_xy = []
    if n is not None:
        nh = lines.count(n, tokens, "hole count", "hole points")
        for k in range(nh):
            n, tokens = lines.next(f"hole point {k + 1} of {nh}")
            hid = lines.number(n, tokens, 0, "hole number", int)
            holes_xy.append(
                (hid, lines.number(n, tokens, 1, "hole x"), lines.number(n, tokens, 2, "hole y"))
            )
    return lines, xy, base, segments, holes_xy


def _poly_attributes(path, lines) -> list:
    """The regional attributes section: [(x, y, attribute), ...]."""
    n, tokens = lines.next("", optional=True)
    if n is None:
        return []
    count = lines.count(n, tokens, "regional attribute count", "regional attribute lines")
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


# -- a file of rings only ---------------------------------------------------------------
def _check_segments(path, segments, base: int) -> None:
    """No segment joins a vertex to itself, no two join the same vertices."""
    seen = {}
    for sid, a, b in segments:
        if a == b:
            fail(path, f"segment {sid} joins vertex {a + base} to itself")
        key = (min(a, b), max(a, b))
        if key in seen:
            fail(
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
            fail(
                path,
                f"segment {nbrs[0][1]} ends at vertex {v + base}, where no other segment "
                "continues (a dangling segment); segments must form closed rings",
            )
        if len(nbrs) > 2:
            fail(
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


def _rings_only(path, xy, base, segments, holes_xy) -> bool:
    """Whether the file is in the rings-and-holes subset of the older reader."""
    deg = Counter()
    for _, a, b in segments:
        deg[a] += 1
        deg[b] += 1
    if len(deg) != len(xy) or any(d != 2 for d in deg.values()) or any(a == b for _, a, b in segments):
        return False
    try:
        rings = _walk_rings(path, len(xy), segments, base)
    except FileFormatError:
        return True  # let the older reader say what is wrong
    shapes = [shapely.Polygon(xy[r]) for r in rings]
    outer = int(np.argmax([s.area for s in shapes]))
    pts = [shapely.Point(hx, hy) for _, hx, hy in holes_xy]
    return all(any(s.contains(p) for p in pts) for k, s in enumerate(shapes) if k != outer)


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
    polygon = make_polygon(path, xy[rings[outer_i]], [xy[rings[i]] for i in order[1:]], labels)

    hole_shapes = [shapely.Polygon(h) for h in polygon.holes]
    has_point = [False] * len(hole_shapes)
    for hid, hx, hy in holes_xy:
        pt = shapely.Point(hx, hy)
        inside = [k for k, h in enumerate(hole_shapes) if h.contains(pt)]
        if not inside:
            fail(
                path,
                f"hole point {hid} ({hx:.17g}, {hy:.17g}) is not inside any hole ring; "
                "move it into the hole it marks, or remove it",
            )
        has_point[inside[0]] = True
    for k, ok in enumerate(has_point):
        if not ok:
            fail(
                path,
                f"{labels[k + 1]} lies inside the outer ring but has no hole point; in "
                "Triangle it would bound an interior region, which uniform2d does not "
                "support: add a hole point inside it to make it a hole",
            )
    return polygon


# -- a file with interior segments, fixed points and labels -------------------------
def _domain(path, xy, edges, holes_xy):
    """The shapely Polygon the segments enclose, less the faces around hole points."""
    faces = list(shapely.polygonize(shapely.linestrings(xy[edges])).geoms)
    if not faces:
        fail(path, "the segments enclose no area; the outline must be a closed chain of segments")
    is_hole = [False] * len(faces)
    for hid, hx, hy in holes_xy:
        hit = [k for k, f in enumerate(faces) if f.contains(shapely.Point(hx, hy))]
        if not hit:
            fail(path, f"hole point {hid} ({hx:.17g}, {hy:.17g}) is not inside any area the "
                        "segments enclose; move it into the hole it marks, or remove it")
        is_hole[hit[0]] = True
    kept = [f for f, h in zip(faces, is_hole) if not h]
    if not kept:
        fail(path, "every area the segments enclose holds a hole point; nothing is left to mesh")
    domain = shapely.union_all(kept)
    if domain.geom_type != "Polygon":
        fail(path, f"the segments enclose {len(domain.geoms)} separate areas; uniform2d meshes "
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
            chain, cur = [start], nxt
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
                cur = nxt
            out.append(chain)
    return out


def read_poly(path) -> Polygon:
    """Read a Triangle .poly file: rings, holes, interior segments, free vertices
    (fixed points) and regional attributes (labels)."""
    path = Path(path)
    lines, xy, base, segments, holes_xy = _poly_sections(path)
    seeds = _poly_attributes(path, lines)
    if not seeds and _rings_only(path, xy, base, segments, holes_xy):
        return _poly_ring_polygon(path, xy, base, segments, holes_xy)
    _check_segments(path, segments, base)
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
    return make_polygon(path, outer, holes, segments=chains,
                             points=xy[fixed].reshape(-1, 2), regions=seeds)


def _write_rings(path, polygon: Polygon) -> None:
    """Write a Triangle .poly file (vertices numbered from 1, one hole point per hole)."""
    out = [
        f"# uniform2d polygon: outer ring and {polygon.n_holes} hole(s), Triangle .poly format",
        f"{len(polygon.vertices)} 2 0 0",
    ]
    out += [f"{k + 1} {num(x)} {num(y)}" for k, (x, y) in enumerate(polygon.vertices)]
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
        out.append(f"{k + 1} {num(p.x)} {num(p.y)}")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


def write_poly(path, polygon: Polygon) -> None:
    """Write a Triangle .poly file: every vertex, the ring edges and segment pieces
    as segments, a hole point per hole and the numeric region labels as regional
    attributes (text labels are dropped with a warning)."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _write_rings(path, polygon)
    V = polygon.vertices
    out = [f"# uniform2d polygon: {polygon.n_holes} hole(s), {len(polygon.segments)} segment(s), "
           f"{len(polygon.points)} fixed point(s); Triangle .poly format",
           f"{len(V)} 2 0 0"]
    out += [f"{k + 1} {num(x)} {num(y)}" for k, (x, y) in enumerate(V)]
    edges = polygon.constraint_edges
    out.append(f"{len(edges)} 0")
    out += [f"{k + 1} {i + 1} {j + 1}" for k, (i, j) in enumerate(edges.tolist())]
    out.append(f"{polygon.n_holes}")
    for k, h in enumerate(polygon.holes):
        p = shapely.Polygon(h).point_on_surface()
        out.append(f"{k + 1} {num(p.x)} {num(p.y)}")
    numeric = [(x, y, lab) for x, y, lab in polygon.region_seeds if not isinstance(lab, str)]
    if len(numeric) < len(polygon.region_seeds):
        logger.warning("%s: .poly regional attributes are numbers; dropping %d text labels",
                       path, len(polygon.region_seeds) - len(numeric))
    out.append(f"{len(numeric)}")
    out += [f"{k + 1} {num(x)} {num(y)} {lab!r} 0" for k, (x, y, lab) in enumerate(numeric)]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


#: This module's entry in :data:`uniform2d.io.registry.POLYGON_FORMATS`.
FORMAT = FileFormat(".poly", DESCRIPTION, read_poly, write_poly)
