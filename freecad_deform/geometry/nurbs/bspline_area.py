"""Exact area of a (rational) B-spline surface and its derivatives with respect to the poles
(Xu, Joneja & Tang 2009, eq. 3-6).

The area is the integral of |S_u x S_v| over the parameter rectangle. Every knot-span cell is
integrated by tensor Gauss-Legendre, with two successive rules of RULES; where they disagree
by more than the cell's share of the tolerance, the cell gets more nodes if the differences
fall fast (a smooth integrand, e.g. a steep terrain), else it is split into four, and so
on. Where |S_u x S_v| vanishes (a collapsed pole row, a degenerate corner) the integrand is
not smooth and more nodes converge slowly; the splitting grades the cells geometrically
toward such points instead. The value kept is the coarser rule's and the difference is
its error estimate (the finer rule converges faster); the sum is the reported error.

The surface is linear in its poles: at each point S_u = sum Ru_m P_m over the (p+1)(q+1)
poles of its cell, so gradient and Hessian are sums of small dense blocks per cell.
"""
import hashlib
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy.sparse import csc_matrix, csr_matrix

from ..vectors import skew

RULES = np.array([10, 15, 20, 30, 40])   # Gauss-Legendre nodes per direction, in turn
MAX_DEPTH = 48          # halvings of a knot-span cell, at most
MAX_RECTS = 4000        # rectangles, at most (|S_u x S_v| = 0 along a curve: a fold)
RTOL = 1e-13            # the area's relative tolerance
LARGE = 20000           # cells beyond which the fixed cells are integrated as below
FIXED_RULES = (5, 6, 8)  # the fixed cells of a large face: cheap rules on every cell,
FIXED_RTOL = 1e-11       # then the cells of the largest differences adaptively, to this
CHUNK = 1024            # cells evaluated at once (bounds memory on large surfaces)


class Surface(NamedTuple):
    poles: np.ndarray          # (nu, nv, 3)
    weights: np.ndarray        # (nu, nv); all ones for a non-rational surface
    uknots: np.ndarray         # full knot vector, with multiplicities
    vknots: np.ndarray
    udegree: int
    vdegree: int


def spans(knots, degree):
    """Break points of the parameter range and, per interval, the knot span index s with
    knots[s] <= x < knots[s + 1]."""
    k = np.asarray(knots, float)
    b = np.unique(k[degree:len(k) - degree])
    return b, np.searchsorted(k, b[:-1], side="right") - 1


def find_span(knots, degree, x):
    """Knot span index of each x (the last non-empty span for x at the end)."""
    b, s = spans(knots, degree)
    return s[np.clip(np.searchsorted(b, x, side="right") - 1, 0, len(s) - 1)]


def basis(knots, degree, span, x):
    """Values and first derivatives (m, degree + 1) of the B-splines N_{span - degree + a},
    a = 0..degree, at x (m,) with span (m,) (de Boor's recurrence, vectorised)."""
    t = np.asarray(knots, float)
    x = np.asarray(x, float)[:, None]
    span = np.asarray(span)[:, None]
    N = np.ones((len(x), 1))
    lower = N
    for j in range(1, degree + 1):
        r = np.arange(1, j + 1)
        left, right = x - t[span + 1 - r], t[span + r] - x
        new = np.zeros((len(x), j + 1))
        saved = np.zeros(len(x))
        for k in range(j):
            temp = N[:, k] / (right[:, k] + left[:, j - 1 - k])
            new[:, k] = saved + right[:, k] * temp
            saved = left[:, j - 1 - k] * temp
        new[:, j] = saved
        lower, N = N, new
    d = np.zeros_like(N)
    if degree:
        i = span - degree + np.arange(degree + 1)
        a = t[i[:, 1:] + degree] - t[i[:, 1:]]
        b = t[i[:, :-1] + degree + 1] - t[i[:, :-1] + 1]
        d[:, 1:] += degree * lower / a
        d[:, :-1] -= degree * lower / b
    return N, d


class Rects(NamedTuple):
    """Parameter rectangles, each inside the knot-span cell (su, sv)."""
    u0: np.ndarray
    u1: np.ndarray
    v0: np.ndarray
    v1: np.ndarray
    su: np.ndarray
    sv: np.ndarray
    depth: np.ndarray
    order: np.ndarray       # the rule kept: RULES[order] nodes per direction
    value: np.ndarray       # its area when known (else NaN)
    last: np.ndarray        # the last difference between rules (inf before any)

    @staticmethod
    def new(u0, u1, v0, v1, su, sv, depth):
        n = len(u0)
        return Rects(u0, u1, v0, v1, su, sv, depth, np.zeros(n, int), np.full(n, np.nan),
                     np.full(n, np.inf))

    def take(self, mask):
        return Rects(*(a[mask] for a in self))

    def split(self):
        """Each rectangle as its four quarters."""
        um, vm = (self.u0 + self.u1) / 2, (self.v0 + self.v1) / 2
        parts = [Rects.new(a, b, c, d, self.su, self.sv, self.depth + 1)
                 for a, b in ((self.u0, um), (um, self.u1))
                 for c, d in ((self.v0, vm), (vm, self.v1))]
        return Rects(*(np.concatenate(a) for a in zip(*parts)))

    def halves(self, along_u):
        """Each rectangle as its two halves, cut across u (along_u) or across v."""
        if along_u:
            m = (self.u0 + self.u1) / 2
            pieces = ((self.u0, m, self.v0, self.v1), (m, self.u1, self.v0, self.v1))
        else:
            m = (self.v0 + self.v1) / 2
            pieces = ((self.u0, self.u1, self.v0, m), (self.u0, self.u1, m, self.v1))
        return Rects.join([Rects.new(*p, self.su, self.sv, self.depth + 1) for p in pieces])

    @staticmethod
    def join(parts):
        return Rects(*(np.concatenate(a) for a in zip(*parts)))


def cells(surface):
    """Every knot-span cell as a Rects."""
    s = surface
    bu, su = spans(s.uknots, s.udegree)
    bv, sv = spans(s.vknots, s.vdegree)
    i, j = np.meshgrid(np.arange(len(su)), np.arange(len(sv)), indexing="ij")
    i, j = i.ravel(), j.ravel()
    return Rects.new(bu[i], bu[i + 1], bv[j], bv[j + 1], su[i], sv[j], np.zeros(len(i), int))


@lru_cache(maxsize=None)
def gauss(n):
    """The n-point Gauss-Legendre nodes and weights on [-1, 1] (computed once per n)."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = w.flags.writeable = False
    return x, w


def _interval_basis(knots, degree, a, b, span, whole, x):
    """Basis values and derivatives (R, n, degree + 1) at the nodes x mapped onto each
    interval [a, b] of knot span `span`, evaluated once per distinct interval (the cells of
    a large face share a few hundred); `whole`: every interval is its whole knot span."""
    if whole:
        _, first, back = np.unique(span, return_index=True, return_inverse=True)
    else:
        _, first, back = np.unique(np.stack([a, b, span.astype(float)], 1), axis=0,
                                   return_index=True, return_inverse=True)
    a, b, span = a[first], b[first], span[first]
    half = (b - a) / 2
    u = (a + half)[:, None] + half[:, None] * x
    N, dN = basis(knots, degree, np.repeat(span, len(x)), u.ravel())
    shape = (len(first), len(x), degree + 1)
    back = np.asarray(back).ravel()
    return N.reshape(shape)[back], dN.reshape(shape)[back]


def _rule(rects, surface, n):
    """Per rectangle: the n x n Gauss-Legendre nodes' weights (R, n, n) and the local basis
    values Nu, dNu (R, n, p+1), Nv, dNv (R, n, q+1)."""
    s = surface
    x, w = gauss(n)
    hu, hv = (rects.u1 - rects.u0) / 2, (rects.v1 - rects.v0) / 2
    whole = not rects.depth.any()       # depth 0: a whole knot-span cell
    Nu, dNu = _interval_basis(s.uknots, s.udegree, rects.u0, rects.u1, rects.su, whole, x)
    Nv, dNv = _interval_basis(s.vknots, s.vdegree, rects.v0, rects.v1, rects.sv, whole, x)
    weights = (hu[:, None] * w)[:, :, None] * (hv[:, None] * w)[:, None, :]
    return weights, Nu, dNu, Nv, dNv


def _local(rects, surface, poles):
    """The (p+1) x (q+1) poles of each rectangle's cell, homogeneous (w P, w) when rational:
    (R, p+1, q+1, 3 or 4)."""
    s = surface
    i = rects.su[:, None] - s.udegree + np.arange(s.udegree + 1)
    j = rects.sv[:, None] - s.vdegree + np.arange(s.vdegree + 1)
    P = np.asarray(poles, float).reshape(s.weights.shape + (3,))[i[:, :, None], j[:, None, :]]
    if np.all(s.weights == 1):
        return P
    w = s.weights[i[:, :, None], j[:, None, :]][..., None]
    return np.concatenate([w * P, w], -1)


def _tangents(rule, P):
    """S_u, S_v (3, R, n, n) at the rule's nodes from the local poles P (batched matrix
    products: the slow part of the adaptive quadrature on large surfaces)."""
    _, Nu, dNu, Nv, dNv = rule
    R, a, b, C = P.shape
    n = Nu.shape[1]
    flat = P.reshape(R, a, b * C)

    def along_v(X, M):      # (R, n, b, C) with M (R, n, b) -> (C, R, n, n)
        return np.matmul(X.transpose(3, 0, 1, 2), M.transpose(0, 2, 1)[None])
    A = np.matmul(Nu, flat).reshape(R, n, b, C)
    Au = np.matmul(dNu, flat).reshape(R, n, b, C)
    Su, Sv = along_v(Au, Nv), along_v(A, dNv)
    if C == 3:
        return Su, Sv
    S = along_v(A, Nv)
    W = S[3]
    return (Su[:3] - Su[3] * S[:3] / W) / W, (Sv[:3] - Sv[3] * S[:3] / W) / W


def rect_areas(rects, surface, poles, n):
    """Area of each rectangle by the n x n Gauss-Legendre rule (n: one per rectangle)."""
    n = np.broadcast_to(n, rects.u0.shape)
    out = np.empty(len(rects.u0))
    for m in np.unique(n):
        pick = np.flatnonzero(n == m)
        out[pick] = _areas(rects.take(pick), surface, poles, int(m))
    return out


def _areas(rects, surface, poles, n):
    out = np.empty(len(rects.u0))
    for start in range(0, len(out), CHUNK):
        part = rects.take(slice(start, start + CHUNK))
        rule = _rule(part, surface, n)
        (ux, uy, uz), (vx, vy, vz) = _tangents(rule, _local(part, surface, poles))
        f = np.sqrt((uy * vz - uz * vy) ** 2 + (uz * vx - ux * vz) ** 2 +
                    (ux * vy - uy * vx) ** 2)
        out[start:start + CHUNK] = (rule[0] * f).sum(axis=(1, 2))
    return out


def adapt(rects, surface, poles, tolerance, max_rects=MAX_RECTS):
    """Refine rectangles until two successive rules agree within tolerance(rects, fine
    areas) each: more nodes while the differences fall fast (a smooth integrand: p), else
    four quarters (a point where the integrand is not smooth: h), up to MAX_DEPTH and
    MAX_RECTS (then the rest is taken as it is, its differences in the error).
    Returns (accepted Rects, their kept rule's areas, the differences: those areas'
    estimated errors)."""
    done, values, errors = [], [], []
    while len(rects.u0):
        n, m = RULES[rects.order], RULES[rects.order + 1]
        coarse = np.where(np.isnan(rects.value), 0.0, rects.value)
        todo = np.isnan(rects.value)
        coarse[todo] = rect_areas(rects.take(todo), surface, poles, n[todo])
        fine = rect_areas(rects, surface, poles, m)
        err = np.abs(fine - coarse)
        ok = (err <= tolerance(rects, fine)) | (rects.depth >= MAX_DEPTH) | \
            (sum(len(d.u0) for d in done) + len(rects.u0) > max_rects)
        done.append(rects.take(ok)._replace(value=coarse[ok]))
        values.append(coarse[ok])
        errors.append(err[ok])
        more = ~ok & (rects.order + 2 < len(RULES)) & (err <= 0.01 * rects.last)
        finer = rects.take(more)
        finer = finer._replace(order=finer.order + 1, value=fine[more], last=err[more])
        rects = Rects.join([finer, _split(rects.take(~ok & ~more), coarse[~ok & ~more],
                                          surface, poles)])
    return Rects.join(done), np.concatenate(values), np.concatenate(errors)


def _split(rects, coarse, surface, poles):
    """The rectangles cut where their integrand is not resolved: in halves across the one
    direction whose halving changes the area (a degenerate or steep edge along the other:
    quarters there would grow as 2^depth along the edge), else in quarters. Halves keep
    their value by the rule they were measured with."""
    n = RULES[rects.order]
    k = len(rects.u0)
    cut = [rects.halves(along_u) for along_u in (True, False)]
    value = [rect_areas(c, surface, poles, np.tile(n, 2)) for c in cut]
    change = [np.abs(v[:k] + v[k:] - coarse) for v in value]
    only = [change[0] > 100 * change[1], change[1] > 100 * change[0]]
    parts = [rects.take(~only[0] & ~only[1]).split()]
    for c, v, pick in zip(cut, value, only):
        both = np.tile(pick, 2)
        parts.append(c.take(both)._replace(value=v[both], order=np.tile(rects.order, 2)[both]))
    return Rects.join(parts)


class Nodes(NamedTuple):
    """Quadrature nodes, sorted by cell: S_u = sum Ru[k] P[index[k]] (Ru: (K, L) local
    coefficients of the L = (p+1)(q+1) poles of the node's cell), likewise S_v."""
    Ru: np.ndarray
    Rv: np.ndarray
    index: np.ndarray
    weights: np.ndarray
    cell_starts: np.ndarray
    S: csr_matrix       # Ru over Rv as one sparse (2K, poles) matrix: S_u over S_v
    ST: csc_matrix      # its transpose (the gradient's pull back to the poles; as CSC
                        # the product runs over the nodes in order)
    tensor: tuple = ()  # non-rational: the rectangles' 1-D rules, one TensorRule per n

    def tangents(self, poles):
        SP = self.S @ np.asarray(poles, float).reshape(-1, 3)
        return SP[:len(self.weights)], SP[len(self.weights):]

    def normal(self, poles):
        """S_u, S_v, f = |S_u x S_v|, the unit normal and 1 / f (0 where f vanishes)."""
        Su, Sv = self.tangents(poles)
        cross = np.cross(Su, Sv)
        f = _row_norm(cross)
        inv = np.divide(1.0, f, out=np.zeros_like(f), where=f > 0)
        return Su, Sv, f, cross * inv[:, None], inv


def _row_norm(x):
    """|x| per row of x (K, 3)."""
    return np.sqrt(np.einsum("ij,ij->i", x, x))


class TensorRule(NamedTuple):
    """Rectangles of one n x n rule on a non-rational surface: node (r, a, b) is row
    pos[r, a, b] of the Nodes, with Ru = dNu[r, a] x Nv[r, b] and Rv = Nu[r, a] x dNv[r, b]
    over the rectangle's poles (flat indices `poles`, (R, L))."""
    pos: np.ndarray
    Nu: np.ndarray
    dNu: np.ndarray
    Nv: np.ndarray
    dNv: np.ndarray
    poles: np.ndarray


def nodes(surface, rects, counts):
    """The Nodes of the n x n rule on each rectangle, n = counts (one per rectangle),
    sorted by cell."""
    sizes = np.unique(counts)
    picks = [rects.take(counts == n) for n in sizes]
    parts = [_nodes(surface, r, int(n)) for r, n in zip(picks, sizes)]
    cell = np.concatenate([p[4] for p in parts])
    order = np.argsort(cell, kind="stable")
    Ru, Rv, index, weights = (np.concatenate([p[k] for p in parts])[order] for k in range(4))
    cell = cell[order]
    starts = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]]) if len(cell) else \
        np.zeros(0, int)
    K, L = index.shape
    tensor = []
    if np.all(surface.weights == 1):
        where = np.empty(K, int)
        where[order] = np.arange(K)
        offset = 0
        for (_, _, part_index, _, _, basis), n in zip(parts, sizes):
            R = len(part_index) // (n * n)
            pos = where[offset:offset + R * n * n].reshape(R, n, n)
            tensor.append(TensorRule(pos, *basis, part_index[::n * n]))
            offset += R * n * n
    indptr = np.arange(0, 2 * K * L + 1, L)
    S = csr_matrix((np.concatenate([Ru.ravel(), Rv.ravel()]), np.tile(index.ravel(), 2),
                    indptr), (2 * K, surface.weights.size))
    return Nodes(Ru, Rv, index, weights, starts, S, S.T, tuple(tensor))


def _nodes(surface, rects, n):
    s = surface
    weights, Nu, dNu, Nv, dNv = _rule(rects, s, n)
    L = (s.udegree + 1) * (s.vdegree + 1)

    def outer(a, b):      # (R, n, pu) x (R, n, pv) -> (R * n * n, L)
        return np.einsum("ria,rjb->rijab", a, b).reshape(-1, L)
    Ru, Rv = outer(dNu, Nv), outer(Nu, dNv)
    i = rects.su[:, None] - s.udegree + np.arange(s.udegree + 1)
    j = rects.sv[:, None] - s.vdegree + np.arange(s.vdegree + 1)
    index = (i[:, :, None] * s.weights.shape[1] + j[:, None, :]).reshape(len(i), 1, 1, L)
    index = np.broadcast_to(index, (len(i), n, n, L)).reshape(-1, L)
    w = s.weights.ravel()[index]
    if np.any(w != 1):   # rational: R = N w / W, differentiated
        R = outer(Nu, Nv) * w
        W, Wu, Wv = R.sum(1), (Ru * w).sum(1), (Rv * w).sum(1)
        Ru = (Ru * w - R * (Wu / W)[:, None]) / W[:, None]
        Rv = (Rv * w - R * (Wv / W)[:, None]) / W[:, None]
    cell = np.repeat(rects.su * s.weights.shape[1] + rects.sv, n * n)
    return Ru, Rv, index, weights.ravel(), cell, (Nu, dNu, Nv, dNv)


class Quadrature:
    """The area as a fixed part (the cells no movable pole touches) plus a sum over the
    nodes of the other cells (`nodes`); the Hessian, which only steers Newton, uses the
    rule with half the nodes on the same rectangles (`light`)."""

    def __init__(self, surface, rects, fixed, active_error, per_area, active):
        self.surface = surface
        self.fixed_parts = fixed
        self.fixed, self.error = fixed[0], fixed[1] + active_error
        self.active_error = active_error    # the error of the part the poles change
        self.per_area, self.active = per_area, active
        self.rects = rects.take(np.lexsort((rects.sv, rects.su)))
        n = RULES[self.rects.order]
        self.nodes = nodes(surface, self.rects, n)
        self.light = nodes(surface, self.rects, np.maximum(n // 2, 6))
        self.scatters = {}      # the Hessian's scatter indices per rule and movable set

    @property
    def count(self):
        """Quadrature nodes that depend on the movable poles."""
        return len(self.nodes.weights)

    def tangents(self, poles):
        return self.nodes.tangents(poles)

    def area(self, poles):
        Su, Sv = self.tangents(poles)
        return self.fixed + float(self.nodes.weights @ _row_norm(np.cross(Su, Sv)))

    def gradient(self, poles, movable):
        """(area, d area / d pole (len(movable), 3)) for the flat pole indices `movable`:
        d f / d P_m = Ru_m (S_v x n) + Rv_m (n x S_u), n the unit normal (eq. 3)."""
        q = self.nodes
        Su, Sv, f, n, _ = q.normal(poles)
        w = q.weights[:, None]
        g = q.ST @ np.concatenate([w * np.cross(Sv, n), w * np.cross(n, Su)])
        return self.fixed + float(q.weights @ f), np.asarray(g)[np.asarray(movable, int)]

    def hessian(self, poles, movable, exact=False):
        """d2 area / d pole coordinates (3k, 3k), index 3 * m + c (eq. 4-6):
        (1/f) dn_a . (I - n n^T) dn_b + n . d2n_ab, with dn = (Rv_m [S_u]x - Ru_m [S_v]x) e_c,
        summed rectangle by rectangle as dense (L, 3, L, 3) blocks; on the light rule
        unless `exact`."""
        q = self.nodes if exact else self.light
        Su, Sv, f, n, inv = q.normal(poles)
        s, w = q.weights * inv, q.weights

        def outer(a, b):
            return a[:, :, None] * b[:, None, :]
        nn = outer(n, n)
        # [S_v]x^T (I - n n^T) [S_v]x = |S_v|^2 n n^T (S_v is orthogonal to n), and so on
        uv = s[:, None, None] * (outer(Su, Sv) - np.einsum("k,ij->kij", (Su * Sv).sum(1),
                                                            np.eye(3))
                                 + outer(np.cross(Sv, n), np.cross(Su, n))) - \
            w[:, None, None] * skew(n)
        uu = (s * (Sv * Sv).sum(1))[:, None, None] * nn
        vv = (s * (Su * Su).sum(1))[:, None, None] * nn
        movable = np.asarray(movable, int)
        k = len(movable)
        position = np.full(np.asarray(poles).size // 3, -1)
        position[movable] = np.arange(k)
        if q.tensor:
            key = (exact, movable.tobytes())
            if key not in self.scatters:
                self.scatters[key] = _scatter(q.tensor, position, k)
            return _tensor_hessian(q.tensor, uu, vv, uv, self.scatters[key], k)
        coef = (("u", "u", uu), ("v", "v", vv), ("u", "v", uv),
                ("v", "u", np.transpose(uv, (0, 2, 1))))
        R = {"u": q.Ru, "v": q.Rv}
        H = np.zeros((k, 3, k, 3))
        ends = np.r_[q.cell_starts[1:], len(f)]
        for start, end in zip(q.cell_starts, ends):
            local = position[q.index[start]]
            keep = np.flatnonzero(local >= 0)
            if not len(keep):
                continue
            m = len(keep)
            block = np.zeros((m * 9, m))
            for a, b, c in coef:    # sum_k R_a[k, i] c[k] R_b[k, j] as one matrix product
                left = R[a][start:end, keep][:, :, None] * c[start:end].reshape(-1, 1, 9)
                block += left.reshape(end - start, -1).T @ R[b][start:end, keep]
            g = local[keep]
            H[np.ix_(g, range(3), g, range(3))] += \
                block.reshape(m, 3, 3, m).transpose(0, 1, 3, 2)
        return H.reshape(3 * k, 3 * k)


def _tensor_hessian(tensor, uu, vv, uv, scatter, k):
    """The Hessian of a non-rational surface from its rectangles' tensor rules: a term
    sum_(a,b) R_i c R_j with R_i = X[a, i1] Y[b, i2] and R_j = Z[a, j1] T[b, j2] is summed
    over b first (the rule's v nodes, one matrix product per rectangle for all its u
    nodes), then over a. The blocks go into H by bincount at the indices `scatter` gives
    (`_scatter`, computed once per movable set); the uv term's transpose (the vu term) is
    the transpose of its sum."""
    G = None
    for r, (use, flat) in zip(tensor, scatter):
        if flat is None:
            continue
        _, n, pu = r.Nu.shape
        pv = r.Nv.shape[2]
        pos = r.pos[use]
        Nu, dNu, Nv, dNv = (x[use] for x in (r.Nu, r.dNu, r.Nv, r.dNv))
        R = len(pos)

        def term(c, X, Y, Z, T):    # (R, pu, pu, 3, 3, pv, pv): [i1, j1, x, y, i2, j2]
            W = (Y[:, :, :, None] * T[:, :, None, :]).reshape(R, n, pv * pv)
            cb = c[pos].reshape(R, n, n, 9).transpose(0, 1, 3, 2).reshape(R, n * 9, n)
            inner = np.matmul(cb, W).reshape(R, n, 9 * pv * pv)         # [a, xy, b]
            V = (X[:, :, :, None] * Z[:, :, None, :]).reshape(R, n, pu * pu)
            return np.matmul(V.transpose(0, 2, 1), inner)
        # uu and vv are symmetric: half of each here, the whole by G + G^T below
        block = term(0.5 * uu, dNu, Nv, dNu, Nv)
        block += term(0.5 * vv, Nu, dNv, Nu, dNv)
        block += term(uv, dNu, Nv, Nu, dNv)
        B = np.bincount(flat, block.ravel(), minlength=(3 * k) ** 2 + 1)
        G = B if G is None else G + B
    if G is None:
        return np.zeros((3 * k, 3 * k))
    G = G[:-1].reshape(3 * k, 3 * k)
    return G + G.T


def _scatter(tensor, position, k):
    """Per tensor rule: (the rectangles that touch a movable pole, the index in the flat
    (3k + 1)^2 Hessian of each entry of their blocks [i1, j1, x, y, i2, j2], or None when
    no rectangle does); entries of poles that stay go to one extra bin."""
    out = []
    for r in tensor:
        R, n, pu = r.Nu.shape
        pv = r.Nv.shape[2]
        local = position[r.poles]                                   # (R, L)
        use = (local >= 0).any(1)
        if not use.any():
            out.append((use, None))
            continue
        local = local[use].reshape(-1, pu, pv)
        row = 3 * local[:, :, :, None] + np.arange(3)               # [r, i1, i2, x]
        keep = np.broadcast_to((local >= 0)[:, :, :, None], row.shape)
        row = np.where(keep, row, -1)
        # [r, i1, j1, x, y, i2, j2]: row (i1, i2, x), column (j1, j2, y)
        ri = row.transpose(0, 1, 3, 2)[:, :, None, :, None, :, None]
        cj = row.transpose(0, 1, 3, 2)[:, None, :, None, :, None, :]
        flat = ri * (3 * k) + cj
        flat = np.where((ri >= 0) & (cj >= 0), flat, (3 * k) ** 2)
        out.append((use, flat.ravel()))
    return out


def touched(rects, surface, movable):
    """Which rectangles lie in a cell whose value depends on a pole in `movable`."""
    s = surface
    nu, nv = s.weights.shape
    mask = np.zeros((nu, nv), bool)
    mask.ravel()[np.asarray(movable, int)] = True
    # cells (su, sv) depend on poles su - p..su, sv - q..sv: a windowed any()
    c = np.cumsum(np.cumsum(np.pad(mask, ((1, 0), (1, 0))).astype(int), 0), 1)
    i0, i1 = rects.su - s.udegree, rects.su + 1
    j0, j1 = rects.sv - s.vdegree, rects.sv + 1
    return (c[i1, j1] - c[i0, j1] - c[i1, j0] + c[i0, j0]) > 0


def quadrature(surface, movable=None, rtol=RTOL):
    """A Quadrature whose area is within rtol (relative) of the exact area, estimated: the
    cells are refined until two rules agree within their share of the tolerance (by
    parameter area, or by the cell's own area where that is larger). `movable`: the flat
    pole indices that may change (None: all); the other cells are summed once into a
    fixed part. On a face of more than LARGE cells (a terrain) those fixed cells come from
    `fixed_cells` instead (every cell of the face once, kept per face), so the set-up stays
    in about a second for 100,000 cells."""
    s = surface
    start = cells(s)
    size = (s.uknots[-s.udegree - 1] - s.uknots[s.udegree]) * \
        (s.vknots[-s.vdegree - 1] - s.vknots[s.vdegree])
    fixed = None
    if movable is not None and len(start.u0) > LARGE:
        active = touched(start, s, movable)
        value, error = fixed_cells(s)
        fixed = (float(np.sum(value[~active])), float(np.sum(error[~active])))
        start = start.take(active)
    estimate = rect_areas(start, s, s.poles, RULES[0])
    total = float(np.sum(estimate)) + (fixed[0] if fixed else 0.0)
    per_area = rtol * total / size
    rects, values, errors = adapt(start, s, s.poles, _tolerance(per_area, rtol))
    return _build(s, rects, values, errors, per_area, movable, fixed)


_FIXED_CELLS = {}       # the last few faces' fixed_cells, by their arrays


def fixed_cells(surface):
    """(area, estimated error) of every knot-span cell of a large face (in `cells` order),
    to FIXED_RTOL of the face's area in sum: the FIXED_RULES on every cell (the finest
    kept, the largest difference of successive ones its error: two rules can agree by
    chance where both are far off, three seldom), then the cells of the largest
    differences (a terrain's steepest cells: 1.2 % of them hold 99.9 % of the differences)
    integrated by `adapt` until the sum of the others' errors and of theirs is within
    FIXED_RTOL.
    Kept for the last two faces, so a recompute with other Poles or another target (the
    task panel's preview) does not integrate every cell again."""
    s = surface
    key = hashlib.sha1(b"".join(np.ascontiguousarray(x, float).tobytes() for x in
                                (s.poles, s.weights, s.uknots, s.vknots)) +
                       bytes([s.udegree, s.vdegree, *FIXED_RULES]) +
                       np.float64(FIXED_RTOL).tobytes()).hexdigest()
    if key in _FIXED_CELLS:
        return _FIXED_CELLS[key]
    every = cells(s)
    if np.all(s.weights == 1):
        areas = [tensor_cell_areas(s, n).ravel() for n in FIXED_RULES]
    else:
        areas = [rect_areas(every, s, s.poles, n) for n in FIXED_RULES]
    value = areas[-1]
    error = np.max([np.abs(b - a) for a, b in zip(areas, areas[1:])], axis=0)
    budget = FIXED_RTOL * float(np.sum(np.abs(value)))
    order = np.argsort(error)
    kept = order[:np.searchsorted(np.cumsum(error[order]), budget / 2, side="right")]
    flagged = np.ones(len(error), bool)
    flagged[kept] = False
    if flagged.any():
        start = every.take(flagged)
        area = float(np.sum((start.u1 - start.u0) * (start.v1 - start.v0)))
        rects, values, errors = adapt(start, s, s.poles, _tolerance(budget / 2 / area, RTOL),
                                      MAX_RECTS + 4 * len(start.u0))
        _, su = spans(s.uknots, s.udegree)
        _, sv = spans(s.vknots, s.vdegree)
        cell = np.searchsorted(su, rects.su) * len(sv) + np.searchsorted(sv, rects.sv)
        value[flagged] = error[flagged] = 0.0
        value += np.bincount(cell, values, len(value))
        error += np.bincount(cell, errors, len(value))
    value.flags.writeable = error.flags.writeable = False
    if len(_FIXED_CELLS) >= 2:
        _FIXED_CELLS.pop(next(iter(_FIXED_CELLS)))
    _FIXED_CELLS[key] = value, error
    return value, error


def tensor_cell_areas(surface, n, block=8):
    """The area of every knot-span cell (cells_u, cells_v) of a non-rational surface by the
    n x n Gauss-Legendre rule: the basis along v applied to all poles once (sparse), then
    along u for `block` spans at a time as dense products (BLAS), the integrand weighted
    and summed per cell at once (several times faster than `rect_areas` on a terrain)."""
    s = surface
    Bu, dBu, wu = _design(s.uknots, s.udegree, n)
    Bv, dBv, wv = _design(s.vknots, s.vdegree, n)
    nu, nv = s.weights.shape
    cu, cv = len(wu) // n, len(wv) // n
    P = np.asarray(s.poles, float).reshape(nu, nv, 3)
    # Y[c], dY[c] (nu, Nv): coordinate c along the v nodes of every pole row
    Y, dY = ([np.ascontiguousarray((B @ P[:, :, c].T).T) for c in range(3)]
             for B in (Bv, dBv))
    wv = wv.reshape(cv, n)
    out = np.empty((cu, cv))
    for r in range(0, cu, block):
        rows = slice(r * n, min(r + block, cu) * n)
        U, dU = Bu[rows], dBu[rows]
        used = np.r_[U.indices, dU.indices]
        c0, c1 = used.min(), used.max() + 1
        U, dU = U[:, c0:c1].toarray(), dU[:, c0:c1].toarray()
        Su = [dU @ y[c0:c1] for y in Y]
        Sv = [U @ y[c0:c1] for y in dY]
        f = _norm(_cross(Su, Sv)).reshape(-1, cv, n)
        out[r:r + block] = (wu[rows, None] * np.einsum("rcj,cj->rc", f, wv)).reshape(
            -1, n, cv).sum(1)
    return out


def _tolerance(per_area, rtol):
    def tolerance(rects, fine):
        return np.maximum(per_area * (rects.u1 - rects.u0) * (rects.v1 - rects.v0),
                          rtol * np.abs(fine))
    return tolerance


def _build(surface, rects, values, errors, per_area, movable, fixed=None):
    """The Quadrature of accepted rectangles; `fixed`: (area, error) of the cells no
    movable pole touches, when already known."""
    active = np.ones(len(rects.u0), bool) if movable is None else \
        touched(rects, surface, movable)
    if fixed is None:
        fixed = (float(np.sum(values[~active])), float(np.sum(errors[~active])))
    return Quadrature(surface, rects.take(active), fixed, float(np.sum(errors[active])),
                      per_area, movable)


def refined(q, poles, area=None, rtol=RTOL):
    """(Quadrature for the surface with `poles`, whether it needed more nodes than q and
    its area there differs from q's by more than rtol): q's rectangles checked with the
    new poles (only movable ones changed), given more nodes or split further where the
    rules disagree; the error estimate is the new one. Each rectangle is checked afresh
    (its kept value belongs to the old poles), from its rule. (More nodes alone happen
    at the rounding floor: a terrain's cells, 700 m^2 to 1e-13, flipped one by one and
    the solve restarted 30 times.) `area`: q's area at `poles` when known (the solve's);
    the new one is the sum the check kept, not evaluated again."""
    s = q.surface._replace(poles=np.asarray(poles, float).reshape(q.surface.poles.shape))
    n = len(q.rects.u0)
    start = q.rects._replace(value=np.full(n, np.nan), last=np.full(n, np.inf))
    rects, values, errors = adapt(start, s, s.poles, _tolerance(q.per_area, rtol))
    new = _build(s, rects, values, errors, q.per_area, None, q.fixed_parts)
    new.active = q.active
    if new.count == q.count:
        return new, False
    now = new.fixed + float(np.sum(values))
    before = q.area(s.poles) if area is None else area
    return new, abs(now - before) > rtol * abs(now)


# --- large non-rational surfaces (a terrain): one tensor rule, the basis as sparse matrices
def _design(knots, degree, n):
    """Sparse value and derivative matrices (spans * n, poles) of the B-spline basis at n
    Gauss-Legendre nodes per knot span, and the nodes' weights."""
    b, s = spans(knots, degree)
    x, w = gauss(n)
    half = np.diff(b) / 2
    u = ((b[:-1] + half)[:, None] + half[:, None] * x).ravel()
    span = np.repeat(s, n)
    N, dN = basis(knots, degree, span, u)
    cols = (span[:, None] - degree + np.arange(degree + 1)).ravel()
    rows = np.repeat(np.arange(len(u)), degree + 1)
    size = (len(u), len(knots) - degree - 1)
    return (csr_matrix((N.ravel(), (rows, cols)), size),
            csr_matrix((dN.ravel(), (rows, cols)), size), (half[:, None] * w).ravel())


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _norm(x):
    return np.sqrt(x[0] ** 2 + x[1] ** 2 + x[2] ** 2)


class Grid:
    """The area of a non-rational surface by one tensor Gauss-Legendre rule, n nodes per
    knot span each way: S_u = dB_u P B_v^T with the basis as sparse matrices, so area,
    gradient and Hessian products are sparse products over the whole grid (about a second
    for a 312 x 323-pole terrain at n = 10) and nothing is stored per node. `mask`
    (cells_u, cells_v): the cells it counts (the others are left to another rule)."""
    ROWS = 32               # knot spans along u evaluated at once (bounds memory)

    def __init__(self, surface, n, mask=None):
        s = surface
        self.n, self.shape = n, s.weights.shape
        self.Bu, self.dBu, self.wu = _design(s.uknots, s.udegree, n)
        self.Bv, self.dBv, self.wv = _design(s.vknots, s.vdegree, n)
        cells_shape = (len(self.wu) // n, len(self.wv) // n)
        mask = np.ones(cells_shape, bool) if mask is None else mask
        step = self.ROWS * n
        self.chunks = []
        for r in range(0, len(self.wu), step):
            rows = slice(r, r + step)
            m = np.repeat(np.repeat(mask[r // n:(r + step) // n], n, 0), n, 1)
            self.chunks.append((self.Bu[rows], self.dBu[rows],
                                self.wu[rows, None] * self.wv[None, :] * m))

    def _along_v(self, poles):
        """(B_v P_c^T)^T and (dB_v P_c^T)^T per coordinate c, (nu, Nv) each."""
        P = np.asarray(poles, float).reshape(self.shape + (3,))
        return [[np.ascontiguousarray((B @ P[:, :, c].T).T) for c in range(3)]
                for B in (self.Bv, self.dBv)]

    @staticmethod
    def _tangents(Y, Bu, dBu):
        return [dBu @ y for y in Y[0]], [Bu @ y for y in Y[1]]

    def area(self, poles):
        Y = self._along_v(poles)
        total = 0.0
        for Bu, dBu, w in self.chunks:
            Su, Sv = self._tangents(Y, Bu, dBu)
            total += float(np.sum(w * _norm(_cross(Su, Sv))))
        return total

    def _pull(self, Bu, dBu, a, b, out):
        """out += sum over the chunk's nodes of dBu^T a B_v + Bu^T b dB_v, per coordinate."""
        for c in range(3):
            out[..., c] += dBu.T @ (self.Bv.T @ a[c].T).T + Bu.T @ (self.dBv.T @ b[c].T).T

    def gradient(self, poles):
        """(area, d area / d poles (nu, nv, 3)) (eq. 3)."""
        Y = self._along_v(poles)
        total, g = 0.0, np.zeros(self.shape + (3,))
        for Bu, dBu, w in self.chunks:
            Su, Sv = self._tangents(Y, Bu, dBu)
            N = _cross(Su, Sv)
            f = _norm(N)
            total += float(np.sum(w * f))
            s = w / np.where(f > 0, f, 1.0)
            wn = [x * s for x in N]
            self._pull(Bu, dBu, _cross(Sv, wn), _cross(wn, Su), g)
        return total, g

    def hessp(self, poles, move):
        """The area's Hessian (d2 area / d poles) applied to the displacement `move`."""
        Y, dY = self._along_v(poles), self._along_v(move)
        h = np.zeros(self.shape + (3,))
        for Bu, dBu, w in self.chunks:
            Su, Sv = self._tangents(Y, Bu, dBu)
            dSu, dSv = self._tangents(dY, Bu, dBu)
            N = _cross(Su, Sv)
            f = _norm(N)
            inv = 1.0 / np.where(f > 0, f, 1.0)
            n = [x * inv for x in N]
            dN = [x + y for x, y in zip(_cross(dSu, Sv), _cross(Su, dSv))]
            along = n[0] * dN[0] + n[1] * dN[1] + n[2] * dN[2]
            wdn = [(d - x * along) * inv * w for d, x in zip(dN, n)]
            wn = [x * w for x in n]
            self._pull(Bu, dBu, [x + y for x, y in zip(_cross(dSv, wn), _cross(Sv, wdn))],
                       [x + y for x, y in zip(_cross(wdn, Su), _cross(wn, dSu))], h)
        return h


class GridQuadrature:
    """The area of a large non-rational surface: the cells where the tensor rules GRID
    agree within their share of the tolerance by the coarser Grid, the others (steep
    wrinkles, degenerate points) by `adapt` as `quadrature` does; `hessp` from a light
    grid (it only steers Newton). `flagged`: cells to give to `adapt` in any case."""
    GRID = (10, 15)
    LIGHT = 4

    def __init__(self, surface, per_area, rtol, flagged=None):
        s = surface
        self.surface, self.per_area, self.rtol = s, per_area, rtol
        coarse, fine = (tensor_cell_areas(s, n) for n in self.GRID)
        every = cells(s)
        size = ((every.u1 - every.u0) * (every.v1 - every.v0)).reshape(coarse.shape)
        bad = np.abs(fine - coarse) > np.maximum(per_area * size, rtol * np.abs(fine))
        self.flagged = bad if flagged is None else bad | flagged
        self.grid = Grid(s, self.GRID[0], ~self.flagged)
        self.light = Grid(s, self.LIGHT)
        self.error = float(np.sum(np.abs(fine - coarse)[~self.flagged]))
        self.value = float(np.sum(coarse[~self.flagged]))     # the area at s.poles
        self.part, self.count = None, int((~self.flagged).sum()) * self.GRID[0] ** 2
        if self.flagged.any():
            start = every.take(self.flagged.ravel())
            rects, values, errors = adapt(start, s, s.poles, _tolerance(per_area, rtol),
                                          MAX_RECTS + 4 * len(start.u0))
            self.part = Quadrature(s, rects, (0.0, 0.0), float(np.sum(errors)), per_area,
                                   None)
            self.error += self.part.error
            self.value += float(np.sum(values))
            self.count += self.part.count
        self.active_error = self.error

    def area(self, poles):
        return self.grid.area(poles) + (self.part.area(poles) if self.part else 0.0)

    def gradient(self, poles):
        """(area, d area / d poles (nu, nv, 3))."""
        a, g = self.grid.gradient(poles)
        if self.part:
            b, h = self.part.gradient(poles, np.arange(g.shape[0] * g.shape[1]))
            a, g = a + b, g + h.reshape(g.shape)
        return a, g

    def hessp(self, poles, move):
        return self.light.hessp(poles, move)


def grid_quadrature(surface, rtol=1e-12):
    """A GridQuadrature whose area is within rtol (relative) of the exact area, estimated."""
    s = surface
    size = (s.uknots[-s.udegree - 1] - s.uknots[s.udegree]) * \
        (s.vknots[-s.vdegree - 1] - s.vknots[s.vdegree])
    return GridQuadrature(s, rtol * Grid(s, GridQuadrature.GRID[0]).area(s.poles) / size, rtol)


def grid_refined(q, poles, area=None):
    """(GridQuadrature for the surface with `poles`, whether its area there differs from
    q's by more than the tolerance): every cell checked again with the new poles; the
    cells flagged before stay flagged. `area`: q's area at `poles` when known; the new
    one is the sum the check computed, not evaluated again."""
    s = q.surface._replace(poles=np.asarray(poles, float).reshape(q.surface.poles.shape))
    new = GridQuadrature(s, q.per_area, q.rtol, q.flagged)
    before = q.area(s.poles) if area is None else area
    return new, abs(new.value - before) > q.rtol * abs(new.value)
