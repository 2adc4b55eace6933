"""Spread: Gauss-Seidel sweeps on the spread of the normalised edge lengths that
cannot make the objective worse.

See :mod:`.relax` for the vertex roles, the targets and how every move keeps
the mesh a valid constrained Delaunay triangulation.
"""

import numpy as np
from ._jit import njit

from .cdt import snap_reciprocal, snap_times
from .star import FIXED, TRIES, accept, counted, dead_part, edge, gather, initial_steps
from .star import keep_state, kept_state, legalize_live, live_slots, measure_live, objective_of
from .star import place_at, restore_state
from .star import refresh_sizes, refuse, ring_neighbours, search, stars, star_ok

__all__ = ["spread"]


@njit(cache=True)
def _mean_length(m, hv, href, slots, alive, dead):
    """Mean normalised length over the edges (those of the dead slots: ``dead``,
    :func:`.star.dead_part`)."""
    tv, tw, xy = m.tv, m.tw, m.xy
    s = 0.0
    k = 0
    for t in slots:
        for h in range(3 * t, 3 * t + 3):
            if counted(tw, alive, h):
                L, tgt = edge(xy, tv, hv, href, h)
                s += L / tgt
                k += 1
    return (s + dead[8]) / (k + dead[9])


@njit(cache=True, borrowed=True)
def _star_spread(x, y, ns, nt, SP, TR, L, cbar, grad, ext, want):
    """Sum (l - cbar)^2 over the cached star's spokes with v at (x, y), its
    gradient into ``grad`` if ``want``, and the star's longest and shortest
    normalised edge and largest normalised perimeter into ``ext``."""
    E = 0.0
    gx = 0.0
    gy = 0.0
    lmax = 0.0
    lmin = np.inf
    for i in range(ns):
        dx = x - SP[i, 0]
        dy = y - SP[i, 1]
        Li = np.sqrt(dx * dx + dy * dy)
        L[i] = Li
        ell = Li / SP[i, 2]
        E += (ell - cbar) ** 2
        lmax = max(lmax, ell)
        lmin = min(lmin, ell)
        if want:
            d = 2.0 * (ell - cbar) / (SP[i, 2] * Li)
            gx += d * dx
            gy += d * dy
    pmax = 0.0
    for j in range(nt):
        i = j + 1 if j + 1 < ns else 0
        pmax = max(pmax, (L[j] + L[i] + TR[j, 0]) / TR[j, 1])
    grad[0] = gx
    grad[1] = gy
    ext[0] = lmax
    ext[1] = lmin
    ext[2] = pmax
    return E


@njit(cache=True, borrowed=True)
def _line_search(grid, role, eid, t, ea, ed, v, x0, y0, ux, uy, st, ns, nt, SP, TR, L, cbar,
                 g2, ext, E0, lmax, lmin, pmax, floor):  # fmt: skip
    """(found, x, y, t, step): the first of :data:`TRIES` halvings of step st from
    (x0, y0) along (ux, uy) whose place keeps the star valid (``star_ok`` with
    ``floor``), lowers v's share of the spread below E0 and keeps the star's
    extremes within (lmax, lmin, pmax).  ``grid``: the triangulation's snapping
    grid and its scale's reciprocal (:func:`.cdt.snap_times`)."""
    for _k in range(TRIES):
        x, y, tt = place_at(role, eid, t, ea, ed, v, x0, y0, ux, uy, st)
        x, y = snap_times(grid[0], grid[3], grid[1], grid[2], x, y)
        if star_ok(x, y, x0, y0, ns, nt, SP, floor):
            E1 = _star_spread(x, y, ns, nt, SP, TR, L, cbar, g2, ext, np.bool_(False))
            if E1 < E0 and ext[0] <= lmax and ext[1] >= lmin and ext[2] <= pmax:
                return True, x, y, tt, st
        st *= 0.5
    return False, x0, y0, t[v], st


@njit(cache=True, inline="always")
def _sweep(m, role, eid, t, ea, ed, hv, href, prevb, nextb, step, moved, lmax, lmin, pmax,
           flat, movers, slots, alive, dead):  # fmt: skip
    """One sweep of :func:`spread` over the movable vertices, in order, each move
    keeping its star within the extremes (lmax, lmin, pmax); returns the moves made."""
    xy, tv, tw = m.xy, m.tv, m.tw
    grid = (m.gs, m.gc[0], m.gc[1], snap_reciprocal(m.gs))
    vh, SP, TR, L = stars(m, slots)
    cbar = _mean_length(m, hv, href, slots, alive, dead)
    grad = np.zeros(2)
    g2 = np.zeros(2)
    ext = np.zeros(3)
    moves = 0
    for v in movers:
        if role[v] == FIXED or vh[v] < 0:
            continue
        h0 = vh[v]
        x0 = xy[v, 0]
        y0 = xy[v, 1]
        ns, nt = gather(xy, tv, tw, v, h0, hv, href, SP, TR)
        E0 = _star_spread(x0, y0, ns, nt, SP, TR, L, cbar, grad, ext, np.bool_(True))
        ux, uy, st = search(role, eid, t, ed, prevb, nextb, v, grad, step[v])
        if st == 0.0:
            continue
        ok, x, y, tt, st = _line_search(
            grid, role, eid, t, ea, ed, v, x0, y0, ux, uy, st, ns, nt, SP, TR, L, cbar,
            g2, ext, E0, lmax, lmin, pmax, flat * (href * hv[v]) ** 2,
        )  # fmt: skip
        if ok:
            accept(xy, t, step, moved, v, x, y, tt, st, href, hv[v])
            moves += 1
        else:
            refuse(step, v, href, hv[v])
    return moves


@njit(cache=True)
def spread(m, role, eid, t, ea, ed, hv, href, objective, sweeps, step0, flat,
           restrict=False):  # fmt: skip
    """Gauss-Seidel sweeps on the spread ``sum (l - mean l)**2`` that cannot make
    ``objective`` worse.

    A move must lower the vertex's share of the spread and keep its star's
    longest and shortest edge and largest perimeter within the mesh's present
    extremes, so the objective can only change through the flips of the
    legalisation; a sweep after which it is worse than at the start ends the
    run in the last state that was not (kept and put back by
    :func:`.star.keep_state` and :func:`.star.restore_state`).  Returns the
    number of sweeps kept.  With ``restrict`` the passes cover only the
    triangles the moves can change (:func:`.star.live_slots`).
    """
    prevb, nextb = ring_neighbours(m, role, eid, t, ea)
    alive, slots, movers = live_slots(m, role, restrict)
    dead = dead_part(m, alive, hv, href, np.int64(0))
    lmax, lmin, pmax = measure_live(m, hv, href, slots, dead)
    start = objective_of(objective, lmax, lmin, pmax)
    best_xy, best_t, undo, nu = kept_state(m, t, movers)
    step = initial_steps(m, hv, href, step0)
    moved = np.ones(m.nv, np.bool_)  # moved in the last sweep (all, before the first)
    todo = np.empty(64, np.int32)
    kept = 0
    for sweep in range(sweeps):
        if m.sized:
            refresh_sizes(m, hv, moved)
        moved[:] = False
        moves = _sweep(m, role, eid, t, ea, ed, hv, href, prevb, nextb, step, moved,
                       lmax, lmin, pmax, flat, movers, slots, alive, dead)  # fmt: skip
        todo, slots, woke, undo, nu = legalize_live(m, moved, todo, alive, slots, undo, nu)
        if woke:
            dead = dead_part(m, alive, hv, href, np.int64(0))
        a, b, c = measure_live(m, hv, href, slots, dead)
        if objective_of(objective, a, b, c) > start:
            break  # a flip made it worse: keep the state before this sweep
        lmax, lmin, pmax = a, b, c
        kept = sweep + 1
        nu = keep_state(m, t, movers, best_xy, best_t)
        if moves == 0:
            break
    restore_state(m, t, movers, best_xy, best_t, undo, nu)
    return kept
