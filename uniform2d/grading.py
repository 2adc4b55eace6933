"""A size ``h`` for a graded mesh: what a caller may pass, and how many points it implies.

``size=`` of :func:`uniform2d.uniform_mesh` and :func:`uniform2d.insert` is a
number (a uniform mesh, as always), a :class:`~uniform2d.SizeField`, or a
callable ``h(points)`` taking a (k, 2) float64 array and returning (k,) positive
sizes.  :func:`as_field` turns a callable into a :class:`~uniform2d.SizeField`
by sampling it once on a regular grid over the polygon's bounding box (the
kernel reads sizes inside compiled loops, where a Python callable cannot run;
bilinear interpolation of a grid fine enough for the field's smallest size
changes the mesh far less than the optimiser's tolerance does).  Outside the
grid a field is clamped to its nearest grid value, so a grid that does not
cover the whole domain still gives a size everywhere.

**Count.**  A mesh of equilateral triangles whose side follows h has about
``T = ∫ 4 / (√3 h²) dA`` triangles and ``N_b = ∮ ds / h`` boundary vertices;
Euler's formula then gives ``N = (T + N_b + 2 - 2 holes) / 2`` vertices, as
:func:`uniform2d.geometry.vertex_count` does for a constant h.  With the field
scaled by s, ``N(s) = (T / s² + N_b / s + 2 - 2 holes) / 2``:
:func:`scale_for_count` solves it for the s at which the mesh has the asked n
(the scale search: a quadratic in 1 / s), :func:`count_for_field` evaluates it
at s = 1 (h absolute).
"""

from __future__ import annotations

import math
import numbers

import numpy as np
import shapely

from .errors import ArgumentTypeError, InsufficientPointsError, InvalidArgumentError
from .polygon import Polygon
from .sizefield import SizeField

__all__ = [
    "evaluate_size",
    "MAX_RANGE",
    "as_field",
    "check_range",
    "count_for_field",
    "field_integrals",
    "scale_for_count",
]

#: A field whose largest size over the domain is more than MAX_RANGE times its
#: smallest is refused at an n where the mesh cannot follow it (see
#: :func:`check_range`).
MAX_RANGE = 1e4
#: Grid nodes along the longer side of the bounding box when a callable is sampled:
#: at least the first, at most the second, else about two per smallest size.
SAMPLES = (65, 513)
#: Cells along the longer side of the bounding box for the count's integral, at most.
CELLS = 512


def _where(p) -> str:
    return f"({p[0]:.6g}, {p[1]:.6g})"


def evaluate_size(h, P: np.ndarray, where: str = "points") -> np.ndarray:
    """``h(P)`` for a size callable and a (k, d) float64 array of ``where``, as a
    (k,) float64 array; a raising callable or a wrong shape is an
    InvalidArgumentError (the surface layer's 3-D sizes use it too)."""
    try:
        v = h(P.copy())
    except Exception as exc:  # the caller's code: any failure is bad input here
        raise InvalidArgumentError(
            f"size callable raised {type(exc).__name__}: {exc} (it is called with a "
            f"(k, {P.shape[1]}) float64 array of {where} and must return k positive sizes)"
        ) from exc
    try:
        v = np.asarray(v, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(f"size callable returned no array of numbers: {exc}") from exc
    if v.shape != (len(P),):
        raise InvalidArgumentError(
            f"size callable returned {v.size} values for {len(P)} points; it must return "
            "one size per point, shape (k,)"
        )
    return v


def _check_positive(P: np.ndarray, v: np.ndarray, inside: np.ndarray, what: str) -> None:
    bad = ~(np.isfinite(v) & (v > 0)) & inside
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise InvalidArgumentError(
            f"{what} is {float(v[i])!r} at {_where(P[i])}, inside the domain; sizes must be finite "
            "and positive everywhere in it"
        )


def as_field(polygon: Polygon, size) -> SizeField | None:
    """The :class:`~uniform2d.SizeField` of ``size``, or None for a number (uniform).

    A callable is sampled on a regular grid over the bounding box of ``polygon``,
    padded by one step, with about two nodes per smallest size (between
    ``SAMPLES`` nodes along the longer side).  Its values at nodes outside the
    domain that are not positive finite numbers (a background mesh's
    interpolant is NaN there) are replaced by the nearest node's in the domain;
    inside the domain they are an error naming the place.

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = as_field(sq, lambda p: 0.1 + p[:, 0])
    >>> round(float(f([[0.5, 0.5]])[0]), 6)
    0.6
    >>> as_field(sq, 0.1) is None
    True
    """
    if size is None or (isinstance(size, numbers.Real) and not isinstance(size, bool)):
        return None
    if isinstance(size, SizeField):
        return size
    if not callable(size):
        raise ArgumentTypeError(
            f"size must be a SizeField or a number, or a callable h(points (k, 2)) -> (k,) "
            f"sizes; got {type(size).__name__}"
        )
    xmin, ymin, xmax, ymax = polygon.bounds
    ext = max(xmax - xmin, ymax - ymin)
    shape = shapely.Polygon(*_rings(polygon))
    coarse = _grid(xmin, ymin, xmax, ymax, ext / (SAMPLES[0] - 1))
    v = evaluate_size(size, coarse[2])
    inside = shapely.intersects_xy(shape, coarse[2][:, 0], coarse[2][:, 1])
    _check_positive(coarse[2], v, inside, "the size")
    hmin = float(v[inside].min()) if np.any(inside) else float(np.nanmin(v))
    nodes = int(np.clip(math.ceil(2 * ext / hmin) + 1, *SAMPLES))
    gx, gy, P = _grid(xmin, ymin, xmax, ymax, ext / (nodes - 1))
    v = evaluate_size(size, P)
    inside = shapely.intersects_xy(shape, P[:, 0], P[:, 1])
    _check_positive(P, v, inside, "the size")
    good = np.isfinite(v) & (v > 0)
    if not np.all(good):
        from scipy.spatial import cKDTree

        _, j = cKDTree(P[good]).query(P[~good])
        v[~good] = v[good][j]
    return SizeField(gx, gy, v.reshape(len(gy), len(gx)))


def _rings(polygon: Polygon):
    off = polygon.ring_offsets
    rings = [polygon.vertices[off[r]:off[r + 1]] for r in range(len(polygon.rings))]
    return rings[0], rings[1:]


def _grid(xmin, ymin, xmax, ymax, step):
    """Nodes (gx, gy, points (ny*nx, 2)) of a grid of ``step`` over the box, padded by a step."""
    gx = xmin - step + step * np.arange(math.ceil((xmax - xmin) / step) + 3)
    gy = ymin - step + step * np.arange(math.ceil((ymax - ymin) / step) + 3)
    X, Y = np.meshgrid(gx, gy)
    return gx, gy, np.column_stack([X.ravel(), Y.ravel()])


def field_integrals(polygon: Polygon, field: SizeField) -> tuple[float, float]:
    """(T, N_b): ``∫ 4 / (√3 h²) dA`` over P and ``∮ ds / h`` over its boundary.

    Cells of a regular grid (up to ``CELLS`` along the longer side, finer than
    the field's grid) inside P count whole at their centre; cells the boundary
    crosses count with their clipped area at its centroid.  Boundary edges are
    split into pieces no longer than a cell, each taken at its midpoint.

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> T, Nb = field_integrals(sq, SizeField.constant(sq.bounds, 0.1))
    >>> round(T, 3), round(Nb, 6)
    (230.94, 40.0)
    """
    xmin, ymin, xmax, ymax = polygon.bounds
    ext = max(xmax - xmin, ymax - ymin)
    fine = min(float(np.diff(field.x).min()), float(np.diff(field.y).min()))
    step = max(ext / CELLS, min(ext / 64, fine))
    nx = max(1, math.ceil((xmax - xmin) / step))
    ny = max(1, math.ceil((ymax - ymin) / step))
    gx = np.linspace(xmin, xmax, nx + 1)
    gy = np.linspace(ymin, ymax, ny + 1)
    shape = shapely.Polygon(*_rings(polygon))
    X, Y = np.meshgrid(gx, gy)
    corner = shapely.contains_xy(shape, X.ravel(), Y.ravel()).reshape(ny + 1, nx + 1)
    inside = corner[:-1, :-1] & corner[1:, :-1] & corner[:-1, 1:] & corner[1:, 1:]
    some = corner[:-1, :-1] | corner[1:, :-1] | corner[:-1, 1:] | corner[1:, 1:]
    # cells the boundary passes through: mixed corners, or a boundary sample inside
    # (a vertex, or an edge between corners, e.g. a hole smaller than a cell)
    crossed = some & ~inside
    V = polygon.vertices
    a, b = V[polygon.edges[:, 0]], V[polygon.edges[:, 1]]
    k = np.maximum(1, np.ceil(np.hypot(*(b - a).T) / (0.25 * step)).astype(np.int64))
    e = np.repeat(np.arange(len(a)), k)
    t = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k, k)
    S = np.concatenate([a[e] + t[:, None] * (b[e] - a[e]), V])
    i = np.clip(np.searchsorted(gx, S[:, 0], side="right") - 1, 0, nx - 1)
    j = np.clip(np.searchsorted(gy, S[:, 1], side="right") - 1, 0, ny - 1)
    crossed[j, i] = True
    whole = inside & ~crossed
    cx, cy = 0.5 * (gx[:-1] + gx[1:]), 0.5 * (gy[:-1] + gy[1:])
    CX, CY = np.meshgrid(cx, cy)
    dx, dy = np.diff(gx)[0], np.diff(gy)[0]
    w = np.where(whole, dx * dy, 0.0).ravel()
    P = np.column_stack([CX.ravel(), CY.ravel()])
    cut = np.flatnonzero(crossed.ravel())
    boxes = shapely.box(P[cut, 0] - dx / 2, P[cut, 1] - dy / 2, P[cut, 0] + dx / 2,
                        P[cut, 1] + dy / 2)
    clipped = shapely.intersection(boxes, shape)
    wc = shapely.area(clipped)
    keep = wc > 0
    w[cut] = wc
    P[cut[keep]] = shapely.get_coordinates(shapely.centroid(clipped[keep]))
    use = w > 0
    h = field(P[use])
    T = float(np.sum(w[use] / h**2)) * 4 / math.sqrt(3)
    Nb = 0.0
    for a, b in polygon.edges.tolist():
        L = float(np.hypot(*(V[b] - V[a])))
        k = max(1, math.ceil(L / step))
        t = (np.arange(k) + 0.5) / k
        mid = V[a] + t[:, None] * (V[b] - V[a])
        Nb += float(np.sum((L / k) / field(mid)))
    return T, Nb


def count_for_field(polygon: Polygon, field: SizeField) -> int:
    """Steiner points n of a mesh whose edges follow ``field`` (absolute sizes).

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> count_for_field(sq, SizeField.constant(sq.bounds, 0.1))   # as steiner_count_for_size
    132
    """
    T, Nb = field_integrals(polygon, field)
    N = (T + Nb + 2 - 2 * polygon.n_holes) / 2
    return max(0, round(N) - len(polygon.vertices))


def scale_for_count(polygon: Polygon, field: SizeField, n: int, integrals=None) -> float:
    """The factor s for which ``s * field`` implies |V| + n vertices.

    ``T / s² + N_b / s = 2 (|V| + n) - 2 + 2 holes``: the positive root of a
    quadratic in 1 / s.

    Examples
    --------
    >>> sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    >>> f = SizeField.constant(sq.bounds, 1.0)
    >>> s = scale_for_count(sq, f, 132)
    >>> round(s, 3), count_for_field(sq, f.scaled(s))
    (0.1, 132)
    """
    T, Nb = field_integrals(polygon, field) if integrals is None else integrals
    c = 2.0 * (len(polygon.vertices) + n) - 2.0 + 2.0 * polygon.n_holes
    if c <= 0:
        raise InsufficientPointsError(f"n = {n} is too small for this polygon")
    u = (-Nb + math.sqrt(Nb * Nb + 4 * T * c)) / (2 * T)  # u = 1 / s
    return 1.0 / u


def _range_over(polygon: Polygon, field: SizeField) -> tuple[float, float]:
    """(smallest, largest) size of the field at its grid nodes in P and P's vertices."""
    X, Y = np.meshgrid(field.x, field.y)
    P = np.column_stack([X.ravel(), Y.ravel()])
    shape = shapely.Polygon(*_rings(polygon))
    inside = shapely.intersects_xy(shape, P[:, 0], P[:, 1])
    v = np.concatenate([field.values.ravel()[inside], field(polygon.vertices)])
    return float(v.min()), float(v.max())


def check_range(polygon: Polygon, field: SizeField, n: int, integrals) -> None:
    """Refuse a field the mesh cannot follow with n points.

    A field whose largest size over P exceeds ``MAX_RANGE`` times its smallest
    leaves, at a small n, the coarse part with sizes larger than P itself (its
    diameter): there the mesh cannot follow it, the points all go to the fine
    part, and the count integral no longer says what the mesh is.  Such an n is
    refused with the smallest n at which the largest scaled size fits in P.
    """
    lo, hi = _range_over(polygon, field)
    if hi <= MAX_RANGE * lo:
        return
    xmin, ymin, xmax, ymax = polygon.bounds
    diameter = math.hypot(xmax - xmin, ymax - ymin)
    s = scale_for_count(polygon, field, n, integrals)
    if s * hi <= diameter:
        return
    T, Nb = integrals
    s_fit = diameter / hi
    need = math.ceil((T / s_fit**2 + Nb / s_fit + 2 - 2 * polygon.n_holes) / 2) - len(
        polygon.vertices)
    raise InvalidArgumentError(
        f"the size field ranges over max/min = {hi / lo:.3g} (more than {MAX_RANGE:g}); with "
        f"n = {n} its largest sizes exceed the domain, where the mesh cannot follow them; "
        f"use n >= {max(need, n + 1)} or a field with a smaller range"
    )
