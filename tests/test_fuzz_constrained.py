"""The constrained fuzz domains (uniform2d.testing.fuzz.constrained): deterministic, mostly valid,
and their regions tile them; on Triangle's meshes of them the regions agree with
Triangle's own regional attributes."""

import numpy as np
import pytest

from uniform2d import InvalidPolygonError
from uniform2d.mesh_regions import triangle_regions

from uniform2d.testing.fuzz import CONSTRAINED_KINDS, constrained, constrained_domain


@pytest.mark.parametrize("kind", CONSTRAINED_KINDS)
def test_constrained_kinds_are_deterministic_and_mostly_valid(kind):
    a, b = constrained(7, kind), constrained(7, kind)
    assert a[0] == b[0] == kind
    for x, y in zip(a[1:], b[1:]):
        if isinstance(x, list):
            assert all(np.array_equal(p, q) for p, q in zip(x, y))
        else:
            assert np.array_equal(x, y)
    valid = 0
    for seed in range(40):
        try:
            _, p = constrained_domain(seed, kind)
        except InvalidPolygonError:
            continue
        valid += 1
        assert p.has_constraints or kind == "c_closed"
        assert abs(p.regions.areas.sum() - p.area) <= 1e-9 * p.area
    assert valid >= 15, valid


def test_the_kinds_make_what_they_say():
    _, p = constrained_domain(3, "c_closed")
    assert len(p.regions) >= 2                      # a zone
    found_t = False
    for seed in range(20):
        try:
            _, p = constrained_domain(seed, "c_tjunction")
        except InvalidPolygonError:
            continue
        found_t |= len(p.outer) > len(constrained(seed, "c_tjunction")[1])  # spliced in
        assert len(p.regions) >= 2                  # the chord splits the outline
    assert found_t


def test_regions_of_triangle_meshes_of_fuzz_domains():
    triangle = pytest.importorskip("triangle")
    from support.conmesh import triangle_mesh

    checked = 0
    for kind in CONSTRAINED_KINDS:
        for seed in range(12):
            try:
                _, p = constrained_domain(seed, kind)
            except InvalidPolygonError:
                continue
            pts, tri, want = triangle_mesh(p, attributes=True)
            assert np.array_equal(triangle_regions(p, pts, tri), want), (kind, seed)
            checked += 1
    assert checked >= 30
    assert triangle is not None
