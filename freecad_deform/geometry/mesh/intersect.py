"""Self-intersection of a triangle mesh whose vertices moved: the pairs of triangles, one
of them moved, that share no vertex and cross (an edge of one through the other).

Candidates are the pairs whose bounding spheres meet (k-d trees of triangle centres per
size class), filtered by bounding boxes, then tested
exactly with segment-triangle tests (coplanar touching and edges that only touch are not
counted).
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

CHUNK = 200000   # candidate pairs tested at once (memory)


def _sphere_candidates(X, T, moved):
    """Pairs (i, j), i < j, one of them moved, sharing no vertex, whose bounding spheres
    (about the centroid) meet: k-d trees per size class of the triangles (radii binned by
    factors of 2), each pair of classes searched within the sum of their largest radii.
    Pairs whose boxes are apart, or where one triangle's sphere, then its corners, lie
    wholly on one side of the other's plane (beyond a relative 1e-6), cannot cross or touch
    and are left out (a large flat facet's sphere meets thousands that its plane does not,
    a needle's sphere thousands that its box does not)."""
    tri = X[T]
    centre = tri.mean(axis=1)
    radius = np.linalg.norm(tri - centre[:, None], axis=2).max(axis=1)
    movers = np.nonzero(moved)[0]
    if len(movers) == 0:
        return np.zeros((0, 2), np.int64)
    normal = _unit_normals(tri)
    offset = np.einsum("ij,ij->i", normal, centre)
    shape = (tri, tri.min(axis=1), tri.max(axis=1), normal, offset)

    def sphere_apart(i, j):               # j's sphere wholly on one side of i's plane
        d = np.abs(np.einsum("ij,ij->i", centre[j], normal[i]) - offset[i])
        return d > radius[j] + 2e-6 * (radius[i] + radius[j])

    level = np.floor(np.log2(np.maximum(radius, 1e-300) / max(radius.max(), 1e-300)))
    level = np.maximum(level, -40)
    order = np.argsort(level, kind="stable")
    _, first = np.unique(level.take(order), return_index=True)
    classes = np.split(order, first[1:])
    largest = [float(radius.take(c).max()) for c in classes]
    trees = [cKDTree(centre.take(c, axis=0)) for c in classes]
    pairs = []
    for ca in classes:
        a = ca[moved.take(ca)]
        if len(a) == 0:
            continue
        tree_a = cKDTree(centre.take(a, axis=0))
        reach = float(radius.take(a).max())
        for cb, tree_b, big in zip(classes, trees, largest):
            found = tree_a.sparse_distance_matrix(tree_b, reach + big, output_type="ndarray")
            i, j = a.take(found["i"]), cb.take(found["j"])
            keep = found["v"] <= radius.take(i) + radius.take(j)
            i, j = i[keep], j[keep]
            keep = i != j
            i, j = i[keep], j[keep]
            keep = ~(sphere_apart(i, j) | sphere_apart(j, i))
            i, j = i[keep], j[keep]
            i, j = _may_meet(i, j, 2e-6 * (radius.take(i) + radius.take(j)), *shape)
            pairs.append(np.minimum(i, j) * len(T) + np.maximum(i, j))
    key = np.unique(np.concatenate(pairs))
    p = np.column_stack([key // len(T), key % len(T)])
    shared = (T[p[:, 0], :, None] == T[p[:, 1], None, :]).any(axis=(1, 2))
    return p[~shared]


SWEEP_PAIRS = 256  # _candidates sweeps along x when that gives at most this many pairs a
                   # triangle (or 4 x 10^6)
SWEEP_CHUNK = 10 ** 6   # pairs along x filtered at once (memory)


def _candidates(X, T, moved):
    """Pairs (i, j), i < j, one of them moved, sharing no vertex, that may cross or touch:
    those whose extents along x overlap (a sort along x) when that makes at most SWEEP_PAIRS
    pairs a triangle (or 4 x 10^6), else _sphere_candidates; both then leave out the pairs
    whose boxes are apart or where one lies wholly on one side of the other's plane. Long
    thin triangles (the pieces of a mesh cut into slabs across x, sheared by a twist) have
    large spheres: the notched cube twisted at Samples 256 and split made tens of millions
    of sphere pairs (22 s) and 4.5 million along x."""
    X, T = np.asarray(X, float), np.asarray(T, np.int64)
    movers = np.flatnonzero(moved)
    if len(movers) == 0:
        return np.zeros((0, 2), np.int64)
    tri = X[T]
    low, high = tri.min(axis=1), tri.max(axis=1)
    order = np.argsort(low[:, 0], kind="stable")
    start = low.take(order, axis=0)[:, 0]
    a0 = np.searchsorted(start, low.take(movers, axis=0)[:, 0], "left")
    a1 = np.searchsorted(start, high.take(movers, axis=0)[:, 0], "right")
    mo = movers[np.argsort(low.take(movers, axis=0)[:, 0], kind="stable")]
    mstart = low.take(mo, axis=0)[:, 0]
    b0 = np.searchsorted(mstart, low[:, 0], "right")      # (equal starts counted once,
    b1 = np.searchsorted(mstart, high[:, 0], "right")     # in the first set)
    count = int((a1 - a0).sum() + (b1 - b0).sum())
    if count > max(SWEEP_PAIRS * len(T), 4 * 10 ** 6):
        return _sphere_candidates(X, T, moved)
    size = np.linalg.norm(high - low, axis=1)
    normal = _unit_normals(tri)
    shape = (tri, low, high, normal, np.einsum("ij,ij->i", tri[:, 0], normal))

    def kept(i, j):                       # the pair keys that may cross or touch
        keep = i != j
        i, j = i[keep], j[keep]
        i, j = _may_meet(i, j, 1e-6 * (size.take(i) + size.take(j)), *shape)
        return np.minimum(i, j) * len(T) + np.maximum(i, j)

    keys = []
    for who, first, last, among, rows in ((movers, a0, a1, order, None),
                                          (None, b0, b1, mo, np.arange(len(T)))):
        n = last - first
        ends = np.cumsum(n)
        cuts = np.searchsorted(ends, np.arange(SWEEP_CHUNK, int(ends[-1]) if len(ends) else 0,
                                               SWEEP_CHUNK), "right")
        for lo_, hi_ in zip(np.r_[0, cuts], np.r_[cuts, len(n)]):
            k = slice(int(lo_), int(hi_))
            this = among.take(_spans(first[k], last[k]))
            owner = np.repeat((movers if who is not None else rows)[k], n[k])
            keys.append(kept(owner, this))
    key = np.unique(np.concatenate(keys))
    p = np.column_stack([key // len(T), key % len(T)])
    shared = (T[p[:, 0], :, None] == T[p[:, 1], None, :]).any(axis=(1, 2))
    return p[~shared]


def _unit_normals(tri):
    """Unit normals of triangles (k, 3, 3) (zero for a triangle of no area)."""
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    return normal


def _may_meet(i, j, slack, tri, low, high, normal, offset):
    """The pairs (i, j) of triangles that may cross or touch: their boxes (low, high)
    meet, and neither lies wholly on one side of the other's plane (normal . x = offset),
    each within its pair's `slack`."""
    keep = ~((low.take(i, axis=0) > high.take(j, axis=0) + slack[:, None])
             | (low.take(j, axis=0) > high.take(i, axis=0) + slack[:, None])).any(axis=1)
    i, j, slack = i[keep], j[keep], slack[keep]
    for turn in range(2):                 # j's corners all on one side of i's plane, then
        one, other = (i, j) if turn == 0 else (j, i)          # i's on one side of j's
        d = np.einsum("ikl,il->ik", tri.take(other, axis=0), normal.take(one, axis=0))
        d -= offset.take(one)[:, None]
        keep = ~((d.min(axis=1) > slack) | (d.max(axis=1) < -slack))
        i, j, slack = i[keep], j[keep], slack[keep]
    return i, j


def _spans(first, last):
    """The integers first[k] <= x < last[k] for every k, in order."""
    n = last - first
    total = int(n.sum())
    if not total:
        return np.zeros(0, np.int64)
    base = np.repeat(first - np.cumsum(n) + n, n)
    return base + np.arange(total)


TOUCH = 1e-6   # relative: what counts as touching in the Base


def _segments_cross(a, b, tri, touch=False):
    """Segments a-b (K,3) that pass through the interior of triangles tri (K,3,3); with
    `touch`, also those that come within TOUCH (relative) of it or lie in its plane."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    d = b - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    scale = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(d, axis=1)
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)
    det = np.where(ok, det, 1.0)
    s = a - tri[:, 0]
    u = np.einsum("ij,ij->i", s, h) / det
    q = np.cross(s, e1)
    v = np.einsum("ij,ij->i", d, q) / det
    t = np.einsum("ij,ij->i", e2, q) / det
    eps = -TOUCH if touch else 1e-12
    hit = ok & (u > eps) & (v > eps) & (u + v < 1 - eps) & (t > eps) & (t < 1 - eps)
    if touch:
        n = np.cross(e1, e2)
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        size = np.maximum(np.maximum(np.linalg.norm(e1, axis=1), np.linalg.norm(e2, axis=1)),
                          np.linalg.norm(d, axis=1))
        off = np.maximum(np.abs(np.einsum("ij,ij->i", s, n)),
                         np.abs(np.einsum("ij,ij->i", b - tri[:, 0], n)))
        hit |= ~ok & (off <= TOUCH * size)
    return hit


def crossing(X, T, pairs, touch=False):
    """Boolean (P,): the triangles of each pair cross (with `touch`: or touch)."""
    out = np.zeros(len(pairs), bool)
    for i in range(0, len(pairs), CHUNK):
        p = pairs[i:i + CHUNK]
        A, B = X[T[p[:, 0]]], X[T[p[:, 1]]]
        lo = np.maximum(A.min(axis=1), B.min(axis=1))
        hi = np.minimum(A.max(axis=1), B.max(axis=1))
        slack = TOUCH * np.ptp(A, axis=1).max(axis=1) if touch else 0.0
        box = np.all(lo <= hi + np.reshape(slack, (-1, 1)), axis=1)
        hit = np.zeros(len(p), bool)
        A, B = A[box], B[box]
        sub = np.zeros(len(A), bool)
        for one, other in ((A, B), (B, A)):
            for k in range(3):
                sub |= _segments_cross(one[:, k], one[:, (k + 1) % 3], other, touch)
        hit[box] = sub
        out[i:i + CHUNK] = hit
    return out


def pieces(T, n):
    """Connected piece (by shared vertices) of each triangle."""
    e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]]])
    _, label = connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])),
                                               shape=(n, n)), directed=False)
    return label[T[:, 0]]


def new_intersections(X0, X1, T, moved):
    """Number of triangle pairs (one of them moved) that cross in X1, between pieces of
    the mesh (or within one) that neither crossed nor touched anywhere in X0: pieces that
    already lie against or through each other in the Base (an assembly of shells, a
    scan's overlaps) stay allowed to."""
    pairs = _candidates(X1, T, moved)
    if len(pairs) == 0:
        return 0
    now = crossing(X1, T, pairs)
    if not now.any():
        return 0
    piece = pieces(T, len(X0))
    before = _candidates(X0, T, moved)
    before = before[crossing(X0, T, before, touch=True)]
    k = piece.max() + 1
    exempt = np.unique(np.sort(piece[before], axis=1) @ [k, 1])
    key = np.sort(piece[pairs[now]], axis=1) @ [k, 1]
    return int(np.count_nonzero(~np.isin(key, exempt)))


def self_crossings(X, T, among=None):
    """Number of pairs of triangles sharing no vertex that cross (an edge of one through the
    interior of the other), over the whole mesh, or those with one of them `among` (a
    mask of the triangles)."""
    X, T = np.asarray(X, float).reshape(-1, 3), np.asarray(T, np.int64).reshape(-1, 3)
    among = np.ones(len(T), bool) if among is None else np.asarray(among, bool)
    if not among.any():
        return 0
    pairs = _candidates(X, T, among)
    return int(np.count_nonzero(crossing(X, T, pairs))) if len(pairs) else 0
