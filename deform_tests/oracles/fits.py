"""Fits written for the tests (numpy and scipy only): the SVD plane, the algebraic circle
of a vertical cylinder, the least-squares plane and cylinder."""
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


def plane_fit(points):
    """(unit normal, offset, rms) of the least-squares plane n . x = offset (SVD)."""
    p = np.asarray(points, float)
    c = p.mean(axis=0)
    _, s, vt = np.linalg.svd(p - c, full_matrices=False)
    n = vt[-1]
    return n, float(n @ c), float(s[-1] / np.sqrt(len(p)))


def cylinder_fit(points, axis_guess):
    """(point on axis, unit axis, radius, rms) of the least-squares cylinder, by
    scipy.optimize from the axis guess and the circle fit of the points projected on it."""
    from scipy.optimize import least_squares
    p = np.asarray(points, float)
    a0 = np.asarray(axis_guess, float) / np.linalg.norm(axis_guess)
    u = np.cross(a0, [1, 0, 0] if abs(a0[0]) < 0.9 else [0, 1, 0])
    u /= np.linalg.norm(u)
    w = np.cross(a0, u)
    x, y = p @ u, p @ w
    # algebraic circle fit (Kasa) as the start
    A = np.column_stack([x, y, np.ones_like(x)])
    cx, cy, k = np.linalg.lstsq(A, x * x + y * y, rcond=None)[0]
    cx, cy = cx / 2, cy / 2
    r0 = np.sqrt(k + cx * cx + cy * cy)
    c0 = cx * u + cy * w + (p @ a0).mean() * a0

    def residual(q):
        c, a = q[:3], q[3:6] / np.linalg.norm(q[3:6])
        d = p - c
        return np.linalg.norm(d - np.outer(d @ a, a), axis=1) - q[6]

    sol = least_squares(residual, np.r_[c0, a0, r0], xtol=1e-14, ftol=1e-14)
    a = sol.x[3:6] / np.linalg.norm(sol.x[3:6])
    return sol.x[:3], a, abs(sol.x[6]), float(np.sqrt(np.mean(sol.fun ** 2)))


def radial(points, point, axis):
    """Distances of the points from the axis (point, unit axis)."""
    r = np.asarray(points, float) - point
    return np.linalg.norm(r - np.outer(r @ axis, axis), axis=1)


def cylinder_fit_free(points):
    """(point on axis, unit axis, radius, largest deviation) of the least-squares cylinder
    started from the points' principal directions (a long cylinder's axis is the largest,
    a short wide one's the smallest; the better fit is kept): no axis guess needed."""
    from scipy.optimize import least_squares
    points = np.asarray(points, float)
    c = points.mean(axis=0)

    def residual(q):
        return radial(points, q[:3], q[3:6] / np.linalg.norm(q[3:6])) - q[6]
    best = None
    for d in np.linalg.svd(points - c)[2][[0, 2]]:
        r0 = radial(points, c, d).mean()
        q = least_squares(residual, np.concatenate([c, d, [r0]]), xtol=1e-15, ftol=1e-15,
                          gtol=1e-15).x
        if best is None or np.abs(residual(q)).max() < np.abs(residual(best)).max():
            best = q
    return best[:3], best[3:6] / np.linalg.norm(best[3:6]), abs(best[6]), \
        np.abs(residual(best)).max()
