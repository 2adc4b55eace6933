"""A polygon's boundary rings resampled at the mesh spacing, within a tolerance of the outline.

The paper keeps every polygon vertex, so a dense outline (a digitised coastline,
a CAD curve exported as thousands of short chords) has its shortest mesh edge set
by its own digitising step.  :func:`resample_polygon` replaces each ring by points
about one spacing ``h`` apart within ``tol * h`` of the outline, as the surface
layer does for its domains (the same dynamic programme, :mod:`.chord_sampling`):

- **kept vertices** are the input vertices that stay: *corners*, turning by more
  than ``corner_angle`` both between their two edges and between the chords to
  the outline half a spacing before and after (at most one in an arc of ``h``, the
  sharpest), and ring vertices a segment or fixed point touches (segments'
  interior vertices and fixed points inside stay as they are);
- a run between kept vertices that is a single input edge is left whole (the
  mesher splits it at the spacing it chooses, its points counting in n too);
- the other **runs** (a whole ring if it has none) are sampled evenly in a
  *straightened* arc length (that of the run simplified by Douglas-Peucker at
  ``tol * h``), ``round(L / h)`` pieces; where that leaves the outline farther
  than ``tol * h`` from a ring edge, the dynamic programme moves the samples
  (edges 0.8 to 1.25 of the run's spacing, then down to 0.5 and 0.25 of it),
  and a run it still cannot fit is split at its farthest input vertex;
- every sample lies on the outline, and every input vertex within the tolerance
  of the ring edge that spans it: the Hausdorff distance between rings and
  outline (both ways) is at most :attr:`Resampled.deviation`;
- with ``widen`` (the default), :mod:`.outline_band` then drops samples where a
  ring edge is much shorter than h and the tolerance allows, and, at the spacing
  found, slides samples along the outline to even out ring edges
  (:mod:`.ring_slide`), moves samples off the outline within the tolerance
  (measured both ways) to widen features narrower than h (piers, notches, necks),
  then moves those with a ring edge under 0.75 h, within the tolerance, to
  lengthen it, and those with one under 0.8 h anywhere in the band between
  their neighbours (:mod:`.ring_pull`); with ``corners="merge"``, a corner and
  a sample under 0.6 h away become one point on the outline (:mod:`.corner_merge`);
- a polygon whose constraint edges are all at least :data:`COARSE_EDGE` of the
  spacing is returned as given; a *coarse* one (:func:`is_coarse`) is resampled,
  by :func:`uniform2d.uniform_mesh` at :data:`COARSE_SPACING` times h;
- if the rings cross (two parts of the outline closer than the tolerance), the
  crossing edges are split at the input vertex nearest their middle (a boundary
  point, counted in n) and sampled again, a few rounds, else the polygon is kept
  as given: the polygon returned is always valid.

Lengths are measured in the coordinates as given: a longitude/latitude outline
is resampled in degrees (project it first, see ``docs/outlines.md``).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import numbers

import numpy as np
import shapely

from .chord_sampling import plain_run, run_counts, sample_run, straightened_lengths
from .errors import InvalidArgumentError, InvalidPolygonError
from .geometry import size_for_count, vertex_count
from .segment_distance import point_segment_distance
from .outline_band import REACH, merge_short_edges, narrowest, widen_rings
from .polygon import Polygon
from .ring_corners import ring_corners
from .ring_crossings import crossing_edges
from .corner_merge import CORNERS, corner_policy, merge_corners
from .ring_pull import pull_apart
from .ring_slide import crowded, even_out, slide_samples
from .short_edges import SEVERE, SHORT_EDGE, short_edge_warning

__all__ = ["COARSE_EDGE", "COARSE_SPACING", "CORNERS", "CORNER_ANGLE", "SEVERE", "SHORT_EDGE", "Resampled",
           "is_coarse", "resample_polygon", "resample_weighted", "short_edge_warning"]

log = logging.getLogger(__name__)

#: Default corner threshold, in degrees of turning angle (the surface layer's).
CORNER_ANGLE = 30.0
#: A polygon with no constraint edge shorter than this fraction of the spacing is
#: not resampled (its shortest edges cost the mesh an edge ratio below about 2).
COARSE_EDGE = 0.6
#: The boundary spacing (a multiple of h) a coarse outline (:func:`is_coarse`) is
#: resampled at by :func:`uniform2d.uniform_mesh` (one of the optimiser's own
#: boundary spacings, ``optimize.schedule.SPACINGS``).
COARSE_SPACING = 1.05
#: The edge-length bounds (fractions of a run's spacing) tried in turn where the
#: tolerance is not met.
_BOUNDS = ((0.8, 1.25), (0.5, 1.25), (0.25, 1.25))
#: Candidate positions per spacing in the dynamic programme (the surface layer's 16
#: costs 4 times the time for little: planar tolerances are fractions of a spacing).
_GRID = 8
#: Rounds of splitting the sampled edges that cross, before the polygon is kept as given.
_ROUNDS = 8
#: Spacing iterations (the boundary count changes the spacing a mesh of n points has).
_ITERATIONS = 8


@dataclasses.dataclass(frozen=True)
class Resampled:
    """A polygon with resampled rings.

    Attributes
    ----------
    polygon : Polygon
        The resampled polygon (segments, fixed points and region labels as given).
    kept : (K,) bool
        For every vertex of ``polygon``: an input vertex kept as such (V); the
        others are boundary points placed by the resampling (they count in n).
    spacing : float
        The spacing h the rings were sampled at.
    tolerance : float
        The tolerance asked for, a fraction of ``spacing``.
    deviation : float
        A bound on the Hausdorff distance between the rings and the input
        outline (a length): the largest, over the ring edges, of the distance
        between an edge and the input it spans, both ways.
    n_corners : int
        Kept corners.
    resampled : bool
        False if the polygon is as given: no constraint edge is shorter than
        :data:`COARSE_EDGE` of the spacing (it needs no resampling), or no
        resampling gave valid rings.
    boundary_spacing : float
        The rings were sampled at this multiple of ``spacing``.
    """

    polygon: Polygon
    kept: np.ndarray
    spacing: float
    tolerance: float
    deviation: float
    n_corners: int
    resampled: bool = True
    boundary_spacing: float = 1.0

    @property
    def n_kept(self) -> int:
        return int(self.kept.sum())

    @property
    def n_boundary(self) -> int:
        """Boundary points placed by the resampling (they count in n)."""
        return int(len(self.kept) - self.kept.sum())

    def info(self) -> dict:
        """A JSON-able summary, for ``Mesh.info["resample"]``."""
        return {
            "tolerance": self.tolerance,
            "spacing": self.spacing,
            "deviation": self.deviation,
            "deviation_fraction": self.deviation / self.spacing,
            "kept_vertices": self.n_kept,
            "corners": self.n_corners,
            "boundary_points": self.n_boundary,
            "resampled": self.resampled,
            "boundary_spacing": self.boundary_spacing,
        }


def resample_polygon(polygon: Polygon, n: int | None = None, *, size: float | None = None,
                     tolerance: float, corner_angle: float = CORNER_ANGLE,
                     boundary_spacing: float = 1.0, widen: bool = True,
                     corners: str = "keep") -> tuple[Resampled, int]:
    """Resample ``polygon``'s rings for a mesh of ``n`` Steiner points (or edge ``size``).

    The spacing h is that of an equilateral mesh of the resampled polygon with
    its kept vertices plus n points (:func:`uniform2d.geometry.size_for_count`),
    found by iterating (the resampled perimeter depends on h); with ``size``, h
    is ``size`` and n follows as in :func:`uniform2d.steiner_count_for_size`.
    The rings are sampled at ``boundary_spacing`` times h (n stays exact: the
    boundary points count in it).  With ``widen`` (the default), features
    narrower than the spacing are then widened within the tolerance
    (:mod:`uniform2d.outline_band`) and ring edges evened out
    (:mod:`uniform2d.ring_slide`): the boundary points placed by the
    resampling then lie within the tolerance of the outline, not on it.
    ``corners`` (with ``widen``): ``"keep"`` every corner, or ``"merge"`` a
    corner with a boundary point less than 0.6 h away into one point on the
    outline between them, where the tolerance holds
    (:func:`uniform2d.corner_merge.merge_corners`); segment ends and fixed
    points never merge.

    Returns
    -------
    Resampled
    int
        The Steiner points left for the mesher: n minus the resampled boundary points.

    Examples
    --------
    >>> import numpy as np
    >>> from uniform2d import Polygon
    >>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> disk = Polygon(np.c_[np.cos(t), np.sin(t)])
    >>> r, n_left = resample_polygon(disk, 300, tolerance=0.05)
    >>> r.n_kept, r.n_boundary + n_left, r.deviation <= 0.05 * r.spacing
    (0, 300, True)
    """
    _check(tolerance, corner_angle)
    drop = corner_policy(corners)
    if isinstance(boundary_spacing, bool) or not (
            isinstance(boundary_spacing, numbers.Real) and 0.5 <= boundary_spacing <= 2):
        raise InvalidArgumentError(
            f"boundary_spacing must be a multiple of the spacing in [0.5, 2], got {boundary_spacing!r}")
    c = float(boundary_spacing)
    if (n is None) == (size is None):
        raise InvalidArgumentError("give exactly one of n (number of Steiner points) and size")
    if size is None and (isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1):
        raise InvalidArgumentError(f"n must be a positive integer, got {n!r}")
    if size is not None and not (isinstance(size, numbers.Real) and math.isfinite(size) and size > 0):
        raise InvalidArgumentError(f"size must be a positive finite number, got {size!r}")
    extra = len(polygon.vertices) - polygon.n_ring_vertices
    if size is not None:
        r = _resample_at(polygon, float(size), tolerance, corner_angle, c=c, widen=widen, move=widen,
                         drop_corners=drop)
        q = r.polygon
        N = vertex_count(q.area, q.perimeter, float(size), q.n_holes)
        return r, max(0, round(N) - r.n_kept) - r.n_boundary
    h = size_for_count(polygon.area, polygon.perimeter, n + extra, polygon.n_holes)
    # a first guess nearer the fixed point: the perimeter without the wiggles the
    # tolerance removes (a dense outline's own perimeter can be many times longer)
    simple = shapely.simplify(polygon.to_shapely(), tolerance * h, preserve_topology=False)
    if simple.geom_type == "Polygon" and not simple.is_empty:
        h = max(h, size_for_count(polygon.area, simple.length, n + extra, polygon.n_holes))
    forced = [np.zeros(len(ring), dtype=bool) for ring in polygon.rings]
    for _ in range(_ITERATIONS):
        caches = [{} for _ in polygon.rings]  # runs sampled at this spacing
        r = _resample_at(polygon, h, tolerance, corner_angle, forced, c, widen, caches=caches,
                         drop_corners=drop)
        q = r.polygon
        h_next = size_for_count(q.area, q.perimeter, n + r.n_kept, q.n_holes)
        if not math.isfinite(h_next) or abs(h_next - h) <= 2e-3 * h:
            break
        h = h_next
    if widen and r.resampled:  # narrow features widened once, at the spacing found
        r = _resample_at(polygon, r.spacing, tolerance, corner_angle, forced, c, widen, True, caches,
                         drop_corners=drop)
    return r, n - r.n_boundary


def is_coarse(polygon: Polygon, spacing: float) -> bool:
    """True if ``polygon``'s shortest constraint edge is between :data:`SHORT_EDGE`
    and :data:`COARSE_EDGE` of ``spacing``: not dense, but too short for a mesh
    that keeps it to have an edge ratio near 2.

    Examples
    --------
    >>> from uniform2d import Polygon
    >>> square = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> is_coarse(square, 2.0), is_coarse(square, 1.0)
    (True, False)
    """
    shortest = _shortest_edge(polygon)
    return SHORT_EDGE * spacing <= shortest < COARSE_EDGE * spacing


def _shortest_edge(polygon: Polygon) -> float:
    V, E = polygon.vertices, polygon.constraint_edges
    return float(np.hypot(*(V[E[:, 1]] - V[E[:, 0]]).T).min())


def _check(tolerance, corner_angle) -> None:
    ok = isinstance(tolerance, numbers.Real) and not isinstance(tolerance, bool)
    if not (ok and math.isfinite(tolerance) and tolerance > 0):
        raise InvalidArgumentError(
            f"resample must be a tolerance > 0 (a fraction of the mesh spacing, e.g. 0.05), "
            f"got {tolerance!r}")
    if isinstance(corner_angle, bool) or not (
            isinstance(corner_angle, numbers.Real) and 0 <= corner_angle <= 180):
        raise InvalidArgumentError(f"corner_angle must be in [0, 180] degrees, got {corner_angle!r}")


def _must_keep(polygon: Polygon) -> np.ndarray:
    """(ring vertices,) bool: ring vertices a segment or a fixed point touches."""
    keep = np.zeros(polygon.n_ring_vertices, dtype=bool)
    idx = np.concatenate([polygon.segment_edges.ravel(), polygon.fixed])
    idx = idx[idx < polygon.n_ring_vertices]
    keep[idx] = True
    return keep


def _as_given(polygon: Polygon, h: float, tol: float) -> Resampled:
    return Resampled(polygon, np.ones(len(polygon.vertices), dtype=bool), h, float(tol), 0.0, 0,
                     resampled=False)


def resample_weighted(polygon: Polygon, spacing: float, tolerance: float, corner_angle: float,
                      weights) -> Resampled:
    """The rings sampled at ``spacing`` in the measure ``weights[r][e]`` x the length of
    edge e of ring r (weights <= 1: pieces ``∫ w ds / spacing``), every input vertex
    within ``tolerance * spacing`` of the rings, never widened and never as given
    (:mod:`uniform2d.graded_outline` samples a size field's local spacing so)."""
    _check(tolerance, corner_angle)
    return _resample_at(polygon, spacing, tolerance, corner_angle, widen=False, weights=weights)


def _resample_at(polygon: Polygon, h: float, tol: float, corner_angle: float,
                 forced=None, c: float = 1.0, widen: bool = True, move: bool = False,
                 caches=None, weights=None, drop_corners=False) -> Resampled:
    """The rings resampled at spacing ``c * h`` within ``tol * h``, made valid (see
    the module notes); the polygon as given if no constraint edge is shorter than
    ``COARSE_EDGE * h``.  ``forced`` (per ring, (k,) bool, updated): input vertices
    where runs must be split (found by an earlier call at another spacing)."""
    if weights is None and _shortest_edge(polygon) >= COARSE_EDGE * h:
        return _as_given(polygon, h, tol)
    h0, tol0 = h, tol  # reported: the mesh spacing and the tolerance asked, a fraction of it
    h, tol = c * h, tol / c  # below: the sampling spacing, the tolerance a fraction of it
    keep = _must_keep(polygon)
    off = polygon.ring_offsets
    thr = math.radians(corner_angle)
    corners = [ring_corners(ring, h, thr) for ring in polygon.rings]
    forced = [np.zeros(len(ring), dtype=bool) for ring in polygon.rings] if forced is None else forced
    caches = [{} for _ in polygon.rings] if caches is None else caches
    for _ in range(_ROUNDS):
        rings = [_Ring(ring, keep[off[r]:off[r + 1]], corners[r], forced[r], h, tol, caches[r], widen,
                       None if weights is None else weights[r], widen and drop_corners, move)
                 for r, ring in enumerate(polygon.rings)]
        samples = [g.sample(h, tol) for g in rings]
        try:
            poly = polygon.with_rings([s[0] for s in samples])
        except InvalidPolygonError as exc:
            log.info("resampled rings invalid at spacing %.6g (%s); splitting there", h, exc)
            crossing = crossing_edges(polygon, samples)
            added = 0
            for r, edges in crossing.items():
                at = rings[r].split_points(samples[r][3], edges)
                added += int((~forced[r][at]).sum())
                forced[r][at] = True
            if not added:
                break
            continue
        kept = np.concatenate([np.concatenate([s[1] for s in samples]),
                               np.ones(len(poly.vertices) - poly.n_ring_vertices, dtype=bool)])
        poly, dev = _widened(polygon, poly, rings, samples, h, tol * h) if move else (
            poly, max(float(s[2].max()) for s in samples))
        return Resampled(poly, kept, h0, float(tol0), float(dev), sum(g.n_corners for g in rings),
                         boundary_spacing=c)
    log.warning("the outline could not be resampled at spacing %.4g without its rings crossing; "
                "every input vertex kept", h)
    return _as_given(polygon, h0, tol0)


def _widened(polygon: Polygon, poly: Polygon, rings, samples, h: float, limit: float):
    """``poly`` widened (:func:`uniform2d.outline_band.widen_rings`) if its rings
    do not cross, and the deviation."""
    inputs = [(g.ring, g.ext) for g in rings]
    band = [(s[0], ~s[1], s[2], s[3]) for s in samples]
    out = widen_rings(inputs, band, REACH * h, limit)
    moved, dev = even_out(inputs, band, out[0], limit, h)
    pulled, dev2 = pull_apart(inputs, band, moved, limit, h)
    for cand, d in ((pulled, max(out[1], dev, dev2)), (moved, max(out[1], dev))):
        if narrowest(cand, REACH * h)[0] >= narrowest(out[0], REACH * h)[0]:
            try:
                return polygon.with_rings(cand), d
            except InvalidPolygonError:
                pass
    try:
        return polygon.with_rings(out[0]), out[1]
    except InvalidPolygonError:
        return poly, max(float(s[2].max()) for s in samples)


class _Ring:
    """One ring's runs between kept vertices and its straightened arc measure."""

    def __init__(self, ring, keep, corners, forced, h, tol, cache, merge=False, weight=None,
                 drop_corners=False, slide=False):
        self.ring = ring
        self.cache = cache  # (start, edges[, pieces]) -> a run's measure or sampling
        self.kept = keep | corners
        self.corner = corners & ~keep
        self.n_corners = int(self.corner.sum())
        # corners a short-edge merge may drop (never segment ends, fixed points, splits)
        self.loose = self.corner & ~forced if drop_corners else np.zeros(len(ring), dtype=bool)
        starts = np.flatnonzero(self.kept | forced)  # forced: run ends that count in n
        self.ends = self.kept | forced
        self.merge = merge
        self.slide = slide
        self.closed = not len(starts)
        self.starts = starts if len(starts) else np.array([0])
        k = len(ring)
        self.nvs = (np.roll(self.starts, -1) - self.starts) % k if len(self.starts) > 1 else np.array([k])
        seg = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
        meas = seg.copy()
        for a, nv in zip(self.starts, self.nvs):
            idx = (a + np.arange(nv + 1)) % k
            key = (int(a), int(nv))
            if key not in cache:
                cache[key] = straightened_lengths(ring[idx], seg[idx[:-1]], tol * h)
            meas[idx[:-1]] = cache[key]
        if weight is not None:  # a size field's local spacing: spacing / h on each edge
            meas = meas * weight
        cum = np.concatenate([[0.0], np.cumsum(meas)])
        self.cum = cum
        self.ext = np.concatenate([cum[:-1], cum[-1] + cum])  # twice round

    def sample(self, h, tol):
        """(points (r, 2), kept (r,), deviation of each edge (r,), measure position
        of each point (r,)) at spacing ``h``, within ``tol`` of the spacing."""
        lp = np.arange(len(self.ring))
        m = run_counts(self.ext[self.starts + self.nvs] - self.ext[self.starts], h, self.closed)
        S, vert = [], []
        for a, nv, mk in zip(self.starts, self.nvs, m):
            key = (int(a), int(nv), int(mk))
            if key not in self.cache:  # a run's sampling depends on its own measure only
                self.cache[key] = self._run(lp, int(a), int(nv), int(mk), h, tol * h)
            for a2, u, v in self.cache[key]:
                S.append(self.ext[a2] + u)
                vert.append(v)
        S, vert = np.concatenate(S), np.concatenate(vert)
        pts = self._points(S, vert)
        k = len(self.ring)
        if self.merge:  # kept, forced and single-edge run ends stay (see outline_band)
            on = np.where(vert >= 0, self.ends[vert % k], False)
            sel = merge_short_edges(self.ring, self.ext, S, pts, ~on, h, tol * h)
            S, vert, pts, on = S[sel], vert[sel], pts[sel], on[sel]
            if self.loose.any():  # resample_corners="merge" (uniform2d.corner_merge)
                loose = np.where(vert >= 0, self.loose[vert % k], False)
                sel, S, pts, merged = merge_corners(self.ring, self.ext, S, pts, loose, ~on, h,
                                                    tol * h)
                vert = np.where(merged, -1, vert)  # a merged point is no input vertex
                S, vert, pts, on = S[sel], vert[sel], pts[sel], (on | merged)[sel]
                self.n_corners = int(self.corner[vert[vert >= 0] % k].sum())
            if self.slide:  # at the spacing found (uniform2d.ring_slide)
                S, pts = slide_samples(self.ring, self.ext, S, pts, ~on & ~crowded(pts, h), tol * h)
        kept = np.zeros(len(S), dtype=bool)
        kept[vert >= 0] = self.kept[vert[vert >= 0] % k]
        return pts, kept, self._deviation(S, pts, per_edge=True), S

    def split_points(self, S, edges):
        """The input vertices (indices) nearest the middle of the sampled edges
        ``edges`` (first points' indices), strictly inside their span."""
        total = self.cum[-1]
        k = len(self.ring)
        a = S[edges]
        b = np.where(edges + 1 < len(S), S[(edges + 1) % len(S)], S[0] + total)
        out = []
        for lo, hi in zip(a, b):
            i = np.searchsorted(self.ext, [lo, hi], side="right")
            inside = np.arange(i[0], i[1])
            inside = inside[(self.ext[inside] > lo) & (self.ext[inside] < hi)]
            if len(inside):
                mid = inside[np.argmin(np.abs(self.ext[inside] - 0.5 * (lo + hi)))]
                out.append(int(mid) % k)
        return np.array(out, dtype=np.int64)

    def _run(self, lp, a, nv, m, h, tol):
        """[(start, offsets, vertex or -1)] sampling run (a, nv), split if need be.
        A run that is one input edge is left whole: the mesher splits it at the
        spacing it chooses (its points count in n like these)."""
        if nv == 1:
            return [(a, np.zeros(1), np.array([a]))]
        u, height = plain_run(self.ring, lp, self.ext, a, nv, m)
        vert = np.full(m, -1)
        vert[0] = a
        for bounds in _BOUNDS:
            if height <= tol:
                return [(a, u, vert)]
            u, vert, height = sample_run(self.ring, lp, self.ext, a, nv, m, tol, bounds, _GRID)
        if height <= tol:
            return [(a, u, vert)]
        # split at the input vertex farthest from the sampling, and sample both parts
        S = self.ext[a] + np.append(u, self.ext[a + nv] - self.ext[a])
        idx = a + np.arange(1, nv)
        d = self._deviation(S, self._points(S, np.append(vert, a + nv)), idx)
        s = int(np.argmax(d)) + 1
        L1, L2 = self.ext[a + s] - self.ext[a], self.ext[a + nv] - self.ext[a + s]
        return (self._run(lp, a, s, max(1, round(L1 / h)), h, tol)
                + self._run(lp, a + s, nv - s, max(1, round(L2 / h)), h, tol))

    def _points(self, S, vert):
        """Points at measure positions S (on the input edges), exact on input vertices."""
        k = len(self.ring)
        s = np.mod(S, self.cum[-1])
        i = np.clip(np.searchsorted(self.cum, s, side="right") - 1, 0, k - 1)
        t = np.clip((s - self.cum[i]) / (self.cum[i + 1] - self.cum[i]), 0.0, 1.0)
        P = self.ring[i] + t[:, None] * (self.ring[(i + 1) % k] - self.ring[i])
        on = vert >= 0
        P[on] = self.ring[vert[on] % k]
        return P

    def _deviation(self, S, P, idx=None, per_edge=False):
        """Distance of input vertices ``idx`` (default all) from the sampled edge
        spanning each (samples at measure positions S, points P, in order); with
        ``per_edge``, per sampled edge the largest over the vertices it spans."""
        k = len(self.ring)
        idx = np.arange(k) if idx is None else idx
        pos = self.ext[idx]
        r = len(S)
        g = np.searchsorted(S, pos, side="right") - 1
        pos2 = np.where(g < 0, pos + self.cum[-1], pos)  # before the first sample: wrap
        g = np.searchsorted(S, pos2, side="right") - 1
        g = np.where(g < 0, r - 1, g)
        d = point_segment_distance(self.ring[idx % k], P[g % r], P[(g + 1) % r])
        if per_edge:
            out = np.zeros(r)
            np.maximum.at(out, g % r, d)
            return out
        return d

