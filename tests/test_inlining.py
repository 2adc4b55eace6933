"""numba's inlining with the callee's IR copied as a whole (uniform2d._kernel.inlining).

A caller inlining a callee of several blocks, compiled with numba's block by
block copies and with the shared copy, must give the same LLVM IR (block
labels aside: numba numbers them from a process-wide counter, so a second
compile of the same function has other numbers), and the shared copy must be
the one that ran (block copies after the first find the scope in the memo).
"""

from __future__ import annotations

import re
import types

import numpy as np
import pytest
from numba.core import inline_closurecall, ir

from uniform2d._kernel import inlining
from uniform2d._kernel._jit import njit


def _callee(a, k):
    s = 0.0
    for i in range(a.shape[0]):
        if a[i] > k:
            s += a[i]
        elif a[i] < -k:
            s -= a[i] * 2.0
        else:
            while s > 10.0:
                s *= 0.5
    return s


def _caller(a):
    t = 0.0
    for k in range(3):
        t += inl(a, k) + inl(a, k + 1)
    return t


inl = None  # the inlined callee, a new dispatcher per compile (set by _compiled)


def _compiled(share: bool) -> str:
    """The caller's LLVM IR, compiled afresh (callee and caller both new)."""
    global inl
    inl = njit(inline="always")(_callee)
    caller = njit(_caller)
    a = np.arange(-3.0, 5.0)
    with inlining.sharing(share):
        got = caller(a)
    assert got == sum(_callee(a, k) + _callee(a, k + 1) for k in range(3))
    return caller.inspect_llvm(caller.signatures[0])


def _canonical(llvm: str) -> str:
    seen: dict[str, str] = {}
    text = re.sub(r"(?<!\w)B\d+", lambda m: seen.setdefault(m.group(0), f"B_{len(seen)}"), llvm)
    return re.sub(r"v\d+", "v", text)  # the dispatchers' unique names


@pytest.fixture
def spied(monkeypatch):
    """The block copies made while inlining: (shared, memo already holds the
    block's scope) per copy."""
    monkeypatch.setattr(inlining, "PACKAGES", inlining.PACKAGES + (__name__.split(".")[0],))
    seen = []
    real = inlining.copy.deepcopy

    def deepcopy(x, memo=None):
        if isinstance(x, ir.Block):
            seen.append(memo is not None and id(x.scope) in memo)
        return real(x, memo)

    monkeypatch.setattr(inlining, "copy", types.SimpleNamespace(deepcopy=deepcopy))
    return seen


def test_installed_by_the_kernels_njit():
    assert getattr(inline_closurecall.InlineWorker.inline_ir, "_whole_copy", False)
    assert isinstance(inline_closurecall.copy, inlining._Copier)


def test_same_llvm_ir_with_one_copy_of_the_scope(spied):
    block_by_block = _compiled(False)
    assert spied and not any(spied)  # numba's copies: a memo of their own
    spied.clear()
    whole = _compiled(True)
    assert sum(spied) >= len(spied) // 2  # the scope copied once per copy of the IR
    assert "_callee" in block_by_block  # (inlined: its variables are named in the caller)
    assert _canonical(whole) == _canonical(block_by_block)


def test_other_packages_keep_numbas_copies(spied, monkeypatch):
    monkeypatch.setattr(inlining, "PACKAGES", ("uniform2d",))
    _compiled(True)
    assert spied and not any(spied)


def _inner(x):
    return x * x - 1.0


def _middle(a, i):
    return inner(a[i]) + inner(a[i] + 1.0) * SCALE


def _outer(a):
    t = 0.0
    for i in range(a.shape[0]):
        t += mid(a, i) - mid(a, a.shape[0] - 1 - i)
    return t + mid(a, 0)


SCALE = 2.0
inner = mid = None  # new dispatchers per compile (set by _compiled_nested)


def _compiled_nested(share: bool, fresh: bool = True):
    """(result, LLVM IR) of ``_outer`` compiled afresh, inlining ``_middle``
    (three call sites) which inlines ``_inner`` (two); with ``fresh``, the
    two inlined kernels are new dispatchers too."""
    global inner, mid
    if fresh:
        inner = njit(inline="always")(_inner)
        mid = njit(inline="always")(_middle)
    outer = njit(_outer)
    with inlining.sharing(share):
        got = outer(np.arange(-2.0, 3.0))
    return got, outer.inspect_llvm(outer.signatures[0])


def _expected(a):
    def m(i):
        return _inner(a[i]) + _inner(a[i] + 1.0) * SCALE

    return sum(m(i) - m(len(a) - 1 - i) for i in range(len(a))) + m(0)


@pytest.fixture
def front_ends_run(monkeypatch):
    """The functions whose front end ran and was kept, in order."""
    monkeypatch.setattr(inlining, "PACKAGES", inlining.PACKAGES + (__name__.split(".")[0],))
    runs = []

    class Spy(dict):
        def __setitem__(self, key, value):
            runs.append(key[0].__name__)
            super().__setitem__(key, value)

    monkeypatch.setattr(inlining, "_front_ends", Spy())
    return runs


def test_front_end_once_per_function_same_llvm_ir(front_ends_run):
    got0, each_site = _compiled_nested(False)
    assert front_ends_run == []  # numba's front end at every site, nothing kept
    got1, once = _compiled_nested(True)
    assert sorted(front_ends_run) == ["_inner", "_middle"]  # one each for 3 + 2 sites
    assert got0 == got1 == _expected(np.arange(-2.0, 3.0))
    assert _canonical(once) == _canonical(each_site)


def test_kept_front_end_dropped_once_a_global_it_read_is_rebound(front_ends_run, monkeypatch):
    a = np.arange(-2.0, 3.0)
    assert _compiled_nested(True)[0] == _expected(a)
    assert _compiled_nested(True, fresh=False)[0] == _expected(a)
    assert sorted(front_ends_run) == ["_inner", "_middle"]  # the second compile kept them
    monkeypatch.setitem(globals(), "SCALE", 5.0)
    assert _compiled_nested(True, fresh=False)[0] == _expected(a)  # _middle reads it again
    assert sorted(front_ends_run) == ["_inner", "_middle", "_middle"]
