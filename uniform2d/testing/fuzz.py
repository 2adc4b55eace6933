"""Random domains for fuzzing: the shapes that break meshers, at every scale.

``domain(seed)`` draws one of the kinds below, then a scale 10**U(-6, 6) and, half
of the time, an offset up to 1e7 in each coordinate.  A case is fully described by
its seed (no global random state).  Unlike :mod:`uniform2d.testing.polygons` the shapes are not kept
"reasonable": they aim at floating-point extremes.

``star_short``   a star-shaped ring whose vertex angles cluster, so some edges are
                 1e-3 of the others;
``collinear``    a convex or rectilinear ring with extra vertices exactly on its
                 edges (axis-parallel ones, so exactly collinear) and, on rotated
                 edges, rounded onto them (collinear within an ulp);
``spike``        a star with one sharp spike (apex angle down to ~0.1 degree);
``rectilinear``  a random orthogonal outline (a union of grid cells), rotated;
``holes``        a convex, star or rectilinear outer ring with 1-4 holes;
``sliver``       a 1:100 rectangle, parallelogram or triangle, rotated.

Some draws are invalid polygons (a spike through an edge, ...); the callers
count those as refused when :class:`uniform2d.Polygon` rejects them.

``constrained(seed)`` draws a domain with interior constraints (a convex or
rectilinear outline, sometimes with a hole) of one of the kinds below, placed the
same way:

``c_points``     fixed points inside, on ring edges and at a relative distance
                 1e-9..1e-3 from the boundary;
``c_free``       free segments (stiffeners, 2-4 vertices) with fixed points on them;
``c_tjunction``  segments from ring vertex to ring vertex or to a point of an
                 axis-parallel edge (T-junctions), and one ending on another;
``c_closed``     closed segments (zones), one sharing a vertex with an open one;
``c_near``       near-degenerate: a segment ending just short of a ring edge or
                 another segment, two meeting at a tiny angle, a fixed point just off
                 a segment, a segment nearly parallel to an edge close to it.

Placing rounds: an exact junction may end a hair off its edge, so some draws cross
(refused with an :class:`~uniform2d.InvalidConstraintError`) and others become
near misses -- both wanted.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..polygon import Polygon
from .polygons import convex_ring, star_ring, with_holes

__all__ = ["KINDS", "CONSTRAINED_KINDS", "domain", "rings", "constrained", "constrained_domain"]

KINDS = ("star_short", "collinear", "spike", "rectilinear", "holes", "sliver")
CONSTRAINED_KINDS = ("c_points", "c_free", "c_tjunction", "c_closed", "c_near")


def _rotate(ring, th):
    c, s = np.cos(th), np.sin(th)
    return ring @ np.array([[c, -s], [s, c]]).T


def _star_short(rng):
    k = int(rng.integers(6, 21))
    ang = np.sort(rng.uniform(0, 2 * np.pi, k))
    j = int(rng.integers(0, k - 1))
    ang[j + 1] = ang[j] + 10.0 ** rng.uniform(-4, -2)  # a short edge
    rad = rng.uniform(0.3, 1.0, k)
    return np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1), []


def _rectilinear_ring(rng, cells=None):
    g = int(rng.integers(3, 8))
    grid = rng.uniform(size=(g, g)) < 0.6
    grid[g // 2, :] = True
    geom = shapely.union_all([shapely.box(i, j, i + 1, j + 1) for i, j in zip(*np.nonzero(grid))])
    if geom.geom_type != "Polygon":
        geom = max(shapely.get_parts(geom), key=lambda q: q.area)
    ring = np.asarray(geom.exterior.coords)[:-1]
    ring = shapely.simplify(shapely.Polygon(ring), 0.0)  # drop collinear grid vertices
    return np.asarray(ring.exterior.coords)[:-1] / g - 0.5


def _collinear(rng):
    if rng.uniform() < 0.5:
        ring = _rectilinear_ring(rng)
    else:
        ring = convex_ring(rng, int(rng.integers(3, 9)))
    out = []
    for a, b in zip(ring, np.roll(ring, -1, axis=0)):
        out.append(a)
        for t in np.sort(rng.choice([0.25, 0.5, 0.75], int(rng.integers(0, 3)), replace=False)):
            out.append(a + t * (b - a))  # exact on axis-parallel edges, within an ulp otherwise
    ring = np.array(out)
    if rng.uniform() < 0.5:
        ring = _rotate(ring, rng.uniform(0, 2 * np.pi))
    return ring, []


def _spike(rng):
    ring = star_ring(rng, int(rng.integers(6, 13)))
    i = int(rng.integers(len(ring)))
    ang = np.arctan2(ring[i, 1], ring[i, 0])
    half = 10.0 ** rng.uniform(-3, -1.5)  # half the apex angle, roughly
    r = rng.uniform(1.5, 3.0)
    tip = r * np.array([np.cos(ang), np.sin(ang)])
    base = 0.3 * np.array([np.cos(ang), np.sin(ang)])
    side = np.array([-np.sin(ang), np.cos(ang)]) * (r - 0.3) * half
    ring = np.concatenate([ring[:i], [base - side, tip, base + side], ring[i + 1 :]])
    return ring, []


def _rectilinear(rng):
    return _rotate(_rectilinear_ring(rng), rng.uniform(0, 2 * np.pi)), []


def _holes(rng):
    nh = int(rng.integers(1, 5))
    if rng.uniform() < 0.6:
        p = with_holes(rng, nh, margin=rng.choice([0.06, 0.01]))
        return p.outer, list(p.holes)
    outer = _rectilinear_ring(rng)
    shell = shapely.Polygon(outer)
    inner = shell.buffer(-0.03, join_style="mitre")
    holes = []
    for _ in range(200):
        if len(holes) == nh or inner.is_empty:
            break
        c = rng.uniform(-0.5, 0.5, 2)
        h = _rotate(np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * rng.uniform(0.01, 0.06), rng.uniform(0, 1)) + c
        hp = shapely.Polygon(h)
        if inner.contains(hp) and all(hp.distance(shapely.Polygon(o)) > 0.01 for o in holes):
            holes.append(h)
    th = rng.uniform(0, 2 * np.pi)
    return _rotate(outer, th), [_rotate(h, th) for h in holes]


def _sliver(rng):
    a = 10.0 ** rng.uniform(-2.3, -1.7)  # 1:100 or so
    kind = int(rng.integers(3))
    if kind == 0:
        ring = np.array([[0, 0], [1, 0], [1, a], [0, a]])
    elif kind == 1:
        ring = np.array([[0, 0], [1, 0], [1.3, a], [0.3, a]])
    else:
        ring = np.array([[0, 0], [1, 0], [rng.uniform(0, 1), a]])
    return _rotate(ring - ring.mean(axis=0), rng.uniform(0, 2 * np.pi)), []


_MAKE = dict(zip(KINDS, (_star_short, _collinear, _spike, _rectilinear, _holes, _sliver)))


def rings(seed, kind: str | None = None):
    """(kind, outer (k, 2), [holes]) of domain ``seed``, placed at its scale and
    offset: plain arrays, so an invalid draw can still be reported."""
    rng = np.random.default_rng(seed)
    kind = KINDS[int(rng.integers(len(KINDS)))] if kind is None else kind
    outer, holes = _MAKE[kind](rng)
    scale = 10.0 ** rng.uniform(-6, 6)
    off = np.zeros(2)
    if rng.uniform() < 0.5:
        off = rng.choice([-1.0, 1.0], 2) * 10.0 ** rng.uniform(0, 7, 2)
    place = lambda r: np.asarray(r, dtype=np.float64) * scale + off  # noqa: E731
    return kind, place(outer), [place(h) for h in holes]


def domain(seed, kind: str | None = None):
    """(kind, Polygon) of domain ``seed``; raises InvalidPolygonError for an invalid draw."""
    kind, outer, holes = rings(seed, kind)
    return kind, Polygon(outer, holes)


# -- constrained domains ------------------------------------------------------------
def _base(rng):
    """An outline (convex or rectilinear, about unit size) and maybe a small hole."""
    if rng.uniform() < 0.5:
        outer = convex_ring(rng, int(rng.integers(4, 10)))
    else:
        outer = _rectilinear_ring(rng) * 2.0
    holes = []
    if rng.uniform() < 0.3:
        c = rng.uniform(-0.15, 0.15, 2)
        hole = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * 0.06 + c
        if shapely.Polygon(outer).buffer(-0.01).contains(shapely.Polygon(hole)):
            holes.append(hole)
    return outer, holes


def _inward(shape, a, b):
    """The unit normal of edge a-b pointing into ``shape``."""
    normal = np.array([a[1] - b[1], b[0] - a[0]]) / np.hypot(*(b - a))
    mid = a + 0.5 * (b - a)
    step = 1e-3 * np.hypot(*(b - a))
    return normal if shape.contains(shapely.Point(mid + normal * step)) else -normal


def _inside(rng, shape, k, margin=0.02):
    """k random points of ``shape`` (shapely) at least ``margin`` from its boundary."""
    inner = shape.buffer(-margin)
    x0, y0, x1, y1 = shape.bounds
    out = []
    for _ in range(200 * k):
        if len(out) == k or inner.is_empty:
            break
        p = rng.uniform([x0, y0], [x1, y1])
        if inner.contains(shapely.Point(p)):
            out.append(p)
    return out


def _c_points(rng, outer, holes, shape):
    pts = _inside(rng, shape, int(rng.integers(1, 8)))
    i = int(rng.integers(len(outer)))
    a, b = outer[i], outer[(i + 1) % len(outer)]
    pts.append(a + 0.5 * (b - a))  # on a ring edge (exactly where the edge is axis-parallel)
    mid = a + 0.37 * (b - a)
    pts.append(mid + _inward(shape, a, b) * 10.0 ** rng.uniform(-9, -3))  # a hair off the edge
    return [], pts


def _c_free(rng, outer, holes, shape):
    segs, pts = [], []
    for _ in range(20):
        if len(segs) == 3:
            break
        line = _inside(rng, shape, int(rng.integers(2, 5)), margin=0.05)
        ls = shapely.LineString(line) if len(line) >= 2 else None
        if ls is None or not ls.is_simple or not shape.contains(ls):
            continue
        if any(ls.intersects(shapely.LineString(s)) for s in segs):
            continue
        segs.append(np.array(line))
        pts.append(line[0] + 0.5 * (line[1] - line[0]))  # on it (or a hair off)
    return segs, pts


def _c_tjunction(rng, outer, holes, shape):
    # a convex outline, so that every chord and every segment between two points
    # of one side of a chord stays inside and crosses nothing
    outer = convex_ring(rng, int(rng.integers(5, 10)))
    k = len(outer)
    i = int(rng.integers(k))
    j = (i + int(rng.integers(3, k - 1))) % k
    chord = np.array([outer[i], outer[j]])
    a, b = outer[(i + 1) % k], outer[(i + 2) % k]
    # a vertex, or a point of an edge (on it only to rounding, unless axis-parallel)
    m = a if rng.uniform() < 0.5 else a + 0.5 * (b - a)
    q = chord[0] + 0.5 * (chord[1] - chord[0])              # a point of the chord
    if rng.uniform() < 0.5:  # a vertex of it: the junction exact wherever it rounds to
        chord = np.array([chord[0], q, chord[1]])
    return outer, [chord, np.array([m, q])], []


def _c_closed(rng, outer, holes, shape):
    segs = []
    for c in _inside(rng, shape, int(rng.integers(1, 3)), margin=0.15):
        r = rng.uniform(0.02, 0.1)
        ring = convex_ring(rng, int(rng.integers(3, 7))) * r + c
        segs.append(np.vstack([ring, ring[:1]]))
    if segs:
        segs.append(np.array([segs[0][0], segs[0][0] + rng.uniform(-0.05, 0.05, 2)]))
    return segs, []


def _c_near(rng, outer, holes, shape):
    segs, pts = [], []
    tiny = 10.0 ** rng.uniform(-12, -6)
    i = int(rng.integers(len(outer)))
    a, b = outer[i], outer[(i + 1) % len(outer)]
    normal = _inward(shape, a, b)
    foot = a + 0.5 * (b - a)
    segs.append(np.array([foot + normal * tiny, foot + normal * 0.2]))       # just short of an edge
    segs.append(np.array([a + 0.2 * (b - a) + normal * tiny * 3,             # nearly along it
                          a + 0.4 * (b - a) + normal * tiny * 5]))
    tip = foot + normal * 0.2
    d = normal * 0.1
    ang = 10.0 ** rng.uniform(-7, -3)
    rot = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
    segs.append(np.array([tip, tip + d + rot @ d]))                          # a tiny angle
    segs.append(np.array([tip, tip + 2 * d]))
    pts.append(foot + normal * 0.1 + np.array([normal[1], -normal[0]]) * tiny)  # just off one
    return segs, pts


_MAKE_C = dict(zip(CONSTRAINED_KINDS, (_c_points, _c_free, _c_tjunction, _c_closed, _c_near)))


def constrained(seed, kind: str | None = None):
    """(kind, outer, [holes], [segments], points (K, 2)) of constrained domain
    ``seed``, placed at its scale and offset: plain arrays."""
    rng = np.random.default_rng([seed, 5])
    kind = CONSTRAINED_KINDS[int(rng.integers(len(CONSTRAINED_KINDS)))] if kind is None else kind
    outer, holes = _base(rng)
    shape = shapely.Polygon(outer, holes)
    made = _MAKE_C[kind](rng, np.asarray(outer), holes, shape)
    if len(made) == 3:  # the kind chose its own outline
        outer, segs, pts = made
        holes = []
    else:
        segs, pts = made
    scale = 10.0 ** rng.uniform(-6, 6)
    off = np.zeros(2)
    if rng.uniform() < 0.5:
        off = rng.choice([-1.0, 1.0], 2) * 10.0 ** rng.uniform(0, 7, 2)
    place = lambda r: np.asarray(r, dtype=np.float64).reshape(-1, 2) * scale + off  # noqa: E731
    return kind, place(outer), [place(h) for h in holes], [place(s) for s in segs], place(pts)


def constrained_domain(seed, kind: str | None = None):
    """(kind, Polygon) of constrained domain ``seed``; raises InvalidPolygonError
    (an InvalidConstraintError for the constraints) for an invalid draw."""
    kind, outer, holes, segs, pts = constrained(seed, kind)
    return kind, Polygon(outer, holes, segments=segs, points=pts)
