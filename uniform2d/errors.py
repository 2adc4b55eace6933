"""Typed exceptions raised by uniform2d.

Every error the library raises on bad input derives from :class:`Uniform2dError`;
the command line turns them into one line on stderr and exit code 2.  Each also
derives from the built-in class a caller would expect (``ValueError`` for bad
values), so ``except ValueError`` keeps working.
"""

__all__ = [
    "Uniform2dError",
    "InvalidPolygonError",
    "InsufficientPointsError",
    "InvalidSitesError",
    "UnsupportedFormatError",
    "FileFormatError",
    "InternalError",
    "CoordinatePrecisionError",
]


class Uniform2dError(Exception):
    """Base class of every error uniform2d raises on bad input."""


class InvalidPolygonError(Uniform2dError, ValueError):
    """The polygon is not a valid simple polygon with holes (the message says where)."""


class CoordinatePrecisionError(InvalidPolygonError):
    """The polygon lies so far from the origin for its size that its coordinates
    cannot hold the points the mesh needs (move it nearer the origin)."""


class InsufficientPointsError(Uniform2dError, ValueError):
    """The requested number of Steiner points is too small for the construction."""


class InvalidSitesError(Uniform2dError, ValueError):
    """Extra initial sites passed to :func:`uniform2d.insert` are unusable."""


class UnsupportedFormatError(Uniform2dError, ValueError):
    """A file extension is not one uniform2d can read or write."""


class FileFormatError(Uniform2dError, ValueError):
    """A file could be opened but its content is not a usable polygon or mesh."""


class InternalError(RuntimeError):
    """uniform2d made a mesh that fails its own validity check.

    Not a :class:`Uniform2dError`: the input is fine, the library is wrong.  The
    mesh is not returned; the message asks for the polygon and n to be reported.
    """
