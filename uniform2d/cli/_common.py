"""Helpers shared by the subcommands (not a public API)."""

from __future__ import annotations

import json
import logging
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator

from .._jsonable import jsonable

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


def print_json(obj) -> None:
    json.dump(jsonable(obj), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def progress(iterable, *, total: int, quiet: bool, desc: str):
    """A tqdm bar on stderr when there is more than one item, stderr is a TTY and not --quiet."""
    if total < 2 or quiet or not sys.stderr.isatty():
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, unit="file", file=sys.stderr)



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


def map_inputs(work: Callable, items: Iterable) -> Iterator[Outcome]:
    """One :class:`Outcome` per item, in order, each as soon as it is known.

    The one loop over a batch's inputs: a failed input never stops the others.
    ``work`` gets one item and returns a plain value (no printing), so that a
    parallel map can take this one's place.
    """
    return (attempt(work, item) for item in items)


def report_failure(name, exc: BaseException) -> str:
    """Print one ``uniform2d: error: <name>: ...`` line for a failed input; return the message."""
    from .main import PROG, error_message

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
    from .main import PROG

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


def check_output_file(path: Path, option: str) -> None:
    """Refuse, before any work, an output file whose directory is missing or is a file."""
    parent = path.parent
    if parent.is_dir():
        return
    base = _first_existing(parent)
    if base.exists() and not base.is_dir():
        raise NotADirectoryError(
            f"cannot write '{path}': '{base}' is a file, not a directory; choose another {option}"
        )
    raise FileNotFoundError(
        f"cannot write '{path}': directory '{parent}' does not exist; create it first"
    )
