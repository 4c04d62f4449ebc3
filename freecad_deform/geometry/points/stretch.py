"""Stretch of a point cloud: rigid parts moved exactly, the gap filled at the cloud's spacing."""
import numpy as np
from scipy.spatial import cKDTree

from ..errors import DeformError
from ..sweep.planes import TOUCH, check_crossing, parallel_gap, signed_distance, unit_normal

EVERY_POINT = "every point is on one side of it"

_SPACINGS = {}   # fingerprint of a cloud -> its spacing: a recompute of the same Base reuses it


def spacing(points, sample=20000, seed=0):
    """Median distance to the nearest other point: the cloud's own sampling step.

    Repeated points are ignored; a cloud without two distinct points has no step. The
    k-d tree over every point is the cost (about 1 s for 10^6 points): the result is kept
    for the same cloud (its size, sum and a strided sample of its coordinates).
    """
    pts = np.asarray(points, float).reshape(-1, 3)
    key = (len(pts), float(pts.sum()), pts[::max(1, len(pts) // 64)].tobytes(), sample, seed)
    if key not in _SPACINGS:
        if len(_SPACINGS) > 16:
            _SPACINGS.clear()
        _SPACINGS[key] = _spacing(pts, sample, seed)
    return _SPACINGS[key]


def _spacing(pts, sample, seed):
    rng = np.random.default_rng(seed)
    probe = pts[rng.choice(len(pts), size=min(sample, len(pts)), replace=False)]
    # an unbalanced, uncompacted tree builds about 2.5x faster and answers the same
    tree = cKDTree(pts, balanced_tree=False, compact_nodes=False)
    dist, _ = tree.query(probe, k=min(8, len(pts)))
    dist[dist == 0] = np.inf  # the probe itself and its exact repeats
    nearest = dist.min(axis=1)
    if not np.isfinite(nearest).any():
        raise DeformError("The point cloud has fewer than two distinct points; give Base a "
                          "real cloud.", "Base")
    return float(np.median(nearest[np.isfinite(nearest)]))


def section_band(s, step):
    """Mask of the points that make the section at the plane: those within step/2 of it.

    A scan can have no point that close: a stereo or time-of-flight scan cut across its
    depth has depth values in discrete layers farther apart than its spacing. Then the
    layer nearest the plane (the points within step/2 of the nearest one) is the section.
    """
    dist = np.abs(s)
    band = dist <= step / 2
    if band.any() or not len(dist):
        return band
    return dist <= dist.min() + step / 2


MAX_FILL = 20_000_000  # points a gap's fill may add: about 0.5 GB of coordinates


def stretch_points(points, origin, normal, distance, origin2=None, normal2=None, step=None):
    """Stretch a cloud by `distance` along `normal` (see the mesh kernel for the cases).

    One plane, distance > 0: points beyond the plane move by distance*normal and the
    section (the points within step/2 of the plane, see section_band) is swept across the gap every `step`
    (default: the cloud's spacing). distance < 0 removes the slab 0 < s < -distance and
    moves the far part back. Two planes: the region between is stretched along the normal,
    cross-sections kept, the part beyond Plane2 moved rigidly.
    """
    pts = np.asarray(points, float).reshape(-1, 3)
    n = unit_normal(normal)
    s = signed_distance(pts, origin, n)
    s[np.abs(s) <= TOUCH] = 0.0  # on the plane: stays with the near part, bit-identical
    check_crossing(s, "Plane", where=EVERY_POINT)
    if distance == 0:
        return pts.copy()
    if origin2 is not None:
        gap = parallel_gap(origin, n, origin2, normal2 if normal2 is not None else n)
        check_crossing(s - gap, "Plane2", where=EVERY_POINT)
        if gap + distance <= 0:
            raise DeformError(f"Distance {distance:g} would collapse the region between the planes "
                              f"(gap {gap:g}); keep Distance above {-gap:g}.", "Distance")
        shift = np.clip(s / gap, 0.0, 1.0) * distance
        return pts + shift[:, None] * n
    if distance < 0:
        if s.max() <= -distance:
            raise DeformError(f"Distance {distance:g} shrinks past the end of the part; the part "
                              f"reaches {s.max():g} beyond Plane, so reduce Distance.", "Distance")
        keep = (s <= 0) | (s >= -distance)
        out = pts[keep].copy()
        out[s[keep] > 0] += distance * n
        return out
    step = step or spacing(pts)
    band = section_band(s, step)
    section = pts[band] - s[band, None] * n
    layers = distance / step
    if (layers - 1) * len(section) > MAX_FILL:
        most = (MAX_FILL / max(len(section), 1) + 1) * step
        raise DeformError(f"Distance {distance:g} would fill the gap with "
                          f"{(layers - 1) * len(section):.3g} points at the cloud's spacing "
                          f"{step:.3g} (at most {MAX_FILL:.3g}); keep Distance below "
                          f"{most:.6g}.", "Distance")
    layers = max(int(np.ceil(layers)), 1)
    offsets = np.arange(1, layers) * (distance / layers)
    out = np.empty((len(pts) + (layers - 1) * len(section), 3))
    out[:len(pts)] = pts
    far = s > 0                           # the far ones moved, column by column: a masked
    for k in np.flatnonzero(n):           # add over (n, 3) rows is 10x slower
        np.add(pts[:, k], distance * n[k], out=out[:len(pts), k], where=far)
    out[len(pts):] = (section[None, :, :] + offsets[:, None, None] * n).reshape(-1, 3)
    return out
