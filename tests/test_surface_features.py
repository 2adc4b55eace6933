"""Feature lines of the surface layer: creases found, chained, kept as mesh edges."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("igl")
pytest.importorskip("trimesh")

from surface.features import find_chains, sample_chains  # noqa: E402
from surface.patch import Patch  # noqa: E402
from uniform2d.errors import InvalidArgumentError  # noqa: E402


def grid_patch(height, nx=20, ny=10):
    """A grid over [-1, 1] x [0, 1] lifted by z = height(x, y)."""
    x = np.linspace(-1, 1, nx + 1)
    y = np.linspace(0, 1, ny + 1)
    X, Y = np.meshgrid(x, y)
    V = np.stack([X.ravel(), Y.ravel(), height(X.ravel(), Y.ravel())], axis=1)
    idx = np.arange(len(V)).reshape(ny + 1, nx + 1)
    F = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = idx[j, i], idx[j, i + 1], idx[j + 1, i + 1], idx[j + 1, i]
            F += [[a, b, c], [a, c, d]]
    return Patch(V, np.array(F)), idx


def roof(slope=0.3, **kw):
    return grid_patch(lambda x, y: -slope * np.abs(x), **kw)


def test_ridge_is_one_chain_from_boundary_to_boundary():
    P, idx = roof()
    chains, fixed = find_chains(P, 20.0)
    assert [list(c) for c in chains] == [list(idx[:, 10])]
    assert len(fixed) == 0
    # the dihedral angle of this ridge is 2 atan(0.3), about 33.4 degrees
    assert find_chains(P, 34.0)[0] == []


def test_ridge_and_valley_meet_in_a_junction():
    # a ridge along x = 0 and a valley along y = 0.5 cross at one vertex
    P, idx = grid_patch(lambda x, y: -0.3 * np.abs(x) + 0.3 * np.abs(y - 0.5))
    chains, _ = find_chains(P, 20.0)
    assert len(chains) == 4  # four arms from the junction to the boundary
    centre = int(idx[5, 10])
    assert all(centre in (c[0], c[-1]) for c in chains)


def test_fixed_vertex_splits_a_chain_and_user_chains_are_checked():
    P, idx = roof()
    chains, fixed = find_chains(P, 20.0, fixed=[int(idx[4, 10])])
    assert len(chains) == 2 and fixed.tolist() == [int(idx[4, 10])]
    user, _ = find_chains(P, None, chains=[idx[3, 2:7]])
    assert [list(c) for c in user] == [list(idx[3, 2:7])]
    with pytest.raises(InvalidArgumentError, match="not joined by an edge"):
        find_chains(P, None, chains=[[int(idx[3, 2]), int(idx[5, 5])]])
    with pytest.raises(InvalidArgumentError, match="on the patch boundary"):
        find_chains(P, None, chains=[idx[0, 2:5]])
    with pytest.raises(InvalidArgumentError, match="feature_angle"):
        find_chains(P, 0.0)


def test_samples_lie_on_the_chain_and_end_exactly_on_its_ends():
    P, idx = roof()
    chains, _ = find_chains(P, 20.0)
    uv = P.vertices[:, :2] * [1.2, 1.0]  # any map: samples follow the same edges
    lines = sample_chains(P, uv, chains, 0.15)
    S, Q = lines.segments[0], lines.xyz[0]
    assert np.array_equal(S[0], uv[chains[0][0]]) and np.array_equal(S[-1], uv[chains[0][-1]])
    assert np.allclose(Q[:, 0], 0.0) and np.allclose(Q[:, 2], 0.0)  # on the ridge line
    assert len(S) == 1 + round(1.0 / 0.15)


@pytest.mark.parametrize("n", [150, 400])
def test_remesh_keeps_the_ridge(n):
    import surface

    P, idx = roof()
    r = surface.remesh((P.vertices, P.faces), n, feature_angle=20.0, check=False, hausdorff=False)
    X = r.vertices
    assert len(X) == n
    on = np.abs(X[:, 0]) <= 1e-12
    # points on the ridge are on the input's ridge line, and there are enough of them
    assert np.allclose(X[on, 2], 0.0, atol=1e-12) and on.sum() >= 1 + round(1.0 / r.report.target_size) - 1
    # no triangle straddles the ridge: its vertices are all on one side (or on it)
    side = np.where(on, 0, np.sign(X[:, 0]))[r.faces]
    assert not ((side.max(axis=1) > 0) & (side.min(axis=1) < 0)).any()
    # every vertex lies on the input surface z = -0.3 |x|
    assert np.allclose(X[:, 2], -0.3 * np.abs(X[:, 0]), atol=1e-9)


def test_remesh_without_features_straddles_the_ridge():
    """The check above can fail: without feature lines triangles do straddle it."""
    import surface

    P, _ = roof()
    r = surface.remesh((P.vertices, P.faces), 400, check=False, hausdorff=False)
    X = r.vertices
    on = np.abs(X[:, 0]) <= 1e-12
    side = np.where(on, 0, np.sign(X[:, 0]))[r.faces]
    assert ((side.max(axis=1) > 0) & (side.min(axis=1) < 0)).any()
