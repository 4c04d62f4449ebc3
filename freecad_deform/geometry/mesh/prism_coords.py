"""Warren's barycentric coordinates in convex triangular prisms (Date & Onosato, eq. 2.1-2.2).

A prism is 6 points: a bottom triangle 0, 1, 2 and the top triangle 3, 4, 5 above it.
Every prism vertex is simple (three faces meet there), so eq. 2.1 applies as written.
The weight of vertex i, w_i = det(n_a, n_b, n_c) / prod_k h_k(x) over its three faces,
is multiplied through by the product of all five face distances: the common factor
cancels in eq. 2.2 and what is left, det * (distances to the two faces NOT at i), stays
finite on the faces and at the vertices themselves.
"""
import numpy as np

# faces: bottom, top, and the three side quads (as 4-cycles of prism vertices)
FACES = ((0, 1, 2), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5))
AT = np.array([[0, 2, 4], [0, 2, 3], [0, 3, 4], [1, 2, 4], [1, 2, 3], [1, 3, 4]])
AWAY = np.array([[1, 3], [1, 4], [1, 2], [0, 3], [0, 4], [0, 2]])


def face_planes(prisms):
    """(outward unit normals (M,5,3), a point on each face (M,5,3)) of prisms (M,6,3)."""
    P = np.asarray(prisms, float)
    normals = np.empty((len(P), 5, 3))
    points = np.empty((len(P), 5, 3))
    for f, idx in enumerate(FACES):
        q = P[:, idx]
        if len(idx) == 3:
            n = np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0])
        else:
            n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
        points[:, f] = q.mean(axis=1)
        normals[:, f] = n
    centre = P.mean(axis=1)
    flip = np.einsum("mfk,mfk->mf", normals, points - centre[:, None]) < 0
    normals[flip] *= -1
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    return normals, points


def vertex_volumes(normals):
    """|det| of the three face normals at each prism vertex (M,6): the numerator of eq. 2.1."""
    n = normals[:, AT]                      # (M, 6, 3 faces, 3)
    return np.abs(np.linalg.det(n))


def distances(normals, points, which, x):
    """Distances (N,5) of points x (N,3) inside prism `which` (N,) to its five faces;
    negative outside that face."""
    return np.einsum("nfk,nfk->nf", points[which] - x[:, None], normals[which])


def coordinates(prisms, which, x):
    """Barycentric coordinates (N,6) of points x (N,3) in prisms[which], and the smallest
    face distance of each point (negative: the point is outside its prism).

    Outside a face its distance is clamped to 0, which gives the coordinates of a point
    on that face: continuous, still a convex combination.
    """
    normals, points = face_planes(prisms)
    return coordinates_from_planes(normals, points, vertex_volumes(normals), which, x)


def coordinates_from_planes(normals, points, volumes, which, x):
    """coordinates() with the prisms' planes computed once (see face_planes)."""
    h = distances(normals, points, which, np.asarray(x, float))
    depth = h.min(axis=1)
    h = np.maximum(h, 0.0)
    w = volumes[which] * h[:, AWAY[:, 0]] * h[:, AWAY[:, 1]]
    total = w.sum(axis=1, keepdims=True)
    degenerate = total[:, 0] <= 0
    w[degenerate] = 1.0 / 6.0
    total[degenerate] = 1.0
    return w / total, depth
