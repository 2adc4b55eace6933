"""Dense sampling check of Algorithm INSERT: no sample point of the polygon may be
farther from its nearest visible site than the weight the algorithm reports.

At step j the algorithm claims that p_j maximises w_{j-1} (the distance to the
nearest visible site) over the whole polygon.  This module checks that claim
against a grid of ~m interior points plus fine samples along every boundary edge:
``max over samples of w_{j-1} <= weight_j (1 + 1e-9)``, and that the reported
weight is the true visible distance of p_j.  It is an *independent* witness for
both the fast kernel and the brute-force reference: visibility here is decided by
shapely (``covers`` of the segment by the polygon grown by a tiny tolerance), not
by the reference's own segment-splitting test, and nothing of ``uniform2d`` but
``Polygon`` is used.

Vectorised: the nearest site of every sample comes from a KD-tree and only that
pair's visibility is checked; samples whose nearest site is hidden fall back to
the next nearest ones, and only then to a per-sample loop.  Along a run the field
is updated incrementally (adding a site can only lower w, and only where the new
site is closer than the current value).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from uniform2d import Polygon

__all__ = [
    "dense_samples",
    "visible_distances",
    "max_visible_distance",
    "VisibleDistanceField",
    "check_sequence",
]

VIS_TOL = 1e-11  # segment may stray this far (relative to polygon size) outside P


class _Vis:
    """Segment-in-closed-polygon test by shapely, with a tiny outward tolerance."""

    def __init__(self, polygon: Polygon):
        self.polygon = polygon
        x0, y0, x1, y1 = polygon.bounds
        self.size = max(x1 - x0, y1 - y0)
        shp = polygon.to_shapely()
        tol = max(VIS_TOL * self.size, 1e-14 * float(np.abs(polygon.vertices).max()))
        self.grown = shp.buffer(tol, quad_segs=2)
        shapely.prepare(self.grown)
        self.convex = polygon.n_holes == 0 and bool(
            (polygon.interior_angles() <= np.pi + 1e-12).all()
        )

    def __call__(self, P: np.ndarray, Q: np.ndarray) -> np.ndarray:
        P = np.atleast_2d(P)
        Q = np.atleast_2d(Q)
        if self.convex or len(P) == 0:
            return np.ones(len(P), dtype=bool)
        same = np.all(P == Q, axis=1)
        out = np.ones(len(P), dtype=bool)
        idx = np.flatnonzero(~same)
        if idx.size:
            lines = shapely.linestrings(np.stack([P[idx], Q[idx]], axis=1))
            out[idx] = shapely.covers(self.grown, lines)
        return out


def dense_samples(polygon: Polygon, m: int = 2000) -> np.ndarray:
    """~m grid points strictly inside the polygon plus fine samples on every edge
    (spacing a quarter of the grid spacing, vertices excluded)."""
    h = float(np.sqrt(polygon.area / m))
    x0, y0, x1, y1 = polygon.bounds
    xs = np.arange(x0 + 0.5 * h, x1, h)
    ys = np.arange(y0 + 0.5 * h, y1, h)
    gx, gy = np.meshgrid(xs, ys)
    gx, gy = gx.ravel(), gy.ravel()
    shp = polygon.to_shapely()
    shapely.prepare(shp)
    inside = shapely.contains_xy(shp, gx, gy)
    grid = np.stack([gx[inside], gy[inside]], axis=1)
    V = polygon.vertices
    edges = polygon.edges
    bnd = []
    for i, j in edges:
        a, b = V[i], V[j]
        k = max(8, int(np.ceil(np.hypot(*(b - a)) / (0.25 * h))))
        t = (np.arange(k) + 0.5) / k
        bnd.append(a + t[:, None] * (b - a))
    return np.concatenate([grid, *bnd])


def visible_distances(polygon: Polygon, sites, samples, *, _vis: _Vis | None = None):
    """Distance from every sample to its nearest visible site (and that site's index)."""
    vis = _vis or _Vis(polygon)
    S = np.asarray(sites, dtype=np.float64).reshape(-1, 2)
    X = np.asarray(samples, dtype=np.float64).reshape(-1, 2)
    tree = cKDTree(S)
    k = min(6, len(S))
    d, idx = tree.query(X, k=k)
    d = d.reshape(len(X), k)
    idx = idx.reshape(len(X), k)
    res = np.full(len(X), np.inf)
    arg = np.full(len(X), -1, dtype=np.int64)
    todo = np.arange(len(X))
    for col in range(k):
        if todo.size == 0:
            break
        ok = vis(X[todo], S[idx[todo, col]])
        res[todo[ok]] = d[todo[ok], col]
        arg[todo[ok]] = idx[todo[ok], col]
        todo = todo[~ok]
    for r in todo:  # slow path: all k nearest sites hidden
        dist = np.hypot(*(S - X[r]).T)
        order = np.argsort(dist, kind="stable")
        ok = vis(np.repeat(X[r : r + 1], len(S), axis=0), S[order])
        first = np.flatnonzero(ok)
        if first.size:
            res[r] = dist[order[first[0]]]
            arg[r] = order[first[0]]
    return res, arg


def max_visible_distance(polygon: Polygon, sites, samples) -> float:
    """max over samples of the distance to the nearest visible site."""
    return float(visible_distances(polygon, sites, samples)[0].max())


class VisibleDistanceField:
    """w(sample) for a growing set of sites, updated incrementally."""

    def __init__(self, polygon: Polygon, samples, sites):
        self.vis = _Vis(polygon)
        self.samples = np.asarray(samples, dtype=np.float64)
        self.sites = [np.asarray(s, dtype=np.float64) for s in np.asarray(sites).reshape(-1, 2)]
        self.w, _ = visible_distances(polygon, sites, self.samples, _vis=self.vis)

    def add(self, p) -> None:
        p = np.asarray(p, dtype=np.float64)
        d = np.hypot(*(self.samples - p).T)
        cand = np.flatnonzero(d < self.w)
        if cand.size:
            ok = self.vis(self.samples[cand], np.repeat(p[None], cand.size, axis=0))
            self.w[cand[ok]] = d[cand[ok]]
        self.sites.append(p)

    def max(self):
        """(largest w over the samples, the sample attaining it)."""
        k = int(np.argmax(self.w))
        return float(self.w[k]), self.samples[k]

    def distance_of(self, p) -> float:
        """Visible distance of an arbitrary point p to the current sites."""
        d, _ = visible_distances(self.vis.polygon, np.array(self.sites), p, _vis=self.vis)
        return float(d[0])


def check_sequence(polygon: Polygon, points, weights, sites=None, *, m: int = 2000, rel=1e-9):
    """Check a run of INSERT step by step.  Returns a list of problems (empty = pass):
    a sample beating the reported weight, or a reported weight that is not the
    visible distance of its point."""
    points = np.asarray(points, dtype=np.float64)
    weights = np.asarray(weights, dtype=np.float64)
    init = polygon.vertices
    if sites is not None and len(np.asarray(sites)):
        init = np.concatenate([init, np.asarray(sites, dtype=np.float64).reshape(-1, 2)])
    field = VisibleDistanceField(polygon, dense_samples(polygon, m), init)
    problems = []
    for j, (p, w) in enumerate(zip(points, weights)):
        mx, where = field.max()
        if mx > w * (1.0 + rel):
            problems.append(
                f"step {j}: sample {where.tolist()} has visible distance {mx:.17g} "
                f"> reported weight {w:.17g} (ratio {mx / w:.12g})"
            )
        true = field.distance_of(p)
        if abs(true - w) > rel * max(true, w):
            problems.append(
                f"step {j}: point {p.tolist()} has visible distance {true:.17g}, "
                f"reported {w:.17g}"
            )
        field.add(p)
    return problems
