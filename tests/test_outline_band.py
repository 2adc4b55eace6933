"""Moves within the tolerance band (uniform2d.outline_band): the point next to a
spike's tip is pushed off the spike's long fixed side (TIP_EDGE), and on a real
outline that gives a better mesh than without; the tolerance held both ways
(shapely's Hausdorff distance, independent of the module's own bound), corners
unmoved bit for bit, n exact."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import uniform2d as u
import uniform2d.outline_band as band
import uniform2d.ring_relocate as ring_relocate
import uniform2d.uniform as uniform_module

from support.halved_rings import resampled_and_meshed

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"


def _spike():
    """A polygon with a thin spike pointing right: its lower side one edge 3 long
    between two fixed points, (0, 0) and the tip (3, 0); its upper side sampled."""
    ring = np.array([(0, 0), (3, 0), (2, 0.25), (1, 0.5), (0, 0.75), (-2, 2), (-4, 0), (-2, -2)],
                    float)
    movable = np.array([0, 0, 1, 1, 1, 1, 1, 1], bool)
    return ring, movable


def test_the_point_next_to_a_spike_tip_is_pushed_off_the_long_side(monkeypatch):
    ring, movable = _spike()
    d = band.widen_moves([ring], [movable], 1.0, 0.25)[0]
    monkeypatch.setattr(band, "TIP_EDGE", np.inf)  # the rule off
    d0 = band.widen_moves([ring], [movable], 1.0, 0.25)[0]
    # the point next to the tip, 0.25 from the lower side, moves away from it
    # (up), within 0.9 of the limit; without the rule it does not move
    assert d[2, 1] > 0.05 and np.hypot(*d[2]) <= 0.9 * 0.25 * (1 + 1e-12)
    assert d0[2].tolist() == [0.0, 0.0]
    # fixed points never move; the spike gets wider at that point
    assert d[~movable].tobytes() == np.zeros((2, 2)).tobytes()
    assert (ring + d)[2, 1] > ring[2, 1]


def test_tip_rule_meshes_chile_within_ratio_2(monkeypatch):
    p = u.read_polygon(OUTLINES / "chile.json")
    n, tol = 2000, 0.25
    # the tip rule alone: no second mesh with whole ring edges halved (uniform2d.ring_split),
    # no relocation moves (uniform2d.ring_relocate)
    monkeypatch.setattr(uniform_module, "SPLIT_RATIO", np.inf)
    monkeypatch.setattr(ring_relocate, "SPLIT_RATIO", np.inf)

    def run():
        r, m = resampled_and_meshed(p, n, tol)
        return r, m.quality().edge_ratio

    r1, ratio1 = run()
    monkeypatch.setattr(band, "TIP_EDGE", np.inf)
    r0, ratio0 = run()
    assert r0.polygon != r1.polygon
    assert r0.polygon.vertices[r0.kept].tobytes() == r1.polygon.vertices[r1.kept].tobytes()
    # 2.00 (1.9997) against 2.77 when written
    assert ratio1 <= 2.0 < 0.75 * ratio0, (ratio1, ratio0)
