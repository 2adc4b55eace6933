"""Abaqus ``.inp`` files: nodes, triangles of a real element type, and named sets.

Written here rather than by meshio, whose writer declares every triangle a
rigid ``R3D3`` element.  A planar mesh (2-D nodes) is written with a
continuum type of :data:`PLANAR_TYPES` (``CPS3``, plane stress, by default;
``CPE3`` plane strain, ``CAX3`` axisymmetric with ``x`` the radius); a
surface (3-D nodes) with a shell type of :data:`SHELL_TYPES` (``S3`` by
default).  After the nodes and elements come the sets of
:func:`uniform2d.io.mesh_sets.mesh_sets` under their Abaqus names:

* ``*ELSET`` per region (``REGION_r`` or ``REGION_r_LABEL``);
* ``*NSET`` per ring, segment and fixed point (``OUTER``, ``HOLE_i``,
  ``SEGMENT_s``, ``POINT_k``): the nodes along it, in order;
* ``*SURFACE, TYPE=ELEMENT`` per ring (``OUTER_EDGES``, ``HOLE_i_EDGES``):
  the element faces on it, for distributed loads (``*DSLOAD``).

Nodes and elements are numbered from 1 in the mesh's order; coordinates are
written in shortest round-trip form, so reading gives the same floats.

Reading goes through meshio, which does not know ``CPE3`` and ``CAX3``: a file
with those element types is read with them taken as ``CPS3`` (the same
3-node triangle).

Examples
--------
>>> import os, tempfile
>>> import numpy as np
>>> path = os.path.join(tempfile.mkdtemp(), "tri.inp")
>>> write_abaqus(path, np.array([[0., 0.], [4., 0.], [0., 3.]]), np.array([[0, 1, 2]]),
...              fixed_points=np.array([0]), element_type="CPE3")
>>> print(open(path).read())
*HEADING
uniform2d mesh: 3 nodes, 1 elements CPE3
*NODE
1, 0.0, 0.0
2, 4.0, 0.0
3, 0.0, 3.0
*ELEMENT, TYPE=CPE3
1, 1, 2, 3
*ELSET, ELSET=REGION_0
1
*NSET, NSET=POINT_0
1
<BLANKLINE>
"""

from __future__ import annotations

import io
import re

import numpy as np

from ..errors import InvalidArgumentError
from .mesh_sets import mesh_sets

__all__ = ["PLANAR_TYPES", "SHELL_TYPES", "read_abaqus_text", "write_abaqus"]

#: 3-node element types for planar meshes; the first is the default.
PLANAR_TYPES = ("CPS3", "CPE3", "CAX3")
#: 3-node element types for surfaces (3-D nodes); the first is the default.
SHELL_TYPES = ("S3", "S3R")
#: Triangle types meshio 5.3 does not read, read as CPS3.
_UNKNOWN_TO_MESHIO = ("CPE3", "CPE3H", "CAX3", "CAX3H", "CPS3T", "CPE3T", "CAX3T")
_PER_LINE = 16  # Abaqus reads at most 16 entries on a data line


def _num(x) -> str:
    return repr(float(x))


def element_type_for(dimension: int, element_type: str | None) -> str:
    """The element type to write for points of ``dimension`` (2 or 3), checked."""
    allowed = PLANAR_TYPES if dimension == 2 else SHELL_TYPES
    if element_type is None:
        return allowed[0]
    name = str(element_type).upper()
    if name not in allowed:
        what = "a planar mesh (2-D points)" if dimension == 2 else "a surface (3-D points)"
        raise InvalidArgumentError(
            f"element type {element_type!r} does not fit {what}; use one of "
            f"{', '.join(allowed)}")
    return name


def _id_lines(ids) -> list[str]:
    ids = [str(int(i)) for i in ids]
    return [", ".join(ids[i:i + _PER_LINE]) for i in range(0, len(ids), _PER_LINE)]


def _chain_nodes(edges: np.ndarray) -> np.ndarray:
    """The nodes of a chain of edges in order, each once (a closed ring not repeated)."""
    nodes = np.concatenate([edges[:, 0], edges[-1:, 1]])
    _, first = np.unique(nodes, return_index=True)
    return nodes[np.sort(first)]


def _faces(triangles: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The element and its face (1: nodes 1-2, 2: 2-3, 3: 3-1) holding each directed edge."""
    he = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    n = int(max(triangles.max(), edges.max())) + 1
    key = he[:, 0] * n + he[:, 1]
    order = np.argsort(key, kind="stable")
    want = edges[:, 0] * n + edges[:, 1]
    at = np.minimum(np.searchsorted(key[order], want), len(key) - 1)
    pos = order[at]
    if not (key[pos] == want).all():
        raise InvalidArgumentError(
            "ring_members must be edges of the triangles in their direction (the interior "
            "on their left, as Mesh.ring_members gives them)")
    return pos // 3, pos % 3 + 1


def write_abaqus(path, points, triangles, point_data=None, *, regions=None, labels=None,
                 segment_members=None, ring_members=None, fixed_points=None,
                 element_type=None) -> None:
    """Write an Abaqus input file as the module docstring says.

    Parameters
    ----------
    path : str or os.PathLike
    points : ndarray, shape (N, 2) or (N, 3), float64
        2-D for a planar mesh, 3-D for a surface.
    triangles : ndarray, shape (M, 3), int64
    point_data : dict, optional
        Not stored.
    regions, labels, segment_members, ring_members, fixed_points
        The sets, as :func:`uniform2d.io.mesh_sets.mesh_sets` takes them.
    element_type : str, optional
        One of :data:`PLANAR_TYPES` (2-D points) or :data:`SHELL_TYPES` (3-D).

    Raises
    ------
    InvalidArgumentError
        If the element type does not fit the points, or ``CAX3`` is asked for
        a mesh with points at ``x < 0`` (the radius).
    """
    points = np.asarray(points, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    etype = element_type_for(points.shape[1], element_type)
    if etype.startswith("CAX") and len(points) and points[:, 0].min() < 0:
        raise InvalidArgumentError(
            f"{etype} is axisymmetric: x is the radius and must be >= 0, but a point has "
            f"x = {points[:, 0].min():.6g}; move the polygon to x >= 0 (or use CPS3, CPE3)")
    lines = ["*HEADING",
             f"uniform2d mesh: {len(points)} nodes, {len(triangles)} elements {etype}", "*NODE"]
    lines += [", ".join([str(k)] + [_num(c) for c in p])
              for k, p in enumerate(points.tolist(), start=1)]
    lines.append(f"*ELEMENT, TYPE={etype}")
    lines += [f"{k}, {a}, {b}, {c}" for k, (a, b, c) in enumerate((triangles + 1).tolist(), 1)]
    sets = mesh_sets(len(triangles), regions=regions, labels=labels, ring_members=ring_members,
                     segment_members=segment_members, fixed_points=fixed_points)
    surfaces = []
    for s in sets:
        if not len(s.items):
            continue
        if s.dim == 2:
            lines += [f"*ELSET, ELSET={s.abaqus}", *_id_lines(s.items + 1)]
            continue
        nodes = _chain_nodes(s.items) if s.dim == 1 else s.items
        lines += [f"*NSET, NSET={s.abaqus}", *_id_lines(nodes + 1)]
        if s.kind == "ring":
            elements, faces = _faces(triangles, s.items)
            surfaces += [f"*SURFACE, TYPE=ELEMENT, NAME={s.abaqus}_EDGES"]
            surfaces += [f"{e + 1}, S{f}" for e, f in zip(elements.tolist(), faces.tolist())]
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write("\n".join(lines + surfaces) + "\n")


_ELEMENT_LINE = re.compile(r"^(\*ELEMENT\b[^\n]*TYPE\s*=\s*)(" + "|".join(_UNKNOWN_TO_MESHIO)
                           + r")\b", re.IGNORECASE | re.MULTILINE)


def read_abaqus_text(path):
    """A meshio mesh of an Abaqus file; element types meshio does not know
    (``CPE3``, ``CAX3``, ...) are read as the 3-node triangle they are."""
    import meshio

    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    if not _ELEMENT_LINE.search(text):
        return meshio.abaqus.read(path)
    # meshio reads a text buffer when given its format (an *INCLUDE then resolves
    # from the working directory only)
    return meshio.read(io.StringIO(_ELEMENT_LINE.sub(r"\1CPS3", text)), file_format="abaqus")
