"""The seams' relaxation in pieces, run in parallel: a band of a mesh moved by the
optimiser tile by tile, the same bytes wherever the tiles run.

After a partitioned mesh is stitched (:mod:`uniform2d.partitioned`), the points
along its cuts (and its rings) move again under the optimiser's stages,
with everything else frozen.  That band crosses the whole mesh, so it is cut
into pieces that can run at once:

1. The plane is tiled in squares of :data:`TILE` h, coloured in four by the
   parity of their row and column: tiles of one colour are a whole tile apart.
2. Four rounds, one per colour.  In a round, every tile of that colour with
   band points in it is a piece: those points (the tile grown by
   :data:`OVERLAP` h, so that the points near a tile's side move again in the
   later round of its neighbour, with both sides free), the mesh
   :data:`CONTEXT` rings of triangles around them (frozen), and the piece's
   region, the union of those triangles, made a :class:`~uniform2d.Polygon`
   of its own (its boundary loops: its band points on the mesh's rings slide
   along them, all other points of the loops are fixed).  A piece is a
   function of its inputs alone (:func:`relax_piece`): the kernel's exact
   constrained Delaunay triangulation of the region with its free points moved.
3. The pieces of a round are independent (a tile apart) and run in
   :class:`uniform2d._parallel.Runner`, here, in local processes or on Dask;
   their points and triangles are written back in tile order before the next
   round reads the mesh.
4. A piece balances its own longest and shortest edges, not the mesh's, so a
   last round here (:func:`finish`) moves the few points near the edges
   furthest from h again with the whole mesh loaded.

The region of a piece is covered by the same triangles before and after (its
boundary does not move, points sliding on P's rings aside), so writing back
keeps the mesh valid and conforming.
"""

from __future__ import annotations

import logging
import time

import numpy as np
from scipy.spatial import cKDTree

from .errors import InternalError
from .geometry import signed_area, unique_edges
from .optimize.moves import KernelMesh
from .optimize.objective import objective_code
from .optimize.schedule import SCHEDULE
from .polygon import Polygon

__all__ = ["CONTEXT", "FINISH", "LIGHT", "LONG", "OVERLAP", "ROUNDS", "SHORT", "SPOT_RADIUS", "TILE",
           "finish", "relax_band", "relax_piece", "round_pieces"]

log = logging.getLogger(__name__)

#: The side of a tile, in target lengths h.
TILE = 48.0

#: Tiles are grown by this many h on every side: the points near a tile's
#: side move again in the later round of its neighbour, with both sides free.
OVERLAP = 4.0

#: Rings of triangles around a piece's free points that are in its region,
#: frozen: its boundary is this far from any point that moves.
CONTEXT = 3

#: Rounds of the pass: tiles of one colour (parity of row, column) per round.
ROUNDS = 4

#: The last round (:func:`finish`) moves the points within SPOT_RADIUS h of an
#: edge shorter than SHORT h or longer than LONG h: where a piece, balancing
#: its own extremes, left the whole mesh's worse.
SHORT = 0.85
LONG = 1.13
SPOT_RADIUS = 3.0
#: Its schedule: the extremes' stages and the spread (the points are near
#: their places already; springs would undo the pieces' balance).
FINISH = SCHEDULE._replace(spring_rounds=0, exponents=(7, 8))
#: The pieces' schedule where the band starts on a lattice (the shared one of
#: :func:`uniform2d.partitioned.global_lattice`): fewer spring rounds and
#: sweeps, all the stages (the extremes are set near the rings).
LIGHT = SCHEDULE._replace(spring_rounds=20, sweeps=20, spread_sweeps=10)

_PINCH_STEPS = 20


def _label_round(T, lab: np.ndarray, rings: int):
    """Grow the vertex labels ``lab`` (-1: none) ``rings`` times across triangles;
    returns the vertex labels and every triangle's label (-1: none)."""
    for _ in range(rings + 1):
        L = lab[T]
        tl = L.max(axis=1)
        lo = np.where(L >= 0, L, np.iinfo(np.int64).max).min(axis=1)
        if ((tl >= 0) & (lo != tl)).any():
            raise InternalError("two pieces of one round touch (a bug: please report it)")
        sel = np.flatnonzero(tl >= 0)
        v, val = T[sel].ravel(), np.repeat(tl[sel], 3)
        lab = lab.copy()
        lab[v] = val
        if (lab[v] != val).any():
            raise InternalError("two pieces of one round share a point (a bug: please report it)")
    return lab, tl


def _fix_pinches(T, tl: np.ndarray, N: int) -> np.ndarray:
    """Triangle labels with every piece's region made free of pinch vertices (a
    vertex where its triangles meet in two fans): such a vertex's star joins."""
    for _ in range(_PINCH_STEPS):
        sel = np.flatnonzero(tl >= 0)
        if not len(sel):
            return tl
        a = T[sel].ravel()
        b = T[sel][:, [1, 2, 0]].ravel()
        lab = np.repeat(tl[sel], 3)
        key = a * N + b
        order = np.argsort(key, kind="stable")
        skey = key[order]
        rev = b * N + a
        at = np.minimum(np.searchsorted(skey, rev), len(skey) - 1)
        inside = (skey[at] == rev) & (lab[order[at]] == lab)
        nl = int(lab.max()) + 1
        pair, count = np.unique(a[~inside] * nl + lab[~inside], return_counts=True)
        pinch = pair[count > 1]
        if not len(pinch):
            return tl
        pv, pl = pinch // nl, pinch % nl
        star = np.zeros(N, dtype=np.int64) - 1
        star[pv] = pl
        S = star[T]
        want = S.max(axis=1)
        add = (want >= 0) & (tl < 0)
        if (((want >= 0) & (tl >= 0) & (tl != want)).any()
                or (np.where(S >= 0, S, np.iinfo(np.int64).max).min(axis=1)[add] != want[add]).any()):
            raise InternalError("two pieces of one round touch (a bug: please report it)")
        tl = tl.copy()
        tl[add] = want[add]
    raise InternalError("a piece's region keeps pinch vertices (a bug: please report it)")


def _tiles(P, origin, h: float, rnd: int) -> np.ndarray:
    """(N,) the tile of colour ``rnd`` each point is in, grown by :data:`OVERLAP`
    h on every side (-1: none).  Tiles of one colour are a tile apart, so a
    point is in one at most."""
    u = (P - np.asarray(origin)) / (TILE * h)
    base = np.floor(u).astype(np.int64)
    frac = u - base
    grow = OVERLAP / TILE
    want = np.array([rnd % 2, rnd // 2])
    ij = np.where(base % 2 == want, base, np.where(frac < grow, base - 1,
                                                     np.where(frac > 1.0 - grow, base + 1, -2)))
    ij += 1  # from -1: a grown tile may reach before the origin
    width = int(base[:, 0].max()) + 3
    return np.where((ij >= 0).all(axis=1), ij[:, 0] + ij[:, 1] * width, -1)


def round_pieces(points, triangles, free, h: float, origin, rnd: int, fixed: int, segments):
    """The pieces of round ``rnd``: per tile of that colour with free points in
    it, ``(rows, ids, item)``: its triangles' rows in ``triangles``, its points'
    global numbers (sorted) and :func:`relax_piece`'s item (local arrays).

    ``fixed``: points below this number never move (P's vertices, segment
    samples); ``segments`` (E, 2) int64: the mesh's constrained interior edges.
    """
    P = np.asarray(points)
    T = np.asarray(triangles, dtype=np.int64)
    N = len(P)
    tile = _tiles(P, origin, h, rnd)
    core = np.asarray(free) & (tile >= 0)
    lab = np.where(core, tile, -1)
    lab, tl = _label_round(T, lab, CONTEXT)
    tl = _fix_pinches(T, tl, N)
    sel = np.flatnonzero(tl >= 0)
    order = sel[np.argsort(tl[sel], kind="stable")]
    labels, start = np.unique(tl[order], return_index=True)
    out = []
    for k, label in enumerate(labels.tolist()):
        rows = np.sort(order[start[k]: start[k + 1] if k + 1 < len(start) else len(order)])
        ids = np.unique(T[rows])
        loc = np.searchsorted(ids, T[rows])
        seg = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
        seg = seg[np.isin(seg, ids).all(axis=1)]
        item = (np.ascontiguousarray(P[ids]), loc, core[ids] & (tile[ids] == label), ids < fixed,
                np.searchsorted(ids, seg), h)
        out.append((rows, ids, item))
    return out


def _edge_keys(T):
    """The directed edges of T as sorted keys ``u * n + v``, and n."""
    n = int(T.max()) + 1
    return np.sort(T.ravel() * n + T[:, [1, 2, 0]].ravel()), n


def _has(skey, keys) -> np.ndarray:
    at = np.minimum(np.searchsorted(skey, keys), len(skey) - 1)
    return skey[at] == keys


def _loops(T) -> list:
    """The boundary loops of a pinch-free triangle set, as vertex lists in order
    (the region on their left), each starting at its smallest vertex."""
    skey, n = _edge_keys(T)
    a = T.ravel()
    b = T[:, [1, 2, 0]].ravel()
    bnd = ~_has(skey, b * n + a)
    nxt = dict(zip(a[bnd].tolist(), b[bnd].tolist()))
    loops, seen = [], set()
    for s in sorted(nxt):
        if s in seen:
            continue
        loop, u = [], s
        while u not in seen:
            seen.add(u)
            loop.append(u)
            u = nxt[u]
        if u != s:
            raise InternalError("a piece's boundary is not a simple loop (a bug: please report it)")
        loops.append(loop)
    return loops


def _components(T, n: int) -> list:
    """Triangle rows of every connected component (sharing vertices) of T."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    r = np.concatenate([T[:, 0], T[:, 1]])
    c = np.concatenate([T[:, 1], T[:, 2]])
    g = coo_matrix((np.ones(len(r)), (r, c)), shape=(n, n))
    _, comp = connected_components(g, directed=False)
    tc = comp[T[:, 0]]
    return [np.flatnonzero(tc == k) for k in np.unique(tc).tolist()]


def _region(P, T, free, fixed, seg):
    """The piece's region as a Polygon: its loops without their free points
    (those slide along P's rings), the segments inside it, its lone fixed points."""
    loops = _loops(T)
    rings = [[v for v in lp if not free[v]] for lp in loops]
    area = [signed_area(P[r]) for r in rings]  # exact sums, not BLAS's: the same on every CPU
    outer = [k for k, s in enumerate(area) if s > 0]
    if len(outer) != 1 or any(len(r) < 3 for r in rings):
        raise InternalError("a piece's region is not one polygon (a bug: please report it)")
    on = {v for lp in loops for v in lp}
    if len(seg):  # the segment pieces inside the region: edges of two of its triangles
        skey, n = _edge_keys(T)
        seg = seg[_has(skey, seg[:, 0] * n + seg[:, 1]) & _has(skey, seg[:, 1] * n + seg[:, 0])]
    seg = [(int(u), int(v)) for u, v in seg]
    ends = {v for e in seg for v in e}
    lone = [v for v in np.flatnonzero(fixed).tolist() if v not in on and v not in ends]
    o = outer[0]
    return Polygon(P[rings[o]], [P[r] for k, r in enumerate(rings) if k != o],
                   segments=[P[list(e)] for e in seg], points=P[lone] if lone else ())


def _relax_component(P, T, free, fixed, seg, h: float, objective: str, schedule):
    """Move one connected region's free points; returns (sites, new xy, triangles)."""
    ids = np.unique(T)
    loc = np.full(len(P), -1, dtype=np.int64)
    loc[ids] = np.arange(len(ids))
    sseg = loc[seg[np.isin(seg, ids).all(axis=1)]] if len(seg) else np.zeros((0, 2), np.int64)
    Pl = P[ids]
    poly = _region(Pl, loc[T], free[ids], fixed[ids], sseg)
    where = {(float(x), float(y)): i for i, (x, y) in enumerate(Pl.tolist())}
    try:
        pv = np.array([where[(float(x), float(y))] for x, y in poly.vertices], dtype=np.int64)
    except KeyError:
        raise InternalError("a piece's polygon has a vertex of its own (a bug: please report it)") from None
    sub = np.full(len(Pl), -1, dtype=np.int64)
    sub[pv] = np.arange(len(pv))
    sites = np.flatnonzero(sub < 0)
    sub[sites] = len(pv) + np.arange(len(sites))
    nV = len(pv)
    st = KernelMesh.from_mesh(poly, np.concatenate([poly.vertices, Pl[sites]]), sub[loc[T]],
                              href=h, frozen=~free[ids][sites])._replace(movable_short=True)
    run = st.advance(schedule, objective_code(objective))
    pts, tri, _ = st.result(run)
    moved = pts[nV:]
    stay = ~free[ids][sites]
    if not np.array_equal(moved[stay], Pl[sites][stay]):
        raise InternalError("a piece moved a frozen point (a bug: please report it)")
    back = np.concatenate([pv, sites])
    go = free[ids][sites]
    return ids[sites[go]], moved[go], ids[back[np.asarray(tri, dtype=np.int64)]]


def relax_piece(item, objective: str = "balanced"):
    """One piece of a round (:func:`round_pieces`'s item, then optionally the
    objective and the schedule, default :data:`~uniform2d.optimize.schedule.SCHEDULE`):
    ``(moved, xy, triangles)``, the local numbers of its free
    points, where they went and the region's new triangles (local numbers).

    A module-level function of its item alone: local processes and Dask
    workers import it by name, and give the same bytes.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> from uniform2d.triangulation import triangulate
    >>> P, T = triangulate(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]),
    ...                    [(0.5, 0.45), (0.3, 0.6), (0.7, 0.6)])
    >>> free = np.arange(7) == 4
    >>> moved, xy, tri = relax_piece((P, T, free, np.arange(7) < 4,
    ...                               np.zeros((0, 2), np.int64), 0.4))
    >>> moved.tolist(), len(tri) == len(T)
    ([4], True)
    """
    P, T, free, fixed, seg, h = item[:6]
    objective = item[6] if len(item) > 6 else objective
    schedule = item[7] if len(item) > 7 else SCHEDULE
    moved, xy, tris = [], [], []
    for rows in _components(T, len(P)):
        m, x, t = _relax_component(P, T[rows], free, fixed, seg, h, objective, schedule)
        moved.append(m)
        xy.append(x)
        tris.append(t)
    return np.concatenate(moved), np.concatenate(xy), np.concatenate(tris)


def relax_band(polygon: Polygon, points, triangles, free, h: float, fixed: int, segments, runner,
               objective: str = "balanced", times: dict | None = None, schedule=SCHEDULE):
    """``points`` (N, 2) and ``triangles`` (M, 3), a mesh of ``polygon``, with the
    ``free`` (N,) points moved: piece by piece in :data:`ROUNDS` rounds on
    ``runner`` (:class:`uniform2d._parallel.Runner`), then :func:`finish`.
    ``fixed`` and ``segments`` as :func:`round_pieces`'s.  Returns new arrays:
    the kernel's exact constrained Delaunay triangulation of the moved points.
    ``times``, if given, gets the seconds spent cutting the pieces out
    (``seams_cut``), running them (``seams_pieces``) and in :func:`finish`
    (``seams_finish``).  ``schedule``: the pieces' (:data:`LIGHT` where the band
    starts on a lattice).
    """
    clock = {"seams_cut": 0.0, "seams_pieces": 0.0}
    P = np.array(points, dtype=np.float64)
    T = np.array(triangles, dtype=np.int64)
    # the triangles a piece can reach (its region, a pinch's star), once: the
    # pieces rewrite them in place, so they cover the same ground every round
    near = np.flatnonzero(_label_round(T, np.where(free, 0, -1), CONTEXT + 3)[1] >= 0)
    for rnd in range(ROUNDS):
        t0 = time.perf_counter()
        pieces = round_pieces(P, T[near], free, h, polygon.bounds[:2], rnd, fixed, segments)
        items = [(*it, objective, schedule) for _, _, it in pieces]
        log.info("seams: round %d, %d pieces, %d free points", rnd, len(items),
                 int(sum(it[2].sum() for it in items)))
        t1 = time.perf_counter()
        for (rows, ids, _), (moved, xy, tri) in zip(pieces, runner.map(relax_piece, items)):
            if len(tri) != len(rows):
                raise InternalError("a piece's region has another triangle count (a bug: please report it)")
            P[ids[moved]] = xy
            T[near[rows]] = ids[tri]
        clock["seams_cut"] += t1 - t0
        clock["seams_pieces"] += time.perf_counter() - t1
    t0 = time.perf_counter()
    out = finish(polygon, P, T, free, h, objective)
    clock["seams_finish"] = time.perf_counter() - t0
    if times is not None:
        times.update(clock)
    return out


def finish(polygon: Polygon, points, triangles, free, h: float, objective: str = "balanced"):
    """The last round, here: the ``free`` points within :data:`SPOT_RADIUS` h of
    an edge shorter than :data:`SHORT` h or longer than :data:`LONG` h move
    again, the whole mesh loaded (its extremes, which a piece does not see,
    set the balance of the objective), everything else frozen.  Returns the
    kernel's exact constrained Delaunay triangulation of the moved points."""
    P = np.asarray(points, dtype=np.float64)
    T = np.asarray(triangles, dtype=np.int64)
    E = unique_edges(T)
    L = np.linalg.norm(P[E[:, 1]] - P[E[:, 0]], axis=1)
    bad = (L < SHORT * h) | (L > LONG * h)
    spots = np.zeros(len(P), dtype=bool)
    if bad.any():
        r = np.nextafter(SPOT_RADIUS * h, np.inf)
        d, _ = cKDTree(0.5 * (P[E[bad, 0]] + P[E[bad, 1]])).query(P, distance_upper_bound=r, workers=-1)
        spots = (d <= r) & np.asarray(free)
    log.info("seams: %d edges beyond [%g, %g] h, %d points move again", int(bad.sum()), SHORT,
             LONG, int(spots.sum()))
    st = KernelMesh.from_mesh(polygon, P, T, href=h, frozen=~spots[len(polygon.vertices):])
    run = st.advance(FINISH, objective_code(objective))
    pts, tri, _ = st.result(run)
    return pts, np.asarray(tri, dtype=np.int64)
