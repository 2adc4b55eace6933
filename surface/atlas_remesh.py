"""The remesh of a whole model: atlas, charts meshed, stitched, relaxed, measured."""

from __future__ import annotations

import logging
import time

import numpy as np
from scipy.spatial import cKDTree

from uniform2d.errors import InsufficientPointsError, InternalError
from uniform2d.geometry import segment_distance

from . import _igl
from .atlas import build_atlas, mesh_atlas
from .errors import InvalidPatchError
from .fidelity import meshlab_checks
from .measure import edge_stats, unique_edges
from .model import Model
from .report import Report
from .result import RemeshResult
from .seam_relax import relax
from .size3d import Size3D, q_stats

__all__ = ["remesh_atlas", "seam_uniformity"]

log = logging.getLogger(__name__)


def seam_uniformity(xyz, faces, seam_xyz, h: float, size=None) -> dict:
    """Edge-length CV within ``2 h`` of the seams (edge midpoints) and away from them
    (with ``size``, a graded size: the CV of length / size)."""
    E = unique_edges(faces)
    L = np.linalg.norm(xyz[E[:, 1]] - xyz[E[:, 0]], axis=1)
    if size is not None:
        L = L / size(0.5 * (xyz[E[:, 0]] + xyz[E[:, 1]]))
    if not len(seam_xyz):
        return {"cv_near_seams": float("nan"), "cv_away": float(L.std() / L.mean()), "near_edges": 0}
    d, _ = cKDTree(seam_xyz).query(0.5 * (xyz[E[:, 0]] + xyz[E[:, 1]]))
    near = d <= 2.0 * h

    def cv(x):
        return float(x.std() / x.mean()) if len(x) else float("nan")

    return {"cv_near_seams": cv(L[near]), "cv_away": cv(L[~near]), "near_edges": int(near.sum())}


def _fidelity(M: Model, xyz, faces, n_charts: int) -> tuple[dict, np.ndarray]:
    d2, _, _ = _igl.closest_points(xyz, M.vertices, M.faces)
    try:
        out = Model(xyz, faces)
    except InvalidPatchError as exc:  # a few points on many charts: two faces coincide
        raise InsufficientPointsError(
            f"{len(xyz)} vertices are too few for this model's {n_charts} charts (the stitched "
            f"mesh is not a surface: {exc}); ask for more vertices"
        ) from None
    bmask = np.zeros(len(xyz), dtype=bool)
    for lp in out.boundary_loops:
        bmask[lp] = True
    bdist = 0.0
    if M.boundary_loops and bmask.any():
        bl = np.concatenate([np.stack([lp, np.roll(lp, -1)], axis=1) for lp in M.boundary_loops])
        V = M.vertices
        bdist = float(segment_distance(xyz[bmask], V[bl[:, 0]], V[bl[:, 1]]).max())
    if out.topology() != M.topology():
        raise InternalError(
            f"the stitched atlas mesh has topology {out.topology()}, the input {M.topology()} "
            "(a bug in surface: please report it with the model)"
        )
    return {"surface_distance_max": float(np.sqrt(d2.max())), "boundary_distance_max": bdist,
            "uv_outside_max": 0.0}, bmask


def remesh_atlas(M: Model, N: int, h, *, feature_angle, features, corner_angle, compensate,
                 check, hausdorff, jobs, scheduler, times, t0) -> RemeshResult:
    """Remesh ``M`` as an atlas with exactly ``N`` vertices at spacing ``h`` (a length,
    or a graded size :class:`surface.size3d.Size3D` at its scale)."""
    t = time.perf_counter()
    graded = h if isinstance(h, Size3D) else None
    if graded is not None:
        atlas = build_atlas(M, graded.scale, feature_angle=feature_angle, features=features,
                            corner_angle=corner_angle, size3d=graded.shape())
        href = float(np.median(graded(M.vertices)))  # the seam band's width
    else:
        atlas = build_atlas(M, h, feature_angle=feature_angle, features=features,
                            corner_angle=corner_angle)
        href = h
    times["atlas"] = time.perf_counter() - t
    t = time.perf_counter()
    xyz, faces, chart = mesh_atlas(atlas, N, h, compensate=compensate, jobs=jobs, scheduler=scheduler)
    times["mesh_2d"] = time.perf_counter() - t
    t = time.perf_counter()
    S = atlas.seams
    fixed = np.zeros(N, dtype=bool)
    fixed[: S.n_points] = S.fixed
    before = seam_uniformity(xyz, faces, S.xyz, href, graded)
    xyz, faces, flips = relax(xyz, faces, np.flatnonzero(~S.fixed), fixed, M.vertices, M.faces,
                              size=graded)
    times["relax"] = time.perf_counter() - t
    t = time.perf_counter()
    stats = edge_stats(xyz, faces)
    fidelity, bmask = _fidelity(M, xyz, faces, len(atlas.charts))
    times["measure"] = time.perf_counter() - t
    meshlab = meshlab_checks(M, xyz, faces, stats, fidelity, times, check, hausdorff)
    times["total"] = time.perf_counter() - t0
    info = atlas.summary()
    info.update(seams_before_relax=before, seams=seam_uniformity(xyz, faces, S.xyz, href, graded),
                flips=flips)
    ratios = [c["area_scale_ratio"] for c in info["charts"]]
    edges = {k: v for k, v in stats.items() if not k.startswith("face_")}
    if graded is not None:
        E = unique_edges(faces)
        q = graded.edge_q(xyz, E)
        edges.update(q_stats(q))
        href = float(np.mean(np.linalg.norm(xyz[E[:, 1]] - xyz[E[:, 0]], axis=1) / q))
    report = Report(
        n_vertices=len(xyz), n_faces=len(faces), n_boundary=int(bmask.sum()),
        n_corners=S.n_nodes, target_size=href, diagonal=M.diagonal,
        edges=edges, edges_uv={},
        meshlab=meshlab,
        parameterization={"method": "atlas (lscm per chart)", "area_scale_min": 1.0,
                          "area_scale_max": max(ratios), "area_scale_ratio": max(ratios)},
        size_trend=float("nan"), fidelity=fidelity, timings=times,
        mesher=("atlas: lattice + uniform2d.optimize.improve per chart, 3-D seam relaxation"
                if graded is None else "atlas: rows + INSERT + weighted Lloyd + uniform2d.optimize.improve "
                "with a graded size per chart, 3-D seam relaxation"),
        compensate=bool(compensate), atlas=info,
    )
    for arr in (xyz, faces, bmask, chart):
        arr.setflags(write=False)
    return RemeshResult(xyz, faces, None, bmask, report, None, atlas, chart)
