"""Helpers shared by the subcommands (not a public API)."""

from __future__ import annotations

import json
import math
import sys

from .._jsonable import jsonable


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

