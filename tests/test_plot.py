"""uniform2d.plot: files are written, the figure shows every edge once, big meshes are fast."""

import time

import numpy as np
import pytest
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from scipy.spatial import Delaunay

from uniform2d import Polygon, UnsupportedFormatError
from uniform2d.plot import plot_mesh
from uniform2d.measures import edge_lengths

SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def random_mesh(n, seed=0):
    rng = np.random.default_rng(seed)
    pts = np.vstack([SQUARE.vertices, rng.random((n, 2))])
    return pts, Delaunay(pts).simplices


def edge_collection(fig):
    cols = [c for c in fig.axes[0].collections if isinstance(c, LineCollection)]
    assert len(cols) == 1
    return cols[0]


def test_png_written_and_segments_are_the_edges(tmp_path):
    pts, tri = random_mesh(200)
    path = tmp_path / "mesh.png"
    fig = plot_mesh(pts, tri, path, polygon=SQUARE, title="two hundred")
    assert isinstance(fig, Figure)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    edges, lengths = edge_lengths(pts, tri)
    segs = edge_collection(fig).get_segments()
    assert len(segs) == len(edges)
    np.testing.assert_array_equal(np.array(segs), pts[edges])
    np.testing.assert_allclose(edge_collection(fig).get_array(), lengths / lengths.mean())
    assert fig._suptitle.get_text() == "two hundred"


def test_histogram_bars_count_every_edge():
    for n in (10, 300):  # a narrow (linear axis) and a wide (log axis) spread
        pts, tri = random_mesh(n, seed=n)
        fig = plot_mesh(pts, tri)
        heights = [p.get_height() for p in fig.axes[1].patches]
        assert sum(heights) == len(edge_lengths(pts, tri)[0])


@pytest.mark.parametrize("ext, magic", [(".pdf", b"%PDF"), (".svg", b"<?xml"), (".PNG", b"\x89PNG")])
def test_other_formats(tmp_path, ext, magic):
    pts, tri = random_mesh(30)
    path = tmp_path / f"mesh{ext}"
    plot_mesh(pts, tri, str(path), polygon=SQUARE)
    assert path.read_bytes().startswith(magic)


def test_unsupported_extension_raises_before_drawing(tmp_path):
    pts, tri = random_mesh(10)
    for name in ("mesh.jpg", "mesh"):
        with pytest.raises(UnsupportedFormatError, match="png"):
            plot_mesh(pts, tri, tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_no_path_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fig = plot_mesh(*random_mesh(10))
    assert list(tmp_path.iterdir()) == []
    assert len(fig.axes) == 3  # mesh, histogram, colour bar


def test_uniform_and_hole_meshes(tmp_path):
    # All edges equal (one equilateral triangle) and a polygon with a hole.
    tri_pts = np.array([(0, 0), (1, 0), (0.5, np.sqrt(3) / 2)])
    plot_mesh(tri_pts, [(0, 1, 2)], tmp_path / "eq.png", polygon=tri_pts)
    P = Polygon([(0, 0), (2, 0), (2, 2), (0, 2)], [[(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)]])
    pts = np.vstack([P.vertices, [(1.0, 0.25), (1.75, 1.0), (1.0, 1.75), (0.25, 1.0)]])
    tri = Delaunay(pts).simplices
    centroids = pts[tri].mean(axis=1)
    tri = tri[~((np.abs(centroids - 1.0) < 0.5).all(axis=1))]  # drop the hole
    fig = plot_mesh(pts, tri, tmp_path / "hole.png", polygon=P)
    assert len(fig.axes[0].lines) == 2  # outer ring and hole


def test_inputs_are_not_mutated():
    pts, tri = random_mesh(50)
    pts.setflags(write=False)
    tri.setflags(write=False)
    p0, t0 = pts.copy(), tri.copy()
    plot_mesh(pts, tri, polygon=SQUARE)
    np.testing.assert_array_equal(pts, p0)
    np.testing.assert_array_equal(tri, t0)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="outside"):
        plot_mesh([(0, 0), (1, 0), (0, 1)], [(0, 1, 5)])


def test_hundred_thousand_edges_in_reasonable_time(tmp_path):
    pts, tri = random_mesh(34_000)
    n_edges = len(edge_lengths(pts, tri)[0])
    assert n_edges > 100_000
    t0 = time.perf_counter()
    fig = plot_mesh(pts, tri, tmp_path / "big.png", polygon=SQUARE)
    elapsed = time.perf_counter() - t0
    assert len(edge_collection(fig).get_segments()) == n_edges
    assert (tmp_path / "big.png").stat().st_size > 10_000
    assert elapsed < 60, f"plotting {n_edges} edges took {elapsed:.1f} s"


def test_failed_save_leaves_no_partial_file(tmp_path, monkeypatch):
    pts, tri = random_mesh(50)
    out = tmp_path / "mesh.png"
    out.write_bytes(b"previous")

    def boom(self, fname, **kw):
        with open(fname, "wb") as f:
            f.write(b"half a PNG")
        raise OSError("disk full")

    monkeypatch.setattr(Figure, "savefig", boom)
    with pytest.raises(OSError, match="disk full"):
        plot_mesh(pts, tri, out)
    assert out.read_bytes() == b"previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.png"]


def _luminance(rgb):
    """WCAG relative luminance of sRGB colours in [0, 1], shape (..., 3)."""
    c = np.asarray(rgb, dtype=float)[..., :3]
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return c @ [0.2126, 0.7152, 0.0722]


def _contrast(a, b):
    la, lb = _luminance(a), _luminance(b)
    return (np.maximum(la, lb) + 0.05) / (np.minimum(la, lb) + 0.05)


def lattice_mesh(side, seed=0):
    """A jittered equilateral lattice: nearly every edge close to the mean length."""
    x, y = np.meshgrid(np.arange(side, dtype=float), np.arange(side) * np.sqrt(3) / 2)
    x += 0.5 * (np.arange(side)[:, None] % 2)
    jitter = np.random.default_rng(seed).normal(0, 0.03, (side * side, 2))
    pts = np.c_[x.ravel(), y.ravel()] + jitter
    return pts, Delaunay(pts).simplices


def test_mean_length_edges_stand_out_from_the_background():
    # The colour of an edge exactly as long as the mean, and every colour the map
    # can give, against the panel's background (WCAG contrast: 1 = invisible,
    # 3 = the minimum for graphics, 21 = black on white).
    pts, tri = lattice_mesh(12)
    fig = plot_mesh(pts, tri)
    lc = edge_collection(fig)
    background = fig.axes[0].get_facecolor()
    assert _contrast(lc.cmap(lc.norm(1.0)), background) >= 4.5
    every = lc.cmap(np.linspace(0.0, 1.0, 256))
    assert _contrast(every, background).min() >= 1.9, "a colour of the map is near white"


@pytest.mark.parametrize("side", [22, 70])  # about 500 and 5000 vertices
def test_drawn_mesh_is_visible_in_the_png(side):
    # Rendered pixels, not colours on paper: thin lines are blended with the white
    # background, so measure how much of the mesh panel is clearly darker than it.
    import io

    from PIL import Image

    pts, tri = lattice_mesh(side)
    fig = plot_mesh(pts, tri)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    img = np.asarray(Image.open(buf).convert("RGB"), dtype=float) / 255.0
    box = fig.axes[0].get_window_extent()
    h = img.shape[0]
    inside = img[int(h - box.y1) + 5:int(h - box.y0) - 5, int(box.x0) + 5:int(box.x1) - 5]
    visible = _contrast(inside, np.ones(3)) > 1.5
    assert visible.mean() > 0.15, f"only {visible.mean():.1%} of the mesh panel differs from white"
