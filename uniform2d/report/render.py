"""Rendering a report: figures (PNG), one self-contained HTML page, Markdown.

Everything here reads the ``results`` dict of :func:`uniform2d.report.make_report`
(the content of ``results.json``) plus the meshes; nothing is recomputed.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections import defaultdict

import numpy as np

from .cases import MEASURES

__all__ = ["mesh_figure", "grid_shape", "render_html", "render_markdown", "summary_rows", "fmt", "certificate"]

#: Bins of the edge-length histograms, in units of each mesh's mean edge.
HIST_BINS = np.linspace(0.0, 2.5, 51)
#: (width, height) in inches of one panel of a report figure.
PANEL_SIZE = (3.4, 3.1)
#: Histogram colours, far apart so they stay apart in the page's 128-colour PNGs.
HIST_COLOURS = ("#1f4fd1", "#e8590c", "#2b9348", "#c2185b", "#7b5ea7", "#8d6e00", "#00838f")
#: Colour of a polygon's segments drawn over the meshes.
SEGMENT_COLOUR = "#d62828"


def fmt(value, spec: str) -> str:
    """Format one table cell; ``None`` (or non-finite) becomes an en dash."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return format(value, spec)


def _columns(kind: str):
    if kind == "polygon":  # the certified factors lead, right after the vertex count
        cols = [c for c in MEASURES if c[0] != "hausdorff_max_rel"]
        first = [c for c in cols if c[0] in ("n_vertices", "vertex_error")]
        factors = [c for c in cols if c[0].startswith("factor_")]
        return first + factors + [c for c in cols if c not in first and c not in factors]
    return [c for c in MEASURES if not c[0].startswith("factor_")]


#: The certified measures, in the order they are reported.
_CERTIFIED = (("edge_ratio_bound", "edge ratio"), ("longest_edge_bound", "longest edge"),
              ("max_perimeter_bound", "largest perimeter"))


def certificate(case) -> str:
    """One sentence: how close a polygon case's mesh provably is to the best possible one.

    Reads ``case["quality"]`` (:meth:`uniform2d.Quality.to_dict`); empty when
    the case has no bounds (a surface patch, a failed run).
    """
    q = case.get("quality") or {}
    parts = []
    for key, label in _CERTIFIED:
        b = q.get(key)
        if not b or b.get("factor") is None:
            continue
        active = b["term"] + (f" ({b['detail']})" if b.get("detail") else "")
        parts.append(f"{label} within {(b['factor'] - 1) * 100:.3g} % (bound: {active})")
    if not parts:
        return ""
    return (f"{case['method']}: certified against the best possible mesh with these "
            f"{q.get('n_steiner')} Steiner points: " + "; ".join(parts) + ".")


def groups(results: dict):
    """``[(input dict, n, [case, ...]), ...]`` in report order."""
    by = defaultdict(list)
    for c in results["cases"]:
        by[(c["input"], c["n"])].append(c)
    out = []
    for inp in results["inputs"]:
        for n in results["ns"]:
            if by.get((inp["name"], n)):
                out.append((inp, n, by[(inp["name"], n)]))
    return out


def _time(c) -> str:
    t = c.get("time") or {}
    return fmt(t.get("per_mesh"), ".3f")


def _status(c) -> str:
    return {"ok": "", "not installed": "not installed", "failed": "failed",
            "not comparable": "not comparable"}.get(c["status"], c["status"])


# -- figures -------------------------------------------------------------------
def _edge_lengths(points, triangles):
    e = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return np.linalg.norm(points[e[:, 1]] - points[e[:, 0]], axis=1)


def grid_shape(n_panels: int) -> tuple[int, int]:
    """(rows, columns) of the report figure's grid: at most three columns, no row
    of one panel under a row of three.

    >>> [grid_shape(k) for k in (2, 3, 4, 6, 7)]
    [(1, 2), (1, 3), (2, 2), (2, 3), (3, 3)]
    """
    cols = 2 if n_panels in (2, 4) else min(3, n_panels)
    return math.ceil(n_panels / cols), cols


def mesh_figure(kind: str, items, *, title: str = "", dpi: int = 100, segments=()) -> bytes:
    """PNG of several meshes in a grid, and their edge-length histograms in the
    last cell.

    Panels are :data:`PANEL_SIZE` inches at ``dpi`` (three across: about 1000
    pixels wide at 100 dpi), with text of 9 to 13 points, readable at 100 %.

    Parameters
    ----------
    kind : {"polygon", "surface"}
    items : list of (label, points, triangles)
    title : str
    dpi : int
    segments : sequence of (k, 2) arrays
        A polygon's interior segments, drawn over every planar mesh (so one sees
        that each mesh has them as edges).

    Returns
    -------
    bytes
        The PNG file.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    k = len(items)
    rows, cols = grid_shape(k + 1)
    fig = Figure(figsize=(PANEL_SIZE[0] * cols, PANEL_SIZE[1] * rows + 0.4), dpi=dpi,
                 layout="constrained")
    FigureCanvasAgg(fig)
    for i, (label, P, T) in enumerate(items):
        if kind == "polygon":
            ax = fig.add_subplot(rows, cols, i + 1)
            ax.triplot(P[:, 0], P[:, 1], T, lw=0.45, color="0.15")
            for seg in segments:
                seg = np.asarray(seg)
                ax.plot(seg[:, 0], seg[:, 1], color=SEGMENT_COLOUR, lw=1.6, zorder=3)
            ax.set_aspect("equal")
        else:
            ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
            ax.plot_trisurf(P[:, 0], P[:, 1], P[:, 2], triangles=T, color="0.92",
                            edgecolor="0.15", linewidth=0.25, shade=False)
            ax.set_box_aspect(np.ptp(P, axis=0) + 1e-12)
        ax.set_axis_off()
        ax.set_title(f"{label}: {len(P)} vertices", fontsize=11)
    ax = fig.add_subplot(rows, cols, k + 1)
    for i, (label, P, T) in enumerate(items):
        L = _edge_lengths(P, T)
        ax.hist(L / L.mean(), bins=HIST_BINS, histtype="step", density=True, label=label,
                lw=1.4, color=HIST_COLOURS[i % len(HIST_COLOURS)])
    ax.set_xlabel("edge length / mean", fontsize=10)
    ax.set_ylabel("density", fontsize=10)
    ax.tick_params(labelsize=9)
    ax.set_title("edge lengths", fontsize=11)
    ax.legend(fontsize=9, frameon=False)
    if title:
        fig.suptitle(title, fontsize=13)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    try:  # line art: a 128-colour palette keeps the self-contained page small
        from PIL import Image

        img = Image.open(io.BytesIO(buf.getvalue())).convert("RGB").quantize(colors=128)
        small = io.BytesIO()
        img.save(small, format="PNG", optimize=True)
        return small.getvalue()
    except ImportError:
        return buf.getvalue()


# -- summary -------------------------------------------------------------------
def summary_rows(results: dict, kind: str):
    """Per method: number of cases run, then the median of each measure over them."""
    cols = [c for c in _columns(kind) if c[0] not in ("n_vertices",)]
    methods = []
    for c in results["cases"]:
        if c["kind"] == kind and c["method"] not in methods:
            methods.append(c["method"])
    rows = []
    for m in methods:
        cs = [c for c in results["cases"] if c["kind"] == kind and c["method"] == m]
        ok = [c for c in cs if c["status"] == "ok"]
        row = {"method": m, "cases": len(ok), "of": len(cs),
               "status": next((st for st in ("not installed", "not comparable")
                               if all(c["status"] == st for c in cs)), "")}
        for key, _, _ in cols:
            vals = [c["measures"][key] for c in ok if c["measures"].get(key) is not None]
            if key == "vertex_error":
                vals = [abs(v) for v in vals]
            row[key] = float(np.median(vals)) if vals else None
        rows.append(row)
    return cols, rows


# -- HTML ------------------------------------------------------------------------
_CSS = """
body{font-family:system-ui,sans-serif;margin:2em;max-width:1400px;color:#222}
table{border-collapse:collapse;margin:0.6em 0;font-size:13px}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right}
th{background:#f2f2f2} td.l,th.l{text-align:left}
tr.ours td{background:#eef6ff} tr.missing td{color:#999;font-style:italic}
tr.failed td{color:#a00}
figure{margin:0.5em 0} img{max-width:100%}
.note{color:#555;font-size:13px}
"""


def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _case_row_html(c, cols) -> str:
    cls = "ours" if c["family"] == "ours" else ""
    if c["status"] in ("not installed", "not comparable"):
        cls = "missing"
    elif c["status"] == "failed":
        cls = "failed"
    cells = [f'<td class="l">{_e(c["method"])}</td>']
    if c["status"] == "ok":
        m = c["measures"]
        cells += [f"<td>{_e(fmt(m.get(k), spec))}</td>" for k, _, spec in cols]
        cells.append(f"<td>{_e(_time(c))}</td>")
        cells.append(f'<td class="l"><a href="{_e(c["mesh"])}">{_e(c["mesh"].split("/")[-1])}</a></td>')
    else:
        cells.append(f'<td class="l" colspan="{len(cols) + 2}">{_e(_status(c))}'
                     + (f": {_e(c['message'])}" if c["status"] in ("failed", "not comparable") else "")
                     + "</td>")
    return (f'<tr id="case-{_e(c["id"])}" class="{cls}" data-case="{_e(c["id"])}" '
            f'data-status="{_e(c["status"])}">' + "".join(cells) + "</tr>")


def _header_html(cols) -> str:
    return ("<thead><tr><th class=\"l\">method</th>"
            + "".join(f"<th>{_e(h)}</th>" for _, h, _ in cols)
            + "<th>time [s]</th><th class=\"l\">mesh</th></tr></thead>")


def render_html(results: dict, figures: dict | None = None) -> str:
    """The report as one self-contained HTML page.

    Parameters
    ----------
    results : dict
        The content of ``results.json``.
    figures : dict, optional
        ``{(input name, n): PNG bytes}``, embedded as base64 ``data:`` URIs.

    Returns
    -------
    str
    """
    figures = figures or {}
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           "<title>uniform2d comparison report</title>", f"<style>{_CSS}</style></head><body>",
           "<h1>uniform2d comparison report</h1>",
           f'<p class="note">uniform2d {_e(results["uniform2d_version"])}; '
           f'n = {_e(", ".join(str(n) for n in results["ns"]))} '
           "(Steiner points for polygons, vertices for surface patches). "
           "Every peer is tuned to the same total vertex count as ours; "
           "<i>error</i> is how far it got. Factors are certified: achieved / lower bound "
           "on the optimum over all triangulations with as many points (1 is optimal); "
           "each section names the bound that is active for our meshes. "
           "Time is per mesh (tuning runs a peer several times).</p>",
           "<h2>Peers</h2>", '<table class="peers"><thead><tr><th class="l">peer</th>'
           '<th class="l">kind</th><th class="l">status</th><th class="l">what</th></tr></thead><tbody>']
    for p in results["peers"]:
        st = "installed" if p["available"] else "not installed (pip install " + " ".join(p["requires"]) + ")"
        out.append(f'<tr data-peer="{_e(p["name"])}" data-available="{str(p["available"]).lower()}">'
                   f'<td class="l">{_e(p["name"])}</td><td class="l">{_e(p["kind"])}</td>'
                   f'<td class="l">{_e(st)}</td><td class="l">{_e(p["description"])}</td></tr>')
    out.append("</tbody></table>")
    for kind in ("polygon", "surface"):
        if not any(c["kind"] == kind for c in results["cases"]):
            continue
        cols, rows = summary_rows(results, kind)
        out.append(f"<h2>Summary: {'polygons' if kind == 'polygon' else 'surface patches'} "
                   "(medians over cases; error as |error|)</h2>")
        out.append(f'<table class="summary" data-kind="{kind}"><thead><tr><th class="l">method</th>'
                   "<th>cases</th>" + "".join(f"<th>{_e(h)}</th>" for _, h, _ in cols)
                   + "</tr></thead><tbody>")
        for r in rows:
            spec = {k: s for k, _, s in cols}
            cells = "".join(
                f"<td>{_e(fmt(r[k], '.1f' if k == 'vertex_error' else spec[k]))}</td>" for k, _, _ in cols
            )
            out.append(f'<tr><td class="l">{_e(r["method"])}</td><td>{r["cases"]}/{r["of"]}'
                       + (f" ({_e(r['status'])})" if r["status"] else "") + f"</td>{cells}</tr>")
        out.append("</tbody></table>")
    current = None
    for inp, n, cases in groups(results):
        if inp["name"] != current:
            if current is not None:
                out.append("</section>")
            current = inp["name"]
            out.append(f'<section class="input" id="input-{_e(inp["name"])}" data-input="{_e(inp["name"])}">')
            out.append(f'<h2>{_e(inp["name"])}</h2><p class="note">{_e(inp["path"])} — {_e(_describe(inp))}</p>')
        cols = _columns(inp["kind"])
        out.append(f'<section class="n" data-n="{n}"><h3>n = {n} '
                   f'(target {cases[0]["target_vertices"]} vertices)</h3>')
        for c in cases:
            if c["family"] == "ours" and certificate(c):
                out.append(f'<p class="certificate" data-case="{_e(c["id"])}">{_e(certificate(c))}</p>')
        out.append('<table class="cases">' + _header_html(cols) + "<tbody>")
        out += [_case_row_html(c, cols) for c in cases]
        out.append("</tbody></table>")
        png = figures.get((inp["name"], n))
        if png:
            b64 = base64.b64encode(png).decode("ascii")
            out.append(f'<figure><img alt="meshes of {_e(inp["name"])} at n = {n}" '
                       f'src="data:image/png;base64,{b64}"></figure>')
        out.append("</section>")
    if current is not None:
        out.append("</section>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


def _plural(k: int, word: str) -> str:
    return f"{k} {word}" + ("" if k == 1 else "s")


def _describe(inp) -> str:
    if inp["kind"] == "polygon":
        counts = [f"{inp['n_vertices']} vertices", _plural(inp["n_holes"], "hole")]
        counts += [_plural(inp[k], w) for k, w in (("n_segments", "segment"), ("n_points", "fixed point"),
                                                   ("n_regions", "labelled region")) if inp.get(k)]
        return f"polygon, {', '.join(counts)}, area {inp['area']:.6g}"
    return f"surface patch, {inp['n_vertices']} vertices, {inp['n_faces']} faces"


# -- Markdown ----------------------------------------------------------------------
def render_markdown(results: dict) -> str:
    """The report's tables as Markdown (no pictures; see index.html for those)."""
    lines = ["# uniform2d comparison report", "",
             f"uniform2d {results['uniform2d_version']}; n = "
             + ", ".join(str(n) for n in results["ns"])
             + " (Steiner points for polygons, vertices for surface patches). Peers are tuned to "
             "the same total vertex count; *error* is how far they got. Factors are certified "
             "(achieved / lower bound on the optimum). Time is seconds per mesh.", "",
             "| peer | kind | status |", "|---|---|---|"]
    for p in results["peers"]:
        lines.append(f"| {p['name']} | {p['kind']} | {'installed' if p['available'] else 'not installed'} |")
    for kind in ("polygon", "surface"):
        if not any(c["kind"] == kind for c in results["cases"]):
            continue
        cols, rows = summary_rows(results, kind)
        lines += ["", f"## Summary: {'polygons' if kind == 'polygon' else 'surface patches'} "
                  "(medians; error as |error|)", "",
                  "| method | cases | " + " | ".join(h for _, h, _ in cols) + " |",
                  "|---|" + "---:|" * (len(cols) + 1)]
        spec = {k: s for k, _, s in cols}
        for r in rows:
            cells = [fmt(r[k], ".1f" if k == "vertex_error" else spec[k]) for k, _, _ in cols]
            lines.append(f"| {r['method']} | {r['cases']}/{r['of']}"
                         + (f" ({r['status']})" if r["status"] else "") + " | " + " | ".join(cells) + " |")
    for inp, n, cases in groups(results):
        cols = _columns(inp["kind"])
        lines += ["", f"## {inp['name']}, n = {n} (target {cases[0]['target_vertices']} vertices)", "",
                  f"{inp['path']} — {_describe(inp)}", "",
                  *[f"- {certificate(c)}" for c in cases if c["family"] == "ours" and certificate(c)],
                  *([""] if any(c["family"] == "ours" and certificate(c) for c in cases) else []),
                  "| method | " + " | ".join(h for _, h, _ in cols) + " | time [s] |",
                  "|---|" + "---:|" * (len(cols) + 1)]
        for c in cases:
            if c["status"] == "ok":
                cells = [fmt(c["measures"].get(k), s) for k, _, s in cols] + [_time(c)]
            else:
                msg = _status(c) + (f": {c['message']}" if c["status"] in ("failed", "not comparable")
                                    else "")
                cells = [msg.replace("|", "/")] + [""] * len(cols)
            name = f"**{c['method']}**" if c["family"] == "ours" else c["method"]
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
