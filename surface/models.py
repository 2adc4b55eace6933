"""Example whole models: closed, open, any genus, one or several components.

Every model function returns ``(vertices (N, 3) float64, faces (M, 3) int64)``
(see :func:`sphere`): a clean triangle mesh (duplicate vertices merged, no
unused vertex, no degenerate face, every edge in one or two faces) whose faces
are consistently oriented with their normals pointing out of the body.  The default resolutions give a
few thousand faces, as inputs to :func:`surface.remesh` and to the benchmark
``benchmarks/bench_models.py``.  The output is deterministic.

======================  ==========  ============  ================  ========
model                   components  genus         boundary loops    creases
======================  ==========  ============  ================  ========
:func:`sphere`          1           0             0                 no
:func:`capsule`         1           0             0                 no
:func:`tank`            1           0             0                 2 rims
:func:`box`             1           0             0                 12 edges
:func:`torus`           1           1             0                 no
:func:`two_hole_plate`  1           2             0                 yes
:func:`two_bodies`      2           0, 0          0                 box's
:func:`pierced_sphere`  1           0             1 (one face)      no
:func:`open_with_holes` 1           0             2                 no
======================  ==========  ============  ================  ========

:data:`MODELS` maps names to the model functions;
:func:`surface.model_facts.model_facts` measures the topology of any triangle
mesh with numpy and scipy alone (independently of the remeshing code).

Examples
--------
>>> V, F = torus()
>>> facts = model_facts(V, F)
>>> facts["components"], facts["euler"], facts["genus"], facts["watertight"]
(1, 0, [1], True)
>>> sorted(MODELS)[:3]
['box', 'capsule', 'open_with_holes']
"""

from __future__ import annotations

import itertools
import math
import numbers

import numpy as np

from uniform2d.errors import InvalidArgumentError

from .model_facts import model_facts  # noqa: F401  (every example below states its facts)

__all__ = [
    "sphere",
    "capsule",
    "tank",
    "box",
    "torus",
    "two_hole_plate",
    "two_bodies",
    "pierced_sphere",
    "open_with_holes",
    "MODELS",
]


# --------------------------------------------------------------------------- checks


def _length(name: str, value) -> float:
    """``value`` as a finite positive float, else InvalidArgumentError."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InvalidArgumentError(f"{name} must be a positive number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise InvalidArgumentError(f"{name} must be a finite positive number, got {value!r}")
    return v


def _count(name: str, value, lo: int, hi: int) -> int:
    """``value`` as an int in [lo, hi], else InvalidArgumentError."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InvalidArgumentError(f"{name} must be a whole number, got {value!r}")
    if not lo <= int(value) <= hi:
        raise InvalidArgumentError(f"{name} must be between {lo} and {hi}, got {value}")
    return int(value)


def _clean(V, F):
    """Merge coincident vertices, drop unused ones, return (float64, int64) arrays."""
    V = np.asarray(V, dtype=np.float64)
    scale = max(float(np.abs(V).max()), 1.0)
    key = np.round(V / (scale * 1e-9)).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    F = inv.ravel()[np.asarray(F, dtype=np.int64)]
    used = np.unique(F)
    remap = np.full(len(first), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return np.ascontiguousarray(V[first][used]), np.ascontiguousarray(remap[F])


# --------------------------------------------------------------------------- builders


def _arc(center, radius, a0, a1, h):
    """Points (r, z) on a circular arc from angle a0 to a1 (radians), spacing <= h."""
    k = max(1, math.ceil(abs(a1 - a0) * radius / h))
    t = np.linspace(a0, a1, k + 1)
    return np.column_stack([center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)])


def _line(p, q, h):
    """Points from p to q (2-D), spacing <= h."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    k = max(1, math.ceil(float(np.linalg.norm(q - p)) / h))
    return p + np.linspace(0.0, 1.0, k + 1)[:, None] * (q - p)


def _profile(*pieces):
    """Concatenate polylines, dropping each piece's first point after the first piece."""
    return np.concatenate([pieces[0]] + [p[1:] for p in pieces[1:]])


def _zip_rings(a, b, m, n, oa, ob):
    """Triangles (outward for a profile turning counter-clockwise in (r, z)) between
    ring ``a`` (indices a..a+m-1, angular offset oa steps) and ring b (n, ob)."""
    if m == 1 or n == 1:  # a pole: a fan
        if m == 1:
            return [(a, b + (j + 1) % n, b + j) for j in range(n)]
        return [(a + i, a + (i + 1) % m, b) for i in range(m)]
    tris, i, j = [], 0, 0
    while i < m or j < n:
        next_a = (i + 1 + oa) / m
        next_b = (j + 1 + ob) / n
        if j >= n or (i < m and next_a <= next_b):
            tris.append((a + i % m, a + (i + 1) % m, b + j % n))
            i += 1
        else:
            tris.append((a + i % m, b + (j + 1) % n, b + j % n))
            j += 1
    return tris


def _revolve(profile, h, closed=False):
    """Surface of revolution about the z axis of a polyline of (r, z) points.

    Points with r == 0 become poles; the others rings of about ``2 pi r / h``
    points.  With ``closed`` the last point joins the first (a torus).
    """
    rings, V, start = [], [], 0
    for k, (r, z) in enumerate(profile):
        m = 1 if r <= 0.0 else max(3, round(2.0 * math.pi * r / h))
        off = 0.5 * (k % 2) if m > 1 else 0.0
        t = 2.0 * math.pi * (np.arange(m) + off) / m
        V.append(np.column_stack([r * np.cos(t), r * np.sin(t), np.full(m, z)]))
        rings.append((start, m, off))
        start += m
    pairs = list(itertools.pairwise(rings)) + ([(rings[-1], rings[0])] if closed else [])
    F = [t for (a, m, oa), (b, n, ob) in pairs for t in _zip_rings(a, b, m, n, oa, ob)]
    return _clean(np.concatenate(V), np.array(F, dtype=np.int64))


def _grid_faces(nu: int, nv: int):
    """Triangles of an (nu+1) x (nv+1) grid of points (row-major in u), counter-clockwise
    in (u, v), diagonals alternating like a chequerboard."""
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    i, j = i.ravel(), j.ravel()
    p00 = i * (nv + 1) + j
    p10, p01, p11 = p00 + nv + 1, p00 + 1, p00 + nv + 2
    even = (i + j) % 2 == 0
    t1 = np.where(even[:, None], np.column_stack([p00, p10, p11]), np.column_stack([p00, p10, p01]))
    t2 = np.where(even[:, None], np.column_stack([p00, p11, p01]), np.column_stack([p10, p11, p01]))
    return np.concatenate([t1, t2])


def _box_mesh(extents, h):
    """An axis-aligned box centred at the origin, each face a grid of spacing <= h."""
    ext = np.asarray(extents, dtype=np.float64)
    cells = [max(1, math.ceil(e / h)) for e in ext]
    axes = [np.linspace(-e / 2.0, e / 2.0, c + 1) for e, c in zip(ext, cells)]
    Vs, Fs, base = [], [], 0
    for d in range(3):
        u, v = (d + 1) % 3, (d + 2) % 3
        for side in (-1.0, 1.0):
            U, W = np.meshgrid(axes[u], axes[v], indexing="ij")
            P = np.empty((U.size, 3))
            P[:, u], P[:, v], P[:, d] = U.ravel(), W.ravel(), side * ext[d] / 2.0
            T = _grid_faces(cells[u], cells[v])
            Fs.append((T if side > 0 else T[:, ::-1]) + base)
            Vs.append(P)
            base += len(P)
    return _clean(np.concatenate(Vs), np.concatenate(Fs))


def _voxel_surface(occ, h):
    """Boundary of a set of voxels (bool array), faces pointing out of the solid."""
    occ = np.pad(np.asarray(occ, dtype=bool), 1)
    quads = []
    for d in range(3):
        u, v = (d + 1) % 3, (d + 2) % 3
        a = np.take(occ, np.arange(occ.shape[d] - 1), axis=d)
        b = np.take(occ, np.arange(1, occ.shape[d]), axis=d)
        for mask, flip in ((a & ~b, False), (b & ~a, True)):
            c = np.argwhere(mask)  # voxel corner of the face, on plane c[d] + 1
            c[:, d] += 1
            eu, ev = np.eye(3, dtype=np.int64)[u], np.eye(3, dtype=np.int64)[v]
            q = np.stack([c, c + eu, c + eu + ev, c + ev], axis=1)
            quads.append(q[:, ::-1] if flip else q)
    Q = np.concatenate(quads).reshape(-1, 3)
    F = np.arange(len(Q)).reshape(-1, 4)
    F = np.concatenate([F[:, [0, 1, 2]], F[:, [0, 2, 3]]])
    return _clean(Q * h, F)


# --------------------------------------------------------------------------- models


def sphere(radius=1.0, subdivisions=4):
    """An icosphere (trimesh's subdivided icosahedron): closed, genus 0.

    Parameters
    ----------
    radius : float
    subdivisions : int
        0 to 6; 4 (default) gives 2562 vertices and 5120 faces.

    Returns
    -------
    vertices : (N, 3) float64
    faces : (M, 3) int64

    Examples
    --------
    >>> V, F = sphere()
    >>> V.shape, F.shape
    ((2562, 3), (5120, 3))
    """
    import trimesh

    r = _length("radius", radius)
    k = _count("subdivisions", subdivisions, 0, 6)
    m = trimesh.creation.icosphere(subdivisions=k, radius=r)
    return _clean(m.vertices, m.faces)


def capsule(radius=0.5, length=1.0, segments=48):
    """A cylinder of ``length`` closed by two hemispheres: closed, smooth, genus 0.

    Parameters
    ----------
    radius : float
    length : float
        Length of the cylindrical part (the capsule is ``length + 2 radius`` long).
    segments : int
        Edges around the equator (8 to 1000); sets the spacing ``2 pi radius /
        segments`` everywhere.  The default gives 2996 faces.

    Examples
    --------
    >>> V, F = capsule()
    >>> model_facts(V, F)["genus"]
    [0]
    """
    r, L = _length("radius", radius), _length("length", length)
    h = 2.0 * math.pi * r / _count("segments", segments, 8, 1000)
    prof = _profile(
        _arc((0.0, -L / 2), r, -math.pi / 2, 0.0, h),
        _line((r, -L / 2), (r, L / 2), h),
        _arc((0.0, L / 2), r, 0.0, math.pi / 2, h),
    )
    prof[[0, -1], 0] = 0.0  # exact poles
    return _revolve(prof, h)


def tank(radius=0.5, height=1.0, segments=48):
    """A closed cylinder with flat caps: genus 0, creases (90 degrees) at both rims.

    Parameters
    ----------
    radius : float
    height : float
    segments : int
        Edges around the rims (8 to 1000), which sets the spacing.  The default
        gives 2304 faces.

    Examples
    --------
    >>> V, F = tank()
    >>> facts = model_facts(V, F)
    >>> facts["euler"], facts["watertight"]
    (2, True)
    """
    r, H = _length("radius", radius), _length("height", height)
    h = 2.0 * math.pi * r / _count("segments", segments, 8, 1000)
    prof = _profile(
        _line((0.0, -H / 2), (r, -H / 2), h),
        _line((r, -H / 2), (r, H / 2), h),
        _line((r, H / 2), (0.0, H / 2), h),
    )
    return _revolve(prof, h)


def box(extents=(1.0, 1.0, 1.0), divisions=16):
    """An axis-aligned box centred at the origin, each face a fine triangle grid.

    Genus 0, creases (90 degrees) along its 12 edges, 8 corners.

    Parameters
    ----------
    extents : (3,) floats
        Side lengths along x, y and z.
    divisions : int
        Grid cells along the longest side (1 to 1000); the others get as many
        cells of at most that size.  The default gives 3072 faces on a cube.

    Examples
    --------
    >>> V, F = box()
    >>> len(V), len(F)
    (1538, 3072)
    """
    ext = np.asarray(extents, dtype=object).ravel()
    if ext.shape != (3,):
        raise InvalidArgumentError(f"extents must be three side lengths, got {extents!r}")
    ext = [_length("extents", e) for e in ext]
    k = _count("divisions", divisions, 1, 1000)
    return _box_mesh(ext, max(ext) / k * (1.0 + 1e-12))


def torus(major_radius=1.0, minor_radius=0.35, segments=24):
    """A ring torus about the z axis: closed, smooth, genus 1.

    Parameters
    ----------
    major_radius : float
        Distance from the axis to the centre of the tube.
    minor_radius : float
        Radius of the tube (less than ``major_radius``).
    segments : int
        Edges around the tube (6 to 1000), which sets the spacing everywhere
        (fewer edges on the inner rings).  The default gives 3300 faces.

    Examples
    --------
    >>> V, F = torus()
    >>> model_facts(V, F)["euler"]
    0
    """
    R, r = _length("major_radius", major_radius), _length("minor_radius", minor_radius)
    if r >= R:
        raise InvalidArgumentError(
            f"minor_radius ({r}) must be less than major_radius ({R}) for a ring torus"
        )
    k = _count("segments", segments, 6, 1000)
    h = 2.0 * math.pi * r / k
    prof = _arc((R, 0.0), r, -math.pi, math.pi, h)[:-1]  # counter-clockwise, open loop
    return _revolve(prof, h, closed=True)


def two_hole_plate(size=1.0, voxels=10):
    """A thick plate with two square through-holes: closed, genus 2, with creases.

    Built from the boundary faces of a block of voxels, ``3 x 1.6 x 0.4`` times
    ``size``; the holes are ``0.6 x 0.6``.  Every face is flat and made of many
    triangles; creases (90 degrees) run along the plate's and the holes' edges.

    Parameters
    ----------
    size : float
        Scale of the plate.
    voxels : int
        Voxels per unit of ``size`` (5 to 200, a multiple of 5 so the holes fall
        on voxel faces).  The default gives 2752 faces.

    Examples
    --------
    >>> V, F = two_hole_plate()
    >>> facts = model_facts(V, F)
    >>> facts["euler"], facts["genus"]
    (-2, [2])
    """
    s = _length("size", size)
    k = _count("voxels", voxels, 5, 200)
    if k % 5:
        raise InvalidArgumentError(f"voxels must be a multiple of 5, got {k}")
    u = k // 5  # voxels per 0.2
    occ = np.ones((15 * u, 8 * u, 2 * u), dtype=bool)
    for x0 in (3 * u, 9 * u):  # holes at x in [0.6, 1.2] and [1.8, 2.4], y in [0.5, 1.1]
        occ[x0 : x0 + 3 * u, 5 * u // 2 : 5 * u // 2 + 3 * u, :] = False
    V, F = _voxel_surface(occ, s / k)
    return V - 0.5 * (V.min(axis=0) + V.max(axis=0)), F


def two_bodies(gap=1.0, subdivisions=3, divisions=12):
    """A sphere of radius 1 and a unit cube beside it: two closed components.

    The sphere's faces come first.

    Parameters
    ----------
    gap : float
        Distance between the sphere and the cube.
    subdivisions : int
        Of the sphere (see :func:`sphere`); default 1280 faces.
    divisions : int
        Of the cube (see :func:`box`); default 1728 faces.

    Examples
    --------
    >>> V, F = two_bodies()
    >>> model_facts(V, F)["components"]
    2
    """
    g = _length("gap", gap)
    V1, F1 = sphere(1.0, subdivisions)
    V2, F2 = box((1.0, 1.0, 1.0), divisions)
    V2 = V2 + np.array([1.5 + g, 0.0, 0.0])
    return np.concatenate([V1, V2]), np.concatenate([F1, F2 + len(V1)])


def pierced_sphere(radius=1.0, subdivisions=4):
    """An icosphere with one face removed: open, genus 0, one tiny boundary loop.

    Parameters
    ----------
    radius : float
    subdivisions : int
        See :func:`sphere`.

    Examples
    --------
    >>> V, F = pierced_sphere()
    >>> facts = model_facts(V, F)
    >>> facts["boundary_loops"], facts["watertight"]
    (1, False)
    """
    V, F = sphere(radius, subdivisions)
    return V, F[1:].copy()


def open_with_holes(radius=1.0, hole_angle=30.0, segments=96):
    """A hemisphere with a round hole at its pole: open, genus 0, two boundary loops.

    The spherical zone between the polar angle ``hole_angle`` and the equator,
    normals pointing away from the centre.

    Parameters
    ----------
    radius : float
    hole_angle : float
        Angular radius of the hole in degrees (1 to 80).
    segments : int
        Edges around the equator (8 to 2000), which sets the spacing.  The
        default gives 2538 faces.

    Examples
    --------
    >>> V, F = open_with_holes()
    >>> model_facts(V, F)["boundary_loops"]
    2
    """
    r = _length("radius", radius)
    a = _length("hole_angle", hole_angle)
    if not 1.0 <= a <= 80.0:
        raise InvalidArgumentError(f"hole_angle must be between 1 and 80 degrees, got {a}")
    h = 2.0 * math.pi * r / _count("segments", segments, 8, 2000)
    return _revolve(_arc((0.0, 0.0), r, 0.0, math.radians(90.0 - a), h), h)


#: Model name -> function, for benchmarks and tests.
MODELS = {
    "sphere": sphere,
    "capsule": capsule,
    "tank": tank,
    "box": box,
    "torus": torus,
    "two_hole_plate": two_hole_plate,
    "two_bodies": two_bodies,
    "pierced_sphere": pierced_sphere,
    "open_with_holes": open_with_holes,
}
