"""Fixtures for every test."""

import pytest


@pytest.fixture(autouse=True)
def _no_first_run_notice(request, monkeypatch):
    """The command's first-run notice depends on the numba cache of the machine, not
    on the test: keep it out of the exact stderr the command tests compare.  Tests
    of the notice itself patch it back or are marked ``compile_cache``."""
    if request.node.get_closest_marker("compile_cache") is None:
        import uniform2d.compile_cache

        monkeypatch.setattr(uniform2d.compile_cache, "kernels_cold", lambda: False)


@pytest.fixture(autouse=True)
def _wrappers_kept_after(monkeypatch):
    """A command run here on a (patched) cold cache drops the Python wrappers of
    the kernels only kernels call (uniform2d._kernel.pywrap) for the whole
    process: set back after each test, as numba has it."""
    from uniform2d._kernel import pywrap

    monkeypatch.setattr(pywrap, "_finder", [])
    monkeypatch.setattr(pywrap, "_entries", {})
