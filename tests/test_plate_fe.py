"""The measuring code of benchmarks/plate_fe.py (bench_graded's bolt plate) gives known answers."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

import uniform2d
from uniform2d.testing import check_mesh

pytest.importorskip("skfem")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import plate_fe  # noqa: E402


@pytest.fixture(scope="module")
def plate():
    return plate_fe.plate()


def _mesh(plate, vertices, field=None):
    m = uniform2d.uniform_mesh(plate, vertices - len(plate.vertices), size=field)
    check_mesh(m.points, m.triangles, plate, n_steiner=vertices - len(plate.vertices))
    return m


def test_fast_field_is_the_same_floats(plate):
    base = uniform2d.refine(plate, "holes", ratio=0.2, rate=0.4)
    fast = plate_fe.FastField(base)
    rng = np.random.default_rng(3)
    pts = rng.uniform([-20.0, -20.0], [420.0, 270.0], size=(3000, 2))  # outside too: clamped
    one_by_one = np.array([fast(p[None])[0] for p in pts])
    assert np.array_equal(one_by_one, base(pts))
    assert isinstance(fast(pts[:1]), np.ndarray) and fast(pts[:1]).shape == (1,)
    assert np.array_equal(fast(pts), base(pts))


def test_strain_of_a_quadratic_displacement_is_exact(plate):
    """u = (x^2, x y) is in the P2 space: its strain (2x, x, y / 2) comes out at any point."""
    from skfem import Basis, ElementTriP2, ElementVector, MeshTri

    m = _mesh(plate, 400)
    mesh = MeshTri(m.points.T.copy(), m.triangles.T.copy())
    basis = Basis(mesh, ElementVector(ElementTriP2()), intorder=4)
    u = basis.project(lambda x: np.array([x[0] ** 2, x[0] * x[1]]))
    sol = plate_fe.Solution(basis, u, 0.0)
    shape = shapely.Polygon(plate.outer, plate.holes)
    xy = np.array([p.coords[0] for p in shapely.points(
        np.random.default_rng(5).uniform([0, 0], [400, 250], (2000, 2)))
        if shape.contains(p)]).T
    got = plate_fe._coarse_strain_at(sol, xy)
    want = np.array([2 * xy[0], xy[0], xy[1] / 2])
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * 400)


def test_local_error_sums_to_the_energy_difference(plate):
    """Galerkin orthogonality: ||u - u_h||^2 = a(u) - a(u_h), nearly so with the reference
    (refined where u is singular) for u; a solution against itself has no error."""
    fine = _mesh(plate, 10000, plate_fe.reference_field(plate))
    coarse = _mesh(plate, 800)
    ref = plate_fe.solve(fine.points, fine.triangles)
    sol = plate_fe.solve(coarse.points, coarse.triangles)
    assert sol.energy < ref.energy
    split = plate_fe.local_error(plate, ref, sol)
    assert split.shape == (3,) and np.all(split > 0)
    assert split.sum() == pytest.approx((ref.energy - sol.energy) / ref.energy, rel=0.05)
    assert np.all(plate_fe.local_error(plate, sol, sol) < 1e-20)


def test_hole_vertices_counts_the_rings(plate):
    m = _mesh(plate, 1000)
    on, near = plate_fe.hole_vertices(plate, m.points, m.triangles)
    rings = shapely.MultiLineString([np.vstack([h, h[:1]]) for h in plate.holes])
    d = shapely.distance(shapely.points(m.points), rings)
    assert on == int(np.sum(d < 1e-9)) and on >= sum(len(h) for h in plate.holes)
    assert near == int(np.sum(d <= plate_fe.NEAR))


def test_corner_refined_field_is_the_minimum_of_the_two(plate):
    """hole_field with corners: on its grid's nodes the smaller of the holes' field and the
    corners' one (between nodes, bilinear), finer at the clamped corners."""
    holes = uniform2d.refine(plate, "holes", ratio=0.25, rate=0.3)
    corners = uniform2d.refine(plate, plate_fe.CLAMPED_CORNERS, ratio=0.05, rate=0.3)
    both = plate_fe.hole_field(plate, 0.25, 0.3, 0.05)
    gx, gy = np.meshgrid(both.x, both.y)
    nodes = np.column_stack([gx.ravel(), gy.ravel()])
    np.testing.assert_allclose(both(nodes), np.minimum(holes(nodes), corners(nodes)),
                               rtol=1e-12)
    at = both(plate_fe.CLAMPED_CORNERS)
    assert np.all(at < holes(plate_fe.CLAMPED_CORNERS) / 2)
    pts = np.random.default_rng(7).uniform([0.0, 0.0], [400.0, 250.0], size=(4000, 2))
    assert np.array_equal(plate_fe.hole_field(plate, 0.25, 0.3)(pts), holes(pts))


def test_choose_takes_the_smallest_gmsh_geometric_mean():
    """The principle looks at Gmsh's errors only: ours never changes the choice."""
    def row(ours, gmsh):
        return {"ours": (0, ours, None, None), "gmsh": (0, gmsh, None, None)}

    table = {("a",): {2000: row(0.001, 0.010), 8000: row(0.001, 0.004)},  # product 4e-5
             ("b",): {2000: row(0.100, 0.008), 8000: row(0.100, 0.0045)}}  # product 3.6e-5
    assert plate_fe.choose(table) == ("b",)
