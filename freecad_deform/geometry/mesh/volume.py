"""Tetrahedral volume meshes for DimensionDrive (issue 17): boundary, smooth extension of a
boundary motion into the volume, inversion range and element quality.

A quadratic tetrahedron (10 nodes, SMDS order: corners 0-3, then the mid-edge nodes of
01, 12, 20, 03, 13, 23) is treated as its 8 linear sub-tetrahedra, so one code path
serves both orders: the boundary triangles are the sub-tetrahedra's free faces (4 per
quadratic face, mid-edge nodes included), the Laplacian runs over their edges, and an
element inverts when one of its sub-tetrahedra does.
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.linalg import splu

from ..errors import DeformError

# the 8 linear sub-tetrahedra of a 10-node tetrahedron (corner tets, then the octahedron
# cut along the diagonal 4-9, i.e. mid(01)-mid(23)); each with the orientation of its parent
QUADRATIC_SPLIT = np.array([[0, 4, 6, 7], [4, 1, 5, 8], [6, 5, 2, 9], [7, 8, 9, 3],
                            [4, 5, 6, 9], [4, 6, 7, 9], [4, 7, 8, 9], [4, 8, 5, 9]])
# faces of a linear tetrahedron (a, b, c, d), outward when det(b-a, c-a, d-a) > 0
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def linear_tets(elements):
    """(K,4) linear tetrahedra and (K,) parent element index of (E,4) or (E,10) elements."""
    E = np.asarray(elements, np.int64)
    if E.ndim != 2 or E.shape[1] not in (4, 10):
        raise DeformError("Base holds elements that are not tetrahedra (4 or 10 nodes); "
                          "link a tetrahedral FEM mesh.", "Base")
    if E.shape[1] == 4:
        return E, np.arange(len(E))
    return E[:, QUADRATIC_SPLIT].reshape(-1, 4), np.repeat(np.arange(len(E)), 8)


def signed_volumes(X, tets):
    """Six times the signed volume of each tetrahedron."""
    p = X[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                     np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))


def boundary_triangles(X, tets):
    """(M,3) outward triangles (node indices) of the faces that belong to one tetrahedron."""
    sign = np.sign(signed_volumes(X, tets))
    if np.any(sign == 0):
        raise DeformError("Base has a tetrahedron of zero volume; repair the mesh.", "Base")
    faces = tets[:, TET_FACES].reshape(-1, 3)
    flip = np.repeat(sign < 0, 4)
    faces[flip] = faces[flip][:, [0, 2, 1]]
    key = np.sort(faces, axis=1)
    _, inverse, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return faces[count[inverse.reshape(-1)] == 1]


def edge_graph(tets, n):
    """(E,2) unique edges of the tetrahedra over n nodes."""
    e = tets[:, [0, 0, 0, 1, 1, 2]], tets[:, [1, 2, 3, 2, 3, 3]]
    pairs = np.sort(np.stack([e[0].reshape(-1), e[1].reshape(-1)], 1), axis=1)
    return np.unique(pairs, axis=0)


class Extension:
    """The harmonic extension of a boundary displacement into the volume: the interior
    displacement u_I solves L_II u_I = -L_IB u_B for the Laplacian of the edge graph of the
    corner tetrahedra, weights 1/length (a convex combination at every node: the maximum
    principle holds, no interior node goes beyond what its neighbours do). L_II is
    factorized once, so every boundary field costs one pair of triangular solves. The
    interior mid-edge nodes of quadratic elements move as the mean of their edge's ends,
    so an element's straight edges stay straight (harmonic values there would bend them and
    invert the thin sub-tetrahedra next to the boundary)."""

    def __init__(self, X, elements, boundary):
        n = len(X)
        E = np.asarray(elements, np.int64)
        corners = E[:, :4]
        edges = edge_graph(corners, n)
        length = np.linalg.norm(X[edges[:, 0]] - X[edges[:, 1]], axis=1)
        w = 1.0 / np.maximum(length, 1e-300)
        i, j = edges[:, 0], edges[:, 1]
        W = coo_matrix((np.concatenate([w, w]), (np.concatenate([i, j]), np.concatenate([j, i]))),
                       shape=(n, n)).tocsr()
        L = (coo_matrix((np.asarray(W.sum(axis=1)).reshape(-1), (np.arange(n), np.arange(n))),
                        shape=(n, n)) - W).tocsc()
        self.n = n
        on_boundary = np.zeros(n, bool)
        on_boundary[np.asarray(boundary, np.int64)] = True
        self.boundary = np.nonzero(on_boundary)[0]
        corner = np.zeros(n, bool)
        corner[corners.reshape(-1)] = True
        self.interior = np.nonzero(corner & ~on_boundary)[0]
        fixed = np.nonzero(corner & on_boundary)[0]
        self.coupling = L[self.interior][:, fixed].tocsc()
        self.fixed = np.searchsorted(self.boundary, fixed)
        self.solver = splu(L[self.interior][:, self.interior].tocsc()) \
            if len(self.interior) else None
        if E.shape[1] == 10:
            mids = np.stack([E[:, 4:].reshape(-1), E[:, [0, 1, 2, 0, 1, 2]].reshape(-1),
                             E[:, [1, 2, 0, 3, 3, 3]].reshape(-1)], 1)
            mids = np.unique(mids, axis=0)
            self.mids = mids[~on_boundary[mids[:, 0]]]
        else:
            self.mids = np.zeros((0, 3), np.int64)

    def field(self, boundary_field):
        """(n,3) displacement of every node from (B,3) displacements of the boundary nodes
        (in the order of self.boundary, the sorted boundary node indices)."""
        out = np.zeros((self.n, 3))
        out[self.boundary] = boundary_field
        if self.solver is not None:
            out[self.interior] = self.solver.solve(-(self.coupling @ boundary_field[self.fixed]))
        out[self.mids[:, 0]] = 0.5 * (out[self.mids[:, 1]] + out[self.mids[:, 2]])
        return out


def inversion_reach(X, tets, field):
    """(lo, hi): the interval of s around 0 in which no tetrahedron's signed volume changes
    sign when the nodes move to X + s * field. det(A + s B) = det(A) det(I + s A^-1 B)
    vanishes at s = -1/lambda for the real eigenvalues lambda of A^-1 B."""
    p, f = X[tets], field[tets]
    A = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]], axis=2)
    B = np.stack([f[:, 1] - f[:, 0], f[:, 2] - f[:, 0], f[:, 3] - f[:, 0]], axis=2)
    live = np.abs(B).max(axis=(1, 2)) > 0
    if not np.any(live):
        return -np.inf, np.inf
    lam = np.linalg.eigvals(np.linalg.solve(A[live], B[live]))
    real = np.abs(lam.imag) <= 1e-9 * np.maximum(np.abs(lam), 1e-300)
    lam = lam.real[real & (lam.real != 0)]
    s = -1.0 / lam
    pos, neg = s[s > 0], s[s < 0]
    return (float(neg.max()) if len(neg) else -np.inf), (float(pos.min()) if len(pos) else np.inf)


def scaled_jacobian(X, tets):
    """Scaled Jacobian of each tetrahedron (Verdict's definition): the smallest over its
    corners of det(edges at the corner) / product of their lengths, times sqrt(2), so a
    regular tetrahedron has 1 and an inverted one a negative value; signed as its first
    signed volume given (pass the tetrahedra oriented positive)."""
    p = X[tets]
    best = np.full(len(tets), np.inf)
    for c, (a, b, d) in enumerate(((1, 2, 3), (2, 0, 3), (0, 1, 3), (1, 0, 2))):
        e = p[:, [a, b, d]] - p[:, [c]]
        det = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2]))
        norms = np.prod(np.linalg.norm(e, axis=2), axis=1)
        best = np.minimum(best, det / np.maximum(norms, 1e-300))
    return np.sqrt(2.0) * best


def oriented(X, tets):
    """The tetrahedra with two nodes swapped where their signed volume is negative."""
    t = np.array(tets, copy=True)
    neg = signed_volumes(X, t) < 0
    t[neg] = t[neg][:, [1, 0, 2, 3]]
    return t
