"""Stretch (Wu & Ilies, Cases 1 and 2): split at a plane, move the far part, fill the gap."""
from ..geometry.errors import DeformError
from ..geometry.points_stretch import stretch_points
from ..shapes import brep
from ..shapes.convert import (mesh_arrays, mesh_from_arrays, points_array, points_from_array)
from . import split_sweep as ss
from .base import DeformFeature, Prop


class Stretch(DeformFeature):
    TYPE = "Stretch"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        Prop("App::PropertyDistance", "Distance", "Stretch",
             "How far the part beyond the plane moves along the normal; negative shrinks."),
        ss.USE_PLANE2, ss.PLANE2,
    ) + ss.RESULTS

    def compute(self, obj, kind):
        origin, normal, gap = ss.planes(obj)
        distance = obj.Distance.Value
        second = () if gap is None else (origin + gap * normal, normal)
        if kind == "Points":
            pts = stretch_points(points_array(obj.Base.Points), origin, normal, distance, *second)
            return points_from_array(pts), {}
        if kind == "Mesh":
            from ..geometry.mesh_stretch import stretch_mesh
            v, t = stretch_mesh(*mesh_arrays(obj.Base.Mesh), origin, normal, distance, *second)
            mesh = mesh_from_arrays(v, t)
            return mesh, {"VolumeChange": mesh.Volume - obj.Base.Mesh.Volume}
        shape = obj.Base.Shape
        result = stretch_shape(shape, origin, normal, distance, gap)
        joints = [(origin, normal, ss.constant(normal))]
        if gap is not None:
            joints.append((origin + gap * normal, normal, ss.constant(normal)))
        return result, {**ss.volume_change(result, shape), **ss.joint_report(shape, joints)}


def stretch_shape(shape, origin, normal, distance, gap=None):
    """The stretched shape: each solid of `shape` split, moved, filled and joined."""
    if gap is not None and gap + distance <= 0:
        raise DeformError(f"Distance {distance:g} would collapse the region between the planes "
                          f"(gap {gap:g}); keep Distance above {-gap:g}.", "Distance")
    return ss.deform_shape(
        shape, origin, normal, gap,
        lambda solid: _stretch_solid(solid, origin, normal, distance, gap),
        lambda parts: _stretch_loose(parts, origin, normal, distance, gap))


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
        return _joined(near + middle + brep.translated(far, move),
                       [(origin, normal), (origin + (gap + distance) * normal, normal)])
    if distance > 0:
        near, far = brep.split_zones(solid, origin, normal, [0.0])
        cut = brep.faces_on_plane(near, origin, normal)
        return _joined(near + brep.extruded(cut, move) + brep.translated(far, move),
                       [(origin, normal), (origin + move, normal)])
    near, slab, far = brep.split_zones(solid, origin, normal, [0.0, -distance])
    if near and slab and not far:
        reach = max(brep.extent(s, origin, normal)[1] for s in slab)
        raise DeformError(f"Distance {distance:g} shrinks past the end of the part, which reaches "
                          f"{reach:g} beyond Plane; keep Distance above {-reach:g}.", "Distance")
    return _joined(near + brep.translated(far, move), [(origin, normal)])


def _joined(pieces, joints):
    return brep.join(pieces, joints) if pieces else None


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
