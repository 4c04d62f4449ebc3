"""Taper (Wu & Ilies, the scaling function of Step 6 and Fig. 11): the region between two
planes is scaled across an axis by scale(s), 1 at Plane to Scale at Plane2 (or ScaleX and
ScaleY along the axis frame's X and Y); the part beyond Plane2 is scaled by Scale. Solids go
through the space map face by face (shapes.mapped), meshes and point clouds vertex by
vertex, exactly."""
import numpy as np

from ..geometry.sweep import space_map
from ..geometry.errors import DeformError
from ..shapes import brep
from ..shapes.convert import mesh_arrays, plane_arrays, points_from_array
from . import flex
from . import planes as ss
from .base import DeformFeature, Prop
from .twist import section_centroid, section_centroid_mesh


class Taper(DeformFeature):
    TYPE = "Taper"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        Prop("App::PropertyPlacement", "Plane2", "Planes",
             "Second separating plane, parallel to Plane and beyond it along the normal: the "
             "region between the planes is tapered."),
        Prop("App::PropertyFloat", "Scale", "Motion",
             "Scale across the axis at Plane2 (1 at Plane); the part beyond Plane2 is scaled "
             "by it too.", 0.8),
        Prop("App::PropertyBool", "UseScaleXY", "Motion",
             "Scale by ScaleX and ScaleY along the X and Y of the axis frame (Axis, or Plane "
             "when UseAxis is false) instead of Scale in every direction across the axis.",
             False),
        Prop("App::PropertyFloat", "ScaleX", "Motion", "Scale along X at Plane2 (UseScaleXY).",
             0.8),
        Prop("App::PropertyFloat", "ScaleY", "Motion", "Scale along Y at Plane2 (UseScaleXY).",
             0.8),
        Prop("App::PropertyBool", "UseAxis", "Motion",
             "Scale about Axis (its local Z); when false, about the Plane normal through the "
             "centroid of the cross-section at Plane.", False),
        ss.AXIS) + flex.PROPERTIES + ss.RESULTS + (flex.MAX_DEVIATION,)

    def compute(self, obj, kind):
        origin, normal, gap = ss.planes(obj, require_plane2=True)
        scale = (obj.ScaleX, obj.ScaleY) if obj.UseScaleXY else obj.Scale
        if kind == "Points":
            pts, ignored = ss.cloud(obj.Base)
            centre = None if obj.UseAxis else _near_centre(pts, origin, normal, gap)
            smap = self._map(obj, origin, normal, gap, scale, centre)
            return points_from_array(smap(pts)), ignored
        if kind == "Mesh":
            v, t = mesh_arrays(obj.Base.Mesh)
            centre = None if obj.UseAxis else section_centroid_mesh(obj.Base.Mesh, origin,
                                                                     normal)
            smap = self._map(obj, origin, normal, gap, scale, centre)
            return ss.mesh_result(obj.Base.Mesh, smap(v), t)
        shape = obj.Base.Shape
        solids = brep.solids_of(shape)
        ss.check_crossing(solids, origin, normal, gap)
        centre = None if obj.UseAxis else section_centroid(solids, origin, normal)
        smap = self._map(obj, origin, normal, gap, scale, centre)
        result, outputs = flex.mapped_result(shape, smap, obj)
        return result, {**ss.volume_change(result, shape), **outputs}

    @staticmethod
    def _map(obj, origin, normal, gap, scale, centre):
        """The taper map about Axis, or about the normal through `centre`."""
        if obj.UseAxis:
            point, _ = plane_arrays(obj.Axis)
            rows = np.array(obj.Axis.Rotation.toMatrix().A, float).reshape(4, 4)[:3, :3].T
        else:
            point = centre
            rows = np.array(obj.Plane.Rotation.toMatrix().A, float).reshape(4, 4)[:3, :3].T
        if np.linalg.norm(np.cross(rows[2], normal)) > 1e-9:
            raise DeformError("Axis must be parallel to the Plane normal for a taper; turn "
                              "Axis.", "Axis")
        return space_map.taper_map(origin, normal, gap, scale, point, rows, obj.Profile)


def _near_centre(points, origin, normal, gap):
    """Mean of the cloud points in the first tenth of the region, put on Plane."""
    s = (points - origin) @ normal
    near = points[(s >= 0) & (s <= 0.1 * gap)]
    if len(near) == 0:
        raise DeformError("No point lies just beyond Plane; move Plane so it crosses the "
                          "cloud, or UseAxis.", "Plane")
    c = near.mean(axis=0)
    return c - ((c - origin) @ normal) * normal
