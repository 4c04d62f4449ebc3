"""Bend (Wu & Ilies): the part beyond Plane turns by `angle` (radians) about an axis (point,
direction); the gap is the section revolved. Between two planes (`gap` beyond the first)
the region bends progressively by `profile` and the part beyond turns rigidly.

solid(shape, ...), mesh(mesh, ...) and points(cloud, ...) give (result, outputs);
bend_shape is the B-rep pipeline alone.
"""
import numpy as np

from ..geometry.mesh import sweep as mesh_sweep
from ..geometry.points import sweep as points_sweep
from ..geometry.sweep import motion as mo
from ..geometry.sweep import space_map
from ..geometry.sweep.bend import bend_tangents, check_bend
from ..shapes import brep, mapped
from ..shapes.convert import mesh_arrays, mesh_eps, points_from_array
from . import planes as pp
from .twist import profile_bounds


def solid(shape, origin, normal, angle, axis, gap=None, samples=16, profile="Linear",
          tolerance=1e-3):
    """(shape, {VolumeChange, MaxDeviation, Continuity, SplitFaces}) of a bent B-rep."""
    axis_point, axis_direction = axis
    report = {"MaxDeviation": 0.0}
    result = bend_shape(shape, origin, normal, angle, axis_point, axis_direction, gap,
                        samples, profile, tolerance, report)
    if gap is not None:
        smap = space_map.bend_map(origin, normal, gap, angle, axis_point, axis_direction,
                                  profile)
        return result, {**pp.volume_change(result, shape), **report,
                        **mapped.continuity_report(shape, smap)}
    joints = [(origin, normal, bend_tangents(axis_point, axis_direction))]
    return result, {**pp.volume_change(result, shape), **report,
                    **pp.joint_report(shape, joints)}


def _motion(origin, normal, angle, axis, gap, profile="Linear", points=None):
    """The screw motion of one plane, or the motion of the fraction s / gap of two (at
    profile(s)). A profile other than Linear is first checked not to fold the region
    (the check the solids' space map makes): the section slides back by gap x t(s) while
    it turns by angle x t(s), and where t' > 1 a part near the axis (distance r with
    r |angle| / gap < 1 - 1 / t') slides back faster than it turns."""
    if gap is None:
        return mo.ScrewMotion(mo.rotation(*axis, angle))
    of_s = mesh_sweep.bend_motion(*axis, angle, origin, normal, gap)
    if profile != "Linear" and points is not None and len(points):
        smap = space_map.bend_map(origin, normal, gap, angle, *axis, profile)
        smap.check_fold(fold_samples(points, origin, normal, gap, axis), "Profile")
    return pp.profiled(of_s, profile)


FOLD_LEVELS = 32     # sections of the region the fold check samples
FOLD_POINTS = 512    # points of each (the nearest to and farthest from the axis among them)


def fold_samples(points, origin, normal, gap, axis):
    """Points of the part's outline moved along the normal to FOLD_LEVELS levels inside the
    region: the fold depends on the distance to the axis, not on s, so a mesh whose
    triangles span the region (vertices only at its ends) is sampled too."""
    P = np.asarray(points, float).reshape(-1, 3)
    n = np.asarray(normal, float)
    flat = P - np.outer((P - origin) @ n, n)
    c, k = np.asarray(axis[0], float), np.asarray(axis[1], float) / np.linalg.norm(axis[1])
    d = flat - c
    r = np.linalg.norm(d - np.outer(d @ k, k), axis=1)
    pick = np.unique(np.r_[np.argmin(r), np.argmax(r), np.random.default_rng(0).choice(
        len(flat), min(len(flat), FOLD_POINTS), replace=False)])
    levels = (np.arange(FOLD_LEVELS) + 0.5) / FOLD_LEVELS * gap
    return (flat[pick][None] + levels[:, None, None] * n).reshape(-1, 3)


def mesh(base, origin, normal, angle, axis, gap=None, samples=16, profile="Linear"):
    """(Mesh, {VolumeChange}): the section ring swept through samples + 1 turns (one
    plane), or the region cut into `samples` slabs and mapped at profile(s) (two
    planes)."""
    v, t = mesh_arrays(base)
    motion = _motion(origin, normal, angle, axis, gap, profile, v)
    if gap is not None:               # (one plane: sweep_mesh checks its section itself)
        section = section_points(v, t, origin, normal)
        if len(section):
            check_bend(section, normal, *axis, angle)
    return pp.mesh_result((v, t), *(
        mesh_sweep.sweep_mesh(v, t, origin, normal, motion, samples, mesh_eps(v))
        if gap is None else
        mesh_sweep.map_following(v, t, origin, normal, gap, motion, samples, mesh_eps(v),
                                 angle, *axis, *profile_bounds(profile), bend=True,
                                 what="Bend")))


def section_points(v, t, origin, normal):
    """The points where the mesh's edges cross Plane (and its vertices on it): where a
    two-plane Bend's swept section starts. A bend that turns them back into the near part
    sweeps the region through it (its facets cross the near part's), one whose axis
    crosses them folds the region; check_bend refuses both, as the solids' and the
    one-plane mesh Bend's checks do."""
    s = (np.asarray(v, float) - origin) @ normal
    a, b = t.reshape(-1), np.roll(t, -1, axis=1).reshape(-1)
    sa, sb = s.take(a), s.take(b)
    cross = np.flatnonzero(((sa < 0) & (sb > 0)) | ((sa > 0) & (sb < 0)))
    f = (sa.take(cross) / (sa.take(cross) - sb.take(cross)))[:, None]
    va = v.take(a.take(cross), axis=0)
    return np.concatenate([va + f * (v.take(b.take(cross), axis=0) - va), v[s == 0]])


def points(base, origin, normal, angle, axis, gap=None, profile="Linear"):
    """(Points, {IgnoredPoints}): far points turned, the gap filled (one plane), or each
    point of the region mapped by profile(its fraction of the gap) (two planes)."""
    pts, ignored = pp.cloud(base)
    motion = _motion(origin, normal, angle, axis, gap, profile, pts)
    out = (points_sweep.sweep_points(pts, origin, normal, motion) if gap is None else
           points_sweep.map_points_between(pts, origin, normal, gap, motion))
    return points_from_array(out), ignored


def bend_shape(shape, origin, normal, angle, axis_point, axis_direction, gap=None, samples=16,
               profile="Linear", tolerance=1e-3, report=None):
    """The bent shape: the far part turned by `angle` (radians) about the axis. With two
    planes, a region of one outline is its section revolved (exact, whatever the profile:
    it only spaces the sections differently); any other region goes through the bend map
    (shapes.mapped), report["MaxDeviation"] the largest deviation of a fit."""
    bb = shape.BoundBox
    reach = bb.DiagonalLength + np.linalg.norm(np.array(tuple(bb.Center)) - axis_point)
    if abs(angle) * reach <= brep.TOL:  # no point moves more than the modelling tolerance
        return pp.deform_shape(shape, origin, normal, gap, lambda solid: solid,
                               lambda parts: [p.copy() for p in parts])  # solids oriented
    turn = mo.rotation(axis_point, axis_direction, angle)
    far_motion = turn if gap is None else turn @ mo.translation(-gap * normal)
    far_joint = (mo.apply(turn, origin[None])[0], turn[:3, :3] @ normal)

    def solid_fn(solid):
        offsets = [0.0] if gap is None else [0.0, gap]
        zones = brep.split_zones(solid, origin, normal, offsets)
        near, far = zones[0], zones[-1]
        cut = brep.section_faces(zones[1], origin, normal)
        between = gap is not None and zones[1]
        if not cut and not between:
            return None if not near and not far else brep.join(
                near + brep.transformed(far, far_motion), [(origin, normal), far_joint])
        if cut:
            check_bend(np.vstack([brep.sample_points(f) for f in cut]), normal, axis_point,
                       axis_direction, angle)
        if between and not (cut and brep.is_prismatic(zones[1], origin, normal, gap)):
            # (a solid that starts between the planes, with no section at Plane, too)
            smap = space_map.bend_map(origin, normal, gap, angle, axis_point, axis_direction,
                                      profile)
            result, deviation = mapped.map_solid(solid, smap, tolerance, "Tolerance", zones)
            if report is not None:
                report["MaxDeviation"] = max(report.get("MaxDeviation", 0.0), deviation)
            return result
        middle = brep.revolved(cut, axis_point, axis_direction, angle)
        moved = brep.transformed(far, far_motion)
        brep.check_apart(near, moved, "Angle", (origin, normal))
        return brep.join(near + middle + moved, [(origin, normal), far_joint])

    def loose_fn(parts):
        if gap is not None:
            near, _, far = brep.split_loose(parts, origin, normal, [0.0, gap])
        else:
            near, far = brep.split_loose(parts, origin, normal, [0.0])
        _, cut, wires = brep.split_sheet(near, origin, normal)
        fill = [brep.arc(p, axis_point, axis_direction, angle)
                for p in brep.points_on_plane(wires, origin, normal)]
        if gap is None:
            fill += brep.revolved(cut, axis_point, axis_direction, angle)
        return brep.sheets(near + fill + brep.transformed(far, far_motion))

    return pp.deform_shape(shape, origin, normal, gap, solid_fn, loose_fn)
