"""AreaConstrain (Xu, Joneja & Tang 2009): move chosen poles of a B-spline face as little as
possible (least squares) so its area is exactly the target. Knots, degrees and weights
stay; a face of a shell or solid whose border poles stay put is replaced in it."""
import numpy as np
import Part

from ..geometry.errors import DeformError
from ..geometry.nurbs import area_constrain as ac
from ..shapes import bspline


def target_of(target_area, target_ratio, original):
    """The area asked: target_ratio x the original area, or target_area when the ratio is 0."""
    if target_ratio:
        if target_ratio <= 0:
            raise DeformError("TargetRatio must be positive (or 0 to use TargetArea).",
                              "TargetRatio")
        return target_ratio * original
    return target_area


def face(shape, face, target_area=0.0, target_ratio=0.0, poles=(), dof="Normal",
         method="Lagrange-Newton"):
    """(result, outputs): face `face` ("Face1") of `shape` with the poles named in `poles`
    ("i,j", 1-based; empty: every interior pole) moved so its area is the target. The
    result is `shape` with the face replaced, or the face alone when a border pole moved
    or it cannot be replaced (outputs["Replaced"] says which)."""
    index, element = bspline.face_of(shape, face)
    surface, note = bspline.bspline_of(element)
    arrays = bspline.surface_arrays(surface)
    movable = ac.parse_poles(list(poles), arrays.weights.shape)
    q = ac.area_quadrature(arrays, movable, dof, method)
    original = q.area(arrays.poles)
    solution = ac.constrain_surface_area(arrays, movable,
                                         target_of(target_area, target_ratio, original),
                                         dof, method, q)
    new_face = Part.Face(bspline.with_poles(surface, solution.poles))
    moves = np.linalg.norm((solution.poles - arrays.poles).reshape(-1, 3), axis=1)
    result, prop = None, "TargetRatio" if target_ratio else "TargetArea"
    if not ac.on_boundary(movable, arrays.weights.shape):
        result = bspline.replaced(shape, index, new_face)
    outputs = {"OriginalArea": original, "AchievedArea": solution.area,
               "AreaError": solution.error,
               "NormalFallbacks": [f"{i},{j}" for i, j in solution.fallbacks],
               "HeldPoles": [f"{i},{j}" for i, j in solution.held],
               "Iterations": solution.iterations, "MaxPoleMove": float(moves.max()),
               "KKTResidual": solution.kkt, "Conversion": note,
               "Replaced": result is not None}
    shape_out = result if result is not None else new_face
    if not shape_out.isValid():
        raise _folded(solution.area, moves.max(), original, prop)
    return shape_out, outputs


def _folded(area, move, original, prop):
    """The refusal of a face the solution folded (OCCT's check fails, or OCCT cannot make
    a solid of it)."""
    return DeformError(f"The face at {area:.6g} mm^2 fails OCCT's check (its poles moved up "
                       f"to {move:.3g} mm, folding it); ask for an area nearer the original "
                       f"{original:.6g} mm^2 with {prop}.", prop)
