"""Regions (one integer per triangle) in meshio-backed mesh files.

Each format that carries cell data stores a mesh's regions its own way (the
*style* the registry gives it):

=============  ===========================================================
style          stored as
=============  ===========================================================
``region``     cell data array ``region`` (VTU, legacy VTK, Tecplot),
               the region numbers from 0
``medit``      Medit element references ``medit:ref``, region + 1
``netgen``     Netgen face indices ``netgen:index``, region + 1
``avsucd``     AVS-UCD material ids, the region numbers from 0
``gmsh``       Gmsh physical tags, region + 1 (read only: written by
               :mod:`uniform2d.io.gmsh_file`, with names)
``abaqus``     one element set per region, ``REGION_<r>`` or
               ``REGION_<r>_<LABEL>`` (read only: written by
               :mod:`uniform2d.io.abaqus_file`)
=============  ===========================================================

:func:`to_meshio` gives the keyword arguments of :class:`meshio.Mesh` for a
style it writes, :func:`from_meshio` reads the regions back (None if the file
has none).
"""

from __future__ import annotations

import re

import numpy as np

from ..errors import FileFormatError

__all__ = ["STYLES", "to_meshio", "from_meshio"]

#: style -> (cell data key, offset of the stored number)
_KEYED = {"region": ("region", 0), "medit": ("medit:ref", 1), "netgen": ("netgen:index", 1),
          "avsucd": ("avsucd:material", 0), "gmsh": ("gmsh:physical", 1)}
STYLES = (*_KEYED, "abaqus")
_SET = re.compile(r"^REGION_(\d+)(?:_.*)?$", re.IGNORECASE)


def to_meshio(style: str, regions: np.ndarray) -> dict:
    """``cell_data`` for one triangle block (styles other than gmsh and abaqus)."""
    regions = np.asarray(regions, dtype=np.int64)
    key, offset = _KEYED[style]
    return {"cell_data": {key: [regions + offset]}}


def from_meshio(path, style: str, mesh, n_triangles: int):
    """The (M,) int64 regions of the triangle blocks of a meshio mesh, or None."""
    blocks = [i for i, c in enumerate(mesh.cells) if c.type == "triangle"]
    if style == "abaqus":
        out = np.full(n_triangles, -1, np.int64)
        start = np.cumsum([0] + [len(mesh.cells[i].data) for i in blocks])
        for name, per_block in mesh.cell_sets.items():
            m = _SET.match(name)
            if not m:
                continue
            for k, i in enumerate(blocks):
                idx = np.asarray(per_block[i], dtype=np.int64) if i < len(per_block) else []
                out[start[k] + idx] = int(m.group(1))
        if (out < 0).all():
            return None
        if (out < 0).any():
            raise FileFormatError(f"{path}: some triangles are in no REGION_<r> element set")
        return out
    key, offset = _KEYED[style]
    data = mesh.cell_data.get(key)
    if data is None:
        return None
    values = np.concatenate([np.asarray(data[i]).ravel() for i in blocks])
    if not np.all(values == np.round(values)):
        raise FileFormatError(f"{path}: the {key} cell data are not whole numbers")
    out = values.astype(np.int64) - offset
    if out.min() < 0:
        raise FileFormatError(f"{path}: a {key} value is below {offset}; it is not a region")
    return out
