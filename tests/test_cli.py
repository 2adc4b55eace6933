"""The ``uniform2d`` command line, in process through ``main([...])`` and once as a subprocess."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from uniform2d.testing import check_mesh
from uniform2d import read_mesh, read_polygon
from uniform2d.cli.main import COMMANDS, main

DATA = Path(__file__).resolve().parents[1] / "data"
SQUARE = DATA / "benchmarks" / "square.json"
BRACKET = DATA / "l_bracket.json"
PANEL = DATA / "truss_panel.json"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_error(code, out, err):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("uniform2d: error: ")
    assert "Traceback" not in err


def test_registry_is_one_tuple_of_modules():
    assert {"mesh", "info", "remesh"} <= set(COMMANDS)
    for name in COMMANDS:
        mod = __import__(f"uniform2d.cli.{name}", fromlist=["add_parser", "run"])
        assert callable(mod.add_parser) and callable(mod.run)


def test_version_and_help(capsys):
    import uniform2d

    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.strip() == f"uniform2d {uniform2d.__version__}"
    code, out, _ = run(capsys, "--help")
    assert code == 0
    for name in COMMANDS:
        assert name in out


# -- mesh ----------------------------------------------------------------------
def test_mesh_one_file(capsys, tmp_path):
    out_file = tmp_path / "bracket.vtu"
    code, out, err = run(capsys, "mesh", BRACKET, "-n", 150, "-o", out_file)
    assert code == 0, err
    assert f"wrote {out_file}" in out
    polygon = read_polygon(BRACKET)
    points, triangles = read_mesh(out_file)
    assert len(points) == len(polygon.vertices) + 150
    check_mesh(points, triangles, polygon)


def test_mesh_default_method_takes_an_n_too_small_for_tplus(capsys, tmp_path):
    # --method paper refuses n = 10 for the bracket (test_mesh_bad_input); the
    # default method still gives exactly 10 Steiner points
    out_file = tmp_path / "bracket.vtu"
    code, out, err = run(capsys, "mesh", BRACKET, "-n", 10, "-o", out_file)
    assert code == 0, err
    polygon = read_polygon(BRACKET)
    points, triangles = read_mesh(out_file)
    assert len(points) == len(polygon.vertices) + 10
    check_mesh(points, triangles, polygon)


@pytest.mark.parametrize("ext", [".msh", ".csv", ".truss.json", ".obj"])
def test_mesh_formats_by_extension(capsys, tmp_path, ext):
    out_file = tmp_path / f"sq{ext}"
    code, _, err = run(capsys, "mesh", SQUARE, "--size", 0.2, "-o", out_file)
    assert code == 0, err
    points, triangles = read_mesh(out_file)
    check_mesh(points, triangles, read_polygon(SQUARE))


def test_mesh_default_output_is_next_to_input(capsys, tmp_path):
    src = tmp_path / "sq.json"
    src.write_text(SQUARE.read_text())
    code, _, err = run(capsys, "-q", "mesh", src, "-n", 20)
    assert code == 0, err
    assert (tmp_path / "sq.vtu").is_file()


def test_mesh_several_inputs_to_directory(capsys, tmp_path):
    outdir = tmp_path / "meshes"  # created on demand
    figs = tmp_path / "figs"
    inputs = [BRACKET, PANEL, SQUARE, DATA / "examples" / "l_bracket.wkt"]
    code, out, err = run(capsys, "mesh", *inputs[:3], "-n", 120, "-o", outdir,
                         "--format", "msh", "--plot", f"{figs}/")
    assert code == 0, err
    for src in inputs[:3]:
        dst = outdir / (src.stem + ".msh")
        points, triangles = read_mesh(dst)
        polygon = read_polygon(src)
        assert len(points) == len(polygon.vertices) + 120
        check_mesh(points, triangles, polygon)
        assert (figs / (src.stem + ".png")).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Two inputs with the same stem would overwrite each other: refused up front.
    code, out, err = run(capsys, "mesh", BRACKET, inputs[3], "-n", 120, "-o", tmp_path / "dup")
    assert_one_error(code, out, err)
    assert not (tmp_path / "dup").exists()
    # Several inputs and -o naming a file.
    code, out, err = run(capsys, "mesh", BRACKET, SQUARE, "-n", 120, "-o", tmp_path / "x.vtu")
    assert_one_error(code, out, err)
    assert not (tmp_path / "x.vtu").exists()


def test_mesh_json(capsys, tmp_path):
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 60, "-o", tmp_path / "sq.vtu", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["n_steiner"] == 60 and doc["n_points"] == 64
    assert isinstance(doc["info"], dict) and doc["method"] == "uniform"
    q = doc["quality"]
    assert q["n_vertices"] == 64
    assert q["edge_ratio_bound"]["factor"] >= 1
    # several inputs: one document, a list
    code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 60, "-o", tmp_path / "d", "--json",
                         "--method", "paper")
    assert code == 0, err
    docs = json.loads(out)
    assert [Path(d["input"]).name for d in docs] == ["square.json", "truss_panel.json"]
    for d in docs:  # T+ reports Theorem 2's quantities
        assert d["info"]["k"] >= 0 and d["info"]["d_n"] > 0
        assert isinstance(d["info"]["theorem_applies"], bool)
        assert set(d["info"]["hypotheses"]) == {"d_n <= l(V,V)/2", "d_n <= A/(pi*B)", "n >= 2k"}


def test_mesh_stats_and_plot(capsys, tmp_path):
    png = tmp_path / "sq.png"
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 100, "-o", tmp_path / "sq.vtu",
                         "--stats", "--plot", png, "--method", "paper")
    assert code == 0, err
    assert "Mesh quality" in out and "Lower bounds" in out
    assert "T+ (Theorem 2)" in out and "theorem applies" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_stats_and_json_exclusive(capsys, tmp_path):
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 10, "-o", tmp_path / "a.vtu",
                         "--stats", "--json")
    assert_one_error(code, out, err)
    assert not (tmp_path / "a.vtu").exists()


# -- bad inputs: one line, exit 2, no output -------------------------------------
def _bad_polygon(tmp_path):
    bad = tmp_path / "bowtie.json"
    bad.write_text(json.dumps({"outer": [[0, 0], [2, 2], [2, 0], [0, 1]]}))
    return bad


def test_mesh_plot_into_a_missing_directory_writes_nothing(capsys, tmp_path):
    out_file = tmp_path / "x.vtu"
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 10, "-o", out_file,
                         "--plot", tmp_path / "nodir" / "p.png")
    assert_one_error(code, out, err)
    assert "nodir" in err and "does not exist" in err
    assert list(tmp_path.iterdir()) == []


def test_mesh_plot_paths_are_checked_before_meshing(capsys, tmp_path):
    (tmp_path / "adir.png").mkdir()
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 10, "-o", tmp_path / "x.vtu",
                         "--plot", tmp_path / "adir.png")
    assert_one_error(code, out, err)
    assert "is a directory" in err
    (tmp_path / "afile").write_text("")
    code, out, err = run(capsys, "mesh", SQUARE, BRACKET, "-n", 10, "-o", tmp_path / "out",
                         "--plot", tmp_path / "afile")
    assert_one_error(code, out, err)
    assert "--plot must be a directory" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir.png", "afile"]


def test_mesh_and_figure_are_written_both_or_neither(capsys, tmp_path, monkeypatch):
    import uniform2d.mesh

    def broken(self, path, **kwargs):
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(uniform2d.mesh.Mesh, "write", broken)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 10, "-o", tmp_path / "x.vtu",
                         "--plot", tmp_path / "p.png")
    assert_one_error(code, out, err)
    assert list(tmp_path.iterdir()) == [], "the figure (or its temporary file) was left behind"


def test_mesh_out_of_memory_is_one_line(capsys, tmp_path, monkeypatch):
    import uniform2d.uniform

    def too_big(*args, **kwargs):
        raise MemoryError("Unable to allocate 44.7 GiB for an array")

    monkeypatch.setattr(uniform2d.uniform, "uniform_mesh", too_big)
    out_file = tmp_path / "out.vtu"
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 10, "-o", out_file)
    assert_one_error(code, out, err)
    assert "out of memory" in err and "44.7 GiB" in err and "fewer points" in err
    assert not out_file.exists()


@pytest.mark.parametrize(
    "case",
    ["missing", "self_intersecting", "n_too_small", "unknown_extension", "n_and_size",
     "negative_n", "bad_plot", "unknown_input_extension", "size_too_large"],
)
def test_mesh_bad_input(capsys, tmp_path, case):
    out_file = tmp_path / "out.vtu"
    args = {
        "missing": [tmp_path / "nope.json", "-n", 10],
        "self_intersecting": [_bad_polygon(tmp_path), "-n", 10],
        "n_too_small": [BRACKET, "-n", 10, "--method", "paper"],
        "unknown_extension": [SQUARE, "-n", 10, "-o", tmp_path / "out.step"],
        "n_and_size": [SQUARE, "-n", 10, "--size", 0.1],
        "negative_n": [SQUARE, "-n", -3],
        "bad_plot": [SQUARE, "-n", 10, "--plot", tmp_path / "fig.bmp"],
        "unknown_input_extension": [tmp_path / "poly.step", "-n", 10],
        "size_too_large": [SQUARE, "--size", 100],
    }[case]
    if case == "unknown_input_extension":
        (tmp_path / "poly.step").write_text("x")
    if "-o" not in args:
        args += ["-o", out_file]
    code, out, err = run(capsys, "mesh", *args)
    assert_one_error(code, out, err)
    if case == "n_too_small":
        assert "smallest n" in err
    if case == "self_intersecting":
        assert "intersects itself" in err
    if case == "missing":
        assert "nope.json" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        p.name for p in tmp_path.iterdir() if p.suffix in (".json", ".step")
    ), "an output file was created"


# -- info ------------------------------------------------------------------------
def test_info(capsys):
    code, out, err = run(capsys, "info", DATA / "plate_bolts.json", "--size", 5)
    assert code == 0, err
    assert "vertices:        148" in out and "holes:           5" in out
    assert "l(V,V)" in out and "sharpest corner: 90 deg" in out
    from uniform2d import steiner_count_for_size

    n = steiner_count_for_size(read_polygon(DATA / "plate_bolts.json"), 5.0)
    assert f"n = {n} Steiner points" in out
    code, out, err = run(capsys, "info", PANEL, "--json")
    doc = json.loads(out)
    assert doc["vertices"] == 12 and doc["holes"] == 1
    assert doc["area"] == pytest.approx(12 * 3 - 1.0 * 2.1 - 2.4 * 1.2)
    assert doc["bounds"] == [0, 0, 12, 3]


def test_info_bad_input(capsys, tmp_path):
    assert_one_error(*run(capsys, "info", tmp_path / "nope.json"))
    assert_one_error(*run(capsys, "info", _bad_polygon(tmp_path)))


# -- remesh (surface extra) ------------------------------------------------------
def test_remesh(capsys, tmp_path):
    pytest.importorskip("igl")
    pytest.importorskip("pymeshlab")
    out_file = tmp_path / "plate.obj"
    png = tmp_path / "plate.png"
    code, out, err = run(capsys, "remesh", DATA / "patches" / "plate_hole.obj", "-n", 150,
                         "-o", out_file, "--stats", "--plot", png)
    assert code == 0, err
    assert "3-D edges" in out
    import surface

    patch = surface.read_patch(out_file)
    assert len(patch.vertices) == 150
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, out, err = run(capsys, "remesh", DATA / "patches" / "plate_hole.obj", "-n", 150,
                         "-o", tmp_path / "plate.vtu")
    assert_one_error(code, out, err)
    assert not (tmp_path / "plate.vtu").exists()


# -- the real command ---------------------------------------------------------------
def test_subprocess(tmp_path):
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    cmd = [sys.executable, "-m", "uniform2d.cli.main"]
    out_file = tmp_path / "sq.truss.json"
    ok = subprocess.run(cmd + ["mesh", str(SQUARE), "-n", "30", "-o", str(out_file)],
                        capture_output=True, text=True, env=env, timeout=300)
    assert ok.returncode == 0, ok.stderr
    assert "wrote" in ok.stdout
    points, triangles = read_mesh(out_file)
    assert len(points) == 34
    bad = subprocess.run(cmd + ["mesh", str(_bad_polygon(tmp_path)), "-n", "30",
                                "-o", str(tmp_path / "bad.vtu")],
                         capture_output=True, text=True, env=env, timeout=300)
    assert bad.returncode == 2
    assert bad.stderr.count("\n") == 1 and bad.stderr.startswith("uniform2d: error: ")
    assert not (tmp_path / "bad.vtu").exists()


def test_main_leaves_logging_as_it_found_it(capsys):
    import logging

    root = logging.getLogger()
    handlers, level = list(root.handlers), root.level
    run(capsys, "-v", "info", SQUARE)
    run(capsys, "info", SQUARE / "missing.json")
    assert root.handlers == handlers and root.level == level


def test_progress_bar_only_on_a_terminal(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 40, "-o", tmp_path / "a")
    assert code == 0 and "meshing" in err and "2/2" in err
    code, out, err = run(capsys, "-q", "mesh", SQUARE, PANEL, "-n", 40, "-o", tmp_path / "b")
    assert code == 0 and err == "" and out == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 40, "-o", tmp_path / "c")
    assert code == 0 and err == ""
