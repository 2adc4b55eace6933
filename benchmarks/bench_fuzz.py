"""Fuzz benchmark: mesh many random domains with every method and check every mesh.

Usage::

    python benchmarks/bench_fuzz.py [--domains 10000] [--seed 0] [--jobs 2]
                                    [--limit 120] [--out failures.json]
                                    [--constrained 0.3] [--resample 0.25]

Domain i is ``uniform2d.testing.fuzz.domain(seed * 10**9 + i)``: star-shaped rings with
short edges, exactly and nearly collinear vertices, sharp spikes, rotated
rectilinear outlines, 1-4 holes, 1:100 slivers, at scales 1e-6..1e6 and half of
them offset by up to 1e7.  A fraction ``--constrained`` of them (drawn from the
seed) is instead ``uniform2d.testing.fuzz.constrained(seed * 10**9 + i)``: outlines with
fixed points, free, T-junction and closed segments, near-degenerate ones included.
Each domain gets three calls, n drawn log-uniformly:

    insert(P, n)        n in [1, 1000]
    tplus(P, n)         n in [1, 1000]
    uniform_mesh(P, n)  n in [1, 300]   (the optimiser is the expensive call)

With ``--resample TOL`` each domain gets a fourth call,

    uniform_mesh(P, n, resample=TOL)  n in [1, 300]

whose mesh must have exactly the kept input vertices + n points, pass the same
checks on the resampled polygon it reports (``mesh.polygon``, its segments and
fixed points included), and keep that polygon's rings within TOL spacings of
the input's (shapely's Hausdorff distance, densified, both ways, ring by ring;
rounding slack 1e-9 of the spacing).

Every returned mesh is checked by ``uniform2d.testing.check_mesh`` (exactly
|V| + n points, strictly counter-clockwise triangles, edges glued in opposite
directions, boundary = polygon edges split at points on them, constrained
Delaunay, area); a constrained domain's mesh must also have every fixed point
as a vertex of a triangle and tile the regions, every segment a chain of its
edges (``uniform2d.mesh_regions.triangle_regions``: areas per region to 1e-9 of the
polygon's, or 2 units in the last place times the region's perimeter).  The
area tolerance is 1e-9 relative, or what rounding the boundary points onto
rotated edges allows where the coordinates are coarse for the polygon's size
(4 units in the last place times the perimeter).

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

The counts are printed, the refusals broken down by error type, and for every crash, wrong and hang a JSON reproducer in
the format of the shared reproducers file ({"name", "call", "n", "seen", "outer",
"holes"}, with "segments" and "points" for a constrained domain), also written
to --out.  Runs are deterministic for a given --seed.
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
import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)


CALLS = (("insert", 1000), ("tplus", 1000), ("uniform_mesh", 300))
#: The call --resample adds (its n drawn after the others': theirs stay the same).
RESAMPLE = ("resample", 300)


def _calls(case):
    """The calls made on ``case`` = (seed, constrained, resample tolerance or 0)."""
    return CALLS + ((RESAMPLE,) if case[2] > 0 else ())


def _ns(case):
    rng = np.random.default_rng([case[0], 7])
    return [int(np.floor(np.exp(rng.uniform(0.0, np.log(hi + 1))))) for _, hi in _calls(case)]


def _area_rtol(polygon):
    grain = 4 * np.spacing(float(np.abs(polygon.vertices).max()))
    return max(1e-9, grain * polygon.perimeter / polygon.area)


def draw(case):
    """(kind, outer, holes, segments, points) of ``case`` (see :func:`_calls`)."""
    from uniform2d.testing.fuzz import constrained, rings

    seed, with_constraints = case[:2]
    if with_constraints:
        return constrained(seed)
    kind, outer, holes = rings(seed)
    return kind, outer, holes, [], np.empty((0, 2))


def _check_constraints(poly, pts, tri):
    from uniform2d.errors import InvalidArgumentError
    from uniform2d.mesh_regions import triangle_regions

    if not poly.has_constraints:
        return
    assert np.isin(poly.fixed, tri).all(), "a fixed point is not a vertex of a triangle"
    try:
        triangle_regions(poly, pts, tri)
    except InvalidArgumentError as exc:
        raise AssertionError(f"regions: {exc}") from None


def _deviation_problem(poly, mesh, tol: float) -> str:
    """Why the resampled polygon of ``mesh`` is farther than ``tol`` spacings from
    ``poly`` (ring by ring, both ways), or ""."""
    import shapely

    h = mesh.info["resample"]["spacing"]
    if len(mesh.polygon.rings) != len(poly.rings):
        return f"{len(mesh.polygon.rings)} rings resampled from {len(poly.rings)}"
    for i, (a, b) in enumerate(zip(poly.rings, mesh.polygon.rings)):
        d = shapely.hausdorff_distance(shapely.LinearRing(a), shapely.LinearRing(b), densify=0.25)
        if d > (tol + 1e-9) * h:
            return f"ring {i} resampled {d / h:.6g} spacings from the input (tolerance {tol:g})"
    return ""


def _mesh(poly, call, n, tol):
    """(points, triangles, the polygon meshed, the mesh or None) of one call."""
    import uniform2d

    if call == "insert":
        res = uniform2d.insert(poly, n)
        return res.mesh_points, res.triangles, poly, None
    if call == "resample":
        mesh = uniform2d.uniform_mesh(poly, n, resample=tol)
        return mesh.points, mesh.triangles, mesh.polygon, mesh
    mesh = getattr(uniform2d, call)(poly, n)
    return mesh.points, mesh.triangles, poly, mesh


def run_case(case):
    """[(call, n, status, seen, domain)] for one domain, ``domain`` as :func:`draw` gives it."""
    import uniform2d
    from uniform2d.testing import check_mesh

    dom = draw(case)
    kind, outer, holes, segs, points = dom
    out = []
    try:
        poly = uniform2d.Polygon(outer, holes, segments=segs, points=points)
    except uniform2d.Uniform2dError as exc:
        return [("Polygon", 0, "refused", f"{type(exc).__name__}: {exc}", dom)]
    for (call, _), n in zip(_calls(case), _ns(case)):
        try:
            pts, tri, meshed, mesh = _mesh(poly, call, n, case[2])
        except uniform2d.Uniform2dError as exc:
            out.append((call, n, "refused", f"{type(exc).__name__}: {exc}", dom))
            continue
        except Exception as exc:  # noqa: BLE001 -- every other exception is a crash
            out.append((call, n, "crash", f"{type(exc).__name__}: {exc}", dom))
            continue
        try:
            kept = mesh.info["resample"]["kept_vertices"] if call == "resample" else len(poly.vertices)
            assert len(pts) == kept + n, f"{len(pts)} points for n = {n} ({kept} vertices kept)"
            check_mesh(pts, tri, meshed, area_rtol=_area_rtol(meshed))
            _check_constraints(meshed, np.asarray(pts), np.asarray(tri))
            if call == "resample":
                problem = _deviation_problem(poly, mesh, case[2])
                assert not problem, problem
            out.append((call, n, "ok", "", dom))
        except AssertionError as exc:
            out.append((call, n, "wrong", f"WRONG MESH: {exc}", dom))
    return out


def _warm_up():
    """Compile every kernel the three calls use, so that --limit times meshing only
    (a cold numba cache takes minutes on a loaded machine, not a hang)."""
    import uniform2d

    square = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], [[(0.4, 0.4), (0.6, 0.4), (0.5, 0.6)]])
    uniform2d.insert(square, 40)
    uniform2d.tplus(square, 60)
    uniform2d.uniform_mesh(square, 60)
    uniform2d.uniform_mesh(square, 60, resample=0.25)


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


def _reproducer(case, call, n, status, seen, dom):
    kind, outer, holes, segs, points = dom
    rep = {
        "name": f"fuzz_{status}_{kind}_{case[0]}",
        "call": call,
        "n": int(n),
        "seen": seen[:500],
        "outer": np.asarray(outer).tolist(),
        "holes": [np.asarray(h).tolist() for h in holes],
    }
    if len(segs) or len(points):
        rep["segments"] = [np.asarray(x).tolist() for x in segs]
        rep["points"] = np.asarray(points).tolist()
    return rep


def _error_type(seen: str) -> str:
    return seen.split(":", 1)[0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--domains", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2, help="worker processes")
    ap.add_argument("--limit", type=float, default=120.0, help="seconds per domain before a hang")
    ap.add_argument("--out", type=Path, default=None, help="write the reproducers here (JSON)")
    ap.add_argument("--constrained", type=float, default=0.3,
                    help="fraction of domains with segments and fixed points (default 0.3)")
    ap.add_argument("--resample", type=float, default=0.0, metavar="TOL",
                    help="also mesh every domain with uniform_mesh(P, n, resample=TOL)")
    args = ap.parse_args(argv)

    seeds = [args.seed * 10**9 + i for i in range(args.domains)]
    todo = [(s, bool(np.random.default_rng([s, 3]).uniform() < args.constrained), args.resample)
            for s in seeds]
    todo.reverse()
    counts = {s: 0 for s in ("ok", "refused", "crash", "wrong", "hang")}
    per_call = {}
    refusals = {}
    failures = []
    slots = [s.wait_ready() for s in [_Slot() for _ in range(max(1, args.jobs))]]
    t_start = time.monotonic()
    done = 0

    def record(case, results):
        family = "constrained" if case[1] else "plain"
        for call, n, status, seen, dom in results:
            counts[status] += 1
            per_call.setdefault(call, {}).setdefault(status, 0)
            per_call[call][status] += 1
            if status == "refused":
                key = (family, call, _error_type(seen))
                refusals[key] = refusals.get(key, 0) + 1
            if status in ("crash", "wrong", "hang"):
                rep = _reproducer(case, call, n, status, seen, dom)
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
                dom = draw(s.case)
                seen = f"no answer within {args.limit:g} s"
                record(s.case, [(c, n, "hang", seen, dom) for (c, _), n in zip(_calls(s.case), _ns(s.case))][:1])
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
    if refusals:
        print("refused, by error type:")
        for (family, call, err), k in sorted(refusals.items()):
            print(f"  {family:11s} {call:13s} {err:28s} {k}")
    if args.out is not None:
        args.out.write_text(json.dumps(failures, indent=1) + "\n")
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
