"""Whole models as an atlas of charts: cut, sample the seams once, mesh, lift, stitch.

The pipeline (see ``docs/surface.md``, "Whole models")::

    Model --charts.segment--> charts (disks that flatten with low distortion,
                              cut along creases first)
          --seams.build_seams--> seam points, sampled once in 3-D at spacing h
          --uniform2d.parts.allocate--> interior count of every chart (exact n)
          --chart_mesh.mesh_domain--> every chart's planar mesh, its ring = its
                              seam points (in parallel: uniform2d's batch engine)
          --lift, uniform2d.parts.stitch--> one conforming 3-D mesh
          --seam_relax.relax--> seams that do not show

Every chart's ring consists of seam points only, in the chart's flattening; the
planar mesher keeps ring vertices and adds none on ring edges, so two charts
meeting on a seam share exactly its points and the stitched mesh is
conforming.  A ring that is not simple at the plain sampling (a coarse chord
cutting a tight bend of the flattened boundary) has its chains sampled more
finely, for both charts at once.
"""

from __future__ import annotations

import dataclasses
import logging
import math

import numpy as np

from uniform2d import Polygon
from uniform2d.errors import InsufficientPointsError, InternalError, InvalidPolygonError
from uniform2d.geometry import boundary_edges, signed_area
from uniform2d.parts import allocate, map_parts, stitch

from ._trimesh import dihedral_edges
from .chart_mesh import mesh_domain, size_field
from .charts import CREASE_ANGLE, MAX_AREA_SCALE_RATIO, Chart, segment
from .lift import lift
from .model import Model
from .seams import Seams, build_seams
from .size3d import Size3D, integrals

__all__ = ["Atlas", "build_atlas", "mesh_atlas", "crease_edges"]

log = logging.getLogger(__name__)

#: Times a chart's chains are sampled more finely to make its ring simple.
MAX_REFINE = 6

_AREA_PER_VERTEX = math.sqrt(3.0) / 2.0  # of an equilateral mesh of unit edge


@dataclasses.dataclass(frozen=True)
class Atlas:
    """Charts, their seams and each chart's domain.

    Attributes
    ----------
    charts : list of Chart
    seams : Seams
    polygons : list of uniform2d.Polygon
        Every chart's domain in its flattening: its rings are its seam points.
    index : list of (K,) int64
        Per chart: the seam point of each polygon vertex.
    """

    charts: list
    seams: Seams
    polygons: list
    index: list

    def summary(self) -> dict:
        """Charts, seams and each chart's distortion (JSON-ready)."""
        return {
            "n_charts": len(self.charts),
            "n_seam_points": self.seams.n_points,
            "n_seam_nodes": self.seams.n_nodes,
            "n_seam_chains": len(self.seams.chains),
            "seam_length": self.seams.length(),
            "charts": [
                {"faces": len(c.faces), "area": float(c.patch.area), "method": c.param.method,
                 "area_scale_ratio": c.area_scale_ratio, "boundary_loops": len(c.patch.boundary_loops)}
                for c in self.charts
            ],
        }


def crease_edges(model: Model, feature_angle, features=()) -> np.ndarray:
    """Model edges that must be seams: bent more than ``feature_angle`` (default
    :data:`surface.charts.CREASE_ANGLE`), and the edges of the feature chains."""
    e, ang = dihedral_edges(model.vertices, model.faces)
    thr = CREASE_ANGLE if feature_angle is None else float(feature_angle)
    out = [e[ang > np.radians(thr)]]
    for chain in features:
        c = np.asarray(chain, dtype=np.int64)
        out.append(np.sort(np.stack([c[:-1], c[1:]], axis=1), axis=1))
    E = np.concatenate(out) if out else np.zeros((0, 2), dtype=np.int64)
    return np.unique(E.reshape(-1, 2), axis=0)


def build_atlas(model: Model, spacing: float, *, feature_angle=None, features=(),
                corner_angle: float = 30.0, bound: float = MAX_AREA_SCALE_RATIO,
                size3d=None) -> Atlas:
    """Cut ``model`` into charts and sample its seams at ``spacing`` (with
    ``size3d``, a graded size's shape, in ``∫ ds / size3d``: see
    :func:`surface.seams.build_seams`).

    Raises
    ------
    InsufficientPointsError
        If a chart's ring stays not simple after :data:`MAX_REFINE` refinements
        (ask for more vertices).
    """
    V, F = model.vertices, model.faces
    creases = crease_edges(model, feature_angle, features)
    charts = segment(V, F, creases, bound=bound)
    log.info("atlas: %d charts", len(charts))
    refine: dict = {}
    for _ in range(MAX_REFINE + 1):
        seams = build_seams(V, F, model.boundary_loops, charts, creases, spacing=spacing,
                            corner_angle=corner_angle, refine=refine, size3d=size3d)
        polygons, index, bad = [], [], []
        for i, chart in enumerate(charts):
            try:
                poly, idx = _chart_polygon(chart, seams.rings[i], seams)
            except InvalidPolygonError as exc:
                log.info("chart %d: ring not simple at this sampling (%s); refining", i, exc)
                bad.append(i)
                continue
            polygons.append(poly)
            index.append(idx)
        if not bad:
            return Atlas(charts, seams, polygons, index)
        for i in bad:
            members = set(np.concatenate(seams.rings[i]).tolist())
            for k, c in enumerate(seams.chains):
                if set(c.tolist()) <= members:
                    refine[k] = refine.get(k, 1.0) * 1.5
    raise InsufficientPointsError(
        f"the seams of {len(bad)} chart(s) cannot be sampled at spacing {spacing:.6g} "
        "without their rings crossing in the flattening; ask for more vertices"
    )


def _chart_polygon(chart: Chart, rings, seams: Seams):
    """The chart's domain (a Polygon of its seam points in its flattening) and the
    seam point of each polygon vertex."""
    uv = chart.param.uv
    loc = {int(v): i for i, v in enumerate(chart.vertices)}
    rings_uv = []
    for ring in rings:
        if len(ring) < 3:
            raise InvalidPolygonError(f"a ring of {len(ring)} points")
        e, t = seams.edge[ring], seams.t[ring]
        a = uv[[loc[int(x)] for x in e[:, 0]]]
        b = uv[[loc[int(x)] for x in e[:, 1]]]
        rings_uv.append((1.0 - t)[:, None] * a + t[:, None] * b)
    order = np.argsort([-abs(signed_area(r)) for r in rings_uv], kind="stable")
    poly = Polygon(rings_uv[order[0]], [rings_uv[i] for i in order[1:]])
    where = {}
    for i in order:
        for p, q in zip(map(tuple, rings_uv[i]), rings[i].tolist()):
            where[p] = q
    try:
        idx = np.array([where[tuple(p)] for p in poly.vertices], dtype=np.int64)
    except KeyError:
        raise InternalError("a chart polygon vertex is not a seam point (a bug: please report it)") from None
    return poly, idx


def chart_counts(atlas: Atlas, n_vertices: int, spacing) -> np.ndarray:
    """Interior points of every chart, summing to ``n_vertices`` minus the seam points.

    Each chart's share is what an equilateral mesh of the spacing would put inside
    it, ``area / (sqrt(3)/2 h^2) - perimeter / (2 h)``: in proportion to its 3-D
    area, less the half of its ring that its seam points already cover."""
    rest = n_vertices - atlas.seams.n_points
    if rest < 0:
        raise InsufficientPointsError(
            f"n_vertices={n_vertices} is too small: the atlas's {len(atlas.charts)} charts meet on "
            f"seams that alone need {atlas.seams.n_points} points at that size; ask for more vertices"
        )
    xyz = atlas.seams.xyz
    est = []
    for c, rings in zip(atlas.charts, atlas.seams.rings):
        if isinstance(spacing, Size3D):  # the same with ∫ dA / h², ∮ ds / h
            ia, _ = integrals(c.patch.vertices, c.patch.faces, [], spacing)
            per = sum(float(np.sum(np.linalg.norm(xyz[np.roll(r, -1)] - xyz[r], axis=1)
                                   / spacing(0.5 * (xyz[np.roll(r, -1)] + xyz[r])))) for r in rings)
            est.append(max(ia - per / 2.0, 1e-9))
            continue
        per = sum(np.linalg.norm(xyz[np.roll(r, -1)] - xyz[r], axis=1).sum() for r in rings)
        est.append(max(c.patch.area / (_AREA_PER_VERTEX * spacing**2) - per / (2.0 * spacing), 1e-9))
    return allocate(est, rest)


def _mesh_chart(item):
    """Mesh one chart (a module-level function: batch workers import it by name)."""
    chart, polygon, count, spacing, compensate = item
    graded = isinstance(spacing, Size3D)
    if graded:
        field = size_field(chart.patch, chart.param, spacing.scale, spacing)
    else:
        field = size_field(chart.patch, chart.param, spacing) if compensate else None
    P, T, _ = mesh_domain(polygon, int(count), field, graded_start=graded)
    K = len(polygon.vertices)
    if (boundary_edges(T, len(P)) >= K).any():
        raise InternalError("the planar mesher put a point on a chart's ring (a bug: please report it)")
    xyz = lift(P[K:], chart.patch.vertices, chart.patch.faces, chart.param.uv).xyz
    return T, xyz


def mesh_atlas(atlas: Atlas, n_vertices: int, spacing: float, *, compensate: bool = True,
               jobs: int = 1, scheduler=None):
    """Mesh every chart and stitch them: ``xyz (n_vertices, 3), faces (M, 3)`` and
    the chart of every face, ``(M,) int64``.

    Charts run through uniform2d's batch engine (``jobs`` local processes or a
    Dask ``scheduler``); the result does not depend on which.
    """
    counts = chart_counts(atlas, n_vertices, spacing)
    items = [(c, p, k, spacing, compensate) for c, p, k in zip(atlas.charts, atlas.polygons, counts)]
    done = map_parts(_mesh_chart, items, jobs=jobs, scheduler=scheduler)
    parts = [(idx, xyz, T) for idx, (T, xyz) in zip(atlas.index, done)]
    xyz, faces = stitch(atlas.seams.xyz, parts)
    if len(xyz) != n_vertices:
        raise InternalError(f"the stitched mesh has {len(xyz)} vertices, not {n_vertices} (a bug)")
    chart = np.repeat(np.arange(len(done), dtype=np.int64), [len(T) for T, _ in done])
    return xyz, faces, chart
