"""DXF polygon files, ``.dxf`` (read and written with ezdxf: the ``dxf`` extra).

Read from modelspace:

- Closed curves are the outline (the one with the largest area) and its holes:
  closed ``LWPOLYLINE`` and 2-D/3-D ``POLYLINE`` entities, ``CIRCLE`` entities
  (bolt holes), and chains of two or more ``LINE``, ``ARC`` and open polyline
  entities meeting end to end two by two (a slot drawn as two lines and two
  arcs).  On a layer whose name starts with ``ZONE`` (any case) they are zones
  as in GeoJSON, labelled with their layer name; on a ``SEGMENT*`` layer,
  closed segments.
- Every other ``LINE``, ``ARC`` and open polyline is a segment, ``POINT``
  entities are fixed points, ``TEXT`` and ``MTEXT`` entities label the region
  around their insertion point with their text.
- Curves (circles, arcs, polyline bulges) become polylines whose pieces have a
  sagitta of at most ``chord_tol`` x their radius (default 0.01: 23 pieces a
  full circle); see :mod:`uniform2d.io.dxf_curves` for the rule.
- Other entities (ELLIPSE, SPLINE, INSERT, HATCH, ...) are ignored with one
  logged warning naming them.

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
from ..polygon import Polygon
from . import dxf_curves
from .common import fail, make_polygon, zone_seeds
from .fileformat import FileFormat

__all__ = ["read_dxf", "write_dxf", "FORMAT"]

logger = logging.getLogger(__name__)

#: What :func:`uniform2d.io.polygon_formats` says of this format.
DESCRIPTION = (
    "DXF closed LWPOLYLINE/POLYLINE, CIRCLE and LINE/ARC chains (largest is the outline), "
    "open ones as segments, POINTs, TEXT labels; arcs and bulges to a chord tolerance"
)


def _ezdxf():
    """The ezdxf module (the ``dxf`` extra), or the error saying how to install it."""
    try:
        import ezdxf
    except ModuleNotFoundError:
        raise UnsupportedFormatError(
            "reading and writing .dxf files needs ezdxf: pip install 'uniform2d[dxf]'") from None
    return ezdxf


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


def _dxf_polyline(e, tol: float):
    """(points (k, 2) in world coordinates, bulges as arcs; closed) of a 2-D/3-D
    polyline entity, None for any other."""
    kind = e.dxftype()
    if kind == "LWPOLYLINE":
        xy = dxf_curves.bulge_polyline(list(e.get_points("xyb")), bool(e.closed), tol)
        return dxf_curves.to_wcs(e, xy, float(e.dxf.elevation)), bool(e.closed)
    if kind == "POLYLINE" and e.is_2d_polyline:
        xyb = [(v.dxf.location.x, v.dxf.location.y, v.dxf.get("bulge", 0.0)) for v in e.vertices]
        xy = dxf_curves.bulge_polyline(xyb, bool(e.is_closed), tol)
        return dxf_curves.to_wcs(e, xy, float(e.dxf.elevation.z)), bool(e.is_closed)
    if kind == "POLYLINE" and e.is_3d_polyline:
        xy = np.array([tuple(v)[:2] for v in e.points_in_wcs()], dtype=np.float64).reshape(-1, 2)
        return xy, bool(e.is_closed)
    return None


def _dxf_entities(path, doc, tol: float):
    """Rings (with names), zones, segments, points and seeds of a modelspace."""
    rings, names, zones, segments, points, seeds, ignored = [], [], [], [], [], [], Counter()
    opened = []  # (piece, name, layer, exact ends, entity number) of LINE, ARC, open polylines

    def closed_curve(ring, name, layer, at):
        if layer.upper().startswith(("ZONE", "SEGMENT")):
            segments.append((at, np.vstack([ring, ring[:1]])))
            if layer.upper().startswith("ZONE") and len(ring) >= 3:
                zones.append((shapely.Polygon(ring), layer))
        else:
            rings.append(ring)
            names.append(name.replace(" (", f" #{len(rings)} (", 1))

    for at, e in enumerate(doc.modelspace()):
        kind, layer = e.dxftype(), str(e.dxf.get("layer", "0"))
        what = "polyline" if kind in ("LWPOLYLINE", "POLYLINE") else kind.lower()
        name = f"{what} (handle {e.dxf.handle}, layer {layer})"
        poly = _dxf_polyline(e, tol)
        if poly is not None:
            xy, closed = poly
            if not closed and len(xy) >= 4 and np.array_equal(xy[0], xy[-1]):
                logger.info("%s: %s ends where it starts; read as closed", path, name)
                xy, closed = xy[:-1], True
            if closed:
                closed_curve(xy, name, layer, at)
            else:
                opened.append((xy, name, layer, True, at))
        elif kind == "CIRCLE":
            closed_curve(dxf_curves.circle_ring(e, tol), name, layer, at)
        elif kind == "ARC":
            xy = dxf_curves.arc_polyline(e, tol)
            if np.array_equal(xy[0], xy[-1]):  # start angle = end angle: a whole circle
                closed_curve(xy[:-1], name, layer, at)
            else:
                opened.append((xy, name, layer, False, at))
        elif kind == "LINE":
            opened.append((np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)]),
                           name, layer, True, at))
        elif kind == "POINT":
            points.append(np.array([e.dxf.location.x, e.dxf.location.y]))
        elif _text(e) is not None:
            x, y = float(e.dxf.insert.x), float(e.dxf.insert.y)
            seeds.append((x, y, _text(e)))
        else:
            ignored[kind] += 1
    loops, rest = dxf_curves.chains([o[0] for o in opened], [o[3] for o in opened])
    for order, ring in loops:
        closed_curve(ring, "chain (of " + ", ".join(opened[i][1] for i in order) + ")",
                     opened[order[0]][2], opened[order[0]][4])
    segments += [(opened[i][4], piece) for i, piece in rest]
    segments = [piece for _, piece in sorted(segments, key=lambda s: s[0])]  # file order
    if ignored:
        logger.warning("%s: ignoring %s: uniform2d reads LWPOLYLINE, POLYLINE, CIRCLE, ARC, LINE, "
                       "POINT, TEXT and MTEXT entities (explode blocks and convert ellipses and "
                       "splines to polylines in CAD)",
                       path, ", ".join(f"{n} {k}" for k, n in sorted(ignored.items())))
    return rings, names, zones, segments, points, seeds


def _text(e) -> str | None:
    kind = e.dxftype()
    if kind == "TEXT":
        return e.dxf.text
    if kind == "MTEXT":
        return e.plain_text()
    return None


def _check_parts(path, rings, names, outer: int) -> None:
    """Every other ring must meet the outline's area: one polygon per file."""
    if len(rings[outer]) < 3:
        return
    shape = shapely.Polygon(rings[outer])
    for k, r in enumerate(rings):
        if k != outer and len(r) >= 3 and shape.disjoint(shapely.Polygon(r)):
            raise InvalidPolygonError(
                f"{path}: {names[k]} lies outside the outer ring ({names[outer]}, the "
                "largest); uniform2d meshes one polygon at a time: put each part in its own "
                "file"
            )


def read_dxf(path, *, chord_tol: float = dxf_curves.CHORD_TOL) -> Polygon:
    """Read a DXF modelspace: closed curves (polylines, circles, line and arc
    chains) as the outline and holes (on a ZONE* or SEGMENT* layer: closed
    segments), other LINE/ARC/open polylines as segments, POINT as fixed points,
    TEXT/MTEXT and ZONE* layers as labels.

    Parameters
    ----------
    path : path
    chord_tol : float
        Largest sagitta of the pieces of a curve, as a fraction of its radius
        (:data:`uniform2d.io.dxf_curves.CHORD_TOL`).
    """
    doc = _open_dxf(path)
    rings, names, zones, segments, points, seeds = _dxf_entities(path, doc, chord_tol)
    if not rings:
        found = Counter(e.dxftype() for e in doc.modelspace())
        fail(path, "no closed curve in modelspace (found "
                    + (", ".join(f"{n} {k}" for k, n in sorted(found.items())) or "nothing")
                    + "); draw the outline as a closed LWPOLYLINE or POLYLINE, a CIRCLE, or "
                    "LINEs and ARCs meeting end to end")
    outer = int(np.argmax([abs(shapely.Polygon(r).area) if len(r) >= 3 else 0.0 for r in rings]))
    holes = [r for k, r in enumerate(rings) if k != outer]
    labels = [names[outer]] + [n for k, n in enumerate(names) if k != outer]
    if not (segments or points or seeds):
        _check_parts(path, rings, names, outer)
        return make_polygon(path, rings[outer], holes, labels)
    pts = np.array(points, dtype=np.float64).reshape(-1, 2)
    seeds = zone_seeds(path, rings[outer], holes, segments, pts, zones, seeds)
    return make_polygon(path, rings[outer], holes, labels, segments=segments, points=pts,
                        regions=seeds)


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
