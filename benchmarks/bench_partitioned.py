"""Benchmark: partitioned meshes (``uniform_mesh(polygon, n, parts=K)``), in one run.

Usage::

    python benchmarks/bench_partitioned.py [--quick] [--quality-n N] [--speed-n N]
        [--parts K] [--workers W] [--sim-n N] [--sim-parts K] [--sim-run R] [--no-gmsh]

Every configuration runs in a fresh process (its peak RSS is its own) on the
polygon ``data/benchmarks/square2holes.json``:

1. **Quality** at ``--quality-n`` (1e6) Steiner points: the unpartitioned mesh
   and the one in ``--parts`` (16) parts on a local Dask cluster of
   ``--workers`` (all cores) worker processes; edge ratio and CV of both and
   their ratios (goals: within 1.1x and 1.05x), exactly n, both valid
   (:func:`uniform2d.testing.check_mesh`), and the seams' CV (edges within 2 h
   of a cut) before and after the seam relaxation against the CV away from them.
2. **Speed** at ``--speed-n`` (1e7): wall time of the single-process mesh, of
   the partitioned one gathered and stitched (cluster start not counted), of
   the partitioned one written as a ``.pvtu`` piece by piece (never gathered),
   and Gmsh's ``generate()`` at the same vertex count or at ``--gmsh-n`` (one
   size, from the vertex-count formula); peak RSS of this process and of every
   worker.
3. **Scale**: 1e8 points cannot run here; the partition of ``--sim-n`` (1e8)
   in ``--sim-parts`` (256) parts is made (its time and memory are the
   coordinator's), ``--sim-run`` (2) of its parts are run one by one as a
   worker runs them for a ``.pvtu`` (meshed, checked, written as a piece), in a
   fresh process each given only its part (time, peak RSS: what one worker
   needs), and the run is
   extrapolated: per-worker memory = a part's peak, wall time = parts /
   workers x a part's time.

``--quick`` runs small stand-ins (1e4, 3e4, 4 parts, sim 1e6 in 16 parts) to
check the script.  Timings are of this machine as it is now.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pickle
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

POLYGON = ROOT / "data" / "benchmarks" / "square2holes.json"


def _peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _load_kernels() -> None:
    """Load the compiled kernels (numba's disk cache) with two tiny meshes, so that
    no timed run includes it; also run on every Dask worker."""
    from uniform2d import Polygon, uniform_mesh

    sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    uniform_mesh(sq, 300)
    uniform_mesh(sq, 600, parts=2)


def _worker_peak() -> float:  # runs on a Dask worker
    import resource as r

    return r.getrusage(r.RUSAGE_SELF).ru_maxrss / 1024.0


def _quality(polygon, mesh, check: bool) -> dict:
    from uniform2d.testing import check_mesh

    q = mesh.quality()
    out = {"edge_ratio": q.edge_ratio, "cv": q.cv_edge, "n_steiner": mesh.n_steiner}
    if check:
        t = time.perf_counter()
        check_mesh(mesh.points, mesh.triangles, polygon, n_steiner=mesh.n_steiner)
        out["valid"] = True
        out["check_s"] = time.perf_counter() - t
    return out


def _cluster(workers: int):
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    client = Client(cluster)
    client.run(_load_kernels)
    _load_kernels()
    return cluster, client


def one(cfg: dict) -> dict:
    """One configuration, here (the parent runs each in a fresh process)."""
    import uniform2d
    from uniform2d import read_polygon, uniform_mesh

    polygon = read_polygon(POLYGON)
    n, kind = int(cfg["n"]), cfg["kind"]
    out = {"kind": kind, "n": n}
    if kind == "plain":
        _load_kernels()
        t = time.perf_counter()
        mesh = uniform_mesh(polygon, n)
        out["seconds"] = time.perf_counter() - t
        out["peak_mib"] = _peak_mib()
        out.update(_quality(polygon, mesh, cfg.get("check", False)))
        import numpy as np

        from uniform2d.partition import partition
        from uniform2d.partitioned import seam_uniformity

        if cfg.get("parts"):  # the same measure on the unpartitioned mesh, at the same cuts
            part = partition(polygon, n, cfg["parts"])
            seam = part.points[np.concatenate(part.cuts)]
            out["seams"] = seam_uniformity(mesh.points, mesh.triangles, seam, part.h)
    elif kind in ("parts", "pvtu"):
        cluster, client = _cluster(cfg["workers"])
        try:
            t = time.perf_counter()
            if kind == "parts":
                mesh = uniform_mesh(polygon, n, parts=cfg["parts"], scheduler=client)
                out["seconds"] = time.perf_counter() - t
                out["peak_mib"] = _peak_mib()
                out.update(_quality(polygon, mesh, cfg.get("check", False)))
                out["seams_before_relax"] = mesh.info["seams_before_relax"]
                out["seams"] = mesh.info["seams"]
                out["phases"] = mesh.info["times"]
            else:
                from uniform2d.partitioned import write_pvtu

                with tempfile.TemporaryDirectory() as d:
                    info = write_pvtu(polygon, n, cfg["parts"], Path(d) / "big.pvtu",
                                      scheduler=client)
                    out["seconds"] = time.perf_counter() - t
                    out["bytes"] = sum(f.stat().st_size for f in Path(d).rglob("*") if f.is_file())
                out["peak_mib"] = _peak_mib()
                out["points"] = info["points"]
            out["worker_peak_mib"] = sorted(client.run(_worker_peak).values())
        finally:
            client.close()
            cluster.close()
    elif kind == "gmsh":
        import bench_uniform

        N = n + len(polygon.vertices)
        size = math.sqrt(polygon.area / (N * math.sqrt(3) / 2))
        pts, tri, dt = bench_uniform.gmsh_mesh(polygon, size)
        q = uniform2d.quality(pts, tri)
        out.update(seconds=dt, vertices=len(pts), peak_mib=_peak_mib(), edge_ratio=q.edge_ratio,
                   cv=q.cv_edge)
    elif kind == "sim_partition":
        from uniform2d.partitioned import _plan

        t = time.perf_counter()
        part, items = _plan(polygon, n, cfg["parts"], "balanced")
        out["seconds"] = time.perf_counter() - t
        out["peak_mib"] = _peak_mib()
        out["cut_points"] = part.n_cut
        out["part_points"] = [sum(it[1]) for it in items]
        # each part as write_pvtu hands it to a worker (its piece's path set later)
        import numpy as np

        own = np.cumsum([0] + [c for it in items for c in it[1]])
        full, k = [], 0
        for it, idx in zip(items, part.index):
            full.append((*it, idx, [int(len(part.points) + own[k + j]) for j in range(len(idx))]))
            k += len(idx)
        with open(cfg["items"], "wb") as f:  # for the parts, each in its own process
            pickle.dump(full, f)
    elif kind == "sim_part":
        from uniform2d.partitioned import write_part

        with open(cfg["items"], "rb") as f:
            item = pickle.load(f)[cfg["index"]]
        _load_kernels()
        base = _peak_mib()
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            write_part((*item, str(Path(d) / "piece.vtu")))  # meshed, checked, written
            out["seconds"] = time.perf_counter() - t
        out["peak_mib"] = _peak_mib()
        out["peak_before_mib"] = base
        out["points"] = sum(item[1])
    return out


def run(cfg: dict) -> dict:
    """``one(cfg)`` in a fresh process (its own peak RSS)."""
    cmd = [sys.executable, __file__, "--one", json.dumps(cfg)]
    t = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=False,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    if res.returncode != 0:
        raise RuntimeError(f"{cfg}: {res.stderr[-2000:]}")
    out = json.loads(res.stdout.strip().splitlines()[-1])
    out["process_s"] = time.perf_counter() - t
    print(f"  {cfg['kind']:<14} n={cfg['n']:.0e}: {out.get('seconds', 0):8.1f} s, "
          f"peak {out.get('peak_mib', 0):7.0f} MiB", flush=True)
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--one", help=argparse.SUPPRESS)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--quality-n", type=float, default=1e6)
    p.add_argument("--speed-n", type=float, default=1e7)
    p.add_argument("--parts", type=int, default=16)
    p.add_argument("--workers", type=int, default=os.cpu_count())
    p.add_argument("--sim-n", type=float, default=1e8)
    p.add_argument("--sim-parts", type=int, default=256)
    p.add_argument("--sim-run", type=int, default=2)
    p.add_argument("--sim-workers", type=int, default=64)
    p.add_argument("--no-gmsh", action="store_true")
    p.add_argument("--gmsh-n", type=float, help="Gmsh's size, if not --speed-n (Gmsh at 1e7 "
                   "takes minutes and GBs)")
    p.add_argument("--skip", nargs="*", default=[], choices=("quality", "speed", "scale"))
    a = p.parse_args(argv)
    if a.one:
        print(json.dumps(one(json.loads(a.one))))
        return 0
    if a.quick:
        a.quality_n, a.speed_n, a.parts, a.sim_n, a.sim_parts = 1e4, 3e4, 4, 1e6, 16
    K, W = a.parts, a.workers
    res = {}
    print(f"polygon {POLYGON.name}, K = {K} parts, {W} workers")
    if "quality" not in a.skip:
        nq = int(a.quality_n)
        print(f"quality at n = {nq:.0e}")
        res["q_plain"] = run({"kind": "plain", "n": nq, "check": True, "parts": K})
        res["q_parts"] = run({"kind": "parts", "n": nq, "parts": K, "workers": W, "check": True})
    if "speed" not in a.skip:
        ns = int(a.speed_n)
        print(f"speed at n = {ns:.0e}")
        res["s_plain"] = run({"kind": "plain", "n": ns})
        res["s_parts"] = run({"kind": "parts", "n": ns, "parts": K, "workers": W})
        res["s_pvtu"] = run({"kind": "pvtu", "n": ns, "parts": K, "workers": W})
        if not a.no_gmsh:
            res["s_gmsh"] = run({"kind": "gmsh", "n": int(a.gmsh_n or ns)})
    if "scale" not in a.skip:
        nn = int(a.sim_n)
        print(f"scale: n = {nn:.0e} in {a.sim_parts} parts (simulated)")
        with tempfile.TemporaryDirectory() as d:
            items = str(Path(d) / "items.pickle")
            res["sim_partition"] = run({"kind": "sim_partition", "n": nn, "parts": a.sim_parts,
                                        "items": items})
            res["sim_parts"] = [run({"kind": "sim_part", "n": nn, "index": i, "items": items})
                                for i in range(a.sim_run)]
    report(res, a)
    return 0


def _phases(r: dict) -> str:
    return ", ".join(f"{k} {v:.1f} s" for k, v in r.get("phases", {}).items())


def _ok(x: bool) -> str:
    return "met" if x else "NOT met"


def report(res: dict, a) -> None:
    print("\n== results ==")
    if "q_plain" in res:
        qp, qk = res["q_plain"], res["q_parts"]
        r_ratio = qk["edge_ratio"] / qp["edge_ratio"]
        r_cv = qk["cv"] / qp["cv"]
        print(f"quality n = {qp['n']:.0e}, K = {a.parts}:")
        print(f"  edge ratio  plain {qp['edge_ratio']:.4f}  parts {qk['edge_ratio']:.4f}  "
              f"x{r_ratio:.3f} (goal <= 1.1: {_ok(r_ratio <= 1.1)})")
        print(f"  CV          plain {qp['cv']:.5f}  parts {qk['cv']:.5f}  x{r_cv:.3f} "
              f"(goal <= 1.05: {_ok(r_cv <= 1.05)})")
        print(f"  exactly n: plain {qp['n_steiner'] == qp['n']}, parts {qk['n_steiner'] == qk['n']}; "
              f"valid (check_mesh): plain {qp.get('valid')}, parts {qk.get('valid')}")
        sb, sa, sp = qk["seams_before_relax"], qk["seams"], qp.get("seams", {})
        print(f"  CV within 2h of cuts: before relaxation {sb['cv_near_seams']:.5f}, after "
              f"{sa['cv_near_seams']:.5f}; away {sa['cv_away']:.5f} ({sa['near_edges']} edges near); "
              f"unpartitioned mesh at the same places {sp.get('cv_near_seams', float('nan')):.5f} "
              f"/ away {sp.get('cv_away', float('nan')):.5f}")
        print(f"  time: plain {qp['seconds']:.1f} s, parts on {a.workers} workers {qk['seconds']:.1f} s "
              f"({_phases(qk)})")
    if "s_plain" in res:
        sp, sk, sv = res["s_plain"], res["s_parts"], res["s_pvtu"]
        print(f"speed n = {sp['n']:.0e}, K = {a.parts}, {a.workers} workers:")
        print(f"  single process        {sp['seconds']:8.1f} s  peak {sp['peak_mib']:7.0f} MiB")
        print(f"  parts, gathered       {sk['seconds']:8.1f} s  x{sp['seconds'] / sk['seconds']:.2f} "
              f"faster; coordinator peak {sk['peak_mib']:.0f} MiB, workers "
              f"{', '.join(f'{m:.0f}' for m in sk['worker_peak_mib'])} MiB ({_phases(sk)})")
        print(f"  parts, .pvtu pieces   {sv['seconds']:8.1f} s  x{sp['seconds'] / sv['seconds']:.2f} "
              f"faster; coordinator peak {sv['peak_mib']:.0f} MiB, workers "
              f"{', '.join(f'{m:.0f}' for m in sv['worker_peak_mib'])} MiB "
              f"(whole / K = {sp['peak_mib'] / a.parts:.0f} MiB)")
        if "s_gmsh" in res:
            g = res["s_gmsh"]
            print(f"  gmsh generate()       {g['seconds']:8.1f} s  at n = {g['n']:.0e} ({g['vertices']} vertices, peak "
                  f"{g['peak_mib']:.0f} MiB, edge ratio {g['edge_ratio']:.3f}, CV {g['cv']:.4f})")
    if "sim_partition" in res:
        sp, parts = res["sim_partition"], res["sim_parts"]
        t = sum(x["seconds"] for x in parts) / len(parts)
        mem = max(x["peak_mib"] for x in parts)
        grow = max(x["peak_mib"] - x["peak_before_mib"] for x in parts)
        pts = sum(x["points"] for x in parts) / len(parts)
        K, W = a.sim_parts, a.sim_workers
        print(f"scale n = {sp['n']:.0e} in {K} parts (simulated: {len(parts)} parts run):")
        print(f"  coordinator: partition {sp['seconds']:.1f} s, peak {sp['peak_mib']:.0f} MiB, "
              f"{sp['cut_points']} cut points")
        print(f"  one part: {pts:.0f} points, {t:.1f} s, peak {mem:.0f} MiB ({grow:.0f} MiB above "
              "the process with its kernels loaded)")
        print(f"  extrapolated: {W} workers of >= {mem / 1024:.1f} GiB each, parts "
              f"{K / W * t / 60:.1f} min + partition {sp['seconds'] / 60:.1f} min "
              f"(one worker: {K * t / 3600:.1f} h)")


if __name__ == "__main__":
    raise SystemExit(main())
