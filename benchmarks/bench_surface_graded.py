"""Benchmark: surface.remesh with a graded 3-D size, on the bundled patches and models.

Usage::

    python benchmarks/bench_surface_graded.py [--vertices 2000] [--ratio 4] [--only NAME ...]

For every ``data/patches/*.obj`` (one chart) and ``data/models/*.obj`` (an atlas) the
size is ``h = 1 + (ratio - 1) t``, ``t`` in [0, 1] along the longest side of the
bounding box: ``ratio`` times coarser at one end than at the other.  Printed: the
vertices (exactly ``--vertices``), max q / min q, the CV of q and its mean
(q = 3-D edge length / (c h(midpoint)), c the scale the count chose), and, for
reference, the same model remeshed uniformly with the same count: its edge ratio,
its edge CV and its CV of q against the graded h (how far a uniform mesh is from
following h), and the graded remesh's time over the uniform one's.
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

import _checkout  # noqa: E402, F401  (measure this checkout, not an installed uniform2d)
import surface  # noqa: E402
from surface.measure import unique_edges  # noqa: E402


def along(p, lo, ext, axis, ratio):
    """The size of the benchmark: 1 at the low end of ``axis``, ``ratio`` at the high end."""
    return 1.0 + (ratio - 1.0) * (p[:, axis] - lo) / ext


def size_for(path: Path, ratio: float):
    V = surface.read_model(path).vertices
    lo, hi = V.min(axis=0), V.max(axis=0)
    ax = int(np.argmax(hi - lo))
    return functools.partial(along, lo=float(lo[ax]), ext=float(hi[ax] - lo[ax]), axis=ax, ratio=ratio)


def q_cv(res, h) -> float:
    E = unique_edges(res.faces)
    X = res.vertices
    q = np.linalg.norm(X[E[:, 1]] - X[E[:, 0]], axis=1) / h(0.5 * (X[E[:, 0]] + X[E[:, 1]]))
    return float(q.std() / q.mean())


def run(path: Path, n: int, ratio: float) -> str:
    h = size_for(path, ratio)
    t = time.perf_counter()
    g = surface.remesh(path, n, size=h, check=False, hausdorff=False)
    tg = time.perf_counter() - t
    t = time.perf_counter()
    u = surface.remesh(path, n, check=False, hausdorff=False)
    tu = time.perf_counter() - t
    e, eu = g.report.edges, u.report.edges
    kind = "atlas" if g.atlas is not None else "patch"
    return (f"{path.stem:15s} {kind:5s} {len(g.vertices):6d} {e['q_ratio']:8.3f} {e['q_cv']:7.4f} "
            f"{e['q_mean']:7.3f} | {eu['ratio']:7.3f} {eu['cv']:7.4f} {q_cv(u, h):9.4f} | "
            f"{tg / tu:6.2f}x")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vertices", type=int, default=2000)
    ap.add_argument("--ratio", type=float, default=4.0)
    ap.add_argument("--only", nargs="*", default=None, help="model names (file stems) to run")
    args = ap.parse_args(argv)
    paths = sorted((ROOT / "data" / "patches").glob("*.obj")) + sorted((ROOT / "data" / "models").glob("*.obj"))
    if args.only:
        paths = [p for p in paths if p.stem in args.only]
    print(f"graded size: {args.ratio:g} times coarser along the longest side; {args.vertices} vertices")
    print(f"{'model':15s} {'kind':5s} {'verts':>6s} {'q max/min':>8s} {'q cv':>7s} {'q mean':>7s} | "
          f"{'uniform: ratio':>7s} {'cv':>7s} {'cv of q':>9s} | time / uniform")
    for p in paths:
        print(run(p, args.vertices, args.ratio))
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
