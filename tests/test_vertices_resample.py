"""``--vertices N`` with ``--resample``: exactly N mesh vertices, although the
resampling keeps a count of input vertices that depends on n."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import meshio
import numpy as np
import pytest

import uniform2d as u
from uniform2d.cli.main import main
from uniform2d.testing import check_mesh
from uniform2d.uniform import resampled_outline

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name, total, extra", [
    ("data/outlines/nyc_manhattan.json", 800, []),       # more input vertices than asked for
    ("data/outlines/greenland.json", 900, ["--refine", "corners:0.3"]),  # graded
    ("data/l_bracket.json", 300, []),                     # a CAD outline, few vertices
])
def test_cli_vertices_with_resample_is_exact(tmp_path, capsys, name, total, extra):
    out = tmp_path / "m.vtu"
    code = main(["mesh", str(ROOT / name), "--vertices", str(total), "--resample", "0.25",
                 *extra, "-o", str(out)])
    _, err = capsys.readouterr()
    assert code == 0, err
    m = meshio.read(out)
    assert len(m.points) == total
    assert np.unique(m.points, axis=0).shape[0] == total


def test_resampled_outline_is_what_uniform_mesh_meshes():
    t = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    p = u.Polygon(np.c_[np.cos(t), 0.5 * np.sin(t)])
    res, left = resampled_outline(p, 400, resample=0.25)
    mesh = u.uniform_mesh(p, 400, resample=0.25)
    check_mesh(mesh.points, mesh.triangles, mesh.polygon, n_steiner=mesh.n_steiner)
    assert np.array_equal(mesh.polygon.vertices, res.polygon.vertices)
    assert mesh.n_steiner == left and res.n_boundary + left == 400
    assert len(mesh.points) == res.n_kept + 400


def test_resampled_outline_as_given_keeps_every_vertex():
    """A polygon with no edge too short for the spacing is meshed as given."""
    square = u.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    res, left = resampled_outline(square, 50, resample=0.25)
    assert not res.resampled and res.n_kept == 4 and left == 50
    assert res.polygon is square


def _one_line_exit_2(capsys, argv, out, words):
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and err.startswith("uniform2d: ")
    assert all(w in err for w in words), err
    assert not out.exists()


def test_vertices_below_the_kept_vertices_is_refused(tmp_path, capsys):
    """A star of 60 sharp tips keeps its 120 corners: 100 vertices in all cannot hold them."""
    t = np.arange(120) * np.pi / 60
    r = np.where(np.arange(120) % 2 == 0, 1.0, 0.5)
    src = tmp_path / "star.json"
    u.write_polygon(src, u.Polygon(np.c_[r * np.cos(t), r * np.sin(t)]))
    out = tmp_path / "m.vtu"
    _one_line_exit_2(capsys, ["mesh", src, "--vertices", 100, "--resample", "0.25", "-o", out],
                     out, ["--vertices 100", "120 input vertices kept", "larger --vertices"])


def test_vertices_with_a_kept_count_that_never_settles_is_refused(tmp_path, capsys, monkeypatch):
    """A kept count alternating with n (2 or 3 kept): no n gives the total; said, no file."""
    import uniform2d.uniform as uniform

    real = uniform.resampled_outline

    def alternating(polygon, n, **kw):
        res, left = real(polygon, n, **kw)
        kept = np.zeros_like(res.kept)
        kept[: 2 + (n + 1) % 2] = True
        return dataclasses.replace(res, kept=kept), left

    monkeypatch.setattr(uniform, "resampled_outline", alternating)
    out = tmp_path / "m.vtu"
    _one_line_exit_2(capsys, ["mesh", ROOT / "data/outlines/nyc_manhattan.json", "--vertices",
                              500, "--resample", "0.25", "-o", out],
                     out, ["--vertices 500", "no count gives exactly this total", "-n"])
