"""Where a new Stretch, Bend, Twist or Taper starts when the user picked no plane or axis, and
how a picked one is fitted to the part. Everything is read from the part's bounding box
(`lo`, `hi`: its min and max corners), a plane (origin, normal toward the moving part) and a
line (point, direction), all numpy arrays; the GUI's commands and panels convert.
"""
import numpy as np

from .bend import turning_speed
from .planes import unit_normal

AXES = np.eye(3)


def _box(lo, hi):
    return np.asarray(lo, float), np.asarray(hi, float)


def corners(lo, hi):
    """The 8 corners of the box, (8, 3)."""
    lo, hi = _box(lo, hi)
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                     for z in (lo[2], hi[2])])


def extent(lo, hi, origin, normal):
    """(min, max) signed distance of the box's corners to the plane: the part lies between."""
    low, high = extents(np.reshape(lo, (1, 3)), np.reshape(hi, (1, 3)), origin, normal)
    return float(low[0]), float(high[0])


def extents(lows, highs, origin, normal):
    """(min, max) arrays: extent() of many boxes at once, `lows` and `highs` (N, 3); per
    axis the nearer and farther corner coordinate, no corners built."""
    n = unit_normal(normal)
    low, high = np.asarray(lows, float) * n, np.asarray(highs, float) * n
    at = float(np.dot(np.asarray(origin, float), n))
    return np.minimum(low, high).sum(axis=1) - at, np.maximum(low, high).sum(axis=1) - at


def crosses(lo, hi, origin, normal):
    """Whether the plane cuts the box (beyond 1e-7 of its size on both sides)."""
    low, high = extent(lo, hi, origin, normal)
    tol = 1e-7 * max(1.0, float(np.linalg.norm(np.subtract(hi, lo))))
    return low < -tol and high > tol


def default_plane(lo, hi):
    """(origin, normal): through the box's centre, normal along its longest side."""
    lo, hi = _box(lo, hi)
    return 0.5 * (lo + hi), AXES[int(np.argmax(hi - lo))].copy()


def crossing_origin(lo, hi, origin, normal):
    """`origin`, or, when the plane misses the box (a face on the part's boundary), moved
    along the normal to the middle of the box: the picked plane then only gives a direction."""
    origin = np.asarray(origin, float)
    if crosses(lo, hi, origin, normal):
        return origin.copy()
    low, high = extent(lo, hi, origin, normal)
    return origin + unit_normal(normal) * (0.5 * (low + high))


def section_centre(lo, hi, origin, normal):
    """The box's centre projected onto the plane: the middle of where the cross-section can
    lie (every section point is inside the projected box)."""
    lo, hi = _box(lo, hi)
    n = unit_normal(normal)
    centre = 0.5 * (lo + hi)
    return centre - n * ((centre - np.asarray(origin, float)) @ n)


def axis_through(point, direction, origin):
    """(point, unit direction) of the line, its point the one nearest `origin`."""
    d = unit_normal(direction, "Axis")
    point = np.asarray(point, float)
    return point + d * ((np.asarray(origin, float) - point) @ d), d


def oriented_axis(lo, hi, origin, normal, axis_point, axis_direction, angle=1.0):
    """(point, direction) of the axis, the direction reversed when that makes `angle`'s sign
    turn the middle of the section away from the near part (a picked line has no meaningful
    direction)."""
    d = unit_normal(axis_direction, "Axis")
    speed = turning_speed([section_centre(lo, hi, origin, normal)], normal, axis_point, d, angle)
    return np.asarray(axis_point, float).copy(), (-d if speed[0] < 0 else d)


def default_bend_axis(lo, hi, origin, normal):
    """(point, direction) of a new Bend's axis: in the plane, parallel to the box's
    second-longest side, just outside the box, and directed so that a positive Angle is a
    valid bend (every section point p has n . (w x (p - c)) > 0)."""
    lo, hi = _box(lo, hi)
    n, origin = unit_normal(normal), np.asarray(origin, float)
    lengths = hi - lo
    # the side most along the normal is the one being bent; of the other two, the longer
    # one gives the axis direction
    along = max(range(3), key=lambda i: abs(AXES[i] @ n))
    for i in sorted((i for i in range(3) if i != along), key=lambda i: -lengths[i]):
        w = AXES[i] - n * (AXES[i] @ n)
        if np.linalg.norm(w) > 1e-6:
            break
    w = w / np.linalg.norm(w)
    u = np.cross(n, w)  # in the plane, across the axis: the third side
    values = (corners(lo, hi) - origin) @ u
    low, high = values.min(), values.max()
    margin = max(0.1 * (high - low), 1e-3 * float(np.linalg.norm(lengths)), 1e-6)
    point = origin + u * (low - margin)
    return oriented_axis(lo, hi, origin, n, point, w)


def plane_onto_line(lo, hi, origin, normal, point, direction):
    """The plane's origin moved along the normal onto a line parallel to the plane, when the
    plane still cuts the box there (a Bend picked by its axis alone); else `origin`."""
    n, origin = unit_normal(normal), np.asarray(origin, float)
    if abs(unit_normal(direction, "Axis") @ n) >= 1e-9:
        return origin.copy()
    moved = origin + n * ((np.asarray(point, float) - origin) @ n)
    return moved if crosses(lo, hi, moved, n) else origin.copy()


def region_planes(lo, hi, origin=None, normal=None):
    """(origin, normal, offset) of a new Twist's or Taper's Plane, Plane2 lying `offset`
    beyond it: at 1/3 and 2/3 of the box's longest side; with a picked plane, that plane
    (moved into the box if it misses it) and Plane2 halfway from it to the box's far end."""
    lo, hi = _box(lo, hi)
    if origin is None:
        lengths = hi - lo
        i = int(np.argmax(lengths))
        origin = 0.5 * (lo + hi)
        origin[i] = lo[i] + lengths[i] / 3.0
        return origin, AXES[i].copy(), lengths[i] / 3.0
    origin = crossing_origin(lo, hi, origin, normal)
    return origin, unit_normal(normal), 0.5 * extent(lo, hi, origin, normal)[1]


def across(normal):
    """A unit vector across `normal`: the world axis least along it, made perpendicular
    (where a handle sits beside the part)."""
    n = unit_normal(normal)
    axis = AXES[int(np.argmin(np.abs(AXES @ n)))]
    w = axis - n * (axis @ n)
    return w / np.linalg.norm(w)
