"""``uniform2d remesh``: remesh surfaces with near-equal 3-D edges and exactly N vertices.

Wraps the ``remesh`` of the registered surface-patch layer (the ``surface``
extra: trimesh, libigl, pymeshlab; found through :mod:`uniform2d.plugins`).
Input: any triangle-mesh format the layer reads; output: one of its
``WRITE_FORMATS`` (.obj, .off, .ply, .stl, .glb, .inp with shell elements).
One input: ``-o FILE``, repeated for several formats (``-o a.obj -o a.inp``).
Several: ``-o DIR`` (created if missing) receives ``<input stem><--format>``
each, ``--plot`` must then be a directory too; a bad input is one line and the
others go on (exit code 2 at the end), as with ``uniform2d mesh``.
"""

from __future__ import annotations

import logging
import sys
from pathlib import Path

from ._common import (
    INPUT_ERRORS,
    add_parallel_options,
    angle_degrees,
    check_output_dir,
    check_output_file,
    check_parallel_options,
    names_directory,
    positive_float,
    positive_int,
    report_failure,
    run_batch,
    same_outputs,
)

log = logging.getLogger(__name__)

PARAMS = ("lscm", "arap", "harmonic")


def add_parser(subparsers):
    p = subparsers.add_parser(
        "remesh",
        help="remesh surfaces: patches and whole models (needs the 'surface' extra)",
        description="Remesh triangulated surfaces with exactly N vertices and near-equal "
        "3-D edges: a patch that flattens well is flattened (libigl), its flat domain meshed "
        "with uniform2d and lifted back; any other model (closed, any genus, several parts, "
        "strongly curved) is cut into an atlas of such charts sharing their seams. With one "
        "input, --jobs/--scheduler mesh its charts in parallel (same output bytes). -n counts "
        "ALL the vertices of the output (unlike `uniform2d mesh -n`, which counts the points "
        "added to a polygon's own).",
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="surface mesh file(s) (.obj, .off, .ply, .stl, ...)")
    count = p.add_mutually_exclusive_group(required=True)
    count.add_argument("-n", type=positive_int, metavar="N",
                       help="total number of vertices of the output mesh (boundary included)")
    count.add_argument("--size", type=positive_float, metavar="H", help="target 3-D edge length")
    p.add_argument("-o", "--output", required=True, metavar="OUTPUT", action="append",
                   help="output mesh file (.obj, .off, .ply, .stl, .glb, .inp), or with several "
                   "inputs a directory (created if missing); repeat it to write several "
                   "formats: -o a.obj -o a.inp")
    p.add_argument("--element-type", type=str.upper, choices=("S3", "S3R"), metavar="TYPE",
                   help="Abaqus shell element type of .inp outputs: S3 (default) or S3R")
    p.add_argument("--format", default=".obj", metavar="EXT",
                   help="extension of outputs named after their input in a directory "
                   "(default .obj)")
    p.add_argument("--param", choices=PARAMS, default="lscm",
                   help="parameterisation tried first (default lscm)")
    p.add_argument("--corner-angle", type=angle_degrees, metavar="DEG",
                   help="keep as output vertices the boundary vertices where the boundary "
                   "turns by more than DEG degrees (in 3-D; default: the surface layer's, 30)")
    p.add_argument("--feature-angle", type=angle_degrees, metavar="DEG",
                   help="keep creases: interior edges whose faces' normals differ by more "
                   "than DEG degrees become chains of output edges on the input's edges "
                   "(default: none; a model cut into an atlas still has its seams on edges "
                   "bent more than 60 degrees, which keeps those)")
    p.add_argument("--plot", metavar="PNG", help="also write a figure of the 3-D mesh (with "
                   "several inputs a directory receiving <input stem>.png)")
    add_parallel_options(p, "the inputs")
    show = p.add_mutually_exclusive_group()
    show.add_argument("--stats", action="store_true", help="print the remesh report")
    show.add_argument("--json", action="store_true", help="print the report as JSON")
    return p


def _target(text: str | None, several: bool, option: str) -> tuple[Path | None, bool]:
    """An output path and whether it names a directory (one input: a file unless
    it ends in '/' or is a directory; several: always a directory)."""
    if text is None:
        return None, False
    path = Path(text)
    if several or names_directory(text):
        if several and path.is_file():
            raise ValueError(f"with several inputs, {option} must be a directory, got '{path}'")
        check_output_dir(path, option)
        return path, True
    return path, False


def _plan(args, layer) -> list[tuple[Path, tuple[Path, ...], Path | None]]:
    """(input, outputs, figure) per input, every check that needs no remeshing done."""
    from ..figure_path import check_figure_path

    inputs = [Path(s) for s in args.inputs]
    several = len(inputs) > 1
    ext = args.format if args.format.startswith(".") else "." + args.format
    if several and len(args.output) > 1:
        raise ValueError("with several inputs, give one -o directory (it receives "
                         "<input name><--format> per input)")
    named_file = Path(args.output[0]).suffix.lstrip(".").lower() in layer.WRITE_FORMATS
    if several and named_file and not names_directory(args.output[0]):
        raise ValueError(f"with several inputs, -o must be a directory, got '{args.output[0]}'")
    outs = [_target(text, several, "-o") for text in args.output]
    plot, plot_dir = _target(args.plot, several, "--plot")
    plan = []
    for src in inputs:
        dsts = tuple(out / (src.stem + ext) if out_dir else out for out, out_dir in outs)
        fig = (plot / (src.stem + ".png") if plot_dir else plot) if plot is not None else None
        for dst, (_, out_dir) in zip(dsts, outs):
            layer.check_output(dst)
            if not out_dir:
                check_output_file(dst, "-o")
        if len({d.resolve() for d in dsts}) != len(dsts):
            raise ValueError(f"the outputs {', '.join(map(str, dsts))} name one file twice")
        if fig is not None and not plot_dir:
            check_figure_path(fig)
            check_output_file(fig, "--plot")
        plan.append((src, dsts, fig))
    if args.element_type is not None and not any(
            d.name.lower().endswith(".inp") for _, dsts, _ in plan for d in dsts):
        raise ValueError(f"--element-type {args.element_type} applies to Abaqus .inp outputs, "
                         "and no output is one; add -o NAME.inp")
    same_outputs(plan)
    return plan


def _process(args, job) -> dict:
    """Remesh one input and write its files; returns what to show (no printing here)."""
    from ..plugins import patch_layer

    src, dst, fig = job
    layer = patch_layer()
    if not src.exists():
        raise FileNotFoundError(2, "input file not found", str(src))
    model = layer.read_model(src)
    log.info("%s: %r", src, model)
    inner = getattr(args, "chart_jobs", {})  # one input: its charts in parallel instead
    if args.corner_angle is not None:  # else the layer's default
        inner = {**inner, "corner_angle": args.corner_angle}
    result = layer.remesh(model, n_vertices=args.n, size=args.size, param=args.param,
                          feature_angle=args.feature_angle, **inner)
    for d in dst:
        d.parent.mkdir(parents=True, exist_ok=True)  # checked by _plan: only a named directory
        inp = d.name.lower().endswith(".inp") and getattr(args, "element_type", None)
        result.write(d, **({"element_type": args.element_type} if inp else {}))
    if fig is not None:
        fig.parent.mkdir(parents=True, exist_ok=True)
        layer.plot_result(result, fig)
    return {"input": str(src), "output": str(dst[0]), "outputs": [str(d) for d in dst],
            "plot": str(fig) if fig else None,
            "n_vertices": len(result.vertices), "n_faces": len(result.faces),
            "report": result.report.as_dict(), "summary": result.report.summary()}


def _show(args, doc: dict, several: bool) -> None:
    if args.stats:
        if several:
            print(f"== {doc['input']} -> {', '.join(doc['outputs'])}")
        print(doc["summary"])
    if not args.quiet and not args.json:
        print(f"wrote {', '.join(doc['outputs'])} ({doc['n_vertices']} vertices, {doc['n_faces']} faces)"
              + (f", figure {doc['plot']}" if doc["plot"] else ""))
    sys.stdout.flush()


def run(args) -> int:
    from ..plugins import patch_layer

    check_parallel_options(args)
    plan = _plan(args, patch_layer())
    if len(plan) == 1 and not plan[0][0].exists():
        raise FileNotFoundError(2, "input file not found", str(plan[0][0]))
    if len(plan) == 1 and (args.jobs > 1 or args.scheduler is not None):
        args.chart_jobs = {"jobs": args.jobs, "scheduler": args.scheduler}
        args.jobs, args.scheduler = 1, None
    try:
        return run_batch(args, _process, plan, "remeshing", _show,
                         lambda doc: {k: doc[k] for k in ("input", "output", "outputs", "report")})
    except INPUT_ERRORS as exc:
        if len(plan) > 1:
            raise
        report_failure(plan[0][0], exc)  # one line naming the input, as in a batch
        return 2
