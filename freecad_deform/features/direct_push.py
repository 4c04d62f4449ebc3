"""DirectPush (Yamashita & Fukui's DDM; Pratt for faces of solids): grab any point of a
B-spline edge or face and push it where it must go; poles and knots follow.

The pushes are stored in order (Points[i] goes to Targets[i]) and replayed from the Base
on every recompute, so each stays editable and removable. Fixed points, straight spans
and angles are set up first; every push then respects them. A face of a solid or shell
becomes a B-spline patch (a planar four-sided face: its exact bicubic Bezier form) whose
border poles never move, and the solid is sewn again.
"""
import numpy as np
import Part

from ..geometry import direct_push as dp
from ..geometry.errors import DeformError
from ..shapes import bspline
from .base import DeformFeature, Prop


def pairs(vectors, prop):
    v = [np.array(tuple(x)) for x in vectors]
    if len(v) % 2:
        raise DeformError(f"{prop} holds pairs of vectors; it has an odd count.", prop)
    return list(zip(v[0::2], v[1::2]))


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
             "Edges only: pairs of points; the curve between each pair becomes a straight "
             "span and stays straight under the pushes."),
        Prop("App::PropertyVectorList", "Angles", "Constraints",
             "Edges only: pairs of vectors (corner, (angle in degrees, leg before, leg "
             "after)): a cusp at the corner with straight legs at that angle."),
        Prop("App::PropertyFloat", "MaxPoleMove", "Result",
             "The largest distance a pole moved, mm.", output=True),
        Prop("App::PropertyInteger", "PoleCount", "Result",
             "Poles of the result (knots are inserted for fixed points, spans, angles and "
             "when a push needs more poles).", output=True),
        Prop("App::PropertyString", "Conversion", "Result",
             "How the element became a B-spline.", output=True),
    )

    def compute(self, obj, kind):
        if kind != "Part":
            raise DeformError("Base must be a shape with B-spline (or convertible) edges or "
                              "faces.", "Base")
        if len(obj.Points) != len(obj.Targets):
            raise DeformError(f"Points has {len(obj.Points)} entries and Targets "
                              f"{len(obj.Targets)}; give one target per point.", "Targets")
        shape = obj.Base.Shape
        tol = 1e-6 * max(1.0, shape.BoundBox.DiagonalLength) + 1e-7
        pushes = [(np.array(tuple(p)), np.array(tuple(q))) for p, q in zip(obj.Points,
                                                                         obj.Targets)]
        if str(obj.Element).startswith("Face"):
            return self._face(obj, shape, pushes, tol)
        return self._edge(obj, shape, pushes, tol)

    @staticmethod
    def _on(distance, tol, what, name):
        if distance > tol:
            raise DeformError(f"{what} is not on {name} ({distance:.3g} mm away); pick a "
                              "point on it.", what.split("[")[0])

    def _edge(self, obj, shape, pushes, tol):
        _, edge = bspline.edge_of(shape, obj.Element)
        curve, note = bspline.curve_of(edge)
        c = bspline.curve_arrays(curve)
        p = c.degree
        size = (obj.Range if obj.Range > 0 else p + 1) + 1
        original = c

        def param(x, what):
            t, d = dp.closest_parameter(original, x)
            self._on(d, tol, what, obj.Element)
            return t
        fixed = [param(x, f"Fixed[{i}]") for i, x in enumerate(obj.Fixed)]
        spans = [tuple(sorted((param(a, f"Straight[{2 * i}]"), param(b, f"Straight[{2 * i + 1}]"))))
                 for i, (a, b) in enumerate(pairs(obj.Straight, "Straight"))]
        corners = [(param(x, f"Angles[{2 * i}]"), x, spec)
                   for i, (x, spec) in enumerate(pairs(obj.Angles, "Angles"))]
        for t in fixed:
            c = dp.curve_with_knot(c, t, p)
        for a, b in spans:
            c, _ = dp.make_straight(c, a, b)
        for t, x, (degrees, before, after) in corners:
            if not (0 < degrees < 180 and before > 0 and after > 0):
                raise DeformError("An angle is between 0 and 180 degrees and its legs are "
                                  "longer than 0; change Angles.", "Angles")
            c, _ = dp.make_angle(c, t, np.radians(degrees), (before, after), x)
        start = c
        for i, (x, target) in enumerate(pushes):
            t, d = dp.closest_parameter(c, x)
            if d > tol:  # a point given on the Base, before the constraints reshaped it
                t, d = dp.closest_parameter(original, x)
            self._on(d, tol, f"Points[{i}]", obj.Element)
            c = dp.refine_curve(c, t, size)
            held = [k + j for tf in fixed for k in [dp.pole_at(c, tf)] for j in (-1, 0, 1)]
            held += [k + j for tc, _, _ in corners for k in [dp.pole_at(c, tc)]
                     for j in range(-p, p + 1)]
            groups = [dp.straight_poles(c, a, b) for a, b in spans]
            c = dp.push_curve(c, t, target, size, held, groups)
        moves = self._moves(start, c)
        return bspline.curve_from_arrays(c).toShape(), {
            "MaxPoleMove": moves, "PoleCount": len(c.poles), "Conversion": note}

    @staticmethod
    def _moves(before, after):
        if before.poles.shape != after.poles.shape:
            return float("nan")
        return float(np.linalg.norm((after.poles - before.poles).reshape(-1, 3), axis=1).max()) \
            if after.poles.size else 0.0

    def _face(self, obj, shape, pushes, tol):
        index, face = bspline.face_of(shape, obj.Element, "Element")
        if len(obj.Straight) or len(obj.Angles):
            raise DeformError("Straight spans and Angles work on edges; clear them for a "
                              "face.", "Straight" if len(obj.Straight) else "Angles")
        corners = bspline.quad_corners(face)
        solid = len(shape.Solids) == 1 or (len(shape.Shells) == 1 and len(shape.Faces) > 1)
        if corners is not None:
            s = dp.bezier_patch(corners)
            note = "planar four-sided face: exact bicubic Bezier patch (Pratt)"
        else:
            surface, note = bspline.bspline_of(face, "Element")
            s = bspline.surface_arrays(surface)
        size = (obj.Range if obj.Range > 0 else max(s.udegree, s.vdegree) + 1) + 1
        fixed = []
        for i, x in enumerate(obj.Fixed):
            u, v, d = dp.closest_uv(s, np.array(tuple(x)))
            self._on(d, tol, f"Fixed[{i}]", obj.Element)
            fixed.append((u, v))
        start = s
        for i, (x, target) in enumerate(pushes):
            u, v, d = dp.closest_uv(s, x)
            if d > tol:
                u, v, d = dp.closest_uv(start, x)
            self._on(d, tol, f"Points[{i}]", obj.Element)
            if min(s.weights.shape) < 3:  # no interior pole in one direction (a cylinder)
                s = dp.refine_surface(s, u, v, 1)
            s = dp.push_surface(s, u, v, target, size, fixed)
        new_face = Part.Face(bspline.surface_from_arrays(s))
        outputs = {"MaxPoleMove": self._moves(start, s), "PoleCount": int(s.weights.size),
                   "Conversion": note}
        if not solid:
            return new_face, outputs
        result = bspline.replaced(shape, index, new_face)
        if result is None:
            raise DeformError(f"{obj.Element} could not be sewn back into the Base after the "
                              "push; push less far or pick another point.", "Targets")
        return result, outputs
