"""Row starts stretched between parallel sides (:mod:`uniform2d.optimize.stretch`):
exactly n sites, a valid mesh of them and after the optimiser's moves, the same
bytes twice, and on a rectangle a longest edge (against its lower bound) that no
hexagonal start reaches."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest
from support.benchmarks import benchmark_polygons

import uniform2d
from uniform2d import Polygon
from uniform2d.io import read_polygon
from uniform2d.optimize import seed
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.moves import improve_best
from uniform2d.optimize.stretch import row_edges, row_start
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

RECT = Polygon([(0, 0), (3, 0), (3, 1), (0, 1)])


def test_row_edges_one_per_direction_with_a_parallel_partner():
    polys = benchmark_polygons()
    assert len(row_edges(polys["square"])) == 2
    assert len(row_edges(polys["hexagon"])) == 3
    assert row_edges(polys["heptagon_short"]) == []  # no two edges parallel
    with_segment = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], segments=[[(0.2, 0.5), (0.8, 0.5)]])
    assert row_edges(with_segment) == []


CASES = [(name, n, e) for name in ("square", "rect4x1", "lshape", "hexagon", "square2holes")
         for n in (300, 1500) for e in row_edges(benchmark_polygons()[name])]


@pytest.mark.parametrize("name,n,edge", CASES)
def test_row_start_has_exactly_n_sites_and_a_valid_mesh(name, n, edge):
    p = benchmark_polygons()[name]
    h = target_size(p, n)
    sites, edges, frozen, nb = row_start(p, n, h, edge)
    assert len(sites) == n and len(edges) == n and len(frozen) == n
    assert (edges[:nb] >= 0).all() and (edges[nb:] == -1).all()
    pts, tri = triangulate(p, sites, edges)
    check_mesh(pts, tri, p, n_steiner=n)
    again = row_start(p, n, h, edge)
    assert hashlib.sha256(again[0].tobytes()).digest() == hashlib.sha256(sites.tobytes()).digest()


@pytest.mark.parametrize("name", ["square", "hexagon"])
def test_optimiser_moves_a_row_start_into_a_valid_mesh_of_n_points(name):
    p, n = benchmark_polygons()[name], 300
    h = target_size(p, n)
    sites, edges, frozen, _ = row_start(p, n, h, row_edges(p)[0])
    _, pts, tri, _ = improve_best(p, [(sites, edges, frozen)], href=h)
    assert len(pts) == len(p.vertices) + n
    check_mesh(pts, tri, p, n_steiner=n)


def _plain_rows_count():
    """An n at which the rows on RECT need no row of a point more or fewer."""
    for n in range(150, 400):
        if len(row_start(RECT, n, target_size(RECT, n), 0, exact=False)[0]) == n:
            return n
    raise AssertionError("no n in 150..400 fits plain rows on the rectangle")


def test_rows_on_a_rectangle_reach_a_longest_edge_no_hexagonal_start_reaches():
    n = _plain_rows_count()
    h = target_size(RECT, n)
    sites, edges, _, _ = row_start(RECT, n, h, 0)
    assert np.array_equal(sites, row_start(RECT, n, h, 0, exact=False)[0])

    def factor(s, e):
        pts, tri = triangulate(RECT, s, e)
        check_mesh(pts, tri, RECT, n_steiner=n)
        return uniform2d.quality(pts, tri, RECT, d_n=False).longest_edge_bound.factor

    rows = factor(sites, edges)
    hexagonal = [factor(*seed.start(RECT, n, h, v)[:2]) for v in seed.variants(RECT, n)]
    assert rows < min(hexagonal)


BUNDLED = sorted((Path(__file__).resolve().parents[1] / "data").glob("*.json"))


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_row_start_on_the_bundled_polygons_is_exact_and_valid(path):
    p, n = read_polygon(path), 200
    edges_followed = row_edges(p)
    if p.has_constraints:
        assert edges_followed == []
    for edge in edges_followed[:2]:
        made = row_start(p, n, target_size(p, n), edge)
        assert made is not None and len(made[0]) == n
        pts, tri = triangulate(p, made[0], made[1])
        check_mesh(pts, tri, p, n_steiner=n)
