"""Benchmark of the winner's descent alone (prints figures; not a test).

For each benchmark polygon (``data/benchmarks``): the first start of the
optimiser (:func:`uniform2d.optimize.seed.variants`), built in the kernel and
relaxed by 60 spring rounds (untimed), then the descent stages of the winner's
schedule, p = 2**5 to 2**8 (25 sweeps a stage up to ``schedule.SMALL``
points, 40 above), timed by CPU time: the best of ``--reps`` runs, each on a
fresh copy of the start.  The last line gives the sum over the polygons and a
sha256 prefix of the final points: a change meant to keep the meshes the same
bytes must print the same one.  Compare code by running it in two checkouts,
alternated (the machine's load moves the figures by more than a few per cent).

Run:  python benchmarks/bench_descent.py [--n 1000] [--reps 5] [--only NAME]
"""

from __future__ import annotations

import argparse
import hashlib
import time

import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)
import bench_uniform as bu
from uniform2d._kernel import relax
from uniform2d.optimize import schedule as S
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.moves import KernelMesh
from uniform2d.optimize.objective import objective_code
from uniform2d.optimize.seed import start, variants

STAGES = (5, 6, 7, 8)


def prepared(polygon, n: int):
    """The first start at n points, built and after 60 spring rounds: (state,
    the kernel's arguments)."""
    h = target_size(polygon, n)
    sites, edges, frozen, _ = start(polygon, n, h, variants(polygon, n)[0])
    st = KernelMesh.built(polygon, sites, href=h, frozen=frozen, edges=edges)
    args = (st.m, st.role, st.eid, st.t, st.ea, st.ed, st.hv, st.href)
    relax.spring(*args, iters=60, dt=S.SPRING_STEP, pressure=S.SPRING_PRESSURE,
                 tol=S.SPRING_TOL, cap=S.SPRING_CAP, flat=S.FLAT, restrict=st.restrict)
    return st, args


def descents(st, args, sweeps: int, stages=STAGES) -> float:
    """CPU seconds of the descent stages on the prepared state."""
    obj = objective_code("balanced")
    t0 = time.process_time()
    for k in stages:
        relax.descend(*args, objective=obj, sweeps=sweeps, k=k, step0=S.SEARCH_STEP,
                      flat=S.FLAT, restrict=st.restrict, movable_short=False)
    return time.process_time() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--only", help="one benchmark polygon by name")
    a = ap.parse_args(argv)
    sweeps = 25 if a.n <= S.SMALL else 40
    polys = bu.benchmark_polygons()
    if a.only:
        polys = {a.only: polys[a.only]}
    st, args = prepared(next(iter(polys.values())), 200)
    descents(st, args, 2, STAGES[:1])  # the kernels loaded before any clock starts
    total = 0.0
    digest = hashlib.sha256()
    for name, polygon in polys.items():
        best = float("inf")
        for _ in range(a.reps):
            st, args = prepared(polygon, a.n)
            best = min(best, descents(st, args, sweeps))
        digest.update(st.xy.tobytes())
        total += best
        print(f"{name:16s} {best * 1e3:8.2f} ms", flush=True)
    print(f"sum {total * 1e3:.2f} ms CPU (best of {a.reps}), points sha256 {digest.hexdigest()[:16]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
