"""Cutting a model into charts: disks (holes allowed) that flatten with low distortion.

The segmentation, deterministic and in three steps:

1. **Creases first.**  Edges whose faces' normals differ by more than the crease
   angle, and the caller's feature chains, are barriers: the first regions are
   the connected sets of faces between them (a box gives its six sides, a tank
   its two caps and its wall).
2. **Accept or split.**  A region is a chart when it is a disk with holes (a
   :class:`~surface.patch.Patch`), its flattening passes every check of
   :func:`~surface.parameterize.parameterize`, and the flattening's area scale
   varies by at most :data:`MAX_AREA_SCALE_RATIO` (largest over smallest, per
   face).  Otherwise it is split in two by a 2-means of the face normals grown
   as two competing floods from two seeds (Cohen-Steiner et al.'s variational
   shape approximation with two proxies), so both halves are connected and
   each is flatter than the whole; a closed surface, a handle or a tube is cut
   the same way, because a region that is not a disk always spans normals far
   apart.  A region whose normals are all alike but which still fails is split
   by distance instead (two floods from its two mutually farthest faces).
3. **Merge back.**  Neighbouring charts whose union is also a chart are merged,
   those sharing the longest seam first, so a developable wall split on the way
   becomes one chart again and seams stay few and short.

Why the bounds are 2.5 and 2.0: the compensated size field
(:mod:`surface.sizing`) makes the planar mesh uniform in 3-D whatever the area
scale, but the mesher reaches the field less closely the more it varies.  The
60-degree spherical cap that single patches handle well has an area-scale
ratio 2.15 (size ratio 1.47); a hemisphere has 4.6 and two thirds of a sphere
9.8, where the single-patch remesh loses its uniformity (edge CV 0.13 against
0.07).  So a disk flattens in one piece up to :data:`ONE_PIECE_RATIO` = 2.5,
which keeps every patch that worked as it was.  Inside an atlas, charts are cut
down to 2.0: on the example models of :mod:`surface.models` that gave one chart
more on the curved ones and a better mesh on every one of them, while 1.7 added
seams and lost again (the figures are in the commit that chose it and in
``benchmarks/bench_models.py``).
"""

from __future__ import annotations

import dataclasses
import heapq
import logging

import numpy as np

from uniform2d.errors import InternalError, Uniform2dError

from . import _trimesh
from .errors import InvalidPatchError
from .parameterize import Parameterization, parameterize
from .patch import Patch

__all__ = ["Chart", "segment", "MAX_AREA_SCALE_RATIO", "ONE_PIECE_RATIO", "CREASE_ANGLE"]

log = logging.getLogger(__name__)

#: The largest area-scale ratio (max / min over faces) a chart's flattening may have.
MAX_AREA_SCALE_RATIO = 2.0

#: The largest area-scale ratio with which a disk is flattened in one piece
#: (:func:`surface.remesh`) rather than cut into an atlas.
ONE_PIECE_RATIO = 2.5

#: Edges bent more than this (degrees) are chart boundaries when the caller gives
#: no feature angle: seams on creases cost nothing and keep them.
CREASE_ANGLE = 60.0

#: Rounds of the two-proxy shape approximation in a split.
SPLIT_ROUNDS = 4

#: A region with fewer faces that still fails is an error, not split again.
MIN_FACES = 4


@dataclasses.dataclass(frozen=True)
class Chart:
    """One chart of an atlas.

    Attributes
    ----------
    faces : (k,) int64
        The model faces of the chart, increasing.
    vertices : (m,) int64
        The model vertices they use, increasing: chart vertex i is model vertex
        ``vertices[i]``.
    patch : Patch
        The chart as a patch (chart-local vertex indices).
    param : Parameterization
        Its checked flattening.
    """

    faces: np.ndarray
    vertices: np.ndarray
    patch: Patch
    param: Parameterization

    @property
    def area_scale_ratio(self) -> float:
        s = self.param.area_scale
        return float(s.max() / s.min())


class _Graph:
    """Face adjacency of a model, with barrier edges left out of the floods."""

    def __init__(self, V, F, barrier_edges):
        self.V, self.F = V, F
        pairs, edges, angles = _trimesh.face_adjacency(V, F)
        key = edges[:, 0] * len(V) + edges[:, 1]
        bkey = barrier_edges[:, 0] * len(V) + barrier_edges[:, 1] if len(barrier_edges) else key[:0]
        cut = np.isin(key, bkey)
        self.pairs, self.edges, self.cut = pairs, edges, cut
        keep = pairs[~cut]
        n = len(F)
        order = np.argsort(np.concatenate([keep[:, 0], keep[:, 1]]), kind="stable")
        nbr = np.concatenate([keep[:, 1], keep[:, 0]])[order]
        self.start = np.searchsorted(np.concatenate([keep[:, 0], keep[:, 1]])[order], np.arange(n + 1))
        self.nbr = nbr
        nrm = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        self.area = 0.5 * np.linalg.norm(nrm, axis=1)
        self.normal = nrm / (2.0 * self.area[:, None])
        self.centre = V[F].mean(axis=1)

    def neighbours(self, f: int) -> np.ndarray:
        return self.nbr[self.start[f] : self.start[f + 1]]

    def regions(self) -> list[np.ndarray]:
        """Connected sets of faces between the barriers, by smallest face."""
        label = np.full(len(self.F), -1, dtype=np.int64)
        out = []
        for f0 in range(len(self.F)):
            if label[f0] >= 0:
                continue
            label[f0] = len(out)
            stack, members = [f0], [f0]
            while stack:
                for g in self.neighbours(stack.pop()):
                    if label[g] < 0:
                        label[g] = len(out)
                        stack.append(g)
                        members.append(g)
            out.append(np.sort(np.asarray(members, dtype=np.int64)))
        return out

    def flood(self, faces: np.ndarray, seeds, cost) -> np.ndarray:
        """Competing floods from ``seeds`` over ``faces``: the label (index of a
        seed) of every face, each face taken by the cheapest front reaching it.
        ``cost[k][f]`` (one array per seed, over all faces) orders the fronts;
        ties by face index."""
        inside = np.zeros(len(self.F), dtype=bool)
        inside[faces] = True
        label = [-1] * len(self.F)
        costs = [c.tolist() for c in cost]
        start, nbr, inside = self.start.tolist(), self.nbr.tolist(), inside.tolist()
        heap = [(0.0, int(s), k) for k, s in enumerate(seeds)]
        while heap:
            _, f, k = heapq.heappop(heap)
            if label[f] >= 0:
                continue
            label[f] = k
            ck = costs[k]
            for g in nbr[start[f] : start[f + 1]]:
                if inside[g] and label[g] < 0:
                    heapq.heappush(heap, (ck[g], g, k))
        return np.asarray(label, dtype=np.int64)[faces]


def _accept(V, F, faces: np.ndarray, bound: float) -> Chart | None:
    """The chart of ``faces``, or None if they are not a disk that flattens well."""
    verts, local = np.unique(F[faces], return_inverse=True)
    try:
        patch = Patch(V[verts], local.reshape(-1, 3))
        prm = parameterize(patch, "lscm")
    except Uniform2dError as exc:  # not a disk, bow tie, overlapping flattening
        log.debug("region of %d faces refused: %s", len(faces), exc)
        return None
    s = prm.area_scale
    if not s.max() <= bound * s.min():
        log.debug("region of %d faces: area scale ratio %.3g", len(faces), s.max() / s.min())
        return None
    return Chart(faces, verts, patch, prm)


def _split(g: _Graph, faces: np.ndarray) -> list[np.ndarray]:
    """Two connected halves of ``faces``: by normals (2-proxy shape approximation),
    or by distance where the normals hardly differ."""
    N, A = g.normal[faces], g.area[faces]
    s1 = int(np.argmin(N @ N[0]))
    s2 = int(np.argmin(N @ N[s1]))
    if N[s1] @ N[s2] > np.cos(np.radians(10.0)):
        return _split_by_distance(g, faces)
    seeds, proxies = [faces[s1], faces[s2]], [N[s1], N[s2]]
    for _ in range(SPLIT_ROUNDS):
        lab = g.flood(faces, seeds, [np.sum((g.normal - p) ** 2, axis=1) for p in proxies])
        proxies = []
        for k in range(2):
            m = (A[lab == k, None] * N[lab == k]).sum(axis=0)
            proxies.append(m / max(np.linalg.norm(m), 1e-300))
        seeds = [faces[lab == k][int(np.argmax(N[lab == k] @ proxies[k]))] for k in range(2)]
    return [faces[lab == 0], faces[lab == 1]]


def _split_by_distance(g: _Graph, faces: np.ndarray) -> list[np.ndarray]:
    C = g.centre[faces]
    a = int(np.argmax(np.linalg.norm(C - C[0], axis=1)))
    b = int(np.argmax(np.linalg.norm(C - C[a], axis=1)))
    cost = [np.linalg.norm(g.centre - g.centre[faces[k]], axis=1) for k in (a, b)]
    lab = g.flood(faces, [faces[a], faces[b]], cost)
    return [faces[lab == 0], faces[lab == 1]]


def segment(V, F, barrier_edges, *, bound: float = MAX_AREA_SCALE_RATIO) -> list[Chart]:
    """Charts covering every face of (V, F) once.

    Parameters
    ----------
    V : (N, 3) float64
    F : (M, 3) int64
        A checked model (:class:`surface.model.Model`).
    barrier_edges : (B, 2) int64
        Edges (smaller vertex first) that charts may not cross: creases, feature
        chains.
    bound : float
        Largest area-scale ratio of a chart's flattening.

    Returns
    -------
    list of Chart
        Ordered by smallest face index.

    Raises
    ------
    InvalidPatchError
        If a region of fewer than :data:`MIN_FACES` faces still cannot be
        flattened (the input is too coarse there to be cut into charts).
    """
    g = _Graph(V, F, np.asarray(barrier_edges, dtype=np.int64).reshape(-1, 2))
    todo = g.regions()
    charts: list[Chart] = []
    while todo:
        faces = todo.pop()
        chart = _accept(V, F, faces, bound)
        if chart is not None:
            charts.append(chart)
            continue
        if len(faces) < MIN_FACES:
            f = int(faces[0])
            raise InvalidPatchError(
                f"cannot cut the model into flat charts near face {f} at {g.centre[f].tolist()}: "
                f"a region of {len(faces)} faces neither flattens nor splits; the input is too "
                "coarse there (subdivide it) or not a surface",
                "charts",
            )
        todo.extend(p for p in _split(g, faces) if len(p))
    charts = _merge(g, V, F, charts, bound)
    charts.sort(key=lambda c: int(c.faces[0]))
    if sum(len(c.faces) for c in charts) != len(F):
        raise InternalError("the charts do not cover the model once (a bug: please report it)")
    return charts


def _merge(g: _Graph, V, F, charts: list[Chart], bound: float) -> list[Chart]:
    """Merge neighbouring charts whose union is a chart, longest shared seam first."""
    refused: set = set()  # pairs tried in vain (a chart known by first face and size)
    while True:
        label = np.empty(len(F), dtype=np.int64)
        for i, c in enumerate(charts):
            label[c.faces] = i
        a, b = label[g.pairs[:, 0]], label[g.pairs[:, 1]]
        across = (a != b) & ~g.cut
        if not across.any():
            return charts
        L = np.linalg.norm(V[g.edges[across, 0]] - V[g.edges[across, 1]], axis=1)
        lo, hi = np.minimum(a[across], b[across]), np.maximum(a[across], b[across])
        key, inv = np.unique(lo * len(charts) + hi, return_inverse=True)
        shared = np.bincount(inv, weights=L)
        merged = None
        for k in np.lexsort((key, -shared)):
            i, j = divmod(int(key[k]), len(charts))
            pair = tuple((int(charts[t].faces[0]), len(charts[t].faces)) for t in (i, j))
            if pair in refused:
                continue
            union = np.sort(np.concatenate([charts[i].faces, charts[j].faces]))
            merged = _accept(V, F, union, bound)
            if merged is None:
                refused.add(pair)
            else:
                charts = [c for t, c in enumerate(charts) if t not in (i, j)] + [merged]
                break
        if merged is None:
            return charts
