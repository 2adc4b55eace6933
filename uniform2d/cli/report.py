"""``uniform2d report``: compare uniform2d with peer meshers on polygons and patches.

Wraps :func:`uniform2d.report.make_report`; writes ``DIR/index.html``,
``DIR/report.md``, ``DIR/results.json`` and ``DIR/meshes/``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ._common import (
    add_parallel_options,
    angle_degrees,
    announce_compile,
    check_output_dir,
    check_parallel_options,
    positive_int,
)

DEFAULT_N = (200,)


def _peer_list(text: str) -> list[str]:
    return [p.strip() for p in text.split(",") if p.strip()]


def add_parser(subparsers):
    p = subparsers.add_parser(
        "report",
        help="compare with gmsh, Triangle, a CVT baseline and MeshLab (HTML/Markdown/JSON)",
        description="Mesh every INPUT with uniform2d (T+ and uniform_mesh; surface.remesh "
        "for .obj/.ply/.stl/.off patches) and with each peer tuned to the same vertex "
        "count, and write DIR/index.html (one self-contained page), DIR/report.md, "
        "DIR/results.json (every number) and DIR/meshes/. Peers that are not installed "
        "are listed as such. A polygon's segments, fixed points and regions go to our meshes "
        "and to every peer that takes them (gmsh, triangle, cvt); a peer that cannot is "
        "listed as not comparable.",
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="polygon files and/or surface patches (.obj, .ply, .stl, .off)")
    p.add_argument("-n", type=positive_int, action="append", metavar="N", dest="ns",
                   help="Steiner points for polygons, vertices for patches; repeat for "
                   f"several (default {DEFAULT_N[0]})")
    p.add_argument("--peers", type=_peer_list, metavar="LIST",
                   help="comma-separated peers (default: gmsh,triangle,cvt,meshlab; also cgal, pyacvd "
                   "where installed by hand)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    add_parallel_options(p, "cases")
    p.add_argument("--feature-angle", type=angle_degrees, metavar="DEG",
                   help="surface inputs: keep edges bent more than DEG degrees as feature lines "
                   "in our remesh (as `remesh --feature-angle`; e.g. 30 for a folded plate)")
    p.add_argument("--no-figures", action="store_true", help="leave the pictures out of index.html")
    return p


def run(args) -> int:
    from ..report import make_report

    check_parallel_options(args)
    check_output_dir(Path(args.output), "-o")
    if args.scheduler is None:
        announce_compile(args.quiet)
    results = make_report(
        args.inputs,
        args.output,
        ns=args.ns or DEFAULT_N,
        peers=args.peers,
        jobs=args.jobs,
        scheduler=args.scheduler,
        progress=not args.quiet and sys.stderr.isatty(),
        figures=not args.no_figures,
        feature_angle=args.feature_angle,
    )
    if not args.quiet:
        counts = {}
        for c in results["cases"]:
            counts[c["status"]] = counts.get(c["status"], 0) + 1
        summary = ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
        print(f"{args.output}/index.html: {len(results['cases'])} cases ({summary})")
    return 0
