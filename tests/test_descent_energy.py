"""The descent's star energy: the line search's sum and the gradient's sum are
the same bits, and both are the energy and gradient a plain evaluation of the
formula gives, operation for operation; snapping by the grid's reciprocal is
snapping by its scale."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uniform2d._kernel import cdt, descent


def _reference(x, y, ns, nt, SP, TR, k, w_len, w_short, w_per):
    """(energy, gx, gy) of the star, term by term in Python floats (IEEE
    doubles, each operation rounded once, as the kernel's): spokes first, then
    triangles; an edge whose ell**p underflows makes the energy infinite and
    adds no slope."""
    p = 2.0**k
    E = gx = gy = 0.0
    L = []
    for i in range(ns):
        dx, dy = x - SP[i, 0], y - SP[i, 1]
        Li = math.sqrt(dx * dx + dy * dy)
        L.append(Li)
        s = SP[i, 2]
        ell = Li / s
        q = ell
        for _ in range(k):
            q = q * q
        e = d = 0.0
        if w_len > 0.0:
            e += w_len * q
            d += w_len * p * q / (ell * s)
        if w_short > 0.0:
            if q == 0.0:
                e, d = math.inf, 0.0
            else:
                e += w_short / q
                d -= w_short * p / (q * ell * s)
        E += e
        gx += d * dx / Li
        gy += d * dy / Li
    if w_per > 0.0:
        for j in range(nt):
            i = j + 1 if j + 1 < ns else 0
            tgt = TR[j, 1]
            pi = (L[j] + L[i] + TR[j, 0]) / tgt
            q = pi
            for _ in range(k):
                q = q * q
            E += w_per * q
            d = w_per * p * q / (pi * tgt)
            gx += d * ((x - SP[j, 0]) / L[j] + (x - SP[i, 0]) / L[i])
            gy += d * ((y - SP[j, 1]) / L[j] + (y - SP[i, 1]) / L[i])
    return E, gx, gy


def _star(rng, ns, interior):
    """A star of ns spokes around the origin (counter-clockwise, unit-ish
    lengths and targets), its triangles (ns of an interior vertex, ns - 1 of a
    boundary one) with their opposite lengths and perimeter targets."""
    angles = np.sort(rng.uniform(0.0, 2.0 * np.pi if interior else np.pi, ns))
    r = rng.uniform(0.7, 1.4, ns)
    SP = np.column_stack([r * np.cos(angles), r * np.sin(angles), rng.uniform(0.9, 1.1, ns)])
    nt = ns if interior else ns - 1
    TR = np.empty((ns + 2, 2))
    for j in range(nt):
        i = (j + 1) % ns
        TR[j, 0] = math.hypot(SP[i, 0] - SP[j, 0], SP[i, 1] - SP[j, 1])
        TR[j, 1] = 3.0 * rng.uniform(0.9, 1.1)
    return np.vstack([SP, np.ones((2, 3))]), TR, nt


@pytest.mark.parametrize("k", [2, 5, 8, 9])
@pytest.mark.parametrize("interior", [True, False])
@pytest.mark.parametrize("weights", [(2.0, 0.5, 1.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0),
                                     (1.0, 0.3, 0.0)])
def test_line_search_and_gradient_sums_are_the_plain_formula_bit_for_bit(k, interior, weights):
    rng = np.random.default_rng(1000 * k + 10 * interior + int(10 * sum(weights)))
    w_len, w_short, w_per = weights
    for ns in (3, 5, 6, 7, 11):
        SP, TR, nt = _star(rng, ns, interior)
        L = np.empty(SP.shape[0])
        grad = np.zeros(2)
        for x, y in rng.uniform(-0.2, 0.2, (5, 2)):
            E, gx, gy = _reference(x, y, ns, nt, SP, TR, k, w_len, w_short, w_per)
            Eg = descent._star_gradient(x, y, ns, nt, SP, TR, L, k, 2.0**k, w_len, w_short,
                                        w_per, grad)
            El = descent._star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per, np.inf)
            assert (Eg, grad[0], grad[1]) == (E, gx, gy)
            assert El == E
            # with a bar, the sum stops at it: at or above it exactly when the whole is
            below = descent._star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per,
                                         np.nextafter(E, np.inf))
            assert below == E
            assert descent._star_energy(x, y, ns, nt, SP, TR, L, k, w_len, w_short, w_per,
                                        E) >= E


def test_an_underflowed_short_edge_makes_the_share_infinite_and_adds_no_slope():
    SP = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [-1.0, -1.0, 1.0], [1, 1, 1]], float)
    TR = np.array([[math.sqrt(2.0), 3.0], [math.sqrt(5.0), 3.0], [math.sqrt(5.0), 3.0],
                   [1.0, 1.0]])
    x, y = 0.999, 0.0  # the first spoke 1e-3 of its target: ell**256 underflows
    L = np.empty(4)
    grad = np.zeros(2)
    E, gx, gy = _reference(x, y, 3, 3, SP, TR, 8, 1.0, 0.5, 1.0)
    assert math.isinf(E)
    assert descent._star_gradient(x, y, 3, 3, SP, TR, L, 8, 256.0, 1.0, 0.5, 1.0, grad) == E
    assert (grad[0], grad[1]) == (gx, gy)
    assert math.isinf(descent._star_energy(x, y, 3, 3, SP, TR, L, 8, 1.0, 0.5, 1.0, math.inf))


@pytest.mark.parametrize("scale", [2.0**-30, 0.125, 1.0, 4.0, 2.0**40])
def test_snapping_by_the_reciprocal_is_snapping_by_the_scale(scale):
    rng = np.random.default_rng(7)
    r = cdt.snap_reciprocal(scale)
    assert r == 1.0 / scale
    for cx, cy in ((0.0, 0.0), (3.0 * 2.0**20, -5.0 * 2.0**21)):
        for x, y in rng.normal(0.0, 1.0, (200, 2)):
            assert cdt.snap_times(scale, r, cx, cy, x, y) == cdt.snap_to(scale, cx, cy, x, y)


@pytest.mark.parametrize("scale", [3.0, 0.1, 1.5, 2.0**-1074])
def test_a_scale_without_an_exact_reciprocal_is_divided_by(scale):
    assert cdt.snap_reciprocal(scale) == 0.0
    assert cdt.snap_times(scale, 0.0, 0.0, 0.0, 0.3, 0.7) == cdt.snap_to(scale, 0.0, 0.0, 0.3, 0.7)
