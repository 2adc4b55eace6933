"""The lattice points inside a polygon found row by row (uniform2d._kernel.hexrows),
against the lattice of hex_lattice tested point by point by shapely: the same
points wherever one is not within rounding of the boundary, in the same order;
their capped distances to the boundary the bits of the brute force over every
segment (to_segments); and the optimiser's candidates (farther than half a
spacing from it) the same bytes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from support.benchmarks import benchmark_polygons
from uniform2d import Polygon
from uniform2d._kernel.distance import to_segments
from uniform2d.io import read_polygon
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.lattice import Candidates, hex_lattice
from uniform2d.optimize.rows import boundary_rows
from uniform2d.testing.polygons import with_holes

DATA = Path(__file__).resolve().parents[1] / "data"


def _polygons() -> dict:
    out = dict(benchmark_polygons())
    out["holes11"] = with_holes(11)
    out["plate"] = read_polygon(DATA / "plate_bolts.json")
    return out


def _brute(P, a, b) -> np.ndarray:
    """Each point's distance to the nearest segment, every segment measured
    (to_segments without a cap measures every one)."""
    return to_segments(P, a, b, np.inf)


def _by_shapely(cand: Candidates, polygon: Polygon, sp: float) -> np.ndarray:
    P = hex_lattice(cand.bounds, sp, cand.angle, cand.origin)
    return P[shapely.contains_xy(polygon.to_shapely(), P[:, 0], P[:, 1])]


@pytest.mark.parametrize("name", sorted(_polygons()))
def test_rows_find_the_lattice_points_shapely_finds(name):
    p = _polygons()[name]
    ring = shapely.boundary(p.to_shapely())
    for n in (300, 3000):
        h = target_size(p, n)
        for edge in (0, len(p.edges) - 1):
            cand = Candidates(p, h, edge, None)
            for sp in np.linspace(0.7 * h, 1.3 * h, 7):
                cap = (1.0 + 2.0 * edge / len(p.edges)) * sp
                (got, dist), want = cand._inside(sp, cap), _by_shapely(cand, p, sp)
                assert len(got) > 0
                # the distances: every segment measured, capped (its bits)
                assert dist.tobytes() == np.minimum(_brute(got, cand.sa, cand.sb), cap).tobytes()
                # the same points, in the same order, away from the boundary
                far = 1e-9 * h
                g = got[shapely.distance(ring, shapely.points(got)) > far]
                w = want[shapely.distance(ring, shapely.points(want)) > far]
                assert np.array_equal(g, w)


@pytest.mark.parametrize("name", ["square", "square2holes", "star10", "holes11", "plate"])
def test_the_starts_candidates_are_the_same_bytes(name):
    p = _polygons()[name]
    h = target_size(p, 1000)
    rows = boundary_rows(p, np.ones(len(p.constraint_edges), np.int64), h)
    for r in (None, rows):
        cand = Candidates(p, h, None, r)
        reference = Candidates(p, h, None, r)
        reference._inside = lambda sp, cap, c=reference: (
            lambda Q: (Q, to_segments(Q, c.sa, c.sb, cap)))(_by_shapely(c, p, sp))
        for sp in np.linspace(0.6 * h, 1.4 * h, 9):
            (P, d), (Q, e) = cand(sp), reference(sp)
            assert len(P) > 0
            assert P.tobytes() == Q.tobytes() and d.tobytes() == e.tobytes()
