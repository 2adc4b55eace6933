"""Partitioned meshes (uniform_mesh(parts=K)): exact n, conforming across cuts
(the independent checker on the stitched mesh), the same bytes whatever runs
the parts, .pvtu pieces read back, a lost Dask worker."""

from __future__ import annotations

import functools
import itertools
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from support.lost_worker import kill_once

from uniform2d import Polygon, uniform_mesh
from uniform2d.cli.main import main
from uniform2d.errors import InsufficientPointsError, InvalidArgumentError
from uniform2d.io import write_polygon
from uniform2d.partition import partition
from uniform2d.partitioned import partitioned_mesh, write_pvtu
from uniform2d.testing import check_mesh

L_HOLE = Polygon([(0, 0), (4, 0), (4, 3), (2, 3), (2, 1.5), (0, 1.5)],
                 [[(0.5, 0.5), (1, 0.5), (1, 1), (0.5, 1)]])
PLATE = Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], [[(2.5, 2), (3, 2), (3, 2.5), (2.5, 2.5)]],
                segments=[[(0, 1), (4, 1.2)], [(1, 1.6), (1.5, 2.7), (3.5, 2.8)],
                          [(2, 1.6), (2.3, 2.2)]],
                points=[(0.7, 2.1), (3.2, 0.4)], regions=[(2, 0.5, "low"), (0.3, 2, "high")])


def same(a, b) -> bool:
    return (a.points.tobytes() == b.points.tobytes()
            and a.triangles.tobytes() == b.triangles.tobytes())


@pytest.mark.parametrize("polygon, n, K", [(L_HOLE, 1500, 4), (L_HOLE, 1200, 5), (PLATE, 1500, 3),
                                           (PLATE, 2000, 6)])
def test_exact_n_and_valid_across_the_cuts(polygon, n, K):
    m = uniform_mesh(polygon, n, parts=K)
    check_mesh(m.points, m.triangles, polygon, n_steiner=n)  # constrained Delaunay, cuts gone
    assert m.n_steiner == n and len(m.points) == len(polygon.vertices) + n
    assert m.info["parts"] == K and m.info["cut_points"] > 0
    # every cut point is a vertex of the stitched mesh (shared, not duplicated)
    part = partition(polygon, n, K)
    assert len(part.parts) == K
    assert len(np.unique(m.points, axis=0)) == len(m.points)


def test_cut_points_are_shared_before_the_relaxation():
    m = partitioned_mesh(L_HOLE, 1500, 4, relax=False)
    check_mesh(m.points, m.triangles, L_HOLE, n_steiner=1500, delaunay=False)
    part = partition(L_HOLE, 1500, 4)
    cut = np.unique(np.concatenate(part.cuts))
    np.testing.assert_array_equal(m.points[cut], part.points[cut])
    # a cut piece is an edge of two triangles, one on either side
    T = m.triangles
    edges = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    key, count = np.unique(edges, axis=0, return_counts=True)
    seen = {tuple(k): c for k, c in zip(key.tolist(), count.tolist())}
    inner = [c for c in part.cuts if len(c) > 2]
    for c in inner:
        for a, b in itertools.pairwise(c):
            assert seen[tuple(sorted((int(a), int(b))))] == 2


def test_regions_and_constraints_are_kept():
    m = uniform_mesh(PLATE, 1500, parts=4)
    plain = uniform_mesh(PLATE, 1500)
    assert m.region_labels == ("low", "high")
    for r in range(2):
        a = _area(m.points, m.triangles[m.regions == r])
        assert a == pytest.approx(_area(plain.points, plain.triangles[plain.regions == r]), rel=1e-9)
    assert len(m.segment_members[0]) > 0


def _area(P, T) -> float:
    p = P[T]
    return float(0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                        - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])).sum())


def test_the_parts_share_one_lattice_across_the_cuts():
    """Beyond the rings' bands every point is a point of the one shared lattice
    (:func:`global_lattice`), on both sides of every cut and on it: no seam is
    left; with each part's own lattice (the ``.pvtu`` path's seeds) it is not."""
    from scipy.spatial import cKDTree

    from uniform2d._kernel.distance import to_segments
    from uniform2d.optimize.lattice import hex_lattice
    from uniform2d.optimize.rows import keep_clear
    from uniform2d.partitioned import RING_BAND, global_lattice, seam_uniformity

    square = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    n, K = 30000, 4
    m = uniform_mesh(square, n, parts=K)
    check_mesh(m.points, m.triangles, square, n_steiner=n)
    h = m.info["h"]
    origin, angle, spacing, _ = global_lattice(square, n, h)
    lattice = cKDTree(hex_lattice(square.bounds, spacing, angle, origin))
    part = partition(square, n, K)
    cut = part.points[np.concatenate(part.cuts)]

    def off_lattice(points):
        """How far from the shared lattice (in h) the points beyond the rings'
        bands and within 3 h of a cut are, at the median and 90th percentile."""
        far = to_segments(points, *keep_clear(square), np.inf) > (RING_BAND + 2) * h
        near = cKDTree(cut).query(points)[0] < 3 * h
        d = lattice.query(points[far & near])[0] / h
        assert len(d) > 100
        return np.quantile(d, [0.5, 0.9])

    median, q90 = off_lattice(m.points)
    assert median < 0.01 and q90 < 0.1
    # the parts' own lattices (no shared one): out of phase across the cuts
    own = partitioned_mesh(square, n, K, relax=False)
    assert off_lattice(own.points)[0] > 0.1
    seams = m.info["seams"]
    assert seams["cv_near_seams"] <= seams["cv_away"]
    assert seam_uniformity(own.points, own.triangles, cut, h)["cv_near_seams"] > seams["cv_near_seams"]


def test_same_bytes_with_one_and_two_workers():
    a = uniform_mesh(L_HOLE, 1500, parts=4)
    b = uniform_mesh(L_HOLE, 1500, parts=4, jobs=2)
    assert same(a, b)


def test_without_parts_the_mesh_is_the_unpartitioned_one():
    a = uniform_mesh(L_HOLE, 300)
    assert a.info["method"] == "uniform" and "parts" not in a.info


def test_refusals():
    with pytest.raises(InvalidArgumentError, match="parts must be a positive integer"):
        uniform_mesh(L_HOLE, 300, parts=0)
    with pytest.raises(InsufficientPointsError, match="fewer parts"):
        uniform_mesh(L_HOLE, 10, parts=8)  # the cuts alone take more points
    with pytest.raises(InsufficientPointsError, match="fewer parts"):
        uniform_mesh(L_HOLE, 5, parts=16)  # parts narrower than the spacing
    with pytest.raises(InvalidArgumentError, match="size field"):
        uniform_mesh(L_HOLE, 300, size=lambda p: 1.0 + p[:, 0] ** 2, parts=2)


def test_pvtu_pieces_read_back(tmp_path):
    src = tmp_path / "plate.json"
    write_polygon(src, L_HOLE)
    out = tmp_path / "big.pvtu"
    assert main(["mesh", str(src), "-n", "1500", "--parts", "4", "-o", str(out), "-q"]) == 0
    import meshio

    root = ET.parse(out).getroot()
    assert root.get("type") == "PUnstructuredGrid"
    sources = [p.get("Source") for p in root.iter("Piece")]
    assert len(sources) == 4
    ids, tris, points = [], 0, {}
    for s in sources:
        piece = meshio.read(out.parent / s)
        g = piece.point_data["GlobalPointIds"]
        ids.append(g)
        tris += len(piece.cells_dict["triangle"])
        for i, p in zip(g.tolist(), piece.points[:, :2]):
            assert points.setdefault(i, tuple(p)) == tuple(p)  # a seam point is one point
    glob = np.unique(np.concatenate(ids))
    N = len(L_HOLE.vertices) + 1500
    np.testing.assert_array_equal(glob, np.arange(N))
    ref = partitioned_mesh(L_HOLE, 1500, 4, relax=False)
    assert tris == len(ref.triangles)
    np.testing.assert_array_equal(np.array([points[i] for i in range(N)]), ref.points)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big", "big.pvtu", "plate.json"]


class _Interrupt:
    def update(self, *a):
        raise KeyboardInterrupt


def test_an_interrupted_pvtu_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        write_pvtu(L_HOLE, 800, 3, tmp_path / "m.pvtu", bar=_Interrupt())
    assert list(tmp_path.iterdir()) == []


def test_pvtu_needs_parts(tmp_path, capsys):
    src = tmp_path / "p.json"
    write_polygon(src, L_HOLE)
    code = main(["mesh", str(src), "-n", "300", "-o", str(tmp_path / "m.pvtu")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "add --parts K" in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.json"]


def test_a_lost_worker_gives_the_same_mesh(tmp_path):
    distributed = pytest.importorskip("distributed")
    ref = partitioned_mesh(L_HOLE, 800, 3)
    marker = tmp_path / "killed"
    with distributed.LocalCluster(processes=True, n_workers=2, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        m = partitioned_mesh(L_HOLE, 800, 3, scheduler=client,
                             mesher=functools.partial(kill_once, str(marker)))
    assert marker.exists()  # a worker did die
    assert same(m, ref)


def test_the_command_gathers_any_other_format(tmp_path, capsys):
    from uniform2d import read_mesh

    src = tmp_path / "p.json"
    write_polygon(src, L_HOLE)
    out = tmp_path / "m.vtu"
    assert main(["mesh", str(src), "-n", "900", "--parts", "3", "-o", str(out), "-q"]) == 0
    got = read_mesh(out)
    ref = uniform_mesh(L_HOLE, 900, parts=3)
    np.testing.assert_array_equal(got[0], ref.points)
    np.testing.assert_array_equal(got[1], ref.triangles)
    check_mesh(got[0], got[1], L_HOLE, n_steiner=900)
    capsys.readouterr()
    assert main(["mesh", str(src), "-n", "900", "--parts", "3", "-o", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["n_steiner"] == 900 and doc["info"]["parts"] == 3
    assert doc["info"]["seams"]["near_edges"] > 0


@pytest.mark.parametrize("extra, message", [
    (["--method", "paper", "-o", "m.vtu"], "cannot be used with --method paper"),
    (["-o", "m.pvtu", "--plot", "m.png"], "drop --plot"),
    (["--refine", "holes:0.5", "-o", "m.vtu"], "--refine or --size-field"),
    (["-o", "m.pvtu", "-o", "m.vtu"], "write it alone"),
])
def test_the_command_refuses(tmp_path, capsys, extra, message):
    src = tmp_path / "p.json"
    write_polygon(src, L_HOLE)
    argv = ["mesh", str(src), "-n", "300", "--parts", "2"]
    argv += [str(tmp_path / a) if a.startswith("m.") else a for a in extra]
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and message in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.json"]


def test_the_seam_pass_runs_in_pieces_with_the_same_bytes_anywhere(monkeypatch):
    """The seams' pass in tiles of 20 h (several pieces a round): the same bytes
    with 1 and 2 local processes, exactly n, valid and constrained Delaunay."""
    from uniform2d import seams

    monkeypatch.setattr(seams, "TILE", 20.0)
    monkeypatch.setattr(seams, "OVERLAP", 3.0)
    counts = []
    real = seams.round_pieces

    def counted(*a, **k):
        out = real(*a, **k)
        counts.append(len(out))
        return out

    monkeypatch.setattr(seams, "round_pieces", counted)
    a = uniform_mesh(PLATE, 4000, parts=4)
    b = uniform_mesh(PLATE, 4000, parts=4, jobs=2)
    assert len(counts) == 2 * seams.ROUNDS and max(counts) > 1
    assert same(a, b)
    check_mesh(a.points, a.triangles, PLATE, n_steiner=4000)
    c = uniform_mesh(L_HOLE, 3000, parts=5, jobs=2)
    check_mesh(c.points, c.triangles, L_HOLE, n_steiner=3000)
    assert same(c, uniform_mesh(L_HOLE, 3000, parts=5))


def test_the_pieces_of_a_round_are_apart_and_cover_the_band(monkeypatch):
    """Every band point is a free point of a piece in some round; the pieces of a
    round share no triangle and no free point; a piece moves its free points
    only and keeps its region's triangle count."""
    from uniform2d import seams
    from uniform2d.seams import ROUNDS, relax_piece, round_pieces

    monkeypatch.setattr(seams, "TILE", 16.0)
    monkeypatch.setattr(seams, "OVERLAP", 2.0)
    square = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    m = uniform_mesh(square, 3000)
    P, T, h = m.points, m.triangles, 1.0 / 56
    free = np.zeros(len(P), bool)
    free[4:] = (np.abs(P[4:, 0] - 0.5) < 0.15) | (P[4:, 1] < 0.1)
    seen = np.zeros(len(P), bool)
    for rnd in range(ROUNDS):
        pieces = round_pieces(P, T, free, h, (0.0, 0.0), rnd, 4, np.zeros((0, 2), np.int64))
        assert len(pieces) > 1
        rows = np.concatenate([r for r, _, _ in pieces])
        assert len(rows) == len(np.unique(rows))
        cores = np.concatenate([ids[it[2]] for _, ids, it in pieces])
        assert len(cores) == len(np.unique(cores)) and free[cores].all()
        seen[cores] = True
        for rows, ids, item in pieces[:2]:
            moved, xy, tri = relax_piece(item)
            assert set(moved.tolist()) <= set(np.flatnonzero(item[2]).tolist())
            assert len(tri) == len(rows) and not np.array_equal(xy, item[0][moved])
    np.testing.assert_array_equal(seen, free)


def test_pvtu_pieces_carry_the_regions(tmp_path):
    """Every piece triangle's cell data ``region`` is the region of that triangle
    in the gathered mesh (the parts as meshed), and the index declares it."""
    import meshio

    out = tmp_path / "plate.pvtu"
    write_pvtu(PLATE, 1500, 3, out)
    root = ET.parse(out).getroot()
    assert [a.get("Name") for c in root.iter("PCellData") for a in c] == ["region"]
    ref = partitioned_mesh(PLATE, 1500, 3, relax=False)
    want = {tuple(sorted(t)): r for t, r in zip(ref.triangles.tolist(), ref.regions.tolist())}
    got = {}
    for p in root.iter("Piece"):
        piece = meshio.read(out.parent / p.get("Source"))
        g = piece.point_data["GlobalPointIds"]
        for t, r in zip(piece.cells_dict["triangle"].tolist(), piece.cell_data["region"][0].tolist()):
            got[tuple(sorted(g[t].tolist()))] = r
    assert got == want and set(want.values()) == {0, 1}
