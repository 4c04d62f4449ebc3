"""The deformation handle of Date & Onosato (4.2): prisms around a simplified mesh.

Every simplified triangle is offset both ways along its normal into a triangular prism;
every simplified edge that is not inside one planar region becomes a 3-vertex edge prism
(two copies along the normals of its triangles, one along their mean, on the other side),
which fills the wedge between the triangle prisms there. Each original vertex is bound
once to the one prism of its own region that holds it, by Warren's coordinates; a
simplified vertex is bound to itself (it is one of its own representative vertices).
A deformation then moves the handle points and the mesh follows by one sparse product.
"""
from typing import NamedTuple

import numpy as np
from scipy.sparse import csr_matrix
from scipy.spatial import cKDTree

from .regions import edge_triangles, triangle_normals, vertex_regions
from .prism_coords import coordinates_from_planes, face_planes, vertex_volumes

GROW_STEPS = 6        # offsets double at most this many times to take in their vertices
MIN_OFFSET = 0.1      # the smallest offset, as a fraction of the element's longest edge
MIN_TURN = 1e-3       # radians: a simplified edge turning less gets no edge prism
FULL_SEARCH = 64      # a region with at most this many elements is searched whole
CHUNK = 4096          # points scored at once (memory)
ON_FACE = 1e-12       # x the mesh size: a vertex this far outside its prism's face is on it


class Handle(NamedTuple):
    points: np.ndarray    # (H,3) handle vertex positions
    owner: np.ndarray     # (H,) the original vertex whose representative each point is
    weights: object       # (N,H) scipy.sparse.csr_matrix: Warren coordinates, rows sum to 1
    prisms: np.ndarray    # (P,6,3) the prisms (for drawing and checks)
    outside: int          # vertices held by no prism (their coordinates are clamped)

    def displace(self, moves):
        """Vertex displacements (N,3) from handle point displacements (H,3): eq. 2.3 as
        x + B (P' - P), so a vertex whose prism does not move stays bit-identical."""
        return self.weights @ moves


def segment_distance(x, a, b):
    """Distance from points x (..., 3) to the segments ab (broadcast against x)."""
    ab = b - a
    t = np.clip(np.einsum("...k,...k", x - a, ab) / np.maximum(np.einsum("...k,...k", ab, ab),
                                                             1e-300), 0.0, 1.0)
    return np.linalg.norm(x - a - t[..., None] * ab, axis=-1)


def triangle_fit(x, A, B, C, n):
    """(distance from x to triangle ABC, smallest barycentric of x's projection)."""
    h = np.einsum("...k,...k", x - A, n)
    q = x - h[..., None] * n
    area = np.einsum("...k,...k", np.cross(B - A, C - A), n)
    flat = np.abs(area) <= 1e-300                       # degenerate: only its edges count
    area = np.where(flat, 1.0, area)
    lam = np.stack([np.einsum("...k,...k", np.cross(C - B, q - B), n),
                    np.einsum("...k,...k", np.cross(A - C, q - C), n),
                    np.einsum("...k,...k", np.cross(B - A, q - A), n)], -1) / area[..., None]
    inside = (lam.min(-1) >= 0) & ~flat
    edge = np.minimum(np.minimum(segment_distance(x, A, B), segment_distance(x, B, C)),
                      segment_distance(x, C, A))
    return np.where(inside, np.abs(h), edge), lam


class _TriangleDistance:
    """Exact point-triangle distances (as triangle_fit's) with every per-triangle quantity
    computed once: the barycentric coordinates of a point's projection are affine in the
    point (rows G, offsets o), and so is its parameter along each edge."""

    def __init__(self, A, B, C, n):
        self.n, self.nA = n, np.einsum("ij,ij->i", n, A)
        area = np.einsum("ij,ij->i", np.cross(B - A, C - A), n)
        flat = np.abs(area) <= 1e-300
        inv = np.where(flat, 0.0, 1.0 / np.where(flat, 1.0, area))[:, None]
        self.flat = flat
        self.G = np.stack([np.cross(n, C - B), np.cross(n, A - C), np.cross(n, B - A)], 1) \
            * inv[:, None]
        self.o = -np.einsum("tij,tij->ti", self.G, np.stack([B, C, A], 1))
        self.P = np.stack([A, B, C], 1)
        self.E = np.stack([B - A, C - B, A - C], 1)
        length2 = np.einsum("tij,tij->ti", self.E, self.E)
        self.W = self.E / np.maximum(length2, 1e-300)[..., None]
        self.w = np.einsum("tij,tij->ti", self.W, self.P)

    def __call__(self, x, c):
        """Distances (N, k) of points x (N, 1, 3) to the triangles c (N, k)."""
        x = x[:, 0]
        h = np.einsum("nkj,nj->nk", self.n[c], x) - self.nA[c]
        lam = np.einsum("nkij,nj->nki", self.G[c], x) + self.o[c]
        inside = (lam.min(-1) >= 0) & ~self.flat[c]
        t = np.clip(np.einsum("nkij,nj->nki", self.W[c], x) - self.w[c], 0.0, 1.0)
        foot = self.P[c] + t[..., None] * self.E[c]
        edge = np.sqrt(((x[:, None, None, :] - foot) ** 2).sum(-1).min(-1))
        return np.where(inside, np.abs(h), edge)


def _best(x, elements, centres, fit, k=32):
    """For each point x (N,3), the one of `elements` (indices) it fits best (smallest
    `fit(x, element)`): all of them when they are few, else the k nearest by centre."""
    if len(elements) <= FULL_SEARCH:
        cand = np.broadcast_to(elements, (len(x), len(elements)))
    else:
        _, j = cKDTree(centres[elements]).query(x, k=k)
        cand = elements[j]
    best = np.empty(len(x), np.int64)
    for i in range(0, len(x), CHUNK):
        c = cand[i:i + CHUNK]
        score = fit(x[i:i + CHUNK, None, :], c)
        best[i:i + CHUNK] = c[np.arange(len(c)), np.argmin(score, axis=1)]
    return best


def _edge_prisms(V, S, SL, planar):
    """Edge prisms: (endpoints (E,2), offset directions (E,3,3), labels (E,2))."""
    ns, _ = triangle_normals(V, S)
    edges, faces = edge_triangles(S)
    two = faces[:, 1] >= 0
    edges, faces = edges[two], faces[two]
    la, lb = SL[faces[:, 0]], SL[faces[:, 1]]
    n1, n2 = ns[faces[:, 0]], ns[faces[:, 1]]
    keep = ~((la == lb) & planar[la]) & (np.einsum("ij,ij->i", n1, n2) < np.cos(MIN_TURN))
    edges, faces, la, lb, n1, n2 = (a[keep] for a in (edges, faces, la, lb, n1, n2))
    # convex where the second triangle's far corner is below the first triangle's plane
    far = S[faces[:, 1]]
    far = far[(far != edges[:, :1]) & (far != edges[:, 1:])]
    convex = np.einsum("ij,ij->i", V[far] - V[edges[:, 0]], n1) < 0
    s = np.where(convex, 1.0, -1.0)[:, None]
    mean = n1 + n2
    size = np.linalg.norm(mean, axis=1, keepdims=True)
    # a fold (two triangles back to back, the same corners twice) has no mean normal: its
    # limit, the direction in their plane from the far corner out across the edge
    fold = size[:, 0] <= MIN_TURN
    if fold.any():
        out = np.cross(V[edges[fold, 1]] - V[edges[fold, 0]], n1[fold])
        away = np.einsum("ij,ij->i", V[edges[fold, 0]] - V[far[fold]], out) >= 0
        out *= np.where(away, 1.0, -1.0)[:, None]
        mean[fold], size[fold] = -s[fold] * out, np.linalg.norm(out, axis=1, keepdims=True)
    ok = size[:, 0] > 0                     # none where both triangles are degenerate
    mean = mean[ok] / size[ok]
    dirs = np.stack([s[ok] * n1[ok], s[ok] * n2[ok], -s[ok] * mean], axis=1)
    return edges[ok], dirs, np.stack([la[ok], lb[ok]], 1)


def build_handle(vertices, triangles, labels, planar, simplified):
    """The handle of mesh (vertices, triangles) with region `labels` per triangle,
    `planar[label]` True for planar regions, and `simplified` (triangles in original
    vertex indices, labels) from mesh_simplify.simplify."""
    V = np.asarray(vertices, float)
    S = np.asarray(simplified.triangles, np.int64)
    SL = np.asarray(simplified.labels)
    planar = np.asarray(planar, bool)
    n = len(V)
    regions = vertex_regions(n, triangles, labels)
    keep = np.unique(S)
    free = np.setdiff1d(np.arange(n), keep)
    first = regions.indices[regions.indptr[:-1]]        # a vertex's lowest region

    # triangle prisms
    ns, _ = triangle_normals(V, S)
    A, B, C = V[S[:, 0]], V[S[:, 1]], V[S[:, 2]]
    # edge prisms
    E, dirs, EL = _edge_prisms(V, S, SL, planar)
    Ea, Eb = V[E[:, 0]], V[E[:, 1]]

    # a vertex on two regions goes to the nearest edge prism between those two ...
    edge_of = np.full(n, -1)
    line = free[np.diff(regions.indptr)[free] == 2]
    pair = np.sort(regions.indices[regions.indptr[line][:, None] + np.arange(2)], axis=1)
    for a, b in np.unique(pair, axis=0):
        group = line[(pair[:, 0] == a) & (pair[:, 1] == b)]
        elements = np.nonzero((EL.min(1) == a) & (EL.max(1) == b))[0]
        if len(elements):
            edge_of[group] = _best(V[group], elements, (Ea + Eb) / 2,
                                   lambda x, c: segment_distance(x, Ea[c], Eb[c]))
    # ... any other to the nearest simplified triangle of its (lowest) region ...
    rest = free[edge_of[free] < 0]
    tri_of = np.full(n, -1)
    distance = _TriangleDistance(A, B, C, ns)
    for r in np.unique(first[rest]):
        group = rest[first[rest] == r]
        elements = np.nonzero(SL == r)[0]
        tri_of[group] = _best(V[group], elements if len(elements) else np.arange(len(S)),
                              (A + B + C) / 3, distance)
    # ... or, outside its footprint, to the edge prism across the nearest side
    if len(E):
        _, lam = triangle_fit(V[rest], A[tri_of[rest]], B[tri_of[rest]], C[tri_of[rest]],
                               ns[tri_of[rest]])
        out = lam.min(1) < 0
        side = np.argmin(lam, axis=1)
        corners = S[tri_of[rest]]
        u = corners[np.arange(len(rest)), (side + 1) % 3]
        v = corners[np.arange(len(rest)), (side + 2) % 3]
        key = E[:, 0] * n + E[:, 1]
        order = np.argsort(key)
        want = np.minimum(u, v) * n + np.maximum(u, v)
        pos = np.clip(np.searchsorted(key[order], want), 0, len(E) - 1)
        hit = out & (key[order][pos] == want)
        edge_of[rest[hit]], tri_of[rest[hit]] = order[pos[hit]], -1

    return _bind(V, S, ns, E, dirs, keep, tri_of, edge_of)


def _longest_edge(prism_base):
    return np.max(np.linalg.norm(prism_base - np.roll(prism_base, 1, axis=1), axis=2), axis=1)


def _bind(V, S, ns, E, dirs, keep, tri_of, edge_of):
    """Size the prisms to hold their vertices and compute every vertex's coordinates."""
    nt, ne = len(S), len(E)
    tri_base = V[S]                                         # (T,3,3)
    edge_base = np.concatenate([np.repeat(V[E[:, :1]], 3, 1), np.repeat(V[E[:, 1:]], 3, 1)], 1) \
        if ne else np.zeros((0, 6, 3))
    offset_dirs = np.concatenate([np.concatenate([-ns[:, None].repeat(3, 1), ns[:, None].repeat(3, 1)], 1),
                                  np.concatenate([dirs, dirs], 1) if ne else np.zeros((0, 6, 3))])
    base = np.concatenate([np.concatenate([tri_base, tri_base], 1), edge_base])
    h = MIN_OFFSET * np.concatenate([_longest_edge(tri_base),
                                     np.linalg.norm(V[E[:, 1]] - V[E[:, 0]], axis=1) if ne else []])
    members = np.nonzero((tri_of >= 0) | (edge_of >= 0))[0]
    which = np.where(tri_of[members] >= 0, tri_of[members], nt + edge_of[members])
    x = V[members]
    # triangle prisms: at least as thick as their farthest vertex, with a margin
    t = which < nt
    dist = np.abs(np.einsum("ij,ij->i", x[t] - V[S[which[t], 0]], ns[which[t]]))
    need = np.zeros(nt + ne)
    np.maximum.at(need, which[t], 1.5 * dist)
    h = np.maximum(h, need)
    # a vertex on a side face (rounding puts it 1e-15 outside) is on it: doubling the
    # offset does not move side faces, and the clamped coordinates are those of the face
    on_face = -ON_FACE * float(np.linalg.norm(np.ptp(V, axis=0)))
    for _ in range(GROW_STEPS + 1):
        prisms = base + h[:, None, None] * offset_dirs
        normals, points = face_planes(prisms)
        coords, depth = coordinates_from_planes(normals, points, vertex_volumes(normals), which, x)
        short = np.unique(which[depth < on_face])
        if len(short) == 0:
            break
        h[short] *= 2.0
    outside = int(np.count_nonzero(depth < on_face))

    owner = np.concatenate([keep, S[:, [0, 1, 2, 0, 1, 2]].reshape(-1),
                            E[:, [0, 0, 0, 1, 1, 1]].reshape(-1) if ne else []]).astype(np.int64)
    points = np.concatenate([V[keep], prisms.reshape(-1, 3)])
    rows = np.concatenate([keep, np.repeat(members, 6)])
    cols = np.concatenate([np.arange(len(keep)),
                           (len(keep) + 6 * which[:, None] + np.arange(6)).reshape(-1)])
    vals = np.concatenate([np.ones(len(keep)), coords.reshape(-1)])
    weights = csr_matrix((vals, (rows, cols)), shape=(len(V), len(points)))
    return Handle(points, owner, weights, prisms, outside)
