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

from .bspline_area import Quadrature, quadrature
from .errors import DeformError

DOFS = ("Normal", "Z", "Free")
METHODS = ("Lagrange-Newton", "Penalty")
MAX_ITERATIONS = 60


class Solution(NamedTuple):
    poles: np.ndarray       # (nu, nv, 3) the new poles
    area: float             # exact area of the result
    iterations: int
    multiplier: float       # lambda: displacement = -lambda * area gradient at the optimum
    kkt: float              # |t + lambda g| / |t|: 0 when the displacement is parallel to g


def directions(poles, movable, dof):
    """(3k, n) matrix D: pole displacements = D @ t. Free: 3 per pole; Z: z only; Normal:
    along the control-net normal, the mean of the unit normals of the net's triangles
    around the pole (the paper's proposal, 3.4)."""
    k = len(movable)
    if dof == "Free":
        return np.eye(3 * k)
    if dof == "Z":
        d = np.tile([0.0, 0.0, 1.0], (k, 1))
    elif dof == "Normal":
        d = np.array([net_normal(poles, m) for m in movable])
    else:
        raise DeformError(f"Dof must be one of {', '.join(DOFS)}.", "Dof")
    D = np.zeros((3 * k, k))
    D[3 * np.arange(k)[:, None] + np.arange(3), np.arange(k)[:, None]] = d
    return D


def net_normal(poles, flat_index):
    """Unit mean normal of the control-net triangles around a pole, oriented like
    S_u x S_v (u along the first pole index)."""
    nu, nv, _ = poles.shape
    i, j = divmod(int(flat_index), nv)
    P = poles
    total = np.zeros(3)
    for di, dj, ei, ej in ((1, 0, 0, 1), (0, 1, -1, 0), (-1, 0, 0, -1), (0, -1, 1, 0)):
        a, b = (i + di, j + dj), (i + ei, j + ej)
        if 0 <= a[0] < nu and 0 <= a[1] < nv and 0 <= b[0] < nu and 0 <= b[1] < nv:
            n = np.cross(P[a] - P[i, j], P[b] - P[i, j])
            if np.linalg.norm(n) > 0:
                total += n / np.linalg.norm(n)
    if np.linalg.norm(total) == 0:
        raise DeformError(f"Pole ({i + 1}, {j + 1}) has no control-net normal; use Dof Z "
                          "or Free.", "Dof")
    return total / np.linalg.norm(total)


class Problem:
    """Area, gradient and Hessian as functions of the reduced variables t (n,)."""

    def __init__(self, quadrature, poles, movable, dof):
        self.q = quadrature
        self.Q = np.asarray(poles, float)
        self.movable = np.asarray(movable, int)
        self.D = directions(self.Q, self.movable, dof)

    def poles(self, t):
        P = self.Q.reshape(-1, 3).copy()
        P[self.movable] += (self.D @ t).reshape(-1, 3)
        return P.reshape(self.Q.shape)

    def area(self, t):
        return self.q.area(self.poles(t))

    def gradient(self, t):
        a, g = self.q.gradient(self.poles(t), self.movable)
        return a, self.D.T @ g.ravel()

    def hessian(self, t):
        return self.D.T @ self.q.hessian(self.poles(t), self.movable) @ self.D


def _converged(t, lam, g, c, target):
    stationary = np.linalg.norm(t + lam * g) <= 1e-9 * max(np.linalg.norm(t), 1e-300)
    return abs(c) <= 1e-14 * target and stationary


def lagrange_newton(problem, target):
    """Newton on grad L = 0 (L = 1/2 |t|^2 + lambda (Area - target)) with an l1 merit line
    search and a second-order correction; raises DeformError when it stalls."""
    n = problem.D.shape[1]
    t, lam, mu = np.zeros(n), 0.0, 0.0
    for it in range(1, MAX_ITERATIONS + 1):
        a, g = problem.gradient(t)
        c = a - target
        if it > 1 and _converged(t, lam, g, c, target):
            return t, lam, it - 1
        if not np.any(g):
            raise _stalled(problem, target)
        W = np.eye(n) + lam * problem.hessian(t)
        dt, lam_new = _kkt_step(W, g, t, c)
        mu = max(mu, 2 * abs(lam_new), 1e-12)

        def merit(x):
            return 0.5 * x @ x + mu * abs(problem.area(x) - target)

        slope = t @ dt - mu * abs(c)
        f0, alpha = merit(t), 1.0
        while alpha > 1e-10:
            trial = t + alpha * dt
            if merit(trial) <= f0 + 1e-4 * alpha * min(slope, 0.0):
                break
            if alpha == 1.0:  # second-order correction: back onto the constraint
                at, gt = problem.gradient(trial)
                soc = trial - (at - target) * gt / (gt @ gt)
                if merit(soc) <= f0 + 1e-4 * min(slope, 0.0):
                    trial = soc
                    break
            alpha *= 0.5
        else:
            raise _stalled(problem, target)
        t, lam = trial, lam + alpha * (lam_new - lam)
    raise _stalled(problem, target)


def _kkt_step(W, g, t, c):
    """Solve [[W, g], [g^T, 0]] [dt, lambda] = [-t, -c]; W is shifted to be positive
    definite (on the whole space, which is enough) so dt is a descent direction."""
    n = len(t)
    shift = 0.0
    while True:
        try:
            np.linalg.cholesky(W + shift * np.eye(n))
            break
        except np.linalg.LinAlgError:
            shift = max(2 * shift, 1e-8 * max(1.0, np.abs(W).max()))
    K = np.block([[W + shift * np.eye(n), g[:, None]], [g[None, :], np.zeros((1, 1))]])
    x = np.linalg.solve(K, np.concatenate([-t, [-c]]))
    return x[:n], float(x[n])


def on_constraint(problem, target, direction):
    """s * direction with Area = target, by Newton on s (the paper's feasible start)."""
    s = 0.0
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
    extreme = reachable_extreme(problem, target)
    below = target < problem.area(np.zeros(problem.D.shape[1]))
    if extreme is not None and ((below and target < extreme) or (not below and target > extreme)):
        word = "smallest" if below else "largest"
        side = "above" if below else "below"
        return DeformError(f"TargetArea {target:.8g} cannot be reached with these poles and "
                           f"Dof: the {word} area they give is {extreme:.8g}; set TargetArea "
                           f"{side} that, or free more Poles or another Dof.", "TargetArea")
    return DeformError(f"The solver did not converge to TargetArea {target:.8g}; free more "
                       "Poles or choose another Dof.", "TargetArea")


def constrain_area(quadrature, poles, movable, target, dof="Normal", method="Lagrange-Newton"):
    """Move the `movable` poles (flat indices into poles (nu, nv, 3)) along `dof` as little
    as possible so the area is `target`."""
    if len(movable) == 0:
        raise DeformError("No pole may move; list Poles (or leave it empty for every "
                          "interior pole of a surface that has some).", "Poles")
    if not target > 0:
        raise DeformError("TargetArea must be positive.", "TargetArea")
    problem = Problem(quadrature, poles, movable, dof)
    if method == "Lagrange-Newton":
        t, lam, iterations = lagrange_newton(problem, target)
    elif method == "Penalty":
        t, lam, iterations = penalty_newton(problem, target)
    else:
        raise DeformError(f"Method must be one of {', '.join(METHODS)}.", "Method")
    _, g = problem.gradient(t)
    kkt = np.linalg.norm(t + lam * g) / max(np.linalg.norm(t), 1e-300)
    new = problem.poles(t)
    return Solution(new, quadrature.area(new), iterations, lam, float(kkt))


def constrain_surface_area(surface, movable, target, dof="Normal", method="Lagrange-Newton"):
    """constrain_area on a Surface, with a quadrature exact for the result too: the node
    count is chosen on the original surface, checked on the new one, and the solve is
    repeated with more nodes when the new shape needs them."""
    q = quadrature(surface)
    while True:
        sol = constrain_area(q, surface.poles, movable, target, dof, method)
        check = quadrature(surface._replace(poles=sol.poles))
        if check.count <= q.count:
            return sol
        q = Quadrature(surface, check.count)
