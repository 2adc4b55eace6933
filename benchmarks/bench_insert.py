"""Benchmark of Algorithm INSERT on the unit square (prints figures; not a test).

For n = 1e4, 1e5, 1e6 it prints INSERT's time, points per second and peak memory
per point, each measured in a fresh process (peak RSS above the process's
baseline after imports and warm-up).  It also prints the cold compile time (empty
numba cache) and the warm first call of ``insert(square, 1000)`` in a fresh
process.  When the ``compare`` extra is installed it measures, in the same run,
Triangle making a ``pq20a<area>`` quality mesh with the same number of vertices
(area found by bisection) and Triangle's plain Delaunay triangulation of
INSERT's final point set, and prints the ratios the targets are stated in.

Run:  python benchmarks/bench_insert.py [--sizes 10000 100000 1000000] [--quick]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import textwrap
import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)

SQUARE = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]


def _child(code: str, env=None) -> dict:
    """Run ``code`` in a fresh interpreter; it prints one JSON line last."""
    out = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def insert_run(n: int) -> dict:
    return _child(
        f"""
        import json, resource, time
        import numpy as np
        from uniform2d import Polygon, insert
        sq = Polygon({SQUARE!r})
        insert(sq, 100)                                  # load the compiled kernel
        base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        t = time.perf_counter()
        r = insert(sq, {n})
        dt = time.perf_counter() - t
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        np.save("{{}}".format(__import__("os").environ["U2D_PTS"]), r.mesh_points)
        print(json.dumps(dict(seconds=dt, peak_kib=peak - base, n_vertices=len(r.mesh_points))))
        """,
        env={"U2D_PTS": _points_file(n)},
    )


def _points_file(n: int) -> str:
    return os.path.join(tempfile.gettempdir(), f"u2d_bench_points_{n}.npy")


def cold_compile() -> dict:
    with tempfile.TemporaryDirectory() as cache:
        code = f"""
            import json, time
            t0 = time.perf_counter()
            from uniform2d import Polygon, insert
            t1 = time.perf_counter()
            insert(Polygon({SQUARE!r}), 1000)
            t2 = time.perf_counter()
            print(json.dumps(dict(import_s=t1 - t0, first_call_s=t2 - t1)))
        """
        cold = _child(code, env={"NUMBA_CACHE_DIR": cache})
        warm = _child(code, env={"NUMBA_CACHE_DIR": cache})
    return {"cold": cold, "warm": warm}


def triangle_quality(n_vertices: int) -> dict | None:
    """Triangle's pq20a<area> mesh of the unit square bisected to n_vertices."""
    if importlib.util.find_spec("triangle") is None:
        return None
    return _child(
        f"""
        import json, math, time
        import numpy as np
        import triangle
        target = {n_vertices}
        box = dict(vertices=np.array({SQUARE!r}), segments=np.array([[0,1],[1,2],[2,3],[3,0]]))
        def run(area):
            t = time.perf_counter()
            out = triangle.triangulate(box, "pq20a%.15f" % area)   # fixed-point: 1e-6 is ignored
            return len(out["vertices"]), time.perf_counter() - t
        lo, hi = 0.5 / target, 4.0 / target      # ~2 triangles per vertex, area ~ 1/(2N)
        best = None
        for _ in range(14):
            mid = math.sqrt(lo * hi)
            nv, dt = run(mid)
            if best is None or abs(nv - target) < abs(best[0] - target):
                best = (nv, dt, mid)
            if abs(nv - target) <= max(1, target // 2000):
                break
            if nv > target:
                lo = mid
            else:
                hi = mid
        nv, dt, area = best
        print(json.dumps(dict(seconds=dt, n_vertices=nv, area=area)))
        """
    )


def triangle_delaunay(n: int) -> dict | None:
    if importlib.util.find_spec("triangle") is None:
        return None
    return _child(
        f"""
        import json, time
        import numpy as np
        import triangle
        pts = np.load({_points_file(n)!r})
        triangle.triangulate(dict(vertices=pts[:1000]))
        t = time.perf_counter()
        out = triangle.triangulate(dict(vertices=pts))
        print(json.dumps(dict(seconds=time.perf_counter() - t, n_triangles=len(out["triangles"]))))
        """
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    ap.add_argument("--no-compile", action="store_true", help="skip the cold-compile run")
    args = ap.parse_args(argv)

    rows = []
    for n in args.sizes:
        r = insert_run(n)
        tq = triangle_quality(r["n_vertices"])
        td = triangle_delaunay(n)
        rows.append((n, r, tq, td))
        os.remove(_points_file(n))

    print("\nAlgorithm INSERT on the unit square (each row a fresh process)\n")
    print("| n | INSERT s | points/s | peak bytes/pt | Triangle pq20a s (vertices) | "
          "ratio | Triangle Delaunay s | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for n, r, tq, td in rows:
        bpp = r["peak_kib"] * 1024 / r["n_vertices"]
        q = f"{tq['seconds']:.3f} ({tq['n_vertices']})" if tq else "not installed"
        qr = f"{r['seconds'] / tq['seconds']:.2f}" if tq else "-"
        d = f"{td['seconds']:.3f}" if td else "not installed"
        dr = f"{r['seconds'] / td['seconds']:.2f}" if td else "-"
        print(f"| {n:,} | {r['seconds']:.3f} | {n / r['seconds']:,.0f} | {bpp:.0f} | {q} | {qr} | {d} | {dr} |")
    if len(rows) >= 2:
        (n1, r1, *_), (n2, r2, *_) = rows[-2], rows[-1]
        print(f"\ntime({n2:,}) / time({n1:,}) = {r2['seconds'] / r1['seconds']:.2f}")
    if not args.no_compile:
        c = cold_compile()
        print(
            f"cold: import {c['cold']['import_s']:.2f} s + first call (compile) "
            f"{c['cold']['first_call_s']:.2f} s; warm fresh process: import "
            f"{c['warm']['import_s']:.2f} s + insert(square, 1000) {c['warm']['first_call_s']:.2f} s"
        )
    print("\ntargets: INSERT(1e6) <= 0.5 x Triangle pq20a, <= 2 x Triangle Delaunay; "
          "time(1e6)/time(1e5) <= 12; <= 300 bytes/pt; warm first call <= 1 s; cold compile <= 30 s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
