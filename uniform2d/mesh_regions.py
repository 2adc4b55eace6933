"""The regions of a mesh: which triangle lies in which region of its polygon.

The polygon's own regions (its faces, labels and areas) are the polygon model's
(:mod:`uniform2d.regions`); here a mesh is read against them, for meshes from
uniform2d and from other meshers alike.  :func:`segment_chains` finds the mesh
edges on every interior segment, :func:`triangle_regions` the region of every
triangle (checking that the mesh tiles each region), and
:func:`polygon_vertices_first` renumbers another mesher's mesh so that both apply.

Examples
--------
>>> import uniform2d
>>> slab = uniform2d.Polygon([(0, 0), (4, 0), (4, 2), (0, 2)], segments=[[(1, 0), (1, 2)]])
>>> m = uniform2d.insert(slab, 20)
>>> sorted(set(triangle_regions(slab, m.mesh_points, m.triangles).tolist()))
[0, 1]
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ._kernel.validity import piece_chain
from .errors import InvalidArgumentError
from .regions import Regions
from .tolerance import boundary_tol

__all__ = ["segment_chains", "ring_chains", "triangle_regions", "polygon_vertices_first"]


def _fmt(x, y) -> str:
    return f"({float(x):.17g}, {float(y):.17g})"


def _neighbours(triangles: np.ndarray, n_points: int):
    """CSR (indptr, indices) of the mesh's vertex adjacency."""
    e = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    e = np.unique(np.sort(e, axis=1), axis=0)
    both = np.concatenate([e, e[:, ::-1]])
    order = np.lexsort((both[:, 1], both[:, 0]))
    both = both[order]
    indptr = np.searchsorted(both[:, 0], np.arange(n_points + 1))
    return indptr, both[:, 1]


def _chain(points, indptr, nbrs, used, n_vertices: int, a: int, b: int, tol: float) -> list[int]:
    """The mesh vertices from ``a`` to ``b`` along the straight piece a-b, through
    points within ``tol`` of it (mesh vertices placed on a piece are on its line
    up to the rounding of their coordinates) not ``used`` by another chain.

    A search (the final check's, :func:`uniform2d._kernel.validity.piece_chain`),
    not a walk to the nearest point: where two pieces leave a vertex at a tiny
    angle, or one runs a rounding off a ring edge, the other's points are within
    ``tol`` too, and a walk that took one of them would miss the chain."""
    inner = piece_chain(points, nbrs, indptr, used, points[:n_vertices], a, b, tol)
    if inner is None:
        raise InvalidArgumentError(
            f"the mesh does not contain the segment piece from vertex {a} {_fmt(*points[a])} to "
            f"vertex {b} {_fmt(*points[b])} as a chain of edges; it does not conform to the "
            "polygon's segments")
    used[inner] = True
    return [a, *inner, b]


def _check_mesh_arrays(polygon, points, triangles):
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    if pts.ndim != 2 or pts.shape[1] != 2 or tri.ndim != 2 or tri.shape[1] != 3:
        raise InvalidArgumentError(
            f"expected points (N, 2) and triangles (M, 3), got {pts.shape} and {tri.shape}")
    nv = len(polygon.vertices)
    if len(pts) < nv or not np.array_equal(pts[:nv], polygon.vertices):
        raise InvalidArgumentError(
            "the mesh must start with the polygon's vertices (points[:len(polygon.vertices)] "
            "== polygon.vertices), as every uniform2d mesh does")
    if tri.size and (tri.min() < 0 or tri.max() >= len(pts)):
        raise InvalidArgumentError(f"triangles refer to points outside 0..{len(pts) - 1}")
    return pts, tri


def segment_chains(polygon, points, triangles) -> tuple[np.ndarray, np.ndarray]:
    """The mesh edges that lie on the polygon's segments.

    Returns
    -------
    edges : ndarray, shape (K, 2), int64
        Mesh vertex pairs, in the direction of their segment, piece after piece.
    ids : ndarray, shape (K,), int64
        The segment (index into ``polygon.segments``) of each edge.

    Raises
    ------
    InvalidArgumentError
        If the mesh does not start with ``polygon.vertices`` or does not contain
        a segment piece as a chain of edges.
    """
    pts, tri = _check_mesh_arrays(polygon, points, triangles)
    if not len(polygon.segment_edges):
        return np.empty((0, 2), np.int64), np.empty(0, np.int64)
    indptr, nbrs = _neighbours(tri, len(pts))
    scale = float(np.abs(pts).max())
    # at least the library's own: it puts a vertex that close to a piece on its chain
    near = boundary_tol(polygon)
    used = np.zeros(len(pts), bool)
    edges, ids = [], []
    for (a, b), s in zip(polygon.segment_edges, polygon.segment_ids):
        L = float(np.hypot(*(pts[b] - pts[a])))
        tol = max(1e-9 * L + 8 * np.spacing(scale), near)
        chain = _chain(pts, indptr, nbrs, used, len(polygon.vertices), int(a), int(b), tol)
        edges.extend(zip(chain[:-1], chain[1:]))
        ids.extend([int(s)] * (len(chain) - 1))
    return np.array(edges, np.int64).reshape(-1, 2), np.array(ids, np.int64)


def ring_chains(polygon, points, triangles) -> tuple[np.ndarray, np.ndarray]:
    """The mesh edges on the polygon's rings, each ring walked from its first vertex.

    The boundary edges of a mesh of P (those of one triangle) run along its
    rings, in the rings' direction when the triangles are counter-clockwise
    (the interior on their left); since holes neither touch each other nor the
    outer ring, every mesh boundary vertex has one edge out.

    Returns
    -------
    edges : ndarray, shape (K, 2), int64
        Mesh vertex pairs ``(a, b)``: ring 0 (the outer one) from its first
        vertex round to it, then each hole's.
    ids : ndarray, shape (K,), int64
        The ring (0 the outer ring, ``1 + i`` hole ``i``) of each edge.

    Raises
    ------
    InvalidArgumentError
        If the mesh does not start with ``polygon.vertices`` or its boundary is
        not the polygon's rings.
    """
    pts, tri = _check_mesh_arrays(polygon, points, triangles)
    he = tri[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    key = np.sort(he, axis=1)
    _, inverse, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    boundary = he[count[inverse.ravel()] == 1]
    nxt = np.full(len(pts), -1, np.int64)
    nxt[boundary[:, 0]] = boundary[:, 1]
    edges, ids = [], []
    for r in range(len(polygon.rings)):
        lo, hi = int(polygon.ring_offsets[r]), int(polygon.ring_offsets[r + 1])
        chain = [lo]
        while len(chain) <= len(boundary) and nxt[chain[-1]] >= 0 and (
                len(chain) == 1 or chain[-1] != lo):
            chain.append(int(nxt[chain[-1]]))
        on_ring = set(chain)
        if chain[-1] != lo or len(chain) < 3 or not all(v in on_ring for v in range(lo, hi)):
            raise InvalidArgumentError(
                f"the mesh's boundary does not run along ring {r} of the polygon from its "
                f"vertex {lo} {_fmt(*pts[lo])}; it does not conform to the polygon")
        edges.extend(np.column_stack([chain[:-1], chain[1:]]).tolist())
        ids.extend([r] * (len(chain) - 1))
    if len(edges) != len(boundary):
        raise InvalidArgumentError(
            f"the mesh has {len(boundary)} boundary edges, {len(boundary) - len(edges)} of them "
            "on no ring of the polygon; it does not conform to the polygon")
    return np.array(edges, np.int64).reshape(-1, 2), np.array(ids, np.int64)


def _area_slack(polygon, regions: Regions) -> np.ndarray:
    """(R,) how far a conforming mesh's area in each region may be off its area:
    1e-9 of P's, or, where the coordinates are coarse for the region (far from
    the origin), the rounding of the points on its rotated boundary pieces --
    each up to an ulp off its piece's line, shifting the area by that times the
    length along it."""
    ulp = float(np.spacing(np.abs(polygon.vertices).max()))
    perimeter = np.array([f.length for f in regions.faces])
    return np.maximum(1e-9 * polygon.area, 2 * ulp * perimeter)


def triangle_regions(polygon, points, triangles, regions: Regions | None = None) -> np.ndarray:
    """The region of every triangle of a conforming mesh of ``polygon``, (M,) int64.

    Triangles are grouped by crossing only edges that lie on no segment; each
    group is one region, found by its largest triangle's centroid.  The group's
    area must equal its region's (to rounding), so a mesh that does not conform
    cannot pass unnoticed.

    Raises
    ------
    InvalidArgumentError
        If the mesh does not start with ``polygon.vertices``, misses a segment,
        or its triangles do not tile the regions.
    """
    pts, tri = _check_mesh_arrays(polygon, points, triangles)
    if not len(polygon.segment_edges):
        return np.zeros(len(tri), np.int64)
    regions = regions if regions is not None else polygon.regions
    cut, _ = segment_chains(polygon, pts, tri)
    cut_keys = set(map(tuple, np.sort(cut, axis=1).tolist()))
    he = tri[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    owner = np.repeat(np.arange(len(tri)), 3)
    key = np.sort(he, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    k, o = key[order], owner[order]
    same = np.all(k[1:] == k[:-1], axis=1)
    i = np.flatnonzero(same)
    keep = np.array([tuple(k[j]) not in cut_keys for j in i], dtype=bool)
    i = i[keep] if len(i) else i
    graph = coo_matrix((np.ones(len(i)), (o[i], o[i + 1])), shape=(len(tri), len(tri)))
    n_comp, comp = connected_components(graph, directed=False)
    p = pts[tri]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    centroid = p.mean(axis=1)
    out = np.empty(len(tri), np.int64)
    for c in range(n_comp):
        members = np.flatnonzero(comp == c)
        big = members[np.argmax(area[members])]
        r = regions.locate(*centroid[big])
        if r < 0:
            raise InvalidArgumentError(
                f"triangle {int(big)} of the mesh lies in no region of the polygon; the mesh "
                "does not tile it")
        out[members] = r
    sums = np.bincount(out, weights=area, minlength=len(regions))
    bad = np.flatnonzero(np.abs(sums - regions.areas) > _area_slack(polygon, regions))
    if len(bad):
        r = int(bad[0])
        raise InvalidArgumentError(
            f"the mesh's triangles in region {r} cover {sums[r]:.17g}, but the region's area "
            f"is {regions.areas[r]:.17g}; the mesh does not conform to the polygon's segments")
    return out


def polygon_vertices_first(polygon, points, triangles) -> tuple[np.ndarray, np.ndarray]:
    """The mesh renumbered so that ``points[:len(polygon.vertices)]`` is
    ``polygon.vertices``, as the functions above expect (for meshes from other
    meshers, which keep the polygon's vertices exactly but number them their way).

    Raises
    ------
    InvalidArgumentError
        If a polygon vertex is not a mesh point.
    """
    pts = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    where = {}
    for i, p in enumerate(map(tuple, pts.tolist())):
        where.setdefault(p, i)
    V = polygon.vertices
    missing = [k for k, v in enumerate(map(tuple, V.tolist())) if v not in where]
    if missing:
        k = missing[0]
        raise InvalidArgumentError(
            f"polygon vertex {k} {_fmt(*V[k])} is not a point of the mesh ({len(missing)} missing)")
    first = np.array([where[tuple(v)] for v in V.tolist()], dtype=np.int64)
    rest = np.setdiff1d(np.arange(len(pts)), first)
    order = np.concatenate([first, rest])
    new = np.empty(len(pts), np.int64)
    new[order] = np.arange(len(pts))
    return pts[order], new[tri]
