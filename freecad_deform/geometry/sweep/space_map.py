"""Space maps between two parallel planes (Wu & Ilies, Case 2, and the scaling function of
Step 6): every point p of the region goes through an affine transform A(t) that depends
only on t = profile(s), s = (p - origin) . normal / gap clamped to [0, 1]. Before Plane
(s <= 0) A(0) is the identity; beyond Plane2 the part moves rigidly (or, for a taper, is
scaled) by A(1).

- Twist: A(t) a rotation by t * angle about the axis (mesh_sweep.twist_motion);
- Bend: the section at s turned about the axis, A(t) = mesh_sweep.bend_motion(t);
- Taper: a scale about the axis by 1 + (Scale - 1) t (two values across the axis);
- Stretch: a translation t * distance along the normal (affine for a Linear profile).

Profiles: "Linear" t = s, or "Smooth" t = 3 s^2 - 2 s^3 (zero slope at both planes, so
the map's derivative equals the rigid parts' there and every joint face is G1).
Points are (N, 3) arrays.
"""
import numpy as np

from ..errors import DeformError
from ..mesh.sweep import bend_motion, twist_motion
from .motion import apply_each, fraction_matrices, translation
from .planes import frame, unit_normal

PROFILES = ("Linear", "Smooth")


def profile_value(profile, s):
    """t(s) of a profile for s in [0, 1]."""
    s = np.asarray(s, float)
    if profile == "Linear":
        return s
    if profile == "Smooth":
        return s * s * (3.0 - 2.0 * s)
    raise DeformError(f"Profile must be one of {', '.join(PROFILES)} (it is {profile!r}); "
                      "choose one.", "Profile")


def profile_slope(profile, s):
    """dt/ds of a profile."""
    s = np.asarray(s, float)
    return np.ones_like(s) if profile == "Linear" else 6.0 * s * (1.0 - s)


class SpaceMap:
    """p -> A(profile(s(p))) p. `transforms(t)` gives the (K, 4, 4) affine transforms at the
    fractions t (K,); `rigid` says whether each A(t) is a rigid motion; `apply(t, points)`,
    when given, maps points (N, 3) at their fractions t (N,) without building N matrices."""

    def __init__(self, origin, normal, gap, transforms, profile="Linear", rigid=True,
                 apply=None):
        self.origin = np.asarray(origin, float).reshape(3)
        self.normal = unit_normal(normal)
        self.gap = float(gap)
        if not np.isfinite(self.gap) or self.gap <= 0:
            raise DeformError("Plane2 must lie beyond Plane along its normal (on the moving "
                              "side); move Plane2.", "Plane2")
        profile_value(profile, 0.0)
        self.profile = profile
        self.transforms = transforms
        self.rigid = rigid
        self.apply = apply

    def s(self, points):
        """The position (N,) of each point along the region, clamped to [0, 1]."""
        pts = np.asarray(points, float).reshape(-1, 3)
        return np.clip((pts - self.origin) @ self.normal / self.gap, 0.0, 1.0)

    def matrices(self, s):
        """A(profile(s)) for positions s (K,): (K, 4, 4)."""
        t = profile_value(self.profile, np.asarray(s, float).reshape(-1))
        return fraction_matrices(self.transforms, t)

    def __call__(self, points, clamp=True):
        """The mapped points. clamp=False continues the map's formula past both planes
        (the profile polynomial unclamped): equal to the map inside the region and smooth
        across the planes, for fitting a face whose parameter rectangle reaches out of it."""
        pts = np.asarray(points, float).reshape(-1, 3)
        s = self.s(pts) if clamp else (pts - self.origin) @ self.normal / self.gap
        if self.apply is not None:
            return self.apply(profile_value(self.profile, s), pts)
        return apply_each(fraction_matrices(self.transforms, profile_value(self.profile, s)),
                          pts)

    @property
    def end(self):
        """A(1): how the part beyond Plane2 moves."""
        return self.matrices([1.0])[0]

    def normal_derivative(self, points, side):
        """d map(p + h n)/dh at points on a joint, one-sided into the region (side 0: at
        Plane, from above; side 1: at Plane2, from below), pulled back by the rigid part's
        linear map, minus n: zero where the joint is C1. (N, 3)."""
        pts = np.asarray(points, float).reshape(-1, 3)
        h = 1e-4 * self.gap * (1.0 if side == 0 else -1.0)
        # one-sided, second order: exact for the quadratic start of a Smooth profile
        d = (-3 * self(pts) + 4 * self(pts + h * self.normal)
             - self(pts + 2 * h * self.normal)) / (2 * h)
        lin = np.eye(3) if side == 0 else self.end[:3, :3]
        return np.linalg.solve(lin, d.T).T - self.normal

    def jacobian_det(self, points, h=None):
        """det of the map's derivative at points inside the region (central differences):
        positive where the map does not fold."""
        pts = np.asarray(points, float).reshape(-1, 3)
        h = 1e-6 * self.gap if h is None else h
        cols = [(self(pts + h * e) - self(pts - h * e)) / (2 * h) for e in np.eye(3)]
        return np.linalg.det(np.stack(cols, axis=-1))

    def check_fold(self, points, prop="Angle"):
        """Raise unless the map keeps the orientation at the sample points of the region."""
        pts = np.asarray(points, float).reshape(-1, 3)
        s = (pts - self.origin) @ self.normal / self.gap
        inside = pts[(s > 1e-6) & (s < 1 - 1e-6)]
        if len(inside) and np.min(self.jacobian_det(inside)) <= 0:
            if self.profile == "Linear":
                raise DeformError(f"The deformation folds the region over itself (part of it "
                                  f"would pass through the axis); change {prop}.", prop)
            raise DeformError(f"The {self.profile} profile folds the region over itself; "
                              f"change {prop} to Linear or lower the deformation.", prop)


def twist_map(origin, normal, gap, angle, axis_point, axis_direction, profile="Linear"):
    """Rotation by profile(s) * angle (radians) about the axis. The map also carries
    `twist_axis` (point, unit direction) and `angle_of(s)`: surfaces of revolution about
    that axis map to themselves, their points turning by angle_of(s)."""
    c, k = np.asarray(axis_point, float), unit_normal(axis_direction, "Axis")

    def apply(t, pts):
        return c + _turned(pts - c, k, float(angle) * t)

    smap = SpaceMap(origin, normal, gap,
                    twist_motion(origin, normal, gap, angle, axis_point, axis_direction),
                    profile, apply=apply)
    smap.twist_axis = (np.asarray(axis_point, float), unit_normal(axis_direction, "Axis"))
    smap.angle_of = lambda s: float(angle) * profile_value(profile, s)
    return smap


def bend_map(origin, normal, gap, angle, axis_point, axis_direction, profile="Linear"):
    """The two-plane bend: the section at s goes to the section at Plane turned about the
    axis by angle * t (the Linear map wraps the region around the axis)."""
    c, k = np.asarray(axis_point, float), unit_normal(axis_direction, "Axis")
    shift = float(gap) * unit_normal(normal)

    def apply(t, pts):
        return c + _turned(pts - np.outer(t, shift) - c, k, float(angle) * t)

    return SpaceMap(origin, normal, gap,
                    bend_motion(axis_point, axis_direction, angle, origin, normal, gap), profile,
                    apply=apply)


def _turned(v, k, phi):
    """Vectors v (N, 3) turned by the angles phi (N,) about the unit axis k (Rodrigues)."""
    cos, sin = np.cos(phi)[:, None], np.sin(phi)[:, None]
    return v * cos + np.cross(k, v) * sin + np.outer(v @ k, k) * (1.0 - cos)


def taper_map(origin, normal, gap, scale, axis_point, axis_frame=None, profile="Linear"):
    """Scale about the axis by 1 + (scale - 1) t across it; `scale` a number or (sx, sy)
    along the first two rows of `axis_frame` (rows x, y, axis direction; default: the
    frame of the normal)."""
    sx, sy = (scale, scale) if np.ndim(scale) == 0 else scale
    if not (np.isfinite(sx) and np.isfinite(sy) and sx > 0 and sy > 0):
        raise DeformError("Scale must be positive (the section cannot shrink to nothing or "
                          "turn over); change Scale.", "Scale")
    rows = frame(normal) if axis_frame is None else np.asarray(axis_frame, float)
    ex, ey, w = rows
    c = np.asarray(axis_point, float).reshape(3)

    def transforms(t):
        t = np.asarray(t, float).reshape(-1)
        kx, ky = 1 + (sx - 1) * t, 1 + (sy - 1) * t
        lin = (kx[:, None, None] * np.outer(ex, ex) + ky[:, None, None] * np.outer(ey, ey)
               + np.outer(w, w))
        out = np.zeros((len(t), 4, 4))
        out[:, :3, :3] = lin
        out[:, :3, 3] = c - lin @ c
        out[:, 3, 3] = 1.0
        return out

    def apply(t, pts):
        d = pts - c
        return pts + np.outer((sx - 1) * t * (d @ ex), ex) + np.outer((sy - 1) * t * (d @ ey), ey)

    transforms.vectorized = True
    return SpaceMap(origin, normal, gap, transforms, profile, rigid=sx == sy == 1, apply=apply)


def stretch_map(origin, normal, gap, distance, profile="Linear"):
    """The region stretched along the normal by `distance` (the far part translated)."""
    n = unit_normal(normal)
    if 1 + distance * float(np.max(profile_slope(profile, np.linspace(0, 1, 101)))) / gap <= 0 \
            or gap + distance <= 0:
        raise DeformError("Distance shrinks the region past nothing; raise Distance.",
                          "Distance")

    def transforms(t):
        return translation(np.asarray(t, float).reshape(-1)[:, None] * distance * n)

    transforms.vectorized = True
    smap = SpaceMap(origin, normal, gap, transforms, profile,
                    apply=lambda t, pts: pts + np.outer(t * distance, n))
    smap.affine = profile == "Linear"  # one affine map over the region: planes stay planes
    return smap
