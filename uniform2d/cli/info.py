"""``uniform2d info``: what a polygon file contains, and the n for a target size."""

from __future__ import annotations

import math

from ._common import positive_float, print_json


def add_parser(subparsers):
    p = subparsers.add_parser(
        "info",
        help="summarise a polygon file (vertices, holes, area, corners, n for a size)",
        description="Summarise a polygon file: vertices, holes, area, perimeter, l(V,V) "
        "(least vertex distance), bounding box, sharpest corner, and the number of "
        "Steiner points n that 'mesh --size H' would use.",
    )
    p.add_argument("input", metavar="INPUT", help="polygon file")
    p.add_argument("--size", type=positive_float, metavar="H",
                   help="target edge length: print the n it asks for")
    p.add_argument("--json", action="store_true", help="print one JSON document instead")
    return p


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
    }
    if size is not None:
        out["size"] = size
        out["suggested_n"] = steiner_count_for_size(polygon, size)
    return out


def run(args) -> int:
    from ..io import read_polygon

    polygon = read_polygon(args.input)
    d = describe(polygon, args.size)
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
    ]
    if args.size is not None:
        lines.append(f"  size {g(args.size)} -> n = {d['suggested_n']} Steiner points "
                     f"({d['vertices'] + d['suggested_n']} mesh vertices)")
    print("\n".join(lines))
    return 0
