"""What Stretch, Bend and Twist share (Wu & Ilies): planes, the per-solid split-sweep-join
driver, wireframes that follow, and the continuity report of Lemma 1."""
import numpy as np

from ..geometry import continuity
from ..geometry.errors import DeformError
from ..geometry.planes import parallel_gap
from ..shapes import brep
from ..shapes.convert import plane_arrays
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
RESULTS = (
    Prop("App::PropertyFloat", "VolumeChange", "Result",
         "Volume of the result minus the volume of the Base, in mm^3 (negative when it "
         "shrinks).", output=True),
    Prop("App::PropertyString", "Continuity", "Result",
         "Continuity at each joint (Lemma 1): G1 where a split face's normal is "
         "perpendicular to the trajectory, else C0.", output=True),
    Prop("App::PropertyStringList", "SplitFaces", "Result",
         "Faces of the Base that a separating plane cut.", output=True),
)


def planes(obj, require_plane2=False):
    """(origin, normal, gap) from the Plane properties; gap is None for one plane."""
    origin, normal = plane_arrays(obj.Plane)
    if not (require_plane2 or obj.UsePlane2):
        return origin, normal, None
    origin2, normal2 = plane_arrays(obj.Plane2)
    return origin, normal, parallel_gap(origin, normal, origin2, normal2)


def check_crossing(solids, origin, normal, gap=None):
    """The planes must cut the part: one that misses is bad input for Plane or Plane2."""
    lo = min(brep.extent(s, origin, normal)[0] for s in solids)
    hi = max(brep.extent(s, origin, normal)[1] for s in solids)
    if not lo < 0 < hi:
        raise DeformError("Plane misses the part: the whole part lies on one side of it; "
                          "move Plane so it crosses the part.", "Plane")
    if gap is not None and not lo < gap < hi:
        raise DeformError("Plane2 misses the part; move Plane2 so it crosses the part.", "Plane2")


def deform_shape(shape, origin, normal, gap, solid_fn, loose_fn):
    """Each solid through `solid_fn(solid)`, wireframes through `loose_fn(parts)`.

    solid_fn returns one solid or None; the result is one solid or a compound.
    """
    import Part
    solids = brep.solids_of(shape)
    check_crossing(solids, origin, normal, gap)
    out = [r for r in (solid_fn(s) for s in solids) if r is not None]
    out += loose_fn(brep.loose_parts(shape))
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
        for name, face in brep.crossing_faces(shape, origin, normal):
            points, normals = brep.joint_normals(face, origin, normal)
            if keep:
                mask = keep[0](points)
                points, normals = points[mask], normals[mask]
            if not len(points):
                continue
            kind = continuity.joint_continuity(normals, tangents(points))
            worst[name] = "C0" if "C0" in (kind, worst.get(name)) else kind
    entries = sorted(worst.items(), key=lambda item: int(item[0][4:]))
    return {"Continuity": continuity.report(entries), "SplitFaces": [n for n, _ in entries]}


def sections(solids, origin, normal, offsets):
    """The cross-section faces of `solids` at each offset along `normal` (one list each)."""
    import Part
    import FreeCAD as App
    n = App.Vector(*normal)
    out = []
    for off in offsets:
        d = float(np.dot(origin + off * normal, normal))
        wires = [w for s in solids for w in s.slice(n, d)]
        out.append(Part.makeFace(wires, "Part::FaceMakerBullseye").Faces if wires else [])
    return out


def mesh_result(base_mesh, vertices, triangles):
    """The new Mesh and its VolumeChange, measured in float64 on the arrays."""
    from ..geometry.mesh_measure import mesh_volume
    from ..shapes.convert import mesh_arrays, mesh_from_arrays
    change = mesh_volume(vertices, triangles) - mesh_volume(*mesh_arrays(base_mesh))
    return mesh_from_arrays(vertices, triangles), {"VolumeChange": change}


def volume_change(result, shape):
    return {"VolumeChange": result.Volume - shape.Volume}


def constant(vector):
    """A tangent field equal to `vector` everywhere (a translation)."""
    return lambda points: np.broadcast_to(vector, np.shape(points))
