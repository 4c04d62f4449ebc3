"""Surface deformation under an area constraint (Xu, Joneja & Tang 2009).

min 1/2 |P - Q|^2  s.t.  Area(P) = A_f,  over the chosen poles and degrees of freedom.

Two solvers:
- "Penalty", the paper's: Newton on 1/2 |P - Q|^2 + N/2 (Area - A_f)^2 without line
  search, started from a point on the constraint (Fig. 3). Its area misses A_f by
  O(1/N).
- "Lagrange-Newton" (the default), beyond the paper: Newton on the KKT system with an l1
  merit line search and a second-order correction; it converges to the constraint at
  full precision, with the displacement parallel to the area gradient (KKT).
"""
from typing import NamedTuple

import numpy as np

from scipy.linalg import cho_factor, cho_solve, cho_solve_banded, cholesky_banded
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import ArpackNoConvergence, eigsh
from scipy.spatial import cKDTree

from .bspline_area import (GridQuadrature, basis, find_span, grid_quadrature, grid_refined,
                           quadrature, refined)
from ..errors import DeformError

DOFS = ("Normal", "Z", "Free")
METHODS = ("Lagrange-Newton", "Penalty")
MAX_ITERATIONS = 60
FOLDED = 1e-10          # AreaError / area beyond which the result is refused
MAX_VARIABLES = 2000    # beyond this the dense KKT solve takes minutes: LargeProblem
LEAST_CURVATURE = 0.1   # W's least eigenvalue after a shift, in units of |t|^2 / 2's (1)


class Solution(NamedTuple):
    poles: np.ndarray       # (nu, nv, 3) the new poles
    area: float             # area of the result
    iterations: int
    multiplier: float       # lambda: displacement = -lambda * area gradient at the optimum
    kkt: float              # |t + lambda g| / |t|: 0 when the displacement is parallel to g
    error: float = 0.0      # estimated error of `area` (quadrature), mm^2
    fallbacks: tuple = ()   # 1-based (i, j) of the Normal poles that use the surface normal
    held: tuple = ()        # 1-based (i, j) of listed poles that stay with coincident ones


def coincident(poles, movable):
    """Groups of the movable poles that move as one, and the movable poles that stay.
    Coincident poles (a collapsed row: a degenerate edge) move together so the edge stays
    collapsed; those that coincide with a pole that does not move stay with it."""
    P = np.asarray(poles, float).reshape(-1, 3)
    movable = np.asarray(movable, int)
    tol = 1e-10 * max(np.ptp(P, axis=0).max(), 1e-300)
    pairs = cKDTree(P).query_pairs(tol, output_type="ndarray")
    pairs = pairs[np.isin(pairs, movable).any(axis=1)]
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(P), len(P)))
    _, label = connected_components(graph, directed=False)
    fixed = np.ones(len(P), bool)
    fixed[movable] = False
    held_labels = set(label[fixed & np.isin(label, label[movable])])
    groups, held = {}, []
    for m in movable:
        if label[m] in held_labels:
            held.append(int(m))
        else:
            groups.setdefault(label[m], []).append(int(m))
    return list(groups.values()), held


def directions(poles, groups, dof, surface=None):
    """(3k, n) sparse matrix D (displacements of the poles of `groups`, in order, = D @ t; its
    columns are orthonormal so |t| is the displacement's norm) and the poles whose Normal
    fell back. Free: 3 per group; Z: z only; Normal: along the control-net normal, the mean
    of the unit normals of the net's triangles around the pole (the paper's proposal,
    3.4); where the net has none (coincident poles: a collapsed row), the surface normal
    at the pole's Greville point, else the mean of the neighbours' net normals."""
    if dof not in DOFS:
        raise DeformError(f"Dof must be one of {', '.join(DOFS)}.", "Dof")
    fallbacks, blocks = [], []
    for group in groups:
        if dof == "Free":
            d = np.eye(3)
        elif dof == "Z":
            d = np.array([[0.0], [0.0], [1.0]])
        else:
            n = next((x for x in (net_normal(poles, m) for m in group) if x is not None),
                     None)
            if n is None:
                n = fallback_normal(poles, group[0], surface)
                fallbacks += [tuple(int(x) + 1 for x in divmod(m, poles.shape[1]))
                              for m in group]
            d = n[:, None]
        blocks.append((group, d / np.sqrt(len(group))))
    rows, cols, values = [], [], []
    row = col = 0
    for group, d in blocks:
        r, c = np.nonzero(d)
        for _ in group:
            rows.append(row + r)
            cols.append(col + c)
            values.append(d[r, c])
            row += 3
        col += d.shape[1]
    D = coo_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                   (row, col)).tocsr()
    return D, tuple(sorted(fallbacks))


def net_normal(poles, flat_index):
    """Unit mean normal of the control-net triangles around a pole, oriented like
    S_u x S_v (u along the first pole index); None where every triangle is degenerate."""
    nu, nv, _ = poles.shape
    i, j = divmod(int(flat_index), nv)
    P = poles
    total = np.zeros(3)
    scale = np.abs(P).max()
    for di, dj, ei, ej in ((1, 0, 0, 1), (0, 1, -1, 0), (-1, 0, 0, -1), (0, -1, 1, 0)):
        a, b = (i + di, j + dj), (i + ei, j + ej)
        if 0 <= a[0] < nu and 0 <= a[1] < nv and 0 <= b[0] < nu and 0 <= b[1] < nv:
            n = np.cross(P[a] - P[i, j], P[b] - P[i, j])
            if np.linalg.norm(n) > 1e-24 * scale ** 2:
                total += n / np.linalg.norm(n)
    length = np.linalg.norm(total)
    return total / length if length > 1e-12 else None


def surface_normal(surface, u, v):
    """Unit S_u x S_v of a Surface at (u, v); None where it vanishes."""
    s = surface
    iu, iv = find_span(s.uknots, s.udegree, [u]), find_span(s.vknots, s.vdegree, [v])
    Nu, dNu = basis(s.uknots, s.udegree, iu, [u])
    Nv, dNv = basis(s.vknots, s.vdegree, iv, [v])
    rows = iu[0] - s.udegree + np.arange(s.udegree + 1)
    cols = iv[0] - s.vdegree + np.arange(s.vdegree + 1)
    w = s.weights[np.ix_(rows, cols)]
    P = np.concatenate([w[..., None] * s.poles[np.ix_(rows, cols)], w[..., None]], -1)
    A, Au, Av = (np.einsum("a,b,abc->c", x[0], y[0], P)
                 for x, y in ((Nu, Nv), (dNu, Nv), (Nu, dNv)))
    Su, Sv = Au[:3] * A[3] - Au[3] * A[:3], Av[:3] * A[3] - Av[3] * A[:3]
    n = np.cross(Su, Sv)
    size = np.linalg.norm(Su) * np.linalg.norm(Sv)
    return n / np.linalg.norm(n) if np.linalg.norm(n) > 1e-9 * size > 0 else None


def greville(knots, degree, index):
    return float(np.mean(np.asarray(knots, float)[index + 1:index + degree + 1]))


def fallback_normal(poles, flat_index, surface):
    """The normal of a pole the control net gives none: the surface's at the pole's
    Greville point, else the mean of its neighbours' net normals."""
    nu, nv, _ = poles.shape
    i, j = divmod(int(flat_index), nv)
    if surface is not None:
        s = surface._replace(poles=poles)
        n = surface_normal(s, greville(s.uknots, s.udegree, i),
                           greville(s.vknots, s.vdegree, j))
        if n is not None:
            return n
    near = [net_normal(poles, a * nv + b) for a in range(max(i - 1, 0), min(i + 2, nu))
            for b in range(max(j - 1, 0), min(j + 2, nv)) if (a, b) != (i, j)]
    total = np.sum([n for n in near if n is not None] or [np.zeros(3)], axis=0)
    if np.linalg.norm(total) <= 1e-12:
        raise DeformError(f"Pole ({i + 1}, {j + 1}) has no normal (control net and surface "
                          "degenerate there); use Dof Z or Free.", "Dof")
    return total / np.linalg.norm(total)


class Problem:
    """Area, gradient and Hessian as functions of the reduced variables t (n,); D is
    sparse (a pole's few columns), so the reduced Hessian D^T H D costs O(n^2)."""
    sparse = False          # True: the large, matrix-free solve

    def __init__(self, quadrature, poles, movable, dof):
        self.q = quadrature
        self.Q = np.asarray(poles, float)
        groups, self.held = coincident(self.Q, movable)
        if not groups:
            raise DeformError("Every pole in Poles coincides with a pole that stays (a "
                              "collapsed edge); list other poles.", "Poles")
        self.movable = np.array([m for g in groups for m in g], int)
        self.D, self.fallbacks = directions(self.Q, groups, dof, quadrature.surface)
        self.Dt = self.D.T.tocsr()
        # every group one pole: D is block diagonal, (3, d) per pole, d = n / k columns
        k, n = len(self.movable), self.D.shape[1]
        self.blocks = None
        if len(groups) == k and n % k == 0:
            D = self.D.tocoo()
            pole, d = D.row // 3, n // k
            self.blocks = np.zeros((k, 3, d))
            self.blocks[pole, D.row % 3, D.col - pole * d] = D.data
        self.identity = self.blocks is not None and self.blocks.shape[2] == 3 and \
            np.array_equal(self.blocks, np.broadcast_to(np.eye(3), self.blocks.shape))  # Free
        s = quadrature.surface
        self.band = None if self.sparse else bandwidth(self.D, self.movable, s.weights.shape,
                                                       (s.udegree, s.vdegree))

    def poles(self, t):
        P = self.Q.reshape(-1, 3).copy()
        P[self.movable] += (self.D @ t).reshape(-1, 3)
        return P.reshape(self.Q.shape)

    def area(self, t):
        return self.q.area(self.poles(t))

    def gradient(self, t):
        a, g = self.q.gradient(self.poles(t), self.movable)
        return a, self.Dt @ g.ravel()

    exact = False       # True: the Hessian from the area's own nodes, not the light rule
    shifted = False     # whether the last step's W was shifted (not Newton's own step)

    def hessian(self, t):
        H = self.q.hessian(self.poles(t), self.movable, self.exact)
        B = self.blocks
        if B is None:
            return np.asarray((self.Dt @ H) @ self.D)
        if self.identity:
            return H                                        # Free: D = I
        k, _, d = B.shape
        H = H.reshape(k, 3, k, 3)
        left = np.einsum("aix,aibj->axbj", B, H)
        return np.einsum("axbj,bjy->axby", left, B).reshape(k * d, k * d)

    def step(self, t, lam, g, c, damping=0.0):
        """The Newton step (dt, new lambda) of the KKT system at (t, lam), W + damping I."""
        W = self.hessian(t)
        W *= lam                                # in place: n^2 arrays cost page faults
        W.flat[::len(t) + 1] += 1.0 + damping
        dt, lam, self.shifted = _kkt_step(W, g, t, c, self.band)
        return dt, lam


class LargeProblem(Problem):
    """A Problem on a GridQuadrature (a surface of many poles): D sparse, the area's
    gradient over all poles at once, and the Hessian only as products with vectors."""
    sparse = True

    def gradient(self, t):
        a, g = self.q.gradient(self.poles(t))
        return a, self.D.T @ g.reshape(-1, 3)[self.movable].ravel()

    def hessp(self, P, v):
        move = np.zeros(P.shape).reshape(-1, 3)
        move[self.movable] = (self.D @ v).reshape(-1, 3)
        h = self.q.hessp(P, move.reshape(P.shape))
        return self.D.T @ h.reshape(-1, 3)[self.movable].ravel()

    def step(self, t, lam, g, c, damping=0.0):
        """The KKT step by projected conjugate gradients: dt = the part along g that meets
        the linearised constraint plus the tangential part minimising the model. Where CG
        meets negative curvature on the tangent space, W is shifted past it (as
        _kkt_step does) and CG starts again."""
        gg = g @ g
        normal = -(c / gg) * g
        self.shifted = False
        if lam == 0:                        # W = I
            dt = normal - (t - (t @ g / gg) * g)
            return dt, float(-(g @ (dt + t)) / gg)
        P = self.poles(t)

        def project(v):
            return v - (v @ g / gg) * g
        # inexact Newton: CG as far as the KKT residual calls for (quadratic near the end)
        size = max(np.linalg.norm(t), 1e-300)
        tol = min(1e-2, max(1e-10, 0.1 * (np.linalg.norm(t + lam * g) / size +
                                          abs(c) / (np.sqrt(gg) * size))))
        shift = damping
        for _ in range(60):
            def W(v):
                return (1 + shift) * v + lam * self.hessp(P, v)
            z, curvature = _projected_cg(W, project, -project(t + W(normal)),
                                         1e-13 * (np.linalg.norm(t) + np.linalg.norm(normal)),
                                         tol)
            if curvature is None:
                break
            shift = max(2 * (shift - curvature), 1e-8)
            self.shifted = True
        dt = normal + z
        return dt, float(-(g @ (W(dt) + t)) / gg)


def _projected_cg(W, project, r, floor, tol=1e-10, max_iterations=200):
    """(z, None): z on the tangent space with project(W z) = r, by conjugate gradients, to
    |residual| <= tol |r| or `floor` (the rounding error of r); or (z, Rayleigh quotient
    <= 0) when a direction of negative curvature turns up."""
    z, d, rr = np.zeros_like(r), r.copy(), r @ r
    stop = max(tol ** 2 * rr, floor ** 2, 1e-300)
    for _ in range(max_iterations):
        if rr <= stop:
            break
        Wd = project(W(d))
        curvature = d @ Wd
        if curvature <= 0:
            return z, curvature / (d @ d)
        alpha = rr / curvature
        z, r = z + alpha * d, r - alpha * Wd
        rr, old = r @ r, rr
        d = project(r + (rr / old) * d)
    return z, None


def _converged(t, g, c, target):
    """On the constraint and t parallel to g: |t + lambda g| <= 1e-9 |t| with lambda the
    least-squares multiplier of t (the iterate's lambda lags when steps are short)."""
    lam = -(t @ g) / (g @ g)
    stationary = np.linalg.norm(t + lam * g) <= 1e-9 * max(np.linalg.norm(t), 1e-300)
    return abs(c) <= 1e-14 * target and stationary


def lagrange_newton(problem, target, start=None):
    """Newton on grad L = 0 (L = 1/2 |t|^2 + lambda (Area - target)) with an l1 merit line
    search and a second-order correction, from `start` (t, lambda) or 0; raises DeformError
    when it stalls."""
    n = problem.D.shape[1]
    t, lam = (np.zeros(n), 0.0) if start is None else start
    mu, residual, alpha = 0.0, np.inf, 1.0   # alpha: the last line search's step
    damping = 0.0   # added to W after steps the line search cut hard (W nearly singular)
    known = None    # (area, gradient) at t when the line search computed them
    slow = 0        # full Newton steps in a row that cut the residual less than 10 times
    for it in range(1, MAX_ITERATIONS + 1):
        a, g = problem.gradient(t) if known is None else known
        known, c = None, a - target
        if it > 1 and _converged(t, g, c, target):
            return t, lam, it - 1
        if not np.any(g):
            raise _stalled(problem, target)
        # Newton with the light Hessian converges linearly where that rule is poor (a
        # tiny knot span): after two slow full Newton steps in a row, the Hessian from
        # the area's own nodes (a shifted step converges linearly by itself, and one
        # slow step follows an overshoot: the 20 x 20 canopy)
        new_residual = np.linalg.norm(t + lam * g) + abs(c) * np.linalg.norm(g)
        slow = slow + 1 if it > 3 and alpha == 1.0 and not damping and \
            not problem.shifted and new_residual > 0.1 * residual else 0
        if slow >= 2:
            problem.exact = True
        residual = new_residual
        dt, lam_new = problem.step(t, lam, g, c, damping)
        mu = max(mu, 2 * abs(lam_new), 1e-12)

        def merit(x):
            return 0.5 * x @ x + mu * abs(problem.area(x) - target)

        slope = t @ dt - mu * abs(c)
        f0, alpha = 0.5 * t @ t + mu * abs(c), 1.0      # merit(t): the area is a
        noise = 1e-14 * (f0 + mu * target)     # the merit's rounding error
        while alpha > 1e-10:
            trial = t + alpha * dt
            if alpha == 1.0:  # the full step: its gradient serves the correction or
                at, gt = problem.gradient(trial)    # the next iteration
                if 0.5 * trial @ trial + mu * abs(at - target) <= f0 + 1e-4 * min(slope, 0.0) \
                        + noise:
                    known = at, gt
                    break
                # second-order correction: back onto the constraint
                soc = trial - (at - target) * gt / (gt @ gt)
                if merit(soc) <= f0 + 1e-4 * min(slope, 0.0) + noise:
                    trial = soc
                    break
            elif merit(trial) <= f0 + 1e-4 * alpha * min(slope, 0.0) + noise:
                break
            alpha *= 0.5
        else:
            raise _stalled(problem, target)
        t, lam = trial, lam + alpha * (lam_new - lam)
        # a step cut below 0.1: the model's curvature (W on the tangent space) is far too
        # small along it (100 terrain poles crawled 60 steps at |dt| 13, alpha 1e-3), so W
        # gets damped until full steps pass, then undamped again (Newton's end kept)
        if alpha < 0.1:
            damping = max(4 * damping, LEAST_CURVATURE)
        elif alpha == 1.0:
            damping = damping / 4 if damping > 1e-3 else 0.0
    raise _stalled(problem, target)


def continued(problem, target, start=None, steps=4):
    """lagrange_newton toward `target` in `steps` equal steps of the area, each from the
    last: where one Newton run from `start` leaves the branch of least change (its first
    linear step overshoots into a region where W is indefinite, and it crawls there)."""
    a = problem.area(start[0] if start is not None else np.zeros(problem.D.shape[1]))
    total = 0
    for k in range(1, steps + 1):
        t, lam, iterations = lagrange_newton(problem, a + (target - a) * k / steps, start)
        start, total = (t, lam), total + iterations
    return t, lam, total


def _kkt_step(W, g, t, c, band=None):
    """Solve [[W, g], [g^T, 0]] [dt, lambda] = [-t, -c]: (dt, lambda, whether W was
    shifted). W need only be positive definite
    on the constraint's tangent space (then dt is a descent direction): W + sigma g g^T
    positive definite for a large sigma says so, and its Cholesky factor solves the
    system (g^T dt = -c makes the added term a shift of lambda by sigma c). Else W is
    shifted on the whole space so its least eigenvalue (Lanczos) becomes
    LEAST_CURVATURE: a shift that only just makes W definite leaves it nearly singular,
    the step runs along that eigenvector far past the constraint and the line search
    cuts it to nothing (100 terrain poles crawled 7 iterations so). (Shifting whenever W
    itself is indefinite, even where W is definite on the tangent space, made Newton
    crawl on large moves.) `band`: W's half bandwidth where it is narrow (poles interact
    only through shared cells): W itself, when positive definite, and the shifted W are
    then factored in band form (20 x 20 canopy: 4 ms against 20 ms dense), the same
    system solved."""
    n = len(t)
    sigma, shifted = 0.0, False
    lower = None if band is None else _lower_band(W, band)
    solve = None if lower is None else _band_solver(lower)
    if solve is None:
        scale = max(1.0, W.max(), -W.min())
        sigma = 1e3 * scale / (g @ g)
        M = sigma * np.outer(g, g)
        M += W
        solve = _dense_solver(M)
    if solve is None:
        sigma, shifted = 0.0, True
        try:
            low = float(eigsh(W, k=1, which="SA", v0=np.ones(n), tol=1e-6,
                              return_eigenvectors=False)[0])
        except (ArpackNoConvergence, ValueError):  # ValueError: n too small for ARPACK
            low = float(np.linalg.eigvalsh(W)[0])
        shift = -low + LEAST_CURVATURE
        while solve is None:
            solve = _dense_solver(W + shift * np.eye(n)) if lower is None else \
                _band_solver(lower, shift)
            shift *= 2
    a, b = solve(t), solve(g)
    mu = (c - g @ a) / (g @ b)
    return -a - mu * b, float(mu - sigma * c), shifted


def _dense_solver(M):
    """x -> M^-1 x by M's Cholesky factor, or None when M is not positive definite."""
    try:
        factor = cho_factor(M, lower=True, overwrite_a=True, check_finite=False)
    except np.linalg.LinAlgError:
        return None
    return lambda x: cho_solve(factor, x, check_finite=False)


def _lower_band(W, band):
    """The lower band of W (n x n, half bandwidth `band`) in LAPACK's form: row d holds
    the d-th subdiagonal."""
    n = len(W)
    lower = np.zeros((band + 1, n))
    for d in range(band + 1):
        lower[d, :n - d] = np.diagonal(W, -d)
    return lower


def _band_solver(lower, shift=0.0):
    """x -> (W + shift I)^-1 x by the banded Cholesky factor (W's lower band `lower`),
    or None when W + shift I is not positive definite."""
    ab = lower.copy()
    ab[0] += shift
    try:
        factor = cholesky_banded(ab, lower=True, overwrite_ab=True, check_finite=False)
    except np.linalg.LinAlgError:
        return None
    return lambda x: cho_solve_banded((factor, True), x, check_finite=False)


def bandwidth(D, movable, shape, degrees):
    """The half bandwidth of the reduced Hessian D^T H D (n x n): two variables interact
    only where poles of theirs share a cell (|di| <= p and |dj| <= q); None when the band
    is not narrow (a third of n or more: the dense factor is as quick)."""
    nu, nv = shape
    p, q = degrees
    n = D.shape[1]
    Dc = D.tocsc()
    var = np.repeat(np.arange(n), np.diff(Dc.indptr))
    pole = np.asarray(movable)[Dc.indices // 3]
    lo, hi = np.full(nu * nv, n), np.full(nu * nv, -1)
    np.minimum.at(lo, pole, var)
    np.maximum.at(hi, pole, var)
    lo, hi = lo.reshape(nu, nv), hi.reshape(nu, nv)
    width = 0
    for di in range(-p, p + 1):
        for dj in range(-q, q + 1):
            a = (slice(max(0, -di), nu - max(0, di)), slice(max(0, -dj), nv - max(0, dj)))
            b = (slice(max(0, di), nu - max(0, -di)), slice(max(0, dj), nv - max(0, -dj)))
            both = (hi[a] >= 0) & (hi[b] >= 0)
            if both.any():
                width = max(width, int((hi[b] - lo[a])[both].max()))
    return width if 3 * width < n else None


def on_constraint(problem, target, direction, s=0.0):
    """s * direction with Area = target, by Newton on s from `s` (the paper's feasible
    start)."""
    for _ in range(MAX_ITERATIONS):
        a, g = problem.gradient(s * direction)
        slope = g @ direction
        if abs(a - target) <= 1e-14 * target:
            return s * direction
        if slope == 0:
            break
        step = (target - a) / slope
        s += np.clip(step, -abs(s) - 1.0, abs(s) + 1.0) if s else step
    raise _stalled(problem, target)


def flat_start(problem, target):
    """None, or where the area gradient vanishes at the start (a plane: no first-order
    change along its normal) a point on the constraint along the Hessian's eigenvector of
    largest curvature of the needed sign, and its multiplier."""
    zero = np.zeros(problem.D.shape[1])
    a, g = problem.gradient(zero)
    extent = max(np.ptp(problem.Q.reshape(-1, 3), axis=0).max(), 1e-300)
    if np.linalg.norm(g) > 1e-9 * a / extent or a == target:
        return None
    w, V = np.linalg.eigh(problem.hessian(zero))
    k = int(np.argmax(w)) if target > a else int(np.argmin(w))
    if w[k] * (target - a) <= 0:
        raise _stalled(problem, target)
    t = on_constraint(problem, target, V[:, k], np.sqrt(2 * (target - a) / w[k]))
    _, g = problem.gradient(t)
    return t, -float(t @ g) / float(g @ g)


def penalty_newton(problem, target, weight=None):
    """The paper's method (Fig. 3): start on the constraint along the area gradient, then
    Newton steps on F = 1/2 |t|^2 + N/2 (Area - target)^2, no line search."""
    _, g0 = problem.gradient(np.zeros(problem.D.shape[1]))
    if not np.any(g0):
        raise _stalled(problem, target)
    t = on_constraint(problem, target, g0 / np.linalg.norm(g0))
    N = weight if weight is not None else 1e6 / (g0 @ g0)
    for it in range(1, MAX_ITERATIONS + 1):
        a, g = problem.gradient(t)
        grad = t + N * (a - target) * g
        hess = np.eye(len(t)) + N * (np.outer(g, g) + (a - target) * problem.hessian(t))
        step = np.linalg.solve(hess, -grad)
        t = t + step
        if np.linalg.norm(step) <= 1e-12 * max(np.linalg.norm(t), 1e-300):
            return t, N * (problem.area(t) - target), it
    return t, N * (problem.area(t) - target), MAX_ITERATIONS


def reachable_extreme(problem, target):
    """The smallest (target below) or largest area the poles reach, by Newton with line
    search on the area itself; None when it grows without bound."""
    sign = 1.0 if target < problem.area(np.zeros(problem.D.shape[1])) else -1.0
    t = np.zeros(problem.D.shape[1])
    for _ in range(4 * MAX_ITERATIONS):
        a, g = problem.gradient(t)
        H = sign * problem.hessian(t)
        w, V = np.linalg.eigh(H)
        step = -V @ ((V.T @ (sign * g)) / np.maximum(np.abs(w), 1e-9 * max(np.abs(w).max(), 1)))
        alpha = 1.0
        while alpha > 1e-12 and sign * problem.area(t + alpha * step) > sign * a - 1e-4 * alpha * abs(g @ step):
            alpha *= 0.5
        t = t + alpha * step
        if np.linalg.norm(t) > 1e6 * (1 + np.abs(problem.Q).max()):
            return None
        if alpha * np.linalg.norm(step) <= 1e-12 * max(1.0, np.linalg.norm(t)):
            break
    return problem.area(t)


def _stalled(problem, target):
    extreme = None if problem.sparse else reachable_extreme(problem, target)
    below = target < problem.area(np.zeros(problem.D.shape[1]))
    if extreme is not None and ((below and target < extreme) or (not below and target > extreme)):
        word = "smallest" if below else "largest"
        side = "above" if below else "below"
        return DeformError(f"TargetArea {target:.8g} cannot be reached with these poles and "
                           f"Dof: the {word} area they give is {extreme:.8g}; set TargetArea "
                           f"{side} that, or free more Poles or another Dof.", "TargetArea")
    return DeformError(f"The solver did not converge to TargetArea {target:.8g}; free more "
                       "Poles or choose another Dof.", "TargetArea")


def large(movable, dof):
    """Whether the solve has more variables than the dense solver takes."""
    return len(movable) * (3 if dof == "Free" else 1) > MAX_VARIABLES


def check_size(movable, dof, surface=None, method="Lagrange-Newton"):
    """DeformError naming Poles when the solve is too large for the dense solver and the
    large one (Lagrange-Newton on a non-rational surface) does not apply."""
    if not large(movable, dof) or (surface is not None and np.all(surface.weights == 1) and
                                   method == "Lagrange-Newton"):
        return
    variables = len(movable) * (3 if dof == "Free" else 1)
    raise DeformError(f"{len(movable)} poles with Dof {dof} are {variables} variables, more "
                      f"than the {MAX_VARIABLES} the dense solver takes, and the solver for "
                      "more takes only non-rational faces with Method Lagrange-Newton; list "
                      "in Poles the poles of the region to change.", "Poles")


def area_quadrature(surface, movable, dof="Normal", method="Lagrange-Newton"):
    """The quadrature the solve uses: `quadrature`, or for more variables than the dense
    solver takes a GridQuadrature."""
    check_size(movable, dof, surface, method)
    return grid_quadrature(surface) if large(movable, dof) else quadrature(surface, movable)


def constrain_area(quadrature, poles, movable, target, dof="Normal", method="Lagrange-Newton",
                   start=None):
    """Move the `movable` poles (flat indices into poles (nu, nv, 3)) along `dof` as little
    as possible so the area is `target`; `start`: an earlier Solution to go on from."""
    if len(movable) == 0:
        raise DeformError("No pole may move; list Poles (or leave it empty for every "
                          "interior pole of a surface that has some).", "Poles")
    if not target > 0:
        raise DeformError("TargetArea must be positive.", "TargetArea")
    grid = isinstance(quadrature, GridQuadrature)
    if not grid:
        check_size(movable, dof)
    problem = (LargeProblem if grid else Problem)(quadrature, poles, movable, dof)
    if method == "Lagrange-Newton":
        if start is not None:   # D has orthonormal columns: t = D^T (displacement)
            moved = (start.poles - problem.Q).reshape(-1, 3)[problem.movable].ravel()
            start = (problem.D.T @ moved, start.multiplier)
        elif not grid:
            start = flat_start(problem, target)
        try:
            t, lam, iterations = lagrange_newton(problem, target, start)
        except DeformError:
            t, lam, iterations = continued(problem, target, start)
    elif method == "Penalty":
        t, lam, iterations = penalty_newton(problem, target)
    else:
        raise DeformError(f"Method must be one of {', '.join(METHODS)}.", "Method")
    _, g = problem.gradient(t)
    kkt = np.linalg.norm(t + lam * g) / max(np.linalg.norm(t), 1e-300)
    new = problem.poles(t)
    held = tuple(tuple(int(x) + 1 for x in divmod(m, new.shape[1])) for m in problem.held)
    return Solution(new, quadrature.area(new), iterations, lam, float(kkt), quadrature.error,
                    problem.fallbacks, held)


def constrain_surface_area(surface, movable, target, dof="Normal", method="Lagrange-Newton",
                           q=None):
    """constrain_area on a Surface, with a quadrature that holds for the result too: the
    nodes are chosen on the original surface, checked on the new one (`error` is that
    check's estimate), and the solve goes on on the finer nodes the new shape needs.
    q: quadrature(surface, movable) when already built."""
    q = area_quadrature(surface, movable, dof, method) if q is None else q
    grid = isinstance(q, GridQuadrature)
    sol, iterations = None, 0
    for _ in range(MAX_ITERATIONS):
        sol = constrain_area(q, surface.poles, movable, target, dof, method, sol)
        iterations += sol.iterations
        q, finer = (grid_refined if grid else refined)(q, sol.poles, sol.area)
        # only the cells the poles change can fold; the others' error (the fixed rules
        # of a large face: 1.5e-8 of a terrain's area) is the same before and after
        if not finer and q.active_error > FOLDED * sol.area:
            raise DeformError(f"The surface that meets TargetArea {target:.8g} degenerates "
                              "(|S_u x S_v| near 0 along curves, as where it folds): its "
                              "area is only known to "
                              f"{q.active_error / sol.area:.0e} relative; ask for a smaller "
                              "change or free other Poles.", "TargetArea")
        if not finer:
            return sol._replace(error=q.error, iterations=iterations)
    raise _stalled((LargeProblem if grid else Problem)(q, surface.poles, movable, dof), target)


# --- the poles the Poles property names ------------------------------------------------

def parse_poles(entries, shape):
    """Flat pole indices of "i,j" entries (1-based, as getPole); none: every interior pole,
    or on a face with none (2 poles across: a ruled face) every pole but the corners."""
    nu, nv = shape
    if not entries:
        if nu > 2 and nv > 2:
            return [i * nv + j for i in range(1, nu - 1) for j in range(1, nv - 1)]
        corners = {0, nv - 1, (nu - 1) * nv, nu * nv - 1}
        free = [m for m in range(nu * nv) if m not in corners]
        if not free:
            raise DeformError(f"The face has only its {nu} x {nv} corner poles, and a corner "
                              f"cannot move without tearing the face from its edges; list "
                              f"corner poles in Poles to move them, or pick a face with "
                              f"interior poles.", "Poles")
        return free
    flat = []
    for entry in entries:
        try:
            i, j = (int(x) for x in str(entry).replace("(", "").replace(")", "").split(","))
        except ValueError:
            raise DeformError(f"Poles entry {entry!r} is not 'i,j'; correct Poles.", "Poles")
        if not (1 <= i <= nu and 1 <= j <= nv):
            raise DeformError(f"Poles: pole ({i}, {j}) is outside the {nu} x {nv} poles of "
                              f"the face (1 to {nu}, 1 to {nv}); correct Poles.", "Poles")
        flat.append((i - 1) * nv + (j - 1))
    return sorted(set(flat))


def on_boundary(flat, shape):
    """Whether any of the flat pole indices is on the border of the (nu, nv) net."""
    nu, nv = shape
    i, j = np.divmod(np.asarray(flat), nv)
    return bool(np.any((i == 0) | (i == nu - 1) | (j == 0) | (j == nv - 1)))
