"""The point-moving kernel (uniform2d._kernel.relax) and optimize.improve / lattice_seed.

The kernel keeps its own triangulation up to date by flips while points move; the
independent reference here is a fresh exact CDT of the same points
(:func:`uniform2d.insert` with the points as sites), which must be the same set of
triangles, and the full invariant checker on both.
"""

import numba
import numpy as np
import pytest
import shapely

import uniform2d
from uniform2d import Polygon, SizeField
from uniform2d._kernel import cdt, descent, relax, star as kstar
from uniform2d._kernel import objective as kobj
from uniform2d.optimize import improve, lattice_seed, target_size
from uniform2d.optimize.moves import KernelMesh
from uniform2d.optimize.schedule import FLAT

from uniform2d.testing import check_mesh
from support.benchmarks import benchmark_polygons
from uniform2d.testing.polygons import convex, star, with_holes

BENCH = benchmark_polygons()


def _triangle_set(tri):
    out = set()
    for a, b, c in np.asarray(tri):
        k = int(np.argmin((a, b, c)))
        r = (a, b, c)[k:] + (a, b, c)[:k]
        out.add(tuple(int(x) for x in r))
    return out


def _ramp(p):
    """A size field over p's box, from 1 on one side to 2 on the other."""
    x0, y0, x1, y1 = p.to_shapely().bounds
    x, y = np.linspace(x0, x1, 5), np.linspace(y0, y1, 5)
    return SizeField(x, y, np.tile(1.0 + np.linspace(0, 1, 5), (5, 1)))


def _polygons():
    rng = np.random.default_rng(7)
    ps = [BENCH["square2holes"], BENCH["star10"], BENCH["lshape"]]
    ps += [convex(rng), star(rng), with_holes(rng)]
    return ps


def _half_frozen(st, nV):
    """Freeze the sites left of their median abscissa (as the optimiser freezes a
    lattice's deep interior): whole triangles of fixed vertices, which a
    restricted run leaves out of its passes."""
    x = st.xy[nV:, 0]
    st.role[nV:][(x < np.median(x)) & (st.role[nV:] == relax.FREE)] = relax.FIXED


def _live(st, k, restrict):
    """The kernel's live set and the dead slots' part, as its passes take them."""
    alive, slots, _ = kstar.live_slots(st.m, st.role, restrict)
    return slots, alive, kstar.dead_part(st.m, alive, st.hv, st.href, k)


def _scattered(k, restrict):
    """Polygon k of :func:`_polygons` with a scattered start (many moves and
    flips) loaded, jittered off INSERT's exact symmetries so that the Delaunay
    triangulation is unique and can be compared; with ``restrict``, half frozen."""
    p = _polygons()[k]
    n = 120
    ins = uniform2d.insert(p, n)
    rng = np.random.default_rng(k)
    h = target_size(p, n)
    sites = ins.points.copy()
    inner = ~ins.on_boundary
    jit = sites[inner] + rng.uniform(-0.05, 0.05, (inner.sum(), 2)) * h
    ok = shapely.contains_xy(p.to_shapely(), jit[:, 0], jit[:, 1])
    sites[np.flatnonzero(inner)[ok]] = jit[ok]
    res = uniform2d.insert(p, 0, sites=sites)
    st = KernelMesh.from_mesh(p, res.mesh_points, res.triangles)
    if restrict:  # the passes skip the triangles of the frozen half, and must still keep the CDT
        _half_frozen(st, len(p.vertices))
    return p, st


@pytest.mark.parametrize("k", range(6))
@pytest.mark.parametrize("stage", ["spring", "descend", "spread"])
@pytest.mark.parametrize("restrict", [False, True])
def test_kernel_triangulation_is_the_fresh_cdt_of_its_points(k, stage, restrict):
    p, st = _scattered(k, restrict)
    nV = len(p.vertices)
    fixed = st.role == relax.FIXED
    before = st.xy.copy()
    args = (st.m, st.role, st.eid, st.t, st.ea, st.ed, st.hv, st.href)
    if stage == "spring":
        made = relax.spring(*args, 30, 0.2, 1.02, 1e-4, 0.3, FLAT, restrict)
    elif stage == "descend":  # both end in their best state, which may be the start
        made, _ = relax.descend(*args, 0, 10, 4, 0.05, FLAT, restrict)
    else:
        made = relax.spread(*args, 0, 10, 0.05, FLAT, restrict)
    assert made >= 1
    moved = np.abs(st.xy - before).max(axis=1) > 0
    assert not moved[fixed].any()  # FIXED vertices stay
    assert moved[nV:].any() or stage != "spring"
    # the kernel's triangulation (normalised coordinates) vs a fresh exact CDT
    pts = st.points()
    fresh = uniform2d.insert(p, 0, sites=pts[nV:])
    assert np.array_equal(fresh.mesh_points, pts)
    kern = cdt.triangle_list(st.m)
    assert _triangle_set(kern) == _triangle_set(fresh.triangles)
    check_mesh(pts, kern, p)


@pytest.mark.parametrize("restrict", [False, True])
@pytest.mark.parametrize("graded", [False, True])
@pytest.mark.parametrize("k", [2, 4, 6])
def test_descent_weights_are_the_linearised_log_of_the_objective(k, graded, restrict):
    # independent reference: the p-power sums over the unique edges and the
    # triangles, computed with numpy from the kernel's triangle list
    p = BENCH["square2holes"]
    size = _ramp(p) if graded else None
    res = uniform2d.insert(p, 0, sites=lattice_seed(p, 150))
    st = KernelMesh.from_mesh(p, res.mesh_points, res.triangles, size=size)
    tri = cdt.triangle_list(st.m)
    xy = st.xy
    E = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    E = np.unique(E, axis=0)
    tgt = 0.5 * (st.hv[E[:, 0]] + st.hv[E[:, 1]]) * st.href
    ell = np.linalg.norm(xy[E[:, 1]] - xy[E[:, 0]], axis=1) / tgt
    per = np.linalg.norm(xy[tri] - xy[np.roll(tri, -1, axis=1)], axis=2).sum(axis=1)
    pi = per / (st.hv[tri].sum(axis=1) * st.href)
    P = 2.0**k
    if restrict:  # the frozen half's triangles come from the dead part
        _half_frozen(st, len(p.vertices))
    # with movable_short (here: the ungraded meshes) the short-edge sum leaves
    # out the edges no move can change (fixed at both ends); without, every edge
    movable = st.role != relax.FIXED
    moves = movable[E[:, 0]] | movable[E[:, 1]]
    assert (~moves).any() and moves.any()
    if graded:
        moves[:] = True
    s_len, s_short, s_per = (ell**P).sum(), (ell[moves] ** -P).sum(), (pi**P).sum()
    expect = {
        kobj.BALANCED: (2 / s_len, 1 / s_short, 1 / s_per),
        kobj.RATIO: (1 / s_len, 1 / s_short, 0.0),
        kobj.MAX_EDGE: (1.0, 0.0, 0.0),
        kobj.MAX_PERIMETER: (0.0, 0.0, 1.0),
    }
    live = _live(st, k, restrict)
    assert restrict == (len(live[0]) < len(tri))
    for obj, want in expect.items():
        got = descent._weights(st.m, st.role, not graded, st.hv, st.href, k, obj, *live)
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=0)


@pytest.mark.parametrize("restrict", [False, True])
@pytest.mark.parametrize("graded", [False, True])
def test_measure_weights_pass_gives_measures_bit_for_bit(graded, restrict):
    # the weights themselves are checked against numpy above (_weights is this pass);
    # restricted, the extremes are those of the live and the dead triangles together
    p = BENCH["star10"]
    size = _ramp(p) if graded else None
    res = uniform2d.insert(p, 0, sites=lattice_seed(p, 150))
    st = KernelMesh.from_mesh(p, res.mesh_points, res.triangles, size=size)
    if restrict:
        _half_frozen(st, len(p.vertices))
    for obj in (kobj.BALANCED, kobj.RATIO, kobj.MAX_EDGE, kobj.MAX_PERIMETER):
        for k in (3, 8):
            got = descent._measure_weights(st.m, st.role, restrict, st.hv, st.href, k,
                                           obj, *_live(st, k, restrict))
            assert got[:3] == relax.measure(st.m, st.hv, st.href)


@pytest.mark.parametrize("graded", [False, True])
def test_edge_cv_is_the_cv_of_the_normalised_unique_edges(graded):
    # independent reference: numpy over the unique edges of the kernel's triangles
    p = BENCH["square2holes"]
    size = _ramp(p) if graded else None
    res = uniform2d.insert(p, 120)
    st = KernelMesh.from_mesh(p, res.mesh_points, res.triangles, size=size)
    tri = cdt.triangle_list(st.m)
    E = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    E = np.unique(np.sort(E, axis=1), axis=0)
    L = np.linalg.norm(st.xy[E[:, 1]] - st.xy[E[:, 0]], axis=1)
    ell = L / (0.5 * (st.hv[E[:, 0]] + st.hv[E[:, 1]]))
    assert relax.edge_cv(st.m, st.hv, st.href) == pytest.approx(ell.std() / ell.mean(), rel=1e-9)


def test_improve_best_finishes_the_start_its_ranking_prefers():
    # INSERT's points, and the same points jittered by up to 0.3 target sizes:
    # the ranking must keep the unjittered start (a reversed or broken ranking
    # finishes the other), and the returned mesh is valid with every site kept
    from uniform2d.optimize.moves import improve_best

    p = BENCH["lshape"]
    n = 150
    h = target_size(p, n)
    rng = np.random.default_rng(3)
    ins = uniform2d.insert(p, n)
    inner = ~ins.on_boundary
    scattered = ins.points.copy()
    jit = scattered[inner] + rng.uniform(-0.3, 0.3, (inner.sum(), 2)) * h
    ok = shapely.contains_xy(p.to_shapely(), jit[:, 0], jit[:, 1])
    scattered[np.flatnonzero(inner)[ok]] = jit[ok]
    starts = [(scattered, None, None), (ins.points, None, None)]
    won, pts, tri, info = improve_best(p, starts, href=h)
    assert won == 1
    check_mesh(pts, tri, p)
    assert len(pts) == len(p.vertices) + n
    other = improve(p, scattered, href=h)
    q_won, q_other = uniform2d.quality(pts, tri, p), uniform2d.quality(other[0], other[1], p)
    assert q_won.cv_edge < q_other.cv_edge


@pytest.mark.parametrize("k", range(6))
def test_boundary_points_slide_on_their_own_edge_in_order(k):
    p = _polygons()[k]
    res0 = uniform2d.insert(p, 150)
    sites = res0.points
    pts, tri, info = improve(p, sites)
    nV = len(p.vertices)
    assert pts.shape == (nV + len(sites), 2)
    assert np.array_equal(pts[:nV], p.vertices)
    check_mesh(pts, tri, p)
    a = p.vertices[p.edges[:, 0]]
    d = p.vertices[p.edges[:, 1]] - a
    ext = max(np.ptp(p.vertices[:, 0]), np.ptp(p.vertices[:, 1]))

    def edge_of(q):
        s = np.clip(((q - a) * d).sum(1) / (d * d).sum(1), 0, 1)
        dist = np.linalg.norm(a + s[:, None] * d - q, axis=1)
        e = int(np.argmin(dist))
        return e, s[e], dist[e]

    for i in np.flatnonzero(res0.on_boundary):
        e0, _, _ = edge_of(sites[i])
        e1, s1, dist1 = edge_of(pts[nV + i])
        assert e1 == e0 and dist1 <= 1e-12 * ext and 0 < s1 < 1
    # order along each edge is kept
    for e in range(len(a)):
        idx = [i for i in np.flatnonzero(res0.on_boundary) if edge_of(sites[i])[0] == e]
        s0 = [edge_of(sites[i])[1] for i in idx]
        s1 = [edge_of(pts[nV + i])[1] for i in idx]
        assert np.array_equal(np.argsort(s0), np.argsort(s1))


def test_improve_does_not_mutate_and_is_deterministic():
    p = BENCH["hexagon"]
    sites = np.array(uniform2d.insert(p, 80).points)
    keep = sites.copy()
    a = improve(p, sites)
    b = improve(p, sites)
    assert np.array_equal(sites, keep)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_improve_makes_a_scattered_start_more_uniform():
    p = BENCH["square"]
    sites = uniform2d.insert(p, 300).points
    start = uniform2d.insert(p, 0, sites=sites)
    before = uniform2d.quality(start.mesh_points, start.triangles, p)
    pts, tri, _ = improve(p, sites, objective="ratio")
    after = uniform2d.quality(pts, tri, p)
    assert after.edge_ratio < 0.8 * before.edge_ratio  # INSERT on a square: 2.0
    assert after.cv_edge < before.cv_edge


def test_graded_field_grades_the_mesh():
    """h = 1 + 2x on the unit square: edges near x = 1 come out about 3x those near 0."""
    p = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    x = np.linspace(0, 1, 5)
    field = SizeField(x, x, np.tile(1 + 2 * x, (5, 1)))
    n = 400
    res = uniform2d.insert(p, n, size=field)
    pts, tri, _ = improve(p, res.points, size=field)
    check_mesh(pts, tri, p)
    q = pts[tri]
    L = np.linalg.norm(q - q[:, [1, 2, 0]], axis=2).mean(axis=1)
    cx = q[:, :, 0].mean(axis=1)
    lo, hi = L[cx < 0.2].mean(), L[cx > 0.8].mean()
    assert 2.0 < hi / lo < 4.0
    # against the field, edges are near-uniform: normalised spread well below the raw one
    hmid = 1 + 2 * cx
    assert (L / hmid).std() / (L / hmid).mean() < 0.5 * L.std() / L.mean()


@pytest.mark.parametrize("name", sorted(BENCH))
@pytest.mark.parametrize("count", [1, 37, 500])
def test_lattice_seed_count_inside_and_clear_of_the_boundary(name, count):
    p = BENCH[name]
    s = lattice_seed(p, count)
    assert s.shape == (count, 2)
    shp = p.to_shapely()
    assert shapely.contains_xy(shp, s[:, 0], s[:, 1]).all()
    assert len(np.unique(s, axis=0)) == count
    assert np.array_equal(s, lattice_seed(p, count))
    if count >= 37:
        d = shapely.distance(shp.boundary, shapely.points(s))
        assert d.min() > 0.2 * target_size(p, count)


@pytest.mark.parametrize("objective", ["balanced", "ratio", "max_edge", "max_perimeter"])
def test_spread_stage_lowers_cv_and_never_the_objective(objective):
    from uniform2d.optimize import objective_value
    from uniform2d.optimize.objective import extremes as _extremes

    p = BENCH["lshape"]
    sites = uniform2d.insert(p, 250).points
    h = target_size(p, len(sites))
    a = improve(p, sites, objective=objective, spread_sweeps=0)
    b = improve(p, sites, objective=objective, spread_sweeps=30)
    va = objective_value(objective, *_extremes(a[0], a[1]), h)
    vb = objective_value(objective, *_extremes(b[0], b[1]), h)
    assert vb <= va * (1 + 1e-12)  # held in the kernel; mapping back rounds
    qa, qb = uniform2d.quality(a[0], a[1], p), uniform2d.quality(b[0], b[1], p)
    assert qb.cv_edge < qa.cv_edge


@pytest.mark.parametrize("name", sorted(BENCH))
def test_corner_fans_split_each_corner_into_near_60_degree_angles(name):
    from uniform2d.optimize.rows import FAN_CAP
    from uniform2d.optimize.rows import corner_fans as _corner_fans

    p = BENCH[name]
    V, E = p.vertices, p.edges
    theta = p.interior_angles()
    piece = np.full(len(E), 0.05)
    pts, gaps = _corner_fans(p, piece, 1.0)
    pts = np.concatenate(pts) if pts else np.empty((0, 2))
    # independent count: k - 1 points at every corner, k the nearest whole number of 60° parts
    k = np.array([max(1, int(np.floor(t / (np.pi / 3) + 0.5))) for t in theta])
    k[k == 3] = 1  # near-straight vertices: left to the rows' apexes
    assert len(pts) == (k - 1).sum()
    for v in range(len(V)):
        near = pts[np.isclose(np.hypot(*(pts - V[v]).T), 0.05, rtol=1e-12)]
        out = V[E[E[:, 0] == v][0, 1]] - V[v]  # the edge leaving v: P on its left
        rel = near - V[v]
        ang = np.sort((np.arctan2(rel[:, 1], rel[:, 0]) - np.arctan2(out[1], out[0])) % (2 * np.pi))
        assert len(near) == k[v] - 1
        assert np.allclose(ang, np.arange(1, k[v]) * theta[v] / k[v], atol=1e-12)
        assert k[v] == 1 or abs(np.degrees(theta[v] / k[v]) - 60) <= 30 + 1e-9
    # a piece longer than FAN_CAP * h is capped there
    far, _ = _corner_fans(p, np.full(len(E), 10.0), 0.05)
    for q in far:
        assert np.isclose(np.min(np.hypot(*(V - q).T)), FAN_CAP * 0.05, rtol=1e-12)


@pytest.mark.parametrize("name", ["square", "square2holes", "star10", "heptagon_short"])
def test_boundary_rows_are_fans_and_equilateral_apexes_clear_of_each_other(name):
    from scipy.spatial import cKDTree

    from uniform2d.geometry import polygon_edges as _edge_geometry
    from uniform2d.optimize.boundary import boundary_counts as _boundary_counts
    from uniform2d.optimize.rows import boundary_rows as _boundary_rows
    from uniform2d.optimize.rows import corner_fans as _corner_fans

    p = BENCH[name]
    a, d, L = _edge_geometry(p)
    h = target_size(p, 300)
    m = _boundary_counts(L, h, 300)
    R = _boundary_rows(p, m, h)
    g = L / m
    fans, fan_gaps = _corner_fans(p, g, h)
    fans = np.concatenate(fans) if fans else np.empty((0, 2))
    shp = p.to_shapely()
    assert shapely.contains_xy(shp, R[:, 0], R[:, 1]).all()
    # every row point is a corner's fan point or the apex over the middle of a piece of some edge
    spacing = []
    for r in R:
        f = np.flatnonzero(np.all(fans == r, axis=1))
        if len(f):
            spacing.append(np.concatenate(fan_gaps)[f[0]])
            continue
        q = r - a
        s = (q * d).sum(1) / (L * L)
        dist = np.abs(d[:, 0] * q[:, 1] - d[:, 1] * q[:, 0]) / L
        k = (s * m) % 1.0
        hit = np.flatnonzero((np.abs(dist - g * np.sqrt(3) / 2) < 1e-9 * g) & (np.abs(k - 0.5) < 1e-9))
        assert len(hit) >= 1
        spacing.append(g[hit[0]])
    dmin, _ = cKDTree(R).query(R, k=2)
    assert (dmin[:, 1] >= 0.75 * np.array(spacing) * (1 - 1e-12)).all()
    # only crowded corners lose points: at most two each
    assert len(R) >= m.sum() - 2 * len(p.vertices)


def test_improve_rejects_bad_input_with_typed_errors():
    p = BENCH["square"]
    with pytest.raises(ValueError, match="objective must be one of"):
        improve(p, [(0.5, 0.5)], objective="nope")
    with pytest.raises(uniform2d.InvalidSitesError, match="outside the polygon"):
        improve(p, [(5.0, 5.0)])


@numba.njit
def _tri_arrays(m):
    return m.xy.copy(), m.tv.copy(), m.tw.copy(), m.tc.copy(), m.vseg.copy(), m.vcs.copy(), m.tstamp.copy()


def _state(st):
    """The points, edge parameters and triangulation of a loaded mesh, then its slots' rewrite counters."""
    xy, *rest = _tri_arrays(st.m)
    return [xy, st.t.copy(), *rest]


@pytest.mark.parametrize("restrict", [False, True])
def test_descend_ends_exactly_in_its_best_state(restrict):
    # the flips made after the best sweep are undone and its points put back:
    # the state is bit for bit that of a run stopped right after that sweep
    undone = 0
    for k in range(6):
        def run(sweeps):
            _, st = _scattered(k, restrict)
            args = (st.m, st.role, st.eid, st.t, st.ea, st.ed, st.hv, st.href)
            made, best = relax.descend(*args, 0, sweeps, 4, 0.05, FLAT, restrict)
            return made, best, _state(st)

        made, best, final = run(10)
        # the first run that reaches the same best value stopped at the best sweep
        j = next(s for s in range(made + 1) if run(s)[1] == best)
        ref = run(j)[2]
        for a, b in zip(final[:-1], ref[:-1]):
            np.testing.assert_array_equal(a, b)
        undone += bool((final[-1] != ref[-1]).any())  # flips after sweep j (and undone)
    assert undone
