"""Rigid motions M(t), t in [0, 1], M(0) = identity (Wu & Ilies 2011, section 2.2).

A rigid transform is a 4x4 numpy array acting on homogeneous column vectors: x' = R x + d
is [[R, d], [0, 0, 0, 1]]. A motion object has `matrix(t)` (4, 4), `matrices(ts)` (K, 4, 4)
and `velocity(points, t)`: the tangents d/dt M(t) p of the trajectories of the points p
(given at their original place, t = 0) at parameter t.

- `ScrewMotion(T)`: the constant-speed screw motion from I to T (Chasles): a rotation by
  t*angle about T's screw axis and a slide t*slide along it. A pure rotation revolves every
  point on a circle, a pure translation extrudes it along a line.
- `KeyMotion(keys, params)`: a rational (Juttler & Wagner) motion through key configurations;
  every point trajectory is a rational curve, i.e. a NURBS curve.
- `profile_frames(motion, point, ts)`: placements of the profile plane along the sweeping
  path of a reference point (Steps 5 and 6 of Case 1 in the paper).
"""
import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.spatial.transform import Rotation

from ..blocks import BLOCK, add_rows, tiled
from ..errors import DeformError
from ..vectors import skew, unit
from .planes import frame

_RIGID_TOL = 1e-9        # how far a given 4x4 may be from a rigid transform
_TRANSLATION_ANGLE = 1e-13   # rotation angles below this are treated as exactly zero


# ---------------------------------------------------------------- transforms

def _homogeneous(R, d):
    """[[R, d], [0, 1]] for R (..., 3, 3), d (..., 3)."""
    R, d = np.asarray(R, float), np.asarray(d, float)
    shape = np.broadcast_shapes(R.shape[:-2], d.shape[:-1])
    M = np.zeros(shape + (4, 4))
    M[..., :3, :3] = R
    M[..., :3, 3] = d
    M[..., 3, 3] = 1.0
    return M


def _rodrigues(k, phi):
    """Rotation matrices (..., 3, 3) by the angles phi (...) about the unit vector k."""
    phi = np.asarray(phi, float)
    K = skew(k)
    s, h = np.sin(phi)[..., None, None], np.sin(phi / 2)[..., None, None]
    return np.eye(3) + s * K + 2 * h * h * (K @ K)


def rotation(point, direction, angle):
    """The 4x4 rotation by `angle` (radians, right-hand rule about `direction`) about the
    line through `point`. An array of angles (K,) gives a stack (K, 4, 4)."""
    k = unit(np.asarray(direction, float).reshape(3), "Axis")
    c = np.asarray(point, float).reshape(3)
    R = _rodrigues(k, angle)
    return _homogeneous(R, c - R @ c)


def translation(vector):
    """The 4x4 translation by `vector` (3,); vectors (K, 3) give a stack (K, 4, 4)."""
    v = np.asarray(vector, float)
    return _homogeneous(np.eye(3), v)


def apply(matrix, points, out=None, where=None):
    """Points (N, 3) moved by one transform (4, 4) -> (N, 3), or by each of a stack
    (K, 4, 4) -> (K, N, 3).

    One transform goes BLOCK rows at a time (in the CPU cache), into `out` (N, 3),
    C-contiguous and apart from `points`, when given; with `where` (N,) bool, only those
    rows are moved and the others are copied bit-identical (every row is transformed and the
    others copied back: cheaper than a gather and a scatter of the moved ones)."""
    M = np.asarray(matrix, float)
    P = np.asarray(points, float).reshape(-1, 3)
    if M.ndim > 2:
        return P @ np.swapaxes(M[..., :3, :3], -1, -2) + M[..., None, :3, 3]
    if out is None:
        out = np.empty((len(P), 3))
    elif not out.flags.c_contiguous or np.may_share_memory(out, P):
        raise ValueError("apply: out must be C-contiguous and apart from points")
    turn, shift = np.ascontiguousarray(M[:3, :3].T), tiled(M[:3, 3], len(P))
    for i in range(0, len(P), BLOCK):
        p, head = P[i:i + BLOCK], out[i:i + BLOCK]
        np.matmul(p, turn, out=head)
        add_rows(head, shift)
        if where is not None:
            still = np.flatnonzero(~where[i:i + BLOCK])
            head[still] = p.take(still, axis=0)
    return out


def apply_each(matrices, points):
    """Point i moved by transform i: matrices (N, 4, 4), points (N, 3) -> (N, 3)."""
    M = np.asarray(matrices, float).reshape(-1, 4, 4)
    P = np.asarray(points, float).reshape(-1, 3)
    return np.einsum("nij,nj->ni", M[:, :3, :3], P) + M[:, :3, 3]


def fraction_matrices(motion_of_s, fracs):
    """The transforms (K, 4, 4) of `motion_of_s` at the fractions (K,).

    motion_of_s: a motion object (its `matrices` is used), a callable marked `vectorized`
    (called once with the array; `twist_motion` and `bend_motion` are), or any callable
    frac -> 4x4 (called once per distinct fraction).
    """
    f = np.asarray(fracs, float).reshape(-1)
    if hasattr(motion_of_s, "matrices"):
        return np.asarray(motion_of_s.matrices(f), float).reshape(-1, 4, 4)
    if getattr(motion_of_s, "vectorized", False):
        return np.broadcast_to(np.asarray(motion_of_s(f), float), (len(f), 4, 4))
    distinct, inverse = np.unique(f, return_inverse=True)
    stack = np.array([np.asarray(motion_of_s(float(x)), float).reshape(4, 4) for x in distinct])
    return stack.reshape(-1, 4, 4)[inverse.reshape(-1)]


def _check_rigid(T, prop, what):
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.isfinite(T).all():
        raise DeformError(f"{what} must be a finite 4x4 transform; fix {prop}.", prop)
    R = T[:3, :3]
    if (np.abs(R.T @ R - np.eye(3)).max() > _RIGID_TOL or np.linalg.det(R) <= 0
            or np.abs(T[3] - [0, 0, 0, 1]).max() > _RIGID_TOL):
        raise DeformError(f"{what} is not a rigid motion (it scales, shears or mirrors); "
                          f"fix {prop}.", prop)
    return T


# ---------------------------------------------------------------- screw motion

def _one_minus_sinc(phi):
    """1 - sin(phi)/phi, without cancellation near 0."""
    phi = np.asarray(phi, float)
    p2 = phi * phi
    series = p2 / 6 * (1 - p2 / 20 * (1 - p2 / 42 * (1 - p2 / 72)))
    safe = np.where(phi == 0, 1.0, phi)
    return np.where(np.abs(phi) < 0.1, series, 1 - np.sin(safe) / safe)


def _one_minus_x_cot_x(x):
    """1 - x cot(x), without cancellation near 0 (x in [0, pi/2])."""
    x2 = x * x
    if x < 0.1:
        return x2 / 3 + x2 * x2 / 45 + 2 * x2 ** 3 / 945 + x2 ** 4 / 4725
    return 1 - x / np.tan(x)


class ScrewMotion:
    """The constant-speed screw motion from I to the rigid transform T.

    By Chasles' theorem T is a rotation by `angle` (in [0, pi]) about a line (through
    `axis_point`, the point of the line nearest the origin, along the unit `axis_direction`)
    followed by a slide `slide` along that line. M(t) turns by t*angle and slides t*slide:
    M(t) = exp(t xi) with the constant twist xi = (omega, v), so every trajectory is a helix
    about the axis, a circle for a pure rotation (a revolve), a straight line for a pure
    translation (an extrusion; then the axis is the translation direction through the
    origin, angle 0). Computed without the axis point, so angles near 0 and pi are exact
    to rounding; angles below 1e-13 count as a pure translation.
    """

    def __init__(self, T, prop="Placement"):
        T = _check_rigid(T, prop, "The rigid transformation")
        self.T = T.copy()
        R, d = T[:3, :3], T[:3, 3]
        rotvec = Rotation.from_matrix(R).as_rotvec()
        theta = float(np.linalg.norm(rotvec))
        if theta < _TRANSLATION_ANGLE:
            theta = 0.0
            length = np.linalg.norm(d)
            k = d / length if length > 0 else np.array([0.0, 0.0, 1.0])
            v = d.copy()
        else:
            k = rotvec / theta
            # v = V(theta)^-1 d with V(phi) = I + (1 - cos phi)/phi [k] + (1 - sin phi/phi) [k]^2
            kd = np.cross(k, d)
            v = d - theta / 2 * kd + _one_minus_x_cot_x(theta / 2) * np.cross(k, kd)
        self.angle = theta
        self.axis_direction = k
        self.slide = float(d @ k)
        self._v = v
        self._omega = theta * k
        self.axis_point = np.cross(k, v) / theta if theta > 0 else np.zeros(3)

    def matrices(self, ts):
        """M(t) for each t of ts (K,): (K, 4, 4)."""
        t = np.asarray(ts, float).reshape(-1)
        k, v, theta = self.axis_direction, self._v, self.angle
        phi = t * theta
        R = _rodrigues(k, phi)
        kv = np.cross(k, v)
        # translation t V(t theta) v, written so that theta = 0 needs no special case
        a = 2 * np.sin(phi / 2) ** 2 / theta if theta > 0 else np.zeros_like(t)
        d = (t[:, None] * v + a[:, None] * kv
             + (t * _one_minus_sinc(phi))[:, None] * np.cross(k, kv))
        return _homogeneous(R, d)

    def matrix(self, t):
        """M(t): (4, 4)."""
        return self.matrices([t])[0]

    def velocity(self, points, t=0.0):
        """Trajectory tangents (N, 3) at t of the points (N, 3) given at t = 0: analytic,
        omega x (M(t) p - c) + slide * axis_direction = omega x M(t) p + v."""
        x = apply(self.matrix(t), points)
        return np.cross(self._omega, x) + self._v


# ---------------------------------------------------------------- rational key motion

def _qmul(a, b):
    """Quaternion products (w, x, y, z) of a (..., 4) and b (..., 4)."""
    a0, av, b0, bv = a[..., :1], a[..., 1:], b[..., :1], b[..., 1:]
    return np.concatenate([a0 * b0 - np.sum(av * bv, -1, keepdims=True),
                           a0 * bv + b0 * av + np.cross(av, bv)], -1)


def _conj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def _rot_bilinear(a, b):
    """The symmetric bilinear form B with B(q, q) = |q|^2 R(q/|q|): (..., 3, 3)."""
    w, x, y, z = (a[..., i] for i in range(4))
    W, X, Y, Z = (b[..., i] for i in range(4))
    ww, xx, yy, zz = w * W, x * X, y * Y, z * Z
    xy, xz, yz = x * Y + y * X, x * Z + z * X, y * Z + z * Y
    wx, wy, wz = w * X + x * W, w * Y + y * W, w * Z + z * W
    return np.stack([np.stack([ww + xx - yy - zz, xy - wz, xz + wy], -1),
                     np.stack([xy + wz, ww - xx + yy - zz, yz - wx], -1),
                     np.stack([xz - wy, yz + wx, ww - xx - yy + zz], -1)], -2)


def _dual_quaternion(T):
    """Unit dual quaternion (q, q0) (8,) of the rigid T: x -> q x q* + d, q0 = d q / 2."""
    x, y, z, w = Rotation.from_matrix(T[:3, :3]).as_quat()
    q = np.array([w, x, y, z])
    q0 = 0.5 * _qmul(np.r_[0.0, T[:3, 3]], q)
    return np.r_[q, q0]


class KeyMotion:
    """A smooth rational motion through key configurations (Juttler & Wagner).

    keys: rigid 4x4 transforms, the first the identity; params: their parameters, ascending
    from 0 to 1 (default uniform). The keys' unit dual quaternions (consecutive ones put in
    the same hemisphere) are interpolated per component by a spline Q(t) = q(t) + eps q0(t)
    of degree k: cubic (C2, not-a-knot ends) with 4 or more keys, quadratic with 3, linear
    with 2. M(t) is x -> (q x q* + 2 vec(q0 q*)) / |q|^2, a rigid motion for every t
    whatever Q (q must not vanish; checked), equal to each key at its parameter. Each point
    trajectory is therefore a piecewise rational curve of degree 2k in t (6 for cubic, a
    NURBS curve; 2 with two keys: rational quadratic, e.g. an exact circular arc about the
    axis of a rotation key, a straight line for a translation), with the same continuity
    as the spline. With two keys [I, T] every M(t) is a screw about T's screw axis, but its
    angle and slide are not linear in t (it is not the ScrewMotion).
    `velocity` is analytic (derivative of the spline and of the quotient).
    """

    def __init__(self, keys, params=None, prop="Keys"):
        keys = [_check_rigid(K, prop, f"Key {i + 1}") for i, K in enumerate(keys)]
        if len(keys) < 2:
            raise DeformError(f"A key motion needs at least 2 keys; add keys to {prop}.", prop)
        if np.abs(keys[0] - np.eye(4)).max() > _RIGID_TOL:
            raise DeformError(f"The first key must be the identity (the motion starts where the "
                              f"part is); fix {prop}.", prop)
        n = len(keys)
        t = np.linspace(0.0, 1.0, n) if params is None else np.asarray(params, float).ravel()
        if len(t) != n or not np.isfinite(t).all() or t[0] != 0.0 or t[-1] != 1.0 \
                or (np.diff(t) <= 0).any():
            raise DeformError(f"The key parameters must rise strictly from 0 to 1, one per key; "
                              f"fix {prop}.", prop)
        Q = np.array([_dual_quaternion(K) for K in keys])
        Q[0] = [1, 0, 0, 0, 0, 0, 0, 0]
        for i in range(1, n):
            if Q[i, :4] @ Q[i - 1, :4] < 0:
                Q[i] = -Q[i]
        self.keys = np.array(keys)
        self.params = t
        self.degree = min(3, n - 1)
        self._spline = make_interp_spline(t, Q, k=self.degree, axis=0)
        self._dspline = self._spline.derivative()
        dense = self._spline(np.linspace(0.0, 1.0, 64 * n + 1))[:, :4]
        if (np.einsum("ij,ij->i", dense, dense) < 1e-6).any():
            raise DeformError(f"The keys turn by nearly a full turn between neighbours, so the "
                              f"motion is undefined; add intermediate keys to {prop}.", prop)

    def dual_quaternions(self, ts):
        """The (non-normalised) dual quaternions Q(t) = (q, q0) (K, 8) of the spline."""
        return self._spline(np.asarray(ts, float).reshape(-1))

    def matrices(self, ts):
        """M(t) for each t of ts (K,): (K, 4, 4)."""
        Q = self.dual_quaternions(ts)
        q, q0 = Q[:, :4], Q[:, 4:]
        w = np.einsum("ij,ij->i", q, q)
        R = _rot_bilinear(q, q) / w[:, None, None]
        d = 2 * _qmul(q0, _conj(q))[:, 1:] / w[:, None]
        return _homogeneous(R, d)

    def matrix(self, t):
        """M(t): (4, 4)."""
        return self.matrices([t])[0]

    def derivatives(self, ts):
        """dM/dt (K, 4, 4) (bottom row zero), by the quotient rule on the spline."""
        t = np.asarray(ts, float).reshape(-1)
        Q, dQ = self._spline(t), self._dspline(t)
        q, q0, dq, dq0 = Q[:, :4], Q[:, 4:], dQ[:, :4], dQ[:, 4:]
        w = np.einsum("ij,ij->i", q, q)
        dw = 2 * np.einsum("ij,ij->i", q, dq)
        Rn, dRn = _rot_bilinear(q, q), 2 * _rot_bilinear(q, dq)
        un = 2 * _qmul(q0, _conj(q))[:, 1:]
        dun = 2 * (_qmul(dq0, _conj(q)) + _qmul(q0, _conj(dq)))[:, 1:]
        dR = (dRn * w[:, None, None] - Rn * dw[:, None, None]) / (w * w)[:, None, None]
        dd = (dun * w[:, None] - un * dw[:, None]) / (w * w)[:, None]
        out = _homogeneous(dR, dd)
        out[:, 3, 3] = 0.0
        return out

    def velocity(self, points, t=0.0):
        """Trajectory tangents (N, 3) at t of the points (N, 3) given at t = 0 (analytic)."""
        D = self.derivatives([t])[0]
        return np.asarray(points, float).reshape(-1, 3) @ D[:3, :3].T + D[:3, 3]


# ---------------------------------------------------------------- profile placements

def profile_frames(motion, point, ts, x_axis=None):
    """Placements (K, 4, 4) of the profile plane along the sweeping path of `point` (P1).

    For each t_i: origin M(t_i) P1; z axis the unit trajectory tangent there (from
    `motion.velocity`); x axis the motion's rotation R(t_i) applied to the section's
    `x_axis` (default: a fixed axis perpendicular to the tangent at t = 0, planes.frame)
    and made perpendicular to the tangent; y = z x x. Columns are x, y, z, origin, so the
    placement maps the profile's local XY plane onto the plane normal to the path.
    Where the rotated x axis is (nearly) along the tangent, a fixed perpendicular is used.
    """
    P = np.asarray(point, float).reshape(1, 3)
    ts = np.asarray(ts, float).reshape(-1)
    M = np.asarray(motion.matrices(ts), float)
    origins = apply(M, P)[:, 0]
    tangents = np.array([motion.velocity(P, t)[0] for t in ts]).reshape(-1, 3)
    speed = np.linalg.norm(tangents, axis=1)
    scale = max(1.0, float(np.abs(origins).max(initial=0.0)))
    if (speed <= 1e-12 * scale).any():
        raise DeformError("The reference point does not move along the motion (it lies on the "
                          "rotation axis), so its path has no tangent; move Axis off the "
                          "section.", "Axis")
    z = tangents / speed[:, None]
    x0 = frame(z[0])[0] if x_axis is None else unit(np.asarray(x_axis, float).reshape(3), "Plane")
    x = M[:, :3, :3] @ x0
    x -= np.einsum("ij,ij->i", x, z)[:, None] * z
    length = np.linalg.norm(x, axis=1)
    bad = length < 1e-6
    if bad.any():
        x[bad] = np.array([frame(zi)[0] for zi in z[bad]])
        length[bad] = 1.0
    x /= length[:, None]
    y = np.cross(z, x)
    out = np.zeros((len(ts), 4, 4))
    out[:, :3, 0], out[:, :3, 1], out[:, :3, 2], out[:, :3, 3] = x, y, z, origins
    out[:, 3, 3] = 1.0
    return out


class PiecewiseScrew:
    """Constant-speed screw motions from each key to the next: exact lines and circles
    between the keys, continuous (C0) at them. keys[0] must be the identity."""

    def __init__(self, keys, params=None, prop="Keys"):
        self.keys = [np.asarray(k, float) for k in keys]
        if len(self.keys) < 2 or not np.allclose(self.keys[0], np.eye(4), atol=1e-12):
            raise DeformError("A key motion needs the identity first and at least one more "
                              "key.", prop)
        count = len(self.keys) - 1
        self.params = np.linspace(0.0, 1.0, count + 1) if params is None else np.asarray(
            params, float)
        if len(self.params) != count + 1 or np.any(np.diff(self.params) <= 0):
            raise DeformError("Key parameters must rise from 0 to 1, one per key.", prop)
        self.pieces = [ScrewMotion(b @ np.linalg.inv(a), prop)
                       for a, b in zip(self.keys[:-1], self.keys[1:])]

    def _locate(self, t):
        i = int(np.clip(np.searchsorted(self.params, t, side="right") - 1, 0, len(self.pieces) - 1))
        a, b = self.params[i], self.params[i + 1]
        return i, (t - a) / (b - a), 1.0 / (b - a)

    def matrix(self, t):
        i, local, _ = self._locate(float(t))
        return self.pieces[i].matrix(local) @ self.keys[i]

    def matrices(self, ts):
        return np.array([self.matrix(t) for t in np.asarray(ts, float).reshape(-1)])

    def velocity(self, points, t=0.0):
        """Tangents at M(t) p of the points p (the piece's screw velocity, chain rule)."""
        i, local, rate = self._locate(float(t))
        moved_by_key = apply(self.keys[i], np.asarray(points, float).reshape(-1, 3))
        return rate * self.pieces[i].velocity(moved_by_key, local)


INTERPOLATIONS = ("Rational", "Screw")


def key_motion(keys, interpolation="Rational"):
    """The motion through `keys` (4x4, the identity first): "Rational" is KeyMotion (a C2
    dual-quaternion spline, NURBS paths), "Screw" is PiecewiseScrew (exact between keys)."""
    if interpolation not in INTERPOLATIONS:
        raise DeformError(f"Interpolation must be one of {', '.join(INTERPOLATIONS)}.",
                          "Interpolation")
    return KeyMotion(keys) if interpolation == "Rational" else PiecewiseScrew(keys)
