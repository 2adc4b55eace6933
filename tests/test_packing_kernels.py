"""The graded start's compiled parts (uniform2d._kernel.front, cells.grid_sizes,
the Lloyd pass's cell lookup) and its shortcut for the behind-points test give,
bit for bit, what the numpy code they replaced gave: that code is kept here as the
reference and both run on the same inputs (random ones, and the fronts of real
rounds)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from scipy.spatial import Delaunay, cKDTree

from uniform2d import Polygon, SizeField
from uniform2d._kernel.cells import weighted_centroids
from uniform2d._kernel.rank import bilinear
from uniform2d.graded import boundary_sites
from uniform2d.grading import as_field, scale_for_count
from uniform2d.optimize import packing
from uniform2d.triangulation import triangulate

LSHAPE = Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])
HOLED = Polygon([(0, 0), (4, 0), (4, 2), (0, 2)], [[(1, 0.6), (1.6, 0.6), (1.6, 1.2), (1, 1.2)]])
ang = -2 * np.pi * np.arange(24) / 24
RING = Polygon([(-6, -6), (6, -6), (6, 6), (-6, 6)], [np.column_stack([np.cos(ang), np.sin(ang)])])
CASES = [
    (LSHAPE, lambda p: 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1]), 800),
    (HOLED, lambda p: 0.05 + 0.1 * p[:, 0], 600),
    (RING, lambda p: 0.2333 + 0.27 * np.maximum(np.hypot(p[:, 0], p[:, 1]) - 1, 0), 900),
]


# -- the numpy code the kernels replaced (uniform2d.optimize.packing before) ----------
def _loops_ref(ends):
    k = len(ends)
    n = int(ends.max()) + 1 if k else 0
    out_deg = np.bincount(ends[:, 0], minlength=n)
    in_deg = np.bincount(ends[:, 1], minlength=n)
    start_of = np.full(n, -1, np.int64)
    start_of[ends[:, 0]] = np.arange(k)
    succ = np.where((out_deg[ends[:, 1]] == 1) & (in_deg[ends[:, 1]] == 1), start_of[ends[:, 1]], -1)
    seen = np.zeros(k, bool)
    loops = []
    for first in range(k):
        chain, e = [], first
        while e >= 0 and not seen[e]:
            seen[e] = True
            chain.append(e)
            e = succ[e]
        if e == first:
            loops.append(chain)
    return loops


def _clockwise_ref(loops, P):
    loops = [c for c in loops if len(c) >= 3]
    if not loops:
        return []
    idx = np.concatenate(loops)
    lens = np.array([len(c) for c in loops])
    first = np.cumsum(lens) - lens
    after = np.arange(1, len(idx) + 1)
    after[first + lens - 1] = first
    x, y = P[idx, 0], P[idx, 1]
    area2 = np.add.reduceat(x * y[after] - y * x[after], first)
    return [c for c, a in zip(loops, area2.tolist()) if a < 0]


def _respace_ref(cand, ends, size, n0=0):
    new = {}
    drop = np.zeros(len(cand), dtype=bool)
    t = (np.arange(packing.RING_SAMPLES) + 0.5) / packing.RING_SAMPLES
    for chain in _clockwise_ref(_loops_ref(ends), cand):
        a = cand[chain]
        d = np.roll(a, -1, axis=0) - a
        mids = a[:, None, :] + t[None, :, None] * d[:, None, :]
        inv = (1.0 / size(mids.reshape(-1, 2))).reshape(len(a), -1).mean(axis=1)
        inv *= np.hypot(d[:, 0], d[:, 1])
        cum = np.concatenate([[0.0], np.cumsum(inv)])
        m = int(np.rint(cum[-1]))
        if m == len(a) or (m < len(a) and bool(np.all(ends[chain] < n0))):
            continue
        goal = cum[-1] * np.arange(m) / m
        seg = np.clip(np.searchsorted(cum, goal, side="right") - 1, 0, len(a) - 1)
        frac = (goal - cum[seg]) / np.maximum(inv[seg], 1e-300)
        new[chain[0]] = a[seg] + np.clip(frac, 0.0, 1.0)[:, None] * d[seg]
        drop[chain] = True
    if not new:
        return cand
    out, prev = [], 0
    for i in sorted(new):
        out += [cand[prev:i][~drop[prev:i]], new[i]]
        prev = i + 1
    out.append(cand[prev:][~drop[prev:]])
    return np.concatenate(out)


def _fronts(poly, h, n, rounds=40):
    """(candidates before respacing, their ends, n0, size) of the first rounds of
    frontal_seed on poly (the loop of frontal_seed, the apexes taken before
    _respace_rings)."""
    field = as_field(poly, h)
    s = scale_for_count(poly, field, n)
    size = field.scaled(s)
    b, _ = boundary_sites(poly, field, s, n)
    shape, lines = packing._shape(poly)
    P = np.concatenate([poly.vertices, b])
    n0 = len(P)
    active = np.ones(n0, bool)
    got = []
    real = packing._respace_rings
    try:
        def spy(cand, ends, size_, n0_=0):
            got.append((cand.copy(), ends.copy(), n0_, size_))
            return real(cand, ends, size_, n0_)
        packing._respace_rings = spy
        for _ in range(rounds):
            act = np.flatnonzero(active)
            closed = (lambda X, r, _, t=cKDTree(P[~active]): t.query(X)[0] < r) if (~active).any() else None
            cand, hc, on_open = packing._front(P, act, Delaunay(P[act]), size, shape, n0, closed)
            active[act] = False
            active[on_open] = True
            ok = packing.shapely.contains_xy(shape, cand[:, 0], cand[:, 1])
            ok[ok] = packing._clear(cand[ok], hc[ok], P, size(P), lines, size)
            keep = np.flatnonzero(ok)
            if not len(keep):
                break
            keep = keep[packing._greedy(cand[keep], hc[keep])]
            P = np.concatenate([P, cand[keep]])
            active = np.concatenate([active, np.ones(len(keep), bool)])
    finally:
        packing._respace_rings = real
    return got


@pytest.fixture(scope="module")
def fronts():
    return [f for poly, h, n in CASES for f in _fronts(poly, h, n)]


def _random_ends(rng):
    """Front edges: some closed loops (either turn), open chains, a vertex where two
    chains meet, shuffled."""
    ends, v = [], 0
    for _ in range(rng.integers(1, 8)):
        k = int(rng.integers(1, 9))
        loop = rng.random() < 0.7
        ids = v + np.arange(k + (0 if loop else 1))
        v += len(ids)
        nxt = np.roll(ids, -1) if loop else ids[1:]
        ends += list(zip(ids[:len(nxt)], nxt))
    if len(ends) > 3 and rng.random() < 0.5:  # a vertex where two edges start
        ends.append((ends[0][0], ends[2][1]))
    ends = np.array(ends, dtype=np.int64)
    return ends[rng.permutation(len(ends))]


def test_front_loops_are_the_python_walks():
    rng = np.random.default_rng(11)
    for _ in range(300):
        ends = _random_ends(rng)
        P = rng.normal(size=(len(ends), 2))
        want = _clockwise_ref(_loops_ref(ends), P)
        idx, lens = packing._clockwise(ends, P)
        got = np.split(idx, np.cumsum(lens)[:-1]) if len(lens) else []
        assert [list(c) for c in want] == [c.tolist() for c in got]


def test_front_loops_of_real_fronts(fronts):
    assert sum(len(packing._clockwise(e, c)[1]) for c, e, _, _ in fronts) > 20
    for cand, ends, _, _ in fronts:
        want = _clockwise_ref(_loops_ref(ends), cand)
        idx, lens = packing._clockwise(ends, cand)
        assert np.concatenate(want).tolist() == idx.tolist() if want else len(idx) == 0


def test_respaced_rings_are_the_numpy_ones_bit_for_bit(fronts):
    changed = 0
    for cand, ends, n0, size in fronts:
        want = _respace_ref(cand, ends, size, n0)
        got = packing._respace_rings(cand, ends, size, n0)
        assert got.tobytes() == want.tobytes()
        changed += len(got) != len(cand) or got.tobytes() != cand.tobytes()
    assert changed > 5  # rings were respaced, not only passed through


def test_respaced_rings_on_boundary_only_gain_points():
    """A clockwise ring on boundary points (indices below n0) asking for fewer
    points keeps its apexes, in both versions; above n0 it loses some."""
    k = 12
    a = -2 * np.pi * np.arange(k) / k
    cw = np.column_stack([np.cos(a), np.sin(a)])
    ends = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    perimeter = np.sum(np.linalg.norm(np.roll(cw, -1, axis=0) - cw, axis=1))
    field = SizeField.constant((-2, -2, 2, 2), perimeter / 8)
    for n0, m in ((100, k), (0, 8)):
        got = packing._respace_rings(cw, ends, field, n0)
        assert len(got) == m
        assert got.tobytes() == _respace_ref(cw, ends, field, n0).tobytes()


def test_compiled_field_gives_the_fields_values():
    """The packing's compiled field (cells.grid_sizes, checked point by point in
    test_lloyd) returns SizeField's very values; a plain callable is kept."""
    rng = np.random.default_rng(5)
    x, y = np.array([-1.0, -0.9, 0.0, 0.05, 2.0, 3.0]), np.array([0.0, 0.1, 0.15, 1.0, 4.0])
    f = SizeField(x, y, rng.uniform(0.1, 2.0, (len(y), len(x))))
    P = np.column_stack([rng.uniform(-2, 4, 500), rng.uniform(-1, 5, 500)])
    assert packing._compiled(f)(P).tobytes() == f(P).tobytes()
    assert packing._compiled(np.hypot) is np.hypot


@njit(error_model="numpy")
def _centroids_before(xy, tv, gx, gy, gv, power):
    """The Lloyd pass before its lookup took a multiplication: cell found from
    (x - g0) / (g[-1] - g0), h ** power in numba's integer power."""
    n = xy.shape[0]
    num = np.zeros((n, 2))
    den = np.zeros(n)
    for t in range(tv.shape[0]):
        a, b, c = tv[t, 0], tv[t, 1], tv[t, 2]
        bx, by = xy[b, 0] - xy[a, 0], xy[b, 1] - xy[a, 1]
        cx, cy = xy[c, 0] - xy[a, 0], xy[c, 1] - xy[a, 1]
        d = 2.0 * (bx * cy - by * cx)
        bb, cc = bx * bx + by * by, cx * cx + cy * cy
        ox = xy[a, 0] + (cy * bb - by * cc) / d
        oy = xy[a, 1] + (bx * cc - cx * bb) / d
        for k in range(3):
            v, w1, w2 = tv[t, k], tv[t, (k + 1) % 3], tv[t, (k + 2) % 3]
            px, py = xy[v, 0], xy[v, 1]
            subs = ((0.5 * (px + xy[w1, 0]), 0.5 * (py + xy[w1, 1]), ox, oy),
                    (ox, oy, 0.5 * (px + xy[w2, 0]), 0.5 * (py + xy[w2, 1])))
            for ax, ay, qx, qy in subs:
                sx = (px + ax + qx) / 3.0
                sy = (py + ay + qy) / 3.0
                area = 0.5 * ((ax - px) * (qy - py) - (ay - py) * (qx - px))
                x = min(max(sx, gx[0]), gx[-1])
                y = min(max(sy, gy[0]), gy[-1])
                ij = [0, 0]
                for g, z, s in ((gx, x, 0), (gy, y, 1)):
                    last = g.shape[0] - 2
                    i = min(max(int((z - g[0]) / (g[-1] - g[0]) * (last + 1)), 0), last)
                    while i > 0 and g[i] > z:
                        i -= 1
                    while i < last and g[i + 1] <= z:
                        i += 1
                    ij[s] = i
                w = area / bilinear(gx, gy, gv, ij[0], ij[1], x, y) ** power
                num[v, 0] += w * sx
                num[v, 1] += w * sy
                den[v] += w
    out = np.empty((n, 2))
    for v in range(n):
        out[v, 0] = num[v, 0] / den[v]
        out[v, 1] = num[v, 1] / den[v]
    return out


@pytest.mark.parametrize("power", [2, 3, 4])
def test_lloyd_centroids_are_those_before_bit_for_bit(power):
    rng = np.random.default_rng(power)
    sq = Polygon([(0, 0), (2, 0), (2, 1), (0, 1)])
    P, T = triangulate(sq, rng.random((400, 2)) * [2, 1], None)
    for x in (np.linspace(-0.1, 2.1, 23), np.array([-0.1, 0.05, 0.3, 1.7, 2.1])):
        y = np.array([-0.1, 0.2, 0.25, 1.1])
        f = SizeField(x, y, rng.uniform(0.1, 2.0, (len(y), len(x))))
        got = weighted_centroids(P, T, f.x, f.y, f.values, power)
        assert got.tobytes() == _centroids_before(P, T, f.x, f.y, f.values, power).tobytes()


def test_behind_test_is_the_trees():
    """_Behind.closer (a known neighbour first, the tree for the rest) answers
    ``nearest < r`` exactly as one tree over the points behind, also for radii
    within rounding of a neighbour's distance."""
    rng = np.random.default_rng(2)
    P = rng.random((600, 2))
    act = np.arange(600)
    tri = Delaunay(P)
    behind = packing._Behind()
    left = rng.choice(600, 250, replace=False)
    behind.add(P, act, tri, np.sort(left))
    one = cKDTree(P[np.sort(left)])
    corners = tri.simplices[rng.integers(0, len(tri.simplices), 400)]
    X = P[corners].mean(axis=1) + rng.normal(scale=0.01, size=(400, 2))
    d = one.query(X)[0]
    nb = behind.near[corners]
    kd = np.where(nb >= 0, np.hypot(*(X[:, None, :] - P[np.maximum(nb, 0)]).transpose(2, 0, 1)), np.inf)
    for r in (d, np.nextafter(d, np.inf), np.nextafter(d, 0), kd.min(axis=1), 2 * d, 0.5 * d,
              np.nextafter(kd.min(axis=1), np.inf)):
        r = np.where(np.isfinite(r), r, 1.0)
        assert np.array_equal(behind.closer(X, r, corners), one.query(X)[0] < r)
    assert (nb >= 0).any()


def _greedy_ref(C, hC):
    i, j = packing._within(cKDTree(C).query_ball_point(C, packing.SPACING * hC))
    close = (i != j) & (np.hypot(*(C[j] - C[i]).T) < packing.SPACING * np.minimum(hC[i], hC[j]))
    i, j = i[close], j[close]
    start = np.searchsorted(i, np.arange(len(C) + 1))
    blocked = np.zeros(len(C), dtype=bool)
    for k in np.unique(i).tolist():
        if not blocked[k]:
            blocked[j[start[k]:start[k + 1]]] = True
    return np.flatnonzero(~blocked)


def test_greedy_keeps_what_the_python_loop_kept(fronts):
    rng = np.random.default_rng(9)
    for _ in range(50):
        C = rng.random((int(rng.integers(1, 400)), 2))
        hC = rng.uniform(0.01, 0.1, len(C))
        assert np.array_equal(packing._greedy(C, hC), _greedy_ref(C, hC))
    for cand, _, _, size in fronts[::3]:
        h = size(cand)
        got = packing._greedy(cand, h)
        assert np.array_equal(got, _greedy_ref(cand, h)) and len(got) < len(cand)


def test_far_from_the_boundary_only_where_shapely_agrees():
    """_far says a point is at least r from the boundary only where shapely's
    distance is at least r, also with r at shapely's distance and one rounding
    either side of it, far from the origin too; it settles the clear cases."""
    import shapely

    rng = np.random.default_rng(4)
    for shift in (0.0, 1e6):
        for poly in (LSHAPE, HOLED, RING):  # RING: slanted edges, where roundings differ
            off = poly.ring_offsets
            rings = [poly.vertices[off[k]:off[k + 1]] + shift for k in range(len(poly.rings))]
            _, lines = packing._shape(Polygon(rings[0], rings[1:]))
            lo, hi = poly.vertices.min(axis=0) - 0.5, poly.vertices.max(axis=0) + 0.5
            X = rng.uniform(lo, hi, (2000, 2)) + shift
            exact = shapely.distance(lines, shapely.points(X))
            for r in (exact, np.nextafter(exact, np.inf), np.nextafter(exact, 0), 0.5 * exact,
                      rng.uniform(0, 0.5, len(X))):
                far = packing._far(X, r, lines)
                assert np.all(exact[far] >= r[far])
            assert packing._far(X, 0.5 * exact, lines).mean() > 0.99
    assert len(shapely.get_coordinates(lines)) // 2 <= packing.FEW_EDGES
    many = shapely.multilinestrings(rng.random((packing.FEW_EDGES + 1, 2, 2)))
    assert not packing._far(X, np.zeros(len(X)), many).any()  # too many edges: unsure
