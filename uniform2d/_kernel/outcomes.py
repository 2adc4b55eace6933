"""Names for the integers the compiled loops return, decoded on the Python side.

Compiled code reports failure as a negative integer (numba raises no typed
exceptions cheaply); this module names those values once so that the callers
decode them by name, not by arithmetic repeated at every call site.

* :func:`uniform2d._kernel.insert.run` returns the number of points inserted,
  or ``code - RUN_STRIDE * j`` when step j failed with ``code`` (one of
  :data:`RUN_CODES`).
* :func:`uniform2d._kernel.cavity.insert_sites` returns a non-negative count, or
  ``-(k + 1)`` when site k (position in its index array) could not be inserted.
"""

from __future__ import annotations

__all__ = [
    "ERR_EMPTY", "ERR_LOCATE", "ERR_PRECISION", "RUN_CODES", "RUN_STRIDE", "run_failure",
    "failed_site",
]

ERR_EMPTY = -10  # no candidate left (cannot happen for a valid polygon)
ERR_LOCATE = -11  # a circumcentre could not be located (cannot happen)
ERR_PRECISION = -12  # no point the caller's coordinates hold there can be inserted

#: Multiplier of the failing step in :func:`uniform2d._kernel.insert.run`'s status.
RUN_STRIDE = 100
#: What each failure code of :func:`uniform2d._kernel.insert.run` means.
RUN_CODES = {
    ERR_EMPTY: "no candidate left",
    ERR_LOCATE: "a circumcentre could not be located",
    ERR_PRECISION: "the caller's coordinates cannot hold a point there",
}


def run_failure(status: int) -> tuple[int, str]:
    """(failing step j, what failed) from a negative status of ``insert.run``."""
    j = -status // RUN_STRIDE
    code = status + RUN_STRIDE * j
    return j, RUN_CODES.get(code, f"code {code}")


def failed_site(status: int) -> int:
    """Position of the site that failed, from a negative status of ``cdt.insert_sites``."""
    return -status - 1
