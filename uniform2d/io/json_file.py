"""uniform2d's own polygon format, ``.json``.

``{"outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}``; ``"holes"`` is
optional, rings may be given closed or open, in either orientation, and other
keys (``"units"``, ``"description"``, ...) are ignored.  Three optional keys
carry the constraints: ``"segments"``, a list of polylines ``[[x, y], ...]``
(closed if the last point repeats the first), ``"points"``, a list of
``[x, y]``, and ``"regions"``, a list of ``[x, y, label]`` seeds (label a string
or a number).  A JSON file with a ``"type"`` member is read as GeoJSON
(:mod:`uniform2d.io.geojson_file`).  Written one vertex per line with exact
floats; a polygon without constraints is written with ``"outer"`` and
``"holes"`` only.
"""

from __future__ import annotations

import logging

from ..polygon import Polygon
from .common import (fail, is_number, json_ring, json_ring_text, label_json, label_ok, load_json,
                     make_polygon, num, short)
from .fileformat import FileFormat
from .geojson_file import polygon_from_geojson

__all__ = ["read_json", "write_json", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    'uniform2d polygon JSON {"outer": [[x, y], ...], "holes": [...], "segments": [...], '
    '"points": [...], "regions": [[x, y, label], ...]} (GeoJSON also accepted)'
)

_OUR_JSON = '{"outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}'


def _json_rings(path, data):
    """(outer, holes) of uniform2d's JSON polygon object."""
    if not isinstance(data, dict):
        fail(path, f"expected a JSON object {_OUR_JSON}, got a JSON {type(data).__name__}")
    if "outer" not in data:
        if "nodes" in data and ("triangles" in data or "members" in data):
            fail(
                path,
                "this is a uniform2d truss mesh, not a polygon; read it with "
                "uniform2d.io.read_mesh (truss meshes use the extension .truss.json)",
            )
        keys = ", ".join(repr(k) for k in list(data)[:8]) or "none"
        fail(path, f'missing the "outer" key (keys found: {keys}); expected {_OUR_JSON}')
    outer = json_ring(path, data["outer"], '"outer"', geojson=False)
    holes = data.get("holes", [])
    if holes is None:
        holes = []
    if not isinstance(holes, list):
        fail(path, f'"holes" must be a list of rings, got {short(holes)}')
    if holes and isinstance(holes[0], list) and holes[0] and is_number(holes[0][0]):
        fail(
            path,
            '"holes" must be a list of rings, but it looks like a single ring '
            "(a list of [x, y]); wrap it as [[[x, y], ...]]",
        )
    rings = [json_ring(path, h, f'"holes"[{i}]', geojson=False) for i, h in enumerate(holes)]
    extra = sorted(set(data) - {"outer", "holes", "segments", "points", "regions"})
    if extra:
        logger.debug("%s: ignoring keys %s", path, extra)
    return outer, rings


def _json_constraints(path, data) -> dict:
    segs = data.get("segments") or []
    pts = data.get("points") or []
    regs = data.get("regions") or []
    for key, value in (("segments", segs), ("points", pts), ("regions", regs)):
        if not isinstance(value, list):
            fail(path, f'"{key}" must be a list, got {short(value)}')
    if segs and isinstance(segs[0], list) and segs[0] and is_number(segs[0][0]):
        fail(path, '"segments" must be a list of polylines, but it looks like a single one '
                    "(a list of [x, y]); wrap it as [[[x, y], ...]]")
    segments = [json_ring(path, s, f'"segments"[{i}]', geojson=False) for i, s in enumerate(segs)]
    points = json_ring(path, pts, '"points"', geojson=False)
    seeds = []
    for i, s in enumerate(regs):
        if not (isinstance(s, list) and len(s) == 3 and is_number(s[0]) and is_number(s[1])
                and label_ok(s[2])):
            fail(path, f'"regions"[{i}] must be [x, y, label] with a string or number label, '
                        f"got {short(s)}")
        seeds.append((s[0], s[1], s[2]))
    return {"segments": segments, "points": points, "regions": seeds}


def read_json(path) -> Polygon:
    """Read uniform2d's JSON polygon format with its constraint keys (or GeoJSON)."""
    data = load_json(path)
    if isinstance(data, dict) and "type" in data:
        logger.info("%s: has a 'type' member, reading it as GeoJSON", path)
        return polygon_from_geojson(path, data)
    outer, holes = _json_rings(path, data)
    return make_polygon(path, outer, holes, **_json_constraints(path, data))


def _write_rings(path, polygon: Polygon) -> None:
    """Write uniform2d's JSON polygon format, one vertex per line, exact floats."""
    outer = json_ring_text(polygon.outer, "  ")
    holes = ",\n".join("    " + json_ring_text(h, "    ") for h in polygon.holes)
    holes = f"[\n{holes}\n  ]" if polygon.holes else "[]"
    with open(path, "w", encoding="utf-8") as f:
        f.write(f'{{\n  "outer": {outer},\n  "holes": {holes}\n}}\n')


def write_json(path, polygon: Polygon) -> None:
    """Write uniform2d's JSON polygon format, with the constraint keys if any."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _write_rings(path, polygon)
    outer = json_ring_text(polygon.outer, "  ")
    holes = ",\n".join("    " + json_ring_text(h, "    ") for h in polygon.holes)
    holes = f"[\n{holes}\n  ]" if polygon.holes else "[]"
    segs = ",\n".join("    " + json_ring_text(s, "    ") for s in polygon.segments)
    pts = ",\n".join(f"    [{num(x)}, {num(y)}]" for x, y in polygon.points)
    regs = ",\n".join(f"    [{num(x)}, {num(y)}, {label_json(lab)}]"
                      for x, y, lab in polygon.region_seeds)
    parts = [f'  "outer": {outer}', f'  "holes": {holes}']
    for key, body in (("segments", segs), ("points", pts), ("regions", regs)):
        parts.append(f'  "{key}": ' + (f"[\n{body}\n  ]" if body else "[]"))
    with open(path, "w", encoding="utf-8") as f:
        f.write("{\n" + ",\n".join(parts) + "\n}\n")


#: This module's entry in :data:`uniform2d.io.registry.POLYGON_FORMATS`.
FORMAT = FileFormat(".json", DESCRIPTION, read_json, write_json)
