"""``uniform2d mesh``: mesh polygon files with exactly n Steiner points.

Outputs
-------
* One input: ``-o FILE`` (the format follows the extension, any of
  ``uniform2d.io.mesh_formats()``); ``-o DIR`` (an existing directory) writes
  ``DIR/<input stem><--format>``.  Without ``-o`` the mesh is written next to the
  input as ``<input stem><--format>`` (default ``.vtu``), like ``gmsh -2``.
* Several inputs: ``-o DIR`` (created if missing) receives one
  ``<input stem><--format>`` per input; without ``-o`` each goes next to its
  input.  ``--plot`` is then a directory too (``<stem>.png`` each).

Nothing is written for an input until its mesh exists, and every file is written
atomically.  With several inputs the command stops at the first bad one (files
already written for earlier inputs are complete and kept).
"""

from __future__ import annotations

import logging
import sys
from pathlib import Path

from ._common import positive_float, positive_int, print_json, progress

log = logging.getLogger(__name__)

METHODS = ("uniform", "paper")


def add_parser(subparsers):
    from ..io import mesh_formats

    p = subparsers.add_parser(
        "mesh",
        help="mesh polygon files (exactly n Steiner points, near-equal edges)",
        description="Mesh one or more polygon files with exactly n Steiner points "
        "(boundary and interior) and edges as equal in length as possible.",
        epilog="mesh formats: " + ", ".join(mesh_formats()),
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="polygon file(s): .json, .geojson, .wkt, .poly, .dxf")
    count = p.add_mutually_exclusive_group(required=True)
    count.add_argument("-n", type=positive_int, metavar="N",
                       help="number of Steiner points (boundary and interior)")
    count.add_argument("--size", type=positive_float, metavar="H",
                       help="target edge length; n is derived from the area and perimeter")
    p.add_argument("--method", choices=METHODS, default="uniform",
                   help="'uniform': uniform2d.uniform_mesh (recommended, default); "
                   "'paper': the paper's T+ (uniform2d.tplus)")
    p.add_argument("-o", "--output", metavar="OUTPUT",
                   help="output mesh file (one input) or directory; default: next to the input")
    p.add_argument("--format", default=".vtu", metavar="EXT",
                   help="extension of outputs named after their input (default .vtu)")
    p.add_argument("--plot", metavar="PNG",
                   help="also write a figure of the mesh (.png, .pdf, .svg); "
                   "a directory when there are several inputs")
    show = p.add_mutually_exclusive_group()
    show.add_argument("--stats", action="store_true",
                      help="print the quality summary and optimality certificates")
    show.add_argument("--json", action="store_true",
                      help="print one JSON document (quality, info) to stdout")
    return p


def _stem(path: Path) -> str:
    from ..io.registry import POLYGON_FORMATS, match_format

    fmt = match_format(path, POLYGON_FORMATS)
    name = path.name
    return name[: -len(fmt.extension)] if fmt is not None else path.stem


def _plan(args) -> list[tuple[Path, Path, Path | None]]:
    """(input, output, plot) per input, every check that needs no meshing done."""
    from ..errors import UnsupportedFormatError
    from ..io.registry import MESH_FORMATS, match_format, find_mesh_format
    from ..plot import FIGURE_FORMATS as PLOT_FORMATS

    inputs = [Path(s) for s in args.inputs]
    for src in inputs:  # all inputs before any output
        if not src.exists():
            raise FileNotFoundError(2, "input file not found", str(src))
    ext = args.format if args.format.startswith(".") else "." + args.format
    ext = find_mesh_format("output" + ext.lower(), "write").extension
    several = len(inputs) > 1

    out = Path(args.output) if args.output else None
    if several and out is not None and (out.is_file() or (not out.exists() and match_format(out, MESH_FORMATS))):
        raise ValueError(f"with several inputs, -o must be a directory, got '{out}'")

    plot = Path(args.plot) if args.plot else None
    if plot is not None and not several:
        if plot.suffix.lower() not in PLOT_FORMATS:
            raise UnsupportedFormatError(
                f"cannot save a figure as '{plot}'; use one of {', '.join(PLOT_FORMATS)}"
            )
        if plot.is_dir():
            raise ValueError(f"--plot '{plot}' is a directory; give a file name such as mesh.png")
        if not plot.parent.is_dir():
            raise FileNotFoundError(
                f"cannot save the figure '{plot}': directory '{plot.parent}' does not exist"
            )
    if plot is not None and several and plot.exists() and not plot.is_dir():
        raise ValueError(f"with several inputs, --plot must be a directory, got the file '{plot}'")

    plan = []
    for src in inputs:
        stem = _stem(src)
        if out is None:
            dst = src.parent / (stem + ext)
        elif several or out.is_dir():
            dst = out / (stem + ext)
        else:
            dst = out
            find_mesh_format(dst, "write")
        fig = None
        if plot is not None:
            fig = plot / (stem + ".png") if several else plot
        plan.append((src, dst, fig))
    targets = [d.resolve() for _, d, _ in plan]
    if len(set(targets)) != len(targets):
        raise ValueError("two inputs have the same name: their outputs would overwrite each other")
    return plan


def _mesh_one(polygon, args):
    from ..tplus import tplus
    from ..uniform import steiner_count_for_size, uniform_mesh
    from ..errors import InsufficientPointsError

    if args.method == "uniform":
        return uniform_mesh(polygon, n=args.n, size=args.size)
    n = args.n
    if n is None:
        n = steiner_count_for_size(polygon, args.size)
        if n < 1:
            raise InsufficientPointsError(
                f"size {args.size!r} is larger than the polygon needs: it asks for no "
                "Steiner points; use a smaller size"
            )
    return tplus(polygon, n)


def _write_both(mesh, dst: Path, fig: Path | None) -> None:
    """The mesh file and its figure, both or neither: the figure is drawn to a
    temporary file next to ``fig`` first and moved into place after the mesh is
    written (each write is atomic on its own)."""
    import os
    import secrets

    if fig is None:
        mesh.write(dst)
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tmp = fig.with_name(f".{fig.stem}.tmp-{secrets.token_hex(4)}{fig.suffix}")
    existed = dst.exists()
    try:
        plt.close(mesh.plot(tmp))
        mesh.write(dst)
        try:
            os.replace(tmp, fig)
        except OSError:
            if not existed:
                dst.unlink(missing_ok=True)
            raise
    finally:
        tmp.unlink(missing_ok=True)


def run(args) -> int:
    from ..io import read_polygon

    plan = _plan(args)
    several = len(plan) > 1
    documents = []
    for src, dst, fig in progress(plan, total=len(plan), quiet=args.quiet, desc="meshing"):
        try:
            polygon = read_polygon(src)
            log.info("%s: %r", src, polygon)
            mesh = _mesh_one(polygon, args)
            log.info("%s: %r", src, mesh)
            quality = mesh.quality() if (args.stats or args.json) else None
            if several:
                dst.parent.mkdir(parents=True, exist_ok=True)
                if fig is not None:
                    fig.parent.mkdir(parents=True, exist_ok=True)
            _write_both(mesh, dst, fig)
        except (ValueError, OSError) as exc:
            if several and str(src) not in str(exc):
                exc.args = (f"{src}: {exc}",) if not isinstance(exc, OSError) else exc.args
            raise
        if args.json:
            documents.append({
                "input": str(src),
                "output": str(dst),
                "plot": str(fig) if fig is not None else None,
                "method": args.method,
                "n_steiner": mesh.n_steiner,
                "n_points": len(mesh.points),
                "n_triangles": len(mesh.triangles),
                "info": mesh.info,
                "quality": quality.to_dict(),
            })
        elif args.stats:
            if several:
                print(f"== {src} -> {dst}")
            print(quality.summary())
            if mesh.info.get("method") == "paper" and "d_n" in mesh.info:
                _print_tplus(mesh.info)
        if not args.quiet and not args.json and not args.stats:
            print(f"wrote {dst} ({len(mesh.points)} points, {len(mesh.triangles)} triangles, "
                  f"n = {mesh.n_steiner})" + (f", figure {fig}" if fig is not None else ""))
        sys.stdout.flush()
    if args.json:
        print_json(documents[0] if not several else documents)
    return 0


def _print_tplus(info) -> None:
    g = "{:.6g}".format
    print()
    print(f"T+ (Theorem 2): d_n = {g(info['d_n'])}, k = {info['k']} boundary points, "
          f"gaps {info['gap_min']:.3f}..{info['gap_max']:.3f} d_n")
    for name, ok in info["hypotheses"].items():
        print(f"  {'holds ' if ok else 'FAILS '} {name}")
    if info["theorem_applies"]:
        print(f"  theorem applies: edge ratio <= {g(info['edge_ratio_bound'])}")
    else:
        print("  theorem does not apply (no a-priori edge-ratio bound for this n)")
