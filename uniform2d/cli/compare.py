"""``uniform2d compare``: two mesh files side by side on the report's measures."""

from __future__ import annotations

from ._common import print_json


def add_parser(subparsers):
    p = subparsers.add_parser(
        "compare",
        help="compare two mesh files (edge ratio, longest edge, certified factors, ...)",
        description="Measure two existing planar mesh files on the comparison report's "
        "measures; with --polygon, also the certified factors against that polygon.",
    )
    p.add_argument("mesh_a", metavar="MESH_A", help="mesh file (any format of 'uniform2d mesh')")
    p.add_argument("mesh_b", metavar="MESH_B", help="mesh file")
    p.add_argument("--polygon", metavar="POLY", help="polygon file both meshes triangulate")
    p.add_argument("--json", action="store_true", help="print one JSON document instead")
    return p


def run(args) -> int:
    from ..report import compare_meshes, format_comparison

    result = compare_meshes(args.mesh_a, args.mesh_b, polygon=args.polygon)
    if args.json:
        print_json(result)
    else:
        print(format_comparison(result))
    return 0
