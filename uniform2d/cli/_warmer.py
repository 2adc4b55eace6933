"""The first run's second core: compiling the kernels a mesh needs late, ahead of it.

numba compiles a kernel when it is first called, one after another, in the
calling process: on a cold cache the command's first ``mesh`` spends most of its
time compiling, on one core, while the other cores idle.  What a run compiles
goes into numba's disk cache (``cache=True``), and numba looks there before it
compiles anything, a kernel called from Python or one typed as the callee of
another.  So when :func:`start` finds the kernels cold, it starts one background
process that runs :func:`warm`: the library's own code on a tiny mesh, in an
order chosen against the order a run needs the kernels in.  First the cavity
insertion INSERT's main loop calls too (the run gets there after the exact
triangulation, its first kernels); then what the run needs after INSERT, from
the last (the spread sweeps) to the first, so that the run, compiling from the
first, meets the warmer halfway instead of following it.  Whatever the warmer
finished, the run loads; whatever it did not, the run compiles as before.

The warmer runs the library's code rather than compiling named signatures
because a kernel is cached per argument types (dtypes, layouts, int32 against
int64): only the same calls made the same way compile what a run looks up
(``tests/test_warmer.py`` checks that a run compiles none of them again).

The warmer prints nothing and writes nothing but numba's cache (each file to a
temporary name, then renamed: stopping it at any moment leaves no torn entry).
It ignores Ctrl-C and ends when the command ends, however it ends
(:func:`stop`, or the end of its stdin if the command dies first).
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading

__all__ = ["warm", "start", "stop", "spare_cpus"]

log = logging.getLogger(__name__)


def warm() -> None:
    """Compile, into numba's cache, what a :func:`uniform2d.uniform_mesh` run
    compiles besides the exact triangulation of P and INSERT, by running the
    library's code on a tiny mesh (see the module docstring for the order)."""
    import numpy as np

    from .._kernel import cavity, cdt
    from ..optimize import moves, pipeline
    from ..optimize import schedule as S
    from ..optimize.objective import objective_code
    from ..optimize.seed import target_size, variants
    from ..polygon import Polygon

    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    polygon, n = Polygon(square), 24
    h = target_size(polygon, n)
    sites, edges, frozen, _ = pipeline._start(polygon, n, h, variants(polygon, n)[0])
    # the cavity insertion INSERT's loop calls, typed as it calls it (as
    # polytri.triangulate does), without the rings' Delaunay legalisation
    m, xy = cdt.allocate(3 + len(sites), 2 * len(sites) + 8)
    xy[:3] = [[-8.0, -8.0], [8.0, -8.0], [0.0, 8.0]]
    xy[3:] = sites
    cdt.set_nv(m, len(xy))
    cdt.build_adjacency(m, np.array([[0, 1, 2]], np.int32))
    cavity.insert_sites(m, np.arange(3, len(xy), dtype=np.int64))

    st = moves.load(polygon, sites, href=h, frozen=frozen, edges=edges)
    obj = objective_code("balanced")
    none = moves.default_schedule(len(st.xy), False)._replace(
        spring_rounds=0, sweeps=1, exponents=(), spread_sweeps=0)
    for stage in (dict(spread_sweeps=1), dict(exponents=(S.AFTER_TRIALS,)),
                  dict(spring_rounds=1)):
        moves.advance(st, none._replace(**stage), obj)
        moves.rank(st, obj)
    moves.finish(polygon, moves.unload(polygon, st), moves.Progress())


def spare_cpus() -> int:
    """CPUs this process may run on (its affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def start() -> subprocess.Popen | None:
    """Start the warmer process, for a run about to compile the kernels, if it can
    help: their cache is writable and this process may use two CPUs or more.
    Returns it, or None."""
    from ..compile_cache import cache_writable

    if spare_cpus() < 2 or not cache_writable():
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
