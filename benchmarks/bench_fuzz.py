"""Fuzz benchmark: mesh many random domains with every method and check every mesh.

Usage::

    python benchmarks/bench_fuzz.py [--domains 10000] [--seed 0] [--jobs 2]
                                    [--limit 120] [--out failures.json]

Domain i is ``tests/fuzzgen.domain(seed * 10**9 + i)``: star-shaped rings with
short edges, exactly and nearly collinear vertices, sharp spikes, rotated
rectilinear outlines, 1-4 holes, 1:100 slivers, at scales 1e-6..1e6 and half of
them offset by up to 1e7.  Each domain gets three calls, n drawn log-uniformly:

    insert(P, n)        n in [1, 1000]
    tplus(P, n)         n in [1, 1000]
    uniform_mesh(P, n)  n in [1, 300]   (the optimiser is the expensive call)

Every returned mesh is checked by ``tests/invariants.check_mesh`` (exactly
|V| + n points, strictly counter-clockwise triangles, edges glued in opposite
directions, boundary = polygon edges split at points on them, constrained
Delaunay, area).  The area tolerance is 1e-9 relative, or what rounding the
boundary points onto rotated edges allows where the coordinates are coarse for
the polygon's size (4 units in the last place times the perimeter).

Each call ends as one of

    ok       a mesh that passes the checks;
    refused  a uniform2d.Uniform2dError (an invalid polygon drawn, or an n too
             small for T+), the documented answer to unusable input;
    crash    any other exception (including InternalError: a mesh the library's
             own final check stopped);
    wrong    a mesh returned that fails the checks;
    hang     no answer within --limit seconds (the worker is killed); each
             worker compiles the kernels before its first domain, so the
             clock measures meshing only.

The counts are printed, and for every crash, wrong and hang a JSON reproducer in
the format of the shared reproducers file ({"name", "call", "n", "seen", "outer",
"holes"}), also written to --out.  Runs are deterministic for a given --seed.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import sys
import time
from multiprocessing.connection import wait
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

CALLS = (("insert", 1000), ("tplus", 1000), ("uniform_mesh", 300))


def _ns(case_seed):
    rng = np.random.default_rng([case_seed, 7])
    return [int(np.floor(np.exp(rng.uniform(0.0, np.log(hi + 1))))) for _, hi in CALLS]


def _area_rtol(polygon):
    grain = 4 * np.spacing(float(np.abs(polygon.vertices).max()))
    return max(1e-9, grain * polygon.perimeter / polygon.area)


def run_case(case_seed):
    """[(call, n, status, seen, outer, holes)] for one domain."""
    import uniform2d
    from fuzzgen import rings
    from invariants import check_mesh

    kind, outer, holes = rings(case_seed)
    out = []
    try:
        poly = uniform2d.Polygon(outer, holes)
    except uniform2d.Uniform2dError as exc:
        return [("Polygon", 0, "refused", f"{type(exc).__name__}: {exc}", kind, outer, holes)]
    for (call, _), n in zip(CALLS, _ns(case_seed)):
        try:
            if call == "insert":
                res = uniform2d.insert(poly, n)
                pts, tri = res.mesh_points, res.triangles
            else:
                mesh = getattr(uniform2d, call)(poly, n)
                pts, tri = mesh.points, mesh.triangles
        except uniform2d.Uniform2dError as exc:
            out.append((call, n, "refused", f"{type(exc).__name__}: {exc}", kind, outer, holes))
            continue
        except Exception as exc:  # noqa: BLE001 -- every other exception is a crash
            out.append((call, n, "crash", f"{type(exc).__name__}: {exc}", kind, outer, holes))
            continue
        try:
            assert len(pts) == len(poly.vertices) + n, f"{len(pts)} points for n = {n}"
            check_mesh(pts, tri, poly, area_rtol=_area_rtol(poly))
            out.append((call, n, "ok", "", kind, outer, holes))
        except AssertionError as exc:
            out.append((call, n, "wrong", f"WRONG MESH: {exc}", kind, outer, holes))
    return out


def _warm_up():
    """Compile every kernel the three calls use, so that --limit times meshing only
    (a cold numba cache takes minutes on a loaded machine, not a hang)."""
    import uniform2d

    square = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], [[(0.4, 0.4), (0.6, 0.4), (0.5, 0.6)]])
    uniform2d.insert(square, 40)
    uniform2d.tplus(square, 60)
    uniform2d.uniform_mesh(square, 60)


def _worker(conn):
    import logging

    # coarse grids make quality() warn about area; the checks here decide
    logging.getLogger("uniform2d").setLevel(logging.ERROR)
    _warm_up()
    conn.send("ready")
    while True:
        case = conn.recv()
        if case is None:
            return
        conn.send((case, run_case(case)))


class _Slot:
    def __init__(self):
        self.conn, child = mp.Pipe()
        self.proc = mp.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()
        self.case = None
        self.t0 = 0.0

    def wait_ready(self):
        """Block until the worker has compiled the kernels (see :func:`_warm_up`)."""
        assert self.conn.recv() == "ready"
        return self

    def give(self, case):
        self.case, self.t0 = case, time.monotonic()
        self.conn.send(case)


def _reproducer(case, call, n, status, seen, kind, outer, holes):
    return {
        "name": f"fuzz_{status}_{kind}_{case}",
        "call": call,
        "n": int(n),
        "seen": seen[:500],
        "outer": np.asarray(outer).tolist(),
        "holes": [np.asarray(h).tolist() for h in holes],
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--domains", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2, help="worker processes")
    ap.add_argument("--limit", type=float, default=120.0, help="seconds per domain before a hang")
    ap.add_argument("--out", type=Path, default=None, help="write the reproducers here (JSON)")
    args = ap.parse_args(argv)

    todo = [args.seed * 10**9 + i for i in range(args.domains)]
    todo.reverse()
    counts = {s: 0 for s in ("ok", "refused", "crash", "wrong", "hang")}
    per_call = {}
    failures = []
    slots = [s.wait_ready() for s in [_Slot() for _ in range(max(1, args.jobs))]]
    t_start = time.monotonic()
    done = 0

    def record(case, results):
        for call, n, status, seen, kind, outer, holes in results:
            counts[status] += 1
            per_call.setdefault(call, {}).setdefault(status, 0)
            per_call[call][status] += 1
            if status in ("crash", "wrong", "hang"):
                rep = _reproducer(case, call, n, status, seen, kind, outer, holes)
                failures.append(rep)
                print(json.dumps(rep), flush=True)

    for s in slots:
        if todo:
            s.give(todo.pop())
    while any(s.case is not None for s in slots):
        ready = wait([s.conn for s in slots if s.case is not None], timeout=1.0)
        now = time.monotonic()
        for s in slots:
            if s.case is None:
                continue
            if s.conn in ready:
                case, results = s.conn.recv()
                record(case, results)
                done += 1
                s.case = None
            elif now - s.t0 > args.limit:
                from fuzzgen import rings

                kind, outer, holes = rings(s.case)
                seen = f"no answer within {args.limit:g} s"
                record(s.case, [(c, n, "hang", seen, kind, outer, holes) for (c, _), n in zip(CALLS, _ns(s.case))][:1])
                done += 1
                s.proc.kill()
                s.proc.join()
                slots[slots.index(s)] = s = _Slot().wait_ready()
            if s.case is None and todo:
                s.give(todo.pop())
        if done and done % 500 == 0:
            print(f"# {done} domains, {time.monotonic() - t_start:.0f} s: {counts}", file=sys.stderr, flush=True)
    for s in slots:
        s.conn.send(None)
        s.proc.join(5)
    dt = time.monotonic() - t_start
    print(f"\n{args.domains} domains (seed {args.seed}, {args.jobs} jobs) in {dt:.0f} s")
    print("calls: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    for call, c in per_call.items():
        print(f"  {call:13s} " + ", ".join(f"{k} {v}" for k, v in sorted(c.items())))
    if args.out is not None:
        args.out.write_text(json.dumps(failures, indent=1) + "\n")
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
