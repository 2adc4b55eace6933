"""Chains of a graph of mesh edges: the walk shared by feature lines and seams."""

from __future__ import annotations

__all__ = ["walk_chains"]


def walk_chains(adj: dict, nodes: set, turns=None) -> list[list[int]]:
    """Split a graph of edges into chains between nodes, closed cycles last.

    Parameters
    ----------
    adj : dict int -> list of int
        Neighbours of every vertex of the graph.
    nodes : set of int
        Vertices where chains end; vertices added here (in place) as chains end
        at them: where ``turns`` said so, and the first vertex of every cycle
        that has no node (its smallest).
    turns : callable, optional
        ``turns(a, v, b)``: whether a chain coming from ``a`` must end at ``v``
        rather than go on to ``b`` (a corner).

    Returns
    -------
    list of list of int
        Every edge in exactly one chain; a closed chain ends at its start.

    Examples
    --------
    >>> adj = {0: [1], 1: [0, 2], 2: [1, 3, 4], 3: [2], 4: [2], 7: [8, 9], 8: [7, 9], 9: [7, 8]}
    >>> walk_chains(adj, {0, 2, 3, 4})
    [[0, 1, 2], [2, 3], [2, 4], [7, 8, 9, 7]]
    """
    used: set = set()
    out = []

    def follow(a, b):
        chain = [a, b]
        used.add((min(a, b), max(a, b)))
        while chain[-1] not in nodes:
            v = chain[-1]
            step = [w for w in adj[v] if (min(v, w), max(v, w)) not in used]
            if not step:
                break
            if turns is not None and turns(chain[-2], v, step[0]):
                nodes.add(v)
                break
            used.add((min(v, step[0]), max(v, step[0])))
            chain.append(step[0])
        return chain

    for v in sorted(nodes):
        for w in sorted(adj[v]):
            if (min(v, w), max(v, w)) not in used:
                out.append(follow(v, w))
    for v in sorted(adj):
        for w in sorted(adj[v]):
            if (min(v, w), max(v, w)) not in used:
                nodes.add(v)
                out.append(follow(v, w))
    return out
