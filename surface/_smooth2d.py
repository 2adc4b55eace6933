"""TEMPORARY planar smoothing, until the mesh optimiser of issue 5 lands.

Only here so the surface pipeline can be exercised end to end with reasonable
meshes; :func:`surface.remesh._mesh_domain` is the one place that calls it and
the one place to swap for the real optimiser.  Not a public API.

Method: DistMesh-style repulsive springs (Persson & Strang 2004) with the
boundary vertices fixed, the point count unchanged, the connectivity kept valid
by refusing moves that would invert a triangle, and Lawson edge flips after
each step to restore the (constrained) Delaunay property.  Rest lengths follow
the size field, so grading is kept.
"""

from __future__ import annotations

import numpy as np

__all__ = ["smooth"]


def _signed_area2(P, T):
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def _quality(P, T):
    """4 sqrt(3) area / sum of squared edges: 1 for equilateral, 0 for flat (signed)."""
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    s = ((b - a) ** 2).sum(1) + ((c - b) ** 2).sum(1) + ((a - c) ** 2).sum(1)
    return 2.0 * np.sqrt(3.0) * _signed_area2(P, T) / s


def _interior_edges(T, n):
    """Twin half-edge pairs: (t1, i1, t2, i2) where edge i of t runs T[t,i] -> T[t,i+1]."""
    m = len(T)
    a = T.ravel()
    b = T[:, [1, 2, 0]].ravel()
    key = a * n + b
    rkey = b * n + a
    order = np.argsort(key)
    pos = np.searchsorted(key[order], rkey)
    pos = np.clip(pos, 0, len(key) - 1)
    twin = order[pos]
    has = key[twin] == rkey
    h1 = np.flatnonzero(has)
    h2 = twin[h1]
    keep = h1 < h2
    h1, h2 = h1[keep], h2[keep]
    return h1 // 3, h1 % 3, h2 // 3, h2 % 3, (a[~has], b[~has])


def _incircle(a, b, c, d):
    """> 0 when d is inside the circumcircle of the CCW triangle (a, b, c)."""
    ax, ay = a[:, 0] - d[:, 0], a[:, 1] - d[:, 1]
    bx, by = b[:, 0] - d[:, 0], b[:, 1] - d[:, 1]
    cx, cy = c[:, 0] - d[:, 0], c[:, 1] - d[:, 1]
    return (
        (ax * ax + ay * ay) * (bx * cy - cx * by)
        - (bx * bx + by * by) * (ax * cy - cx * ay)
        + (cx * cx + cy * cy) * (ax * by - bx * ay)
    )


def delaunay_flips(P, T, max_rounds: int = 200) -> np.ndarray:
    """Lawson flips until every interior edge is locally Delaunay.

    Boundary edges (those of a single triangle) are never flipped, so polygon
    edges stay.  Returns new triangles (M, 3), counter-clockwise.
    """
    T = T.copy()
    n = len(P)
    scale = float(np.ptp(P, axis=0).max()) ** 4
    for _ in range(max_rounds):
        t1, i1, t2, i2, _ = _interior_edges(T, n)
        a = T[t1, i1]
        b = T[t1, (i1 + 1) % 3]
        c = T[t1, (i1 + 2) % 3]
        d = T[t2, (i2 + 2) % 3]
        ic = _incircle(P[a], P[b], P[c], P[d])
        bad = np.flatnonzero(ic > 1e-12 * scale)
        if len(bad) == 0:
            return T
        bad = bad[np.argsort(-ic[bad], kind="stable")]
        used = np.zeros(len(T), dtype=bool)
        for k in bad:
            if used[t1[k]] or used[t2[k]]:
                continue
            used[t1[k]] = used[t2[k]] = True
            T[t1[k]] = (a[k], d[k], c[k])
            T[t2[k]] = (d[k], b[k], c[k])
    return T


def smooth(
    points, triangles, n_fixed_mask, size=None, iterations: int = 40, dt: float = 0.2,
    min_quality: float = 0.3,
):
    """Relax the free points of a planar triangulation towards equal (graded) edges.

    Parameters
    ----------
    points : (N, 2) float64
    triangles : (M, 3) int, counter-clockwise
    n_fixed_mask : (N,) bool
        True for points that must not move (boundary points).
    size : callable or None
        Size field h(points (K, 2)) -> (K,); None for uniform.
    iterations : int
    dt : float
        Step factor of the spring forces.
    min_quality : float
        A move may not push a triangle's quality ``4 sqrt(3) A / sum(l**2)``
        (1 equilateral, 0 flat) below this value, unless it improves it.

    Returns
    -------
    points : (N, 2) float64
    triangles : (M, 3) int64
    """
    P = np.array(points, dtype=np.float64)
    T = np.array(triangles, dtype=np.int64)
    fixed = np.asarray(n_fixed_mask, dtype=bool)
    free = ~fixed
    n = len(P)
    T = delaunay_flips(P, T)
    for _ in range(iterations):
        e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
        e = np.unique(np.sort(e, axis=1), axis=0)
        vec = P[e[:, 0]] - P[e[:, 1]]
        L = np.linalg.norm(vec, axis=1)
        mid = 0.5 * (P[e[:, 0]] + P[e[:, 1]])
        hb = np.ones(len(e)) if size is None else np.asarray(size(mid), dtype=np.float64)
        L0 = hb * 1.2 * np.sqrt((L * L).sum() / (hb * hb).sum())
        Fm = np.maximum(L0 - L, 0.0) / L
        fv = Fm[:, None] * vec
        force = np.zeros_like(P)
        np.add.at(force, e[:, 0], fv)
        np.add.at(force, e[:, 1], -fv)
        step = dt * force
        step[fixed] = 0.0
        # refuse moves that invert or flatten a triangle (repeat: reverting one
        # point can expose another triangle it shares)
        moving = free.copy()
        q0 = _quality(P, T)
        for _r in range(20):
            Q = P + np.where(moving[:, None], step, 0.0)
            q1 = _quality(Q, T)
            bad_t = (q1 <= min_quality) & (q1 < q0)
            if not bad_t.any():
                break
            moving[T[bad_t].ravel()] = False
        else:
            Q = P
        P = Q
        T = delaunay_flips(P, T)
    return P, T
