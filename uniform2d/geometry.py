"""Small geometric facts shared by the core, the peers and the surface layer.

* how many vertices an equilateral mesh of a given edge length has, and the
  edge length for a given count (:func:`vertex_count`, :func:`size_for_count`);
* a polygon's edges as start points and vectors (:func:`polygon_edges`);
* the unique and the boundary edges of a triangle list (:func:`unique_edges`,
  :func:`boundary_edges`);
* distances from points to segments, in any dimension (:func:`segment_distance`,
  :func:`nearest_segment`);
* the signed area of a ring (:func:`signed_area`);
* coordinates the caller gave, read and checked (:func:`xy_array`,
  :func:`check_finite`), for the polygon model's rings and segments.

Everything here is plain numpy on the caller's arrays (never modified).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "vertex_count",
    "size_for_count",
    "polygon_edges",
    "unique_edges",
    "boundary_edges",
    "point_segment_distance",
    "segment_distance",
    "nearest_segment",
    "signed_area",
    "xy_array",
    "check_finite",
]


def vertex_count(area: float, perimeter: float, size: float, n_holes: int = 0) -> float:
    """Vertices N of a mesh of equilateral triangles of side ``size`` (not rounded).

    Such a mesh has T = A / (√3/4 · h²) triangles and about B/h boundary
    vertices; Euler's formula for a domain with h_P holes,
    T = 2N − N_b − 2 + 2 h_P, then gives N = (T + N_b + 2 − 2 h_P) / 2.

    Examples
    --------
    >>> round(vertex_count(1.0, 4.0, 0.1), 3)
    136.47
    """
    T = area / (math.sqrt(3) / 4 * size * size)
    Nb = perimeter / size
    return (T + Nb + 2 - 2 * n_holes) / 2


def size_for_count(area: float, perimeter: float, n_vertices: int, n_holes: int = 0) -> float:
    """Edge length h at which a mesh of equilateral triangles has ``n_vertices`` vertices.

    The inverse of :func:`vertex_count`, a quadratic in 1/h; ``inf`` if no
    positive length gives that many.

    Examples
    --------
    >>> round(size_for_count(1.0, 4.0, 133), 2)
    0.1
    """
    a = 4.0 * area / math.sqrt(3.0)
    c = 2.0 - 2.0 * n_holes - 2.0 * n_vertices
    disc = perimeter * perimeter - 4.0 * a * c
    u = (-perimeter + math.sqrt(max(disc, 0.0))) / (2.0 * a)
    return 1.0 / u if u > 0 else math.inf


def polygon_edges(polygon, constraints: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(starts (E, 2), vectors (E, 2), lengths (E,)) of a polygon's edges, in
    :attr:`uniform2d.Polygon.edges` order (the interior is on each edge's left);
    with ``constraints``, of every edge the mesh must keep, the interior segment
    pieces after the rings' edges (:attr:`uniform2d.Polygon.constraint_edges`)."""
    V = polygon.vertices
    E = polygon.constraint_edges if constraints else polygon.edges
    a = V[E[:, 0]]
    d = V[E[:, 1]] - a
    L = np.hypot(d[:, 0], d[:, 1])
    return a, d, L


def is_vertex(polygon, pts: np.ndarray) -> np.ndarray:
    """Which of the points (k, 2) equal a polygon vertex exactly (a fixed point may
    lie within rounding of a segment piece without splitting it, and a point
    placed on the piece can land on it)."""
    V = polygon.vertices
    return np.isin(pts[:, 0] + 1j * pts[:, 1], V[:, 0] + 1j * V[:, 1])


def unique_edges(triangles, n_points: int | None = None, *, return_counts: bool = False):
    """Unique undirected edges (E, 2) int64 of a triangle list, ``i < j``, sorted.

    With ``return_counts``, also how many triangles use each edge (1 on the
    boundary, 2 inside).  ``n_points`` (default: the largest index + 1) only
    has to exceed every vertex index.
    """
    tri = np.asarray(triangles)
    if n_points is None:
        n_points = int(tri.max()) + 1 if tri.size else 1
    N = np.int64(n_points)
    M = len(tri)
    # one key array, filled a corner pair at a time and sorted in place: no
    # (3M, 2) copy of the edges, no separate min/max arrays
    key = np.empty(3 * M, np.int64)
    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        a, b = tri[:, i].astype(np.int64), tri[:, j].astype(np.int64)
        part = key[k * M:(k + 1) * M]
        np.minimum(a, b, out=part)
        part *= N
        part += np.maximum(a, b)
    key.sort()
    first = np.ones(len(key), bool)
    first[1:] = key[1:] != key[:-1]
    start = np.flatnonzero(first)
    del first
    keys = key[start]
    del key
    if return_counts:  # run lengths, without a copy of ``start`` with its end appended
        counts = np.empty(len(start), np.int64)
        np.subtract(start[1:], start[:-1], out=counts[:-1])
        counts[-1:] = 3 * M - start[-1:]
    del start
    edges = np.empty((len(keys), 2), np.int64)
    np.divmod(keys, N, out=(edges[:, 0], edges[:, 1]))
    return (edges, counts) if return_counts else edges


def boundary_edges(triangles, n_points: int) -> np.ndarray:
    """The edges (K, 2) used by one triangle only, directed as in their triangle
    (counter-clockwise around the mesh), in triangle order."""
    T = np.asarray(triangles)
    E = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    srt = np.sort(E, axis=1)
    key = srt[:, 0].astype(np.int64) * n_points + srt[:, 1]
    _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    return E[cnt[inv.ravel()] == 1]


def point_segment_distance(P, A, B) -> np.ndarray:
    """Distance from each point P[i] to the segment A[i]-B[i], row-wise, (K, D) -> (K,).

    Any dimension; a segment of length 0 is its point."""
    AB = B - A
    L2 = np.einsum("ij,ij->i", AB, AB)
    AP = P - A
    t = np.divide(np.einsum("ij,ij->i", AP, AB), L2, out=np.zeros(len(P)), where=L2 > 0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(AP - t[:, None] * AB, axis=1)


def segment_distance(points, a, b, chunk: int = 256) -> np.ndarray:
    """Distance from each point (K, D) to the nearest of the segments a[i]-b[i] (E, D).

    Any dimension; works in chunks of ``chunk`` points (memory chunk·E).
    For many 2-D points against a polygon's edges with a cap on the distances
    of interest, the compiled :func:`uniform2d._kernel.distance.to_segments` is faster.
    """
    P = np.asarray(points, dtype=np.float64)
    out = np.full(len(P), np.inf)
    E = len(a)
    for s in range(0, len(P), chunk):
        p = P[s : s + chunk]
        d = point_segment_distance(np.repeat(p, E, axis=0), np.tile(a, (len(p), 1)), np.tile(b, (len(p), 1)))
        out[s : s + chunk] = d.reshape(len(p), E).min(axis=1)
    return out


def nearest_segment(q, a, b) -> tuple[int, float]:
    """(index, parameter t in [0, 1]) of the segment a[i]-b[i] nearest to point q;
    the nearest point is ``a[i] + t (b[i] - a[i])``."""
    ab = b - a
    tt = np.clip(((q - a) * ab).sum(1) / (ab * ab).sum(1), 0, 1)
    d = np.linalg.norm(a + tt[:, None] * ab - q, axis=1)
    e = int(np.argmin(d))
    return e, float(tt[e])


def signed_area(ring) -> float:
    """Shoelace area of a ring (positive if counter-clockwise), (k, 2) float64.

    Summed relative to the ring's first vertex, so the rounding error scales with
    the ring's size, not with its distance from the origin.  The products are
    added exactly (``math.fsum``), not by BLAS's dot, whose kernel OpenBLAS
    picks per CPU, each adding in its own order: the area sets the spacing, so
    the last bit of it must not depend on the CPU."""
    ring = np.asarray(ring, dtype=np.float64)
    x = ring[:, 0] - ring[0, 0]
    y = ring[:, 1] - ring[0, 1]
    return 0.5 * math.fsum(np.concatenate([x * np.roll(y, -1), -(np.roll(x, -1) * y)]))


def xy_array(coords, name: str, error: type) -> np.ndarray:
    """``coords`` as a float64 array, or ``error`` naming ``name`` if they are not numbers."""
    try:
        return np.array(coords, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{name}: coordinates must be numbers in a (k, 2) array-like ({exc})") from None


def check_finite(xy: np.ndarray, name: str, error: type, advice: str = "") -> None:
    """Raise ``error`` naming the first vertex of ``xy`` (K, 2) with a non-finite
    coordinate, and ``advice`` after it."""
    bad = ~np.isfinite(xy).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        x, y = xy[i]
        raise error(f"{name}: vertex {i} has a non-finite coordinate ({x:.17g}, {y:.17g}){advice}")
