"""The Gmsh peer embeds a polygon's segments and fixed points: its meshes conform."""

import numpy as np
import pytest

from uniform2d import InvalidArgumentError, Polygon
from uniform2d.mesh_regions import polygon_vertices_first, segment_chains, triangle_regions

from test_io_constraints import slab

gmsh_peer = pytest.importorskip("uniform2d.peers.gmsh_peer")
pytest.importorskip("gmsh")


@pytest.mark.parametrize("size", [1.0, 0.4])
def test_gmsh_meshes_contain_segments_points_and_regions(size):
    p = slab()
    pts, tri = polygon_vertices_first(p, *gmsh_peer.mesh_with_size(p, size))
    assert np.array_equal(pts[:len(p.vertices)], p.vertices)
    edges, ids = segment_chains(p, pts, tri)
    for s, line in enumerate(p.segments):
        L = np.hypot(*(pts[edges[ids == s, 1]] - pts[edges[ids == s, 0]]).T).sum()
        assert L == pytest.approx(np.hypot(*np.diff(line, axis=0).T).sum(), rel=1e-9)
    reg = triangle_regions(p, pts, tri)
    assert sorted(set(reg.tolist())) == [0, 1, 2]


def test_tuned_gmsh_mesh_hits_the_vertex_count():
    p = slab()
    m = gmsh_peer.mesh(p, 300)
    assert abs(len(m.points) - 300) <= 3


def test_vertices_first_refuses_a_mesh_without_them():
    p = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], points=[(0.5, 0.5)])
    with pytest.raises(InvalidArgumentError, match=r"polygon vertex 4 \(0.5, 0.5\) is not a point"):
        polygon_vertices_first(p, p.vertices[:4], [[0, 1, 2], [0, 2, 3]])
