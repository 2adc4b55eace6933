"""The report of a surface remesh: uniformity in 3-D, the pymeshlab cross-check,
parameterisation distortion, and fidelity to the input surface.

:func:`cross_check` is where pymeshlab's numbers are compared with ours: they
must agree to a relative ``1e-9`` or :class:`~surface.errors.CrossCheckError` is
raised (a disagreement is a bug in one of the two, never a warning).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np

from uniform2d import libm

from .errors import CrossCheckError

__all__ = ["Report", "cross_check", "size_trend", "CROSS_CHECK_RTOL"]

#: Relative tolerance of the pymeshlab cross-check.
CROSS_CHECK_RTOL = 1e-9

#: Below this standard deviation of log(area scale) :func:`size_trend` is NaN.
TREND_MIN_SPREAD = 0.02


def cross_check(ours: dict, theirs: dict, rtol: float = CROSS_CHECK_RTOL) -> dict:
    """Compare our edge statistics with pymeshlab's.

    Parameters
    ----------
    ours : dict
        :func:`surface.measure.edge_stats` of the mesh.
    theirs : dict
        :func:`surface._meshlab.edge_measures` of the same mesh.
    rtol : float

    Returns
    -------
    dict
        pymeshlab's scalar values and ``max_rel_diff``, the largest relative
        difference found over every compared quantity.

    Raises
    ------
    CrossCheckError
        If the edge counts differ or any compared value differs by more than ``rtol``.
    """
    if ours["n_edges"] != theirs["n_edges"]:
        raise CrossCheckError(
            f"edge count: ours {ours['n_edges']}, pymeshlab {theirs['n_edges']}"
        )
    pairs = {
        "min": (ours["min"], theirs["min"]),
        "max": (ours["max"], theirs["max"]),
        "mean": (ours["mean"], theirs["avg_edge_length"]),
        "total": (ours["total"], theirs["total_edge_length"]),
    }
    worst = 0.0
    for name, (a, b) in pairs.items():
        rel = abs(a - b) / max(abs(a), abs(b), 1e-300)
        worst = max(worst, rel)
        if rel > rtol:
            raise CrossCheckError(
                f"edge length {name}: ours {a!r}, pymeshlab {b!r} (relative difference "
                f"{rel:.3g} > {rtol:g})"
            )
    for name in ("face_min", "face_max"):
        a, b = np.asarray(ours[name]), np.asarray(theirs[name])
        if a.shape != b.shape:
            raise CrossCheckError(f"per-face {name}: {a.shape} values vs {b.shape} from pymeshlab")
        rel = np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), 1e-300)
        k = int(np.argmax(rel))
        worst = max(worst, float(rel[k]))
        if rel[k] > rtol:
            raise CrossCheckError(
                f"per-face {name} of face {k}: ours {a[k]!r}, pymeshlab {b[k]!r} "
                f"(relative difference {rel[k]:.3g} > {rtol:g})"
            )
    return {
        "n_edges": theirs["n_edges"],
        "min": theirs["min"],
        "max": theirs["max"],
        "mean": theirs["avg_edge_length"],
        "total": theirs["total_edge_length"],
        "max_rel_diff": worst,
        "agrees": True,
    }


def size_trend(edge_len, edge_scale) -> float:
    """Slope of log(3-D edge length) against log(local area scale).

    0 when the edge size does not follow the parameterisation's distortion
    (compensated); about -1/2 when the mesh is uniform in UV instead
    (uncompensated conformal map).  NaN when the scale hardly varies (standard
    deviation of its log below :data:`TREND_MIN_SPREAD`): a developable patch
    has no trend to measure.
    """
    x = libm.log(np.asarray(edge_scale, dtype=np.float64))
    y = libm.log(np.asarray(edge_len, dtype=np.float64))
    if x.std() < TREND_MIN_SPREAD:
        return float("nan")
    x = x - x.mean()
    sxx = float(np.sum(x * x))  # not np.dot: BLAS's kernel, and its sums, are per CPU
    return float(np.sum(x * (y - y.mean())) / sxx)


@dataclasses.dataclass
class Report:
    """Everything measured about one remesh.

    Attributes
    ----------
    n_vertices, n_faces, n_boundary, n_corners : int
        Output counts (boundary = vertices on the input boundary).
    target_size : float
        Target 3-D edge length used.
    edges : dict
        3-D edge statistics: ``min``, ``max``, ``mean``, ``ratio``, ``cv``,
        ``angle_min``, ``angle_max`` (degrees), ``n_edges``; with a graded size
        also ``q_min``, ``q_max``, ``q_mean``, ``q_ratio``, ``q_cv`` of
        ``q = length / size(midpoint)`` (:func:`surface.size3d.q_stats`).
    edges_uv : dict
        The same of the planar mesh (in UV).
    meshlab : dict or None
        pymeshlab's values and the largest relative difference (see :func:`cross_check`).
    parameterization : dict
        Method used, attempts, distortion (see
        :meth:`surface.parameterize.Parameterization.distortion`).
    size_trend : float
        :func:`size_trend` of the output (0 = compensated).
    fidelity : dict
        ``surface_distance_max`` (our exact distance of output vertices to the
        input surface), ``boundary_distance_max`` (output boundary vertices to the
        input boundary edges), ``uv_outside_max`` (largest distance of a meshed
        point outside the UV triangulation, before clamping), and pymeshlab's
        Hausdorff distances ``hausdorff_out_in`` / ``hausdorff_in_out`` (dicts with
        max, mean, rms); every length also divided by ``diagonal``.
    timings : dict
        Seconds per step.
    mesher : str
        What produced the planar mesh.
    compensate : bool
        Whether the planar mesh was graded to be uniform in 3-D.
    atlas : dict or None
        For a model remeshed as an atlas: charts (faces, area, area-scale ratio),
        seams (points, nodes, chains, length), the edge CV near seams and away from
        them before and after the seam relaxation, and the flips it made.
    """

    n_vertices: int
    n_faces: int
    n_boundary: int
    n_corners: int
    target_size: float
    diagonal: float
    edges: dict
    edges_uv: dict
    meshlab: dict | None
    parameterization: dict
    size_trend: float
    fidelity: dict
    timings: dict
    mesher: str
    compensate: bool
    atlas: dict | None = None

    def as_dict(self) -> dict:
        """A JSON-serialisable dict."""
        return json.loads(json.dumps(dataclasses.asdict(self), default=_jsonable))

    def summary(self) -> str:
        """A few human-readable lines."""
        e, f = self.edges, self.fidelity
        lines = [
            f"vertices {self.n_vertices} (boundary {self.n_boundary}, corners "
            f"{self.n_corners}), faces {self.n_faces}",
            f"3-D edges: ratio {e['ratio']:.3f}, cv {e['cv']:.4f}, mean {e['mean']:.6g} "
            f"(target {self.target_size:.6g}), angles {e['angle_min']:.1f}..{e['angle_max']:.1f} deg",
            self._param_text(),
            f"fidelity: vertices off surface {f['surface_distance_max_rel']:.2e}, boundary "
            f"{f['boundary_distance_max_rel']:.2e} of the diagonal",
        ]
        if "q_cv" in e:
            lines.insert(2, f"relative to the size: q ratio {e['q_ratio']:.3f}, cv {e['q_cv']:.4f}, "
                            f"mean {e['q_mean']:.4f}")
        if f.get("hausdorff_out_in"):
            lines.append(
                f"Hausdorff (pymeshlab): out->in {f['hausdorff_out_in']['max'] / self.diagonal:.2e}, "
                f"in->out {f['hausdorff_in_out']['max'] / self.diagonal:.2e} of the diagonal"
            )
        if self.atlas:
            a, sm = self.atlas, self.atlas["seams"]
            lines.append(
                f"atlas: {a['n_charts']} charts (area scale ratio up to "
                f"{max(c['area_scale_ratio'] for c in a['charts']):.2f}), {a['n_seam_chains']} seams, "
                f"{a['n_seam_points']} seam points; edge cv near seams {sm['cv_near_seams']:.4f}, "
                f"away {sm['cv_away']:.4f}"
            )
        if self.meshlab:
            lines.append(
                f"pymeshlab cross-check: agrees (max relative difference "
                f"{self.meshlab['max_rel_diff']:.1e})"
            )
        return "\n".join(lines)

    def _param_text(self) -> str:
        p = self.parameterization
        if self.atlas:
            return f"parameterisation: {p['method']}, area-scale ratio per chart up to {p['area_scale_ratio']:.3f}"
        return (f"parameterisation: {p['method']}, area scale {p['area_scale_min']:.3f}.."
                f"{p['area_scale_max']:.3f}, " + self._trend_text())

    def _trend_text(self) -> str:
        if not np.isfinite(self.size_trend):
            return "no size trend to measure (the area scale hardly varies)"
        return f"size trend {self.size_trend:+.3f}" + (
            " (compensated)" if self.compensate else " (not compensated)"
        )

    def __str__(self) -> str:
        return self.summary()


def _jsonable(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    return str(o)
