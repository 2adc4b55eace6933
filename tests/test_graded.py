"""Graded meshes (uniform_mesh size= a callable, a SizeField, a refine field or a file):
exactly n points, valid constrained Delaunay meshes, the count integral and the scale
search, constraints with grading, the bad inputs, and uniformity relative to h."""

from __future__ import annotations

import json
from pathlib import Path

import meshio
import numpy as np
import pytest

import uniform2d
from uniform2d import Polygon, SizeField, read_polygon
from uniform2d.cli.main import main
from uniform2d.errors import InvalidArgumentError, Uniform2dError
from uniform2d.grading import (
    as_field,
    check_range,
    count_for_field,
    field_integrals,
    scale_for_count,
)
from uniform2d.io.size_file import read_size_field
from uniform2d.measures import edge_lengths
from uniform2d.refine import minimum, refine
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

DATA = Path(__file__).resolve().parents[1] / "data"
LSHAPE = Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])
SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def corner(p):
    return 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1])


def checked(mesh, polygon, n):
    check_mesh(mesh.points, mesh.triangles, polygon, n_steiner=n)
    assert mesh.n_steiner == n and len(mesh.points) == len(polygon.vertices) + n
    assert mesh.info["method"] == "graded"
    return mesh


# -- exact n with every kind of size ---------------------------------------------
@pytest.mark.parametrize("n", [1, 7, 300])
def test_callable_exact_n(n):
    checked(uniform2d.uniform_mesh(LSHAPE, n, size=corner), LSHAPE, n)


def test_sizefield_and_refine_exact_n():
    x = np.linspace(0, 1, 5)
    f = SizeField(x, x, 0.05 + 0.2 * np.add.outer(x, x))
    checked(uniform2d.uniform_mesh(SQUARE, 250, size=f), SQUARE, 250)
    plate = read_polygon(DATA / "plate_bolts.json")
    checked(uniform2d.uniform_mesh(plate, 400, size=refine(plate, "holes", ratio=0.25)), plate, 400)
    both = minimum(LSHAPE, refine(LSHAPE, "corners", ratio=0.1), refine(LSHAPE, "boundary", ratio=0.5))
    checked(uniform2d.uniform_mesh(LSHAPE, 333, size=both), LSHAPE, 333)


def test_file_fields_exact_n(tmp_path):
    x = np.linspace(-1, 1, 9)
    X, Y = np.meshgrid(x, x)
    v = corner(np.column_stack([X.ravel(), Y.ravel()])).reshape(X.shape)
    np.savez(tmp_path / "h.npz", x=x, y=x, values=v)
    (tmp_path / "h.json").write_text(json.dumps({"x": x.tolist(), "y": x.tolist(),
                                                  "values": v.tolist()}))
    bg_points = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    bg_tri = triangulate(Polygon([(-1, -1), (1, -1), (1, 1), (-1, 1)]), bg_points[:, :2][
        ~np.isin(np.abs(bg_points[:, :2]).max(axis=1), [1.0])])[1]
    pts2 = triangulate(Polygon([(-1, -1), (1, -1), (1, 1), (-1, 1)]), bg_points[:, :2][
        ~np.isin(np.abs(bg_points[:, :2]).max(axis=1), [1.0])])[0]
    meshio.write(tmp_path / "bg.vtu", meshio.Mesh(
        np.column_stack([pts2, np.zeros(len(pts2))]), [("triangle", bg_tri)],
        point_data={"size": corner(pts2)}))
    for name in ("h.npz", "h.json", "bg.vtu"):
        f = read_size_field(tmp_path / name)
        m = checked(uniform2d.uniform_mesh(LSHAPE, 200, size=f), LSHAPE, 200)
        # the file's field is the same h: the mesh is as dense near the corner
        near = np.hypot(*m.points.T) < 0.3
        assert near.sum() > 0.25 * len(m.points), name


def test_number_is_the_uniform_path():
    a = uniform2d.uniform_mesh(SQUARE, size=0.2)
    b = uniform2d.uniform_mesh(SQUARE, a.n_steiner)
    assert a.points.tobytes() == b.points.tobytes() and a.info["method"] == "uniform"
    assert a.size is None and a.quality().to_dict()["relative"] is None


def test_deterministic():
    a = uniform2d.uniform_mesh(LSHAPE, 150, size=corner)
    b = uniform2d.uniform_mesh(LSHAPE, 150, size=corner)
    assert a.points.tobytes() == b.points.tobytes()
    assert a.triangles.tobytes() == b.triangles.tobytes()


def test_insert_takes_a_callable():
    a = uniform2d.insert(LSHAPE, 120, size=corner)
    b = uniform2d.insert(LSHAPE, 120, size=as_field(LSHAPE, corner))
    assert a.points.tobytes() == b.points.tobytes()
    assert np.median(np.hypot(*a.points.T)) < 0.5  # dense near the corner


# -- the count integral and the scale search ---------------------------------------
def test_count_matches_the_constant_formula():
    plate = read_polygon(DATA / "plate_bolts.json")
    for poly, h in ((SQUARE, 0.1), (SQUARE, 0.013), (LSHAPE, 0.05), (plate, 7.0)):
        want = uniform2d.steiner_count_for_size(poly, h)
        got = count_for_field(poly, SizeField.constant(poly.bounds, h))
        assert abs(got - want) <= max(1, 0.002 * want), (h, got, want)


@pytest.mark.parametrize("n", [10, 500, 20000])
def test_scale_search_inverts_the_count(n):
    f = as_field(LSHAPE, corner)
    s = scale_for_count(LSHAPE, f, n)
    assert s > 0
    assert abs(count_for_field(LSHAPE, f.scaled(s)) - n) <= 1


def test_without_n_the_field_is_absolute():
    h = lambda p: 0.5 * corner(p)  # noqa: E731
    m = uniform2d.uniform_mesh(LSHAPE, size=h)
    assert m.n_steiner == count_for_field(LSHAPE, as_field(LSHAPE, h))
    assert m.info["size_scale"] == pytest.approx(1.0, abs=0.01)
    q = m.quality().relative
    assert 0.9 < q.q_mean < 1.1  # edges have the absolute sizes asked for


# -- constraints with grading -------------------------------------------------------
@pytest.mark.parametrize("name,near", [("slab_columns.json", "points"),
                                        ("plate_zones.json", "segments"),
                                        ("roof_panel.json", "segments")])
def test_constraints_and_regions(name, near):
    P = read_polygon(DATA / "constrained" / name)
    m = checked(uniform2d.uniform_mesh(P, 300, size=refine(P, near, ratio=0.2)), P, 300)
    ref = uniform2d.uniform_mesh(P, 300)
    # the same regions, each with its area
    assert len(m.region_labels) == len(ref.region_labels)
    def area(mesh, k):
        p = mesh.points[mesh.triangles[mesh.regions == k]]
        u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        return 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum()

    for k in range(len(m.region_labels)):
        assert area(m, k) == pytest.approx(area(ref, k), rel=1e-9)
    edges, _ = m.segment_members
    assert len(edges) > 0 or not P.segments


# -- uniformity relative to h --------------------------------------------------------
def test_relative_uniformity():
    """On a gently graded square the mesh follows h: q's spread is small, far below
    INSERT's start, and its mean is the scale the count asked for."""
    h = lambda p: 0.05 + 0.1 * p[:, 0]  # noqa: E731
    m = checked(uniform2d.uniform_mesh(SQUARE, 500, size=h), SQUARE, 500)
    q = m.quality().relative
    assert q.q_cv < 0.12 and q.q_ratio < 1.8 and 0.9 < q.q_mean < 1.1
    start = uniform2d.insert(SQUARE, 500, size=h)
    q0 = uniform2d.quality(start.mesh_points, start.triangles, size=m.size).relative
    assert q.q_cv < 0.75 * q0.q_cv
    # twice as many points where h is half as large: density ~ 1 / h**2
    left = (m.points[:, 0] < 0.25).sum()
    right = (m.points[:, 0] > 0.75).sum()
    assert left > 2 * right


def test_quality_relative_measures():
    _, L = edge_lengths([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    q = uniform2d.quality([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)], size=lambda p: np.full(len(p), 2.0))
    assert q.relative.q_max == pytest.approx(L.max() / 2) and q.relative.q_cv > 0
    assert "Relative to the size field" in q.summary()


# -- bad input -------------------------------------------------------------------------
def test_size_not_positive_names_the_place():
    with pytest.raises(InvalidArgumentError, match=r"at \(0, 0\)"):
        uniform2d.uniform_mesh(LSHAPE, 100, size=lambda p: np.hypot(p[:, 0], p[:, 1]))
    with pytest.raises(InvalidArgumentError, match="nan at"):
        uniform2d.uniform_mesh(SQUARE, 100, size=lambda p: np.where(p[:, 0] > 0.5, np.nan, 1.0))


def test_nan_outside_the_domain_is_filled():
    # a background interpolant is NaN outside its mesh: fine where there is no domain
    h = lambda p: np.where((p[:, 0] < 0) | (p[:, 1] < 0), np.nan, 0.1)  # noqa: E731
    checked(uniform2d.uniform_mesh(SQUARE, 50, size=h), SQUARE, 50)


def test_raising_or_misshaped_callable():
    def boom(p):
        raise KeyError("no data here")

    with pytest.raises(InvalidArgumentError, match="size callable raised KeyError"):
        uniform2d.uniform_mesh(SQUARE, 10, size=boom)
    with pytest.raises(InvalidArgumentError, match="one size per point"):
        uniform2d.uniform_mesh(SQUARE, 10, size=lambda p: np.ones(3))
    with pytest.raises(TypeError, match="SizeField"):
        uniform2d.uniform_mesh(SQUARE, 10, size="fine")


def test_range_refused_with_the_smallest_n():
    h = lambda p: 1e-6 + np.hypot(p[:, 0], p[:, 1])  # noqa: E731
    with pytest.raises(InvalidArgumentError, match=r"use n >= (\d+)") as info:
        uniform2d.uniform_mesh(SQUARE, 10, size=h)
    need = int(info.value.args[0].split("use n >= ")[1].split()[0])
    f = as_field(SQUARE, h)
    I = field_integrals(SQUARE, f)
    check_range(SQUARE, f, need, I)  # the n it names is accepted
    with pytest.raises(InvalidArgumentError):
        check_range(SQUARE, f, need - 2, I)


def test_grid_not_covering_is_clamped():
    f = SizeField([0.4, 0.6], [0.4, 0.6], [[0.05, 0.2], [0.05, 0.2]])
    m = checked(uniform2d.uniform_mesh(SQUARE, 120, size=f), SQUARE, 120)
    assert (m.points[:, 0] < 0.5).sum() > (m.points[:, 0] > 0.5).sum()


def test_refine_and_file_errors(tmp_path):
    with pytest.raises(InvalidArgumentError, match="no holes"):
        refine(SQUARE, "holes")
    with pytest.raises(InvalidArgumentError, match="ratio"):
        refine(LSHAPE, "corners", ratio=2.0)
    with pytest.raises(InvalidArgumentError, match="near must be"):
        refine(LSHAPE, "edges")
    (tmp_path / "bad.json").write_text(json.dumps({"x": [0, 1], "y": [0, 1]}))
    with pytest.raises(Uniform2dError, match="missing: values"):
        read_size_field(tmp_path / "bad.json")


# -- command line ------------------------------------------------------------------------
def _one_error(capsys, *argv):
    code = main([str(a) for a in argv])
    _, err = capsys.readouterr()
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("uniform2d: error: "), err
    return lines[0]


def test_cli_refine_and_size_field(tmp_path, capsys):
    out = tmp_path / "m.vtu"
    code = main(["mesh", str(DATA / "plate_bolts.json"), "-n", "300", "--refine", "holes:0.25",
                 "--refine", "boundary:0.5:0.2", "-o", str(out), "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc["n_steiner"] == 300 and doc["info"]["method"] == "graded"
    assert "relative" in doc["quality"]
    m = uniform2d.read_mesh(out)
    assert len(m[0]) == len(read_polygon(DATA / "plate_bolts.json").vertices) + 300
    x = np.linspace(0, 400, 5)
    np.savez(tmp_path / "h.npz", x=x, y=np.linspace(0, 250, 4), values=np.full((4, 5), 9.0))
    assert main(["info", str(DATA / "plate_bolts.json"), "--size-field", str(tmp_path / "h.npz")]) == 0
    assert "size field -> n = " in capsys.readouterr().out
    assert main(["mesh", str(DATA / "plate_bolts.json"), "--size-field", str(tmp_path / "h.npz"),
                 "-o", str(out)]) == 0
    capsys.readouterr()
    assert main(["mesh", str(DATA / "plate_bolts.json"), "--vertices", "700", "--refine",
                 "holes:0.3", "-o", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_points"] == 700


def test_cli_refine_with_size_is_absolute(tmp_path, capsys):
    src = DATA / "plate_bolts.json"
    assert main(["info", str(src), "--refine", "holes:0.25", "--size", "20"]) == 0
    n = int(capsys.readouterr().out.split("size field -> n = ")[1].split()[0])
    plate = read_polygon(src)
    assert n == count_for_field(plate, refine(plate, "holes", ratio=0.25, size=20.0))
    assert main(["mesh", str(src), "--refine", "holes:0.25", "--size", "20", "-o",
                 str(tmp_path / "m.vtu"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["n_steiner"] == n and 0.9 < doc["quality"]["relative"]["q_mean"] < 1.1


def test_cli_bad_input_one_line(tmp_path, capsys):
    src = DATA / "plate_bolts.json"
    out = tmp_path / "m.vtu"
    assert "near:ratio" in _one_error(capsys, "mesh", src, "-n", "100", "--refine", "holes", "-o", out)
    assert "needs -n" in _one_error(capsys, "mesh", src, "--refine", "holes:0.3", "-o", out)
    assert "no such file" in _one_error(capsys, "mesh", src, "-n", "100", "--size-field",
                                        tmp_path / "none.npz", "-o", out)
    (tmp_path / "neg.json").write_text(json.dumps({"x": [0, 400], "y": [0, 250],
                                                    "values": [[1, -1], [1, 1]]}))
    assert "positive" in _one_error(capsys, "mesh", src, "-n", "100", "--size-field",
                                    tmp_path / "neg.json", "-o", out)
    assert "T+" in _one_error(capsys, "mesh", src, "-n", "100", "--refine", "holes:0.3",
                              "--method", "paper", "-o", out)
    assert not out.exists()
