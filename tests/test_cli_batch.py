"""``uniform2d mesh`` with several inputs, output paths, and the messages a user sees
when the disk or a path is wrong (one line naming the user's path and what to do)."""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest

from uniform2d.testing import check_mesh
from uniform2d import read_mesh, read_polygon
from uniform2d.cli._common import Outcome, map_inputs
from uniform2d.cli.main import main

DATA = Path(__file__).resolve().parents[1] / "data"
SQUARE = DATA / "benchmarks" / "square.json"
PANEL = DATA / "truss_panel.json"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def one_error(code, err) -> str:
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith("uniform2d: error: ") and "Traceback" not in err
    return lines[0]


def bowtie(directory: Path) -> Path:
    bad = directory / "bowtie.json"
    bad.write_text(json.dumps({"outer": [[0, 0], [2, 2], [2, 0], [0, 1]]}))
    return bad


def files(directory: Path) -> list[str]:
    return sorted(str(p.relative_to(directory)) for p in directory.rglob("*"))


# -- keep-going batches ------------------------------------------------------------
def test_map_inputs_keeps_going_and_keeps_order():
    def work(x):
        if x == "bad":
            raise ValueError("bad input")
        if x == "huge":
            raise MemoryError("Unable to allocate")
        return x.upper()

    outcomes = list(map_inputs(work, ["a", "bad", "huge", "b"]))
    assert [o.item for o in outcomes] == ["a", "bad", "huge", "b"]
    assert [o.value for o in outcomes] == ["A", None, None, "B"]
    assert [type(o.error).__name__ for o in outcomes] == ["NoneType", "ValueError", "MemoryError",
                                                        "NoneType"]
    assert all(isinstance(o, Outcome) for o in outcomes)


def test_map_inputs_stops_on_a_bug():
    def work(x):
        raise ZeroDivisionError("a bug, not a bad input")

    with pytest.raises(ZeroDivisionError):
        list(map_inputs(work, ["a", "b"]))


def test_batch_meshes_every_good_input_and_reports_each_bad_one(capsys, tmp_path):
    bad = bowtie(tmp_path)
    missing_dir = tmp_path / "out"
    code, out, err = run(capsys, "mesh", SQUARE, bad, PANEL, "-n", 40, "-o", f"{missing_dir}/")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 2, err
    assert lines[0].startswith("uniform2d: error: ") and "bowtie.json" in lines[0]
    assert "intersects itself" in lines[0]
    assert lines[1] == "uniform2d: error: 1 of 3 inputs failed"
    assert files(missing_dir) == ["square.vtu", "truss_panel.vtu"]
    for src in (SQUARE, PANEL):
        points, triangles = read_mesh(missing_dir / (src.stem + ".vtu"))
        polygon = read_polygon(src)
        assert len(points) == len(polygon.vertices) + 40
        check_mesh(points, triangles, polygon)
    assert out.count("wrote ") == 2


def test_batch_json_lists_failures_and_stats_go_on(capsys, tmp_path):
    bad = bowtie(tmp_path)
    code, out, err = run(capsys, "mesh", bad, SQUARE, "-n", 30, "-o", tmp_path / "j", "--json")
    assert code == 2 and err.strip().splitlines()[-1].endswith("1 of 2 inputs failed")
    docs = json.loads(out)
    assert docs[0]["input"] == str(bad) and "intersects itself" in docs[0]["error"]
    assert docs[1]["n_steiner"] == 30 and docs[1]["quality"]["n_vertices"] == 34
    code, out, err = run(capsys, "mesh", bad, SQUARE, "-n", 30, "-o", tmp_path / "s", "--stats")
    assert code == 2 and out.count("Mesh quality") == 1


def test_batch_failure_lines_stay_whole_beside_the_progress_bar(capsys, tmp_path, monkeypatch):
    import sys

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    bad = bowtie(tmp_path)
    code, out, err = run(capsys, "mesh", SQUARE, bad, "-n", 20, "-o", tmp_path / "o")
    lines = [line.split("\r")[-1] for line in err.splitlines()]
    assert code == 2 and "meshing" in err
    assert any(line.startswith(f"uniform2d: error: {bad}") for line in lines), err
    assert "uniform2d: error: 1 of 2 inputs failed" in lines


def test_batch_memory_error_fails_one_input_only(capsys, tmp_path, monkeypatch):
    import uniform2d.cli.mesh as cli_mesh

    real = cli_mesh._mesh_one

    def mesh_one(polygon, args, *rest):
        if len(polygon.vertices) == 4:
            raise MemoryError("Unable to allocate 44.7 GiB")
        return real(polygon, args, *rest)

    monkeypatch.setattr(cli_mesh, "_mesh_one", mesh_one)
    code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 30, "-o", tmp_path / "m")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 2
    assert "square.json" in lines[0] and "out of memory" in lines[0] and "fewer points" in lines[0]
    assert files(tmp_path / "m") == ["truss_panel.vtu"]


# -- output paths ----------------------------------------------------------------
def test_plot_with_several_inputs_must_name_a_directory(capsys, tmp_path):
    for plot in ("p.png", "figs"):
        code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 20, "-o", tmp_path / "o",
                             "--plot", tmp_path / plot)
        line = one_error(code, err)
        assert "--plot must be a directory" in line and "ending in '/'" in line
    assert files(tmp_path) == [], "refused only after meshing"
    (tmp_path / "existing").mkdir()
    for plot in (tmp_path / "existing", f"{tmp_path / 'new'}/"):
        code, out, err = run(capsys, "-q", "mesh", SQUARE, PANEL, "-n", 20, "-o", tmp_path / "o",
                             "--plot", plot)
        assert code == 0, err
        assert files(Path(plot)) == ["square.png", "truss_panel.png"]


def test_one_input_and_a_trailing_slash_names_a_new_directory(capsys, tmp_path):
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", f"{tmp_path / 'new' / 'sub'}/",
                         "--plot", f"{tmp_path / 'figs'}/")
    assert code == 0, err
    points, triangles = read_mesh(tmp_path / "new" / "sub" / "square.vtu")
    check_mesh(points, triangles, read_polygon(SQUARE))
    assert (tmp_path / "figs" / "square.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("option, value", [
    ("-o", "afile/x.vtu"), ("-o", "afile/sub/"), ("--plot", "afile/p.png"),
    ("--plot", "afile/figs/"), ("-o", "afile/deeper/x.vtu"),
])
def test_an_output_under_a_file_is_refused_before_meshing(capsys, tmp_path, monkeypatch, option,
                                                          value):
    import uniform2d.cli.mesh as cli_mesh

    monkeypatch.setattr(cli_mesh, "_mesh_one", lambda *a: pytest.fail("meshed before the check"))
    (tmp_path / "afile").write_text("")
    args = ["-o", tmp_path / "x.vtu"] if option == "--plot" else []
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, *args, option, f"{tmp_path}/{value}")
    line = one_error(code, err)
    assert f"'{tmp_path / 'afile'}' is a file" in line and "does not exist" not in line
    assert files(tmp_path) == ["afile"]


def test_an_output_in_a_missing_directory_is_refused_before_meshing(capsys, tmp_path, monkeypatch):
    import uniform2d.cli.mesh as cli_mesh

    monkeypatch.setattr(cli_mesh, "_mesh_one", lambda *a: pytest.fail("meshed before the check"))
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "nodir" / "x.vtu")
    line = one_error(code, err)
    assert f"'{tmp_path / 'nodir'}' does not exist" in line and "create it" in line
    assert files(tmp_path) == []


def test_unknown_format_names_what_the_user_typed(capsys, tmp_path):
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "--format", "foo")
    line = one_error(code, err)
    assert "--format 'foo'" in line and "output" not in line and ".vtu" in line
    code, out, err = run(capsys, "-q", "mesh", SQUARE, "-n", 20, "-o", tmp_path, "--format", "MSH")
    assert code == 0, err
    assert (tmp_path / "square.msh").is_file()


# -- what the disk says ------------------------------------------------------------------
def test_disk_full_names_the_users_file(capsys, tmp_path, monkeypatch):
    from uniform2d.io import registry

    fmt = registry.MESH_FORMATS[".vtu"]

    def full(path, *args, **kwargs):
        with open(path, "wb") as f:
            f.write(b"half a mesh")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))  # as write() raises it: no file

    broken = type(fmt)(**{**fmt.__dict__, "writer": full})
    monkeypatch.setitem(registry.MESH_FORMATS, ".vtu", broken)
    out_file = tmp_path / "x.vtu"
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", out_file)
    line = one_error(code, err)
    assert str(out_file) in line and "No space left on device" in line
    assert "free some disk space" in line and ".tmp-" not in line
    assert files(tmp_path) == []


def test_disk_full_while_saving_the_figure_names_the_figure(capsys, tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    def full(self, fname, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(Figure, "savefig", full)
    png = tmp_path / "p.png"
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "x.vtu", "--plot", png)
    line = one_error(code, err)
    assert line.endswith(f"{png}; free some disk space or write to another disk")
    assert files(tmp_path) == []


def test_plot_on_a_read_only_file_system_names_the_figure(capsys, tmp_path, monkeypatch):
    real_open = os.open
    ro = tmp_path / "ro"
    ro.mkdir()

    def read_only(path, flags, *args, **kwargs):
        if Path(path).parent == ro and flags & os.O_CREAT:
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(path))
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", read_only)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "x.vtu",
                         "--plot", ro / "p.png")
    line = one_error(code, err)
    assert f"Read-only file system: {ro / 'p.png'}; " in line and "write somewhere else" in line
    assert ".tmp-" not in line
    assert files(tmp_path) == ["ro"]


def test_report_into_an_existing_file_fails_before_any_work(capsys, tmp_path, monkeypatch):
    import uniform2d.report

    monkeypatch.setattr(uniform2d.report, "make_report",
                        lambda *a, **k: pytest.fail("started the report"))
    target = tmp_path / "results.html"
    target.write_text("keep me")
    code, out, err = run(capsys, "report", SQUARE, "-o", target)
    line = one_error(code, err)
    assert f"-o '{target}' is a file, not a directory" in line
    assert target.read_text() == "keep me"


def test_atomic_write_says_when_the_parent_is_a_file(tmp_path):
    from uniform2d.io.atomic import atomic_write

    (tmp_path / "afile").write_text("")
    with pytest.raises(NotADirectoryError, match="'.*afile' is a file, not a directory"):
        atomic_write(tmp_path / "afile" / "x.txt", lambda tmp: None)
