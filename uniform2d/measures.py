"""Measuring a triangle mesh: pure functions of its points and triangles.

Nothing here needs the polygon or runs the mesher: :func:`mesh_measures` gives
every field of :class:`uniform2d.quality_result.Quality` that does not depend on
P (counts, edge lengths and their spread, angles, perimeters, area, the
histogram), :func:`edge_lengths` the unique edges and their lengths.  The
certificate, which compares the measures with lower bounds on the optimum, is
:func:`uniform2d.quality.quality`.
"""

from __future__ import annotations

import math

import numpy as np

from . import libm
from ._kernel.edges import edges_by_vertex
from .errors import InvalidArgumentError

__all__ = ["as_points", "as_triangles", "edges_with_counts", "edge_lengths", "histogram",
           "triangle_measures", "mesh_measures", "TRIANGLE_BLOCK"]


# -- input checks --------------------------------------------------------------
def as_points(points) -> np.ndarray:
    """``points`` as a checked (N, 2) float64 array of finite coordinates."""
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InvalidArgumentError(f"points: expected a (N, 2) array, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        i = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InvalidArgumentError(f"points: point {i} has a non-finite coordinate {pts[i].tolist()}")
    return pts


def as_triangles(triangles, n_points: int) -> np.ndarray:
    """``triangles`` as a checked (M, 3) int64 array of indices into ``n_points`` points."""
    tri = np.asarray(triangles)
    if tri.ndim != 2 or tri.shape[1] != 3:
        raise InvalidArgumentError(f"triangles: expected a (M, 3) array, got shape {tri.shape}")
    if tri.size and not np.issubdtype(tri.dtype, np.integer):
        raise InvalidArgumentError(f"triangles: expected integer vertex indices, got dtype {tri.dtype}")
    tri = tri.astype(np.int64, copy=False)
    if tri.size and (tri.min() < 0 or tri.max() >= n_points):
        bad = int(np.flatnonzero(((tri < 0) | (tri >= n_points)).any(axis=1))[0])
        raise InvalidArgumentError(
            f"triangles: triangle {bad} {tri[bad].tolist()} refers to a point outside "
            f"0..{n_points - 1}"
        )
    return tri


# -- edges ---------------------------------------------------------------------
def edges_with_counts(tri: np.ndarray, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Unique undirected edges (E, 2) int64 with i < j, sorted, and how many triangles use each.

    The same as :func:`uniform2d.geometry.unique_edges`, with counts, bucketed by
    the smaller vertex instead of sorted as a whole (each bucket holds a vertex's
    few larger neighbours): at 1e6 points a tenth of the sort's time.  The
    kernel always gets a read-only view, so it is compiled once, not once for
    read-only triangles (a Mesh's) and once for writable ones."""
    view = np.ascontiguousarray(tri, dtype=np.int64).view()
    view.flags.writeable = False
    return edges_by_vertex(view, np.int64(n_points))


def edge_lengths(points, triangles) -> tuple[np.ndarray, np.ndarray]:
    """The unique undirected edges of a triangle mesh and their lengths.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Vertex coordinates, float64.
    triangles : array_like, shape (M, 3)
        Vertex indices of each triangle, integers in ``0..N-1``.

    Returns
    -------
    edges : ndarray, shape (E, 2), int64
        Each edge once, as ``(i, j)`` with ``i < j``, sorted lexicographically.
    lengths : ndarray, shape (E,), float64
        Euclidean length of each edge.

    Examples
    --------
    >>> from uniform2d.measures import edge_lengths
    >>> pts = [(0, 0), (1, 0), (1, 1), (0, 1)]
    >>> edges, lengths = edge_lengths(pts, [(0, 1, 2), (0, 2, 3)])
    >>> edges.tolist()
    [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    >>> lengths.round(4).tolist()
    [1.0, 1.4142, 1.0, 1.0, 1.0]
    """
    pts = as_points(points)
    tri = as_triangles(triangles, len(pts))
    edges, _ = edges_with_counts(tri, len(pts))
    d = pts[edges[:, 1]] - pts[edges[:, 0]]
    return edges, np.hypot(d[:, 0], d[:, 1])


# -- the measures --------------------------------------------------------------
def histogram(values: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """np.histogram over [min, max], widened to +-0.5 when the values (nearly) coincide."""
    lo, hi = float(values.min()), float(values.max())
    if hi - lo <= 1e-9 * max(1.0, abs(hi)):
        lo, hi = lo - 0.5, hi + 0.5
    return np.histogram(values, bins=bins, range=(lo, hi))


#: Triangles measured at a time by :func:`mesh_measures`.
TRIANGLE_BLOCK = 1 << 16


def triangle_measures(pts: np.ndarray, tri: np.ndarray):
    """(largest perimeter, smallest and largest angle in degrees, |twice the area|
    of each triangle) of the triangles ``tri`` (K, 3)."""
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    sides = np.stack(
        [np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1)],
        axis=1,
    )

    def _angle(p, q, r):  # angle at p of triangle p, q, r
        u, v = q - p, r - p
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        return libm.arctan2(np.abs(cross), (u * v).sum(axis=1))

    angles = np.degrees(np.stack([_angle(a, b, c), _angle(b, c, a), _angle(c, a, b)], axis=1))
    ab, ac = b - a, c - a
    cross = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    return float(sides.sum(axis=1).max()), float(angles.min()), float(angles.max()), cross


def mesh_measures(pts: np.ndarray, tri: np.ndarray, bins: int) -> dict:
    """Every field of :class:`Quality` that does not need the polygon."""
    # Edges.
    edges, counts = edges_with_counts(tri, len(pts))
    n_edges, n_boundary = len(edges), int((counts == 1).sum())
    # a coordinate at a time: no (E, 2) gathers
    i, j = edges[:, 0], edges[:, 1]
    dx, dy = pts[j, 0], pts[j, 1]
    dx -= pts[i, 0]
    dy -= pts[i, 1]
    del edges, counts, i, j  # only the lengths are used from here on
    lengths = np.hypot(dx, dy)
    del dx, dy
    shortest = float(lengths.min())
    longest = float(lengths.max())
    ratio = longest / shortest if shortest > 0 else math.inf
    mean = float(lengths.mean())
    std = float(lengths.std())
    cv = std / mean if mean > 0 else math.inf
    rel = lengths / mean if mean > 0 else np.zeros_like(lengths)
    hist_counts, hist_edges = histogram(rel, bins)

    # Triangles: perimeters, angles, areas, in blocks (each needs a dozen (M, 2)
    # temporaries, hundreds of MB at 1e6 points at once); the areas are summed in
    # one go, so the total is the same to the bit
    max_perimeter, min_angle, max_angle = -math.inf, math.inf, -math.inf
    cross = np.empty(len(tri))
    for lo in range(0, len(tri), TRIANGLE_BLOCK):
        t = tri[lo:lo + TRIANGLE_BLOCK]
        p, a_min, a_max, cross[lo:lo + len(t)] = triangle_measures(pts, t)
        max_perimeter = max(max_perimeter, p)
        min_angle, max_angle = min(min_angle, a_min), max(max_angle, a_max)
    area = float(0.5 * cross.sum())

    return dict(
        n_vertices=len(pts), n_triangles=len(tri), n_edges=n_edges, n_boundary_edges=n_boundary,
        area=area, shortest_edge=shortest, longest_edge=longest, edge_ratio=ratio,
        mean_edge=mean, std_edge=std, cv_edge=cv,
        min_angle=min_angle, max_angle=max_angle, max_perimeter=max_perimeter,
        histogram_counts=tuple(int(x) for x in hist_counts),
        histogram_edges=tuple(float(x) for x in hist_edges),
    )
