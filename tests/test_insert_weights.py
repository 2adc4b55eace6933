"""INSERT's weights are non-increasing up to the documented tie tolerance, and the
documentation states the tolerance the kernel uses."""

import sys
from pathlib import Path

import pytest

import uniform2d
from uniform2d._kernel import insert as kinsert

BENCH = Path(__file__).resolve().parents[1] / "data" / "benchmarks"


def test_documented_tolerance_is_the_kernels():
    assert kinsert.REL_TIE == 1e-9
    assert "(1 + 1e-9)" in uniform2d.InsertResult.__doc__
    module_doc = " ".join(sys.modules["uniform2d.insert"].__doc__.split())
    assert "may weigh up to a relative 1e-9 more" in module_doc


@pytest.mark.parametrize("name, n", [("lshape", 60), ("lshape", 400), ("star10", 300),
                                     ("square2holes", 300), ("hexagon", 200)])
def test_weights_rise_by_no_more_than_the_tie_tolerance(name, n):
    w = uniform2d.insert(uniform2d.read_polygon(BENCH / f"{name}.json"), n).weights
    rise = w[1:] / w[:-1] - 1.0
    assert rise.max() <= 1e-9, f"rises by {rise.max():.3g} at step {int(rise.argmax()) + 1}"
    # and the sequence does come down: the last weight is well below the first
    assert w[-1] < 0.5 * w[0]
