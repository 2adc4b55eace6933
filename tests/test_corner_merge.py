"""Resampled ring points slid along the outline (uniform2d.ring_slide) and corners
merged with a close ring point (resample_corners="merge", uniform2d.corner_merge):
the tolerance held (Hausdorff distance measured by shapely), fixed points and
segment ends kept, exactly n points, valid meshes, and bad input refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

import uniform2d as u
from uniform2d.cli.main import main
from uniform2d.corner_merge import merge_corners
from uniform2d.errors import InvalidArgumentError
from uniform2d.outline import resample_polygon
from uniform2d.ring_slide import slide_samples
from uniform2d.testing import check_mesh

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"


def hausdorff(a: u.Polygon, b: u.Polygon) -> float:
    """Ring by ring, segments densified (shapely's discrete Hausdorff distance)."""
    return max(shapely.hausdorff_distance(shapely.LinearRing(ra), shapely.LinearRing(rb),
                                          densify=0.05)
               for ra, rb in zip(a.rings, b.rings))


def zigzag_ring(k=400, seed=1):
    """A closed ring: a circle of radius 3 with radial noise, k vertices."""
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    r = 3 + 0.05 * np.random.default_rng(seed).standard_normal(k)
    return np.c_[r * np.cos(t), r * np.sin(t)]


def measure(ring):
    seg = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    return np.concatenate([cum[:-1], cum[-1] + cum])


def spans(ring, ext, S):
    """Per ring edge (sample e to e + 1): the input path it spans, as a LineString."""
    k = len(ring)
    total = ext[k]
    out = []
    for e in range(len(S)):
        lo = S[e]
        hi = S[e + 1] if e + 1 < len(S) else S[0] + total
        inner = [i for i in range(2 * k) if lo < ext[i] < hi]
        out.append(inner)
    return out


def test_slide_keeps_samples_on_the_outline_within_the_tolerance_and_evens_edges():
    ring = zigzag_ring()
    ext = measure(ring)
    k = len(ring)
    rng = np.random.default_rng(3)
    idx = np.sort(rng.choice(k, 40, replace=False))  # uneven samples on input vertices
    S, P = ext[idx], ring[idx]
    movable = np.ones(len(S), dtype=bool)
    movable[::7] = False
    limit = 0.3
    S2, P2 = slide_samples(ring, ext, S, P, movable, limit)
    outline = shapely.LinearRing(ring)
    assert np.all(np.diff(S2) > 0) and S2[-1] < S2[0] + ext[k]
    assert np.array_equal(P2[~movable], P[~movable]) and np.array_equal(S2[~movable], S[~movable])
    assert max(outline.distance(shapely.Point(p)) for p in P2) < 1e-9
    # every input vertex spanned by an edge within the tolerance of it (or no farther
    # than before, where it was farther): shapely's distance, independently
    before = [max([shapely.LineString([P[e], P[(e + 1) % len(P)]]).distance(
        shapely.Point(ring[i % k])) for i in span], default=0.0)
        for e, span in enumerate(spans(ring, ext, S))]
    for e, span in enumerate(spans(ring, ext, S2)):
        edge = shapely.LineString([P2[e], P2[(e + 1) % len(P2)]])
        for i in span:
            assert edge.distance(shapely.Point(ring[i % k])) <= max(limit, before[e]) + 1e-12
    L = np.hypot(*(np.roll(P, -1, axis=0) - P).T)
    L2 = np.hypot(*(np.roll(P2, -1, axis=0) - P2).T)
    assert L2.min() > L.min() and L2.std() < L.std()


def test_slide_refuses_a_move_that_would_leave_the_tolerance():
    """A square's corner spanned by a sample's edges: the sample may not slide so
    far that the corner leaves the tolerance of the edge spanning it."""
    ring = np.array([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)], float)
    ext = measure(ring)
    S = np.array([0.0, 1.97, 3.0, 6.0])
    P = np.array([(0, 0), (1.97, 0), (2, 1), (0, 2)], float)
    movable = np.array([False, True, False, False])
    corner = shapely.Point(2, 0)
    # equal edges (0,0)-X and X-(2,1) would put X near (1.2, 0), 0.6 from the corner
    S2, P2 = slide_samples(ring, ext, S, P, movable, 0.05)
    assert shapely.LineString([P2[1], P2[2]]).distance(corner) <= 0.05
    S3, P3 = slide_samples(ring, ext, S, P, movable, 0.9)  # a loose tolerance: it slides
    assert S3[1] < 1.5 and shapely.LineString([P3[1], P3[2]]).distance(corner) <= 0.9


def test_merge_corners_within_the_tolerance_and_only_corners_with_free_points():
    ring = np.array([(0, 0), (4, 0), (4.1, 0.3), (4, 4), (0, 4)], float)
    ext = measure(ring)
    S, P = ext[:5], ring.copy()
    corner = np.array([0, 1, 0, 1, 1], bool)
    keep, S2, P2, merged = merge_corners(ring, ext, S, P, corner, ~corner, 1.0, 0.25)
    assert keep.tolist() == [True, True, False, True, True] and merged.sum() == 1
    q = P2[keep]
    assert hausdorff(u.Polygon(ring), u.Polygon(q)) <= 0.25
    # nothing free to merge with: nothing merges
    keep, S3, P3, merged = merge_corners(ring, ext, S, P, corner, np.zeros(5, bool), 1.0, 0.25)
    assert keep.all() and not merged.any() and np.array_equal(P3, P)


def both_modes(p, n):
    """The meshes of ``p`` resampled at tolerance 0.25 with corners kept and merged,
    each checked: valid, exactly n Steiner points, within the tolerance both ways."""
    meshes = (u.uniform_mesh(p, n, resample=0.25),
              u.uniform_mesh(p, n, resample=0.25, resample_corners="merge"))
    for m in meshes:
        r = m.info["resample"]
        check_mesh(m.points, m.triangles, m.polygon)
        assert len(m.points) == r["kept_vertices"] + n
        assert hausdorff(p, m.polygon) <= 0.25 * r["spacing"] * (1 + 1e-9)
        assert r["deviation"] <= 0.25 * r["spacing"] * (1 + 1e-9)
    return meshes


@pytest.mark.parametrize("name", ["brazil", "usa"])
def test_merge_mode_holds_the_tolerance_and_n_on_real_outlines(name):
    p = u.read_polygon(OUTLINES / f"{name}.json")
    n = 800
    keep, mesh = both_modes(p, n)
    # merging only removes corners (kept input vertices) and every kept one is an input vertex
    assert mesh.info["resample"]["corners"] <= keep.info["resample"]["corners"]
    V = p.vertices[:, 0] + 1j * p.vertices[:, 1]
    kept_pts = mesh.polygon.vertices
    r = mesh.info["resample"]
    assert np.isin(kept_pts[:, 0] + 1j * kept_pts[:, 1], V).sum() >= r["kept_vertices"]


def stepped_rectangle():
    """A 4 x 1 rectangle digitised every 0.01, its bottom side stepping up by 0.05 at
    x = 2 (two corners 0.05 apart, under half the spacing at n = 300), a segment
    from a ring vertex and a fixed point inside."""
    s, e = np.arange(0, 4, 0.01), np.arange(0, 1, 0.01)
    a, b = np.arange(0, 2.001, 0.01), np.arange(2, 4, 0.01)
    ring = np.concatenate([np.c_[a, 0 * a], np.c_[b, 0.05 + 0 * b],
                           np.c_[4 + 0 * e, 0.05 + 0.95 * e], np.c_[4 - s, 1 + 0 * s],
                           np.c_[0 * e, 1 - e]])
    return u.Polygon(ring, segments=[(ring[120], (1.2, 0.6))], points=[(3.0, 0.5)]), ring[120]


def test_merge_mode_merges_a_step_and_keeps_fixed_points_and_segment_ends():
    p, seg_end = stepped_rectangle()
    n = 300
    keep, m = both_modes(p, n)
    for mesh in (keep, m):
        pts = {tuple(x) for x in mesh.points}
        assert tuple(seg_end) in pts and (1.2, 0.6) in pts and (3.0, 0.5) in pts
    # the step's corner merged with the sample at the step's other corner: one corner
    # fewer, and the shortest ring edge longer
    assert m.info["resample"]["corners"] == keep.info["resample"]["corners"] - 1
    assert (2.0, 0.0) in {tuple(x) for x in keep.points}
    assert (2.0, 0.0) not in {tuple(x) for x in m.points}

    def shortest_ring_edge(q):
        return min(np.hypot(*(np.roll(r, -1, axis=0) - r).T).min() for r in q.rings)
    assert shortest_ring_edge(m.polygon) > shortest_ring_edge(keep.polygon)


def test_bad_resample_corners_refused():
    p = u.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    with pytest.raises(InvalidArgumentError, match="resample_corners must be one of"):
        u.uniform_mesh(p, 50, resample=0.25, resample_corners="drop")
    with pytest.raises(InvalidArgumentError, match="works with resample="):
        u.uniform_mesh(p, 50, resample_corners="merge")
    with pytest.raises(InvalidArgumentError, match="uniform size"):
        u.uniform_mesh(p, 50, size=lambda x: 0.1 + 0 * x[:, 0], resample=0.25,
                       resample_corners="merge")
    with pytest.raises(InvalidArgumentError, match="resample_corners must be one of"):
        resample_polygon(p, 50, tolerance=0.25, corners=None)


def test_cli_resample_corners(tmp_path, capsys):
    src = OUTLINES / "iceland.json"
    out = tmp_path / "m.vtu"
    assert main(["mesh", str(src), "-n", "200", "--resample-corners", "merge", "-o",
                 str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--resample-corners works with --resample only" in err[0]
    assert not out.exists()
    assert main(["mesh", str(src), "-n", "200", "--resample", "0.25", "--resample-corners",
                 "merge", "-o", str(out)]) == 0
    assert out.exists()


def test_cli_resample_corners_merge_with_a_field_refused(tmp_path, capsys):
    out = tmp_path / "m.vtu"
    assert main(["mesh", str(OUTLINES / "iceland.json"), "-n", "200", "--resample", "0.25",
                 "--resample-corners", "merge", "--refine", "boundary:0.5", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--resample-corners merge works with a uniform size only" in err[0]
    assert not out.exists()


def test_moved_heights_bounds_the_hausdorff_distance_to_the_spanned_input():
    """moved_heights (even_out's check) is at least the Hausdorff distance between
    a moved ring edge and the input path it spans (shapely), and close to it."""
    from uniform2d.ring_slide import moved_heights

    ring = zigzag_ring(k=300, seed=4)
    ext = measure(ring)
    k = len(ring)
    idx = np.arange(0, k, 10)
    S, A = ext[idx], ring[idx]
    rng = np.random.default_rng(5)
    e = np.arange(len(S))
    X = A + 0.05 * rng.standard_normal(A.shape)
    Y = np.roll(A, -1, axis=0) + 0.05 * rng.standard_normal(A.shape)
    got = moved_heights(ring, ext, S, A, e, X, Y)
    for q in e:
        path = shapely.LineString(np.vstack([A[q], ring[idx[q] + 1:idx[q] + 10],
                                             A[(q + 1) % len(A)]]))
        edge = shapely.LineString([X[q], Y[q]])
        d = shapely.hausdorff_distance(path, edge, densify=0.01)
        step = np.hypot(*(Y[q] - X[q])) / 32
        assert d <= got[q] + 1e-12 and got[q] <= d + step


def test_merge_refused_next_to_a_shorter_ring_edge_pinned_at_its_far_end():
    """A corner 0.32 from a sample, the ring edge after that sample's neighbour shorter
    still (0.22) and ending at a point that stays (a spike's tip): merging would leave
    that edge as short with one ring point fewer around it, so the pair stays; with
    that edge longer (0.45), or its far end free to move, it merges."""
    def merged(tip, tip_free=False):
        ring = np.array([(0, 0), (4, 0), (4.1, 0.3), (4, 4), tip, (0, 4)], float)
        ext = measure(ring)
        corner = np.array([0, 1, 0, 0, 0, 0], bool)
        free = np.array([0, 0, 1, 1, tip_free, 0], bool)
        keep, _, P2, m = merge_corners(ring, ext, ext[:6], ring.copy(), corner, free, 1.0, 0.25)
        L = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
        L2 = np.hypot(*(np.roll(P2[keep], -1, axis=0) - P2[keep]).T)
        return bool(m.any()), L.min(), L2.min()
    pinned, longer, free = merged((3.8, 4.1)), merged((3.6, 4.2)), merged((3.8, 4.1), True)
    assert pinned[0] is False and pinned[1] == pinned[2]
    assert longer[0] is True and longer[2] > longer[1]
    assert free[0] is True


def test_merge_mode_ring_no_shorter_than_keep_mode_on_russia():
    """Russia at n = 2000: a corner merged next to a spike's tip left the sample before
    the tip 0.43 h from it (0.58 h with the corner kept); merge mode's shortest ring
    edge must be no shorter than keep mode's."""
    p = u.read_polygon(OUTLINES / "russia.json")

    def shortest(corners):
        r, _ = resample_polygon(p, 2000, tolerance=0.25, corners=corners)
        return min(np.hypot(*(np.roll(g, -1, axis=0) - g).T).min() for g in r.polygon.rings) / r.spacing
    assert shortest("merge") >= shortest("keep")
