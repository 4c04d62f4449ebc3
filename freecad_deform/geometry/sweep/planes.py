"""Separating planes: a point and a unit normal pointing toward the part that moves."""
import numpy as np

from ..blocks import BLOCK, tiled
from ..errors import DeformError
from ..vectors import unit


TOUCH = 1e-9  # points this close to a plane count as on it (the kernels' default eps)


def unit_normal(normal, prop="Plane"):
    """`normal` scaled to length 1; a zero vector is bad input for `prop`."""
    return unit(normal, prop, "normal")


def missed(prop, where=None):
    """The refusal of a plane `prop` that does not cross the part (`where`: what lies on
    which side of it)."""
    why = f": {where}" if where else ""
    return DeformError(f"{prop} misses the part{why}; move {prop} so it crosses the part.", prop)


def check_crossing(s, prop, eps=TOUCH, touching=False,
                   where="the whole part lies on one side of it"):
    """Plane `prop` must cross the part whose points lie at signed distances `s` from it:
    some beyond eps on each side, or (touching) within eps of the plane counting for both
    sides."""
    lo, hi = float(np.min(s)), float(np.max(s))
    if not ((lo <= eps and hi >= -eps) if touching else (lo < -eps and hi > eps)):
        raise missed(prop, where)


def signed_distance(points, origin, normal):
    """Signed distance (N,) of each point (N, 3) to the plane, positive on the moving side:
    (p - origin) @ n, BLOCK rows at a time without an (N, 3) temporary, exactly 0 at a point
    equal to origin (the cheaper p @ n - origin . n is not). A normal of length 1 (to
    rounding) is used as it is, so a kernel holding a unit n gets distances along exactly
    that n; any other is scaled to length 1."""
    n = unit_as_given(normal)
    pts = np.ascontiguousarray(points, dtype=float).reshape(-1, 3)
    s = np.empty(len(pts))
    rows = np.empty(min(BLOCK, len(pts)) * 3)
    minus_o = tiled(-np.asarray(origin, dtype=float).reshape(3), len(pts))
    for i in range(0, len(pts), BLOCK):
        block = pts[i:i + BLOCK].reshape(-1)
        r = rows[:block.size]
        np.add(block, minus_o[:block.size], out=r)
        np.matmul(r.reshape(-1, 3), n, out=s[i:i + BLOCK])
    return s


def unit_as_given(normal):
    """The normal itself when its length is 1 to rounding (distances are then measured
    along exactly the n a kernel holds), else scaled to length 1."""
    n = np.asarray(normal, dtype=float).reshape(3)
    return n if abs(n @ n - 1.0) <= 1e-15 else unit_normal(normal)


def frame(normal):
    """An orthonormal basis (u, v, n) with n = normal, as the rows of a 3x3 array."""
    n = unit_normal(normal)
    helper = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u)
    return np.array([u, np.cross(n, u), n])


def parallel_gap(origin, normal, origin2, normal2, tol=1e-9):
    """Distance from plane 1 to plane 2 along normal 1; they must be parallel and in order."""
    n1, n2 = unit_normal(normal), unit_normal(normal2, "Plane2")
    if np.linalg.norm(np.cross(n1, n2)) > tol:
        angle = np.degrees(np.arccos(np.clip(abs(n1 @ n2), 0.0, 1.0)))
        raise DeformError(f"Plane2 is not parallel to Plane (they meet at {angle:.3g} degrees): "
                          f"the region between them is bounded by parallel planes, so turn "
                          f"Plane2 to match Plane.", "Plane2")
    gap = float((np.asarray(origin2, float) - np.asarray(origin, float)) @ n1)
    if gap <= tol:
        raise DeformError("Plane2 must lie beyond Plane along its normal (on the moving side); "
                          "move Plane2.", "Plane2")
    return gap
