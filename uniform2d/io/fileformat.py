"""The record of one file format: what the registry lists and each format module declares."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

__all__ = ["FileFormat"]


@dataclass(frozen=True)
class FileFormat:
    """One registered file format.

    Attributes
    ----------
    extension : str
        Lower-case extension with its leading dot, possibly compound.
    description : str
        One human-readable line.
    reader, writer : callable
        See the module docstring for their signatures.
    point_data : bool
        Mesh formats only: whether per-point data is stored (otherwise it is
        dropped with a logged warning).
    regions : bool
        Mesh formats only: whether one region per triangle is stored (otherwise
        the regions are dropped with a logged warning).
    members : bool
        Mesh formats only: whether members (edges) on the polygon's segments
        are marked (the truss formats).
    sets : bool
        Mesh formats only: whether the named sets of
        :mod:`uniform2d.io.mesh_sets` are stored (rings, segments, fixed
        points); the writer then takes ``segment_members``, ``ring_members``
        and ``fixed_points``.
    element_types : tuple of str
        Mesh formats only: the element types the writer can declare (its
        ``element_type`` keyword; the first is the default), empty if none.
    """

    extension: str
    description: str
    reader: Callable
    writer: Callable
    point_data: bool = False
    regions: bool = False
    members: bool = False
    sets: bool = False
    element_types: tuple = ()
