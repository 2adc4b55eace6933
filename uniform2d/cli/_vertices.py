"""``--vertices N``: the Steiner count n that gives N mesh vertices in all."""

from __future__ import annotations

from ..errors import InsufficientPointsError, InvalidArgumentError


def steiner_for_vertices(polygon, total: int) -> int:
    """The Steiner count giving ``total`` mesh vertices: ``total - |V|``."""
    nv = len(polygon.vertices)
    if total <= nv:
        raise InvalidArgumentError(
            f"--vertices {total} leaves no point to add: the polygon has {nv} vertices of its "
            f"own (ring vertices, segment ends and fixed points); give --vertices above {nv}, "
            "or -n for the points to add")
    return total - nv


def steiner_for_vertices_resampled(polygon, total: int, *, size, resample: float,
                                   corner_angle=None, resample_corners=None) -> int:
    """The Steiner count giving ``total`` vertices when the rings are resampled.

    A resampled mesh has n + (input vertices kept) vertices, and which input
    vertices stay depends on the spacing, i.e. on n: n = total - kept(n) is
    found by iterating the resampling alone (it settles in a step or two).
    """
    from ..uniform import resampled_outline

    extra = {} if corner_angle is None else {"corner_angle": corner_angle}
    if resample_corners is not None:
        extra["resample_corners"] = resample_corners
    # a dense outline may have more vertices than asked for: most go
    n = max(1, total - len(polygon.vertices))
    seen = set()
    while n not in seen:
        seen.add(n)
        res, _ = resampled_outline(polygon, n, size=size, resample=resample, **extra)
        following = total - res.n_kept
        if following == n:
            return n
        if following < 1:
            raise InsufficientPointsError(
                f"--vertices {total} leaves no point to add once the outline is resampled "
                f"({res.n_kept} input vertices kept); give a larger --vertices")
        n = following
    raise InvalidArgumentError(
        f"--vertices {total} with --resample: the input vertices the resampling keeps change "
        "with the count and no count gives exactly this total; give -n (the points to add) "
        "or a slightly different --vertices")
