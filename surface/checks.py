"""The checks every surface mesh passes before anything else reads it.

Shared by :class:`surface.patch.Patch` (a disk with holes) and
:class:`surface.model.Model` (any manifold, oriented triangle mesh): array
shapes and values, degenerate faces, manifold edges and vertices, consistent
orientation, connected components and boundary loops.  Each check raises
:class:`~surface.errors.InvalidPatchError` with a message that says what to do.
"""

from __future__ import annotations

import logging

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .errors import InvalidPatchError

__all__ = [
    "CheckedMesh", "DEGENERATE_RATIO", "read_only", "as_arrays", "face_areas", "check_degenerate", "check_manifold",
    "check_connected", "components", "boundary_loops",
]

log = logging.getLogger(__name__)

#: A face is degenerate when ``2 * area < DEGENERATE_RATIO * longest_edge**2``.
DEGENERATE_RATIO = 1e-12


def as_arrays(vertices, faces):
    try:
        V = np.array(vertices, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPatchError(
            f"vertices must be numbers in an (N, 3) array ({exc})", "not_triangle_mesh"
        ) from None
    if V.ndim == 2 and V.shape[1] == 2:
        V = np.column_stack([V, np.zeros(len(V))])
    if V.ndim != 2 or V.shape[1] != 3:
        raise InvalidPatchError(
            f"vertices must be an (N, 3) array of positions, got shape {V.shape}",
            "not_triangle_mesh",
        )
    try:
        F0 = np.asarray(faces)
        if F0.dtype == object:
            raise ValueError("ragged face list (faces of different sizes)")
    except ValueError as exc:
        raise InvalidPatchError(
            f"not a triangle mesh: {exc}; triangulate the faces first "
            "(e.g. trimesh.load(..., force='mesh') triangulates polygons)",
            "not_triangle_mesh",
        ) from None
    if F0.ndim != 2 or F0.shape[1] != 3 or len(F0) == 0:
        what = (
            f"faces with {F0.shape[1]} corners" if F0.ndim == 2 and len(F0) else f"shape {F0.shape}"
        )
        raise InvalidPatchError(
            f"not a triangle mesh: faces must be an (M, 3) array of vertex indices with "
            f"M >= 1, got {what}; triangulate the faces first (split each quad along a "
            "diagonal, e.g. trimesh.geometry.triangulate_quads)",
            "not_triangle_mesh",
        )
    if not np.issubdtype(F0.dtype, np.integer):
        if not (np.issubdtype(F0.dtype, np.floating) and np.all(F0 == np.round(F0))):
            raise InvalidPatchError(
                "faces must hold integer vertex indices", "not_triangle_mesh"
            )
    F = F0.astype(np.int64)
    if F.min() < 0 or F.max() >= len(V):
        i = int(np.flatnonzero((F < 0).any(axis=1) | (F >= len(V)).any(axis=1))[0])
        raise InvalidPatchError(
            f"face {i} {F[i].tolist()} refers to a vertex that does not exist "
            f"(there are {len(V)} vertices, indices start at 0)",
            "not_triangle_mesh",
        )
    used = np.zeros(len(V), dtype=bool)
    used[F.ravel()] = True
    bad = ~np.isfinite(V[used]).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(used)[np.flatnonzero(bad)[0]])
        raise InvalidPatchError(
            f"vertex {i} has a non-finite coordinate {V[i].tolist()}; remove NaN/inf values",
            "not_triangle_mesh",
        )
    dropped = int((~used).sum())
    if dropped:
        log.info("dropping %d unreferenced vertices", dropped)
        remap = np.cumsum(used) - 1
        V = V[used]
        F = remap[F]
    return np.ascontiguousarray(V), np.ascontiguousarray(F), dropped


def face_areas(V, F):
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)


def check_degenerate(V, F):
    rep = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    e = [V[F[:, (i + 1) % 3]] - V[F[:, i]] for i in range(3)]
    longest2 = np.max([np.einsum("ij,ij->i", x, x) for x in e], axis=0)
    dbl = 2.0 * face_areas(V, F)
    flat = ~(dbl > DEGENERATE_RATIO * longest2)
    bad = rep | flat
    if bad.any():
        idx = np.flatnonzero(bad)
        i = int(idx[0])
        why = "it uses a vertex twice" if rep[i] else (
            "zero area: its corners are collinear or coincide"
        )
        more = f" ({len(idx)} degenerate faces in all)" if len(idx) > 1 else ""
        raise InvalidPatchError(
            f"face {i} is degenerate ({why}){more}; remove it or merge its vertices, e.g. "
            "trimesh's update_faces(nondegenerate_faces()) then merge_vertices()",
            "degenerate",
        )


def check_manifold(V, F):
    """Check edge and vertex manifoldness and orientation.

    Returns the unique edges (E, 2) and ``boundary_next``: a dict-like array
    mapping each boundary vertex to the next one along its loop (-1 elsewhere).
    """
    n = len(V)
    m = len(F)
    srt = np.sort(F, axis=1)
    rows = srt[np.lexsort(srt.T[::-1])]
    same = (rows[1:] == rows[:-1]).all(axis=1)
    if same.any():
        dup = np.flatnonzero((srt == rows[np.flatnonzero(same)[0]]).all(axis=1))
        k = int(dup[0])
        raise InvalidPatchError(
            f"non-manifold: faces {dup[0]} and {dup[1]} use the same three vertices "
            f"{F[k].tolist()}; remove the duplicate face",
            "non_manifold",
        )
    a = F.ravel()  # half-edge h = 3f + i goes from F[f, i] to F[f, (i + 1) % 3]
    b = F[:, [1, 2, 0]].ravel()
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    key = lo * n + hi
    order = np.argsort(key, kind="stable")
    ks = key[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    counts = np.diff(np.r_[starts, len(ks)])
    if (counts > 2).any():
        j = int(np.flatnonzero(counts > 2)[0])
        h = order[starts[j]]
        fs = sorted(int(x) // 3 for x in order[starts[j] : starts[j] + counts[j]])
        raise InvalidPatchError(
            f"non-manifold: edge ({lo[h]}, {hi[h]}) is shared by {counts[j]} faces "
            f"{fs}; a patch edge may belong to at most two faces — split the mesh there "
            "or remove the extra faces",
            "non_manifold",
        )
    edges = np.stack([lo[order[starts]], hi[order[starts]]], axis=1)
    pair = counts == 2
    h1 = order[starts[pair]]
    h2 = order[starts[pair] + 1]
    same_dir = a[h1] == a[h2]
    if same_dir.any():
        h = h1[np.flatnonzero(same_dir)[0]]
        raise InvalidPatchError(
            f"non-manifold orientation: the two faces of edge ({lo[h]}, {hi[h]}) "
            f"(faces {h1[same_dir][0] // 3} and {h2[same_dir][0] // 3}) run along it in "
            "the same direction, so the faces are not consistently oriented (or the "
            "surface is non-orientable); fix the winding, e.g. trimesh.repair.fix_winding",
            "non_manifold",
        )
    # One fan of faces around each vertex: corners of the same vertex in two faces
    # sharing an edge are joined; every vertex must end up with one corner group.
    def corner(h, which):  # corner of the start (0) or end (1) vertex of half-edge h
        f, i = h // 3, h % 3
        return 3 * f + (i + which) % 3

    r = np.concatenate([corner(h1, 0), corner(h1, 1)])
    c = np.concatenate([corner(h2, 1), corner(h2, 0)])
    g = coo_matrix((np.ones(len(r), dtype=np.int8), (r, c)), shape=(3 * m, 3 * m))
    _, lab = connected_components(g, directed=False)
    fans = np.unique(F.ravel().astype(np.int64) * (3 * m) + lab)  # (vertex, fan) pairs
    nfans = np.bincount(fans // (3 * m), minlength=n)
    if (nfans > 1).any():
        v = int(np.flatnonzero(nfans > 1)[0])
        raise InvalidPatchError(
            f"non-manifold vertex {v} at {V[v].tolist()}: {nfans[v]} separate fans of "
            "faces meet only at this point (a 'bow tie'); duplicate the vertex so each "
            "fan has its own copy, or remove one fan",
            "non_manifold",
        )
    single = order[starts[counts == 1]]
    boundary_next = np.full(n, -1, dtype=np.int64)
    boundary_next[a[single]] = b[single]
    return edges, boundary_next


def components(n: int, edges) -> tuple[int, np.ndarray]:
    """Connected components of the vertex graph: (count, (n,) label per vertex)."""
    g = coo_matrix((np.ones(len(edges), dtype=np.int8), (edges[:, 0], edges[:, 1])), shape=(n, n))
    ncomp, lab = connected_components(g, directed=False)
    return int(ncomp), lab.astype(np.int64)


def check_connected(V, F, edges):
    ncomp, lab = components(len(V), edges)
    if ncomp > 1:
        fl = np.bincount(lab[F[:, 0]], minlength=ncomp)
        sizes = sorted(fl.tolist(), reverse=True)
        raise InvalidPatchError(
            f"the mesh has {ncomp} separate components ({sizes[:6]} faces"
            f"{' ...' if ncomp > 6 else ''}); remesh one piece at a time, e.g. "
            "trimesh.Trimesh.split(only_watertight=False) and keep the piece you want",
            "components",
        )


def boundary_loops(boundary_next):
    nxt = boundary_next
    todo = np.flatnonzero(nxt >= 0)
    seen = np.zeros(len(nxt), dtype=bool)
    loops = []
    for s in todo:  # increasing index: every loop starts at its smallest vertex
        if seen[s]:
            continue
        lp = [s]
        seen[s] = True
        v = nxt[s]
        while v != s:
            lp.append(v)
            seen[v] = True
            v = nxt[v]
        loops.append(np.array(lp, dtype=np.int64))
    return loops


def read_only(a: np.ndarray) -> np.ndarray:
    """``a``, made read-only (the checked meshes' arrays are immutable)."""
    a.setflags(write=False)
    return a


class CheckedMesh:
    """What every checked surface mesh shows (:class:`~surface.patch.Patch`,
    :class:`~surface.model.Model`): read-only arrays and the measures of them."""

    __slots__ = ("_vertices", "_faces", "_edges", "_loops", "_n_dropped")

    def _keep(self, V, F, edges, loops, dropped) -> None:
        self._vertices = read_only(V)
        self._faces = read_only(F)
        self._edges = read_only(edges)
        self._loops = tuple(read_only(lp) for lp in loops)
        self._n_dropped = dropped

    @property
    def vertices(self) -> np.ndarray:
        """Vertex positions, (N, 3) float64, read-only."""
        return self._vertices

    @property
    def faces(self) -> np.ndarray:
        """Triangles, (M, 3) int64, read-only, in the input orientation."""
        return self._faces

    @property
    def edges(self) -> np.ndarray:
        """Unique undirected edges, (E, 2) int64 with ``edges[:, 0] < edges[:, 1]``."""
        return self._edges

    @property
    def boundary_loops(self) -> tuple[np.ndarray, ...]:
        """Boundary loops as vertex-index arrays; each follows the face orientation
        (interior on the left seen from the front side), starting at its smallest index.
        Ordered by smallest vertex index."""
        return self._loops

    @property
    def n_vertices(self) -> int:
        return len(self._vertices)

    @property
    def n_faces(self) -> int:
        return len(self._faces)

    @property
    def n_dropped_vertices(self) -> int:
        """How many unreferenced input vertices were dropped."""
        return self._n_dropped

    @property
    def face_areas(self) -> np.ndarray:
        """Area of every face, (M,) float64."""
        return face_areas(self._vertices, self._faces)

    @property
    def area(self) -> float:
        return float(self.face_areas.sum())

    @property
    def boundary_length(self) -> float:
        """Total 3-D length of the boundary loops."""
        V = self._vertices
        return float(
            sum(np.linalg.norm(V[np.roll(lp, -1)] - V[lp], axis=1).sum() for lp in self.boundary_loops)
        )

    @property
    def diagonal(self) -> float:
        """Length of the bounding-box diagonal."""
        return float(np.linalg.norm(self._vertices.max(axis=0) - self._vertices.min(axis=0)))
