"""Moving the vertices of a constrained Delaunay triangulation, in place.

The optimiser (:mod:`uniform2d.optimize`) improves a mesh by moving its points;
this module does the moving on a :class:`~uniform2d._kernel.cdt.Tri` (flat
half-edge arrays, see ``cdt``) without ever rebuilding it.

Vertex roles (``role[v]``)
--------------------------
``FIXED``  never moves (the polygon's vertices).
``FREE``   an interior point; moves in the plane.
``SLIDE``  a boundary point on polygon edge ``eid[v]``: its place is
           ``ea[e] + t[v] * ed[e]`` and it moves by changing ``t[v]``, never past
           its neighbours along the ring (so the boundary chain keeps its order).

Every move keeps the mesh valid, exactly
----------------------------------------
Every trial place is first rounded to what the caller's coordinates hold
(:func:`cdt.snap`; the identity near the origin), so the points the optimiser
hands back are exactly the ones decided on here; a SLIDE vertex may then sit a
rounding off its edge's line, and stays on its constraint by index.
A move is only made if every triangle around the moved vertex stays strictly
counter-clockwise (exact ``orient2d``).  With the boundary chain in order that
means the triangles still tile P, so nothing has to be located again.  After a
round of moves, :func:`cdt.legalize_stack` (started from the edges around the
moved vertices) makes every unconstrained edge locally
Delaunay with the exact ``incircle`` (Lawson flips never touch a constrained,
i.e. boundary, edge), so after every round the mesh is again the constrained
Delaunay triangulation of its points.

Targets
-------
``hv[v]`` is the target size at vertex v relative to ``href`` (1 everywhere for
a uniform mesh; the size field for a graded one), refreshed from the Tri's size
grid after each round.  An edge's target is ``href * (hv[a] + hv[b]) / 2``, its
normalised length ``l = L / target``; a triangle's normalised perimeter is its
perimeter over the sum of its three edge targets.

Three ways to move
------------------
:func:`spring`   Jacobi rounds of linear springs whose rest lengths are the
                 targets scaled so that their root mean square equals the
                 edges' (times ``pressure``): a least-squares pull towards equal
                 normalised lengths (small spread, the edge CV).
:func:`descend`  Gauss-Seidel sweeps over the vertices, each moved by a
                 backtracking line search on its share of the energy
                 ``w_len sum l**p + w_short sum l**-p`` over edges (and
                 ``w_per sum pi**p`` over perimeters): with large p that is the
                 max/min of the objective, decreased one vertex at a time (a
                 decrease of a vertex's share is a decrease of the total).  The
                 weights (:func:`_weights`, once per sweep) make the energy the
                 linearised log of the objective, so no term drowns the others.
                 The best state by the true objective is kept.
:func:`spread`   Gauss-Seidel sweeps on ``sum (l - mean l)**2`` (the spread, the
                 edge CV), a move accepted only if the star's longest and
                 shortest edge and largest perimeter stay within the mesh's
                 extremes, so the objective is held while the spread drops.

Besides validity, moves obey a quality guard (a float test, not a predicate): no
triangle around the moved vertex may become flatter than ``flat * target**2``
(twice its area) unless it was flatter before, so slivers cannot form but can heal.

Around a vertex v the kernel turns counter-clockwise with ``h -> tw[prv(h)]``
starting from an outgoing half-edge (``vseg[v]`` on the boundary, where the turn
ends at -1)::

            c
           / \\         h = v->b, prv(h) = c->v, tw[prv(h)] = v->c: the next
          /   \\        outgoing half-edge, counter-clockwise around v
         v --h-> b
"""

import numpy as np
from numba import njit

from .cdt import legalize_stack, nxt, prv, snap
from .heap import grown
from .insert import size_at
from .objective import MAX_EDGE, MAX_PERIMETER, RATIO, combine
from .predicates import orient2d

__all__ = ["FIXED", "FREE", "SLIDE", "spring", "descend", "spread", "measure", "refresh_sizes"]

FIXED, FREE, SLIDE = 0, 1, 2
#: A vertex whose energy share is below this fraction of the largest share rests.
RELEVANT = 1e-2
#: A descent stage ends after PATIENCE sweeps in a row none of which lowered the
#: objective by the fraction GAIN below the last value that did (slow creep is
#: not worth the sweeps).
PATIENCE = 6
GAIN = 1e-4
#: Halvings of the step a line search tries before the vertex gives up.
TRIES = 8


@njit(cache=True)
def refresh_sizes(m, hv, which):
    """hv[v] = the size field at vertex v (1 without a field), for each v with
    ``which[v]`` (the vertices moved since the last refresh)."""
    for v in range(m.nv):
        if which[v]:
            hv[v] = size_at(m, m.xy[v, 0], m.xy[v, 1])


@njit(cache=True, inline="always")
def _edge(xy, tv, hv, href, h):
    """(length, target) of the edge of half-edge h."""
    a = tv[h]
    b = tv[nxt(h)]
    dx = xy[b, 0] - xy[a, 0]
    dy = xy[b, 1] - xy[a, 1]
    return np.sqrt(dx * dx + dy * dy), 0.5 * (hv[a] + hv[b]) * href


@njit(cache=True)
def measure(m, hv, href):
    """(longest, shortest, largest perimeter), all normalised by their targets."""
    xy, tv = m.xy, m.tv
    lmax = 0.0
    lmin = np.inf
    pmax = 0.0
    for t in range(m.nt):
        per = 0.0
        tgt = 0.0
        for i in range(3):
            L, s = _edge(xy, tv, hv, href, 3 * t + i)
            per += L
            tgt += s
            ell = L / s
            lmax = max(lmax, ell)
            lmin = min(lmin, ell)
        pmax = max(pmax, per / tgt)
    return lmax, lmin, pmax


_combine = njit(cache=True)(combine)


@njit(cache=True)
def objective_of(objective, lmax, lmin, pmax):
    """The scalar minimised, from the normalised extremes (see :mod:`.objective`)."""
    return _combine(objective, lmax / lmin, lmax, pmax)


@njit(cache=True)
def _ring_neighbours(m, role):
    """Previous and next vertex along the boundary ring of every SLIDE vertex."""
    n = m.nv
    prevb = np.full(n, -1, np.int64)
    nextb = np.full(n, -1, np.int64)
    for v in range(n):
        h = m.vseg[v]
        if h >= 0:
            w = m.tv[nxt(h)]
            nextb[v] = w
            prevb[w] = v
    return prevb, nextb


@njit(cache=True)
def _t_of(role, t, u, at_start):
    """Parameter of ring neighbour u on the edge of a SLIDE vertex (0/1 at its ends)."""
    if role[u] == SLIDE:
        return t[u]
    return 0.0 if at_start else 1.0


@njit(cache=True)
def _outgoing(m):
    """One outgoing half-edge per vertex: the boundary one for boundary vertices."""
    vh = np.full(m.nv, -1, np.int64)
    for h in range(3 * m.nt):
        v = m.tv[h]
        if vh[v] < 0:
            vh[v] = h
    for v in range(m.nv):
        if m.vseg[v] >= 0:
            vh[v] = m.vseg[v]
    return vh


@njit(cache=True)
def _star_buffers(m):
    """Buffers for the largest star: spokes (S, 3), triangles (S, 2), lengths (S,)."""
    deg = np.zeros(m.nv, np.int64)
    for h in range(3 * m.nt):
        deg[m.tv[h]] += 1
    s = deg.max() + 2
    return np.empty((s, 3)), np.empty((s, 2)), np.empty(s)


@njit(cache=True)
def _gather(m, v, h0, hv, href, SP, TR):
    """Cache the star of v (outgoing half-edge h0) for its line search.

    Spoke i: ``SP[i] = (x, y, target)`` of the i-th neighbour counter-clockwise;
    triangle j has spokes j and j + 1 (mod the spoke count) and
    ``TR[j] = (length of its edge opposite v, its perimeter target)``.  Returns
    (spokes, triangles): equal for an interior vertex, spokes = triangles + 1 on
    the boundary (an open fan).  Nothing of the star but v moves during the
    search, so lengths opposite v are computed once here.
    """
    xy, tv, tw = m.xy, m.tv, m.tw
    h = h0
    j = 0
    while True:
        b = tv[nxt(h)]
        c = tv[prv(h)]
        SP[j, 0] = xy[b, 0]
        SP[j, 1] = xy[b, 1]
        SP[j, 2] = 0.5 * (hv[v] + hv[b]) * href
        ex = xy[c, 0] - xy[b, 0]
        ey = xy[c, 1] - xy[b, 1]
        TR[j, 0] = np.sqrt(ex * ex + ey * ey)
        TR[j, 1] = (hv[v] + hv[b] + hv[c]) * href
        j += 1
        g = tw[prv(h)]
        if g < 0:  # boundary: the last spoke is v-c
            SP[j, 0] = xy[c, 0]
            SP[j, 1] = xy[c, 1]
            SP[j, 2] = 0.5 * (hv[v] + hv[c]) * href
            return j + 1, j
        h = g
        if h == h0:
            return j, j


@njit(cache=True)
def _star_ok(x, y, x0, y0, ns, nt, SP, floor):
    """Whether every triangle of the cached star stays strictly CCW with v moved
    from (x0, y0) to (x, y) (exact), and none whose doubled area is below
    ``floor`` gets flatter (a quality guard, not a predicate: slivers may not
    form, but may heal)."""
    for j in range(nt):
        i = j + 1 if j + 1 < ns else 0
        det = orient2d(x, y, SP[j, 0], SP[j, 1], SP[i, 0], SP[i, 1])
        if det <= 0.0:
            return False
        if det < floor:
            old = orient2d(x0, y0, SP[j, 0], SP[j, 1], SP[i, 0], SP[i, 1])
            if det < old:
                return False
    return True


@njit(cache=True)
def _suspects(m, moved, todo):
    """The unconstrained edges with a moved vertex in either triangle (each once),
    for the legalisation after a sweep.  Returns (todo, count)."""
    tv, tw = m.tv, m.tw
    sp = 0
    for h in range(3 * m.nt):
        g = tw[h]
        if g < h:  # boundary (-1), or the twin's turn
            continue
        if moved[tv[h]] or moved[tv[nxt(h)]] or moved[tv[prv(h)]] or moved[tv[prv(g)]]:
            todo = grown(todo, sp + 1)
            todo[sp] = h
            sp += 1
    return todo, sp


# ----------------------------------------------------------------------------- springs
@njit(cache=True)
def spring(m, role, eid, t, ea, ed, hv, href, iters, dt, pressure, tol, cap, flat):
    """Jacobi spring rounds (see the module docstring); returns the rounds made.

    A vertex moves by ``dt`` times its spring force, at most ``cap * href * hv[v]``;
    a SLIDE vertex by the tangential part, at most a quarter of its gap to either
    ring neighbour.  Moves that would invert a triangle, or flatten one whose
    doubled area is below ``flat * (href * mean hv)**2`` further, are undone (its
    three vertices stay), then the mesh is legalised.  Stops when the largest
    move is below ``tol * href``.
    """
    n = m.nv
    xy, tv, tw = m.xy, m.tv, m.tw
    prevb, nextb = _ring_neighbours(m, role)
    F = np.zeros((n, 2))
    new = np.empty((n, 2))
    newt = t.copy()
    moved = np.ones(n, np.bool_)  # moved in the last round (all, before the first)
    todo = np.empty(64, np.int32)
    it = 0
    for it in range(1, iters + 1):
        if m.sized:
            refresh_sizes(m, hv, moved)
        # rest-length scale c: sum (c * target)^2 = pressure^2 * sum L^2
        sL = 0.0
        sT = 0.0
        for h in range(3 * m.nt):
            g = tw[h]
            if g >= 0 and g < h:
                continue
            a = tv[h]
            b = tv[nxt(h)]
            L2 = (xy[b, 0] - xy[a, 0]) ** 2 + (xy[b, 1] - xy[a, 1]) ** 2
            s = 0.5 * (hv[a] + hv[b])
            sL += L2
            sT += s * s
        c = pressure * np.sqrt(sL / sT)
        F[:, :] = 0.0
        for h in range(3 * m.nt):
            g = tw[h]
            if g >= 0 and g < h:
                continue
            a = tv[h]
            b = tv[nxt(h)]
            dx = xy[b, 0] - xy[a, 0]
            dy = xy[b, 1] - xy[a, 1]
            L = np.sqrt(dx * dx + dy * dy)
            f = (c * 0.5 * (hv[a] + hv[b]) - L) / L
            F[b, 0] += f * dx
            F[b, 1] += f * dy
            F[a, 0] -= f * dx
            F[a, 1] -= f * dy
        biggest = _trial(
            m, role, eid, t, ea, ed, hv, href, prevb, nextb, F, dt, cap, new, newt, moved
        )
        _commit(m, role, t, new, newt, moved, hv, flat * href * href)
        todo, sp = _suspects(m, moved, todo)
        legalize_stack(m, todo, sp)
        if biggest < tol * href:
            break
    return it


@njit(cache=True)
def _trial(m, role, eid, t, ea, ed, hv, href, prevb, nextb, F, dt, cap, new, newt, moved):
    """Trial places ``new``/``newt`` of all movable vertices; returns the largest move."""
    xy = m.xy
    biggest = 0.0
    for v in range(m.nv):
        moved[v] = False
        if role[v] == FIXED:
            continue
        dx = dt * F[v, 0]
        dy = dt * F[v, 1]
        lim = cap * href * hv[v]
        if role[v] == FREE:
            step = np.hypot(dx, dy)
            if step > lim:
                dx *= lim / step
                dy *= lim / step
                step = lim
            if step == 0.0:
                continue
            new[v, 0], new[v, 1] = snap(m, xy[v, 0] + dx, xy[v, 1] + dy)
            moved[v] = True
            biggest = max(biggest, step)
        else:
            e = eid[v]
            ex, ey = ed[e, 0], ed[e, 1]
            L2 = ex * ex + ey * ey
            dtv = (dx * ex + dy * ey) / L2
            tp = _t_of(role, t, prevb[v], True)
            tn = _t_of(role, t, nextb[v], False)
            gap = 0.25 * min(t[v] - tp, tn - t[v])
            gap = min(gap, lim / np.sqrt(L2))
            dtv = min(max(dtv, -gap), gap)
            if dtv == 0.0:
                continue
            newt[v] = t[v] + dtv
            new[v, 0], new[v, 1] = snap(m, ea[e, 0] + newt[v] * ex, ea[e, 1] + newt[v] * ey)
            moved[v] = True
            biggest = max(biggest, abs(dtv) * np.sqrt(L2))
    return biggest


@njit(cache=True)
def _commit(m, role, t, new, newt, moved, hv, flat2):
    """Apply the trial places, undoing those that would invert a triangle (exact)
    or flatten one below ``flat2 * mean(hv)**2`` (see :func:`spring`)."""
    xy, tv = m.xy, m.tv
    changed = True
    while changed:
        changed = False
        for tt in range(m.nt):
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
    for v in range(m.nv):
        if moved[v]:
            xy[v, 0] = new[v, 0]
            xy[v, 1] = new[v, 1]
            if role[v] == SLIDE:
                t[v] = newt[v]


# ----------------------------------------------------------------------------- descent
@njit(cache=True, inline="always")
def _pw(x, k):
    """x ** (2 ** k), by k squarings (the exponents are powers of two: fast, exact enough)."""
    for _ in range(k):
        x = x * x
    return x


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


@njit(cache=True)
def _star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per, grad, want):
    """The cached star's share of the energy with v at (x, y) (see :func:`_gather`);
    its gradient into ``grad`` if ``want``.  ``L`` receives the spoke lengths."""
    p = 2.0**k
    E = 0.0
    gx = 0.0
    gy = 0.0
    for i in range(ns):
        dx = x - SP[i, 0]
        dy = y - SP[i, 1]
        Li = np.sqrt(dx * dx + dy * dy)
        L[i] = Li
        e, d = _edge_energy(Li / SP[i, 2], SP[i, 2], k, p, w_len, w_short, want)
        E += e
        if want:
            gx += d * dx / Li
            gy += d * dy / Li
    if w_per > 0.0:
        for j in range(nt):
            i = j + 1 if j + 1 < ns else 0
            tgt = TR[j, 1]
            pi = (L[j] + L[i] + TR[j, 0]) / tgt
            q = _pw(pi, k)
            E += w_per * q
            if want:
                d = w_per * p * q / (pi * tgt)
                gx += d * ((x - SP[j, 0]) / L[j] + (x - SP[i, 0]) / L[i])
                gy += d * ((y - SP[j, 1]) / L[j] + (y - SP[i, 1]) / L[i])
    grad[0] = gx
    grad[1] = gy
    return E


@njit(cache=True)
def _search(role, eid, t, ed, prevb, nextb, v, grad, step_v):
    """Direction (ux, uy) against the gradient and the first trial step for v: in
    the plane for a FREE vertex; along its edge for a SLIDE one, at most 0.45 of
    the room to the ring neighbour on that side.  A step of 0 means no move."""
    if role[v] == SLIDE:
        e = eid[v]
        ex, ey = ed[e, 0], ed[e, 1]
        L = np.hypot(ex, ey)
        gt = -(grad[0] * ex + grad[1] * ey) / L
        if gt == 0.0:
            return 0.0, 0.0, 0.0
        sgn = 1.0 if gt > 0 else -1.0
        if sgn > 0:
            room = _t_of(role, t, nextb[v], False) - t[v]
        else:
            room = t[v] - _t_of(role, t, prevb[v], True)
        return sgn * ex / L, sgn * ey / L, min(step_v, 0.45 * room * L)
    gn = np.hypot(grad[0], grad[1])
    if gn == 0.0:
        return 0.0, 0.0, 0.0
    return -grad[0] / gn, -grad[1] / gn, step_v


@njit(cache=True)
def _at(role, eid, t, ea, ed, v, x0, y0, ux, uy, s):
    """(x, y, t) of v moved by s along (ux, uy); a SLIDE vertex stays on its edge."""
    if role[v] == SLIDE:
        e = eid[v]
        ex, ey = ed[e, 0], ed[e, 1]
        tt = t[v] + s * (ux * ex + uy * ey) / (ex * ex + ey * ey)
        return ea[e, 0] + tt * ex, ea[e, 1] + tt * ey, tt
    return x0 + s * ux, y0 + s * uy, t[v]


@njit(cache=True)
def _wake(m, h0, active):
    """Mark the vertex of outgoing half-edge h0 and all its neighbours active."""
    tv, tw = m.tv, m.tw
    active[tv[h0]] = True
    h = h0
    while True:
        active[tv[nxt(h)]] = True
        active[tv[prv(h)]] = True
        h = tw[prv(h)]
        if h < 0 or h == h0:
            return


@njit(cache=True)
def _weights(m, hv, href, k, objective):
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
    largest perimeter's by far).  An edge so short that ``l**p`` underflows makes
    ``S_short`` infinite and its weight 0 for that sweep (typically a polygon
    edge far below the target size, which fixes the shortest edge anyway).
    """
    if objective == MAX_EDGE:
        return 1.0, 0.0, 0.0
    if objective == MAX_PERIMETER:
        return 0.0, 0.0, 1.0
    tv, tw, xy = m.tv, m.tw, m.xy
    s_len = 0.0
    s_short = 0.0
    s_per = 0.0
    for t in range(m.nt):
        per = 0.0
        tgt = 0.0
        for i in range(3):
            h = 3 * t + i
            L, s = _edge(xy, tv, hv, href, h)
            per += L
            tgt += s
            g = tw[h]
            if g < 0 or g > h:  # each edge once
                q = _pw(L / s, k)
                s_len += q
                # an underflowed q (a polygon edge far shorter than the target,
                # such as a tiny hole's) leaves no room for the short-edge term
                s_short += 1.0 / q if q > 0.0 else np.inf
        s_per += _pw(per / tgt, k)
    if objective == RATIO:
        return 1.0 / s_len, 1.0 / s_short, 0.0
    return 2.0 / s_len, 1.0 / s_short, 1.0 / s_per


@njit(cache=True)
def descend(m, role, eid, t, ea, ed, hv, href, objective, sweeps, k, step0, best_xy, best_t,
            best_tv, flat):  # fmt: skip
    """Gauss-Seidel line-search sweeps on the p-norm energy of ``objective``, p = 2**k.

    After each sweep the mesh is legalised and measured; the best state by the
    true objective is written to ``best_*`` (which must hold the starting state)
    and its value returned with the number of sweeps made.  Each vertex keeps its
    own step, starting at ``step0 * href * hv[v]``: grown 1.5x after an accepted
    move, halved after a refused one.  A vertex whose line search fails rests
    until a neighbour moves (an active set: converged regions cost nothing).  A
    move may not flatten a triangle around the vertex whose doubled area is below
    ``flat * (href * hv[v])**2`` any further.  The run ends early when the
    objective stops improving (:data:`PATIENCE`, :data:`GAIN`) or nothing moves.
    A vertex's star is read once per visit (:func:`_gather`); the trials of its
    line search only recompute the distances to the moved vertex.
    """
    n = m.nv
    xy = m.xy
    prevb, nextb = _ring_neighbours(m, role)
    lmax, lmin, pmax = measure(m, hv, href)
    best = objective_of(objective, lmax, lmin, pmax)
    step = np.empty(n)
    for v in range(n):
        step[v] = step0 * href * hv[v]
    grad = np.zeros(2)
    g2 = np.zeros(2)
    active = np.ones(n, np.bool_)
    moved = np.ones(n, np.bool_)  # moved in the last sweep (all, before the first)
    todo = np.empty(64, np.int32)
    done = 0
    stale = 0
    mark = best  # the value PATIENCE sweeps must beat by GAIN
    emax = 0.0
    for sweep in range(sweeps):
        if m.sized:
            refresh_sizes(m, hv, moved)
        moved[:] = False
        w_len, w_short, w_per = _weights(m, hv, href, k, objective)
        vh = _outgoing(m)
        SP, TR, L = _star_buffers(m)
        # a vertex whose share is below RELEVANT times the largest share of the
        # previous sweep cannot change the objective's extremes: skip it
        floor = RELEVANT * emax
        emax = 0.0
        moves = 0
        for v in range(n):
            if role[v] == FIXED or vh[v] < 0 or not active[v]:
                continue
            h0 = vh[v]
            x0 = xy[v, 0]
            y0 = xy[v, 1]
            ns, nt = _gather(m, v, h0, hv, href, SP, TR)
            E0 = _star_energy(x0, y0, ns, nt, SP, TR, L, k, w_len, w_short, w_per, grad, True)
            emax = max(emax, E0)
            if E0 < floor:
                active[v] = False
                continue
            ux, uy, st = _search(role, eid, t, ed, prevb, nextb, v, grad, step[v])
            if st == 0.0:
                continue
            ok = False
            for _k in range(TRIES):
                x, y, tt = _at(role, eid, t, ea, ed, v, x0, y0, ux, uy, st)
                x, y = snap(m, x, y)
                if _star_ok(x, y, x0, y0, ns, nt, SP, flat * (href * hv[v]) ** 2):
                    E1 = _star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per, g2, False)
                    if E1 < E0:
                        ok = True
                        break
                st *= 0.5
            if ok:
                xy[v, 0] = x
                xy[v, 1] = y
                t[v] = tt
                step[v] = min(1.5 * st, 0.3 * href * hv[v])
                moves += 1
                moved[v] = True
                _wake(m, h0, active)
            else:
                step[v] = max(0.5 * step[v], 1e-9 * href * hv[v])
                active[v] = False
        todo, sp = _suspects(m, moved, todo)
        legalize_stack(m, todo, sp)
        done = sweep + 1
        lmax, lmin, pmax = measure(m, hv, href)
        val = objective_of(objective, lmax, lmin, pmax)
        if val < best:
            best = val
            best_xy[:, :] = xy[: best_xy.shape[0]]
            best_t[:] = t
            best_tv[:] = m.tv[: best_tv.shape[0]]
        if val < mark * (1.0 - GAIN):
            mark = val
            stale = 0
        else:
            stale += 1
        if moves == 0 or stale >= PATIENCE:
            break
    return done, best


# ----------------------------------------------------------------------------- spread
@njit(cache=True)
def _mean_length(m, hv, href):
    """Mean normalised length over the edges."""
    tv, tw, xy = m.tv, m.tw, m.xy
    s = 0.0
    k = 0
    for h in range(3 * m.nt):
        g = tw[h]
        if g >= 0 and g < h:
            continue
        L, tgt = _edge(xy, tv, hv, href, h)
        s += L / tgt
        k += 1
    return s / k


@njit(cache=True)
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


@njit(cache=True)
def spread(m, role, eid, t, ea, ed, hv, href, objective, sweeps, step0, best_xy, best_t,
           best_tv, flat):  # fmt: skip
    """Gauss-Seidel sweeps on the spread ``sum (l - mean l)**2`` that cannot make
    ``objective`` worse.

    A move must lower the vertex's share of the spread and keep its star's
    longest and shortest edge and largest perimeter within the mesh's present
    extremes, so the objective can only change through the flips of the
    legalisation; a sweep after which it is worse than at the start ends the
    run, and ``best_*`` (which must hold the starting state) keep the last state
    that was not.  Returns the number of sweeps kept.
    """
    n = m.nv
    xy = m.xy
    prevb, nextb = _ring_neighbours(m, role)
    lmax, lmin, pmax = measure(m, hv, href)
    start = objective_of(objective, lmax, lmin, pmax)
    step = np.empty(n)
    for v in range(n):
        step[v] = step0 * href * hv[v]
    grad = np.zeros(2)
    g2 = np.zeros(2)
    ext = np.zeros(3)
    moved = np.ones(n, np.bool_)  # moved in the last sweep (all, before the first)
    todo = np.empty(64, np.int32)
    kept = 0
    for sweep in range(sweeps):
        if m.sized:
            refresh_sizes(m, hv, moved)
        moved[:] = False
        vh = _outgoing(m)
        SP, TR, L = _star_buffers(m)
        cbar = _mean_length(m, hv, href)
        moves = 0
        for v in range(n):
            if role[v] == FIXED or vh[v] < 0:
                continue
            h0 = vh[v]
            x0 = xy[v, 0]
            y0 = xy[v, 1]
            ns, nt = _gather(m, v, h0, hv, href, SP, TR)
            E0 = _star_spread(x0, y0, ns, nt, SP, TR, L, cbar, grad, ext, True)
            ux, uy, st = _search(role, eid, t, ed, prevb, nextb, v, grad, step[v])
            if st == 0.0:
                continue
            ok = False
            for _k in range(TRIES):
                x, y, tt = _at(role, eid, t, ea, ed, v, x0, y0, ux, uy, st)
                x, y = snap(m, x, y)
                if _star_ok(x, y, x0, y0, ns, nt, SP, flat * (href * hv[v]) ** 2):
                    E1 = _star_spread(x, y, ns, nt, SP, TR, L, cbar, g2, ext, False)
                    if E1 < E0 and ext[0] <= lmax and ext[1] >= lmin and ext[2] <= pmax:
                        ok = True
                        break
                st *= 0.5
            if ok:
                xy[v, 0] = x
                xy[v, 1] = y
                t[v] = tt
                step[v] = min(1.5 * st, 0.3 * href * hv[v])
                moves += 1
                moved[v] = True
            else:
                step[v] = max(0.5 * step[v], 1e-9 * href * hv[v])
        todo, sp = _suspects(m, moved, todo)
        legalize_stack(m, todo, sp)
        a, b, c = measure(m, hv, href)
        if objective_of(objective, a, b, c) > start:
            break  # a flip made it worse: keep the state before this sweep
        lmax, lmin, pmax = a, b, c
        kept = sweep + 1
        best_xy[:, :] = xy[: best_xy.shape[0]]
        best_t[:] = t
        best_tv[:] = m.tv[: best_tv.shape[0]]
        if moves == 0:
            break
    return kept
