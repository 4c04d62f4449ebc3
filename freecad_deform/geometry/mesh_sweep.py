"""Bend, twist and general rigid motions on closed triangle meshes (Wu & Ilies 2011).

Case 1 (`sweep_mesh`, one plane): the mesh is cut at the plane (mesh_stretch.cut), the far
part moved by M(1) and the gap filled with the section ring swept through `samples` + 1
configurations M(i/samples). Case 2 (`map_between`, two parallel planes): the region between
the planes is cut into `samples` slabs and each vertex mapped by the motion at its fraction of
the gap, the part beyond Plane2 moved rigidly. Meshes are vertices (N, 3) float and triangles
(M, 3) int, counter-clockwise seen from outside; s is the signed distance to Plane.
"""
import numpy as np

from .errors import DeformError
from .mesh_stretch import _arrays, _check_crossing, _cut, _seam
from .motion import apply, apply_each, fraction_matrices, rotation, translation
from .planes import unit_normal


def _check_samples(samples):
    if isinstance(samples, bool) or not float(samples).is_integer() or samples < 1:
        raise DeformError(f"Samples must be a whole number of at least 1 (it is {samples}); "
                          f"raise Samples.", "Samples")
    return int(samples)


def sweep_mesh(vertices, triangles, origin, normal, motion, samples=16, eps=1e-9):
    """Case 1 with a rigid motion (e.g. a ScrewMotion for a bend); returns (vertices, triangles).

    The mesh is cut at the plane; triangles with every vertex at s <= 0 (after snapping
    |s| <= eps onto the plane) stay bit-identical; the others are moved by motion.matrix(1),
    on-plane vertices they share with the near part duplicated first. The gap between the
    section ring and its moved copy is filled by the rings M(i/samples) (section ring),
    i = 0..samples, consecutive rings joined by two triangles per seam edge as in the
    stretch band (which this is for a translation and samples = 1). Closed 2-manifold in,
    closed 2-manifold out (self-intersection is not checked beyond the test below).

    The motion must carry every section vertex toward the moving side at t = 0
    (velocity . normal > 0), else the band would fold back through the fixed part: a
    DeformError names Axis (the axis crosses the section) or Angle (it all turns backward).
    """
    V, T = _arrays(vertices, triangles)
    o, n = np.asarray(origin, float), unit_normal(normal)
    samples = _check_samples(samples)
    _check_crossing((V - o) @ n, eps, "Plane")
    V, T, s = _cut(V, T, o, n, eps)
    is_far = (s[T] > 0).any(axis=1)
    near, far = T[~is_far], T[is_far]
    near_used = np.zeros(len(V), bool)
    near_used[near] = True
    far_used = np.zeros(len(V), bool)
    far_used[far] = True
    dup = np.flatnonzero(near_used & far_used)
    N = len(V)
    copy = np.arange(N)
    copy[dup] = N + np.arange(len(dup))
    _, a, b = _seam(far, near, s == 0)
    ring = np.unique(np.concatenate([a, b]))
    if len(ring):
        _check_no_fold(motion.velocity(V[ring], 0.0), n)
    # ring level i of seam vertex v: v itself (i = 0), copy[v] (i = samples), else appended
    ts = np.arange(1, samples) / samples
    inner = apply(motion.matrices(ts), V[ring]).reshape(-1, 3) if samples > 1 else np.empty((0, 3))
    base = N + len(dup)

    def level(i, v):
        if i == 0:
            return v
        if i == samples:
            return copy[v]
        return base + (i - 1) * len(ring) + np.searchsorted(ring, v)

    band = []
    for i in range(samples):
        a0, b0, a1, b1 = level(i, a), level(i, b), level(i + 1, a), level(i + 1, b)
        band += [np.stack([a0, b0, b1], 1), np.stack([a0, b1, a1], 1)]
    T = np.concatenate([near, copy[far]] + band)
    V = np.concatenate([V, V[dup], inner])
    move = np.zeros(len(V), bool)
    move[:N] = far_used & ~near_used
    move[N:base] = True
    V[move] = apply(motion.matrix(1.0), V[move])
    return V, T


def _check_no_fold(velocity, n):
    vn = velocity @ n
    tol = 1e-9 * max(float(np.linalg.norm(velocity, axis=1).max()), 1e-300)
    if (vn <= tol).all():
        raise DeformError("The motion carries the section back into the fixed part instead of "
                          "away from it; change the sign of Angle (or turn the Plane normal "
                          "toward the part that moves).", "Angle")
    if (vn <= tol).any():
        raise DeformError("The axis crosses or touches the section at Plane, so the swept "
                          "section would fold through the part; move Axis off the section.",
                          "Axis")


def map_between(vertices, triangles, origin, normal, gap, motion_of_s, samples=16, eps=1e-9):
    """Case 2 (twist; bend with two planes); returns (vertices, triangles).

    Plane2 is parallel to Plane at s = gap. The mesh is cut at s = 0, s = gap and the
    samples - 1 planes between (so no triangle spans two slabs); vertices with s <= 0 stay
    bit-identical (those within eps of a plane are snapped onto it first), those with
    s >= gap are moved by motion_of_s(1.0), those between by motion_of_s(s / gap) (exactly
    i / samples on the i-th plane). motion_of_s: fraction -> 4x4 (see
    motion.fraction_matrices; `twist_motion`, `bend_motion` or a motion object). Only the
    cuts change the topology; closed stays closed. The mesh between the planes follows the
    map only at its vertices: the triangles are flat, so a curved map is sampled `samples`
    times across the gap.
    """
    V, T = _arrays(vertices, triangles)
    o, n = np.asarray(origin, float), unit_normal(normal)
    gap = _check_gap(gap)
    samples = _check_samples(samples)
    if gap / samples <= 2 * eps:
        raise DeformError(f"{samples} Samples put the cutting planes closer than the tolerance "
                          f"in a gap of {gap:g}; lower Samples.", "Samples")
    s = (V - o) @ n
    _check_crossing(s, eps, "Plane")
    _check_crossing(s - gap, eps, "Plane2")
    plane_of = np.empty(0, np.int64)
    for j in [0, samples, *range(1, samples)]:
        V, T, sj = _cut(V, T, o + (gap * j / samples) * n, n, eps)
        plane_of = np.concatenate([plane_of, np.full(len(V) - len(plane_of), -1)])
        plane_of[sj == 0] = j
    f = np.clip(((V - o) @ n) / gap, 0.0, 1.0)
    on = plane_of >= 0
    f[on] = plane_of[on] / samples
    move = f > 0
    V[move] = apply_each(fraction_matrices(motion_of_s, f[move]), V[move])
    return V, T


def _check_gap(gap):
    gap = float(gap)
    if not np.isfinite(gap) or gap <= 0:
        raise DeformError("Plane2 must lie beyond Plane along its normal (on the moving side); "
                          "move Plane2.", "Plane2")
    return gap


def _vectorized(fn):
    fn.vectorized = True
    return fn


def twist_motion(origin, normal, gap, angle, axis_point=None, axis_direction=None):
    """f(frac) -> 4x4 taking the section at s = frac*gap to its twisted place: a rotation by
    frac*angle (radians) about the axis (default: the Plane normal through `origin`). No
    translation, so the length along the axis is kept. f also takes an array of fractions
    (K,) and then returns (K, 4, 4)."""
    n = unit_normal(normal)
    _check_gap(gap)
    point = np.asarray(origin if axis_point is None else axis_point, float)
    direction = n if axis_direction is None else axis_direction
    rotation(point, direction, 0.0)                       # checks the direction now
    angle = float(angle)

    @_vectorized
    def motion_of_s(frac):
        return rotation(point, direction, np.asarray(frac, float) * angle)

    return motion_of_s


def bend_motion(axis_point, axis_direction, angle, origin, normal, gap):
    """f(frac) -> 4x4 for a bend between two planes: the section at s = frac*gap goes to the
    place of the section at s = 0 turned by frac*angle about the axis (which should lie in
    Plane, outside the section): rotation(frac*angle) @ translation(-frac*gap*normal).
    The slab becomes the section at Plane revolved by `angle`; the part beyond Plane2 is moved
    by f(1). Vectorized like twist_motion."""
    n = unit_normal(normal)
    gap = _check_gap(gap)
    point = np.asarray(axis_point, float)
    rotation(point, axis_direction, 0.0)
    angle = float(angle)

    @_vectorized
    def motion_of_s(frac):
        f = np.asarray(frac, float)
        return rotation(point, axis_direction, f * angle) @ translation(
            -(f * gap)[..., None] * n)

    return motion_of_s
