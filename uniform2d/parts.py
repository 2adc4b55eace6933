"""Parts meshed apart and stitched on shared points: exact counts, conforming seams.

The machinery behind any mesh made of parts that meet on seams sampled once:
the surface layer's atlas of charts (:mod:`surface.atlas`) and partitioned
planar meshes.  Each part is a polygon whose boundary points on a seam are
*shared* points, numbered once for the whole mesh, and whose other points are
its own.  Because a seam's points are fixed vertices of both parts that meet
on it, the stitched mesh is conforming by construction; nothing is matched
afterwards.

- :func:`allocate` splits a count over the parts (so the whole has exactly n
  points);
- :func:`map_parts` meshes the parts, here, in local processes or on a Dask
  cluster, with the same results in the same order whichever;
- :func:`stitch` numbers the parts' points globally and joins their triangles.
"""

from __future__ import annotations

import numpy as np

from ._parallel import ordered_map
from .errors import InternalError, InvalidArgumentError

__all__ = ["allocate", "map_parts", "stitch"]


def allocate(weights, total: int) -> np.ndarray:
    """Split ``total`` into integers proportional to ``weights`` (largest remainder).

    Parameters
    ----------
    weights : (K,) array_like of float
        Non-negative, not all zero.
    total : int
        Non-negative.

    Returns
    -------
    (K,) int64
        Summing to ``total`` exactly; ties in the remainders go to the lower index.

    Examples
    --------
    >>> allocate([1.0, 1.0, 2.0], 10).tolist()
    [3, 2, 5]
    >>> allocate([0.0, 3.0], 4).tolist()
    [0, 4]
    """
    w = np.asarray(weights, dtype=np.float64)
    if w.ndim != 1 or not len(w) or not np.isfinite(w).all() or (w < 0).any() or not w.sum() > 0:
        raise InvalidArgumentError("weights must be a non-empty list of non-negative numbers, not all 0")
    if int(total) != total or total < 0:
        raise InvalidArgumentError(f"total must be a non-negative integer, got {total!r}")
    w = w / w.max()  # a sum of at least 1: subnormal weights would overflow the ratio
    exact = w * (int(total) / w.sum())
    out = np.floor(exact).astype(np.int64)
    rest = int(total) - int(out.sum())
    order = np.lexsort((np.arange(len(w)), -(exact - out)))
    out[order[:rest]] += 1
    return out


def map_parts(fn, parts, *, jobs: int = 1, scheduler=None) -> list:
    """``[fn(part) for part in parts]``, in local processes or on a Dask cluster.

    Parameters
    ----------
    fn : callable
        A module-level function (workers import it by name) of one part.
    parts : sequence
        Picklable descriptions of the parts.
    jobs : int
        Local worker processes (1: here, serially).
    scheduler : str or distributed.Client, optional
        A Dask scheduler's address or a connected client; overrides ``jobs``.

    Returns
    -------
    list
        In the order of ``parts``, whatever order they finished in: the stitched
        mesh is the same bytes whichever way the parts ran.

    Examples
    --------
    >>> map_parts(abs, [-2, 3, -1])
    [2, 3, 1]
    """
    return list(ordered_map(fn, parts, jobs=jobs, scheduler=scheduler))


def stitch(shared, parts):
    """One mesh from parts that share points.

    Parameters
    ----------
    shared : (S, d) float64
        The shared points (seam points), numbered 0..S-1 in the result.
    parts : sequence of (index, points, triangles)
        Per part: ``index`` (K,) int64, the shared number of each of the part's
        first K points; ``points`` (k, d) float64, its own points (its local
        points K..K+k-1); ``triangles`` (m, 3) int64 in local numbering.

    Returns
    -------
    points : (S + sum k, d) float64
        Shared points first, then each part's own points in part order.
    triangles : (sum m, 3) int64

    Examples
    --------
    Two triangles sharing the edge (0, 1) of a square, each with one own point
    numbered locally 2:

    >>> import numpy as np
    >>> shared = np.array([[0.0, 0.0], [1.0, 1.0]])
    >>> a = (np.array([0, 1]), np.array([[1.0, 0.0]]), np.array([[0, 2, 1]]))
    >>> b = (np.array([1, 0]), np.array([[0.0, 1.0]]), np.array([[0, 2, 1]]))
    >>> P, T = stitch(shared, [a, b])
    >>> P.tolist(), T.tolist()
    ([[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]], [[0, 2, 1], [1, 3, 0]])
    """
    shared = np.asarray(shared, dtype=np.float64)
    pts, tris = [shared], []
    offset = len(shared)
    for index, own, T in parts:
        index = np.asarray(index, dtype=np.int64)
        own = np.asarray(own, dtype=np.float64).reshape(-1, shared.shape[1])
        T = np.asarray(T, dtype=np.int64)
        K = len(index)
        if T.size and (T.min() < 0 or T.max() >= K + len(own)):
            raise InternalError("a part's triangle refers to a point it does not have (a bug: please report it)")
        glob = np.concatenate([index, offset + np.arange(len(own), dtype=np.int64)])
        tris.append(glob[T])
        pts.append(own)
        offset += len(own)
    T = np.concatenate(tris) if tris else np.zeros((0, 3), dtype=np.int64)
    return np.concatenate(pts), T
