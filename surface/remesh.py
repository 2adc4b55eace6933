"""Remeshing a surface patch with edges as equal in length as possible.

The pipeline (see ``docs/surface.md``)::

    patch --check--> Patch --parameterize--> UV map (flip- and overlap-free)
          --boundary_domain--> Polygon (corners kept, boundary even in 3-D length
                               within a chord-height tolerance)
          --compensation_field--> SizeField h * sqrt(area scale)
          --chart_mesh.mesh_domain--> planar mesh with exactly n_vertices points
          --lift--> 3-D mesh on the input surface --report--> measures + cross-check
"""

from __future__ import annotations

import logging
import numbers
import time

import numpy as np

from uniform2d.errors import InsufficientPointsError, InvalidArgumentError
from uniform2d.geometry import boundary_edges, nearest_segment, segment_distance

from . import _igl
from .chart_mesh import mesh_domain, size_field
from .domain import CORNER_ANGLE, boundary_domain
from .features import constrain, find_chains, lift_points
from .lift import lift
from .io import as_model
from .measure import edge_stats, unique_edges
from .atlas_remesh import remesh_atlas
from .charts import ONE_PIECE_RATIO
from .errors import ParameterizationError
from .fidelity import meshlab_checks
from .model import Model
from .parameterize import parameterize
from .patch import Patch
from .quality_gate import check_quality
from .result import RemeshResult
from .report import Report, size_trend
from .size3d import Size3D, count_for_size, integrals, q_stats, scale_for_count
from .sizing import (
    target_size, vertex_count
)

__all__ = ["RemeshResult", "remesh"]

log = logging.getLogger(__name__)

def _as_count(n) -> int:
    if isinstance(n, bool) or not isinstance(n, numbers.Integral):
        if isinstance(n, numbers.Real) and float(n).is_integer():
            n = int(n)
        else:
            raise InvalidArgumentError(f"n_vertices must be an integer, got {n!r}")
    if n < 3:
        raise InvalidArgumentError(f"n_vertices must be at least 3, got {n}")
    return int(n)


def remesh(
    patch,
    n_vertices=None,
    *,
    size=None,
    param: str = "lscm",
    compensate: bool = True,
    corner_angle: float = CORNER_ANGLE,
    chord_tol: float | str | None = "auto",
    check: bool = True,
    hausdorff: bool = True,
    optimize: bool = True,
    feature_angle: float | None = None,
    features=(),
    fixed=(),
    jobs: int = 1,
    scheduler=None,
) -> RemeshResult:
    """Remesh a surface with near-equal 3-D edges and exactly ``n_vertices`` vertices.

    A disk (holes allowed) whose flattening has low distortion is flattened in one
    piece; every other model -- closed, of any genus, in several parts, or too
    curved -- is cut into an atlas of such charts (:mod:`surface.atlas`), whose
    seams are sampled once and shared, and the charts' meshes are stitched and
    relaxed across the seams.

    Parameters
    ----------
    patch : path, (V, F) pair, trimesh.Trimesh, Patch or Model
        Any manifold, consistently oriented triangle mesh (see :class:`surface.Model`):
        open or closed, of any genus, in one or several parts.
    n_vertices : int, optional
        Exact number of vertices of the output.  Default: the input's vertex count
        (unless ``size`` is given).
    size : float or callable, optional
        Target 3-D edge length instead of a count (give one or the other); the
        count is then derived from the area and boundary length.  A callable
        ``h(points (k, 3)) -> (k,)`` is a graded size on the surface (see
        :mod:`surface.size3d`): the edges follow ``h``, composed with the
        compensation field, and the boundary and seams are spaced by equal
        ``∫ ds / h``.  With ``n_vertices``, ``h``'s shape is kept and its scale
        chosen for exactly ``n_vertices``; without, ``h`` is absolute.  The
        report's ``edges`` then has ``q_min``, ``q_max``, ``q_ratio``, ``q_cv``
        of ``q = length / h(midpoint)`` (at the chosen scale).  Graded sizes need
        ``compensate=True`` and no feature lines or fixed vertices on a single
        patch; ``jobs > 1`` needs a callable that pickles.
    param : {"lscm", "arap", "harmonic"}
        Parameterisation to try first (see :mod:`surface.parameterize`).
    compensate : bool
        Grade the planar mesh by ``sqrt`` of the parameterisation's area scale and
        space the boundary evenly in 3-D, so the output is uniform in 3-D.  With
        False the planar mesh is uniform in UV instead.  Where that size varies
        by less than :data:`UNIFORM_SIZE` over the patch (a developable patch:
        the map is an isometry up to discretisation) no field is needed and the
        planar mesh is uniform.
    corner_angle : float
        Boundary vertices turning more than this (degrees, in 3-D) are kept.
    chord_tol : "auto", float or None
        Chord-height tolerance of the boundary, as a fraction of the edge length:
        boundary runs whose even spacing leaves an input boundary vertex farther
        than this from the output boundary edge are resampled (vertices moved onto
        input vertices, edges shortened down to 0.8 of the spacing; see
        :func:`surface.domain.boundary_domain`).  ``"auto"`` (default): the larger
        of 1/128 and the chord error the interior of the mesh has anyway
        (:func:`surface.chord.interior_chord_error`).  None: evenly spaced boundary.
    check : bool
        Run the pymeshlab cross-check (raises CrossCheckError on disagreement).
    hausdorff : bool
        Measure the Hausdorff distances to the input with pymeshlab.
    optimize : bool
        Mesh the domain with a lattice relaxed by :func:`uniform2d.optimize.improve`
        in the compensation metric (default), or, with False, with the paper's
        Algorithm INSERT alone (graded by the same field).
    feature_angle : float, optional
        Keep creases: interior edges whose faces' normals differ by more than this
        (degrees) become feature lines (see :mod:`surface.features`): chains of
        output edges lying on the input's feature edges.  Default: none (an atlas
        still cuts its charts along edges bent more than
        :data:`surface.charts.CREASE_ANGLE`, which keeps them).
    features : sequence of sequences of int
        More feature lines, as chains of consecutive input vertex indices.
    fixed : sequence of int
        Input vertices that must be output vertices (kept exactly where they are;
        single-chart patches only).
    jobs : int
        Local processes meshing an atlas's charts (the result does not depend on it).
    scheduler : str or distributed.Client, optional
        A Dask scheduler meshing the charts instead (the ``dask`` extra).

    Returns
    -------
    RemeshResult

    Raises
    ------
    InvalidPatchError
        If the mesh fails a check of :class:`surface.Model`.
    ParameterizationError
        If no flip-free, non-overlapping flattening was found.
    RemeshQualityError
        If the result's edge ratio exceeds :data:`surface.quality_gate.EDGE_RATIO_LIMIT`.
    InsufficientPointsError
        If ``n_vertices`` is too small to place the boundary points.
    CrossCheckError
        If pymeshlab disagrees with our edge measures.
    """
    times = {}
    t0 = time.perf_counter()
    M: Model = as_model(patch)
    times["check"] = time.perf_counter() - t0
    if callable(size) and not isinstance(size, numbers.Real):
        N, h = _graded_count(M, n_vertices, size)
        if not compensate:
            raise InvalidArgumentError("a graded size (a callable) needs compensate=True: it is a 3-D size")
    else:
        N, h = _count_and_size(M, n_vertices, size)
    t = time.perf_counter()
    P, prm = _one_chart(M, param)
    times["parameterize"] = time.perf_counter() - t
    if P is None:
        if len(fixed):
            raise InvalidArgumentError(
                "fixed vertices are supported on patches that flatten in one piece; this model "
                "is remeshed as an atlas of charts (closed, several parts, a handle or too curved)"
            )
        if not optimize:
            raise InvalidArgumentError(
                "optimize=False (INSERT alone) is for patches that flatten in one piece; this "
                "model is remeshed as an atlas of charts"
            )
        result = remesh_atlas(
            M, N, h, feature_angle=feature_angle, features=features, corner_angle=corner_angle,
            compensate=compensate, check=check, hausdorff=hausdorff, jobs=jobs,
            scheduler=scheduler, times=times, t0=t0,
        )
    else:
        result = _remesh_patch(
            P, prm, N, h, size=size, compensate=compensate, corner_angle=corner_angle,
            chord_tol=chord_tol, check=check, hausdorff=hausdorff, optimize=optimize,
            feature_angle=feature_angle, features=features, fixed=fixed, times=times, t0=t0,
        )
    check_quality(result.report)
    return result


def _one_chart(M: Model, param: str):
    """``(Patch, Parameterization)`` when ``M`` is a disk whose flattening has an
    area-scale ratio within :data:`surface.charts.ONE_PIECE_RATIO`, else
    ``(None, None)``: the model is remeshed as an atlas."""
    P = M.as_patch()
    if P is None:
        return None, None
    try:
        prm = parameterize(P, param)
    except ParameterizationError as exc:
        log.info("the patch does not flatten in one piece (%s): remeshing it as an atlas", exc)
        return None, None
    s = prm.area_scale
    if not s.max() <= ONE_PIECE_RATIO * s.min():
        log.info("flattening's area scale varies %.3g-fold: remeshing as an atlas", s.max() / s.min())
        return None, None
    return P, prm


def _remesh_patch(P: Patch, prm, N, h, *, size, compensate, corner_angle, chord_tol, check,
                  hausdorff, optimize, feature_angle, features, fixed, times, t0) -> RemeshResult:
    """The single-chart remesh: ``P`` flattened in one piece by ``prm``."""
    t = time.perf_counter()
    measure = "3d" if compensate else "uv"
    chains, fixed = find_chains(P, feature_angle, features, fixed, corner_angle)
    graded = h if isinstance(h, Size3D) else None
    if graded is not None and (chains or len(fixed)):
        raise InvalidArgumentError(
            "feature lines and fixed vertices are not supported with a graded size (a callable) "
            "on a patch that flattens in one piece; give a constant size or leave them out"
        )
    on_boundary = set(np.concatenate(P.boundary_loops).tolist())
    keep = sorted({int(v) for c in chains for v in (c[0], c[-1]) if v in on_boundary}
                  | (set(fixed.tolist()) & on_boundary))  # fmt: skip

    def domain_at(hm):
        if graded is not None:
            return boundary_domain(P, prm.uv, hm, measure=measure, corner_angle=corner_angle,
                                   chord_tol=chord_tol, size3d=graded.shape()), None
        d = boundary_domain(
            P, prm.uv, hm, measure=measure, corner_angle=corner_angle, chord_tol=chord_tol,
            keep=keep,
        )
        if not (chains or len(fixed)):
            return d, None
        return constrain(P, prm.uv, d, chains, fixed, hm, measure)

    domain, lines = domain_at(h if graded is None else graded.scale)
    times["domain"] = time.perf_counter() - t
    K = len(domain.polygon.vertices)
    if N < K:
        raise _too_few(P, N, h if graded is not None else size, K, domain.n_corners, domain_at)

    t = time.perf_counter()
    field = size_field(P, prm, h) if graded is None else size_field(P, prm, graded.scale, graded)
    times["size_field"] = time.perf_counter() - t

    t = time.perf_counter()
    pts, tris, mesher = mesh_domain(
        domain.polygon, N - K, field if compensate else None, optimize=optimize,
        graded_start=graded is not None,
    )
    times["mesh_2d"] = time.perf_counter() - t

    t = time.perf_counter()
    xyz, bmask, lifted = _lift(P, prm, domain, pts, tris, lines)
    times["lift"] = time.perf_counter() - t

    t = time.perf_counter()
    stats = edge_stats(xyz, tris)
    fidelity = _fidelity(P, xyz, tris, bmask, lifted)
    times["measure"] = time.perf_counter() - t
    meshlab = meshlab_checks(P, xyz, tris, stats, fidelity, times, check, hausdorff)
    times["total"] = time.perf_counter() - t0

    return _patch_result(P, prm, h, domain, field, (pts, tris, xyz, bmask),
                         (stats, fidelity, meshlab), times, mesher, compensate)


def _patch_result(P: Patch, prm, h, domain, field, mesh, measured, times, mesher,
                  compensate) -> RemeshResult:
    """The single-chart remesh's result and report: ``mesh`` is (uv points,
    triangles, lifted points, boundary mask), ``measured`` (3-D edge stats,
    fidelity, MeshLab's checks); with a graded size ``h`` (:class:`Size3D`) the
    edges are also measured against it."""
    pts, tris, xyz, bmask = mesh
    stats, fidelity, meshlab = measured
    graded = h if isinstance(h, Size3D) else None
    dist = prm.distortion(P.face_areas)
    dist["attempts"] = [list(a) for a in prm.attempts]
    edges = {k: v for k, v in stats.items() if not k.startswith("face_")}
    target = h
    if graded is not None:
        E = unique_edges(tris)
        q = graded.edge_q(xyz, E)
        edges.update(q_stats(q))
        target = float(np.mean(np.linalg.norm(xyz[E[:, 1]] - xyz[E[:, 0]], axis=1) / q))
    report = Report(
        n_vertices=len(pts), n_faces=len(tris), n_boundary=int(bmask.sum()),
        n_corners=domain.n_corners, target_size=target, diagonal=P.diagonal,
        edges=edges,
        edges_uv={k: v for k, v in edge_stats(pts, tris).items() if not k.startswith("face_")},
        meshlab=meshlab, parameterization=dist, size_trend=_size_trend(pts, tris, xyz, field, h),
        fidelity=fidelity, timings=times, mesher=mesher, compensate=bool(compensate),
    )
    for arr in (xyz, tris, pts, bmask):
        arr.setflags(write=False)
    return RemeshResult(xyz, tris, pts, bmask, report, domain)


def _count_and_size(P: Patch, n_vertices, size) -> tuple[int, float]:
    """The vertex count N and target edge length h asked for (one gives the other)."""
    A, Bl, chi = P.area, P.boundary_length, P.euler_characteristic
    if n_vertices is not None and size is not None:
        raise InvalidArgumentError("give n_vertices or size, not both")
    if size is not None:
        try:
            h = float(size)
        except (TypeError, ValueError):
            raise InvalidArgumentError(
                f"size must be a positive length or a callable h(points (k, 3)) -> (k,) sizes, "
                f"got {size!r}"
            ) from None
        if not (np.isfinite(h) and h > 0):
            raise InvalidArgumentError(f"size must be a positive length, got {size!r}")
        N = vertex_count(A, Bl, h, chi)
        if N < 3:
            raise InvalidArgumentError(f"size={size} is larger than the patch; use a smaller size")
    else:
        N = P.n_vertices if n_vertices is None else _as_count(n_vertices)
        h = target_size(A, Bl, N, chi) if N - chi > 0 else float("inf")
    return N, h


def _graded_count(M: Model, n_vertices, size) -> tuple[int, Size3D]:
    """The vertex count N and the graded size at its scale (see :mod:`surface.size3d`)."""
    g = size if isinstance(size, Size3D) else Size3D(size)
    chi = M.euler_characteristic
    ia, ib = integrals(M.vertices, M.faces, M.boundary_loops, g)
    g = Size3D(g.h, 1.0, (ia, ib, chi))
    if n_vertices is None:
        N = count_for_size(chi, ia, ib)
        if N < 3:
            raise InvalidArgumentError("the size callable is larger than the surface; use smaller sizes")
        return N, g
    N = _as_count(n_vertices)
    return N, g.scaled(scale_for_count(N, chi, ia, ib))


def _too_few(P: Patch, N: int, size, K: int, n_corners: int, domain_at):
    """The error for a count below the boundary's own K points, with the smallest
    count m that works (the least m whose domain has at most m points)."""
    A, Bl, chi = P.area, P.boundary_length, P.euler_characteristic

    def boundary_count(m):
        if isinstance(size, Size3D):
            return len(domain_at(size.spacing_for(m))[0].polygon.vertices)
        return len(domain_at(target_size(A, Bl, m, chi))[0].polygon.vertices)

    lo, hi = N, max(2 * N, 16)
    while boundary_count(hi) > hi:
        lo, hi = hi, 2 * hi
    while hi - lo > 1:  # smallest m with boundary_count(m) <= m
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if boundary_count(mid) <= mid else (mid, hi)
    what = f"n_vertices={N}" if size is None or isinstance(size, Size3D) else f"size={size} (about {N} vertices)"
    return InsufficientPointsError(
        f"{what} is too small: the boundary and feature lines alone need {K} points at that size "
        f"({n_corners} corners kept); the smallest vertex count that works "
        f"is {hi}"
    )


def _lift(P: Patch, prm, domain, pts, tris, lines=None):
    """The planar mesh on the patch: (xyz, boundary mask, the interior's lift).

    Polygon vertices go where the domain placed them; points the planar mesher
    put on polygon edges go to the same fraction of the input boundary arc, and
    points on feature lines to the same fraction of the feature arc
    (:func:`surface.features.lift_points`); interior points are lifted through
    the parameterisation."""
    V, F = P.vertices, P.faces
    n, K = len(pts), len(domain.polygon.vertices)
    nr = domain.polygon.n_ring_vertices
    bmask = np.zeros(n, dtype=bool)
    bmask[boundary_edges(tris, n).ravel()] = True
    xyz = np.zeros((n, 3))
    xyz[:nr] = domain.xyz
    placed = np.zeros(n, dtype=bool)
    placed[:K] = True
    if lines is not None:
        for k, q in lift_points(lines, domain.polygon, pts, V, np.flatnonzero(~bmask[K:]) + K).items():
            xyz[k] = q
            placed[k] = True
    extra = np.flatnonzero(bmask[K:]) + K
    if len(extra):
        ring_next = np.empty(K, dtype=np.int64)
        off = domain.polygon.ring_offsets
        for r in range(len(off) - 1):
            idx = np.arange(off[r], off[r + 1])
            ring_next[idx] = np.roll(idx, -1)
        pv = domain.polygon.vertices
        for k in extra:
            e, tt = nearest_segment(pts[k], pv, pv[ring_next])
            xyz[k] = domain.chord_points([e], [ring_next[e]], [tt], V)[0][0]
        log.info("%d points were inserted on the boundary", len(extra))
    inner = np.flatnonzero(~bmask & ~placed)
    lifted = lift(pts[inner], V, F, prm.uv)
    xyz[inner] = lifted.xyz
    return xyz, bmask, lifted


def _size_trend(pts, tris, xyz, field, h):
    """:func:`surface.report.size_trend` of the 3-D edges against the field's area scale."""
    E = unique_edges(tris)
    mid = 0.5 * (pts[E[:, 0]] + pts[E[:, 1]])
    L = np.linalg.norm(xyz[E[:, 1]] - xyz[E[:, 0]], axis=1)
    if isinstance(h, Size3D):  # q against the compensation alone
        hq = h(0.5 * (xyz[E[:, 0]] + xyz[E[:, 1]]))
        return size_trend(L / hq, (field(mid) / hq) ** 2)
    scale_mid = np.ones(len(mid)) if field is None else (field(mid) / h) ** 2
    return size_trend(L, scale_mid)


def _fidelity(P: Patch, xyz, tris, bmask, lifted) -> dict:
    """How far the output lies from the input surface, its boundary and its UV domain."""
    V, F = P.vertices, P.faces
    d2, _, _ = _igl.closest_points(xyz, V, F)
    bl = np.concatenate([np.stack([lp, np.roll(lp, -1)], axis=1) for lp in P.boundary_loops])
    bdist = segment_distance(xyz[bmask], V[bl[:, 0]], V[bl[:, 1]])
    return {
        "surface_distance_max": float(np.sqrt(d2.max())),
        "boundary_distance_max": float(bdist.max()),
        "uv_outside_max": float(lifted.uv_distance.max()) if lifted.uv_distance.size else 0.0,
    }
