"""The ``uniform2d`` command line.

Usage (``uniform2d --help`` and ``uniform2d COMMAND --help`` say more)::

    uniform2d mesh data/plate_bolts.json -n 400 -o plate.vtu --stats --plot plate.png
    uniform2d info data/l_bracket.json --size 5
    uniform2d remesh data/patches/cap60.obj -n 500 -o cap.obj --stats

Layout: :mod:`uniform2d.cli.main` builds the parser and runs the chosen
subcommand; each subcommand is one module of this package defining
``add_parser(subparsers)`` and ``run(args) -> int``, listed by name in
:data:`uniform2d.cli.main.COMMANDS`.  Only this package prints; the library
logs and raises.
"""

from .main import main

__all__ = ["main"]
