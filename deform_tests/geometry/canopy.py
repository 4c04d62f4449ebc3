"""Test surfaces as numpy arrays: a bicubic canopy (clamped, uniform knots) and a rational
quadratic cylinder patch whose area is known in closed form."""
import numpy as np
from scipy.interpolate import BSpline

from freecad_deform.geometry.nurbs.bspline_area import Surface


def clamped(n, degree):
    inner = np.linspace(0, 1, n - degree + 1)[1:-1]
    return np.concatenate([np.zeros(degree + 1), inner, np.ones(degree + 1)])


def canopy(n=6, m=None, size=(100.0, 60.0), height=25.0, degree=3):
    """n x m poles over a size[0] x size[1] rectangle, lifted by a sine bump and a slope."""
    m = m or n
    x, y = np.meshgrid(np.linspace(0, size[0], n), np.linspace(0, size[1], m), indexing="ij")
    z = height * np.sin(np.pi * x / size[0]) * np.sin(np.pi * y / size[1]) + 0.1 * x
    poles = np.stack([x, y, z], -1)
    return Surface(poles, np.ones((n, m)), clamped(n, degree), clamped(m, degree), degree,
                   degree)


def cylinder_patch(radius=5.0, height=20.0):
    """A quarter cylinder as a rational quadratic x linear surface: area pi r h / 2."""
    w = np.sqrt(0.5)
    arc = np.array([[radius, 0, 0], [radius, radius, 0], [0, radius, 0]], float)
    poles = np.stack([arc, arc + [0, 0, height]], 1)              # (3, 2, 3)
    weights = np.array([[1, 1], [w, w], [1, 1]], float)
    return Surface(poles, weights, np.array([0, 0, 0, 1, 1, 1.0]), np.array([0, 0, 1, 1.0]),
                   2, 1)


def c1_knots(n, degree=3):
    """Clamped knots with every inner knot doubled (C1 bicubic, as IGES surfaces often are)."""
    inner = np.linspace(0, 1, (n - degree - 1) // 2 + 2)[1:-1]
    return np.concatenate([np.zeros(degree + 1), np.repeat(inner, 2), np.ones(degree + 1)])


def hood(nu=18, nv=8, collapsed=2):
    """A C1 bicubic hood (nu x nv poles, inner knots doubled) whose first `collapsed` pole
    rows are one point: the edge u = 0 is degenerate and the patch triangular there. At
    the corner (u, v) = (1, 0) S_u and S_v are parallel (the corner is flattened to 180
    degrees), so |S_u x S_v| vanishes there like the distance to the corner."""
    s, t = np.linspace(0, 1, nu), np.linspace(-1, 1, nv)
    S, T = np.meshgrid(s, t, indexing="ij")
    width = 40 * np.sqrt(np.maximum(S - s[collapsed - 1], 0) / (1 - s[collapsed - 1]))
    z = 30 * np.sin(np.pi * S) * (1 - 0.6 * T ** 2) + 10 * S
    P = np.stack([200 * S, width * T, z], -1)
    P[:collapsed] = P[0, 0]
    P[-2, 0] = P[-1, 0] - 0.8 * (P[-1, 1] - P[-1, 0])
    return Surface(P, np.ones((nu, nv)), c1_knots(nu), c1_knots(nv), 3, 3)


def own_area(s, poles=None, nodes=40, toward=None, levels=60):
    """The area from scipy's BSpline on the poles themselves (non-rational); toward: a
    corner (u, v) of the parameter square the grid is graded toward (2^-l, l < levels)."""
    P = s.poles if poles is None else poles
    x, w = np.polynomial.legendre.leggauss(nodes)

    def grid(knots, end):
        k = np.unique(knots)
        if end is not None:
            a, b = (k[0], k[1]) if end == k[0] else (k[-1], k[-2])
            k = np.unique(np.r_[k, a + (b - a) * 2.0 ** -np.arange(1, levels)])
        half = np.diff(k) / 2
        return ((k[:-1] + k[1:])[:, None] / 2 + half[:, None] * x).ravel(), \
            (half[:, None] * w).ravel()
    u, wu = grid(s.uknots, None if toward is None else toward[0])
    v, wv = grid(s.vknots, None if toward is None else toward[1])
    su = BSpline(s.uknots, P, s.udegree)                # along u: coefficients (nv, 3) each
    rows, drows = su(u), su.derivative()(u)           # (len(u), nv, 3)
    sv = BSpline(s.vknots, np.moveaxis(rows, 1, 0), s.vdegree)
    dsv = BSpline(s.vknots, np.moveaxis(drows, 1, 0), s.vdegree)
    Su = dsv(v)                                        # (len(v), len(u), 3)
    Sv = sv.derivative()(v)
    f = np.linalg.norm(np.cross(Su, Sv), axis=2)
    return float(wv @ f @ wu)
