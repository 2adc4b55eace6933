"""Figures of ``docs/surface.md`` (not part of the API).

Run from the repository root::

    python -m surface._figures docs/img

Writes ``surface_cap60_3d.png``, ``surface_cap60_uv.png`` and
``surface_gallery.png`` from the patches in ``data/patches``, and
``surface_atlas.png`` from the example models of :mod:`surface.models`.
"""

from __future__ import annotations

import importlib
import inspect
import io
import sys
from pathlib import Path

import numpy as np

from uniform2d.plot import EDGE_CMAP as CMAP

from .measure import unique_edges
from .parameterize import parameterize
from .io import read_patch
from .remesh import remesh

DATA = Path(__file__).resolve().parent.parent / "data" / "patches"
LIM = (0.6, 1.5)  # colour range of edge length / target
VIEWS = {"cylinder": (20, 60), "cone": (35, -70), "cap60": (30, -60), "plate_hole": (40, -90)}


def _edges3d(ax, V, F, colour=None, values=None, lw=0.4, zoom=1.4):
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
    ax.set_box_aspect(tuple(ext), zoom=zoom)
    ax.set_axis_off()
    return lc


def _save_trimmed(fig, path, dpi=130, pad=12, colours=None):
    """Save ``fig`` cropped to what is drawn: a 3-D axes keeps room for any view of
    its box, which for a flat or low patch is mostly empty."""
    from PIL import Image

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, facecolor="white")
    img = Image.open(buf).convert("RGB")
    ink = np.argwhere((np.asarray(img) < 250).any(axis=2))
    (top, left), (bottom, right) = ink.min(axis=0), ink.max(axis=0)
    box = (max(left - pad, 0), max(top - pad, 0), min(right + pad + 1, img.width),
           min(bottom + pad + 1, img.height))
    img = img.crop(box)
    if colours:  # an adaptive palette: a quarter of the bytes for shaded faces
        img = img.convert("P", palette=Image.ADAPTIVE, colors=colours)
    img.save(path, optimize=True)


def _charts3d(ax, V, F, chart, zoom=1.0):
    """The faces coloured by chart (an atlas's), seams drawn where colours meet."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from matplotlib import colormaps

    colours = colormaps["tab20"](np.asarray(chart) % 20)
    pc = Poly3DCollection(V[F], facecolors=colours, edgecolors="none", linewidths=0)
    ax.add_collection3d(pc)
    _edges3d(ax, V, F, colour="0.25", lw=0.15, zoom=zoom)


def plot_result(result, path) -> None:
    """The figure of ``uniform2d remesh --plot``: the 3-D mesh with its edges
    coloured by length / mean, beside their histogram, and for an atlas the
    faces coloured by chart first; written atomically."""
    import mpl_toolkits.mplot3d  # noqa: F401  (registers the 3-D projection)
    from matplotlib.figure import Figure

    from uniform2d.io.atomic import atomic_write

    V, F = result.vertices, result.faces
    E = unique_edges(F)
    length = np.linalg.norm(V[E[:, 1]] - V[E[:, 0]], axis=1)
    rel = length / length.mean()
    atlas = getattr(result, "chart", None) is not None
    k = 3 if atlas else 2
    fig = Figure(figsize=(5.5 * k, 4.6), layout="constrained")
    if atlas:
        ax = fig.add_subplot(1, k, 1, projection="3d")
        _charts3d(ax, V, F, result.chart)
        ax.set_title(f"atlas: {len(result.atlas.charts)} charts")
    ax = fig.add_subplot(1, k, k - 1, projection="3d")
    lw = float(np.clip(40.0 / np.sqrt(len(E)), 0.2, 1.0))
    # A box shaped like the patch frames it tightly; zoom 1 keeps every view of it inside.
    lc = _edges3d(ax, V, F, values=lambda _E: rel, lw=lw, zoom=1.0)
    fig.colorbar(lc, ax=ax, shrink=0.7, label="3-D edge length / mean")
    h = fig.add_subplot(1, k, k)
    counts, bins = np.histogram(rel, bins=40)
    h.bar(bins[:-1], counts, width=np.diff(bins), align="edge", edgecolor="0.35", linewidth=0.4,
          color=lc.cmap(lc.norm(0.5 * (bins[:-1] + bins[1:]))))
    h.set_xlabel("3-D edge length / mean")
    h.set_ylabel("edges")
    fig.suptitle(f"{len(V)} vertices, {len(F)} faces, edge ratio {length.max() / length.min():.3g}")
    ext = Path(path).suffix
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=150, format=ext[1:].lower()), extension=ext)


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

    fig = plt.figure(figsize=(13, 4.6))
    fig.subplots_adjust(left=0, right=0.9, bottom=0, top=1, wspace=0)
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    _edges3d(ax, cap.vertices, cap.faces, colour="0.35", lw=0.3)
    ax.view_init(30, -60)
    ax.set_title(f"input: {cap.n_vertices} vertices", y=0.9)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    lc = _edges3d(ax, r.vertices, r.faces, values=_len3d(r), lw=0.5)
    ax.view_init(30, -60)
    e = r.report.edges
    ax.set_title(f"remeshed: {n} vertices\nedge ratio {e['ratio']:.2f}, cv {e['cv']:.3f}", y=0.9)
    fig.colorbar(lc, ax=fig.axes, shrink=0.6, label="3-D edge length / target")
    _save_trimmed(fig, out / "surface_cap60_3d.png")
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
    fig.subplots_adjust(left=0, right=0.92, bottom=0, top=0.88, wspace=0.05)
    for i, name in enumerate(names):
        res = remesh(DATA / f"{name}.obj", n, hausdorff=False)
        ax = fig.add_subplot(1, len(names), i + 1, projection="3d")
        lc = _edges3d(ax, res.vertices, res.faces, values=_len3d(res), lw=0.3)
        ax.view_init(*VIEWS[name])
        e = res.report.edges
        ax.set_title(f"{name}\nratio {e['ratio']:.2f}, cv {e['cv']:.3f}", fontsize=10)
    fig.colorbar(lc, ax=fig.axes, shrink=0.6, label="3-D edge length / target")
    _save_trimmed(fig, out / "surface_gallery.png")
    plt.close(fig)
    atlas_gallery(out)


def atlas_gallery(out, n=2000):
    """``surface_atlas.png``: whole models, charts coloured above, edges below."""
    import matplotlib.pyplot as plt

    from . import models

    names = ["sphere", "torus", "tank", "two_hole_plate"]
    fig = plt.figure(figsize=(16, 8))
    fig.subplots_adjust(left=0, right=0.92, bottom=0, top=0.92, wspace=0.05, hspace=0.05)
    for i, name in enumerate(names):
        V, F = models.MODELS[name]()
        res = remesh((V, F), n, feature_angle=30, hausdorff=False)
        ax = fig.add_subplot(2, len(names), i + 1, projection="3d")
        _charts3d(ax, res.vertices, res.faces, res.chart, zoom=1.2)
        ax.view_init(25, -60)
        ax.set_title(f"{name}: {len(res.atlas.charts)} charts", fontsize=10)
        ax = fig.add_subplot(2, len(names), len(names) + i + 1, projection="3d")
        lc = _edges3d(ax, res.vertices, res.faces, values=_len3d(res), lw=0.3, zoom=1.2)
        ax.view_init(25, -60)
        e = res.report.edges
        ax.set_title(f"ratio {e['ratio']:.2f}, cv {e['cv']:.3f}, worst angle {e['angle_min']:.0f} deg",
                     fontsize=10, y=0.95)
    fig.colorbar(lc, ax=fig.axes, shrink=0.5, label="3-D edge length / target")
    _save_trimmed(fig, Path(out) / "surface_atlas.png", colours=128)
    plt.close(fig)


if __name__ == "__main__":
    main(*(sys.argv[1:2] or ["docs/img"]))
