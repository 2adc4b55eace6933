"""uniform2d: triangular meshes whose edges are as equal in length as possible.

Planar core after Aurenhammer, Katoh, Kojima, Ohsaki and Xu, "Approximating
Uniform Triangular Meshes in Polygons": canonical Voronoi insertion (Algorithm
INSERT), the two-phase mesh T+, and optimality certificates.
"""

from .errors import (
    FileFormatError,
    InsufficientPointsError,
    InvalidPolygonError,
    InvalidSitesError,
    Uniform2dError,
    UnsupportedFormatError,
)
from .polygon import Polygon

__version__ = "0.1.0"

__all__ = [
    "Polygon",
    "Uniform2dError",
    "InvalidPolygonError",
    "InsufficientPointsError",
    "InvalidSitesError",
    "UnsupportedFormatError",
    "FileFormatError",
    "__version__",
]
