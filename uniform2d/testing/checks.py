"""Independent checks of a triangulation of a polygon (used by every mesh test of uniform2d).

Nothing here uses uniform2d's kernel: adjacency is rebuilt with numpy, and the
geometric signs are decided in floating point with a conservative error bound,
falling back to exact rational arithmetic (``fractions.Fraction``) near zero.

``check_mesh(points, triangles, polygon)`` raises :class:`AssertionError` (with what
is wrong) unless:

* every triangle is strictly counter-clockwise;
* every interior edge is shared by exactly two triangles with opposite
  directions (neighbour symmetry), every other edge lies on the boundary;
* the boundary edges, chained, are exactly the polygon's edges split at the mesh
  vertices lying on them (every polygon edge present, nothing else on the boundary);
* the triangle areas add up to the polygon's area;
* every interior segment piece of P is a chain of mesh edges from one end to the
  other whose inner vertices lie on the piece (within rounding of the
  coordinates: Steiner points, or a fixed point that close), in order along it;
  every fixed point is a mesh vertex;
* every interior edge that is not on a segment is locally Delaunay (the opposite
  vertex is not strictly inside the circumcircle) -- with the boundary and the
  segments as constraints, this is the constrained Delaunay property.

``n_steiner`` (optional) also asks for exactly that many points besides P's vertices.
The checks raise :class:`AssertionError` themselves (not ``assert``), so they hold
under ``python -O`` too, as ``numpy.testing``'s do.

Examples
--------
>>> import uniform2d
>>> from uniform2d.testing import check_mesh
>>> square = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
>>> mesh = uniform2d.insert(square, 10)
>>> check_mesh(mesh.mesh_points, mesh.triangles, square, n_steiner=10)
>>> check_mesh(square.vertices, [(0, 1, 2)], square)
Traceback (most recent call last):
    ...
AssertionError: boundary vertex 0 is off polygon edge 2->3 by 1
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

__all__ = ["check_mesh", "orientations", "edge_table", "segment_chains", "non_delaunay_edges"]


def _orient_exact(a, b, c) -> int:
    ax, ay, bx, by, cx, cy = (Fraction(float(v)) for v in (*a, *b, *c))
    d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    return (d > 0) - (d < 0)


def _incircle_exact(a, b, c, d) -> int:
    rows = []
    for p in (a, b, c):
        x = Fraction(float(p[0])) - Fraction(float(d[0]))
        y = Fraction(float(p[1])) - Fraction(float(d[1]))
        rows.append((x, y, x * x + y * y))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    return (det > 0) - (det < 0)


def orientations(points, triangles) -> np.ndarray:
    """Exact sign of every triangle's orientation, (M,) int."""
    p = points[triangles]
    bx, by = p[:, 1, 0] - p[:, 0, 0], p[:, 1, 1] - p[:, 0, 1]
    cx, cy = p[:, 2, 0] - p[:, 0, 0], p[:, 2, 1] - p[:, 0, 1]
    det = bx * cy - by * cx
    bound = 1e-14 * (np.abs(bx * cy) + np.abs(by * cx))
    sign = np.sign(det).astype(int)
    for i in np.flatnonzero(np.abs(det) <= bound):
        sign[i] = _orient_exact(*p[i])
    return sign


def edge_table(triangles):
    """Directed half-edges (3M, 2) and, for each, the index of its twin or -1."""
    t = np.asarray(triangles, dtype=np.int64)
    he = np.stack([t, np.roll(t, -1, axis=1)], axis=2).reshape(-1, 2)
    n = int(he.max()) + 1
    key = he[:, 0] * n + he[:, 1]
    rkey = he[:, 1] * n + he[:, 0]
    order = np.argsort(key)
    pos = np.searchsorted(key[order], rkey)
    pos = np.clip(pos, 0, len(key) - 1)
    twin = np.where(key[order][pos] == rkey, order[pos], -1)
    return he, twin, key


def check_mesh(points, triangles, polygon, *, delaunay=True, area_rtol=1e-9, n_steiner=None):
    """Raise :class:`AssertionError` unless ``(points, triangles)`` is a valid
    (constrained Delaunay, with ``delaunay``) triangulation of ``polygon``, as the
    module says; ``area_rtol`` is the relative tolerance of the area sum."""
    points = np.asarray(points, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    _check_arrays(points, triangles)
    o = orientations(points, triangles)
    if not (o > 0).all():
        raise AssertionError(f"{int((o <= 0).sum())} triangles are not strictly counter-clockwise")
    # neighbour symmetry: no directed edge twice; each undirected edge at most twice
    he, twin, key = edge_table(triangles)
    if len(np.unique(key)) != len(key):
        raise AssertionError("a directed edge appears in two triangles")
    nV = len(polygon.vertices)
    if not np.array_equal(points[:nV], polygon.vertices):
        raise AssertionError("mesh must start with the polygon vertices")
    _check_boundary(points, he[twin < 0], polygon)
    if n_steiner is not None and len(points) != nV + n_steiner:
        raise AssertionError(f"{len(points) - nV} Steiner points, not {n_steiner}")
    _check_fixed(points, triangles, polygon)
    on_segments = segment_chains(points, he, polygon)
    _check_area(points, triangles, polygon, area_rtol)
    if delaunay:
        bad = non_delaunay_edges(points, triangles, he, twin)
        bad = [h for h in bad if (int(he[h, 0]), int(he[h, 1])) not in on_segments]
        if bad:
            raise AssertionError(f"{len(bad)} interior edges are not locally Delaunay, e.g. {bad[:3]}")


def _check_arrays(points, triangles) -> None:
    """Shapes, indices in range and finite coordinates."""
    if not (points.ndim == 2 and points.shape[1] == 2):
        raise AssertionError(f"points must be (N, 2), got {points.shape}")
    if not (triangles.ndim == 2 and triangles.shape[1] == 3):
        raise AssertionError(f"triangles must be (M, 3), got {triangles.shape}")
    if not (triangles.min() >= 0 and triangles.max() < len(points)):
        raise AssertionError(f"triangles refer to points outside 0..{len(points) - 1}")
    if not np.isfinite(points).all():
        raise AssertionError("a point has a non-finite coordinate")


def _check_boundary(points, bnd, polygon) -> None:
    """The boundary half-edges ``bnd`` are the polygon's edges split at mesh
    vertices on them, in order: each polygon edge walked from its start vertex,
    every hop staying on the edge, and no boundary edge left over."""
    succ = {}
    for u, v in bnd:
        if int(u) in succ:
            raise AssertionError(f"boundary vertex {int(u)} has two outgoing boundary edges")
        succ[int(u)] = int(v)
    V = polygon.vertices
    covered = 0
    for a, b in polygon.edges:
        cur = int(a)
        pa, pb = V[a], V[b]
        d = pb - pa
        L = float(np.hypot(*d))
        last_t = 0.0
        for _ in range(len(points) + 1):
            if cur not in succ:
                raise AssertionError(f"polygon edge {int(a)}->{int(b)} is not on the mesh boundary")
            nxt_v = succ[cur]
            covered += 1
            if nxt_v == b:
                break
            q = points[nxt_v]
            t = float(np.dot(q - pa, d)) / (L * L)
            off = abs(float(d[0] * (q - pa)[1] - d[1] * (q - pa)[0])) / L
            if not (off <= 1e-9 * L + 1e-12 * max(1.0, float(np.abs(V).max()))):
                raise AssertionError(
                    f"boundary vertex {nxt_v} is off polygon edge {int(a)}->{int(b)} by {off:g}")
            if not (last_t < t < 1.0):
                raise AssertionError(f"boundary vertex {nxt_v} out of order on edge {int(a)}->{int(b)}")
            last_t = t
            cur = nxt_v
        else:
            raise AssertionError("boundary walk did not terminate")
    if covered != len(bnd):
        raise AssertionError("the mesh boundary has edges that are not on the polygon")


def _check_fixed(points, triangles, polygon) -> None:
    """Every fixed point is a mesh vertex (used by a triangle) where it was given."""
    used = np.zeros(len(points), bool)
    used[triangles.ravel()] = True
    for i, k in enumerate(np.asarray(polygon.fixed)):
        if not (used[k] and np.array_equal(points[k], polygon.points[i])):
            raise AssertionError(f"fixed point {i} is not a mesh vertex where it was given")


def _check_area(points, triangles, polygon, area_rtol: float) -> None:
    """The triangles' areas sum to the polygon's, within ``area_rtol``."""
    p = points[triangles]
    area = 0.5 * (
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    ).sum()
    if not (abs(area - polygon.area) <= area_rtol * polygon.area):
        raise AssertionError(f"the triangles cover {area!r}, the polygon {polygon.area!r}")


def segment_chains(points, he, polygon) -> set:
    """Assert every segment piece of ``polygon`` is a chain of the mesh's edges
    (directed half-edges ``he``) through Steiner points on it, in order, no
    point on two chains; return those edges as a set of (u, v) pairs, both
    directions.

    Where two pieces leave a vertex at a tiny angle (or a piece runs a rounding
    off a ring edge), the points of one are within the tolerance of the other
    too: the search takes the neighbours nearest the piece's line first and
    backs up from dead ends."""
    V = polygon.vertices
    nbrs: dict[int, set] = {}
    for u, v in he:
        nbrs.setdefault(int(u), set()).add(int(v))
        nbrs.setdefault(int(v), set()).add(int(u))
    tol = 1e-9 * max(1.0, float(np.abs(V).max()))
    out = set()
    used: set = set()
    for a, b in np.asarray(polygon.segment_edges):
        chain = _chain(points, nbrs, used, V, int(a), int(b), tol)
        if chain is None:
            raise AssertionError(f"segment piece {int(a)}-{int(b)} is not a chain of mesh edges")
        used |= set(chain[1:-1])
        for p, q in zip(chain[:-1], chain[1:]):
            out |= {(p, q), (q, p)}
    return out


def _chain(points, nbrs, used, V, a, b, tol):
    """A path a .. b of mesh edges through unused points near the piece a-b with
    growing parameter, or None (depth-first, nearest the line first; a vertex
    that led nowhere is not tried again, its parameter being fixed)."""
    pa, d = V[a], V[b] - V[a]
    L = float(np.hypot(*d))
    seen: set = set()
    path, stack = [a], [None]
    tcs = [0.0]
    while path:
        cur, tc = path[-1], tcs[-1]
        if stack[-1] is None:
            if b in nbrs.get(cur, ()):
                return path + [b]
            cands = []
            for w in nbrs.get(cur, ()):
                if w == a or w in used or w in seen:
                    continue
                q = points[w] - pa
                t = float(q @ d) / (L * L)
                off = abs(float(d[0] * q[1] - d[1] * q[0])) / L
                if off <= 1e-9 * L + tol and tc < t < 1.0:
                    cands.append((off, t, w))
            stack[-1] = sorted(cands, reverse=True)
        if not stack[-1]:
            path.pop(), stack.pop(), tcs.pop()
            continue
        _, t, w = stack[-1].pop()
        if w in seen:
            continue
        seen.add(w)
        path.append(w), stack.append(None), tcs.append(t)
    return None


def non_delaunay_edges(points, triangles, he=None, twin=None):
    """Interior half-edges (h < twin) whose opposite vertex is strictly inside the
    circumcircle of the triangle on the other side."""
    if he is None:
        he, twin, _ = edge_table(triangles)
    t = np.asarray(triangles, dtype=np.int64)
    h = np.flatnonzero((twin >= 0) & (np.arange(len(twin)) < twin))
    g = twin[h]
    apex_h = t.reshape(-1)[3 * (h // 3) + (h % 3 + 2) % 3]
    apex_g = t.reshape(-1)[3 * (g // 3) + (g % 3 + 2) % 3]
    a = points[he[h, 0]]
    b = points[he[h, 1]]
    c = points[apex_h]
    d = points[apex_g]
    rows = [q - d for q in (a, b, c)]
    lift = [(r * r).sum(axis=1) for r in rows]
    (a1, a2), (b1, b2), (c1, c2) = [(r[:, 0], r[:, 1]) for r in rows]
    a3, b3, c3 = lift
    det = a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)
    perm = (
        np.abs(a1 * b2 * c3) + np.abs(a1 * b3 * c2) + np.abs(a2 * b1 * c3)
        + np.abs(a2 * b3 * c1) + np.abs(a3 * b1 * c2) + np.abs(a3 * b2 * c1)
    )  # fmt: skip
    suspicious = np.flatnonzero(det > -1e-12 * perm)
    bad = []
    for i in suspicious:
        if det[i] > 1e-12 * perm[i] or _incircle_exact(a[i], b[i], c[i], d[i]) > 0:
            bad.append(int(h[i]))
    return bad
