"""Fingerprints of the meshes uniform2d makes, to check that a restructuring changed no bit.

Prints one line per case: its name, the sha256 of ``points.tobytes() +
triangles.tobytes()`` (float64 points, int64 triangles, C order) and a few cheap
figures for a human reader.  Run it before and after a change and compare the
outputs (``diff``); any differing hash is a changed mesh.

Cases:

* the benchmark polygons (``data/benchmarks/*.json``): :func:`uniform2d.uniform_mesh`
  at each ``--n`` (default 200, 1000, 10000), :func:`uniform2d.tplus` and
  :func:`uniform2d.insert` at n = 200;
* the bundled polygons (``data/*.json``): uniform_mesh, tplus and insert at n = 200;
* the square moved far from the origin and scaled down (the kernel's translated,
  re-certified path): uniform_mesh, tplus and insert at n = 200;
* the surface patches (``data/patches/*.obj``, and any ``--patches`` given):
  ``surface.remesh`` at 600 vertices, lattice + optimiser (default) and INSERT
  alone (``optimize=False``), and the MeshLab peer's isotropic remeshing at the
  patch's size for 600 vertices (skipped if the surface extra is missing);
  with ``--tuned`` also the MeshLab peer tuned to 600 vertices;
* the whole models (``data/models/*.obj``): ``surface.remesh`` at 1000 vertices
  with ``feature_angle=30`` (an atlas of charts).

Run:  python benchmarks/hash_meshes.py [--n 200 1000 10000] [--patches DIR ...] > hashes.txt
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

import numpy as np

import _checkout  # noqa: F401  (measure this checkout, not an installed uniform2d)
import uniform2d
from uniform2d.io import read_polygon

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


def digest(points, triangles) -> str:
    p = np.ascontiguousarray(points, dtype=np.float64)
    t = np.ascontiguousarray(triangles, dtype=np.int64)
    return hashlib.sha256(p.tobytes() + t.tobytes()).hexdigest()


def emit(name: str, points, triangles, figures: str = "") -> None:
    print(f"{name:40s} {digest(points, triangles)}  {len(points)} pts {len(triangles)} tri {figures}")
    sys.stdout.flush()


def planar(name: str, poly, ns, small: int = 200) -> None:
    for n in ns:
        m = uniform2d.uniform_mesh(poly, n)
        q = m.quality()
        emit(
            f"{name} uniform n={n}", m.points, m.triangles,
            f"ratio {q.edge_ratio:.6f} cv {q.cv_edge:.6f} fallback {m.info.get('fallback')}",
        )
    t = uniform2d.tplus(poly, small)
    emit(f"{name} tplus n={small}", t.points, t.triangles, f"d_n {t.info['d_n']:.9g} k {t.info['k']}")
    r = uniform2d.insert(poly, small)
    emit(f"{name} insert n={small}", r.mesh_points, r.triangles, f"last weight {r.weights[-1]:.9g}")


def patches(paths, tuned: bool) -> None:
    try:
        import surface
        from uniform2d.peers import meshlab_peer
    except ImportError as exc:
        print(f"# surface cases skipped: {exc}")
        return
    for path in paths:
        for optimize in (True, False):
            res = surface.remesh(path, 600, check=False, hausdorff=False, optimize=optimize)
            emit(
                f"{path.stem} remesh 600 optimize={optimize}", res.vertices, res.faces,
                f"uv {digest(res.uv, res.faces)[:16]} cv {res.report.edges['cv']:.6f}",
            )
        patch = surface.read_patch(path)
        size = uniform2d.peers.size_for_count(patch.area, 0.0, 600)
        V, F = meshlab_peer.mesh_with_size(patch.vertices, patch.faces, size)
        emit(f"{path.stem} meshlab size={size:.6g}", V, F)
        if tuned:
            pm = meshlab_peer.mesh((patch.vertices, patch.faces), 600)
            emit(f"{path.stem} meshlab tuned to 600", pm.points, pm.triangles, f"size {pm.size!r}")


def models(paths) -> None:
    try:
        import surface
    except ImportError as exc:
        print(f"# model cases skipped: {exc}")
        return
    for path in paths:
        res = surface.remesh(path, 1000, feature_angle=30, check=False, hausdorff=False)
        emit(f"{path.stem} atlas 1000", res.vertices, res.faces,
             f"charts {len(res.atlas.charts)} cv {res.report.edges['cv']:.6f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[200, 1000, 10000])
    ap.add_argument("--patches", type=Path, nargs="*", default=[], help="more folders of .obj patches")
    ap.add_argument("--tuned", action="store_true", help="also the MeshLab peer tuned to 600 vertices")
    args = ap.parse_args(argv)
    for path in sorted((DATA / "benchmarks").glob("*.json")):
        planar(path.stem, read_polygon(path), args.n)
    for path in sorted(DATA.glob("*.json")):
        planar(path.stem, read_polygon(path), [200])
    square = read_polygon(DATA / "benchmarks" / "square.json")
    planar("square far", square.transformed(1e-3, (1e6, -3e5)), [200])
    found = sorted((DATA / "patches").glob("*.obj"))
    for folder in args.patches:
        found += sorted(folder.glob("*.obj"))
    patches(found, args.tuned)
    models(sorted((DATA / "models").glob("*.obj")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
