"""Oracles for meshes cut at many parallel planes, written for the tests (numpy only, no
hypothesis, so FreeCAD's own runner can import them too)."""
import numpy as np


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
