"""Corners of an outline's ring at the scale of a mesh spacing (:mod:`uniform2d.outline`).

A digitised outline turns sharply at many vertices that are only its
digitising steps; a corner is a vertex that turns both between its own two
edges and between the chords to the outline half a spacing before and after it.
"""

from __future__ import annotations

import numpy as np

from . import libm

__all__ = ["ring_corners", "scale_turning"]


def scale_turning(ring: np.ndarray, s: float) -> np.ndarray:
    """Turning angle (k,) radians at every vertex of a closed ring (k, 2), measured
    between the chords from the ring point an arc ``s`` before it and to the one
    an arc ``s`` after it (at most a quarter of the ring)."""
    seg = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    s = min(s, cum[-1] / 4)

    def at(t):
        t = np.mod(t, cum[-1])
        i = np.clip(np.searchsorted(cum, t, side="right") - 1, 0, len(ring) - 1)
        f = (t - cum[i]) / seg[i]
        return ring[i] + f[:, None] * (ring[(i + 1) % len(ring)] - ring[i])

    a = ring - at(cum[:-1] - s)
    b = at(cum[:-1] + s) - ring
    return np.abs(libm.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=1)))


def ring_corners(ring: np.ndarray, h: float, thr: float) -> np.ndarray:
    """(k,) bool: the corners of a closed ring (k, 2) at spacing ``h``: vertices
    turning by more than ``thr`` radians both between their own two edges and at
    the scale of the mesh (:func:`scale_turning` at ``h / 2``), at most one in any
    arc of length ``h`` (the sharpest first when two are closer than ``h``).

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([(0, 0), (0.5, 0), (1, 0), (1, 1), (0, 1)], dtype=float)
    >>> ring_corners(square, 0.2, np.radians(30)).tolist()
    [True, False, True, True, True]
    """
    a = np.roll(ring, 1, axis=0) - ring
    b = np.roll(ring, -1, axis=0) - ring
    own = np.pi - np.abs(libm.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=1)))
    wide = scale_turning(ring, h / 2)
    cand = np.flatnonzero((own > thr) & (wide > thr))
    out = np.zeros(len(ring), dtype=bool)
    if not len(cand):
        return out
    taken = np.empty((0, 2))
    for i in cand[np.lexsort((cand, -np.minimum(own, wide)[cand]))]:
        if not len(taken) or np.hypot(*(taken - ring[i]).T).min() >= h:
            taken = np.vstack([taken, ring[i]])
            out[i] = True
    return out
