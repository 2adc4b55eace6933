"""Run every docstring example of the surface package (documentation that must stay true)."""

import doctest
import importlib
import pkgutil

import pytest

pytest.importorskip("igl")
pytest.importorskip("pymeshlab")
pytest.importorskip("trimesh")

import surface  # noqa: E402

MODULES = ["surface"] + sorted(
    m.name
    for m in pkgutil.walk_packages(surface.__path__, "surface.")
    if not m.name.split(".")[-1].startswith("__")
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} docstring example(s) failed in {name}"
