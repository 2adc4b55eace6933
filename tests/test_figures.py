"""Readable figures: the report's panels in a grid of a sensible size, and the
plot's colour bar spanning the edges' range (not a symmetric one around 1)."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from uniform2d import tplus, uniform_mesh
from uniform2d.io import read_polygon
from uniform2d.plot import plot_mesh
from uniform2d.report.render import grid_shape, mesh_figure

ROOT = Path(__file__).resolve().parents[1]


def _rel_lengths(points, triangles):
    e = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]),
                axis=1)
    e = np.unique(e, axis=0)
    L = np.hypot(*(points[e[:, 1]] - points[e[:, 0]]).T)
    return L / L.mean()


def test_colour_bar_spans_the_edges():
    p = read_polygon(ROOT / "data/l_bracket.json")
    m = tplus(p, 300)
    rel = _rel_lengths(m.points, m.triangles)
    assert rel.min() < 0.5 and rel.max() < 1.6  # far from symmetric about 1
    fig = plot_mesh(m.points, m.triangles, polygon=p)
    norm = fig.axes[0].collections[-1].norm
    lo, hi = np.quantile(rel, [0.002, 0.998])
    assert norm.vmin == pytest.approx(lo, rel=1e-12) and norm.vmax == pytest.approx(hi, rel=1e-12)
    bar = fig.axes[2]
    assert min(bar.get_ylim()) >= rel.min() and max(bar.get_ylim()) <= rel.max()
    ticks = [t for t in bar.get_yticks() if lo <= t <= hi]
    assert 1.0 in ticks and len(ticks) >= 3


def test_near_uniform_mesh_keeps_a_range_around_one():
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    pts = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], dtype=float)
    fig = plot_mesh(pts, [(0, 1, 2), (0, 2, 3)], polygon=square)
    norm = fig.axes[0].collections[-1].norm
    assert norm.vmin <= 1 / 1.05 * (1 + 1e-12) and norm.vmax >= 1.05 * (1 - 1e-12)


@pytest.mark.parametrize("k, shape", [(1, (1, 2)), (2, (1, 3)), (3, (2, 2)), (5, (2, 3)),
                                      (6, (3, 3))])
def test_grid_of_panels(k, shape):
    assert grid_shape(k + 1) == shape


@pytest.mark.parametrize("kind, k", [("polygon", 5), ("surface", 2)])
def test_report_figure_size(kind, k):
    p = read_polygon(ROOT / "data/constrained/roof_panel.json")
    m = uniform_mesh(p, 100)
    if kind == "polygon":
        items = [(f"m{i}", m.points, m.triangles) for i in range(k)]
    else:
        P3 = np.column_stack([m.points, 0.1 * m.points[:, 0] ** 2])
        items = [(f"m{i}", P3, m.triangles) for i in range(k)]
    png = mesh_figure(kind, items, title="t", segments=p.segments)
    w, h = Image.open(io.BytesIO(png)).size
    rows, cols = grid_shape(k + 1)
    # panels of 3.4 x 3.1 inches at 100 dpi: no strip of thumbnails
    assert (w, h) == (340 * cols, 310 * rows + 40)
    assert w >= 600 and h >= 300 and w / h <= 3.0
