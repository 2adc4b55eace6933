"""Writing what ``uniform2d mesh`` made: every output file and the figure, all or none."""

from __future__ import annotations

import os
import secrets
from pathlib import Path

__all__ = ["write_outputs", "load_plotting"]


def _write_meshes(mesh, dsts: tuple[Path, ...], element_type) -> None:
    """Every mesh file, or none of those that did not exist before: each is
    written atomically, and a failure removes the ones this call created."""
    created = []
    try:
        for dst in dsts:
            existed = dst.exists()
            inp = dst.name.lower().endswith(".inp")
            mesh.write(dst, **({"element_type": element_type} if inp and element_type else {}))
            if not existed:
                created.append(dst)
    except BaseException:
        for dst in created:
            dst.unlink(missing_ok=True)
        raise


def load_plotting():
    """Import matplotlib on its file-only backend (Agg), pyplot and the figures'
    module; returns pyplot.  ``mesh`` calls it before it meshes an input with a
    figure: on a cold numba cache the import then runs while the warmer
    compiles (:mod:`._warmer`), not after the mesh, where the warmer is done
    and one CPU idles."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .. import plot  # noqa: F401  (Mesh.plot's module: imported here with the rest)

    return plt


def write_outputs(mesh, dsts: tuple[Path, ...], fig: Path | None, element_type=None) -> None:
    """The mesh files and their figure, all or none: the figure is drawn to a
    temporary file next to ``fig`` first and moved into place after the mesh
    files are written (each write is atomic on its own).  Errors name ``fig``,
    never the temporary file."""
    from ..io.atomic import named_for

    if fig is None:
        _write_meshes(mesh, dsts, element_type)
        return
    plt = load_plotting()
    tmp = fig.with_name(f".{fig.stem}.tmp-{secrets.token_hex(4)}{fig.suffix}")
    new = [d for d in dsts if not d.exists()]
    try:
        try:
            plt.close(mesh.plot(tmp))
        except OSError as exc:
            raise named_for(exc, tmp, fig) from None
        _write_meshes(mesh, dsts, element_type)
        try:
            os.replace(tmp, fig)
        except OSError as exc:
            for dst in new:
                dst.unlink(missing_ok=True)
            raise named_for(exc, tmp, fig) from None
    finally:
        tmp.unlink(missing_ok=True)
