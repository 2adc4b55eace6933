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
