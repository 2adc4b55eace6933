"""Entry point of the ``uniform2d`` command: ``main(argv=None) -> int``.

Adding a subcommand
-------------------
Write ``uniform2d/cli/<name>.py`` defining

* ``add_parser(subparsers)`` -- ``p = subparsers.add_parser("<name>", help=...)``,
  then its arguments (and return ``p``);
* ``run(args) -> int`` -- do the work, print results, return the exit code
  (raise :class:`uniform2d.Uniform2dError`, ``ValueError`` or ``OSError`` for bad
  input: :func:`main` turns them into one ``uniform2d: error: ...`` line and
  exit code 2);

and add ``"<name>"`` to :data:`COMMANDS`.  Keep heavy imports inside ``run`` so
``uniform2d --help`` stays fast.  ``--quiet``/``--verbose`` are added to every
subcommand here and arrive as ``args.quiet`` (bool) and ``args.verbose`` (int).
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import sys

from ._common import PROG, error_message

__all__ = ["main", "COMMANDS", "build_parser"]

#: The subcommands, in the order ``--help`` lists them: one module of
#: ``uniform2d.cli`` each.  Registering a new one is adding its name here.
COMMANDS = ("mesh", "info", "remesh", "report", "compare")

class _Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (``uniform2d: error: ...``, exit code 2)."""

    def error(self, message):
        self.exit(2, f"{PROG}: error: {message} (see '{self.prog} --help')\n")


def _command_modules():
    """(name, module) for every registered subcommand."""
    return [(name, importlib.import_module(f"{__package__}.{name}")) for name in COMMANDS]


def _add_common(parser: argparse.ArgumentParser, default) -> None:
    parser.add_argument(
        "-q", "--quiet", action="store_true", default=default(False),
        help="print nothing but errors (and what --stats/--json ask for); no progress bar",
    )
    parser.add_argument(
        "-v", "--verbose", action="count", default=default(0),
        help="log progress to stderr (-vv for debug messages)",
    )


def build_parser() -> tuple[argparse.ArgumentParser, dict]:
    """The argument parser and ``{name: module}`` of its subcommands."""
    from .. import __version__

    parser = _Parser(
        prog=PROG,
        description="Triangular meshes whose edges are as equal in length as possible, "
        "with exactly n Steiner points.",
        epilog=f"Run '{PROG} COMMAND --help' for the options of a command.",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    _add_common(parser, lambda v: v)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    modules = {}
    for name, module in _command_modules():
        before = set(sub.choices)
        module.add_parser(sub)
        for new in set(sub.choices) - before:
            # SUPPRESS: an option given before the command is not reset after it.
            _add_common(sub.choices[new], lambda v: argparse.SUPPRESS)
            modules[new] = module
    return parser, modules


class _StderrHandler(logging.StreamHandler):
    """Writes to whatever ``sys.stderr`` is at the time of the record."""

    def __init__(self):
        super().__init__(sys.stderr)

    @property
    def stream(self):
        return sys.stderr

    @stream.setter
    def stream(self, value):
        pass


def _setup_logging(quiet: bool, verbose: int):
    """Route log records to stderr for this run; returns a function undoing it."""
    level = logging.ERROR if quiet else (
        logging.WARNING if verbose == 0 else logging.INFO if verbose == 1 else logging.DEBUG
    )
    handler = _StderrHandler()
    handler.setFormatter(logging.Formatter(f"{PROG}: %(levelname)s: %(message)s"))
    root = logging.getLogger()
    saved = [(root, root.level)]
    root.addHandler(handler)
    root.setLevel(level)
    # Third-party chatter (numba, matplotlib, trimesh, Dask) only with -vvv.
    for name in ("numba", "matplotlib", "PIL", "trimesh", "distributed", "tornado", "asyncio"):
        logger = logging.getLogger(name)
        saved.append((logger, logger.level))
        logger.setLevel(logging.DEBUG if verbose >= 3 else logging.WARNING)

    def undo():
        root.removeHandler(handler)
        for logger, lvl in saved:
            logger.setLevel(lvl)

    return undo


def main(argv=None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit code.

    Exit codes: 0 success, 2 bad input or usage, or too little memory for the
    request (one line on stderr, no traceback, no output file), 1 a mesh that
    failed uniform2d's own final check (a bug to report: one line, the
    traceback with -vvv, no output file), 130 interrupted, 141 stdout closed
    early (a pipe).
    """
    from ..errors import InternalError, Uniform2dError

    parser, modules = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    undo_logging = _setup_logging(args.quiet, args.verbose)
    try:
        return int(modules[args.command].run(args) or 0)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `uniform2d mesh ... --json | head`: stop quietly
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 141
    except (Uniform2dError, ValueError, OSError, ImportError, MemoryError) as exc:
        logging.getLogger(__name__).debug("error details", exc_info=True)
        print(f"{PROG}: error: {error_message(exc)}", file=sys.stderr)
        return 2
    except InternalError as exc:
        logging.getLogger(__name__).debug("internal error details", exc_info=True)
        print(f"{PROG}: internal error: {exc}", file=sys.stderr)
        return 1
    finally:
        undo_logging()


if __name__ == "__main__":
    sys.exit(main())
