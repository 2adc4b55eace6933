"""The star of a vertex and the mesh-wide measures shared by the ways to move points.

Used by :mod:`.spring`, :mod:`.descent` and :mod:`.spread` (overview:
:mod:`.relax`): vertex roles, the size targets, the normalised extremes and the
objective, the cached star of a vertex (:func:`gather`) and its validity test
(:func:`star_ok`), a vertex's line-search direction and places, and the
legalisation after a round of moves.

Around a vertex v the kernel turns counter-clockwise with ``h -> tw[prv(h)]``
starting from an outgoing half-edge (``vseg[v]`` on the boundary, where the turn
ends at -1)::

            c
           / \\         h = v->b, prv(h) = c->v, tw[prv(h)] = v->c: the next
          /   \\        outgoing half-edge, counter-clockwise around v
         v --h-> b
"""

import numpy as np
from ._jit import njit

from .cdt import new_tag, nxt, prv
from .heap import grown
from .lawson import UNDO, _lawson_recorded, undo_flips
from .objective import combine
from .predicates import orient2d
from .rank import size_at

FIXED, FREE, SLIDE = 0, 1, 2
#: Halvings of the step a line search tries before the vertex gives up.
TRIES = 8
#: Rings of triangles of fixed vertices around the movable ones that the
#: passes of a restricted run cover from the start (:func:`live_slots`): a flip
#: that reaches farther wakes a slot, which costs a pass over the rest.
LIVE_RINGS = 2


@njit(cache=True, borrowed=True)
def pw(x, k):
    """x ** (2 ** k), by k squarings (the exponents are powers of two: fast, exact enough)."""
    for _ in range(k):
        x = x * x
    return x


@njit(cache=True, borrowed=True)
def counted(tw, alive, h):
    """Whether half-edge h stands for its edge in a pass over the live slots:
    each edge once, by the smaller of two live twins, by the live one of a
    live and a dead twin (never by a dead one: those edges are in
    :func:`dead_part`), on the boundary by its only half."""
    g = tw[h]
    return g < 0 or g > h or alive[g // 3] == 0


@njit(cache=True)
def slot_list(alive):
    """The slots t with ``alive[t]``, in increasing order."""
    k = 0
    for t in range(alive.shape[0]):
        if alive[t]:
            k += 1
    out = np.empty(k, np.int64)
    k = 0
    for t in range(alive.shape[0]):
        if alive[t]:
            out[k] = t
            k += 1
    return out


@njit(cache=True)
def live_slots(m, role, restrict):
    """(alive, slots, movers): which triangle slots the passes of a run cover
    (``alive[t]`` 1), those slots in increasing order, and the vertices that
    are not FIXED, in order.

    Without ``restrict`` every slot is alive, and every pass is the plain pass
    over the whole mesh, bit for bit.  With it, the slots with a movable vertex
    and :data:`LIVE_RINGS` rings of triangles around them: a triangle of three
    fixed vertices that no flip rewrites keeps its shape, so what it adds to the
    measures is computed once (:func:`dead_part`), and the passes over a large
    mesh whose deep interior is frozen cost what its movable band costs.  A
    flip that rewrites a dead slot wakes it (:func:`legalize_live`)."""
    nt = m.nt
    tv, tw = m.tv, m.tw
    alive = np.ones(nt, np.int8)
    if restrict:
        for t in range(nt):
            fixed = role[tv[3 * t]] == FIXED and role[tv[3 * t + 1]] == FIXED
            alive[t] = 0 if fixed and role[tv[3 * t + 2]] == FIXED else 1
        for _ in range(LIVE_RINGS):
            grow = alive.copy()
            for t in range(nt):
                if alive[t]:
                    for i in range(3):
                        g = tw[3 * t + i]
                        if g >= 0:
                            grow[g // 3] = 1
            alive = grow
    n_move = 0
    for v in range(m.nv):
        if role[v] != FIXED:
            n_move += 1
    movers = np.empty(n_move, np.int64)
    n_move = 0
    for v in range(m.nv):
        if role[v] != FIXED:
            movers[n_move] = v
            n_move += 1
    return alive, slot_list(alive), movers


@njit(cache=True)
def dead_part(m, alive, hv, href, k):
    """What the dead slots (``alive[t]`` 0) add to the passes: (longest,
    shortest, largest perimeter, sum l**p, sum l**-p, sum pi**p, sum L**2,
    sum target**2, sum l, edge count), the extremes normalised by their
    targets, p = 2**k, each edge once (:func:`counted`'s complement); neutral
    (0, inf, 0, 0, ...) when every slot is alive."""
    xy, tv, tw = m.xy, m.tv, m.tw
    out = np.zeros(10)
    out[1] = np.inf
    for t in range(m.nt):
        if alive[t]:
            continue
        Ls, ss, per, tgt = triangle_terms(xy, tv, hv, href, t)
        for i in range(3):
            h = 3 * t + i
            L = Ls[i]
            ell = L / ss[i]
            out[0] = max(out[0], ell)
            out[1] = min(out[1], ell)
            g = tw[h]
            if g < 0 or (g > h and alive[g // 3] == 0):
                q = pw(ell, k)
                out[3] += q
                out[4] += 1.0 / q if q > 0.0 else np.inf
                out[6] += L * L
                s0 = 0.5 * (hv[tv[h]] + hv[tv[nxt(h)]])  # the spring's target, without href
                out[7] += s0 * s0
                out[8] += ell
                out[9] += 1.0
        out[2] = max(out[2], per / tgt)
        out[5] += pw(per / tgt, k)
    return out


@njit(cache=True)
def refresh_sizes(m, hv, which):
    """hv[v] = the size field at vertex v (1 without a field), for each v with
    ``which[v]`` (the vertices moved since the last refresh)."""
    for v in range(m.nv):
        if which[v]:
            hv[v] = size_at(m, m.xy[v, 0], m.xy[v, 1])


@njit(cache=True, borrowed=True)
def edge(xy, tv, hv, href, h):
    """(length, target) of the edge of half-edge h."""
    a = tv[h]
    b = tv[nxt(h)]
    dx = xy[b, 0] - xy[a, 0]
    dy = xy[b, 1] - xy[a, 1]
    return np.sqrt(dx * dx + dy * dy), 0.5 * (hv[a] + hv[b]) * href


@njit(cache=True, borrowed=True)
def triangle_terms(xy, tv, hv, href, t):
    """The terms every pass over the triangles reads of slot t: its three edges'
    lengths and targets (:func:`edge`, in half-edge order) and its perimeter
    and the perimeter's target, summed in that order."""
    L0, s0 = edge(xy, tv, hv, href, 3 * t)
    L1, s1 = edge(xy, tv, hv, href, 3 * t + 1)
    L2, s2 = edge(xy, tv, hv, href, 3 * t + 2)
    return (L0, L1, L2), (s0, s1, s2), L0 + L1 + L2, s0 + s1 + s2


@njit(cache=True)
def measure(m, hv, href):
    """(longest, shortest, largest perimeter), all normalised by their targets."""
    none = np.zeros(3)  # no dead slots: the neutral part
    none[1] = np.inf
    return measure_live(m, hv, href, np.arange(m.nt), none)


@njit(cache=True)
def measure_live(m, hv, href, slots, dead):
    """:func:`measure` over the live ``slots``, with the dead ones' part ``dead``
    (:func:`dead_part`): the same values, bit for bit, when every slot is live."""
    xy, tv = m.xy, m.tv
    lmax = 0.0
    lmin = np.inf
    pmax = 0.0
    for t in slots:
        Ls, ss, per, tgt = triangle_terms(xy, tv, hv, href, t)
        for i in range(3):
            ell = Ls[i] / ss[i]
            lmax = max(lmax, ell)
            lmin = min(lmin, ell)
        pmax = max(pmax, per / tgt)
    return max(lmax, dead[0]), min(lmin, dead[1]), max(pmax, dead[2])


@njit(cache=True)
def edge_cv(m, hv, href):
    """The coefficient of variation (std / mean) of the normalised edge lengths,
    each edge once: the spread a start leaves, for ranking starts without
    building a mesh outside the kernel."""
    xy, tv, tw = m.xy, m.tv, m.tw
    s1 = 0.0
    s2 = 0.0
    k = 0
    for h in range(3 * m.nt):
        if tw[h] > h:  # the twin's turn
            continue
        L, s = edge(xy, tv, hv, href, h)
        ell = L / s
        s1 += ell
        s2 += ell * ell
        k += 1
    mean = s1 / k
    return np.sqrt(max(s2 / k - mean * mean, 0.0)) / mean


_combine = njit(cache=True)(combine)


@njit(cache=True)
def objective_of(objective, lmax, lmin, pmax):
    """The scalar minimised, from the normalised extremes (see :mod:`.objective`)."""
    return _combine(objective, lmax / lmin, lmax, pmax)


@njit(cache=True)
def ring_neighbours(m, role, eid, t, ea):
    """Previous and next vertex along the boundary ring, or along the interior
    segment piece ``eid[v]`` (start ``ea[eid[v]]``), of every SLIDE vertex."""
    n = m.nv
    prevb = np.full(n, -1, np.int64)
    nextb = np.full(n, -1, np.int64)
    for v in range(n):
        h = m.vseg[v]
        if h >= 0:
            w = m.tv[nxt(h)]
            nextb[v] = w
            prevb[w] = v
    for h in range(3 * m.nt):
        v = m.tv[h]
        if m.tc[h] == 0 or role[v] != SLIDE:
            continue
        w = m.tv[nxt(h)]
        e = eid[v]
        if role[w] == SLIDE:
            before = t[w] < t[v]
        else:  # an end of the piece (or a point frozen on it: then by its place)
            before = m.xy[w, 0] == ea[e, 0] and m.xy[w, 1] == ea[e, 1]
        if before:
            prevb[v] = w
        else:
            nextb[v] = w
    return prevb, nextb


@njit(cache=True, borrowed=True)
def t_of(role, t, u, at_start):
    """Parameter of ring neighbour u on the edge of a SLIDE vertex (0/1 at its ends)."""
    if role[u] == SLIDE:
        return t[u]
    return 0.0 if at_start else 1.0


@njit(cache=True)
def stars(m, slots):
    """One outgoing half-edge per vertex of the live ``slots`` (the boundary one
    for boundary vertices; -1 for none) and buffers for the largest star: spokes (S, 3), triangles
    (S, 2), lengths (S,).  One pass over the half-edges for both: a sweep needs
    both, and on a large mesh whose deep interior is frozen each pass costs about
    as much as the moves of the few vertices that move.  (vh, SP, TR, L)."""
    vh = np.full(m.nv, -1, np.int64)
    deg = np.zeros(m.nv, np.int32)
    top = 0
    for t in slots:  # every half-edge leaving a movable vertex is in a live slot
        for h in range(3 * t, 3 * t + 3):
            v = m.tv[h]
            if vh[v] < 0:
                vh[v] = h
            deg[v] += 1
            top = max(top, deg[v])
    for v in range(m.nv):
        if m.vseg[v] >= 0:
            vh[v] = m.vseg[v]
    s = top + 2
    return vh, np.empty((s, 3)), np.empty((s, 2)), np.empty(s)


@njit(cache=True, borrowed=True)
def gather(xy, tv, tw, v, h0, hv, href, SP, TR):
    """Cache the star of v (outgoing half-edge h0) for its line search.

    Spoke i: ``SP[i] = (x, y, target)`` of the i-th neighbour counter-clockwise;
    triangle j has spokes j and j + 1 (mod the spoke count) and
    ``TR[j] = (length of its edge opposite v, its perimeter target)``.  Returns
    (spokes, triangles): equal for an interior vertex, spokes = triangles + 1 on
    the boundary (an open fan).  Nothing of the star but v moves during the
    search, so lengths opposite v are computed once here.  The triangulation's
    arrays ``m.xy, m.tv, m.tw`` are passed, not the structref, which would
    count a reference at every visit.
    """
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


@njit(cache=True, borrowed=True)
def star_ok(x, y, x0, y0, ns, nt, SP, floor):
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
def suspects(m, moved, todo, alive, slots):
    """The unconstrained edges with a moved vertex in either triangle (each once,
    :func:`counted`), for the legalisation after a sweep.  Returns (todo, count)."""
    tv, tw = m.tv, m.tw
    # first which triangles hold a moved vertex (moved vertices are in live
    # slots only), then each edge reads its twin's flag: a byte per triangle
    # instead of the twin's vertex, scattered over the half-edge arrays
    hot = np.zeros(m.nt, np.bool_)
    for t in slots:
        hot[t] = moved[tv[3 * t]] or moved[tv[3 * t + 1]] or moved[tv[3 * t + 2]]
    # room for every half-edge of the slots at once: an array variable
    # reassigned inside the loop would count references at every turn
    todo = grown(todo, 3 * slots.shape[0])
    sp = 0
    for t in slots:
        for h in range(3 * t, 3 * t + 3):
            g = tw[h]
            if g < 0 or not counted(tw, alive, h):  # boundary, or the twin's turn
                continue
            if hot[t] or hot[g // 3]:
                todo[sp] = h
                sp += 1
    return todo, sp


@njit(cache=True, borrowed=True)
def search(role, eid, t, ed, prevb, nextb, v, grad, step_v):
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
            room = t_of(role, t, nextb[v], np.bool_(False)) - t[v]
        else:
            room = t[v] - t_of(role, t, prevb[v], np.bool_(True))
        return sgn * ex / L, sgn * ey / L, min(step_v, 0.45 * room * L)
    gn = np.hypot(grad[0], grad[1])
    if gn == 0.0:
        return 0.0, 0.0, 0.0
    return -grad[0] / gn, -grad[1] / gn, step_v


@njit(cache=True, borrowed=True)
def place_at(role, eid, t, ea, ed, v, x0, y0, ux, uy, s):
    """(x, y, t) of v moved by s along (ux, uy); a SLIDE vertex stays on its edge."""
    if role[v] == SLIDE:
        e = eid[v]
        ex, ey = ed[e, 0], ed[e, 1]
        tt = t[v] + s * (ux * ex + uy * ey) / (ex * ex + ey * ey)
        return ea[e, 0] + tt * ex, ea[e, 1] + tt * ey, tt
    return x0 + s * ux, y0 + s * uy, t[v]


@njit(cache=True)
def legalize_live(m, moved, todo, alive, slots, undo, nu):
    """Make every edge around the moved vertices locally Delaunay again
    (:func:`suspects`, then Lawson flips), and wake every dead slot a flip
    rewrote.  With ``nu`` >= 0 the flips are recorded in ``undo`` from record nu
    on (:func:`.lawson.record_flip`).  Returns (todo, grown if needed; slots;
    whether a slot woke: the caller's :func:`dead_part` is then stale; undo;
    the new record count)."""
    todo, sp = suspects(m, moved, todo, alive, slots)
    k, undo, nu = _lawson_recorded(m, todo, sp, new_tag(m), np.int64(0), undo, nu)
    woke = False
    for i in range(k):
        t = m.cav[i]
        if alive[t] == 0:
            alive[t] = 1
            woke = True
    if woke:
        slots = slot_list(alive)
    return todo, slots, woke, undo, nu


@njit(cache=True)
def initial_steps(m, hv, href, step0):
    """Every vertex's first trial step of the line searches: ``step0 * href * hv[v]``."""
    step = np.empty(m.nv)
    for v in range(m.nv):
        step[v] = step0 * href * hv[v]
    return step


@njit(cache=True, borrowed=True)
def accept(xy, t, step, moved, v, x, y, tt, st, href, hvv):
    """Move v to (x, y) (edge parameter tt) found with trial step st; its next
    first step is 1.5 st, at most 0.3 of its target size ``href * hvv``."""
    xy[v, 0] = x
    xy[v, 1] = y
    t[v] = tt
    step[v] = min(1.5 * st, 0.3 * href * hvv)
    moved[v] = True


@njit(cache=True, borrowed=True)
def refuse(step, v, href, hvv):
    """A failed line search halves v's first step (not below 1e-9 of its target)."""
    step[v] = max(0.5 * step[v], 1e-9 * href * hvv)


@njit(cache=True)
def kept_state(m, t, movers):
    """(xy, t, undo, nu) holding the present state of a run whose moves are
    those of ``movers`` (:func:`keep_state`)."""
    best_xy = np.empty((movers.shape[0], 2))
    best_t = np.empty(movers.shape[0])
    undo = np.empty(64 * UNDO, np.int32)
    return best_xy, best_t, undo, keep_state(m, t, movers, best_xy, best_t)


@njit(cache=True)
def keep_state(m, t, movers, best_xy, best_t):
    """Keep the present state in ``best_*``: the points and edge parameters of
    the ``movers`` (no other vertex moves) and, for the triangulation, nothing
    but an empty flip record (the count returned, 0): every flip from here on
    is recorded (:func:`legalize_live`), and :func:`restore_state` undoes
    them.  A copy of the whole triangulation would cost what the mesh costs;
    the flips of a run touch only its live slots."""
    for i in range(movers.shape[0]):
        v = movers[i]
        best_xy[i, 0] = m.xy[v, 0]
        best_xy[i, 1] = m.xy[v, 1]
        best_t[i] = t[v]
    return np.int64(0)  # not a literal 0: the callers' flip counts stay one type


@njit(cache=True)
def restore_state(m, t, movers, best_xy, best_t, undo, nu):
    """Put back what :func:`keep_state` kept, the ``nu`` flips recorded since in
    ``undo`` undone: exactly the triangulation and points of then."""
    undo_flips(m, undo, nu)
    for i in range(movers.shape[0]):
        v = movers[i]
        m.xy[v, 0] = best_xy[i, 0]
        m.xy[v, 1] = best_xy[i, 1]
        t[v] = best_t[i]
