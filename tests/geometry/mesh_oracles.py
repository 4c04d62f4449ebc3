"""Test meshes and oracles written for the tests, independent of the kernels under test."""
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


def volume(V, T):
    """Signed enclosed volume by the divergence theorem."""
    return np.linalg.det(V[T]).sum() / 6


def assert_closed_manifold(V, T, min_area=1e-14):
    """Every directed edge once and its reverse present; every vertex used; no zero area."""
    e = set()
    for tri in T.tolist():
        for a, b in zip(tri, tri[1:] + tri[:1]):
            assert (a, b) not in e, f"directed edge {a}->{b} used twice"
            e.add((a, b))
    assert all((b, a) in e for a, b in e), "open edge"
    assert set(np.unique(T)) == set(range(len(V))), "unused or missing vertex"
    area = np.linalg.norm(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]), axis=1)
    assert area.min() > min_area
