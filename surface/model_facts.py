"""The topology and validity of any triangle mesh, with numpy and scipy alone.

Independent of the remeshing code (it shares nothing with :mod:`surface.checks`
or :class:`surface.Model`), so tests and benchmarks can hold the remesh to it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse
import scipy.sparse.csgraph

from uniform2d.errors import InvalidArgumentError

__all__ = ["model_facts"]


def _edge_table(F):
    """Directed edges (3M, 2), undirected edge id of each (3M,), its face count (E,)."""
    D = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    _, inv, cnt = np.unique(np.sort(D, axis=1), axis=0, return_inverse=True, return_counts=True)
    return D, inv.ravel(), cnt


def _labels(n: int, edges) -> np.ndarray:
    """Connected-component label of each of n nodes joined by ``edges`` (K, 2)."""
    A = scipy.sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    return scipy.sparse.csgraph.connected_components(A, directed=False)[1]


def _signed_volumes(V, F, comp, k: int) -> np.ndarray:
    """Signed volume enclosed by each of the k components' faces (divergence theorem)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    return np.bincount(comp, weights=vol, minlength=k)


def _mesh_arrays(V, F):
    """(V float64 (N, 3), F int64 (M, 3)) or InvalidArgumentError saying what is wrong."""
    V, F = np.asarray(V), np.asarray(F)
    if V.ndim != 2 or V.shape[1] != 3 or not np.issubdtype(V.dtype, np.number):
        raise InvalidArgumentError(
            f"vertices must be an (N, 3) array of numbers, got shape {V.shape}"
        )
    if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0 or not np.issubdtype(F.dtype, np.integer):
        raise InvalidArgumentError(
            f"faces must be a non-empty (M, 3) array of vertex indices, got shape {F.shape}"
        )
    if F.min() < 0 or F.max() >= len(V):
        raise InvalidArgumentError(
            f"face indices must be in [0, {len(V) - 1}] (indices of the vertices given)"
        )
    return V.astype(np.float64), F.astype(np.int64)


def model_facts(V, F) -> dict:
    """Topology and validity of a triangle mesh, with numpy and scipy alone.

    Parameters
    ----------
    V : (N, 3) array
    F : (M, 3) int array

    Returns
    -------
    dict
        ``components`` (int, joined through shared vertices), ``euler`` (V - E + F
        of the used vertices), ``boundary_loops`` (int), ``watertight`` (every
        edge in exactly two faces), ``manifold_edges`` (no edge in more than two
        faces), ``oriented`` (every edge in two faces is used once each way),
        ``degenerate_faces`` (faces with a repeated vertex or zero area),
        ``unused_vertices``, and per component (in order of their first face):
        ``euler_per_component``, ``boundary_loops_per_component``, ``genus``
        (``(2 - euler - loops) / 2``, meaningful for oriented manifolds) and
        ``volume`` (signed enclosed volume, positive when the normals point out;
        meaningful for closed components).

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> f = model_facts(V, F)
    >>> f["euler"], f["genus"], f["watertight"], f["oriented"], round(f["volume"][0], 4)
    (2, [0], True, True, 0.1667)
    >>> model_facts(V, F[1:])["boundary_loops"]
    1
    """
    V, F = _mesh_arrays(V, F)
    D, eid, cnt = _edge_table(F)
    vlab = _labels(len(V), D)
    order = np.unique(vlab[F[:, 0]], return_index=True)[1]
    names = vlab[F[order, 0]]  # component labels in order of their first face
    comp_of_label = np.full(vlab.max() + 1, -1)
    comp_of_label[names] = np.arange(len(names))
    fcomp = comp_of_label[vlab[F[:, 0]]]
    k = len(names)
    used = np.unique(F)
    n_v = np.bincount(comp_of_label[vlab[used]], minlength=k)
    first = np.unique(eid, return_index=True)[1]
    n_e = np.bincount(fcomp[first % len(F)], minlength=k)
    n_f = np.bincount(fcomp, minlength=k)
    bnd = D[np.isin(eid, np.flatnonzero(cnt == 1))]
    blab = _labels(len(V), bnd)
    loops = np.zeros(k, dtype=np.int64)
    for lab in np.unique(blab[bnd[:, 0]]) if len(bnd) else []:
        loops[comp_of_label[vlab[bnd[blab[bnd[:, 0]] == lab][0, 0]]]] += 1
    chi = n_v - n_e + n_f
    pair = cnt[eid] == 2
    fwd = np.bincount(eid[pair & (D[:, 0] < D[:, 1])], minlength=len(cnt))
    area2 = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    repeated = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    return {
        "components": int(k),
        "euler": int(chi.sum()),
        "boundary_loops": int(loops.sum()),
        "watertight": bool(np.all(cnt == 2)),
        "manifold_edges": bool(np.all(cnt <= 2)),
        "oriented": bool(np.all(fwd[cnt == 2] == 1)),
        "degenerate_faces": int(np.count_nonzero(repeated | (area2 <= 1e-14 * area2.max()))),
        "unused_vertices": int(len(V) - len(used)),
        "euler_per_component": chi.astype(int).tolist(),
        "boundary_loops_per_component": loops.astype(int).tolist(),
        "genus": [int(g) for g in (2 - chi - loops) // 2],
        "volume": _signed_volumes(V, F, fcomp, k).tolist(),
    }
