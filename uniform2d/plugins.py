"""Where layers built on uniform2d plug into its command line and report.

uniform2d's core never imports the layers built on it.  A layer that remeshes
surface patches registers one module under the entry-point group
:data:`PATCH_GROUP` in its ``pyproject.toml``, as pytest and meshio plugins do::

    [project.entry-points."uniform2d.patches"]
    surface = "surface.plugin"

``uniform2d remesh`` and ``uniform2d report`` (for patch inputs) then find it
with :func:`patch_layer`.  The module provides:

``read_patch(path)``
    The patch in a file, with ``vertices`` (N, 3) and ``faces`` (M, 3).
``read_model(path)``
    The same for any manifold surface (closed, any genus, several parts).
``remesh(patch, n_vertices=None, *, size=None, param="lscm", corner_angle=..., check=True, hausdorff=True, feature_angle=None, jobs=1, scheduler=None)``
    A remeshed patch with ``vertices``, ``faces``, ``report`` (``summary()``,
    ``as_dict()``, ``mesher``, ``target_size``, ``parameterization``) and ``write(path)``.
``WRITE_FORMATS`` and ``check_output(path)``
    The extensions ``write`` supports; an ``UnsupportedFormatError`` for any other.
``plot_result(result, path)``
    A figure of a remeshed patch (3-D edges coloured by length), saved to ``path``.
``measures(V, F, V0, F0)``
    The report's table measures of a remesh (V, F) of the patch (V0, F0).
``warm_up()``
    Compile and load everything a remesh uses (before timed runs).
"""

from __future__ import annotations

from importlib.metadata import entry_points
from types import ModuleType

__all__ = ["PATCH_GROUP", "patch_layer"]

#: Entry-point group of the surface-patch layer.
PATCH_GROUP = "uniform2d.patches"

_INSTALL = "install it with: pip install 'uniform2d[surface]'"


def patch_layer(required: bool = True) -> ModuleType | None:
    """The registered surface-patch layer (the first, by name).

    Raises ImportError (saying how to install it) if none is registered or it
    cannot be imported, unless ``required`` is False: then None.
    """
    found = sorted(entry_points(group=PATCH_GROUP), key=lambda ep: ep.name)
    if not found:
        if not required:
            return None
        raise ImportError(f"surface patches need the surface layer, and none is registered; {_INSTALL}")
    try:
        return found[0].load()
    except ImportError as exc:
        if not required:
            return None
        raise ImportError(f"surface patches need the surface extra ({exc}); {_INSTALL}") from None
