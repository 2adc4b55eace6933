"""Benchmark: graded meshes with exactly n points, ours against Gmsh given the same h.

Usage::

    python benchmarks/bench_graded.py [--vertices 2000] [--fe-vertices 2000 8000] [--no-fe]
        [--resample TOL] [--sweep]

Cases (each a polygon and a size field h):

* ``lshape-corner``: the L-shape [-1, 1]^2 minus the quadrant x > 0, y < 0, with
  h = 0.02 + 0.6 r (r the distance to the re-entrant corner);
* ``bolt-plate``: ``data/plate_bolts.json`` with ``uniform2d.refine(..., "holes",
  ratio=0.25)`` (size a quarter of the coarse one on the holes, growing at slope 0.3);
* ``bracket``: ``data/l_bracket.json`` with the minimum of refinement near its
  re-entrant corner (the filleted inner one, ratio 0.2) and near its holes (ratio 0.3).

For every case: ours, ``uniform2d.uniform_mesh(polygon, n, size=h)`` with n = vertices
- |V| Steiner points; Gmsh's Frontal-Delaunay with h through its size callback
(``gmsh.model.mesh.setSizeCallback``), the callback's scale bisected until its vertex
count is as close to ours as the bisection gets (``uniform2d.peers.gmsh_peer.graded_mesh``).
Printed: vertices, max q / min q and the CV of q (q = edge length / h(midpoint)), the
smallest angle, the time, and ours against ``uniform_mesh(polygon, n)`` (uniform, the
same n) in time.  Goals: max q / min q <= 1.6 and CV <= 0.06; time <= 1.5x uniform.

Finite elements (scikit-fem, the ``fe`` extra: ``pip install ".[fe,compare]"``; skipped
with a note when missing or with ``--no-fe``):

* L-shape, Poisson with exact solution u = r^(2/3) sin(2 theta / 3) (Dirichlet data
  from u), P1, H1-seminorm error of ours graded, Gmsh graded and ours uniform at the
  same vertex count.
* Bolt plate, plane stress (E = 210000, nu = 0.3), left edge clamped, unit traction
  along x on the right edge, P2 (``benchmarks/plate_fe.py``): the energy-norm error
  sqrt(a(u, u) - a(u_h, u_h)) relative to sqrt(a(u, u)) (Galerkin orthogonality), a(u, u)
  extrapolated from reference solutions refined at the holes and the clamped corners,
  of ours graded, Gmsh graded and ours uniform at each of ``--fe-vertices``, on the
  field ``plate_fe.hole_field(plate, ratio, rate, corners)`` (refined at the holes and
  optionally at the clamped corners) chosen by a stated principle that does not look at
  ours (``plate_fe.PRINCIPLE``: the field of the sweep with the smallest Gmsh error);
  with the share of the squared error near the holes, near the clamped corners and
  elsewhere.  ``--sweep`` prints the whole sweep of ``plate_fe.RATIOS`` x
  ``plate_fe.RATES`` x ``plate_fe.CORNERS`` first and applies the principle to it (slow:
  minutes per field).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

import _checkout  # noqa: E402, F401  (measure this checkout, not an installed uniform2d)
import plate_fe  # noqa: E402
import uniform2d  # noqa: E402
from uniform2d.peers import gmsh_peer  # noqa: E402
from uniform2d.relative import relative_measures  # noqa: E402

LSHAPE = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])


def corner_h(p):
    return 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1])


def cases():
    plate = uniform2d.read_polygon(ROOT / "data" / "plate_bolts.json")
    bracket = uniform2d.read_polygon(ROOT / "data" / "l_bracket.json")
    return {
        "lshape-corner": (LSHAPE, corner_h),
        "bolt-plate": (plate, uniform2d.refine(plate, "holes", ratio=0.25)),
        "bracket": (bracket, uniform2d.minimum_size(
            bracket, uniform2d.refine(bracket, "corners", ratio=0.2),
            uniform2d.refine(bracket, "holes", ratio=0.3))),
    }


def min_angle(P, T):
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    out = []
    for u, v, w in ((a, b, c), (b, c, a), (c, a, b)):
        e1, e2 = v - u, w - u
        cos = (e1 * e2).sum(1) / np.hypot(*e1.T) / np.hypot(*e2.T)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return float(np.min(out))


def timed(f, *a, **k):
    t = time.perf_counter()
    r = f(*a, **k)
    return r, time.perf_counter() - t


def uniformity(vertices: int, resample: float | None = None) -> dict:
    print(f"Relative uniformity at {vertices} vertices (q = edge length / h(midpoint))")
    print(f"  {'case':15s}{'mesher':8s}{'vertices':>9s}{'max/min q':>11s}{'CV q':>8s}"
          f"{'min angle':>11s}{'time s':>8s}")
    if resample is not None:
        print(f"  (ours+rs: an extra row, the rings resampled at h's local spacing, "
              f"resample={resample:g}, the same vertex count)")
    meshes = {}
    for name, (P, h) in cases().items():
        n = vertices - len(P.vertices)
        uniform2d.uniform_mesh(P, n, size=h)  # compiled kernels and caches warm
        ours, t_ours = timed(uniform2d.uniform_mesh, P, n, size=h)
        _, t_uni = timed(uniform2d.uniform_mesh, P, n)
        # Gmsh calls its size callback one point at a time: the same floats without numpy
        h_gmsh = plate_fe.FastField(h) if isinstance(h, uniform2d.SizeField) else h
        g, t_g = timed(gmsh_peer.graded_mesh, P, h_gmsh, len(ours.points))
        meshes[name] = (P, h, ours)
        rows = [("ours", ours.points, ours.triangles, t_ours, ours.size),
                ("gmsh", g.points, g.triangles, t_g, ours.size)]
        if resample is not None:  # an extra row: rings resampled at the local spacing
            n_rs = n
            for _ in range(3):  # the kept vertices are not the input's: same total count
                rs, t_rs = timed(uniform2d.uniform_mesh, P, n_rs, size=h, resample=resample)
                if len(rs.points) == vertices:
                    break
                n_rs += vertices - len(rs.points)
            rows.append(("ours+rs", rs.points, rs.triangles, t_rs, rs.size))
        for who, pts, tri, t, size in rows:
            r = relative_measures(pts, tri, size)
            print(f"  {name:15s}{who:8s}{len(pts):9d}{r.q_ratio:11.3f}{r.q_cv:8.4f}"
                  f"{min_angle(pts, tri):11.2f}{t:8.2f}")
        exact = len(ours.points) == vertices
        print(f"  {'':15s}exactly {vertices} vertices: {exact}; time ours / uniform_mesh "
              f"same n: {t_ours:.2f} / {t_uni:.2f} s = {t_ours / t_uni:.2f}x")
    print("  goals: max/min q <= 1.6, CV q <= 0.06, time <= 1.5x uniform")
    return meshes


# -- finite elements -----------------------------------------------------------------
def lshape_error(P, T) -> float:
    """P1 H1-seminorm error of the L-shape singular solution on the mesh (P, T)."""
    from skfem import Basis, ElementTriP1, Functional, MeshTri, condense, solve
    from skfem.models.poisson import laplace

    m = MeshTri(np.ascontiguousarray(P.T), np.ascontiguousarray(T.T))
    basis = Basis(m, ElementTriP1(), intorder=4)

    def exact(x, y):
        r = np.hypot(x, y)
        th = np.mod(np.arctan2(y, x), 2 * np.pi)
        return r ** (2 / 3) * np.sin(2 * th / 3)

    A = laplace.assemble(basis)
    u = np.zeros(basis.N)
    D = m.boundary_nodes()
    u[D] = exact(*m.p[:, D])
    u = solve(*condense(A, np.zeros(basis.N), x=u, D=D))
    uh = basis.interpolate(u)

    @Functional
    def err(w):
        x, y = w.x
        r2 = np.maximum(x**2 + y**2, 1e-300)
        th = np.mod(np.arctan2(y, x), 2 * np.pi)
        c = (2 / 3) * r2 ** (-1 / 6) / np.sqrt(r2)
        ux = c * (np.sin(2 * th / 3) * x - np.cos(2 * th / 3) * y) / np.sqrt(r2) * np.sqrt(r2)
        uy = c * (np.sin(2 * th / 3) * y + np.cos(2 * th / 3) * x) / np.sqrt(r2) * np.sqrt(r2)
        return (w["uh"].grad[0] - ux) ** 2 + (w["uh"].grad[1] - uy) ** 2

    return float(np.sqrt(err.assemble(basis, uh=uh)))


def fe(meshes, vertices_list, sweep: bool = False) -> None:
    try:
        import skfem  # noqa: F401
    except ImportError:
        print("\nFE errors skipped: scikit-fem is not installed (pip install scikit-fem)")
        return
    P, h, ours = meshes["lshape-corner"]
    n = len(ours.points) - len(P.vertices)
    uni = uniform2d.uniform_mesh(P, n)
    g = gmsh_peer.graded_mesh(P, h, len(ours.points))
    print(f"\nL-shape r^(2/3) singularity, P1, H1-seminorm error (~{len(ours.points)} vertices)")
    for who, pts, tri in (("ours graded", ours.points, ours.triangles),
                          ("gmsh graded", g.points, g.triangles),
                          ("ours uniform", uni.points, uni.triangles)):
        print(f"  {who:14s}{len(pts):7d} vertices   error {lshape_error(pts, tri):.5f}")

    plate_fe.report(meshes["bolt-plate"][0], vertices_list, sweep)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vertices", type=int, default=2000)
    ap.add_argument("--fe-vertices", type=int, nargs="+", default=[2000, 8000])
    ap.add_argument("--no-fe", action="store_true")
    ap.add_argument("--resample", type=float, default=None, metavar="TOL",
                    help="add a row 'ours+rs': the rings resampled at the field's local "
                    "spacing (uniform_mesh resample=TOL), same vertex count")
    ap.add_argument("--sweep", action="store_true",
                    help="bolt plate FE: sweep the field's hole ratio, rate and clamped-corner "
                    "ratio (both meshers on each field) and choose the field by "
                    "plate_fe.PRINCIPLE")
    args = ap.parse_args()
    meshes = uniformity(args.vertices, args.resample)
    if not args.no_fe:
        fe(meshes, args.fe_vertices, args.sweep)


if __name__ == "__main__":
    main()
