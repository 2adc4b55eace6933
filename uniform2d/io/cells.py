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
``gmsh``       Gmsh physical and elementary tags, region + 1, with the
               labels as physical names (written as Gmsh 2.2, which keeps
               one tag per element: meshio's Gmsh 4.1 writer cannot)
``abaqus``     one element set per region, ``REGION_<r>`` or
               ``REGION_<r>_<LABEL>`` (the label in letters, digits, ``_``)
=============  ===========================================================

:func:`to_meshio` gives the keyword arguments of :class:`meshio.Mesh` for a
style, :func:`from_meshio` reads the regions back (None if the file has none).
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


def _label_text(label) -> str:
    return re.sub(r"[^A-Za-z0-9_]+", "_", str(label)).strip("_").upper()


def gmsh_name(r: int, label) -> str:
    return f"region {r}" if label is None else str(label)


def set_name(r: int, label) -> str:
    text = _label_text(label) if label is not None else ""
    return f"REGION_{r}" + (f"_{text}" if text else "")


def to_meshio(style: str, regions: np.ndarray, labels) -> dict:
    """``cell_data``, ``cell_sets`` and ``field_data`` for one triangle block."""
    regions = np.asarray(regions, dtype=np.int64)
    labels = tuple(labels) if labels is not None else (None,) * (int(regions.max()) + 1)
    if style == "abaqus":
        return {"cell_sets": {set_name(r, labels[r] if r < len(labels) else None):
                              [np.flatnonzero(regions == r)] for r in np.unique(regions)}}
    key, offset = _KEYED[style]
    out = {"cell_data": {key: [regions + offset]}}
    if style == "gmsh":
        out["cell_data"]["gmsh:geometrical"] = [regions + offset]
        names = {}
        for r in np.unique(regions):
            name = gmsh_name(int(r), labels[r] if r < len(labels) else None)
            names.setdefault(name, np.array([r + offset, 2]))
        out["field_data"] = names
    return out


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
