"""The whole-model: any manifold, consistently oriented triangle mesh.

A :class:`Model` is what :func:`surface.remesh` accepts: closed or open, of any
genus, in one or several components.  It runs the checks of
:mod:`surface.checks` (shapes and values, degenerate faces, manifold edges and
vertices, consistent orientation) and records the topology the remesh must
keep: components, boundary loops, Euler characteristic and genus of each
component.  A model that is one disk (possibly with holes) is also a
:class:`~surface.patch.Patch` (:meth:`Model.as_patch`), which can be flattened
in one piece; every other model is cut into an atlas of charts
(:mod:`surface.atlas`).
"""

from __future__ import annotations

import numpy as np

from .checks import (
    CheckedMesh, as_arrays, boundary_loops, check_degenerate, check_manifold, components,
    read_only,
)
from .patch import Patch

__all__ = ["Model"]


class Model(CheckedMesh):
    """A checked manifold, oriented triangle mesh of any topology (immutable).

    Parameters
    ----------
    vertices : array_like, shape (N, 3) or (N, 2)
    faces : array_like, shape (M, 3)

    Raises
    ------
    InvalidPatchError
        Non-finite or badly shaped arrays, degenerate faces, non-manifold edges or
        vertices, inconsistent orientation (see :mod:`surface.checks`).

    Examples
    --------
    >>> import trimesh
    >>> s = trimesh.creation.icosphere(2)
    >>> m = Model(s.vertices, s.faces)
    >>> m.n_components, m.euler_characteristic, m.genus, m.is_closed
    (1, 2, (0,), True)
    >>> m.as_patch() is None           # a sphere cannot be flattened in one piece
    True
    """

    __slots__ = ("_vlabel", "_chi")

    def __init__(self, vertices, faces):
        V, F, dropped = as_arrays(vertices, faces)
        check_degenerate(V, F)
        edges, boundary_next = check_manifold(V, F)
        ncomp, vlabel = components(len(V), edges)
        self._keep(V, F, edges, boundary_loops(boundary_next), dropped)
        self._vlabel = read_only(vlabel)
        nv = np.bincount(vlabel, minlength=ncomp)
        ne = np.bincount(vlabel[edges[:, 0]], minlength=ncomp)
        nf = np.bincount(vlabel[F[:, 0]], minlength=ncomp)
        self._chi = tuple(int(x) for x in nv - ne + nf)

    @property
    def n_components(self) -> int:
        return len(self._chi)

    @property
    def euler_characteristic(self) -> int:
        return int(sum(self._chi))

    @property
    def loops_per_component(self) -> tuple[int, ...]:
        """Number of boundary loops of every component."""
        counts = np.bincount([self._vlabel[lp[0]] for lp in self._loops], minlength=self.n_components)
        return tuple(int(c) for c in counts)

    @property
    def genus(self) -> tuple[int, ...]:
        """Genus of every component: ``(2 - chi - loops) / 2``."""
        return tuple((2 - c - b) // 2 for c, b in zip(self._chi, self.loops_per_component))

    @property
    def is_closed(self) -> bool:
        return not self._loops

    @property
    def is_disk(self) -> bool:
        """One component that is a disk, possibly with holes (a :class:`Patch`)."""
        return self.n_components == 1 and bool(self._loops) and self.genus == (0,)

    def as_patch(self) -> Patch | None:
        """The model as a :class:`Patch`, or None when it is not one disk with holes."""
        return Patch(self._vertices, self._faces) if self.is_disk else None

    def topology(self) -> dict:
        """What a remesh must keep: components, Euler characteristics, loops, genus."""
        return {
            "components": self.n_components,
            "euler": list(self._chi),
            "boundary_loops": list(self.loops_per_component),
            "genus": list(self.genus),
        }

    def __repr__(self) -> str:
        return (
            f"Model({self.n_vertices} vertices, {self.n_faces} faces, {self.n_components} "
            f"component(s), {len(self._loops)} boundary loop(s), genus {list(self.genus)})"
        )
