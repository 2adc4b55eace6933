"""The first run's kernel warmer: it compiles what a run looks up later, and the
command starts it only on a cold cache, says nothing through it, and stops it."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from test_cli_batch import run
from uniform2d.cli import _warmer

DATA = Path(__file__).resolve().parents[1] / "data"
PLATE = DATA / "plate_bolts.json"
SQUARE = DATA / "benchmarks" / "square.json"

#: Runs in a fresh process: the uniform2d kernels numba compiles (not loads from
#: its cache) while the code in argv[1] runs, in order, as JSON on stdout; the
#: code may append to ``marks`` the count compiled so far.
COMPILES = r"""
import json, sys
from numba.core import event

compiled, marks = [], []

class Compiled(event.Listener):
    def on_start(self, e):
        pass

    def on_end(self, e):
        f = e.data["dispatcher"].py_func
        if (f.__module__ or "").startswith("uniform2d."):
            compiled.append((f"{f.__module__}.{f.__qualname__}", str(e.data["args"])))

event.register("numba:compile", Compiled())
exec(sys.argv[1])
json.dump({"compiled": compiled, "marks": marks}, sys.stdout)
"""

#: As the command line's processes on a cold cache: kernels no Python code
#: calls compiled without a wrapper for Python (see uniform2d._kernel.pywrap).
DROP = "from uniform2d.compile_cache import drop_unused_wrappers; drop_unused_wrappers()\n"

WARM = DROP + "from uniform2d.warmup import warm; warm()"

#: README command 1's mesh; the mark is the end of the T+ phase (INSERT and T+):
#: everything after it is the optimiser's.  On one thread, since with more T+
#: is made beside the optimisation (the phase ends at once) and the mark would
#: split nothing; the kernels' types are the same either way.
MESH = DROP + f"""
from uniform2d import uniform_mesh
from uniform2d.threads import set_threads
from uniform2d.io import read_polygon

set_threads(1)

def progress(phase, done, total):
    if (phase, done) == ("T+", 1):
        marks.append(len(compiled))

uniform_mesh(read_polygon({str(PLATE)!r}), 400, progress=progress)
"""


def _compiles(code: str, cache: Path) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run([sys.executable, "-c", COMPILES, code], env=env, capture_output=True,
                          text=True, timeout=900, check=True)
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def warmed_then_meshed(tmp_path_factory):
    """(the warmer's compiles, the mesh's record) on one cold cache: the
    README mesh after the warmer, as a first run makes them."""
    cache = tmp_path_factory.mktemp("numba_cache")
    return _compiles(WARM, cache)["compiled"], _compiles(MESH, cache)


@pytest.mark.slow
@pytest.mark.compile_cache
def test_a_mesh_after_the_warmer_compiles_nothing_it_compiled_nor_anything_after_insert(
        warmed_then_meshed):
    """The warmer's calls are typed as the run's: were one argument's type to
    drift (a dtype, a layout, int32 for int64), the run would compile that
    kernel again, under another signature, and this would fail.  INSERT, the
    run's last compile, is the warmer's first: whole (its run and the steps it
    calls by name), the run compiles none of it."""
    warmed, mesh = warmed_then_meshed
    names = {name for name, _ in warmed}
    later = {"uniform2d._kernel.cavity.insert_point", "uniform2d._kernel.distance.to_segments",
             "uniform2d._kernel.validity._unmatched", "uniform2d._kernel.spring.spring",
             "uniform2d._kernel.descent.descend", "uniform2d._kernel.spread.spread",
             "uniform2d._kernel.star.edge_cv", "uniform2d._kernel.star.refresh_sizes",
             "uniform2d._kernel.insert.run", "uniform2d._kernel.insert.push_initial",
             "uniform2d._kernel.insert._gather", "uniform2d._kernel.insert._choose",
             "uniform2d._kernel.edges.edges_by_vertex",
             "uniform2d._kernel.clearance.closest_pair"}
    assert later <= names
    compiled, (insert_done,) = mesh["compiled"], mesh["marks"]
    assert {tuple(c) for c in compiled} & {tuple(w) for w in warmed} == set()  # the cache works
    # ... and the run typed no kernel the warmer compiled another way (but the
    # one made for several array dtypes)
    again = {name for name, _ in compiled} & names - {"uniform2d._kernel.heap.grown"}
    assert again == set()
    assert compiled[insert_done:] == []  # the optimiser compiles nothing


@pytest.mark.slow
@pytest.mark.compile_cache
def test_the_first_run_compiles_every_kernel_for_one_type_of_arguments(warmed_then_meshed):
    """Each specialisation is compiled with its callees: a kernel called
    with an int32 here and an int64 there, or a literal 0 (numba types
    ``Literal[int](0)`` apart from int64), would be compiled twice.  Only
    heap.grown is meant for several array dtypes, and the half-edge steps
    cdt.nxt and cdt.prv take the half-edges read from the int32 arrays as
    they are (two one-line compiles; a cast at every call site would not be
    worth them)."""
    warmed, mesh = warmed_then_meshed
    signatures: dict = {}
    for name, args in warmed + mesh["compiled"]:
        signatures.setdefault(name, set()).add(args)
    twice = {name: sorted(s) for name, s in signatures.items() if len(s) > 1}
    for meant in ("heap.grown", "cdt.nxt", "cdt.prv"):
        twice.pop(f"uniform2d._kernel.{meant}", None)
    assert twice == {}


# -- the command -------------------------------------------------------------------------
class _Started:
    """Records the warmers the command starts (real ones, or none)."""

    def __init__(self, monkeypatch, real=True):
        self.procs = []
        start = _warmer.start

        def recording():
            proc = start() if real else None
            self.procs.append(proc)
            return proc

        monkeypatch.setattr(_warmer, "start", recording)


def _ended(warmer) -> bool:
    """Whether every process of ``warmer`` has ended (and been waited for)."""
    return all(p.returncode is not None for p in warmer.procs)


@pytest.fixture
def cold(monkeypatch):
    """A cold cache, on a machine with a CPU to spare (whatever its load now)."""
    import uniform2d.compile_cache as C

    monkeypatch.setattr(C, "kernels_cold", lambda: True)
    monkeypatch.setattr(_warmer, "busy", lambda cpus: False)


@pytest.mark.skipif(_warmer.spare_cpus() < 2, reason="the warmer needs two CPUs")
def test_the_command_stops_its_warmer_and_prints_the_same_bytes(capfd, tmp_path, monkeypatch,
                                                                   cold):
    started = _Started(monkeypatch)
    code, out, err = run(capfd, "mesh", SQUARE, "-n", 30, "-o", tmp_path / "a.vtu", "--stats")
    (warmer,) = started.procs
    assert code == 0 and warmer is not None and _ended(warmer)
    monkeypatch.setattr(_warmer, "spare_cpus", lambda: 1)
    code, out1, err1 = run(capfd, "mesh", SQUARE, "-n", 30, "-o", tmp_path / "b.vtu", "--stats")
    assert code == 0 and started.procs[1:] == [None]
    assert (out.replace("a.vtu", "b.vtu"), err) == (out1, err1)  # --stats ends with "wrote ..."
    assert (tmp_path / "a.vtu").read_bytes() == (tmp_path / "b.vtu").read_bytes()


@pytest.mark.skipif(_warmer.spare_cpus() < 2, reason="the warmer needs two CPUs")
@pytest.mark.parametrize("stop", [KeyboardInterrupt, ValueError])
def test_an_interrupted_or_failed_command_stops_its_warmer(capfd, tmp_path, monkeypatch, cold,
                                                           stop):
    import uniform2d.uniform as U

    started = _Started(monkeypatch)

    def fails(*args, **kwargs):
        raise stop("stopped")

    monkeypatch.setattr(U, "uniform_mesh", fails)
    code, out, err = run(capfd, "mesh", SQUARE, "-n", 30, "-o", tmp_path / "a.vtu")
    (warmer,) = started.procs
    assert code == (130 if stop is KeyboardInterrupt else 2)
    assert warmer is not None and _ended(warmer)
    assert not (tmp_path / "a.vtu").exists()


def test_no_warmer_when_warm_on_one_cpu_unwritable_or_for_the_paper_method(
        capsys, tmp_path, monkeypatch):
    import uniform2d.compile_cache as C

    started = _Started(monkeypatch, real=False)
    args = ("mesh", SQUARE, "-n", 30, "-o", tmp_path / "a.vtu")
    assert run(capsys, *args)[0] == 0  # the kernels are not cold (conftest)
    monkeypatch.setattr(C, "kernels_cold", lambda: True)
    assert run(capsys, *args, "--method", "paper")[0] == 0
    assert started.procs == []
    assert run(capsys, *args)[0] == 0
    assert started.procs == [None]  # asked for once, on a cold cache


def test_start_refuses_one_cpu_busy_cpus_and_an_unwritable_cache(monkeypatch):
    import uniform2d.compile_cache as C

    def no_process(*args, **kwargs):
        raise AssertionError("no warmer should start")

    monkeypatch.setattr(subprocess, "Popen", no_process)
    monkeypatch.setattr(_warmer, "busy", lambda cpus: False)
    monkeypatch.setattr(_warmer, "spare_cpus", lambda: 1)
    assert _warmer.start() is None
    monkeypatch.setattr(_warmer, "spare_cpus", lambda: 2)
    monkeypatch.setattr(C, "cache_writable", lambda: False)
    assert _warmer.start() is None
    monkeypatch.setattr(C, "cache_writable", lambda: True)
    monkeypatch.setattr(_warmer, "busy", lambda cpus: True)
    assert _warmer.start() is None


def test_cpus_are_busy_when_the_load_leaves_none_idle_besides_the_run(monkeypatch):
    load = [0.0]

    def loadavg():
        if load[0] is None:
            raise OSError("no load average here")
        return (load[0], 0.0, 0.0)

    monkeypatch.setattr(os, "getloadavg", loadavg)
    monkeypatch.setattr(_warmer, "_idle_cpus", lambda interval: None)  # no /proc/stat
    for value, cpus, busy in [(0.2, 2, False), (1.0, 2, False), (1.3, 2, True), (3.5, 2, True),
                              (2.5, 4, False), (3.5, 4, True), (None, 2, False)]:
        load[0] = value
        assert _warmer.busy(cpus) is busy, (value, cpus)


def test_cpus_are_busy_when_fewer_than_two_idle_now(monkeypatch):
    idle = [0.0]
    monkeypatch.setattr(_warmer, "_idle_cpus", lambda interval: idle[0])
    monkeypatch.setattr(os, "getloadavg", lambda: (9.0, 9.0, 9.0))  # not asked: a minute's past
    for value, cpus, busy in [(2.0, 2, False), (1.6, 2, False), (1.2, 2, True), (0.1, 2, True),
                              (1.6, 8, False), (1.2, 8, True)]:
        idle[0] = value
        assert _warmer.busy(cpus) is busy, (value, cpus)


@pytest.mark.skipif(not os.path.exists("/proc/stat"), reason="Linux's CPU totals")
def test_idle_cpus_are_read_between_none_and_all():
    idle = _warmer._idle_cpus(0.05)
    assert idle is not None and 0.0 <= idle <= os.cpu_count()


def test_the_kernels_cache_is_writable_here():
    from uniform2d.compile_cache import cache_writable

    assert cache_writable() is True  # numba caches this test run's kernels somewhere


def test_a_warmer_done_before_the_command_ends_cleanly_with_its_stdin_open():
    """Finished while the command still holds its stdin open, the warmer ends at
    once, with status 0 and nothing on stderr (a normal interpreter exit under the
    thread reading stdin is aborted by Python: SIGABRT, 'Fatal Python error')."""
    root = Path(__file__).resolve().parents[1]
    code = (f"import sys; sys.path[0] = {str(root)!r}; import uniform2d.warmup as w; "
            "w.warm = lambda: None; from uniform2d.cli._warmer import main; main()")
    proc = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert proc.wait(timeout=120) == 0
        assert proc.stderr.read() == b""
    finally:
        proc.kill()
        proc.stdin.close()
        proc.stdout.close()
        proc.stderr.close()


def _warmer_running(claims: Path, code: str, close_stdin: bool = False) -> _warmer.Warmer:
    """A :class:`_warmer.Warmer` whose processes run ``code`` (their stderr in
    the claims directory, as :func:`_warmer.start` has it)."""
    claims.mkdir(exist_ok=True)

    def spawn(stderr):
        with open(stderr, "wb") as err:
            proc = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                                    stdout=subprocess.DEVNULL, stderr=err)
        if close_stdin:
            proc.stdin.close()
        return proc

    return _warmer.Warmer(str(claims), spawn)


def _settled(warmer: _warmer.Warmer) -> None:
    """Wait until the first process has ended, the restart is decided and every
    process started has ended (no time limit in the outcome: the processes end
    by themselves)."""
    warmer.procs[0].wait(timeout=120)
    warmer._watch.join(timeout=120)
    assert not warmer._watch.is_alive()
    for p in warmer.procs:
        p.wait(timeout=120)


@pytest.mark.skipif(not hasattr(os, "kill") or sys.platform == "win32", reason="POSIX signals")
def test_a_warmer_killed_by_a_signal_is_started_again_once_and_both_fault_reports_logged(
        tmp_path, caplog):
    """The code crashes every time: the first process is started again, the
    second is not; stop() logs both ends with faulthandler's reports."""
    import logging

    from uniform2d import compile_claims

    claims = tmp_path / "claims"
    warmer = _warmer_running(claims, "import faulthandler, os, signal; faulthandler.enable(); "
                                     "os.kill(os.getpid(), signal.SIGSEGV)")
    _settled(warmer)
    assert [p.returncode for p in warmer.procs] == [-11, -11]
    compile_claims.share(str(claims))
    with caplog.at_level(logging.DEBUG, logger=_warmer.__name__):
        _warmer.stop(warmer)
    assert "the kernel warmer ended early (signal 11), started again" in caplog.text
    assert "the kernel warmer started again ended early (signal 11); its stderr" in caplog.text
    assert caplog.text.count("Segmentation fault") == 2  # faulthandler's reports, from each stderr
    assert len(warmer.procs) == 2 and not claims.exists() and compile_claims.shared() is None


def test_a_warmer_whose_stdin_ends_first_says_so_is_not_started_again_and_stop_logs_it(
        tmp_path, caplog):
    import logging

    from uniform2d import compile_claims

    root = Path(__file__).resolve().parents[1]
    code = (f"import sys, time; sys.path[0] = {str(root)!r}; import uniform2d.warmup as w; "
            "w.warm = lambda: time.sleep(120); from uniform2d.cli._warmer import main; main()")
    claims = tmp_path / "claims"
    warmer = _warmer_running(claims, code, close_stdin=True)
    _settled(warmer)
    assert [p.returncode for p in warmer.procs] == [_warmer.EOF_STATUS]  # the command is ending
    compile_claims.share(str(claims))
    with caplog.at_level(logging.DEBUG, logger=_warmer.__name__):
        _warmer.stop(warmer)
    assert "ended early (its stdin ended); its stderr: (empty)" in caplog.text
    assert "started again" not in caplog.text


def test_stop_says_nothing_of_a_warmer_done_or_still_at_work_nor_starts_it_again(tmp_path,
                                                                                  caplog):
    import logging

    from uniform2d import compile_claims

    for code in ("pass", "import time; time.sleep(120)"):
        claims = tmp_path / "claims"
        warmer = _warmer_running(claims, code)
        if code == "pass":
            _settled(warmer)
        compile_claims.share(str(claims))
        with caplog.at_level(logging.DEBUG, logger=_warmer.__name__):
            _warmer.stop(warmer)
        assert len(warmer.procs) == 1 and _ended(warmer)
        assert "ended early" not in caplog.text and not claims.exists()
        assert ("was done" if code == "pass" else "stopped at work") in caplog.text
        caplog.clear()


def test_a_warmer_stopped_by_an_exception_says_which_first_and_is_started_again_once(
        tmp_path, caplog):
    """An exception ends the warmer with its own status (not SIGABRT, which a
    normal exit under its stdin's reader would get), the exception's line first
    in its stderr, where stop()'s log starts."""
    import logging

    from uniform2d import compile_claims

    root = Path(__file__).resolve().parents[1]
    code = (f"import sys; sys.path[0] = {str(root)!r}; import uniform2d.warmup as w\n"
            "def warm():\n    raise RuntimeError('no kernel today')\n"
            "w.warm = warm\nfrom uniform2d.cli._warmer import main; main()")
    claims = tmp_path / "claims"
    warmer = _warmer_running(claims, code)
    _settled(warmer)
    assert [p.returncode for p in warmer.procs] == [_warmer.ERROR_STATUS] * 2
    assert (claims / _warmer._STDERR).read_text().startswith(
        "warmer stopped by RuntimeError: no kernel today\n")
    compile_claims.share(str(claims))
    with caplog.at_level(logging.DEBUG, logger=_warmer.__name__):
        _warmer.stop(warmer)
    assert ("the kernel warmer ended early (a Python exception), started again; its stderr: "
            "warmer stopped by RuntimeError: no kernel today") in caplog.text
    assert "the kernel warmer started again ended early (a Python exception)" in caplog.text
    assert "Fatal Python error" not in caplog.text


class _Killed:
    """Has the command's first ``kills`` warmer processes killed (SIGABRT, as
    the early ends seen under load) as soon as they start and, when the command
    starts its warmer, waits until the restart is decided and the killed ones
    have ended: the run then meets the same warmers whatever the timing."""

    def __init__(self, monkeypatch, kills: int):
        import signal

        self.warmers, spawned = [], []

        class Warmer(_warmer.Warmer):
            def __init__(self, claims, spawn):
                def spawn_killed(stderr):
                    proc = spawn(stderr)
                    if len(spawned) < kills:
                        os.kill(proc.pid, signal.SIGABRT)
                    spawned.append(proc)
                    return proc

                super().__init__(claims, spawn_killed)
                self._watch.join(timeout=120)
                assert not self._watch.is_alive()
                for p in self.procs[:kills]:
                    p.wait(timeout=120)
                killed.warmers.append(self)

        killed = self
        monkeypatch.setattr(_warmer, "Warmer", Warmer)


@pytest.mark.skipif(_warmer.spare_cpus() < 2, reason="the warmer needs two CPUs")
@pytest.mark.skipif(not hasattr(os, "kill") or sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("kills", [1, 2])
def test_a_killed_warmer_is_started_again_once_and_the_command_prints_the_same_bytes(
        capfd, tmp_path, monkeypatch, cold, kills):
    """Killed once, the warmer is started again; killed again, not a third time;
    either way the command's output and file are an undisturbed run's."""
    args = ("mesh", SQUARE, "-n", 30, "--stats")
    code, out, err = run(capfd, *args, "-o", tmp_path / "a.vtu")  # undisturbed
    assert code == 0
    killed = _Killed(monkeypatch, kills)
    code, out1, err1 = run(capfd, *args, "-o", tmp_path / "b.vtu")
    assert code == 0
    (warmer,) = killed.warmers
    assert len(warmer.procs) == 2 and _ended(warmer)
    assert [p.returncode for p in warmer.procs][:kills] == [-6] * kills
    assert (out.replace("a.vtu", "b.vtu"), err) == (out1, err1)
    assert (tmp_path / "a.vtu").read_bytes() == (tmp_path / "b.vtu").read_bytes()


#: The command on a cold cache (argv: its arguments), its warmer's first process
#: killed (SIGABRT) as soon as it starts, and the restart decided before the run
#: goes on (as :class:`_Killed` does in this process).
KILLED_FIRST = r"""
import os, signal, sys
import uniform2d.cli._warmer as w

w.busy = lambda cpus: False
base = w.Warmer

class Warmer(base):
    def __init__(self, claims, spawn):
        def spawn_killed(stderr):
            proc = spawn(stderr)
            if not hasattr(self, "procs"):
                os.kill(proc.pid, signal.SIGABRT)
            return proc

        super().__init__(claims, spawn_killed)
        self._watch.join(timeout=600)

w.Warmer = Warmer
from uniform2d.cli.main import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.slow
@pytest.mark.compile_cache
@pytest.mark.skipif(_warmer.spare_cpus() < 2, reason="the warmer needs two CPUs")
@pytest.mark.skipif(not hasattr(os, "kill") or sys.platform == "win32", reason="POSIX signals")
def test_on_a_cold_cache_a_warmer_killed_at_its_start_is_started_again_and_the_mesh_is_the_same(
        capsys, tmp_path):
    """The second warmer compiles the first one's list beside the run, from an
    empty cache: the .vtu is the bytes of a run on this test session's cache."""
    args = ["mesh", str(SQUARE), "-n", "30", "--stats", "-vv"]
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba_cache")}
    done = subprocess.run([sys.executable, "-c", KILLED_FIRST, *args, "-o", str(tmp_path / "a.vtu")],
                          env=env, capture_output=True, text=True, timeout=1800,
                          cwd=Path(__file__).resolve().parents[1])
    assert done.returncode == 0, done.stderr
    assert "the kernel warmer ended early (signal 6), started again" in done.stderr
    assert "the kernel warmer started again ended early" not in done.stderr
    assert run(capsys, *args[:-1], "-o", tmp_path / "b.vtu")[0] == 0
    assert (tmp_path / "a.vtu").read_bytes() == (tmp_path / "b.vtu").read_bytes()
