"""What a request needs from the machine, checked before any work starts."""

from __future__ import annotations

import os

from .errors import TooManyPointsError

__all__ = ["BYTES_PER_POINT", "physical_memory", "check_point_count"]

#: A lower bound on the peak memory per mesh vertex of every meshing path (the
#: points, triangles, constrained triangulation, heap and optimiser arrays
#: together); a request above ``physical_memory() / BYTES_PER_POINT`` cannot
#: finish, whatever else runs on the machine.
BYTES_PER_POINT = 300


def physical_memory() -> int | None:
    """Bytes of physical memory of this machine (None where the OS does not say)."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def _gigabytes(nbytes: float) -> str:
    return f"{nbytes / 2**30:.3g} GiB"


def check_point_count(n_points: int, what: str = "points") -> None:
    """Raise :class:`~uniform2d.errors.TooManyPointsError` (a ``MemoryError``) if a
    mesh with ``n_points`` vertices cannot fit in this machine's memory.

    ``what`` names the request in the message (e.g. ``"n = 1000000000"``).
    """
    total = physical_memory()
    need = int(n_points) * BYTES_PER_POINT
    if total is not None and need > total:
        raise TooManyPointsError(
            f"{what} needs at least {_gigabytes(need)} of memory, more than the "
            f"{_gigabytes(total)} this machine has"
        )
