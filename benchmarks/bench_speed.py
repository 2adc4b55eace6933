"""Benchmark: every speed and memory target of uniform2d against its peer, in one run.

Usage::

    python benchmarks/bench_speed.py [--quick] [--skip NAME ...]

Rows (NAME in brackets), each measured now, its peer in the same run:

- ``uniform_mesh`` at n = 1000 and n = 10000 Steiner points [n1000, n10000]:
  seconds per polygon, geometric mean over the benchmark polygons
  (``data/benchmarks``, kernels loaded first), on 1 and 2 threads and on every
  core (:func:`uniform2d.threads.set_threads`), against Gmsh Frontal-Delaunay at
  the same vertex count (its ``generate()`` alone, size bisected to the count as
  in ``bench_uniform.py``; one surface: Gmsh meshes it on one thread); targets
  5x and 1x Gmsh's time;
- the bolt plate (``data/plate_bolts.json``) at 2000 vertices in all [plate],
  the same way (informative);
- 1e5 and 1e6 vertices on the square [1e5, 1e6], each in a fresh process
  (``bench_uniform.speed_run``): time and peak RSS per vertex; Gmsh at 1e5 only
  (its size bisection at 1e6 takes longer than the benchmark is worth);
- INSERT on 1e6 points [insert] (``bench_insert.py``) against Triangle's plain
  Delaunay triangulation of INSERT's final points and its ``pq20a`` quality
  mesh with as many vertices;
- the first run [first]: README command 1's mesh on an empty numba cache
  (``bench_compile.first_run``), wall seconds.

The table at the end gives each figure, the peer's, their ratio, the target and
whether it is met.  ``--quick`` runs small stand-ins (n = 200 and 1000, 1e4
and 3e4 vertices, INSERT on 1e5 points, no first run) in about a minute, to
check the script: their targets read "n/a (quick)".  Timings are of this
machine as it is now: run it with nothing else running.  ``--cpu`` times the
everyday rows by CPU time instead (ours and Gmsh's ``generate()``), which
other work on the machine changes far less than the wall time.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)
import bench_compile  # noqa: E402
import bench_insert  # noqa: E402
import bench_uniform as bu  # noqa: E402
import uniform2d  # noqa: E402
from uniform2d.threads import get_threads, set_threads  # noqa: E402

ROWS = ("n1000", "n10000", "plate", "1e5", "1e6", "insert", "first")


def _everyday(n: int, threads: list[int], clock=time.perf_counter,
              total: bool = False) -> tuple[dict, float]:
    """({thread count: our seconds per polygon}, Gmsh's) at n Steiner points,
    geometric means over the benchmark polygons; every thread count and Gmsh
    measured polygon by polygon, in turn, so that a change of the machine's
    load falls on all of them alike.  ``clock``: wall (default) or this
    process's CPU time (``--cpu``: on a machine other work loads, the work
    each does; with several threads, theirs summed).  ``total``: the bolt
    plate (``data/plate_bolts.json``) alone, at n vertices in all."""
    if total:
        plate = bu.read_polygon(bu.ROOT / "data" / "plate_bolts.json")
        polys, steiner = {"plate": plate}, n - len(plate.vertices)
    else:
        polys, steiner = bu.benchmark_polygons(), n
    for p in polys.values():
        uniform2d.uniform_mesh(p, 200)  # kernels loaded before any clock starts
    ours, gmsh = {k: [] for k in threads}, []
    for p in polys.values():
        for k in threads:
            set_threads(k)
            t = clock()
            uniform2d.uniform_mesh(p, steiner)
            ours[k].append(clock() - t)
        gmsh.append(bu.gmsh_tuned(p, len(p.vertices) + steiner, clock)[2])
    set_threads(None)
    return {k: bu.gmean(v) for k, v in ours.items()}, bu.gmean(gmsh)


def _rows(args) -> list[tuple]:
    """(figure, ours, peer, ratio, target, met) for every row not skipped."""
    quick = args.quick
    na = "n/a (quick)"
    threads = sorted({1, 2, get_threads()})
    out = []

    def add(figure, ours, peer, ratio, target, met):
        out.append((figure, ours, peer, ratio, na if quick else target,
                    "-" if quick or met is None else ("yes" if met else "no")))
        print(" | ".join(str(x) for x in out[-1]), flush=True)

    # the goals: n = 1000 within 5x Gmsh's time, n = 10000 within Gmsh's
    # (the bolt plate: no goal of its own, the example of an everyday mesh)
    for name, n, factor in (("n1000", 200 if quick else 1000, 5.0),
                            ("n10000", 1000 if quick else 10000, 1.0),
                            ("plate", 2000, None)):
        if name in args.skip:
            continue
        times, gm = _everyday(n, threads, time.process_time if args.cpu else time.perf_counter,
                              total=name == "plate")
        for k, ours in times.items():
            target = f"<= {factor:g}x Gmsh" if factor else "(informative)"
            met = ours <= factor * gm if factor else None
            unit = "CPU s" if args.cpu else "s"
            what = f"n = {n}" if name != "plate" else f"bolt plate, {n} vertices"
            add(f"uniform_mesh {what}, {k} thread{'s' * (k > 1)}, {unit}/polygon (gmean)",
                f"{ours:.3f}", f"Gmsh {gm:.3f}", f"{ours / gm:.1f}x", target, met)
    square = bu.benchmark_polygons()["square"]
    for name, N in (("1e5", 10_000 if quick else 100_000), ("1e6", 30_000 if quick else 1_000_000)):
        if name in args.skip:
            continue
        r = bu.speed_run(N, "balanced", tplus=False)  # T+ alone is not a row here
        t, bpv = r["t_ours"], r["peak"] / N  # uniform_mesh, T+ included
        if name == "1e5":
            gm = bu.gmsh_tuned(square, N)[2]
            add(f"uniform_mesh {N:,} vertices (square), s", f"{t:.2f}", f"Gmsh {gm:.2f}",
                f"{t / gm:.2f}x", "<= 0.5x Gmsh", t <= 0.5 * gm)
        else:
            add(f"uniform_mesh {N:,} vertices (square), s", f"{t:.1f}", "Gmsh not run at this size",
                "-", "<= 25 s", t <= 25.0)
            add(f"uniform_mesh {N:,} vertices, peak B/vertex", f"{bpv:.0f}", "-", "-",
                "<= 400 B/vertex", bpv <= 400.0)
    if "insert" not in args.skip:
        n = 100_000 if quick else 1_000_000
        r = bench_insert.insert_run(n)
        td = bench_insert.triangle_delaunay(n)
        tq = bench_insert.triangle_quality(r["n_vertices"])
        Path(bench_insert._points_file(n)).unlink(missing_ok=True)
        if td is None:
            add(f"INSERT {n:,} points, s", f"{r['seconds']:.2f}", "Triangle not installed", "-",
                "<= 2x Triangle Delaunay", None)
        else:
            ratio = r["seconds"] / td["seconds"]
            add(f"INSERT {n:,} points, s", f"{r['seconds']:.2f}",
                f"Triangle Delaunay {td['seconds']:.2f}", f"{ratio:.2f}x",
                "<= 2x Triangle Delaunay", ratio <= 2.0)
            add(f"INSERT {n:,} points, s", f"{r['seconds']:.2f}",
                f"Triangle pq20a {tq['seconds']:.2f}", f"{r['seconds'] / tq['seconds']:.2f}x",
                "(informative)", None)
    if "first" not in args.skip and not quick:
        r = bench_compile.first_run()
        wall = r["wall"] if r else float("nan")
        add("first run, README command 1, empty cache, s", f"{wall:.1f}", "-", "-",
            "<= 20 s on two cores", wall <= 20.0)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small stand-ins, to check the script")
    ap.add_argument("--cpu", action="store_true",
                    help="time the everyday rows by this process's CPU time, ours and Gmsh's "
                    "(a machine other work loads: the work done, not the wait)")
    ap.add_argument("--skip", nargs="*", default=[], choices=ROWS, metavar="NAME",
                    help=f"rows to leave out: {', '.join(ROWS)}")
    args = ap.parse_args(argv)
    rows = _rows(args)
    print("\n| figure | uniform2d | peer (same run) | ratio | target | met |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
