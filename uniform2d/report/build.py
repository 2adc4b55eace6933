"""Building a report directory: plan, run, write meshes, results.json, report.md, index.html."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np

from .._jsonable import jsonable
from ..errors import InvalidArgumentError
from .cases import describe_constraints, load_inputs, plan, polygon_of
from .render import mesh_figure, render_html, render_markdown
from .runners import iter_cases

log = logging.getLogger(__name__)

__all__ = ["make_report", "strip_timings"]

#: Version of the layout of results.json.
RESULTS_FORMAT = 1


def strip_timings(results: dict) -> dict:
    """A copy of ``results`` without the timings (what must not depend on where cases ran)."""
    out = json.loads(json.dumps(results))
    for c in out["cases"]:
        c.pop("time", None)
    return out


def _input_info(inp) -> dict:
    d = {"name": inp.name, "path": inp.path, "kind": inp.kind}
    if inp.kind == "polygon":
        p = polygon_of(inp.geometry)
        d.update(n_vertices=len(p.vertices), n_holes=p.n_holes, area=p.area, perimeter=p.perimeter,
                 **describe_constraints(inp.geometry))
    else:
        d.update(n_vertices=len(inp.geometry["vertices"]), n_faces=len(inp.geometry["faces"]))
    return d


def _write_mesh(out_dir: Path, case: dict, points, triangles) -> str:
    rel = f"meshes/{case['id']}" + (".vtu" if case["kind"] == "polygon" else ".obj")
    path = out_dir / rel
    if case["kind"] == "polygon":
        from ..io import write_mesh

        write_mesh(path, points, triangles)
    else:
        write_obj(path, points, triangles)
    return rel


def write_obj(path, vertices, faces) -> None:
    """Write a triangle mesh as Wavefront OBJ with shortest round-trip floats (exact)."""
    lines = ["# uniform2d report mesh"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=np.float64).tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces, dtype=np.int64).tolist()]
    Path(path).write_text("\n".join(lines) + "\n")


def _draw(group, pngs: dict, inputs: dict) -> None:
    """The figure of one input at one n: ``group`` is its [(case, points, triangles)]."""
    first = group[0][0]
    items = [(c["method"], pts, tri) for c, pts, tri in group if pts is not None]
    inp = inputs[first["input"]]
    segments = inp.geometry.get("segments", ()) if inp.kind == "polygon" else ()
    if items:
        pngs[(first["input"], first["n"])] = mesh_figure(
            first["kind"], items, title=f"{first['input']}, n = {first['n']}", segments=segments
        )


def make_report(paths, out_dir, *, ns=(200,), peers=None, jobs: int = 1, scheduler=None,
                progress: bool = False, figures: bool = True, feature_angle=None) -> dict:
    """Compare uniform2d with peer meshers on polygons and surface patches.

    Parameters
    ----------
    paths : list of path
        Polygon files (any format of :func:`uniform2d.read_polygon`) and surface
        patches (``.obj``, ``.ply``, ``.stl``, ``.off``).
    out_dir : path
        Created if needed; receives ``index.html``, ``report.md``,
        ``results.json`` and ``meshes/<case>.vtu`` (planar; exact binary
        floats) / ``.obj`` (surface; shortest round-trip floats).
    ns : sequence of int
        Steiner points for polygons; vertex counts for surface patches.
    peers : sequence of str, optional
        Peer names (default: :func:`uniform2d.peers.defaults`, those of the
        project's extras; any of :func:`uniform2d.peers.names` may be named).
        Peers that are not installed are listed as such, never dropped.
    jobs : int
        Local worker processes.
    scheduler : str or distributed.Client, optional
        A Dask scheduler address (or Client) to run the cases on instead.
    progress : bool
        tqdm bar over cases on stderr.
    figures : bool
        Embed mesh pictures and histograms in ``index.html``.
    feature_angle : float, optional
        For surface patches: edges bent more than this (degrees) are kept as
        feature lines by our remesh (see ``surface.remesh``).  Polygons keep
        their segments, fixed points and regions in our meshes and in every peer
        that takes them; the cases of a peer that does not are "not comparable".

    Returns
    -------
    dict
        The content of ``results.json``.

    Raises
    ------
    ValueError
        For an unknown peer, an empty input list or a bad n.
    """
    from .. import __version__
    from .. import peers as _peers

    paths = [str(p) for p in paths]
    if not paths:
        raise InvalidArgumentError("give at least one input file")
    ns = [int(n) for n in ns]
    if not ns or min(ns) < 1:
        raise InvalidArgumentError(f"every n must be a positive integer, got {ns}")
    ns = list(dict.fromkeys(ns))
    names = list(_peers.defaults()) if peers is None else list(dict.fromkeys(peers))
    unknown = [p for p in names if p not in _peers.names()]
    if unknown:
        raise InvalidArgumentError(
            f"unknown peer(s) {', '.join(unknown)}; choose from {', '.join(_peers.names())}"
        )
    info = [_peers.describe(p) for p in names]
    for p in info:
        if not p["available"]:
            log.warning("peer %s is not installed (needs %s)", p["name"], ", ".join(p["requires"]))
    inputs = load_inputs(paths)
    by_name = {i.name: i for i in inputs}
    cases = plan(inputs, ns, names, availability={p["name"]: p["available"] for p in info},
                 feature_angle=feature_angle)
    out_dir = Path(out_dir)
    (out_dir / "meshes").mkdir(parents=True, exist_ok=True)
    # Each result is written, and each figure drawn, as soon as its cases are in:
    # with workers, this process draws while they mesh.
    results_list, pngs = [], {}
    group: list = []
    for r in iter_cases(cases, jobs=jobs, scheduler=scheduler, progress=progress):
        if r["status"] == "ok":
            pts, tri = r.pop("points"), r.pop("triangles")
            r["mesh"] = _write_mesh(out_dir, r, pts, tri)
        else:
            pts = tri = r["mesh"] = None
        results_list.append(r)
        if figures:
            if group and (group[0][0]["input"], group[0][0]["n"]) != (r["input"], r["n"]):
                _draw(group, pngs, by_name)
                group = []
            group.append((r, pts, tri))
    if group:
        _draw(group, pngs, by_name)
    results = jsonable({
        "format": RESULTS_FORMAT,
        "uniform2d_version": __version__,
        "ns": ns,
        "peers": info,
        "inputs": [_input_info(i) for i in inputs],
        "cases": results_list,
    })
    (out_dir / "results.json").write_text(json.dumps(results, indent=1, allow_nan=False) + "\n")
    (out_dir / "index.html").write_text(render_html(results, pngs), encoding="utf-8")
    (out_dir / "report.md").write_text(render_markdown(results), encoding="utf-8")
    log.info("report written to %s (%d cases)", out_dir, len(results_list))
    return results
