"""Numba kernel: predicates, flat-array CDT, lazy heap, Algorithm INSERT.

Calls from one kernel function to another pass integer arguments as
``np.int64(...)`` where a caller would otherwise give a literal constant or an
int32 array element: numba compiles a separate specialisation of the callee for
every distinct argument type, ``Literal[int](4096)`` and int32 included, and
each extra copy of ``locate``, ``insert_point``, ``legalize_stack`` and their
callees lengthens the cold compile (once per machine: ``cache=True``).  Boolean
flags go as ``np.bool_(...)`` for the same reason (a literal True and a literal
False are two specialisations).  Array copies are loops rather than slice
assignments, and small reductions (min, max, searchsorted, cumsum) are written
out: numba's generic versions, and the shape-mismatch error path a slice
assignment brings in, compile far longer than the loops they replace.
"""
