"""Gmsh ``.msh`` files (MSH 4.1, ASCII) with the mesh's named sets as physical groups.

Written here rather than by meshio, whose MSH 4.1 writer keeps one physical tag
per cell block and no physical points or curves.  The file holds:

* one geometric entity per set of :func:`uniform2d.io.mesh_sets.mesh_sets`:
  a surface per region (entity tag ``r + 1``), a curve per ring and per
  segment, a point per fixed point, each in the physical group of its set
  (physical tag = the set's tag, physical name = its name);
* the nodes in one block, tagged ``1..N`` in the mesh's order (so meshio and
  scikit-fem read them in that order);
* the triangles (type 2) grouped by region, each tagged with its index in the
  mesh plus one; then the line elements (type 1) along every ring and segment,
  and a point element (type 15) per fixed point.

Reading back (:func:`uniform2d.io.read_mesh`, through meshio) gives the same
points and triangles, the triangles grouped by region; ``regions=True`` reads
each triangle's physical tag minus one.  scikit-fem's ``Mesh.load`` sees the
regions as ``mesh.subdomains`` and the rings and segments as
``mesh.boundaries`` (by name); Gmsh lists all of them with
``gmsh.model.getPhysicalGroups``.  Point data is not stored.

Examples
--------
>>> import os, tempfile
>>> from dataclasses import replace

import numpy as np
>>> from uniform2d.io.gmsh_file import write_gmsh
>>> path = os.path.join(tempfile.mkdtemp(), "square.msh")
>>> ring = (np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), np.zeros(4, int))
>>> write_gmsh(path, np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]]),
...            np.array([[0, 1, 2], [0, 2, 3]]), ring_members=ring)
>>> print(open(path).read().split("$Entities")[0])
$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "region 0"
1 2 "outer"
$EndPhysicalNames
<BLANKLINE>
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .mesh_sets import mesh_sets

__all__ = ["write_gmsh"]

_ELEMENT_TYPE = {2: 2, 1: 1, 0: 15}  # dim -> Gmsh element type (triangle, line, point)


def _num(x: float) -> str:
    return repr(float(x))


def _box(points: np.ndarray, nodes: np.ndarray) -> str:
    p = points[np.unique(nodes)]
    lo, hi = p.min(axis=0), p.max(axis=0)
    return " ".join(map(_num, [lo[0], lo[1], 0.0, hi[0], hi[1], 0.0]))


def _physical(s) -> str:
    """numPhysicalTags physicalTag...: the set's tag, none for tag 0 (a bare mesh)."""
    return f"1 {s.tag}" if s.tag else "0"


def _entities(points, triangles, sets) -> list[str]:
    """The $Entities section: one entity per non-empty set, tagged per dimension."""
    by_dim = {0: [], 1: [], 2: []}
    for s in sets:
        by_dim[s.dim].append(s)
    lines = ["$Entities", f"{len(by_dim[0])} {len(by_dim[1])} {len(by_dim[2])} 0"]
    for k, s in enumerate(by_dim[0], start=1):
        x, y = points[s.items[0]]
        lines.append(f"{k} {_num(x)} {_num(y)} 0.0 {_physical(s)}")
    for k, s in enumerate(by_dim[1], start=1):
        lines.append(f"{k} {_box(points, s.items)} {_physical(s)} 0")
    for k, s in enumerate(by_dim[2], start=1):
        lines.append(f"{k} {_box(points, triangles[s.items])} {_physical(s)} 0")
    lines.append("$EndEntities")
    return lines


def _elements(triangles, sets) -> list[str]:
    """The $Elements section: triangles tagged by their index + 1, then lines and points."""
    blocks, next_tag = [], len(triangles) + 1
    count = {0: 0, 1: 0, 2: 0}
    for s in sets:
        count[s.dim] += 1
        head = f"{s.dim} {count[s.dim]} {_ELEMENT_TYPE[s.dim]} {len(s.items)}"
        if s.dim == 2:
            rows = np.column_stack([s.items + 1, triangles[s.items] + 1])
        else:
            ids = np.arange(next_tag, next_tag + len(s.items))
            next_tag += len(s.items)
            rows = np.column_stack([ids, s.items.reshape(len(s.items), -1) + 1])
        blocks.append(head + "\n" + "\n".join(" ".join(map(str, r)) for r in rows.tolist()))
    total = sum(len(s.items) for s in sets)
    return ["$Elements", f"{len(blocks)} {total} 1 {next_tag - 1}", *blocks, "$EndElements"]


def write_gmsh(path, points, triangles, point_data=None, *, regions=None, labels=None,
               segment_members=None, ring_members=None, fixed_points=None) -> None:
    """Write an MSH 4.1 ASCII file as the module docstring says.

    Parameters
    ----------
    path : str or os.PathLike
    points : ndarray, shape (N, 2), float64
    triangles : ndarray, shape (M, 3), int64
    point_data : dict, optional
        Not stored (:func:`uniform2d.io.write_mesh` drops it with a warning).
    regions, labels, segment_members, ring_members, fixed_points
        The sets, as :func:`uniform2d.io.mesh_sets.mesh_sets` takes them.
    """
    points = np.asarray(points, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    sets = [s for s in mesh_sets(len(triangles), regions=regions, labels=labels,
                                 ring_members=ring_members, segment_members=segment_members,
                                 fixed_points=fixed_points) if len(s.items)]
    named = regions is not None or len(sets) > 1
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat"]
    if named:
        lines += ["$PhysicalNames", str(len(sets))]
        lines += [f'{s.dim} {s.tag} "{s.name.replace(chr(34), chr(39))}"' for s in sets]
        lines.append("$EndPhysicalNames")
    else:  # a bare mesh: one surface in no physical group, as meshio wrote it
        sets = [replace(s, tag=0) for s in sets]
    entities = _entities(points, triangles, sets)
    n = len(points)
    nodes = ["$Nodes", f"1 {n} 1 {n}", f"2 1 0 {n}", "\n".join(map(str, range(1, n + 1))),
             "\n".join(f"{_num(x)} {_num(y)} 0.0" for x, y in points.tolist()), "$EndNodes"]
    text = "\n".join(lines + entities + nodes + _elements(triangles, sets)) + "\n"
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
