"""What :func:`surface.remesh` returns."""

from __future__ import annotations

import dataclasses

import numpy as np

from .atlas import Atlas
from .domain import Domain
from .io import write_patch
from .report import Report

__all__ = ["RemeshResult"]


@dataclasses.dataclass(frozen=True)
class RemeshResult:
    """A remeshed patch.

    Attributes
    ----------
    vertices : (N, 3) float64
        On the input surface; boundary vertices on input boundary edges.
    faces : (M, 3) int64
        Oriented like the input faces.
    uv : (N, 2) float64 or None
        The planar mesh the faces were built on, in the parameter plane (None
        for a model remeshed as an atlas: every chart has its own plane).
    boundary : (N,) bool
        Vertices on the boundary.
    report : Report
    domain : Domain or None
        The polygon that was meshed and where its vertices lie on the input
        (None for an atlas).
    atlas : surface.atlas.Atlas or None
        The charts and seams, when the model was remeshed as an atlas.
    chart : (M,) int64 or None
        The chart each face was meshed in (an atlas only; a face flipped across a
        seam by the relaxation keeps the chart it had).
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None
    boundary: np.ndarray
    report: Report
    domain: Domain | None
    atlas: Atlas | None = None
    chart: np.ndarray | None = None

    def write(self, path, **kwargs):
        """Write the 3-D mesh (see :func:`surface.write_patch`; ``.inp`` files
        declare shell elements, ``element_type="S3"`` by default)."""
        return write_patch(path, self.vertices, self.faces, **kwargs)
