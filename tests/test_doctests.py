"""Run every docstring example in the package as a test (they are documentation
that must stay true)."""

import doctest
import importlib
import pkgutil

import pytest

import uniform2d

MODULES = sorted(
    m.name
    for m in pkgutil.walk_packages(uniform2d.__path__, "uniform2d.")
    if not m.name.split(".")[-1].startswith("__")
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} docstring example(s) failed in {name}"
