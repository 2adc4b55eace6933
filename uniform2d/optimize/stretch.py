"""Starts of rows stretched between parallel sides of P.

A hexagonal lattice of the target size fits a strip between two parallel
polygon edges only by chance: the rows stop a fraction of a spacing short of
the far side, and that layer keeps its long edges through the point moves.
:func:`row_start` puts rows parallel to a polygon edge whose spacing divides
the distance between every two consecutive levels of the edges parallel to
it exactly, and along every row, between the places where it meets the
boundary, points at a spacing that divides that piece of the row exactly
(staggered by half a spacing from row to row where the lattice would be).
The count is made exact by one point more or less on some of the rows
(:func:`_exact`), spread over the mesh, not by dropping or adding points
where the lattice meets the boundary.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import shapely

from .._kernel.distance import to_segments
from ..geometry import polygon_edges
from ..polygon import Polygon
from . import schedule

__all__ = ["row_edges", "row_start"]

#: Edges whose directions differ by less than this (sine of the angle) are
#: parallel for a row start: a choice of where rows go, not a predicate.
PARALLEL = 1e-9
#: Row spacings tried, relative to the lattice's (h sqrt(3) / 2): the one whose
#: count needs the fewest rows with a point more or fewer wins (the first of
#: equals), a row a few per cent closer costing less than a shear line.
ROW_STRETCH = (1.0, 0.98, 1.02, 0.96, 1.04, 0.94, 1.06)


def _levels(polygon: Polygon, e: int):
    """(unit direction of edge e, its inward normal, the sorted distinct levels
    (along the normal, from edge e's line) of every ring edge parallel to e)."""
    a, d, L = polygon_edges(polygon)
    u = d[e] / L[e]
    nrm = np.array([-u[1], u[0]])
    sine = np.abs(d[:, 0] * u[1] - d[:, 1] * u[0]) / L
    lev = (a[sine <= PARALLEL] - a[e]) @ nrm
    lev = np.sort(lev)
    keep = np.r_[True, np.diff(lev) > PARALLEL * max(1.0, float(np.ptp(lev)))]
    return u, nrm, lev[keep]


def row_edges(polygon: Polygon) -> list[int]:
    """The ring edges a row start can follow: longest first, one per direction,
    only directions with at least two parallel edges at different levels (the
    rows are stretched between those), and none for polygons with segments or
    fixed points (their pieces are not rows)."""
    if polygon.has_constraints:
        return []
    _, d, L = polygon_edges(polygon)
    out, seen = [], []
    for e in np.lexsort((np.arange(len(L)), -L)):
        u = d[e] / L[e]
        if any(abs(u[0] * w[1] - u[1] * w[0]) <= PARALLEL for w in seen):
            continue
        seen.append(u)
        if len(_levels(polygon, int(e))[2]) >= 2:
            out.append(int(e))
    return out


def _row_levels(lev: np.ndarray, lo: float, hi: float, t0: float) -> np.ndarray:
    """Row levels: between consecutive parallel levels an exact division of the gap
    into round(gap / t0) rows' spacings, beyond the outermost ones steps of t0
    up to the polygon's extent (lo, hi); the parallel levels themselves too."""
    rows = [lev]
    for y0, y1 in itertools.pairwise(lev):
        q = max(1, round((y1 - y0) / t0))
        rows.append(y0 + (y1 - y0) * np.arange(1, q) / q)
    below = lev[0] - t0 * np.arange(1, int((lev[0] - lo) / t0) + 1)
    above = lev[-1] + t0 * np.arange(1, int((hi - lev[-1]) / t0) + 1)
    rows += [below[below > lo], above[above < hi]]
    return np.sort(np.concatenate(rows))


def _pieces(polygon: Polygon, shp, origin, u, nrm, levels, reach: float):
    """The pieces of every row strictly inside P: (row index, start, end) with
    start and end along u from ``origin`` (shapely's intersection)."""
    out = []
    tiny = 1e-9 * reach
    for j, y in enumerate(levels):
        p0 = origin + nrm * y - u * reach
        p1 = origin + nrm * y + u * reach
        inter = shapely.intersection(shp, shapely.LineString([p0, p1]))
        parts = getattr(inter, "geoms", [inter])
        for g in parts:
            if g.geom_type != "LineString" or g.is_empty:
                continue
            c = np.asarray(g.coords)
            s = np.sort((c - origin) @ u)
            mid = origin + nrm * y + u * (0.5 * (s[0] + s[-1]))
            inside = shapely.contains_xy(shp, mid[0], mid[1])
            # a row along a parallel edge, inside by rounding only, is not inside
            if s[-1] > s[0] and inside and shp.boundary.distance(shapely.Point(mid)) > tiny:
                out.append((j, float(s[0]), float(s[-1])))
    return out


def _on_boundary(polygon: Polygon, q: np.ndarray, near: float):
    """(edge, parameter) of the ring edge point q lies on, or None within ``near``
    of a vertex (a crossing there would make a sliver with it)."""
    a, d, L = polygon_edges(polygon)
    t = np.clip(((q - a) * d).sum(axis=1) / L**2, 0.0, 1.0)
    dist = np.hypot(*(a + d * t[:, None] - q).T)
    e = int(np.argmin(dist))
    if min(t[e], 1.0 - t[e]) * L[e] <= near:
        return None
    return e, float(t[e])


def _exact(k: np.ndarray, inner: np.ndarray, lengths: np.ndarray, want: int) -> np.ndarray:
    """k with one piece more (or fewer) on the row pieces of the longest (shortest)
    spacing until the pieces' points (k - 1 + 2 * phase each, ``inner`` the
    count at k) come to ``want``; among equal spacings every so many, in order,
    so that the extra points spread over the mesh."""
    k = k.copy()
    r = want - int(inner.sum())
    if r == 0:
        return k
    step = 1 if r > 0 else -1
    gap = lengths / k
    key = np.round(gap / gap.max(), 9) * step
    ok = k + step >= 1
    idx = np.flatnonzero(ok)
    order = idx[np.lexsort((idx, -key[idx]))]
    r = min(abs(r), len(order))
    cut = key[order[r - 1]]
    above = order[key[order] > cut]
    tied = order[key[order] == cut]
    m = r - len(above)
    chosen = np.concatenate([above, tied[(np.arange(m) * len(tied)) // m]]) if m else above
    k[chosen] += step
    return k


def row_start(polygon: Polygon, n: int, h: float, edge: int, exact: bool = True,
              stretches=None):
    """The sites of a row start along ring edge ``edge`` (one of :func:`row_edges`):
    (sites, polygon edge of each or -1, which stay put, number on the boundary),
    as :func:`uniform2d.optimize.seed.start` returns; exactly n sites, or None
    where the rows cannot give n (too few points for the rows' crossings).

    Points on the boundary: where the rows cross an edge that is not parallel
    to them (split further where the crossings are more than 1.5 spacings
    apart), and every parallel edge split evenly at the along-row spacing.
    ``exact`` False: the layout nearest to n sites without the rows of a point
    more or fewer (a reference of what plain rows reach, as
    ``benchmarks/bench_uniform.py`` makes).  ``stretches``: the row spacings
    tried (default :data:`ROW_STRETCH`).
    """
    best = None
    for stretch in ROW_STRETCH if stretches is None else stretches:
        defects, made = _rows_at(polygon, n, h, edge, stretch * h * math.sqrt(3.0) / 2.0, exact)
        if made is not None and (best is None or defects < best[0]):
            best = (defects, made)
    return None if best is None else best[1]


def _rows_at(polygon: Polygon, n: int, h: float, edge: int, t0: float, exact: bool = True):
    """:func:`row_start` with rows about t0 apart: (how many row pieces took a
    point more or fewer to make the count exact, the start or None)."""
    a, d, _ = polygon_edges(polygon)
    u, nrm, lev = _levels(polygon, edge)
    origin = a[edge]
    V = polygon.vertices
    vl = (V - origin) @ nrm
    levels = _row_levels(lev, float(vl.min()), float(vl.max()), t0)
    reach = 2.0 * float(np.ptp(V, axis=0).max()) + float(np.abs(V - origin).max())
    pieces = _pieces(polygon, polygon.to_shapely(), origin, u, nrm, levels, reach)
    if not pieces:
        return 0, None
    frame = (origin, u, nrm, levels)
    bpts, beid = _crossings(polygon, pieces, frame, h)
    runs = _runs(polygon, pieces, frame)
    want = n - len(bpts)
    missing, k, phase = _along_spacing(runs, want, h)
    if exact:
        lengths = np.array([s1 - s0 for _, s0, s1, _ in runs])
        k = _exact(k, k - 1 + phase, lengths, want)
    ipts, ppts, peid = _run_points(polygon, runs, k, phase, frame)
    bpts = np.concatenate([bpts, ppts])
    beid = np.concatenate([beid, peid])
    if exact and len(bpts) + len(ipts) != n:
        return 0, None
    deep = to_segments(ipts, a, a + d, 2.0 * schedule.BAND * h) > schedule.BAND * h
    frozen = np.concatenate([np.zeros(len(bpts), bool), deep])
    edges = np.concatenate([beid, np.full(len(ipts), -1, np.int64)])
    return missing, (np.concatenate([bpts, ipts]), edges, frozen, len(bpts))


def _crossings(polygon: Polygon, pieces, frame, h: float):
    """The boundary points of the edges the row pieces cross (:func:`_boundary`):
    where the pieces meet the boundary is fixed, whatever the along-row spacing."""
    a, d, _ = polygon_edges(polygon)
    origin, u, nrm, levels = frame
    cross, ceid, ct = [], [], []
    for j, s0, s1 in pieces:
        for s in (s0, s1):
            hit = _on_boundary(polygon, origin + nrm * levels[j] + u * s, 0.25 * h)
            if hit is not None:
                cross.append(a[hit[0]] + d[hit[0]] * hit[1])
                ceid.append(hit[0])
                ct.append(hit[1])
    return _boundary(polygon, np.array(cross).reshape(-1, 2), np.array(ceid, np.int64),
                     np.array(ct), u, h)


def _runs(polygon: Polygon, pieces, frame) -> list:
    """The runs of points, (row, start, end, polygon edge or -1) along the rows:
    the row pieces inside (-1), then the edges parallel to the rows (on the row
    nearest each)."""
    a, d, L = polygon_edges(polygon)
    origin, u, nrm, levels = frame
    runs = [(j, s0, s1, -1) for j, s0, s1 in pieces]
    sine = np.abs(d[:, 0] * u[1] - d[:, 1] * u[0]) / L
    for e in np.flatnonzero(sine <= PARALLEL):
        y = float((a[e] - origin) @ nrm)
        j = int(np.argmin(np.abs(levels - y)))
        sa, sb = float((a[e] - origin) @ u), float((a[e] + d[e] - origin) @ u)
        runs.append((j, min(sa, sb), max(sa, sb), int(e)))
    return runs


def _along_spacing(runs, want: int, h: float):
    """(how far the nearest count is from ``want``, pieces per run, stagger per
    run) at the along-row spacing, bisected between 0.6 h and 1.6 h, whose
    points are nearest ``want``."""
    lengths = np.array([s1 - s0 for _, s0, s1, _ in runs])
    starts = np.array([s0 for _, s0, _, _ in runs])
    rowj = np.array([j for j, _, _, _ in runs])

    def layout(s):
        """(points of every run, pieces, stagger) at along-row spacing s."""
        k = np.maximum(1, np.rint(lengths / s)).astype(np.int64)
        # half a spacing off where a lattice of spacing s from the edge's start is
        f = (starts / s - 0.5 * rowj) % 1.0
        phase = ((f >= 0.25) & (f < 0.75)).astype(np.int64)
        return k - 1 + phase, k, phase

    lo_s, hi_s = 0.6 * h, 1.6 * h
    best = None
    for _ in range(40):
        mid = 0.5 * (lo_s + hi_s)
        got, k, phase = layout(mid)
        c = int(got.sum())
        if best is None or abs(c - want) < abs(best[0] - want):
            best = (c, k, phase)
        if c == want:
            break
        if c > want:
            lo_s = mid
        else:
            hi_s = mid
    c, k, phase = best
    return abs(c - want), k, phase


def _run_points(polygon: Polygon, runs, k, phase, frame):
    """(points inside, points on the parallel edges, their edges): ``k[i]``
    pieces a run, its points at the pieces' ends or (staggered) middles."""
    a, d, _ = polygon_edges(polygon)
    origin, u, nrm, levels = frame
    ipts, ppts, peid = [], [np.empty((0, 2))], [np.empty(0, np.int64)]
    for (j, s0, s1, e), kk, ph in zip(runs, k, phase):
        i = (np.arange(kk) + 0.5) if ph else np.arange(1, kk, dtype=np.float64)
        s = s0 + (s1 - s0) * i / kk
        if e < 0:
            ipts.append(origin + nrm * levels[j] + u * s[:, None])
            continue
        sa = float((a[e] - origin) @ u)
        t = (s - sa) / (float((a[e] + d[e] - origin) @ u) - sa)
        ppts.append(a[e] + d[e] * np.sort(t)[:, None])
        peid.append(np.full(len(t), e, np.int64))
    ipts = np.concatenate(ipts) if ipts else np.empty((0, 2))
    return ipts, np.concatenate(ppts), np.concatenate(peid)


def _boundary(polygon: Polygon, cross, ceid, ct, u, h: float):
    """The boundary points of the edges the rows cross (not parallel to them): the
    crossings, and between two crossings (or a crossing and a vertex) more than
    1.5 h apart, evenly spaced points splitting them."""
    a, d, L = polygon_edges(polygon)
    sine = np.abs(d[:, 0] * u[1] - d[:, 1] * u[0]) / L
    pts, eid = [], []
    for e in np.flatnonzero(sine > PARALLEL):
        t = np.sort(np.r_[0.0, ct[ceid == e], 1.0])
        t = np.unique(t)
        out = []
        for t0, t1 in itertools.pairwise(t):
            m = max(1, round((t1 - t0) * L[e] / h)) if (t1 - t0) * L[e] > 1.5 * h else 1
            out.append(t0 + (t1 - t0) * np.arange(m) / m)
        tt = np.concatenate(out)[1:]
        pts.append(a[e] + d[e] * tt[:, None])
        eid.append(np.full(len(tt), e, np.int64))
    if not pts:
        return np.empty((0, 2)), np.empty(0, np.int64)
    return np.concatenate(pts), np.concatenate(eid)
