"""``uniform2d mesh``: mesh polygon files with exactly n Steiner points.

Outputs
-------
* One input: ``-o FILE`` (the format follows the extension, any of
  ``uniform2d.io.mesh_formats()``); ``-o DIR`` (an existing directory, or any
  name ending in ``/``, created if missing) writes ``DIR/<input stem><--format>``.
  Without ``-o`` the mesh is written next to the input as
  ``<input stem><--format>`` (default ``.vtu``), like ``gmsh -2``.  ``--plot``
  names a figure file, or a directory when it ends in ``/``.
* Several inputs: ``-o DIR`` (created if missing) receives one
  ``<input stem><--format>`` per input; without ``-o`` each goes next to its
  input.  ``--plot`` must then name a directory too (an existing one, or a name
  ending in ``/``) and receives ``<stem>.png`` each.

Every output path is checked before any meshing.  Nothing is written for an
input until its mesh exists, and every file is written atomically.  With several
inputs a bad one does not stop the others: each failure is one
``uniform2d: error: <input>: ...`` line, and after the last input a summary line
and exit code 2.  ``--json`` then lists ``{"input": ..., "error": ...}`` for it.
"""

from __future__ import annotations

import logging
import os
import sys
from pathlib import Path

from ._common import (
    PhaseBar,
    add_parallel_options,
    check_output_dir,
    check_output_file,
    check_parallel_options,
    names_directory,
    positive_float,
    positive_int,
    run_batch,
    shows_progress,
)

log = logging.getLogger(__name__)

METHODS = ("uniform", "paper")

#: ParaView's partitioned VTU: written piece by piece with --parts.
PVTU = ".pvtu"


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
                   help="output mesh file (one input) or directory (existing, or ending in '/': "
                   "created); default: next to the input")
    p.add_argument("--format", default=".vtu", metavar="EXT",
                   help="extension of outputs named after their input (default .vtu)")
    p.add_argument("--plot", metavar="PNG",
                   help="also write a figure of the mesh (.png, .pdf, .svg); a name ending in '/' "
                   "is a directory receiving <input name>.png (with several inputs --plot must be "
                   "a directory)")
    p.add_argument("--parts", type=positive_int, metavar="K",
                   help="mesh each input in K parts of near-equal area on the --jobs processes or "
                   "the --scheduler cluster, and stitch them (docs/partitioned.md); with "
                   "-o NAME.pvtu every part is written as its own piece, never gathered")
    add_parallel_options(p, "the inputs (with --parts: the parts)")
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


def _format_extension(text: str, parts=None) -> str:
    from ..errors import UnsupportedFormatError
    from ..io.registry import MESH_FORMATS

    ext = (text if text.startswith(".") else "." + text).lower()
    if ext == PVTU and parts:
        return ext
    if ext not in MESH_FORMATS:
        raise UnsupportedFormatError(
            f"unknown --format '{text}'; use one of {', '.join(MESH_FORMATS)}"
        )
    return ext


def _plot_target(text: str | None, several: bool) -> tuple[Path | None, bool]:
    """The --plot path and whether it names a directory, checked before any meshing."""
    from ..plot import check_figure_path

    if text is None:
        return None, False
    plot = Path(text)
    if names_directory(text) and (several or text.endswith(("/", os.sep))):
        check_output_dir(plot, "--plot")
        return plot, True
    if several:
        raise ValueError(
            f"with several inputs, --plot must be a directory (an existing one, or a name "
            f"ending in '/'), got '{text}'"
        )
    if plot.is_dir():
        raise ValueError(f"--plot '{plot}' is a directory; give a file name such as mesh.png "
                         f"(or '{plot}/' for <input name>.png inside it)")
    check_figure_path(plot)
    check_output_file(plot, "--plot")
    return plot, False


def _output_target(text: str | None, several: bool, parts=None) -> tuple[Path | None, bool]:
    """The -o path and whether it names a directory, checked before any meshing."""
    from ..io.registry import MESH_FORMATS, find_mesh_format, match_format

    if text is None:
        return None, False
    out = Path(text)
    if several and (out.is_file() or (not names_directory(text) and match_format(out, MESH_FORMATS))):
        raise ValueError(f"with several inputs, -o must be a directory, got '{out}'")
    if several or names_directory(text):
        check_output_dir(out, "-o")
        return out, True
    if out.suffix.lower() == PVTU:
        if not parts:
            raise ValueError(f"'{out}': a .pvtu is written piece by piece from a mesh made in "
                             "parts; add --parts K (or write another format)")
        check_output_file(out, "-o")
        return out, False
    find_mesh_format(out, "write")
    check_output_file(out, "-o")
    return out, False


def _plan(args) -> list[tuple[Path, Path, Path | None]]:
    """(input, output, plot) per input, every check that needs no meshing done."""
    inputs = [Path(s) for s in args.inputs]
    for src in inputs:  # all inputs before any output
        if not src.exists():
            raise FileNotFoundError(2, "input file not found", str(src))
    ext = _format_extension(args.format, args.parts)
    several = len(inputs) > 1
    out, out_is_dir = _output_target(args.output, several, args.parts)
    plot, plot_is_dir = _plot_target(args.plot, several)

    plan = []
    for src in inputs:
        stem = _stem(src)
        if out is None:
            dst = src.parent / (stem + ext)
        else:
            dst = out / (stem + ext) if out_is_dir else out
        fig = None
        if plot is not None:
            fig = plot / (stem + ".png") if plot_is_dir else plot
        if dst.suffix.lower() == PVTU and fig is not None:
            raise ValueError("--plot needs the whole mesh, which a .pvtu output never gathers; "
                             "drop --plot or write another format")
        plan.append((src, dst, fig))
    targets = [d.resolve() for _, d, _ in plan]
    if len(set(targets)) != len(targets):
        raise ValueError("two inputs have the same name: their outputs would overwrite each other")
    return plan


def _count(polygon, args) -> int:
    """n from -n or --size, checked against this machine's memory."""
    from ..errors import InsufficientPointsError
    from ..resources import check_point_count
    from ..uniform import steiner_count_for_size

    n, what = args.n, f"n = {args.n}"
    if n is None:
        n = steiner_count_for_size(polygon, args.size)
        what = f"size {args.size!r} (n = {n})"
        if n < 1:
            raise InsufficientPointsError(
                f"size {args.size!r} is larger than the polygon needs: it asks for no "
                "Steiner points; use a smaller size"
            )
    check_point_count(n + len(polygon.vertices), what)
    return n


def _mesh_one(polygon, args, progress=None):
    from ..tplus import tplus
    from ..uniform import uniform_mesh

    if args.method == "uniform":
        return uniform_mesh(polygon, n=args.n, size=args.size, progress=progress)
    return tplus(polygon, _count(polygon, args))


def _parts_bar(args, name: str):
    from tqdm import tqdm

    return tqdm(total=args.parts, desc=name, unit="part", file=sys.stderr, leave=False,
                disable=not shows_progress(args.quiet))


def _process_parts(args, job) -> dict:
    """One input in ``--parts`` parts: a .pvtu written piece by piece, or the
    stitched mesh in any other format."""
    from ..io import read_polygon
    from ..partitioned import partitioned_mesh, write_pvtu

    src, dst, fig = job
    polygon = read_polygon(src)
    n = _count(polygon, args)
    dst.parent.mkdir(parents=True, exist_ok=True)
    with _parts_bar(args, src.name) as bar:
        if dst.suffix.lower() == PVTU:
            info = write_pvtu(polygon, n, args.parts, dst, jobs=args.part_jobs,
                              scheduler=args.part_scheduler, bar=bar)
            return {"input": str(src), "output": str(dst), "plot": None, "method": "partitioned",
                    "n_steiner": n, "n_points": info["points"], "n_triangles": info["triangles"],
                    "info": info, "quality": None, "summary": "(a .pvtu is never gathered: "
                    "no quality summary)", "regions": None}
        mesh = partitioned_mesh(polygon, n, args.parts, jobs=args.part_jobs,
                                scheduler=args.part_scheduler, bar=bar)
    return _written(args, src, dst, fig, polygon, mesh)


def _write_both(mesh, dst: Path, fig: Path | None) -> None:
    """The mesh file and its figure, both or neither: the figure is drawn to a
    temporary file next to ``fig`` first and moved into place after the mesh is
    written (each write is atomic on its own).  Errors name ``fig``, never the
    temporary file."""
    import os
    import secrets

    from ..io.atomic import named_for

    if fig is None:
        mesh.write(dst)
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tmp = fig.with_name(f".{fig.stem}.tmp-{secrets.token_hex(4)}{fig.suffix}")
    existed = dst.exists()
    try:
        try:
            plt.close(mesh.plot(tmp))
        except OSError as exc:
            raise named_for(exc, tmp, fig) from None
        mesh.write(dst)
        try:
            os.replace(tmp, fig)
        except OSError as exc:
            if not existed:
                dst.unlink(missing_ok=True)
            raise named_for(exc, tmp, fig) from None
    finally:
        tmp.unlink(missing_ok=True)


def _process(args, job: tuple[Path, Path, Path | None]) -> dict:
    """Mesh one input and write its files; returns what to show (no printing here)."""
    from ..io import read_polygon
    from ..optimize.pipeline import PHASES

    src, dst, fig = job
    polygon = read_polygon(src)
    log.info("%s: %r", src, polygon)
    bar = PhaseBar(PHASES, src.name) if getattr(args, "phase_bar", False) else None
    try:
        mesh = _mesh_one(polygon, args, bar)
    finally:
        if bar is not None:
            bar.close()
    return _written(args, src, dst, fig, polygon, mesh)


def _written(args, src: Path, dst: Path, fig, polygon, mesh) -> dict:
    """Write the mesh (and its figure); what to show of it."""
    log.info("%s: %r", src, mesh)
    quality = mesh.quality() if (args.stats or args.json) else None
    dst.parent.mkdir(parents=True, exist_ok=True)  # checked by _plan: only a named directory
    if fig is not None:
        fig.parent.mkdir(parents=True, exist_ok=True)
    _write_both(mesh, dst, fig)
    return {
        "input": str(src),
        "output": str(dst),
        "plot": str(fig) if fig is not None else None,
        "method": args.method,
        "n_steiner": mesh.n_steiner,
        "n_points": len(mesh.points),
        "n_triangles": len(mesh.triangles),
        "info": mesh.info,
        "quality": quality.to_dict() if quality is not None else None,
        "summary": quality.summary() if quality is not None else None,
        "regions": _regions(mesh) if polygon.has_constraints or polygon.region_seeds else None,
    }


def _regions(mesh) -> list[dict]:
    """Triangles and area of the mesh in each region, with its label."""
    import numpy as np

    p = mesh.points[mesh.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    labels = mesh.region_labels
    count = np.bincount(mesh.regions, minlength=len(labels))
    sums = np.bincount(mesh.regions, weights=area, minlength=len(labels))
    return [{"triangles": int(c), "area": float(a), "label": lab}
            for c, a, lab in zip(count, sums, labels)]


def _show(args, doc: dict, several: bool) -> None:
    if args.stats:
        if several:
            print(f"== {doc['input']} -> {doc['output']}")
        print(doc["summary"])
        for k, r in enumerate(doc["regions"] or []):
            label = "" if r["label"] is None else f" ({r['label']})"
            print(f"  region {k}{label}: {r['triangles']} triangles, area {r['area']:.6g}")
        if doc["info"].get("method") == "paper" and "d_n" in doc["info"]:
            _print_tplus(doc["info"])
    elif not args.quiet and not args.json:
        print(f"wrote {doc['output']} ({doc['n_points']} points, {doc['n_triangles']} triangles, "
              f"n = {doc['n_steiner']})" + (f", figure {doc['plot']}" if doc["plot"] else ""))
    sys.stdout.flush()


def run(args) -> int:
    check_parallel_options(args)
    plan = _plan(args)
    if args.parts:
        if args.method != "uniform":
            raise ValueError("--parts makes the uniform mesh in parts; it cannot be used with "
                             "--method paper")
        # the inputs one after the other here; the parts of each on the workers
        args.part_jobs, args.part_scheduler = args.jobs, args.scheduler
        args.jobs, args.scheduler = 1, None
        args.phase_bar = False
        return run_batch(args, _process_parts, plan, "meshing", _show,
                         lambda doc: {k: v for k, v in doc.items() if k != "summary"}, warm=True)
    # one input runs here, where its phases can be shown as they pass
    args.phase_bar = len(plan) == 1 and shows_progress(args.quiet)
    return run_batch(args, _process, plan, "meshing", _show,
                     lambda doc: {k: v for k, v in doc.items() if k != "summary"},
                     warm=args.method == "uniform")


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
