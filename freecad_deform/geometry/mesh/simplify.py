"""Region-preserving mesh simplification for the deformation handle (Date & Onosato 2008).

Sections 4.2 and 5.1 of the paper simplify the segmented mesh with VSA; here a constrained
quadric-error half-edge collapse does it instead. The surviving vertex of a collapse keeps
its position, so every simplified vertex is an original vertex (the correspondence v_c is
the identity), and no collapse crosses a region boundary, so each simplified triangle lies
in one region. Meshes are vertices (N, 3) float and consistently oriented triangles (M, 3).
"""
import heapq
import math
from typing import NamedTuple

import numpy as np

from ..vectors import unit

INTERIOR, LINE, CORNER = 0, 1, 2
MAX_TURN_COS = 0.5  # a collapse may turn a remaining triangle's normal by less than 60 degrees
MIN_AREA = 1e-12    # ... and must leave its doubled area above this times the bbox diagonal^2


class Simplified(NamedTuple):
    """Simplified mesh: triangles (k, 3) index the original vertices, labels (k,) their regions."""
    triangles: np.ndarray
    labels: np.ndarray


def simplify(vertices, triangles, labels, tolerance) -> Simplified:
    """Collapse edges, cheapest first, while the quadric error stays within `tolerance`.

    labels (M,) give the region of each triangle. A vertex inside a region may collapse
    into any neighbour; a vertex on a boundary line (region boundary or mesh border, two
    boundary edges separating the same pair of regions) only along that line; corners
    (every other boundary vertex) stay. A collapse must keep the mesh manifold, turn no
    remaining triangle by 60 degrees or more nor flatten it, and never lay a boundary line
    onto another (so a closed loop keeps 3 vertices and no region vanishes). Its cost is
    the sum of squared distances of the surviving vertex to the planes of the original
    triangles merged into it and, for boundary vertices, to the planes through their
    boundary edges perpendicular to the triangles (these keep the lines straight); for a
    vertex inside a region, the mean per plane. `tolerance` is a length bounding its
    square root. Rounding puts a floor near 1e-8 of the edge length under that root.
    Triangles keep their orientation and label; flat parts of a region are then made
    Delaunay by edge flips, and a second round of collapses (on the simplified mesh's
    own quadrics) takes what the flips freed.
    """
    V = np.asarray(vertices, float)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    lab = np.asarray(labels).reshape(-1)
    for _ in range(2):  # flips free collapses the guards refused: one more round
        mesh = _Collapser(V, T, lab, float(tolerance))
        mesh.run()
        T, lab = np.array(mesh.tris, np.int64).reshape(-1, 3)[mesh.alive], lab[mesh.alive]
        T = delaunay_flips(V, T, lab)
    return Simplified(T, lab)


def delaunay_flips(V, tris, lab, flat=1e-9):
    """Flip edges inside flat parts of a region until every such edge is locally Delaunay.

    Collapsing leaves slivers (a far corner joined to two close boundary vertices); the
    handle interpolates across each simplified triangle, so a sliver turns into a steep
    deformation and an early flip of the mesh under it. An edge is flipped when its two
    triangles have the same label, are coplanar (normals within `flat` radians), form a
    convex quadrilateral and their opposite angles add up to more than pi.
    """
    T = [list(t) for t in np.asarray(tris).tolist()]
    P = np.asarray(V, float).tolist()
    lab = np.asarray(lab).tolist()
    edges = {}
    for f, t in enumerate(T):
        for k in range(3):
            edges.setdefault(frozenset((t[k], t[(k + 1) % 3])), []).append(f)
    todo = [e for e, fs in edges.items() if len(fs) == 2]
    while todo:
        e = todo.pop()
        fs = edges.get(e, ())
        if len(fs) != 2 or lab[fs[0]] != lab[fs[1]]:
            continue
        f, g = fs
        k = next(k for k in range(3) if {T[f][k], T[f][(k + 1) % 3]} == e)
        a, b, c = T[f][k], T[f][(k + 1) % 3], T[f][(k + 2) % 3]   # f is a, b, c in order
        d = next(x for x in T[g] if x not in e)                    # g is b, a, d
        if not _should_flip(P[a], P[b], P[c], P[d], flat):
            continue
        T[f], T[g] = [a, d, c], [b, c, d]
        del edges[e]
        edges[frozenset((c, d))] = [f, g]
        for edge, old, new in (((b, c), f, g), ((a, d), g, f)):
            key = frozenset(edge)
            edges[key] = [new if h == old else h for h in edges[key]]
        todo += [frozenset(q) for q in ((a, c), (c, b), (b, d), (d, a))]
    return np.array(T, np.int64).reshape(-1, 3)


class _Collapser:
    """The mesh being collapsed: triangle fans, neighbour sets, quadrics and the heap.

    Heap entries are (cost, stamp, u, v); `stamp[u, v]` keeps the stamp and cost of the
    one live entry of a pair, so superseded pushes are skipped. Each collapse u -> v
    re-queues every pair whose cost or checks it can change (those from v and from u's
    old neighbours, and those into v), so a live entry's cost is current and a pair
    refused when popped comes back once its neighbourhood changes. The quadrics are
    plain lists of floats: a collapse re-costs a dozen pairs, where numpy's per-call
    cost would be most of the loop.
    """

    def __init__(self, V, T, lab, tolerance):
        n = len(V)
        kind, ends, A = _setup(V, T, lab)
        self.A = A.reshape(n, 9).tolist()
        self.trace = np.trace(A, axis1=1, axis2=2).tolist()
        self.b, self.c = [[0.0, 0.0, 0.0] for _ in range(n)], [0.0] * n
        self.kind, self.lab = kind.tolist(), lab.tolist()
        self.along = {u: [] for u in np.flatnonzero(kind == LINE).tolist()}
        for a, b in ends.tolist():
            for x, y in ((a, b), (b, a)):
                if x in self.along:
                    self.along[x].append(y)
        self.V, self.P = V, V.tolist()
        self.tol2 = tolerance ** 2
        self.min_area = MIN_AREA * float(np.sum(np.ptp(V, axis=0) ** 2)) if n else 0.0
        self.tris, self.alive = T.tolist(), np.ones(len(T), bool)
        self.fan, self.nbr = [set() for _ in range(n)], [set() for _ in range(n)]
        for f, (a, b, c) in enumerate(self.tris):
            for x, y, z in ((a, b, c), (b, c, a), (c, a, b)):
                self.fan[x].add(f)
                self.nbr[x].update((y, z))
        self.heap, self.stamp, self.count = [], {}, 0

    def targets(self, u):
        """Where u may go: any neighbour inside a region, along its line, nowhere if a corner."""
        return list(self.nbr[u]) if self.kind[u] == INTERIOR else self.along.get(u, [])

    def queue(self, pairs):
        """Push the collapses u -> v among `pairs` whose cost is within the tolerance."""
        stamp, tol2, mean_cost = self.stamp, self.tol2, self.mean_cost
        for u, v in pairs:
            c = mean_cost(u, v)
            if c > tol2:
                stamp.pop((u, v), None)
            elif stamp.get((u, v), (0, None))[1] != c:
                self.count += 1
                stamp[u, v] = self.count, c
                heapq.heappush(self.heap, (c, self.count, u, v))

    def queue_all(self, pairs):
        """queue() for the first pairs, costed at once (every quadric is still a sum of
        planes through its vertex: b = c = 0)."""
        if not pairs:
            return
        us, vs = np.array(pairs).T
        d = self.V[vs] - self.V[us]
        A = np.array(self.A).reshape(-1, 3, 3)
        cost = 0.0 + np.einsum("ki,kij,kj->k", d, A[us], d)
        trace = np.array(self.trace)
        cost = np.where(np.array(self.kind)[us] == INTERIOR, cost / (trace[us] + trace[vs]),
                        cost)
        keep = np.flatnonzero(cost <= self.tol2)
        self.heap = [(c, k + 1, u, v) for k, (c, u, v) in enumerate(zip(
            cost[keep].tolist(), us[keep].tolist(), vs[keep].tolist()))]
        self.stamp = {(u, v): (k, c) for c, k, u, v in self.heap}
        self.count = len(self.heap)
        heapq.heapify(self.heap)

    def mean_cost(self, u, v):
        """cost(), per merged plane for a vertex inside a region: its mean squared distance
        to them (their count is the trace of the summed n n^T). A sum grows with every
        merge and would keep a finely meshed curved region (a cylinder with interior
        vertices) fine, where the handle needs long prisms; boundary lines keep the sum,
        so curved boundaries keep the vertices that make them round."""
        if self.kind[u] == INTERIOR:
            return self.cost(u, v) / (self.trace[u] + self.trace[v])
        return self.cost(u, v)

    def cost(self, u, v):
        """Quadric error of moving u to v: Q_v at v plus Q_u at v.

        Each vertex keeps its quadric as (A, b, c) about its own position, where the planes
        of its original triangles pass through it (b = c = 0 to start); this avoids the
        cancellation of evaluating the homogeneous 4 x 4 form far from the origin.
        """
        p, q = self.P[u], self.P[v]
        x, y, z = q[0] - p[0], q[1] - p[1], q[2] - p[2]
        a, b = self.A[u], self.b[u]
        return (self.c[v] + self.c[u] + 2 * (b[0] * x + b[1] * y + b[2] * z)
                + (x * a[0] * x + x * a[1] * y + x * a[2] * z + y * a[3] * x + y * a[4] * y
                   + y * a[5] * z + z * a[6] * x + z * a[7] * y + z * a[8] * z))

    def allowed(self, u, v):
        """Link condition, no duplicate triangle, no flipped or degenerate triangle."""
        tris = self.tris
        if self.kind[u] == LINE:  # u's other line edge uw becomes vw: not onto a line edge
            w = next(x for x in self.along[u] if x != v)
            labels = [self.lab[f] for f in self.fan[v] if w in tris[f]]
            if labels and (len(labels) == 1 or labels[0] != labels[1]):
                return False
        shared = [f for f in self.fan[u] if v in tris[f]]
        kept = [f for f in self.fan[u] if v not in tris[f]]
        if self.nbr[u] & self.nbr[v] != {w for f in shared for w in tris[f]} - {u, v}:
            return False
        around_v = {frozenset(tris[f]) for f in self.fan[v]}
        if any(frozenset(tris[f]) - {u} | {v} in around_v for f in kept):
            return False
        P, moved = self.P, self.P[v]
        for f in kept:
            old = _normal(*(P[w] for w in tris[f]))
            new = _normal(*(moved if w == u else P[w] for w in tris[f]))
            size = math.sqrt(_dot(new, new))
            if size <= self.min_area or (
                    _dot(old, new) <= MAX_TURN_COS * math.sqrt(_dot(old, old)) * size):
                return False
        return True

    def collapse(self, u, v, cost):
        """Move u's triangles to v, drop the two on edge uv, merge u's quadric into v's."""
        tris, fan, nbr = self.tris, self.fan, self.nbr
        for f in fan[u]:
            if v in tris[f]:
                self.alive[f] = False
                for w in tris[f]:
                    if w != u:
                        fan[w].discard(f)
            else:
                tris[f][tris[f].index(u)] = v
                fan[v].add(f)
        for x in nbr[u]:
            nbr[x].discard(u)
            if x != v:
                nbr[x].add(v)
                nbr[v].add(x)
        self.c[v] = cost  # u's quadric moved to v's position, added to v's
        p, q, a = self.P[u], self.P[v], self.A[u]
        x, y, z = q[0] - p[0], q[1] - p[1], q[2] - p[2]
        bu, bv = self.b[u], self.b[v]
        self.b[v] = [bv[0] + (bu[0] + (a[0] * x + a[1] * y + a[2] * z)),
                     bv[1] + (bu[1] + (a[3] * x + a[4] * y + a[5] * z)),
                     bv[2] + (bu[2] + (a[6] * x + a[7] * y + a[8] * z))]
        A = self.A[v] = [s + t for s, t in zip(self.A[v], a)]
        self.trace[v] = A[0] + A[4] + A[8]
        if self.kind[u] == LINE:
            w = next(x for x in self.along.pop(u) if x != v)
            for x, y in ((v, w), (w, v)):
                if x in self.along:
                    self.along[x] = [y if z == u else z for z in self.along[x]]
        fan[u], nbr[u] = set(), set()

    def run(self):
        """Collapse cheapest first until no admissible collapse is left."""
        self.queue_all([(u, v) for u in range(len(self.P)) for v in self.targets(u)])
        heap, stamp, nbr, kind, along = self.heap, self.stamp, self.nbr, self.kind, self.along
        while heap:
            cost, count, u, v = heapq.heappop(heap)
            if stamp.get((u, v), (None,))[0] != count:
                continue
            del stamp[u, v]
            if v not in nbr[u] or not self.allowed(u, v):
                continue
            moved = nbr[u] - {v}
            self.collapse(u, v, self.cost(u, v))
            pairs = [(v, t) for t in self.targets(v)]
            # a pair without v keeps its cost: queued again only if it was popped (refused)
            pairs += [(x, t) for x in moved for t in self.targets(x)
                      if t == v or (x, t) not in stamp]
            pairs += [(w, v) for w in nbr[v] - moved
                      if kind[w] == INTERIOR or v in along.get(w, ())]
            self.queue(pairs)


def _normal(a, b, c):
    """(b - a) x (c - a): the normal of triangle abc times twice its area."""
    px, py, pz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    qx, qy, qz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    return py * qz - pz * qy, pz * qx - px * qz, px * qy - py * qx


def _dot(p, q):
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]


def _setup(V, T, lab):
    """Vertex classes, the boundary edges (pairs of vertices) and the initial quadrics."""
    n, m = len(V), len(T)
    region = np.unique(lab, return_inverse=True)[1].reshape(-1)
    border = int(region.max(initial=-1)) + 1
    a, b = T.reshape(-1), np.roll(T, -1, axis=1).reshape(-1)  # half-edge a -> b of its face
    face = np.repeat(np.arange(m), 3)
    keys, first, edge, count = np.unique(np.minimum(a, b) * n + np.maximum(a, b),
                                         return_index=True, return_inverse=True,
                                         return_counts=True)
    side = np.full((len(keys), 2), border)  # the regions on either side, or the border
    side[:, 0] = region[face[first]]
    second = np.flatnonzero(np.arange(3 * m) != first[edge])
    side[edge[second], 1] = region[face[second]]
    on_line = (side[:, 0] != side[:, 1]) | (count == 1)
    ends = np.c_[keys // n, keys % n][on_line]
    pairs = np.repeat(np.sort(side[on_line], axis=1) @ [border + 1, 1], 2)
    hits = np.bincount(ends.reshape(-1), minlength=n)
    lo, hi = np.full(n, np.iinfo(np.int64).max), np.full(n, -1)
    np.minimum.at(lo, ends.reshape(-1), pairs)
    np.maximum.at(hi, ends.reshape(-1), pairs)
    kind = np.where(hits == 0, INTERIOR, np.where((hits == 2) & (lo == hi), LINE, CORNER))
    return kind, ends, _quadrics(V, T, a, b, face, on_line[edge])


def _quadrics(V, T, a, b, face, on_line):
    """Per-vertex sums of n n^T over the planes through it: its triangles' planes and, at
    both ends of a boundary half-edge, the plane through it perpendicular to its triangle."""
    nrm = unit(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]))
    fence = unit(np.cross(nrm[face[on_line]], V[b[on_line]] - V[a[on_line]]))
    A = np.zeros((len(V), 3, 3))
    for at, n in ((T[:, 0], nrm), (T[:, 1], nrm), (T[:, 2], nrm),
                  (a[on_line], fence), (b[on_line], fence)):
        np.add.at(A, at, n[:, :, None] * n[:, None, :])
    return A


def _should_flip(a, b, c, d, flat):
    """Whether edge ab of triangles abc and bad should become cd (see delaunay_flips).
    Points are 3-tuples of floats: this runs once per edge, where numpy's per-call cost
    on 3-vectors would dominate."""
    def sub(p, q):
        return p[0] - q[0], p[1] - q[1], p[2] - q[2]

    def norm(p):
        return math.sqrt(_dot(p, p))

    n1, n2 = _normal(a, b, c), _normal(b, a, d)
    l1, l2 = norm(n1), norm(n2)
    if l1 == 0 or l2 == 0 or norm(_cross(n1, n2)) > flat * l1 * l2 or _dot(n1, n2) < 0:
        return False
    if _dot(_cross(sub(d, a), sub(c, a)), n1) <= 0 or _dot(_cross(sub(c, b), sub(d, b)), n1) <= 0:
        return False                                   # not convex: the flip would fold

    def angle(p, q, r):                                # at q
        u, v = sub(p, q), sub(r, q)
        return math.atan2(norm(_cross(u, v)), _dot(u, v))
    return angle(a, c, b) + angle(a, d, b) > math.pi + 1e-12


def _cross(p, q):
    return p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]
