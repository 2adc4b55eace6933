"""Borrowed structref copies (``uniform2d._kernel.borrow``): the copy works on the
original's memory, and settling it back leaves the original exactly as if it had
been used directly -- also when a buffer grew on the way."""

from __future__ import annotations

import numpy as np
from numba import njit

from uniform2d._kernel import heap
from uniform2d._kernel.borrow import borrowed, settle


@njit
def _fill_borrowed(H, keys):
    B = borrowed(H)
    for i in range(keys.shape[0]):
        heap.push(B, keys[i], np.int32(i), np.int32(-i))
    settle(H, B)


@njit
def _fill(H, keys):
    for i in range(keys.shape[0]):
        heap.push(H, keys[i], np.int32(i), np.int32(-i))


@njit
def _drain(H):
    out = np.empty((H.size, 3))
    for i in range(out.shape[0]):
        k, a, b = heap.pop(H)
        out[i, 0], out[i, 1], out[i, 2] = k, a, b
    return out


@njit
def _writes_through(H):
    B = borrowed(H)
    B.keys[0] = 7.5  # no growth: the copy's array is the original's memory
    B.size = 1
    before = H.size
    settle(H, B)
    return before, H.size, H.keys[0]


def test_borrowed_heap_settles_like_the_original():
    keys = np.random.default_rng(5).random(1000)  # 16 slots: the buffers grow 6 times
    direct, via = heap.new_heap(16), heap.new_heap(16)
    _fill(direct, keys)
    _fill_borrowed(via, keys)
    assert np.array_equal(_drain(direct), _drain(via))


def test_borrowed_shares_memory_and_settles_scalars():
    H = heap.new_heap(16)
    before, after, key = _writes_through(H)
    assert (before, after, key) == (0, 1, 7.5)
