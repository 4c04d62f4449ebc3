"""DirectPush (Yamashita & Fukui's DDM; Pratt for faces of solids): grab any point of a
B-spline edge or face and push it where it must go; poles and knots follow.

The pushes are stored in order (Points[i] goes to Targets[i]) and replayed from the Base
on every recompute (ops.direct_push), so each stays editable and removable. Fixed points,
straight spans and angles are set up first; every push then respects them.
"""
from ..geometry.errors import DeformError
from ..ops import direct_push as op
from .base import DeformFeature, Prop


def inputs_of(obj):
    """The properties a replay reads (ops.direct_push.INPUTS), and the Base's shape."""
    inputs = {name: getattr(obj, name) for name in op.INPUTS}
    inputs["Shape"] = obj.Base.Shape
    return inputs


class DirectPush(DeformFeature):
    TYPE = "DirectPush"
    RESULT = "Part::FeaturePython"
    PROPERTIES = (
        Prop("App::PropertyLink", "Base", "Base",
             "The shape that holds the edge or face; it is never modified."),
        Prop("App::PropertyString", "Element", "Base",
             "The edge or face to push: Edge1, Face1, ... (converted to a B-spline when it "
             "is not one).", "Edge1"),
        Prop("App::PropertyVectorList", "Points", "Pushes",
             "Grabbed points, in order: Points[i] is on the element as the earlier pushes "
             "left it, and goes to Targets[i]."),
        Prop("App::PropertyVectorList", "Targets", "Pushes",
             "Where each grabbed point must go (same count as Points)."),
        Prop("App::PropertyInteger", "Range", "Pushes",
             "The paper's m: a push moves poles V_i..V_i+m around the point (m + 1 per "
             "direction on a surface). 0: degree + 1.", 0),
        Prop("App::PropertyVectorList", "Fixed", "Constraints",
             "Points of the element that keep their position and tangent."),
        Prop("App::PropertyVectorList", "Straight", "Constraints",
             "Pairs of points; the curve between each pair (on a face: the iso-curve from "
             "the first toward the second) becomes a straight span and stays straight "
             "under the pushes."),
        Prop("App::PropertyVectorList", "Angles", "Constraints",
             "Pairs of vectors (corner, (angle in degrees, leg before, leg after)): a cusp "
             "at the corner with straight legs at that angle (on a face: a crease along "
             "the v iso-curve through the corner, straight sides)."),
        Prop("App::PropertyStringList", "Blend", "Constraints",
             "Faces of a solid: edges (Edge1, ...) rounded the way Pratt proposes: the poles "
             "the two faces share along the edge go midway between their neighbours, so "
             "the faces meet with C1 (planar four-sided faces)."),
        Prop("App::PropertyFloat", "MaxPoleMove", "Result",
             "The largest distance a pole moved, mm.", output=True),
        Prop("App::PropertyInteger", "PoleCount", "Result",
             "Poles of the result (knots are inserted for fixed points, spans, angles and "
             "when a push needs more poles).", output=True),
        Prop("App::PropertyInteger", "RangeUsed", "Result",
             "The Range the pushes used: Range, or less when the element has fewer poles "
             "(a larger Range moves all of its interior poles).", output=True),
        Prop("App::PropertyString", "Conversion", "Result",
             "How the element became a B-spline.", output=True),
    )

    def compute(self, obj, base_kind):
        if base_kind != "Part":
            raise DeformError("Base must be a shape with B-spline (or convertible) edges or "
                              "faces.", "Base")
        values = (obj.Base.Shape, obj.Element, obj.Points, obj.Targets, obj.Range, obj.Fixed,
                  obj.Straight, obj.Angles)
        if str(obj.Element).startswith("Face"):
            return op.face(*values, blend=obj.Blend)
        return op.curve(*values)
