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

__all__ = ["start", "stop", "spare_cpus", "busy", "main", "EOF_STATUS"]

log = logging.getLogger(__name__)

#: The warmer's exit status when its stdin ends before it is done: the command
#: died, or closed the pipe without :func:`stop` (which kills the warmer first).
EOF_STATUS = 3

_STDERR = "warmer.stderr"  # the warmer's stderr, in the claims directory


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
        claims = tempfile.mkdtemp(prefix="uniform2d-claims-")
    except OSError:
        log.debug("no directory for the compile claims", exc_info=True)
        return None
    try:
        with open(os.path.join(claims, _STDERR), "wb") as err:
            proc = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                                    stdout=subprocess.DEVNULL, stderr=err,
                                    env={**os.environ, compile_claims.ENV: claims})
    except OSError:  # no process to spare: the run compiles everything itself
        log.debug("cannot start the kernel warmer", exc_info=True)
        shutil.rmtree(claims, ignore_errors=True)
        return None
    compile_claims.share(claims)  # each kernel compiled by one of the two
    return proc


def stop(proc: subprocess.Popen | None) -> None:
    """End the warmer (it may be in the middle of a compile: nothing is lost but
    that compile), wait for it and stop claiming kernels."""
    if proc is None:
        return
    status = proc.poll()  # before the kill: None while it compiles, 0 when done
    proc.kill()
    proc.wait()
    proc.stdin.close()
    claims = compile_claims.shared()
    compile_claims.share(None)
    if claims is not None:
        if status not in (None, 0):
            _log_early_end(status, os.path.join(claims, _STDERR))
        else:
            log.debug("the kernel warmer %s", "was done" if status == 0 else "stopped at work")
        shutil.rmtree(claims, ignore_errors=True)


def _log_early_end(status: int, stderr: str) -> None:
    """Say, at debug level, how the warmer ended before it was done (a run then
    compiles what the warmer did not: seconds more)."""
    how = ("its stdin ended" if status == EOF_STATUS else
           f"signal {-status}" if status < 0 else f"exit status {status}")
    try:
        with open(stderr, "rb") as f:  # the start: a fault report's stack, most recent first
            text = f.read(8000).decode("utf-8", "replace")
    except OSError:
        text = ""
    text = text.split("\nExtension modules:")[0].strip()  # (faulthandler's list of them)
    log.debug("the kernel warmer ended early (%s); its stderr: %s", how, text or "(empty)")


def _exit_at_eof() -> None:
    sys.stdin.buffer.read()
    os._exit(EOF_STATUS)


def main() -> None:
    """The warmer process: :func:`uniform2d.warmup.warm`, ending early when its stdin
    closes, and at once (``os._exit``) when it is done."""
    import faulthandler
    import signal

    from ..compile_cache import drop_unused_wrappers
    from ..warmup import warm

    faulthandler.enable()  # a fatal signal's report, on its stderr (see the module doc)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command decides when to stop
    threading.Thread(target=_exit_at_eof, daemon=True).start()
    compile_claims.share(os.environ.get(compile_claims.ENV) or None)
    drop_unused_wrappers()  # as the command does on a cold cache
    warm()
    # done before the command: end here, as at the end of stdin.  A normal exit
    # would finalize the interpreter under the thread blocked reading stdin,
    # which Python aborts ("Fatal Python error: ... could not acquire lock for
    # <stdin> at interpreter shutdown", SIGABRT); everything is in the cache.
    os._exit(0)
