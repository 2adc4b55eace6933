"""``uniform2d mesh``: mesh polygon files with exactly n Steiner points.

Outputs
-------
* One input: ``-o FILE`` (the format follows the extension, any of
  ``uniform2d.io.mesh_formats()``); ``-o DIR`` (an existing directory, or any
  name ending in ``/``, created if missing) writes ``DIR/<input stem><--format>``.
  ``-o`` may be repeated: ``-o a.msh -o a.inp -o a.vtu`` writes the one mesh in
  each format (``--element-type`` picks the Abaqus element type of ``.inp``
  outputs).
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
    same_outputs,
    shows_progress,
)
from ._mesh_write import load_plotting, write_outputs
from ._sizing import add_size_options, field_from_args, has_field
from ._vertices import steiner_for_vertices, steiner_for_vertices_resampled

log = logging.getLogger(__name__)

METHODS = ("uniform", "paper")
#: Abaqus element types of planar meshes (uniform2d.io.abaqus_file.PLANAR_TYPES).
ELEMENT_TYPES = ("CPS3", "CPE3", "CAX3")

#: ParaView's partitioned VTU: written piece by piece with --parts.
PVTU = ".pvtu"


def add_parser(subparsers):
    from ..io import mesh_formats

    p = subparsers.add_parser(
        "mesh",
        help="mesh polygon files (exactly n Steiner points, near-equal edges)",
        description="Mesh one or more polygon files with exactly n Steiner points "
        "(boundary and interior) and edges as equal in length as possible. -n counts the "
        "points ADDED to the polygon's own vertices |V| (its ring vertices, segment ends and "
        "fixed points): the mesh has n + |V| vertices. --vertices N asks for N vertices in "
        "total instead.",
        epilog="mesh formats: " + ", ".join(mesh_formats()),
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="polygon file(s): .json, .geojson, .wkt, .poly, .dxf")
    # one of the three, or none with --size-field (checked by _check_count)
    count = p.add_mutually_exclusive_group()
    count.add_argument("-n", type=positive_int, metavar="N",
                       help="number of Steiner points: vertices added on the boundary and inside, "
                       "on top of the polygon's own |V| (the mesh has N + |V| vertices)")
    count.add_argument("--vertices", type=positive_int, metavar="N",
                       help="total number of mesh vertices, the polygon's own included "
                       "(N - |V| Steiner points; N must exceed |V|)")
    count.add_argument("--size", type=positive_float, metavar="H",
                       help="target edge length; n is derived from the area and perimeter "
                       "(with --refine: the coarse size, n derived from the field)")
    add_size_options(p)
    p.add_argument("--resample", type=positive_float, metavar="TOL",
                   help="resample the outline at the mesh spacing, within TOL x spacing of it "
                   "(e.g. 0.05 or 0.25): for dense outlines (coastlines, CAD curves); corners, "
                   "segment ends and fixed points stay, the other boundary points count in n; with --refine or --size-field, at the field's "
                   "local spacing")
    p.add_argument("--corner-angle", type=float, default=None, metavar="DEG",
                   help="with --resample: input vertices turning by more than DEG degrees stay "
                   "(default 30)")
    p.add_argument("--resample-corners", choices=("keep", "merge"), default=None,
                   help="with --resample: 'keep' every corner (default), or 'merge' a corner "
                   "with a ring point closer than 0.6 spacings into one point on the outline "
                   "between them, within the tolerance (fewer short boundary edges)")
    p.add_argument("--method", choices=METHODS, default="uniform",
                   help="'uniform': uniform2d.uniform_mesh (recommended, default); "
                   "'paper': the paper's T+ (uniform2d.tplus)")
    p.add_argument("-o", "--output", metavar="OUTPUT", action="append",
                   help="output mesh file (one input) or directory (existing, or ending in '/': "
                   "created); default: next to the input. Repeat it to write one mesh in "
                   "several formats: -o a.msh -o a.inp -o a.vtu")
    p.add_argument("--element-type", type=str.upper, choices=ELEMENT_TYPES, metavar="TYPE",
                   help="Abaqus element type of .inp outputs: " + ", ".join(ELEMENT_TYPES)
                   + " (plane stress, plane strain, axisymmetric; default CPS3)")
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
    from ..figure_path import check_figure_path

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
    """One -o path and whether it names a directory, checked before any meshing."""
    from ..io.registry import MESH_FORMATS, find_mesh_format, match_format

    if text is None:
        return None, False
    out = Path(text)
    if several and (out.is_file() or (not names_directory(text) and match_format(out, MESH_FORMATS))):
        raise ValueError(f"with several inputs, -o must be a directory, got '{out}'")
    if several or names_directory(text):
        check_output_dir(out, "-o")  # it exists and is writable, or can be made
        return out, True
    if out.suffix.lower() == PVTU:
        if not parts:
            raise ValueError(f"'{out}': a .pvtu is written piece by piece from a mesh made in "
                             "parts; add --parts K (or write another format)")
        check_output_file(out, "-o")
        return out, False
    find_mesh_format(out, "write")
    check_output_file(out, "-o")  # its directory exists and is writable
    return out, False


def _outputs(args, inputs: list[Path], ext: str) -> list[tuple[Path, ...]]:
    """The output files of each input, every -o checked before any meshing."""
    texts = args.output or [None]
    several = len(inputs) > 1
    if several and len(texts) > 1:
        raise ValueError("with several inputs, give one -o directory (it receives "
                         "<input name><--format> per input)")
    targets = [_output_target(t, several, args.parts) for t in texts]
    outs = []
    for src in inputs:
        stem = _stem(src)
        mine = tuple(src.parent / (stem + ext) if out is None else
                     (out / (stem + ext) if is_dir else out) for out, is_dir in targets)
        for (out, _), d in zip(targets, mine):
            if out is None:  # next to the input: that directory must be writable
                check_output_file(d, "-o")
        if len({d.resolve() for d in mine}) != len(mine):
            raise ValueError(f"the outputs {', '.join(map(str, mine))} name one file twice")
        outs.append(mine)
    if args.element_type is not None and not any(
            d.name.lower().endswith(".inp") for mine in outs for d in mine):
        raise ValueError(f"--element-type {args.element_type} applies to Abaqus .inp outputs, "
                         "and no output is one; add -o NAME.inp")
    return outs


def _plan(args) -> list[tuple[Path, tuple[Path, ...], Path | None]]:
    """(input, outputs, plot) per input, every check that needs no meshing done."""
    inputs = [Path(s) for s in args.inputs]
    for src in inputs:  # all inputs before any output
        if not src.exists():
            raise FileNotFoundError(2, "input file not found", str(src))
    ext = _format_extension(args.format, args.parts)
    several = len(inputs) > 1
    outs = _outputs(args, inputs, ext)
    plot, plot_is_dir = _plot_target(args.plot, several)

    plan = []
    for src, dst in zip(inputs, outs):
        fig = None
        if plot is not None:
            fig = plot / (_stem(src) + ".png") if plot_is_dir else plot
        if any(d.suffix.lower() == PVTU for d in dst):
            if fig is not None:
                raise ValueError("--plot needs the whole mesh, which a .pvtu output never "
                                 "gathers; drop --plot or write another format")
            if len(dst) > 1:
                raise ValueError("a .pvtu output is written piece by piece by the workers; "
                                 "write it alone (other formats in another run)")
        plan.append((src, dst, fig))
    same_outputs(plan)
    return plan


def _count(polygon, args) -> int:
    """n from -n or --size, checked against this machine's memory."""
    from ..errors import InsufficientPointsError
    from ..resources import check_point_count
    from ..uniform import steiner_count_for_size

    n = args.n
    what = f"n = {n}"
    if getattr(args, "vertices", None) is not None:
        n = steiner_for_vertices(polygon, args.vertices)
        what = f"--vertices {args.vertices} (n = {n})"
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

    n_arg = args.n
    field = field_from_args(polygon, args)
    if getattr(args, "vertices", None) is not None and args.resample is not None:
        n_arg = steiner_for_vertices_resampled(
            polygon, args.vertices, size=args.size if field is None else field,
            resample=args.resample, corner_angle=args.corner_angle,
            resample_corners=args.resample_corners)
    elif getattr(args, "vertices", None) is not None:
        n_arg = steiner_for_vertices(polygon, args.vertices)
    if field is not None:
        extra = {} if args.corner_angle is None else {"corner_angle": args.corner_angle}
        return uniform_mesh(polygon, n=n_arg, size=field, resample=args.resample,
                            progress=progress, **extra)
    if args.method == "uniform":
        extra = {} if args.corner_angle is None else {"corner_angle": args.corner_angle}
        if args.resample_corners is not None:
            extra["resample_corners"] = args.resample_corners
        return uniform_mesh(polygon, n=n_arg, size=args.size, resample=args.resample,
                            progress=progress, **extra)
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

    src, dsts, fig = job
    polygon = read_polygon(src)
    n = _count(polygon, args)
    with _parts_bar(args, src.name) as bar:
        if dsts[0].suffix.lower() == PVTU:  # then the only output (_plan)
            dst = dsts[0]
            dst.parent.mkdir(parents=True, exist_ok=True)
            info = write_pvtu(polygon, n, args.parts, dst, jobs=args.part_jobs,
                              scheduler=args.part_scheduler, bar=bar)
            return {"input": str(src), "output": str(dst), "outputs": [str(dst)], "plot": None,
                    "method": "partitioned",
                    "n_steiner": n, "n_points": info["points"], "n_triangles": info["triangles"],
                    "info": info, "quality": None, "summary": "(a .pvtu is never gathered: "
                    "no quality summary)", "regions": None}
        mesh = partitioned_mesh(polygon, n, args.parts, jobs=args.part_jobs,
                                scheduler=args.part_scheduler, bar=bar)
    return _written(args, src, dsts, fig, polygon, mesh)


def _process(args, job: tuple[Path, Path, Path | None]) -> dict:
    """Mesh one input and write its files; returns what to show (no printing here)."""
    from ..graded import PHASES as GRADED
    from ..io import read_polygon
    from ..optimize.pipeline import PHASES

    src, dst, fig = job
    polygon = read_polygon(src)
    log.info("%s: %r", src, polygon)
    if fig is not None:
        load_plotting()  # before the mesh, beside the warmer on a cold cache
    bar = PhaseBar(GRADED if has_field(args) else PHASES, src.name) if getattr(args, "phase_bar", False) else None
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
    for d in dst:
        d.parent.mkdir(parents=True, exist_ok=True)  # checked by _plan: only a named directory
    if fig is not None:
        fig.parent.mkdir(parents=True, exist_ok=True)
    write_outputs(mesh, dst, fig, getattr(args, "element_type", None))
    return {
        "input": str(src),
        "output": str(dst[0]),
        "outputs": [str(d) for d in dst],
        "plot": str(fig) if fig is not None else None,
        "method": args.method,
        "n_steiner": mesh.info["resample"]["n"] if "resample" in mesh.info else mesh.n_steiner,
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
            print(f"== {doc['input']} -> {', '.join(doc['outputs'])}")
        print(doc["summary"])
        if "warning" in doc["info"]:
            print("note: " + doc["info"]["warning"])
        if "resample" in doc["info"]:
            print(_resample_line(doc["info"]["resample"]))
        for k, r in enumerate(doc["regions"] or []):
            label = "" if r["label"] is None else f" ({r['label']})"
            print(f"  region {k}{label}: {r['triangles']} triangles, area {r['area']:.6g}")
        if doc["info"].get("method") == "paper" and "d_n" in doc["info"]:
            _print_tplus(doc["info"])
    if not args.quiet and not args.json:
        print(f"wrote {', '.join(doc['outputs'])} ({doc['n_points']} points, {doc['n_triangles']} triangles, "
              f"n = {doc['n_steiner']})" + (f", figure {doc['plot']}" if doc["plot"] else ""))
        if "resample" in doc["info"] and not args.stats:  # else shown with the stats
            print("  " + _resample_line(doc["info"]["resample"]))
    sys.stdout.flush()


def _resample_line(r: dict) -> str:
    return (f"outline resampled at spacing {r['spacing']:.6g}: deviation {r['deviation']:.4g} "
            f"({r['deviation_fraction']:.3f} of the spacing, tolerance {r['tolerance']:g}), "
            f"{r['kept_vertices']} input vertices kept, {r['boundary_points']} boundary points")


def _check_count(args) -> None:
    """-n, --vertices, --size and the field options: what may go together (argparse
    keeps the first three apart)."""
    counted = args.n is not None or getattr(args, "vertices", None) is not None
    if args.resample is not None and (args.method != "uniform"
                                      or getattr(args, "parts", None) is not None):
        raise ValueError("--resample works with --method uniform (the default) in one part "
                         "(not with --parts)")
    if args.corner_angle is not None and args.resample is None:
        raise ValueError("--corner-angle works with --resample only")
    if args.resample_corners is not None and args.resample is None:
        raise ValueError("--resample-corners works with --resample only")
    if args.resample_corners == "merge" and has_field(args):
        raise ValueError("--resample-corners merge works with a uniform size only (not with "
                         "--refine or --size-field)")
    if has_field(args):
        if args.method != "uniform":
            raise ValueError("--refine and --size-field need --method uniform (the paper's T+ "
                             "has no size field)")
        if args.refine and not counted and args.size is None:
            raise ValueError("--refine needs -n N or --vertices N (the count; the field's "
                             "shape) or --size H (its coarse size; n follows)")
        return
    if not counted and args.size is None:
        raise ValueError("give one of -n N, --vertices N and --size H (or a size field: "
                         "--refine, --size-field)")


def run(args) -> int:
    _check_count(args)
    check_parallel_options(args)
    plan = _plan(args)
    if args.parts:
        if has_field(args):
            raise ValueError("--parts makes a uniform mesh in parts; it cannot be used with "
                             "--refine or --size-field yet")
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
