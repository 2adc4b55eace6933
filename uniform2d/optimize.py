"""Beyond the paper: the most uniform mesh uniform2d can make with exactly n Steiner points.

Pipeline (:func:`optimize_mesh`):

1. **Target size.**  h solves "an equilateral mesh of side h has |V| + n vertices"
   (the count of :func:`uniform2d.uniform.steiner_count_for_size`, inverted).
2. **Boundary.**  Every polygon edge of length L gets m = max(1, round(L/h)) equal
   pieces (all rings); k = Σ(m − 1) boundary Steiner points, evenly spaced.
   If k would exceed n the counts are reduced on the longest pieces first.
3. **Interior seed.**  n − k points of a hexagonal lattice, aligned with the
   longest polygon edge, spacing bisected so the lattice points at least a
   margin inside P number n − k (the last few are removed near the boundary /
   added in the largest triangles, deterministically).
4. **Relaxation.**  Spring smoothing (linear springs of rest length ℓ0 on the
   edges of the constrained Delaunay triangulation of the current points,
   rebuilt every step), polygon vertices and boundary points fixed, interior
   points that would leave P stay where they were.
5. **Objective pass.**  Gradient descent on a p-norm of the chosen objective
   (edge lengths for "max_edge", longest and shortest for "ratio", triangle
   perimeters for "max_perimeter", all three for "balanced"), boundary points
   sliding along their edges in order; the best iterate by the true objective
   is kept.
6. **Certification.**  The exact constrained Delaunay triangulation of P with the
   final points (:func:`uniform2d.insert`); its quality is compared with the
   starting T+ on the objective, and the better mesh is returned.

Every triangulation (steps 3–6) is the exact constrained Delaunay triangulation
of the current points, from :func:`uniform2d.insert` with the points as sites
(Hilbert-ordered bulk insertion: faster than ``scipy.spatial.Delaunay`` here, and
it respects holes and concave corners exactly).
"""

from __future__ import annotations

import logging
import math
import numbers

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .errors import InsufficientPointsError
from .insert import insert
from .mesh import Mesh
from .polygon import Polygon

__all__ = ["optimize_mesh", "OBJECTIVES", "objective_value"]

log = logging.getLogger(__name__)

OBJECTIVES = ("balanced", "ratio", "max_edge", "max_perimeter")


# ----------------------------------------------------------------------------- sizes
def target_size(polygon: Polygon, n: int) -> float:
    """Side h of an equilateral mesh of P with |V| + n vertices (inverse of steiner_count_for_size)."""
    A, B, H = polygon.area, polygon.perimeter, polygon.n_holes
    N = n + len(polygon.vertices)
    a = 4.0 * A / math.sqrt(3.0)
    c = 2.0 * N - 2.0 + 2.0 * H
    x = (-B + math.sqrt(B * B + 4.0 * a * c)) / (2.0 * a)  # x = 1/h
    return 1.0 / x


def _edge_geometry(polygon: Polygon):
    V = polygon.vertices
    E = polygon.edges
    a = V[E[:, 0]]
    d = V[E[:, 1]] - a
    L = np.hypot(d[:, 0], d[:, 1])
    return a, d, L


def _boundary_counts(L: np.ndarray, h: float, n: int) -> np.ndarray:
    """Pieces per polygon edge: round(L/h), at least 1, at most n extra points in total."""
    m = np.maximum(1, np.rint(L / h)).astype(np.int64)
    while (m - 1).sum() > n:
        e = int(np.argmax(np.where(m > 1, L / m, -1.0)))  # least harmful: merge on longest... shortest piece
        e = int(np.argmin(np.where(m > 1, L / m, np.inf)))
        m[e] -= 1
    return m


def _boundary_points(a, d, m):
    pts, eid, t = [], [], []
    for e in range(len(m)):
        s = np.arange(1, m[e]) / m[e]
        pts.append(a[e] + d[e] * s[:, None])
        eid.append(np.full(len(s), e, dtype=np.int64))
        t.append(s)
    if not pts:
        return np.empty((0, 2)), np.empty(0, np.int64), np.empty(0)
    return np.concatenate(pts), np.concatenate(eid), np.concatenate(t)


# ----------------------------------------------------------------------------- seed
def _hex_lattice(polygon: Polygon, spacing: float, angle: float, origin) -> np.ndarray:
    xmin, ymin, xmax, ymax = polygon.bounds
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    R0 = math.hypot(xmax - xmin, ymax - ymin) / 2 + 2 * spacing
    R = R0 + math.hypot(origin[0] - cx, origin[1] - cy)
    dy = spacing * math.sqrt(3.0) / 2
    nr = int(math.ceil(R / dy)) + 1
    nc = int(math.ceil(R / spacing)) + 2
    j, i = np.meshgrid(np.arange(-nr, nr + 1), np.arange(-nc, nc + 1), indexing="ij")
    u = (i + 0.5 * (j & 1)) * spacing
    v = j * dy
    c, s = math.cos(angle), math.sin(angle)
    # lattice anchored at ``origin`` (a polygon vertex), rotated by ``angle``
    x = origin[0] + c * u - s * v
    y = origin[1] + s * u + c * v
    keep = (np.abs(x - cx) <= R0) & (np.abs(y - cy) <= R0)
    return np.stack([x[keep], y[keep]], axis=1)


def _seed_interior(polygon: Polygon, count: int, h: float, bpts: np.ndarray) -> np.ndarray:
    """``count`` interior points on a hexagonal lattice, deterministic."""
    if count <= 0:
        return np.empty((0, 2))
    a, d, L = _edge_geometry(polygon)
    e = int(np.argmax(L))
    angle = math.atan2(d[e, 1], d[e, 0])
    # anchor a lattice row at distance h·√3/2 inside the longest edge
    nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]  # left normal: inside for the CCW outer ring
    origin = a[e] + nrm * h * math.sqrt(3) / 2 + d[e] / L[e] * (h / 2)
    shp = polygon.to_shapely()
    shapely.prepare(shp)
    bnd = shp.boundary
    shapely.prepare(bnd)

    def cand(sp):
        P = _hex_lattice(polygon, sp, angle, origin)
        inside = shapely.contains_xy(shp, P[:, 0], P[:, 1])
        P = P[inside]
        dist = shapely.distance(bnd, shapely.points(P))
        return P[dist >= 0.5 * sp], dist[dist >= 0.5 * sp]

    lo, hi = 0.5 * h, 1.5 * h  # count(sp) decreases with sp
    best = None
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        P, dist = cand(mid)
        if best is None or abs(len(P) - count) < abs(len(best[0]) - count) or (
            abs(len(P) - count) == abs(len(best[0]) - count) and len(P) >= count
        ):
            best = (P, dist)
        if len(P) == count:
            break
        if len(P) > count:
            lo = mid
        else:
            hi = mid
    P, dist = best
    if len(P) > count:  # drop the points nearest to the boundary
        order = np.lexsort((np.arange(len(P)), dist))
        P = P[np.sort(order[len(P) - count :])]
    while len(P) < count:  # add centroids of the largest triangles
        allp = np.concatenate([polygon.vertices, bpts, P])
        tri = _cdt(polygon, allp)
        q = allp[tri]
        area = 0.5 * np.abs(_cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]))
        need = count - len(P)
        order = np.lexsort((np.arange(len(tri)), -area))[:need]
        P = np.concatenate([P, q[order].mean(axis=1)])
    return P


# ----------------------------------------------------------------------------- triangulation
def _cdt(polygon: Polygon, points: np.ndarray) -> np.ndarray:
    """The exact constrained Delaunay triangulation of ``points`` (the polygon's
    vertices first, then boundary and interior points), CCW, restricted to P."""
    nV = len(polygon.vertices)
    return np.asarray(insert(polygon, 0, sites=points[nV:]).triangles)


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _edges(tri: np.ndarray) -> np.ndarray:
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    e.sort(axis=1)
    n = int(e.max()) + 1 if len(e) else 1
    key = np.unique(e[:, 0] * n + e[:, 1])
    return np.stack([key // n, key % n], axis=1)


def _scatter(idx_pos, idx_neg, vec, n):
    """G[i] = Σ vec over edges with idx_pos == i minus Σ over idx_neg == i (bincount, fast)."""
    G = np.empty((n, 2))
    for c in (0, 1):
        G[:, c] = np.bincount(idx_pos, vec[:, c], minlength=n) - np.bincount(idx_neg, vec[:, c], minlength=n)
    return G


# ----------------------------------------------------------------------------- objectives
def _measures(points, tri, edges=None):
    if edges is None:
        edges = _edges(tri)
    dv = points[edges[:, 1]] - points[edges[:, 0]]
    L = np.hypot(dv[:, 0], dv[:, 1])
    q = points[tri]
    s = (
        np.hypot(*(q[:, 1] - q[:, 0]).T)
        + np.hypot(*(q[:, 2] - q[:, 1]).T)
        + np.hypot(*(q[:, 0] - q[:, 2]).T)
    )
    return L.max(), L.min(), s.max()


def objective_value(objective: str, longest: float, shortest: float, perimeter: float, h: float):
    """Scalar the objective pass minimises (lower is better); h makes it scale-free."""
    if objective == "ratio":
        return longest / shortest
    if objective == "max_edge":
        return longest / h
    if objective == "max_perimeter":
        return perimeter / (3 * h)
    # balanced: geometric mean of the three
    return ((longest / shortest) * (longest / h) * (perimeter / (3 * h))) ** (1.0 / 3.0)


def _quality_objective(objective, q, h):
    return objective_value(objective, q.longest_edge, q.shortest_edge, q.max_perimeter, h)


# ----------------------------------------------------------------------------- relaxation
class _State:
    """Points: polygon vertices (fixed), boundary points (edge id, parameter), interior points."""

    def __init__(self, polygon, bpts, beid, bt, ipts):
        self.polygon = polygon
        self.nV = len(polygon.vertices)
        self.a, self.d, self.L = _edge_geometry(polygon)
        self.beid, self.bt = beid, bt
        self.nb = len(bpts)
        self.points = np.concatenate([polygon.vertices, bpts, ipts]).astype(np.float64)
        self.shp = polygon.to_shapely()
        shapely.prepare(self.shp)
        self.bnd = self.shp.boundary

    @property
    def interior(self):
        return slice(self.nV + self.nb, len(self.points))

    @property
    def bslice(self):
        return slice(self.nV, self.nV + self.nb)

    def triangulate(self):
        return _cdt(self.polygon, self.points)

    def move_interior(self, disp, clearance):
        """Apply ``disp`` to the interior points; a point whose new place is outside P
        or closer than ``clearance`` to the boundary keeps its place."""
        sl = self.interior
        old = self.points[sl]
        new = old + disp
        ok = shapely.contains_xy(self.shp, new[:, 0], new[:, 1])
        if clearance > 0:
            idx = np.flatnonzero(ok)
            near = shapely.distance(self.bnd, shapely.points(new[idx])) < clearance
            ok[idx[near]] = False
        self.points[sl] = np.where(ok[:, None], new, old)

    def slide_boundary(self, g):
        """Move boundary points along their edges by the tangential part of ``g``,
        keeping their order and a minimum relative gap on each edge."""
        if self.nb == 0:
            return
        e = self.beid
        tang = self.d[e] / self.L[e][:, None]
        dt = (g * tang).sum(axis=1) / self.L[e]
        t = self.bt + dt
        # keep order: clip each to the open interval between neighbours (old positions)
        out = np.empty_like(t)
        for edge in np.unique(e):
            idx = np.flatnonzero(e == edge)  # stored in increasing t
            told = self.bt[idx]
            lo = np.concatenate([[0.0], told[:-1]])
            hi = np.concatenate([told[1:], [1.0]])
            gap = 0.25 * np.minimum(np.diff(np.concatenate([[0.0], told])), np.diff(np.concatenate([told, [1.0]])))
            out[idx] = np.clip(t[idx], lo + gap, hi - gap)
            out[idx] = np.clip(out[idx], told - gap, told + gap)
        self.bt = out
        self.points[self.bslice] = self.a[e] + self.d[e] * out[:, None]


def _rebalance_boundary(st: "_State", h: float, hysteresis: float = 0.6) -> int:
    """Move points between the interior and the polygon edges so that each edge's
    gap matches the length of the mesh edges next to it; returns the number of moves."""
    tri = st.triangulate()
    E = _edges(tri)
    p = st.points
    nV, nb = st.nV, st.nb
    L = np.hypot(*(p[E[:, 1]] - p[E[:, 0]]).T)
    isb = np.zeros(len(p), bool)
    isb[: nV + nb] = True
    # polygon edge of each boundary vertex (vertices of P belong to two edges: skip them)
    pe = np.full(len(p), -1, np.int64)
    pe[nV : nV + nb] = st.beid
    inner = ~(isb[E[:, 0]] & isb[E[:, 1]])  # edges touching the interior
    m = np.bincount(st.beid, minlength=len(st.L)) + 1
    new_m = m.copy()
    add_pts = []
    take = []
    ipos = np.arange(nV + nb, len(p))
    for e in range(len(st.L)):
        sel = inner & ((pe[E[:, 0]] == e) | (pe[E[:, 1]] == e))
        if not sel.any():
            continue
        ell = L[sel].mean()
        mstar = st.L[e] / ell
        if mstar - m[e] > hysteresis and len(ipos):
            # nearest interior point to the edge, projecting inside it
            q = p[ipos] - st.a[e]
            t = (q @ st.d[e]) / st.L[e] ** 2
            dist = np.abs(_cross(st.d[e], q)) / st.L[e]
            cand = np.flatnonzero((t > 0.05) & (t < 0.95) & (dist < 1.2 * h))
            cand = [c for c in cand if ipos[c] not in take]
            if cand:
                c = min(cand, key=lambda c: (dist[c], c))
                take.append(int(ipos[c]))
                new_m[e] += 1
        elif m[e] - mstar > hysteresis and m[e] > 1:
            new_m[e] -= 1
            nrm = np.array([-st.d[e, 1], st.d[e, 0]]) / st.L[e]
            mid = st.a[e] + 0.5 * st.d[e]
            for sgn in (1.0, -1.0):
                c = mid + sgn * nrm * 0.6 * h
                if shapely.contains_xy(st.shp, c[0], c[1]):
                    add_pts.append(c)
                    break
            else:
                new_m[e] += 1
    moves = int(np.abs(new_m - m).sum())
    if moves == 0:
        return 0
    keep = np.setdiff1d(ipos, np.array(take, dtype=np.int64))
    ipts = p[keep]
    if add_pts:
        ipts = np.concatenate([ipts, np.array(add_pts)])
    bpts, beid, bt = _boundary_points(st.a, st.d, new_m)
    assert len(bpts) + len(ipts) == nb + len(ipos)
    st.beid, st.bt, st.nb = beid, bt, len(bpts)
    st.points = np.concatenate([st.polygon.vertices, bpts, ipts]).astype(np.float64)
    return moves


def _spring_relax(st: _State, h: float, iters: int, tol: float = 1e-4):
    """Linear springs of rest length h on the constrained Delaunay edges."""
    sl = st.interior
    ni = sl.stop - sl.start
    if ni == 0:
        return 0
    it = 0
    for it in range(1, iters + 1):
        tri = st.triangulate()
        E = _edges(tri)
        p = st.points
        dv = p[E[:, 1]] - p[E[:, 0]]
        L = np.hypot(dv[:, 0], dv[:, 1])
        # rest length: keep the mean edge ≈ its present value, slightly pushed outward
        L0 = 1.02 * math.sqrt((L * L).mean())
        f = ((L0 - L) / L)[:, None] * dv  # positive: repel
        F = _scatter(E[:, 1], E[:, 0], f, len(p))
        disp = 0.2 * F[sl]
        step = np.hypot(disp[:, 0], disp[:, 1])
        lim = 0.3 * h
        big = step > lim
        disp[big] *= (lim / step[big])[:, None]
        st.move_interior(disp, 0.2 * h)
        if step.max() < tol * h:
            break
    return it


def _objective_pass(st: _State, objective: str, h: float, iters: int, p_exp: float = 8.0):
    """Gradient descent on a p-norm surrogate of the objective; keeps the best iterate."""
    best_pts = st.points.copy()
    best_bt = st.bt.copy()
    tri = st.triangulate()
    best_val = objective_value(objective, *_measures(st.points, tri), h)
    step = 0.02 * h
    sl, bs = st.interior, st.bslice
    for _ in range(iters):
        p = st.points
        E = _edges(tri)
        dv = p[E[:, 1]] - p[E[:, 0]]
        L = np.hypot(dv[:, 0], dv[:, 1])
        u = dv / L[:, None]
        Lmean = L.mean()
        x = L / Lmean
        w = np.zeros_like(L)
        if objective in ("max_edge", "ratio", "balanced"):
            w += x ** (p_exp - 1)  # d/dL of sum x^p / p  (penalises long edges)
        if objective in ("ratio", "balanced"):
            w -= x ** (-p_exp - 1)  # penalises short edges
        g = w[:, None] * u
        G = _scatter(E[:, 1], E[:, 0], g, len(p))
        if objective in ("max_perimeter", "balanced"):
            q = p[tri]
            per = np.zeros(len(tri))
            us = []
            for i, j in ((0, 1), (1, 2), (2, 0)):
                dd = q[:, j] - q[:, i]
                ll = np.hypot(dd[:, 0], dd[:, 1])
                per += ll
                us.append((i, j, dd / ll[:, None]))
            wt = (per / per.mean()) ** (p_exp - 1)
            for i, j, uu in us:
                gg = wt[:, None] * uu
                G += _scatter(tri[:, j], tri[:, i], gg, len(p))
        # normalise: the largest move is ``step``
        gi = G[sl]
        gb = G[bs]
        mag = max(np.abs(gi).max() if len(gi) else 0.0, np.abs(gb).max() if len(gb) else 0.0)
        if mag == 0:
            break
        scale = step / mag
        st.move_interior(-scale * gi, 0.2 * h)
        st.slide_boundary(-scale * gb)
        tri = st.triangulate()
        val = objective_value(objective, *_measures(st.points, tri), h)
        if val < best_val:
            best_val = val
            best_pts = st.points.copy()
            best_bt = st.bt.copy()
            step *= 1.1
        else:
            step *= 0.7
            if step < 1e-4 * h:
                break
    st.points = best_pts
    st.bt = best_bt
    return best_val


# ----------------------------------------------------------------------------- driver
def optimize_mesh(
    polygon: Polygon,
    n: int,
    *,
    objective: str = "balanced",
    relax_iters: int | None = None,
    pass_iters: int | None = None,
    start: Mesh | None = None,
    rebalance_rounds: int = 0,
    p_exp: float = 32.0,
) -> Mesh:
    """The most uniform mesh with exactly ``n`` Steiner points (see module docstring)."""
    from .quality import quality
    from .tplus import tplus

    if not isinstance(polygon, Polygon):
        polygon = Polygon(polygon)
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise InsufficientPointsError(f"n must be a positive integer, got {n!r}")
    if objective not in OBJECTIVES:
        raise ValueError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
    n = int(n)
    nV = len(polygon.vertices)

    tp = start if start is not None else tplus(polygon, n)
    d_n = tp.info.get("d_n")
    q_tp = tp.quality(d_n=d_n if d_n is not None else False)

    h = target_size(polygon, n)
    a, d, L = _edge_geometry(polygon)
    m = _boundary_counts(L, h, n)
    bpts, beid, bt = _boundary_points(a, d, m)
    ipts = _seed_interior(polygon, n - len(bpts), h, bpts)
    st = _State(polygon, bpts, beid, bt, ipts)

    if relax_iters is None:
        relax_iters = 60 if n < 5000 else 20
    if pass_iters is None:
        pass_iters = 80 if n < 5000 else 40
    it_relax = _spring_relax(st, h, relax_iters)
    moved = 0
    for _ in range(rebalance_rounds):
        mv = _rebalance_boundary(st, h)
        moved += mv
        if mv == 0:
            break
        it_relax += _spring_relax(st, h, relax_iters)
    _objective_pass(st, objective, h, pass_iters, p_exp)

    res = insert(polygon, 0, sites=st.points[nV:])
    pts = np.array(res.mesh_points)
    tri = np.array(res.triangles)
    q_new = quality(pts, tri, polygon, n_steiner=n, d_n=d_n if d_n is not None else False)
    v_new = _quality_objective(objective, q_new, h)
    v_tp = _quality_objective(objective, q_tp, h)

    def summary(q):
        return {
            "edge_ratio": q.edge_ratio,
            "longest_edge": q.longest_edge,
            "max_perimeter": q.max_perimeter,
            "cv_edge": q.cv_edge,
            "min_angle": q.min_angle,
        }

    info = {
        "method": "uniform",
        "objective": objective,
        "d_n": d_n,
        "h": h,
        "k": int(len(bpts)),
        "relax_iterations": it_relax,
        "boundary_moves": moved,
        "start": {"method": tp.info.get("method"), **summary(q_tp), "objective": v_tp},
        "before": summary(q_tp),
        "after": summary(q_new),
        "objective_value": v_new,
    }
    if not (v_new <= v_tp) or len(pts) != nV + n:
        info["fallback"] = "tplus"
        info["after"] = summary(q_tp)
        info["objective_value"] = v_tp
        log.info("uniform: optimised mesh (%g) not better than T+ (%g); returning T+", v_new, v_tp)
        return Mesh(np.array(tp.points), np.array(tp.triangles), polygon, n, {**tp.info, **info})
    info["fallback"] = None
    return Mesh(pts, tri, polygon, n, info)
