"""Whole models remeshed as an atlas of charts: topology, exact counts, conforming
seams, creases, identical bytes in parallel, and the refusals.

Every property is checked against references independent of the atlas: trimesh's
own topology and watertightness, libigl's point-to-mesh distances, and the
input's exact geometry (a box's edges, a sphere's radius)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("igl")
pytest.importorskip("pymeshlab")
trimesh = pytest.importorskip("trimesh")

import surface  # noqa: E402
from hypothesis import given, settings, strategies as st  # noqa: E402
from surface import _igl  # noqa: E402
from surface.atlas import build_atlas  # noqa: E402
from surface.errors import RemeshQualityError  # noqa: E402
from surface.model import Model  # noqa: E402
from surface.seams import _equal_chords  # noqa: E402
from uniform2d.errors import InsufficientPointsError  # noqa: E402
from uniform2d.parts import allocate, stitch  # noqa: E402


def sphere(sub=4):
    s = trimesh.creation.icosphere(sub)
    return np.asarray(s.vertices), np.asarray(s.faces)


def torus():
    t = trimesh.creation.torus(1.0, 0.35, major_sections=64, minor_sections=24)
    return np.asarray(t.vertices), np.asarray(t.faces)


def box():
    b = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    for _ in range(4):
        b = b.subdivide()
    return np.asarray(b.vertices), np.asarray(b.faces)


def two_bodies():
    a = trimesh.creation.icosphere(3)
    b = trimesh.creation.icosphere(3)
    b.vertices = b.vertices * 0.5 + [3.0, 0.0, 0.0]
    m = trimesh.util.concatenate([a, b])
    return np.asarray(m.vertices), np.asarray(m.faces)


def pierced():
    V, F = sphere()
    return V, F[1:]


def band():
    """An open sphere band between two latitudes: one component, two boundary loops."""
    s = trimesh.creation.uv_sphere(count=[48, 96])
    V, F = np.asarray(s.vertices), np.asarray(s.faces)
    z = V[F].mean(axis=1)[:, 2]
    keep = F[np.abs(z) < 0.6]
    used, inv = np.unique(keep, return_inverse=True)
    return V[used], inv.reshape(-1, 3)


def facts(V, F) -> dict:
    """Topology by trimesh (independent of surface.Model)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    m = trimesh.Trimesh(V, F, process=False)
    adj = np.asarray(m.face_adjacency).reshape(-1, 2)
    g = coo_matrix((np.ones(len(adj)), (adj[:, 0], adj[:, 1])), shape=(len(F), len(F)))
    bodies = connected_components(g, directed=False)[0]
    return {"euler": int(m.euler_number), "bodies": int(bodies), "watertight": bool(m.is_watertight),
            "winding": bool(m.is_winding_consistent)}


CASES = {
    "sphere": (sphere, 800, 0),
    "torus": (torus, 800, 1),
    "two_bodies": (two_bodies, 900, 0),
    "pierced": (pierced, 800, 0),
    "band": (band, 700, 0),
}


@pytest.fixture(scope="module")
def results():
    out = {}
    for name, (make, n, _) in CASES.items():
        V, F = make()
        out[name] = (V, F, surface.remesh((V, F), n, check=True, hausdorff=False))
    return out


@pytest.mark.parametrize("name", sorted(CASES))
def test_exact_count_and_topology(results, name):
    V, F, r = results[name]
    assert len(r.vertices) == CASES[name][1]
    assert facts(r.vertices, r.faces) == facts(V, F)
    assert r.atlas is not None and r.report.atlas["n_charts"] == len(r.atlas.charts)


@pytest.mark.parametrize("name", sorted(CASES))
def test_on_the_surface_and_uniform(results, name):
    V, F, r = results[name]
    d2, _, _ = _igl.closest_points(r.vertices, V, F)
    diag = np.linalg.norm(np.ptp(V, axis=0))
    assert np.sqrt(d2.max()) <= 1e-9 * diag
    e = r.report.edges
    # far from the 1000-fold ratios of a bad flattening; the pierced sphere keeps
    # the input's own hole, whose edges are half the spacing
    assert e["ratio"] <= (3.6 if name == "pierced" else 2.2) and e["angle_min"] >= 20.0
    assert e["cv"] <= 0.1


def test_seams_conforming_and_shared(results):
    """Every seam point is a vertex of the triangles of both charts meeting there,
    and no other output vertex lies on a seam chain's segments."""
    _, _, r = results["sphere"]
    S = r.atlas.seams
    assert facts(r.vertices, r.faces)["watertight"]
    used = np.zeros(len(r.vertices), dtype=bool)
    used[r.faces.ravel()] = True
    assert used[: S.n_points].all()
    # each chart's ring is the same seam points its neighbours use, in reverse
    rings = [tuple(ring.tolist()) for rs in S.rings for ring in rs]
    assert sum(len(x) for x in rings) >= 2 * (S.n_points - S.n_nodes)


def test_seam_relaxation_helps(results):
    for name in ("sphere", "torus"):
        a = results[name][2].report.atlas
        assert a["seams"]["cv_near_seams"] < a["seams_before_relax"]["cv_near_seams"]


def test_pierced_sphere_is_an_atlas_not_a_spoilt_patch(results):
    V, F, r = results["pierced"]
    assert r.uv is None and len(r.atlas.charts) >= 2
    assert r.report.edges["ratio"] < 4.0


def test_genus_and_components_of_model():
    m = Model(*torus())
    assert m.genus == (1,) and m.is_closed and m.as_patch() is None
    m = Model(*two_bodies())
    assert m.n_components == 2 and m.genus == (0, 0)
    m = Model(*band())
    assert m.loops_per_component == (2,) and m.is_disk


def test_box_creases_kept():
    V, F = box()
    r = surface.remesh((V, F), 1000, feature_angle=30, check=False, hausdorff=False)
    assert len(r.vertices) == 1000 and facts(r.vertices, r.faces) == facts(V, F)
    assert len(r.atlas.charts) == 6
    h = r.report.edges["mean"]
    # points along the box's 12 edges lie on the output (to 0.02 h)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    pts = []
    for i in range(8):
        for j in range(i + 1, 8):
            if np.count_nonzero(corners[i] != corners[j]) == 1:
                t = np.linspace(0, 1, 41)[:, None]
                pts.append((1 - t) * corners[i] + t * corners[j])
    d2, _, _ = _igl.closest_points(np.concatenate(pts), r.vertices, r.faces)
    assert np.sqrt(d2.max()) <= 0.02 * h
    # and every output vertex lies on a face of the box
    assert np.isclose(np.abs(r.vertices / [1, 0.5, 0.5]).max(axis=1), 1.0, atol=1e-12).all()


def test_jobs_give_identical_bytes():
    V, F = torus()
    a = surface.remesh((V, F), 600, check=False, hausdorff=False)
    b = surface.remesh((V, F), 600, check=False, hausdorff=False, jobs=2)
    assert a.vertices.tobytes() == b.vertices.tobytes() and a.faces.tobytes() == b.faces.tobytes()


def test_count_too_small_and_quality_gate():
    V, F = sphere()
    with pytest.raises(InsufficientPointsError) as info:
        surface.remesh((V, F), 3, check=False, hausdorff=False)
    assert "ask for more vertices" in str(info.value)
    # one face removed from a fine sphere, remeshed coarsely: the input's hole has
    # edges far shorter than the spacing, which the library refuses to hide
    V, F = sphere(5)
    with pytest.raises(RemeshQualityError) as info:
        surface.remesh((V, F[1:]), 150, check=False, hausdorff=False)
    assert "edge ratio" in str(info.value) and "more vertices" in str(info.value)


def test_atlas_charts_within_the_distortion_bound():
    V, F = sphere()
    m = Model(V, F)
    atlas = build_atlas(m, 0.1)
    from surface.charts import MAX_AREA_SCALE_RATIO

    assert all(c.area_scale_ratio <= MAX_AREA_SCALE_RATIO for c in atlas.charts)
    covered = np.sort(np.concatenate([c.faces for c in atlas.charts]))
    assert np.array_equal(covered, np.arange(len(F)))


def test_equal_chords_on_a_zigzag():
    k = np.arange(41)
    X = np.column_stack([k * 0.1, 0.05 * (k % 2), np.zeros(41)])
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=1))])
    s = _equal_chords(X, cum, 7)
    pts = np.array([np.interp(x, cum, X[:, 0]) for x in s]), np.array([np.interp(x, cum, X[:, 1]) for x in s])
    chords = np.hypot(np.diff(pts[0]), np.diff(pts[1]))
    assert np.ptp(chords) <= 1e-8 * chords.mean() and s[0] == 0.0 and s[-1] == cum[-1]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 1e6), min_size=1, max_size=12).filter(lambda w: sum(w) > 0),
       st.integers(0, 100000))
def test_allocate_exact_and_proportional(w, total):
    out = allocate(w, total)
    assert out.sum() == total and (out >= 0).all()
    exact = np.asarray(w) * total / sum(w)
    assert np.all(np.abs(out - exact) < 1.0 + 1e-9)


def test_stitch_numbers_shared_points_once():
    shared = np.zeros((3, 3))
    a = (np.array([0, 1, 2]), np.ones((2, 3)), np.array([[0, 3, 1], [1, 4, 2]]))
    b = (np.array([2, 1]), np.full((1, 3), 2.0), np.array([[0, 1, 2]]))
    P, T = stitch(shared, [a, b])
    assert len(P) == 6 and T.tolist() == [[0, 3, 1], [1, 4, 2], [2, 1, 5]]


def test_remesh_command_on_a_closed_model(tmp_path):
    V, F = torus()
    src = tmp_path / "torus.obj"
    surface.write_patch(src, V, F)
    outs = []
    for jobs in ("1", "2"):
        dst = tmp_path / f"out{jobs}.obj"
        cmd = [sys.executable, "-m", "uniform2d.cli.main", "remesh", str(src), "-n", "500",
               "-o", str(dst), "--jobs", jobs, "-q"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        outs.append(dst.read_bytes())
    assert outs[0] == outs[1]
    m = trimesh.load(tmp_path / "out1.obj", process=False)
    assert len(m.vertices) == 500 and m.is_watertight and m.euler_number == 0


def test_genus_two_and_open_with_holes_from_the_example_models():
    from surface import models
    from surface.model_facts import model_facts

    for make, n in ((models.two_hole_plate, 900), (models.open_with_holes, 700),
                    (models.capsule, 700), (models.tank, 700)):
        V, F = make()
        r = surface.remesh((V, F), n, feature_angle=30, check=False, hausdorff=False)
        assert len(r.vertices) == n and facts(r.vertices, r.faces) == facts(V, F)
        ref = model_facts(V, F)
        out = model_facts(r.vertices, r.faces)
        assert out["genus"] == ref["genus"] and out["boundary_loops"] == ref["boundary_loops"]
        assert r.report.edges["ratio"] <= 2.5 and r.report.edges["angle_min"] >= 25.0


def test_dask_scheduler_gives_identical_bytes():
    distributed = pytest.importorskip("distributed")
    V, F = torus()
    a = surface.remesh((V, F), 500, check=False, hausdorff=False)
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=1,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        b = surface.remesh((V, F), 500, check=False, hausdorff=False, scheduler=client)
    assert a.vertices.tobytes() == b.vertices.tobytes() and a.faces.tobytes() == b.faces.tobytes()


@pytest.mark.parametrize("scale, offset", [(1e-6, 0.0), (1e6, 0.0), (1.0, 1e4)])
def test_scale_and_translation_invariant(scale, offset):
    """The same model at another scale or far from the origin: the same count and
    topology, and edge measures within a few percent of the unit model's."""
    V, F = torus()
    ref = surface.remesh((V, F), 600, check=False, hausdorff=False).report.edges
    W = V * scale + offset
    r = surface.remesh((W, F), 600, check=False, hausdorff=False)
    assert len(r.vertices) == 600 and facts(r.vertices, r.faces) == facts(W, F)
    e = r.report.edges
    assert abs(e["ratio"] / ref["ratio"] - 1) < 0.05 and abs(e["cv"] / ref["cv"] - 1) < 0.1
    assert abs(e["mean"] / (ref["mean"] * scale) - 1) < 0.01


def test_atlas_refuses_what_it_cannot_keep():
    V, F = torus()
    with pytest.raises(surface.InvalidPatchError.__mro__[1], match="fixed vertices"):
        surface.remesh((V, F), 500, fixed=[0], check=False, hausdorff=False)
    with pytest.raises(surface.InvalidPatchError.__mro__[1], match="optimize=False"):
        surface.remesh((V, F), 500, optimize=False, check=False, hausdorff=False)


def test_remesh_command_refuses_a_count_below_the_seams(tmp_path, capsys):
    from uniform2d.cli.main import main

    V, F = torus()
    src, dst = tmp_path / "torus.obj", tmp_path / "out.obj"
    surface.write_patch(src, V, F)
    code = main(["remesh", str(src), "-n", "5", "-o", str(dst)])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "ask for more vertices" in lines[0]
    assert not dst.exists() and sorted(x.name for x in tmp_path.iterdir()) == ["torus.obj"]
