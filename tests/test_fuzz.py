"""Fuzzing: random hard domains (``uniform2d.testing.fuzz``) through every method, every mesh checked.

Hypothesis draws a domain seed and an n; the domain is one of the shapes that
broke meshers before (short edges, exact and near collinear vertices, spikes,
rotated rectilinear outlines, holes, slivers) at a scale 1e-6..1e6 and an offset
up to 1e7.  A call may refuse with a ``Uniform2dError`` (an invalid polygon
drawn, an n too small for T+); anything else must be a mesh that passes
``uniform2d.testing.check_mesh`` with exactly n Steiner points.  The long run is
``benchmarks/bench_fuzz.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import uniform2d
from uniform2d.testing.fuzz import KINDS, rings
from uniform2d.testing import check_mesh

SETTINGS = settings(
    max_examples=40, deadline=None, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip


def _polygon(seed, kind):
    _, outer, holes = rings(seed, kind)
    try:
        return uniform2d.Polygon(outer, holes)
    except uniform2d.InvalidPolygonError:
        return None


def _check(poly, n, pts, tri):
    assert len(pts) == len(poly.vertices) + n
    # rounding boundary points onto rotated edges is all the area may lose
    grain = 4 * np.spacing(float(np.abs(poly.vertices).max()))
    check_mesh(pts, tri, poly, area_rtol=max(1e-9, grain * poly.perimeter / poly.area))


def _run(call, seed, kind, n):
    """One call on domain ``seed``: a valid mesh, or a documented refusal (a
    polygon too far out for its size; T+ with too few points)."""
    poly = _polygon(seed, kind)
    if poly is None:
        return
    refusals = (uniform2d.CoordinatePrecisionError,)
    if call == "tplus":
        refusals += (uniform2d.InsufficientPointsError,)
    try:
        out = getattr(uniform2d, call)(poly, n)
    except refusals:
        return
    _check(poly, n, out.mesh_points if call == "insert" else out.points, out.triangles)


@pytest.mark.parametrize("kind", KINDS)
@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 300))
def test_insert_and_tplus_on_hard_domains(kind, seed, n):
    _run("insert", seed, kind, n)
    _run("tplus", seed, kind, n)


@pytest.mark.parametrize("kind", KINDS)
@settings(SETTINGS, max_examples=10)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 60))
def test_uniform_mesh_on_hard_domains(kind, seed, n):
    _run("uniform_mesh", seed, kind, n)


@pytest.mark.parametrize("kind", KINDS)
@settings(SETTINGS, max_examples=5)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(20, 200))
def test_resampled_mesh_on_hard_domains(kind, seed, n):
    """resample=0.25: exactly the kept vertices + n points, a valid mesh of the
    resampled polygon, every ring of it within the tolerance of the input's
    (shapely's Hausdorff distance, densified, both ways); or n too small for
    the resampled boundary, said as such."""
    import shapely

    poly = _polygon(seed, kind)
    if poly is None:
        return
    try:
        m = uniform2d.uniform_mesh(poly, n, resample=0.25)
    except (uniform2d.CoordinatePrecisionError, uniform2d.InsufficientPointsError):
        return
    info = m.info["resample"]
    assert len(m.points) == info["kept_vertices"] + n
    res = m.polygon
    grain = 4 * np.spacing(float(np.abs(res.vertices).max()))
    check_mesh(m.points, m.triangles, res, area_rtol=max(1e-9, grain * res.perimeter / res.area))
    assert len(res.rings) == len(poly.rings)
    for a, b in zip(poly.rings, res.rings):
        d = shapely.hausdorff_distance(shapely.LinearRing(a), shapely.LinearRing(b), densify=0.25)
        assert d <= (0.25 + 1e-9) * info["spacing"]
