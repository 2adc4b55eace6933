"""Graded meshes with resampled rings (uniform_mesh(..., size=field, resample=tol),
uniform2d.graded_outline): exactly n, the tolerance held against the local spacing
(shapely's distances, independent of the resampler's own), valid meshes, boundary
edges following h on the bolt plate's polygonal holes, and the command."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely

import uniform2d as u
from uniform2d.cli.main import main
from uniform2d.errors import InsufficientPointsError
from uniform2d.refine import refine
from uniform2d.testing import check_mesh

DATA = Path(__file__).resolve().parents[1] / "data"
TOL = 0.25


def wiggly_disk(k=3000, amp=0.0005, seed=0):
    """A dense circle of radius 1 with digitising noise of ``amp``, and a square hole."""
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    r = 1 + amp * np.random.default_rng(seed).standard_normal(k)
    hole = [(-0.2, -0.2), (-0.2, 0.2), (0.2, 0.2), (0.2, -0.2)]
    return u.Polygon(np.c_[r * np.cos(t), r * np.sin(t)], [hole])


def graded(p):
    return 0.05 + 0.15 * np.hypot(p[:, 0] - 1, p[:, 1])  # fine near (1, 0)


def checked(mesh, n):
    """The mesh valid, n points beyond the kept input vertices, and the kept count."""
    r = mesh.info["resample"]
    check_mesh(mesh.points, mesh.triangles, mesh.polygon, n_steiner=mesh.n_steiner)
    assert r["n"] == n and r["resampled"]
    assert len(mesh.points) == n + r["kept_vertices"]
    assert mesh.n_steiner + r["boundary_points"] == n
    assert mesh.info["method"] == "graded"
    return r


@pytest.mark.parametrize("n", [150, 400, 1000])
def test_exact_n_and_tolerance_against_local_spacing(n):
    p = wiggly_disk()
    m = u.uniform_mesh(p, n, size=graded, resample=TOL)
    checked(m, n)
    q = m.polygon
    assert np.array_equal(q.rings[1], p.rings[1])  # the hole's corners kept, its edges whole
    for ra, rb in zip(p.rings, q.rings):
        a, b = shapely.LinearRing(ra), shapely.LinearRing(rb)
        # per point against the local spacing s h there: input vertices from the rings,
        # and the rings' points from the input outline
        assert np.all(shapely.distance(b, shapely.points(ra)) <= TOL * m.size(ra))
        assert np.all(shapely.distance(a, shapely.points(rb)) <= TOL * m.size(rb))
        # both ways, densified, against the largest local spacing on the ring
        hmax = float(m.size(np.concatenate([ra, rb])).max())
        assert shapely.hausdorff_distance(a, b, densify=0.1) <= TOL * hmax
    # the outer ring follows h: more boundary points near (1, 0), where h is finest
    outer = q.rings[0]
    right = int((outer[:, 0] > 0.5).sum())
    left = int((outer[:, 0] < -0.5).sum())
    assert right > 2 * left


def test_polygonal_holes_resampled_at_the_local_spacing():
    """The bolt plate's 24-gon holes have edges about 1.1 local spacings long, which
    the graded path cannot split: resampled, the hole edges follow h."""
    plate = u.read_polygon(DATA / "plate_bolts.json")
    h = refine(plate, "holes", ratio=0.25)
    holes = shapely.MultiPolygon([shapely.Polygon(r) for r in plate.rings[1:]])

    def hole_q(m):
        T = m.triangles  # the mesh's boundary edges on the holes
        e = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
        e, c = np.unique(e, axis=0, return_counts=True)
        e = e[c == 1]
        a, b = m.points[e[:, 0]], m.points[e[:, 1]]
        mid = (a + b) / 2
        on = shapely.distance(holes, shapely.points(mid)) <= TOL * m.size(mid)
        assert on.sum() >= 6 * 20
        return np.hypot(*(b - a)[on].T) / m.size(mid[on])

    n = 2000 - len(plate.vertices)  # 2000 vertices without resampling
    plain = u.uniform_mesh(plate, n, size=h)
    res = u.uniform_mesh(plate, n, size=h, resample=TOL)
    checked(res, n)
    q0, q1 = hole_q(plain), hole_q(res)
    assert q1.max() / q1.min() < q0.max() / q0.min()
    assert abs(q1.mean() - 1) < abs(q0.mean() - 1)


def test_too_few_points_refused():
    with pytest.raises(InsufficientPointsError, match="resampled"):
        u.uniform_mesh(wiggly_disk(), 5, size=graded, resample=TOL)


def test_cli_refine_and_resample(tmp_path, capsys):
    src = DATA / "plate_bolts.json"
    out = tmp_path / "m.vtu"
    code = main(["mesh", str(src), "-n", "300", "--refine", "holes:0.25", "--resample", "0.25",
                 "-o", str(out), "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc["n_steiner"] == 300 and doc["info"]["method"] == "graded"
    kept = doc["info"]["resample"]["kept_vertices"]
    pts = u.read_mesh(out)[0]
    assert len(pts) == 300 + kept == doc["n_points"]


def test_constraints_kept():
    """A segment from a ring vertex and a fixed point: the ring vertex stays, the
    segment is a chain of mesh edges, the fixed point a mesh point."""
    p = wiggly_disk()
    ring = p.rings[0]
    q = u.Polygon(ring, [p.rings[1]], segments=[[ring[0], (0.5, 0.0)]], points=[(-0.5, 0.5)])
    m = u.uniform_mesh(q, 400, size=graded, resample=TOL)
    checked(m, 400)
    for pt in (ring[0], (0.5, 0.0), (-0.5, 0.5)):
        assert np.any(np.all(m.points == np.asarray(pt), axis=1))


def test_deterministic():
    p = wiggly_disk()
    a = u.uniform_mesh(p, 150, size=graded, resample=TOL)
    b = u.uniform_mesh(p, 150, size=graded, resample=TOL)
    assert a.points.tobytes() == b.points.tobytes()
    assert a.triangles.tobytes() == b.triangles.tobytes()
