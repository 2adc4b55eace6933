"""DXF polygon files, ``.dxf`` (read and written with ezdxf: the ``dxf`` extra).

Closed ``LWPOLYLINE`` and 2-D/3-D ``POLYLINE`` entities in modelspace are the
outline (the one with the largest area) and its holes, except those on a layer
whose name starts with ``ZONE`` (any case), which are zones as in GeoJSON,
labelled with their layer name, and those on a ``SEGMENT*`` layer, which are
closed segments.  Open ``LINE``, ``LWPOLYLINE`` and ``POLYLINE`` entities are
segments, ``POINT`` entities fixed points, ``TEXT`` and ``MTEXT`` entities label
the region around their insertion point with their text.  Arc segments
(bulges) are replaced by their chords, with a logged warning.

Written on layers ``OUTER`` and ``HOLES`` (and ``SEGMENTS``, ``POINTS`` and
``REGIONS`` for a polygon with constraints), with ezdxf's fixed metadata: the
same polygon gives the same bytes.
"""

from __future__ import annotations

import logging
from collections import Counter

import numpy as np
import shapely

from ..errors import InvalidPolygonError, UnsupportedFormatError
from ..geometry import signed_area
from ..polygon import Polygon
from .common import fail, make_polygon, zone_seeds
from .fileformat import FileFormat

__all__ = ["read_dxf", "write_dxf", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    "DXF closed LWPOLYLINE/POLYLINE entities (largest is the outline), open ones and LINEs "
    "as segments, POINTs, TEXT labels"
)


def _ezdxf():
    """The ezdxf module (the ``dxf`` extra), or the error saying how to install it."""
    try:
        import ezdxf
    except ModuleNotFoundError:
        raise UnsupportedFormatError(
            "reading and writing .dxf files needs ezdxf: pip install 'uniform2d[dxf]'") from None
    return ezdxf


# -- rings: the outline and its holes ------------------------------------------------
_GEOMETRY_ENTITIES = {"LINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE", "INSERT", "HATCH"}


def _open_dxf(path):
    """The ezdxf document of the file; a file ezdxf cannot read is an InvalidPolygonError."""
    ezdxf = _ezdxf()
    try:
        return ezdxf.readfile(path)
    except ezdxf.DXFError as exc:
        fail(path, f"not a readable DXF file ({exc})")
    except (FileNotFoundError, PermissionError, IsADirectoryError):
        raise
    except (OSError, UnicodeDecodeError) as exc:
        fail(path, f"not a readable DXF file ({exc})")
    except (StopIteration, EOFError, IndexError, ValueError) as exc:  # truncated files
        fail(path, f"not a readable DXF file (truncated or malformed: {type(exc).__name__})")


def _dxf_polyline(e):
    """(points, closed, has bulges) of a 2-D/3-D polyline entity, None for any other."""
    kind = e.dxftype()
    if kind == "LWPOLYLINE":
        pts = [tuple(v) for v in e.vertices_in_wcs()]
        return pts, bool(e.closed), any(b != 0 for (b,) in e.get_points("b"))
    if kind == "POLYLINE" and (e.is_2d_polyline or e.is_3d_polyline):
        pts = [tuple(v) for v in e.points_in_wcs()]
        return pts, bool(e.is_closed), any(v.dxf.get("bulge", 0) != 0 for v in e.vertices)
    return None


def _dxf_ring(path, name: str, pts, closed: bool, bulged: bool) -> np.ndarray:
    """One polyline's ring (x, y); an open one is an error unless it ends where it starts."""
    xy = np.asarray(pts, dtype=np.float64).reshape(-1, 3)[:, :2]
    if not closed:
        if len(xy) >= 4 and np.array_equal(xy[0], xy[-1]):
            logger.info("%s: %s ends where it starts; read as closed", path, name)
        else:
            fail(
                path,
                f"{name} is open; close it (set its 'closed' flag in CAD) or delete it: "
                "every polyline must be the outline or a hole",
            )
    if bulged:
        logger.warning(
            "%s: %s has arc segments (bulges); they are read as straight chords. "
            "Approximate arcs by short segments in CAD if the curvature matters",
            path,
            name,
        )
    return xy


def _dxf_rings(path, doc):
    """The rings of the modelspace's polylines and their labels, in file order."""
    rings, labels, ignored = [], [], Counter()
    for e in doc.modelspace():
        poly = _dxf_polyline(e)
        if poly is None:
            ignored[e.dxftype()] += 1
            continue
        name = f"polyline #{len(rings) + 1} (handle {e.dxf.handle}, layer {e.dxf.get('layer', '0')})"
        rings.append(_dxf_ring(path, name, *poly))
        labels.append(name)
    geometric = {k: n for k, n in ignored.items() if k in _GEOMETRY_ENTITIES}
    if geometric:
        logger.warning(
            "%s: ignoring %s; uniform2d reads only closed LWPOLYLINE/POLYLINE entities "
            "(convert circles, arcs and lines to closed polylines)",
            path,
            ", ".join(f"{n} {k}" for k, n in sorted(geometric.items())),
        )
    if not rings:
        found = ", ".join(f"{n} {k}" for k, n in sorted(ignored.items())) or "nothing"
        fail(
            path,
            f"no closed polylines in modelspace (found {found}); draw the outline and the "
            "holes as closed LWPOLYLINE or POLYLINE entities",
        )
    return rings, labels


def _read_rings(path) -> Polygon:
    """Read closed polylines from a DXF modelspace: the largest is outer, the rest holes."""
    rings, labels = _dxf_rings(path, _open_dxf(path))
    outer_i = int(np.argmax([abs(signed_area(r)) for r in rings]))
    order = [outer_i] + [i for i in range(len(rings)) if i != outer_i]
    outer_shape = shapely.Polygon(rings[outer_i]) if len(rings[outer_i]) >= 3 else None
    for i in order[1:]:
        if outer_shape is not None and len(rings[i]) >= 3 and outer_shape.disjoint(
            shapely.Polygon(rings[i])
        ):
            raise InvalidPolygonError(
                f"{path}: {labels[i]} lies outside the outer ring ({labels[outer_i]}, the "
                "largest); uniform2d meshes one polygon at a time: put each part in its own "
                "file"
            )
    return make_polygon(
        path, rings[outer_i], [rings[i] for i in order[1:]], [labels[i] for i in order]
    )


# -- segments, points, zones and labels ---------------------------------------------
def _text(e) -> str | None:
    kind = e.dxftype()
    if kind == "TEXT":
        return e.dxf.text
    if kind == "MTEXT":
        return e.plain_text()
    return None


def _dxf_entities(path, doc):
    """Rings (with names), zones, segments, points and seeds of a modelspace."""
    rings, names, zones, segments, points, seeds, ignored = [], [], [], [], [], [], Counter()
    for e in doc.modelspace():
        kind, layer = e.dxftype(), str(e.dxf.get("layer", "0"))
        poly = _dxf_polyline(e)
        if poly is not None:
            pts, closed, bulged = poly
            xy = np.asarray(pts, dtype=np.float64).reshape(-1, 3)[:, :2]
            ends_at_start = len(xy) >= 4 and np.array_equal(xy[0], xy[-1])
            name = f"polyline (handle {e.dxf.handle}, layer {layer})"
            if bulged:
                logger.warning("%s: %s has arc segments (bulges); they are read as straight "
                               "chords", path, name)
            kind_of = layer.upper()
            if (closed or ends_at_start) and kind_of.startswith(("ZONE", "SEGMENT")):
                ring = xy[:-1] if ends_at_start else xy
                segments.append(np.vstack([ring, ring[:1]]))
                if kind_of.startswith("ZONE") and len(ring) >= 3:
                    zones.append((shapely.Polygon(ring), layer))
            elif closed or ends_at_start:
                rings.append(_dxf_ring(path, name, pts, closed, False))
                names.append(name)
            else:
                segments.append(xy)
        elif kind == "LINE":
            segments.append(np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)]))
        elif kind == "POINT":
            points.append(np.array([e.dxf.location.x, e.dxf.location.y]))
        elif _text(e) is not None:
            x, y = float(e.dxf.insert.x), float(e.dxf.insert.y)
            seeds.append((x, y, _text(e)))
        else:
            ignored[kind] += 1
    if ignored:
        logger.warning("%s: ignoring %s", path, ", ".join(f"{n} {k}" for k, n in sorted(ignored.items())))
    return rings, names, zones, segments, points, seeds


def read_dxf(path) -> Polygon:
    """Read a DXF modelspace: closed polylines as the outline and holes (on a
    ZONE* or SEGMENT* layer: closed segments), open LINE/LWPOLYLINE/POLYLINE as
    segments, POINT as fixed points, TEXT/MTEXT and ZONE* layers as labels."""
    doc = _open_dxf(path)
    rings, names, zones, segments, points, seeds = _dxf_entities(path, doc)
    if not (segments or points or seeds):
        return _read_rings(path)
    if not rings:
        found = Counter(e.dxftype() for e in doc.modelspace())
        fail(path, "no closed polylines in modelspace (found "
                    + ", ".join(f"{n} {k}" for k, n in sorted(found.items()))
                    + "); draw the outline as a closed LWPOLYLINE or POLYLINE")
    outer = int(np.argmax([abs(shapely.Polygon(r).area) if len(r) >= 3 else 0.0 for r in rings]))
    holes = [r for k, r in enumerate(rings) if k != outer]
    pts = np.array(points, dtype=np.float64).reshape(-1, 2)
    seeds = zone_seeds(path, rings[outer], holes, segments, pts, zones, seeds)
    return make_polygon(path, rings[outer], holes,
                             [names[outer]] + [n for k, n in enumerate(names) if k != outer],
                             segments=segments, points=pts, regions=seeds)


def _write_rings(path, polygon: Polygon) -> None:
    """Write the rings as closed LWPOLYLINEs (layer OUTER, then layer HOLES)."""
    ezdxf = _ezdxf()

    # ezdxf stamps the time and random GUIDs into every file unless told to write
    # its fixed ones (when the document is made and when it is saved): same
    # polygon, same bytes
    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2010")
        doc.layers.add("OUTER", color=7)
        doc.layers.add("HOLES", color=1)
        msp = doc.modelspace()
        for k, ring in enumerate(polygon.rings):
            msp.add_lwpolyline(
                [(float(x), float(y)) for x, y in ring],
                close=True,
                dxfattribs={"layer": "OUTER" if k == 0 else "HOLES"},
            )
        doc.saveas(path)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed


def write_dxf(path, polygon: Polygon) -> None:
    """Write the rings (layers OUTER, HOLES), segments as LWPOLYLINEs (SEGMENTS,
    closed ones closed), fixed points as POINTs (POINTS) and labels as TEXT
    (REGIONS); labels read back as text."""
    if not (polygon.has_constraints or polygon.region_seeds):
        return _write_rings(path, polygon)
    ezdxf = _ezdxf()
    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2010")
        for name, colour in (("OUTER", 7), ("HOLES", 1), ("SEGMENTS", 3), ("POINTS", 5),
                             ("REGIONS", 4)):
            doc.layers.add(name, color=colour)
        msp = doc.modelspace()
        for k, ring in enumerate(polygon.rings):
            msp.add_lwpolyline([(float(x), float(y)) for x, y in ring], close=True,
                               dxfattribs={"layer": "OUTER" if k == 0 else "HOLES"})
        for s in polygon.segments:
            closed = len(s) > 3 and np.array_equal(s[0], s[-1])
            pts = s[:-1] if closed else s
            msp.add_lwpolyline([(float(x), float(y)) for x, y in pts], close=closed,
                               dxfattribs={"layer": "SEGMENTS"})
        for x, y in polygon.points:
            msp.add_point((float(x), float(y)), dxfattribs={"layer": "POINTS"})
        for x, y, label in polygon.region_seeds:
            msp.add_text(str(label), dxfattribs={"layer": "REGIONS", "insert": (x, y)})
        doc.saveas(path)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed


#: This module's entry in :data:`uniform2d.io.registry.POLYGON_FORMATS`.
FORMAT = FileFormat(".dxf", DESCRIPTION, read_dxf, write_dxf)
