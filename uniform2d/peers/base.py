"""The peer interface, the registry, and the size-parameter tuner.

A peer is a module with these module-level names:

``NAME`` : str
    Registry key (``"gmsh"``).
``KIND`` : {"planar", "surface"}
    What it meshes: a :class:`~uniform2d.Polygon`, or a surface patch given as
    ``(V, F)`` arrays.
``DESCRIPTION`` : str
    One line for the report ("Gmsh 4.x Frontal-Delaunay, ...").
``REQUIRES`` : tuple of str
    The pip packages it needs (shown when it is not installed).
``available() -> bool``
    Whether it can run here.  Must not raise.
``mesh(domain, n_vertices) -> PeerMesh``
    A mesh of ``domain`` with as close to ``n_vertices`` vertices as the peer
    can get (usually by :func:`tune` on its size parameter).

The registry (:data:`PEERS`) maps names to module paths; modules are imported
only when used, and only they import the peer's library (no other module of
uniform2d imports gmsh or triangle).
"""

from __future__ import annotations

import importlib
import logging
import math
from dataclasses import dataclass, field
from types import ModuleType
from typing import Callable

import numpy as np

from ..geometry import size_for_count

log = logging.getLogger(__name__)

__all__ = [
    "PEERS",
    "PeerMesh",
    "Tuned",
    "names",
    "load",
    "available",
    "kind",
    "describe",
    "takes_constraints",
    "mesh",
    "tune",
    "tuned_mesh",
    "tuned_planar_mesh",
    "planar_result",
    "orient_ccw",
    "compact",
    "size_for_count",
]

#: Registered peers, in report order: name -> module.
PEERS: dict[str, str] = {
    "gmsh": "uniform2d.peers.gmsh_peer",
    "triangle": "uniform2d.peers.triangle_peer",
    "cvt": "uniform2d.peers.cvt_peer",
    "meshlab": "uniform2d.peers.meshlab_peer",
    "cgal": "uniform2d.peers.cgal_peer",
    "pyacvd": "uniform2d.peers.pyacvd_peer",
}

#: The peers a report compares with when none are named: those of the project's
#: extras.  CGAL's bindings and pyacvd (comparison-only, installed by hand) run
#: when named (``--peers``).
DEFAULT = ("gmsh", "triangle", "cvt", "meshlab")


@dataclass(frozen=True, eq=False)
class PeerMesh:
    """A peer's mesh and how it was tuned.

    Attributes
    ----------
    points : ndarray, shape (N, 2) or (N, 3), float64
    triangles : ndarray, shape (M, 3), int64
        Counter-clockwise for planar meshes.
    size : float or None
        The value of the peer's size parameter that produced it (``None`` if
        the peer takes the vertex count directly).
    evaluations : int
        Number of meshes made while tuning (1 for an exact-count peer).
    info : dict
        Peer-specific details (parameter name, tuning history, ...).
    """

    points: np.ndarray
    triangles: np.ndarray
    size: float | None = None
    evaluations: int = 1
    info: dict = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class Tuned:
    """Result of :func:`tune`.

    Attributes
    ----------
    result : object
        What ``make(size)`` returned for the best size.
    size : float
        The best size found.
    count : int
        Its vertex count.
    evaluations : int
        Number of calls of ``make``.
    history : tuple of (float, int)
        Every (size, count) tried, in order.
    """

    result: object
    size: float
    count: int
    evaluations: int
    history: tuple


def defaults() -> tuple[str, ...]:
    """The peers of a report that names none (:data:`DEFAULT`)."""
    return DEFAULT


def names() -> tuple[str, ...]:
    """Registered peer names, in report order."""
    return tuple(PEERS)


def load(name: str) -> ModuleType:
    """The module of peer ``name``.

    Raises
    ------
    KeyError
        If ``name`` is not registered.
    """
    if name not in PEERS:
        raise KeyError(f"unknown peer {name!r}; known peers: {', '.join(PEERS)}")
    return importlib.import_module(PEERS[name])


def available(name: str) -> bool:
    """Whether peer ``name`` can run here (its optional dependencies import)."""
    try:
        return bool(load(name).available())
    except Exception as exc:  # a broken optional install counts as missing
        log.debug("peer %s unavailable: %s", name, exc)
        return False


def kind(name: str) -> str:
    """``"planar"`` or ``"surface"``."""
    return load(name).KIND


def takes_constraints(name: str) -> bool:
    """Whether planar peer ``name`` meshes a polygon's interior segments and fixed
    points as mesh edges and vertices (its module sets ``CONSTRAINTS = True``).

    A peer that does not is given only the rings, so its mesh is of another
    problem: the report marks its cases of a constrained polygon "not comparable".
    """
    return bool(getattr(load(name), "CONSTRAINTS", False))


def describe(name: str) -> dict:
    """Name, kind, description, required packages and availability of a peer."""
    mod = load(name)
    return {
        "name": mod.NAME,
        "kind": mod.KIND,
        "description": mod.DESCRIPTION,
        "requires": list(mod.REQUIRES),
        "available": available(name),
    }


def mesh(name: str, domain, n_vertices: int) -> PeerMesh:
    """Run peer ``name`` on ``domain`` aiming at ``n_vertices`` vertices."""
    return load(name).mesh(domain, int(n_vertices))


def tune(
    make: Callable[[float], object],
    count: Callable[[object], int],
    target: int,
    size0: float,
    *,
    max_evals: int = 40,
    rtol: float = 1e-6,
) -> Tuned:
    """Bisect a size parameter until the vertex count equals ``target``.

    The count is assumed to decrease (not necessarily strictly, nor exactly
    monotonically) as the size grows.  The size is first bracketed by steps of
    a factor 1.25 from ``size0``, then bisected geometrically; the search stops
    at an exact hit, when the bracket is narrower than ``rtol`` relative, or
    after ``max_evals`` meshes.  The size whose count is closest to ``target``
    wins (ties: the one found first), so the result is deterministic.

    Parameters
    ----------
    make : callable
        ``make(size)`` -> a mesh.
    count : callable
        ``count(mesh)`` -> its vertex count.
    target : int
    size0 : float
        Starting guess (e.g. :func:`size_for_count`).
    max_evals : int
    rtol : float

    Returns
    -------
    Tuned

    Examples
    --------
    >>> t = tune(lambda h: int(100 / h**2), lambda c: c, 400, 1.0)
    >>> t.count, round(t.size, 2)
    (400, 0.5)
    """
    history = []
    best = None

    def ev(size):
        nonlocal best
        res = make(size)
        c = int(count(res))
        history.append((float(size), c))
        if best is None or abs(c - target) < abs(best[2] - target):
            best = (res, float(size), c)
        return c

    s = float(size0)
    c = ev(s)
    lo = hi = None  # lo: count >= target (small size); hi: count <= target
    if c == target:
        lo = hi = s
    elif c > target:
        lo = s
        while len(history) < max_evals:
            s *= 1.25
            c = ev(s)
            if c <= target:
                hi = s
                break
            lo = s
    else:
        hi = s
        while len(history) < max_evals:
            s /= 1.25
            c = ev(s)
            if c >= target:
                lo = s
                break
            hi = s
    if lo is not None and hi is not None:
        while best[2] != target and len(history) < max_evals and hi > lo * (1.0 + rtol):
            mid = math.sqrt(lo * hi)
            c = ev(mid)
            if c == target:
                break
            if c > target:
                lo = mid
            else:
                hi = mid
    res, size, c = best
    log.debug("tuned size %.6g -> %d vertices (target %d, %d meshes)", size, c, target, len(history))
    return Tuned(res, size, c, len(history), tuple(history))


def tuned_mesh(make, n_vertices: int, size0: float, info, **options) -> PeerMesh:
    """The mesh ``make(size)`` (a (points, triangles) pair) with its size tuned by
    :func:`tune` to ``n_vertices`` vertices; ``info(size)`` describes the parameter,
    the tuning history is added to it."""
    t = tune(make, lambda m: len(m[0]), n_vertices, size0, **options)
    pts, tri = t.result
    return PeerMesh(pts, tri, t.size, t.evaluations, {**info(t.size), "history": t.history})


def orient_ccw(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Triangles with clockwise ones reversed (planar points)."""
    p = points[triangles]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (
        p[:, 1, 1] - p[:, 0, 1]
    ) * (p[:, 2, 0] - p[:, 0, 0])
    tri = triangles.copy()
    cw = cross < 0
    tri[cw] = tri[cw][:, ::-1]
    return tri


def compact(points: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop vertices no triangle uses, renumbering the triangles (order kept)."""
    used = np.zeros(len(points), dtype=bool)
    used[triangles.ravel()] = True
    if used.all():
        return points, triangles
    new = np.cumsum(used) - 1
    return points[used], new[triangles]


def planar_result(points: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A planar mesher's output as every peer returns it: unused vertices dropped,
    the points contiguous, every triangle counter-clockwise."""
    points, triangles = compact(points, triangles)
    return np.ascontiguousarray(points), orient_ccw(points, triangles)


def tuned_planar_mesh(mesh_with_size, polygon, n_vertices: int, info) -> PeerMesh:
    """:func:`tuned_mesh` of a planar mesher ``mesh_with_size(polygon, size)``,
    from the size of an equilateral mesh with ``n_vertices`` vertices."""
    size0 = size_for_count(polygon.area, polygon.perimeter, n_vertices, polygon.n_holes)
    return tuned_mesh(lambda h: mesh_with_size(polygon, h), n_vertices, size0, info)
