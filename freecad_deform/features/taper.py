"""Taper (Wu & Ilies, the scaling function of Step 6 and Fig. 11): the region between two
planes is scaled across an axis by scale(s), 1 at Plane to Scale at Plane2 (or ScaleX and
ScaleY along the axis frame's X and Y); the part beyond Plane2 is scaled by Scale. Solids go
through the space map face by face (shapes.mapped), meshes and point clouds vertex by
vertex, exactly."""
import numpy as np

from ..ops import taper
from ..shapes.convert import plane_arrays
from . import flex
from . import planes as ss
from .base import DeformFeature, Prop


class Taper(DeformFeature):
    TYPE = "Taper"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        ss.region_plane2("is tapered"),
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

    def compute(self, obj, base_kind):
        origin, normal, gap = ss.planes(obj, require_plane2=True)
        scale = (obj.ScaleX, obj.ScaleY) if obj.UseScaleXY else obj.Scale
        # the axis frame: Axis's, or Plane's about the section centroid (point None)
        frame = obj.Axis if obj.UseAxis else obj.Plane
        rows = np.array(frame.Rotation.toMatrix().A, float).reshape(4, 4)[:3, :3].T
        point = plane_arrays(obj.Axis)[0] if obj.UseAxis else None
        if base_kind == "Points":
            return taper.points(obj.Base.Points, origin, normal, gap, scale, rows, point,
                                obj.Profile)
        if base_kind == "Mesh":
            return taper.mesh(obj.Base.Mesh, origin, normal, gap, scale, rows, point,
                              obj.Profile)
        return taper.solid(obj.Base.Shape, origin, normal, gap, scale, rows, point,
                           obj.Profile, flex.tolerance(obj))
