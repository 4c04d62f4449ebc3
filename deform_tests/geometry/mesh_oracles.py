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
    T = np.asarray(T, np.int64)
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    key = a * len(V) + b
    uniq, counts = np.unique(key, return_counts=True)
    assert counts.max() == 1, f"directed edge {uniq[counts > 1][0] // len(V)}->" \
        f"{uniq[counts > 1][0] % len(V)} used twice"
    assert np.isin(b * len(V) + a, uniq).all(), "open edge"
    assert np.array_equal(np.unique(T), np.arange(len(V))), "unused or missing vertex"
    V = np.asarray(V, float)
    area = np.linalg.norm(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]), axis=1)
    assert area.min() > min_area


def mesh_section(V, T, origin, normal, segments=False):
    """(area, centroid[, (p, q) segment ends]) of the cross-section of a closed, outward-oriented triangle mesh by
    a plane: each crossing triangle gives one segment, oriented along normal x (triangle
    normal) so the outline runs counter-clockwise about `normal` (holes clockwise); then
    the shoelace sums. A vertex on the plane counts as on its positive side."""
    V, T = np.asarray(V, float), np.asarray(T)
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross([0, 0, 1], n) if abs(n[2]) < 0.9 else np.cross([1, 0, 0], n)
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    s = (V - origin) @ n
    pos = (s >= 0)[T]
    cross = pos.any(axis=1) & ~pos.all(axis=1)
    tri, sp = V[T[cross]], s[T[cross]]
    pts = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        sa, sb = sp[:, a], sp[:, b]
        cut = (sa >= 0) != (sb >= 0)
        t = np.where(cut, sa / np.where(cut, sa - sb, 1.0), 0.0)
        pts.append((cut, tri[:, a] + t[:, None] * (tri[:, b] - tri[:, a])))
    ends = np.stack([p for c, p in pts], 1)[np.stack([c for c, p in pts], 1)].reshape(-1, 2, 3)
    p, q = ends[:, 0], ends[:, 1]
    tn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", q - p, np.cross(n, tn)) < 0
    p, q = np.where(flip[:, None], q, p), np.where(flip[:, None], p, q)
    x0, y0 = (p - origin) @ u, (p - origin) @ w
    x1, y1 = (q - origin) @ u, (q - origin) @ w
    c = x0 * y1 - x1 * y0
    area = c.sum() / 2
    if area == 0:
        return (0.0, None, (p, q)) if segments else (0.0, None)
    mx, my = ((x0 + x1) * c).sum() / 6 / area, ((y0 + y1) * c).sum() / 6 / area
    centroid = np.asarray(origin, float) + mx * u + my * w
    return (float(area), centroid, (p, q)) if segments else (float(area), centroid)


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
