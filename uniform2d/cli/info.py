"""``uniform2d info``: what a polygon file contains, and the n for a target size."""

from __future__ import annotations

import math

import numpy as np

from ._common import positive_float, print_json
from ._sizing import add_size_options, field_from_args


def add_parser(subparsers):
    p = subparsers.add_parser(
        "info",
        help="summarise a polygon file (vertices, holes, area, corners, regions, n for a size)",
        description="Summarise a polygon file: vertices, holes, area, perimeter, l(V,V) "
        "(least vertex distance), bounding box, sharpest corner, the segments (with their "
        "lengths), fixed points and regions (area, label), the smallest sensible n, and the "
        "number of Steiner points n that 'mesh --size H' would use.",
    )
    p.add_argument("input", metavar="INPUT", help="polygon file")
    p.add_argument("--size", type=positive_float, metavar="H",
                   help="target edge length: print the n it asks for")
    add_size_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON document instead")
    return p


def smallest_sensible_n(polygon) -> int:
    """The points T+ puts on the rings and segments when they are spaced at most
    3 l(V, V) apart (l(V, V) the least distance between two vertices, constraint
    vertices included).  T+ spaces them at most 3 d_n apart and d_n <= l(V, V),
    so it places at least this many and needs n at least this large: a lower
    bound on :func:`uniform2d.tplus.smallest_feasible_n`, cheap to compute, with
    segments counted as ring edges are."""
    e = polygon.constraint_edges
    d = polygon.vertices[e[:, 1]] - polygon.vertices[e[:, 0]]
    spacing = 3.0 * polygon.min_vertex_distance()
    return max(1, int((np.ceil(np.hypot(d[:, 0], d[:, 1]) / spacing) - 1).sum()))


def units_note(polygon) -> str:
    """What the lengths above are measured in: the coordinates as given, degrees
    if they look like longitude/latitude."""
    xmin, ymin, xmax, ymax = polygon.bounds
    if -180 <= xmin and xmax <= 360 and -90 <= ymin and ymax <= 90:
        return ("the coordinates as given; these look like longitude/latitude, so lengths "
                "and areas are in degrees: project first for metres (docs/outlines.md)")
    return "the coordinates as given (no unit conversion)"


def _constraints(polygon) -> dict:
    segs = []
    for s in polygon.segments:
        length = float(np.hypot(*np.diff(s, axis=0).T).sum())
        segs.append({"vertices": int(len(s)), "length": length,
                     "closed": bool(len(s) > 3 and np.array_equal(s[0], s[-1]))})
    r = polygon.regions
    return {
        "segments": segs,
        "segment_length": float(sum(s["length"] for s in segs)),
        "points": [[float(x), float(y)] for x, y in polygon.points],
        "regions": [{"area": float(a), "label": lab} for a, lab in zip(r.areas, r.labels)],
    }


def describe(polygon, size=None) -> dict:
    """The facts ``info`` prints, as a dict."""
    from ..uniform import steiner_count_for_size

    angles = polygon.interior_angles()
    i = int(angles.argmin())
    xmin, ymin, xmax, ymax = polygon.bounds
    out = {
        "vertices": int(len(polygon.vertices)),
        "rings": [int(len(r)) for r in polygon.rings],
        "holes": int(polygon.n_holes),
        "area": polygon.area,
        "perimeter": polygon.perimeter,
        "l(V,V)": polygon.min_vertex_distance(),
        "bounds": [xmin, ymin, xmax, ymax],
        "width": xmax - xmin,
        "height": ymax - ymin,
        "sharpest_corner_deg": math.degrees(float(angles[i])),
        "sharpest_corner_vertex": i,
        "sharpest_corner_at": [float(v) for v in polygon.vertices[i]],
        "reflex_vertices": int((angles > math.pi).sum()),
        **_constraints(polygon),
        "smallest_sensible_n": smallest_sensible_n(polygon),
        "units": units_note(polygon),
    }
    if size is not None:
        out["size"] = size
        out["suggested_n"] = steiner_count_for_size(polygon, size)
    return out


def run(args) -> int:
    from ..io import read_polygon

    polygon = read_polygon(args.input)
    d = describe(polygon, args.size)
    field = field_from_args(polygon, args)
    if field is not None:
        from ..grading import count_for_field

        d["field_n"] = count_for_field(polygon, field)
    if args.json:
        print_json({"input": args.input, **d})
        return 0
    g = "{:.6g}".format
    xmin, ymin, xmax, ymax = d["bounds"]
    ring_sizes = " + ".join(str(k) for k in d["rings"])
    lines = [
        f"{args.input}",
        f"  vertices:        {d['vertices']} ({ring_sizes}: outer ring"
        + (" + holes)" if d["holes"] else ")"),
        f"  holes:           {d['holes']}",
        f"  area:            {g(d['area'])}",
        f"  perimeter:       {g(d['perimeter'])}",
        f"  l(V,V):          {g(d['l(V,V)'])}  (least distance between two vertices)",
        f"  bounding box:    x {g(xmin)} .. {g(xmax)}, y {g(ymin)} .. {g(ymax)} "
        f"({g(d['width'])} x {g(d['height'])})",
        f"  sharpest corner: {d['sharpest_corner_deg']:.4g} deg at vertex "
        f"{d['sharpest_corner_vertex']} ({g(d['sharpest_corner_at'][0])}, "
        f"{g(d['sharpest_corner_at'][1])})",
        f"  reflex vertices: {d['reflex_vertices']}",
        f"  lengths:         in {d['units']}",
        *_constraint_lines(d, g),
        f"  smallest sensible n: {d['smallest_sensible_n']}  (T+ puts at least this many "
        "points on the rings and segments)",
    ]
    if field is not None:
        lines.append(f"  size field -> n = {d['field_n']} Steiner points "
                     f"({d['vertices'] + d['field_n']} mesh vertices)")
    elif args.size is not None:
        lines.append(f"  size {g(args.size)} -> n = {d['suggested_n']} Steiner points "
                     f"({d['vertices'] + d['suggested_n']} mesh vertices)")
    print("\n".join(lines))
    return 0


def _constraint_lines(d: dict, g) -> list[str]:
    out = []
    if d["segments"]:
        out.append(f"  segments:        {len(d['segments'])}, total length {g(d['segment_length'])}")
        for k, s in enumerate(d["segments"]):
            kind = "closed" if s["closed"] else "open"
            out.append(f"    segment {k}: {s['vertices']} vertices, {kind}, length {g(s['length'])}")
    if d["points"]:
        out.append(f"  fixed points:    {len(d['points'])}")
    if len(d["regions"]) > 1 or any(r["label"] is not None for r in d["regions"]):
        out.append(f"  regions:         {len(d['regions'])}")
        for k, r in enumerate(d["regions"]):
            label = "" if r["label"] is None else f", label {r['label']!r}"
            out.append(f"    region {k}: area {g(r['area'])}{label}")
    return out
