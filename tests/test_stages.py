"""The starts' Python moved out of the GIL, the same bytes: the spacing search
in one kernel call (uniform2d._kernel.spacing) finds the lattice the Python
search (optimize.lattice.closest_count) finds, a load from a kept copy of
its rings' triangulation (uniform2d.triangulation._staged) leaves the kernel
in the state a load made afresh leaves it in, and a boundary row made for all
edges at once (optimize.rows._layer) is the row made edge by edge."""

from __future__ import annotations

import math
from pathlib import Path

import numba
import numpy as np
import pytest
from support.benchmarks import benchmark_polygons

from uniform2d import Polygon
from uniform2d.geometry import polygon_edges
from uniform2d.io import read_polygon
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.lattice import Candidates, Fit, closest_count
from uniform2d.optimize.rows import _layer, boundary_rows
from uniform2d.optimize.seed import start, variants
from uniform2d.testing.polygons import with_holes
from uniform2d.triangulation import _stages, load

DATA = Path(__file__).resolve().parents[1] / "data"


def _polygons() -> dict:
    out = dict(benchmark_polygons())
    out["holes11"] = with_holes(11)
    out["plate"] = read_polygon(DATA / "plate_bolts.json")
    out["segments"] = Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], segments=[[(2, 0), (2, 3)]],
                              points=[(1, 1.5), (3.2, 0.7)])
    out["slit"] = Polygon([(0, 0), (8, 0), (8, 4), (0, 4)], segments=[[(3, 2), (4, 2), (5, 2)]])
    return out


def _same(a, b) -> bool:
    return a[0].tobytes() == b[0].tobytes() and a[1].tobytes() == b[1].tobytes()


@pytest.mark.parametrize("name", sorted(benchmark_polygons()) + ["holes11", "plate"])
def test_the_kernel_search_finds_the_python_search_lattice(name):
    p = _polygons()[name]
    for n in (200, 1000, 5000):
        h = target_size(p, n)
        rows = boundary_rows(p, np.ones(len(p.constraint_edges), np.int64), h)
        for edge in (None, len(p.edges) - 1):
            for first, held in ((None, None), (rows, None), (rows, rows[::3])):
                for fit in Fit:
                    for count in (n - 37, n):
                        want = closest_count(Candidates(p, h, edge, first, held=held), count, h, fit)
                        got = Candidates(p, h, edge, first, held=held).search(count, h, fit)
                        assert _same(got, want), (n, edge, first is None, held is None, fit, count)


@numba.njit
def _state(m):
    return (m.xy, m.tv, m.tw, m.tstamp, m.vseg, m.tmark, m.vmark, m.vmap, m.stack, m.cav, m.bh,
            m.vbuf, m.ebuf, m.nv, m.nt, m.tag, m.sgx, m.sgy, m.sgv, m.hmin, m.sized, m.gc, m.gs,
            m.wg, m.tc, m.vcs)


def _bytes(m) -> list:
    return [np.asarray(x).tobytes() for x in _state(m)]


@pytest.mark.parametrize("name", sorted(_polygons()))
def test_a_load_from_kept_rings_is_the_load_made_afresh(name):
    p = _polygons()[name]
    n = 300
    for variant in variants(p, n)[:4]:
        sites, edges, _, _ = start(p, n, target_size(p, n), variant)
        _stages.clear()
        fresh = load(p, sites, edges=edges)
        # the rings kept from a load of other interior sites (in reverse order)
        _stages.clear()
        inner = (edges < 0) | (edges >= p.n_ring_vertices)
        other, other_edges = sites.copy(), edges.copy()
        other[inner], other_edges[inner] = sites[inner][::-1], edges[inner][::-1]
        load(p, other, edges=other_edges)
        assert len(_stages) == 1
        kept = load(p, sites, edges=edges)
        assert len(_stages) == 1  # the kept rings read, not others kept
        assert numba.typeof(kept.m) == numba.typeof(fresh.m)
        assert _bytes(kept.m) == _bytes(fresh.m)
        assert _bytes(kept.m) != _bytes(load(p, sites[::-1], edges=edges[::-1]).m)


def _layer_edge_by_edge(p, m, layer):
    """Row ``layer`` of boundary_rows made edge by edge, side by side."""
    a, d, L = polygon_edges(p, constraints=True)
    rows, gaps = [], []
    for e in range(len(L)):
        g = L[e] / m[e]
        nrm = np.array([-d[e, 1], d[e, 0]]) / L[e]
        s = ((np.arange(m[e]) + 0.5) if layer % 2 else np.arange(1, m[e])) / m[e]
        mid = a[e] + d[e] * s[:, None]
        for side in (1.0,) if e < len(p.edges) else (1.0, -1.0):
            rows.append(mid + side * nrm * g * math.sqrt(3) / 2 * layer)
            gaps.append(np.full(len(s), g))
    return np.concatenate(rows), np.concatenate(gaps)


@pytest.mark.parametrize("name", sorted(_polygons()))
def test_a_row_made_at_once_is_the_row_made_edge_by_edge(name):
    p = _polygons()[name]
    a, d, L = polygon_edges(p, constraints=True)
    rng = np.random.default_rng(5)
    for _ in range(10):
        m = rng.integers(1, 30, len(L))
        for layer in (1, 2, 3):
            want = _layer_edge_by_edge(p, m, layer)
            assert _same(_layer(p, a, d, L, m, layer), want)


def test_the_hilbert_order_in_one_kernel_call_is_numpy_s(monkeypatch):
    from uniform2d._kernel import hilbert

    rng = np.random.default_rng(7)
    cases = [rng.random((n, 2)) * 10.0 ** rng.integers(-3, 4) for n in (1, 2, 50, 3000)]
    cases.append(np.round(rng.random((500, 2)) * 8) / 8)  # ties: cells shared, kept in order
    cases.append(np.repeat(rng.random((1, 2)), 5, axis=0))  # all one point
    kernel = [hilbert.hilbert_order(p) for p in cases]
    monkeypatch.setattr(hilbert, "KERNEL_MAX", 0)
    for p, got in zip(cases, kernel):
        assert got.tobytes() == hilbert.hilbert_order(p).tobytes()
