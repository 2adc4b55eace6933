"""VTK files (``.vtu``, legacy ``.vtk``) with the mesh's named sets as cells.

A mesh without sets is written by meshio as before: the triangles, their
``region`` cell data when given.  With sets (:mod:`uniform2d.io.mesh_sets`: a
mesh written by :meth:`uniform2d.Mesh.write` has at least its rings), the file
also holds

* a ``line`` cell per mesh edge on a ring or segment, after the triangles,
  and a ``vertex`` cell per fixed point after those;
* the cell data ``region`` (the triangle's region, -1 on lines and vertices)
  and ``set`` (the tag of the cell's set, the numbers Gmsh files use);
* in ``.vtu`` files, the names: one field data array per set, named after it,
  holding ``[tag, dim]`` (as meshio gives Gmsh's physical names), so ParaView
  and ``meshio.read(path).field_data`` show which ``set`` number is which.

Legacy ``.vtk`` files get the cells and numbers but no names (meshio's legacy
writer stores no field data).

Examples
--------
>>> import os, tempfile
>>> import meshio
>>> import numpy as np
>>> from uniform2d.io import write_mesh
>>> path = os.path.join(tempfile.mkdtemp(), "square.vtu")
>>> ring = (np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), np.zeros(4, int))
>>> write_mesh(path, [[0., 0.], [1., 0.], [1., 1.], [0., 1.]], [[0, 1, 2], [0, 2, 3]],
...            ring_members=ring)
>>> m = meshio.read(path)
>>> [(c.type, len(c)) for c in m.cells], {k: v.tolist() for k, v in m.field_data.items()}
([('triangle', 2), ('line', 4)], {'region 0': [1, 2], 'outer': [2, 1]})
>>> m.cell_data["set"][1].tolist()
[2, 2, 2, 2]
"""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np

from .mesh_files import meshio_writer, write_meshio
from .mesh_sets import mesh_sets

__all__ = ["vtk_writer"]


def _field_data(path, sets) -> None:
    """Put the set names into the ``<UnstructuredGrid>`` of a VTU file as field data."""
    arrays = "".join(
        f'<DataArray type="Int64" Name={quoteattr(s.name)} NumberOfTuples="2" '
        f'format="ascii">{s.tag} {s.dim}</DataArray>\n' for s in sets)
    with open(path, "rb") as f:
        data = f.read()
    head = b"<UnstructuredGrid>"
    at = data.index(head) + len(head)
    block = ("\n<FieldData>\n" + arrays + "</FieldData>").encode("utf-8")
    with open(path, "wb") as f:
        f.write(data[:at] + block + data[at:])


def vtk_writer(file_format: str, **options):
    """A writer for meshio's `file_format` (``"vtu"`` or ``"vtk"``) with named sets."""
    plain = meshio_writer(file_format, pad_z=True, regions="region", **options)

    def write(path, points, triangles, point_data=None, *, regions=None, labels=None,
              segment_members=None, ring_members=None, fixed_points=None):
        import meshio

        if ring_members is None and segment_members is None and fixed_points is None:
            return plain(path, points, triangles, point_data, regions=regions, labels=labels)
        pts = np.asarray(points, dtype=np.float64)
        tri = np.asarray(triangles, dtype=np.int64)
        sets = [s for s in mesh_sets(len(tri), regions=regions, labels=labels,
                                     ring_members=ring_members, segment_members=segment_members,
                                     fixed_points=fixed_points) if len(s.items)]
        region = np.full(len(tri), -1, np.int64)
        tag = np.zeros(len(tri), np.int64)
        for s in sets:
            if s.dim == 2:
                region[s.items], tag[s.items] = s.index, s.tag
        cells, region_data, tag_data = [("triangle", tri)], [region], [tag]
        for dim, kind in ((1, "line"), (0, "vertex")):
            mine = [s for s in sets if s.dim == dim]
            if mine:
                cells.append((kind, np.concatenate([s.items.reshape(len(s.items), -1)
                                                    for s in mine])))
                tag_data.append(np.concatenate([np.full(len(s.items), s.tag) for s in mine]))
                region_data.append(np.full(len(tag_data[-1]), -1, np.int64))
        mesh = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]), cells,
                           point_data={k: np.asarray(v) for k, v in (point_data or {}).items()},
                           cell_data={"region": region_data, "set": tag_data})
        write_meshio(path, mesh, file_format, **options)
        if file_format == "vtu":
            _field_data(path, sets)

    write.__name__ = f"write_{file_format}"
    write.__doc__ = f"Write a triangle mesh and its named sets with meshio's {file_format!r} writer."
    return write
