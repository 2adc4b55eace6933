"""Benchmark: INSERT on a long straight edge facing many boundary vertices (issue 35, part 2).

The synthetic polygon is a coastline above a straight cut: the cut is a single
edge 360 units long, and the coastline above it has k wiggly vertices, dipping
into the cut's diametral disk, so that the cut's subsegment candidate sees
hundreds to thousands of sites.  For k = 275, 550, 1100, 2200 it prints the time
of ``insert(p, 1)`` and of ``uniform_mesh(p, 2000)``, each in a fresh process
after a warm-up call on a small polygon (numba's compiled kernels loaded), and
the growth exponent d log t / d log k between consecutive rows.  ``--shape dome``
puts a dome of k vertices over the cut instead, whose lowest vertices hide
behind long boundary edges from the box's sides (the nearest site along a side
is then not the visible one).

With ``--old ROOT`` it also times the same calls from another checkout (e.g. the
main branch's worktree, whose evaluation is cubic in the sites), each run cut
off after ``--old-timeout`` seconds (printed as ``>T``).  A checkout is used by
putting it first on ``PYTHONPATH`` in the child process.

Run:  python benchmarks/bench_insert_edges.py [--k 275 550 1100 2200] [--shape dome]
      [--old /work/wt-orig [--no-new] [--old-timeout 300]]
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

COAST = """
import numpy as np
import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)

def coastline(k):
    '''A straight cut 360 long, (0, 0) -> (360, 0), and above it a coastline of k
    vertices from (360, 90) back to (0, 90): a slow swell, a zigzag of +-6 and a
    little noise, its lowest points about 40 above the cut (inside the cut's
    diametral disk, radius 180).'''
    rng = np.random.default_rng(35)
    x = np.linspace(360.0, 0.0, k)
    u = np.linspace(0.0, 1.0, k)
    y = 80.0 - 30.0 * np.sin(np.pi * u) + 6.0 * (-1.0) ** np.arange(k) + rng.uniform(-2.0, 2.0, k)
    return [(0.0, 0.0), (360.0, 0.0)] + [(float(a), float(b)) for a, b in zip(x, y)]

def dome(k):
    '''The same cut under a dome of k vertices (radius 150 about (180, 20)), its ends
    joined to the corners (360, 200) and (0, 200) by long edges that hide the
    dome's lowest vertices from the box's sides.'''
    th = np.linspace(np.pi * 0.02, np.pi * 0.98, k)
    arc = [(180.0 + 150.0 * np.cos(t), 20.0 + 150.0 * np.sin(t)) for t in th]
    return [(0.0, 0.0), (360.0, 0.0), (360.0, 200.0)] + arc + [(0.0, 200.0)]
"""


def _child(root: Path, k: int, what: str, timeout: float, shape: str = "coastline") -> float | None:
    """Seconds for ``what`` ('insert' or 'uniform') at k in a fresh process run from
    checkout ``root``; None if it ran out of time."""
    code = textwrap.dedent(COAST) + textwrap.dedent(
        f"""
        import json, time
        import uniform2d
        from uniform2d import Polygon
        sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
        uniform2d.insert(sq, 20)                     # load the compiled kernels
        uniform2d.uniform_mesh(sq, 50)
        p = Polygon({shape}({k}))
        t = time.perf_counter()
        if {what!r} == "insert":
            uniform2d.insert(p, 1)
        else:
            uniform2d.uniform_mesh(p, 2000)
        print(json.dumps({{"t": time.perf_counter() - t}}))
        """
    )
    env = {**os.environ, "PYTHONPATH": str(root)}
    try:
        # run in the checkout: ``python -c`` puts the working directory first on sys.path
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env=env, check=True, timeout=timeout, cwd=root)
    except subprocess.TimeoutExpired:
        return None
    return json.loads(out.stdout.strip().splitlines()[-1])["t"]


SKIPPED = -1.0  # a column not measured (--no-new)


def _fmt(t: float | None, timeout: float) -> str:
    if t == SKIPPED:
        return "-"
    return f">{timeout:.0f}" if t is None else f"{t:.3f}"


def _slope(rows, col):
    """Growth exponents between consecutive rows of column col (None where unknown)."""
    out = [None]
    for (k0, *r0), (k1, *r1) in itertools.pairwise(rows):
        a, b = r0[col], r1[col]
        out.append(None if a is None or b is None or a <= 0 or b <= 0
                   else math.log(b / a) / math.log(k1 / k0))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, nargs="+", default=[275, 550, 1100, 2200])
    ap.add_argument("--old", type=Path, default=None, help="another checkout to time too")
    ap.add_argument("--old-timeout", type=float, default=300.0)
    ap.add_argument("--timeout", type=float, default=600.0)
    ap.add_argument("--no-new", action="store_true", help="time only the --old checkout")
    ap.add_argument("--shape", choices=["coastline", "dome"], default="coastline",
                    help="the coastline above the cut (default), or a dome over it")
    args = ap.parse_args()
    rows = []
    for k in args.k:
        if args.no_new:
            row = [k, SKIPPED, SKIPPED]
        else:
            row = [k, _child(ROOT, k, "insert", args.timeout, args.shape),
                   _child(ROOT, k, "uniform", args.timeout, args.shape)]
        if args.old is not None:
            row += [_child(args.old, k, "insert", args.old_timeout, args.shape),
                    _child(args.old, k, "uniform", args.old_timeout, args.shape)]
        rows.append(row)
    head = f"{'k':>6} {'insert(p,1) s':>14} {'exp':>5} {'uniform(p,2000) s':>18} {'exp':>5}"
    if args.old is not None:
        head += f" {'old insert s':>14} {'exp':>5} {'old uniform s':>18} {'exp':>5}"
    print(head)
    cols = range(1, 5 if args.old is not None else 3)
    slopes = {c: _slope(rows, c - 1) for c in cols}
    for i, row in enumerate(rows):
        line = f"{row[0]:6d}"
        for c in cols:
            tout = args.timeout if c <= 2 else args.old_timeout
            e = slopes[c][i]
            width = 14 if c % 2 else 18
            line += f" {_fmt(row[c], tout):>{width}} {'' if e is None else f'{e:.2f}':>5}"
        print(line)
        sys.stdout.flush()
    print("exp: growth exponent d log t / d log k from the row above")


if __name__ == "__main__":
    main()
