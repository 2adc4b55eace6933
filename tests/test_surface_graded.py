"""surface.remesh with a graded 3-D size (size= a callable on (k, 3) points): exact
counts, edges that follow the size (q = 3-D length / size at the midpoint, measured
here from the output with trimesh's own edges), the count integral and scale search,
closed models through the atlas, and the bad sizes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("igl")
trimesh = pytest.importorskip("trimesh")

import surface  # noqa: E402
from surface import _igl  # noqa: E402
from surface.size3d import Size3D, count_for_size, integrals, scale_for_count  # noqa: E402
from uniform2d.errors import InvalidArgumentError, Uniform2dError  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "data"


def along(path, k=3.0):
    """A size growing (1 + k)-fold along the longest axis of the model at ``path``."""
    V = trimesh.load(path, process=False).vertices
    lo, hi = V.min(axis=0), V.max(axis=0)
    ax = int(np.argmax(hi - lo))
    return lambda p: 1.0 + k * (p[:, ax] - lo[ax]) / (hi[ax] - lo[ax])


def q_of(vertices, faces, h):
    """q of every edge, from trimesh's unique edges (independent of surface.measure)."""
    m = trimesh.Trimesh(vertices, faces, process=False)
    e = m.edges_unique
    a, b = m.vertices[e[:, 0]], m.vertices[e[:, 1]]
    return np.linalg.norm(b - a, axis=1) / h(0.5 * (a + b))


def on_input(res, path):
    src = trimesh.load(path, process=False)
    d2, _, _ = _igl.closest_points(res.vertices, np.asarray(src.vertices), np.asarray(src.faces))
    return float(np.sqrt(d2.max())) / float(np.linalg.norm(src.extents))


@pytest.mark.parametrize("name,n", [("cap60", 900), ("plate_hole", 700)])
def test_patch_exact_n_and_follows_h(name, n):
    path = DATA / "patches" / f"{name}.obj"
    h = along(path)
    res = surface.remesh(path, n, size=h, check=False, hausdorff=False)
    assert len(res.vertices) == n
    q = q_of(res.vertices, res.faces, h)
    cv = q.std() / q.mean()
    assert cv < 0.12
    # the report's scale-free figures are the same q's
    assert res.report.edges["q_cv"] == pytest.approx(cv, rel=1e-9)
    assert res.report.edges["q_ratio"] == pytest.approx(q.max() / q.min(), rel=1e-9)
    # and the mesh is graded: the same count made uniform has a far larger spread of q
    uni = surface.remesh(path, n, check=False, hausdorff=False)
    qu = q_of(uni.vertices, uni.faces, h)
    assert qu.std() / qu.mean() > 2.5 * cv
    assert on_input(res, path) < 1e-3
    assert "q ratio" in res.report.summary()
    # the boundary is spaced by equal ∫ ds / h: its edges have about the mesh's q
    m = trimesh.Trimesh(res.vertices, res.faces, process=False)
    be = m.edges[trimesh.grouping.group_rows(m.edges_sorted, require_count=1)]
    a, b = res.vertices[be[:, 0]], res.vertices[be[:, 1]]
    qb = np.linalg.norm(b - a, axis=1) / h(0.5 * (a + b))
    assert qb.std() / qb.mean() < 0.1
    assert 0.85 < qb.mean() / q.mean() < 1.15


def test_closed_model_atlas_exact_n():
    path = DATA / "models" / "torus.obj"
    h = along(path)
    res = surface.remesh(path, 1500, size=h, check=False, hausdorff=False)
    assert len(res.vertices) == 1500
    out = trimesh.Trimesh(res.vertices, res.faces, process=False)
    src = trimesh.load(path, process=False)
    assert out.is_watertight and out.euler_number == src.euler_number
    q = q_of(res.vertices, res.faces, h)
    assert q.std() / q.mean() < 0.12
    assert res.atlas is not None and "graded" in res.report.mesher
    assert on_input(res, path) < 1e-3
    # the seams are sampled by equal ∫ ds / h: their pieces (relaxed, in the output)
    # have about the mesh's q
    X = res.vertices
    qs = np.concatenate([np.linalg.norm(np.diff(X[c], axis=0), axis=1)
                         / h(0.5 * (X[c[1:]] + X[c[:-1]])) for c in res.atlas.seams.chains])
    assert qs.std() / qs.mean() < 0.12
    assert 0.85 < qs.mean() / q.mean() < 1.15


def test_absolute_size_gives_its_count():
    path = DATA / "patches" / "cap60.obj"
    src = trimesh.load(path, process=False)
    ext = float(np.linalg.norm(src.extents))
    g = along(path)

    def h(p):
        return 0.02 * ext * g(p)

    res = surface.remesh(path, size=h, check=False, hausdorff=False)
    M = surface.Model(np.asarray(src.vertices), np.asarray(src.faces))
    ia, ib = integrals(M.vertices, M.faces, M.boundary_loops, Size3D(h))
    assert len(res.vertices) == count_for_size(M.euler_characteristic, ia, ib)
    q = q_of(res.vertices, res.faces, h)
    assert 0.9 < q.mean() < 1.15  # h absolute: edges about h long


def test_integrals_and_scale_search():
    # a unit square in the plane z = 0, h = 0.1 (1 + x): I_A = ∫ 1/h² dA / (√3/2)
    n = 41
    x = np.linspace(0.0, 1.0, n)
    X, Y = np.meshgrid(x, x)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    loop = np.concatenate([idx[0, :], idx[1:, -1], idx[-1, -2::-1], idx[-2:0:-1, 0]])
    h = Size3D(lambda p: 0.1 * (1.0 + p[:, 0]))
    ia, ib = integrals(V, F, [loop], h)
    assert ia == pytest.approx(100 * 0.5 / (np.sqrt(3) / 2), rel=1e-3)  # ∫ 1/(1+x)² dx = 1/2
    assert ib == pytest.approx(10 * (np.log(2) * 2 + 1 + 0.5) / 2, rel=1e-3)
    for N in (10, 137, 5000):
        s = scale_for_count(N, 1, ia, ib)
        assert ia / s**2 + ib / s == pytest.approx(N - 1, rel=1e-12)


@pytest.mark.parametrize("bad,where", [
    (lambda p: np.where(p[:, 0] > p[:, 0].min(), 1.0, np.nan), "nan"),
    (lambda p: 1.0 - 2.0 * (p[:, 0] > np.median(p[:, 0])), "-1.0"),
    (lambda p: 1.0 / 0 + p[:, 0], "ZeroDivisionError"),
    (lambda p: np.ones(3), "one size per point"),
])
def test_bad_size_is_a_typed_error(bad, where):
    path = DATA / "patches" / "cap60.obj"
    with pytest.raises(InvalidArgumentError, match=where) as exc:
        surface.remesh(path, 300, size=bad, check=False, hausdorff=False)
    assert isinstance(exc.value, Uniform2dError)


def test_graded_refusals():
    path = DATA / "patches" / "cap60.obj"
    h = along(path)
    with pytest.raises(InvalidArgumentError, match="compensate"):
        surface.remesh(path, 300, size=h, compensate=False, check=False, hausdorff=False)
    with pytest.raises(InvalidArgumentError, match="feature lines"):
        surface.remesh(path, 300, size=h, fixed=[0], check=False, hausdorff=False)
    with pytest.raises(InvalidArgumentError, match="callable"):
        surface.remesh(path, size="fine", check=False, hausdorff=False)


def test_points_on_a_chart_ring_are_pulled_inside():
    from surface.chart_mesh import _pull_inside
    from uniform2d import Polygon

    sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    seed = np.array([[0.5, 0.0], [0.5, 0.4], [0.2, 0.7]])
    out, fixed = _pull_inside(sq, seed, np.array([True, False, False]))
    assert out.tolist() == [[0.5, 0.2], [0.5, 0.4], [0.2, 0.7]] and not fixed.any()
    # halfway across the notch of an L is outside: the lattice instead, strictly inside
    ell = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    seed = np.array([[1.0, 1.5], [1.9, 0.9], [0.2, 0.2]])
    out, fixed = _pull_inside(ell, seed, np.array([True, False, False]))
    assert out.shape == (3, 2) and not fixed.any()
    assert not np.array_equal(out[1:], seed[1:])
    import shapely
    assert shapely.contains_xy(shapely.Polygon(ell.vertices), out[:, 0], out[:, 1]).all()


def torus_size(p):
    """A module-level size (processes import it by name)."""
    return 0.4 + np.abs(p[:, 2]) + 0.1 * p[:, 0]


def test_atlas_in_processes_same_bytes():
    path = DATA / "models" / "torus.obj"
    a = surface.remesh(path, 900, size=torus_size, check=False, hausdorff=False)
    b = surface.remesh(path, 900, size=torus_size, check=False, hausdorff=False, jobs=2)
    assert len(a.vertices) == 900
    assert a.vertices.tobytes() == b.vertices.tobytes() and a.faces.tobytes() == b.faces.tobytes()
