"""What Stretch, Bend, Twist and Taper share (Wu & Ilies): planes, the per-solid split-sweep-join
driver, wireframes that follow, and the continuity report of Lemma 1."""
import numpy as np

from ..geometry.sweep import continuity
from ..geometry.sweep import motion as mo
from ..geometry.errors import DeformError
from ..geometry.sweep.planes import parallel_gap
from ..shapes import brep
from ..shapes.convert import matrix_array, plane_arrays
from .base import Prop

BASE = Prop("App::PropertyLink", "Base", "Base",
            "The solid, mesh or point cloud to deform; it is never modified.")
PLANE = Prop("App::PropertyPlacement", "Plane", "Planes",
             "Separating plane: its local XY plane splits the part, its local Z (the normal) "
             "points toward the part that moves.")
USE_PLANE2 = Prop("App::PropertyBool", "UsePlane2", "Planes",
                  "Deform only the region between Plane and Plane2, keeping its cross-sections "
                  "(Case 2); the part beyond Plane2 moves rigidly.", False)
PLANE2 = Prop("App::PropertyPlacement", "Plane2", "Planes",
              "Second separating plane, parallel to Plane and beyond it along the normal; used "
              "when UsePlane2 is true.")
AXIS = Prop("App::PropertyPlacement", "Axis", "Motion",
            "Axis of rotation: its position is a point on the axis, its local Z the direction "
            "(right-hand rule for Angle).")
ANGLE = Prop("App::PropertyAngle", "Angle", "Motion", "How far the far part turns about Axis.")
SAMPLES = Prop("App::PropertyInteger", "Samples", "Sweep",
               "Number of intermediate profiles where the sweep is not exact (lofts, meshes).",
               16)
KEYS = Prop("App::PropertyPlacementList", "KeyPlacements", "Motion",
            "Key placements of the far part (the paper's key frames), passed in order before "
            "its final place; the gap is then a loft through Samples profiles normal to the "
            "path. Empty: the exact sweep (extrusion or revolve).")
INTERPOLATION = Prop("App::PropertyEnumeration", "Interpolation", "Motion",
                     "How the motion passes through KeyPlacements: Rational, a C2 dual-quaternion "
                     "spline whose point paths are NURBS; Screw, a screw motion from key to key.",
                     list(mo.INTERPOLATIONS))
USE_END = Prop("App::PropertyBool", "UseEndPlacement", "Motion",
               "Move the far part to EndPlacement (any rigid motion: a screw, a slide across "
               "the normal) instead of by the feature's own motion; the gap is lofted along the "
               "key-frame motion through KeyPlacements to it.", False)
END = Prop("App::PropertyPlacement", "EndPlacement", "Motion",
           "Final placement of the far part (the paper's last key frame), used when "
           "UseEndPlacement is true.")
RESULTS = (
    Prop("App::PropertyFloat", "VolumeChange", "Result",
         "Volume of the result minus the volume of the Base, in mm^3 (negative when it "
         "shrinks).", output=True),
    Prop("App::PropertyString", "Continuity", "Result",
         "Continuity at each joint (Lemma 1): G1 where a split face's normal is "
         "perpendicular to the trajectory, else C0.", output=True),
    Prop("App::PropertyStringList", "SplitFaces", "Result",
         "Faces of the Base that a separating plane cut.", output=True),
    Prop("App::PropertyInteger", "IgnoredPoints", "Result",
         "Points of a point-cloud Base left out because a coordinate is NaN or infinite "
         "(a scanner's missing returns); they are not in the result.", output=True),
)


def planes(obj, require_plane2=False):
    """(origin, normal, gap) from the Plane properties; gap is None for one plane."""
    origin, normal = plane_arrays(obj.Plane)
    if not (require_plane2 or obj.UsePlane2):
        return origin, normal, None
    origin2, normal2 = plane_arrays(obj.Plane2)
    gap = parallel_gap(origin, normal, origin2, normal2)
    if gap <= 10 * brep.TOL:
        raise DeformError(f"Plane2 is only {gap:.3g} beyond Plane, within ten times the "
                          f"modelling tolerance: no region lies between them; move Plane2.",
                          "Plane2")
    return origin, normal, gap


MAX_SAMPLES = 4096  # profiles of a sweep; a mesh band's size and time grow linearly with it


def check_samples(obj, least):
    """Samples within [least, MAX_SAMPLES]: fewer cannot sweep, more would never finish."""
    if not least <= obj.Samples <= MAX_SAMPLES:
        raise DeformError(f"Samples {obj.Samples} is outside {least} to {MAX_SAMPLES}; set "
                          f"Samples within that range.", "Samples")


def check_crossing(parts, origin, normal, gap=None):
    """The planes must cut the part (by more than the modelling tolerance): one that misses
    or only touches it is bad input for Plane or Plane2."""
    lo = min(brep.extent(s, origin, normal)[0] for s in parts)
    hi = max(brep.extent(s, origin, normal)[1] for s in parts)
    if not (lo < -brep.TOL and hi > brep.TOL):
        raise DeformError("Plane misses the part: the whole part lies on one side of it; "
                          "move Plane so it crosses the part.", "Plane")
    if gap is not None and not lo < gap < hi:
        raise DeformError("Plane2 misses the part; move Plane2 so it crosses the part.", "Plane2")


def deform_shape(shape, origin, normal, gap, solid_fn, loose_fn):
    """Each solid through `solid_fn(solid)`, wireframes through `loose_fn(parts)`.

    solid_fn returns one solid or None; the result is one solid or a compound.
    """
    import Part
    solids = brep.solids_of(shape, loose_allowed=True)
    loose = brep.loose_parts(shape)
    check_crossing(solids + loose, origin, normal, gap)
    out = [r for r in (solid_fn(s) for s in solids) if r is not None]
    out += loose_fn(loose)
    return out[0] if len(out) == 1 else Part.makeCompound(out)


def joint_report(shape, joints):
    """Output values for the faces that the planes cut.

    `joints` are (origin, normal, tangents[, keep]) with tangents(points) the trajectory
    tangents of the joint points and keep(points) an optional mask of the points that lie
    on the joint (a segment of a folded surface); a face is G1 only if it is G1 at every
    joint it crosses.
    """
    worst = {}
    for origin, normal, tangents, *keep in joints:
        for name, face, edges in brep.crossing_faces(shape, origin, normal):
            points, normals = brep.joint_normals(face, edges)
            if keep:
                mask = keep[0](points)
                points, normals = points[mask], normals[mask]
            if not len(points):
                continue
            kind = continuity.joint_continuity(normals, tangents(points))
            worst[name] = "C0" if "C0" in (kind, worst.get(name)) else kind
    entries = sorted(worst.items(), key=lambda item: int(item[0][4:]))
    return {"Continuity": continuity.report(entries), "SplitFaces": [n for n, _ in entries]}


def key_motion(obj, final):
    """The motion through the object's KeyPlacements ending at `final` (at EndPlacement
    with UseEndPlacement), or None."""
    free_end = getattr(obj, "UseEndPlacement", False)
    if free_end:
        final = matrix_array(obj.EndPlacement)
    if not (len(obj.KeyPlacements) or free_end):
        return None
    keys = [np.eye(4)] + [matrix_array(p) for p in obj.KeyPlacements] + [final]
    return mo.key_motion(keys, obj.Interpolation)


def motion_joints(origin, normal, motion):
    """Joint planes and Lemma 1 tangents of a Case 1 sweep by `motion`: at the Plane, and
    at the far part's face (tangents at t = 1 turned back to the original frame)."""
    end = motion.matrix(1.0)
    return [(origin, normal, lambda p: motion.velocity(p, 0.0)),
            (mo.apply(end, origin[None])[0], end[:3, :3] @ normal,
             lambda p: motion.velocity(mo.apply(np.linalg.inv(end), p), 1.0) @ end[:3, :3])]


def sweep_solid(solid, origin, normal, motion, samples, prop="KeyPlacements"):
    """Case 1 with a general motion (Steps 4-7): the section swept through profiles normal
    to the path of its centroid, placed and turned by the motion, and lofted."""
    near, far = brep.split_zones(solid, origin, normal, [0.0])
    cut = brep.faces_on_plane(near, origin, normal)
    end = motion.matrix(1.0)
    if not cut:  # this solid lies on one side: kept or moved whole
        return (near + brep.transformed(far, end))[0]
    centroid = sum(np.array(tuple(f.CenterOfMass)) * f.Area for f in cut) / sum(
        f.Area for f in cut)
    ts = np.linspace(0.0, 1.0, samples + 1)
    frames = mo.profile_frames(motion, centroid, ts)
    across = brep.projected(cut, origin, normal, frames[0])
    profiles = ([cut] + [brep.transformed(across, f @ np.linalg.inv(frames[0]))
                         for f in frames[1:-1]] + [brep.transformed(cut, end)])
    for t, profile in zip(ts[1:], profiles[1:]):  # the sweep must not reach back into the part
        reach = min(float(((brep.sample_points(f) - origin) @ normal).min()) for f in profile)
        if reach < -brep.TOL:
            raise DeformError(f"The path leaves Plane too obliquely: the profile at t = {t:.2g} "
                              f"reaches {-reach:.3g} mm behind Plane; change {prop} or "
                              f"Interpolation.", prop)
    joints = [(origin, normal), (mo.apply(end, origin[None])[0], end[:3, :3] @ normal)]
    return lofted_join(near, cut, profiles, far, (origin, normal), end, joints, prop)


def lofted_join(near, cut, profiles, far, far_plane, end, joints, prop):
    """One solid from the near pieces, the loft through `profiles` (from the near part's
    `cut` faces to the far part's section at `far_plane`, moved by `end`) and the far
    pieces: their faces sewn, the cut faces left out."""
    moved = brep.transformed(far, end)
    brep.check_apart(near, moved, prop)
    far_cut = brep.faces_on_plane(far, *far_plane)
    faces = ([f for s in near for f in s.Faces if not any(f.isSame(c) for c in cut)]
             + brep.loft_sides(profiles, prop)
             + brep.transformed([f for s in far for f in s.Faces
                                 if not any(f.isSame(c) for c in far_cut)], end))
    return brep.join_faces(faces, joints, prop)


def keyed(obj, kind, origin, normal, gap, motion):
    """Result and outputs of a Case 1 deformation by a key motion, for every kind of Base."""
    from ..geometry.mesh import sweep as mesh_sweep
    from ..geometry.points import sweep as points_sweep
    from ..shapes.convert import mesh_arrays, mesh_eps, points_from_array
    if gap is not None:
        raise DeformError("KeyPlacements move the part beyond one Plane; clear KeyPlacements "
                          "or UsePlane2.", "KeyPlacements")
    check_samples(obj, 2)
    if kind == "Points":
        pts, ignored = cloud(obj.Base)
        return points_from_array(points_sweep.sweep_points(pts, origin, normal, motion)), ignored
    if kind == "Mesh":
        v, t = mesh_arrays(obj.Base.Mesh)
        return mesh_result(obj.Base.Mesh, *mesh_sweep.sweep_mesh(
            v, t, origin, normal, motion, obj.Samples, mesh_eps(v)))
    shape, end = obj.Base.Shape, motion.matrix(1.0)

    def loose_fn(parts):
        near, far = brep.split_loose(parts, origin, normal, [0.0])
        return near + brep.transformed(far, end)

    result = deform_shape(shape, origin, normal, None,
                          lambda s: sweep_solid(s, origin, normal, motion, obj.Samples), loose_fn)
    return result, {**volume_change(result, shape),
                    **joint_report(shape, motion_joints(origin, normal, motion))}


def sections(solids, origin, normal, offsets):
    """The cross-section faces of `solids` at each offset along `normal` (one list each),
    solid by solid: the solids of an assembly may overlap, and one face maker over all their
    wires would nest one solid's outline in another's."""
    import Part
    import FreeCAD as App
    n = App.Vector(*normal)
    out = []
    for off in offsets:
        d = float(np.dot(origin + off * normal, normal))
        faces = []
        for solid in solids:
            wires = solid.slice(n, d)
            if wires:
                faces += Part.makeFace(wires, "Part::FaceMakerBullseye").Faces
        out.append(faces)
    return out


def mesh_result(base_mesh, vertices, triangles):
    """The new Mesh and its VolumeChange, measured in float64 on the arrays."""
    from ..geometry.mesh.measure import mesh_volume
    from ..shapes.convert import mesh_arrays, mesh_from_arrays
    change = mesh_volume(vertices, triangles) - mesh_volume(*mesh_arrays(base_mesh))
    return mesh_from_arrays(vertices, triangles), {"VolumeChange": change}


def cloud(base):
    """The finite points of a point-cloud Base and the IgnoredPoints output."""
    from ..shapes.convert import points_array
    pts = points_array(base.Points)
    return pts, {"IgnoredPoints": base.Points.CountPoints - len(pts)}


def volume_change(result, shape):
    """Material gained, from the solids alone (loose faces have no volume; a reversed
    Base solid counts as the material it bounds)."""
    return {"VolumeChange": brep.solids_volume(result) - brep.solids_volume(shape)}


def constant(vector):
    """A tangent field equal to `vector` everywhere (a translation)."""
    return lambda points: np.broadcast_to(vector, np.shape(points))
