"""Stretch of a closed triangle mesh: split at the plane, sweep the section, join.

Wu & Ilies 2011, "Shaping with deformations". The plane is a point and a normal that
points toward the part that moves; s below is the signed distance to it. Meshes are
vertices (N, 3) float and triangles (M, 3) int, counter-clockwise seen from outside.
"""
import itertools

import numpy as np
from scipy.spatial import cKDTree

from ..errors import DeformError
from ..sweep.motion import ScrewMotion, translation
from ..sweep.planes import check_crossing, parallel_gap, unit_normal
from .cut import arrays, cut_arrays, seam
from .sweep import sweep_mesh


def stretch_mesh(vertices, triangles, origin, normal, distance, origin2=None, normal2=None,
                 eps=1e-9):
    """The mesh stretched by `distance` along `normal`; returns (vertices, triangles).

    One plane, distance > 0: the part beyond the plane moves by distance*normal and the
    section is swept across the gap. distance < 0: the slab 0 < s < -distance is removed
    and the far part moved back; the slab must have a constant cross-section. Two planes
    (origin2 given; normal2 defaults to normal): the region between them is stretched
    along the normal with its cross-sections kept, the part beyond Plane2 moved rigidly.
    """
    V, T = arrays(vertices, triangles, copy=False)
    o, n, d = np.asarray(origin, float), unit_normal(normal), float(distance)
    if d > 0 and origin2 is None:      # sweep_mesh checks the Plane as below
        return _extend(V, T, o, n, d, eps)
    V, T = arrays(V, T)
    check_crossing((V - o) @ n, "Plane", eps, touching=True)
    if d == 0:
        return V, T
    if origin2 is not None:
        return _stretch_between(V, T, o, n, d, np.asarray(origin2, float),
                                n if normal2 is None else normal2, eps)
    return _shrink(V, T, o, n, -d, eps)


def _extend(V, T, o, n, d, eps):
    """Case distance > 0: the sweep by a translation along the normal, in one band."""
    return sweep_mesh(V, T, o, n, ScrewMotion(translation(d * n)), samples=1, eps=eps)


def _stretch_between(V, T, o, n, d, o2, n2, eps):
    """Case two planes: s -> s + clip(s/L, 0, 1)*distance, exact on each side of the cuts."""
    L = parallel_gap(o, n, o2, n2)
    if L + d <= 0:
        raise DeformError(f"Distance {d:g} would collapse the region between Plane and Plane2 "
                          f"({L:g} apart); keep Distance above {-L:g}.", "Distance")
    check_crossing((V - o2) @ n, "Plane2", eps, touching=True)
    V, T, s1 = cut_arrays(V, T, o, n, eps)
    V, T, s2 = cut_arrays(V, T, o2, n, eps)
    f = np.ones(len(V))
    f[:len(s1)] = np.clip(s1 / L, 0.0, 1.0)
    f[s2 >= 0] = 1.0
    move = f > 0
    V[move] += (f[move] * d)[:, None] * n
    return V, T


def _shrink(V, T, o, n, D, eps):
    """Case distance < 0: drop the slab 0 < s < D, move the far part back and zip."""
    s = (V - o) @ n
    if not (s > D + eps).any():
        raise DeformError(f"Distance {-D:g} shrinks past the end of the part, which reaches "
                          f"{s.max():g} beyond Plane; reduce Distance to less than {s.max():g} "
                          f"in size.", "Distance")
    tol = 1e-9 * np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    V, T, s1 = cut_arrays(V, T, o, n, eps)
    V, T, s2 = cut_arrays(V, T, o + D * n, n, eps)
    s1 = np.concatenate([s1, np.full(len(V) - len(s1), D)])   # new vertices are on plane 2
    is_near = (s1[T] <= 0).all(axis=1)
    is_far = (s2[T] >= 0).all(axis=1) & ~is_near
    near, far, slab = T[is_near], T[is_far], T[~(is_near | is_far)]
    V[s2 >= 0] -= D * n
    near_seam, far_seam = seam(near, slab, s1 == 0), seam(far, slab, s2 == 0)
    near_pts, far_pts = np.unique(near_seam[1:]), np.unique(far_seam[1:])
    near, near_ring = _insert(V, near, near_seam, far_pts, tol)
    far, far_ring = _insert(V, far, far_seam, near_pts, tol)
    dist, k = cKDTree(V[near_pts]).query(V[far_pts], distance_upper_bound=tol)
    weld = np.arange(len(V))
    weld[far_pts[dist <= tol]] = near_pts[k[dist <= tol]]
    far, far_ring = weld[far], weld[far_ring]
    N = len(V)
    if not np.array_equal(np.sort(near_ring @ [N, 1]), np.sort(far_ring @ [1, N])):
        raise DeformError(f"The cross-section changes between Plane and {D:g} beyond it; a mesh "
                          f"can only be shrunk across a slab of constant cross-section, so move "
                          f"Plane or reduce Distance.", "Distance")
    used, T = np.unique(np.concatenate([near, far]), return_inverse=True)
    return V[used], T.reshape(-1, 3)


def _insert(V, tris, seam, points, tol):
    """Split the seam edges of `tris` at the `points` lying inside them, so the seam has no
    T-junction with them; each split triangle becomes a fan from its opposite corner.
    Returns the triangles and the seam's directed sub-edges (k, 2)."""
    rows, A, B = seam
    axis = V[B] - V[A]
    length = np.linalg.norm(axis, axis=1)
    axis /= length[:, None]
    nearby = cKDTree(V[points]).query_ball_point((V[A] + V[B]) / 2, length / 2 + tol)
    edge = np.repeat(np.arange(len(A)), [len(c) for c in nearby])
    p = points[np.fromiter(itertools.chain.from_iterable(nearby), np.int64, len(edge))]
    rel = V[p] - V[A[edge]]
    u = np.einsum("ij,ij->i", rel, axis[edge])                 # position along the edge
    off = np.linalg.norm(rel - u[:, None] * axis[edge], axis=1)
    inside = (off <= tol) & (u > tol) & (u < length[edge] - tol)
    order = np.lexsort((u[inside], edge[inside]))
    edge, p = edge[inside][order], p[inside][order]
    split = np.unique(edge)
    ring = np.c_[A, B][~np.isin(np.arange(len(A)), split)].tolist()
    fans = {}
    for e, pts in zip(split.tolist(), np.split(p, np.searchsorted(edge, split[1:]))):
        a, b = int(A[e]), int(B[e])
        chain = [a, *pts.tolist(), b]
        ring += zip(chain, chain[1:])
        fan = fans.setdefault(int(rows[e]), [tuple(tris[rows[e]].tolist())])
        i = next(i for i, t in enumerate(fan) if (a, b) in zip(t, t[1:] + t[:1]))
        c = next(v for v in fan[i] if v not in (a, b))
        fan[i:i + 1] = [(c, x, y) for x, y in zip(chain, chain[1:])]
    keep = np.ones(len(tris), bool)
    keep[list(fans)] = False
    extra = np.array([t for fan in fans.values() for t in fan], dtype=np.int64)
    return (np.concatenate([tris[keep], extra.reshape(-1, 3)]),
            np.array(ring, dtype=np.int64).reshape(-1, 2))
