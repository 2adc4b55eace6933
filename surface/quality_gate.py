"""The last check of every remesh: a result the library's own measures call bad
is refused, never returned as a success.

A remesh's edge ratio (longest over shortest 3-D edge; for a graded size,
the ratio of the largest to the smallest ``q = length / size``) above
:data:`EDGE_RATIO_LIMIT` raises :class:`~surface.errors.RemeshQualityError`.
The limit is far above what the remesh gives where it works (1.5-2.2 on the
bundled patches and whole models) and far below what a failed flattening gives
(a sphere with one face removed, flattened in one piece: 1000 and more).  What
reaches it in practice is an input whose own features are much shorter than
the spacing asked for: a hole, a boundary edge or a gap between creases shorter
than a quarter of the edge length, which the remesh keeps as it is.
"""

from __future__ import annotations

from .errors import RemeshQualityError

__all__ = ["check_quality", "EDGE_RATIO_LIMIT"]

#: The largest edge ratio a remesh may be returned with.
EDGE_RATIO_LIMIT = 4.0


def check_quality(report) -> None:
    """Raise :class:`RemeshQualityError` if ``report``'s edge ratio exceeds the limit.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> check_quality(SimpleNamespace(edges={"ratio": 1.6, "min": 1.0, "max": 1.6},
    ...                               target_size=1.2, n_vertices=100))
    >>> check_quality(SimpleNamespace(edges={"ratio": 9.0, "min": 0.1, "max": 0.9},
    ...                               target_size=0.5, n_vertices=100))
    Traceback (most recent call last):
    ...
    surface.errors.RemeshQualityError: the remesh with 100 vertices has an edge ratio of 9 (limit 4): its shortest edge is 0.1, its longest 0.9, for a target of 0.5; the input has features (holes, boundary edges, gaps between creases) much shorter than the spacing: ask for more vertices (a smaller size) or simplify those features
    """
    e = report.edges
    if "q_ratio" in e:  # a graded size: the ratio of q = length / size
        if not e["q_ratio"] <= EDGE_RATIO_LIMIT:
            raise RemeshQualityError(
                f"the graded remesh with {report.n_vertices} vertices has a ratio of "
                f"length / size of {e['q_ratio']:.3g} between its edges (limit "
                f"{EDGE_RATIO_LIMIT:g}); the size varies faster than the mesh can follow, or the "
                "input has features much shorter than it: ask for more vertices or a smoother size"
            )
        return
    if not e["ratio"] <= EDGE_RATIO_LIMIT:
        raise RemeshQualityError(
            f"the remesh with {report.n_vertices} vertices has an edge ratio of {e['ratio']:.3g} "
            f"(limit {EDGE_RATIO_LIMIT:g}): its shortest edge is {e['min']:.3g}, its longest "
            f"{e['max']:.3g}, for a target of {report.target_size:.3g}; the input has features "
            "(holes, boundary edges, gaps between creases) much shorter than the spacing: ask "
            "for more vertices (a smaller size) or simplify those features"
        )
