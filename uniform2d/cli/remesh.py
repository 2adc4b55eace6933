"""``uniform2d remesh``: remesh a disk-like surface patch with near-equal 3-D edges.

Wraps the ``remesh`` of the registered surface-patch layer (the ``surface``
extra: trimesh, libigl, pymeshlab; found through :mod:`uniform2d.plugins`).
Input: any triangle-mesh format the layer reads; output: one of its
``WRITE_FORMATS`` (.obj, .off, .ply, .stl, .glb).
"""

from __future__ import annotations

import logging
from pathlib import Path

from ._common import check_output_file, positive_float, positive_int, print_json

log = logging.getLogger(__name__)

PARAMS = ("lscm", "arap", "harmonic")


def add_parser(subparsers):
    p = subparsers.add_parser(
        "remesh",
        help="remesh a surface patch (needs the 'surface' extra)",
        description="Remesh a disk-like triangulated surface patch (possibly with holes) "
        "with exactly N vertices and near-equal 3-D edges: flatten it (libigl), mesh "
        "the flat domain with uniform2d, lift the mesh back.",
    )
    p.add_argument("input", metavar="INPUT", help="surface mesh file (.obj, .off, .ply, .stl, ...)")
    count = p.add_mutually_exclusive_group(required=True)
    count.add_argument("-n", type=positive_int, metavar="N",
                       help="number of vertices of the output")
    count.add_argument("--size", type=positive_float, metavar="H", help="target 3-D edge length")
    p.add_argument("-o", "--output", required=True, metavar="OUTPUT",
                   help="output mesh file (.obj, .off, .ply, .stl, .glb)")
    p.add_argument("--param", choices=PARAMS, default="lscm",
                   help="parameterisation tried first (default lscm)")
    p.add_argument("--plot", metavar="PNG", help="also write a figure of the 3-D mesh")
    show = p.add_mutually_exclusive_group()
    show.add_argument("--stats", action="store_true", help="print the remesh report")
    show.add_argument("--json", action="store_true", help="print the report as JSON")
    return p


def run(args) -> int:
    from ..plugins import patch_layer

    src, dst = Path(args.input), Path(args.output)
    layer = patch_layer()
    layer.check_output(dst)
    check_output_file(dst, "-o")
    if args.plot:
        from ..plot import check_figure_path

        check_figure_path(args.plot)
        check_output_file(Path(args.plot), "--plot")
    if not src.exists():
        raise FileNotFoundError(2, "input file not found", str(src))
    patch = layer.read_patch(src)
    log.info("%s: %r", src, patch)
    result = layer.remesh(patch, n_vertices=args.n, size=args.size, param=args.param)
    result.write(dst)
    if args.plot:
        layer.plot_result(result, args.plot)
    if args.json:
        print_json({"input": str(src), "output": str(dst), "report": result.report.as_dict()})
    elif args.stats:
        print(result.report.summary())
    elif not args.quiet:
        print(f"wrote {dst} ({len(result.vertices)} vertices, {len(result.faces)} faces)"
              + (f", figure {args.plot}" if args.plot else ""))
    return 0
