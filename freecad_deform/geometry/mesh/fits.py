"""Least-squares plane and cylinder fits of mesh regions (Date & Onosato, 4.2 and 5.1).

The cylinder axis comes from the region's normals (they are all perpendicular to it);
the axis position and radius come from a circle fit of the points seen along the axis,
then all five parameters are refined by a geometric least-squares fit.
"""
from typing import NamedTuple

import numpy as np
from scipy.optimize import least_squares


class Plane(NamedTuple):
    normal: np.ndarray   # unit, oriented like the region's triangle normals
    offset: float        # the plane is normal . x = offset (the paper's fourth coefficient d)
    rms: float           # root mean square distance of the points from the plane


class Cylinder(NamedTuple):
    axis: np.ndarray     # unit direction
    point: np.ndarray    # the axis point nearest the points' centroid
    radius: float
    rms: float           # root mean square of (distance from the axis - radius)


def fit_plane(points, normals=None):
    """Least-squares plane of `points`; `normals` (any number of them) orient it."""
    p = np.asarray(points, float)
    c = p.mean(axis=0)
    normal = np.linalg.svd(p - c, full_matrices=False)[2][-1]
    if normals is not None and np.sum(np.asarray(normals) @ normal) < 0:
        normal = -normal
    normal[np.abs(normal) < 1e-15] = 0.0
    normal /= np.linalg.norm(normal)
    d = (p - c) @ normal
    return Plane(normal, float(c @ normal), float(np.sqrt(np.mean(d * d))))


def _frame(axis):
    """Two unit vectors completing `axis` to an orthonormal frame."""
    helper = np.eye(3)[np.argmin(np.abs(axis))]
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)


def _circle(xy):
    """Algebraic (Kasa) circle fit: (centre (2,), radius)."""
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    b = (xy * xy).sum(axis=1)
    (cx, cy, k), *_ = np.linalg.lstsq(A, b, rcond=None)
    return np.array([cx, cy]), float(np.sqrt(max(k + cx * cx + cy * cy, 0.0)))


def fit_cylinder(points, normals):
    """Least-squares cylinder of `points` whose surface normals are `normals`."""
    p = np.asarray(points, float)
    axis = np.linalg.svd(np.asarray(normals, float), full_matrices=False)[2][-1]
    u, v = _frame(axis)
    c = p.mean(axis=0)
    q = p - c
    centre, radius = _circle(np.column_stack([q @ u, q @ v]))

    def residual(x):     # the products written out: least_squares calls it ~150 times
        a = axis + x[0] * u + x[1] * v
        a = a / np.sqrt(a @ a)
        r = q - (x[2] * u + x[3] * v)
        r -= (r @ a)[:, None] * a
        return np.sqrt((r * r).sum(axis=1)) - x[4]

    x0 = np.array([0.0, 0.0, centre[0], centre[1], radius])
    fit = least_squares(residual, x0, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    x = fit.x
    a = axis + x[0] * u + x[1] * v
    a /= np.linalg.norm(a)
    a[np.abs(a) < 1e-15] = 0.0
    a /= np.linalg.norm(a)
    o = c + x[2] * u + x[3] * v
    o = o + ((c - o) @ a) * a
    res = fit.fun
    return Cylinder(a, o, float(abs(x[4])), float(np.sqrt(np.mean(res * res))))
