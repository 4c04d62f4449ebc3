"""AreaConstrain (Xu, Joneja & Tang 2009): move chosen poles of a B-spline face as little as
possible (least squares) so its area is exactly the target. Knots, degrees and weights
stay; a face of a shell or solid whose boundary poles stay put is replaced in it."""
import FreeCAD as App
import numpy as np
import Part

from ..geometry.nurbs import area_constrain as ac
from ..geometry.errors import DeformError
from ..shapes import bspline
from .base import DeformFeature, Prop


def parse_poles(entries, shape):
    """Flat pole indices of "i,j" entries (1-based, as getPole); none: every interior pole,
    or on a face with none (2 poles across: a ruled face) every pole but the corners."""
    nu, nv = shape
    if not entries:
        if nu > 2 and nv > 2:
            return [i * nv + j for i in range(1, nu - 1) for j in range(1, nv - 1)]
        corners = {0, nv - 1, (nu - 1) * nv, nu * nv - 1}
        free = [m for m in range(nu * nv) if m not in corners]
        if not free:
            raise DeformError(f"The face has only its {nu} x {nv} corner poles, and a corner "
                              f"cannot move without tearing the face from its edges; list "
                              f"corner poles in Poles to move them, or pick a face with "
                              f"interior poles.", "Poles")
        return free
    flat = []
    for entry in entries:
        try:
            i, j = (int(x) for x in str(entry).replace("(", "").replace(")", "").split(","))
        except ValueError:
            raise DeformError(f"Poles entry {entry!r} is not 'i,j'; correct Poles.", "Poles")
        if not (1 <= i <= nu and 1 <= j <= nv):
            raise DeformError(f"Poles: pole ({i}, {j}) is outside the {nu} x {nv} poles of "
                              f"the face (1 to {nu}, 1 to {nv}); correct Poles.", "Poles")
        flat.append((i - 1) * nv + (j - 1))
    return sorted(set(flat))


def on_boundary(flat, shape):
    nu, nv = shape
    i, j = np.divmod(np.asarray(flat), nv)
    return bool(np.any((i == 0) | (i == nu - 1) | (j == 0) | (j == nv - 1)))


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

    def target(self, obj, original):
        if obj.TargetRatio:
            if obj.TargetRatio <= 0:
                raise DeformError("TargetRatio must be positive (or 0 to use TargetArea).",
                                  "TargetRatio")
            return obj.TargetRatio * original
        return obj.TargetArea.Value

    def compute(self, obj, kind):
        if kind != "Part":
            raise DeformError("Base must be a shape with a B-spline (or convertible) face.",
                              "Base")
        shape = obj.Base.Shape
        index, face = bspline.face_of(shape, obj.Face)
        surface, note = bspline.bspline_of(face)
        if "not exact" in note:
            App.Console.PrintWarning(f"{obj.Label}: {obj.Face}: {note}.\n")
        arrays = bspline.surface_arrays(surface)
        movable = parse_poles(list(obj.Poles), arrays.weights.shape)
        q = ac.area_quadrature(arrays, movable, obj.Dof, obj.Method)
        original = q.area(arrays.poles)
        solution = ac.constrain_surface_area(arrays, movable, self.target(obj, original),
                                             obj.Dof, obj.Method, q)
        new_surface = bspline.with_poles(surface, solution.poles)
        new_face = Part.Face(new_surface)
        result = None
        if not on_boundary(movable, arrays.weights.shape):
            result = bspline.replaced(shape, index, new_face)
        moves = np.linalg.norm((solution.poles - arrays.poles).reshape(-1, 3), axis=1)
        outputs = {"OriginalArea": original, "AchievedArea": solution.area,
                   "AreaError": solution.error,
                   "NormalFallbacks": [f"{i},{j}" for i, j in solution.fallbacks],
                   "HeldPoles": [f"{i},{j}" for i, j in solution.held],
                   "Iterations": solution.iterations, "MaxPoleMove": float(moves.max()),
                   "KKTResidual": solution.kkt, "Conversion": note,
                   "Replaced": result is not None}
        return (result if result is not None else new_face), outputs
