"""The spring round's trial places (uniform2d._kernel.spring._trial), whose
FREE moves below their cap skip ``np.hypot``, against the rule written out in
numpy with ``np.hypot`` for every move: the same places, bit for bit, and the
same largest move, on forces that leave some moves capped, some uncapped,
some at the cap within rounding, some zero and some far below the rest."""

from __future__ import annotations

import numpy as np
import pytest

from uniform2d import Polygon
from uniform2d._kernel.cdt import snap
from uniform2d._kernel.relax import FREE, FIXED
from uniform2d._kernel.spring import _trial
from uniform2d._kernel.star import live_slots, ring_neighbours
from uniform2d.optimize.moves import KernelMesh


def _reference(st, F, dt, cap, movers):
    """(new places of the FREE movers, largest FREE move) by the plain rule."""
    out, biggest = {}, 0.0
    for v in movers:
        if st.role[v] != FREE:
            continue
        dx, dy = dt * F[v, 0], dt * F[v, 1]
        lim = cap * st.href * st.hv[v]
        step = np.hypot(dx, dy)
        if step > lim:
            dx *= lim / step
            dy *= lim / step
            step = lim
        if step == 0.0:
            continue
        out[v] = snap(st.m, st.xy[v, 0] + dx, st.xy[v, 1] + dy)
        biggest = max(biggest, step)
    return out, biggest


@pytest.mark.parametrize("seed", range(4))
def test_trial_as_the_plain_rule(seed):
    rng = np.random.default_rng(seed)
    sq = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    g = (np.arange(1, 10) / 10.0)
    sites = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2) + rng.normal(0, 0.01, (81, 2))
    st = KernelMesh.built(sq, sites, edges=np.full(len(sites), -1, np.int64))
    n = len(st.xy)
    dt, cap = 0.2, 0.3
    lim = cap * st.href * st.hv
    # directions at random; lengths from zero and 1e-200 of the cap to 3 caps,
    # with a few at the cap within a few ulps
    ang = rng.uniform(0, 2 * np.pi, n)
    frac = rng.choice([0.0, 1e-200, 1e-8, 0.3, 0.999999, 1.0, 1.0 + 1e-15, 3.0], n)
    frac *= rng.uniform(1 - 1e-15, 1 + 1e-15, n) if seed % 2 else 1.0
    F = np.stack([np.cos(ang), np.sin(ang)], 1) * (frac * lim / dt)[:, None]
    _, _, movers = live_slots(st.m, st.role, False)
    prevb, nextb = ring_neighbours(st.m, st.role, st.eid, st.t, st.ea)
    new = np.zeros((n, 2))
    newt = st.t.copy()
    moved = np.zeros(n, np.bool_)
    biggest = _trial(st.m, st.role, st.eid, st.t, st.ea, st.ed, st.hv, st.href, prevb, nextb,
                     F, dt, cap, new, newt, moved, movers)
    ref, ref_biggest = _reference(st, F, dt, cap, movers)
    assert biggest == ref_biggest and biggest > 0.0
    free = [v for v in movers if st.role[v] == FREE]
    assert sorted(ref) == [v for v in free if moved[v]]
    for v, (x, y) in ref.items():
        assert new[v, 0] == x and new[v, 1] == y
    assert not moved[[v for v in range(n) if st.role[v] == FIXED]].any()
