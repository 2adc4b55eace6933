"""How far a remesh lies from its input, and pymeshlab's second opinion on it."""

from __future__ import annotations

import time

from . import _meshlab
from .report import cross_check

__all__ = ["meshlab_checks"]


def meshlab_checks(P, xyz, tris, stats, fidelity, times, check, hausdorff):
    """pymeshlab's cross-check of the edge measures (returned) and its Hausdorff
    distances (added to ``fidelity``), with their timings; then the relative figures."""
    meshlab = None
    V, F = P.vertices, P.faces
    if check:
        t = time.perf_counter()
        meshlab = cross_check(stats, _meshlab.edge_measures(xyz, tris))
        times["cross_check"] = time.perf_counter() - t
    if hausdorff:
        t = time.perf_counter()
        ns = int(min(200_000, 10 * (len(F) + len(tris))))
        fidelity["hausdorff_out_in"] = _meshlab.hausdorff(xyz, tris, V, F, ns)
        fidelity["hausdorff_in_out"] = _meshlab.hausdorff(V, F, xyz, tris, ns)
        times["hausdorff"] = time.perf_counter() - t
    diag = P.diagonal
    for key in list(fidelity):
        if isinstance(fidelity[key], float):
            fidelity[key + "_rel"] = fidelity[key] / diag
    for key in ("hausdorff_out_in", "hausdorff_in_out"):
        if key in fidelity:
            fidelity[key + "_max_rel"] = fidelity[key]["max"] / diag
    return meshlab
