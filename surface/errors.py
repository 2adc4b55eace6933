"""Typed exceptions raised by the surface layer.

Each derives from :class:`uniform2d.errors.Uniform2dError` (so the command line
reports it as one line and exit code 2), which is a :class:`ValueError`.  Bad
arguments raise :class:`uniform2d.errors.InvalidArgumentError`.  Messages
say what is wrong and what to do about it.
"""

from uniform2d.errors import Uniform2dError

__all__ = ["InvalidPatchError", "ParameterizationError", "CrossCheckError", "RemeshQualityError"]


class InvalidPatchError(Uniform2dError):
    """The input is not a usable patch.

    The attribute :attr:`reason` names the failed check, one of
    ``"not_triangle_mesh"``, ``"non_manifold"``, ``"closed"``, ``"components"``,
    ``"topology"`` (not a disk with holes), ``"degenerate"``, ``"charts"`` (a model
    that cannot be cut into charts that flatten).
    """

    def __init__(self, message: str, reason: str = "invalid"):
        super().__init__(message)
        self.reason = reason


class ParameterizationError(Uniform2dError):
    """No parameterisation method produced a flip-free, non-overlapping map."""


class CrossCheckError(Uniform2dError):
    """pymeshlab's measures of the output mesh disagree with ours (a bug: report it)."""


class RemeshQualityError(Uniform2dError):
    """The remesh came out worse than the library accepts (see
    :mod:`surface.quality_gate`); the message says why and what to try."""
