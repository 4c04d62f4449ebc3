"""Region-preserving mesh simplification for the deformation handle (Date & Onosato 2008).

Sections 4.2 and 5.1 of the paper simplify the segmented mesh with VSA, each region
triangulated from its outline; here too: the outlines are simplified once, flat regions
are ear-clipped, curved disks triangulated in a harmonic map, and only curved regions of
other topology (tubes) go through a constrained quadric-error half-edge collapse. Every
simplified vertex is an original vertex (the correspondence v_c is the identity) and each
simplified triangle lies in one region. Meshes are vertices (N, 3) float and consistently
oriented triangles (M, 3).
"""
import heapq
import math
from functools import partial
from typing import NamedTuple

import numpy as np
from scipy.sparse import csr_matrix, diags
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

from .dimension_handle import segment_distance, triangle_fit
from ..vectors import unit

INTERIOR, LINE, CORNER = 0, 1, 2
MAX_TURN_COS = 0.5  # a collapse may turn a remaining triangle's normal by less than 60 degrees
MIN_AREA = 1e-12    # ... and must leave its doubled area above this times the bbox diagonal^2
CHUNK = 4096       # x 16 point-triangle pairs measured at once by _far_labels (memory)
LOOP_VERTICES = 3000  # _collapsed's loop takes over from _batched at this many vertices
BATCH_SHARE = 0.5  # _batched takes collapses within this share of the tolerance
MIN_BATCH = 0.01   # ... and stops after a round that removed fewer than this share of vertices
PICK_TRIES = 4     # rounds of picking in one batch of _batched (refused ones drop out)


class Simplified(NamedTuple):
    """Simplified mesh: triangles (k, 3) index the original vertices, labels (k,) their regions."""
    triangles: np.ndarray
    labels: np.ndarray


def simplify(vertices, triangles, labels, tolerance) -> Simplified:
    """The simplified mesh of (vertices, triangles) with region `labels` (M,) per triangle.

    Every region is rebuilt from its outline at once (as VSA and the paper do): the
    boundary lines (between corners: vertices where three regions meet or lines branch;
    or closed loops) keep the vertices Douglas-Peucker needs to stay within `tolerance`
    (a length). A flat region (every vertex within half the tolerance of its plane, every
    triangle facing within 60 degrees of it) is its outline, holes bridged, ear-clipped.
    A curved region that is a topological disk is mapped onto the polygon of its kept
    outline vertices on the unit circle (Tutte's harmonic map: every vertex lands inside)
    and triangulated there, its edges flipped toward the surface's own Delaunay
    triangulation; interior vertices go in, the farthest of each bad triangle, until the
    vertices inside every triangle (those RIM_RINGS edges or more off the outline) lie
    within MAX_FAR tolerances of it (RMS_FAR in the root mean square) and none turns away
    from the region. Curved regions of other
    topology (a tube) are simplified first by quadric edge collapses (_collapsed), and
    their lines taken from there. A region the route fails on (a flat outline that does
    not ear-clip, a curved disk whose map folds) is collapsed on its own inside the lines
    decided for its neighbours. Every vertex ends within MAX_FAR tolerances of its
    regions' triangles; a mesh the route cannot take so (a pinched region, two regions
    spanning the same chord of their line) is collapsed whole. Flat parts of a region are
    then made Delaunay by edge flips.
    """
    V = np.asarray(vertices, float)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    lab = np.asarray(labels).reshape(-1)
    try:
        T2, lab2 = _Outlines(V, T, lab, float(tolerance)).run()
    except _Unfit:
        return _collapsed(V, T, lab, float(tolerance))
    return Simplified(delaunay_flips(V, T2, lab2), lab2)


def _far_labels(V, T, lab, T2, lab2, limit, k=4):
    """The labels of the regions with a vertex beyond `limit` of their simplified
    triangles (T2, lab2), each vertex measured in every region it is in: the outline route
    measures only vertices away from the outlines, and a region collapsed on its own can
    drop a vertex of its neighbour's outline. A vertex is measured to the k triangles
    whose centres are nearest, and where those are too far, to all of its region's."""
    def distances(pts, tris, cand):
        out = np.empty(len(pts))
        rows = max(1, CHUNK * 16 // cand.shape[1])      # (rows, candidates, 3) at a time
        for i in range(0, len(pts), rows):
            c = cand[i:i + rows]
            A, B, C = tris[c, 0], tris[c, 1], tris[c, 2]
            out[i:i + rows] = triangle_fit(pts[i:i + rows, None], A, B, C,
                                           unit(np.cross(B - A, C - A)))[0].min(axis=1)
        return out

    far = []
    regions = np.unique(lab)
    order, order2 = np.argsort(lab, kind="stable"), np.argsort(lab2, kind="stable")
    cuts = np.searchsorted(lab[order], regions, side="right")[:-1]
    cuts2 = np.searchsorted(lab2[order2], regions, side="right")[:-1]
    for r, mine, simple in zip(regions.tolist(), np.split(order, cuts), np.split(order2, cuts2)):
        pts = V[np.unique(T[mine])]
        tris = V[T2[simple[lab2[simple] == r]]]
        if not len(tris):
            far.append(r)
            continue
        near = cKDTree(tris.mean(axis=1)).query(pts, k=min(k, len(tris)))[1]
        out = distances(pts, tris, near.reshape(len(pts), -1)) > limit
        if out.any() and distances(pts[out], tris, np.broadcast_to(
                np.arange(len(tris)), (int(out.sum()), len(tris)))).max() > limit:
            far.append(r)
    return far


def _collapsed(V, T, lab, tolerance, corners=None, gone=None) -> Simplified:
    """Collapse edges, cheapest first, while the quadric error stays within `tolerance`.

    A vertex inside a region may collapse into any neighbour; a vertex on a boundary line
    (region boundary or mesh border, two boundary edges separating the same pair of
    regions) only along that line; corners (every other boundary vertex, and `corners`
    (N,) where True) stay. A collapse must keep the mesh manifold, turn no remaining
    triangle by 60 degrees or more nor flatten it, and never lay a boundary line onto
    another (so a closed loop keeps 3 vertices and no region vanishes). Its cost is the sum
    of squared distances of the surviving vertex to the planes of the original triangles
    merged into it and, for boundary vertices, to the planes through their boundary edges
    perpendicular to the triangles (these keep the lines straight); for a vertex inside a
    region, the mean per plane. `tolerance` bounds its square root; a line vertex where
    `gone` (N,) is True costs nothing (its line was decided elsewhere without it). Triangles
    keep their orientation and label; after flips, a second round takes what the flips freed.
    A mesh of more than LOOP_VERTICES vertices is first brought down to that many by
    batches of independent collapses (_batched), the loop taking the rest cheapest first.
    """
    for first in (True, False):  # flips free collapses the guards refused: one more round
        kind, _, A = _setup(V, T, lab)
        if corners is not None:
            kind[corners] = CORNER
        quadrics = A, np.zeros((len(V), 3)), np.zeros(len(V))
        if first:
            T, lab, quadrics = _batched(V, T, lab, kind, quadrics, tolerance, gone)
        mesh = _Collapser(V, T, lab, tolerance, kind, quadrics, gone)
        mesh.run()
        T, lab = np.array(mesh.tris, np.int64).reshape(-1, 3)[mesh.alive], lab[mesh.alive]
        T = delaunay_flips(V, T, lab)
    return Simplified(T, lab)


def _batched(V, T, lab, kind, quadrics, tolerance, gone):
    """(triangles, labels, quadrics) of the mesh brought down toward LOOP_VERTICES vertices
    by rounds of collapses costed and checked as _Collapser does, in numpy: each round
    takes the collapses within BATCH_SHARE of the tolerance that meet no cheaper one
    (_picked) and pass _Collapser's checks (_refused), and applies them at once; none
    changes what another reads or writes, so a round is a sequence of valid collapses.
    A round removing under MIN_BATCH of the vertices is the last. The loop's one collapse
    at a time costs some 0.3 ms in Python: 10 s on a 70 k-triangle scan, where these
    rounds take about 1 s."""
    A, b, c = (q.copy() for q in quadrics)
    n = len(V)
    trace = np.trace(A, axis1=1, axis2=2)
    gone = np.zeros(n, bool) if gone is None else gone & (kind == LINE)
    min_area = MIN_AREA * float(np.sum(np.ptp(V, axis=0) ** 2)) if n else 0.0
    live = np.count_nonzero(np.bincount(T.reshape(-1), minlength=n))
    while live > LOOP_VERTICES:
        mesh = _Edges(T, lab, n)
        # the collapses allowed: inside a region to any neighbour, along a line on it
        src, dst = mesh.src, mesh.dst
        line = mesh.on_line[mesh.edge]
        take = np.where(kind[src] == INTERIOR, True, (kind[src] == LINE) & line)
        us, vs = src[take], dst[take]
        d = V[vs] - V[us]
        full = np.einsum("ki,kij,kj->k", d, A[us], d) + (
            c[vs] + c[us] + 2 * np.einsum("ki,ki->k", b[us], d))
        cost = np.where(kind[us] == INTERIOR, full / (trace[us] + trace[vs]), full)
        cost[gone[us]] = 0.0
        ok = cost <= (BATCH_SHARE * tolerance) ** 2
        us, vs, cost, full = us[ok], vs[ok], cost[ok], full[ok]
        k = _picked(mesh, us, vs, cost, partial(_refused, V, T, kind, mesh, min_area=min_area))
        u, v = us[k], vs[k]
        c[v] = full[k]
        b[v] += b[u] + np.einsum("kij,kj->ki", A[u], V[v] - V[u])
        A[v] += A[u]
        trace[v] += trace[u]
        to = np.arange(n)
        to[u] = v
        T = to[T]
        kept = (T[:, 0] != T[:, 1]) & (T[:, 1] != T[:, 2]) & (T[:, 2] != T[:, 0])
        T, lab = T[kept], lab[kept]
        if len(k) < MIN_BATCH * live:
            break                       # the rest waits on other collapses: the loop's
        live -= len(k)
    return T, lab, (A, b, c)


class _Edges:
    """The edges of a mesh (n vertices, triangles T with labels): undirected edges `keys`
    (a * n + b, a < b) and whether each is on a line (border or region boundary);
    directed edges src -> dst sorted by src (offsets `start` (n + 1,)), `edge` the
    undirected edge of each; the triangles at each vertex (`fans`, offsets `fan_start`)."""

    def __init__(self, T, lab, n):
        self.n = n
        a, b = T.reshape(-1), T[:, [1, 2, 0]].reshape(-1)
        face = np.repeat(np.arange(len(T)), 3)
        self.keys, first, inv, count = np.unique(
            np.minimum(a, b) * n + np.maximum(a, b), return_index=True, return_inverse=True,
            return_counts=True)
        other = np.empty(len(self.keys), lab.dtype)
        other[inv.reshape(-1)] = lab[face]
        self.on_line = (count == 1) | (lab[face[first]] != other)
        x, y = self.keys // n, self.keys % n
        src, dst = np.r_[x, y], np.r_[y, x]
        order = np.argsort(src)
        self.src, self.dst = src[order], dst[order]
        self.edge = np.r_[np.arange(len(x)), np.arange(len(x))][order]
        self.start = np.searchsorted(self.src, np.arange(n + 1))
        order = np.argsort(a)
        self.fans, self.fan_start = face[order], np.searchsorted(a[order], np.arange(n + 1))

    def around(self, start, ids):
        """(owner, item): the items start[ids[i]]:start[ids[i] + 1] of each id, flattened."""
        counts = start[ids + 1] - start[ids]
        owner = np.repeat(np.arange(len(ids)), counts)
        return owner, start[ids][owner] + np.arange(len(owner)) - np.repeat(
            np.cumsum(counts) - counts, counts)

    def find(self, x, y):
        """The undirected edge index of each pair x, y (-1 where there is none)."""
        key = np.minimum(x, y) * self.n + np.maximum(x, y)
        at = np.clip(np.searchsorted(self.keys, key), 0, max(len(self.keys) - 1, 0))
        return np.where(self.keys[at] == key, at, -1)

    def spread(self, values, fn):
        """fn (np.minimum or np.maximum) of each vertex's value and its neighbours'."""
        out = values.copy()
        has = np.flatnonzero(self.start[1:] > self.start[:-1])
        out[has] = fn(out[has], fn.reduceat(values[self.dst], self.start[has]))
        return out


def _picked(mesh, us, vs, cost, refused):
    """The indices of the collapses among candidates (us, vs, cost; grouped by u) taken in
    one round. Two collapses u -> v and x -> y do not meet when neither x nor y is u or
    next to it and neither u nor v is x or next to it: then neither changes a vertex's
    neighbours, fan or quadric that the other reads or writes. Each u offers its
    cheapest candidate; those cheaper than every offer they would meet are taken unless
    `refused` (u, v) -> bool; refused ones drop out and the next offers are tried, clear
    of those taken (PICK_TRIES times)."""
    n, big = mesh.n, np.iinfo(np.int64).max
    order = np.argsort(cost)
    rank = np.empty(len(cost), np.int64)
    rank[order] = np.arange(len(cost))
    heads = np.flatnonzero(np.r_[True, us[1:] != us[:-1]]) if len(us) else np.zeros(0, int)
    alive = np.ones(len(us), bool)
    near_u, near_v = np.zeros(n, bool), np.zeros(n, bool)   # where no new u, v may be
    taken = []
    for _ in range(PICK_TRIES):
        open_ = alive & ~near_u[us] & ~near_v[vs]
        if not open_.any():
            break
        offer = np.minimum.reduceat(np.where(open_, rank, big), heads)
        offer = offer[offer < big]
        first = np.full(n, big)                  # the offer of each u
        first[us[order[offer]]] = offer
        into = np.full(n, big)                   # the cheapest offer into each v
        to = vs[order[offer]]
        k = np.lexsort((offer, to))
        k = k[np.r_[True, to[k][1:] != to[k][:-1]]]
        into[to[k]] = offer[k]
        around = mesh.spread(first, np.minimum)
        pick = open_ & (rank == np.minimum(np.minimum(around[us], around[vs]),
                                          mesh.spread(into, np.minimum)[us]))
        bad = refused(us[pick], vs[pick])
        alive[np.flatnonzero(pick)[bad]] = False
        good = np.flatnonzero(pick)[~bad]
        taken.append(good)
        mark = np.zeros(n, np.int8)
        mark[us[good]] = 1
        near_v |= mesh.spread(mark, np.maximum) > 0
        mark[vs[good]] = 1
        near_u |= mesh.spread(mark, np.maximum) > 0
    return np.concatenate(taken) if taken else np.zeros(0, np.int64)


def _refused(V, T, kind, mesh, u, v, min_area):
    """Which collapses u -> v (arrays) _Collapser.allowed() would refuse: a line vertex
    laying its other line edge onto a line, the link condition, a duplicate triangle, a
    remaining triangle turned by 60 degrees or more or flattened."""
    bad = np.zeros(len(u), bool)
    # a line vertex's other line edge u w becomes v w: not onto a line edge
    at = np.flatnonzero(kind[u] == LINE)
    if len(at):
        owner, k = mesh.around(mesh.start, u[at])
        other = mesh.on_line[mesh.edge[k]] & (mesh.dst[k] != v[at][owner])
        w = np.full(len(at), -1)
        w[owner[other]] = mesh.dst[k[other]]
        e = mesh.find(v[at], w)
        hit = (w >= 0) & (e >= 0)
        hit[hit] = mesh.on_line[e[hit]]
        bad[at[hit]] = True
    # the triangles around u: those on u v go, the others are kept and turn
    owner, k = mesh.around(mesh.fan_start, u)
    f = mesh.fans[k]
    tri = T[f]
    on_uv = (tri == v[owner, None]).any(axis=1)
    # link: the common neighbours of u and v are the third corners of the triangles on u v
    gone, by = tri[on_uv], owner[on_uv]
    third = gone[(gone != u[by, None]) & (gone != v[by, None])]
    pairs = np.unique(by * mesh.n + third)
    thirds = np.bincount(pairs // mesh.n, minlength=len(u))
    nb_owner, j = mesh.around(mesh.start, u)
    w = mesh.dst[j]
    common = (w != v[nb_owner]) & (mesh.find(v[nb_owner], w) >= 0)
    bad |= np.bincount(nb_owner[common], minlength=len(u)) != thirds
    # kept triangles: u moved onto v
    kept = ~on_uv
    owner, tri = owner[kept], tri[kept]
    P = V[tri]
    old = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    P[tri == u[owner, None]] = V[v[owner]]
    new = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    size = np.linalg.norm(new, axis=1)
    turned = (size <= min_area) | (np.einsum("ij,ij->i", old, new)
                                   <= MAX_TURN_COS * np.linalg.norm(old, axis=1) * size)
    bad[owner[turned]] = True
    # a duplicate: a kept triangle u a b with both third corners, where v a b exists
    both = np.isin(owner[:, None] * mesh.n + tri, pairs).sum(axis=1) == 2
    for i, t in zip(owner[both].tolist(), tri[both].tolist()):
        rest = set(t) - {int(u[i])} | {int(v[i])}
        fan = mesh.fans[mesh.fan_start[v[i]]:mesh.fan_start[v[i] + 1]]
        if any(set(x) == rest for x in T[fan].tolist()):
            bad[i] = True
    return bad


def delaunay_flips(V, tris, lab, flat=1e-9):
    """Flip edges inside flat parts of a region until every such edge is locally Delaunay.

    Collapsing and ear clipping leave slivers (a far corner joined to two close boundary
    vertices); the handle interpolates across each simplified triangle, so a sliver turns
    into a steep deformation and an early flip of the mesh under it. An edge is flipped
    when its two triangles have the same label, are coplanar (normals within `flat`
    radians), form a convex quadrilateral and their opposite angles add up to more than pi.
    """
    T = [list(t) for t in np.asarray(tris).tolist()]
    P = np.asarray(V, float).tolist()
    lab = np.asarray(lab).tolist()
    edges = _edge_map(T)

    def should(f, g, a, b, c, d):
        return lab[f] == lab[g] and _should_flip(P[a], P[b], P[c], P[d], flat)
    _lawson(T, edges, [e for e, fs in edges.items() if len(fs) == 2], should)
    return np.array(T, np.int64).reshape(-1, 3)


def _edge_map(T):
    """{frozenset edge: [the triangles on it]} of triangles T (lists of 3 ids)."""
    edges = {}
    for f, t in enumerate(T):
        for k in range(3):
            edges.setdefault(frozenset((t[k], t[(k + 1) % 3])), []).append(f)
    return edges


def _lawson(T, edges, todo, should):
    """Flip edges of T (lists, changed in place; `edges` kept current) popped from `todo`:
    edge ab of triangles f = abc and g = bad becomes cd when should(f, g, a, b, c, d);
    the four edges around it are looked at again."""
    while todo:
        e = todo.pop()
        fs = edges.get(e, ())
        if len(fs) != 2:
            continue
        f, g = fs
        k = next(k for k in range(3) if {T[f][k], T[f][(k + 1) % 3]} == e)
        a, b, c = T[f][k], T[f][(k + 1) % 3], T[f][(k + 2) % 3]   # f is a, b, c in order
        d = next(x for x in T[g] if x not in e)                    # g is b, a, d
        if not should(f, g, a, b, c, d):
            continue
        T[f], T[g] = [a, d, c], [b, c, d]
        del edges[e]
        edges[frozenset((c, d))] = [f, g]
        for edge, old, new in (((b, c), f, g), ((a, d), g, f)):
            key = frozenset(edge)
            edges[key] = [new if h == old else h for h in edges[key]]
        todo += [frozenset(q) for q in ((a, c), (c, b), (b, d), (d, a))]


class _Collapser:
    """The mesh being collapsed: triangle fans, neighbour sets, quadrics and the heap.

    Heap entries are (cost, stamp, u, v); `stamp[u, v]` keeps the stamp and cost of the
    one live entry of a pair, so superseded pushes are skipped. Each collapse u -> v
    re-queues every pair whose cost or checks it can change (those from v and from u's
    old neighbours, and those into v), so a live entry's cost is current and a pair
    refused when popped comes back once its neighbourhood changes. The quadrics are
    plain lists of floats: a collapse re-costs a dozen pairs, where numpy's per-call
    cost would be most of the loop. `kind` holds the vertex classes and `quadrics` the
    (A, b, c) of every vertex (see cost), both as _batched left them.
    """

    def __init__(self, V, T, lab, tolerance, kind, quadrics, gone=None):
        n = len(V)
        ends = _kinds(V, T, lab)[1]
        A, linear, constant = quadrics
        self.gone = set() if gone is None else set(np.flatnonzero(gone & (kind == LINE)).tolist())
        self.A = A.reshape(n, 9).tolist()
        self.trace = np.trace(A, axis1=1, axis2=2).tolist()
        self.b, self.c = linear.tolist(), constant.tolist()
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
        """queue() for the first pairs, costed at once."""
        if not pairs:
            return
        us, vs = np.array(pairs).T
        d = self.V[vs] - self.V[us]
        A = np.array(self.A).reshape(-1, 3, 3)
        b, c = np.array(self.b), np.array(self.c)
        cost = np.einsum("ki,kij,kj->k", d, A[us], d) + (
            c[vs] + c[us] + 2 * np.einsum("ki,ki->k", b[us], d))
        trace = np.array(self.trace)
        cost = np.where(np.array(self.kind)[us] == INTERIOR, cost / (trace[us] + trace[vs]),
                        cost)
        cost[np.isin(us, list(self.gone))] = 0.0
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
        if u in self.gone:
            return 0.0
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
    kind, ends, a, b, face, on_line = _kinds(V, T, lab)
    return kind, ends, _quadrics(V, T, a, b, face, on_line)


def _kinds(V, T, lab):
    """(vertex classes, boundary edges, and the half-edges a -> b of faces `face` with
    whether each lies on a boundary line, for the quadrics)."""
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
    return kind, ends, a, b, face, on_line[edge]


def _quadrics(V, T, a, b, face, on_line):
    """Per-vertex sums of n n^T over the planes through it: its triangles' planes and, at
    both ends of a boundary half-edge, the plane through it perpendicular to its triangle."""
    nrm = unit(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]))
    fence = unit(np.cross(nrm[face[on_line]], V[b[on_line]] - V[a[on_line]]))
    at = np.concatenate([T[:, 0], T[:, 1], T[:, 2], a[on_line], b[on_line]])
    n = np.concatenate([nrm, nrm, nrm, fence, fence])
    nn = (n[:, :, None] * n[:, None, :]).reshape(-1, 9)
    # summed in this order, as np.add.at would (bincount is its fast form)
    return np.stack([np.bincount(at, nn[:, k], len(V)) for k in range(9)], 1).reshape(-1, 3, 3)


def _should_flip(a, b, c, d, flat):
    """Whether edge ab of triangles abc and bad should become cd (see delaunay_flips).
    Points are 3-tuples of floats: this runs once per edge, where numpy's per-call cost
    on 3-vectors would dominate."""
    n1, n2 = _normal(a, b, c), _normal(b, a, d)
    l1, l2 = _norm(n1), _norm(n2)
    ab = _sub(b, a)
    flat_ab = 1e-12 * _dot(ab, ab)
    if min(l1, l2) <= flat_ab < max(l1, l2):  # one triangle is edge ab with a point on it:
        n = n2 if l1 < l2 else n1             # the flip covers the other one's area
        p = c if l1 < l2 else d
        return (0 < _dot(_sub(p, a), ab) < _dot(ab, ab) and _dot(_normal(a, d, c), n) > 0
                and _dot(_normal(b, c, d), n) > 0)
    if l1 == 0 or l2 == 0 or _norm(_cross(n1, n2)) > flat * l1 * l2 or _dot(n1, n2) < 0:
        return False
    if _dot(_cross(_sub(d, a), _sub(c, a)), n1) <= 0 or \
            _dot(_cross(_sub(c, b), _sub(d, b)), n1) <= 0:
        return False                                   # not convex: the flip would fold
    return _angle(a, c, b) + _angle(a, d, b) > math.pi + 1e-12


def _sub(p, q):
    return p[0] - q[0], p[1] - q[1], p[2] - q[2]


def _norm(p):
    return math.sqrt(_dot(p, p))


def _angle(p, q, r):
    """The angle at q of triangle pqr."""
    u, v = _sub(p, q), _sub(r, q)
    return math.atan2(_norm(_cross(u, v)), _dot(u, v))


def _cross(p, q):
    return p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]


# ------------------------------------------------------------------ regions from their outlines

FLAT_TURN_COS = 0.5   # a flat region's triangles all face within 60 degrees of its plane
MAX_FAR, RMS_FAR = 3.0, 1.5  # a curved region's vertices from its triangles (x tolerance)
RIM_RINGS = 2         # a curved region is measured and refined this many edges off its outline
SLOW_SHARE = 0.5      # beyond this share of triangles to collapse, the whole mesh is (cheaper)
MAX_INSERTS = 16      # rounds of insertion before a curved region is collapsed instead


class _Unfit(Exception):
    """The outline route cannot take this mesh (simplify() collapses it whole instead)."""


class _Outlines:
    """simplify()'s outline route: lines first, then every region from its outline."""

    def __init__(self, V, T, lab, tolerance):
        self.V, self.T, self.tol = V, T, tolerance
        n = len(V)
        self.kind = _kinds(V, T, lab)[0]
        self.labels, self.region = np.unique(lab, return_inverse=True)
        self.region = self.region.reshape(-1)
        self.size = float(np.linalg.norm(np.ptp(V, axis=0))) if n else 0.0
        self.min_area = MIN_AREA * float(np.sum(np.ptp(V, axis=0) ** 2)) if n else 0.0
        self.normals = unit(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]))
        self.loops = self._loops()

    def _loops(self):
        """Per region, its boundary loops: vertex lists in walking order (region on the left)."""
        T, n, K = self.T, len(self.V), len(self.labels)
        a, b = T.reshape(-1), T[:, [1, 2, 0]].reshape(-1)
        r = np.repeat(self.region, 3)
        key = (a * n + b) * K + r
        order = np.argsort(key)
        sk = key[order]
        if np.any(sk[1:] == sk[:-1]):
            raise _Unfit                     # a half-edge twice in one region
        rev = (b * n + a) * K + r
        pos = np.clip(np.searchsorted(sk, rev), 0, len(sk) - 1)
        rim = np.flatnonzero(sk[pos] != rev)
        rim = rim[np.argsort(r[rim], kind="stable")]
        cuts = np.searchsorted(r[rim], np.arange(K + 1))
        loops = []
        for k in range(K):
            h = rim[cuts[k]:cuts[k + 1]]
            nxt = dict(zip(a[h].tolist(), b[h].tolist()))
            if len(nxt) < len(h):
                raise _Unfit                 # the region touches itself at a vertex
            seen, mine = set(), []
            for s in nxt:
                if s in seen:
                    continue
                loop, x = [], s
                while x not in seen:
                    seen.add(x)
                    loop.append(x)
                    x = nxt[x]
                if x != s:
                    raise _Unfit
                mine.append(loop)
            loops.append(mine)
        return loops

    def run(self):
        """(triangles, labels) of every region, in one pass: the tubes (and the curved
        disks next to them that fail on lines of their own) collapsed and their lines
        taken from there, the other lines by Douglas-Peucker, every other region from its
        outline. A region that fails there, or whose vertices end beyond MAX_FAR
        tolerances of its triangles (_far_regions), is then collapsed on its own inside its
        decided outline, whose other vertices go first; a flat or curved neighbour is
        built again with any of them that stayed. _Unfit (the whole mesh collapsed) when
        one stays on a tube's line or a region ends too far all the same."""
        V, T = self.V, self.T
        K, n = len(self.labels), len(V)
        flat, disk = self._classes()
        slow = ~flat & ~disk
        if slow.any():
            slow |= self._failing_by_tubes(slow, flat)
        keep = self.kind == CORNER
        decided = np.zeros(n, bool)
        parts = {}
        if slow.any():
            mask = slow[self.region]
            if np.count_nonzero(mask) > SLOW_SHARE * len(T):
                raise _Unfit                    # little left to gain: collapse it all
            tris, labels = self._collapsed_alone(mask, keep, decided)
            keep[np.unique(tris)] = True
            decided[T[mask]] = True
            parts.update(self._by_region(tris, labels, mask))
        for k in range(K):
            for loop in self.loops[k]:
                self._lines(loop, keep, decided)
        failed = []
        for k in np.flatnonzero(~slow).tolist():
            try:
                parts[k] = self._built(k, flat[k], keep)
            except _Unfit:
                failed.append(k)
        built = [k for k in np.flatnonzero(~slow).tolist() if k in parts]
        failed += self._far_regions(parts, built)
        check = set(np.flatnonzero(slow).tolist())
        if failed:
            for k in failed:
                parts.pop(k, None)
            mask = np.isin(self.region, failed)
            tris, labels = self._collapsed_alone(mask, keep, decided)
            parts.update(self._by_region(tris, labels, mask))
            # outline vertices that collapse kept go into the neighbours' outlines
            extra = np.zeros(n, bool)
            extra[np.unique(tris)] = True
            extra &= ~keep
            keep |= extra
            for k in set(range(K)) - set(failed):
                if any(extra[loop].any() for loop in self.loops[k]):
                    if slow[k]:
                        raise _Unfit        # a tube's lines stay as its collapse left them
                    parts[k] = self._built(k, flat[k], keep)
                    check.add(k)
            check |= set(failed)
        if self._far_regions(parts, sorted(check)):
            raise _Unfit
        T2 = np.concatenate([parts[k] for k in range(K)]).astype(np.int64)
        # two regions may each span the same chord of their common line (an ear of three
        # nearly collinear kept vertices on both sides): an edge then runs twice one way
        directed = T2.reshape(-1) * n + T2[:, [1, 2, 0]].reshape(-1)
        if len(np.unique(directed)) < len(directed):
            raise _Unfit
        return T2, np.repeat(self.labels, [len(parts[k]) for k in range(K)])

    def _failing_by_tubes(self, slow, flat):
        """(K,) the curved disks next to a tube (`slow`) that fail on lines of their own
        (Douglas-Peucker everywhere): they join the tubes' collapse, where collapsing
        them later could leave their common line with a vertex the tube dropped."""
        out = np.zeros(len(self.labels), bool)
        on = np.zeros(len(self.V), bool)
        on[self.T[slow[self.region]]] = True
        near = [k for k in np.flatnonzero(~slow & ~flat).tolist()
                if any(on[loop].any() for loop in self.loops[k])]
        if not near:
            return out
        keep, decided = self.kind == CORNER, np.zeros(len(self.V), bool)
        sizes = np.bincount(self.region, minlength=len(self.labels))
        for k in sorted(near, key=lambda k: -sizes[k]):
            for loop in self.loops[k]:
                self._lines(loop, keep, decided)
            try:
                self._built(k, False, keep)
            except _Unfit:
                out[k] = True
                if sizes[slow | out].sum() > SLOW_SHARE * len(self.T):
                    break                       # the whole mesh is collapsed anyway
        return out

    def _classes(self):
        """(flat (K,), disk (K,)): the regions ear-clipped, and the curved ones mapped."""
        V, T, tol = self.V, self.T, self.tol
        K = len(self.labels)
        flat, disk = np.zeros(K, bool), np.zeros(K, bool)
        self.frames = {}
        for k in range(K):
            tri = T[self.region == k]
            ids = np.unique(tri)
            c = V[ids].mean(axis=0)
            normal = np.linalg.svd(V[ids] - c, full_matrices=False)[2][-1]
            area = np.cross(V[tri[:, 1]] - V[tri[:, 0]], V[tri[:, 2]] - V[tri[:, 0]]).sum(axis=0)
            if area @ normal < 0:
                normal = -normal
            flat[k] = (np.abs((V[ids] - c) @ normal).max() <= max(0.5 * tol, 1e-9 * self.size)
                       and (self.normals[self.region == k] @ normal).min() > FLAT_TURN_COS)
            self.frames[k] = normal
            # Euler characteristic 1: every edge twice but the outline's once
            edges = (3 * len(tri) + sum(len(loop) for loop in self.loops[k])) // 2
            disk[k] = (len(self.loops[k]) == 1 and len(ids) - edges + len(tri) == 1
                       and len(ids) > len(self.loops[k][0]))   # a vertex inside to refine
        return flat, disk

    def _collapsed_alone(self, mask, keep, decided):
        """(triangles (original ids), their labels) of the triangles `mask` collapsed on
        their own, the vertices `keep` staying, the others `decided` (on lines decided
        before) going first."""
        V, T = self.V, self.T
        ids, sub = np.unique(T[mask], return_inverse=True)
        S = _collapsed(V[ids], sub.reshape(-1, 3), self.labels[self.region[mask]], self.tol,
                       keep[ids], (decided & ~keep)[ids])
        return ids[S.triangles], S.labels

    def _by_region(self, tris, labels, mask):
        """{region index: its triangles} of triangles `tris` with `labels` from
        _collapsed_alone(mask)."""
        region = np.searchsorted(self.labels, labels)
        return {int(k): tris[region == k] for k in np.unique(self.region[mask])}

    def _far_regions(self, parts, regions):
        """The regions among `regions` with a vertex beyond MAX_FAR tolerances of their
        triangles in `parts` (see _far_labels)."""
        if not regions:
            return []
        tris = [parts[k] for k in regions]
        T2 = np.concatenate(tris).astype(np.int64)
        lab2 = np.repeat(regions, [len(t) for t in tris])
        mask = np.isin(self.region, regions)
        return _far_labels(self.V, self.T[mask], self.region[mask], T2, lab2,
                           MAX_FAR * self.tol)

    def _built(self, k, flat, keep):
        """Region k's triangles from its outline's vertices `keep` (_Unfit if it fails)."""
        loops = [[v for v in loop if keep[v]] for loop in self.loops[k]]
        if min(len(loop) for loop in loops) < 3:
            raise _Unfit
        return self._flat(k, loops) if flat else self._curved(k, loops[0])

    def _lines(self, loop, keep, decided):
        """Decide the kept vertices of the lines of one boundary loop (Douglas-Peucker
        within the tolerance between corners; a loop without corners keeps three or more)."""
        corners = [i for i, v in enumerate(loop) if self.kind[v] == CORNER]
        if not corners:
            if decided[loop[0]]:
                return
            P = self.V[loop]               # from the vertex farthest from the centre
            first = int(np.argmax(np.linalg.norm(P - P.mean(axis=0), axis=1)))
            loop = loop[first:] + loop[:first]
            P = self.V[loop]
            far = int(np.argmax(np.linalg.norm(P - P[0], axis=1)))
            if far == 0:
                raise _Unfit
            chain = loop + [loop[0]]
            mask = np.zeros(len(chain), bool)
            for lo, hi in ((0, far), (far, len(loop))):
                mask[lo:hi + 1] |= _douglas_peucker(self.V[chain[lo:hi + 1]], self.tol)
            if np.count_nonzero(mask[:-1]) < 3:
                d = segment_distance(P, P[0], P[far])
                d[[0, far]] = -1
                mask[int(np.argmax(d))] = True
            keep[np.array(loop)[mask[:-1]]] = True
            decided[loop] = True
            return
        start = corners[0]
        loop = loop[start:] + loop[:start] + [loop[start]]
        cut = [i - start if i >= start else i - start + len(loop) - 1 for i in corners]
        cut = sorted(cut) + [len(loop) - 1]
        for lo, hi in zip(cut, cut[1:]):
            chain = loop[lo:hi + 1]
            if len(chain) < 3 or decided[chain[1]]:
                continue
            mask = _douglas_peucker(self.V[chain], self.tol)
            keep[np.array(chain)[mask]] = True
            decided[chain[1:-1]] = True

    def _flat(self, k, loops):
        """Ear clipping of a flat region's outline (holes bridged) in its plane."""
        normal = self.frames[k]
        u = unit(np.cross(normal, np.eye(3)[np.argmin(np.abs(normal))]))
        w = np.cross(normal, u)
        xy = [self.V[loop] @ np.c_[u, w] for loop in loops]
        _check_simple(xy)
        areas = np.array([_signed_area(p) for p in xy])
        outers = np.flatnonzero(areas > 0)      # each piece's outline; holes run clockwise
        if not len(outers):
            raise _Unfit
        home = {i: [] for i in outers.tolist()}
        for i in np.flatnonzero(areas <= 0).tolist():
            around = [j for j in outers.tolist() if _inside(xy[i][0], xy[j])]
            if not around:
                raise _Unfit
            home[min(around, key=lambda j: areas[j])].append(i)
        out = []
        for i, holes in home.items():
            ring, pts = list(loops[i]), xy[i]
            holes = sorted(holes, key=lambda h: -xy[h][:, 0].max())
            for done, h in enumerate(holes):
                ring, pts = _bridged(ring, pts, loops[h], xy[h],
                                     [xy[j] for j in holes[done + 1:]])
            out.append(_ear_clipped(ring, pts))
        # Delaunay in the plane: ear clipping fans out from reflex corners, and the
        # region's float32 rounding tilts its triangles beyond delaunay_flips' flatness
        at = {v: p for loop, p in zip(loops, xy) for v, p in zip(loop, p.tolist())}
        T = [list(t) for t in np.concatenate(out).tolist()]
        edges = _edge_map(T)

        def should(f, g, a, b, c, d):
            A, B, C, D = at[a], at[b], at[c], at[d]
            return (_turn(A, D, C) > 0 and _turn(B, C, D) > 0
                    and _angle2(A, C, B) + _angle2(A, D, B) > math.pi + 1e-12)
        _lawson(T, edges, [e for e, fs in edges.items() if len(fs) == 2], should)
        return np.array(T, np.int64).reshape(-1, 3)

    def _curved(self, k, boundary):
        """Triangles of a curved disk region with outline `boundary` (its kept vertices):
        in Tutte's harmonic map the farthest interior vertex of every triangle that is too
        far from the vertices inside it (MAX_FAR, RMS_FAR), turned away or flat goes in."""
        V, T, tol = self.V, self.T, self.tol
        tri = T[self.region == k]
        loop = np.array(self.loops[k][0])
        ids = np.unique(tri)
        local = np.full(len(V), -1)
        local[ids] = np.arange(len(ids))
        L = local[tri]
        m = len(ids)
        i = L[:, [0, 1, 2, 1, 2, 0]].ravel()
        j = L[:, [1, 2, 0, 0, 1, 2]].ravel()
        W = csr_matrix((np.ones(len(i)), (i, j)), (m, m))
        W.data[:] = 1.0
        on_rim = np.zeros(m, bool)
        on_rim[local[loop]] = True
        # the outline on the polygon of its kept vertices on the unit circle (by arc
        # length), so every interior vertex maps inside it
        step = np.linalg.norm(V[np.roll(loop, -1)] - V[loop], axis=1)
        arc = np.r_[0.0, np.cumsum(step)]
        corner = np.flatnonzero(np.isin(loop, boundary))
        at = np.r_[arc[corner], arc[-1] + arc[corner[0]]]
        ring = np.c_[np.cos(2 * np.pi * at / arc[-1]), np.sin(2 * np.pi * at / arc[-1])]
        s = np.where(arc[:-1] < at[0], arc[:-1] + arc[-1], arc[:-1])
        seg = np.clip(np.searchsorted(at, s, side="right") - 1, 0, len(corner) - 1)
        f = ((s - at[seg]) / (at[seg + 1] - at[seg]))[:, None]
        uv = np.zeros((m, 2))
        uv[local[loop]] = (1 - f) * ring[seg] + f * ring[seg + 1]
        inner = np.flatnonzero(~on_rim)
        if len(inner):
            Lap = diags(np.asarray(W.sum(axis=1)).ravel()) - W
            rhs = W[inner][:, local[loop]] @ uv[local[loop]]
            uv[inner] = np.asarray(spsolve(Lap[inner][:, inner].tocsc(), rhs)).reshape(-1, 2)
            if not np.all(np.isfinite(uv)):
                raise _Unfit
        around = np.zeros((m, 3))
        for c in range(3):
            np.add.at(around, L[:, c], self.normals[self.region == k])
        rim = local[np.array(boundary)]
        by_rim = on_rim.copy()
        for _ in range(RIM_RINGS - 1):
            by_rim |= (W @ by_rim.astype(float)) > 0
        X = V[ids]
        mesh = _Surface(uv, X, around, rim, self.min_area)
        # the vertices that measure and refine: those RIM_RINGS edges or more off the
        # outline (Douglas-Peucker keeps the outline; a vertex inserted next to a line
        # that moves would flip its small triangle early)
        probe = inner[~by_rim[inner]] if np.any(~by_rim[inner]) else inner
        added = np.zeros(m, bool)
        last, folds_before = None, math.inf
        for _ in range(MAX_INSERTS):
            S = np.array(mesh.T, np.int64)
            A, B, C = X[S[:, 0]], X[S[:, 1]], X[S[:, 2]]
            n3 = np.cross(B - A, C - A)
            size = np.linalg.norm(n3, axis=1)
            ref = around[S].sum(axis=1)
            bad = (size <= self.min_area) | (np.einsum("ij,ij->i", n3, ref) <= 0)
            # folded or flat triangles that a round of insertions did not make fewer only
            # multiply with more (sh2's, counter's curved disks): collapsed instead (a
            # second or third round made none fewer on sh2, TR12J, counter or the tests'
            # meshes: one of them went from 24 to 33 folds)
            folds = int(np.count_nonzero(bad))
            if folds and folds >= folds_before:
                raise _Unfit
            folds_before = folds
            if last is None:
                where = _locate(uv[probe], uv[S])[0]
            else:       # a point whose triangle changed is in one of the changed ones
                same = np.zeros(len(S), bool)
                same[:len(last)] = (S[:len(last)] == last).all(axis=1)
                moved = np.flatnonzero(~same[where])
                changed = np.flatnonzero(~same)
                where[moved] = changed[_locate(uv[probe[moved]], uv[S[changed]])[0]]
            last = S
            nz = np.maximum(size, 1e-300)[:, None]
            dist, _ = triangle_fit(X[probe], A[where], B[where], C[where], (n3 / nz)[where])
            worst = np.full(len(S), -1.0)
            np.maximum.at(worst, where, dist)
            mean = np.bincount(where, dist * dist, len(S)) / np.maximum(
                np.bincount(where, minlength=len(S)), 1)
            bad |= (worst > MAX_FAR * tol) | (mean > (RMS_FAR * tol) ** 2)
            if not bad.any():
                return ids[S]
            # the farthest vertex in each bad triangle; none inside: the vertex nearest
            # its centre in the map
            can = ~added[probe] & bad[where]
            pick = np.zeros(len(S), np.int64) - 1
            if can.any():
                c = np.flatnonzero(can)
                order = c[np.lexsort((-dist[c], where[c]))]
                first = np.r_[True, where[order][1:] != where[order][:-1]]
                pick[where[order][first]] = probe[order][first]
            lacking = np.flatnonzero(bad & (pick < 0))
            free = probe[~added[probe]]
            if len(lacking) and len(free):
                centre = uv[S[lacking]].mean(axis=1)
                pick[lacking] = free[np.argmin(np.linalg.norm(
                    uv[free][None] - centre[:, None], axis=2), axis=1)]
            pick = np.unique(pick[pick >= 0])
            hint = dict(zip(probe.tolist(), where.tolist()))
            if not any([mesh.insert(p, hint[p]) for p in pick.tolist()]):
                raise _Unfit
            added[pick] = True
        raise _Unfit


class _Surface:
    """A triangulation (local vertex ids, counter-clockwise in the map `uv`) of a curved disk
    region: its outline fanned, points inserted by splitting the triangle holding them,
    every edge flipped toward the Delaunay triangulation of the surface (the two angles
    across it in space add up to at most pi) where the map stays a triangulation."""

    def __init__(self, uv, X, around, ring, min_area):
        self.uv, self.Q, self.P, self.min_area = uv, uv.tolist(), X.tolist(), min_area
        self.N = around.tolist()
        r = [int(x) for x in ring]
        self.T = [[r[0], r[i], r[i + 1]] for i in range(1, len(r) - 1)]
        self.edges = _edge_map(self.T)
        _lawson(self.T, self.edges, [e for e, fs in self.edges.items() if len(fs) == 2],
                self._should)

    def _should(self, f, g, a, b, c, d):
        Q, P = self.Q, self.P
        if _turn(Q[a], Q[d], Q[c]) <= 0 or _turn(Q[b], Q[c], Q[d]) <= 0:
            return False                               # not convex in the map
        if not (self._facing(a, d, c) and self._facing(b, c, d)):
            return False                               # the new pair would fold or be flat
        if not (self._facing(a, b, c) and self._facing(b, a, d)):
            return True                                # the old pair folds
        return _angle(P[a], P[c], P[b]) + _angle(P[a], P[d], P[b]) > math.pi + 1e-12

    def _facing(self, a, b, c):
        """Whether triangle abc is no sliver and faces the way the surface does at its
        corners (the sums of the region's normals there)."""
        P, N = self.P, self.N
        n = _normal(P[a], P[b], P[c])
        return _norm(n) > self.min_area and _dot(n, _add3(N[a], N[b], N[c])) > 0

    def insert(self, p, f):
        """Split the triangle holding point p (f, if it still does) in three, or the two
        on the edge p lies on in two each, and flip around it; False when p lies on the
        outline (it cannot go in)."""
        Q = self.Q
        a, b, c = self.T[f]
        lam = min(_turn(Q[a], Q[b], Q[p]), _turn(Q[b], Q[c], Q[p]), _turn(Q[c], Q[a], Q[p]))
        if lam <= 0:
            where, lam = _locate(self.uv[[p]], self.uv[np.array(self.T)])
            f, lam = int(where[0]), lam[0]
        a, b, c = self.T[f]
        turns = [_turn(Q[a], Q[b], Q[p]), _turn(Q[b], Q[c], Q[p]), _turn(Q[c], Q[a], Q[p])]
        k = int(np.argmin(turns))
        if turns[k] > 1e-12 * _turn(Q[a], Q[b], Q[c]):
            self._split3(p, f)
            return True
        a, b, c = self.T[f][k:] + self.T[f][:k]                # p on edge ab
        fs = self.edges[frozenset((a, b))]
        if len(fs) != 2:
            return False
        g = fs[0] if fs[1] == f else fs[1]
        d = next(x for x in self.T[g] if x not in (a, b))      # g is b, a, d
        f2, g2 = len(self.T), len(self.T) + 1
        self.T[f], self.T[g] = [a, p, c], [b, p, d]
        self.T += [[p, b, c], [p, a, d]]
        del self.edges[frozenset((a, b))]
        self._handed_over((((b, c), f, f2), ((a, d), g, g2)))
        self.edges[frozenset((a, p))] = [f, g2]
        self.edges[frozenset((p, b))] = [f2, g]
        self.edges[frozenset((p, c))] = [f, f2]
        self.edges[frozenset((p, d))] = [g, g2]
        _lawson(self.T, self.edges, [frozenset(e) for e in ((a, c), (c, b), (b, d), (d, a))],
                self._should)
        return True

    def _handed_over(self, moves):
        """Each ((x, y), old, new): edge xy now borders triangle `new` where it bordered `old`."""
        for (x, y), old, new in moves:
            key = frozenset((x, y))
            self.edges[key] = [new if q == old else q for q in self.edges[key]]

    def _split3(self, p, f):
        a, b, c = self.T[f]
        g, h = len(self.T), len(self.T) + 1
        self.T[f] = [a, b, p]
        self.T += [[b, c, p], [c, a, p]]
        self._handed_over((((b, c), f, g), ((c, a), f, h)))
        self.edges[frozenset((a, p))] = [f, h]
        self.edges[frozenset((b, p))] = [f, g]
        self.edges[frozenset((c, p))] = [g, h]
        _lawson(self.T, self.edges, [frozenset(e) for e in ((a, b), (b, c), (c, a))],
                self._should)


def _add3(p, q, r):
    return p[0] + q[0] + r[0], p[1] + q[1] + r[1], p[2] + q[2] + r[2]


def _turn(a, b, c):
    """Twice the signed area of the 2D triangle abc (2-lists of floats)."""
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _angle2(p, q, r):
    """The angle at q of the 2D triangle pqr."""
    u0, u1, v0, v1 = p[0] - q[0], p[1] - q[1], r[0] - q[0], r[1] - q[1]
    return math.atan2(abs(u0 * v1 - u1 * v0), u0 * v0 + u1 * v1)


def _locate(points, tris):
    """(triangle index (k,), its smallest barycentric (k,)) of each 2D point in the
    triangles tris (t, 3, 2): the one it lies in, or is nearest to lying in."""
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    area = _cross2(b - a, c - a)
    where = np.empty(len(points), np.int64)
    best = np.empty(len(points))
    for i in range(0, len(points), 256):
        q = points[i:i + 256, None, :]
        lam = np.minimum(np.minimum(_cross2(c - b, q - b), _cross2(a - c, q - c)),
                         _cross2(b - a, q - a)) / area
        where[i:i + 256] = np.argmax(lam, axis=1)
        best[i:i + 256] = lam[np.arange(len(lam)), where[i:i + 256]]
    return where, best


def _douglas_peucker(P, tol):
    """Which points of the polyline P (k, 3) Douglas-Peucker keeps within `tol` (both ends)."""
    keep = np.zeros(len(P), bool)
    keep[[0, -1]] = True
    todo = [(0, len(P) - 1)]
    while todo:
        i, j = todo.pop()
        if j - i < 2:
            continue
        d = segment_distance(P[i + 1:j], P[i], P[j])
        k = int(np.argmax(d))
        if d[k] > tol:
            keep[i + 1 + k] = True
            todo += [(i, i + 1 + k), (i + 1 + k, j)]
    return keep


def _signed_area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _cross2(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _crossing(p, q, A, B):
    """Whether segment pq properly crosses any of the segments A[i] B[i] (2D), or passes
    through one of their ends A[i] (a bridge along a row of holes' rightmost vertices)."""
    d1 = _cross2(q - p, A - p)
    d2 = _cross2(q - p, B - p)
    d3 = _cross2(B - A, p - A)
    d4 = _cross2(B - A, q - A)
    if np.any((d1 * d2 < 0) & (d3 * d4 < 0)):
        return True
    pq = q - p
    t = (A - p) @ pq
    on = (np.abs(d1) <= 1e-12 * (pq @ pq)) & (t > 0) & (t < pq @ pq)
    return bool(np.any(on & ~np.all(A == p, axis=1) & ~np.all(A == q, axis=1)))


def _check_simple(loops):
    """_Unfit unless the 2D loops' edges meet only at shared ends (Douglas-Peucker may
    cut a corner across another part of the outline)."""
    A = np.concatenate(loops)
    B = np.concatenate([np.roll(p, -1, axis=0) for p in loops])
    d1 = _cross2(B - A, A[:, None] - A)          # [i, j]: end A[i] against edge j
    d2 = _cross2(B - A, B[:, None] - A)
    if np.any((d1 * d2 < 0) & (d1.T * d2.T < 0)):
        raise _Unfit


def _inside(p, poly):
    """Even-odd test of point p in polygon poly (k, 2)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    up = (a[:, 1] > p[1]) != (b[:, 1] > p[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (p[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(up & (x > p[0])) % 2)


def _bridged(ring, pts, hole, hxy, later):
    """The outer ring joined to a hole (its rightmost vertex to the nearest visible ring
    vertex) by a bridge walked both ways. The bridge leaves the ring inside the corner it
    starts from: a vertex an earlier bridge doubled is taken at the copy whose corner holds
    it (at the other, the ring would cross itself there and ear clipping find no ear)."""
    i = int(np.argmax(hxy[:, 0]))
    M = hxy[i]
    segs = [(pts, np.roll(pts, -1, axis=0)), (hxy, np.roll(hxy, -1, axis=0))]
    segs += [(h, np.roll(h, -1, axis=0)) for h in later]
    A = np.concatenate([s[0] for s in segs])
    B = np.concatenate([s[1] for s in segs])
    lo = np.array([h.min(axis=0) for h in later]).reshape(-1, 2)
    hi = np.array([h.max(axis=0) for h in later]).reshape(-1, 2)
    for c in np.argsort(np.linalg.norm(pts - M, axis=1)):
        mid = 0.5 * (pts[c] + M)
        boxed = np.flatnonzero(np.all((lo <= mid) & (mid <= hi), axis=1))
        if not _into_corner(pts[c - 1], pts[c], pts[(c + 1) % len(pts)], M) or _crossing(
                M, pts[c], A, B) or _inside(mid, hxy) or any(_inside(mid, later[h])
                                                             for h in boxed.tolist()):
            continue
        c = int(c)
        ring = ring[:c + 1] + hole[i:] + hole[:i + 1] + ring[c:]
        pts = np.concatenate([pts[:c + 1], hxy[i:], hxy[:i + 1], pts[c:]])
        return ring, pts
    raise _Unfit


def _into_corner(a, p, b, m):
    """Whether m lies strictly inside the corner at p of a counter-clockwise ring a, p, b."""
    e0, e1, u = a - p, b - p, m - p
    left, right = _cross2(e1, u) > 0, _cross2(u, e0) > 0
    return bool(left and right) if _cross2(e1, e0) > 0 else bool(left or right)


def _ear_clipped(ring, pts):
    """Triangles (k - 2, 3) of the counter-clockwise polygon `ring` (ids) at `pts` (k, 2):
    ears cut walking on from the last one; only vertices that are not convex can lie in
    a convex corner's triangle (the outline meets it there first)."""
    idx = list(range(len(ring)))
    out = []
    scale = np.ptp(pts, axis=0).max() ** 2
    pos = 0
    while len(idx) > 3:
        P = pts[idx]
        prev, nxt = np.roll(P, 1, axis=0), np.roll(P, -1, axis=0)
        convex = _cross2(P - prev, nxt - P) > 1e-14 * scale
        blockers = P[~convex]
        for step in range(len(idx)):
            i = (pos + step) % len(idx)
            if not convex[i]:
                continue
            a, b, d = prev[i], P[i], nxt[i]
            rest = blockers[~(np.all(blockers == a, axis=1) | np.all(blockers == b, axis=1)
                              | np.all(blockers == d, axis=1))]
            if np.any((_cross2(b - a, rest - a) >= 0) & (_cross2(d - b, rest - b) >= 0)
                      & (_cross2(a - d, rest - d) >= 0)):
                continue
            out.append((ring[idx[i - 1]], ring[idx[i]], ring[idx[(i + 1) % len(idx)]]))
            del idx[i]
            pos = max(i - 1, 0)
            break
        else:
            raise _Unfit
    a, b, d = (pts[x] for x in idx)
    if _cross2(b - a, d - b) <= 1e-14 * scale:
        raise _Unfit
    out.append(tuple(ring[x] for x in idx))
    return np.array(out, np.int64).reshape(-1, 3)
