"""Descent: Gauss-Seidel line-search sweeps on a p-norm energy of the objective.

See :mod:`.relax` for the vertex roles, the targets, the energy and how every
move keeps the mesh a valid constrained Delaunay triangulation.
"""

import numpy as np
from ._jit import njit

from .cdt import nxt, prv, snap_reciprocal, snap_times
from .objective import MAX_EDGE, MAX_PERIMETER, RATIO
from .star import FIXED, TRIES, accept, counted, dead_part, gather, initial_steps
from .star import keep_state, kept_state, legalize_live, live_slots, measure_live, objective_of
from .star import place_at, restore_state
from .star import pw as _pw
from .star import refresh_sizes, refuse, ring_neighbours, search, stars, star_ok, triangle_terms

__all__ = ["descend"]

#: A vertex whose energy share is below this fraction of the largest share rests.
RELEVANT = 1e-2
#: A descent stage ends after PATIENCE sweeps in a row none of which lowered the
#: objective by the fraction GAIN below the last value that did (slow creep is
#: not worth the sweeps); the defaults of :func:`descend`'s ``patience`` and
#: ``gain`` (:class:`uniform2d.optimize.schedule.Stage` may set others).
PATIENCE = 6
GAIN = 1e-4


@njit(cache=True, inline="always")
def _edge_energy(ell, s, k, p, w_len, w_short, want):
    """(energy, d energy / d length if ``want``) of an edge of normalised length
    ell, target s."""
    q = _pw(ell, k)
    E = 0.0
    d = 0.0
    if w_len > 0.0:
        E += w_len * q
        if want:
            d += w_len * p * q / (ell * s)
    if w_short > 0.0:
        if q == 0.0:  # ell**p underflowed (an edge some 6 % of its target at p = 256)
            return np.inf, 0.0
        E += w_short / q
        if want:
            d -= w_short * p / (q * ell * s)
    return E, d


@njit(cache=True, borrowed=True)
def _star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per, cap):
    """The cached star's share of the energy with v at (x, y) (see :func:`gather`),
    as the line search needs it: the sum stops as soon as it reaches ``cap``
    (every term is >= 0 and a float sum of such terms never decreases, so the
    whole share would not be below ``cap`` either; the value returned is then
    only known to be >= ``cap``).  ``L`` receives the spoke lengths.  The terms
    and their order are :func:`_star_gradient`'s."""
    E = 0.0
    for i in range(ns):
        dx = x - SP[i, 0]
        dy = y - SP[i, 1]
        Li = np.sqrt(dx * dx + dy * dy)
        L[i] = Li
        e, _ = _edge_energy(Li / SP[i, 2], SP[i, 2], k, 0.0, w_len, w_short, np.bool_(False))
        E += e
        if E >= cap:
            return E
    if w_per > 0.0:
        for j in range(nt):
            i = j + 1 if j + 1 < ns else 0
            E += w_per * _pw((L[j] + L[i] + TR[j, 0]) / TR[j, 1], k)
            if E >= cap:
                return E
    return E


@njit(cache=True, borrowed=True)
def _star_gradient(x, y, ns, nt, SP, TR, L, k, p, w_len, w_short, w_per, grad):
    """The cached star's share of the energy with v at (x, y) (see :func:`gather`),
    p = 2**k, and its gradient into ``grad``.  ``L`` receives the spoke
    lengths.  Each spoke's unit vector enters the derivatives of its two
    triangles' perimeters: computed once, the same quotient for both."""
    E = 0.0
    gx = 0.0
    gy = 0.0
    for i in range(ns):
        dx = x - SP[i, 0]
        dy = y - SP[i, 1]
        Li = np.sqrt(dx * dx + dy * dy)
        L[i] = Li
        e, d = _edge_energy(Li / SP[i, 2], SP[i, 2], k, p, w_len, w_short, np.bool_(True))
        E += e
        gx += d * dx / Li
        gy += d * dy / Li
    if w_per > 0.0 and nt > 0:
        ux0 = (x - SP[0, 0]) / L[0]
        uy0 = (y - SP[0, 1]) / L[0]
        ujx = ux0
        ujy = uy0
        for j in range(nt):
            i = j + 1 if j + 1 < ns else 0
            tgt = TR[j, 1]
            pi = (L[j] + L[i] + TR[j, 0]) / tgt
            q = _pw(pi, k)
            E += w_per * q
            d = w_per * p * q / (pi * tgt)
            if i == 0:  # the last triangle of an interior vertex: spoke 0 again
                uix = ux0
                uiy = uy0
            else:
                uix = (x - SP[i, 0]) / L[i]
                uiy = (y - SP[i, 1]) / L[i]
            gx += d * (ujx + uix)
            gy += d * (ujy + uiy)
            ujx = uix
            ujy = uiy
    grad[0] = gx
    grad[1] = gy
    return E


@njit(cache=True, borrowed=True)
def _wake(tv, tw, h0, active):
    """Mark the vertex of outgoing half-edge h0 and all its neighbours active
    (``tv, tw``: the triangulation's arrays)."""
    active[tv[h0]] = True
    h = h0
    while True:
        active[tv[nxt(h)]] = True
        active[tv[prv(h)]] = True
        h = tw[prv(h)]
        if h < 0 or h == h0:
            return


@njit(cache=True)
def _weights(m, role, movable_short, hv, href, k, objective, slots, alive, dead):
    """Weights (w_len, w_short, w_per) of the three energy terms for ``objective``.

    The terms ``S_len = sum l**p``, ``S_short = sum l**-p`` and ``S_per = sum
    pi**p`` are smooth stand-ins for ``lmax**p``, ``lmin**-p`` and ``pmax**p``, so
    ``log`` of an objective that is a product of powers of the extremes is, up to
    the factor 1/p, a weighted sum of their logs: for ``"balanced"``,
    ``(lmax**2 / lmin * pmax)**(1/3)``, it is ``2 log S_len + log S_short + log
    S_per``.  Linearised at the present mesh (log is concave, so a decrease of the
    linearisation is a decrease of the sum) each term is weighted by its exponent
    over its present value.  Equal weights would let the term with the largest
    sum drown the others (at large p the longest edge's term outweighs the
    largest perimeter's by far).  With ``movable_short`` (the optimiser's own
    meshes) ``S_short`` counts only edges with a movable end (``role``): an
    edge fixed at both ends (a short polygon edge, a small hole's) cannot
    change, and would alone set the weight, leaving the movable short edges,
    and the needle triangles they make, unweighed.  Without it (the surface
    layer's charts, whose unsplit boundary edges are all fixed) every edge
    counts: there the edge CV is the target, and it rose by up to 2.6 % on the
    benchmark patches with the fixed edges left out.  An edge so
    short that ``l**p`` underflows makes ``S_short`` infinite and its weight 0
    for that sweep.
    """
    _, _, _, w_len, w_short, w_per = _measure_weights(m, role, movable_short, hv, href, k,
                                                      objective, slots, alive, dead)
    return w_len, w_short, w_per


@njit(cache=True)
def _measure_weights(m, role, movable_short, hv, href, k, objective, slots, alive, dead):
    """:func:`measure` and :func:`_weights` of the present mesh in one pass over its
    live triangles (the dead ones' part is ``dead``, :func:`.star.dead_part`)
    instead of two: the same terms, summed in the same order, so the same
    values.  (lmax, lmin, pmax, w_len, w_short, w_per)."""
    if objective == MAX_EDGE or objective == MAX_PERIMETER:  # weights without a pass
        lmax, lmin, pmax = measure_live(m, hv, href, slots, dead)
        if objective == MAX_EDGE:
            return lmax, lmin, pmax, 1.0, 0.0, 0.0
        return lmax, lmin, pmax, 0.0, 0.0, 1.0
    tv, tw, xy = m.tv, m.tw, m.xy
    every = not movable_short  # every edge, as the objective has it
    lmax = 0.0
    lmin = np.inf
    pmax = 0.0
    s_len = 0.0
    s_short = 0.0
    s_per = 0.0
    for t in slots:
        Ls, ss, per, tgt = triangle_terms(xy, tv, hv, href, t)
        for i in range(3):
            h = 3 * t + i
            # each edge once: a twin's length and target are the same bits
            # (its differences negated, its sum commuted), so the extremes too
            if counted(tw, alive, h):
                ell = Ls[i] / ss[i]
                lmax = max(lmax, ell)
                lmin = min(lmin, ell)
                q = _pw(ell, k)
                s_len += q
                # an edge no move can change (both ends fixed: a short polygon
                # edge, a tiny hole's) would set the short-edge term's weight
                # alone and leave the movable short edges unweighed
                if every or role[tv[h]] != FIXED or role[tv[nxt(h)]] != FIXED:
                    s_short += 1.0 / q if q > 0.0 else np.inf
        pmax = max(pmax, per / tgt)
        s_per += _pw(per / tgt, k)
    lmax, lmin, pmax = max(lmax, dead[0]), min(lmin, dead[1]), max(pmax, dead[2])
    s_len += dead[3]
    if every:  # else the dead edges' short-edge part: fixed at both ends
        s_short += dead[4]
    s_per += dead[5]
    w_short = 1.0 / s_short if s_short > 0.0 else 0.0
    if objective == RATIO:
        return lmax, lmin, pmax, 1.0 / s_len, w_short, 0.0
    return lmax, lmin, pmax, 2.0 / s_len, w_short, 1.0 / s_per


@njit(cache=True, borrowed=True)
def _line_search(grid, role, eid, t, ea, ed, v, x0, y0, ux, uy, st, ns, nt, SP, TR, L, k,
                 w_len, w_short, w_per, E0, floor):  # fmt: skip
    """(found, x, y, t, step): the first of :data:`TRIES` halvings of step st from
    (x0, y0) along (ux, uy) whose place keeps the star valid (``star_ok`` with
    ``floor``) and lowers v's energy share below E0.  ``grid``: the
    triangulation's snapping grid and its scale's reciprocal
    (:func:`.cdt.snap_times`)."""
    for _k in range(TRIES):
        x, y, tt = place_at(role, eid, t, ea, ed, v, x0, y0, ux, uy, st)
        x, y = snap_times(grid[0], grid[3], grid[1], grid[2], x, y)
        if star_ok(x, y, x0, y0, ns, nt, SP, floor):
            E1 = _star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per, E0)
            if E1 < E0:
                return True, x, y, tt, st
        st *= 0.5
    return False, x0, y0, t[v], st


@njit(cache=True, inline="always")
def _sweep(m, role, eid, t, ea, ed, hv, href, prevb, nextb, step, active, moved, k,
           w_len, w_short, w_per, floor, flat, movers, slots):  # fmt: skip
    """One sweep of :func:`descend` over the active vertices, in order; returns
    (moves made, the largest energy share met).  A vertex whose share is below
    ``floor`` rests; so does one whose line search fails, until a neighbour moves."""
    xy, tv, tw = m.xy, m.tv, m.tw
    grid = (m.gs, m.gc[0], m.gc[1], snap_reciprocal(m.gs))
    vh, SP, TR, L = stars(m, slots)
    grad = np.zeros(2)
    p = 2.0**k
    emax = 0.0
    moves = 0
    for v in movers:
        if role[v] == FIXED or vh[v] < 0 or not active[v]:
            continue
        h0 = vh[v]
        x0 = xy[v, 0]
        y0 = xy[v, 1]
        ns, nt = gather(xy, tv, tw, v, h0, hv, href, SP, TR)
        E0 = _star_gradient(x0, y0, ns, nt, SP, TR, L, k, p, w_len, w_short, w_per, grad)
        emax = max(emax, E0)
        if E0 < floor:
            active[v] = False
            continue
        ux, uy, st = search(role, eid, t, ed, prevb, nextb, v, grad, step[v])
        if st == 0.0:
            continue
        ok, x, y, tt, st = _line_search(
            grid, role, eid, t, ea, ed, v, x0, y0, ux, uy, st, ns, nt, SP, TR, L, k,
            w_len, w_short, w_per, E0, flat * (href * hv[v]) ** 2,
        )  # fmt: skip
        if ok:
            accept(xy, t, step, moved, v, x, y, tt, st, href, hv[v])
            moves += 1
            _wake(tv, tw, h0, active)
        else:
            refuse(step, v, href, hv[v])
            active[v] = False
    return moves, emax


@njit(cache=True)
def descend(m, role, eid, t, ea, ed, hv, href, objective, sweeps, k, step0, flat,
            restrict=False, movable_short=False, patience=PATIENCE, gain=GAIN):  # fmt: skip
    """Gauss-Seidel line-search sweeps on the p-norm energy of ``objective``, p = 2**k.

    After each sweep the mesh is legalised and measured; the run ends in the
    best state by the true objective (the start's, if no sweep beat it; kept
    and put back by :func:`.star.keep_state` and :func:`.star.restore_state`),
    whose value it returns with the number of sweeps made.  Each vertex keeps its
    own step, starting at ``step0 * href * hv[v]``: grown 1.5x after an accepted
    move, halved after a refused one.  A vertex whose line search fails rests
    until a neighbour moves (an active set: converged regions cost nothing).  A
    move may not flatten a triangle around the vertex whose doubled area is below
    ``flat * (href * hv[v])**2`` any further.  The run ends early when the
    objective stops improving (``patience`` sweeps in a row none of which lowered it
    by the fraction ``gain``; defaults :data:`PATIENCE`, :data:`GAIN`) or nothing moves.
    A vertex's star is read once per visit (:func:`gather`); the trials of its
    line search only recompute the distances to the moved vertex.  With
    ``restrict`` the passes cover only the triangles the moves can change
    (:func:`.star.live_slots`); without it, every triangle.  ``movable_short``:
    the short-edge weight from the edges with a movable end (:func:`_weights`).
    """
    prevb, nextb = ring_neighbours(m, role, eid, t, ea)
    alive, slots, movers = live_slots(m, role, restrict)
    dead = dead_part(m, alive, hv, href, k)
    # without a size field the mesh a sweep's weights are taken on is the one the
    # sweep before measured: one pass gives both (:func:`_measure_weights`)
    lmax, lmin, pmax, w_len, w_short, w_per = _measure_weights(
        m, role, movable_short, hv, href, k, objective, slots, alive, dead)
    best = objective_of(objective, lmax, lmin, pmax)
    best_xy, best_t, undo, nu = kept_state(m, t, movers)
    step = initial_steps(m, hv, href, step0)
    active = np.ones(m.nv, np.bool_)
    moved = np.ones(m.nv, np.bool_)  # moved in the last sweep (all, before the first)
    todo = np.empty(64, np.int32)
    done = 0
    stale = 0
    mark = best  # the value ``patience`` sweeps must beat by ``gain``
    emax = 0.0
    for sweep in range(sweeps):
        if m.sized:
            refresh_sizes(m, hv, moved)
            w_len, w_short, w_per = _weights(m, role, movable_short, hv, href, k, objective,
                                             slots, alive, dead)
        moved[:] = False
        # a vertex whose share is below RELEVANT times the largest share of the
        # previous sweep cannot change the objective's extremes: skip it
        moves, emax = _sweep(
            m, role, eid, t, ea, ed, hv, href, prevb, nextb, step, active, moved, k,
            w_len, w_short, w_per, RELEVANT * emax, flat, movers, slots,
        )  # fmt: skip
        todo, slots, woke, undo, nu = legalize_live(m, moved, todo, alive, slots, undo, nu)
        if woke:
            dead = dead_part(m, alive, hv, href, k)
        done = sweep + 1
        if m.sized:
            lmax, lmin, pmax = measure_live(m, hv, href, slots, dead)
        else:
            lmax, lmin, pmax, w_len, w_short, w_per = _measure_weights(
                m, role, movable_short, hv, href, k, objective, slots, alive, dead)
        val = objective_of(objective, lmax, lmin, pmax)
        if val < best:
            best = val
            nu = keep_state(m, t, movers, best_xy, best_t)
        if val < mark * (1.0 - gain):
            mark = val
            stale = 0
        else:
            stale += 1
        if moves == 0 or stale >= patience:
            break
    restore_state(m, t, movers, best_xy, best_t, undo, nu)
    return done, best
