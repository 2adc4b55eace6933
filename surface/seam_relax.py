"""Relaxing a stitched atlas mesh across its seams, on the input surface.

Each chart is meshed as well as the planar optimiser can, but its ring is
fixed: along a seam the two charts' rows meet as they come, with vertices of
valence 5 and 7 and triangles squeezed or stretched.  The seam is a cut of the
atlas, not of the surface, so here it stops being one: in a band of
:data:`BAND_RINGS` rings around every seam point that is not on a crease or
the model boundary,

1. **flips**: first where an edge's two opposite angles (in 3-D) sum to more
   than 180 degrees and flipping raises the pair's smallest angle (a Delaunay
   pass: it removes the flat triangles a chord of a ring can leave), then
   where that brings the valences of the four vertices closer to 6 (fixed
   vertices do not count), the new edge is no farther from the mean length
   than :data:`FLIP_SLACK`, and the pair's smallest angle does not drop below
   :data:`FLIP_MIN_ANGLE` or below what it was (Botsch and Kobbelt's isotropic
   remeshing step, without splits and collapses, which would change the
   count); a flip is made only where the two new triangles face the way the
   old ones did;
2. **tangential springs** move every free vertex of the band towards edges of
   the mean length, each edge pulling with a weight that grows as the fourth
   power of its deviation (:data:`EXTREME`), so the longest and shortest edges
   move first (a least-squares spring alone leaves the extremes, which set the
   edge ratio); moves stay in the input's tangent plane and end on the input
   surface (its closest point, libigl).

Seam points on creases and on the model boundary do not move, so creases and
boundaries stay exactly where the seam sampling put them.  A round that would
fold a triangle against the input surface is undone and the relaxation stops.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from uniform2d import libm

from . import _igl
from .measure import corner_angles, unique_edges

__all__ = ["relax", "band", "BAND_RINGS"]

log = logging.getLogger(__name__)

#: Rings of neighbours around the free seam points that are relaxed.
BAND_RINGS = 3

#: Outer rounds (one flip pass and :data:`SMOOTH_STEPS` smoothing steps each).
ROUNDS = 4
SMOOTH_STEPS = 8

#: Fraction of the mean spring force a vertex moves by in one step.
STEP = 0.5

#: Edges off the mean length by this fraction pull twice as hard as a spring;
#: the weight grows as the deviation's fourth power, so the extremes move first.
EXTREME = 0.2

#: A flip may not make the pair's smallest angle smaller than this (degrees).
FLIP_MIN_ANGLE = 25.0

#: A flip may not make the edge farther from the mean length than this fraction of
#: it, unless the flipped edge was farther still.
FLIP_SLACK = 0.15

#: A face whose normal turns more than this from the input's (degrees) is a fold.
FOLD_ANGLE = 60.0


def band(faces, seeds, n: int, rings: int | None = None) -> np.ndarray:
    """(n,) bool: the vertices within ``rings`` edges (default :data:`BAND_RINGS`)
    of the ``seeds``."""
    rings = BAND_RINGS if rings is None else rings
    E = unique_edges(faces)
    inside = np.zeros(n, dtype=bool)
    inside[np.asarray(seeds, dtype=np.int64)] = True
    for _ in range(rings):
        grow = inside[E[:, 0]] | inside[E[:, 1]]
        inside[E[grow].ravel()] = True
    return inside


def _normals(X, F):
    n = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def _surface_normals(P, tree, N0):
    _, face, closest = tree.closest(P)
    return closest, N0[face]


def _folded(X, F, tree, N0) -> bool:
    c = X[F].mean(axis=1)
    _, nin = _surface_normals(c, tree, N0)
    return bool((np.einsum("ij,ij->i", _normals(X, F), nin) < np.cos(np.radians(FOLD_ANGLE))).any())


def _fourth(r):
    """r**4 by two squarings: numpy's ``r ** 4`` is its power ufunc, whose AVX-512
    loop rounds otherwise than the C library's pow on other CPUs."""
    r2 = r * r
    return r2 * r2


def _smooth(X, F, move, tree, N0, steps: int, size=None):
    """Spring steps of the ``move`` vertices towards edges of the mean length
    (with ``size``, a graded size: of the mean length / size times the size at
    the edge's midpoint), within the input's tangent plane, projected back onto
    the input."""
    E = unique_edges(F)
    n = len(X)
    idx = np.flatnonzero(move)
    for _ in range(steps):
        d = X[E[:, 1]] - X[E[:, 0]]
        L = np.linalg.norm(d, axis=1)
        if size is None:
            dev = L / L.mean() - 1.0
            w = 1.0 + _fourth(dev / EXTREME)  # the far-off edges pull hardest
            pull = (w * dev * L.mean() / L)[:, None] * d
        else:
            hm = size(0.5 * (X[E[:, 0]] + X[E[:, 1]]))
            q = L / hm
            dev = q / q.mean() - 1.0
            w = 1.0 + _fourth(dev / EXTREME)
            pull = (w * dev * q.mean() * hm / L)[:, None] * d
        s = np.zeros_like(X)
        np.add.at(s, E[:, 0], pull)
        np.add.at(s, E[:, 1], -pull)
        wsum = np.bincount(E.ravel(), weights=np.repeat(w, 2), minlength=n)
        step = STEP * s[idx] / wsum[idx, None]
        _, nrm = _surface_normals(X[idx], tree, N0)
        step -= np.einsum("ij,ij->i", step, nrm)[:, None] * nrm
        closest, _ = _surface_normals(X[idx] + step, tree, N0)
        X[idx] = closest
    return X


def _angle(X, at, p, q) -> float:
    """The angle at ``at`` between ``p`` and ``q`` (plain floats: called per edge)."""
    ox, oy, oz = X[at]
    ax, ay, az = X[p][0] - ox, X[p][1] - oy, X[p][2] - oz
    bx, by, bz = X[q][0] - ox, X[q][1] - oy, X[q][2] - oz
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    return math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz)


def _wants(rule, X, u, v, c, d, val, free, mean) -> bool:
    """Whether ``rule`` asks to flip (u, v) to (c, d)."""
    if rule == "delaunay":  # the opposite angles sum to more than pi: not Delaunay
        return _angle(X, c, u, v) + _angle(X, d, u, v) > math.pi
    change = 0  # in the sum of squared valence defects of the free vertices
    for x, step in ((u, -1), (v, -1), (c, 1), (d, 1)):
        if free[x]:
            change += (val[x] - 6 + step) ** 2 - (val[x] - 6) ** 2
    if change >= 0:
        return False
    slack = max(abs(math.dist(X[u], X[v]) - mean), FLIP_SLACK * mean)
    return abs(math.dist(X[c], X[d]) - mean) <= slack


def _candidates(X, sub, free, locked, rule, val, mean) -> list:
    """The edges of the faces ``sub`` (two faces each, a free end, not locked) that
    ``rule`` asks to flip as the pass starts, sorted: only these are looked at one
    by one (the rest of the band wait for the next round)."""
    n = len(X)
    a, b, o = sub.ravel(), sub[:, [1, 2, 0]].ravel(), sub[:, [2, 0, 1]].ravel()
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    key = lo * n + hi
    order = np.argsort(key, kind="stable")
    pair = key[order][1:] == key[order][:-1]
    i, j = order[:-1][pair], order[1:][pair]
    U, W, C, D = lo[i], hi[i], o[i], o[j]
    lk = np.array([p * n + q for p, q in locked], dtype=np.int64)
    ok = (free[U] | free[W]) & (C != D) & ~np.isin(key[i], lk)
    if rule == "delaunay":
        ok &= _opposite_angle(X, C, U, W) + _opposite_angle(X, D, U, W) > np.pi
    else:
        f = free.astype(np.int64)
        change = sum(f[x] * ((val[x] - 6 + s) ** 2 - (val[x] - 6) ** 2)
                     for x, s in ((U, -1), (W, -1), (C, 1), (D, 1)))
        ok &= change < 0
        slack = np.maximum(np.abs(np.linalg.norm(X[U] - X[W], axis=1) - mean), FLIP_SLACK * mean)
        ok &= np.abs(np.linalg.norm(X[C] - X[D], axis=1) - mean) <= slack
    return sorted(zip(U[ok].tolist(), W[ok].tolist()))


def _opposite_angle(X, at, p, q) -> np.ndarray:
    a, b = X[p] - X[at], X[q] - X[at]
    return libm.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))


def _flip_pass(X, F, free, locked, rule: str, Xl) -> int:
    """One pass of flips over the edges with a free end, in place: ``"delaunay"``
    (3-D angles) or ``"valence"`` (towards valence 6).  ``Xl`` is ``X.tolist()``
    (per-edge reads in plain Python: numpy scalars cost more; flips move no point)."""
    E = unique_edges(F)
    val = np.bincount(E.ravel(), minlength=len(X))
    mean = np.linalg.norm(X[E[:, 1]] - X[E[:, 0]], axis=1).mean()
    # the faces within one ring of a free vertex: every face a flip reads or makes
    near = free.copy()
    near[E[free[E[:, 0]] | free[E[:, 1]]].ravel()] = True
    rows = np.flatnonzero(near[F].any(axis=1))
    F_list = dict(zip(rows.tolist(), F[rows].tolist()))
    edge_faces: dict = {}
    for f, (a, b, c) in F_list.items():
        for u, v in ((a, b), (b, c), (c, a)):
            edge_faces.setdefault((u, v) if u < v else (v, u), []).append(f)
    flips = 0
    cand = _candidates(X, F[rows], free, locked, rule, val, mean)
    val = val.tolist()
    free_l = free.tolist()
    for u, v in cand:
        fs = edge_faces.get((u, v))
        if fs is None or len(fs) != 2:  # flipped away earlier in this pass
            continue
        f, g = fs
        c = sum(F_list[f]) - u - v  # the third corner of each face
        d = sum(F_list[g]) - u - v
        if c == d or (min(c, d), max(c, d)) in edge_faces:
            continue
        if not _wants(rule, Xl, u, v, c, d, val, free_l, mean):
            continue
        new_f, new_g = _flipped(F_list[f], u, v, c, d)
        if not _flip_ok(X, [F_list[f], F_list[g]], [new_f, new_g], rule == "delaunay"):
            continue
        F_list[f], F_list[g] = new_f, new_g
        del edge_faces[(u, v)]
        edge_faces[(min(c, d), max(c, d))] = [f, g]
        for x, y in ((u, c), (u, d), (v, c), (v, d)):  # the quad's sides: which face now
            lst = edge_faces[(min(x, y), max(x, y))]
            here, there = (f, g) if x in new_f and y in new_f else (g, f)
            lst[lst.index(there if there in lst else here)] = here
        val[u] -= 1
        val[v] -= 1
        val[c] += 1
        val[d] += 1
        flips += 1
    F[rows] = np.asarray([F_list[int(f)] for f in rows], dtype=np.int64).reshape(-1, 3)
    return flips


def _flipped(tri_f, u, v, c, d):
    """The two triangles after flipping (u, v) to (c, d), with the orientation of
    ``tri_f`` = (.., u, v, c in cyclic order) kept."""
    i = tri_f.index(u)
    if tri_f[(i + 1) % 3] == v:  # f runs u -> v -> c: g runs v -> u -> d
        return [u, d, c], [v, c, d]
    return [v, d, c], [u, c, d]


def _flip_ok(X, old, new, strict=False) -> bool:
    n_old = _normals(X, np.asarray(old))
    n_new = _normals(X, np.asarray(new))
    ref = n_old.sum(axis=0)
    # sums of products, not ``@``/``norm``: BLAS's kernel, and its sums, are per CPU
    if not ((n_new * ref).sum(axis=1) > 0.5 * np.sqrt(np.sum(ref * ref))).all():
        return False
    a_old = np.degrees(corner_angles(X, np.asarray(old))).min()
    a_new = np.degrees(corner_angles(X, np.asarray(new))).min()
    return a_new > a_old if strict else a_new >= min(a_old, FLIP_MIN_ANGLE)


def relax(X, F, free_seeds, fixed, V0, F0, size=None):
    """Relax the band around ``free_seeds`` (free seam points); ``fixed`` (n,) bool
    vertices never move and edges between two of them never flip.  ``size``: a
    graded 3-D size (:class:`surface.size3d.Size3D`) the springs measure edges
    against; with it only the Delaunay flips are made (the valence flips
    compare lengths with one mean length).

    Returns new ``(X, F)`` (the inputs are not changed) and the number of flips.
    """
    X = np.array(X, dtype=np.float64)
    F = np.array(F, dtype=np.int64)
    V0 = np.asarray(V0, dtype=np.float64)
    F0 = np.asarray(F0, dtype=np.int64)
    N0 = _normals(V0, F0)
    if not len(free_seeds):
        return X, F, 0
    tree = _igl.SurfaceTree(V0, F0)
    E = unique_edges(F)
    locked = set(map(tuple, E[fixed[E[:, 0]] & fixed[E[:, 1]]].tolist()))
    flips = 0
    for _ in range(ROUNDS):
        move = band(F, free_seeds, len(X)) & ~fixed
        X0, F_0 = X.copy(), F.copy()
        Xl = X.tolist()
        flips += _flip_pass(X, F, move, locked, "delaunay", Xl)
        if size is None:  # valence flips compare lengths with one mean: not for a graded size
            flips += _flip_pass(X, F, move, locked, "valence", Xl)
        X = _smooth(X, F, move, tree, N0, SMOOTH_STEPS, size)
        if _folded(X, F, tree, N0):
            log.info("seam relaxation stopped: a round would fold a triangle")
            return X0, F_0, flips
    return X, F, flips
