"""Inputs, the case list, and running one case.

A *case* is one (input, n, method): a plain, picklable dict that carries the
input's geometry itself (no file access), so it runs the same in this process,
in a process pool, or on a Dask worker on another machine.  :func:`run_case`
is a pure function of its case apart from the timings.

Methods
-------
Polygons: ``tplus`` (:func:`uniform2d.tplus`) and ``uniform``
(:func:`uniform2d.uniform_mesh`) with n Steiner points, i.e. ``n + |V|``
vertices, then every planar peer tuned to that same vertex count.
Surface patches: ``remesh`` (the registered surface layer's ``remesh`` with
``n_vertices=n`` and the report's ``feature_angle``, see
:mod:`uniform2d.plugins`), then every surface peer tuned to n vertices.

A polygon keeps its whole problem: rings, interior segments, fixed points and
region labels go to our methods and to every peer that takes them
(:func:`uniform2d.peers.takes_constraints`).  A peer that does not is not run
on a polygon with segments or fixed points: its cases say ``"not comparable"``,
since its mesh would be of another problem.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..plugins import patch_layer

log = logging.getLogger(__name__)

__all__ = [
    "SURFACE_SUFFIXES",
    "OURS",
    "Input",
    "load_input",
    "plan",
    "run_case",
    "planar_measures",
    "MEASURES",
]

#: File extensions read as surface patches (everything else is a polygon file).
SURFACE_SUFFIXES = (".obj", ".ply", ".stl", ".off")

#: Our own methods, per input kind.
OURS = {"polygon": ("tplus", "uniform"), "surface": ("remesh",)}

#: The table columns: (key in ``case["measures"]``, header, format).
MEASURES = (
    ("n_vertices", "vertices", "d"),
    ("vertex_error", "error", "+d"),
    ("edge_ratio", "edge ratio", ".3f"),
    ("longest_edge", "longest edge", ".4g"),
    ("max_perimeter", "largest perimeter", ".4g"),
    ("factor_longest_edge", "factor L", ".3f"),
    ("factor_perimeter", "factor P", ".3f"),
    ("factor_edge_ratio", "factor ratio", ".3f"),
    ("min_angle", "min angle", ".1f"),
    ("cv_edge", "edge CV", ".4f"),
    ("hausdorff_max_rel", "deviation", ".2e"),
)


@dataclass(frozen=True)
class Input:
    """One report input.

    Attributes
    ----------
    name : str
        Unique label (file stem, suffixed ``-2``, ``-3`` ... on clashes).
    path : str
        The file, as given.
    kind : {"polygon", "surface"}
    geometry : dict
        ``{"outer": ..., "holes": [...], "segments": [...], "points": [...],
        "regions": [...]}`` (lists of (x, y); regions as (x, y, label)) for a polygon,
        ``{"vertices": (N, 3) list, "faces": (M, 3) list}`` for a patch.
    """

    name: str
    path: str
    kind: str
    geometry: dict

    def n_boundary_vertices(self) -> int:
        """|V| of a polygon, constraint vertices included (0 for a patch)."""
        if self.kind != "polygon":
            return 0
        return len(polygon_of(self.geometry).vertices)


def load_input(path, name: str | None = None) -> Input:
    """Read a polygon file or a surface model (by extension, see :data:`SURFACE_SUFFIXES`).

    Raises
    ------
    FileNotFoundError, UnsupportedFormatError, FileFormatError, InvalidPatchError
        As the readers do.
    """
    p = Path(path)
    name = name or p.name.split(".")[0]
    if p.suffix.lower() in SURFACE_SUFFIXES:
        patch = patch_layer().read_model(p)
        geom = {"vertices": np.asarray(patch.vertices).tolist(), "faces": np.asarray(patch.faces).tolist()}
        return Input(name, str(path), "surface", geom)
    from ..io import read_polygon

    return Input(name, str(path), "polygon", polygon_geometry(read_polygon(p)))


def polygon_geometry(polygon) -> dict:
    """The plain, picklable geometry of a :class:`uniform2d.Polygon`: its rings
    as given (T-junctions are spliced again by :func:`polygon_of`), segments,
    fixed points and region labels.

    >>> from uniform2d import Polygon
    >>> g = polygon_geometry(Polygon([(0, 0), (2, 0), (2, 1), (0, 1)], points=[(1, 0.5)]))
    >>> g["points"], len(polygon_of(g).vertices)
    ([[1.0, 0.5]], 5)
    """
    return {
        "outer": polygon.outer.tolist(),
        "holes": [h.tolist() for h in polygon.holes],
        "segments": [s.tolist() for s in polygon.segments],
        "points": polygon.points.tolist(),
        "regions": [[float(x), float(y), lab] for x, y, lab in polygon.region_seeds],
    }


def polygon_of(geom: dict):
    """The :class:`uniform2d.Polygon` of :func:`polygon_geometry`'s dict."""
    from ..polygon import Polygon

    return Polygon(geom["outer"], geom["holes"], segments=geom.get("segments", ()),
                   points=geom.get("points", ()), regions=geom.get("regions", ()))


def describe_constraints(geom: dict) -> dict:
    """Counts of a polygon geometry's constraints: segments, fixed points, regions."""
    return {"n_segments": len(geom.get("segments", ())), "n_points": len(geom.get("points", ())),
            "n_regions": len(geom.get("regions", ()))}


def _unique_names(paths) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for p in paths:
        stem = Path(p).name.split(".")[0] or "input"
        k = seen.get(stem, 0) + 1
        seen[stem] = k
        out.append(stem if k == 1 else f"{stem}-{k}")
    return out


def load_inputs(paths) -> list[Input]:
    """:func:`load_input` for every path, with unique names."""
    return [load_input(p, nm) for p, nm in zip(paths, _unique_names(paths))]


def plan(inputs, ns, peer_names, *, availability=None, feature_angle=None) -> list[dict]:
    """The case list: for each input, each n, our methods then each applicable peer.

    Parameters
    ----------
    inputs : list of Input
    ns : list of int
        Steiner points for polygons, vertex counts for patches.
    peer_names : list of str
        Peers to compare with (registered names).
    availability : dict, optional
        ``{peer: bool}``; default :func:`uniform2d.peers.available` for each.
        A peer that is not available still gets its cases, with status
        ``"not installed"``; they are never run.  Nor are those of a peer that
        cannot take a polygon's segments or fixed points: status ``"not comparable"``.
    feature_angle : float, optional
        Passed to the surface layer's ``remesh`` for surface inputs: edges bent
        more than this (degrees) are kept as feature lines.

    Returns
    -------
    list of dict
        Cases, in report order; keys ``id``, ``input``, ``kind``, ``n``,
        ``method``, ``family`` (``"ours"`` or ``"peer"``), ``target_vertices``,
        ``status`` (``"pending"``, ``"not installed"`` or ``"not comparable"``)
        and ``geometry``.
    """
    from .. import peers as _peers

    if availability is None:
        availability = {p: _peers.available(p) for p in peer_names}
    kinds = {p: _peers.kind(p) for p in peer_names}
    constrained = {p: _peers.takes_constraints(p) for p in peer_names if kinds[p] == "planar"}
    cases = []
    for inp in inputs:
        peer_kind = "planar" if inp.kind == "polygon" else "surface"
        for n in ns:
            target = int(n) + inp.n_boundary_vertices()
            methods = [(m, "ours") for m in OURS[inp.kind]]
            methods += [(p, "peer") for p in peer_names if kinds[p] == peer_kind]
            for method, family in methods:
                status = "pending"
                if family == "peer" and not availability.get(method, False):
                    status = "not installed"
                elif family == "peer" and _has_constraints(inp) and not constrained[method]:
                    status = "not comparable"
                cases.append(
                    {
                        "id": f"{inp.name}-n{int(n)}-{method}",
                        "input": inp.name,
                        "path": inp.path,
                        "kind": inp.kind,
                        "n": int(n),
                        "method": method,
                        "family": family,
                        "target_vertices": target,
                        "status": status,
                        "geometry": inp.geometry,
                        **({"feature_angle": feature_angle} if inp.kind == "surface" else {}),
                    }
                )
    return cases


def _has_constraints(inp) -> bool:
    g = inp.geometry
    return inp.kind == "polygon" and bool(g.get("segments") or g.get("points"))


# -- measures --------------------------------------------------------------------
def _f(x):
    return float(x) if x is not None and math.isfinite(x) else None


def planar_measures(points, triangles, polygon=None) -> tuple[dict, dict]:
    """Table measures and the full :func:`uniform2d.quality` dict of a planar mesh.

    Without a polygon the certified factors are ``None``.
    """
    from ..quality import quality

    q = quality(points, triangles, polygon)
    m = {
        "n_vertices": int(q.n_vertices),
        "n_triangles": int(q.n_triangles),
        "edge_ratio": _f(q.edge_ratio),
        "longest_edge": _f(q.longest_edge),
        "max_perimeter": _f(q.max_perimeter),
        "factor_longest_edge": _f(q.longest_edge_bound.factor) if q.longest_edge_bound else None,
        "factor_perimeter": _f(q.max_perimeter_bound.factor) if q.max_perimeter_bound else None,
        "factor_edge_ratio": _f(q.edge_ratio_bound.factor) if q.edge_ratio_bound else None,
        "min_angle": _f(q.min_angle),
        "cv_edge": _f(q.cv_edge),
    }
    return m, q.to_dict()


# -- running a case ----------------------------------------------------------------
def _make(case):
    """(points, triangles, details) of a case; details is JSON-able."""
    method, n = case["method"], case["n"]
    if case["kind"] == "polygon":
        polygon = polygon_of(case["geometry"])
        if method in ("tplus", "uniform"):
            from ..tplus import tplus
            from ..uniform import uniform_mesh

            m = tplus(polygon, n) if method == "tplus" else uniform_mesh(polygon, n)
            keep = ("method", "d_n", "k", "theorem_applies", "gap_min", "gap_max")
            return m.points, m.triangles, {k: m.info.get(k) for k in keep if k in m.info}
        from .. import peers

        pm = peers.mesh(method, polygon, case["target_vertices"])
        return pm.points, pm.triangles, _peer_details(pm)
    V0 = np.asarray(case["geometry"]["vertices"], dtype=np.float64)
    F0 = np.asarray(case["geometry"]["faces"], dtype=np.int64)
    if method == "remesh":
        r = patch_layer().remesh((V0, F0), n, check=False, hausdorff=False,
                                 feature_angle=case.get("feature_angle"))
        det = {"mesher": r.report.mesher, "target_size": r.report.target_size,
               "parameterization": r.report.parameterization.get("method")}
        return np.asarray(r.vertices), np.asarray(r.faces), det
    from .. import peers

    pm = peers.mesh(method, (V0, F0), case["target_vertices"])
    return pm.points, pm.triangles, _peer_details(pm)


def _peer_details(pm) -> dict:
    d = {"size": pm.size, "evaluations": int(pm.evaluations)}
    for k, v in pm.info.items():
        if k == "history":
            d["history"] = [[float(s), int(c)] for s, c in v]
        elif isinstance(v, (int, float, str, bool)) or v is None:
            d[k] = v
    return d


def warm_up() -> None:
    """Load uniform2d's numba kernels in this process (INSERT, T+, the optimiser
    and, when the surface layer is installed, a small remesh), so no case's
    time includes compiling or loading them."""
    from ..polygon import Polygon
    from ..tplus import tplus
    from ..uniform import uniform_mesh

    square = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    tplus(square, 20)
    uniform_mesh(square, 20)
    layer = patch_layer(required=False)
    if layer is not None:
        layer.warm_up()


def run_case(case: dict) -> dict:
    """Run one case.

    Returns
    -------
    dict
        The case without its geometry, plus ``status`` (``"ok"``, ``"failed"``
        or ``"not installed"``), ``message``, ``measures`` (see
        :data:`MEASURES`), ``quality`` (the full :func:`uniform2d.quality`
        dict, planar only), ``details`` (method specifics: tuning, d_n, ...),
        ``time`` (``{"total": s, "per_mesh": s}``: all meshes made while
        tuning, and that divided by their number; the only non-deterministic
        field) and,
        when ``status == "ok"``, ``points`` and ``triangles`` arrays (the
        caller writes them and removes them).
    """
    out = {k: v for k, v in case.items() if k != "geometry"}
    out.update(message="", measures=None, quality=None, details=None, time=None)
    if case["status"] == "not installed":
        out["message"] = f"{case['method']} is not installed"
        return out
    if case["status"] == "not comparable":
        out["message"] = (f"{case['method']} cannot take the segments and fixed points: "
                          "its mesh would be of another problem")
        return out
    t0 = time.perf_counter()
    try:
        pts, tri, details = _make(case)
    except Exception as exc:  # a failing mesher is a result, not a crash of the report
        log.warning("case %s failed: %s", case["id"], exc)
        out["status"] = "failed"
        out["message"] = " ".join(f"{type(exc).__name__}: {exc}".split())
        out["time"] = {"total": time.perf_counter() - t0}
        return out
    elapsed = time.perf_counter() - t0
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    tri = np.ascontiguousarray(tri, dtype=np.int64)
    if case["kind"] == "polygon":
        meas, qd = planar_measures(pts, tri, polygon_of(case["geometry"]))
    else:
        V0 = np.asarray(case["geometry"]["vertices"], dtype=np.float64)
        F0 = np.asarray(case["geometry"]["faces"], dtype=np.int64)
        meas, qd = patch_layer().measures(pts, tri, V0, F0), None
    meas["vertex_error"] = meas["n_vertices"] - case["target_vertices"]
    meas["vertex_error_rel"] = meas["vertex_error"] / case["target_vertices"]
    evals = int(details.get("evaluations", 1)) if details else 1
    out.update(status="ok", measures=meas, quality=qd, details=details,
               time={"total": elapsed, "per_mesh": elapsed / max(evals, 1)},
               points=pts, triangles=tri)
    return out
