"""The :class:`Mesh` returned by the mesh generators."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .polygon import Polygon

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
    """

    points: np.ndarray
    triangles: np.ndarray
    polygon: Polygon
    n_steiner: int
    info: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        for a in (self.points, self.triangles):
            a.setflags(write=False)

    def quality(self, *, d_n=None):
        """Quality measures and certificates, see :func:`uniform2d.quality`.

        ``d_n`` defaults to the value recorded in :attr:`info` when there is one.
        """
        from .quality import quality

        if d_n is None:
            d_n = self.info.get("d_n")
        return quality(
            self.points, self.triangles, self.polygon, n_steiner=self.n_steiner, d_n=d_n
        )

    def write(self, path, **kwargs) -> None:
        """Write the mesh; the format follows the file extension (see ``uniform2d.io``)."""
        from .io import write_mesh

        write_mesh(path, self.points, self.triangles, **kwargs)

    def plot(self, path=None, **kwargs):
        """Plot edges coloured by length and the edge-length histogram; returns the Figure."""
        from .plot import plot_mesh

        return plot_mesh(self.points, self.triangles, path, polygon=self.polygon, **kwargs)

    def __repr__(self) -> str:
        return (
            f"Mesh({len(self.points)} points, {len(self.triangles)} triangles, "
            f"n_steiner={self.n_steiner}, method={self.info.get('method')!r})"
        )
