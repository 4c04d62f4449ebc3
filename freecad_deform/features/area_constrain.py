"""AreaConstrain (Xu, Joneja & Tang 2009): move chosen poles of a B-spline face as little as
possible (least squares) so its area is exactly the target. Knots, degrees and weights
stay; a face of a shell or solid whose boundary poles stay put is replaced in it.
The pipeline is ops.area_constrain."""
import FreeCAD as App

from ..geometry.nurbs import area_constrain as ac
from ..geometry.errors import DeformError
from ..ops import area_constrain as op
from .base import DeformFeature, Prop


class AreaConstrain(DeformFeature):
    TYPE = "AreaConstrain"
    RESULT = "Part::FeaturePython"
    PROPERTIES = (
        Prop("App::PropertyLink", "Base", "Base",
             "The shape that holds the face; it is never modified."),
        Prop("App::PropertyString", "Face", "Base",
             "The face to change, e.g. Face1. A face that is not a B-spline is converted.",
             "Face1"),
        Prop("App::PropertyArea", "TargetArea", "Area",
             "The area the face must have (used when TargetRatio is 0)."),
        Prop("App::PropertyFloat", "TargetRatio", "Area",
             "The target as a ratio of the original area (1.05 = +5 %); 0: use TargetArea.",
             0.0),
        Prop("App::PropertyStringList", "Poles", "Poles",
             "The poles that may move, as 'i,j' (1-based, as getPole(i, j)); empty: every "
             "interior pole (a face with none: every pole but the corners). Coincident "
             "poles (a collapsed row) move as one; those on a pole that stays, stay."),
        Prop("App::PropertyEnumeration", "Dof", "Poles",
             "How a pole may move: Normal, along the control-net normal (one variable, "
             "keeps the shape closest); Z, along z only; Free, in 3D.", list(ac.DOFS)),
        Prop("App::PropertyEnumeration", "Method", "Solver",
             "Lagrange-Newton: Newton on the KKT system with line search, exact area. "
             "Penalty: the paper's penalty Newton (area off by about 1e-8 relative).",
             list(ac.METHODS)),
        Prop("App::PropertyFloat", "OriginalArea", "Result",
             "Exact area of the face before (Gauss-Legendre on every knot span), mm^2.",
             output=True),
        Prop("App::PropertyFloat", "AchievedArea", "Result",
             "Exact area of the new face, mm^2.", output=True),
        Prop("App::PropertyFloat", "AreaError", "Result",
             "Estimated error of AchievedArea (quadrature graded toward points where the "
             "surface degenerates), mm^2.", output=True),
        Prop("App::PropertyStringList", "NormalFallbacks", "Result",
             "Poles 'i,j' with no control-net normal (coincident neighbours) that moved "
             "along the surface normal at their Greville point instead.", output=True),
        Prop("App::PropertyStringList", "HeldPoles", "Result",
             "Poles 'i,j' in Poles that stayed: they coincide with a pole that stays (a "
             "collapsed row of a degenerate edge).", output=True),
        Prop("App::PropertyInteger", "Iterations", "Result", "Newton iterations taken.",
             output=True),
        Prop("App::PropertyFloat", "MaxPoleMove", "Result",
             "The largest distance a pole moved, mm.", output=True),
        Prop("App::PropertyFloat", "KKTResidual", "Result",
             "|d + lambda grad A| / |d| for the pole displacement d: 0 when the "
             "displacement is parallel to the area gradient (optimal).", output=True),
        Prop("App::PropertyString", "Conversion", "Result",
             "How the face became a B-spline surface.", output=True),
        Prop("App::PropertyBool", "Replaced", "Result",
             "True: the result is the Base with the face replaced; False: the face alone "
             "(a boundary pole moved, or the Base is not one shell or solid).", output=True),
    )

    def compute(self, obj, base_kind):
        if base_kind != "Part":
            raise DeformError("Base must be a shape with a B-spline (or convertible) face.",
                              "Base")
        result, outputs = op.face(obj.Base.Shape, obj.Face, obj.TargetArea.Value,
                                  obj.TargetRatio, list(obj.Poles), obj.Dof, obj.Method)
        if "not exact" in outputs["Conversion"]:
            App.Console.PrintWarning(f"{obj.Label}: {obj.Face}: {outputs['Conversion']}.\n")
        return result, outputs
