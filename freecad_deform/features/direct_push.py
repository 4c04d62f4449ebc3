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
            self._check_angle(degrees, before, after)
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
    def _check_angle(degrees, before, after):
        if not (0 < degrees < 180 and before > 0 and after > 0):
            raise DeformError("An angle is between 0 and 180 degrees and its legs are "
                              "longer than 0; change Angles.", "Angles")

    @staticmethod
    def _moves(before, after):
        if before.poles.shape != after.poles.shape:
            return float("nan")
        return float(np.linalg.norm((after.poles - before.poles).reshape(-1, 3), axis=1).max()) \
            if after.poles.size else 0.0

    def _face(self, obj, shape, pushes, tol):
        index, face = bspline.face_of(shape, obj.Element, "Element")
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
        original, spans = s, []
        for i, (a, b) in enumerate(pairs(obj.Straight, "Straight")):
            ends = []
            for k, x in enumerate((a, b)):
                u, v, d = dp.closest_uv(s, x)
                self._on(d, tol, f"Straight[{2 * i + k}]", obj.Element)
                ends.append((u, v))
            spans.append(tuple(ends))
            s, _ = dp.make_straight_surface(s, *ends)
        held = []
        for i, (x, (degrees, before, after)) in enumerate(pairs(obj.Angles, "Angles")):
            u, v, d = dp.closest_uv(s, x)
            self._on(d, tol, f"Angles[{2 * i}]", obj.Element)
            self._check_angle(degrees, before, after)
            s, held = dp.make_angle_surface(s, (u, v), np.radians(degrees), (before, after), x)
        start, landed = s, []
        for i, (x, target) in enumerate(pushes):
            u, v, d = dp.closest_uv(s, x)
            if d > tol:  # a point given on the Base, before the constraints reshaped it
                u, v, d = dp.closest_uv(original, x)
            self._on(d, tol, f"Points[{i}]", obj.Element)
            if min(s.weights.shape) < 3:  # no interior pole in one direction (a cylinder)
                s = dp.refine_surface(s, u, v, 1)
            groups = [dp.straight_group(s, a, b) for a, b in spans]
            s = dp.push_surface(s, u, v, target, size, fixed, groups, held)
            landed.append((u, v, target))
        outputs = {"MaxPoleMove": self._moves(start, s), "PoleCount": int(s.weights.size),
                   "Conversion": note}
        if not solid:
            if len(obj.Blend):
                raise DeformError("Blend needs a face of a solid or shell.", "Blend")
            return Part.Face(bspline.surface_from_arrays(s)), outputs
        patches, inner = {index: s}, set()
        for name in obj.Blend:
            inner |= self._blend(shape, patches, name, tol).get(index, set())
        if obj.Blend and landed:
            patches[index] = self._reland(patches[index], landed, inner)
        result = bspline.replaced_all(shape, {i: Part.Face(bspline.surface_from_arrays(p))
                                              for i, p in patches.items()})
        if result is None:
            raise DeformError(f"{obj.Element} could not be sewn back into the Base after the "
                              "push; push less far or pick another point.", "Targets")
        return result, outputs

    @staticmethod
    def _blend(shape, patches, name, tol):
        """Pratt's rounding of edge `name`: its two faces as bicubic Bezier patches, every
        pole they share along it put midway between its neighbours on either face (C1
        across the edge). Each end pole moves within the plane of the third face at that
        corner, which becomes a patch too, so the solid stays closed."""
        _, edge = bspline.edge_of(shape, name, "Blend")
        faces = [i for i, f in enumerate(shape.Faces) if any(e.isSame(edge) for e in f.Edges)]
        ends = [np.array(tuple(v.Point)) for v in edge.Vertexes]
        if len(faces) != 2:
            raise DeformError(f"Blend {name} is not an edge between two faces.", "Blend")
        for i in faces:
            patches.setdefault(i, _patch(shape.Faces[i], name))
        rows = [bspline_row(patches[i], ends, tol, name) for i in faces]
        (a, ra), (b, rb) = zip(faces, rows)
        A, B = patches[a].poles.copy(), patches[b].poles.copy()
        shared = 0.5 * (A[ra[1]] + B[rb[1]])
        for corner, end in ((0, ends[0]), (-1, ends[1])):
            thirds = [i for i, f in enumerate(shape.Faces) if i not in faces and any(
                np.linalg.norm(np.array(tuple(v.Point)) - end) <= tol for v in f.Vertexes)]
            if len(thirds) != 1:
                raise DeformError(f"Blend {name}: three faces must meet at each end of the "
                                  "edge.", "Blend")
            c = thirds[0]
            patches.setdefault(c, _patch(shape.Faces[c], name))
            C = patches[c].poles.copy()
            k = np.argmin(np.linalg.norm(C - end, axis=2))
            C[np.unravel_index(k, C.shape[:2])] = shared[corner]
            patches[c] = patches[c]._replace(poles=C)
        A[ra[0]], B[rb[0]] = shared, shared
        patches[a], patches[b] = patches[a]._replace(poles=A), patches[b]._replace(poles=B)
        return {i: set(np.ravel_multi_index(r[1], patches[i].weights.shape).tolist())
                for i, r in zip(faces, rows)}

    @staticmethod
    def _reland(s, landed, held):
        """The pushed points back on their targets after a blend moved the patch's border:
        a least-norm correction of the interior poles, keeping the rows that make the
        blend C1 (`held`)."""
        nu, nv = s.weights.shape
        P = s.poles.reshape(-1, 3)
        rows = [dp.surface_row(s, u, v) for u, v, _ in landed]
        rhs = [t - r @ P for r, (_, _, t) in zip(rows, landed)]
        movable = [i * nv + j for i in range(1, nu - 1) for j in range(1, nv - 1)
                   if i * nv + j not in held]
        D = dp.least_norm(nu * nv, movable, rows, rhs)
        return s._replace(poles=(P + D).reshape(s.poles.shape))


def _patch(face, name):
    corners = bspline.quad_corners(face)
    if corners is None:
        raise DeformError(f"Blend {name}: its faces and the faces at its ends must be planar "
                          "and four-sided (they become Bezier patches).", "Blend")
    return dp.bezier_patch(corners)


def bspline_row(patch, ends, tol, name):
    """(index of the border row along the edge from ends[0] to ends[1], index of the row
    next to it inside), as numpy index tuples into patch.poles, ordered like the edge."""
    nu, nv = patch.weights.shape
    iu, iv = np.arange(nu), np.arange(nv)
    borders = [((np.zeros(nv, int), iv), (np.ones(nv, int), iv)),
               ((np.full(nv, nu - 1), iv), (np.full(nv, nu - 2), iv)),
               ((iu, np.zeros(nu, int)), (iu, np.ones(nu, int))),
               ((iu, np.full(nu, nv - 1)), (iu, np.full(nu, nv - 2)))]
    for row, inner in borders:
        for flip in (False, True):
            r = tuple(x[::-1] for x in row) if flip else row
            pts = patch.poles[r]
            if np.linalg.norm(pts[0] - ends[0]) <= tol and np.linalg.norm(pts[-1] - ends[1]) <= tol:
                return r, (tuple(x[::-1] for x in inner) if flip else inner)
    raise DeformError(f"Blend {name} is not along the border of its face's patch (was the "
                      "face refined?).", "Blend")
