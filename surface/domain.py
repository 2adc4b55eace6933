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
  are first sampled evenly in 3-D arc length, ``round(L / h)`` pieces for a run
  of 3-D length ``L`` (at least one piece a run, at least three a ring): the
  *plain* sampling.  Spacing in 3-D length is what compensates the
  parameterisation's scale along the boundary.  Without compensation the
  spacing is even in UV arc length instead;
- a run whose plain sampling leaves the input boundary farther than the
  **chord-height tolerance** from the ring is resampled.  The *chord height* of
  a ring edge is the largest 3-D distance from it of the input boundary vertices
  it spans.  On a smooth arc of curvature ``k`` it is the sagitta ``k l^2 / 8``
  of an edge of length ``l``; on an input polyline about as coarse as ``h`` it is
  up to twice that, where an edge cuts across an input vertex or starts half-way
  along a long input edge.  The resampling is a dynamic programme over
  candidate positions (``16`` per plain spacing, plus every input vertex): ring
  edges between 0.8 and 1.25 times the plain spacing, no chord higher than the
  tolerance (or than the least height those lengths allow, if that is more),
  and, among those samplings, the least sum of ``log(l / l_plain) ** 2``.  So it
  moves ring vertices onto input vertices where the input polyline is coarse,
  shortens edges where the boundary curves, and keeps the plain sampling
  wherever that is within the tolerance (straight runs always are).  The
  default tolerance is the larger of ``h / 128`` (:data:`CHORD_TOL`) and the
  chord error the interior of the mesh has anyway
  (:func:`interior_chord_error`): the boundary is refined only where it would
  deviate from the input more than the interior does.

Every ring vertex lies on a boundary edge ``(a, b)`` of the input, at fraction
``t``: its UV and 3-D positions are the same linear interpolation of the edge's
end points, so a lifted boundary vertex lies exactly on the input boundary.
"""

from __future__ import annotations

import dataclasses
import logging
import numbers

import numpy as np

from uniform2d import Polygon
from uniform2d.polygon import _signed_area
from uniform2d.errors import InsufficientPointsError, InvalidArgumentError, InvalidPolygonError

from . import _igl
from .locate import walk
from .lift import barycentric
from .patch import Patch

__all__ = [
    "Domain",
    "boundary_domain",
    "interior_chord_error",
    "turning_angles",
    "CORNER_ANGLE",
    "CHORD_TOL",
]

log = logging.getLogger(__name__)

#: Default corner threshold, in degrees of 3-D turning angle.
CORNER_ANGLE = 30.0

#: Default chord-height tolerance, as a fraction of the boundary spacing ``h``: a
#: ring edge may leave at most ``h / 128`` between itself and the input boundary.
#: On a circular arc that is a turning of at most 1/16 rad (3.6 degrees) per edge
#: of length ``h``, about 100 edges per full turn (Gmsh's "elements per 2 pi").
CHORD_TOL = 1 / 128
#: A patch whose vertices all lie within this fraction of its bounding-box
#: diagonal from their best-fitting plane is planar: its interior chord error is 0.
PLANAR = 1e-12

#: Candidate positions per plain spacing (besides the input vertices).
_GRID = 16
#: Ring edges stay within these factors of their run's plain spacing.
_SHORTEST, _LONGEST = 0.8, 1.25


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
    chord_tol : float or None
        The chord-height tolerance the rings were sampled with (a 3-D length), or
        None for the plain even sampling.
    chord_height : float
        Largest 3-D distance of an input boundary vertex from the ring edge that
        spans it (0 when every ring edge joins neighbouring input vertices).
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
    chord_tol: float | None = None
    chord_height: float = 0.0

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


def interior_chord_error(patch: Patch, uv, h: float, area_scale=None) -> float:
    """The deviation from the input that the interior of an ``h``-mesh has anyway.

    At every interior vertex ``p`` of the input, three chords through ``p`` (along
    0, 60 and 120 degrees in the parameter plane, the directions of a hexagonal
    lattice) whose ends are a 3-D distance of about ``h / 2`` from ``p`` (UV
    half-length ``h / 2 * sqrt(s)``, ``s`` the smoothed area scale at ``p``), the
    ends placed on the input surface through the map (chords with an end outside
    the parameter domain are left out).  Returns the largest distance of such a
    ``p`` from its chords: the chord error of an interior edge of length ``h``,
    the input's own tessellation included (the ends lie on input faces, ``p`` is
    an input vertex, so a crease between input faces counts like curvature).

    Parameters
    ----------
    patch : Patch
    uv : (N, 2) float64
        The parameterisation (faces counter-clockwise).
    h : float
        Edge length of the mesh.
    area_scale : (M,) float64, optional
        Per-face UV area / 3-D area (default: from ``uv``).

    Returns
    -------
    float
        A 3-D length (0 for a planar patch).
    """
    from .sizing import vertex_scale

    V, F = patch.vertices, patch.faces
    X = V - V.mean(axis=0)
    normal = np.linalg.eigh(X.T @ X)[1][:, 0]  # of the best-fitting plane
    if np.abs(X @ normal).max() <= PLANAR * np.linalg.norm(np.ptp(V, axis=0)):
        return 0.0  # planar: chords lie in the surface (this skips 6 point locations per vertex)
    uv = np.asarray(uv, dtype=np.float64)
    if area_scale is None:
        e1, e2 = uv[F[:, 1]] - uv[F[:, 0]], uv[F[:, 2]] - uv[F[:, 0]]
        area_scale = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) / patch.face_areas
    inner = np.ones(len(V), dtype=bool)
    for lp in patch.boundary_loops:
        inner[lp] = False
    idx = np.flatnonzero(inner)
    if len(idx) == 0:
        return 0.0
    r = 0.5 * h * np.sqrt(vertex_scale(V, F, area_scale)[idx])
    ang = np.radians([0.0, 60.0, 120.0])
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    ends = uv[idx][:, None, None, :] + np.stack([d, -d])[None] * r[:, None, None, None]
    q = ends.reshape(-1, 2)
    # walk from a face at each end's own vertex; a tree search where that fails
    at = np.empty(len(V), dtype=np.int64)
    at[F.ravel()] = np.repeat(np.arange(len(F)), 3)
    F64 = np.asarray(F, dtype=np.int64)
    face = walk(q, np.repeat(at[idx], 6), uv, F64, _igl.face_neighbours(F64))
    lost = face < 0
    if lost.any():
        face[lost] = _igl.closest_faces(q[lost], uv, F)[1]
    tri = F[face]
    bary = barycentric(q, uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]], clamp=False)
    X = np.einsum("ki,kij->kj", bary, V[tri]).reshape(len(idx), 2, 3, 3)
    # chords with an end outside the parameter domain (near the boundary) are skipped
    inside = (bary.min(axis=1) >= 0).reshape(len(idx), 2, 3).all(axis=1).ravel()
    if not inside.any():
        return 0.0
    A, B = X[:, 0].reshape(-1, 3)[inside], X[:, 1].reshape(-1, 3)[inside]
    P = np.repeat(V[idx], 3, axis=0)[inside]
    return float(_segment_dist(P, A, B).max())


def _run_counts(lengths, h, closed_single):
    m = np.maximum(1, np.round(np.asarray(lengths) / h)).astype(np.int64)
    if closed_single:
        m = np.maximum(m, 3)
    while m.sum() < 3:  # at least a triangle per ring
        m[int(np.argmax(np.asarray(lengths) / m))] += 1
    return m


def _segment_dist(P, A, B):
    """Distance from points P to segments A-B (all (K, d), row-wise)."""
    AB = B - A
    L2 = np.einsum("ij,ij->i", AB, AB)
    AP = P - A
    t = np.divide(np.einsum("ij,ij->i", AP, AB), L2, out=np.zeros(len(P)), where=L2 > 0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(AP - t[:, None] * AB, axis=1)


def _run_positions(V, lp, a, nv, off, u, rv):
    """3-D points at arc offsets ``u`` of a run (``rv``: the run vertex a point is
    on, or -1), linear on the input edges like the ring vertices."""
    seg = np.clip(np.searchsorted(off, u, side="right") - 1, 0, nv - 1)
    t = (u - off[seg]) / (off[seg + 1] - off[seg])
    n = len(lp)
    P = (1 - t)[:, None] * V[lp[(a + seg) % n]] + t[:, None] * V[lp[(a + seg + 1) % n]]
    on = rv >= 0
    P[on] = V[lp[(a + rv[on]) % n]]
    return P


def _plain_run(V, lp, ext, a, nv, m):
    """The plain even sampling of a run and its chord height.

    Returns
    -------
    u : (m,) float64
        Arc offsets of the samples from the run start (the run's end excluded).
    height : float
        Largest 3-D distance of an input boundary vertex from the ring edge that
        spans it.
    """
    off = ext[a : a + nv + 1] - ext[a]
    L = float(off[-1])
    u = L * np.arange(m) / m
    if nv < 2:
        return u, 0.0
    ue = np.concatenate([u, [L]])
    rv = np.full(m + 1, -1)
    rv[0], rv[-1] = 0, nv
    P = _run_positions(V, lp, a, nv, off, ue, rv)
    inner = off[1:-1]
    g = np.searchsorted(ue, inner, side="right") - 1  # the ring edge spanning each
    d = _segment_dist(V[lp[(a + np.arange(1, nv)) % len(lp)]], P[g], P[g + 1])
    return u, float(d.max())


def _sample_run(V, lp, ext, a, nv, m, tol):
    """Sample one run of a boundary loop (see :func:`boundary_domain`).

    The candidate positions are a grid of ``m * _GRID`` even steps plus the input
    vertices; a dynamic programme over them picks the ring vertices so that every
    ring edge is between ``_SHORTEST`` and ``_LONGEST`` times ``L / m`` long (in
    arc length), no input boundary vertex is farther than ``tol`` from the ring
    edge that spans it (or than the least largest distance achievable within
    those lengths, if that is more), and, among those samplings, the sum of
    ``log(edge / (L / m)) ** 2`` is least: the plain even sampling if it meets
    the tolerance.

    Parameters
    ----------
    V : (N, 3) float64
        Patch vertices (chord heights are 3-D distances).
    lp : (n,) int64
        The loop.
    ext : (2n + 1,) float64
        Cumulative arc length of the loop in the resampling measure, run twice round.
    a, nv : int
        The run starts at loop position ``a`` and ends ``nv`` input edges later.
    m : int
        Piece count of the plain even sampling; its spacing ``L / m`` is the target.
    tol : float
        Chord-height tolerance (a 3-D length).

    Returns
    -------
    u : (k,) float64
        Arc offsets of the samples from the run start (first is 0, the end excluded).
    vert : (k,) int64
        Loop position (in ``0 .. 2n``) of the input vertex a sample sits on, or -1.
    height : float
        Largest distance of the input boundary from a ring edge of the run.
    """
    off = ext[a : a + nv + 1] - ext[a]  # offsets of the run's input vertices
    L = float(off[-1])
    href = L / m
    G = m * _GRID
    ug = L * np.arange(1, G) / G  # the run's ends are added as vertices below
    # input vertices that are the nearest vertex of some grid point (all of them
    # unless the input is finer than the grid) join the candidates
    inner = off[1:-1]
    if len(inner):
        k = np.clip(np.searchsorted(inner, ug), 1, len(inner))
        kr = np.minimum(k, len(inner) - 1)
        near = np.where(np.abs(ug - inner[k - 1]) <= np.abs(inner[kr] - ug), k - 1, kr)
        vsel = np.unique(near) + 1  # run vertex index (0 = start)
    else:
        vsel = np.zeros(0, dtype=np.int64)
    vidx = np.concatenate([[0], vsel, [nv]])
    gkeep = ~np.isin(ug, off[vidx])
    u = np.concatenate([ug[gkeep], off[vidx]])
    rv = np.concatenate([np.full(int(gkeep.sum()), -1), vidx])  # run vertex or -1
    order = np.lexsort((rv, u))
    u, rv = u[order], rv[order]
    on = rv >= 0
    C = _run_positions(V, lp, a, nv, off, u, rv)
    nc = len(u)
    # input vertices that are not candidates: their distance to the chord between the
    # candidates around them bounds how far a longer chord may be from them
    excess = np.zeros(nc)
    rest = np.setdiff1d(np.arange(1, nv), rv[on])
    if len(rest):
        g = np.searchsorted(u, off[rest], side="right") - 1
        d = _segment_dist(V[lp[(a + rest) % len(lp)]], C[g], C[g + 1])
        np.maximum.at(excess, g, d)
    lo, hi = href * _SHORTEST, href * _LONGEST
    W = max(1, int(np.max(np.searchsorted(u, u + hi, side="right") - 1 - np.arange(nc))))
    # the chords (i, i + d) of admissible length, and H[d, i]: the largest distance of
    # the input boundary between their ends from them (inf if not admissible)
    i_all = np.arange(nc)
    pi, pd = [], []
    for d in range(1, W + 1):
        ell = u[d:] - u[:-d]
        sel = np.flatnonzero((ell >= lo) & (ell <= hi))
        pi.append(i_all[sel])
        pd.append(np.full(len(sel), d))
    pi, pd = np.concatenate(pi), np.concatenate(pd)
    # the largest distance from a chord is at an input vertex (distance to a segment
    # is convex along each input edge), so the candidates on input vertices are the
    # points to check, and all of them when some input vertices are not candidates
    # (those are then covered by ``excess``)
    check = np.flatnonzero(on) if len(rest) == 0 else np.arange(nc)
    first = np.searchsorted(check, pi, side="right")
    count = np.searchsorted(check, pi + pd, side="left") - first
    hmax = np.zeros(len(pi))
    emax = excess[pi]
    for e in range(int(count.max(initial=0))):
        s = np.flatnonzero(count > e)
        k = check[first[s] + e]
        dist = _segment_dist(C[k], C[pi[s]], C[pi[s] + pd[s]])
        hmax[s] = np.maximum(hmax[s], dist)
        emax[s] = np.maximum(emax[s], excess[k])
    H = np.full((W + 1, nc), np.inf)
    H[pd, pi] = hmax + emax
    # dynamic programme over the candidates in order, in blocks shorter than ``lo``
    # (no admissible chord inside a block, so a block depends on earlier ones only)
    blocks = []
    j0 = 1
    while j0 < nc:
        rel = u[j0 + 1 : j0 + W + 1] - u[j0]  # same arithmetic as the length test
        hit = np.flatnonzero(rel >= lo)
        j1 = j0 + 1 + int(hit[0] if len(hit) else len(rel))
        J = np.arange(j0, min(j1, nc))
        d = np.arange(1, W + 1)
        I = J[:, None] - d[None, :]
        ell = u[J][:, None] - u[np.maximum(I, 0)]
        ok = (I >= 0) & (ell >= lo) & (ell <= hi)
        hgt = np.where(ok, H[d[None, :], np.maximum(I, 0)], np.inf)
        blocks.append((J, np.maximum(I, 0), ell, ok, hgt))
        j0 = J[-1] + 1
    # first pass: the smallest achievable largest chord height (within tol unless the
    # length bounds forbid it somewhere) ...
    bestH = np.full(nc, np.inf)
    bestH[0] = 0.0
    for J, I, ell, ok, hgt in blocks:
        bestH[J] = np.min(np.maximum(bestH[I], hgt), axis=1)
    bound = max(tol, bestH[-1])
    # ... second pass: among the samplings within that height, the most even one:
    # least sum of log^2(chord length / href), zero for the plain even sampling
    bestC = np.full(nc, np.inf)
    prev = np.full(nc, -1, dtype=np.int64)
    bestC[0] = 0.0
    for J, I, ell, ok, hgt in blocks:
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(ok & (hgt <= bound), bestC[I] + np.log(ell / href) ** 2, np.inf)
        b = np.argmin(c, axis=1)
        bestC[J] = c[np.arange(len(J)), b]
        prev[J] = np.where(np.isfinite(bestC[J]), I[np.arange(len(J)), b], -1)
    path = [nc - 1]
    while path[-1] > 0:
        path.append(int(prev[path[-1]]))
    path = np.array(path[::-1])
    height = float(np.max(H[np.diff(path), path[:-1]]))
    path = path[:-1]  # the run's end is the next run's start
    return u[path], np.where(rv[path] >= 0, a + rv[path], -1), height


def _tolerance(chord_tol, worst, h, patch, uv):
    """The chord-height tolerance (a 3-D length, or None) at spacing ``h``, given the
    largest chord height ``worst`` of the plain even sampling (see :func:`boundary_domain`)."""
    if chord_tol is None:
        return None
    if chord_tol != "auto":
        return float(chord_tol) * h
    tol = CHORD_TOL * h
    if worst > tol:  # only then does the interior's own error matter
        tol = max(tol, interior_chord_error(patch, uv, h))
    return tol


def boundary_domain(
    patch: Patch,
    uv,
    spacing: float,
    *,
    measure: str = "3d",
    corner_angle: float = CORNER_ANGLE,
    max_refine: int = 4,
    chord_tol: float | str | None = "auto",
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
    chord_tol : "auto", float or None
        Chord-height tolerance of the rings, as a fraction of ``spacing``: no input
        boundary vertex may be farther (in 3-D) from the ring edge that spans it.
        Runs whose plain even sampling exceeds it are resampled (see the module
        notes).  ``"auto"`` (default): the larger of :data:`CHORD_TOL` (1/128) and
        the chord error the interior of the mesh has anyway
        (:func:`interior_chord_error`, computed only if some plain chord exceeds
        1/128).  None: the plain even sampling everywhere.

    Returns
    -------
    Domain

    Raises
    ------
    InsufficientPointsError
        If even the refined spacing gives crossing rings (ask for more vertices).
    """
    if measure not in ("3d", "uv"):
        raise InvalidArgumentError("measure must be '3d' or 'uv'")
    if not (chord_tol is None or (isinstance(chord_tol, str) and chord_tol == "auto") or (
        isinstance(chord_tol, numbers.Real) and not isinstance(chord_tol, bool) and chord_tol >= 0
    )):
        raise InvalidArgumentError(
            f"chord_tol must be 'auto', a fraction >= 0 or None, got {chord_tol!r}"
        )
    if not spacing > 0:
        raise InvalidArgumentError(f"spacing must be positive, got {spacing}")
    V = patch.vertices
    uv = np.asarray(uv, dtype=np.float64)
    turn = np.abs(turning_angles(patch))
    thr = np.radians(corner_angle)
    X = V if measure == "3d" else uv

    arcs = []
    for lp in patch.boundary_loops:
        seg = np.linalg.norm(X[np.roll(lp, -1)] - X[lp], axis=1)
        arcs.append((np.concatenate([[0.0], np.cumsum(seg)]), lp))

    # runs: per loop, the start (loop position) and edge count of every run between
    # corners (a whole loop if it has none)
    runs = []
    for li, lp in enumerate(patch.boundary_loops):
        cidx = np.flatnonzero(turn[lp] > thr)  # positions in the loop
        starts = cidx if len(cidx) else np.array([0])
        n = len(lp)
        nvs = (np.roll(starts, -1) - starts) % n if len(starts) > 1 else np.array([n])
        cum = arcs[li][0]
        ext = np.concatenate([cum[:-1], cum[-1] + cum])  # the loop twice round
        runs.append((starts, nvs, ext, len(cidx) > 0))

    h = float(spacing)
    for attempt in range(max_refine + 1):
        # the plain even sampling of every run, and its chord heights
        plain = []  # per loop, per run: (pieces, offsets, chord height)
        for li, lp in enumerate(patch.boundary_loops):
            starts, nvs, ext, _ = runs[li]
            m = _run_counts(ext[starts + nvs] - ext[starts], h, len(starts) == 1)
            plain.append([
                (int(mk),) + _plain_run(V, lp, ext, int(a), int(nv), int(mk))
                for a, nv, mk in zip(starts, nvs, m)
            ])
        worst = max(p[2] for loop_runs in plain for p in loop_runs)
        tol = _tolerance(chord_tol, worst, h, patch, uv)
        rings, heights = [], []
        for li, lp in enumerate(patch.boundary_loops):
            cum, _ = arcs[li]
            total = cum[-1]
            starts, nvs, ext, has_corners = runs[li]
            n = len(lp)
            s_all, v_all, is_corner = [], [], []
            for k in range(len(starts)):
                m, u, hk = plain[li][k]
                vert = np.full(m, -1, dtype=np.int64)
                vert[0] = starts[k]
                if tol is not None and hk > tol:
                    u, vert, hk = _sample_run(V, lp, ext, int(starts[k]), int(nvs[k]), m, tol)
                    if hk > tol:
                        log.info(
                            "loop %d: chord height %.3g h over the tolerance %.3g h, the "
                            "least within the edge-length bounds on a run of %d pieces",
                            li, hk / h, tol / h, len(u),
                        )
                heights.append(hk)
                s_all.append(ext[starts[k]] + u)
                v_all.append(vert)
                c = np.zeros(len(u), dtype=bool)
                c[0] = has_corners
                is_corner.append(c)
            s = np.concatenate(s_all)
            s = np.where(s >= total, s - total, s)
            vert = np.concatenate(v_all)
            at_v = vert >= 0
            s[at_v] = cum[vert[at_v] % n]  # exactly on the input vertex
            i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, n - 1)
            i[at_v] = vert[at_v] % n
            t = (s - cum[i]) / (cum[i + 1] - cum[i])
            t = np.where(at_v | (s == cum[i]), 0.0, np.clip(t, 0.0, 1.0))
            a = lp[i]
            b = lp[(i + 1) % n]
            ring_uv = (1 - t)[:, None] * uv[a] + t[:, None] * uv[b]
            ring_xyz = (1 - t)[:, None] * V[a] + t[:, None] * V[b]
            # exact end points where t is 0
            ring_uv[t == 0] = uv[a[t == 0]]
            ring_xyz[t == 0] = V[a[t == 0]]
            rings.append(
                dict(uv=ring_uv, xyz=ring_xyz, a=a, b=b, t=t, s=s, corner=np.concatenate(is_corner))
            )
        areas = [abs(_signed_area(r["uv"])) for r in rings]
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
        return Domain(
            poly, xyz, edge, tt, loop, ss, corner, tuple(forward), tuple(arcs),
            chord_tol=tol, chord_height=max(heights),
        )
    raise InsufficientPointsError(
        f"the boundary cannot be resampled at spacing {spacing:.6g} without its rings "
        "crossing in the parameter plane (tight bends or narrow gaps); ask for more "
        "vertices (a smaller size)"
    )
