"""Seams of an atlas: the curves where charts meet, sampled once in 3-D.

Every model edge between two charts, and every model boundary edge, is a seam
edge.  The seam edges form a graph whose **nodes** are the vertices where three
or more charts (or two charts and the model boundary) meet, where the graph
branches or ends, where a crease seam meets a smooth one, and where a crease
or the boundary turns by more than the corner angle; a cycle with no node gets
one at its smallest vertex.  Between nodes the seam edges form **chains**.

Each chain is sampled once, into ``m`` pieces of equal chords with ``m`` the
chain's straightened length over the spacing (a chain that zigzags along the
input's edges is measured by the chords of its samples, not by its zigzag);
its samples lie on the chain's model edges.  A crease or boundary chain whose
even sampling would cut the input's corners by more than :data:`CHORD_TOL` of
the spacing is sampled by the single patch's boundary resampling instead.  Both charts that meet on
a chain take exactly those samples as boundary vertices, so the stitched mesh
is conforming by construction.  The ring of a chart is its boundary loops
walked in order, nodes and samples as they come.

Seam points on a crease or on the model boundary keep their place when the
stitched mesh is relaxed (:mod:`surface.seam_relax`); those on a smooth seam
are free: the seam is a cut of the atlas, not of the surface.
"""

from __future__ import annotations

import bisect
import dataclasses
import math

import numpy as np

from . import _trimesh
from .graph import walk_chains
from .resample import plain_run, sample_run

__all__ = ["Seams", "build_seams", "CHORD_TOL"]

#: On creases and the boundary, the largest distance (a fraction of the spacing)
#: an input vertex may keep from the output chord spanning it: the crease goal of
#: the whole-model benchmark.  Tighter costs uniformity where the crease is a
#: coarse polygon (the resampling's pieces range over 0.8-1.25 of the spacing).
CHORD_TOL = 0.02


@dataclasses.dataclass(frozen=True)
class Seams:
    """The sampled seams of an atlas.

    Attributes
    ----------
    xyz : (S, 3) float64
        Every seam point, nodes first.
    edge : (S, 2) int64
        The model edge ``(u, v)`` holding the point (``(v, v)`` for a node).
    t : (S,) float64
        Fraction along it: ``xyz = (1 - t) V[u] + t V[v]``.
    fixed : (S,) bool
        On a crease or the model boundary (kept in place by the relaxation).
    chains : list of (k,) int64
        The points of every chain in order, its two nodes at the ends.
    rings : list of list of (k,) int64
        Per chart: the seam points of each boundary loop, in loop order.
    n_nodes : int
    """

    xyz: np.ndarray
    edge: np.ndarray
    t: np.ndarray
    fixed: np.ndarray
    chains: list
    rings: list
    n_nodes: int

    @property
    def n_points(self) -> int:
        return len(self.xyz)

    def length(self) -> float:
        """Total 3-D length of the sampled chains."""
        return float(sum(np.linalg.norm(np.diff(self.xyz[c], axis=0), axis=1).sum() for c in self.chains))


def _seam_edges(F, label, pairs, edges, crease, loops):
    """Seam edges (E, 2) and whether each is fixed (crease or boundary)."""
    across = label[pairs[:, 0]] != label[pairs[:, 1]]
    e = [edges[across]]
    fixed = [crease[across]]
    for lp in loops:
        b = np.stack([lp, np.roll(lp, -1)], axis=1)
        e.append(np.sort(b, axis=1))
        fixed.append(np.ones(len(b), dtype=bool))
    return np.concatenate(e), np.concatenate(fixed)


def _nodes(V, F, label, E, fixed, on_boundary, corner):
    """Seam vertices that end chains (see the module notes)."""
    n = len(V)
    deg = np.bincount(E.ravel(), minlength=n)
    pairs = np.unique(np.stack([F.ravel(), np.repeat(label, 3)], axis=1), axis=0)
    charts = np.bincount(pairs[:, 0], minlength=n) + on_boundary
    nodes = set(np.flatnonzero(((deg > 0) & (deg != 2)) | ((deg > 0) & (charts >= 3))).tolist())
    nf = np.bincount(E[fixed].ravel(), minlength=n)
    nodes |= set(np.flatnonzero((deg == 2) & (nf == 1)).tolist())  # crease meets smooth seam
    adj: dict[int, list[int]] = {}
    for a, b in E.tolist():
        adj.setdefault(a, []).append(b)
        adj.setdefault(b, []).append(a)
    cos_corner = np.cos(np.radians(corner))
    for v in np.flatnonzero((deg == 2) & (nf == 2)).tolist():
        a, b = adj[v]
        u, w = V[v] - V[a], V[b] - V[v]
        # sums of products, not ``@``/``norm`` (BLAS, whose kernel is per CPU)
        if np.sum(u * w) < cos_corner * np.sqrt(np.sum(u * u)) * np.sqrt(np.sum(w * w)):
            nodes.add(v)
    return nodes, adj


def _pieces(V, chain, h) -> int:
    """Pieces of a chain: its length measured along the chords of an even sampling."""
    c = np.asarray(chain)
    L = np.linalg.norm(np.diff(V[c], axis=0), axis=1).sum()
    m = max(1, int(round(L / h)))
    for _ in range(2):  # straighten: the chords of m pieces, then m again
        P = _positions(V, c, m)[0]
        m = max(1, int(round(np.linalg.norm(np.diff(P, axis=0), axis=1).sum() / h)))
    return max(m, 3) if chain[0] == chain[-1] else m


def _at(X, cum, s):
    """The point at arc position ``s`` of the polyline X (arc positions ``cum``;
    plain lists: the walk below calls this thousands of times)."""
    i = min(max(bisect.bisect_right(cum, s) - 1, 0), len(X) - 2)
    t = min(max((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0), 1.0)
    a, b = X[i], X[i + 1]
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]))


def _walk_chord(X, cum, s0, c):
    """The first arc position after ``s0`` at straight distance ``c`` from the point
    at ``s0``, or None past the polyline's end."""
    p = _at(X, cum, s0)
    k = bisect.bisect_right(cum, s0)
    while k < len(X) and math.dist(X[k], p) < c:
        k += 1
    if k == len(X):
        return None
    s_a = max(cum[k - 1], s0)  # the crossing lies between s_a and vertex k
    a = _at(X, cum, s_a)
    u = [X[k][i] - a[i] for i in range(3)]
    ap = [a[i] - p[i] for i in range(3)]
    # |a + x u - p| = c for x in [0, 1]: the larger root
    A = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    B = 2.0 * (u[0] * ap[0] + u[1] * ap[1] + u[2] * ap[2])
    C = ap[0] * ap[0] + ap[1] * ap[1] + ap[2] * ap[2] - c * c
    x = (-B + math.sqrt(max(B * B - 4 * A * C, 0.0))) / (2 * A) if A > 0 else 1.0
    return s_a + min(max(x, 0.0), 1.0) * (cum[k] - s_a)


def _chord_walk(X, cum, m, chord):
    """Walk m - 1 chords of length ``chord`` from the start: (arc positions, excess),
    the excess being the straight distance left to the end minus the chord
    (negative when the walk ran out: minus the chords it could not take)."""
    s = [0.0]
    while len(s) < m:
        nxt = _walk_chord(X, cum, s[-1], chord)
        if nxt is None:
            return s, -chord * (m - len(s))
        s.append(nxt)
    return s, math.dist(X[-1], _at(X, cum, s[-1])) - chord


def _equal_chords(X, cum, m):
    """Arc positions of m + 1 points along the polyline X, ends included, whose m
    chords are equal (to 1e-9 where possible), or None where the polyline folds
    back too much.

    The chord is the root of the walk's excess (:func:`_chord_walk`), which falls
    as the chord grows: regula falsi (Illinois) between a chord too short and one
    too long, bisecting when the walk runs out.  Where the excess jumps (a
    chord's end switching between two arms of a zigzag) no chord is exact: the
    complete walk of least excess found is taken."""
    X, cum = X.tolist(), cum.tolist()
    lo, hi = 0.0, 1.5 * cum[-1] / m
    f_lo, f_hi = cum[-1], _chord_walk(X, cum, m, hi)[1]
    side, best, best_f = 0, None, np.inf
    for _ in range(100):
        if f_hi < 0 and f_lo > 0 and -f_hi < hi * m:  # a usable secant
            chord = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        else:
            chord = 0.5 * (lo + hi)
        s, f = _chord_walk(X, cum, m, chord)
        if len(s) == m and abs(f) < best_f:
            best, best_f = np.asarray(s + [cum[-1]]), abs(f)
        if best_f <= 1e-9 * chord:
            return best
        if f > 0:
            lo, f_lo = chord, f
            f_hi = f_hi / 2 if side == 1 else f_hi  # Illinois: the stale end counts half
            side = 1
        else:
            hi, f_hi = chord, f
            f_lo = f_lo / 2 if side == -1 else f_lo
            side = -1
        if hi - lo <= 1e-12 * hi:
            break
    return best


def _weighted_pieces(V, c, spacing, size3d, closed) -> tuple[int, np.ndarray]:
    """Pieces of a chain for a graded size: ``round(∫ ds / size3d / spacing)`` measured
    along the chords of its samples (a chain zigzagging along the input's edges is
    not sampled more densely), and the chain's cumulative ``∫ ds / size3d`` along
    its edges (the measure its samples are even in)."""
    X = V[c]
    seg = np.linalg.norm(np.diff(X, axis=0), axis=1) / size3d(0.5 * (X[1:] + X[:-1]))
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    m = max(1, round(float(cum[-1]) / spacing))
    for _ in range(2):  # straighten, as _pieces does: the chords of m pieces, then m again
        P = _positions(V, c, m, cum=cum)[0]
        m = max(1, round(float(np.sum(np.linalg.norm(np.diff(P, axis=0), axis=1)
                                      / size3d(0.5 * (P[1:] + P[:-1])))) / spacing))
    return (max(m, 3) if closed else m), cum


def _positions(V, c, m, equal_chords=False, chord_tol=None, cum=None):
    """Points along chain ``c``, ends included: (xyz, edge index, t).  m pieces evenly
    spaced in arc length, or, with ``equal_chords``, with equal straight distances
    between neighbours, so a seam that zigzags along the input's edges is not
    sampled more densely than a straight one.  With ``chord_tol`` (a crease or a
    boundary, whose shape the output keeps), where the even sampling leaves an
    input vertex farther than that from the chord spanning it, the pieces are
    placed by the single patch's boundary resampling instead
    (:func:`surface.resample.sample_run`: lengths within 0.8-1.25 of the spacing,
    onto the input's vertices where it turns).  ``cum``: the chain's cumulative
    arc length in another measure (a graded size's), with ``equal_chords`` False."""
    X = V[c]
    if cum is None:
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=1))])
    s = cum[-1] * np.arange(m + 1) / m
    if chord_tol is not None and m > 1 and plain_run(V, c, cum, 0, len(c) - 1, m)[1] > chord_tol:
        u, _, _ = sample_run(V, c, cum, 0, len(c) - 1, m, chord_tol)
        s = np.append(u, cum[-1])
    elif equal_chords and m > 1:
        eq = _equal_chords(X, cum, m)
        if eq is not None and np.all(np.diff(eq) > 0):
            s = eq
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(c) - 2)
    t = np.clip((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0, 1.0)
    P = (1 - t)[:, None] * V[c[i]] + t[:, None] * V[c[i + 1]]
    return P, i, t


def build_seams(V, F, loops, charts, crease_edges, *, spacing, corner_angle=30.0, refine=None,
                size3d=None) -> Seams:
    """Sample the seams of ``charts`` at ``spacing``.

    Parameters
    ----------
    V, F : the model's vertices and faces.
    loops : sequence of (k,) int64
        The model's boundary loops.
    charts : list of :class:`surface.charts.Chart`
    crease_edges : (C, 2) int64
        Edges (smaller vertex first) whose seam points stay put.
    spacing : float
        3-D distance between consecutive samples.
    corner_angle : float
        A crease or boundary turning more than this (degrees) has a node there.
    refine : dict, optional
        Chain index -> factor multiplying its number of pieces (used when a
        chart's ring is not simple at the plain sampling).
    size3d : callable, optional
        A graded 3-D size's shape (:class:`surface.size3d.Size3D` at scale 1):
        chains are then sampled evenly in ``∫ ds / size3d`` with ``spacing`` in
        that measure (the size's scale), and the chord tolerance is
        :data:`CHORD_TOL` of the size at the chain's start times the spacing.

    Returns
    -------
    Seams
    """
    label = np.empty(len(F), dtype=np.int64)
    for i, c in enumerate(charts):
        label[c.faces] = i
    pairs, edges, _ = _trimesh.face_adjacency(V, F)
    ckey = crease_edges[:, 0] * len(V) + crease_edges[:, 1] if len(crease_edges) else np.zeros(0, np.int64)
    crease = np.isin(edges[:, 0] * len(V) + edges[:, 1], ckey)
    E, fixed = _seam_edges(F, label, pairs, edges, crease, loops)
    on_boundary = np.zeros(len(V), dtype=np.int64)
    for lp in loops:
        on_boundary[lp] = 1
    nodes, adj = _nodes(V, F, label, E, fixed, on_boundary, corner_angle)
    chains = walk_chains(adj, nodes)
    fkey = set(map(tuple, E[fixed].tolist()))
    node_list = sorted(nodes)
    node_id = {v: k for k, v in enumerate(node_list)}
    xyz, edge, t, fix = [V[node_list]], [np.stack([node_list, node_list], axis=1)], [np.zeros(len(node_list))], [
        np.array([any((min(v, w), max(v, w)) in fkey for w in adj[v]) for v in node_list], dtype=bool)
    ]
    on_edge: dict = {}
    point_chains = []
    count = len(node_list)
    refine = refine or {}
    for k, chain in enumerate(chains):
        c = np.asarray(chain, dtype=np.int64)
        kept = (min(chain[0], chain[1]), max(chain[0], chain[1])) in fkey
        if size3d is None:
            m = max(1, int(np.ceil(_pieces(V, chain, spacing) * refine.get(k, 1.0))))
            P, i, tt = _positions(V, c, m, equal_chords=True,
                                  chord_tol=CHORD_TOL * spacing if kept and chain[0] != chain[-1] else None)
        else:
            m, cum = _weighted_pieces(V, c, spacing, size3d, chain[0] == chain[-1])
            m = max(1, int(np.ceil(m * refine.get(k, 1.0))))
            tol = CHORD_TOL * spacing * float(size3d(V[c[:1]])[0])
            P, i, tt = _positions(V, c, m, chord_tol=tol if kept and chain[0] != chain[-1] else None,
                                  cum=cum)
        m = len(P) - 1
        ids = [node_id[chain[0]]] + list(range(count, count + m - 1)) + [node_id[chain[-1]]]
        for j in range(1, m):
            on_edge.setdefault((int(c[i[j]]), int(c[i[j] + 1])), []).append((float(tt[j]), count + j - 1))
        xyz.append(P[1:m])
        edge.append(np.stack([c[i[1:m]], c[i[1:m] + 1]], axis=1))
        t.append(tt[1:m])
        fix.append(np.full(m - 1, kept))
        point_chains.append(np.asarray(ids, dtype=np.int64))
        count += m - 1
    rings = [_chart_rings(c, node_id, on_edge) for c in charts]
    return Seams(
        np.concatenate(xyz), np.concatenate(edge).astype(np.int64), np.concatenate(t),
        np.concatenate(fix), point_chains, rings, len(node_list),
    )


def _chart_rings(chart, node_id, on_edge) -> list[np.ndarray]:
    """The seam points of each boundary loop of ``chart``, in loop order."""
    rings = []
    for lp in chart.patch.boundary_loops:
        g = chart.vertices[lp]
        ring = []
        for x, y in zip(g.tolist(), np.roll(g, -1).tolist()):
            if x in node_id:
                ring.append(node_id[x])
            fwd = on_edge.get((x, y), [])
            back = [(1.0 - s, p) for s, p in on_edge.get((y, x), [])]
            ring.extend(p for _, p in sorted(fwd + back))
        rings.append(np.asarray(ring, dtype=np.int64))
    return rings

