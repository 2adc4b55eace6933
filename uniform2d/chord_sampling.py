"""Sampling one run of a boundary loop: the plain even sampling and the dynamic programme.

A *run* is the part of a boundary loop between two kept corners (a whole loop
if it has none).  :func:`plain_run` spaces its ring vertices evenly;
:func:`sample_run` moves them, where the plain sampling leaves the input
boundary farther than a chord-height tolerance from the ring, by a dynamic
programme over candidate positions.  Any dimension: the planar outlines of
:mod:`uniform2d.outline` and the surface layer's 3-D boundary loops use it alike.
"""

from __future__ import annotations

import itertools

import numpy as np
import shapely

from . import libm
from ._kernel.chords import chord_heights
from .segment_distance import point_segment_distance

__all__ = ["plain_run", "run_counts", "sample_run", "straightened_lengths"]

#: Candidate positions per plain spacing (besides the input vertices).
_GRID = 16
#: Ring edges stay within these factors of their run's plain spacing.
_SHORTEST, _LONGEST = 0.8, 1.25


def run_counts(lengths, h, closed_single):
    """Pieces per run: round(length / h), at least 1 (3 for a loop that is one
    run), at least 3 over the loop."""
    m = np.maximum(1, np.round(np.asarray(lengths) / h)).astype(np.int64)
    if closed_single:
        m = np.maximum(m, 3)
    while m.sum() < 3:  # at least a triangle per ring
        m[int(np.argmax(np.asarray(lengths) / m))] += 1
    return m


def _run_positions(V, lp, a, nv, off, u, rv):
    """3-D points at arc offsets ``u`` of a run (``rv``: the run vertex a point is
    on, or -1), linear on the input edges like the ring vertices."""
    seg = np.clip(np.searchsorted(off, u, side="right") - 1, 0, nv - 1)
    t = (u - off[seg]) / (off[seg + 1] - off[seg])
    n = len(lp)
    P = (1 - t)[:, None] * V[lp[(a + seg) % n]] + t[:, None] * V[lp[(a + seg + 1) % n]]
    on = rv >= 0
    P[on] = V[lp[(a + rv[on]) % n]]
    return P


def plain_run(V, lp, ext, a, nv, m):
    """The plain even sampling of a run and its chord height.

    Returns
    -------
    u : (m,) float64
        Arc offsets of the samples from the run start (the run's end excluded).
    height : float
        Largest 3-D distance of an input boundary vertex from the ring edge that
        spans it.
    """
    off = ext[a : a + nv + 1] - ext[a]
    L = float(off[-1])
    u = L * np.arange(m) / m
    if nv < 2:
        return u, 0.0
    ue = np.concatenate([u, [L]])
    rv = np.full(m + 1, -1)
    rv[0], rv[-1] = 0, nv
    P = _run_positions(V, lp, a, nv, off, ue, rv)
    inner = off[1:-1]
    g = np.searchsorted(ue, inner, side="right") - 1  # the ring edge spanning each
    d = point_segment_distance(V[lp[(a + np.arange(1, nv)) % len(lp)]], P[g], P[g + 1])
    return u, float(d.max())


def _candidates(V, lp, a, nv, off, m, grid=_GRID):
    """The candidate positions of a run: a grid of ``m * grid`` even steps plus
    the input vertices nearest to it.  Returns their arc offsets ``u``, run
    vertex ``rv`` (or -1), 3-D points ``C`` and ``excess``: for each gap between
    candidates, the largest distance of a skipped input vertex from its chord."""
    L = float(off[-1])
    G = m * grid
    ug = L * np.arange(1, G) / G  # the run's ends are added as vertices below
    # input vertices that are the nearest vertex of some grid point (all of them
    # unless the input is finer than the grid) join the candidates
    inner = off[1:-1]
    if len(inner):
        k = np.clip(np.searchsorted(inner, ug), 1, len(inner))
        kr = np.minimum(k, len(inner) - 1)
        near = np.where(np.abs(ug - inner[k - 1]) <= np.abs(inner[kr] - ug), k - 1, kr)
        vsel = np.unique(near) + 1  # run vertex index (0 = start)
    else:
        vsel = np.zeros(0, dtype=np.int64)
    vidx = np.concatenate([[0], vsel, [nv]])
    gkeep = ~np.isin(ug, off[vidx])
    u = np.concatenate([ug[gkeep], off[vidx]])
    rv = np.concatenate([np.full(int(gkeep.sum()), -1), vidx])  # run vertex or -1
    order = np.lexsort((rv, u))
    u, rv = u[order], rv[order]
    C = _run_positions(V, lp, a, nv, off, u, rv)
    # input vertices that are not candidates: their distance to the chord between the
    # candidates around them bounds how far a longer chord may be from them
    excess = np.zeros(len(u))
    rest = np.setdiff1d(np.arange(1, nv), rv[rv >= 0])
    if len(rest):
        g = np.searchsorted(u, off[rest], side="right") - 1
        d = point_segment_distance(V[lp[(a + rest) % len(lp)]], C[g], C[g + 1])
        np.maximum.at(excess, g, d)
    return u, rv, C, excess, len(rest) > 0


def _chord_heights(u, on, C, excess, skipped, lo, hi):
    """W, the most candidates a chord of admissible length spans, and H[d, i]: the
    largest distance of the input boundary between the ends of chord (i, i + d)
    from it (inf if its length is not within [lo, hi])."""
    nc = len(u)
    W = max(1, int(np.max(np.searchsorted(u, u + hi, side="right") - 1 - np.arange(nc))))
    # the largest distance from a chord is at an input vertex (distance to a segment
    # is convex along each input edge), so the candidates on input vertices are the
    # points to check, and all of them when some input vertices are not candidates
    # (those are then covered by ``excess``)
    check = np.flatnonzero(on) if not skipped else np.arange(nc)
    if C.shape[1] != 2:
        return W, _heights_any_dimension(u, C, check, excess, W, lo, hi)
    return W, chord_heights(np.ascontiguousarray(u, dtype=np.float64), np.ascontiguousarray(C),
                            check, np.ascontiguousarray(excess, dtype=np.float64), W,
                            float(lo), float(hi))


def _heights_any_dimension(u, C, check, excess, W, lo, hi):
    """:func:`uniform2d._kernel.chords.chord_heights` in numpy, for C in any
    dimension (the same bits in the plane)."""
    nc = len(u)
    i_all = np.arange(nc)
    pi, pd = [], []
    for d in range(1, W + 1):
        ell = u[d:] - u[:-d]
        sel = np.flatnonzero((ell >= lo) & (ell <= hi))
        pi.append(i_all[sel])
        pd.append(np.full(len(sel), d))
    pi, pd = np.concatenate(pi), np.concatenate(pd)
    first = np.searchsorted(check, pi, side="right")
    count = np.searchsorted(check, pi + pd, side="left") - first
    hmax = np.zeros(len(pi))
    emax = excess[pi]
    for e in range(int(count.max(initial=0))):
        s = np.flatnonzero(count > e)
        k = check[first[s] + e]
        dist = point_segment_distance(C[k], C[pi[s]], C[pi[s] + pd[s]])
        hmax[s] = np.maximum(hmax[s], dist)
        emax[s] = np.maximum(emax[s], excess[k])
    H = np.full((W + 1, nc), np.inf)
    H[pd, pi] = hmax + emax
    return H


def _blocks(u, H, W, lo, hi):
    """The candidates in order, in blocks shorter than ``lo`` (no admissible chord
    inside a block, so a block depends on earlier ones only): per block its
    candidates J, their predecessors I, chord lengths, admissibility and heights."""
    nc = len(u)
    blocks = []
    j0 = 1
    while j0 < nc:
        rel = u[j0 + 1 : j0 + W + 1] - u[j0]  # same arithmetic as the length test
        hit = np.flatnonzero(rel >= lo)
        j1 = j0 + 1 + int(hit[0] if len(hit) else len(rel))
        J = np.arange(j0, min(j1, nc))
        d = np.arange(1, W + 1)
        I = J[:, None] - d[None, :]
        ell = u[J][:, None] - u[np.maximum(I, 0)]
        ok = (I >= 0) & (ell >= lo) & (ell <= hi)
        hgt = np.where(ok, H[d[None, :], np.maximum(I, 0)], np.inf)
        blocks.append((J, np.maximum(I, 0), ell, ok, hgt))
        j0 = J[-1] + 1
    return blocks


def _best_path(blocks, nc, tol, href):
    """The dynamic programme: candidate indices of the chosen ring vertices."""
    # first pass: the smallest achievable largest chord height (within tol unless the
    # length bounds forbid it somewhere) ...
    bestH = np.full(nc, np.inf)
    bestH[0] = 0.0
    for J, I, ell, ok, hgt in blocks:
        bestH[J] = np.min(np.maximum(bestH[I], hgt), axis=1)
    bound = max(tol, bestH[-1])
    # ... second pass: among the samplings within that height, the most even one:
    # least sum of log^2(chord length / href), zero for the plain even sampling
    bestC = np.full(nc, np.inf)
    prev = np.full(nc, -1, dtype=np.int64)
    bestC[0] = 0.0
    for J, I, ell, ok, hgt in blocks:
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(ok & (hgt <= bound), bestC[I] + libm.log(ell / href) ** 2, np.inf)
        b = np.argmin(c, axis=1)
        bestC[J] = c[np.arange(len(J)), b]
        prev[J] = np.where(np.isfinite(bestC[J]), I[np.arange(len(J)), b], -1)
    path = [nc - 1]
    while path[-1] > 0:
        path.append(int(prev[path[-1]]))
    return np.array(path[::-1])


def sample_run(V, lp, ext, a, nv, m, tol, bounds=(_SHORTEST, _LONGEST), grid=_GRID):
    """Sample one run of a boundary loop.

    The candidate positions are a grid of ``m * grid`` even steps plus the input
    vertices; a dynamic programme over them picks the ring vertices so that every
    ring edge is between ``bounds[0]`` and ``bounds[1]`` times ``L / m`` long (in
    arc length; by default 0.8 and 1.25), no input boundary vertex is farther than ``tol`` from the ring
    edge that spans it (or than the least largest distance achievable within
    those lengths, if that is more), and, among those samplings, the sum of
    ``log(edge / (L / m)) ** 2`` is least: the plain even sampling if it meets
    the tolerance.

    Parameters
    ----------
    V : (N, D) float64
        The loop's points (chord heights are distances in D dimensions).
    lp : (n,) int64
        The loop.
    ext : (2n + 1,) float64
        Cumulative arc length of the loop in the resampling measure, run twice round.
    a, nv : int
        The run starts at loop position ``a`` and ends ``nv`` input edges later.
    m : int
        Piece count of the plain even sampling; its spacing ``L / m`` is the target.
    tol : float
        Chord-height tolerance (a length).
    bounds : (float, float)
        The ring edges' shortest and longest lengths, as fractions of ``L / m``.
    grid : int
        Candidate positions per plain spacing (besides the input vertices).

    Returns
    -------
    u : (k,) float64
        Arc offsets of the samples from the run start (first is 0, the end excluded).
    vert : (k,) int64
        Loop position (in ``0 .. 2n``) of the input vertex a sample sits on, or -1.
    height : float
        Largest distance of the input boundary from a ring edge of the run.
    """
    off = ext[a : a + nv + 1] - ext[a]  # offsets of the run's input vertices
    href = float(off[-1]) / m
    u, rv, C, excess, skipped = _candidates(V, lp, a, nv, off, m, grid)
    lo, hi = href * bounds[0], href * bounds[1]
    W, H = _chord_heights(u, rv >= 0, C, excess, skipped, lo, hi)
    path = _best_path(_blocks(u, H, W, lo, hi), len(u), tol, href)
    height = float(np.max(H[np.diff(path), path[:-1]]))
    path = path[:-1]  # the run's end is the next run's start
    return u[path], np.where(rv[path] >= 0, a + rv[path], -1), height


def straightened_lengths(pts, seg, eps):
    """Per edge of the polyline ``pts`` (k + 1, 2) of edge lengths ``seg`` (k,): its
    length scaled so that each stretch between the vertices Douglas-Peucker keeps at
    ``eps`` measures its chord (a zigzag finer than ``eps`` adds no length)."""
    simple = shapely.get_coordinates(shapely.simplify(shapely.LineString(pts), eps, preserve_topology=False))
    marks = np.zeros(len(pts), dtype=bool)
    j = 0
    for i in range(len(pts)):  # the kept vertices, in order (a closed run repeats its start)
        if j < len(simple) and pts[i, 0] == simple[j, 0] and pts[i, 1] == simple[j, 1]:
            marks[i] = True
            j += 1
    marks[0] = marks[-1] = True
    at = np.flatnonzero(marks)
    out = seg.copy()
    for p, q in itertools.pairwise(at):
        arc = seg[p:q].sum()
        chord = float(np.hypot(*(pts[q] - pts[p])))
        if arc > 0 and chord > 0:
            out[p:q] = seg[p:q] * (chord / arc)
    return out
