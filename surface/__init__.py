"""surface: uniform remeshing of surfaces with exactly n vertices.

A patch (a triangle mesh that is a disk, possibly with holes) is flattened with
libigl, its parameter domain meshed by the planar core :mod:`uniform2d`, and the
planar mesh lifted back onto the patch.  A whole model (closed, of any genus, in
several parts, or too curved to flatten in one piece) is cut into an atlas of
such charts whose seams are sampled once and shared, meshed chart by chart and
stitched.  The result is measured in 3-D and cross-checked with pymeshlab.

>>> import numpy as np, surface
>>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], float)
>>> p = surface.Patch(V, [[0, 1, 2], [0, 2, 3]])
>>> p
Patch(4 vertices, 2 faces, 1 boundary loop(s))

Requires the ``surface`` extra: trimesh, libigl 2.6.3 and pymeshlab
(``pip install 'uniform2d[surface]'``); without them importing this package
raises one :class:`ImportError` saying so.
"""

import importlib.util
import logging

logging.getLogger(__name__).addHandler(logging.NullHandler())


def _require_extra() -> None:
    """One clear ImportError when the extra is missing, not one from deep inside."""
    for module in ("igl", "pymeshlab", "trimesh"):
        if importlib.util.find_spec(module) is None:
            raise ImportError(
                f"the surface layer needs the 'surface' extra (module '{module}' is not "
                "installed); install it with: pip install 'uniform2d[surface]'",
                name=module,
            )


_require_extra()

from .errors import (  # noqa: E402
    CrossCheckError, InvalidPatchError, ParameterizationError, RemeshQualityError,
)
from .io import as_model, as_patch, read_model, read_patch, write_patch  # noqa: E402
from .model import Model  # noqa: E402
from .parameterize import Parameterization, parameterize  # noqa: E402
from .patch import Patch  # noqa: E402
from .remesh import remesh  # noqa: E402
from .result import RemeshResult  # noqa: E402
from .report import Report  # noqa: E402

__all__ = [
    "remesh",
    "RemeshResult",
    "Report",
    "read_patch",
    "read_model",
    "write_patch",
    "Patch",
    "Model",
    "as_patch",
    "as_model",
    "parameterize",
    "Parameterization",
    "InvalidPatchError",
    "ParameterizationError",
    "CrossCheckError",
    "RemeshQualityError",
]
