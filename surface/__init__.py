"""surface: uniform remeshing of developable and mildly curved surface patches.

A patch (a triangle mesh that is a disk, possibly with holes) is flattened with
libigl, its parameter domain meshed by the planar core :mod:`uniform2d`, and the
planar mesh lifted back onto the patch.  The result is measured in 3-D and
cross-checked with pymeshlab.

>>> import numpy as np, surface
>>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], float)
>>> p = surface.Patch(V, [[0, 1, 2], [0, 2, 3]])
>>> p
Patch(4 vertices, 2 faces, 1 boundary loop(s))

Requires the ``surface`` extra: trimesh, libigl 2.6.3 and pymeshlab.
"""

from .errors import CrossCheckError, InvalidPatchError, ParameterizationError
from .io import as_patch, read_patch, write_patch
from .parameterize import Parameterization, parameterize
from .patch import Patch
from .remesh import RemeshResult, remesh
from .report import Report

__all__ = [
    "remesh",
    "RemeshResult",
    "Report",
    "read_patch",
    "write_patch",
    "Patch",
    "as_patch",
    "parameterize",
    "Parameterization",
    "InvalidPatchError",
    "ParameterizationError",
    "CrossCheckError",
]
