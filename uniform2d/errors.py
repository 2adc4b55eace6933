"""Typed exceptions raised by uniform2d.

Every error the library raises on bad input derives from :class:`Uniform2dError`,
which is a ``ValueError`` (so ``except ValueError`` keeps working); the command
line turns them into one line on stderr and exit code 2.

>>> from uniform2d import Polygon, uniform_mesh
>>> uniform_mesh(Polygon([(0, 0), (1, 0), (0, 1)]))
Traceback (most recent call last):
    ...
uniform2d.errors.InvalidArgumentError: give exactly one of n (number of Steiner points) and size
"""

__all__ = [
    "Uniform2dError",
    "InvalidPolygonError",
    "InvalidConstraintError",
    "InsufficientPointsError",
    "InvalidSitesError",
    "UnsupportedFormatError",
    "FileFormatError",
    "InvalidArgumentError",
    "ArgumentTypeError",
    "InternalError",
    "CoordinatePrecisionError",
    "TooManyPointsError",
]


class Uniform2dError(ValueError):
    """Base class of every error uniform2d raises on bad input (a ``ValueError``)."""


class InvalidPolygonError(Uniform2dError):
    """The polygon is not a valid simple polygon with holes (the message says where)."""


class InvalidConstraintError(InvalidPolygonError):
    """A segment or fixed point of a polygon is unusable: it crosses a ring, a hole
    or another segment, overlaps one, lies outside the polygon, or repeats (the
    message names the pieces and the place)."""


class CoordinatePrecisionError(InvalidPolygonError):
    """The polygon lies so far from the origin for its size that its coordinates
    cannot hold the points the mesh needs (move it nearer the origin)."""


class InsufficientPointsError(Uniform2dError):
    """The requested number of Steiner points is too small for the construction."""


class InvalidSitesError(Uniform2dError):
    """Extra initial sites passed to :func:`uniform2d.insert` are unusable."""


class UnsupportedFormatError(Uniform2dError):
    """A file extension is not one uniform2d can read or write."""


class FileFormatError(Uniform2dError):
    """A file could be opened but its content is not a usable polygon or mesh."""


class InvalidArgumentError(Uniform2dError):
    """A function argument has a value (or combination of values) it cannot use."""


class ArgumentTypeError(InvalidArgumentError, TypeError):
    """A function argument has the wrong type (also a ``TypeError``)."""


#: The end of every :class:`InternalError` message that names no mesh.
PLEASE_REPORT = (
    "(a bug in uniform2d, not a problem with the input: please report it with the polygon and n)")


class InternalError(RuntimeError):
    """uniform2d failed on valid input: a mesh that fails its own validity check,
    or a step that cannot fail on a valid polygon did.

    Not a :class:`Uniform2dError`: the input is fine, the library is wrong.  No
    mesh is returned; the message asks for the polygon and n to be reported.
    """


class TooManyPointsError(InvalidArgumentError, MemoryError):
    """More points were asked for than this machine's memory can hold (also a
    ``MemoryError``); refused before any work starts."""
