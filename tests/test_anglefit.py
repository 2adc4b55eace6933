"""The angle fit (:mod:`uniform2d.optimize.anglefit`).

The floor: Gmsh's worst angle on ``star10`` (Frontal-Delaunay, size bisected
to the count as in ``benchmarks/bench_angles.py``), computed here when Gmsh is
importable, else the figure measured once (43.70 deg; Gmsh's closest count to
310 vertices is 304, it jumps from 304 to 326).  Before the fit the mesh at
n = 300 had 41.45 deg.
"""

from pathlib import Path

import numpy as np
import pytest
from support.benchmarks import benchmark_polygons
from support.boundary_edges import edges_of

import uniform2d
from uniform2d.geometry import polygon_edges
from uniform2d.optimize import anglefit
from uniform2d.optimize.angles import MIN_GAIN, angles_and_gradients, forced_angle
from uniform2d.optimize.boundary import target_size
from uniform2d.peers import base as peers
from uniform2d.quality import quality
from uniform2d.testing import check_mesh

POLYGONS = benchmark_polygons()
#: Gmsh's worst angle on star10 tuned to 310 vertices (304 made), measured once.
GMSH_STAR10 = 43.70


@pytest.fixture(scope="module")
def star10():
    """star10 at n = 300: (polygon, mesh)."""
    p = POLYGONS["star10"]
    return p, uniform2d.uniform_mesh(p, 300)


def test_star10_reaches_gmsh_angle(star10):
    p, m = star10
    check_mesh(m.points, m.triangles, p)
    assert m.n_steiner == 300 and len(m.points) == 300 + len(p.vertices)
    floor = GMSH_STAR10
    if peers.available("gmsh"):
        g = peers.mesh("gmsh", p, len(m.points))
        floor = quality(g.points, g.triangles).min_angle
        assert abs(floor - GMSH_STAR10) < 0.01  # the figure above, for runs without Gmsh
    q = m.quality()
    assert q.min_angle >= floor
    assert m.info["angle_fits"] >= 1


@pytest.fixture(scope="module")
def unfitted():
    """star10's mesh at n = 300 made without the fit."""
    p = POLYGONS["star10"]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(anglefit, "FIT_BELOW", 0.0)
        m = uniform2d.uniform_mesh(p, 300)
    assert m.info["angle_fits"] == 0
    return p, m


def test_fit_raises_worst_angle_with_edges_held(unfitted):
    p, m = unfitted
    nV = len(p.vertices)
    edges = edges_of(p, m.points)
    pts0, tri0 = m.points.copy(), m.triangles.copy()
    q0 = quality(m.points, m.triangles)
    pts, tri, kept = anglefit.fit_worst_angle(p, m.points, m.triangles, edges)
    assert np.array_equal(m.points, pts0) and np.array_equal(m.triangles, tri0)  # not mutated
    assert kept >= 1
    check_mesh(pts, tri, p)
    assert len(pts) == len(pts0) and np.array_equal(pts[:nV], p.vertices)
    assert np.array_equal(edges_of(p, pts), edges)  # boundary sites stayed on their edges
    q = quality(pts, tri)
    assert q.min_angle >= q0.min_angle + kept * MIN_GAIN
    for k in ("edge_ratio", "longest_edge", "max_perimeter"):
        assert getattr(q, k) <= getattr(q0, k)
    assert q.cv_edge <= q0.cv_edge * (1 + anglefit.CV_SLACK) ** kept


def test_fine_meshes_left_alone(unfitted, monkeypatch):
    """A mesh whose worst angle is FIT_BELOW or more comes back as it is."""
    p, m = unfitted
    monkeypatch.setattr(anglefit, "FIT_BELOW", quality(m.points, m.triangles).min_angle)
    out = anglefit.fit_worst_angle(p, m.points, m.triangles, edges_of(p, m.points))
    assert out[0] is m.points and out[1] is m.triangles and out[2] == 0


def test_same_mesh_on_any_blas_thread_count(star10):
    """The program's linear algebra (SciPy's BLAS) runs on one thread whatever
    the process's BLAS threads: the same bytes on any machine."""
    from threadpoolctl import threadpool_limits

    p, m = star10
    for threads in (1, 2):
        with threadpool_limits(limits=threads, user_api="blas"):
            again = uniform2d.uniform_mesh(p, 300)
        assert again.points.tobytes() == m.points.tobytes()
        assert again.triangles.tobytes() == m.triangles.tobytes()


def test_near_constraints_reach_what_all_of_them_reach(unfitted, monkeypatch):
    """The program stating only the constraints near binding at its start
    (NEAR_ANGLE, NEAR_LENGTH) raises the worst angle as far as the one stating
    all of them, breaking none of those it left out."""
    p, m = unfitted
    edges = edges_of(p, m.points)
    near = anglefit.fit_worst_angle(p, m.points, m.triangles, edges)
    monkeypatch.setattr(anglefit, "NEAR_ANGLE", 180.0)
    monkeypatch.setattr(anglefit, "NEAR_LENGTH", 1.0)  # every constraint stated
    full = anglefit.fit_worst_angle(p, m.points, m.triangles, edges)
    assert near[2] == full[2] >= 1
    check_mesh(near[0], near[1], p)
    qn, qf = quality(near[0], near[1]), quality(full[0], full[1])
    assert abs(qn.min_angle - qf.min_angle) < 1e-3
    for k in ("edge_ratio", "longest_edge", "max_perimeter", "cv_edge"):
        assert getattr(qn, k) <= getattr(qf, k) * (1 + 1e-6)


def test_near_rows_hold_the_binding_ones(unfitted):
    """The rows the near program states include the worst angle, the longest
    and the shortest edge and the largest perimeter of the region; without
    ``near`` every row."""
    p, m = unfitted
    nV = len(p.vertices)
    free, T, E = anglefit._region(m.points, m.triangles, nV)
    q = m.points[T]
    A, _ = angles_and_gradients(q)
    L = np.hypot(*(m.points[E[:, 0]] - m.points[E[:, 1]]).T)
    per = np.hypot(*(q - q[:, [1, 2, 0]]).transpose(2, 0, 1)).sum(axis=1)
    limits = (L.max(), L.min(), per.max(), L.mean(), 0.0)
    corners, hi, lo, tp = anglefit._rows(m.points, T, E, limits, A.min(), True)
    assert int(np.argmin(A)) in corners and len(corners) < len(A)
    assert tuple(E[np.argmax(L)]) in set(map(tuple, hi)) and len(hi) < len(E)
    assert tuple(E[np.argmin(L)]) in set(map(tuple, lo)) and len(lo) < len(E)
    assert tuple(T[np.argmax(per)]) in set(map(tuple, tp)) and len(tp) < len(T)
    corners, hi, lo, tp = anglefit._rows(m.points, T, E, limits, A.min(), False)
    assert len(corners) == 3 * len(T) and len(hi) == len(lo) == len(E) and len(tp) == len(T)


def test_a_near_program_breaking_a_left_out_constraint_gives_way_to_the_full_one(
        unfitted, monkeypatch):
    """With next to nothing stated (no angle but the worst, no edge or
    perimeter limit) the near program's moves break constraints it left out:
    each round then runs the full program, and the fit is the full one's."""
    p, m = unfitted
    edges = edges_of(p, m.points)
    ran = []
    program = anglefit._program

    def counted(points, T, E, D, limits, rows=None, give=False):
        if rows is not None:
            ran.append(len(rows[0]) == 3 * len(T))
        return program(points, T, E, D, limits, rows, give)

    monkeypatch.setattr(anglefit, "_program", counted)
    monkeypatch.setattr(anglefit, "NEAR_ANGLE", 0.0)
    monkeypatch.setattr(anglefit, "NEAR_LENGTH", -1.0)
    fallback = anglefit.fit_worst_angle(p, m.points, m.triangles, edges)
    assert True in ran and False in ran  # near programs, then full ones
    monkeypatch.setattr(anglefit, "NEAR_ANGLE", 180.0)
    monkeypatch.setattr(anglefit, "NEAR_LENGTH", 1.0)
    full = anglefit.fit_worst_angle(p, m.points, m.triangles, edges)
    assert fallback[2] == full[2] >= 1
    assert np.array_equal(fallback[0], full[0]) and np.array_equal(fallback[1], full[1])


def _mixed():
    """bench_constrained's ``mixed``: a hole of 16 edges of 0.64 target sizes
    at n = 300, a closed zone, a wall, free segments and fixed points."""
    return uniform2d.read_polygon(Path(__file__).resolve().parents[1] / "data" / "constrained"
                                  / "mixed.json")


@pytest.fixture(scope="module")
def mixed_held():
    """``mixed`` at n = 300 made without the loose rounds: (polygon, mesh)."""
    p = _mixed()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(anglefit, "LOOSE_ROUNDS", 0)
        m = uniform2d.uniform_mesh(p, 300)
    assert m.info["angle_first_fits"] == 0
    return p, m


def test_loose_rounds_raise_the_angle_within_their_budget(mixed_held):
    """Below ANGLE_FINE the worst angle comes first: every loose round raises
    it, the edges give at most LOOSE_BUDGET over the mesh the rounds start
    from, the mesh stays valid with the same points on the same edges."""
    p, m = mixed_held
    q0 = m.quality()
    assert q0.min_angle < anglefit.ANGLE_FINE
    edges = edges_of(p, m.points)
    pts0 = m.points.copy()
    pts, tri, kept = anglefit.loosen_worst_angle(p, m.points, m.triangles, edges)
    assert np.array_equal(m.points, pts0)  # not mutated
    assert kept >= 1
    check_mesh(pts, tri, p, n_steiner=300)
    assert np.array_equal(edges_of(p, pts), edges)
    q = quality(pts, tri)
    assert q.min_angle >= q0.min_angle + kept * MIN_GAIN
    for k in ("edge_ratio", "longest_edge", "max_perimeter", "cv_edge"):
        assert getattr(q, k) <= getattr(q0, k) * (1 + anglefit.LOOSE_BUDGET)


def test_mixed_reaches_gmsh_angle_with_better_edges():
    """Gmsh with the same lines and points embedded, its size bisected to 336
    vertices (ours: 334), measured by bench_constrained: worst angle 38.66 deg,
    edge ratio 2.986, CV 0.154.  Without the loose rounds ours was 31.1 deg."""
    p = _mixed()
    m = uniform2d.uniform_mesh(p, 300)
    check_mesh(m.points, m.triangles, p, n_steiner=300)
    q = m.quality()
    assert m.info["angle_first_fits"] >= 1 and m.info["fallback"] is None
    assert q.min_angle >= 38.66 and q.edge_ratio < 2.986 and q.cv_edge < 0.154


def test_fine_meshes_not_loosened(star10):
    """A mesh whose worst angle is ANGLE_FINE or more comes back as it is."""
    p, m = star10
    assert m.quality().min_angle >= anglefit.ANGLE_FINE
    out = anglefit.loosen_worst_angle(p, m.points, m.triangles, edges_of(p, m.points))
    assert out[0] is m.points and out[1] is m.triangles and out[2] == 0


def test_loose_rounds_stay_below_tplus_objective(monkeypatch):
    """The loose rounds trade edges for the worst angle, never so far that the
    optimiser's objective passes T+'s (the mesh would be T+'s then, with its
    worse angle): the L-bracket at n = 200, 20.8 deg without them."""
    p = uniform2d.read_polygon(Path(__file__).resolve().parents[1] / "data" / "l_bracket.json")
    m = uniform2d.uniform_mesh(p, 200)
    assert m.info["fallback"] is None and m.info["angle_first_fits"] >= 1
    assert m.info["objective_value"] <= m.info["start"]["objective"]
    assert m.info["start"]["min_angle"] < m.quality().min_angle
    monkeypatch.setattr(anglefit, "LOOSE_ROUNDS", 0)
    held = uniform2d.uniform_mesh(p, 200)
    assert held.info["angle_first_fits"] == 0
    assert held.quality().min_angle + 5.0 < m.quality().min_angle


def test_loose_program_jacobian_matches_differences(unfitted):
    """The loose program's constraint Jacobian, moves and gives alike, is the
    derivative of its constraints (central differences), at a point where
    every give is under way."""
    p, m = unfitted
    nV = len(p.vertices)
    free, T, E = anglefit._region(m.points, m.triangles, nV)
    a, d, _ = polygon_edges(p, constraints=True)
    edges = edges_of(p, m.points)
    q = m.points[T]
    L = np.hypot(*(m.points[E[:, 0]] - m.points[E[:, 1]]).T)
    per = np.hypot(*(q - q[:, [1, 2, 0]]).transpose(2, 0, 1)).sum(axis=1)
    limits = (L.max(), L.min(), per.max(), L.mean(), ((L - L.mean()) ** 2).sum())
    D, _ = anglefit._jacobian_map(m.points, free, edges, nV, d, 1.0)
    _, fun, jac = anglefit._program(m.points, T, E, D, limits, None, True)
    rng = np.random.default_rng(1)
    x = np.r_[rng.uniform(-1e-3, 1e-3, D.shape[2]), [0.3, 0.5, 0.7, 0.9], 30.0]
    J = jac(x)
    assert J.shape == (len(fun(x)), len(x))
    step = 1e-6
    for col in list(range(3)) + list(range(len(x) - 1 - anglefit.GIVES, len(x))):
        e = np.zeros(len(x))
        e[col] = step
        numeric = (fun(x + e) - fun(x - e)) / (2 * step)
        assert np.allclose(J[:, col], numeric, rtol=1e-5, atol=1e-6)


def test_no_loose_rounds_above_the_forced_angle():
    """``plate_zones`` at n = 300: its worst triangle stands on the hole, whose
    24 edges (a circle of radius 20: 2 * 20 * sin(7.5 deg) = 5.22) are 0.27 of
    the target size h; the angle forced there, 2 asin(l / (l + h)) = 24.3 deg,
    is below the mesh's 32.0 (Gmsh's, bench_constrained: 22.50), so no edges
    are traded for the angle."""
    p = uniform2d.read_polygon(Path(__file__).resolve().parents[1] / "data" / "constrained"
                               / "plate_zones.json")
    m = uniform2d.uniform_mesh(p, 300)
    piece = 2 * 20 * np.sin(np.radians(7.5))
    h = target_size(p, 300)
    forced = np.degrees(2 * np.arcsin(piece / (piece + h)))
    assert 24.0 < forced < 24.5
    assert np.isclose(forced_angle(p, m.points, m.triangles), forced, rtol=1e-6)
    assert m.info["angle_first_fits"] == 0
    assert m.quality().min_angle > forced > 22.50
