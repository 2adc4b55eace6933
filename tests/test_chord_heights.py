"""The resampling's chord heights: the compiled planar loop gives the bits of the
numpy version (which stays for 3-D runs), on the runs of real outlines."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import uniform2d as u
from uniform2d import chord_sampling
from uniform2d.uniform import resampled_outline

DATA = Path(__file__).resolve().parents[1] / "data" / "outlines"


@pytest.mark.parametrize("name,scale,shift", [("australia", 1.0, 0.0), ("nyc_manhattan", 1.0, 0.0),
                                              ("canada", 1e-6, 0.0), ("brazil", 1.0, 1e7)])
def test_compiled_heights_are_the_numpy_heights(monkeypatch, name, scale, shift):
    seen = []
    planar = chord_sampling._chord_heights

    def recorded(u_, on, C, excess, skipped, lo, hi):
        W, H = planar(u_, on, C, excess, skipped, lo, hi)
        seen.append((u_, on, C, excess, skipped, lo, hi, W, H))
        return W, H

    monkeypatch.setattr(chord_sampling, "_chord_heights", recorded)
    p = u.read_polygon(DATA / f"{name}.json")
    p = u.Polygon(p.vertices[: len(p.rings[0])] * scale + shift)  # the outer ring
    resampled_outline(p, 600, resample=0.25)
    assert seen, "the dynamic programme ran"
    finite = 0
    for u_, on, C, excess, skipped, lo, hi, W, H in seen:
        check = np.flatnonzero(on) if not skipped else np.arange(len(u_))
        want = chord_sampling._heights_any_dimension(u_, C, check, excess, W, lo, hi)
        np.testing.assert_array_equal(H, want)
        finite += int(np.isfinite(H).sum())
    assert finite > 100


def test_three_dimensional_runs_take_the_numpy_heights():
    t = np.linspace(0.0, 1.0, 40)
    C = np.c_[t, np.sin(7 * t) * 0.05, np.cos(5 * t) * 0.05]
    u_ = np.r_[0.0, np.cumsum(np.hypot.reduce(np.diff(C, axis=0), axis=1))]
    on = np.zeros(40, bool)
    on[::3] = True
    W, H = chord_sampling._chord_heights(u_, on, C, np.zeros(40), False, 0.05, 0.2)
    flat = chord_sampling._chord_heights(u_, on, C[:, :2], np.zeros(40), False, 0.05, 0.2)[1]
    assert np.isfinite(H).any() and not np.array_equal(np.isfinite(H), False)
    assert not np.array_equal(H, flat)  # the third coordinate counts
