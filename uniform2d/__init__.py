"""uniform2d: triangular meshes whose edges are as equal in length as possible.

Planar core after Aurenhammer, Katoh, Kojima, Ohsaki and Xu, "Approximating
Uniform Triangular Meshes in Polygons": canonical Voronoi insertion (Algorithm
INSERT), the two-phase mesh T+, and optimality certificates.

>>> import uniform2d
>>> mesh = uniform2d.uniform_mesh(uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]), n=50)
>>> len(mesh.points)
54
"""

import logging

from .errors import (
    CoordinatePrecisionError,
    FileFormatError,
    InsufficientPointsError,
    InvalidArgumentError,
    InternalError,
    InvalidConstraintError,
    InvalidPolygonError,
    InvalidSitesError,
    TooManyPointsError,
    Uniform2dError,
    UnsupportedFormatError,
)
from .insert import InsertResult, insert
from .io import mesh_formats, polygon_formats, read_mesh, read_polygon, write_mesh, write_polygon
from .io.size_file import read_size_field
from .mesh import Mesh
from .polygon import Polygon
from .quality import Quality, quality
from .refine import minimum as minimum_size, refine
from .sizefield import SizeField
from .tplus import tplus
from .uniform import steiner_count_for_size, uniform_mesh

__version__ = "0.1.0"

# A library leaves log output to the application (the command shows it with -v).
logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "Polygon",
    "insert",
    "InsertResult",
    "tplus",
    "uniform_mesh",
    "steiner_count_for_size",
    "Mesh",
    "quality",
    "Quality",
    "SizeField",
    "refine",
    "minimum_size",
    "read_size_field",
    "read_polygon",
    "write_polygon",
    "read_mesh",
    "write_mesh",
    "polygon_formats",
    "mesh_formats",
    "Uniform2dError",
    "InvalidPolygonError",
    "InvalidConstraintError",
    "TooManyPointsError",
    "InsufficientPointsError",
    "InvalidSitesError",
    "UnsupportedFormatError",
    "FileFormatError",
    "InvalidArgumentError",
    "InternalError",
    "CoordinatePrecisionError",
    "__version__",
]
