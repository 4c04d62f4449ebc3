"""Fits written in the tests (numpy only) that the DimensionDrive tests measure meshes with:
an SVD plane, an algebraic circle of a vertical cylinder's vertices, and a count of the
triangles a deformation flipped."""
import numpy as np


def plane(P):
    """(centroid, unit normal, largest distance of P from the plane) of the SVD plane."""
    c = P.mean(axis=0)
    n = np.linalg.svd(P - c)[2][-1]
    return c, n, np.abs((P - c) @ n).max()


def circle(P):
    """(centre xy, radius, largest deviation) of the vertical cylinder through P."""
    xy = P[:, :2]
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    (cx, cy, k), *_ = np.linalg.lstsq(A, (xy * xy).sum(1), rcond=None)
    r = np.sqrt(k + cx * cx + cy * cy)
    return np.array([cx, cy]), r, np.abs(np.hypot(xy[:, 0] - cx, xy[:, 1] - cy) - r).max()


def flips(V, X, T):
    """How many triangles T turned over between the vertex arrays V and X."""
    n0 = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    n1 = np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])
    return int(np.count_nonzero(np.einsum("ij,ij->i", n0, n1) <= 0))
