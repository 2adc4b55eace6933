"""Run every docstring example of both packages as a test (documentation that must
stay true).  The surface package needs the ``surface`` extra (in ``test``)."""

import doctest
import importlib
import importlib.util
import pkgutil

import pytest


def _modules(package: str) -> list[str]:
    pkg = importlib.import_module(package)
    return [package] + sorted(
        m.name
        for m in pkgutil.walk_packages(pkg.__path__, package + ".")
        if not m.name.split(".")[-1].startswith("__")
    )


_SURFACE = all(importlib.util.find_spec(m) for m in ("igl", "pymeshlab", "trimesh"))
MODULES = _modules("uniform2d") + (_modules("surface") if _SURFACE else [])


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} docstring example(s) failed in {name}"
