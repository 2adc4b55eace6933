"""Random domains for fuzzing: the shapes that break meshers, at every scale.

``domain(seed)`` draws one of the kinds below, then a scale 10**U(-6, 6) and, half
of the time, an offset up to 1e7 in each coordinate.  A case is fully described by
its seed (no global random state).  Unlike :mod:`polygen` the shapes are not kept
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
"""

from __future__ import annotations

import numpy as np
import shapely

from polygen import _convex_ring, _star_ring, with_holes

__all__ = ["KINDS", "domain", "rings"]

KINDS = ("star_short", "collinear", "spike", "rectilinear", "holes", "sliver")


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
        ring = _convex_ring(rng, int(rng.integers(3, 9)))
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
    ring = _star_ring(rng, int(rng.integers(6, 13)))
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
    from uniform2d import Polygon

    kind, outer, holes = rings(seed, kind)
    return kind, Polygon(outer, holes)
