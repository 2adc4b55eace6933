"""The surface patch model: a checked triangle mesh that is a disk with holes.

A :class:`Patch` is what every later step of the surface layer works on.  Building
one runs every check the parameterisation needs, in this order, and raises
:class:`~surface.errors.InvalidPatchError` with a message that says what to do:

1. a triangle mesh: vertices (N, 3) finite, faces (M, 3) valid indices, M >= 1;
2. no degenerate face (a repeated vertex index, or zero area: twice the area
   below ``1e-12`` times the squared longest edge of the face);
3. manifold: no duplicated face, every edge in at most two faces, the two faces
   of an edge oriented consistently, one fan of faces around every vertex;
4. one connected component;
5. not closed (a closed surface has to be cut open first);
6. a disk with holes: Euler characteristic ``chi = 2 - L`` for ``L`` boundary loops.

Vertices that no face uses are dropped (a logged note, not an error).
"""

from __future__ import annotations


from .checks import (
    DEGENERATE_RATIO, CheckedMesh, as_arrays, boundary_loops, check_connected, check_degenerate,
    check_manifold,
)
from .errors import InvalidPatchError

__all__ = ["Patch", "DEGENERATE_RATIO"]


class Patch(CheckedMesh):
    """A checked disk-with-holes triangle mesh (immutable).

    Parameters
    ----------
    vertices : array_like, shape (N, 3) or (N, 2)
        Vertex positions; a 2-column array is a planar patch (z = 0).
    faces : array_like, shape (M, 3)
        Triangles as vertex indices; the orientation is kept.

    Raises
    ------
    InvalidPatchError
        If any check listed in the module documentation fails; ``err.reason``
        names the check.

    Examples
    --------
    >>> import numpy as np
    >>> from surface.patch import Patch
    >>> p = Patch([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    >>> p.n_vertices, p.n_faces, p.euler_characteristic, len(p.boundary_loops)
    (4, 2, 1, 1)
    >>> p.boundary_loops[0].tolist()          # interior on the left, smallest index first
    [0, 1, 2, 3]
    >>> Patch([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])
    Traceback (most recent call last):
    ...
    surface.errors.InvalidPatchError: face 0 is degenerate (zero area: its corners are collinear or coincide); remove it or merge its vertices, e.g. trimesh's update_faces(nondegenerate_faces()) then merge_vertices()
    """

    __slots__ = ("_chi",)

    def __init__(self, vertices, faces):
        V, F, dropped = as_arrays(vertices, faces)
        check_degenerate(V, F)
        edges, boundary_next = check_manifold(V, F)
        check_connected(V, F, edges)
        loops = boundary_loops(boundary_next)
        if not loops:
            raise InvalidPatchError(
                "the mesh is closed (it has no boundary edge), so it cannot be flattened; "
                "cut it first, e.g. along a seam or by removing a strip of faces, so that "
                "it becomes a disk, possibly with holes",
                "closed",
            )
        chi = len(V) - len(edges) + len(F)
        expected = 2 - len(loops)
        if chi != expected:
            genus = (expected - chi) / 2
            raise InvalidPatchError(
                f"the mesh is not a disk with holes: Euler characteristic V - E + F = {chi} "
                f"with {len(loops)} boundary loop(s), where a disk with {len(loops) - 1} "
                f"hole(s) has {expected} (the surface has {genus:g} handle(s)); cut each "
                "handle open along a closed curve that goes around it, then remesh",
                "topology",
            )
        self._keep(V, F, edges, loops, dropped)
        self._chi = chi

    @property
    def euler_characteristic(self) -> int:
        return self._chi

    def __repr__(self) -> str:
        return (
            f"Patch({self.n_vertices} vertices, {self.n_faces} faces, "
            f"{len(self._loops)} boundary loop(s))"
        )
