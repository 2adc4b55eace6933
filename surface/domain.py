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
  (:func:`surface.chord.interior_chord_error`): the boundary is refined only where it would
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
from uniform2d.errors import InsufficientPointsError, InvalidArgumentError, InvalidPolygonError
from uniform2d.geometry import signed_area

from .chord import interior_chord_error
from .patch import Patch
from .resample import plain_run, run_counts, sample_run

__all__ = [
    "Domain",
    "boundary_domain",
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
    keep=(),
    size3d=None,
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
        (:func:`surface.chord.interior_chord_error`, computed only if some plain chord exceeds
        1/128).  None: the plain even sampling everywhere.
    keep : sequence of int
        Input boundary vertices kept as corners whatever their angle (where a
        feature line meets the boundary, see :mod:`surface.features`).
    size3d : callable, optional
        A graded 3-D size (:class:`surface.size3d.Size3D`, shape only): the arc
        length is then ``∫ ds / size3d`` (3-D ``ds``), ``spacing`` is in that
        unitless measure (the scale of the size) and the chord tolerance is a
        fraction of ``spacing`` times the median size at the boundary vertices.

    Returns
    -------
    Domain

    Raises
    ------
    InsufficientPointsError
        If even the refined spacing gives crossing rings (ask for more vertices).
    """
    _check_arguments(measure, chord_tol, spacing)
    V = patch.vertices
    uv = np.asarray(uv, dtype=np.float64)
    X = V if measure == "3d" else uv
    arcs = _loop_arcs(patch, X, size3d)
    runs = _loop_runs(patch, arcs, np.radians(corner_angle), keep)
    h = float(spacing)
    # the 3-D length per unit of spacing that the chord tolerance refers to
    unit = 1.0 if size3d is None else float(np.median(size3d(V[np.concatenate(patch.boundary_loops)])))
    for attempt in range(max_refine + 1):
        # the plain even sampling of every run, and its chord heights
        plain = [_plain_loop(V, lp, runs[li], h) for li, lp in enumerate(patch.boundary_loops)]
        worst = max(p[2] for loop_runs in plain for p in loop_runs)
        tol = _tolerance(chord_tol, worst, h if size3d is None else h * unit, patch, uv)
        rings, heights = [], []
        for li, lp in enumerate(patch.boundary_loops):
            ring, hk = _ring(V, uv, lp, li, arcs[li][0], runs[li], plain[li], tol, h)
            rings.append(ring)
            heights += hk
        areas = [abs(signed_area(r["uv"])) for r in rings]
        order = [int(np.argmax(areas))] + [i for i in range(len(rings)) if i != int(np.argmax(areas))]
        try:
            poly = Polygon(rings[order[0]]["uv"], [rings[i]["uv"] for i in order[1:]])
        except InvalidPolygonError as exc:
            log.info("resampled boundary invalid at spacing %.6g (%s); refining", h, exc)
            h *= 0.7
            continue
        if attempt:
            log.warning("boundary spacing refined to %.6g to keep the rings simple", h)
        return _assemble(poly, rings, order, arcs, tol, max(heights))
    raise InsufficientPointsError(
        f"the boundary cannot be resampled at spacing {spacing:.6g} without its rings "
        "crossing in the parameter plane (tight bends or narrow gaps); ask for more "
        "vertices (a smaller size)"
    )


def _check_arguments(measure, chord_tol, spacing) -> None:
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


def _loop_arcs(patch: Patch, X, size3d=None) -> list:
    """Per boundary loop: (cumulative arc length in the measure X, divided by
    ``size3d`` at each edge's midpoint if given, loop vertices)."""
    arcs = []
    for lp in patch.boundary_loops:
        seg = np.linalg.norm(X[np.roll(lp, -1)] - X[lp], axis=1)
        if size3d is not None:
            V = patch.vertices
            seg = seg / size3d(0.5 * (V[lp] + V[np.roll(lp, -1)]))
        arcs.append((np.concatenate([[0.0], np.cumsum(seg)]), lp))
    return arcs


def _loop_runs(patch: Patch, arcs, thr, keep=()) -> list:
    """Per loop: the start (loop position) and edge count of every run between
    corners (a whole loop if it has none), the loop's arc length run twice round,
    and whether it has corners."""
    turn = np.abs(turning_angles(patch))
    runs = []
    for li, lp in enumerate(patch.boundary_loops):
        cidx = np.flatnonzero((turn[lp] > thr) | np.isin(lp, np.asarray(keep, dtype=np.int64)))
        starts = cidx if len(cidx) else np.array([0])
        n = len(lp)
        nvs = (np.roll(starts, -1) - starts) % n if len(starts) > 1 else np.array([n])
        cum = arcs[li][0]
        ext = np.concatenate([cum[:-1], cum[-1] + cum])  # the loop twice round
        runs.append((starts, nvs, ext, len(cidx) > 0))
    return runs


def _plain_loop(V, lp, runs, h) -> list:
    """Per run of a loop: (pieces, plain offsets, plain chord height)."""
    starts, nvs, ext, _ = runs
    m = run_counts(ext[starts + nvs] - ext[starts], h, len(starts) == 1)
    return [
        (int(mk),) + plain_run(V, lp, ext, int(a), int(nv), int(mk))
        for a, nv, mk in zip(starts, nvs, m)
    ]


def _ring(V, uv, lp, li, cum, runs, plain, tol, h):
    """One loop's ring: its runs sampled (resampled where the plain chord height
    exceeds ``tol``), placed on the input boundary edges.  Returns the ring (a
    dict of per-vertex arrays) and the chord heights of its runs."""
    total = cum[-1]
    starts, nvs, ext, has_corners = runs
    n = len(lp)
    s_all, v_all, is_corner, heights = [], [], [], []
    for k in range(len(starts)):
        m, u, hk = plain[k]
        vert = np.full(m, -1, dtype=np.int64)
        vert[0] = starts[k]
        if tol is not None and hk > tol:
            u, vert, hk = sample_run(V, lp, ext, int(starts[k]), int(nvs[k]), m, tol)
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
    ring = dict(uv=ring_uv, xyz=ring_xyz, a=a, b=b, t=t, s=s, corner=np.concatenate(is_corner))
    return ring, heights


def _assemble(poly, rings, order, arcs, tol, height) -> Domain:
    """The Domain: every ring's arrays in the polygon's normalised vertex order."""
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
    return Domain(
        poly, xyz, edge, tt, loop, ss, corner, tuple(forward), tuple(arcs),
        chord_tol=tol, chord_height=height,
    )
