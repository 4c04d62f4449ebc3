"""Stretch (Wu & Ilies, Cases 1 and 2): split at a plane, move the far part, fill the gap."""
import numpy as np

from ..geometry import continuity
from ..geometry.errors import DeformError
from ..geometry.planes import parallel_gap
from ..geometry.points_stretch import stretch_points
from ..shapes import brep
from ..shapes.convert import (mesh_arrays, mesh_from_arrays, plane_arrays, points_array,
                              points_from_array)
from .base import DeformFeature, Prop


class Stretch(DeformFeature):
    TYPE = "Stretch"
    PROPERTIES = (
        Prop("App::PropertyLink", "Base", "Base",
             "The solid, mesh or point cloud to stretch; it is never modified."),
        Prop("App::PropertyPlacement", "Plane", "Stretch",
             "Separating plane: its local XY plane splits the part, its local Z (the normal) "
             "points toward the part that moves."),
        Prop("App::PropertyDistance", "Distance", "Stretch",
             "How far the part beyond the plane moves along the normal; negative shrinks."),
        Prop("App::PropertyBool", "UsePlane2", "Stretch",
             "Stretch only the region between Plane and Plane2, keeping its cross-sections "
             "(Case 2); the part beyond Plane2 moves rigidly.", False),
        Prop("App::PropertyPlacement", "Plane2", "Stretch",
             "Second separating plane, parallel to Plane and beyond it along the normal; "
             "used when UsePlane2 is true."),
        Prop("App::PropertyFloat", "VolumeChange", "Result",
             "Volume of the result minus the volume of the Base, in mm^3 (negative when it "
             "shrinks).", output=True),
        Prop("App::PropertyString", "Continuity", "Result",
             "Continuity at each joint (Lemma 1): G1 where a split face's normal is "
             "perpendicular to the motion, else C0.", output=True),
        Prop("App::PropertyStringList", "SplitFaces", "Result",
             "Faces of the Base that a separating plane cut.", output=True),
    )

    def compute(self, obj, kind):
        origin, normal = plane_arrays(obj.Plane)
        distance = obj.Distance.Value
        gap = None
        if obj.UsePlane2:
            origin2, normal2 = plane_arrays(obj.Plane2)
            gap = parallel_gap(origin, normal, origin2, normal2)
        if kind == "Points":
            pts = stretch_points(points_array(obj.Base.Points), origin, normal, distance,
                                 *(() if gap is None else (origin2, normal2)))
            return points_from_array(pts), {}
        if kind == "Mesh":
            from ..geometry.mesh_stretch import stretch_mesh
            base_mesh = obj.Base.Mesh
            v, t = mesh_arrays(base_mesh)
            v, t = stretch_mesh(v, t, origin, normal, distance,
                                *(() if gap is None else (origin2, normal2)))
            mesh = mesh_from_arrays(v, t)
            return mesh, {"VolumeChange": mesh.Volume - base_mesh.Volume}
        shape = obj.Base.Shape
        result = stretch_shape(shape, origin, normal, distance, gap)
        joints = _joints(shape, origin, normal, gap)
        return result, {
            "VolumeChange": result.Volume - shape.Volume,
            "Continuity": continuity.report((name, kind) for name, kind in joints),
            "SplitFaces": [name for name, _ in joints],
        }


def stretch_shape(shape, origin, normal, distance, gap=None):
    """The stretched shape: each solid of `shape` split, moved, filled and joined."""
    import Part
    solids = brep.solids_of(shape)
    lo = min(brep.extent(s, origin, normal)[0] for s in solids)
    hi = max(brep.extent(s, origin, normal)[1] for s in solids)
    if not lo < 0 < hi:
        raise DeformError("Plane misses the part: the whole part lies on one side of it; "
                          "move Plane so it crosses the part.", "Plane")
    if gap is not None and not lo < gap < hi:
        raise DeformError("Plane2 misses the part; move Plane2 so it crosses the part.", "Plane2")
    if gap is not None and gap + distance <= 0:
        raise DeformError(f"Distance {distance:g} would collapse the region between the planes "
                          f"(gap {gap:g}); keep Distance above {-gap:g}.", "Distance")
    out = [_stretch_solid(s, origin, normal, distance, gap) for s in solids]
    out = [s for s in out if s is not None] + _stretch_loose(
        brep.loose_parts(shape), origin, normal, distance, gap)
    return out[0] if len(out) == 1 else Part.makeCompound(out)


def _stretch_loose(parts, origin, normal, distance, gap):
    """Wireframes and free faces: the same split and motion, cut points swept across the gap."""
    move = distance * normal
    if not parts or distance == 0:
        return [p.copy() for p in parts]
    if gap is not None:
        near, between, far = brep.split_loose(parts, origin, normal, [0.0, gap])
        between = brep.affine_stretched(between, origin, normal, (gap + distance) / gap)
        return near + between + brep.translated(far, move)
    if distance > 0:
        near, far = brep.split_loose(parts, origin, normal, [0.0])
        fill = brep.swept_points(brep.points_on_plane(near, origin, normal), move)
        return near + fill + brep.translated(far, move)
    near, _, far = brep.split_loose(parts, origin, normal, [0.0, -distance])
    return near + brep.translated(far, move)


def _stretch_solid(solid, origin, normal, distance, gap):
    move = distance * normal
    if distance == 0:
        return solid.copy()
    if gap is not None:
        near, between, far = brep.split_zones(solid, origin, normal, [0.0, gap])
        cut = brep.faces_on_plane(near, origin, normal)
        if cut and brep.is_prismatic(between, origin, normal, gap):
            middle = brep.extruded(cut, (gap + distance) * normal)
        else:
            middle = brep.affine_stretched(between, origin, normal, (gap + distance) / gap)
        return _joined(near + middle + brep.translated(far, move), origin, normal,
                       [0.0, gap + distance])
    if distance > 0:
        near, far = brep.split_zones(solid, origin, normal, [0.0])
        cut = brep.faces_on_plane(near, origin, normal)
        return _joined(near + brep.extruded(cut, move) + brep.translated(far, move), origin,
                       normal, [0.0, distance])
    near, slab, far = brep.split_zones(solid, origin, normal, [0.0, -distance])
    if near and slab and not far:
        reach = max(brep.extent(s, origin, normal)[1] for s in slab)
        raise DeformError(f"Distance {distance:g} shrinks past the end of the part, which reaches "
                          f"{reach:g} beyond Plane; keep Distance above {-reach:g}.", "Distance")
    return _joined(near + brep.translated(far, move), origin, normal, [0.0])


def _joined(pieces, origin, normal, joints):
    return brep.join(pieces, origin, normal, joints) if pieces else None


def _joints(shape, origin, normal, gap):
    """(face name, "G1"/"C0") for every face of `shape` a separating plane cuts."""
    planes = [origin] if gap is None else [origin, origin + gap * normal]
    worst = {}
    for o in planes:
        for name, face in brep.crossing_faces(shape, o, normal):
            _, normals = brep.joint_normals(face, o, normal)
            kind = continuity.joint_continuity(normals, normal)
            worst[name] = "C0" if "C0" in (kind, worst.get(name)) else kind
    return sorted(worst.items(), key=lambda item: int(item[0][4:]))
