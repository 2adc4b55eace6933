"""The first run's second core: a process that compiles the kernels a mesh needs late.

numba compiles a kernel when it is first called, one after another, in the
calling process: on a cold cache the command's first ``mesh`` spends most of its
time compiling, on one core, while the other cores idle.  So when the command
finds the kernels cold, :func:`start` starts one background process that runs
:func:`uniform2d.warmup.warm` (what it compiles, and in which order, is the
library's business: see there); whatever it finished, the run loads from
numba's cache, whatever it did not, the run compiles as before, and a kernel
one of them is compiling the other waits for rather than compiling it too
(:mod:`uniform2d.compile_claims`).  A second
process only helps on a CPU that would otherwise idle, so none is started when
the system's load leaves none idle.

The warmer prints nothing and writes nothing but numba's cache (each file to a
temporary name, then renamed: stopping it at any moment leaves no torn entry,
at worst one stray temporary file).
It ignores Ctrl-C and ends when the command ends, however it ends
(:func:`stop`, or the end of its stdin if the command dies first).  Its stderr
goes to a file beside the claims, with ``faulthandler``'s report of a fatal
signal: a warmer that ended early (not by :func:`stop`, nor done) is logged
by :func:`stop`, at debug level (``-vv``), with the start of that file.

A warmer that ends early (a fatal signal, an exit status other than 0 while
the command runs: seen under load, SIGABRT inside numba's compile) is started
again, once (:class:`Warmer`): the kernels it had claimed are claimed no more
(the system drops a dead process's locks), so the run compiles whichever it
reaches first, and the new warmer loads from the cache what the first one
and the run have compiled and goes on down its list, waiting, as the first
did, for a kernel the run is compiling.  So a lost warmer costs the run its
restart (Python and imports, and the compile it was in the middle of), not
the rest of its list compiled by the run.  The compiled kernels are the same
whoever compiles them, and so are the meshes.
"""

from __future__ import annotations

import logging
import os
import shutil
import subprocess
import sys
import tempfile
import threading

from .. import compile_claims

__all__ = ["Warmer", "start", "stop", "spare_cpus", "busy", "main", "EOF_STATUS", "ERROR_STATUS"]

log = logging.getLogger(__name__)

#: The warmer's exit status when its stdin ends before it is done: the command
#: died, or closed the pipe without :func:`stop` (which kills the warmer first).
EOF_STATUS = 3

#: Its exit status after a Python exception (the exception first on its stderr).
ERROR_STATUS = 4

_STDERR = "warmer.stderr"  # the warmer's stderr, in the claims directory
_STDERR_AGAIN = "warmer-2.stderr"  # the restarted one's


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


class Warmer:
    """A run's warmer process, and the one started again if it ends early: once.

    A thread waits for the first process; if it ends before :func:`stop` with a
    status other than 0 (done) or :data:`EOF_STATUS` (the command is ending),
    the same warmer starts again, its stderr in a second file.  The second
    starts after the first has ended, so the two never compile at once (the
    claims are for the warmer and the run, one of each), and a second early
    end is only logged: a fault that comes back at once is not paid for twice.
    """

    def __init__(self, claims: str, spawn):
        """``spawn(stderr_path)`` starts a warmer process (a ``Popen`` with a
        stdin pipe) or raises OSError."""
        self.claims = claims
        self._spawn = spawn
        self.procs = [spawn(os.path.join(claims, _STDERR))]  # the first, then its restart
        self.first_status = None  # the first's status, had it ended early
        self._lock = threading.Lock()  # between the restart and stop()
        self._stopped = False
        self._watch = threading.Thread(target=self._restart_if_early, daemon=True,
                                       name="uniform2d-warmer-watch")
        self._watch.start()

    def _restart_if_early(self) -> None:
        status = self.procs[0].wait()
        with self._lock:
            if self._stopped or status in (0, EOF_STATUS):
                return
            self.first_status = status
            try:
                self.procs.append(self._spawn(os.path.join(self.claims, _STDERR_AGAIN)))
            except OSError:  # the run compiles the rest itself, as without a warmer
                log.debug("cannot start the kernel warmer again", exc_info=True)

    def stop(self) -> list:
        """Kill and wait for its processes (no restart after this); returns
        each one's status before the kill (None: it was at work)."""
        with self._lock:
            self._stopped = True
        statuses = [p.poll() for p in self.procs]
        for p in self.procs:
            p.kill()
            p.wait()
            p.stdin.close()
        self._watch.join()  # (its process is reaped: at once)
        if self.first_status is not None:
            statuses[0] = self.first_status
        return statuses


def start() -> Warmer | None:
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
        claims = tempfile.mkdtemp(prefix="uniform2d-claims-")
    except OSError:
        log.debug("no directory for the compile claims", exc_info=True)
        return None
    env = {**os.environ, compile_claims.ENV: claims}

    def spawn(stderr: str) -> subprocess.Popen:
        with open(stderr, "wb") as err:
            return subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                                    stdout=subprocess.DEVNULL, stderr=err, env=env)

    try:
        warmer = Warmer(claims, spawn)
    except OSError:  # no process to spare: the run compiles everything itself
        log.debug("cannot start the kernel warmer", exc_info=True)
        shutil.rmtree(claims, ignore_errors=True)
        return None
    compile_claims.share(claims)  # each kernel compiled by one of the two
    return warmer


def stop(warmer: Warmer | None) -> None:
    """End the warmer (it may be in the middle of a compile: nothing is lost but
    that compile), wait for it and stop claiming kernels."""
    if warmer is None:
        return
    statuses = warmer.stop()
    claims = compile_claims.shared()
    compile_claims.share(None)
    if claims is None:
        return
    files = [_STDERR, _STDERR_AGAIN]
    for i, status in enumerate(statuses):
        which = "kernel warmer" if i == 0 else "kernel warmer started again"
        if status not in (None, 0):
            restarted = i == 0 and len(statuses) > 1
            _log_early_end(which, status, os.path.join(claims, files[i]), restarted)
        else:
            log.debug("the %s %s", which, "was done" if status == 0 else "stopped at work")
    shutil.rmtree(claims, ignore_errors=True)


def _log_early_end(which: str, status: int, stderr: str, restarted: bool) -> None:
    """Say, at debug level, how the warmer ended before it was done (a run then
    compiles what the warmer did not: seconds more), and whether it was started
    again."""
    how = ("its stdin ended" if status == EOF_STATUS else
           "a Python exception" if status == ERROR_STATUS else
           f"signal {-status}" if status < 0 else f"exit status {status}")
    try:
        with open(stderr, "rb") as f:  # the start: a fault report's stack, most recent first
            text = f.read(8000).decode("utf-8", "replace")
    except OSError:
        text = ""
    text = text.split("\nExtension modules:")[0].strip()  # (faulthandler's list of them)
    log.debug("the %s ended early (%s)%s; its stderr: %s", which, how,
              ", started again" if restarted else "", text or "(empty)")


def _exit_at_eof() -> None:
    sys.stdin.buffer.read()
    os._exit(EOF_STATUS)


def _exit_on(exc: BaseException) -> None:
    """End the warmer after an exception, with :data:`ERROR_STATUS`: the
    exception's line first on stderr (stop() logs the file's start), then its
    traceback.  Not by raising it: the interpreter's exit under the thread
    blocked reading stdin is aborted (SIGABRT, as a fatal signal would end it)."""
    import traceback

    text = "".join(traceback.format_exception_only(type(exc), exc)).strip()
    sys.stderr.write(f"warmer stopped by {text[:2000]}\n\n")
    traceback.print_exception(exc)
    sys.stderr.flush()
    os._exit(ERROR_STATUS)


def main() -> None:
    """The warmer process: :func:`uniform2d.warmup.warm`, ending early when its stdin
    closes or at an exception, and at once (``os._exit``) when it is done."""
    import faulthandler
    import signal

    from ..compile_cache import drop_unused_wrappers
    from ..warmup import warm

    faulthandler.enable()  # a fatal signal's report, on its stderr (see the module doc)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command decides when to stop
    threading.Thread(target=_exit_at_eof, daemon=True).start()
    compile_claims.share(os.environ.get(compile_claims.ENV) or None)
    try:
        drop_unused_wrappers()  # as the command does on a cold cache
        warm()
    except BaseException as exc:  # (SystemExit and KeyboardInterrupt too: none is expected)
        _exit_on(exc)
    # done before the command: end here, as at the end of stdin.  A normal exit
    # would finalize the interpreter under the thread blocked reading stdin,
    # which Python aborts ("Fatal Python error: ... could not acquire lock for
    # <stdin> at interpreter shutdown", SIGABRT); everything is in the cache.
    os._exit(0)
