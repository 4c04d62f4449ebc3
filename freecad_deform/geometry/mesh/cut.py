"""Cutting a closed triangle mesh at a plane (Wu & Ilies's split), shared by the stretch
and sweep kernels: the cut, and the seam where the two sides meet.

Meshes are vertices (N, 3) float and triangles (M, 3) int, counter-clockwise seen from
outside; s is the signed distance to the plane, positive on the side that moves.
"""
from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ..sweep.planes import signed_distance, unit_normal


def cut(vertices, triangles, origin, normal, eps=1e-9):
    """Split every triangle that straddles the plane so each lies on one side of it.

    Vertices with |s| <= eps are snapped onto the plane; each cut edge gets one new
    vertex on the plane, shared by both its triangles, so a closed 2-manifold stays one.
    Original vertices keep their indices (new ones are appended) and triangles their
    orientation; the quadrilateral left by a cut is split along its shorter diagonal.
    """
    V, T = arrays(vertices, triangles)
    V, T, _ = cut_arrays(V, T, np.asarray(origin, float), unit_normal(normal), eps)
    return V, T


def arrays(vertices, triangles, copy=True):
    """(N, 3) float and (M, 3) int64 arrays of the input: fresh copies, or the input itself
    where it is such an array already (copy=False, for a kernel that writes only to new
    arrays)."""
    make = np.array if copy else np.asarray
    return (make(vertices, dtype=float).reshape(-1, 3),
            make(triangles, dtype=np.int64).reshape(-1, 3))


def _directed(T):
    """The directed edges of the triangles, T[:, j] -> T[:, j+1], flattened row by row."""
    return T.ravel(), np.roll(T, -1, axis=1).ravel()


class Split(NamedTuple):
    """A cut at a plane before it is assembled (see `split`)."""
    s: np.ndarray        # (N,) signed distances, exactly 0 on the snapped vertices
    snap: np.ndarray     # the vertices within eps of the plane
    offset: np.ndarray   # their distances before the snap: each moves by -offset * n
    code: np.ndarray     # (N,) uint8 per vertex: 1 beyond the plane, 2 below, 4 on it
    side: np.ndarray     # (M,) uint8 per triangle: the OR of its corners' codes (3 & side
                         # == 3: the triangle is cut)
    P: np.ndarray        # (K, 3) the new vertices on the plane, numbered N + k
    pieces: np.ndarray   # (L, 3) the cut triangles' pieces, none flat, in that numbering


def split(V, T, o, n, eps, s):
    """The cut of `cut_arrays` without building its result, for the kernels that lay out
    their own: one gather of a code per corner classifies every triangle; only the cut
    ones are looked at further. `s` (the signed distances) is written in place."""
    N = len(V)
    snap = np.flatnonzero(np.abs(s) <= eps)
    offset = s[snap]
    s[snap] = 0.0
    code = (s > 0).view(np.uint8) | ((s < 0).view(np.uint8) << 1)
    code[snap] = 4
    c = code.take(T)
    side = c[:, 0] | c[:, 1] | c[:, 2]
    rows = np.flatnonzero((side & 3) == 3)
    Ts, cT = T[rows], c[rows] & 3
    cs = (cT | np.roll(cT, -1, axis=1)) == 3                 # edge j: vertex j -> j+1 crosses
    ea, eb = Ts[cs], np.roll(Ts, -1, axis=1)[cs]
    keys, inv = np.unique(np.minimum(ea, eb) * N + np.maximum(ea, eb), return_inverse=True)
    lo, hi = keys // N, keys % N
    t = s[lo] / (s[lo] - s[hi])
    P = V[lo] + t[:, None] * (V[hi] - V[lo])
    P -= ((P - o) @ n)[:, None] * n
    P, inv = _merge_close(P, inv, eps)
    new = np.full(Ts.shape, -1, dtype=np.int64)
    new[cs] = N + inv
    # Rotate each cut triangle to start at its pivot: the lone vertex on one side when
    # two edges cross, else the on-plane vertex opposite the one crossing edge.
    two = cs.sum(axis=1) == 2
    pivot = np.where(two, np.argmax(cs & np.roll(cs, 1, axis=1), axis=1),
                     (np.argmax(cs, axis=1) + 2) % 3)
    turn = (pivot[:, None] + np.arange(3)) % 3
    a, b, c = np.take_along_axis(Ts, turn, axis=1).T
    pab, pbc, pca = np.take_along_axis(new, turn, axis=1).T
    a2, b2, c2, p, q = a[two], b[two], c[two], pab[two], pca[two]
    pp, pq = P[p - N], P[q - N]                   # b2 and c2 are off the plane: not snapped
    short = np.linalg.norm(pp - V[c2], axis=1) <= np.linalg.norm(V[b2] - pq, axis=1)
    quad1 = np.where(short[:, None], np.stack([p, b2, c2], 1), np.stack([p, b2, q], 1))
    quad2 = np.where(short[:, None], np.stack([p, c2, q], 1), np.stack([b2, c2, q], 1))
    one = ~two
    pieces = np.concatenate([np.stack([a2, p, q], 1), quad1, quad2,
                             np.stack([a[one], b[one], pbc[one]], 1),
                             np.stack([a[one], pbc[one], c[one]], 1)])
    return Split(s, snap, offset, code, side, P, without_flat(pieces))


def placed(V, sp, n, extra=0):
    """(N + K + extra, 3): the vertices with the snapped ones on the plane, then the cut's
    new ones, then `extra` rows left for the caller."""
    N, K = len(V), len(sp.P)
    W = np.empty((N + K + extra, 3))
    W[:N] = V
    W[sp.snap] -= sp.offset[:, None] * n
    W[N:N + K] = sp.P
    return W


def cut_arrays(V, T, o, n, eps):
    """`cut` on clean arrays (see `arrays`); also returns s, exactly 0 for the vertices on
    the plane. The input's own triangles are kept as they are, in their order, followed by
    the cut ones' pieces."""
    sp = split(V, T, o, n, eps, signed_distance(V, o, n))
    kept = np.flatnonzero((sp.side & 3) != 3)
    T = np.concatenate([T.take(kept, axis=0), sp.pieces])
    return placed(V, sp, n), T, np.concatenate([sp.s, np.zeros(len(sp.P))])


def without_flat(T):
    """T without its triangles that repeat a vertex (a copy only when there are some)."""
    flat = (T[:, 0] == T[:, 1]) | (T[:, 1] == T[:, 2]) | (T[:, 2] == T[:, 0])
    return np.compress(~flat, T, axis=0) if flat.any() else T


def _merge_close(P, inv, eps):
    """New points closer than eps to each other become one (the first of each cluster).

    A sliver triangle crossing the plane near its sharp tip puts its two cut points
    almost together; stored apart they would make a needle facet (and in float32 one
    point). Merged, the two facets on that tiny edge vanish (an edge collapse on the
    plane) and the mesh stays a closed 2-manifold."""
    if len(P) < 2:
        return P, inv
    pairs = cKDTree(P).query_pairs(eps, output_type="ndarray")
    if not len(pairs):
        return P, inv
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(P), len(P)))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, len(P))
    np.minimum.at(first, label, np.arange(len(P)))
    keep, cluster = np.unique(first[label], return_inverse=True)
    return P[keep], cluster.reshape(-1)[inv]


def seam(part, other, on):
    """Directed edges (row, a, b) of `part` between vertices `on` the plane whose reverse
    b -> a is an edge of `other`: where the two triangle sets meet."""
    N = len(on)
    rows = _two_on(part, on)                  # only triangles with an edge on the plane
    a, b = _directed(part[rows])
    oa, ob = _directed(other[_two_on(other, on)])
    mine = np.flatnonzero(on[a] & on[b])
    theirs = on[oa] & on[ob]
    hit = mine[np.isin(b[mine] * N + a[mine], oa[theirs] * N + ob[theirs])]
    return rows[hit // 3], a[hit], b[hit]


def _two_on(T, on):
    """Rows of T with at least two vertices `on`."""
    k = on.view(np.int8).take(T)
    return np.flatnonzero(k[:, 0] + k[:, 1] + k[:, 2] >= 2)
