"""Every error raised on a bad argument is a Uniform2dError and a ValueError, so a
caller can catch either, and the command line reports it as one line."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import uniform2d
from uniform2d import Polygon, Uniform2dError, errors

SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def test_the_base_class_is_a_value_error():
    assert issubclass(Uniform2dError, ValueError)
    for name in errors.__all__:
        cls = getattr(errors, name)
        if cls is errors.InternalError:  # a bug of the library, never the caller's input
            assert not issubclass(cls, Uniform2dError)
            continue
        assert issubclass(cls, Uniform2dError) and issubclass(cls, ValueError), name
    assert issubclass(errors.ArgumentTypeError, TypeError)
    with pytest.raises(ValueError):
        raise Uniform2dError("caught as a ValueError")


@pytest.mark.parametrize("kwargs", [{}, {"n": 10, "size": 0.1}])
def test_uniform_mesh_needs_exactly_one_of_n_and_size(kwargs):
    with pytest.raises(errors.InvalidArgumentError, match="exactly one of n .* and size"):
        uniform2d.uniform_mesh(SQUARE, **kwargs)


def _sizefield():
    from uniform2d.sizefield import SizeField

    SizeField([0, 1], [1, 0], np.ones((2, 2)))


def _write_mesh(tmp_path):
    uniform2d.write_mesh(tmp_path / "m.vtu", [(0, 0), (1, 0), (np.nan, 1)], [(0, 1, 2)])


@pytest.mark.parametrize("call, match", [
    (lambda tmp: uniform2d.steiner_count_for_size(SQUARE, -1.0), "size must be a positive"),
    (lambda tmp: uniform2d.tplus(SQUARE, 40, spacing=(3.0, 2.0)), "spacing must be"),
    (lambda tmp: _sizefield(), "strictly increasing"),
    (lambda tmp: uniform2d.plot.plot_mesh([(0, 0), (1, 0), (0, 1)], np.zeros((0, 3), int)),
     "no triangles"),
    (_write_mesh, "non-finite"),
    (lambda tmp: uniform2d.write_mesh(tmp / "m.csv", [(0, 0), (1, 0), (0, 1)], [(0, 1, 2)],
                                      point_data={"x": np.zeros((3, 2))}), "one value per node"),
    (lambda tmp: uniform2d.report.make_report([], tmp / "r"), "at least one input"),
    (lambda tmp: uniform2d.quality(np.zeros((3, 3)), [(0, 1, 2)]), "expected a \\(N, 2\\) array"),
    (lambda tmp: uniform2d.quality([(0, 0), (1, 0), (0, 1)], [(0, 1, 5)]), "refers to a point outside"),
    (lambda tmp: uniform2d.uniform_mesh(SQUARE, 10, objective="nicest"), "objective must be one of"),
    (lambda tmp: uniform2d.insert(SQUARE, 3, size=-1.0), "size must be a positive number"),
])
def test_bad_arguments_raise_invalid_argument_error(tmp_path, call, match):
    import uniform2d.plot  # noqa: F401
    import uniform2d.report  # noqa: F401

    with pytest.raises(errors.InvalidArgumentError, match=match) as info:
        call(tmp_path)
    assert isinstance(info.value, ValueError)


def test_a_wrong_type_is_both_a_type_error_and_a_uniform2d_error(tmp_path):
    with pytest.raises(errors.ArgumentTypeError, match="expects a uniform2d.Polygon") as info:
        uniform2d.write_polygon(tmp_path / "p.json", [(0, 0), (1, 0), (0, 1)])
    assert isinstance(info.value, TypeError) and isinstance(info.value, Uniform2dError)
    with pytest.raises(errors.ArgumentTypeError, match="size must be a SizeField or a number"):
        uniform2d.insert(SQUARE, 3, size="big")


@pytest.mark.skipif(not all(importlib.util.find_spec(m) for m in ("igl", "trimesh")),
                    reason="needs the surface extra")
@pytest.mark.parametrize("kwargs, match", [
    ({"n_vertices": 2}, "at least 3"),
    ({"n_vertices": 50, "size": 0.1}, "not both"),
    ({"size": -1.0}, "positive length"),
    ({"n_vertices": 50, "param": "nope"}, "unknown parameterisation"),
])
def test_surface_bad_arguments(kwargs, match):
    import surface

    V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], float)
    patch = surface.Patch(V, [[0, 1, 2], [0, 2, 3]])
    with pytest.raises(errors.InvalidArgumentError, match=match):
        surface.remesh(patch, **kwargs)


def test_internal_failures_are_internal_errors(monkeypatch):
    """A step that cannot fail on a valid polygon raises InternalError (a
    RuntimeError, not a Uniform2dError) asking for a report: here the exact
    triangulation given a repeated vertex, and the loader when the kernel
    cannot insert a vertex."""
    from uniform2d import triangulation
    from uniform2d._kernel import polytri

    xy = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (0.0, 1.0)])
    with pytest.raises(errors.InternalError, match="please report") as exc:
        polytri.triangulate(xy, [[0, 1, 2, 3]])
    assert isinstance(exc.value, RuntimeError) and not isinstance(exc.value, Uniform2dError)
    monkeypatch.setattr(triangulation.cavity, "insert_sites", lambda m, idx: -1)
    P = uniform2d.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], points=[(0.5, 0.5)])
    with pytest.raises(errors.InternalError, match="could not insert vertex 4 .*please report"):
        triangulation.load(P)
