"""Peer meshers the comparison report measures uniform2d against.

Each peer lives in its own module and is loaded lazily through the registry in
:mod:`uniform2d.peers.base`, so that importing this package never imports an
optional dependency (gmsh, triangle, pymeshlab, CGAL, pyacvd).  A peer whose dependency is
missing is reported as "not installed" (:func:`available` is False).

>>> from uniform2d import peers
>>> peers.names()
('gmsh', 'triangle', 'cvt', 'meshlab', 'cgal', 'pyacvd')
>>> peers.kind("cvt")
'planar'
"""

from .base import (
    PeerMesh,
    Tuned,
    available,
    defaults,
    describe,
    kind,
    load,
    mesh,
    names,
    size_for_count,
    takes_constraints,
    tune,
)

__all__ = [
    "names",
    "defaults",
    "load",
    "available",
    "kind",
    "describe",
    "takes_constraints",
    "mesh",
    "PeerMesh",
    "Tuned",
    "tune",
    "size_for_count",
]
