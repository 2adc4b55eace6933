"""The figure formats :mod:`uniform2d.plot` writes, checked without matplotlib.

The command line checks ``--plot``'s name before it meshes anything, and imports
matplotlib only to draw: on a cold numba cache, while the warmer compiles
(:mod:`uniform2d.cli._warmer`), not before it starts.
"""

from __future__ import annotations

import os

from .errors import UnsupportedFormatError

__all__ = ["check_figure_path", "FIGURE_FORMATS"]

FIGURE_FORMATS = (".png", ".pdf", ".svg")


def check_figure_path(path) -> str:
    """The figure format of ``path`` (its lower-case extension, e.g. ``".png"``).

    Raises
    ------
    UnsupportedFormatError
        If the extension is not .png, .pdf or .svg; the message names ``path``.
    """
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FIGURE_FORMATS:
        raise UnsupportedFormatError(
            f"cannot save a figure as '{os.fspath(path)}'; use one of {', '.join(FIGURE_FORMATS)}"
        )
    return ext
