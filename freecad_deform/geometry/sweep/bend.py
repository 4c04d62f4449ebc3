"""Bend and twist checks and tangents: which way the section turns, and whether it can."""
import numpy as np

from ..errors import DeformError
from .planes import unit_normal


def turning_speed(points, normal, axis_point, axis_direction, angle):
    """Speed along `normal` of each section point as it starts to turn by `angle` about the axis."""
    w = unit_normal(axis_direction, "Axis")
    vel = np.cross(w, np.asarray(points, float) - np.asarray(axis_point, float))
    return np.sign(angle) * (vel @ unit_normal(normal))


def check_bend(points, normal, axis_point, axis_direction, angle):
    """Raise unless every section point turns away from the near part (a valid bend).

    The axis crossing the section means the bend radius is smaller than the section's
    extent (the swept region would fold over itself); all points turning backward means
    the far part would swing into the near one.
    """
    if angle == 0 or abs(angle) >= 2 * np.pi:
        raise DeformError("Angle must be non-zero and less than 360 degrees; change Angle.",
                          "Angle")
    pts = np.asarray(points, float)
    speed = turning_speed(pts, normal, axis_point, axis_direction, angle)
    scale = max(np.ptp(pts, axis=0).max(), 1e-9) * 1e-9
    if np.all(np.abs(speed) <= scale):
        raise DeformError("Axis is parallel to the Plane normal, so nothing bends; turn Axis "
                          "into the plane (use Twist to turn about the normal).", "Axis")
    if speed.min() < -scale and speed.max() > scale:
        raise DeformError("The bend radius is smaller than the section: Axis passes through the "
                          "cross-section at Plane; move Axis outside the section.", "Axis")
    if speed.max() <= scale:
        raise DeformError("Angle turns the far part into the near part; reverse the sign of "
                          "Angle (or flip Axis).", "Angle")


def bend_tangents(axis_point, axis_direction, shift=None):
    """Trajectory tangents of joint points under a bend: w x (p - c), p first moved by -shift."""
    w = unit_normal(axis_direction, "Axis")
    c = np.asarray(axis_point, float)
    s = np.zeros(3) if shift is None else np.asarray(shift, float)
    return lambda points: np.cross(w, np.asarray(points, float) - s - c)


def twist_tangents(normal, gap, angle, axis_point, axis_direction):
    """Tangents of the twisted trajectories s -> R(angle s / gap)(p + s n) at the joints."""
    n = unit_normal(normal)
    w = unit_normal(axis_direction, "Axis")
    c = np.asarray(axis_point, float)
    return lambda points: n + (angle / gap) * np.cross(w, np.asarray(points, float) - c)
