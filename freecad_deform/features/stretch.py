"""Stretch (Wu & Ilies, Cases 1 and 2): split at a plane, move the far part, fill the gap."""
from ..geometry.errors import DeformError
from ..geometry.sweep import motion as mo
from ..ops import stretch
from ..shapes import brep
from . import flex
from . import planes as ss
from .base import DeformFeature, Prop


class Stretch(DeformFeature):
    TYPE = "Stretch"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        Prop("App::PropertyDistance", "Distance", "Stretch",
             "How far the part beyond the plane moves along the normal; negative shrinks."),
        ss.USE_PLANE2, ss.PLANE2,
        Prop("App::PropertyVectorList", "Polyline", "Planes",
             "Case 3: corner points of a polyline in a plane that contains the Plane normal; "
             "the separating surface is the polyline extruded perpendicular to that plane, "
             "and the part moves along the Plane normal. Empty: the flat Plane."),
        ss.KEYS, ss.INTERPOLATION, ss.USE_END, ss.END, ss.SAMPLES, flex.TOLERANCE,
    ) + ss.RESULTS + (flex.MAX_DEVIATION,)

    def compute(self, obj, base_kind):
        origin, normal, gap = ss.planes(obj)
        distance = obj.Distance.Value
        if abs(distance) <= brep.TOL:  # below the modelling tolerance nothing moves
            distance = 0.0
        if len(obj.Polyline) > 0:
            if base_kind != "Part" or obj.UsePlane2:
                raise DeformError("A Polyline separating surface works on solids with one "
                                  "surface; clear Polyline or UsePlane2.", "Polyline")
            return stretch.polyline(obj.Base.Shape, obj.Polyline, normal, distance)
        motion = ss.key_motion(obj, mo.translation(distance * normal))
        if motion is not None:
            return ss.keyed(obj, base_kind, origin, normal, gap, motion)
        if base_kind == "Points":
            return stretch.points(obj.Base.Points, origin, normal, distance, gap)
        if base_kind == "Mesh":
            return stretch.mesh(obj.Base.Mesh, origin, normal, distance, gap)
        return stretch.solid(obj.Base.Shape, origin, normal, distance, gap, flex.tolerance(obj))
