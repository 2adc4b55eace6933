"""What :func:`uniform2d.quality.quality` returns: the :class:`Quality` record of a
mesh's measures, the :class:`Bound` certificates in it, and their renderings as
text (:meth:`Quality.summary`, :meth:`Quality.certificate`) and JSON
(``to_dict``).  The measuring is in :mod:`uniform2d.measures`, the bounds in :mod:`uniform2d.bounds`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

__all__ = ["Quality", "Bound"]


def _json_float(x):
    return float(x) if x is not None and math.isfinite(x) else None


@dataclass(frozen=True)
class Bound:
    """A lower bound on the optimum of one measure, and how this mesh compares.

    Attributes
    ----------
    value : float
        The lower bound: no triangulation of the polygon with at most
        ``n_steiner`` Steiner points does better than this.
    term : str
        Name of the term that gives ``value`` (the largest of ``terms``).
    terms : tuple of (str, float)
        Every term that applies, in a fixed order; ``value`` is their maximum.
    achieved : float
        The value this mesh achieves.
    factor : float
        ``achieved / value`` (at least 1): the mesh is provably within this
        factor of the optimum.
    detail : str
        Where the active term comes from, e.g. ``"90 deg at (0, 0), best
        split in 2"`` for the ``corner`` term of a square's edge ratio.
    """

    value: float
    term: str
    terms: tuple[tuple[str, float], ...]
    achieved: float
    factor: float
    detail: str = ""

    @property
    def active(self) -> str:
        """The active term and where it comes from, in words."""
        return f"{self.term} ({self.detail})" if self.detail else self.term

    def to_dict(self) -> dict:
        """Plain JSON-serialisable dict (non-finite numbers become ``None``)."""
        return {
            "value": _json_float(self.value),
            "term": self.term,
            "terms": {k: _json_float(v) for k, v in self.terms},
            "achieved": _json_float(self.achieved),
            "factor": _json_float(self.factor),
            "detail": self.detail,
        }


def _within(factor: float) -> str:
    """A certified factor in words: how far above the best possible mesh at most."""
    if not math.isfinite(factor):
        return "no finite factor"
    pct = (factor - 1.0) * 100.0
    if pct < 0.05:
        return "optimal (within 0.05 %)"
    return f"within {pct:.3g} % of the best possible"


@dataclass(frozen=True)
class Quality:
    """Quality measures of a triangle mesh (see :func:`quality`).

    Lengths are in the units of the points, angles in degrees.  The last seven
    fields are ``None`` when no polygon was given.

    Attributes
    ----------
    n_vertices, n_triangles, n_edges, n_boundary_edges : int
        Counts; an edge is a boundary edge when one triangle uses it.
    area : float
        Total area of the triangles.
    shortest_edge, longest_edge : float
        Shortest and longest edge (Problem 2 minimises the longest).
    edge_ratio : float
        ``longest_edge / shortest_edge`` (Problem 1); ``inf`` for a zero-length edge.
    mean_edge, std_edge, cv_edge : float
        Mean, population standard deviation and coefficient of variation
        (std / mean) of the edge lengths.
    min_angle, max_angle : float
        Smallest and largest angle of any triangle, degrees.
    max_perimeter : float
        Largest triangle perimeter (Problem 3).
    histogram_counts : tuple of int
        Number of edges in each bin of ``length / mean_edge``; sums to ``n_edges``.
    histogram_edges : tuple of float
        The ``len(histogram_counts) + 1`` bin edges, in units of ``mean_edge``.
    n_steiner : int or None
        Number n of Steiner points the bounds assume.
    t_max : int or None
        Most triangles a triangulation of the polygon with n Steiner points can have.
    convex : bool or None
        Whether the polygon is convex without holes (the packing terms apply).
    d_n : float or None
        The packing distance used by the packing terms, ``None`` if they were not used.
    longest_edge_bound, max_perimeter_bound, edge_ratio_bound : Bound or None
        Lower bounds on the optimum and the certified factors.
    """

    n_vertices: int
    n_triangles: int
    n_edges: int
    n_boundary_edges: int
    area: float
    shortest_edge: float
    longest_edge: float
    edge_ratio: float
    mean_edge: float
    std_edge: float
    cv_edge: float
    min_angle: float
    max_angle: float
    max_perimeter: float
    histogram_counts: tuple[int, ...]
    histogram_edges: tuple[float, ...]
    n_steiner: int | None = None
    t_max: int | None = None
    convex: bool | None = None
    d_n: float | None = None
    longest_edge_bound: Bound | None = None
    max_perimeter_bound: Bound | None = None
    edge_ratio_bound: Bound | None = None
    #: Measures relative to a size field (:mod:`uniform2d.relative`), given one.
    relative: "RelativeQuality | None" = None  # noqa: F821 (uniform2d.relative)

    def to_dict(self) -> dict:
        """All fields as plain JSON-serialisable types.

        Bounds become nested dicts, tuples become lists, and non-finite numbers
        (an infinite edge ratio) become ``None``.
        """
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if f.name == "relative" and v is not None:
                v = v.to_dict()
            elif isinstance(v, Bound):
                v = v.to_dict()
            elif isinstance(v, tuple):
                v = [_json_float(x) if isinstance(x, float) else x for x in v]
            elif isinstance(v, float):
                v = _json_float(v)
            out[f.name] = v
        return out

    @property
    def bounds(self) -> dict[str, Bound]:
        """``{"longest_edge": ..., "max_perimeter": ..., "edge_ratio": ...}``; empty without a polygon."""
        if self.longest_edge_bound is None:
            return {}
        return {"longest_edge": self.longest_edge_bound, "max_perimeter": self.max_perimeter_bound,
                "edge_ratio": self.edge_ratio_bound}

    def certificate(self) -> list[str]:
        """The certified factors in words, one line per measure, with the active bound."""
        if self.longest_edge_bound is None:
            return []
        lines = [f"Certified against every triangulation of the polygon with n = {self.n_steiner} "
                 "Steiner points:"]
        for label, b in zip(("Longest edge", "Largest perimeter", "Edge ratio"), self.bounds.values()):
            lines.append(f"  {label:18s} {_within(b.factor):>34s}   bound: {b.active}")
        return lines

    def summary(self) -> str:
        """A text report in the spirit of Triangle's ``-V`` statistics, led by the certificate."""
        g = "{:.6g}".format
        lines = self.certificate()
        lines += [
            *([""] if lines else []),
            "Mesh quality",
            f"  Vertices: {self.n_vertices}   Triangles: {self.n_triangles}   "
            f"Edges: {self.n_edges}   Boundary edges: {self.n_boundary_edges}",
            f"  Area: {g(self.area)}",
            f"  Shortest edge: {g(self.shortest_edge)}   Longest edge: {g(self.longest_edge)}"
            f"   Ratio: {g(self.edge_ratio)}",
            f"  Mean edge: {g(self.mean_edge)}   Std: {g(self.std_edge)}   CV: {g(self.cv_edge)}",
            f"  Smallest angle: {self.min_angle:.4g} deg   Largest angle: {self.max_angle:.4g} deg",
            f"  Largest triangle perimeter: {g(self.max_perimeter)}",
            "  Edge length / mean histogram:",
        ]
        c, e = self.histogram_counts, self.histogram_edges
        for i in range(0, len(c), 4):
            cells = [f"{e[k]:5.3f} - {e[k + 1]:5.3f}: {c[k]:7d}" for k in range(i, min(i + 4, len(c)))]
            lines.append("    " + "   ".join(cells))
        if self.relative is not None:
            lines += self.relative.summary()
        if self.longest_edge_bound is not None:
            lines += [
                "",
                f"Lower bounds over all triangulations with n = {self.n_steiner} Steiner points "
                f"(at most {self.t_max} triangles"
                + (f", packing d_n = {g(self.d_n)}" if self.d_n is not None else "")
                + ")",
                f"  {'':20s}{'achieved':>12s}{'bound':>12s}{'factor':>10s}   active term",
            ]
            for label, b in zip(("Longest edge", "Largest perimeter", "Edge ratio"), self.bounds.values()):
                lines.append(
                    f"  {label:20s}{g(b.achieved):>12s}{g(b.value):>12s}"
                    f"{b.factor:>10.4g}   {b.term}"
                )
            if not self.convex:
                lines.append("  (packing terms not used: Lemma 9 needs a convex polygon without holes)")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()
