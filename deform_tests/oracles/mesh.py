"""Mesh oracles written for the tests (numpy and scipy only, no hypothesis, so FreeCAD's
own runner imports them too): a convex test blob, enclosed volume, the closed 2-manifold
check, plane sections, flipped triangles, and the counts and segments of a mesh cut at
many parallel planes."""
import numpy as np
from scipy.spatial import ConvexHull


def blob(count=500, seed=1):
    """Convex, irregularly triangulated closed mesh: hull of random points on the unit sphere."""
    p = np.random.default_rng(seed).normal(size=(count, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    T = ConvexHull(p).simplices.copy()
    outward = np.einsum("ij,ij->i", np.cross(p[T[:, 1]] - p[T[:, 0]], p[T[:, 2]] - p[T[:, 0]]),
                        p[T[:, 0]]) > 0
    T[~outward] = T[~outward][:, ::-1]
    return p, T


def arrays(mesh):
    """(vertices (N, 3) float, triangles (M, 3) int64) of a FreeCAD Mesh, read through its
    Topology (the tests' own reading, not the add-on's conversion)."""
    points, facets = mesh.Topology
    return (np.array([tuple(p) for p in points], float).reshape(-1, 3),
            np.array(facets, np.int64).reshape(-1, 3))


def volume(V, T):
    """Signed enclosed volume by the divergence theorem."""
    return np.linalg.det(V[T]).sum() / 6


def assert_closed_manifold(V, T, min_area=1e-14):
    """Every directed edge once and its reverse present; every vertex used; no zero area."""
    T = np.asarray(T, np.int64)
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    key = a * len(V) + b
    uniq, counts = np.unique(key, return_counts=True)
    assert counts.max() == 1, f"directed edge {uniq[counts > 1][0] // len(V)}->" \
        f"{uniq[counts > 1][0] % len(V)} used twice"
    assert np.isin(b * len(V) + a, uniq).all(), "open edge"
    assert np.array_equal(np.unique(T), np.arange(len(V))), "unused or missing vertex"
    V = np.asarray(V, float)
    area = np.linalg.norm(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]), axis=1)
    assert area.min() > min_area


def mesh_section(V, T, origin, normal, segments=False):
    """(area, centroid[, (p, q) segment ends]) of the cross-section of a closed, outward-oriented triangle mesh by
    a plane: each crossing triangle gives one segment, oriented along normal x (triangle
    normal) so the outline runs counter-clockwise about `normal` (holes clockwise); then
    the shoelace sums. A vertex on the plane counts as on its positive side."""
    V, T = np.asarray(V, float), np.asarray(T)
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross([0, 0, 1], n) if abs(n[2]) < 0.9 else np.cross([1, 0, 0], n)
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    s = (V - origin) @ n
    pos = (s >= 0)[T]
    cross = pos.any(axis=1) & ~pos.all(axis=1)
    tri, sp = V[T[cross]], s[T[cross]]
    pts = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        sa, sb = sp[:, a], sp[:, b]
        cut = (sa >= 0) != (sb >= 0)
        t = np.where(cut, sa / np.where(cut, sa - sb, 1.0), 0.0)
        pts.append((cut, tri[:, a] + t[:, None] * (tri[:, b] - tri[:, a])))
    ends = np.stack([p for c, p in pts], 1)[np.stack([c for c, p in pts], 1)].reshape(-1, 2, 3)
    p, q = ends[:, 0], ends[:, 1]
    tn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", q - p, np.cross(n, tn)) < 0
    p, q = np.where(flip[:, None], q, p), np.where(flip[:, None], p, q)
    x0, y0 = (p - origin) @ u, (p - origin) @ w
    x1, y1 = (q - origin) @ u, (q - origin) @ w
    c = x0 * y1 - x1 * y0
    area = c.sum() / 2
    if area == 0:
        return (0.0, None, (p, q)) if segments else (0.0, None)
    mx, my = ((x0 + x1) * c).sum() / 6 / area, ((y0 + y1) * c).sum() / 6 / area
    centroid = np.asarray(origin, float) + mx * u + my * w
    return (float(area), centroid, (p, q)) if segments else (float(area), centroid)


def flips(V, X, T):
    """How many triangles T turned over between the vertex arrays V and X."""
    n0 = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    n1 = np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])
    return int(np.count_nonzero(np.einsum("ij,ij->i", n0, n1) <= 0))


def expected_count(V0, T0, origin, n, gap, samples, eps):
    """Triangles after cutting at the planes s = gap * j / samples: 2k + 1 for a triangle
    whose levels span k planes strictly (2k when its middle vertex lies on one of them),
    1 for the others; vertices within eps of a plane count as on it."""
    h = gap / samples
    level = (V0 - origin) @ n / h
    plane = np.clip(np.round(level), 0, samples)
    level = np.where(np.abs(level - plane) * h <= eps, plane, level)
    lo, mid, hi = np.sort(level[T0], axis=1).T
    k = np.clip(np.ceil(hi) - 1, None, samples) - np.clip(np.floor(lo) + 1, 0, None) + 1
    k = np.maximum(k, 0)
    mid_on = (mid == np.round(mid)) & (lo < mid) & (mid < hi) & (0 <= mid) & (mid <= samples)
    return int(np.where(k > 0, 2 * k + 1 - mid_on, 1).sum())


def section_segments(V0, T0, origin, n, level):
    """(p, q) ends of the section of the mesh at s = level: one segment per triangle with
    vertices strictly on both sides (the meshes here have no vertex on a plane)."""
    s = (V0 - origin) @ n - level
    st_ = s[T0]
    cross = (st_.min(axis=1) < 0) & (st_.max(axis=1) > 0)
    ends = []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        a, b = T0[cross, i], T0[cross, j]
        cut = (s[a] < 0) != (s[b] < 0)
        t = np.where(cut, s[a] / np.where(cut, s[a] - s[b], 1.0), np.nan)
        ends.append(V0[a] + t[:, None] * (V0[b] - V0[a]))
    ends = np.stack(ends, 1)
    ok = ~np.isnan(ends[..., 0])
    ends = ends[ok].reshape(-1, 2, 3)
    return ends[:, 0], ends[:, 1]


def distance_to_segments(points, p, q):
    """Distance from each point to the nearest of the segments p q (some may be points)."""
    d = q - p
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), np.finfo(float).tiny)
    t = np.clip(np.einsum("kij,ij->ki", points[:, None] - p, d) / length2, 0, 1)
    return np.linalg.norm(points[:, None] - (p + t[..., None] * d), axis=2).min(axis=1)


QUADRATIC_PARTS = [[0, 4, 6, 7], [4, 1, 5, 8], [6, 5, 2, 9], [7, 8, 9, 3],
                   [4, 5, 6, 9], [4, 6, 7, 9], [4, 7, 8, 9], [4, 8, 5, 9]]


def tet_volumes(X, conn):
    """Signed volumes of linear tetrahedra (conn (M, 4), indices into X), or of the 8 parts
    each 10-node element is cut into (corner tets, octahedron along mid(01)-mid(23); SMDS
    order of the mid-edge nodes)."""
    conn = np.asarray(conn)
    if conn.shape[1] == 10:
        conn = conn[:, QUADRATIC_PARTS].reshape(-1, 4)
    p = np.asarray(X, float)[conn]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                     np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6


def centres_from(V, V0, origin, n, gap, samples):
    """Where the quadrilaterals' centre vertices start in a slab cut's result: its new
    vertices are the cut points (each on a plane) and then the centres (each off every
    plane); checks that order and returns the first centre's index."""
    level = (V[len(V0):] - origin) @ n * samples / gap
    on = np.abs(level - np.round(level)) < 1e-9 * max(1.0, samples)
    k = int(on.sum())
    assert on[:k].all() and not on[k:].any()
    return len(V0) + k


def check_centres(V, T, first, atol):
    """Each vertex from `first` on is a quadrilateral's centre: in exactly four triangles,
    the only new vertex of each, at the mean of its four neighbours."""
    rows = T[(T >= first).any(axis=1)]
    if first == len(V):
        return
    assert ((rows >= first).sum(axis=1) == 1).all()
    c = rows.max(axis=1)
    order = np.argsort(c, kind="stable")
    rows, c = rows[order], c[order]
    np.testing.assert_array_equal(np.bincount(c - first, minlength=len(V) - first), 4)
    ring = rows[rows < first].reshape(-1, 8)      # each neighbour twice
    np.testing.assert_allclose(V[c[::4]], V[ring].mean(axis=1), atol=atol)
