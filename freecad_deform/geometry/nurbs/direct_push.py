"""Direct deformation of B-spline curves and surfaces (Yamashita & Fukui, DDM).

A grabbed point C(t_p) goes exactly to its target. The curve is linear in its poles
(C(t) = sum R_i(t) V_i, with the rational basis R when there are weights), so every
request is a linear constraint on the pole displacements; among all displacements of the
poles in the range that meet them, the least-norm one is taken. For one push this is the
paper's V'_j = V_j + a w_j (m1 - m0) with a = 1 / sum w^2, so the point lands exactly.

Primitives (the paper's 4.2, here in 3D, for curves and surfaces):
- fixed point: knots inserted at it up to the degree, the pole there and its two
  neighbours held: position, tangent and the curve on both sides keep;
- straight span: the poles that shape the span put on one line, and from then on moved
  only together (one translation), so the span stays straight; on a surface the span is
  an iso-curve segment, its row of poles isolated by knots up to the degree;
- angle: a cusp (knots up to the degree) with straight legs of given lengths at a given
  angle, the corner where asked; on a surface a crease along an iso-curve with straight
  sides. On surfaces fixed points hold position and tangent plane by linear constraints.
"""
import bisect
import operator
from typing import NamedTuple

import numpy as np
from scipy.interpolate import BSpline
from scipy.spatial.transform import Rotation

from .bspline_area import Surface
from ..errors import DeformError


class Curve(NamedTuple):
    poles: np.ndarray      # (n, 3)
    weights: np.ndarray    # (n,)
    knots: np.ndarray      # full knot vector
    degree: int


def basis(knots, degree, n, t, derivative=0):
    """The n B-spline basis functions (or their derivative) at parameters t (k,) -> (k, n)."""
    b = BSpline(knots, np.eye(n), degree)
    if derivative:
        b = b.derivative(derivative)
    return np.atleast_2d(b(np.atleast_1d(np.asarray(t, float))))


def curve_row(c, t, derivative=0):
    """Coefficients (n,) with C^(d)(t) = row @ poles: rational basis (or its derivative)."""
    N = basis(c.knots, c.degree, len(c.weights), t)[0] * c.weights
    if not derivative:
        return N / N.sum()
    dN = basis(c.knots, c.degree, len(c.weights), t, 1)[0] * c.weights
    W, dW = N.sum(), dN.sum()
    return dN / W - N * dW / W**2


def local_basis(knots, degree, t, derivative=0):
    """(first, values): the degree + 1 basis functions N_first..N_first+degree that can be
    nonzero at t (or their derivative); only the knots around t are used, so the cost does
    not grow with the number of poles."""
    n = len(knots) - degree - 1
    k = int(np.clip(np.searchsorted(knots, t, side="right") - 1, degree, n - 1))
    b = BSpline(knots[k - degree:k + degree + 2], np.eye(degree + 1), degree)
    if derivative:
        b = b.derivative(derivative)
    return k - degree, b(float(t))


def span_basis(knots, degree, t):
    """(first, values): local_basis's degree + 1 values at t on a knot list, by de Boor's
    triangle on plain floats: a push evaluates them once, where building a scipy BSpline
    costs ten times the whole push."""
    n = len(knots) - degree - 1
    k = min(max(bisect.bisect_right(knots, t) - 1, degree), n - 1)
    if degree == 3:
        return k - 3, _cubic_basis(knots, k, t)
    return k - degree, _de_boor(knots, degree, k, t)


def _de_boor(knots, degree, k, t):
    """The degree + 1 basis values N_k-degree..N_k at t in knot span k (The NURBS Book,
    A2.2)."""
    N, left, right = [1.0] + [0.0] * degree, [0.0] * (degree + 1), [0.0] * (degree + 1)
    for j in range(1, degree + 1):
        left[j], right[j] = t - knots[k + 1 - j], knots[k + j] - t
        saved = 0.0
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            N[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        N[j] = saved
    return N


def _cubic_basis(U, k, t):
    """_de_boor for degree 3 unrolled (the same operations in the same order, so the same
    floats): bicubic faces are the common case and the loops cost a third of a push."""
    l1, l2, l3 = t - U[k], t - U[k - 1], t - U[k - 2]
    r1, r2, r3 = U[k + 1] - t, U[k + 2] - t, U[k + 3] - t
    temp = 1.0 / (r1 + l1)
    a0, a1 = r1 * temp, l1 * temp
    temp = a0 / (r1 + l2)
    b0, saved = r1 * temp, l2 * temp
    temp = a1 / (r2 + l1)
    b1, b2 = saved + r2 * temp, l1 * temp
    temp = b0 / (r1 + l3)
    c0, saved = r1 * temp, l3 * temp
    temp = b1 / (r2 + l2)
    c1, saved = saved + r2 * temp, l2 * temp
    temp = b2 / (r3 + l1)
    return [c0, c1, saved + r3 * temp, l1 * temp]


def surface_row(s, u, v, du=0, dv=0):
    """Coefficients (nu * nv,) of S (or S_u, S_v) at (u, v) in the row-major poles; only
    the (udegree + 1) x (vdegree + 1) poles around (u, v) are visited."""
    nu, nv = s.weights.shape
    iu, Nu = local_basis(s.uknots, s.udegree, u)
    jv, Nv = local_basis(s.vknots, s.vdegree, v)
    block = (slice(iu, iu + len(Nu)), slice(jv, jv + len(Nv)))
    w = s.weights[block]
    R = np.outer(Nu, Nv) * w
    W = R.sum()
    if not (du or dv):
        values = R / W
    else:
        if du:
            D = np.outer(local_basis(s.uknots, s.udegree, u, 1)[1], Nv) * w
        else:
            D = np.outer(Nu, local_basis(s.vknots, s.vdegree, v, 1)[1]) * w
        values = D / W - R * D.sum() / W**2
    row = np.zeros((nu, nv))
    row[block] = values
    return row.ravel()


def influencing(s, uv):
    """Flat indices of the poles whose basis function is nonzero at any of the parameter
    points uv (k, 2): the poles that move those points of the surface."""
    uv = np.atleast_2d(np.asarray(uv, float))
    nu, nv = s.weights.shape
    if not uv.size:
        return set()
    mats = []
    for knots, degree, n, t in ((s.uknots, s.udegree, nu, uv[:, 0]),
                                (s.vknots, s.vdegree, nv, uv[:, 1])):
        t = np.clip(t, knots[degree], knots[n])
        m = BSpline.design_matrix(t, knots, degree).tocsr()
        m.eliminate_zeros()
        mats.append(m)
    Bu, Bv = mats
    found = set()
    for k in range(len(uv)):
        ii = Bu.indices[Bu.indptr[k]:Bu.indptr[k + 1]]
        jj = Bv.indices[Bv.indptr[k]:Bv.indptr[k + 1]]
        found.update((ii[:, None] * nv + jj[None, :]).ravel().tolist())
    return found


def evaluate(c, t):
    return curve_row(c, t) @ c.poles


# --- knot insertion (Boehm), on homogeneous poles ---------------------------------------------

def insert_knot(knots, degree, poles, weights, t, times=1):
    """(knots, poles, weights) with knot t inserted `times` times (shape unchanged).
    poles (n, ...) along the first axis; weights (n, ...) likewise."""
    U = np.asarray(knots, float)
    Pw = np.concatenate([poles * weights[..., None], weights[..., None]], axis=-1)
    p = degree
    for _ in range(times):
        k = int(np.searchsorted(U, t, side="right")) - 1
        if np.count_nonzero(np.isclose(U, t, rtol=0, atol=1e-12)) >= p:
            break
        new = [Pw[i] for i in range(k - p + 1)]
        for i in range(k - p + 1, k + 1):
            a = (t - U[i]) / (U[i + p] - U[i])
            new.append((1 - a) * Pw[i - 1] + a * Pw[i])
        new += [Pw[i] for i in range(k, len(Pw))]
        Pw = np.array(new)
        U = np.insert(U, k + 1, t)
    w = Pw[..., -1]
    return U, Pw[..., :-1] / w[..., None], w


def multiplicity(knots, t):
    return int(np.count_nonzero(np.isclose(knots, t, rtol=0, atol=1e-12)))


def curve_with_knot(c, t, times):
    need = max(0, times - multiplicity(c.knots, t))
    if need == 0:
        return c
    U, P, w = insert_knot(c.knots, c.degree, c.poles, c.weights, t, need)
    return Curve(P, w, U, c.degree)


def knots_and_mults(full, tol=1e-12):
    """(distinct knots, multiplicities) of a full knot vector, knots closer than tol one."""
    knots, mults = [], []
    for k in np.asarray(full, float):
        if knots and abs(k - knots[-1]) <= tol:
            mults[-1] += 1
        else:
            knots.append(float(k))
            mults.append(1)
    return knots, mults


def reversed_curve(c):
    """The Curve c run backwards, on a [0, 1] knot vector: reversed(t) = c(1 - t)."""
    return c._replace(poles=c.poles[::-1], weights=c.weights[::-1], knots=1 - c.knots[::-1])


def compatible(a, b):
    """Two Curves of the same degree on [0, 1] with each other's knots inserted: the same
    knot vector, so their poles pair up (opposite sides of a Coons patch)."""
    for k in np.unique(np.concatenate([a.knots, b.knots])):
        times = max(multiplicity(a.knots, k), multiplicity(b.knots, k))
        a, b = curve_with_knot(a, k, times), curve_with_knot(b, k, times)
    return a, b


# --- least-norm solve -------------------------------------------------------------------------

def least_norm(n, movable, rows, rhs, groups=(), tol=1e-9):
    """Displacements (n, 3) of the poles: zero off `movable`, rows @ D = rhs exactly, each
    group of pole indices moving by one common translation, |D| least.

    rows (k, n): each constraint's coefficients over all poles; rhs (k, 3)."""
    movable = np.asarray(sorted(set(movable)), int)
    A = np.asarray(rows, float)[:, movable] if len(rows) else np.zeros((0, len(movable)))
    b = np.asarray(rhs, float).reshape(-1, 3)
    extra = []
    pos = {m: i for i, m in enumerate(movable)}
    for g in groups:
        g = [pos[x] for x in g if x in pos]
        for x in g[1:]:
            row = np.zeros(len(movable))
            row[g[0]], row[x] = 1.0, -1.0
            extra.append(row)
    if extra:
        A = np.vstack([A, extra])
        b = np.vstack([b, np.zeros((len(extra), 3))])
    if len(movable) == 0:
        raise DeformError("No pole may move: the Range holds none that are not fixed; "
                          "raise Range or remove Fixed points.", "Range")
    X, *_ = np.linalg.lstsq(A, b, rcond=None)
    miss = np.abs(A @ X - b).max() if len(b) else 0.0
    if miss > tol * max(1.0, np.abs(b).max()):
        raise DeformError(f"The pushes and constraints contradict each other (they miss by "
                          f"{miss:.3g} mm); remove a Fixed point or a Straight span near the "
                          "push, or raise Range.", "Points")
    D = np.zeros((n, 3))
    D[movable] = X
    return D


# --- curves -----------------------------------------------------------------------------------

def pole_at(c, t):
    """Index of the pole the curve passes through at t (a knot of multiplicity = degree)."""
    k = int(np.searchsorted(c.knots, t - 1e-12, side="left"))
    return k - 1


def window(weights, size, low, high, first=0):
    """`size` consecutive pole indices within [low, high] for a point whose basis weights
    over the poles are `weights`: the poles it depends on (the paper's V_i..V_i+degree),
    widened evenly on both sides, or the heaviest ones when fewer are asked. `weights`
    may be those of poles first.. only (all others zero). Plain Python: a push calls it
    twice on a few values, where numpy's per-call cost would dominate."""
    weights = weights.tolist() if isinstance(weights, np.ndarray) else weights
    nonzero = [k for k, x in enumerate(weights) if x > 0]
    lo, hi = first + nonzero[0], first + nonzero[-1]
    size = min(size, high - low + 1)
    if size < hi - lo + 1:
        centre = first + max(range(len(weights)), key=weights.__getitem__)
        start = centre - (size - 1) // 2
    else:
        start = lo - (size - (hi - lo + 1)) // 2
    start = min(max(start, low), high - size + 1)
    return range(start, start + size)


def straight_poles(c, a, b):
    """Indices of the poles that shape the curve between parameters a < b."""
    first = int(np.searchsorted(c.knots, a, side="right")) - 1
    last = int(np.searchsorted(c.knots, b, side="left")) - 1
    return list(range(first - c.degree, max(last, first) + 1))


def make_straight(c, a, b):
    """(curve, pole group): the span [a, b] made exactly straight, its poles on the line
    through C(a) and C(b) (knots at a and b first, so no pole outside is touched)."""
    c = curve_with_knot(curve_with_knot(c, a, 1), b, 1)
    group = straight_poles(c, a, b)
    p0, p1 = evaluate(c, a), evaluate(c, b)
    d = p1 - p0
    if np.linalg.norm(d) == 0:
        raise DeformError("A Straight span has no length; give Straight two different points.",
                          "Straight")
    d = d / np.linalg.norm(d)
    P = c.poles.copy()
    P[group] = p0 + np.outer((P[group] - p0) @ d, d)
    return c._replace(poles=P), group


def make_angle(c, t, angle, legs, corner=None):
    """(curve, held poles): a cusp at t whose legs are straight, `legs` = (before, after)
    long, meeting at `angle` (radians) at `corner` (default: where the curve is). The legs
    leave along the tangent, turned toward the curve's centre of curvature by half of
    (pi - angle) each, in the osculating plane."""
    p = c.degree
    tangent = curve_row(c, t, 1) @ c.poles
    tangent = tangent / np.linalg.norm(tangent)
    h = 1e-4 * (c.knots[-1] - c.knots[0])
    bend = (curve_row(c, min(t + h, c.knots[-1]), 1) - curve_row(c, max(t - h, c.knots[0]), 1)) @ c.poles
    normal = np.cross(tangent, bend)
    if np.linalg.norm(normal) < 1e-9 * max(np.linalg.norm(bend), 1e-300):
        normal = np.cross(tangent, np.eye(3)[np.argmin(np.abs(tangent))])
    normal /= np.linalg.norm(normal)
    half = (np.pi - angle) / 2
    d2 = Rotation.from_rotvec(half * normal).apply(tangent)
    d1 = Rotation.from_rotvec(-half * normal).apply(-tangent)
    c = curve_with_knot(c, t, p)
    k = pole_at(c, t)
    before, after = list(range(k - p, k + 1)), list(range(k, k + p + 1))
    if before[0] < 0 or after[-1] >= len(c.poles):
        raise DeformError("An angle needs degree poles on both sides of its corner; move "
                          "the Angles corner farther from the curve's ends.", "Angles")
    P = c.poles.copy()
    o = P[k] if corner is None else np.asarray(corner, float)
    for idx, d, length in ((before[::-1], d1, legs[0]), (after, d2, legs[1])):
        for j, i in enumerate(idx):
            P[i] = o + d * length * j / p
    return c._replace(poles=P), sorted(set(before + after))


def is_closed(c, tol):
    """The curve's two end poles coincide (a circle, a closed B-spline): its seam is an
    ordinary point."""
    return bool(np.linalg.norm(c.poles[0] - c.poles[-1]) <= tol)


def push_curve(c, t, target, size, held=(), groups=(), closed=False):
    """The curve with C(t) moved exactly to `target`, moving at most `size` poles around t
    (never the two end poles, nor `held`), least-norm. `groups` are the poles of straight
    spans: a push on a span moves its group as one (it stays straight), a push beside it
    leaves the group where it is. On a `closed` curve a point that depends on the end
    poles moves them together (the curve stays closed)."""
    n = len(c.poles)
    row = curve_row(c, t)
    on = [g for g in groups if np.any(row[g] > 0) and set(np.nonzero(row)[0]) <= set(g)]
    held = set(held) | {i for g in groups if g not in on for i in g}
    movable = [i for i in window(row, size, 1, n - 2) if i not in held]
    for g in on:
        movable += [i for i in g if i not in movable and 0 < i < n - 1 and i not in held]
    groups = list(groups)
    seam = closed and (row[0] > 0 or row[-1] > 0) and not held & {0, n - 1}
    if seam:
        movable += [0, n - 1]
        groups.append([0, n - 1])
    d = np.asarray(target, float) - row @ c.poles
    P = c.poles + least_norm(n, movable, [row], [d], groups)
    if seam:
        P[-1] = P[0]
    return c._replace(poles=P)


def refine_curve(c, t, size):
    """Insert knots next to t until the range has `size` movable (non-end) poles; stops
    when a span around t is too short to split (knots closer than 1e-12 are one knot)."""
    while len(c.poles) - 2 < size:
        k = int(np.clip(np.searchsorted(c.knots, t, side="right") - 1, c.degree,
                        len(c.knots) - c.degree - 2))
        a, b = c.knots[k], c.knots[k + 1]
        if b - a <= 4e-12:
            break
        c = curve_with_knot(c, (a + b) / 2, multiplicity(c.knots, (a + b) / 2) + 1)
    return c


def range_bound(n_interior, degree):
    """The most poles a push may move along one direction: every interior pole of the
    element, or degree + 2 (knots inserted) when it has fewer."""
    return max(n_interior, degree + 2)


# --- surfaces ---------------------------------------------------------------------------------

BORDER = ("The grabbed point is on (or a hair from) the border of the face, a degenerated "
          "edge or a boundary shared with the faces around it, where only poles that must "
          "stay move it; pick Points farther inside.")


def push_surface(s, u, v, target, size, fixed=(), groups=(), held=()):
    """The surface with S(u, v) moved exactly to `target`, moving at most size x size
    interior poles around it (border poles never), least-norm. `fixed` (u, v) points keep
    their position and tangent plane (S, S_u, S_v unchanged: 9 linear constraints each).
    `groups` are straight spans' poles: held, or moved as one when the point is on one;
    `held` poles (an angle's) never move."""
    if not (fixed or groups or held):
        return _push_free(s, u, v, target, size)
    nu, nv = s.weights.shape
    row = surface_row(s, u, v)
    grid = np.abs(row.reshape(nu, nv))
    ii = window(grid.sum(axis=1), size, 1, nu - 2)
    jj = window(grid.sum(axis=0), size, 1, nv - 2)
    on = [g for g in groups if set(np.nonzero(row)[0]) & set(g)
          and abs(row[g].sum() - 1) < 1e-9]
    held = {i for g in groups if g not in on for i in g} | set(held)
    movable = [i * nv + j for i in ii for j in jj if i * nv + j not in held]
    movable += [i for g in on for i in g if i not in movable
                and 0 < i // nv < nu - 1 and 0 < i % nv < nv - 1]
    if row[movable].sum() < 1e-3:   # the poles that may move would go >1000x as far
        raise DeformError(BORDER, "Points")
    rows = [row]
    rhs = [np.asarray(target, float) - row @ s.poles.reshape(-1, 3)]
    for fu, fv in fixed:
        for du, dv in ((0, 0), (1, 0), (0, 1)):
            rows.append(surface_row(s, fu, fv, du, dv))
            rhs.append(np.zeros(3))
    D = least_norm(nu * nv, movable, rows, rhs, on)
    return s._replace(poles=s.poles + D.reshape(s.poles.shape))


def _push_free(s, u, v, target, size):
    """push_surface without constraints, in closed form on the (p + 1) x (q + 1) poles
    the point depends on (R their rational basis times W): the least-norm move of the
    movable ones is r_k d / sum r_k^2 (the paper's formula), what least_norm's solve
    gives for one row. R >= 0 (weights are positive), so its row and column sums weigh
    the window. R is built on Python floats and numpy only evaluates the point and moves
    the poles: on arrays this small each numpy call costs more than the arithmetic."""
    nu, nv = s.weights.shape
    iu, Nu = span_basis(s.uknots.tolist(), s.udegree, u)
    jv, Nv = span_basis(s.vknots.tolist(), s.vdegree, v)
    a, b = len(Nu), len(Nv)
    R = [[x * y * w for y, w in zip(Nv, ws)]
         for x, ws in zip(Nu, s.weights[iu:iu + a, jv:jv + b].tolist())]
    rows, columns = list(map(sum, R)), list(map(sum, zip(*R)))
    W = sum(rows)
    ii = window(rows, size, 1, nu - 2, iu)
    jj = window(columns, size, 1, nv - 2, jv)
    i0, i1 = (max(ii[0], iu), min(ii[-1] + 1, iu + a)) if ii else (iu, iu)
    j0, j1 = (max(jj[0], jv), min(jj[-1] + 1, jv + b)) if jj else (jv, jv)
    moved = [x for r in R[i0 - iu:i1 - iu] for x in r[j0 - jv:j1 - jv]]
    if sum(moved) < 1e-3 * W:
        raise DeformError(BORDER, "Points")
    R = np.array(R)
    point = np.dot(R.reshape(-1), s.poles[iu:iu + a, jv:jv + b].reshape(-1, 3)).tolist()
    scale = W / sum(map(operator.mul, moved, moved))
    target = np.asarray(target, float).tolist()
    step = np.array([(t - p / W) * scale for t, p in zip(target, point)])  # pole k: r_k step
    poles = s.poles.copy()
    block = poles[i0:i1, j0:j1]
    block += R[i0 - iu:i1 - iu, j0 - jv:j1 - jv, None] * step
    return type(s)(poles, *s[1:])


def refine_surface(s, u, v, size):
    """Insert knots next to (u, v) in each direction that has fewer than `size` interior
    poles (the paper's note a: the number of poles may change)."""
    for axis in (0, 1):
        knots = s.uknots if axis == 0 else s.vknots
        degree = s.udegree if axis == 0 else s.vdegree
        t = u if axis == 0 else v
        while s.weights.shape[axis] - 2 < size:
            k = int(np.clip(np.searchsorted(knots, t, side="right") - 1, degree,
                            len(knots) - degree - 2))
            if knots[k + 1] - knots[k] <= 4e-12:
                break
            mid = (knots[k] + knots[k + 1]) / 2
            P, w = s.poles, s.weights
            if axis == 1:
                P, w = P.swapaxes(0, 1), w.T
            knots, P, w = insert_knot(knots, degree, P, w, mid, 1)
            if axis == 1:
                P, w = P.swapaxes(0, 1), w.T
            s = s._replace(poles=P, weights=w, **({"uknots": knots} if axis == 0
                                                  else {"vknots": knots}))
    return s


def refine_at(s, u, v):
    """s with a knot inserted in the middle of every knot span that the basis functions at
    (u, v) cover, along u and along v: the poles next to the point get half the support
    on both sides (the shape is kept)."""
    for axis, t in ((0, u), (1, v)):
        knots = s.uknots if axis == 0 else s.vknots
        p = s.udegree if axis == 0 else s.vdegree
        k = int(np.clip(np.searchsorted(knots, t, side="right") - 1, p, len(knots) - p - 2))
        lo, hi = max(k - p, p), min(k + p, len(knots) - p - 2)
        for mid in [0.5 * (knots[m] + knots[m + 1]) for m in range(lo, hi + 1)
                    if knots[m + 1] > knots[m]]:
            s = _insert_along(s, axis, mid, 1 + multiplicity(
                s.uknots if axis == 0 else s.vknots, mid))
    return s


def _insert_along(s, axis, t, times):
    """Surface s with knot t inserted `times` more times along u (axis 0) or v (axis 1)."""
    knots = s.uknots if axis == 0 else s.vknots
    degree = s.udegree if axis == 0 else s.vdegree
    need = max(0, times - multiplicity(knots, t))
    if need == 0:
        return s
    P, w = (s.poles, s.weights) if axis == 0 else (s.poles.swapaxes(0, 1), s.weights.T)
    knots, P, w = insert_knot(knots, degree, P, w, t, need)
    if axis == 1:
        P, w = P.swapaxes(0, 1), w.T
    return s._replace(poles=P, weights=w, **({"uknots": knots} if axis == 0 else
                                              {"vknots": knots}))


def with_knots_of(s, other):
    """s (a Curve or a Surface) with the knots of `other` that it lacks inserted, so their
    poles compare one to one; None when `other` lacks some knot of s."""
    axes = [(0, "knots")] if isinstance(s, Curve) else [(0, "uknots"), (1, "vknots")]
    for axis, name in axes:
        theirs = getattr(other, name)
        if any(multiplicity(theirs, k) < multiplicity(getattr(s, name), k)
               for k in np.unique(getattr(s, name))):
            return None
        for k in np.unique(theirs):
            times = multiplicity(theirs, k)
            s = curve_with_knot(s, k, times) if isinstance(s, Curve) else \
                _insert_along(s, axis, k, times)
    return s


def _iso(a, b):
    """(axis the segment runs along, the other axis, the other parameter, lo, hi)."""
    axis = 0 if abs(a[0] - b[0]) >= abs(a[1] - b[1]) else 1
    lo, hi = sorted((a[axis], b[axis]))
    if hi - lo <= 0:
        raise DeformError("A Straight span has no length; give Straight two different points.",
                          "Straight")
    return axis, 1 - axis, 0.5 * (a[1 - axis] + b[1 - axis]), lo, hi


def straight_group(s, a, b):
    """Flat indices of the poles that shape the iso-curve segment from a to b, once knots
    isolate it (see make_straight_surface)."""
    axis, other, fixed, lo, hi = _iso(a, b)
    knots_other = s.vknots if other == 1 else s.uknots
    row = int(np.searchsorted(knots_other, fixed - 1e-12, side="left")) - 1
    knots = s.uknots if axis == 0 else s.vknots
    degree = s.udegree if axis == 0 else s.vdegree
    n = len(knots) - degree - 1
    span = straight_poles(Curve(np.zeros((n, 3)), np.ones(n), knots, degree), lo, hi)
    nv = s.weights.shape[1]
    return [i * nv + row for i in span] if axis == 0 else [row * nv + j for j in span]


def make_straight_surface(s, a, b):
    """(surface, group of flat pole indices): the iso-curve through the parameter points
    a = (u, v) and b, along the direction in which they differ more, made a straight
    segment between them. Knots up to the degree at the other parameter put that
    iso-curve on one row of poles; the poles of that row that shape the segment go on the
    line through S(a) and S(b); the shape elsewhere is kept."""
    axis, other, fixed, lo, hi = _iso(a, b)
    s = _insert_along(s, other, fixed, s.vdegree if other == 1 else s.udegree)
    s = _insert_along(_insert_along(s, axis, lo, 1), axis, hi, 1)
    group = straight_group(s, a, b)
    P = s.poles.reshape(-1, 3).copy()

    def point(t):
        return surface_row(s, *((t, fixed) if axis == 0 else (fixed, t))) @ P
    p0, p1 = point(lo), point(hi)
    d = (p1 - p0) / np.linalg.norm(p1 - p0)
    P[group] = p0 + np.outer((P[group] - p0) @ d, d)
    return s._replace(poles=P.reshape(s.poles.shape)), group


def make_angle_surface(s, corner_uv, angle, legs, corner=None):
    """(surface, held flat pole indices): a crease along the iso-curve v = corner_uv[1]
    whose two sides are straight in v, `legs` = (before, after) long, meeting at `angle`
    (radians), the crease through `corner` (default: where the surface is). Knots up to
    the degree put the crease on one row of poles; the rows on either side are laid out
    along the two leg directions (common to the whole crease, so each side is ruled)."""
    u, v = corner_uv
    q = s.vdegree
    P0 = s.poles.reshape(-1, 3)
    tangent = surface_row(s, u, v, 1, 0) @ P0
    across = surface_row(s, u, v, 0, 1) @ P0
    normal = np.cross(tangent, across)
    tangent, normal = tangent / np.linalg.norm(tangent), normal / np.linalg.norm(normal)
    forward = np.cross(normal, tangent)                  # along +v, in the tangent plane
    half = (np.pi - angle) / 2
    d2 = Rotation.from_rotvec(-half * tangent).apply(forward)   # both legs bend to -normal
    d1 = Rotation.from_rotvec(half * tangent).apply(-forward)
    s = _insert_along(s, 1, v, q)
    j0 = int(np.searchsorted(s.vknots, v - 1e-12, side="left")) - 1
    nu, nv = s.weights.shape
    if j0 - q < 0 or j0 + q >= nv:
        raise DeformError("An angle needs degree rows of poles on both sides of its crease; "
                          "move the Angles corner farther from the face's border.", "Angles")
    P = s.poles.copy()
    if corner is not None:
        P[:, j0] += np.asarray(corner, float) - surface_row(s, u, v) @ s.poles.reshape(-1, 3)
    for k in range(1, q + 1):
        P[:, j0 - k] = P[:, j0] + d1 * legs[0] * k / q
        P[:, j0 + k] = P[:, j0] + d2 * legs[1] * k / q
    held = [i * nv + j for i in range(nu) for j in range(j0 - q, j0 + q + 1)]
    return s._replace(poles=P), held


def coons_patch(c0, c1, d0, d1):
    """The discrete Coons patch of four boundary curves: c0 (v = 0) and c1 (v = 1) run
    along u, d0 (u = 0) and d1 (u = 1) along v, meeting at the corners; each opposite pair
    with the same degree, knots and weights. Its border rows are exactly the curves' poles
    (the boundary is kept); the interior poles are their bilinear blend, so a planar
    boundary gives a planar patch (Pratt: a face with other than four sides)."""
    n, m = len(c0.poles), len(d0.poles)
    s = np.linspace(0, 1, n)[:, None, None]
    t = np.linspace(0, 1, m)[None, :, None]
    P = ((1 - t) * c0.poles[:, None] + t * c1.poles[:, None]
         + (1 - s) * d0.poles[None] + s * d1.poles[None]
         - ((1 - s) * (1 - t) * c0.poles[0] + s * (1 - t) * c0.poles[-1]
            + (1 - s) * t * c1.poles[0] + s * t * c1.poles[-1]))
    return Surface(P, np.outer(c0.weights, d0.weights), c0.knots, d0.knots, c0.degree,
                   d0.degree)


def bezier_patch(corners, degree=3):
    """A degree x degree Bezier surface with the bilinear grid of 4 corners as poles: the
    exact B-spline form of a planar four-sided face (Pratt): corners (00, 10, 11, 01)."""
    a, b, c, d = (np.asarray(x, float) for x in corners)
    s = np.linspace(0, 1, degree + 1)
    S, T = np.meshgrid(s, s, indexing="ij")
    P = ((1 - S) * (1 - T))[..., None] * a + (S * (1 - T))[..., None] * b + \
        (S * T)[..., None] * c + ((1 - S) * T)[..., None] * d
    knots = np.r_[np.zeros(degree + 1), np.ones(degree + 1)]
    return Surface(P, np.ones(P.shape[:2]), knots, knots.copy(), degree, degree)


# --- where a point is -------------------------------------------------------------------------

def closest_parameter(c, x, samples=400):
    """Parameter t of the curve point nearest x: dense samples, then Newton on
    (C(t) - x) . C'(t) = 0."""
    x = np.asarray(x, float)
    a, b = c.knots[c.degree], c.knots[-c.degree - 1]
    ts = np.linspace(a, b, samples)
    N = basis(c.knots, c.degree, len(c.weights), ts) * c.weights
    pts = (N / N.sum(axis=1, keepdims=True)) @ c.poles
    t = ts[np.argmin(np.linalg.norm(pts - x, axis=1))]
    for _ in range(30):
        d = evaluate(c, t) - x
        d1 = curve_row(c, t, 1) @ c.poles
        h = 1e-7 * (b - a)
        d2 = (curve_row(c, min(t + h, b), 1) - curve_row(c, max(t - h, a), 1)) @ c.poles / (2 * h)
        step = -(d @ d1) / (d1 @ d1 + d @ d2)
        t = float(np.clip(t + step, a, b))
        if abs(step) < 1e-15 * (b - a):
            break
    return t, float(np.linalg.norm(evaluate(c, t) - x))


def closest_uv(s, x, samples=60):
    """(u, v, distance) of the surface point nearest x: a grid, then Gauss-Newton (a
    rank-deficient step where the surface degenerates, so no division by zero there)."""
    x = np.asarray(x, float)
    nu, nv = s.weights.shape
    (u0, u1), (v0, v1) = (s.uknots[s.udegree], s.uknots[-s.udegree - 1]), \
        (s.vknots[s.vdegree], s.vknots[-s.vdegree - 1])
    us, vs = np.linspace(u0, u1, samples), np.linspace(v0, v1, samples)
    Nu = basis(s.uknots, s.udegree, nu, us)
    Nv = basis(s.vknots, s.vdegree, nv, vs)
    Pw = np.concatenate([s.poles * s.weights[..., None], s.weights[..., None]], axis=2)
    H = (Nu @ Pw.reshape(nu, -1)).reshape(samples, nv, 4)
    grid = np.einsum("bj,ajk->abk", Nv, H)
    grid = grid[..., :3] / grid[..., 3:]
    a, b = np.unravel_index(np.argmin(np.linalg.norm(grid - x, axis=2)), grid.shape[:2])
    u, v = us[a], vs[b]
    P = s.poles.reshape(-1, 3)
    small = 1e-15 * max(u1 - u0, v1 - v0, abs(u0), abs(u1), abs(v0), abs(v1))
    for _ in range(30):
        d = surface_row(s, u, v) @ P - x
        J = np.column_stack([surface_row(s, u, v, 1, 0) @ P, surface_row(s, u, v, 0, 1) @ P])
        step, *_ = np.linalg.lstsq(J, -d, rcond=None)
        if not np.all(np.isfinite(step)):
            break
        u, v = float(np.clip(u + step[0], u0, u1)), float(np.clip(v + step[1], v0, v1))
        if np.abs(step).max() <= small:
            break
    return u, v, float(np.linalg.norm(surface_row(s, u, v) @ P - x))
