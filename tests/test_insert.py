"""The fast kernel ``uniform2d.insert`` against the brute-force reference.

``uniform2d.insert(polygon, n, sites=None)`` must reproduce Algorithm INSERT step by
step -- the same points (absolute tolerance 1e-9 x polygon size), the same weights
(relative 1e-9) and the same on-boundary flags -- as ``tests/support/reference_insert.py``,
which recomputes every step from scratch with no code in common with the kernel.
Cases: every benchmark polygon (n = 200) and 33 random polygons (convex,
star-shaped, with 1-3 holes; n from 30 to 200), plus runs with extra initial sites.
On top of that, for the kernel alone: the dense sampling check at every step
(``tests/support/dense_check.py``), non-increasing weights, bit-identical repeated calls,
invariance under scaling and translation, and a sane mesh.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import pytest
import shapely

from uniform2d.testing import polygons
from support.benchmarks import benchmark_polygons
import uniform2d
from uniform2d.testing import check_mesh
from support.dense_check import check_sequence
from support.reference_insert import reference_insert
from uniform2d import Polygon

P_TOL = 1e-9  # points: absolute, times the polygon size
W_TOL = 1e-9  # weights: relative


@dataclass(frozen=True)
class Case:
    id: str
    polygon: Polygon
    n: int
    sites: tuple | None = None

    @property
    def size(self) -> float:
        x0, y0, x1, y1 = self.polygon.bounds
        return max(x1 - x0, y1 - y0)

    def site_array(self):
        return None if self.sites is None else np.array(self.sites, dtype=np.float64)


def _cases() -> list[Case]:
    out = [Case(f"bench-{k}-n200", p, 200) for k, p in benchmark_polygons().items()]
    for i in range(11):
        s = 100 + i
        rng = np.random.default_rng(s)
        k = int(rng.integers(3, 11))
        n = 200 if i == 10 else int(rng.integers(30, 81))
        out.append(Case(f"convex-s{s}-k{k}-n{n}", polygons.convex(rng, k), n))
    for i in range(11):
        s = 200 + i
        rng = np.random.default_rng(s)
        k = int(rng.integers(6, 15))
        n = 200 if i == 10 else int(rng.integers(30, 81))
        out.append(Case(f"star-s{s}-k{k}-n{n}", polygons.star(rng, k), n))
    for i in range(11):
        s = 300 + i
        h = 1 + i % 3
        n = 200 if i == 10 else int(np.random.default_rng(s).integers(30, 81))
        out.append(Case(f"holes-s{s}-h{h}-n{n}", polygons.with_holes(s, h), n))
    return out


def _site_cases() -> list[Case]:
    bench = benchmark_polygons()
    out = []
    sq = bench["square"]
    out.append(Case("square-4sites-n60", sq, 60, ((0.5, 0.0), (0.3, 0.6), (1.0, 0.25), (0.8, 0.8))))
    L = bench["lshape"]
    a = L.outer[3][0]  # the reflex corner is (a, a)
    out.append(Case("lshape-3sites-n60", L, 60, ((0.0, 0.3), (0.8, 0.2), (a, 1.5 * a))))
    for name, P in (("star-s7", polygons.star(7)), ("holes-s3", polygons.with_holes(3, 2))):
        inner = P.to_shapely().representative_point()
        pts = [(inner.x, inner.y), tuple(0.5 * (P.outer[0] + P.outer[1]))]
        if P.n_holes:
            h = P.holes[0]
            pts.append(tuple(0.5 * (h[1] + h[2])))
        out.append(Case(f"{name}-{len(pts)}sites-n60", P, 60, tuple(map(tuple, pts))))
    return out


CASES = _cases()
SITE_CASES = _site_cases()
ALL = CASES + SITE_CASES
BY_ID = {c.id: c for c in ALL}


def _params(cases):
    return [pytest.param(c.id, id=c.id) for c in cases]


@functools.lru_cache(maxsize=None)
def _reference(case_id: str):
    c = BY_ID[case_id]
    return reference_insert(c.polygon, c.n, c.site_array())


@functools.lru_cache(maxsize=None)
def _kernel(case_id: str):
    c = BY_ID[case_id]
    return uniform2d.insert(c.polygon, c.n, sites=c.site_array())


def _distance_to_boundary(polygon: Polygon, p) -> float:
    return float(polygon.to_shapely().boundary.distance(shapely.Point(p)))


def assert_same_sequence(case: Case, res, ref) -> None:
    """Step-by-step equality with a message that pinpoints the first divergence."""
    n = case.n
    assert np.shape(res.points) == (n, 2), f"points shape {np.shape(res.points)}"
    assert np.shape(res.weights) == (n,), f"weights shape {np.shape(res.weights)}"
    assert np.shape(res.on_boundary) == (n,), f"on_boundary shape {np.shape(res.on_boundary)}"
    kp = np.asarray(res.points, dtype=np.float64)
    kw = np.asarray(res.weights, dtype=np.float64)
    kb = np.asarray(res.on_boundary, dtype=bool)
    dp = np.abs(kp - ref.points).max(axis=1)
    dw = np.abs(kw - ref.weights) / ref.weights
    bad = (dp > P_TOL * case.size) | (dw > W_TOL) | (kb != ref.on_boundary)
    if bad.any():
        j = int(np.flatnonzero(bad)[0])
        db_k = _distance_to_boundary(case.polygon, kp[j])
        db_r = _distance_to_boundary(case.polygon, ref.points[j])
        raise AssertionError(
            f"{case.id}: {int(bad.sum())} of {n} steps differ; first at step {j}:\n"
            f"  kernel    p = {kp[j].tolist()!r}  w = {float(kw[j])!r}  on_boundary = {bool(kb[j])}"
            f"  (distance to boundary {db_k:.3g})\n"
            f"  reference p = {ref.points[j].tolist()!r}  w = {float(ref.weights[j])!r}"
            f"  on_boundary = {bool(ref.on_boundary[j])}  (distance to boundary {db_r:.3g})\n"
            f"  |dp| = {dp[j]:.3g} (tol {P_TOL * case.size:.3g}), rel dw = {dw[j]:.3g}"
            f" (tol {W_TOL:g}); the reference had {ref.n_tied[j]} distinct tied"
            f" maxima at this step"
        )


# -- kernel == reference ------------------------------------------------------------------
@pytest.mark.parametrize("case_id", _params(CASES))
def test_matches_reference(case_id):
    case = BY_ID[case_id]
    assert_same_sequence(case, _kernel(case_id), _reference(case_id))


@pytest.mark.parametrize("case_id", _params(SITE_CASES))
def test_matches_reference_with_sites(case_id):
    case = BY_ID[case_id]
    assert_same_sequence(case, _kernel(case_id), _reference(case_id))


# -- kernel alone ----------------------------------------------------------------------------
@pytest.mark.parametrize("case_id", _params(ALL))
def test_dense_check_every_step(case_id):
    case = BY_ID[case_id]
    res = _kernel(case_id)
    problems = check_sequence(case.polygon, res.points, res.weights, case.site_array())
    assert not problems, f"{case.id}:\n" + "\n".join(problems[:5])


@pytest.mark.parametrize("case_id", _params(ALL))
def test_weights_non_increasing(case_id):
    w = np.asarray(_kernel(case_id).weights)
    assert (w > 0).all()
    up = np.flatnonzero(w[1:] > w[:-1] * (1 + 1e-12))
    assert up.size == 0, f"weights increase at steps {(up + 1).tolist()[:10]}"


DET_CASES = [c for c in CASES if c.id.startswith("bench-")] + [CASES[7], CASES[18], CASES[29]]


@pytest.mark.parametrize("case_id", _params(DET_CASES + SITE_CASES[:2]))
def test_bit_identical_repeat(case_id):
    c = BY_ID[case_id]
    a = uniform2d.insert(c.polygon, c.n, sites=c.site_array())
    b = uniform2d.insert(c.polygon, c.n, sites=c.site_array())
    for name in ("points", "weights", "on_boundary", "mesh_points", "triangles"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), f"{name} differs between two identical calls"


def _snap(p: Polygon, bits: int = 8) -> Polygon:
    """Vertices rounded to multiples of 2**-bits, so that adding +-1e6 is exact.

    Without this the translated polygon is a *different* polygon: coordinates near
    1e6 keep only ~1e-10 absolute precision, which perturbs the weights of a unit
    polygon at n = 200 by ~2e-9 relative -- more than the tie tolerance 1e-9.
    The grid is coarse on purpose: rounding irrational coordinates (the hexagon's)
    breaks their symmetry, and on a fine grid it leaves near-degeneracies -- e.g. a
    nearly cocircular quadruple whose Delaunay diagonal is decided by a ~1e-16
    in-circle determinant, with Voronoi vertices 5e-8 apart and weights 1e-13 apart
    -- that no tie rule can resolve the same way after a rounding perturbation.  On a
    2**-8 grid broken symmetries are broken by ~1e-3: nothing is left ambiguous.
    Scaling needs no snapping: it perturbs by rounding only (~1e-16), and exact ties
    (true symmetries) stay within the tie tolerance.
    """
    f = lambda r: np.round(np.asarray(r) * 2.0**bits) / 2.0**bits  # noqa: E731
    return Polygon(f(p.outer), [f(h) for h in p.holes])


TRANSFORMS = [
    pytest.param(1e-6, (0.0, 0.0), id="scale1e-6"),
    pytest.param(1e6, (0.0, 0.0), id="scale1e6"),
    pytest.param(1.0, (1e6, -1e6), id="offset1e6"),
]


@pytest.mark.parametrize("scale, offset", TRANSFORMS)
@pytest.mark.parametrize("case_id", _params(DET_CASES))
def test_scale_and_offset_invariance(case_id, scale, offset):
    c = BY_ID[case_id]
    P = _snap(c.polygon) if offset != (0.0, 0.0) else c.polygon
    n = min(c.n, 150)
    base = uniform2d.insert(P, n)
    moved = uniform2d.insert(P.transformed(scale, offset), n)
    exp_p = np.asarray(base.points) * scale + np.asarray(offset)
    dp = np.abs(np.asarray(moved.points) - exp_p).max(axis=1)
    dw = np.abs(np.asarray(moved.weights) / (np.asarray(base.weights) * scale) - 1)
    # far from the origin every point is rounded to what the coordinates hold
    # before it is inserted (so the mesh is exactly the certified one): a weight
    # can then move by that rounding, a few units in the last place of the offset
    grain = 4 * np.spacing(np.abs(np.asarray(offset)).max()) / (np.asarray(base.weights) * scale)
    bad = (dp > P_TOL * c.size * scale) | (dw > W_TOL + grain)
    bad |= np.asarray(moved.on_boundary) != np.asarray(base.on_boundary)
    if bad.any():
        j = int(np.flatnonzero(bad)[0])
        raise AssertionError(
            f"{c.id} x{scale:g} +{offset}: {int(bad.sum())} steps differ, first at {j}: "
            f"expected p = {exp_p[j].tolist()!r} w = {float(base.weights[j] * scale)!r} "
            f"on_boundary = {bool(base.on_boundary[j])}, got p = "
            f"{np.asarray(moved.points)[j].tolist()!r} w = {float(moved.weights[j])!r} "
            f"on_boundary = {bool(moved.on_boundary[j])}"
        )


@pytest.mark.parametrize("case_id", _params(ALL))
def test_mesh_is_a_ccw_triangulation_of_the_polygon(case_id):
    c = BY_ID[case_id]
    res = _kernel(case_id)
    X = np.asarray(res.mesh_points, dtype=np.float64)
    T = np.asarray(res.triangles)
    assert X.ndim == 2 and X.shape[1] == 2 and T.ndim == 2 and T.shape[1] == 3
    a, b, cc = X[T[:, 0]], X[T[:, 1]], X[T[:, 2]]
    area2 = (b[:, 0] - a[:, 0]) * (cc[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (cc[:, 0] - a[:, 0])
    assert (area2 > 0).all(), f"{(area2 <= 0).sum()} triangles are not counter-clockwise"
    assert 0.5 * area2.sum() == pytest.approx(c.polygon.area, rel=1e-9)
    # every polygon vertex, extra site and inserted point is a mesh vertex
    need = [c.polygon.vertices, np.asarray(res.points)]
    if c.sites is not None:
        need.append(c.site_array())
    need = np.concatenate(need)
    d = np.min(np.abs(need[:, None, :] - X[None, :, :]).max(axis=2), axis=1)
    assert (d <= 1e-12 * c.size).all(), f"{(d > 1e-12 * c.size).sum()} points missing from the mesh"
    # the full independent checks: neighbour symmetry, orientation, every polygon edge
    # present (split at the boundary points), area, and local Delaunay on every
    # unconstrained edge -- decided exactly (uniform2d.testing.checks)
    check_mesh(X, T, c.polygon)


@pytest.mark.parametrize("case_id", _params(DET_CASES))
def test_min_distance_after_is_the_meshes_closest_pair(case_id):
    """T+'s d_n without the mesh: bit for bit the distance of the full result, and
    the closest pair of the reference's points and V by brute force."""
    from scipy.spatial.distance import pdist

    from uniform2d.insert import min_distance_after

    c = BY_ID[case_id]
    d = min_distance_after(c.polygon, c.n)
    assert d == _kernel(case_id).min_distance()
    ref = _reference(case_id)
    brute = pdist(np.concatenate([c.polygon.vertices, ref.points])).min()
    assert abs(d - brute) <= 2 * P_TOL * c.size
