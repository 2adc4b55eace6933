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
    as_arrays, boundary_loops, check_degenerate, check_manifold, components, face_areas,
)
from .patch import Patch

__all__ = ["Model"]


def _ro(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


class Model:
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

    __slots__ = ("_vertices", "_faces", "_edges", "_loops", "_vlabel", "_flabel", "_chi", "_n_dropped")

    def __init__(self, vertices, faces):
        V, F, dropped = as_arrays(vertices, faces)
        check_degenerate(V, F)
        edges, boundary_next = check_manifold(V, F)
        ncomp, vlabel = components(len(V), edges)
        self._vertices = _ro(V)
        self._faces = _ro(F)
        self._edges = _ro(edges)
        self._loops = tuple(_ro(lp) for lp in boundary_loops(boundary_next))
        self._vlabel = _ro(vlabel)
        self._flabel = _ro(vlabel[F[:, 0]])
        nv = np.bincount(vlabel, minlength=ncomp)
        ne = np.bincount(vlabel[edges[:, 0]], minlength=ncomp)
        nf = np.bincount(self._flabel, minlength=ncomp)
        self._chi = tuple(int(x) for x in nv - ne + nf)
        self._n_dropped = dropped

    @property
    def vertices(self) -> np.ndarray:
        """Vertex positions, (N, 3) float64, read-only."""
        return self._vertices

    @property
    def faces(self) -> np.ndarray:
        """Triangles, (M, 3) int64, read-only, in the input orientation."""
        return self._faces

    @property
    def edges(self) -> np.ndarray:
        """Unique undirected edges, (E, 2) int64 with ``edges[:, 0] < edges[:, 1]``."""
        return self._edges

    @property
    def boundary_loops(self) -> tuple[np.ndarray, ...]:
        """Boundary loops (interior on the left), each from its smallest vertex index."""
        return self._loops

    @property
    def n_components(self) -> int:
        return len(self._chi)

    @property
    def component_of_face(self) -> np.ndarray:
        """(M,) int64: the component of every face."""
        return self._flabel

    @property
    def component_of_vertex(self) -> np.ndarray:
        """(N,) int64: the component of every vertex."""
        return self._vlabel

    @property
    def component_euler(self) -> tuple[int, ...]:
        """Euler characteristic V - E + F of every component."""
        return self._chi

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
    def n_vertices(self) -> int:
        return len(self._vertices)

    @property
    def n_faces(self) -> int:
        return len(self._faces)

    @property
    def n_dropped_vertices(self) -> int:
        return self._n_dropped

    @property
    def face_areas(self) -> np.ndarray:
        return face_areas(self._vertices, self._faces)

    @property
    def area(self) -> float:
        return float(self.face_areas.sum())

    @property
    def boundary_length(self) -> float:
        V = self._vertices
        return float(sum(np.linalg.norm(V[np.roll(lp, -1)] - V[lp], axis=1).sum() for lp in self._loops))

    @property
    def diagonal(self) -> float:
        return float(np.linalg.norm(self._vertices.max(axis=0) - self._vertices.min(axis=0)))

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
