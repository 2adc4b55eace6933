"""Tests of surface.models: every example model has the topology it claims.

Checked twice: with :func:`surface.models.model_facts` (numpy/scipy) and with
trimesh's own watertightness, Euler number, winding and volume.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("igl")
pytest.importorskip("pymeshlab")
trimesh = pytest.importorskip("trimesh")

from surface import models  # noqa: E402
from surface.model_facts import model_facts  # noqa: E402
from surface.models import MODELS  # noqa: E402
from uniform2d.errors import InvalidArgumentError  # noqa: E402

# name: (components, euler, boundary loops, genus per component)
EXPECTED = {
    "sphere": (1, 2, 0, [0]),
    "capsule": (1, 2, 0, [0]),
    "tank": (1, 2, 0, [0]),
    "box": (1, 2, 0, [0]),
    "torus": (1, 0, 0, [1]),
    "two_hole_plate": (1, -2, 0, [2]),
    "two_bodies": (2, 4, 0, [0, 0]),
    "pierced_sphere": (1, 1, 1, [0]),
    "open_with_holes": (1, 0, 2, [0]),
}

# name: a finer resolution than the default, to test the parameter too
FINER = {
    "sphere": {"subdivisions": 5},
    "capsule": {"segments": 64},
    "tank": {"segments": 64},
    "box": {"extents": (2.0, 1.0, 0.5), "divisions": 24},
    "torus": {"segments": 32},
    "two_hole_plate": {"voxels": 15},
    "two_bodies": {"subdivisions": 4, "divisions": 16},
    "pierced_sphere": {"subdivisions": 5},
    "open_with_holes": {"segments": 128, "hole_angle": 45.0},
}


def test_every_model_is_listed():
    assert set(MODELS) == set(EXPECTED) == set(FINER)
    assert set(MODELS) <= set(models.__all__)


@pytest.mark.parametrize("fine", [False, True], ids=["default", "finer"])
@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_topology(name, fine):
    V, F = MODELS[name](**(FINER[name] if fine else {}))
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert F.dtype == np.int64 and F.ndim == 2 and F.shape[1] == 3
    assert np.all(np.isfinite(V))
    assert 1000 <= len(F) <= 30000
    comps, euler, loops, genus = EXPECTED[name]
    f = model_facts(V, F)
    assert (f["components"], f["euler"], f["boundary_loops"], f["genus"]) == (
        comps, euler, loops, genus
    )
    assert f["watertight"] == (loops == 0)
    assert f["manifold_edges"] and f["oriented"]
    assert f["degenerate_faces"] == 0 and f["unused_vertices"] == 0


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_trimesh_agrees(name):
    V, F = MODELS[name]()
    comps, euler, loops, _ = EXPECTED[name]
    m = trimesh.Trimesh(V, F, process=False)
    assert m.is_watertight == (loops == 0)
    assert m.euler_number == euler
    assert m.is_winding_consistent
    assert m.body_count == comps
    assert m.area_faces.min() > 1e-6 * m.area_faces.mean()  # no degenerate face
    assert len(trimesh.grouping.unique_rows(V, digits=9)[0]) == len(V)  # no duplicates


@pytest.mark.parametrize("name", sorted(n for n, e in EXPECTED.items() if e[2] == 0))
def test_closed_models_point_outward(name):
    V, F = MODELS[name]()
    assert all(v > 0 for v in model_facts(V, F)["volume"])
    for part in trimesh.Trimesh(V, F, process=False).split(only_watertight=False):
        assert part.is_volume and part.volume > 0


@pytest.mark.parametrize("name", ["pierced_sphere", "open_with_holes"])
def test_open_models_point_away_from_centre(name):
    V, F = MODELS[name]()
    m = trimesh.Trimesh(V, F, process=False)
    assert np.all(np.einsum("ij,ij->i", m.face_normals, m.triangles_center) > 0)


def test_vertices_on_their_surfaces():
    V, _ = models.sphere(radius=2.0)
    assert np.allclose(np.linalg.norm(V, axis=1), 2.0)
    V, _ = models.torus(major_radius=1.0, minor_radius=0.3)
    rho = np.hypot(V[:, 0], V[:, 1])
    assert np.allclose(np.hypot(rho - 1.0, V[:, 2]), 0.3)
    V, _ = models.box(extents=(2.0, 1.0, 0.5))
    assert np.allclose(np.abs(V).max(axis=0), [1.0, 0.5, 0.25])
    assert np.all(np.isclose(np.abs(V), [1.0, 0.5, 0.25]).any(axis=1))
    V, _ = models.tank(radius=0.5, height=1.0)
    assert np.all(np.isclose(np.hypot(V[:, 0], V[:, 1]), 0.5) | np.isclose(np.abs(V[:, 2]), 0.5))
    V, _ = models.capsule(radius=0.5, length=1.0)
    axis_point = np.column_stack([0 * V[:, 0], 0 * V[:, 0], np.clip(V[:, 2], -0.5, 0.5)])
    assert np.allclose(np.linalg.norm(V - axis_point, axis=1), 0.5)


def test_creases_where_claimed():
    for name, n_sharp in (("box", 12 * 16), ("tank", 2 * 48), ("sphere", 0), ("capsule", 0)):
        m = trimesh.Trimesh(*MODELS[name](), process=False)
        sharp = np.count_nonzero(m.face_adjacency_angles > math.radians(30))
        assert sharp == n_sharp, name


def test_deterministic():
    for f in MODELS.values():
        (V1, F1), (V2, F2) = f(), f()
        assert np.array_equal(V1, V2) and np.array_equal(F1, F2)


@pytest.mark.parametrize(
    "call",
    [
        lambda: models.sphere(radius=-1.0),
        lambda: models.sphere(radius=float("nan")),
        lambda: models.sphere(subdivisions=1.5),
        lambda: models.sphere(subdivisions=9),
        lambda: models.capsule(segments=2),
        lambda: models.tank(height=0),
        lambda: models.box(extents=(1.0, 2.0)),
        lambda: models.box(divisions=True),
        lambda: models.torus(major_radius=1.0, minor_radius=1.0),
        lambda: models.two_hole_plate(voxels=7),
        lambda: models.two_bodies(gap="1"),
        lambda: models.open_with_holes(hole_angle=90),
    ],
)
def test_bad_arguments(call):
    with pytest.raises(InvalidArgumentError):
        call()


def test_facts_of_bad_meshes():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], float)
    fan = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # edge 0-1 in three faces
    assert not model_facts(V, fan)["manifold_edges"]
    flipped = np.array([[0, 1, 2], [0, 1, 3]])  # edge 0-1 used the same way twice
    f = model_facts(V, flipped)
    assert not f["oriented"] and f["boundary_loops"] == 1 and f["unused_vertices"] == 1
    flat = np.array([[0, 1, 1], [0, 1, 2]])
    assert model_facts(V, flat)["degenerate_faces"] == 1


@pytest.mark.parametrize(
    "V, F",
    [
        (np.zeros((3, 2)), [[0, 1, 2]]),
        (np.zeros((3, 3)), np.zeros((0, 3), int)),
        (np.zeros((3, 3)), [[0, 1, 3]]),
        (np.zeros((3, 3)), [[0.0, 1.0, 2.0]]),
    ],
)
def test_facts_refuse_bad_arrays(V, F):
    with pytest.raises(InvalidArgumentError):
        model_facts(V, F)


def test_facts_of_two_open_parts():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    f = model_facts(V, [[0, 1, 2], [3, 4, 5]])
    assert f["components"] == 2 and f["boundary_loops"] == 2
    assert f["boundary_loops_per_component"] == [1, 1] and f["euler_per_component"] == [1, 1]
    assert f["genus"] == [0, 0] and not f["watertight"]
