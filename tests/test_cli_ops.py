"""Running the command: huge n refused at once, the first-run notice, the progress of
one long mesh, Ctrl-C, and batches in local processes or on a Dask cluster (same
bytes as a serial run, keep-going)."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from uniform2d import Polygon, TooManyPointsError, Uniform2dError, uniform_mesh
from test_cli_batch import files, one_error, run
from uniform2d.cli.main import main
from uniform2d.optimize.pipeline import PHASES

DATA = Path(__file__).resolve().parents[1] / "data"
SQUARE = DATA / "benchmarks" / "square.json"
PANEL = DATA / "truss_panel.json"
BRACKET = DATA / "l_bracket.json"
UNIT = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


# -- huge n --------------------------------------------------------------------------
def test_huge_n_is_refused_at_once_like_a_too_small_size(capsys, tmp_path):
    out = tmp_path / "x.vtu"
    code, _, err = run(capsys, "mesh", SQUARE, "-n", 10**9, "-o", out)
    by_n = one_error(code, err)
    code, _, err = run(capsys, "mesh", SQUARE, "--size", 1e-7, "-o", out)
    by_size = one_error(code, err)
    code, _, err = run(capsys, "mesh", SQUARE, "-n", 10**9, "--method", "paper", "-o", out)
    assert one_error(code, err) == by_n
    for line in (by_n, by_size):
        assert line.startswith("uniform2d: error: out of memory (")
        assert line.endswith("); ask for fewer points")
    assert "n = 1000000000 needs at least" in by_n and "this machine has" in by_n
    assert files(tmp_path) == []


def test_too_many_points_is_a_memory_error_and_a_uniform2d_error(monkeypatch):
    import uniform2d.resources as R

    monkeypatch.setattr(R, "physical_memory", lambda: 2**30)
    fits = 2**30 // R.BYTES_PER_POINT
    R.check_point_count(fits)  # exactly what fits is not refused
    with pytest.raises(TooManyPointsError, match=r"n = 7 needs at least 1 GiB of memory, more "
                       r"than the 1 GiB this machine has"):
        R.check_point_count(fits + 1, "n = 7")
    with pytest.raises(MemoryError):
        uniform_mesh(UNIT, n=fits)  # n Steiner points and the 4 corners
    with pytest.raises(Uniform2dError):
        uniform_mesh(UNIT, size=1e-6)
    monkeypatch.setattr(R, "physical_memory", lambda: None)  # unknown: nothing refused
    R.check_point_count(10**15)


# -- first run -----------------------------------------------------------------------
@pytest.mark.compile_cache
def test_an_empty_numba_cache_is_cold_and_a_used_one_is_not(tmp_path):
    from uniform2d.compile_cache import cold_kernels, kernels_cold

    code = "from uniform2d.compile_cache import cold_kernels; print(*cold_kernels())"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    run_ = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=300)
    cold, total = map(int, run_.stdout.split())
    assert total > 20 and cold == total
    uniform_mesh(UNIT, 30)  # compiles (or loads) what a mesh needs, in this process's cache
    cold, total = cold_kernels()
    assert cold < total / 2 and kernels_cold() is False


#: In a fresh process on this checkout's cache: every kernel that Python code
#: does not call made stale (what numba reads from the index of a kernel whose
#: source was edited since: nothing), then whether the cache counts as cold, and
#: the uniform2d kernels a mesh then compiles.
STALE_CALLEES = r"""
import json
from numba.core import event
from uniform2d import Polygon, uniform_mesh
from uniform2d.compile_cache import _kernel_dispatchers, entry_kernels, kernels_cold

dispatchers = _kernel_dispatchers()
entries = {id(d) for d in entry_kernels(dispatchers)}
stale = [d for d in dispatchers if id(d) not in entries]
for d in stale:
    d._cache._cache_file._load_index = dict
compiled = []

class Compiled(event.Listener):
    def on_start(self, e):
        pass

    def on_end(self, e):
        f = e.data["dispatcher"].py_func
        if (f.__module__ or "").startswith("uniform2d."):
            compiled.append(f.__qualname__)

event.register("numba:compile", Compiled())
cold = kernels_cold()
uniform_mesh(Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), 30)
print(json.dumps({"stale": len(stale), "total": len(dispatchers), "cold": cold,
                  "compiled": compiled}))
"""


@pytest.mark.compile_cache
def test_stale_entries_of_kernels_only_kernels_call_do_not_make_the_cache_cold():
    """A development checkout's cache after a kernel called only by other kernels
    was edited: its callers load from the cache all the same (numba does not
    look at their callees' entries), so nothing compiles, and the cache is not
    cold though most kernels' entries are stale."""
    from uniform2d.compile_cache import _kernel_dispatchers, entry_kernels

    uniform_mesh(UNIT, 30)  # this checkout's cache holds what the mesh needs
    names = {d.py_func.__qualname__ for d in entry_kernels(_kernel_dispatchers())}
    assert {"run", "push_initial", "to_segments", "legalize_all"} <= names  # called from Python
    assert not names & {"_revalidate", "eval_segment", "two_sum", "incircle"}  # only from kernels
    done = subprocess.run([sys.executable, "-c", STALE_CALLEES], capture_output=True, text=True,
                          timeout=300, check=True)
    res = json.loads(done.stdout)
    assert res["stale"] > res["total"] / 2  # counting every kernel, the cache would look cold
    assert res["cold"] is False and res["compiled"] == []


def test_the_notice_is_printed_once_only_when_compiling(capsys, tmp_path, monkeypatch):
    import uniform2d.compile_cache as C

    monkeypatch.setattr(C, "kernels_cold", lambda: True)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "a.vtu")
    assert code == 0 and err.count(C.COMPILE_NOTICE) == 1 and err.startswith("uniform2d: ")
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "b.vtu", "-q")
    assert code == 0 and err == ""
    monkeypatch.setattr(C, "kernels_cold", lambda: False)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "c.vtu")
    assert code == 0 and err == ""


@pytest.mark.compile_cache
def test_a_cache_numba_cannot_read_says_nothing(monkeypatch):
    import uniform2d.compile_cache as C

    def broken():
        raise AttributeError("numba moved its cache internals")

    monkeypatch.setattr(C, "cold_kernels", broken)
    assert C.kernels_cold() is None


# -- progress of one mesh ---------------------------------------------------------------
def test_uniform_mesh_reports_its_phases_in_order_and_the_same_mesh():
    calls = []
    mesh = uniform_mesh(UNIT, 60, progress=lambda *a: calls.append(a))
    plain = uniform_mesh(UNIT, 60)
    assert np.array_equal(mesh.points, plain.points)
    assert np.array_equal(mesh.triangles, plain.triangles)
    phases = [p for p, _, _ in calls]
    seen = list(dict.fromkeys(phases))
    assert seen == list(PHASES)  # 64 points: every phase, relocation included
    for phase in seen:
        steps = [(d, t) for p, d, t in calls if p == phase]
        total = steps[0][1]
        assert steps[0][0] == 0 and steps[-1] == (total, total)
        assert [d for d, _ in steps] == sorted(d for d, _ in steps)
    assert max(t for p, _, t in calls if p == "seed") > 1  # several starts, one step each


def test_phase_bar_shows_only_after_its_delay():
    from uniform2d.cli._common import PhaseBar

    shown, silent = io.StringIO(), io.StringIO()
    for stream, delay in ((shown, 0.0), (silent, 60.0)):
        bar = PhaseBar(PHASES, "square.json", delay=delay, file=stream)
        uniform_mesh(UNIT, 30, progress=bar)
        bar.close()
    assert "square.json" in shown.getvalue() and "seed" in shown.getvalue()
    assert silent.getvalue() == ""


# -- Ctrl-C ------------------------------------------------------------------------------
def test_ctrl_c_while_meshing_stops_with_one_line_and_no_file(capsys, tmp_path, monkeypatch):
    import uniform2d.uniform

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(uniform2d.uniform, "uniform_mesh", interrupted)
    code, out, err = run(capsys, "mesh", SQUARE, PANEL, "-n", 20, "-o", f"{tmp_path}/out/",
                         "--plot", f"{tmp_path}/figs/")
    assert code == 130 and err == "uniform2d: interrupted\n" and out == ""
    assert [p for p in files(tmp_path) if Path(p).suffix] == []


def test_an_internal_error_is_one_line_exit_1_and_no_file(capsys, tmp_path, monkeypatch):
    import uniform2d.uniform
    from uniform2d.errors import InternalError

    def invalid(*args, **kwargs):
        raise InternalError("uniform_mesh made an invalid mesh (test); please report it")

    monkeypatch.setattr(uniform2d.uniform, "uniform_mesh", invalid)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "sq.vtu",
                         "--plot", tmp_path / "sq.png")
    assert code == 1 and out == ""
    assert err == "uniform2d: internal error: uniform_mesh made an invalid mesh (test); please report it\n"
    assert files(tmp_path) == []


def test_ctrl_c_while_writing_leaves_no_partial_file(capsys, tmp_path, monkeypatch):
    import meshio

    def half_written(path, *args, **kwargs):
        Path(path).write_text("<VTKFile half of it")
        raise KeyboardInterrupt

    monkeypatch.setattr(meshio, "write", half_written)
    code, out, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "sq.vtu",
                         "--plot", tmp_path / "sq.png")
    assert code == 130 and err == "uniform2d: interrupted\n"
    assert files(tmp_path) == []


# -- batches beyond one process ------------------------------------------------------------
@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """Three polygons and a bad one, and their serial run."""
    d = tmp_path_factory.mktemp("batch")
    bad = d / "bowtie.json"
    bad.write_text(json.dumps({"outer": [[0, 0], [2, 2], [2, 0], [0, 1]]}))
    inputs = [str(SQUARE), str(bad), str(PANEL), str(BRACKET)]
    serial = d / "serial"
    code = main(["mesh", *inputs, "-n", "40", "-o", f"{serial}/", "--json", "-q"])
    assert code == 2
    return inputs, serial


def _check_same_as_serial(capsys, batch, out: Path, *options):
    inputs, serial = batch
    capsys.readouterr()
    code, stdout, err = run(capsys, "mesh", *inputs, "-n", 40, "-o", f"{out}/", *options)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 2, err
    assert lines[0].startswith("uniform2d: error: ") and "bowtie.json" in lines[0]
    assert lines[1] == "uniform2d: error: 1 of 4 inputs failed"
    assert files(out) == files(serial) == ["l_bracket.vtu", "square.vtu", "truss_panel.vtu"]
    for name in files(serial):
        assert (out / name).read_bytes() == (serial / name).read_bytes(), name
    wrote = [line.split()[1] for line in stdout.splitlines()]
    assert wrote == [str(out / n) for n in ("square.vtu", "truss_panel.vtu", "l_bracket.vtu")]


def test_jobs_2_writes_the_same_bytes_and_keeps_going(capsys, batch, tmp_path):
    _check_same_as_serial(capsys, batch, tmp_path / "jobs", "--jobs", 2)


def test_a_local_dask_cluster_writes_the_same_bytes_and_keeps_going(capsys, batch, tmp_path):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        _check_same_as_serial(capsys, batch, tmp_path / "dask", "--scheduler",
                              cluster.scheduler_address)


def test_jobs_and_scheduler_errors(capsys, tmp_path, monkeypatch):
    import importlib.util

    code, _, err = run(capsys, "mesh", SQUARE, "-n", 20, "-o", tmp_path / "a.vtu", "--jobs", 0)
    assert "--jobs must be at least 1, got 0" in one_error(code, err)
    code, _, err = run(capsys, "mesh", SQUARE, "-n", 20, "--jobs", 2, "--scheduler", "tcp://x:1")
    assert code == 2 and "not allowed with argument" in err
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "distributed" else real(name, *a))
    code, _, err = run(capsys, "mesh", SQUARE, "-n", 20, "--scheduler", "tcp://127.0.0.1:1")
    assert "pip install 'uniform2d[dask]'" in one_error(code, err)
    assert files(tmp_path) == []


def test_remesh_batches_keep_going_with_the_same_bytes_in_two_processes(capsys, tmp_path):
    pytest.importorskip("igl")
    pytest.importorskip("pymeshlab")
    bad = tmp_path / "broken.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    inputs = [DATA / "patches" / "cap60.obj", bad, DATA / "patches" / "plate_hole.obj"]
    outputs = {}
    for how in ("serial", "jobs"):
        extra = ["--jobs", 2] if how == "jobs" else []
        code, out, err = run(capsys, "remesh", *inputs, "-n", 60, "-o", f"{tmp_path}/{how}/",
                             "--format", "ply", *extra)
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 2, err
        assert "broken.obj" in lines[0] and lines[1] == "uniform2d: error: 1 of 3 inputs failed"
        assert files(tmp_path / how) == ["cap60.ply", "plate_hole.ply"]
        assert [line.split()[1] for line in out.splitlines()] == [
            f"{tmp_path}/{how}/cap60.ply", f"{tmp_path}/{how}/plate_hole.ply"]
        outputs[how] = {n: (tmp_path / how / n).read_bytes() for n in files(tmp_path / how)}
    assert outputs["serial"] == outputs["jobs"]
    code, out, err = run(capsys, "remesh", *inputs, "-n", 60, "-o", tmp_path / "x.ply")
    assert "with several inputs, -o must be a directory" in one_error(code, err)
    assert not (tmp_path / "x.ply").exists()
