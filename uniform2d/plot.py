"""Figures of a mesh: edges coloured by length, and the edge-length distribution.

Uses matplotlib's object-oriented API with no pyplot state, so it is safe in
scripts, servers and tests (nothing is ever shown on screen).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import FuncNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter

from .errors import InvalidArgumentError
from .figure_path import FIGURE_FORMATS, check_figure_path
from .measures import as_points, as_triangles, edge_lengths, histogram
from .io.atomic import atomic_write
from .polygon import as_polygon

__all__ = ["plot_mesh", "check_figure_path", "FIGURE_FORMATS", "EDGE_CMAP"]

log = logging.getLogger(__name__)

#: Perceptual "plasma" without its light yellow end: dark blue = short, magenta =
#: mean, orange = long.  Every colour, the mean's above all, stands out on white.
EDGE_CMAP = ListedColormap(colormaps["plasma"](np.linspace(0.0, 0.8, 256)), name="plasma_on_white")


def _log(x):
    return np.log(np.maximum(x, 1e-300))


def _exp(x):
    return np.exp(x)


def _ratio_ticks(lo: float, hi: float) -> list[float]:
    """Colour-bar ticks between ``lo`` <= 1 <= ``hi``: 1, and on each side the
    largest round ratio inside the range and one about halfway to it (in log scale)."""
    cands = [1.02, 1.05, 1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 1e3, 1e4]
    ticks = {1.0}
    for limit, side in ((hi, 1.0), (1.0 / lo, -1.0)):
        inside = [c for c in cands if c <= limit * (1 + 1e-9)]
        if inside:
            halfway = [c for c in inside if c <= np.sqrt(inside[-1])]
            ticks.update(c ** side for c in inside[-1:] + halfway[-1:])
    return sorted(ticks)


def plot_mesh(points, triangles, path=None, *, polygon=None, title=None, regions=None,
              region_labels=None, size=None) -> Figure:
    """Plot a triangle mesh with each edge coloured by its length, beside a histogram.

    The left panel draws every edge coloured by ``length / mean length`` on a
    log scale centred at 1 (dark blue shorter, magenta the mean, orange longer),
    with the polygon boundary on top; no colour is pale, so every edge shows on
    the white background.  The right panel is the histogram of
    ``length / mean length`` with the mean, shortest and longest edge marked.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Vertex coordinates, float64.  Not modified.
    triangles : array_like, shape (M, 3)
        Vertex indices of each triangle, integers.  Not modified.
    path : str or path-like, optional
        Where to save the figure; the format follows the extension
        (``.png``, ``.pdf`` or ``.svg``).  Not saved if omitted.
    polygon : Polygon, optional
        Boundary drawn over the mesh (a :class:`~uniform2d.Polygon`, a shapely
        Polygon or an outer ring).
    title : str, optional
        Figure title; by default the vertex and triangle counts and edge ratio.
    regions : array_like of int, shape (M,), optional
        The region of every triangle (:attr:`uniform2d.Mesh.regions`): the
        triangles are filled in a light colour per region.  The polygon's
        segments are drawn thicker than the mesh edges, like its rings, and its
        fixed points as dots.
    region_labels : sequence, optional
        The label of each region (None for none): a legend below the mesh names
        the colours of the labelled ones.
    size : callable, optional
        A size field h (a graded mesh's :attr:`uniform2d.Mesh.size`): edges are then
        coloured by q = length / h(midpoint) over its mean, and the histogram is
        that of q (:mod:`uniform2d.relative`).

    Returns
    -------
    matplotlib.figure.Figure
        The figure: ``fig.axes[0]`` the mesh (its edges are the one
        :class:`~matplotlib.collections.LineCollection` there),
        ``fig.axes[1]`` the histogram, ``fig.axes[2]`` the colour bar; with
        ``regions``, the fills are a :class:`~matplotlib.collections.PolyCollection`
        below the edges.

    Raises
    ------
    UnsupportedFormatError
        If ``path`` has an extension other than .png, .pdf or .svg.
    ValueError
        If the arrays have the wrong shape or an index is out of range.

    Examples
    --------
    >>> from uniform2d.plot import plot_mesh
    >>> pts = [(0, 0), (1, 0), (1, 1), (0, 1)]
    >>> fig = plot_mesh(pts, [(0, 1, 2), (0, 2, 3)], polygon=pts)
    >>> len(fig.axes)
    3
    >>> len(fig.axes[0].collections[0].get_segments())      # one segment per edge
    5
    """
    if path is not None:
        check_figure_path(path)
    pts = as_points(points)
    tri = as_triangles(triangles, len(pts))
    if len(tri) == 0:
        raise InvalidArgumentError("triangles: the mesh has no triangles")
    poly = as_polygon(polygon) if polygon is not None else None
    reg = _as_regions(regions, len(tri))

    edges, lengths = edge_lengths(pts, tri)
    if size is not None:  # q = length / h(midpoint): uniformity relative to h
        mid = 0.5 * (pts[edges[:, 0]] + pts[edges[:, 1]])
        lengths = lengths / np.asarray(size(mid), dtype=np.float64)
    mean = float(lengths.mean())
    rel = lengths / mean if mean > 0 else np.ones_like(lengths)
    span, norm, extend = _colour_scale(rel, mean)

    fig = Figure(figsize=(12.0, 5.4), layout="constrained")
    ax_mesh, ax_hist = fig.subplots(1, 2, width_ratios=[1.45, 1.0])
    if reg is not None:
        _region_fill(ax_mesh, pts, tri, reg, region_labels)
    lc = _mesh_panel(fig, ax_mesh, pts, tri, edges, rel, poly, norm, span, extend)
    ratio = _histogram_panel(ax_hist, rel, lengths, mean, lc, norm)
    if size is not None:
        _relative_labels(ax_mesh, ax_hist, lc)
    if title is None:
        what = "max q / min q" if size is not None else "edge ratio"
        title = f"{len(pts)} vertices, {len(tri)} triangles, {what} {ratio:.4g}"
    fig.suptitle(title, fontsize=12)

    if path is not None:
        ext = Path(path).suffix
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=150, format=ext[1:].lower()), extension=ext)
        log.info("wrote %s", path)
    return fig


def _relative_labels(ax_mesh, ax_hist, lc) -> None:
    """The panels' words for q = length / h(midpoint) instead of the length."""
    ax_mesh.set_title("Edges coloured by q / mean q, q = length / h(midpoint)", fontsize=11)
    lc.colorbar.set_label("q / mean q", fontsize=9)
    log_x = ax_hist.get_xscale() == "log"
    ax_hist.set_xlabel("q / mean q" + (" (log scale)" if log_x else ""), fontsize=9)
    ax_hist.set_title("Distribution of q (edge length relative to h)", fontsize=11)


def _as_regions(regions, n_tri: int):
    if regions is None:
        return None
    reg = np.asarray(regions)
    if reg.shape != (n_tri,) or not np.issubdtype(reg.dtype, np.integer) or (n_tri and reg.min() < 0):
        raise InvalidArgumentError(
            f"regions must be one non-negative integer per triangle ({n_tri}), got shape "
            f"{reg.shape} and dtype {reg.dtype}")
    return reg


#: Light fills, one per region (cycled), pale enough for every edge colour to show.
REGION_COLOURS = colormaps["Pastel1"].colors + colormaps["Pastel2"].colors


def _region_fill(ax, pts, tri, reg, labels=None) -> None:
    from matplotlib.patches import Patch

    colours = [REGION_COLOURS[r % len(REGION_COLOURS)] for r in reg.tolist()]
    pc = PolyCollection(pts[tri], facecolors=colours, edgecolors="none", zorder=0)
    ax.add_collection(pc)
    named = [(r, lab) for r, lab in enumerate(labels or ()) if lab is not None]
    if named:
        handles = [Patch(facecolor=REGION_COLOURS[r % len(REGION_COLOURS)], edgecolor="0.3",
                         label=f"{r}: {lab}") for r, lab in named]
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.06),
                  ncol=min(4, len(handles)), fontsize=8, frameon=False)


def _colour_scale(rel, mean):
    """((lo, hi), norm, extend): the colour map spans length / mean in [lo, hi]."""
    # Colour by log(length / mean) over the range the edges span, so that the
    # whole colour map is used: from the 0.2% to the 99.8% quantile, so that a
    # few outliers (shown saturated) do not wash out the rest, and at least
    # 1/1.05 to 1.05 so that a near-uniform mesh is not coloured by its noise.
    if mean > 0 and rel.min() > 0:
        q_lo, q_hi = np.quantile(rel, [0.002, 0.998])
        lo, hi = float(min(q_lo, 1.0 / 1.05)), float(max(q_hi, 1.05))
    else:
        lo, hi = 0.5, 2.0
    norm = FuncNorm((_log, _exp), vmin=lo, vmax=hi)
    extend = {(False, False): "neither", (True, False): "min", (False, True): "max",
              (True, True): "both"}[(bool(rel.min() < lo), bool(rel.max() > hi))]
    return (lo, hi), norm, extend


def _mesh_panel(fig, ax_mesh, pts, tri, edges, rel, poly, norm, span, extend):
    """The edges coloured by length / mean, the boundary on top, and the colour bar."""
    n_e = len(edges)
    lw = float(np.clip(55.0 / np.sqrt(n_e), 0.2, 1.2))
    lc = LineCollection(pts[edges], cmap=EDGE_CMAP, norm=norm, linewidths=lw, capstyle="round")
    lc.set_array(rel)
    lc.set_rasterized(n_e > 20000)  # keep vector files small for big meshes
    ax_mesh.add_collection(lc)
    if poly is not None:
        for ring in poly.rings:
            closed = np.vstack([ring, ring[:1]])
            ax_mesh.plot(closed[:, 0], closed[:, 1], color="0.1", lw=max(1.6 * lw, 0.9), zorder=3)
        for seg in poly.segments:
            ax_mesh.plot(seg[:, 0], seg[:, 1], color="0.1", lw=max(2.4 * lw, 1.4), zorder=3,
                         solid_capstyle="round")
        fixed = poly.points
        if len(fixed):
            ax_mesh.plot(fixed[:, 0], fixed[:, 1], "o", color="0.1", ms=max(4 * lw, 2.5), zorder=4)
    used = pts[np.unique(tri)]
    lo, hi = used.min(axis=0), used.max(axis=0)
    if poly is not None:
        lo = np.minimum(lo, poly.vertices.min(axis=0))
        hi = np.maximum(hi, poly.vertices.max(axis=0))
    pad = 0.03 * float(max(hi - lo)) or 1.0
    ax_mesh.set_xlim(lo[0] - pad, hi[0] + pad)
    ax_mesh.set_ylim(lo[1] - pad, hi[1] + pad)
    ax_mesh.set_aspect("equal")
    ax_mesh.set_title("Edges coloured by length / mean", fontsize=11)
    ax_mesh.tick_params(labelsize=8)
    cb = fig.colorbar(lc, ax=ax_mesh, shrink=0.85, pad=0.02, extend=extend)
    ticks = _ratio_ticks(*span)
    cb.set_ticks(ticks, labels=[f"{t:.3g}" for t in ticks])
    cb.set_label("edge length / mean", fontsize=9)
    cb.ax.tick_params(labelsize=8)
    return lc


def _histogram_bins(ax_hist, rel, n_e):
    """(counts, bin edges, log scale?) of length / mean."""
    # A wide spread (a few very long or short edges) is drawn on a log axis so that
    # the bulk and the outliers are both visible.
    rmin, rmax = float(rel.min()), float(rel.max())
    uniform = rmax - rmin <= 1e-9 * rmax
    log_x = not uniform and rmin > 0 and rmax / rmin > 4.0
    n_bins = int(np.clip(np.sqrt(n_e), 8, 60))
    if uniform:  # all edges (nearly) equal: one narrow bar at their common value
        counts, bin_edges = np.array([n_e]), np.array([rmin - 0.02, rmax + 0.02])
    elif log_x:
        counts, bin_edges = np.histogram(rel, bins=np.geomspace(rmin, rmax, n_bins + 1))
        ax_hist.set_xscale("log")
    else:
        counts, bin_edges = histogram(rel, n_bins)
    return counts, bin_edges, uniform, log_x


def _histogram_panel(ax_hist, rel, lengths, mean, lc, norm) -> float:
    """The histogram of length / mean with the mean and the extremes marked;
    returns the edge ratio."""
    n_e = len(rel)
    rmin, rmax = float(rel.min()), float(rel.max())
    counts, bin_edges, uniform, log_x = _histogram_bins(ax_hist, rel, n_e)
    centres = np.sqrt(bin_edges[:-1] * bin_edges[1:]) if log_x else 0.5 * (bin_edges[:-1] + bin_edges[1:])
    colours = lc.cmap(norm(centres))
    ax_hist.bar(
        bin_edges[:-1], counts, width=np.diff(bin_edges), color=colours,
        edgecolor="0.35", linewidth=0.4, align="edge",
    )
    ax_hist.axvline(1.0, color="0.1", lw=1.4, label=f"mean  {mean:.4g}")
    ax_hist.axvline(rmin, color=EDGE_CMAP(0.0), lw=1.2, ls="--",
                    label=f"shortest  {lengths.min():.4g}  ({rmin:.3f})")
    ax_hist.axvline(rmax, color=EDGE_CMAP(1.0), lw=1.2, ls="--",
                    label=f"longest  {lengths.max():.4g}  ({rmax:.3f})")
    ax_hist.set_xlabel("edge length / mean", fontsize=9)
    ax_hist.set_ylabel("number of edges", fontsize=9)
    ax_hist.set_title("Edge-length distribution", fontsize=11)
    ax_hist.tick_params(labelsize=8)
    ax_hist.set_ylim(0, counts.max() * 1.25 + 0.5)
    if log_x:
        ax_hist.set_xlim(rmin / 1.15, rmax * 1.15)
        plain = FuncFormatter(lambda x, _pos: f"{x:g}")
        ax_hist.xaxis.set_major_formatter(plain)
        if rmax / rmin < 30:  # less than about a decade and a half: label the minor ticks too
            ax_hist.xaxis.set_minor_formatter(plain)
            ax_hist.tick_params(axis="x", which="minor", labelsize=7)
        ax_hist.set_xlabel("edge length / mean (log scale)", fontsize=9)
    elif uniform:
        ax_hist.set_xlim(rmin - 0.2, rmax + 0.2)
    else:
        span = rmax - rmin
        ax_hist.set_xlim(min(rmin, 1.0) - 0.06 * span, max(rmax, 1.0) + 0.06 * span)
    ratio = rmax / rmin if rmin > 0 else np.inf
    cv = float(lengths.std() / mean) if mean > 0 else np.inf
    ax_hist.legend(
        loc="upper right", fontsize=8, frameon=True, framealpha=0.9,
        title=f"{n_e} edges   ratio {ratio:.4g}   CV {cv:.3g}", title_fontsize=8,
    )
    ax_hist.grid(axis="y", color="0.9", lw=0.6)
    ax_hist.set_axisbelow(True)
    return ratio
