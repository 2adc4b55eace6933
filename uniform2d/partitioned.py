"""One mesh made in K parts, here, in local processes or on a Dask cluster.

:func:`partitioned_mesh` is ``uniform_mesh(polygon, n, parts=K)``:

1. :func:`uniform2d.partition.partition` cuts P into K parts of near-equal
   area and samples every ring, segment and cut once at the target spacing h;
2. the points left, n minus those samples, are shared among the parts' faces
   by area (:func:`uniform2d.parts.allocate`: exactly n in all);
3. every part is meshed apart (:func:`uniform2d.parts.map_parts`): a lattice
   seed moved by :func:`uniform2d.optimize.improve`, its ring kept, so the
   parts meet on the cut points they share;
4. the parts are stitched (:func:`uniform2d.parts.stitch`) and the band within
   :data:`BAND` h of the cuts is relaxed (:func:`relax_seams`): the cuts stop
   being constraints, their points and their neighbours move and the mesh is
   made constrained Delaunay again.

The result does not depend on where the parts ran: the same K gives the same
bytes with 1 process, 8 or a cluster.  Different K cut differently and give
different, equally valid meshes.
"""

from __future__ import annotations

import itertools
import logging
import math

import numpy as np
from scipy.spatial import cKDTree

from ._parallel import ordered_map
from .errors import InsufficientPointsError, InternalError
from .geometry import polygon_edges, unique_edges
from .mesh import Mesh
from .optimize import improve
from .optimize.moves import improve_kept
from .optimize.seed import start
from .partition import Partition, partition
from .parts import allocate, stitch
from .polygon import Polygon
from .triangulation import triangulate
from .validity import ensure_valid

__all__ = ["BAND", "mesh_faces", "part_counts", "partitioned_mesh", "relax_seams", "seam_uniformity"]

log = logging.getLogger(__name__)

#: The band relaxed after stitching: points within BAND h of a cut move.
BAND = 3.0

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


def mesh_faces(item):
    """Mesh one part: ``[(own points (c, 2), triangles (m, 3) local), ...]`` per face.

    ``item`` is ``(faces, counts, h, angle)``; a face's local points are its
    polygon's vertices, then its ``count`` Steiner points: the optimiser's start
    for a large mesh (its ring's own stretches split at h, a first row, a
    lattice aligned as close to ``angle`` as the face allows), moved by
    :func:`uniform2d.optimize.moves.improve_kept` with the deep lattice frozen.
    A module-level function: local processes and Dask workers import it by name."""
    faces, counts, h, angle = item
    out = []
    for poly, count in zip(faces, counts):
        K = len(poly.vertices)
        if count == 0:
            P, T = triangulate(poly)
        else:
            sites, edges, frozen, _ = start(poly, count, h, (1.0, _lattice_edge(poly, angle), True))
            P, T, _ = improve_kept(poly, sites, href=h, frozen=frozen, edges=edges)
        if len(P) != K + count:
            raise InternalError(f"a part has {len(P) - K} points, not {count} (a bug: please report it)")
        out.append((np.ascontiguousarray(P[K:]), np.asarray(T, dtype=np.int64)))
    return out


def _lattice_edge(poly: Polygon, angle: float) -> int:
    """The face's edge nearest ``angle`` (modulo 60 degrees; the longest of those
    within a degree): every part's lattice runs the same way, as one lattice
    of the whole would, and along the cuts."""
    _, d, L = polygon_edges(poly)
    off = np.abs((np.arctan2(d[:, 1], d[:, 0]) - angle + math.pi / 6) % (math.pi / 3) - math.pi / 6)
    near = off <= max(off.min(), math.radians(1.0))
    return int(np.lexsort((np.arange(len(L)), -L, ~near))[0])


def seam_uniformity(points, triangles, seam_points, h: float) -> dict:
    """Edge-length CV within ``2 h`` of the seams (edge midpoints) and away from them.

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> d = seam_uniformity(P, np.array([[0, 1, 2], [1, 3, 2]]), P[:1], 0.1)
    >>> d["near_edges"], round(d["cv_away"], 3)
    (0, 0.146)
    """
    E = unique_edges(np.asarray(triangles))
    P = np.asarray(points)
    L = np.linalg.norm(P[E[:, 1]] - P[E[:, 0]], axis=1)
    near = np.zeros(len(E), dtype=bool)
    if len(seam_points):
        d, _ = cKDTree(np.asarray(seam_points)).query(0.5 * (P[E[:, 0]] + P[E[:, 1]]))
        near = d <= 2.0 * h

    def cv(x):
        return float(x.std() / x.mean()) if len(x) else float("nan")

    return {"cv_near_seams": cv(L[near]), "cv_away": cv(L[~near]), "near_edges": int(near.sum())}


def relax_seams(polygon: Polygon, points, part: Partition):
    """The stitched mesh with the band within :data:`BAND` h of the cuts relaxed.

    The cut points are ordinary points now: they and their neighbours move
    (:func:`uniform2d.optimize.improve` with everything else frozen; those on a
    ring slide along it), and the result is the exact constrained Delaunay
    triangulation of the moved points, which also makes the mesh Delaunay
    across the cuts again.  Vertices and segment samples do not move.

    Returns
    -------
    points : (N, 2) float64
    triangles : (M, 3) int64
    """
    nV = len(polygon.vertices)
    P = np.asarray(points, dtype=np.float64)
    free = np.zeros(len(P), dtype=bool)
    if part.cuts:
        d, _ = cKDTree(part.points[np.concatenate(part.cuts)]).query(P)
        free = d <= BAND * part.h
    free[: len(part.points) - part.n_cut] = False  # vertices and segment samples stay
    pts, tri, _ = improve(polygon, P[nV:], href=part.h, frozen=~free[nV:])
    return pts, tri


def partitioned_mesh(polygon: Polygon, n: int, parts: int, *, jobs: int = 1, scheduler=None,
                     relax: bool = True, bar=None) -> Mesh:
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
    bar : tqdm, optional
        Updated once per part meshed.

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> from uniform2d.partitioned import partitioned_mesh
    >>> m = partitioned_mesh(Polygon([(0, 0), (3, 0), (3, 1), (0, 1)]), 300, 3)
    >>> m.n_steiner, m.info["parts"]
    (300, 3)
    """
    nV = len(polygon.vertices)
    part = partition(polygon, n, parts)
    counts = part_counts(part, n)
    _, d, L = polygon_edges(polygon)
    e = int(np.argmax(L))
    angle = float(np.arctan2(d[e, 1], d[e, 0]))
    items = [(faces, c, part.h, angle) for faces, c in zip(part.parts, counts)]
    done = list(ordered_map(mesh_faces, items, jobs=jobs, scheduler=scheduler, bar=bar))
    pieces = [(idx, own, T) for ii, res in zip(part.index, done) for idx, (own, T) in zip(ii, res)]
    P, T = stitch(part.points, pieces)
    if len(P) != nV + n:
        raise InternalError(f"the stitched mesh has {len(P) - nV} Steiner points, not {n} (a bug)")
    seam = part.points[np.concatenate(part.cuts)] if part.cuts else np.zeros((0, 2))
    before = seam_uniformity(P, T, seam, part.h)
    if relax and part.cuts:
        P, T = relax_seams(polygon, P, part)
    ensure_valid(P, T, polygon, n, "uniform_mesh(parts=...)")
    info = {"method": "partitioned", "parts": int(parts), "h": part.h,
            "cut_points": part.n_cut, "shared_points": len(part.points) - nV,
            "seams_before_relax": before, "seams": seam_uniformity(P, T, seam, part.h)}
    log.info("partitioned: %d parts, %d cut points, seams %s", parts, part.n_cut, info["seams"])
    return Mesh(np.asarray(P), np.asarray(T, dtype=np.int64), polygon, n, info)
