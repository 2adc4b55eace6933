"""Surface benchmark: ``surface.remesh`` against MeshLab's isotropic explicit remeshing.

Both meshes have the same vertex count (MeshLab's target length is bisected to it,
see ``uniform2d.peers.meshlab_peer``) on every benchmark patch.  Prints edge ratio,
edge CV, min angle, deviation from the input (Hausdorff distance / bounding-box
diagonal) and time side by side, with the issue's targets.  Figures, not a test.

Run:  python benchmarks/bench_surface.py [PATCH ...] [-n 2000] [-o OUTDIR]
      (default patches: ../shared/benchmarks/patches/*.obj beside the repository)
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

from uniform2d.report.build import make_report

HERE = Path(__file__).resolve().parent
DEFAULT = sorted((HERE.parents[1] / "shared" / "benchmarks" / "patches").glob("*.obj"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("patches", nargs="*", type=Path, default=DEFAULT)
    ap.add_argument("-n", type=int, default=2000, help="vertex count (default 2000)")
    ap.add_argument("-o", type=Path, default=None, help="keep the full report here")
    args = ap.parse_args(argv)
    if not args.patches:
        ap.error("no patches given and ../shared/benchmarks/patches not found")

    out = args.o or Path(tempfile.mkdtemp(prefix="u2d_bench_surface_"))
    make_report([str(p) for p in args.patches], out, ns=(args.n,), peers=["meshlab"], figures=False)
    cases = json.loads((out / "results.json").read_text())["cases"]

    print(f"\nsurface.remesh vs MeshLab isotropic remeshing at {args.n} vertices\n")
    print("| patch | method | vertices | edge ratio | edge CV | min angle | deviation/diag | time s |")
    print("|---|---|---|---|---|---|---|---|")
    for c in sorted(cases, key=lambda c: (c["input"], c["method"] != "remesh")):
        if c["status"] != "ok":
            print(f"| {c['input']} | {c['method']} | {c['status']} | | | | | |")
            continue
        m = c["measures"]
        print(
            f"| {c['input']} | {c['method']} | {m['n_vertices']} | {m['edge_ratio']:.3f} | "
            f"{m['cv_edge']:.3f} | {m['min_angle']:.1f}° | {m['hausdorff_max_rel']:.2e} | "
            f"{c['time']['per_mesh']:.2f} |"
        )
    print(
        "\ntargets for surface.remesh: exact vertex count; edge ratio <= 2.0 on every patch; "
        "CV <= 0.08; deviation <= MeshLab's; time <= MeshLab's"
    )
    if args.o is None:
        print(f"(full report: {out})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
