"""Benchmark: constrained domains, ours against Gmsh with the same points and curves embedded.

Usage::

    python benchmarks/bench_constrained.py [--n 300 1000] [--case NAME ...] [--no-ours]

Cases: the constrained examples of ``data/constrained/`` (a slab with column supports,
an opening and a stiffener; a roof panel with a ridge and two valleys; a plate with a
doubler zone; ``mixed``, a square with a hole, an edge-to-edge wall, a closed zone, a
free stiffener, a bent segment ending near the hole and fixed points on and off the
segments).

For every case and n it makes:

* ``ours``: ``uniform2d.uniform_mesh(polygon, n)`` (exactly n Steiner points);
* ``T+``: the paper's ``uniform2d.tplus(polygon, n)``;
* ``gmsh``: Gmsh's Frontal-Delaunay with every segment piece and fixed point embedded
  (``uniform2d.peers.gmsh_peer``), its size bisected until its vertex count is
  |V| + n, or as close as the bisection gets.

and prints, for each mesh: vertices, edge ratio, longest edge and largest perimeter
over their lower bounds (``uniform2d.quality`` with the same n and T+'s d_n for all),
the edge-length CV, the smallest angle, the time, and whether the mesh conforms (every
segment a chain of its edges, every fixed point a vertex, the regions tiled: checked by
``uniform2d.mesh_regions``).  A mesher that refuses a case (a uniform2d error, e.g. while
constraints are not supported by one of its steps, or an ``InternalError``) is listed
with the error's type.
The last line says whether ours beats Gmsh on both edge ratio and CV in every case.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

import _checkout  # noqa: E402, F401  (measure this checkout, not an installed uniform2d)
import uniform2d  # noqa: E402
from uniform2d.errors import InternalError, Uniform2dError  # noqa: E402
from uniform2d.mesh_regions import polygon_vertices_first, triangle_regions  # noqa: E402


def cases() -> dict[str, uniform2d.Polygon]:
    return {p.stem: uniform2d.read_polygon(p)
            for p in sorted((ROOT / "data" / "constrained").glob("*.json"))}


def conforms(polygon, points, triangles) -> bool:
    try:
        pts, tri = polygon_vertices_first(polygon, points, triangles)
        triangle_regions(polygon, pts, tri)
        return True
    except Uniform2dError:
        return False


def _timed(make):
    t0 = time.perf_counter()
    try:
        out = make()
    except (Uniform2dError, InternalError) as exc:
        return None, time.perf_counter() - t0, type(exc).__name__
    return out, time.perf_counter() - t0, None


def row(name, polygon, n, points, triangles, seconds, d_n) -> dict:
    # without T+'s d_n the bounds use no packing term (d_n=False: nothing is run for it)
    q = uniform2d.quality(points, triangles, polygon, n_steiner=n,
                          d_n=d_n if d_n is not None else False)
    return {"mesher": name, "vertices": len(points), "ratio": q.edge_ratio,
            "long": q.longest_edge_bound.factor, "perim": q.max_perimeter_bound.factor,
            "cv": q.cv_edge, "min_angle": q.min_angle, "time": seconds,
            "conforms": conforms(polygon, points, triangles)}


def run_case(polygon, n: int, with_ours: bool) -> list:
    rows = []
    tp, t_tp, err = _timed(lambda: uniform2d.tplus(polygon, n))
    d_n = tp.info.get("d_n") if tp is not None else None
    rows.append(row("T+", polygon, n, tp.points, tp.triangles, t_tp, d_n) if tp is not None
                else {"mesher": "T+", "refused": err})
    if with_ours:
        ours, t_ours, err = _timed(lambda: uniform2d.uniform_mesh(polygon, n))
        rows.append(row("ours", polygon, n, ours.points, ours.triangles, t_ours, d_n)
                    if ours is not None else {"mesher": "ours", "refused": err})
    from uniform2d.peers import gmsh_peer

    t0 = time.perf_counter()
    g = gmsh_peer.mesh(polygon, len(polygon.vertices) + n)
    rows.append(row("gmsh", polygon, n, g.points, g.triangles, time.perf_counter() - t0, d_n))
    return rows


def _print(rows) -> None:
    for r in rows:
        if "refused" in r:
            print(f"  {r['mesher']:5s} refused: {r['refused']}")
            continue
        print(f"  {r['mesher']:5s} {r['vertices']:6d} {r['ratio']:7.3f} {r['long']:7.3f} "
              f"{r['perim']:7.3f} {r['cv']:7.4f} {r['min_angle']:7.2f} {r['time']:7.2f}s  "
              f"{'yes' if r['conforms'] else 'NO'}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, nargs="+", default=[300, 1000])
    ap.add_argument("--case", nargs="+", help="only these cases")
    ap.add_argument("--no-ours", action="store_true", help="skip uniform_mesh")
    args = ap.parse_args(argv)
    all_cases = cases()
    chosen = args.case or list(all_cases)
    wins, angles = [], []
    print("mesher  verts   ratio long/LB perim/LB     CV  min ang    time  conforms")
    for name in chosen:
        for n in args.n:
            print(f"{name}, n = {n}")
            rows = run_case(all_cases[name], n, not args.no_ours)
            _print(rows)
            by = {r["mesher"]: r for r in rows if "refused" not in r}
            if "ours" in by and "gmsh" in by:
                wins.append(by["ours"]["ratio"] < by["gmsh"]["ratio"]
                            and by["ours"]["cv"] < by["gmsh"]["cv"] and by["ours"]["conforms"])
                angles.append(by["ours"]["min_angle"] >= by["gmsh"]["min_angle"])
    if wins:
        print(f"ours better than Gmsh on edge ratio and CV: {sum(wins)} of {len(wins)} cases")
        print(f"our worst angle at least Gmsh's (issue 34): {sum(angles)} of {len(angles)} cases")
    else:
        print("ours made no mesh to compare (see 'refused' above)")
    return 0 if wins and all(wins) else 1


if __name__ == "__main__":
    sys.exit(main())
