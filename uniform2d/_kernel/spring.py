"""Spring rounds: Jacobi moves of all vertices at once along linear springs.

See :mod:`.relax` for the vertex roles, the targets and how every move keeps
the mesh a valid constrained Delaunay triangulation.
"""

import numpy as np
from ._jit import njit

from .cdt import nxt, snap_reciprocal, snap_times
from .predicates import orient2d
from .star import FIXED, FREE, SLIDE, counted, dead_part, legalize_live, live_slots
from .star import refresh_sizes, ring_neighbours, t_of

__all__ = ["spring"]


@njit(cache=True)
def spring(m, role, eid, t, ea, ed, hv, href, iters, dt, pressure, tol, cap, flat,
           restrict=False):  # fmt: skip
    """Jacobi spring rounds (see the module docstring); returns the rounds made.

    A vertex moves by ``dt`` times its spring force, at most ``cap * href * hv[v]``;
    a SLIDE vertex by the tangential part, at most a quarter of its gap to either
    ring neighbour.  Moves that would invert a triangle, or flatten one whose
    doubled area is below ``flat * (href * mean hv)**2`` further, are undone (its
    three vertices stay), then the mesh is legalised.  Stops when the largest
    move is below ``tol * href``.  With ``restrict`` the passes cover only the
    triangles the moves can change (:func:`.star.live_slots`).
    """
    n = m.nv
    xy, tv, tw = m.xy, m.tv, m.tw
    prevb, nextb = ring_neighbours(m, role, eid, t, ea)
    alive, slots, movers = live_slots(m, role, restrict)
    dead = dead_part(m, alive, hv, href, np.int64(0))
    F = np.zeros((n, 2))
    new = np.empty((n, 2))
    newt = t.copy()
    moved = np.ones(n, np.bool_)  # moved in the last round (all, before the first)
    todo = np.empty(64, np.int32)
    it = 0
    for it in range(1, iters + 1):
        if m.sized:
            refresh_sizes(m, hv, moved)
        if it == 1:  # from here on only the movers' flags change
            for v in range(n):
                moved[v] = False
        # rest-length scale c: sum (c * target)^2 = pressure^2 * sum L^2
        sL = 0.0
        sT = 0.0
        for tt in slots:
            for h in range(3 * tt, 3 * tt + 3):  # each edge once
                if not counted(tw, alive, h):
                    continue
                a = tv[h]
                b = tv[nxt(h)]
                L2 = (xy[b, 0] - xy[a, 0]) ** 2 + (xy[b, 1] - xy[a, 1]) ** 2
                s = 0.5 * (hv[a] + hv[b])
                sL += L2
                sT += s * s
        c = pressure * np.sqrt((sL + dead[6]) / (sT + dead[7]))
        for v in movers:  # the forces read: those of fixed vertices are not
            F[v, 0] = 0.0
            F[v, 1] = 0.0
        for tt in slots:
            for h in range(3 * tt, 3 * tt + 3):
                if not counted(tw, alive, h):
                    continue
                a = tv[h]
                b = tv[nxt(h)]
                if role[a] == FIXED and role[b] == FIXED:
                    continue  # no force of a fixed vertex is read (most, deep in a large mesh)
                dx = xy[b, 0] - xy[a, 0]
                dy = xy[b, 1] - xy[a, 1]
                L = np.sqrt(dx * dx + dy * dy)
                f = (c * 0.5 * (hv[a] + hv[b]) - L) / L
                F[b, 0] += f * dx
                F[b, 1] += f * dy
                F[a, 0] -= f * dx
                F[a, 1] -= f * dy
        biggest = _trial(
            m, role, eid, t, ea, ed, hv, href, prevb, nextb, F, dt, cap, new, newt, moved, movers
        )
        _commit(m, role, t, new, newt, moved, hv, flat * href * href, slots, movers)
        # no flip recorded (a negative count): spring rounds keep no best state
        todo, slots, woke, _, _ = legalize_live(m, moved, todo, alive, slots, todo, np.int64(-1))
        if woke:
            dead = dead_part(m, alive, hv, href, np.int64(0))
        if biggest < tol * href:
            break
    return it


@njit(cache=True)
def _trial(m, role, eid, t, ea, ed, hv, href, prevb, nextb, F, dt, cap, new, newt, moved,
           movers):  # fmt: skip
    """Trial places ``new``/``newt`` of all ``movers``; returns the largest move.

    A FREE vertex's move whose squared length is certainly below its cap
    (:func:`_uncapped`: most of them) is made without its length, which only
    the largest move needs; that is then the largest ``np.hypot`` of the few
    whose squared length is within rounding of the largest (:func:`_longest`),
    the same value as the maximum over all of them."""
    xy = m.xy
    # the snapping grid and its scale's reciprocal (:func:`.cdt.snap_times`), read once
    gs, gx, gy, gr = m.gs, m.gc[0], m.gc[1], snap_reciprocal(m.gs)
    biggest = 0.0
    top2 = 0.0  # the largest squared length of the uncapped moves
    for v in movers:
        moved[v] = False
        if role[v] == FIXED:
            continue
        dx = dt * F[v, 0]
        dy = dt * F[v, 1]
        lim = cap * href * hv[v]
        if role[v] == FREE:
            s2 = dx * dx + dy * dy
            if _uncapped(s2, lim):
                new[v, 0], new[v, 1] = snap_times(gs, gr, gx, gy, xy[v, 0] + dx, xy[v, 1] + dy)
                moved[v] = True
                top2 = max(top2, s2)
                continue
            step = np.hypot(dx, dy)
            if step > lim:
                dx *= lim / step
                dy *= lim / step
                step = lim
            if step == 0.0:
                continue
            new[v, 0], new[v, 1] = snap_times(gs, gr, gx, gy, xy[v, 0] + dx, xy[v, 1] + dy)
            moved[v] = True
            biggest = max(biggest, step)
        else:
            e = eid[v]
            ex, ey = ed[e, 0], ed[e, 1]
            L2 = ex * ex + ey * ey
            dtv = (dx * ex + dy * ey) / L2
            tp = t_of(role, t, prevb[v], np.bool_(True))
            tn = t_of(role, t, nextb[v], np.bool_(False))
            gap = 0.25 * min(t[v] - tp, tn - t[v])
            gap = min(gap, lim / np.sqrt(L2))
            dtv = min(max(dtv, -gap), gap)
            if dtv == 0.0:
                continue
            newt[v] = t[v] + dtv
            new[v, 0], new[v, 1] = snap_times(gs, gr, gx, gy, ea[e, 0] + newt[v] * ex,
                                              ea[e, 1] + newt[v] * ey)
            moved[v] = True
            biggest = max(biggest, abs(dtv) * np.sqrt(L2))
    if top2 > 0.0:
        biggest = max(biggest, _longest(role, F, dt, cap, href, hv, movers, top2))
    return biggest


#: An uncapped move's squared length is at least this (its larger component's
#: square is then a normal number, and the float sum within 2 ulps of the exact
#: one) and at most (1 - UNCAPPED) times its cap's square: the move is then
#: certainly shorter than the cap, whatever ``np.hypot`` would round.
UNCAPPED_MIN = 1e-280
UNCAPPED = 1e-12
#: The moves :func:`_longest` measures: squared length within this fraction of
#: the largest (the rounding of the squares and of ``np.hypot``, a few ulps,
#: can change the order of moves only that close).
NEAR_LONGEST = 1e-9


@njit(cache=True, inline="always")
def _uncapped(s2, lim):
    """Whether a move of float squared length ``s2`` is certainly shorter than
    ``lim`` (see :data:`UNCAPPED`)."""
    return UNCAPPED_MIN <= s2 <= (1.0 - UNCAPPED) * (lim * lim)


@njit(cache=True)
def _longest(role, F, dt, cap, href, hv, movers, top2):
    """The largest ``np.hypot`` of the uncapped FREE moves of :func:`_trial`
    (the same moves, recomputed bit for bit), of those whose squared length is
    at least (1 - NEAR_LONGEST) ``top2``: the longest is among them."""
    out = 0.0
    for v in movers:
        if role[v] != FREE:
            continue
        dx = dt * F[v, 0]
        dy = dt * F[v, 1]
        s2 = dx * dx + dy * dy
        if s2 >= (1.0 - NEAR_LONGEST) * top2 and _uncapped(s2, cap * href * hv[v]):
            out = max(out, np.hypot(dx, dy))
    return out


@njit(cache=True, inline="always")
def _commit(m, role, t, new, newt, moved, hv, flat2, slots, movers):
    """Apply the trial places, undoing those that would invert a triangle (exact)
    or flatten one below ``flat2 * mean(hv)**2`` (see :func:`spring`); only the
    live ``slots`` can hold a moved vertex."""
    xy, tv = m.xy, m.tv
    changed = True
    while changed:
        changed = False
        for tt in slots:
            a = tv[3 * tt]
            b = tv[3 * tt + 1]
            c = tv[3 * tt + 2]
            if not (moved[a] or moved[b] or moved[c]):
                continue
            ax, ay = (new[a, 0], new[a, 1]) if moved[a] else (xy[a, 0], xy[a, 1])
            bx, by = (new[b, 0], new[b, 1]) if moved[b] else (xy[b, 0], xy[b, 1])
            cx, cy = (new[c, 0], new[c, 1]) if moved[c] else (xy[c, 0], xy[c, 1])
            det = orient2d(ax, ay, bx, by, cx, cy)
            bad = det <= 0.0
            if not bad:
                hm = (hv[a] + hv[b] + hv[c]) / 3.0
                if det < flat2 * hm * hm:
                    old = orient2d(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1])
                    bad = det < old
            if bad:
                moved[a] = False
                moved[b] = False
                moved[c] = False
                changed = True
    for v in movers:
        if moved[v]:
            xy[v, 0] = new[v, 0]
            xy[v, 1] = new[v, 1]
            if role[v] == SLIDE:
                t[v] = newt[v]
