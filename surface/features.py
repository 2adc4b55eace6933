"""Feature lines: creases and given edge chains that the remeshed patch keeps.

A *feature edge* is an interior edge of the input whose two faces' normals differ
by more than ``feature_angle`` (a crease: a ridge, a valley, a fold), or an edge of
a chain the caller gives.  The feature edges form *chains* of input vertices,
split at *nodes*: vertices where other than two feature edges meet, boundary
vertices, fixed vertices, and vertices where the chain turns more than the
corner angle in 3-D.  Each chain is sampled evenly in arc length (like a
boundary run, ``round(L / h)`` pieces, at least one; a closed chain at least
three), every sample on an input edge of the chain, and given to the planar
mesher as an interior segment in the parameter plane; fixed vertices become its
fixed points.  The mesher keeps every segment as a chain of mesh edges, so after
lifting each mesh point on a segment is sent to the same fraction of the input
feature arc between the segment's two samples: it lies exactly on the input's
feature edges, and no output triangle straddles a crease.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np

from uniform2d import Polygon, libm
from uniform2d.errors import (
    InsufficientPointsError, InternalError, InvalidArgumentError, InvalidConstraintError)

from ._trimesh import dihedral_edges
from .graph import walk_chains
from .patch import Patch

__all__ = ["FeatureLines", "find_chains", "sample_chains"]

log = logging.getLogger(__name__)


def _user_edges(patch: Patch, chains) -> np.ndarray:
    """The edges of the caller's vertex chains, checked to be interior input edges."""
    out = []
    if not len(chains):
        return np.empty((0, 2), np.int64)
    known = {tuple(e) for e in patch.edges.tolist()}
    boundary = {tuple(sorted((int(a), int(b)))) for lp in patch.boundary_loops
                for a, b in zip(lp, np.roll(lp, -1))}  # fmt: skip
    for k, chain in enumerate(chains):
        c = np.asarray(chain)
        if c.ndim != 1 or len(c) < 2 or not np.issubdtype(c.dtype, np.integer):
            raise InvalidArgumentError(
                f"feature chain {k} must be a sequence of at least 2 vertex indices"
            )
        for a, b in zip(c[:-1].tolist(), c[1:].tolist()):
            e = (min(a, b), max(a, b))
            if e not in known:
                raise InvalidArgumentError(
                    f"feature chain {k}: vertices {a} and {b} are not joined by an edge of "
                    "the patch; give chains of consecutive mesh vertices"
                )
            if e in boundary:
                raise InvalidArgumentError(
                    f"feature chain {k}: edge ({a}, {b}) is on the patch boundary, which "
                    "is kept anyway; give interior edges only"
                )
            out.append(e)
    return np.array(out, dtype=np.int64).reshape(-1, 2)


def _check_fixed(patch: Patch, fixed) -> np.ndarray:
    f = np.unique(np.asarray(fixed, dtype=np.int64).ravel()) if len(fixed) else np.empty(0, np.int64)
    if len(f) and (f.min() < 0 or f.max() >= patch.n_vertices):
        raise InvalidArgumentError(
            f"fixed vertex indices must be in [0, {patch.n_vertices}), got {int(f.min())}..{int(f.max())}"
        )
    return f


def _turns(V, a, v, b, thr) -> bool:
    u, w = V[v] - V[a], V[b] - V[v]
    # sums of products, not ``@``/``norm`` (BLAS, whose kernel is per CPU), and
    # the C library's acos: the same turns on every CPU
    c = float(np.sum(u * w)) / (np.sqrt(np.sum(u * u)) * np.sqrt(np.sum(w * w)))
    return libm.arccos(np.clip(c, -1.0, 1.0)) > thr


def find_chains(patch: Patch, feature_angle=None, chains=(), fixed=(), corner_angle=30.0):
    """Feature chains (lists of input vertices, a closed one ends at its start)
    and the fixed vertices, from the crease threshold and the caller's chains."""
    E = [_user_edges(patch, chains)]
    if feature_angle is not None:
        if not (0.0 < float(feature_angle) < 180.0):
            raise InvalidArgumentError(f"feature_angle must be in (0, 180) degrees, got {feature_angle!r}")
        e, ang = dihedral_edges(patch.vertices, patch.faces)
        E.append(e[ang > np.radians(float(feature_angle))])
    E = np.unique(np.concatenate(E), axis=0)
    f = _check_fixed(patch, fixed)
    adj: dict[int, list[int]] = {}
    for a, b in E.tolist():
        adj.setdefault(a, []).append(b)
        adj.setdefault(b, []).append(a)
    on_boundary = set(np.concatenate(patch.boundary_loops).tolist())
    nodes = {v for v, w in adj.items() if len(w) != 2 or v in on_boundary}
    nodes |= set(f.tolist()) & set(adj)
    V, thr = patch.vertices, np.radians(corner_angle)
    return walk_chains(adj, nodes, lambda a, v, b: _turns(V, a, v, b, thr)), f


@dataclasses.dataclass(frozen=True)
class FeatureLines:
    """Sampled feature chains: where each sample and segment point sits on the input.

    Attributes
    ----------
    segments : list of (k_i, 2) float64
        The samples of each chain in the parameter plane (the planar segments).
    xyz : list of (k_i, 3) float64
        The same samples on the input.
    pieces : dict
        ``(uv start, uv end)`` of each piece (as tuples) -> (chain, s0, s1), the
        arc positions of its ends.
    anchors : dict
        uv (as a tuple) -> xyz of every sample and fixed vertex.
    """

    chains: list
    cum: list
    segments: list
    xyz: list
    pieces: dict
    anchors: dict

    def point_on(self, V, chain: int, s: float) -> np.ndarray:
        """The input point at arc position ``s`` of ``chain``."""
        cum, c = self.cum[chain], self.chains[chain]
        i = int(np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(c) - 2))
        t = float(np.clip((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0, 1.0))
        return (1 - t) * V[c[i]] + t * V[c[i + 1]]


def _sample(V, X, uv, chain, h):
    c = np.asarray(chain)
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(X[c[1:]] - X[c[:-1]], axis=1))])
    closed = c[0] == c[-1]
    m = max(3 if closed else 1, int(round(cum[-1] / h)))
    s = cum[-1] * np.arange(m + 1) / m
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(c) - 2)
    t = np.clip((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0, 1.0)
    t[0], i[-1], t[-1] = 0.0, len(c) - 2, 1.0
    a, b = c[i], c[i + 1]
    P = (1 - t)[:, None] * uv[a] + t[:, None] * uv[b]
    Q = (1 - t)[:, None] * V[a] + t[:, None] * V[b]
    P[0], P[-1], Q[0], Q[-1] = uv[c[0]], uv[c[-1]], V[c[0]], V[c[-1]]  # exact ends
    return cum, s, P, Q


def sample_chains(patch: Patch, uv, chains, h: float, measure: str = "3d") -> FeatureLines:
    """Sample every chain evenly (3-D or UV arc length) at spacing ``h``."""
    V = patch.vertices
    X = V if measure == "3d" else uv
    cums, segs, xyzs, pieces, anchors = [], [], [], {}, {}
    for k, chain in enumerate(chains):
        cum, s, P, Q = _sample(V, X, uv, chain, h)
        cums.append(cum)
        segs.append(P)
        xyzs.append(Q)
        for j in range(len(s) - 1):
            pieces[(tuple(P[j]), tuple(P[j + 1]))] = (k, s[j], s[j + 1])
        anchors.update(zip(map(tuple, P), Q))
    return FeatureLines([np.asarray(c) for c in chains], cums, segs, xyzs, pieces, anchors)


def constrain(patch: Patch, uv, domain, chains, fixed, h: float, measure: str, max_refine=4):
    """The domain with the feature chains as segments and the interior fixed
    vertices as fixed points: ``(domain, FeatureLines)``.

    Where the samples' chords cross in the parameter plane (a tight bend near
    another line), the chains are sampled again at 0.7 times the spacing, at
    most ``max_refine`` times.
    """
    poly0 = domain.polygon
    on_boundary = set(np.concatenate(patch.boundary_loops).tolist())
    inner = [int(v) for v in fixed if int(v) not in on_boundary]
    pts = uv[inner] if inner else np.empty((0, 2))
    for attempt in range(max_refine + 1):
        lines = sample_chains(patch, uv, chains, h, measure)
        try:
            poly = Polygon(poly0.outer, poly0.holes, segments=lines.segments, points=pts)
        except InvalidConstraintError as exc:
            log.info("feature lines invalid at spacing %.6g (%s); refining", h, exc)
            h *= 0.7
            continue
        if poly.n_ring_vertices != poly0.n_ring_vertices:
            raise InternalError("a feature line met the boundary away from a ring vertex (a bug in "
                                "uniform2d: please report it with the patch)")
        lines.anchors.update(zip(map(tuple, pts), patch.vertices[inner]))
        if attempt:
            log.warning("feature-line spacing refined to %.6g to keep the lines apart", h)
        return dataclasses.replace(domain, polygon=poly), lines
    raise InsufficientPointsError(
        "the feature lines cannot be sampled without crossing in the parameter plane "
        "(tight bends or lines very close together); ask for more vertices (a smaller size)"
    )


def lift_points(lines: FeatureLines, polygon, pts, V, candidates):
    """3-D positions of the polygon's constraint vertices and of the ``candidates``
    (mesh point indices) that lie on a segment piece: ``{index: xyz}``.

    A point on a piece goes to the same fraction of the input feature arc between
    the piece's two samples, so it lies on the input's feature edges.
    """
    out = {}
    for k in range(polygon.n_ring_vertices, len(polygon.vertices)):
        out[k] = lines.anchors[tuple(polygon.vertices[k])]
    ext = float(np.ptp(polygon.vertices, axis=0).max())
    cand = np.asarray(candidates, dtype=np.int64)
    for i, j in polygon.segment_edges:
        a, b = polygon.vertices[i], polygon.vertices[j]
        key = lines.pieces.get((tuple(a), tuple(b)))
        if key is None:
            key = lines.pieces.get((tuple(b), tuple(a)))
            a, b = b, a
        if key is None:
            continue
        ab = b - a
        q = pts[cand]
        f = np.clip(((q - a) @ ab) / (ab @ ab), 0.0, 1.0)
        d = np.linalg.norm(a + f[:, None] * ab - q, axis=1)
        for k, fk in zip(cand[d <= 1e-9 * ext], f[d <= 1e-9 * ext]):
            chain, s0, s1 = key
            out[int(k)] = lines.point_on(V, chain, s0 + fk * (s1 - s0))
    return out
