"""The final check every mesh passes before the library returns it.

The kernel keeps its triangulation valid by construction (exact predicates on
the coordinates actually stored; see :mod:`uniform2d._kernel.cdt`), and this
check says so again, independently and cheaply (compiled loops and vectorised
numpy, the exact ``orient2d`` only where its floating-point filter cannot
decide), on the arrays the caller gets.  A mesh of P with n Steiner points is valid when

* it has exactly ``|V| + n`` points, finite, the polygon's vertices first and
  unchanged, every point a corner of some triangle;
* every triangle is strictly counter-clockwise (exact);
* no directed edge occurs twice, so an edge is shared by at most two triangles,
  in opposite directions;
* the unpaired (boundary) edges chain, from each polygon vertex, through Steiner
  points only, to the next vertex of its ring, every point on the way within
  :func:`uniform2d.tolerance.boundary_tol` of that polygon edge and in order along
  it, and there are no other boundary edges;
* every interior segment piece is a chain of mesh edges from one end to the
  other through Steiner points within the tolerance of the piece, in order
  along it (fixed points are polygon vertices, so corners by the first rule);
* the triangle areas add up to P's area (up to what the boundary points' offsets
  and rounding allow).

Why that is enough: the triangles form a surface whose border is the chain of
unpaired edges, a copy of P's boundary moved by at most the tolerance at its
Steiner points.  With every triangle positively oriented, the number of
triangles covering a point is the winding number of that border around it:
1 inside P, 0 outside.  So the triangles cover P exactly once and nothing else,
and no point lies outside.
"""

import numpy as np
from ._jit import njit

from .predicates import orient2d

__all__ = ["mesh_problem", "piece_chain"]


@njit(cache=True)
def _not_ccw(points, triangles):
    """Number of triangles that are not strictly counter-clockwise (exact)."""
    bad = 0
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        if orient2d(points[a, 0], points[a, 1], points[b, 0], points[b, 1],
                    points[c, 0], points[c, 1]) <= 0.0:  # fmt: skip
            bad += 1
    return bad


@njit(cache=True)
def _walk(succ, ring_next, nV, edge_of):
    """Follow the boundary successor ``succ`` from every polygon vertex to the next
    vertex of its ring, writing the polygon edge (the start vertex's index) of the
    Steiner points met into ``edge_of``.  Returns the number of boundary edges
    walked, or -1 if a walk leaves its edge (meets another polygon vertex, a
    dead end or a loop)."""
    walked = 0
    n = succ.shape[0]
    for a in range(nV):
        if ring_next[a] < 0:
            continue  # a constraint vertex inside P
        cur = a
        for _ in range(n + 1):
            nxt = succ[cur]
            if nxt < 0:
                return -1
            walked += 1
            if nxt == ring_next[a]:
                break
            if nxt < nV or edge_of[nxt] >= 0:
                return -1
            edge_of[nxt] = a
            cur = nxt
        else:
            return -1
    return walked


@njit(cache=True)
def _unmatched(triangles, n_points):
    """The directed edges u -> v of ``triangles`` with no reverse v -> u (the
    boundary), as ``(count, bu, bv)``, grouped by the smaller of u and v;
    ``count`` is -1 (and the arrays empty) if a directed edge occurs twice.

    Every directed edge is filed once, under its smaller vertex, with the other
    vertex and its direction (a counting sort): an edge and its reverse land in
    the same short list (~6 entries), so each list is checked on its own.  No
    sorted key arrays of all 3M directed edges (~250 MB at 1e6 points), and no
    look-ups in other vertices' lists, which cost a cache miss each when the
    points are not in a spatially coherent order."""
    nt = triangles.shape[0]
    start = np.zeros(n_points + 1, np.int64)
    for t in range(nt):
        for i in range(3):
            start[min(triangles[t, i], triangles[t, (i + 1) % 3]) + 1] += 1
    for v in range(n_points):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    other = np.empty(3 * nt, np.int64)  # 2 * the other vertex + 1 if it is the start
    for t in range(nt):
        for i in range(3):
            u, v = triangles[t, i], triangles[t, (i + 1) % 3]
            a = min(u, v)
            other[fill[a]] = 2 * (u + v - a) + (1 if u > v else 0)
            fill[a] += 1
    count = 0
    for a in range(n_points):
        for k in range(start[a], start[a + 1]):
            back = False
            for j in range(start[a], start[a + 1]):
                if j < k and other[j] == other[k]:
                    return -1, other[:0], other[:0]
                if other[j] == other[k] ^ 1:
                    back = True
            if not back:
                count += 1
    bu = np.empty(count, np.int64)
    bv = np.empty(count, np.int64)
    c = 0
    for a in range(n_points):
        for k in range(start[a], start[a + 1]):
            back = False
            for j in range(start[a], start[a + 1]):
                if other[j] == other[k] ^ 1:
                    back = True
                    break
            if not back:
                b = other[k] >> 1
                bu[c], bv[c] = (b, a) if other[k] & 1 else (a, b)
                c += 1
    return count, bu, bv


@njit(cache=True)
def _area2(points, triangles):
    """Twice the total signed area of the triangles, summed with compensation
    (Neumaier): the error stays a few units in the last place of the sum of the
    terms' magnitudes, whatever their number and order."""
    s = 0.0
    comp = 0.0
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        x = (points[b, 0] - points[a, 0]) * (points[c, 1] - points[a, 1]) - (
            points[b, 1] - points[a, 1]
        ) * (points[c, 0] - points[a, 0])
        y = s + x
        if abs(s) >= abs(x):
            comp += (s - y) + x
        else:
            comp += (x - y) + s
        s = y
    return s + comp


def mesh_problem(points, triangles, polygon, n_steiner, boundary_tol):
    """None if the mesh is a valid triangulation of ``polygon`` with ``n_steiner``
    Steiner points (module docstring), else what is wrong, in a few words."""
    P = np.asarray(points)
    T = np.asarray(triangles)
    V = polygon.vertices
    nV = len(V)
    if P.ndim != 2 or P.shape[1] != 2 or P.dtype != np.float64 or len(P) != nV + n_steiner:
        return f"{len(P)} points of shape {P.shape}, expected ({nV + n_steiner}, 2) float64"
    if not np.isfinite(P).all() or not np.array_equal(P[:nV], V):
        return "the points do not start with the polygon's vertices, or are not finite"
    if T.ndim != 2 or T.shape[1] != 3 or len(T) == 0 or T.min() < 0 or T.max() >= len(P):
        return f"triangles of shape {T.shape} do not index the points"
    if np.bincount(T.ravel(), minlength=len(P)).min() == 0:
        return "a point is not a corner of any triangle"
    # writable C arrays (copies only where needed): one compiled version of _not_ccw
    T = np.require(T, np.int64, ["C", "W"])
    Pc = np.require(P, np.float64, ["C", "W"])
    bad = _not_ccw(Pc, T)
    if bad:
        return f"{bad} triangles are not strictly counter-clockwise"
    # directed edges: unique; the boundary is the set without a reverse
    count, bu, bv = _unmatched(T, np.int64(len(P)))
    if count < 0:
        return "an edge occurs twice in the same direction (overlapping triangles)"
    succ = np.full(len(P), -1, np.int64)
    if len(np.unique(bu)) != len(bu):
        return "a boundary vertex has two outgoing boundary edges"
    succ[bu] = bv
    E = polygon.edges
    ring_next = np.full(nV, -1, np.int64)
    ring_next[E[:, 0]] = E[:, 1]
    edge_of = np.full(len(P), -1, np.int64)
    walked = _walk(succ, ring_next, nV, edge_of)
    if walked != len(bu):
        return "the mesh boundary is not the polygon's boundary split at mesh points"
    on = np.flatnonzero(edge_of >= 0)
    if len(on):
        e = edge_of[on]  # vertex a starts edge a (Polygon.edges layout)
        a = V[E[e, 0]]
        d = V[E[e, 1]] - a
        rel = P[on] - a
        L = np.hypot(d[:, 0], d[:, 1])
        off = np.abs(d[:, 0] * rel[:, 1] - d[:, 1] * rel[:, 0]) / L
        if off.max() > boundary_tol:
            return f"a boundary point is {off.max():.3g} off its polygon edge"
        t = (rel * d).sum(axis=1) / (L * L)
        tt = np.full(len(P), np.nan)
        tt[on] = t
        tt[:nV] = 0.0
        nxt_t = np.where(bv < nV, 1.0, tt[bv])
        if not (nxt_t > tt[bu]).all() or not ((t > 0.0) & (t < 1.0)).all():
            return "boundary points are out of order along their polygon edge"
    if len(polygon.segment_edges):
        problem = _pieces_problem(P, T.ravel(), T[:, [1, 2, 0]].ravel(), polygon, boundary_tol)
        if problem is not None:
            return problem
    area = 0.5 * _area2(Pc, T)
    slack = 1e-9 * polygon.area + 2.0 * polygon.perimeter * boundary_tol
    if abs(area - polygon.area) > slack:
        return f"the triangles cover {area!r}, the polygon has area {polygon.area!r}"
    return None


def _pieces_problem(P, u, v, polygon, tol):
    """None if every segment piece of ``polygon`` is a chain of the mesh edges
    ``u -> v`` (directed, both directions present for interior edges) through
    points on it (Steiner points, or a fixed point within the tolerance of it),
    no point on two chains, else what is wrong."""
    order = np.argsort(u, kind="stable")
    us, vs = u[order], v[order]
    start = np.searchsorted(us, np.arange(len(P) + 1))
    used = np.zeros(len(P), bool)
    for a, b in polygon.segment_edges:
        chain = piece_chain(P, vs, start, used, polygon.vertices, int(a), int(b), tol)
        if chain is None:
            return f"segment piece {int(a)}-{int(b)} is not a chain of mesh edges"
        used[chain] = True
    return None


def piece_chain(P, vs, start, used, V, a, b, tol):
    """The inner vertices of a chain of mesh edges from a to b through points
    within ``tol`` of the piece a-b, in order along it and not ``used``, or None.

    Two pieces leaving a vertex at a tiny angle, or a piece a rounding off a
    ring edge, put the points of the other chain within ``tol`` of this one
    too: so the search tries the neighbours nearest the piece's line first and
    backs up from a dead end (each vertex is tried once: the parameter only
    grows along a chain, so a vertex that led nowhere leads nowhere again)."""
    pa, d = V[a], V[b] - V[a]
    # dot products written out: ``@`` goes to BLAS, whose kernel (FMA or not)
    # OpenBLAS picks per CPU, and the last bits decide which chain is tried first
    L2 = float(d[0] * d[0] + d[1] * d[1])
    seen = np.zeros(len(P), bool)
    path = [(a, 0.0, None)]
    while path:
        cur, tc, todo = path[-1]
        if todo is None:
            nb = vs[start[cur]:start[cur + 1]]
            if (nb == b).any():
                return [w for w, _, _ in path[1:]]
            nb = nb[(nb != a) & ~used[nb] & ~seen[nb]]
            rel = P[nb] - pa
            t = (rel[:, 0] * d[0] + rel[:, 1] * d[1]) / L2
            off = np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]) / np.sqrt(L2)
            ok = (off <= tol) & (t > tc) & (t < 1.0)
            k = np.flatnonzero(ok)
            todo = [(int(nb[j]), float(t[j])) for j in k[np.lexsort((t[k], off[k]))][::-1]]
            path[-1] = (cur, tc, todo)
        if not todo:
            path.pop()
            continue
        w, tw = todo.pop()
        if seen[w]:
            continue
        seen[w] = True
        path.append((w, tw, None))
    return None
