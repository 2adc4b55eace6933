"""Make the figures of docs/guide.md (and docs/graded.md).

Run from anywhere (needs only uniform2d and matplotlib)::

    python docs/make_figures.py            # writes docs/img/guide_*.png
    python docs/make_figures.py OUTDIR

Deterministic: the same uniform2d gives the same pictures.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

import uniform2d as u  # noqa: E402
from uniform2d.tplus import boundary_points  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


def _outline(ax, polygon, **kw):
    kw = {"color": "k", "lw": 1.2, **kw}
    for ring in polygon.rings:
        r = np.vstack([ring, ring[:1]])
        ax.plot(r[:, 0], r[:, 1], **kw)


def _edges(ax, points, triangles, **kw):
    kw = {"color": "0.6", "lw": 0.5, **kw}
    ax.triplot(points[:, 0], points[:, 1], triangles, **kw)


def fig_bracket(out: Path) -> None:
    """uniform_mesh of the L-bracket at size 4, as Mesh.plot draws it."""
    bracket = u.read_polygon(DATA / "l_bracket.json")
    mesh = u.uniform_mesh(bracket, size=4.0)
    fig = mesh.plot(out / "guide_bracket.png")
    plt.close(fig)


def fig_insert(out: Path) -> None:
    """Algorithm INSERT on an L-shape: the first points and their weights."""
    poly = u.read_polygon(DATA / "benchmarks" / "lshape.json")
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.3))
    for ax, n in zip(axes, (3, 12, 60)):
        res = u.insert(poly, n)
        P = np.asarray(res.mesh_points)
        _edges(ax, P, np.asarray(res.triangles))
        _outline(ax, poly)
        pts = np.asarray(res.points)
        ax.scatter(pts[:, 0], pts[:, 1], c=np.arange(n), cmap="viridis", s=22, zorder=3)
        # the empty circle of the last point: radius = its weight
        last, w = pts[-1], float(res.weights[-1])
        ax.add_patch(plt.Circle(last, w, fill=False, ls="--", color="tab:red", lw=1))
        ax.set_title(f"n = {n}: last weight w = {w:.3g}")
        ax.set_aspect("equal")
        ax.set_axis_off()
    fig.suptitle("Algorithm INSERT: each point is the one farthest from all sites (colour = order)")
    fig.tight_layout()
    fig.savefig(out / "guide_insert.png", dpi=130)
    plt.close(fig)


def fig_tplus(out: Path) -> None:
    """The two phases of T+ on the star-shaped benchmark polygon."""
    poly = u.read_polygon(DATA / "benchmarks" / "star10.json")
    n = 120
    res1 = u.insert(poly, n)
    d_n = res1.min_distance()
    bpts, _ = boundary_points(poly, 3 * d_n)
    mesh = u.tplus(poly, n)
    P, T = np.asarray(mesh.points), np.asarray(mesh.triangles)
    nv, k = len(poly.vertices), mesh.info["k"]

    fig, axes = plt.subplots(1, 3, figsize=(13, 5))
    ax = axes[0]
    _edges(ax, np.asarray(res1.mesh_points), np.asarray(res1.triangles))
    _outline(ax, poly)
    p1 = np.asarray(res1.points)
    ax.scatter(p1[:, 0], p1[:, 1], s=10, color="0.3", zorder=3)
    ax.set_title(f"phase 1: INSERT n = {n} points\nd_n = {d_n:.3g} (least distance)", fontsize=11)
    ax = axes[1]
    _outline(ax, poly)
    ax.scatter(bpts[:, 0], bpts[:, 1], s=18, color="tab:red", zorder=3,
               label=f"k = {k} boundary points, gaps <= 3 d_n")
    ax.scatter(poly.vertices[:, 0], poly.vertices[:, 1], s=18, color="k", zorder=3, label="V")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02), fontsize=9, ncol=2, frameon=False)
    ax.set_title("boundary points:\nm = ceil(L / 3 d_n) pieces per edge", fontsize=11)
    ax = axes[2]
    _edges(ax, P, T, color="0.45")
    _outline(ax, poly)
    ax.scatter(P[nv:nv + k, 0], P[nv:nv + k, 1], s=12, color="tab:red", zorder=3)
    ax.scatter(P[nv + k:, 0], P[nv + k:, 1], s=12, color="tab:blue", zorder=3)
    q = mesh.quality()
    ax.set_title(f"T+: phase 2 inserts n - k = {n - k} (blue)\nedge ratio {q.edge_ratio:.3g} <= 6",
                 fontsize=11)
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(out / "guide_tplus.png", dpi=130)
    plt.close(fig)


def fig_corner(out: Path) -> None:
    """g(beta), the least edge ratio of a triangle with an angle beta, and the floor
    min over k of g(alpha / k) that a polygon corner alpha puts on every mesh."""
    from uniform2d.bounds import corner_ratio_floor, triangle_ratio_floor

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9.6, 3.8))
    beta = np.linspace(1.0, 179.0, 1000)
    r = np.radians(beta)
    ax1.plot(beta, 2 * np.cos(r), "--", color="0.6", label="2 cos β (angles β, β, 180 − 2β)")
    ax1.plot(beta, 1 / (2 * np.sin(r / 2)), ":", color="0.6", label="1 / (2 sin(β/2)) (apex β, β ≤ 60°)")
    ax1.plot(beta, [triangle_ratio_floor(x) for x in r], color="tab:red", lw=2, label="g(β)")
    ax1.set_ylim(0.9, 3)
    ax1.set_xlabel("an angle β of the triangle (degrees)")
    ax1.set_ylabel("least longest / shortest side")
    ax1.legend(fontsize=7)
    ax1.set_title("one triangle", fontsize=9)
    alpha = np.linspace(1.0, 359.0, 2000)
    ax2.plot(alpha, [corner_ratio_floor(x)[0] for x in np.radians(alpha)], color="tab:red", lw=2)
    for m in range(1, 6):
        ax2.axvline(60 * m, color="0.85", lw=0.8)
    ax2.set_ylim(0.95, 2.1)
    ax2.set_xlabel("interior angle α of a polygon corner (degrees)")
    ax2.set_ylabel("least edge ratio of any mesh")
    ax2.set_title("corner floor min over k of g(α / k)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "guide_corner.png", dpi=130)
    plt.close(fig)


def fig_truss(out: Path) -> None:
    """The truss panel meshed as a truss: members coloured by length."""
    panel = u.read_polygon(DATA / "truss_panel.json")
    mesh = u.uniform_mesh(panel, size=0.5)
    fig = mesh.plot(out / "guide_truss.png", title=(
        f"truss panel, size 0.5 m: {len(mesh.points)} nodes, "
        f"edge ratio {mesh.quality().edge_ratio:.3g}"))
    plt.close(fig)


def fig_constrained(out: Path) -> None:
    """The three constrained examples: regions filled, segments thick, supports dotted."""
    from uniform2d.plot import REGION_COLOURS

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), width_ratios=[9, 10, 8])
    for ax, (name, n) in zip(axes, (("slab_columns", 300), ("roof_panel", 300),
                                    ("plate_zones", 400))):
        poly = u.read_polygon(DATA / "constrained" / f"{name}.json")
        mesh = u.uniform_mesh(poly, n)
        colours = [REGION_COLOURS[r % len(REGION_COLOURS)] for r in mesh.regions.tolist()]
        ax.add_collection(PolyCollection(mesh.points[mesh.triangles], facecolors=colours,
                                         edgecolors="none"))
        _edges(ax, mesh.points, mesh.triangles, color="0.35")
        _outline(ax, poly)
        for seg in poly.segments:
            ax.plot(seg[:, 0], seg[:, 1], color="k", lw=2.4)
        if len(poly.points):
            ax.plot(poly.points[:, 0], poly.points[:, 1], "o", color="k", ms=5)
        labels = ", ".join(str(lab) for lab in mesh.region_labels if lab is not None)
        ax.set_title(f"{name}.json, n = {n}\n{labels}", fontsize=10)
        ax.set_aspect("equal")
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(out / "guide_constrained.png", dpi=130)
    plt.close(fig)


def fig_graded(out: Path) -> None:
    """Graded meshes (docs/graded.md): edges coloured by q = length / h(midpoint)."""
    L = u.Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])
    mesh = u.uniform_mesh(L, 1200, size=lambda p: 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1]))
    plt.close(mesh.plot(out / "graded_lshape.png"))
    plate = u.read_polygon(DATA / "plate_bolts.json")
    mesh = u.uniform_mesh(plate, 2000, size=u.refine(plate, "holes", ratio=0.25))
    plt.close(mesh.plot(out / "graded_plate.png"))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else ROOT / "docs" / "img"
    out.mkdir(parents=True, exist_ok=True)
    for f in (fig_bracket, fig_insert, fig_tplus, fig_corner, fig_truss, fig_constrained,
              fig_graded):
        f(out)
        print(f"{f.__name__}: done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
