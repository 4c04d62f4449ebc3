"""Segmentation of a triangle mesh into regions by dihedral angle (Date & Onosato, 5.1).

An edge is a feature edge when the normals of its two triangles turn by more than the
feature angle; a region is a set of triangles connected across non-feature edges.
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


def triangle_normals(vertices, triangles):
    """(unit normals (M,3), areas (M,)) of the triangles; degenerate ones get a zero normal."""
    p = np.asarray(vertices, float)[triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1.0)[:, None], 0.5 * length


def weld(vertices, triangles):
    """(vertices, triangles, inverse): the vertices at exactly the same place made one (a
    PLY or OFF exporter that writes each face's own corners leaves a closed part as loose
    faces), kept in the order of their first use; vertices[inverse] gives the input's back.
    The triangles keep their order."""
    V = np.asarray(vertices, float).reshape(-1, 3)
    T = np.asarray(triangles, np.int64).reshape(-1, 3)
    _, first, inverse = np.unique(V, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if len(first) == len(V):
        return V, T, np.arange(len(V))
    order = np.argsort(first)                       # welded vertices in first-use order
    rank = np.empty(len(first), np.int64)
    rank[order] = np.arange(len(first))
    return V[first[order]], rank[inverse][T], rank[inverse]


def edge_triangles(triangles):
    """(edges (E,2) sorted vertex pairs, faces (E,2) the triangles on each side, -1 on a
    border). An edge with more than two triangles (non-manifold) keeps its first two."""
    T = np.asarray(triangles, np.int64)
    m = len(T)
    e = np.sort(np.stack([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]], axis=1).reshape(-1, 2), axis=1)
    face = np.repeat(np.arange(m), 3)
    n = int(T.max()) + 1 if m else 0
    keys, inverse = np.unique(e[:, 0] * n + e[:, 1], return_inverse=True)  # rows in order
    edges = np.c_[keys // n, keys % n] if m else np.zeros((0, 2), np.int64)
    inverse = inverse.reshape(-1)
    order = np.argsort(inverse, kind="stable")
    first = np.searchsorted(inverse[order], np.arange(len(edges)))
    count = np.bincount(inverse, minlength=len(edges))
    faces = np.full((len(edges), 2), -1, np.int64)
    faces[:, 0] = face[order[first]]
    two = count >= 2
    faces[two, 1] = face[order[first[two] + 1]]
    return edges, faces


COPLANAR = 1e-8  # 1 - cos of the angle (1.4e-4 rad) below which two normals are one


def segment(vertices, triangles, feature_angle):
    """Region label (M,) of each triangle, 0..K-1, the largest region first.

    `feature_angle` (radians): adjacent triangles whose normals turn by more than this
    are in different regions.
    """
    normals, _ = triangle_normals(vertices, triangles)
    _, faces = edge_triangles(triangles)
    inner = faces[(faces[:, 1] >= 0)]
    cos = np.einsum("ij,ij->i", normals[inner[:, 0]], normals[inner[:, 1]])
    # coplanar triangles stay together whatever the angle: their normals differ by the
    # rounding of float32 vertices (a FeatureAngle of 1e-66 made each triangle a region)
    smooth = inner[cos >= min(np.cos(feature_angle), 1.0 - COPLANAR)]
    m = len(triangles)
    graph = coo_matrix((np.ones(len(smooth)), (smooth[:, 0], smooth[:, 1])), shape=(m, m))
    _, labels = connected_components(graph, directed=False)
    sizes = np.bincount(labels)
    rank = np.empty_like(sizes)
    rank[np.argsort(-sizes, kind="stable")] = np.arange(len(sizes))
    return rank[labels]


def region_adjacency(triangles, labels):
    """Set of (a, b) label pairs, a < b, of regions that share an edge."""
    _, faces = edge_triangles(triangles)
    inner = faces[faces[:, 1] >= 0]
    a, b = labels[inner[:, 0]], labels[inner[:, 1]]
    pairs = np.unique(np.sort(np.stack([a, b], 1)[a != b], axis=1), axis=0)
    return {(int(x), int(y)) for x, y in pairs}


def vertex_regions(n_vertices, triangles, labels):
    """Sparse (N, K) incidence: entry (v, r) is non-zero when vertex v is on region r."""
    T = np.asarray(triangles, np.int64)
    rows = T.reshape(-1)
    cols = np.repeat(labels, 3)
    k = int(labels.max()) + 1 if len(labels) else 0
    m = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_vertices, k)).tocsr()
    m.sum_duplicates()
    return m


def region_colours(labels):
    """A distinct float RGB per region label (golden-ratio hues), one per triangle."""
    labels = np.asarray(labels)
    hue = (np.arange(labels.max() + 1) * 0.618034) % 1.0
    k = (np.array([5.0, 3.0, 1.0])[None, :] + hue[:, None] * 6.0) % 6.0
    rgb = 0.92 - 0.62 * np.clip(np.minimum(k, 4.0 - k), 0.0, 1.0)
    return [tuple(float(c) for c in rgb[i]) for i in labels]
