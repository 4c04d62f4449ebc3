"""Bend (Wu & Ilies): the far part turns about an axis; the gap is the section revolved."""
import numpy as np

from ..geometry.sweep import motion as mo
from ..ops import bend
from ..shapes.convert import plane_arrays
from . import flex
from . import planes as ss
from .base import DeformFeature


class Bend(DeformFeature):
    TYPE = "Bend"
    PROPERTIES = (ss.BASE, ss.PLANE, ss.ANGLE, ss.AXIS, ss.USE_PLANE2, ss.PLANE2,
                  ss.KEYS, ss.INTERPOLATION, ss.SAMPLES) + ss.RESULTS + flex.PROPERTIES + (
                      flex.MAX_DEVIATION,)

    def compute(self, obj, base_kind):
        origin, normal, gap = ss.planes(obj)
        axis = plane_arrays(obj.Axis)
        angle = np.radians(obj.Angle.Value)
        ss.check_samples(obj, 1)
        motion = ss.key_motion(obj, mo.rotation(*axis, angle))
        if motion is not None:
            return ss.keyed(obj, base_kind, origin, normal, gap, motion)
        if base_kind == "Points":
            return bend.points(obj.Base.Points, origin, normal, angle, axis, gap, obj.Profile)
        if base_kind == "Mesh":
            return bend.mesh(obj.Base.Mesh, origin, normal, angle, axis, gap, obj.Samples,
                             obj.Profile)
        return bend.solid(obj.Base.Shape, origin, normal, angle, axis, gap, obj.Samples,
                          obj.Profile, flex.tolerance(obj))
