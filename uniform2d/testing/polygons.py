"""Random test polygons: convex, star-shaped and holed, fully described by a seed.

Every generator takes an ``np.random.Generator`` or an integer seed (anything
``np.random.default_rng`` accepts) and never touches a global random state, so a
test case is fully described by its seed.  Generated shapes are kept "reasonable"
(no sliver edges, holes separated from each other and from the outer ring by a
margin) so that they exercise the geometry -- reflex corners, visibility around
holes -- rather than floating-point extremes.  All return :class:`uniform2d.Polygon`.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..errors import InvalidArgumentError
from ..polygon import Polygon

__all__ = ["convex", "star", "with_holes", "convex_ring", "star_ring"]


def _rng(rng) -> np.random.Generator:
    return np.random.default_rng(rng)


def _angles(rng: np.random.Generator, k: int, spread=(0.6, 1.4)) -> np.ndarray:
    """k sorted angles around the circle; every gap within ``spread`` x the mean gap."""
    gaps = rng.uniform(spread[0], spread[1], k)
    gaps *= 2.0 * np.pi / gaps.sum()
    return rng.uniform(0.0, 2.0 * np.pi) + np.concatenate([[0.0], np.cumsum(gaps[:-1])])


def _place(rng: np.random.Generator, ring: np.ndarray, size: float) -> np.ndarray:
    """Random rotation, the given size and a random offset."""
    th = rng.uniform(0.0, 2.0 * np.pi)
    rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    off = rng.uniform(-2.0, 2.0, 2)
    return ring @ rot.T * size + off


def convex_ring(rng: np.random.Generator, k: int) -> np.ndarray:
    """A strictly convex ring of ``k`` vertices on a random ellipse."""
    ang = _angles(rng, k)
    ax = rng.uniform(0.45, 1.0)  # ellipse: strictly convex, no collinear vertices
    return np.stack([np.cos(ang), ax * np.sin(ang)], axis=1)


def star_ring(rng: np.random.Generator, k: int) -> np.ndarray:
    """Radial polygon at sorted angles with random radii; has at least one reflex vertex."""
    while True:
        ang = _angles(rng, k)
        rad = rng.uniform(0.35, 1.0, k)
        ring = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)
        prev = np.roll(ring, 1, axis=0) - ring
        nxt = np.roll(ring, -1, axis=0) - ring
        cross = nxt[:, 0] * prev[:, 1] - nxt[:, 1] * prev[:, 0]
        ang_i = np.arctan2(cross, (nxt * prev).sum(1))
        interior = np.where(ang_i <= 0, ang_i + 2 * np.pi, ang_i)
        # CCW ring (angles increase): reflex where the interior angle exceeds pi.
        if (interior > np.pi + 0.1).any() and interior.min() > 0.25:
            return ring


def convex(rng, k: int | None = None) -> Polygon:
    """A random strictly convex polygon with ``k`` vertices (default: 3..10)."""
    return _one_ring(rng, k, convex_ring, (3, 11), 3, "a polygon")


def star(rng, k: int | None = None) -> Polygon:
    """A random star-shaped, non-convex polygon with ``k`` vertices (default 6..14),
    vertices at sorted angles with random radii, at least one reflex vertex."""
    return _one_ring(rng, k, star_ring, (6, 15), 4, "a non-convex polygon")


def _one_ring(rng, k, ring, default: tuple, least: int, what: str) -> Polygon:
    """A polygon of one ``ring(rng, k)`` (k drawn from ``default``, a half-open
    range, when not given; at least ``least``), at a random size and offset."""
    rng = _rng(rng)
    if k is None:
        k = int(rng.integers(*default))
    if k < least:
        raise InvalidArgumentError(f"{what} needs k >= {least} vertices")
    return Polygon(_place(rng, ring(rng, k), rng.uniform(0.5, 2.0)))


def with_holes(rng, n_holes: int | None = None, margin: float = 0.06) -> Polygon:
    """A convex or star-shaped outer ring (radius ~1) with ``n_holes`` (default 1..3)
    small convex or star-shaped holes strictly inside it, every hole at least
    ``margin`` (relative to the outer radius) from the outer ring and from the
    other holes."""
    rng = _rng(rng)
    if n_holes is None:
        n_holes = int(rng.integers(1, 4))
    for _attempt in range(1000):
        if rng.uniform() < 0.5:
            outer = convex_ring(rng, int(rng.integers(4, 11)))
        else:
            outer = star_ring(rng, int(rng.integers(6, 13)))
        shell = shapely.Polygon(outer)
        inner = shell.buffer(-margin, join_style="mitre")
        if inner.is_empty:
            continue
        x0, y0, x1, y1 = inner.bounds
        holes: list[np.ndarray] = []
        hole_polys: list[shapely.Polygon] = []
        for _try in range(400):
            if len(holes) == n_holes:
                break
            r = rng.uniform(0.08, 0.2)
            if rng.uniform() < 0.5:
                h = convex_ring(rng, int(rng.integers(3, 7)))
            else:
                h = star_ring(rng, int(rng.integers(5, 9)))
            th = rng.uniform(0.0, 2.0 * np.pi)
            rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
            h = h @ rot.T * r + rng.uniform([x0, y0], [x1, y1])
            hp = shapely.Polygon(h)
            if not inner.contains(hp):
                continue
            if any(hp.distance(o) < margin for o in hole_polys):
                continue
            holes.append(h)
            hole_polys.append(hp)
        if len(holes) == n_holes:
            size = rng.uniform(0.5, 2.0)
            off = rng.uniform(-2.0, 2.0, 2)
            return Polygon(outer * size + off, [h * size + off for h in holes])
    raise InvalidArgumentError(  # pragma: no cover
        f"could not place {n_holes} holes {margin} apart in 1000 outlines; ask for fewer "
        "holes or a smaller margin")
