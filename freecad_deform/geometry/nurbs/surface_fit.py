"""Least-squares B-spline fits at GIVEN parameters, refined until a tolerance holds.

A mapped face keeps its own (u, v) parametrisation: the fit S'(u, v) ~ M(S(u, v)) is made
on a grid of the face's parameters, so the pcurves of its edges stay valid on the fitted
surface. The least squares are separable (tensor-product design matrices from scipy's
BSpline), the deviation is measured at the points midway between the fitting samples
(never used in the fit), and every knot span whose deviation exceeds the tolerance is cut
in two until none does. Values are arrays of any dimension d (3D points, 2D pcurves).
"""
from typing import NamedTuple

import numpy as np
from scipy.interpolate import BSpline
from scipy.linalg import cho_factor, cho_solve

SAMPLES_PER_SPAN = 3     # fitting samples per knot span; the deviation is checked between


class CurveFit(NamedTuple):
    knots: np.ndarray       # full knot vector (degree + 1 fold ends)
    poles: np.ndarray       # (n, d)
    degree: int
    deviation: float        # largest distance at the check points


class SurfaceFit(NamedTuple):
    uknots: np.ndarray
    vknots: np.ndarray
    poles: np.ndarray       # (nu, nv, d)
    degree: int             # or (u degree, v degree)
    deviation: float


def knot_vector(breaks, degree):
    """Clamped knot vector with the given breakpoints (ascending, ends included)."""
    b = np.asarray(breaks, float)
    return np.concatenate([[b[0]] * degree, b, [b[-1]] * degree])


def samples(breaks, per_span=SAMPLES_PER_SPAN):
    """(fitting parameters, check parameters midway between them) over the breakpoints."""
    b = np.asarray(breaks, float)
    f = np.arange(per_span) / per_span
    fit = np.concatenate([(b[:-1, None] + f * np.diff(b)[:, None]).ravel(), b[-1:]])
    return fit, 0.5 * (fit[:-1] + fit[1:])


def design(params, knots, degree):
    """Dense B-spline collocation matrix (len(params), len(knots) - degree - 1)."""
    x = np.clip(np.asarray(params, float), knots[degree], knots[-degree - 1])
    return BSpline.design_matrix(x, knots, degree).toarray()


def _solve(B, X):
    """Least squares B P = X along the first axis of X, by the normal equations: B^T B
    is a banded, well-conditioned Gram matrix of B-splines sampled SAMPLES_PER_SPAN times
    per span (Schoenberg-Whitney holds), so Cholesky is exact enough and fast."""
    flat = X.reshape(X.shape[0], -1)
    try:
        solved = cho_solve(cho_factor(B.T @ B), B.T @ flat)
    except np.linalg.LinAlgError:  # knots far closer than elsewhere: the general solver
        solved = np.linalg.lstsq(B, flat, rcond=None)[0]
    return solved.reshape((B.shape[1],) + X.shape[1:])


def _at_least(breaks, count):
    """Breakpoints with the longest spans cut in two until there are `count` spans (so the
    samples outnumber the poles)."""
    b = np.asarray(breaks, float)
    while len(b) - 1 < count:
        k = int(np.argmax(np.diff(b)))
        b = np.insert(b, k + 1, 0.5 * (b[k] + b[k + 1]))
    return b


def _span_of(params, breaks):
    return np.clip(np.searchsorted(breaks, params, side="right") - 1, 0, len(breaks) - 2)


def _refined(breaks, bad):
    """Breakpoints with every span flagged in `bad` cut at its middle."""
    mids = 0.5 * (breaks[:-1] + breaks[1:])[bad]
    return np.sort(np.concatenate([breaks, mids]))


def fit_curve(fn, t0, t1, tol, degree=3, spans=4, max_spans=1024):
    """Fit fn: params (m,) -> values (m, d) on [t0, t1] to `tol`, refining spans."""
    breaks = np.linspace(t0, t1, spans + 1)
    while True:
        fit_t, check_t = samples(breaks)
        knots = knot_vector(breaks, degree)
        poles = _solve(design(fit_t, knots, degree), np.asarray(fn(fit_t), float))
        err = np.linalg.norm(design(check_t, knots, degree) @ poles - fn(check_t), axis=-1)
        bad = np.zeros(len(breaks) - 1, bool)
        bad[_span_of(check_t, breaks)[err > tol]] = True
        if not bad.any() or len(breaks) - 1 + bad.sum() > max_spans:
            return CurveFit(knots, poles, degree, float(err.max(initial=0.0)))
        breaks = _refined(breaks, bad)


def fit_surface(fn, u_range, v_range, tol, degree=3, spans=(4, 4), max_spans=256,
                breaks=None):
    """Fit fn: (U (mu,), V (mv,)) -> values (mu, mv, d) on the grid U x V over the
    parameter rectangle to `tol`. fn is called once per round, on the fitting samples
    interleaved with the check points midway between them; the fit uses the samples only.
    A span is cut in u where the fit along u alone misses the mid-u points by more than
    tol / 2, in v likewise, and in both where only the surface fit misses. Returns the fit with the largest
    deviation found (above tol only when max_spans stopped the refinement). `breaks`:
    the initial breakpoints (u, v) instead of `spans` uniform spans. Where the values agree
    at both ends of a direction (a seam) the end pole rows are made equal, and a boundary
    where every value is one point (a pole of a sphere, an apex) gets all its poles on that
    point: the fit is closed exactly where the original is, so seams and degenerated edges
    stay what they are. `degree`: one for both directions, or (u degree, v degree) (a
    direction along which the values are exactly linear fits at degree 1, one span)."""
    pu, pv = degrees(degree)
    ub, vb = (np.linspace(*u_range, spans[0] + 1), np.linspace(*v_range, spans[1] + 1)) \
        if breaks is None else (_at_least(breaks[0], pu), _at_least(breaks[1], pv))
    while True:
        fu, cu = samples(ub)
        fv, cv = samples(vb)
        uk, vk = knot_vector(ub, pu), knot_vector(vb, pv)
        G = np.asarray(fn(_interleaved(fu, cu), _interleaved(fv, cv)), float)
        # one design matrix per direction: the fitting samples are its even rows
        du, dv = design(_interleaved(fu, cu), uk, pu), design(_interleaved(fv, cv), vk, pv)
        Du, Dv = du[::2], dv[::2]
        P = _closed(np.swapaxes(_solve(Dv, np.swapaxes(_solve(Du, G[::2, ::2]), 0, 1)), 0, 1),
                    G[::2, ::2])
        err = np.linalg.norm(_grid(du, P, dv) - G, axis=-1)
        deviation = float(np.max(err[1::2, :], initial=0.0))
        deviation = max(deviation, float(np.max(err[:, 1::2], initial=0.0)))
        if deviation <= tol:
            return SurfaceFit(uk, vk, P, degree, deviation)
        # each direction's own error: the samples fitted along it alone, checked midway
        err_u = np.linalg.norm(np.einsum("ia,ajd->ijd", du[1::2],
                                         _solve(Du, G[::2, ::2])) - G[1::2, ::2], axis=-1)
        err_v = np.linalg.norm(np.einsum("ia,ajd->ijd", dv[1::2],
                                         _solve(Dv, np.swapaxes(G[::2, ::2], 0, 1)))
                               - np.swapaxes(G[::2, 1::2], 0, 1), axis=-1)
        bad_u = np.zeros(len(ub) - 1, bool)
        bad_v = np.zeros(len(vb) - 1, bool)
        bad_u[_span_of(cu, ub)[(err_u > 0.5 * tol).any(axis=1)]] = True
        bad_v[_span_of(cv, vb)[(err_v > 0.5 * tol).any(axis=1)]] = True
        if not (bad_u.any() or bad_v.any()):
            bad_u[_span_of(cu, ub)[(err[1::2, :] > tol).any(axis=1)]] = True
            bad_v[_span_of(cv, vb)[(err[:, 1::2] > tol).any(axis=0)]] = True
        if len(ub) - 1 + bad_u.sum() > max_spans or len(vb) - 1 + bad_v.sum() > max_spans:
            return SurfaceFit(uk, vk, P, degree, deviation)
        ub, vb = _refined(ub, bad_u), _refined(vb, bad_v)


def _closed(P, G):
    """Poles with seams closed and collapsed boundaries kept collapsed, as the sample
    values G (on the fitting grid) show them (see fit_surface)."""
    P = P.copy()
    eps = 1e-12 * max(float(np.ptp(G.reshape(-1, G.shape[-1]), axis=0).max()), 1e-300)
    if np.abs(G[0] - G[-1]).max() <= eps:
        P[0] = P[-1] = 0.5 * (P[0] + P[-1])
    if np.abs(G[:, 0] - G[:, -1]).max() <= eps:
        P[:, 0] = P[:, -1] = 0.5 * (P[:, 0] + P[:, -1])
    for rows, values in (((0, slice(None)), G[0]), ((-1, slice(None)), G[-1]),
                         ((slice(None), 0), G[:, 0]), ((slice(None), -1), G[:, -1])):
        if np.ptp(values, axis=0).max() <= eps:
            P[rows] = values[0]
    return P


def _grid(du, P, dv):
    """sum_ab du[i, a] P[a, b] dv[j, b]: (i, j, d), as two matrix products."""
    return np.einsum("ia,ajd->ijd", du, np.einsum("abd,jb->ajd", P, dv, optimize=True),
                     optimize=True)


def _interleaved(fit, check):
    """fit[0], check[0], fit[1], ..., fit[-1]."""
    out = np.empty(len(fit) + len(check))
    out[::2], out[1::2] = fit, check
    return out


def degrees(degree):
    """(u degree, v degree) of a SurfaceFit's `degree`: one for both, or a pair."""
    return (degree, degree) if np.ndim(degree) == 0 else tuple(degree)


def evaluate_surface(fit, u, v):
    """The fitted surface on the grid u x v: (len(u), len(v), d)."""
    pu, pv = degrees(fit.degree)
    return _grid(design(u, fit.uknots, pu), fit.poles, design(v, fit.vknots, pv))


def evaluate_curve(fit, t):
    return design(t, fit.knots, fit.degree) @ fit.poles
