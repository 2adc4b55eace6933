"""Figures of ``docs/surface.md`` (not part of the API).

Run from the repository root::

    python -m surface._figures docs/img

Writes ``surface_cap60_3d.png``, ``surface_cap60_uv.png`` and
``surface_gallery.png`` from the patches in ``data/patches``.
"""

from __future__ import annotations

import importlib
import inspect
import sys
from pathlib import Path

import numpy as np

from .measure import unique_edges
from .parameterize import parameterize
from .io import read_patch
from .remesh import remesh

DATA = Path(__file__).resolve().parent.parent / "data" / "patches"
CMAP = "coolwarm"
LIM = (0.6, 1.5)  # colour range of edge length / target
VIEWS = {"cylinder": (20, 60), "cone": (35, -70), "cap60": (30, -60), "plate_hole": (40, -90)}


def _edges3d(ax, V, F, colour=None, values=None, lw=0.4):
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    E = unique_edges(F)
    seg = V[E]
    lc = Line3DCollection(seg, linewidths=lw)
    if values is not None:
        lc.set_array(values(E))
        lc.set_cmap(CMAP)
        lc.set_clim(*LIM)
    else:
        lc.set_color(colour or "0.4")
    ax.add_collection3d(lc)
    lo, hi = V.min(0), V.max(0)
    ext = np.maximum(hi - lo, 1e-3 * (hi - lo).max())
    ax.set_xlim(lo[0], lo[0] + ext[0])
    ax.set_ylim(lo[1], lo[1] + ext[1])
    ax.set_zlim(lo[2], lo[2] + ext[2])
    ax.set_box_aspect(tuple(ext), zoom=1.25)
    ax.set_axis_off()
    return lc


def _len3d(r):
    h = r.report.target_size
    return lambda E: np.linalg.norm(r.vertices[E[:, 1]] - r.vertices[E[:, 0]], axis=1) / h


def _edges2d(ax, P, F, values):
    from matplotlib.collections import LineCollection

    E = unique_edges(F)
    lc = LineCollection(P[E], linewidths=0.5, cmap=CMAP)
    lc.set_array(values(E))
    lc.set_clim(*LIM)
    ax.add_collection(lc)
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_axis_off()
    return lc


def _core_has_size() -> bool:
    ins = importlib.import_module("uniform2d.insert").insert
    return "size" in inspect.signature(ins).parameters


def main(outdir="docs/img", n=1000):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    cap = read_patch(DATA / "cap60.obj")
    r = remesh(cap, n)

    fig = plt.figure(figsize=(13, 5.5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    _edges3d(ax, cap.vertices, cap.faces, colour="0.35", lw=0.3)
    ax.view_init(30, -60)
    ax.set_title(f"input: {cap.n_vertices} vertices")
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    lc = _edges3d(ax, r.vertices, r.faces, values=_len3d(r), lw=0.5)
    ax.view_init(30, -60)
    e = r.report.edges
    ax.set_title(f"remeshed: {n} vertices\nedge ratio {e['ratio']:.2f}, cv {e['cv']:.3f}")
    fig.colorbar(lc, ax=fig.axes, shrink=0.6, label="3-D edge length / target")
    fig.savefig(out / "surface_cap60_3d.png", dpi=130, bbox_inches="tight")
    plt.close(fig)

    prm = parameterize(cap)
    panels = [("off", remesh(cap, n, compensate=False, hausdorff=False))]
    if _core_has_size():
        panels.append(("on", r))
    fig, axes = plt.subplots(1, 1 + len(panels), figsize=(5 * (1 + len(panels)), 4.8))
    tp = axes[0].tripcolor(
        prm.uv[:, 0], prm.uv[:, 1], cap.faces, facecolors=prm.area_scale, cmap="viridis"
    )
    axes[0].set_aspect("equal")
    axes[0].set_axis_off()
    axes[0].set_title("LSCM area scale (UV area / 3-D area)")
    fig.colorbar(tp, ax=axes[0], shrink=0.7)
    for ax, (label, res) in zip(axes[1:], panels):
        lc = _edges2d(ax, res.uv, res.faces, _len3d(res))
        ax.set_title(
            f"UV mesh, compensation {label}\n3-D size trend {res.report.size_trend:+.2f}"
        )
    fig.colorbar(lc, ax=list(axes[1:]), shrink=0.7, label="3-D edge length / target")
    fig.savefig(out / "surface_cap60_uv.png", dpi=130, bbox_inches="tight")
    plt.close(fig)

    names = ["cylinder", "cone", "cap60", "plate_hole"]
    fig = plt.figure(figsize=(16, 4.5))
    for i, name in enumerate(names):
        res = remesh(DATA / f"{name}.obj", n, hausdorff=False)
        ax = fig.add_subplot(1, len(names), i + 1, projection="3d")
        lc = _edges3d(ax, res.vertices, res.faces, values=_len3d(res), lw=0.3)
        ax.view_init(*VIEWS[name])
        e = res.report.edges
        ax.set_title(f"{name}\nratio {e['ratio']:.2f}, cv {e['cv']:.3f}", fontsize=10)
    fig.colorbar(lc, ax=fig.axes, shrink=0.6, label="3-D edge length / target")
    fig.savefig(out / "surface_gallery.png", dpi=130, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    main(*(sys.argv[1:2] or ["docs/img"]))
