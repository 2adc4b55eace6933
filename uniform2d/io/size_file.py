"""Size fields read from files: :func:`read_size_field`.

Two kinds of file:

* a **grid**: ``.npz`` with arrays ``x`` (nx,), ``y`` (ny,) and ``values``
  (ny, nx), or ``.json`` with the same three keys, read as a
  :class:`~uniform2d.SizeField` (bilinear; outside the grid the nearest grid
  value: a grid that does not cover the domain is clamped);
* **point data of a background mesh**, any format meshio reads (``.vtu``,
  ``.msh``, ...): the sizes at its points (the point data array named ``size``,
  or the only one), interpolated linearly on the Delaunay triangles of its
  points (scipy's ``LinearNDInterpolator``; on a convex background mesh these
  are its own triangles up to cocircular ties), with the nearest point's size
  outside them.  The result is a callable, sampled onto a grid over the
  polygon when it is used (:func:`uniform2d.grading.as_field`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import FileFormatError
from ..sizefield import SizeField

__all__ = ["GRID_SUFFIXES", "read_size_field"]

GRID_SUFFIXES = (".npz", ".json")


def _grid(path: Path, data) -> SizeField:
    missing = [k for k in ("x", "y", "values") if k not in data]
    if missing:
        raise FileFormatError(
            f"{path}: a size grid needs the arrays x, y and values (values[j, i] = h(x[i], "
            f"y[j])); missing: {', '.join(missing)}")
    try:
        return SizeField(data["x"], data["y"], data["values"])
    except ValueError as exc:
        raise FileFormatError(f"{path}: {exc}") from None


def _background(path: Path):
    import meshio
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

    try:
        m = meshio.read(path)
    except Exception as exc:  # noqa: BLE001 (meshio raises many kinds on a file it cannot read)
        raise FileFormatError(f"{path}: not a size grid (.npz, .json) nor a mesh meshio "
                              f"reads: {exc}") from None
    data = m.point_data
    if "size" in data:
        v = data["size"]
    elif len(data) == 1:
        (v,) = data.values()
    else:
        raise FileFormatError(
            f"{path}: the background mesh needs one point data array of sizes (named 'size' "
            f"if there are several); found {sorted(data) or 'none'}")
    v = np.asarray(v, dtype=np.float64).reshape(-1)
    P = np.asarray(m.points, dtype=np.float64)[:, :2]
    if len(v) != len(P) or len(P) < 3:
        raise FileFormatError(f"{path}: {len(v)} sizes for {len(P)} points")
    lin = LinearNDInterpolator(P, v)
    near = NearestNDInterpolator(P, v)

    def h(p):
        out = lin(p)
        out = np.asarray(out, dtype=np.float64).reshape(-1)
        miss = np.isnan(out)
        if np.any(miss):
            out[miss] = near(p[miss])
        return out

    return h


def read_size_field(path):
    """The size field in ``path``: a :class:`~uniform2d.SizeField` for a grid file,
    a callable ``h(points (k, 2)) -> (k,)`` for a background mesh (see the module
    docstring); either goes to ``uniform_mesh(..., size=)``.

    Examples
    --------
    >>> import json, os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "h.json")
    >>> _ = open(p, "w").write(json.dumps({"x": [0, 1], "y": [0, 1], "values": [[1, 2], [1, 2]]}))
    >>> read_size_field(p)([[0.5, 0.5]]).tolist()
    [1.5]
    """
    path = Path(path)
    if not path.exists():
        raise FileFormatError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        try:
            with np.load(path) as z:
                return _grid(path, {k: z[k] for k in z.files})
        except (OSError, ValueError) as exc:
            raise FileFormatError(f"{path}: not a readable .npz file: {exc}") from None
    if suffix == ".json":
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise FileFormatError(f"{path}: not a readable JSON file: {exc}") from None
        if not isinstance(data, dict):
            raise FileFormatError(f"{path}: expected an object with x, y and values")
        return _grid(path, data)
    return _background(path)
