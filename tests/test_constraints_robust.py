"""Near-degenerate constrained domains from the fuzz benchmark (seed 0).

``data/constrained_near.json`` holds eight domains of ``tests/fuzzgen.constrained``
(kinds ``c_near`` and ``c_tjunction``): two segments leaving one vertex at an
angle of ~1e-7, a fixed point a few units in the last place off a segment, a
segment ending a rounding off a ring edge, far from the origin.  There the
points of one segment piece lie within rounding tolerance of another piece (or
of a ring edge), so "which chain of edges is this piece" is ambiguous by
distance alone; and the closest vertices are so near that T+ would need
millions of boundary points.

Every mesh is checked by ``invariants.check_mesh`` (each piece a chain of mesh
edges, no point on two chains, the rest constrained Delaunay, exactly n).
"""

from __future__ import annotations

import functools
import json
import time
from pathlib import Path

import numpy as np
import pytest

import uniform2d
from invariants import check_mesh, edge_table, segment_chains
from uniform2d import Polygon
from uniform2d.errors import InsufficientPointsError
from uniform2d.tplus import _phase1, least_k

DATA = Path(__file__).parent / "data" / "constrained_near.json"


@functools.cache
def domain(name: str) -> Polygon:
    d = json.loads(DATA.read_text())[name]
    return Polygon(d["outer"], d["holes"], segments=d["segments"], points=d["points"])


# (domain, n): INSERT's meshes whose pieces the old greedy chain walk could not
# follow (a crash in the library's own check, or a false "not Delaunay" from the
# test checker, which then left real piece edges in its Delaunay test)
INSERTS = [
    ("c_near_9", 2544), ("c_near_9", 2368), ("c_near_34", 3584), ("c_near_34", 1984),
    ("c_near_34", 355), ("c_tjunction_16", 463), ("c_near_21", 21), ("c_near_26", 8),
    ("c_near_31", 1), ("c_near_35", 790), ("c_near_36", 80),
]  # fmt: skip


@pytest.mark.parametrize("name,n", INSERTS)
def test_insert_near_degenerate(name, n):
    P = domain(name)
    res = uniform2d.insert(P, n)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=n)


def test_chains_are_disjoint_where_pieces_nearly_overlap():
    """Pieces 9-12 and 9-13 of c_near_9 leave vertex 9 at an angle of ~2e-7: their
    chains are found separately, share no inner vertex, and both start at 9."""
    P = domain("c_near_9")
    res = uniform2d.insert(P, 2544)
    he, _, _ = edge_table(res.triangles)
    on = segment_chains(res.mesh_points, he, P)
    first = {v for u, v in on if u == 9}
    assert len(first) == 3  # 8-9 ends at 9 too: one edge on each of the three pieces


@pytest.mark.parametrize("name,n", [("c_near_9", 36), ("c_near_34", 30), ("c_near_21", 41)])
def test_uniform_mesh_near_degenerate(name, n):
    P = domain(name)
    mesh = uniform2d.uniform_mesh(P, n)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)


@pytest.mark.parametrize(
    "name,n", [("c_near_9", 158), ("c_near_21", 44), ("c_near_26", 3), ("c_near_31", 53),
               ("c_near_35", 31), ("c_near_36", 859), ("c_near_34", 6)],
)  # fmt: skip
def test_tplus_refuses_at_once_when_vertices_nearly_coincide(name, n):
    """d_n <= l(V, V) for every n: where that is tiny, T+ needs more boundary
    points than any n it could be run for; the refusal names the distance."""
    P = domain(name)
    t0 = time.perf_counter()
    with pytest.raises(InsufficientPointsError, match="apart") as exc:
        uniform2d.tplus(P, n)
    assert time.perf_counter() - t0 < 30.0
    least = int(str(exc.value).split("at least ")[1].split()[0])
    assert least == least_k(P) > n
    assert f"{P.min_vertex_distance():.6g}" in str(exc.value)


@pytest.mark.parametrize("n", [1, 10, 100, 1000])
def test_least_k_is_a_lower_bound(n):
    """least_k never exceeds the k phase 1 actually asks for (L-shaped room with
    a stiffener and a column, so l(V, V) is a real short distance)."""
    P = Polygon(
        [(0, 0), (6, 0), (6, 2), (3, 2), (3, 5), (0, 5)],
        segments=[[(1, 1), (1, 4.0)], [(1, 4.0), (2.5, 4.2)]],
        points=[(1.05, 2.0)],
    )
    d_n, pts, _, m = _phase1(P, n, 3.0)
    k = int(m.sum() - len(m)) if pts is None else len(pts)
    assert least_k(P) <= k
    assert d_n <= P.min_vertex_distance()


def test_tplus_feasible_polygon_unchanged():
    """Where l(V, V) is not tiny the old search still names the smallest n."""
    P = Polygon([(0, 0), (10, 0), (10, 1), (0, 1)], segments=[[(2, 0.5), (8, 0.5)]])
    with pytest.raises(InsufficientPointsError, match=r"smallest n that works for this polygon is (\d+)") as exc:
        uniform2d.tplus(P, 1)
    need = int(str(exc.value).rsplit(" ", 1)[1])
    mesh = uniform2d.tplus(P, need)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=need)
    assert np.isfinite(mesh.info["d_n"])
