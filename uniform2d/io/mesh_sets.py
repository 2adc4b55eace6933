"""Named sets of a mesh: where an analyst puts supports and loads.

A mesh of a polygon carries, besides its triangles, the places a finite-element
model refers to by name: its regions (triangles), its rings and interior
segments (chains of edges), and its fixed points (nodes).  :func:`mesh_sets`
lists them once, with the names and numbers every format writes
(:mod:`uniform2d.io.gmsh_file`, :mod:`uniform2d.io.abaqus_file`,
:mod:`uniform2d.io.vtk_file`):

==============  =====  =============================  ==============================
set             dim    name (Gmsh, VTU, scikit-fem)   Abaqus name
==============  =====  =============================  ==============================
region ``r``    2      its label, else ``region r``   ``REGION_r`` or ``REGION_r_LABEL``
outer ring      1      ``outer``                      ``OUTER``
hole ``i``      1      ``hole i``                     ``HOLE_i``
segment ``s``   1      ``segment s``                  ``SEGMENT_s``
point ``k``     0      ``point k``                    ``POINT_k``
==============  =====  =============================  ==============================

Numbers count from 0 as in the Python API (``polygon.holes[i]``,
``polygon.segments[s]``, ``polygon.points[k]``, :attr:`uniform2d.Mesh.regions`).
Every set has a *tag* (Gmsh's physical tag), unique among all sets: region
``r`` is ``r + 1``, then the rings, the segments and the points follow.  A name
used twice (two regions with one label, a region labelled ``outer``) gets
`` (tag t)`` appended to the later ones, so every name is unique too.

Examples
--------
>>> import numpy as np
>>> sets = mesh_sets(2, regions=np.array([0, 1]), labels=("web", None),
...                  ring_members=(np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), np.zeros(4, int)),
...                  fixed_points=np.array([2]))
>>> [(s.name, s.dim, s.tag, s.abaqus) for s in sets]
[('web', 2, 1, 'REGION_0_WEB'), ('region 1', 2, 2, 'REGION_1'), ('outer', 1, 3, 'OUTER'), ('point 0', 0, 4, 'POINT_0')]
>>> sets[3].items.tolist()
[2]
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["MeshSet", "abaqus_name", "mesh_sets"]


@dataclass(frozen=True)
class MeshSet:
    """One named set of a mesh.

    Attributes
    ----------
    name : str
        Its name in Gmsh, VTU and scikit-fem (unique among the sets).
    abaqus : str
        Its Abaqus set name (letters, digits and ``_``, upper case).
    dim : int
        2 for triangles, 1 for edges, 0 for nodes.
    tag : int
        Its number, from 1, unique among the sets (Gmsh's physical tag).
    kind : str
        ``region``, ``ring``, ``segment`` or ``point``.
    index : int
        The region, ring (0 outer, ``1 + i`` hole i), segment or point number.
    items : ndarray of int64
        Triangle indices (dim 2, shape (K,)), edges as node pairs (dim 1,
        shape (K, 2), along the ring or segment) or node indices (dim 0, (K,)).
    """

    name: str
    abaqus: str
    dim: int
    tag: int
    kind: str
    index: int
    items: np.ndarray


def abaqus_name(text: str) -> str:
    """``text`` as an Abaqus set name: runs of other characters become ``_``, upper case."""
    return re.sub(r"[^A-Za-z0-9_]+", "_", str(text)).strip("_").upper()


def _region_abaqus(r: int, label) -> str:
    text = abaqus_name(label) if label is not None else ""
    return f"REGION_{r}" + (f"_{text}" if text else "")


def _edge_sets(members, kind: str, names) -> list[tuple]:
    if members is None:
        return []
    edges, ids = (np.asarray(a, dtype=np.int64) for a in members)
    out = []
    for i in np.unique(ids).tolist():
        name = names(i)
        out.append((name, abaqus_name(name), 1, kind, i, edges[ids == i].reshape(-1, 2)))
    return out


def mesh_sets(n_triangles: int, *, regions=None, labels=None, ring_members=None,
              segment_members=None, fixed_points=None) -> list[MeshSet]:
    """The named sets of a mesh, regions first, then rings, segments and points.

    Parameters
    ----------
    n_triangles : int
    regions : ndarray, shape (M,), optional
        The region of every triangle; None: one region 0 holding them all.
    labels : sequence, optional
        The label of each region (None for none).
    ring_members, segment_members : (edges (K, 2), ids (K,)), optional
        Mesh edges on the rings (:attr:`uniform2d.Mesh.ring_members`) and on
        the segments (:attr:`uniform2d.Mesh.segment_members`).
    fixed_points : ndarray, shape (F,), optional
        The mesh node of each fixed point (``polygon.fixed``).

    Returns
    -------
    list of MeshSet
    """
    reg = np.zeros(n_triangles, np.int64) if regions is None else np.asarray(regions, np.int64)
    n_regions = int(reg.max()) + 1 if len(reg) else 0
    labels = tuple(labels) if labels is not None else ()
    raw = []
    for r in range(n_regions):
        label = labels[r] if r < len(labels) else None
        raw.append((f"region {r}" if label is None else str(label), _region_abaqus(r, label),
                    2, "region", r, np.flatnonzero(reg == r)))
    raw += _edge_sets(ring_members, "ring", lambda i: "outer" if i == 0 else f"hole {i - 1}")
    raw += _edge_sets(segment_members, "segment", lambda i: f"segment {i}")
    if fixed_points is not None:
        raw += [(f"point {k}", f"POINT_{k}", 0, "point", k, np.array([v], np.int64))
                for k, v in enumerate(np.asarray(fixed_points, np.int64).tolist())]
    out, seen, seen_abaqus = [], set(), set()
    for tag, (name, abq, dim, kind, index, items) in enumerate(raw, start=1):
        if name in seen:
            name = f"{name} (tag {tag})"
        if abq in seen_abaqus:
            abq = f"{abq}_TAG_{tag}"
        seen.add(name)
        seen_abaqus.add(abq)
        out.append(MeshSet(name, abq, dim, tag, kind, index, items))
    return out
