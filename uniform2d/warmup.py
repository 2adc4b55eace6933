"""Compiling, ahead of a run, the kernels a mesh needs late: the first run's warm-up.

numba compiles a kernel when it is first called, and what it compiles goes into
its disk cache (``cache=True``, see :mod:`uniform2d.compile_cache`), where numba
looks before it compiles anything, a kernel called from Python or one typed as
the callee of another.  :func:`warm` compiles, in a second process that the
command starts on a cold cache (:mod:`uniform2d.cli._warmer`), in an order
chosen against the order a :func:`uniform2d.uniform_mesh` run needs the kernels
in.  The run first compiles the optimiser's start (the distance to P's edges,
the lattice), the exact triangulation of the start and the relaxation; INSERT,
for T+ and the certificates' d_n, it compiles last (on a thread of its own,
from the relaxation on: ``optimize.pipeline``), and it is the largest compile
of all.  So the warmer compiles INSERT first, whole, then the kernels the
run needs after its start, from the last (the optimiser's spread sweeps) back
to the first (the start's check): the run, compiling them from the first,
meets the warmer halfway instead of following it (the measures of T+'s mesh,
needed after INSERT, come right after it).

A kernel is cached per argument types (dtypes, layouts, int32 against int64),
so the warm-up makes its calls with the library's own code on tiny inputs (a
lattice mesh loaded as the optimiser loads one; INSERT's queues as INSERT makes
them), and where a call cannot run on those, with signatures written out;
``tests/test_warmer.py`` checks that a run after it compiles none of its
kernels again.
"""

from __future__ import annotations

import numpy as np
from numba import types

from . import libm
from ._kernel import heap
from ._kernel import insert as kinsert
from ._kernel.clearance import bucket_grid, closest_pair, none_within
from ._kernel.cdt import allocate
from ._kernel.edges import edges_by_vertex
from .optimize import schedule as S
from .optimize.boundary import target_size
from .optimize.moves import KernelMesh, Progress, default_schedule, finish
from .optimize.objective import objective_code
from .optimize.seed import start, variants
from .polygon import Polygon

__all__ = ["warm"]


def warm() -> None:
    """Compile, into numba's cache, kernels a :func:`uniform2d.uniform_mesh` run
    compiles late, by running the library's code on tiny inputs, in the order
    the module docstring gives."""
    # INSERT, whole: the run needs it last, and the warmer alone has the time
    # to compile it before then (compiled by the run, it was the last third of
    # the run's compile, the warmer idle)
    _insert_run()
    # ... and the measures of T+'s mesh (always on read-only triangles) and of
    # its points (d_n, for T+ and the certificates: the run's last compile)
    edges_by_vertex.compile((types.Array(types.int64, 2, "C", readonly=True), types.int64))
    closest_pair(np.zeros((2, 2)), 1.0)
    # ... and the C library's functions, which the optimiser's last stages (the
    # polish, the angle fit) call first
    x = np.full(2, 0.5)
    for f in (libm.exp, libm.log, libm.arcsin, libm.arccos):
        f(x)
    libm.arctan2(x, x)

    # then what the run compiles before INSERT, from its end back: the
    # optimiser's stages, the last first, on a lattice mesh ...
    polygon, points, triangles, edges = _lattice(4)
    st = KernelMesh.from_mesh(polygon, points, triangles, edges=edges)
    obj = objective_code("balanced")
    none = default_schedule(len(st.xy), False)._replace(
        spring_rounds=0, sweeps=1, exponents=(), spread_sweeps=0)
    for stage in (dict(spread_sweeps=1), dict(exponents=(S.AFTER_TRIALS,)),
                  dict(spring_rounds=1)):
        st.advance(none._replace(**stage), obj)
        st.rank(obj)
    # ... its start (the distance to P's edges) and the start's check
    n = len(points) - len(polygon.vertices)
    start(polygon, n, target_size(polygon, n), variants(polygon, n)[0])
    # (the lattices' test against points placed before them, which this start
    # does not reach: the rows around small holes)
    R = np.zeros((1, 2))
    x0, y0, nx, ny, first, order = bucket_grid(R, 1.0)
    none_within(R.copy(), R, x0, y0, 1.0, nx, ny, first, order, 1.0)
    finish(polygon, st.sites(), Progress())


def _insert_run() -> None:
    """Compile INSERT's run (its queues and, called by name, its steps) on a
    tiny empty triangulation, typed as :func:`uniform2d.insert` types it,
    inserting nothing."""
    m, _ = allocate(4, 4)
    M = heap.new_heap(16)
    kinsert.push_initial(m, M)  # (no triangle yet: pushes nothing)
    P = kinsert.new_pool(64)
    kinsert.run(m, M, P, 0, np.empty((0, 2), np.float64), np.empty(0, np.float64),
                np.zeros(0, np.bool_), 0.0, 0.0)


def _lattice(k: int):
    """(square polygon, points, triangles, edges): the k x k unit lattice of the
    square [0, k]^2 cut into triangles (Delaunay), its corners first, then the
    other lattice points, with the polygon edge each lies on (-1 inside)."""
    g = np.arange(k + 1, dtype=np.float64)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    corner = np.array([0, k, (k + 1) ** 2 - 1, k * (k + 1)])
    order = np.concatenate([corner, np.setdiff1d(np.arange((k + 1) ** 2), corner)])
    rank = np.argsort(order)  # lattice index -> place in ``order``
    a = (np.arange(k)[:, None] * (k + 1) + np.arange(k)[None, :]).ravel()  # lower-left corners
    cells = np.stack([a, a + 1, a + k + 2, a + k + 1], axis=1)
    triangles = rank[np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])]
    points = np.column_stack([x, y])[order]
    edges = np.full(len(points), -1, np.int64)
    for e, (axis, value) in enumerate([(1, 0.0), (0, k), (1, k), (0, 0.0)]):
        edges[points[:, axis] == value] = e
    polygon = Polygon(points[:4])
    return polygon, points, triangles.astype(np.int64), edges[4:]
