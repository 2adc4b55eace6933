"""Regions: the faces into which a polygon's rings and segments split its interior.

The ring edges and the segment pieces of a :class:`~uniform2d.Polygon` are
already noded exactly (they meet only at shared vertices), so the faces are the
polygons that :func:`shapely.polygonize` closes from them, less those in holes.
A segment with a free end (a stiffener) bounds no face; a closed segment, or a
chain of segments from ring to ring, does.

Numbering
---------
Regions are numbered in the lexicographic order (x, then y) of their vertex
lists sorted lexicographically: the region whose smallest vertex is smallest
comes first, and regions sharing their smallest vertex are told apart by the
next ones.  The rule depends only on the coordinates, so it is the same for
the same polygon whichever way its rings and segments were given, and it is
kept by positive scaling and translation.

Labels
------
``Polygon(..., regions=[(x, y, label), ...])`` labels the region strictly
containing each seed point (Triangle's regional attributes); a region without
a seed has the label ``None``.

Examples
--------
>>> from uniform2d import Polygon
>>> slab = Polygon([(0, 0), (4, 0), (4, 2), (0, 2)], segments=[[(1, 0), (1, 2)]],
...                regions=[(3, 1, "concrete")])
>>> r = slab.regions
>>> r.areas.tolist(), r.labels
([2.0, 6.0], (None, 'concrete'))
>>> r.locate(0.5, 1.0), r.locate(2, 1), r.locate(1, 1)
(0, 1, -1)
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
import shapely
from .errors import InvalidConstraintError

__all__ = ["Regions", "faces", "region_seeds", "build"]

def _fmt(x, y) -> str:
    return f"({float(x):.17g}, {float(y):.17g})"


@dataclass(frozen=True, eq=False)
class Regions:
    """The regions of a polygon, in numbering order.

    Attributes
    ----------
    faces : tuple of shapely.Polygon
        Region ``r`` is ``faces[r]`` (holes of a face are holes of P or regions
        enclosed by it).
    areas : ndarray, shape (R,), float64
    labels : tuple
        The label of each region (``None`` where no seed marks it).
    """

    faces: tuple
    areas: np.ndarray
    labels: tuple

    def __len__(self) -> int:
        return len(self.faces)

    def locate(self, x, y) -> int:
        """The region strictly containing (x, y), or -1 (outside P, in a hole, or
        on a ring or segment)."""
        pt = shapely.Point(float(x), float(y))
        for r, f in enumerate(self.faces):
            if f.contains_properly(pt):
                return r
        return -1


def _lines(polygon) -> np.ndarray:
    """Every ring edge and segment piece as a (K, 2, 2) array of end points."""
    e = polygon.constraint_edges
    return polygon.vertices[e]


def faces(polygon) -> list:
    """The faces of ``polygon`` (shapely Polygons), numbered as the module says."""
    if not len(polygon.segment_edges):
        return [polygon.to_shapely()]
    found = shapely.polygonize(shapely.linestrings(_lines(polygon))).geoms
    whole = polygon.to_shapely()
    shapely.prepare(whole)
    kept = [f for f in found if whole.contains_properly(f.representative_point())]

    def key(face):
        pts = [tuple(c) for ring in (face.exterior, *face.interiors) for c in ring.coords[:-1]]
        return sorted(pts)

    return sorted(kept, key=key)


def _check_label(i: int, label):
    ok = isinstance(label, str) or (
        isinstance(label, numbers.Real) and not isinstance(label, bool) and np.isfinite(label))
    if not ok:
        raise InvalidConstraintError(
            f"region {i}: the label {label!r} is not a string or a finite number; "
            "label regions with names or numbers")
    return label.item() if isinstance(label, np.generic) else label


def region_seeds(seeds) -> tuple:
    """Check ``[(x, y, label), ...]``; return them as a tuple of (float, float, label)."""
    if seeds is None:
        return ()
    if isinstance(seeds, (str, bytes)) or not hasattr(seeds, "__len__"):
        raise InvalidConstraintError(
            f"regions must be a sequence of (x, y, label) seeds, got {type(seeds).__name__}")
    out = []
    for i, s in enumerate(seeds):
        if isinstance(s, (str, bytes)) or not hasattr(s, "__len__") or len(s) != 3:
            raise InvalidConstraintError(
                f"region {i}: expected a seed (x, y, label), got {s!r}; give the point "
                "inside the region and its label")
        try:
            x, y = float(s[0]), float(s[1])
        except (TypeError, ValueError):
            raise InvalidConstraintError(
                f"region {i}: the seed coordinates {s[0]!r}, {s[1]!r} are not numbers") from None
        if not (np.isfinite(x) and np.isfinite(y)):
            raise InvalidConstraintError(f"region {i}: the seed {_fmt(x, y)} is not finite")
        out.append((x, y, _check_label(i, s[2])))
    return tuple(out)


def build(polygon, seeds) -> Regions:
    """The :class:`Regions` of ``polygon`` with the labels of ``seeds`` (checked
    by :func:`region_seeds`)."""
    fs = faces(polygon)
    labels = [None] * len(fs)
    marked = {}
    for i, (x, y, label) in enumerate(seeds):
        pt = shapely.Point(x, y)
        hit = [r for r, f in enumerate(fs) if f.intersects(pt)]
        inside = [r for r in hit if fs[r].contains_properly(pt)]
        if not inside:
            where = "on a ring or segment" if hit else "outside the polygon or in a hole"
            raise InvalidConstraintError(
                f"region {i}: the seed {_fmt(x, y)} lies {where}; put it strictly inside "
                "the region it labels")
        r = inside[0]
        if r in marked:
            j = marked[r]
            raise InvalidConstraintError(
                f"regions {j} and {i} both lie in region {r} (seeds {_fmt(*seeds[j][:2])} and "
                f"{_fmt(x, y)}); give one seed per region, or add the segment that separates them")
        marked[r] = i
        labels[r] = label
    areas = np.array([f.area for f in fs], dtype=np.float64)
    areas.setflags(write=False)
    return Regions(tuple(fs), areas, tuple(labels))
