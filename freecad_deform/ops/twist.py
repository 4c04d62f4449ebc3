"""Twist (Wu & Ilies, Case 2): the region between Plane and the plane `gap` beyond it turns
progressively by `angle` (radians) x profile(s / gap) about an axis (point, direction)
parallel to the normal; the part beyond turns rigidly; length and cross-sections are kept.
Without an axis, the twist turns about the normal through the centroid of the section at
Plane.

solid(shape, ...), mesh(mesh, ...) and points(cloud, ...) give (result, outputs);
twist_shape is the B-rep pipeline alone.
"""
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.mesh import sweep as mesh_sweep
from ..geometry.points import sweep as points_sweep
from ..geometry.sweep import motion as mo
from ..geometry.sweep import space_map
from ..shapes import brep, mapped
from ..shapes.convert import mesh_arrays, mesh_eps, points_from_array
from . import planes as pp

# The most one mesh slab may turn: flat triangles between sections turned further cross
# each other (measured: a thin-walled C section at 60 deg, an L and a holed block at 75;
# a box at 100)
MESH_SLAB_TURN = np.pi / 4


def solid(shape, origin, normal, gap, angle, axis=None, samples=16, profile="Linear",
          tolerance=1e-3):
    """(shape, {VolumeChange, MaxDeviation, Continuity, SplitFaces}) of a twisted B-rep."""
    axis = axis or (pp.section_centroid(brep.solids_of(shape), origin, normal), normal)
    report = {"MaxDeviation": 0.0}
    result = twist_shape(shape, origin, normal, gap, angle, *axis, samples, profile,
                         tolerance, report)
    smap = space_map.twist_map(origin, normal, gap, angle, *axis, profile)
    return result, {**pp.volume_change(result, shape), **report,
                    **mapped.continuity_report(shape, smap)}


def mesh(base, origin, normal, gap, angle, axis=None, samples=16, profile="Linear"):
    """(Mesh, {VolumeChange}): the region cut into `samples` slabs, each vertex turned by
    profile(its fraction of the gap); a slab turned by more than MESH_SLAB_TURN is
    refused (Smooth turns its middle slabs 1.5 times the mean)."""
    steepest = 1.5 if profile == "Smooth" else 1.0    # the profile's largest slope
    if steepest * abs(angle) > samples * MESH_SLAB_TURN:
        raise DeformError(f"Angle turns the steepest of the {samples} Samples slabs by "
                          f"{steepest * np.degrees(abs(angle)) / samples:.4g} deg, more than "
                          f"the 45 deg their flat triangles can follow; raise Samples to at "
                          f"least {int(np.ceil(steepest * abs(angle) / MESH_SLAB_TURN))} or "
                          f"lower Angle.", "Samples")
    v, t = mesh_arrays(base)
    axis = axis or (pp.section_centroid_mesh(base, origin, normal, (v, t)), normal)
    of_s = pp.profiled(mesh_sweep.twist_motion(origin, normal, gap, angle, *axis), profile)
    return pp.mesh_result((v, t), *mesh_sweep.map_following(
        v, t, origin, normal, gap, of_s, samples, mesh_eps(v), angle, *axis,
        *profile_bounds(profile), what="Twist"))


def profile_bounds(profile):
    """(largest |t'|, largest |t''|) of a profile t on [0, 1] (Smooth: 3f^2 - 2f^3)."""
    return (1.0, 0.0) if profile == "Linear" else (1.5, 6.0)


def points(base, origin, normal, gap, angle, axis=None, profile="Linear"):
    """(Points, {IgnoredPoints}): each point of the region turned by profile(its fraction
    of the gap)."""
    pts, ignored = pp.cloud(base)
    axis = axis or (pp.section_centroid_cloud(pts, origin, normal), normal)
    of_s = pp.profiled(mesh_sweep.twist_motion(origin, normal, gap, angle, *axis), profile)
    out = points_sweep.map_points_between(pts, origin, normal, gap, of_s)
    return points_from_array(out), ignored


def twist_shape(shape, origin, normal, gap, angle, axis_point, axis_direction, samples=16,
                profile="Linear", tolerance=1e-3, report=None):
    """The twisted shape: sections at s turned by angle * profile(s / gap) about the axis,
    lofted where the region has one outline; elsewhere the region's faces go through the
    twist map (shapes.mapped), report["MaxDeviation"] the largest deviation of a fit."""
    smap = space_map.twist_map(origin, normal, gap, angle, axis_point, axis_direction, profile)
    turn = mo.rotation(axis_point, axis_direction, angle)
    far_joint = (mo.apply(turn, (origin + gap * normal)[None])[0], turn[:3, :3] @ normal)
    fracs = np.linspace(0.0, 1.0, samples + 1)

    def turn_to(frac):
        return mo.rotation(axis_point, axis_direction,
                           space_map.profile_value(profile, frac) * angle)

    def through_map(solid, zones):
        result, deviation = mapped.map_solid(solid, smap, tolerance, "Tolerance", zones)
        if report is not None:
            report["MaxDeviation"] = max(report.get("MaxDeviation", 0.0), deviation)
        return result

    def solid_fn(solid):
        zones = near, between, far = brep.split_zones(solid, origin, normal, [0.0, gap])
        cut = brep.section_faces(between, origin, normal)
        if not between:  # this solid lies before Plane or beyond Plane2: one piece
            if len(near) + len(far) != 1:
                raise DeformError("The split at Plane and Plane2 lost the region between "
                                  "them; move Plane2 a little.", "Plane2")
            return (near + brep.transformed(far, turn))[0]
        top = [brep.faces_on_plane(z, origin + gap * normal, normal) for z in (between, far)]
        if not (cut and brep.is_prismatic(between, origin, normal, gap)) or not (
                brep.all_shared(cut, near) and brep.all_shared(top[0], far)
                and brep.all_shared(top[1], between)):
            return through_map(solid, zones)  # the loft joins only sections both sides share
        profiles = [brep.transformed(brep.translated(cut, f * gap * normal), turn_to(f))
                    for f in fracs]
        result = pp.lofted_join(near, cut, profiles, far, (origin + gap * normal, normal), turn,
                                [(origin, normal), far_joint], "Angle")
        # a twist keeps the volume: a loft too coarse for a steep twist cuts inside its path,
        # and OCCT's loft can fail outright (a long plate of as1_pe_203 under a Smooth
        # twist lost 4 times its region): then the twist map, exact to Tolerance
        # the loft also strays from the exact helicoids between its profiles (0.01 mm on
        # as1_pe_203's 5 m block): beyond Tolerance, the map takes the region too
        lost = abs(brep.solids_volume(result, remember=True)  # VolumeChange reads it back
                   - brep.solids_volume(solid))
        if lost > 1e-3 * sum(s.Volume for s in between):
            try:
                return through_map(solid, zones)
            except DeformError:
                raise DeformError(f"The twist is too steep for {samples} Samples (the loft "
                                  f"loses {lost:.4g} mm^3); raise Samples or move Plane2 "
                                  f"farther.", "Samples") from None
        deviation = loft_deviation(result, cut, origin, normal, gap, space_map.twist_map(
            origin, normal, gap, -angle, axis_point, axis_direction, profile))
        if deviation > tolerance:
            return through_map(solid, zones)
        if report is not None:
            report["MaxDeviation"] = max(report.get("MaxDeviation", 0.0), deviation)
        return result

    def loose_fn(parts):
        near, between, far = brep.split_loose(parts, origin, normal, [0.0, gap])
        return near + brep.transformed(far, turn)

    return pp.deform_shape(shape, origin, normal, gap, solid_fn, loose_fn)


def loft_deviation(result, cut, origin, normal, gap, turn_back, per_face=6, most=400):
    """The largest distance between the lofted faces of `result` (its B-spline faces that
    span the region) and the exact twist, at points between the profiles: turned back by
    the angle at their s (`turn_back`: the inverse twist map, points (N, 3) at once) and
    moved back to Plane, each must lie on the outline of the `cut` faces (measured with
    OCCT's distToShape)."""
    import Part
    from ..shapes.convert import vector
    outline = Part.makeCompound([e for f in cut for e in f.Edges])
    pts = []
    for face in result.Faces:
        if type(face.Surface).__name__ != "BSplineSurface":
            continue
        s = [(np.array(tuple(v.Point)) - origin) @ normal for v in face.Vertexes]
        if min(s) > brep.TOL or max(s) < gap - brep.TOL:
            continue  # not a side of the loft
        u0, u1, v0, v1 = face.ParameterRange
        for u in np.linspace(u0, u1, per_face + 2)[1:-1]:
            for v in np.linspace(v0, v1, 4 * per_face + 2)[1:-1]:
                pts.append(tuple(face.valueAt(u, v)))
    if not pts:
        return 0.0
    pts = np.array(pts)
    if len(pts) > most:
        pts = pts[np.random.default_rng(0).choice(len(pts), most, replace=False)]
    back = turn_back(pts) - np.outer((pts - origin) @ normal, normal)
    return max(outline.distToShape(Part.Vertex(vector(q)))[0] for q in back)
