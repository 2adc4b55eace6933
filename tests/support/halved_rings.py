"""The rings a resampled mesh was made of: the resampled polygon, with the ring
edges uniform_mesh halved (uniform2d.ring_split) as midpoints inserted."""

from __future__ import annotations

import numpy as np


def assert_halved_from(mesh, polygon) -> None:
    """Assert ``mesh.polygon``'s rings are ``polygon``'s with exactly
    ``mesh.info["resample"]["halved_edges"]`` ring edges halved: dropping the
    mesh polygon's ring vertices that are no vertex of ``polygon`` leaves
    ``polygon``'s ring vertices bit for bit, and each dropped one is the exact
    midpoint of its two neighbours."""
    halved = mesh.info["resample"]["halved_edges"]
    q = mesh.polygon
    assert len(q.rings) == len(polygon.rings)
    for ring, base in zip(q.rings, polygon.rings):
        key = ring[:, 0] + 1j * ring[:, 1]
        old = np.isin(key, base[:, 0] + 1j * base[:, 1])
        assert ring[old].tobytes() == base.tobytes()
        for i in np.flatnonzero(~old):
            a, b = ring[i - 1], ring[(i + 1) % len(ring)]
            assert old[i - 1] and old[(i + 1) % len(ring)]
            assert np.array_equal(ring[i], 0.5 * (a + b))
        halved -= int((~old).sum())
    assert halved == 0
