"""Twist (Wu & Ilies, Case 2): the region between two planes turns progressively about an
axis; the part beyond Plane2 turns rigidly; length and cross-sections are kept."""
import numpy as np

from ..geometry.sweep import motion as mo
from ..geometry.sweep import space_map
from ..geometry.errors import DeformError
from ..shapes import brep, mapped
from ..shapes.convert import mesh_arrays, mesh_eps, plane_arrays, points_from_array
from . import flex
from . import planes as ss
from .base import DeformFeature, Prop


class Twist(DeformFeature):
    TYPE = "Twist"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        Prop("App::PropertyPlacement", "Plane2", "Planes",
             "Second separating plane, parallel to Plane and beyond it along the normal: the "
             "region between the planes twists."),
        Prop("App::PropertyQuantity", "Angle", "Motion",
             "How far the region twists about Axis (with Turns); any number of turns, where "
             "an angle property would stop at 360 deg.", unit="deg"),
        Prop("App::PropertyInteger", "Turns", "Motion",
             "Whole turns added to Angle: the region twists by Angle + 360 deg x Turns.", 0),
        Prop("App::PropertyBool", "UseAxis", "Motion",
             "Twist about Axis; when false, about the Plane normal through the centroid of the "
             "cross-section at Plane.", False),
        ss.AXIS, ss.SAMPLES) + ss.RESULTS + flex.PROPERTIES + (flex.MAX_DEVIATION,)

    def compute(self, obj, kind):
        origin, normal, gap = ss.planes(obj, require_plane2=True)
        angle = np.radians(obj.Angle.Value + 360.0 * obj.Turns)
        ss.check_samples(obj, 2)
        if kind in ("Mesh", "Points"):
            return self._discrete(obj, kind, origin, normal, gap, angle)
        shape = obj.Base.Shape
        axis = self._axis(obj, shape, origin, normal)
        report = {"MaxDeviation": 0.0}
        result = twist_shape(shape, origin, normal, gap, angle, *axis, obj.Samples,
                             obj.Profile, flex.tolerance(obj), report)
        smap = space_map.twist_map(origin, normal, gap, angle, *axis, obj.Profile)
        return result, {**ss.volume_change(result, shape), **report,
                        **mapped.continuity_report(shape, smap)}

    @staticmethod
    def _axis(obj, shape, origin, normal):
        return given_axis(obj, normal) or (
            section_centroid(brep.solids_of(shape), origin, normal), normal)

    def _discrete(self, obj, kind, origin, normal, gap, angle):
        from ..geometry.mesh import sweep as mesh_sweep
        from ..geometry.points import sweep as points_sweep
        if kind == "Points":
            pts, ignored = ss.cloud(obj.Base)
            axis = given_axis(obj, normal) or (_cloud_centroid(pts, origin, normal), normal)
            of_s = mesh_sweep.twist_motion(origin, normal, gap, angle, *axis)
            out = points_sweep.map_points_between(pts, origin, normal, gap, of_s)
            return points_from_array(out), ignored
        v, t = mesh_arrays(obj.Base.Mesh)
        axis = given_axis(obj, normal) or (
            section_centroid_mesh(obj.Base.Mesh, origin, normal), normal)
        of_s = mesh_sweep.twist_motion(origin, normal, gap, angle, *axis)
        return ss.mesh_result(obj.Base.Mesh, *mesh_sweep.map_between(
            v, t, origin, normal, gap, of_s, obj.Samples, mesh_eps(v)))


def given_axis(obj, normal):
    """(point, direction) of Axis when UseAxis, else None; a twist turns about the normal,
    so an Axis that leaves it would tilt the far part."""
    if not obj.UseAxis:
        return None
    point, direction = plane_arrays(obj.Axis)
    tilt = np.degrees(np.arcsin(min(1.0, np.linalg.norm(np.cross(direction, normal)))))
    if tilt > 1e-7:
        raise DeformError(f"Axis is {tilt:.3g} degrees off the Plane normal; a twist turns "
                          f"about the normal, so align Axis with it (or clear UseAxis).",
                          "Axis")
    return point, direction


def section_centroid(solids, origin, normal):
    """Area centroid of the cross-section at the plane (the default twist axis passes here)."""
    faces = ss.sections(solids, origin, normal, [0.0])[0]
    if not faces:
        raise DeformError("Plane misses the part; move Plane so it crosses the part.", "Plane")
    area = sum(f.Area for f in faces)
    return sum(np.array(tuple(f.CenterOfMass)) * f.Area for f in faces) / area


def section_centroid_mesh(mesh, origin, normal):
    """Centroid of the mesh's cross-section polylines at the plane (their vertex mean)."""
    import FreeCAD as App
    lines = mesh.crossSections([(App.Vector(*origin), App.Vector(*normal))])[0]
    pts = np.array([tuple(p) for line in lines for p in line])
    if len(pts) == 0:
        raise DeformError("Plane misses the part; move Plane so it crosses the part.", "Plane")
    return pts.mean(axis=0)


def _cloud_centroid(points, origin, normal):
    from ..geometry.points.stretch import section_band, spacing
    s = (points - origin) @ normal
    near = points[section_band(s, 2 * spacing(points))]
    if len(near) == 0:
        raise DeformError("Plane misses the part; move Plane so it crosses the part.", "Plane")
    return near.mean(axis=0) - ((near.mean(axis=0) - origin) @ normal) * normal


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

    def solid_fn(solid):
        near, between, far = brep.split_zones(solid, origin, normal, [0.0, gap])
        cut = brep.faces_on_plane(near, origin, normal)
        if not between:  # this solid lies before Plane or beyond Plane2
            return (near + brep.transformed(far, turn))[0]
        if not (cut and brep.is_prismatic(between, origin, normal, gap)):
            result, deviation = mapped.map_solid(solid, smap, tolerance, "Tolerance",
                                                 (near, between, far))
            if report is not None:
                report["MaxDeviation"] = max(report.get("MaxDeviation", 0.0), deviation)
            return result
        profiles = [brep.transformed(brep.translated(cut, f * gap * normal), turn_to(f))
                    for f in fracs]
        result = ss.lofted_join(near, cut, profiles, far, (origin + gap * normal, normal), turn,
                                [(origin, normal), far_joint], "Angle")
        # a twist keeps the volume: a loft too coarse for a steep twist cuts inside its path
        lost = abs(result.Volume - solid.Volume)
        if lost > 1e-3 * sum(s.Volume for s in between):
            raise DeformError(f"The twist is too steep for {samples} Samples (the loft loses "
                              f"{lost:.4g} mm^3); raise Samples or move Plane2 farther.",
                              "Samples")
        return result

    def loose_fn(parts):
        near, between, far = brep.split_loose(parts, origin, normal, [0.0, gap])
        return near + brep.transformed(far, turn)

    return ss.deform_shape(shape, origin, normal, gap, solid_fn, loose_fn)
