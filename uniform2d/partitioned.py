"""One mesh made in K parts, here, in local processes or on a Dask cluster.

:func:`partitioned_mesh` is ``uniform_mesh(polygon, n, parts=K)``:

1. :func:`uniform2d.partition.partition` cuts P into K parts of near-equal
   area and samples every ring, segment and cut once at the target spacing h;
2. the points left, n minus those samples, are shared among the parts' faces
   by area (:func:`uniform2d.parts.allocate`: exactly n in all);
3. every part is meshed apart (:func:`uniform2d.parts.map_parts`,
   :func:`mesh_face`): the optimiser's start for a large mesh moved by its
   kernel, the cut points on its ring kept, so the parts meet on the cut
   points they share;
4. the parts are stitched (:func:`uniform2d.parts.stitch`) and the band within
   :data:`BAND` h of the cuts is relaxed (:func:`relax_seams`): the cuts stop
   being constraints, their points and their neighbours move and the mesh is
   made constrained Delaunay again; the band is moved in pieces, in parallel
   on the parts' workers (:mod:`uniform2d.seams`).

The result does not depend on where the parts ran: the same K gives the same
bytes with 1 process, 8 or a cluster.  Different K cut differently and give
different, equally valid meshes.
"""

from __future__ import annotations

import itertools
import logging
import math
import shutil
import time

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import libm
from ._kernel.distance import to_segments
from ._parallel import Runner, ordered_map
from .errors import InsufficientPointsError, InternalError
from .geometry import is_vertex, polygon_edges, unique_edges
from .mesh import Mesh
from .optimize.boundary import boundary_counts, boundary_points
from .optimize.fill import fill_band_gaps
from .optimize.lattice import Candidates, hex_lattice
from .optimize.moves import improve_kept
from .optimize.rows import boundary_rows, keep_clear
from .optimize.schedule import SCHEDULE, schedule_for
from .optimize.seed import start
from .partition import Partition, partition
from .parts import allocate, stitch
from .polygon import Polygon
from .seams import LIGHT, relax_band
from .triangulation import triangulate
from .validity import ensure_valid

__all__ = ["BAND", "CUT_REACH", "RESEED", "RING_KEEP", "global_lattice", "mesh_face", "mesh_faces",
           "part_counts", "partitioned_mesh", "relax_seams", "seam_uniformity", "write_part", "write_pvtu"]

log = logging.getLogger(__name__)

#: The band relaxed after stitching: points within BAND h of a cut move.
BAND = 6.0

#: The band made the shared lattice again after stitching (wider than the
#: optimiser's own band, :data:`uniform2d.optimize.schedule.BAND`, in which a
#: part's points leave its lattice).
RESEED = 10.0

#: The band along the rings relaxed again after stitching (in h; the
#: optimiser's own, :data:`uniform2d.optimize.schedule.BAND`).
RING_BAND = 12.0

#: With the shared lattice, the cuts' band moves only within CUT_REACH h of the
#: rings: beyond, reseeded, it is that lattice exactly, as is the mesh around it.
CUT_REACH = 27.0

#: Secant steps of :func:`global_lattice`'s search on the spacing.
_SPACING_STEPS = 6

#: Points this close to a ring, segment or fixed point (in h) are not reseeded.
RING_KEEP = 1.5

_AREA_PER_VERTEX = math.sqrt(3.0) / 2.0  # of an equilateral mesh of unit edge


def _boundary_pieces(poly: Polygon, h: float) -> np.ndarray:
    """Pieces of every constraint edge of a face, as the optimiser's start splits
    them (:func:`uniform2d.optimize.boundary.boundary_counts`, uncapped)."""
    _, _, L = polygon_edges(poly, constraints=True)
    return np.maximum(1, np.rint(L / h)).astype(np.int64)


def part_counts(part: Partition, n: int) -> list:
    """Steiner points of every face of every part: with the shared points, n in all.

    A face places the points on its ring's own stretches (between the shared
    points) as the optimiser's start does, and gets, of the rest, what an
    equilateral mesh of spacing h would put inside it, ``area / (sqrt(3)/2 h^2)
    - (perimeter / 2 + segments) / h`` (:func:`uniform2d.parts.allocate`: the
    sum is exact).

    Raises
    ------
    InsufficientPointsError
        If the shared and ring points alone are more than n.
    """
    h = part.h
    pairs = {(int(a), int(b)) for c in part.cuts for a, b in itertools.pairwise(c)}
    ring, est = [], []
    for faces, idx in zip(part.parts, part.index):
        for f, ii in zip(faces, idx):
            m = _boundary_pieces(f, h)
            E = ii[f.constraint_edges]
            if any(m[e] > 1 for e in range(len(E)) if (int(E[e, 0]), int(E[e, 1])) in pairs
                   or (int(E[e, 1]), int(E[e, 0])) in pairs):
                raise InternalError("a cut piece would get points of its own (a bug: please report it)")
            ring.append(int((m - 1).sum()))
            seg = polygon_edges(f, constraints=True)[2][len(f.edges):].sum()
            est.append(max(f.area / (_AREA_PER_VERTEX * h * h) - (f.perimeter / 2 + seg) / h, 1e-9))
    shared = len(part.points) - part.n_vertices
    rest = n - shared - sum(ring)
    if rest < 0:
        raise InsufficientPointsError(
            f"n = {n} is too small for {len(part.parts)} parts: their rings, segments and cuts "
            f"alone take {shared + sum(ring)} points; ask for more points or fewer parts"
        )
    flat = np.asarray(ring) + allocate(est, rest)
    out, k = [], 0
    for faces in part.parts:
        out.append([int(c) for c in flat[k:k + len(faces)]])
        k += len(faces)
    return out


def mesh_face(poly: Polygon, count: int, h: float, angle: float, objective: str = "balanced",
              schedule: dict | None = None, lattice=None):
    """One face's mesh: ``points`` (the polygon's vertices, then ``count``
    Steiner points) and ``triangles`` (m, 3) int64.

    The optimiser's start for a large mesh (the ring's own stretches split at
    h, a first row, a lattice aligned as close to ``angle`` as the face allows),
    moved by :func:`uniform2d.optimize.moves.improve_kept` with the deep lattice
    frozen; the ring's shared points (on cuts) stay, its own ones slide.
    ``schedule``: the fields of :class:`uniform2d.optimize.schedule.Schedule`
    (default: the one for the face's own size).  ``lattice``: ``(origin,
    angle, spacing)`` of the whole mesh's lattice (:func:`global_lattice`):
    the parts' deep lattices are then one lattice, in phase across the cuts."""
    K = len(poly.vertices)
    if count == 0:
        P, T = triangulate(poly)
    else:
        sites, edges, frozen, _ = start(poly, count, h, (1.0, _lattice_edge(poly, angle), True),
                                        lattice=lattice)
        P, T, _ = improve_kept(poly, sites, objective=objective, href=h, frozen=frozen, edges=edges,
                               **(schedule or {}))
    if len(P) != K + count and not (lattice and lattice[3]):
        raise InternalError(f"a part has {len(P) - K} points, not {count} (a bug: please report it)")
    return np.asarray(P), np.asarray(T, dtype=np.int64)


def mesh_faces(item):
    """Mesh one part: ``[(own points (c, 2), triangles (m, 3) local), ...]`` per face.

    ``item`` is ``(faces, counts, h, angle, objective, schedule, lattice)``
    (:func:`mesh_face` for each face); a face's local points are its polygon's vertices, then its own.
    A module-level function: local processes and Dask workers import it by name."""
    faces, counts, h, angle, objective, schedule, lattice = item[:7]
    out = []
    for poly, count in zip(faces, counts):
        P, T = mesh_face(poly, count, h, angle, objective, schedule, lattice)
        out.append((np.ascontiguousarray(P[len(poly.vertices):]), T))
    return out


def write_part(item) -> tuple[int, int]:
    """Mesh one part and write it as a piece: ``item`` is :func:`mesh_faces`'s, then
    ``(index, first, path)``: per face the global number of each polygon vertex,
    per face the global number of its first own point, and the piece's file;
    optionally then the whole polygon, whose region each triangle is in is
    written as the cell array ``region``.  Returns the piece's (points, triangles)."""
    from .io.pvtu import write_piece

    index, first, path = item[7:10]
    whole = item[10] if len(item) > 10 else None
    ids, pts, tris, regs, base = [], [], [], [], 0
    for poly, count, idx, f0, (own, T) in zip(item[0], item[1], index, first, mesh_faces(item)):
        P = np.concatenate([poly.vertices, own])
        ensure_valid(P, T, poly, count, "a part")
        ids.append(np.concatenate([idx, f0 + np.arange(len(own), dtype=np.int64)]))
        pts.append(P)
        tris.append(T + base)
        if whole is not None:
            regs.append(_face_regions(whole, poly, P, T))
        base += len(ids[-1])
    ids, pts, tris = np.concatenate(ids), np.concatenate(pts), np.concatenate(tris)
    glob, first_at, local = np.unique(ids, return_index=True, return_inverse=True)
    write_piece(path, pts[first_at], local[tris], glob, np.concatenate(regs) if regs else None)
    return len(glob), len(tris)


def _face_regions(whole: Polygon, face: Polygon, P, T) -> np.ndarray:
    """(m,) int64: the region of ``whole`` each triangle of a face's mesh is in:
    the triangles joined across the edges on no segment, each group located
    by its largest triangle's centroid (as :func:`uniform2d.mesh_regions.triangle_regions`)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    if not len(whole.segment_edges):
        return np.zeros(len(T), np.int64)
    seg = {tuple(e) for e in np.sort(face.segment_edges, axis=1).tolist()}
    he = np.sort(T[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    owner = np.repeat(np.arange(len(T)), 3)
    order = np.lexsort((he[:, 1], he[:, 0]))
    k, o = he[order], owner[order]
    i = np.flatnonzero((k[1:] == k[:-1]).all(axis=1))
    i = i[[tuple(k[j]) not in seg for j in i.tolist()]] if len(i) else i
    _, comp = connected_components(coo_matrix((np.ones(len(i)), (o[i], o[i + 1])),
                                              shape=(len(T), len(T))), directed=False)
    q = P[T]
    a, b = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
    area = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    out = np.empty(len(T), np.int64)
    for c in np.unique(comp).tolist():
        tri = np.flatnonzero(comp == c)
        x, y = q[tri[np.argmax(area[tri])]].mean(axis=0)
        out[tri] = whole.regions.locate(x, y)
    return out


def _lattice_edge(poly: Polygon, angle: float) -> int:
    """The face's edge nearest ``angle`` (modulo 60 degrees; the longest of those
    within a degree): every part's lattice runs the same way, as one lattice
    of the whole would, and along the cuts."""
    _, d, L = polygon_edges(poly)
    off = np.abs((libm.arctan2(d[:, 1], d[:, 0]) - angle + math.pi / 6) % (math.pi / 3) - math.pi / 6)
    near = off <= max(off.min(), math.radians(1.0))
    return int(np.lexsort((np.arange(len(L)), -L, ~near))[0])


def _within(sites, points, r: float) -> np.ndarray:
    """(k,) bool: which ``points`` are within ``r`` of one of ``sites``; the tree
    stops looking beyond r (at 1e7 points four times faster than a full query)."""
    d, _ = cKDTree(np.asarray(sites)).query(points, distance_upper_bound=np.nextafter(r, np.inf), workers=-1)
    return d <= r


def seam_uniformity(points, triangles, seam_points, h: float) -> dict:
    """Edge-length CV within ``2 h`` of the seams (edge midpoints) and away from them.

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> d = seam_uniformity(P, np.array([[0, 1, 2], [1, 3, 2]]), P[:1], 0.1)
    >>> d["near_edges"], round(d["cv_away"], 3)
    (0, 0.153)
    """
    E = unique_edges(np.asarray(triangles))
    P = np.asarray(points)
    L = np.linalg.norm(P[E[:, 1]] - P[E[:, 0]], axis=1)
    near = np.zeros(len(E), dtype=bool)
    if len(seam_points):
        near = _within(seam_points, 0.5 * (P[E[:, 0]] + P[E[:, 1]]), 2.0 * h)

    def cv(x):
        return float(x.std() / x.mean()) if len(x) else float("nan")

    return {"cv_near_seams": cv(L[near]), "cv_away": cv(L[~near]), "near_edges": int(near.sum())}


def global_lattice(polygon: Polygon, n: int, h: float) -> tuple:
    """``(origin, angle, spacing, True)``: the lattice every part and the seams
    share (:func:`uniform2d.optimize.lattice.seed_interior`'s ``lattice``).

    Anchored as an unpartitioned mesh's (a row h sqrt(3)/2 inside the longest
    edge, along it), its spacing such that the whole polygon, with its
    boundary points and first rows, holds n points as near as a few secant
    steps find (the count goes about as 1/spacing**2): the points the seams
    must add or leave out after the parts are few (added after the parts'
    relaxation, many would crowd the rings' first layer)."""
    a, d, L = polygon_edges(polygon, constraints=True)
    m = boundary_counts(L, h, n)
    bpts = boundary_points(a, d, m)[0]
    bpts = bpts[~is_vertex(polygon, bpts)] if polygon.has_constraints else bpts
    rows = boundary_rows(polygon, m, h)
    cand = Candidates(polygon, h, None, rows)
    want = n - len(bpts) - len(rows)
    sp = h
    for _ in range(_SPACING_STEPS):
        got = len(cand(sp)[0])
        if got == want:
            break
        sp *= math.sqrt(got / want)
    return (cand.origin, float(cand.angle), float(sp), True)


def _reseed(polygon: Polygon, P: np.ndarray, part: Partition, lattice, n: int) -> np.ndarray:
    """The Steiner points with the band within :data:`RESEED` h of the cuts (and
    :data:`RING_KEEP` h or more from the rings, segments and fixed points)
    replaced by the shared lattice's points there: the parts' lattices are that
    lattice deeper inside, so the band joins them without a seam.  n Steiner
    points in the end: lattice points nearest the rings are left out, or points
    added in the largest triangles along the rings
    (:func:`uniform2d.optimize.fill.fill_band_gaps`)."""
    h, nV = part.h, len(polygon.vertices)
    cutp = part.points[np.concatenate(part.cuts)]
    sa, sb = keep_clear(polygon)
    far = RING_KEEP * h
    band = _within(cutp, P, RESEED * h) & (to_segments(P, sa, sb, far) >= far)
    band[: len(part.points) - part.n_cut] = False  # vertices and segment samples stay
    lo, hi = cutp.min(axis=0) - RESEED * h, cutp.max(axis=0) + RESEED * h
    box = np.maximum(lo, polygon.bounds[:2]).tolist() + np.minimum(hi, polygon.bounds[2:]).tolist()
    Q = hex_lattice(box, lattice[2], lattice[1], lattice[0])
    Q = Q[_within(cutp, Q, RESEED * h)]
    Q = Q[shapely.contains_xy(polygon.to_shapely(), Q[:, 0], Q[:, 1])]
    dq = to_segments(Q, sa, sb, far)
    Q, dq = Q[dq >= far], dq[dq >= far]
    gone = np.flatnonzero(band)
    extra = len(gone) + n - (len(P) - nV) - len(Q)
    if extra < 0:  # too many lattice points: those nearest the rings go
        order = np.lexsort((np.arange(len(Q)), dq))
        Q = Q[np.sort(order[-extra:])]
    log.info("seams: %d band points replaced by %d of the shared lattice (%d to place)", int(band.sum()), len(Q), extra)
    sites = np.concatenate([P[nV:][~band[nV:]], Q])
    if extra > 0:  # too few: added where the mesh is sparsest along the rings
        sites = fill_band_gaps(polygon, np.zeros((0, 2)), sites, len(sites) + extra, h, sa, sb)
    return sites


def relax_seams(polygon: Polygon, points, triangles, part: Partition, objective: str = "balanced",
                lattice=None, n: int | None = None, runner=None, times: dict | None = None):
    """The stitched mesh with the band within :data:`BAND` h of the cuts relaxed.

    The cut points are ordinary points now: they and their neighbours move (the
    optimiser's moves, :mod:`uniform2d.optimize`, with everything else frozen
    and the full schedule, on the band only; those on a ring slide along it),
    piece by piece on ``runner`` (:func:`uniform2d.seams.relax_band`; default:
    here), and the result is the kernel's own exact constrained Delaunay
    triangulation of the moved points.  Vertices and segment samples do not
    move.  With ``lattice`` (the parts' shared
    lattice, :func:`global_lattice`) the band within :data:`RESEED` h of the
    cuts is first made that lattice again (the mesh is triangulated anew, with
    ``n`` Steiner points: the parts may have taken their lattice's natural
    count); the band relaxed is then the rings' and, within :data:`CUT_REACH` h
    of them, the cuts' :data:`RESEED` + 1 h (schedule :data:`uniform2d.seams.LIGHT`).  ``times``
    gets the seams' pass's own times (:func:`uniform2d.seams.relax_band`).

    Returns
    -------
    points : (N, 2) float64
    triangles : (M, 3) int64
    """
    nV = len(polygon.vertices)
    P = np.asarray(points, dtype=np.float64)
    fixed = len(part.points) - part.n_cut
    width = BAND
    if lattice is not None:
        sites = _reseed(polygon, P, part, lattice, len(P) - nV if n is None else n)
        P, triangles = triangulate(polygon, sites)
        width = RESEED + 1.0
    cut = _within(part.points[np.concatenate(part.cuts)], P, width * part.h)
    if lattice is None:
        free = cut
    else:  # and the rings' bands: a part's worst corner left them slack; the cut's
        # band is the shared lattice beyond them, so it moves only near the rings
        sa, sb = keep_clear(polygon)
        ring, reach = (RING_BAND + 1.0) * part.h, CUT_REACH * part.h
        dr = to_segments(P, sa, sb, reach)
        free = (dr < ring) | (cut & (dr < reach))
    free[:fixed] = False  # vertices and segment samples stay (first in both)
    seg = [ii[f.segment_edges] for faces, idx in zip(part.parts, part.index) for f, ii in zip(faces, idx)]
    seg = np.unique(np.sort(np.concatenate([np.zeros((0, 2), np.int64), *seg]), axis=1), axis=0)
    sched = SCHEDULE if lattice is None else LIGHT
    if runner is not None:
        return relax_band(polygon, P, triangles, free, part.h, fixed, seg, runner, objective, times, sched)
    with Runner() as run:
        return relax_band(polygon, P, triangles, free, part.h, fixed, seg, run, objective, times, sched)


def _plan(polygon: Polygon, n: int, parts: int, objective: str, shared: bool = False):
    """The partition and every part's item for :func:`mesh_faces`; with ``shared``
    (and no segments), the parts take the natural counts of one shared lattice
    (:func:`global_lattice`)."""
    part = partition(polygon, n, parts)
    counts = part_counts(part, n)
    _, d, L = polygon_edges(polygon)
    angle = math.atan2(*d[np.argmax(L)][::-1])  # the longest edge's direction
    # the whole mesh's schedule: a part is meshed as the whole would be there
    sched = schedule_for(len(polygon.vertices) + n, False)._asdict()
    lat = None
    if shared and part.cuts and not len(polygon.segment_edges):
        lat = global_lattice(polygon, n, part.h)
    return part, [(faces, c, part.h, angle, objective, sched, lat)
                  for faces, c in zip(part.parts, counts)]


def write_pvtu(polygon: Polygon, n: int, parts: int, path, *, jobs: int = 1, scheduler=None,
               objective: str = "balanced", bar=None) -> dict:
    """Mesh in ``parts`` parts, each worker writing its part as a piece of ``path``.

    The mesh is never gathered: this process holds the partition and the cut
    points only.  The seams are not relaxed (that needs both sides of a cut in
    one place): the pieces are the parts as meshed, conforming across the cuts,
    each constrained Delaunay, the cuts still chains of edges.  Files as
    :mod:`uniform2d.io.pvtu` says: nothing is left behind if a part fails or
    the run is interrupted.  Returns ``{"parts", "points", "triangles", "h",
    "cut_points"}``.
    """
    from .io.pvtu import commit, piece_dir, piece_name

    part, items = _plan(polygon, n, parts, objective)
    S = len(part.points)
    own = np.cumsum([0] + [c for it in items for c in it[1]])
    tmp = piece_dir(path)
    names = [piece_name(path, k) for k in range(len(items))]
    full, k = [], 0
    regions = polygon.has_constraints or bool(polygon.region_seeds)
    for it, idx, name in zip(items, part.index, names):
        full.append((*it, idx, [int(S + own[k + j]) for j in range(len(idx))], str(tmp / name),
                     polygon if regions else None))
        k += len(idx)
    try:
        done = list(ordered_map(write_part, full, jobs=jobs, scheduler=scheduler, bar=bar))
        commit(path, tmp, names, regions)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    return {"parts": int(parts), "points": len(polygon.vertices) + n,
            "triangles": int(sum(t for _, t in done)), "h": part.h, "cut_points": part.n_cut}


def partitioned_mesh(polygon: Polygon, n: int, parts: int, *, jobs: int = 1, scheduler=None,
                     relax: bool = True, objective: str = "balanced", bar=None,
                     mesher=None) -> Mesh:
    """A mesh with exactly ``n`` Steiner points made in ``parts`` parts (see the module).

    Parameters
    ----------
    polygon : Polygon
    n : int
    parts : int
    jobs : int
        Local processes (1: here).
    scheduler : str or distributed.Client, optional
        A Dask scheduler's address or client; overrides ``jobs``.
    relax : bool
        Relax the seams after stitching (default).
    objective : str
        What the parts' and the seams' point moves lower
        (:data:`uniform2d.optimize.OBJECTIVES`).
    bar : tqdm, optional
        Updated once per part meshed.
    mesher : callable, optional
        What runs one part (default :func:`mesh_faces`): a module-level wrapper
        of it may instrument the parts (the tests kill a worker with one).

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.partitioned import partitioned_mesh
    >>> m = partitioned_mesh(Polygon([(0, 0), (3, 0), (3, 1), (0, 1)]), 300, 3)
    >>> m.n_steiner, m.info["parts"]
    (300, 3)
    """
    nV = len(polygon.vertices)
    clock, times, seams = time.perf_counter(), {}, {}

    def lap(name):
        nonlocal clock
        now = time.perf_counter()
        times[name] = now - clock
        clock = now

    part, items = _plan(polygon, n, parts, objective, relax)
    lat = items[0][6]
    lap("partition")
    with Runner(jobs, scheduler) as run:
        done = list(run.map(mesher or mesh_faces, items, bar=bar))
        lap("parts")
        pieces = [(idx, own, T) for ii, res in zip(part.index, done) for idx, (own, T) in zip(ii, res)]
        del done
        P, T = stitch(part.points, pieces)
        del pieces
        if lat is None and len(P) != nV + n:
            raise InternalError(f"the stitched mesh has {len(P) - nV} Steiner points, not {n} (a bug)")
        seam = part.points[np.concatenate(part.cuts)] if part.cuts else np.zeros((0, 2))
        before = seam_uniformity(P, T, seam, part.h)
        lap("stitch")
        if relax and part.cuts:
            P, T = relax_seams(polygon, P, T, part, objective, lat, n, runner=run, times=seams)
        lap("relax")
        times.update(seams)
    ensure_valid(P, T, polygon, n, "uniform_mesh(parts=...)")
    lap("check")
    info = {"method": "partitioned", "parts": int(parts), "h": part.h,
            "cut_points": part.n_cut, "shared_points": len(part.points) - nV,
            "seams_before_relax": before, "seams": seam_uniformity(P, T, seam, part.h),
            "times": times}
    log.info("partitioned: %d parts, %d cut points, seams %s", parts, part.n_cut, info["seams"])
    return Mesh(np.asarray(P), np.asarray(T, dtype=np.int64), polygon, n, info)
