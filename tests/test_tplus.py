"""Acceptance tests of T+ (Section 3 of the paper) and of uniform_mesh.

Everything T+ reports is recomputed here independently from an INSERT run:
d_n (least distance among V and the phase-1 points, by cKDTree), k (the
boundary points, placed from d_n by the rule m = max(1, ceil(L / (3 d_n)))
pieces per edge) and the hypotheses of Theorem 2.  Then, on the 7 benchmark
polygons and on random convex, non-convex and holed polygons, at an n where
the hypotheses hold: T+ is a valid CDT of P with exactly n Steiner points, the k
prescribed points are where they should be, every prescribed gap L/m is in
[1.5, 3] d_n, and the edge ratio is at most 6 (Theorem 2).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.spatial import cKDTree

from uniform2d.testing import polygons
from support.benchmarks import benchmark_polygons
from uniform2d.testing import check_mesh
from uniform2d import InsufficientPointsError, Polygon, insert, tplus, uniform_mesh
from uniform2d import steiner_count_for_size

N_MAX = 4000  # largest n tried when looking for one where Theorem 2 applies
N_RANDOM = 60  # random polygons checked (a third each: convex, star-shaped, with holes)


# -- the independent recomputation ------------------------------------------------
def phase1(polygon: Polygon, n: int) -> dict:
    """d_n, the prescribed boundary points and Theorem 2's hypotheses, from scratch."""
    sites = np.concatenate([polygon.vertices, insert(polygon, n).points])
    d, _ = cKDTree(sites).query(sites, k=2)
    d_n = float(d[:, 1].min())
    V = polygon.vertices
    # the documented piece count: a ratio within tau of an integer j counts as j
    tau = 1e-9 + 16 * np.finfo(float).eps * float(np.abs(V).max()) / d_n
    pts, gaps = [], []
    for ring in polygon.rings:
        for a, b in zip(ring, np.roll(ring, -1, axis=0)):
            L = math.dist(a, b)
            r = L / (3 * d_n)
            m = max(1, math.ceil(r - tau * r))
            gaps.append(L / m)
            pts += [a + (b - a) * (i / m) for i in range(1, m)]
    k = len(pts)
    vv = cKDTree(V).query(V, k=2)[0][:, 1].min()
    return {
        "d_n": d_n,
        "k": k,
        "points": np.array(pts).reshape(-1, 2),
        "gaps": np.array(gaps),
        "l(V,V)": float(vv),
        "hypotheses": {
            "d_n <= l(V,V)/2": d_n <= vv / 2,
            "d_n <= A/(pi*B)": d_n <= polygon.area / (math.pi * polygon.perimeter),
            "n >= 2k": n >= 2 * k,
        },
    }


def n_where_theorem_applies(polygon: Polygon):
    """The first n of a geometric sequence (ratio ~1.4) at which d_n <= l(V,V)/2 and n >= 2k."""
    n = 20
    while n <= N_MAX:
        ref = phase1(polygon, n)
        h = ref["hypotheses"]
        if h["d_n <= l(V,V)/2"] and h["n >= 2k"]:
            return n, ref
        n = int(n * 1.4)
    return None, None


def boundary_edges(triangles):
    e = np.sort(np.asarray(triangles)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    uniq, counts = np.unique(e, axis=0, return_counts=True)
    return uniq[counts == 1]


def check_tplus(polygon: Polygon, n: int, ref: dict):
    mesh = tplus(polygon, n)
    info = mesh.info
    P, T = np.asarray(mesh.points), np.asarray(mesh.triangles)
    V = polygon.vertices
    scale = max(polygon.bounds[2] - polygon.bounds[0], polygon.bounds[3] - polygon.bounds[1])

    # A valid CDT of P with exactly n Steiner points.
    check_mesh(P, T, polygon)
    assert mesh.n_steiner == n and len(P) == len(V) + n
    assert np.array_equal(P[: len(V)], V)

    # What T+ reports agrees with the recomputation.
    d_n = ref["d_n"]
    assert info["d_n"] == pytest.approx(d_n, rel=1e-12)
    assert info["k"] == ref["k"]
    assert info["hypotheses"] == ref["hypotheses"]
    assert info["theorem_applies"] is True and info["edge_ratio_bound"] == 6
    assert info["l(V,V)"] == pytest.approx(ref["l(V,V)"], rel=1e-15)

    # The k prescribed points are where the rule puts them (and are mesh vertices).
    k = ref["k"]
    if k:
        dist, _ = cKDTree(P).query(ref["points"])
        assert dist.max() <= 1e-12 * scale
        dist, _ = cKDTree(ref["points"]).query(P[len(V) : len(V) + k])
        assert dist.max() <= 1e-12 * scale
    # Every prescribed gap L/m is in [1.5, 3] d_n (the corrected spacing rule).
    gaps = ref["gaps"] / d_n
    assert gaps.min() >= 1.5 * (1 - 1e-12) and gaps.max() <= 3 * (1 + 1e-12)
    assert info["gap_min"] == pytest.approx(gaps.min(), rel=1e-12)
    assert info["gap_max"] == pytest.approx(gaps.max(), rel=1e-12)
    # Boundary edges of the mesh: the prescribed gaps, possibly split further by phase 2.
    be = boundary_edges(T)
    blen = np.linalg.norm(P[be[:, 1]] - P[be[:, 0]], axis=1)
    assert blen.max() <= 3 * d_n * (1 + 1e-9)
    assert len(be) >= len(V) + k

    # Theorem 2: every edge <= 6 d_n and the edge ratio <= 6.
    q = mesh.quality()
    assert q.longest_edge <= 6 * d_n * (1 + 1e-9)
    assert q.edge_ratio <= 6 * (1 + 1e-9), (q.edge_ratio, n)
    return mesh


# -- the benchmark polygons ---------------------------------------------------------
BENCH = benchmark_polygons()


def test_seven_benchmarks():
    assert len(BENCH) == 7


@pytest.mark.parametrize("name", sorted(BENCH))
def test_tplus_benchmark(name):
    polygon = BENCH[name]
    n, ref = n_where_theorem_applies(polygon)
    assert n is not None, f"{name}: Theorem 2 never applies for n <= {N_MAX}"
    check_tplus(polygon, n, ref)
    # and a larger n as well
    check_tplus(polygon, 3 * n, phase1(polygon, 3 * n))


# -- random polygons -----------------------------------------------------------------
def _random_cases():
    gens = [("convex", polygons.convex), ("star", polygons.star), ("holes", polygons.with_holes)]
    return [(kind, gen, 7000 + i) for i in range(N_RANDOM // 3) for kind, gen in gens]


@pytest.mark.parametrize("kind,gen,seed", _random_cases(), ids=[f"{k}-{s}" for k, _, s in _random_cases()])
def test_tplus_random(kind, gen, seed):
    polygon = gen(seed)
    n, ref = n_where_theorem_applies(polygon)
    if n is None:  # a tiny hole edge can need more points than we want to spend here
        pytest.skip(f"Theorem 2 does not apply for n <= {N_MAX}")
    check_tplus(polygon, n, ref)


def test_most_random_polygons_are_checked():
    found = sum(n_where_theorem_applies(gen(seed))[0] is not None for _, gen, seed in _random_cases())
    assert found >= 50, found


# -- reporting when the theorem does not apply ------------------------------------------
def test_hypotheses_reported_false():
    # Small bolt holes: d_n stays at l(V,V), so d_n <= l(V,V)/2 fails for moderate n.
    from pathlib import Path

    from uniform2d import read_polygon

    plate = read_polygon(Path(__file__).resolve().parents[1] / "data" / "plate_bolts.json")
    mesh = tplus(plate, 400)
    ref = phase1(plate, 400)
    assert mesh.info["hypotheses"] == ref["hypotheses"]
    assert mesh.info["hypotheses"]["d_n <= l(V,V)/2"] is False
    assert mesh.info["theorem_applies"] is False and mesh.info["edge_ratio_bound"] is None
    check_mesh(np.asarray(mesh.points), np.asarray(mesh.triangles), plate)
    assert len(mesh.points) == len(plate.vertices) + 400


# -- k > n -----------------------------------------------------------------------------
def test_k_greater_than_n_names_the_smallest_n():
    poly = BENCH["square2holes"]
    n = 5
    assert phase1(poly, n)["k"] > n
    with pytest.raises(InsufficientPointsError, match=r"smallest n that works for this polygon is (\d+)") as exc:
        tplus(poly, n)
    need = int(re.search(r"is (\d+)", str(exc.value)).group(1))
    assert need > n
    mesh = tplus(poly, need)  # the named n works
    assert mesh.info["k"] <= need and len(mesh.points) == len(poly.vertices) + need
    check_mesh(np.asarray(mesh.points), np.asarray(mesh.triangles), poly)
    assert phase1(poly, need - 1)["k"] > need - 1  # and n - 1 does not
    with pytest.raises(InsufficientPointsError):
        tplus(poly, need - 1)


@pytest.mark.parametrize("bad", [0, -1, 2.5, True])
def test_tplus_bad_n(bad):
    with pytest.raises(InsufficientPointsError):
        tplus(BENCH["square"], bad)


# -- uniform_mesh --------------------------------------------------------------------------
def test_uniform_mesh_n_and_size():
    sq = BENCH["rect4x1"]
    mesh = uniform_mesh(sq, 80)
    assert mesh.n_steiner == 80 and len(mesh.points) == len(sq.vertices) + 80
    check_mesh(np.asarray(mesh.points), np.asarray(mesh.triangles), sq)

    size = 0.2
    n = steiner_count_for_size(sq, size)
    mesh = uniform_mesh(sq, size=size)
    assert mesh.n_steiner == n
    check_mesh(np.asarray(mesh.points), np.asarray(mesh.triangles), sq)
    # the size rule gives edges of about the requested size
    assert 0.7 * size < mesh.quality().mean_edge < 1.3 * size


def test_uniform_mesh_exactly_one_of_n_and_size():
    sq = BENCH["square"]
    with pytest.raises(ValueError):
        uniform_mesh(sq, 10, size=0.1)
    with pytest.raises(ValueError):
        uniform_mesh(sq)
    with pytest.raises(InsufficientPointsError):
        uniform_mesh(sq, size=10.0)
    with pytest.raises(ValueError):
        uniform_mesh(sq, size=-1.0)


@pytest.mark.parametrize(
    "width, scale, offset, n", [(0.011995, 1.0, 1e3, 200), (0.010755, 1e6, 1e9, 700)]
)
def test_thin_strip_far_from_the_origin_is_exactly_delaunay(width, scale, offset, n):
    # the strip's boundary points make near-cocircular quadruples; far from the
    # origin the returned points are rounded images of the kernel's, and the
    # triangulation must be Delaunay for those (it was not before insert
    # re-legalised on the returned coordinates)
    ring = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, width), (0.0, width)]) * scale + offset
    P = Polygon(ring)
    m = tplus(P, n)
    assert len(m.points) == 4 + n
    check_mesh(m.points, m.triangles, P)
