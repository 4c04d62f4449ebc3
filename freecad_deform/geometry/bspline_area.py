"""Exact area of a (rational) B-spline surface and its derivatives with respect to the poles
(Xu, Joneja & Tang 2009, eq. 3-6).

The surface is linear in its poles: S(u, v) = sum R_ij(u, v) P_ij with the (rational)
basis R, so S_u and S_v at the quadrature points are sparse matrices Ru, Rv times the
poles. The area is sum_k w_k |S_u x S_v| over Gauss-Legendre nodes on every knot span,
with as many nodes as it takes to stop changing in the last digits. Gradient and Hessian
are the paper's integrands, vectorised: sparse products over the quadrature points.
"""
from typing import NamedTuple

import numpy as np
from scipy.interpolate import BSpline
from scipy.sparse import bsr_matrix, csr_matrix, diags, kron

MAX_NODES = 48          # Gauss-Legendre nodes per knot span, at most
DENSE_POLES = 32        # up to this many movable poles the Hessian is assembled densely


class Surface(NamedTuple):
    poles: np.ndarray          # (nu, nv, 3)
    weights: np.ndarray        # (nu, nv); all ones for a non-rational surface
    uknots: np.ndarray         # full knot vector, with multiplicities
    vknots: np.ndarray
    udegree: int
    vdegree: int


def _nodes(knots, degree, count):
    """Gauss-Legendre nodes and weights on every non-empty span of the knot vector."""
    x, w = np.polynomial.legendre.leggauss(count)
    k = np.unique(knots[degree:len(knots) - degree])
    a, b = k[:-1], k[1:]
    half = 0.5 * (b - a)
    return ((a + b)[:, None] / 2 + half[:, None] * x).ravel(), (half[:, None] * w).ravel()


def _basis(knots, degree, n, x):
    """Values and first derivatives (len(x), n) of the n B-spline basis functions at x."""
    b = BSpline(knots, np.eye(n), degree, extrapolate=False)
    return np.nan_to_num(b(x)), np.nan_to_num(b.derivative()(x))


class Quadrature:
    """The surface's derivative matrices at the quadrature nodes: S_u = Ru @ poles,
    S_v = Rv @ poles (poles flattened row-major, (nu * nv, 3)), and the node weights."""

    def __init__(self, surface, count):
        s = surface
        nu, nv = s.weights.shape
        u, wu = _nodes(s.uknots, s.udegree, count)
        v, wv = _nodes(s.vknots, s.vdegree, count)
        Nu, dNu = (csr_matrix(m) for m in _basis(s.uknots, s.udegree, nu, u))
        Nv, dNv = (csr_matrix(m) for m in _basis(s.vknots, s.vdegree, nv, v))
        w = s.weights.ravel()
        Ru, Rv = kron(dNu, Nv, format="csr"), kron(Nu, dNv, format="csr")
        if np.any(w != 1):  # rational: R_ij = N_i N_j w_ij / W, differentiated
            R = kron(Nu, Nv, format="csr")
            W, Wu, Wv = R @ w, Ru @ w, Rv @ w
            scale = diags(w)
            Ru = (diags(1 / W) @ Ru @ scale - diags(Wu / W**2) @ R @ scale).tocsr()
            Rv = (diags(1 / W) @ Rv @ scale - diags(Wv / W**2) @ R @ scale).tocsr()
        self.Ru, self.Rv = Ru, Rv
        self.weights = np.outer(wu, wv).ravel()
        self.count = count

    def tangents(self, poles):
        P = np.asarray(poles, float).reshape(-1, 3)
        return self.Ru @ P, self.Rv @ P

    def area(self, poles):
        Su, Sv = self.tangents(poles)
        return float(self.weights @ np.linalg.norm(np.cross(Su, Sv), axis=1))

    def gradient(self, poles, movable):
        """(area, d area / d pole (len(movable), 3)) for the flat pole indices `movable`:
        d f / d P_m = Ru_m (S_v x n) + Rv_m (n x S_u), n the unit normal (eq. 3)."""
        Su, Sv = self.tangents(poles)
        cross = np.cross(Su, Sv)
        f = np.linalg.norm(cross, axis=1)
        n = cross / f[:, None]
        w = self.weights[:, None]
        g = self.Ru[:, movable].T @ (w * np.cross(Sv, n)) + self.Rv[:, movable].T @ (
            w * np.cross(n, Su))
        return float(self.weights @ f), np.asarray(g)

    def hessian(self, poles, movable):
        """d2 area / d pole coordinates (3k, 3k), index 3 * m + c (eq. 4-6):
        (1/f) dn_a . (I - n n^T) dn_b + n . d2n_ab, with dn = (Rv_m [S_u]x - Ru_m [S_v]x) e_c."""
        Su, Sv = self.tangents(poles)
        cross = np.cross(Su, Sv)
        f = np.linalg.norm(cross, axis=1)
        n = cross / f[:, None]
        A, B, N = _skew(Su), _skew(Sv), _skew(n)
        Pi = np.eye(3) - n[:, :, None] * n[:, None, :]
        s = (self.weights / f)[:, None, None]
        w = self.weights[:, None, None]
        t = np.transpose
        coef = {("u", "u"): s * t(B, (0, 2, 1)) @ Pi @ B,
                ("v", "v"): s * t(A, (0, 2, 1)) @ Pi @ A,
                ("u", "v"): -s * t(B, (0, 2, 1)) @ Pi @ A - w * N,
                ("v", "u"): -s * t(A, (0, 2, 1)) @ Pi @ B + w * N}
        k = len(movable)
        if k <= DENSE_POLES:  # few poles: dense per-point products are cheapest
            D = {"u": self.Ru[:, movable].toarray(), "v": self.Rv[:, movable].toarray()}
            H = np.zeros((k, 3, k, 3))
            for (a, b), c in coef.items():
                for i in range(3):
                    for j in range(3):
                        H[:, i, :, j] += D[a].T @ (c[:, i, j, None] * D[b])
            return H.reshape(3 * k, 3 * k)
        # with J_a = kron(R_a[:, movable], I3): H = sum over a, b of J_a^T blockdiag(c_ab) J_b
        J = {a: kron(R[:, movable], np.eye(3), format="csr")
             for a, R in (("u", self.Ru), ("v", self.Rv))}
        m = len(f)
        H = sum(J[a].T @ bsr_matrix((c, np.arange(m), np.arange(m + 1)), shape=(3 * m, 3 * m))
                @ J[b] for (a, b), c in coef.items())
        return H.toarray()


def _skew(x):
    """[x]_x (N, 3, 3): the matrix of the cross product x cross ."""
    z = np.zeros(len(x))
    return np.stack([np.stack([z, -x[:, 2], x[:, 1]], -1),
                     np.stack([x[:, 2], z, -x[:, 0]], -1),
                     np.stack([-x[:, 1], x[:, 0], z], -1)], 1)


def quadrature(surface, rtol=1e-14):
    """A Quadrature with enough nodes per span that doubling them changes the area by less
    than `rtol` (relative): machine precision, where OCCT's Face.Area gives about 1e-4."""
    q = Quadrature(surface, max(surface.udegree, surface.vdegree) + 2)
    a = q.area(surface.poles)
    while q.count < MAX_NODES:
        finer = Quadrature(surface, min(2 * q.count, MAX_NODES))
        b = finer.area(surface.poles)
        if abs(b - a) <= rtol * abs(b):
            return q
        q, a = finer, b
    return q
