"""Bend, twist and general rigid motions on point clouds (Wu & Ilies 2011, section 3).

The rigid parts are moved exactly; in Case 1 the gap is filled with the section points moved
by sampled configurations of the motion, as in the paper's point-cloud examples.
"""
import numpy as np

from ..errors import DeformError
from ..mesh.sweep import move_by_fraction
from ..sweep.motion import apply
from ..sweep.planes import TOUCH, check_crossing, signed_distance, unit_normal
from .stretch import EVERY_POINT, MAX_FILL, section_band, spacing

_PATH_SAMPLES = 2049   # samples of the centroid's trajectory to measure its length


def sweep_points(points, origin, normal, motion, step=None, prop="Angle"):
    """Case 1 on a cloud: returns the moved points (input order) followed by the fill.

    Points with s <= 0 are returned bit-identical, points with s > 0 moved by
    motion.matrix(1). The section (points with |s| <= step/2, or the nearest layer, see
    points_stretch.section_band, projected onto the plane) is
    copied by motion.matrix(t_k), the t_k in (0, 1) spaced so that consecutive copies of the
    section's centroid are `step` apart along its trajectory (measured on 2049 samples);
    step defaults to the cloud's spacing (points_stretch.spacing). For a translation along
    the normal this is stretch_points' fill. A motion that leaves the centroid in place
    (a turn about an axis through it) adds no fill. A fill beyond MAX_FILL points is
    refused naming `prop`, the property that sets the motion.
    """
    pts = np.asarray(points, float).reshape(-1, 3)
    n = unit_normal(normal)
    s = signed_distance(pts, origin, n)
    check_crossing(s, "Plane", touching=True, where=EVERY_POINT)
    step = spacing(pts) if step is None else float(step)
    if not np.isfinite(step) or step <= 0:
        raise DeformError(f"The fill step must be a positive length (it is {step:g}); "
                          f"give a positive Step.", "Step")
    far = s > TOUCH
    near = section_band(s, step)
    section = pts[near] - s[near, None] * n
    if len(section) == 0:
        return _moved(pts, far, motion.matrix(1.0), 0)
    _check_leaves(motion.velocity(section, 0.0) @ n, prop)
    dense = np.linspace(0.0, 1.0, _PATH_SAMPLES)
    path = apply(np.asarray(motion.matrices(dense)), section.mean(axis=0)[None])[:, 0]
    length = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    layers = max(int(np.ceil(length[-1] / step - 1e-9)), 1)
    if layers == 1:
        return _moved(pts, far, motion.matrix(1.0), 0)
    if (layers - 1) * len(section) > MAX_FILL:
        raise DeformError(f"The gap's fill would add {(layers - 1) * len(section):.3g} points "
                          f"at the cloud's spacing {step:.3g} along a {length[-1]:.6g} mm path "
                          f"(at most {MAX_FILL:.3g}); shorten the motion ({prop}).", prop)
    ts = np.interp(np.arange(1, layers) * (length[-1] / layers), length, dense)
    out = _moved(pts, far, motion.matrix(1.0), (layers - 1) * len(section))
    fill = out[len(pts):].reshape(len(ts), len(section), 3)
    for matrix, layer in zip(np.asarray(motion.matrices(ts)), fill):   # written in place
        np.matmul(section, matrix[:3, :3].T, out=layer)
        layer += matrix[:3, 3]
    return out


def _check_leaves(vn, prop):
    """The section must leave Plane toward the moving side (the mesh sweep's rule): a
    motion that carries section points back into the fixed part fills the gap inside it
    (a Bend of -30 deg about an axis beside the part was accepted for a cloud and refused
    for its mesh). `vn`: the section points' velocities along the normal at t = 0; a turn
    in the plane (all zero) adds no fill and passes."""
    tol = 1e-9 * max(float(np.abs(vn).max()), 1e-300)
    if not (vn < -tol).any():
        return
    if (vn <= tol).all():
        raise DeformError("The motion carries the section back into the fixed part instead of "
                          "away from it; change the sign of Angle (or turn the Plane normal "
                          "toward the part that moves)." if prop == "Angle" else
                          f"The motion carries the section back into the fixed part instead "
                          f"of away from it; change {prop}.", prop)
    raise DeformError("The axis crosses the section at Plane, so the swept section would "
                      "fold through the part; move Axis off the section." if prop == "Angle"
                      else f"The motion turns part of the section back into the fixed part; "
                      f"change {prop}.", "Axis" if prop == "Angle" else prop)


def _moved(pts, far, matrix, extra):
    """(N + extra, 3): the points, those in `far` moved by `matrix`, the rest bit-identical,
    then `extra` rows left for the fill."""
    out = np.empty((len(pts) + extra, 3))
    apply(matrix, pts, out=out[:len(pts)], where=far)
    return out


def map_points_between(points, origin, normal, gap, motion_of_s):
    """Case 2 on a cloud: point by point, s <= 0 bit-identical, s >= gap moved by
    motion_of_s(1.0), between by motion_of_s(s / gap) (a fraction -> 4x4, see
    motion.fraction_matrices). Same order and count as the input."""
    pts = np.asarray(points, float).reshape(-1, 3)
    n = unit_normal(normal)
    gap = float(gap)
    if not np.isfinite(gap) or gap <= 0:
        raise DeformError("Plane2 must lie beyond Plane along its normal (on the moving side); "
                          "move Plane2.", "Plane2")
    s = signed_distance(pts, origin, n)
    ends = np.array([s.min(), s.max()])       # all the plane tests need, without a copy of s
    check_crossing(ends, "Plane", touching=True, where=EVERY_POINT)
    check_crossing(ends - gap, "Plane2", touching=True, where=EVERY_POINT)
    s /= gap
    return move_by_fraction(pts, np.clip(s, 0.0, 1.0, out=s), motion_of_s)
