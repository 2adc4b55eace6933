"""Figures of constrained meshes: regions filled, segments thicker, fixed points dotted."""

import numpy as np
import pytest
from matplotlib.collections import LineCollection, PolyCollection

from uniform2d import InvalidArgumentError
from uniform2d.mesh import Mesh
from uniform2d.plot import REGION_COLOURS, plot_mesh

from support.conmesh import triangle_mesh
from test_io_constraints import slab


@pytest.fixture(scope="module")
def mesh():
    p = slab()
    pts, tri = triangle_mesh(p, max_area=1.0)
    return Mesh(pts, tri, p, len(pts) - len(p.vertices))


def test_regions_coloured_and_constraints_thicker(tmp_path, mesh):
    fig = mesh.plot(tmp_path / "m.png")
    assert (tmp_path / "m.png").stat().st_size > 0
    ax = fig.axes[0]
    fills = [c for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(fills) == 1 and len(fills[0].get_paths()) == len(mesh.triangles)
    colours = fills[0].get_facecolors()
    # one colour per region, the same for all its triangles
    for r in range(len(mesh.polygon.regions)):
        assert len(np.unique(colours[mesh.regions == r], axis=0)) == 1
    assert len({tuple(c) for c in colours}) == 3
    edges = next(c for c in ax.collections if isinstance(c, LineCollection))
    mesh_lw = float(edges.get_linewidths()[0])
    seg_lines = [ln for ln in ax.lines if ln.get_linestyle() == "-" and len(ln.get_xdata()) in
                 {len(s) for s in mesh.polygon.segments}]
    assert len(seg_lines) >= len(mesh.polygon.segments)
    assert all(ln.get_linewidth() > mesh_lw for ln in seg_lines)
    dots = [ln for ln in ax.lines if ln.get_marker() == "o"]
    assert len(dots) == 1 and len(dots[0].get_xdata()) == len(mesh.polygon.points)


def test_labelled_regions_get_a_legend(mesh):
    fig = mesh.plot()
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts == ["0: west", "2: zone"]


def test_plot_without_regions_has_no_fill(mesh):
    fig = plot_mesh(mesh.points, mesh.triangles)
    assert not [c for c in fig.axes[0].collections if isinstance(c, PolyCollection)]


def test_bad_regions(mesh):
    with pytest.raises(InvalidArgumentError, match="one non-negative integer per triangle"):
        plot_mesh(mesh.points, mesh.triangles, regions=[0, 1])
    assert len(REGION_COLOURS) >= 10
