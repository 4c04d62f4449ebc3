"""Test surfaces as numpy arrays (a bicubic canopy, a rational cylinder patch with a
closed-form area, an 18 x 8-pole hood) and their area by Gauss-Legendre quadrature on
scipy's B-spline basis, independent of the kernels under test."""
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
    u, wu = _nodes(s.uknots, nodes, None if toward is None else toward[0], levels)
    v, wv = _nodes(s.vknots, nodes, None if toward is None else toward[1], levels)
    return float(wv @ _area_element(s, P, u, v) @ wu)


def own_cell_areas(s, nodes=60):
    """The area of every knot-span cell (cells_u, cells_v), as own_area integrates it."""
    u, wu = _nodes(s.uknots, nodes)
    v, wv = _nodes(s.vknots, nodes)
    f = _area_element(s, s.poles, u, v).reshape(len(wv) // nodes, nodes, len(wu) // nodes,
                                                 nodes)
    return np.einsum("jbia,ia,jb->ij", f, wu.reshape(-1, nodes), wv.reshape(-1, nodes))


def _nodes(knots, nodes, end=None, levels=60):
    """Gauss-Legendre nodes and weights, `nodes` per knot span (spans split toward the
    knot `end` at 2^-l, l < levels, when given)."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    k = np.unique(knots)
    if end is not None:
        a, b = (k[0], k[1]) if end == k[0] else (k[-1], k[-2])
        k = np.unique(np.r_[k, a + (b - a) * 2.0 ** -np.arange(1, levels)])
    half = np.diff(k) / 2
    return ((k[:-1] + k[1:])[:, None] / 2 + half[:, None] * x).ravel(), \
        (half[:, None] * w).ravel()


def _area_element(s, P, u, v):
    """|S_u x S_v| (len(v), len(u)) from scipy's BSpline on the poles P (non-rational)."""
    su = BSpline(s.uknots, P, s.udegree)                # along u: coefficients (nv, 3) each
    rows, drows = su(u), su.derivative()(u)           # (len(u), nv, 3)
    sv = BSpline(s.vknots, np.moveaxis(rows, 1, 0), s.vdegree)
    dsv = BSpline(s.vknots, np.moveaxis(drows, 1, 0), s.vdegree)
    Su = dsv(v)                                        # (len(v), len(u), 3)
    Sv = sv.derivative()(v)
    return np.linalg.norm(np.cross(Su, Sv), axis=2)


def _basis(x, knots, degree):
    """Values and first derivatives (len(x), n) of the B-spline basis at x (scipy)."""
    from scipy.interpolate import BSpline
    t, k = np.asarray(knots, float), degree
    x = np.clip(x, t[k], t[-k - 1])
    N = BSpline.design_matrix(x, t, k).toarray()
    if k == 0:
        return N, np.zeros_like(N)
    M = BSpline.design_matrix(x, t, k - 1).toarray()          # n + 1 functions
    n = N.shape[1]
    left = t[k:k + n] - t[:n]
    right = t[k + 1:k + 1 + n] - t[1:n + 1]
    a = np.divide(k, left, out=np.zeros(n), where=left > 0)
    b = np.divide(k, right, out=np.zeros(n), where=right > 0)
    return N, M[:, :n] * a - M[:, 1:n + 1] * b


def _gauss(breaks, nodes, splits):
    """Gauss-Legendre nodes and weights over every interval of `breaks`, each cut in
    `splits` equal parts."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    edges = np.concatenate([np.linspace(a, b, splits + 1)[:-1] for a, b in
                            zip(breaks[:-1], breaks[1:])] + [breaks[-1:]])
    lo, hi = edges[:-1], edges[1:]
    pts = ((hi - lo)[:, None] * (x + 1) / 2 + lo[:, None]).ravel()
    wts = ((hi - lo)[:, None] * w / 2).ravel()
    return pts, wts


def bspline_area(poles, weights, uknots, vknots, udeg, vdeg, urange, vrange,
                 nodes=8, splits=1, chunk=256):
    """Area of a (rational) tensor B-spline surface over urange x vrange by Gauss-Legendre
    on every knot span (cut in `splits` parts), evaluated with scipy's basis matrices."""
    P = np.asarray(poles, float)
    W = np.asarray(weights, float)
    Pw = P * W[..., None]
    ub = np.unique(np.clip(uknots, *urange))
    vb = np.unique(np.clip(vknots, *vrange))
    uq, uw = _gauss(ub, nodes, splits)
    vq, vw = _gauss(vb, nodes, splits)
    Nv, dNv = _basis(vq, vknots, vdeg)
    total = 0.0
    for s in range(0, len(uq), chunk):
        Nu, dNu = _basis(uq[s:s + chunk], uknots, udeg)

        def grid(A, B, C):
            return np.einsum("ai,ij...,bj->ab...", A, C, B, optimize=True)

        A, Au, Av = grid(Nu, Nv, Pw), grid(dNu, Nv, Pw), grid(Nu, dNv, Pw)
        w, wu, wv = grid(Nu, Nv, W), grid(dNu, Nv, W), grid(Nu, dNv, W)
        S = A / w[..., None]
        Su = (Au - S * wu[..., None]) / w[..., None]
        Sv = (Av - S * wv[..., None]) / w[..., None]
        J = np.linalg.norm(np.cross(Su, Sv), axis=-1)
        total += float(uw[s:s + chunk] @ J @ vw)
    return total


def converged_area(*surface, tol=1e-13, max_splits=16):
    """bspline_area with nodes doubled, then every span cut in 2, 4, ... until two
    successive values agree to `tol` (relative): (area, last change). Cutting the spans
    as well as adding nodes converges where the Jacobian vanishes at a corner."""
    plan = [(4, 1), (8, 1), (16, 1)] + [(16, s) for s in (2, 4, 8, 16) if s <= max_splits]
    last = None
    for nodes, splits in plan:
        value = bspline_area(*surface, nodes=nodes, splits=splits)
        if last is not None and abs(value - last) <= tol * abs(value):
            return value, abs(value - last) / abs(value)
        last = value
    return last, abs(value - bspline_area(*surface, nodes=8, splits=max_splits)) / abs(value)


def converged_area_pieces(*surface, band=2):
    """converged_area over the inner spans and, each on its own, the four strips of `band`
    knot spans along the border: on a large face (a terrain) only the border spans need
    split spans, and converging them alone keeps the inner grid at 16 nodes. (area, the
    pieces' last changes summed, relative)."""
    poles, weights, uknots, vknots, udeg, vdeg, urange, vrange = surface
    ku = np.unique(np.clip(uknots, *urange))
    kv = np.unique(np.clip(vknots, *vrange))
    if len(ku) <= 2 * band + 1 or len(kv) <= 2 * band + 1:
        return converged_area(*surface)
    ui, vi = (ku[band], ku[-band - 1]), (kv[band], kv[-band - 1])
    pieces = [(ui, vi), ((ku[0], ui[0]), (kv[0], kv[-1])), ((ui[1], ku[-1]), (kv[0], kv[-1])),
              (ui, (kv[0], vi[0])), (ui, (vi[1], kv[-1]))]
    parts = [converged_area(*surface[:6], ur, vr) for ur, vr in pieces]
    total = sum(a for a, _ in parts)
    return total, sum(c * abs(a) for a, c in parts) / abs(total)
