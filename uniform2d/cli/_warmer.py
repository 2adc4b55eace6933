"""The first run's second core: compiling the kernels a mesh needs late, ahead of it.

numba compiles a kernel when it is first called, one after another, in the
calling process: on a cold cache the command's first ``mesh`` spends most of its
time compiling, on one core, while the other cores idle.  What a run compiles
goes into numba's disk cache (``cache=True``), and numba looks there before it
compiles anything, a kernel called from Python or one typed as the callee of
another.  So when the command finds the kernels cold, :func:`start` starts one
background process that runs :func:`warm`, which compiles in an order chosen
against the order the run needs the kernels in.  The run first compiles the
exact triangulation of P and INSERT's queues; the warmer meanwhile compiles
INSERT's first step, which the run types next.  Then the kernels the run needs
after INSERT, from the last (the optimiser's spread sweeps) back to the first
(the measures of T+'s mesh): the run, compiling them from the first, meets
the warmer halfway instead of following it.  Whatever the warmer finished,
the run loads; whatever it did not, the run compiles as before.  A second process only helps on a CPU that would
otherwise idle, so none is started when the system's load leaves none idle.

A kernel is cached per argument types (dtypes, layouts, int32 against int64),
so the warmer makes its calls with the library's own code on tiny inputs (a
lattice mesh loaded as the optimiser loads one; INSERT's queues as INSERT makes
them), and where a call cannot run on those, with signatures written out;
``tests/test_warmer.py`` checks that a run after it compiles
none of its kernels again.

The warmer prints nothing and writes nothing but numba's cache (each file to a
temporary name, then renamed: stopping it at any moment leaves no torn entry,
at worst one stray temporary file).
It ignores Ctrl-C and ends when the command ends, however it ends
(:func:`stop`, or the end of its stdin if the command dies first).
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading

__all__ = ["warm", "start", "stop", "spare_cpus", "busy"]

log = logging.getLogger(__name__)


def warm() -> None:
    """Compile, into numba's cache, kernels a :func:`uniform2d.uniform_mesh` run
    compiles late, by running the library's code on tiny inputs, in the order
    the module docstring gives."""
    from numba import types

    from .._kernel import cdt, heap
    from .._kernel import insert as kinsert
    from ..optimize import moves, pipeline
    from ..optimize import schedule as S
    from ..optimize.objective import objective_code
    from ..optimize.seed import target_size, variants
    from .._kernel.edges import edges_by_vertex

    # INSERT's first step, which brings most of its predicates, while the run
    # compiles the exact triangulation of P and INSERT's queues (its later
    # steps the run reaches before the warmer could finish them)
    m, _ = cdt.allocate(4, 4)
    M, P = heap.new_heap(16), kinsert.new_pool(64)
    kinsert._gather(m, M, P, 0.0)

    # then what the run compiles after INSERT, from its end back: the
    # optimiser's stages, the last first, on a lattice mesh ...
    polygon, points, triangles, edges = _lattice(4)
    st = moves._load(polygon, points, triangles, None, None, None, edges)
    obj = objective_code("balanced")
    none = moves.default_schedule(len(st.xy), False)._replace(
        spring_rounds=0, sweeps=1, exponents=(), spread_sweeps=0)
    for stage in (dict(spread_sweeps=1), dict(exponents=(S.AFTER_TRIALS,)),
                  dict(spring_rounds=1)):
        moves.advance(st, none._replace(**stage), obj)
        moves.rank(st, obj)
    # ... its start (the distance to P's edges) and the start's check ...
    n = len(points) - len(polygon.vertices)
    pipeline._start(polygon, n, target_size(polygon, n), variants(polygon, n)[0])
    moves.finish(polygon, moves.unload(polygon, st), moves.Progress())
    # ... and the measures of T+'s mesh (always on read-only triangles)
    edges_by_vertex.compile((types.Array(types.int64, 2, "C", readonly=True), types.int64))


def _lattice(k: int):
    """(square polygon, points, triangles, edges): the k x k unit lattice of the
    square [0, k]^2 cut into triangles (Delaunay), its corners first, then the
    other lattice points, with the polygon edge each lies on (-1 inside)."""
    import numpy as np

    from ..polygon import Polygon

    g = np.arange(k + 1, dtype=np.float64)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    corner = np.array([0, k, (k + 1) ** 2 - 1, k * (k + 1)])
    order = np.concatenate([corner, np.setdiff1d(np.arange((k + 1) ** 2), corner)])
    rank = np.argsort(order)  # lattice index -> place in ``order``
    a = (np.arange(k)[:, None] * (k + 1) + np.arange(k)[None, :]).ravel()  # lower-left corners
    cells = np.stack([a, a + 1, a + k + 2, a + k + 1], axis=1)
    triangles = rank[np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])]
    points = np.column_stack([x, y])[order]
    edges = np.full(len(points), -1, np.int64)
    for e, (axis, value) in enumerate([(1, 0.0), (0, k), (1, k), (0, 0.0)]):
        edges[points[:, axis] == value] = e
    polygon = Polygon(points[:4])
    return polygon, points, triangles.astype(np.int64), edges[4:]


def spare_cpus() -> int:
    """CPUs this process may run on (its affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def busy(cpus: int) -> bool:
    """Whether other work leaves fewer than two of ``cpus`` idle, one for this
    run and one for the warmer: then a second compiling process takes CPU from
    the run itself (with per-session scheduling, as Linux's autogroups, the
    command's share of the machine does not grow with its processes).

    Measured over a tenth of a second where the system says how busy its CPUs
    are (Linux's ``/proc/stat``): the last minute's load average, the fallback,
    still counts work that has just ended (the ``pip install`` before a first
    run).  False where neither can be read."""
    idle = _idle_cpus(0.1)
    if idle is not None:
        return idle < min(cpus, 2) - 0.5
    try:
        return os.getloadavg()[0] > cpus - 1
    except (AttributeError, OSError):
        return False


def _idle_cpus(interval: float) -> float | None:
    """How many CPUs (of all the system's) idled over the next ``interval``
    seconds, from ``/proc/stat``'s totals; None where it cannot be read."""
    import time

    def totals():
        with open("/proc/stat", encoding="ascii") as f:
            ticks = [int(t) for t in f.readline().split()[1:]]
        return ticks[3] + ticks[4], sum(ticks)  # idle + iowait, all

    try:
        idle0, all0 = totals()
        time.sleep(interval)
        idle1, all1 = totals()
    except (OSError, ValueError, IndexError):
        return None
    if all1 <= all0:
        return None
    return (idle1 - idle0) / (all1 - all0) * (os.cpu_count() or 1)


def start() -> subprocess.Popen | None:
    """Start the warmer process, for a run about to compile the kernels, if it can
    help: their cache is writable, this process may use two CPUs or more and
    one of them is idle (:func:`busy`).  Returns it, or None."""
    from ..compile_cache import cache_writable

    cpus = spare_cpus()
    if not sys.executable or cpus < 2 or busy(cpus) or not cache_writable():
        return None
    # the package this process runs, whatever the current directory holds
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    code = f"import sys; sys.path[0] = {root!r}; from uniform2d.cli._warmer import main; main()"
    try:
        return subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:  # no process to spare: the run compiles everything itself
        log.debug("cannot start the kernel warmer", exc_info=True)
        return None


def stop(proc: subprocess.Popen | None) -> None:
    """End the warmer (it may be in the middle of a compile: nothing is lost but
    that compile) and wait for it."""
    if proc is None:
        return
    proc.kill()
    proc.wait()
    proc.stdin.close()


def _exit_at_eof() -> None:
    sys.stdin.buffer.read()
    os._exit(0)


def main() -> None:
    """The warmer process: :func:`warm`, ending early when its stdin closes."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command decides when to stop
    threading.Thread(target=_exit_at_eof, daemon=True).start()
    warm()
