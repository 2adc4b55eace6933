"""The :class:`Mesh` returned by the mesh generators."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from .io import write_mesh
from .io.registry import find_mesh_format
from .mesh_regions import ring_chains, segment_chains, triangle_regions
from .polygon import Polygon
from .quality import quality

__all__ = ["Mesh"]


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangulation of a polygon with a known number of Steiner points.

    Attributes
    ----------
    points : ndarray, shape (N, 2), float64
        Vertices: the polygon vertices first (exactly ``polygon.vertices``), then
        the n Steiner points (boundary and interior).
    triangles : ndarray, shape (M, 3), int64
        Counter-clockwise vertex indices.
    polygon : Polygon
    n_steiner : int
        Number of points added to the polygon vertices, N - |V|.
    info : dict
        How the mesh was made (method, d_n, k, the hypotheses of Theorem 2, ...).
    regions : ndarray, shape (M,), int64
        The region (:mod:`uniform2d.regions`) of every triangle, found by
        :mod:`uniform2d.mesh_regions`; all 0 for a polygon without segments.
    region_labels : tuple
        The label of each region (``None`` where the polygon gives none).
    segment_members : tuple of ndarray
        ``(edges (K, 2) int64, ids (K,) int64)``: the mesh edges on the polygon's
        segments and the segment of each.
    ring_members : tuple of ndarray
        ``(edges (K, 2) int64, ids (K,) int64)``: the mesh edges on the polygon's
        rings, each ring from its first vertex, and the ring of each (0 the
        outer ring, ``1 + i`` hole ``i``).
    size : SizeField or None
        The size field a graded mesh follows, at the scale of its n (None for a
        uniform mesh); :meth:`quality` then measures relative to it too.
    """

    points: np.ndarray
    triangles: np.ndarray
    polygon: Polygon
    n_steiner: int
    info: dict[str, Any] = field(default_factory=dict)
    size: Any = None

    def __post_init__(self):
        for a in (self.points, self.triangles):
            a.setflags(write=False)

    @cached_property
    def regions(self) -> np.ndarray:
        out = triangle_regions(self.polygon, self.points, self.triangles)
        out.setflags(write=False)
        return out

    @property
    def region_labels(self) -> tuple:
        return self.polygon.regions.labels

    @cached_property
    def segment_members(self) -> tuple[np.ndarray, np.ndarray]:
        edges, ids = segment_chains(self.polygon, self.points, self.triangles)
        edges.setflags(write=False)
        ids.setflags(write=False)
        return edges, ids

    @cached_property
    def ring_members(self) -> tuple[np.ndarray, np.ndarray]:
        edges, ids = ring_chains(self.polygon, self.points, self.triangles)
        edges.setflags(write=False)
        ids.setflags(write=False)
        return edges, ids

    def quality(self, *, d_n=None):
        """Quality measures and certificates, see :func:`uniform2d.quality`.

        ``d_n`` defaults to the value recorded in :attr:`info` when there is one.
        """
        if d_n is None:
            d_n = self.info.get("d_n")
        return quality(
            self.points, self.triangles, self.polygon, n_steiner=self.n_steiner, d_n=d_n,
            size=self.size,
        )

    def write(self, path, **kwargs) -> None:
        """Write the mesh; the format follows the file extension (see ``uniform2d.io``).

        Formats with named sets (``.msh``, ``.inp``, ``.vtu``, ``.vtk``) also get
        the rings, the segments and the fixed points (see
        :mod:`uniform2d.io.mesh_sets`); keyword arguments are passed on to
        :func:`uniform2d.io.write_mesh` (e.g. ``element_type="CPE3"`` for
        ``.inp``).
        """
        if self.polygon.has_constraints or self.polygon.region_seeds:
            kwargs.setdefault("regions", self.regions)
            kwargs.setdefault("region_labels", self.region_labels)
            kwargs.setdefault("segment_members", self.segment_members)
        if find_mesh_format(path, "write").sets:
            kwargs.setdefault("ring_members", self.ring_members)
            if len(self.polygon.fixed):
                kwargs.setdefault("fixed_points", self.polygon.fixed)
        write_mesh(path, self.points, self.triangles, **kwargs)

    def plot(self, path=None, **kwargs):
        """Plot edges coloured by length and the edge-length histogram; returns the Figure."""
        from .plot import plot_mesh

        if self.polygon.has_constraints or self.polygon.region_seeds:
            kwargs.setdefault("regions", self.regions)
            kwargs.setdefault("region_labels", self.region_labels)
        if self.size is not None:  # a graded mesh: edges coloured by length / h
            kwargs.setdefault("size", self.size)
        return plot_mesh(self.points, self.triangles, path, polygon=self.polygon, **kwargs)

    def __repr__(self) -> str:
        return (
            f"Mesh({len(self.points)} points, {len(self.triangles)} triangles, "
            f"n_steiner={self.n_steiner}, method={self.info.get('method')!r})"
        )
