"""Lawson's flips on the flat-array CDT: making edges locally Delaunay again.

:func:`legalize_all` flips until every unconstrained edge is locally Delaunay;
:func:`legalize_stack` does it from the suspect half-edges on a stack (after an
insertion or a round of point moves).  :func:`lawson_recorded` also records
every flip (:func:`record_flip`) so that :func:`undo_flips` can restore the
triangulation exactly: the relaxation's trial moves are undone that way.
"""

import numpy as np

from ._jit import njit
from .cdt import flip_on, nxt, prv, reserve
from .external import called_by_name
from .heap import grown
from .predicates import incircle

__all__ = ["legalize_all", "legalize_stack", "lawson_recorded", "record_flip", "undo_flips", "UNDO"]


@njit(cache=True, borrowed=True)
def _not_delaunay(xy, tv, tw, tc, h):
    """Whether the unconstrained edge h fails the in-circle test (on the
    triangulation's arrays ``m.xy, m.tv, m.tw, m.tc``)."""
    g = np.int64(tw[h])  # an int64 half-edge: prv compiles for one type
    if g < 0 or tc[h]:
        return False
    a = tv[h]
    b = tv[nxt(h)]
    c = tv[prv(h)]
    d = tv[prv(g)]
    return (
        incircle(xy[a, 0], xy[a, 1], xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], xy[d, 0], xy[d, 1])
        > 0.0
    )



@njit(cache=True)
def legalize_all(m):
    """Flip until every unconstrained edge is locally Delaunay; returns the flip count."""
    nt = m.nt
    todo = np.empty(6 * nt + 16, np.int32)
    sp = 0
    for h in range(3 * nt):
        if m.tw[h] > h:
            todo[sp] = h
            sp += 1
    return legalize_stack(m, todo, np.int64(sp))



@njit(cache=True, inline="always")
def legalize_stack(m, todo, sp):
    """Lawson flips starting from the half-edges ``todo[:sp]`` (each edge that
    becomes suspect is pushed); returns the flip count.  ``todo`` grows as needed."""
    return _lawson(m, todo, sp, np.int32(-1), np.int64(0))



@njit(cache=True)
def _lawson(m, todo, sp, tag, k):
    """:func:`legalize_stack`; with ``tag`` >= 0 also appends every rewritten slot
    not yet marked ``tag`` to ``cav`` from ``cav[k]`` on, and returns the new k."""
    # no flip recorded (a negative count): the log argument is never touched
    return _lawson_recorded(m, todo, sp, tag, k, todo, np.int64(-1))[0]



@njit(cache=True)
def lawson_recorded(m, todo, sp, tag, k, undo, nu):
    """:func:`_lawson` that, with ``nu`` >= 0, first records every flip in ``undo``
    (:func:`record_flip`, from record nu on).  Returns (what :func:`_lawson`
    returns, undo (grown if needed), the new record count)."""
    flips = np.int64(0)  # not a literal 0: _flips compiles for one type of count
    while sp > 0:
        # the room a flip needs (the four edges it pushes after one pop, its
        # record) is made here, out of the flips' loop: an array variable
        # reassigned in that loop would count references at every turn
        if sp + 3 > todo.shape[0]:
            todo = grown(todo, sp + 3)
        if nu >= 0 and (nu + 1) * UNDO > undo.shape[0]:
            undo = grown(undo, (nu + 1) * UNDO)
        sp, k, flips, nu = _flips(m, m.xy, m.tv, m.tw, m.tc, m.tstamp, m.vseg, m.vcs, m.tmark,
                                  todo, sp, tag, k, undo, nu, flips)
    return (k if tag >= 0 else flips), undo, nu


@njit(cache=True)
def _flips(m, xy, tv, tw, tc, tstamp, vseg, vcs, tmark, todo, sp, tag, k, undo, nu, flips):
    """:func:`lawson_recorded`'s flips while ``todo`` and ``undo`` have room
    for the next one; returns (sp, k, flips, nu).  The triangulation's arrays
    are passed (``m`` only for ``cav``, which :func:`.cdt.reserve` may grow)."""
    while sp > 0 and sp + 3 <= todo.shape[0] and (nu < 0 or (nu + 1) * UNDO <= undo.shape[0]):
        sp -= 1
        h = np.int64(todo[sp])  # an int64 half-edge: nxt/prv compile for one type
        if not _not_delaunay(xy, tv, tw, tc, h):
            continue
        t = h // 3
        u = tw[h] // 3
        if nu >= 0:
            nu = _record(tv, tw, tc, vseg, vcs, h, undo, nu)
        flip_on(tv, tw, tc, tstamp, vseg, vcs, h)
        flips += 1
        if tag >= 0:
            for s in (t, u):
                if tmark[s] != tag:
                    tmark[s] = tag
                    reserve(m, k + 1)
                    m.cav[k] = s
                    k += 1
        # the four outer edges of the new pair
        todo[sp] = 3 * t
        todo[sp + 1] = 3 * t + 1
        todo[sp + 2] = 3 * u
        todo[sp + 3] = 3 * u + 1
        sp += 4
    return sp, k, flips, nu



#: int32 entries of a flip's record (:func:`record_flip`): its two slots, their
#: six half-edges' origin, twin and flag, and the ``vseg`` and ``vcs`` of their
#: four vertices.
UNDO = 2 + 18 + 12



@njit(cache=True)
def record_flip(m, h, undo, nu):
    """Append to ``undo`` (record nu on, grown if needed) everything
    :func:`flip` of h overwrites, for :func:`undo_flips`: the two slots and
    their vertices' ``vseg`` and ``vcs`` (the outer twins' links follow from
    the slots').  Returns (undo, nu + 1)."""
    if (nu + 1) * UNDO > undo.shape[0]:
        undo = grown(undo, (nu + 1) * UNDO)
    return undo, _record(m.tv, m.tw, m.tc, m.vseg, m.vcs, h, undo, nu)


@njit(cache=True, borrowed=True)
def _record(tv, tw, tc, vseg, vcs, h, undo, nu):
    """:func:`record_flip` on the triangulation's arrays, ``undo`` holding
    record nu already; returns nu + 1."""
    h = np.int64(h)
    g = np.int64(tw[h])
    r = nu * UNDO
    undo[r] = h // 3
    undo[r + 1] = g // 3
    i = r + 2
    for s in (h // 3, g // 3):
        for e in range(3 * s, 3 * s + 3):
            undo[i] = tv[e]
            undo[i + 1] = tw[e]
            undo[i + 2] = tc[e]
            i += 3
    for e in (h, nxt(h), prv(h), prv(g)):  # the quad's four vertices
        v = tv[e]
        undo[i] = v
        undo[i + 1] = vseg[v]
        undo[i + 2] = vcs[v]
        i += 3
    return nu + 1



@njit(cache=True)
def undo_flips(m, undo, nu):
    """Undo the ``nu`` flips recorded in ``undo``, the last first: the
    triangulation (``tv``, ``tw``, ``tc``, ``vseg``, ``vcs``) is then exactly
    what it was before the first."""
    for rec in range(nu - 1, -1, -1):
        r = rec * UNDO
        i = r + 2
        for j in range(2):
            s = np.int64(undo[r + j])
            for e in range(3 * s, 3 * s + 3):
                m.tv[e] = undo[i]
                m.tw[e] = undo[i + 1]
                m.tc[e] = undo[i + 2]
                i += 3
        for j in range(2):  # the outer twins point back into the slots
            s = np.int64(undo[r + j])
            for e in range(3 * s, 3 * s + 3):
                if m.tw[e] >= 0:
                    m.tw[m.tw[e]] = e
        for j in range(4):
            v = undo[i]
            m.vseg[v] = undo[i + 1]
            m.vcs[v] = undo[i + 2]
            i += 3


_lawson_recorded = called_by_name(lawson_recorded)
