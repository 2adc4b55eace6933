"""Helpers shared by the subcommands (not a public API)."""

from __future__ import annotations

import errno
import functools
import json
import logging
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator

from .._jsonable import jsonable

#: The command's name, which starts every line it prints on stderr.
PROG = "uniform2d"


#: What to do about an operating-system error, by errno.
_OS_HINTS = {
    errno.ENOSPC: "free some disk space or write to another disk",
    errno.EDQUOT: "free some of your disk quota or write to another disk",
    errno.EROFS: "the file system is read-only: write somewhere else",
    errno.EACCES: "check its permissions or write somewhere else",
    errno.EPERM: "check its permissions or write somewhere else",
}


def error_message(exc: BaseException) -> str:
    """One line describing a user-facing error."""
    if isinstance(exc, MemoryError):
        msg = f"out of memory ({exc or 'no details'}); ask for fewer points"
    elif isinstance(exc, OSError) and exc.strerror and exc.filename:
        msg = f"{exc.strerror}: {exc.filename}"
        if exc.errno in _OS_HINTS:
            msg += f"; {_OS_HINTS[exc.errno]}"
    elif isinstance(exc, ImportError) and not isinstance(exc, ModuleNotFoundError):
        msg = str(exc)
    elif isinstance(exc, ModuleNotFoundError):
        msg = f"missing optional dependency '{exc.name}' ({exc})"
    else:
        msg = str(exc) or type(exc).__name__
    return " ".join(msg.split())


log = logging.getLogger(__name__)


def positive_int(text: str) -> int:
    """argparse type: an integer (range checks are the library's job, so it can name the fix)."""
    try:
        return int(text)
    except ValueError:
        import argparse

        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def positive_float(text: str) -> float:
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def angle_degrees(text: str) -> float:
    """argparse type: an angle in degrees strictly between 0 and 180."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an angle in degrees, got '{text}'") from None
    if not 0.0 < value < 180.0:
        raise argparse.ArgumentTypeError(f"the angle must be between 0 and 180 degrees, got {text}")
    return value


def announce_compile(quiet: bool = False, cold: bool | None = None) -> bool:
    """Say once on stderr that the kernels are being compiled, if they are about
    to be (``cold``; by default: a cold numba cache) and not --quiet; return
    whether it was said."""
    from ..compile_cache import COMPILE_NOTICE, kernels_cold
    if quiet or not (kernels_cold() if cold is None else cold):
        return False
    print(f"{PROG}: {COMPILE_NOTICE}", file=sys.stderr, flush=True)
    return True


def add_parallel_options(parser, what: str) -> None:
    """``--jobs K`` and ``--scheduler ADDRESS`` (one or the other) for a command
    running many independent ``what``; they arrive as ``args.jobs``, ``args.scheduler``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--jobs", "-j", type=positive_int, default=1, metavar="K",
                       help=f"run {what} in K local processes (default 1)")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help=f"run {what} on an existing Dask cluster, e.g. tcp://host:8786 "
                       "(needs the 'dask' extra)")


def check_parallel_options(args) -> None:
    """Refuse a --jobs below 1 and a --scheduler without Dask, before any work."""
    from .._parallel import check_jobs

    if args.jobs < 1:
        raise ValueError(f"--jobs must be at least 1, got {args.jobs}")
    try:
        check_jobs(args.jobs, args.scheduler)
    except ImportError:
        raise ImportError("--scheduler needs the 'dask' extra: pip install 'uniform2d[dask]'") from None


def print_json(obj) -> None:
    json.dump(jsonable(obj), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def shows_progress(quiet: bool) -> bool:
    """Whether progress bars go to stderr: it is a terminal and not --quiet."""
    return not quiet and sys.stderr.isatty()


def file_bar(total: int, quiet: bool, desc: str):
    """A tqdm bar over a batch's files (updated as each finishes), on stderr when
    there is more than one file, stderr is a terminal and not --quiet."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="file", file=sys.stderr,
                disable=total < 2 or not shows_progress(quiet))


class PhaseBar:
    """``progress(phase, done, total)`` for :func:`uniform2d.uniform_mesh`: a tqdm
    bar over the phases of one run, shown only once the run has taken ``delay``
    seconds (short runs stay silent).  The bar moves by one per phase, by a
    fraction within a phase that has several steps."""

    def __init__(self, phases, desc: str, *, delay: float = 2.0, file=None):
        from tqdm import tqdm

        self.phases, self.desc = list(phases), desc
        self.bar = tqdm(total=len(self.phases), desc=desc, unit="phase", delay=delay,
                        miniters=0, mininterval=0, leave=False,
                        file=file if file is not None else sys.stderr,
                        bar_format="{desc} {percentage:3.0f}%|{bar}| [{elapsed}]")

    def __call__(self, phase: str, done: int, total: int) -> None:
        at = self.phases.index(phase) if phase in self.phases else len(self.phases) - 1
        step = f"{phase} {done}/{total}" if total > 1 else phase
        self.bar.set_description_str(f"{self.desc}: {step}", refresh=False)
        self.bar.update(at + done / max(total, 1) - self.bar.n)

    def close(self) -> None:
        self.bar.close()



# -- batches ------------------------------------------------------------------------
#: Errors that fail one input of a batch and let the others go on (anything
#: else, e.g. an interrupt or a bug, stops the batch).
INPUT_ERRORS = (ValueError, OSError, ImportError, MemoryError)


@dataclass
class Outcome:
    """What became of one input of a batch: its ``value``, or the ``error`` it raised."""

    item: object
    value: object = None
    error: BaseException | None = None


def attempt(work: Callable, item) -> Outcome:
    """``work(item)`` as an :class:`Outcome`; a bad input's error is kept, not raised."""
    try:
        return Outcome(item, value=work(item))
    except INPUT_ERRORS as exc:
        log.debug("%s failed", item, exc_info=True)
        return Outcome(item, error=exc)


def map_inputs(work: Callable, items: Iterable, *, jobs: int = 1, scheduler=None,
               bar=None) -> Iterator[Outcome]:
    """One :class:`Outcome` per item, in order, each as soon as it and those
    before it are known.

    The one loop over a batch's inputs: a failed input never stops the others.
    ``work`` gets one item and returns a plain value (no printing).  With
    ``jobs`` > 1 the items run in that many local processes, with ``scheduler``
    on a Dask cluster (:func:`uniform2d._parallel.ordered_map`); ``work`` must
    then be picklable (a module-level function, or a ``functools.partial`` of one).
    """
    from .._parallel import ordered_map

    return ordered_map(functools.partial(attempt, work), items, jobs=jobs, scheduler=scheduler,
                       bar=bar)


def collect(outcomes: Iterable[Outcome], several: bool, show: Callable,
            document: Callable) -> tuple[int, list]:
    """Go through a batch's outcomes in input order: a failure is one line (the
    only input's error is raised as it is), a success is ``show(value)``.
    Returns (the number of failures, one ``document(value)`` or
    ``{"input": ..., "error": ...}`` per input, for --json)."""
    documents, failed = [], 0
    for outcome in outcomes:
        src = outcome.item[0]
        if outcome.error is not None:
            if not several:
                raise outcome.error
            failed += 1
            documents.append({"input": str(src), "error": report_failure(src, outcome.error)})
            continue
        documents.append(document(outcome.value))
        show(outcome.value)
    return failed, documents


def run_batch(args, process: Callable, plan: list, desc: str, show: Callable,
              document: Callable, warm: bool = False) -> int:
    """The batch loop of a command over ``plan`` (one tuple per input, its input
    path first); returns the exit code.

    ``process(args, job)`` (module-level: it may run in another process) does one
    input and returns a dict; ``show(args, doc, several)`` prints it, above the
    bar over files; ``document(doc)`` is what --json lists for it.  Runs in
    ``args.jobs`` local processes or on the Dask cluster ``args.scheduler``.
    With ``warm`` (the inputs are meshed by :func:`uniform2d.uniform_mesh`), a
    cold numba cache and the batch in this process, a second process compiles
    the kernels the meshing needs later meanwhile (:mod:`._warmer`).
    """
    from . import _warmer
    from ..compile_cache import drop_unused_wrappers, kernels_cold

    several = len(plan) > 1
    warmer = None
    if args.scheduler is None:  # here, or in local workers sharing this cache
        cold = bool(kernels_cold())
        announce_compile(args.quiet, cold)
        if cold:
            drop_unused_wrappers()
        if cold and warm and (args.jobs == 1 or not several):
            warmer = _warmer.start()
    try:
        return _run_batch(args, process, plan, desc, show, document)
    finally:
        _warmer.stop(warmer)


def _run_batch(args, process, plan, desc, show, document) -> int:
    several = len(plan) > 1
    with file_bar(len(plan), args.quiet, desc) as bar:

        def shown(doc):
            with bar.external_write_mode(file=sys.stdout):  # above the bar, not through it
                show(args, doc, several)

        outcomes = map_inputs(functools.partial(process, args), plan, jobs=args.jobs,
                              scheduler=args.scheduler, bar=bar)
        failed, documents = collect(outcomes, several, shown, document)
    if args.json:
        print_json(documents[0] if not several else documents)
    return batch_status(failed, len(plan))


def report_failure(name, exc: BaseException) -> str:
    """Print one ``uniform2d: error: <name>: ...`` line for a failed input; return the message."""
    msg = error_message(exc)
    if str(name) not in msg:
        msg = f"{name}: {msg}"
    if "tqdm" in sys.modules:  # a progress bar may be on stderr: print above it
        sys.modules["tqdm"].tqdm.write(f"{PROG}: error: {msg}", file=sys.stderr)
    else:
        print(f"{PROG}: error: {msg}", file=sys.stderr)
    return msg


def batch_status(failed: int, total: int) -> int:
    """Exit code of a batch: 0, or 2 after a one-line summary when some inputs failed."""
    if not failed:
        return 0
    print(f"{PROG}: error: {failed} of {total} inputs failed", file=sys.stderr)
    return 2


# -- output paths -------------------------------------------------------------------
def names_directory(text: str) -> bool:
    """Whether an output argument names a directory: an existing one, or any ending in '/'."""
    return text.endswith(("/", os.sep)) or Path(text).is_dir()


def _first_existing(path: Path) -> Path:
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_output_dir(path: Path, option: str) -> None:
    """Refuse, before any work, an output directory that is a file or cannot be created."""
    if path.is_dir():
        _check_writable(path, f"cannot write into '{path}'", option)
        return
    if path.exists():
        raise NotADirectoryError(
            f"{option} '{path}' is a file, not a directory; give a directory "
            "(it is created if missing)"
        )
    base = _first_existing(path)
    if base.exists() and not base.is_dir():
        raise NotADirectoryError(
            f"cannot create the directory '{path}': '{base}' is a file; choose another {option}"
        )
    _check_writable(base, f"cannot create the directory '{path}'", option)


def _check_writable(directory: Path, what: str, option: str) -> None:
    """Refuse a directory this process may not create files in (before any work)."""
    if not os.access(directory, os.W_OK | os.X_OK):
        raise PermissionError(f"{what}: the directory '{directory}' is not writable; "
                              f"choose another {option} or change its permissions")


def same_outputs(plan) -> None:
    """Refuse a batch in which two inputs would write the same file, naming both."""
    seen: dict = {}
    for job in plan:
        src, dsts = job[0], job[1]
        for dst in (dsts if isinstance(dsts, (tuple, list)) else (dsts,)):
            key = Path(dst).resolve()
            if key in seen:
                raise ValueError(f"inputs '{seen[key]}' and '{src}' would both write '{dst}'; "
                                 "rename one, or mesh them into different directories")
            seen[key] = src


def check_output_file(path: Path, option: str) -> None:
    """Refuse, before any work, an output file whose directory is missing or is a file."""
    parent = path.parent
    if parent.is_dir():
        _check_writable(parent, f"cannot write '{path}'", option)
        if path.is_dir():
            raise IsADirectoryError(f"cannot write '{path}': it is a directory; choose another "
                                    f"{option} (or '{path}/' to write inside it)")
        return
    base = _first_existing(parent)
    if base.exists() and not base.is_dir():
        raise NotADirectoryError(
            f"cannot write '{path}': '{base}' is a file, not a directory; choose another {option}"
        )
    raise FileNotFoundError(
        f"cannot write '{path}': directory '{parent}' does not exist; create it first"
    )
