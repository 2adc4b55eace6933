"""Numba kernel: predicates, flat-array CDT, lazy heap, Algorithm INSERT."""
