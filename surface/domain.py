"""The planar domain: the UV boundary loops, resampled, as a :class:`uniform2d.Polygon`.

Each boundary loop of the patch, mapped to UV, becomes one ring: the loop with
the largest enclosed UV area is the outer ring, the others holes.  The ring
vertices are not the input boundary vertices but a resampling of the loop:

- **corners** are kept: boundary vertices whose *turning angle*, measured in 3-D,
  exceeds ``corner_angle`` (default :data:`CORNER_ANGLE` = 30 degrees).  The
  turning angle at a boundary vertex is ``pi`` minus the sum of the 3-D face
  angles at that vertex (the discrete geodesic curvature of the boundary): 0 on a
  straight or smoothly curving boundary, 90 degrees at the corner of a rectangle;
- the **runs** between consecutive corners (a whole loop if it has no corner)
  are resampled with evenly spaced points in 3-D arc length, ``round(L / h)``
  pieces for a run of 3-D length ``L`` (at least one piece a run, at least three
  a ring).  Spacing in 3-D length is what compensates the parameterisation's
  scale along the boundary.  Without compensation the spacing is even in UV
  arc length instead.

Every ring vertex lies on a boundary edge ``(a, b)`` of the input, at fraction
``t``: its UV and 3-D positions are the same linear interpolation of the edge's
end points, so a lifted boundary vertex lies exactly on the input boundary.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np

from uniform2d import Polygon
from uniform2d.errors import InsufficientPointsError, InvalidPolygonError

from .patch import Patch

__all__ = ["Domain", "boundary_domain", "turning_angles", "CORNER_ANGLE"]

log = logging.getLogger(__name__)

#: Default corner threshold, in degrees of 3-D turning angle.
CORNER_ANGLE = 30.0


@dataclasses.dataclass(frozen=True)
class Domain:
    """The polygon to mesh and where each of its vertices sits on the input.

    Attributes
    ----------
    polygon : uniform2d.Polygon
        Outer ring then holes; ``polygon.vertices`` is the order of all arrays below.
    xyz : (K, 3) float64
        3-D position of every polygon vertex (on an input boundary edge).
    edge : (K, 2) int64
        The input boundary edge ``(a, b)`` (vertex indices, along the loop) that
        holds the vertex.
    t : (K,) float64
        Fraction along that edge: ``xyz = (1 - t) * V[a] + t * V[b]``.
    loop : (K,) int64
        Index of the patch boundary loop (into ``patch.boundary_loops``).
    s : (K,) float64
        Arc-length position along that loop (in the resampling measure).
    corner : (K,) bool
        Whether the vertex is a kept corner.
    """

    polygon: Polygon
    xyz: np.ndarray
    edge: np.ndarray
    t: np.ndarray
    loop: np.ndarray
    s: np.ndarray
    corner: np.ndarray
    forward: tuple  # per ring: does the ring run in its loop's direction?
    _arcs: tuple = dataclasses.field(repr=False)  # per loop: (cum, loop vertices) measure

    @property
    def n_corners(self) -> int:
        return int(self.corner.sum())

    def locate_on_boundary(self, loop: int, s) -> tuple[np.ndarray, np.ndarray]:
        """Input boundary edges and fractions at arc positions ``s`` of ``loop``.

        Returns
        -------
        edge : (K, 2) int64
        t : (K,) float64
        """
        cum, verts = self._arcs[loop]
        s = np.mod(np.asarray(s, dtype=np.float64), cum[-1])
        i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(verts) - 1)
        t = np.clip((s - cum[i]) / (cum[i + 1] - cum[i]), 0.0, 1.0)
        edge = np.stack([verts[i], verts[(i + 1) % len(verts)]], axis=1)
        return edge, t

    def chord_points(self, i, j, frac, V) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Map points on polygon edges back onto the input boundary.

        A point at fraction ``frac`` of the polygon edge from vertex ``i`` to the
        next ring vertex ``j`` is sent to the same fraction of the input boundary
        arc between them (in the resampling arc-length measure).

        Parameters
        ----------
        i, j : (K,) int
            Consecutive ring vertices (indices into ``polygon.vertices``).
        frac : (K,) float64
            Fractions in [0, 1].
        V : (N, 3) float64
            Patch vertices.

        Returns
        -------
        xyz : (K, 3) float64
        edge : (K, 2) int64
        t : (K,) float64
        """
        i = np.asarray(i, dtype=np.int64)
        j = np.asarray(j, dtype=np.int64)
        frac = np.asarray(frac, dtype=np.float64)
        ring = np.searchsorted(self.polygon.ring_offsets, i, side="right") - 1
        xyz = np.zeros((len(i), 3))
        edge = np.zeros((len(i), 2), dtype=np.int64)
        t = np.zeros(len(i))
        for k in range(len(i)):
            lp = int(self.loop[i[k]])
            total = self._arcs[lp][0][-1]
            if self.forward[ring[k]]:
                gap = (self.s[j[k]] - self.s[i[k]]) % total
                s = self.s[i[k]] + frac[k] * gap
            else:
                gap = (self.s[i[k]] - self.s[j[k]]) % total
                s = self.s[i[k]] - frac[k] * gap
            e, tt = self.locate_on_boundary(lp, [s])
            edge[k], t[k] = e[0], tt[0]
            xyz[k] = (1 - t[k]) * V[e[0, 0]] + t[k] * V[e[0, 1]]
        return xyz, edge, t


def turning_angles(patch: Patch) -> np.ndarray:
    """3-D turning angle at every vertex, (N,) radians (0 at interior vertices).

    ``pi`` minus the sum of the incident face angles at a boundary vertex;
    positive where the boundary turns towards the interior (a convex corner).

    Examples
    --------
    >>> from surface.patch import Patch
    >>> p = Patch([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    >>> import numpy as np
    >>> np.degrees(turning_angles(p)).round(6).tolist()
    [90.0, 90.0, 90.0, 90.0]
    """
    from .measure import corner_angles

    V, F = patch.vertices, patch.faces
    sums = np.bincount(F.ravel(), weights=corner_angles(V, F).ravel(), minlength=len(V))
    out = np.zeros(len(V))
    for lp in patch.boundary_loops:
        out[lp] = np.pi - sums[lp]
    return out


def _run_counts(lengths, h, closed_single):
    m = np.maximum(1, np.round(np.asarray(lengths) / h)).astype(np.int64)
    if closed_single:
        m = np.maximum(m, 3)
    while m.sum() < 3:  # at least a triangle per ring
        m[int(np.argmax(np.asarray(lengths) / m))] += 1
    return m


def boundary_domain(
    patch: Patch,
    uv,
    spacing: float,
    *,
    measure: str = "3d",
    corner_angle: float = CORNER_ANGLE,
    max_refine: int = 4,
) -> Domain:
    """Resample the UV boundary loops of ``patch`` into a polygon.

    Parameters
    ----------
    patch : Patch
    uv : (N, 2) float64
        A checked parameterisation of ``patch`` (faces counter-clockwise).
    spacing : float
        Target distance between consecutive ring vertices, in the ``measure``.
    measure : {"3d", "uv"}
        Arc length used for even spacing: 3-D (compensated) or UV.
    corner_angle : float
        Turning-angle threshold in degrees above which a boundary vertex is kept.
    max_refine : int
        If the resampled rings cross (a coarse chord cutting a tight bend), the
        spacing is shrunk by 0.7 and tried again, at most this many times.

    Returns
    -------
    Domain

    Raises
    ------
    InsufficientPointsError
        If even the refined spacing gives crossing rings (ask for more vertices).
    """
    if measure not in ("3d", "uv"):
        raise ValueError("measure must be '3d' or 'uv'")
    if not spacing > 0:
        raise ValueError(f"spacing must be positive, got {spacing}")
    V = patch.vertices
    uv = np.asarray(uv, dtype=np.float64)
    turn = np.abs(turning_angles(patch))
    thr = np.radians(corner_angle)
    X = V if measure == "3d" else uv

    arcs = []
    for lp in patch.boundary_loops:
        seg = np.linalg.norm(X[np.roll(lp, -1)] - X[lp], axis=1)
        arcs.append((np.concatenate([[0.0], np.cumsum(seg)]), lp))

    h = float(spacing)
    for attempt in range(max_refine + 1):
        rings = []
        for li, lp in enumerate(patch.boundary_loops):
            cum, _ = arcs[li]
            total = cum[-1]
            cidx = np.flatnonzero(turn[lp] > thr)  # positions in the loop
            if len(cidx) == 0:
                starts = np.array([0])
            else:
                starts = cidx
            ends = np.roll(starts, -1)
            sa = cum[starts]
            lengths = np.where(
                ends > starts, cum[ends] - sa, total - sa + cum[ends]
            ) if len(starts) > 1 else np.array([total])
            m = _run_counts(lengths, h, len(starts) == 1)
            s_all, is_corner = [], []
            for k in range(len(starts)):
                j = np.arange(m[k])
                s_all.append(sa[k] + lengths[k] * j / m[k])
                c = np.zeros(m[k], dtype=bool)
                c[0] = len(cidx) > 0
                is_corner.append(c)
            s = np.concatenate(s_all)
            s = np.where(s >= total, s - total, s)
            cum_, verts = arcs[li]
            i = np.clip(np.searchsorted(cum_, s, side="right") - 1, 0, len(verts) - 1)
            t = (s - cum_[i]) / (cum_[i + 1] - cum_[i])
            t = np.where(np.concatenate(is_corner) | (s == cum_[i]), 0.0, np.clip(t, 0.0, 1.0))
            a = verts[i]
            b = verts[(i + 1) % len(verts)]
            ring_uv = (1 - t)[:, None] * uv[a] + t[:, None] * uv[b]
            ring_xyz = (1 - t)[:, None] * V[a] + t[:, None] * V[b]
            # exact end points where t is 0
            ring_uv[t == 0] = uv[a[t == 0]]
            ring_xyz[t == 0] = V[a[t == 0]]
            rings.append(
                dict(uv=ring_uv, xyz=ring_xyz, a=a, b=b, t=t, s=s, corner=np.concatenate(is_corner))
            )
        areas = [abs(_shoelace(r["uv"])) for r in rings]
        order = [int(np.argmax(areas))] + [i for i in range(len(rings)) if i != int(np.argmax(areas))]
        try:
            poly = Polygon(rings[order[0]]["uv"], [rings[i]["uv"] for i in order[1:]])
        except InvalidPolygonError as exc:
            log.info("resampled boundary invalid at spacing %.6g (%s); refining", h, exc)
            h *= 0.7
            continue
        # map our ring order to the polygon's normalised order (reversal keeps first)
        parts, forward = [], []
        for pos, li in enumerate(order):
            r = rings[li]
            ring = poly.rings[pos]
            if np.array_equal(ring, r["uv"]):
                perm = np.arange(len(ring))
            else:
                perm = np.roll(np.arange(len(ring))[::-1], 1)
                assert np.array_equal(ring, r["uv"][perm])
            parts.append((li, r, perm))
            forward.append(bool(perm[1] == 1) if len(perm) > 1 else True)
        xyz = np.concatenate([r["xyz"][p] for _, r, p in parts])
        edge = np.concatenate([np.stack([r["a"], r["b"]], axis=1)[p] for _, r, p in parts])
        tt = np.concatenate([r["t"][p] for _, r, p in parts])
        loop = np.concatenate([np.full(len(p), li) for li, _, p in parts])
        ss = np.concatenate([r["s"][p] for _, r, p in parts])
        corner = np.concatenate([r["corner"][p] for _, r, p in parts])
        for arr in (xyz, edge, tt, loop, ss, corner):
            arr.setflags(write=False)
        if attempt:
            log.warning("boundary spacing refined to %.6g to keep the rings simple", h)
        return Domain(poly, xyz, edge, tt, loop, ss, corner, tuple(forward), tuple(arcs))
    raise InsufficientPointsError(
        f"the boundary cannot be resampled at spacing {spacing:.6g} without its rings "
        "crossing in the parameter plane (tight bends or narrow gaps); ask for more "
        "vertices (a smaller size)"
    )


def _shoelace(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
