"""Comparing two existing planar mesh files on the report's measures."""

from __future__ import annotations

from .cases import MEASURES, planar_measures
from .render import fmt

__all__ = ["compare_meshes", "format_comparison"]


def compare_meshes(path_a, path_b, polygon=None) -> dict:
    """Measure two mesh files (:func:`uniform2d.io.read_mesh`) side by side.

    Parameters
    ----------
    path_a, path_b : path
    polygon : path or Polygon, optional
        The polygon both meshes triangulate; enables the certified factors.

    Returns
    -------
    dict
        ``{"polygon": path or None, "meshes": [{"path", "measures", "quality"}, ...]}``.
    """
    from ..io import read_mesh, read_polygon
    from ..polygon import Polygon

    poly_path = None
    if polygon is not None and not isinstance(polygon, Polygon):
        poly_path = str(polygon)
        polygon = read_polygon(polygon)
    out = []
    for p in (path_a, path_b):
        pts, tri = read_mesh(p)
        m, q = planar_measures(pts, tri, polygon)
        out.append({"path": str(p), "measures": m, "quality": q})
    return {"polygon": poly_path, "meshes": out}


def format_comparison(result: dict) -> str:
    """A plain-text table of :func:`compare_meshes`' result."""
    cols = [c for c in MEASURES if c[0] not in ("vertex_error", "hausdorff_max_rel")]
    if result["polygon"] is None and all(
        m["measures"]["factor_longest_edge"] is None for m in result["meshes"]
    ):
        cols = [c for c in cols if not c[0].startswith("factor_")]
    a, b = result["meshes"]
    w = max(18, len(a["path"]), len(b["path"])) + 2
    lines = [f"{'':20s}{'A':>{w}s}{'B':>{w}s}", f"{'file':20s}{a['path']:>{w}s}{b['path']:>{w}s}"]
    for key, head, spec in cols:
        lines.append(f"{head:20s}{fmt(a['measures'].get(key), spec):>{w}s}"
                     f"{fmt(b['measures'].get(key), spec):>{w}s}")
    if result["polygon"]:
        lines.append(f"(factors certified against {result['polygon']}; 1 is optimal)")
    return "\n".join(lines)
