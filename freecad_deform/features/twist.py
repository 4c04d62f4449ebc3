"""Twist (Wu & Ilies, Case 2): the region between two planes turns progressively about an
axis; the part beyond Plane2 turns rigidly; length and cross-sections are kept."""
import numpy as np

from ..geometry.errors import DeformError
from ..ops import twist
from ..shapes.convert import plane_arrays
from . import flex
from . import planes as ss
from .base import DeformFeature, Prop


class Twist(DeformFeature):
    TYPE = "Twist"
    PROPERTIES = (
        ss.BASE, ss.PLANE,
        ss.region_plane2("twists"),
        Prop("App::PropertyQuantity", "Angle", "Motion",
             "How far the region twists about Axis (with Turns); any number of turns, where "
             "an angle property would stop at 360 deg.", unit="deg"),
        Prop("App::PropertyInteger", "Turns", "Motion",
             "Whole turns added to Angle: the region twists by Angle + 360 deg x Turns.", 0),
        Prop("App::PropertyBool", "UseAxis", "Motion",
             "Twist about Axis; when false, about the Plane normal through the centroid of the "
             "cross-section at Plane.", False),
        ss.AXIS, ss.SAMPLES) + ss.RESULTS + flex.PROPERTIES + (flex.MAX_DEVIATION,)

    def compute(self, obj, base_kind):
        origin, normal, gap = ss.planes(obj, require_plane2=True)
        angle = np.radians(obj.Angle.Value + 360.0 * obj.Turns)
        ss.check_samples(obj, 2)
        axis = given_axis(obj, normal)
        if base_kind == "Points":
            return twist.points(obj.Base.Points, origin, normal, gap, angle, axis,
                                obj.Profile)
        if base_kind == "Mesh":
            return twist.mesh(obj.Base.Mesh, origin, normal, gap, angle, axis, obj.Samples,
                              obj.Profile)
        return twist.solid(obj.Base.Shape, origin, normal, gap, angle, axis, obj.Samples,
                           obj.Profile, flex.tolerance(obj))


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
