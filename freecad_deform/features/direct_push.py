"""DirectPush (Yamashita & Fukui's DDM; Pratt for faces of solids): grab any point of a
B-spline edge or face and push it where it must go; poles and knots follow.

The pushes are stored in order (Points[i] goes to Targets[i]) and replayed from the Base
on every recompute, so each stays editable and removable. Fixed points, straight spans
and angles are set up first; every push then respects them. A face becomes a B-spline
patch (a planar four-sided face: its exact bicubic Bezier form) whose border poles never
move; a trimmed face keeps its boundary in parameter space (rebuilt on its pcurves), and
in a solid or shell also the poles that move that boundary stay, so the face goes back
with its own edges and the solid stays closed.
"""
from types import SimpleNamespace
from typing import NamedTuple

import FreeCAD as App
import numpy as np
import Part

from ..geometry.nurbs import direct_push as dp
from ..geometry.errors import DeformError
from ..shapes import bspline
from .base import DeformFeature, Prop


def pairs(vectors, prop):
    v = [np.array(tuple(x)) for x in vectors]
    if len(v) % 2:
        raise DeformError(f"{prop} holds pairs of vectors; it has an odd count.", prop)
    return list(zip(v[0::2], v[1::2]))


INPUTS = ("Element", "Points", "Targets", "Range", "Fixed", "Straight", "Angles")


class State(NamedTuple):
    """The element in numpy after its constraints (`start`) and its pushes (`current`):
    what the feature builds its result from and what the task panel drags."""
    kind: str          # "Edge" or "Face"
    original: object   # the Base's element as a Curve / Surface: constraints are given on it
    start: object      # after the constraints
    current: object    # after the constraints and every push
    size: int          # poles a push may move (per direction)
    fixed: list        # Fixed as parameters: t, or (u, v)
    spans: list        # Straight as parameter pairs
    corners: list      # the corner parameters of Angles (edges)
    held: list         # the poles an angle holds (faces)
    params: list       # where each push grabbed the element (as the pushes before left it)
    points: list       # the point there
    note: str          # how the element became a B-spline
    tol: float         # how far a point may be from the element
    surface: object = None    # the Part surface `original` came from (a fast rebuild)
    trim: object = None       # a trimmed face: the face whose pcurves bound the result
    boundary: object = None   # a trimmed face of a solid or shell: its pcurves' (u, v)
                              # points; the poles that move them stay


def inputs_of(obj):
    """The properties a replay reads, and the Base's shape."""
    inputs = {name: getattr(obj, name) for name in INPUTS}
    inputs["Shape"] = obj.Base.Shape
    return inputs


def point_at(arrays, at):
    if isinstance(arrays, dp.Curve):
        return dp.evaluate(arrays, at)
    return dp.surface_row(arrays, *at) @ arrays.poles.reshape(-1, 3)


def _check_angle(degrees, before, after):
    if not (0 < degrees < 180 and before > 0 and after > 0):
        raise DeformError("An angle is between 0 and 180 degrees and its legs are longer "
                          "than 0; change Angles.", "Angles")


def _on(distance, tol, what, name):
    if distance > tol:
        raise DeformError(f"{what} is not on {name} ({distance:.3g} mm away); pick a point "
                          "on it.", what.split("[")[0])


def _edge_start(shape, inputs, tol):
    name = inputs["Element"]
    curve, note = bspline.curve_of(bspline.edge_of(shape, name)[1])
    c = original = bspline.curve_arrays(curve)
    p = c.degree

    def param(x, what):
        t, d = dp.closest_parameter(original, np.array(tuple(x)))
        _on(d, tol, what, name)
        return t
    fixed = [param(x, f"Fixed[{i}]") for i, x in enumerate(inputs["Fixed"])]
    spans = [tuple(sorted((param(a, f"Straight[{2 * i}]"), param(b, f"Straight[{2 * i + 1}]"))))
             for i, (a, b) in enumerate(pairs(inputs["Straight"], "Straight"))]
    corners = [(param(x, f"Angles[{2 * i}]"), x, spec)
               for i, (x, spec) in enumerate(pairs(inputs["Angles"], "Angles"))]
    for t in fixed:
        c = dp.curve_with_knot(c, t, p)
    for a, b in spans:
        c, _ = dp.make_straight(c, a, b)
    for t, x, (degrees, before, after) in corners:
        _check_angle(degrees, before, after)
        c, _ = dp.make_angle(c, t, np.radians(degrees), (before, after), x)
    size = _size(inputs["Range"], p, len(c.poles) - 2)
    return State("Edge", original, c, c, size, fixed, spans, [t for t, _, _ in corners], [],
                 [], [], note, tol)


def _size(value, degree, interior):
    """Poles a push may move (per direction): Range + 1 (Range 0: degree + 2), at most
    what the element has (dp.range_bound): a larger Range moves all of them."""
    if value < 0:
        raise DeformError(f"Range {value} is negative; give 0 (degree + 1) or more.", "Range")
    return min((value if value > 0 else degree + 1) + 1, dp.range_bound(interior, degree))


def _planar_few_edges(face):
    return face.Surface.TypeId == "Part::GeomPlane" and len(face.Wires) == 1 and \
        len(face.Edges) <= 4


_ELEMENTS = {}   # a few recent faces: (face, what _element made of it); see _element


def _element(shape, face):
    """(arrays, note, Part surface or None, trimmed face or None, boundary (u, v) or None)
    of a face: its patch, its surface as arrays, and for a trimmed face of a solid or
    shell its pcurves' points. Kept for the last few faces (the entry holds the face, so
    its hash stays its own): a replay on a 100k-pole terrain face then costs no copy of
    its poles."""
    key = (face.hashCode(), face.Orientation, bspline.owner_of(shape, face)[0] is not None)
    if key in _ELEMENTS:
        return _ELEMENTS[key][1]
    corners = bspline.quad_corners(face)
    surface = trim = boundary = None
    if corners is not None:
        s, note = dp.bezier_patch(corners), "planar four-sided face: exact bicubic Bezier patch (Pratt)"
    elif bspline.natural(face):
        surface, note = bspline.smoothed(face) or \
            bspline.bspline_of(face, "Element", checked=True)
    elif _planar_few_edges(face):
        s, note = bspline.coons_of(face, "Element")
    else:
        smooth = bspline.smoothed(face)
        surface, trim, note = (*smooth[:1], face, smooth[1] + ", trimmed: rebuilt on its "
                               "boundary's pcurves") if smooth else \
            bspline.trimmed_surface(face, "Element")
        if key[2]:
            boundary = bspline.boundary_uv(trim, surface, "Element")
    if surface is not None:
        note += bspline.no_straight_directions(surface)
        s = bspline.surface_arrays(surface)
    for array in s[:4]:
        array.flags.writeable = False
    if len(_ELEMENTS) >= 4:
        _ELEMENTS.pop(next(iter(_ELEMENTS)))
    _ELEMENTS[key] = (face, (s, note, surface, trim, boundary))
    return s, note, surface, trim, boundary


def _face_start(shape, inputs, tol):
    name = inputs["Element"]
    face = bspline.face_of(shape, name, "Element")[1]
    s, note, surface, trim, boundary = _element(shape, face)
    original = s

    def uv(x, what):
        u, v, d = dp.closest_uv(original, np.array(tuple(x)))
        _on(d, tol, what, name)
        return u, v
    fixed = [uv(x, f"Fixed[{i}]") for i, x in enumerate(inputs["Fixed"])]
    spans = [(uv(a, f"Straight[{2 * i}]"), uv(b, f"Straight[{2 * i + 1}]"))
             for i, (a, b) in enumerate(pairs(inputs["Straight"], "Straight"))]
    for a, b in spans:
        s, _ = dp.make_straight_surface(s, a, b)
    held = []
    for i, (x, (degrees, before, after)) in enumerate(pairs(inputs["Angles"], "Angles")):
        _check_angle(degrees, before, after)
        s, held = dp.make_angle_surface(s, uv(x, f"Angles[{2 * i}]"), np.radians(degrees),
                                        (before, after), np.array(tuple(x)))
    size = _size(inputs["Range"], max(s.udegree, s.vdegree), max(s.weights.shape) - 2)
    return State("Face", original, s, s, size, fixed, spans, [], held, [], [], note, tol,
                 surface, trim, boundary)


def where(state, current, x, what="Points", name="the element"):
    """Where the point x grabs `current`: its parameter there, or on the Base's element
    when the constraints reshaped it (a point given before them)."""
    x = np.array(tuple(x))
    if state.kind == "Edge":
        t, d = dp.closest_parameter(current, x)
        if d > state.tol:
            t, d = dp.closest_parameter(state.original, x)
        at = t
    else:
        u, v, d = dp.closest_uv(current, x)
        if d > state.tol:
            u, v, d = dp.closest_uv(state.original, x)
        at = (u, v)
    _on(d, state.tol, what, name)
    if state.kind == "Face" and state.trim is not None and not state.trim.isPartOfDomain(*at):
        raise DeformError(f"{what} is on the surface of {name} but outside the face (beyond "
                          "its trimmed boundary); pick a point on the face.", "Points")
    return at


class Grab:
    """`arrays` (the element under the state's constraints) grabbed at parameter `at`: the
    point there, a face's unit normal there, and pushed(target): the element with that
    point moved exactly to the target."""

    def __init__(self, state, arrays, at):
        self.state, self.at, self.normal = state, at, None
        if state.kind == "Edge":
            arrays = dp.refine_curve(arrays, at, state.size)
            p = arrays.degree
            self.held = [k + j for t in state.fixed for k in [dp.pole_at(arrays, t)]
                         for j in (-1, 0, 1)]
            self.held += [k + j for t in state.corners for k in [dp.pole_at(arrays, t)]
                          for j in range(-p, p + 1)]
            self.groups = [dp.straight_poles(arrays, a, b) for a, b in state.spans]
        else:
            if min(arrays.weights.shape) < 3:  # no interior pole in one direction (a cylinder)
                arrays = dp.refine_surface(arrays, *at, 1)
            self.held = state.held
            if state.boundary is not None:
                arrays, self.held = self._inside(state, arrays, at)
            self.groups = [dp.straight_group(arrays, a, b) for a, b in state.spans]
            poles = arrays.poles.reshape(-1, 3)
            normal = np.cross(dp.surface_row(arrays, *at, 1, 0) @ poles,
                              dp.surface_row(arrays, *at, 0, 1) @ poles)
            if np.linalg.norm(normal) > 0:
                self.normal = normal / np.linalg.norm(normal)
        self.arrays = arrays
        self.point = point_at(arrays, at)

    @staticmethod
    def _inside(state, arrays, at, tries=10, share=0.5):
        """(arrays, held): the poles that move the trimmed boundary of a face of a solid
        held (the analogue of border poles), knots inserted next to the point (the paper's
        note a) until the poles free to move carry `share` of the point's basis (fewer
        would move far to carry the point)."""
        for _ in range(tries):
            held = set(state.held) | dp.influencing(arrays, state.boundary)
            nu, nv = arrays.weights.shape
            row = dp.surface_row(arrays, *at)
            free = sum(row[k] for k in np.nonzero(row)[0] if k not in held and
                       0 < k // nv < nu - 1 and 0 < k % nv < nv - 1)
            if free >= share or state.held:
                break
            arrays = dp.refine_at(arrays, *at)
        return arrays, sorted(held)

    def pushed(self, target):
        target = np.asarray(target, float)
        try:
            if self.state.kind == "Edge":
                return dp.push_curve(self.arrays, self.at, target, self.state.size, self.held,
                                     self.groups, dp.is_closed(self.state.original,
                                                               self.state.tol))
            return dp.push_surface(self.arrays, *self.at, target, self.state.size,
                                   self.state.fixed, self.groups, self.held)
        except DeformError as e:
            if "contradict" not in str(e):
                raise
            raise self._contradiction(e) from None

    def _contradiction(self, error):
        """The contradiction named by what holds the poles the point depends on: an end of
        the edge (Points), a Fixed point, a Straight span or an Angle; else too few poles
        in Range."""
        state, a = self.state, self.arrays
        if state.kind == "Edge":
            support = set(np.nonzero(dp.curve_row(a, self.at))[0].tolist())
            fixed = [{dp.pole_at(a, t) + j for j in (-1, 0, 1)} for t in state.fixed]
            p = a.degree
            angles = [{dp.pole_at(a, t) + j for j in range(-p, p + 1)} for t in state.corners]
            if support <= {0, len(a.poles) - 1}:
                return DeformError("The point is an end of the edge, and the ends of an open "
                                   "edge never move (its neighbours hold them); pick Points "
                                   "inside the edge.", "Points")
        else:
            support = dp.influencing(a, [self.at])
            fixed = [dp.influencing(a, [uv]) for uv in state.fixed]
            angles = [set(state.held)]
        for name, sets in (("Fixed", fixed), ("Angles", angles),
                           ("Straight", [set(g) for g in self.groups])):
            hit = [i for i, x in enumerate(sets) if x & support]
            if hit:
                entry = f"{name}[{hit[0]}]" if name == "Fixed" else name
                return DeformError(f"The push and {entry} contradict each other: the point "
                                   f"is on (or next to) what {name} holds in place; push "
                                   f"farther from it or change {name}.", name)
        return DeformError(f"{error} ".split(";")[0] + "; raise Range.", "Range")


def replay(inputs, params=None):
    """The State after the constraints and every push, as the result shows it; with
    `params`, push i grabs the element at params[i] instead of at Points[i]."""
    shape = inputs["Shape"]
    tol = 1e-6 * max(1.0, shape.BoundBox.DiagonalLength) + 1e-7
    start = _face_start if str(inputs["Element"]).startswith("Face") else _edge_start
    state = start(shape, inputs, tol)
    current = state.start
    for i, target in enumerate(inputs["Targets"]):
        at = params[i] if params is not None else where(
            state, current, inputs["Points"][i], f"Points[{i}]", inputs["Element"])
        grab = Grab(state, current, at)
        state.params.append(at)
        state.points.append(grab.point)
        try:
            current = grab.pushed(np.array(tuple(target)))
        except DeformError as e:
            raise DeformError(f"Points[{i}]: {e}", e.prop) from None
    return state._replace(current=current)


def _moves(before, after):
    """The largest pole move (knots inserted since are inserted into `before` too, so the
    poles compare one to one), or nan when they cannot be."""
    if before.poles.shape != after.poles.shape:
        before = dp.with_knots_of(before, after)
        if before is None or before.poles.shape != after.poles.shape:
            return float("nan")
    return float(np.linalg.norm((after.poles - before.poles).reshape(-1, 3), axis=1).max()) \
        if after.poles.size else 0.0


def _moved_region(before, after):
    """(u0, u1, v0, v1): the parameter rectangle where the surface `after` differs from
    `before` (the supports of the poles that moved), or None when none moved."""
    if before.poles.shape != after.poles.shape:
        before = dp.with_knots_of(before, after)
        if before is None or before.poles.shape != after.poles.shape:
            return (after.uknots[after.udegree], after.uknots[-after.udegree - 1],
                    after.vknots[after.vdegree], after.vknots[-after.vdegree - 1])
    i, j = np.nonzero(np.any(after.poles != before.poles, axis=2))
    if not len(i):
        return None
    (p, U), (q, W) = (after.udegree, after.uknots), (after.vdegree, after.vknots)
    # pole k's basis is nonzero on [U[k], U[k + p + 1]], within [U[p], U[n]]
    return (float(U[max(i.min(), p)]), float(U[min(i.max() + p + 1, len(U) - p - 1)]),
            float(W[max(j.min(), q)]), float(W[min(j.max() + q + 1, len(W) - q - 1)]))


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

    def compute(self, obj, kind):
        if kind != "Part":
            raise DeformError("Base must be a shape with B-spline (or convertible) edges or "
                              "faces.", "Base")
        if len(obj.Points) != len(obj.Targets):
            raise DeformError(f"Points has {len(obj.Points)} entries and Targets "
                              f"{len(obj.Targets)}; give one target per point.", "Targets")
        inputs = inputs_of(obj)
        state, result = self._build(obj, inputs)
        moves = _moves(state.start, state.current)
        outputs = {"MaxPoleMove": moves, "PoleCount": int(len(state.current.weights.ravel())),
                   "Conversion": state.note, "RangeUsed": state.size - 1}
        if state.kind == "Face" and len(obj.Targets) and self._cuts(obj, state, result):
            raise self._unreachable(obj, inputs)
        self._landed(obj, state, result)
        return result, outputs

    @staticmethod
    def _landed(obj, state, result):
        """The last target is on the result's element (OCCT rebuilt what was solved; an
        earlier push's point may move with the later pushes)."""
        if not len(obj.Targets):
            return
        element = result if state.kind == "Edge" or result.ShapeType == "Face" else \
            result.Faces[bspline.face_of(obj.Base.Shape, obj.Element, "Element")[0]]
        for i, t in list(enumerate(obj.Targets))[-1:]:
            miss = element.distToShape(Part.Vertex(t))[0]
            if miss > 10 * state.tol:
                raise DeformError(f"Targets[{i}]: the pushed {obj.Element} as OCCT builds it "
                                  f"misses this target by {miss:.3g} mm (a push this far "
                                  f"is beyond what the element can take); move Targets[{i}] "
                                  "nearer to its point.",
                                  "Targets")

    def _build(self, obj, inputs):
        """(state, shape): the pushes of `inputs` replayed and the result built."""
        state = replay(inputs)
        try:
            if state.kind == "Edge":
                return state, bspline.curve_from_arrays(state.current).toShape()
            view = SimpleNamespace(Base=obj.Base, Element=obj.Element, Blend=obj.Blend,
                                   Targets=inputs["Targets"])
            return state, self._face(view, state)
        except Part.OCCError:   # OCCT refused the new curve or face
            raise DeformError(f"OCCT could not build the pushed {obj.Element}; move the "
                              "Targets nearer to their Points.", "Targets") from None

    @staticmethod
    def _cuts(obj, state, result):
        """The pushed face of a solid or shell crosses another face of the result."""
        shape = obj.Base.Shape
        index = bspline.face_of(shape, obj.Element, "Element")[0]
        if bspline.owner_of(shape, shape.Faces[index])[0] is None:
            return False
        region = _moved_region(state.start, state.current)
        return region is not None and bspline.cuts_others(result, index, 10 * state.tol,
                                                          region)

    def _unreachable(self, obj, inputs, steps=7):
        """The refusal of a push that makes the solid cut itself, with how far along the
        last push the point can go (bisection on its length, to 1/2^steps of it)."""
        k = len(inputs["Targets"]) - 1
        p, t = np.array(tuple(inputs["Points"][k])), np.array(tuple(inputs["Targets"][k]))
        length = float(np.linalg.norm(t - p))
        lo, hi = 0.0, 1.0
        for _ in range(steps):
            mid = 0.5 * (lo + hi)
            trial = dict(inputs, Targets=list(inputs["Targets"][:k]) +
                         [App.Vector(*(p + mid * (t - p)))])
            try:
                state, result = self._build(obj, trial)
                bad = self._cuts(obj, state, result)
            except DeformError:
                bad = True
            lo, hi = (lo, mid) if bad else (mid, hi)
        return DeformError(f"Targets[{k}]: pushed that far, {obj.Element} cuts through other "
                           "faces of its solid (the result would intersect itself); along "
                           f"this push the point can go about {lo * length:.3g} mm of the "
                           f"{length:.3g} mm asked: set Targets[{k}] nearer to Points[{k}].",
                           "Targets")

    def _face(self, obj, state):
        """The Base with the pushed face in place of the element (alone when the Base is
        the face). A face of a solid or shell keeps its edges, shared with its neighbours
        (the border and boundary poles did not move), so the solid stays closed; a Blend
        rounds edges and the faces are sewn again. Everything else in the Base stays."""
        shape = obj.Base.Shape
        face = bspline.face_of(shape, obj.Element, "Element")[1]
        if state.surface is not None:
            surface = bspline.moved(state.surface, state.original, state.current)
        else:
            surface = bspline.surface_from_arrays(state.current)
        owner, index = bspline.owner_of(shape, face)
        if owner is None:
            if len(obj.Blend):
                raise DeformError("Blend needs a face of a solid or shell; empty Blend or pick "
                                  "such a face in Element.", "Blend")
            new = self._rebuilt(obj, state, surface)
            return new if shape.ShapeType == "Face" else shape.replaceShape([(face, new)])
        if not obj.Blend:
            result = bspline.with_surface(owner, index, surface)
            exact = Part.Face(surface) if state.trim is None else \
                bspline.face_on(surface, state.trim, "Element")
            if exact is not None and (result is None or abs(
                    result.Faces[index].Area - exact.Area) > 1e-9 * exact.Area):
                # OCCT's projected pcurves moved the boundary in (u, v): sew the face
                # rebuilt on its own pcurves instead, if that leaves the others as they were
                sewn = bspline.replaced(owner, index, exact)
                if sewn is not None and bspline.same_faces(owner, sewn, skip=index):
                    result = sewn
        else:
            result = self._blended(obj, state, owner, index)
        if result is None:
            raise DeformError(f"{obj.Element} could not be joined to its neighbours again "
                              "after the push; move the Targets nearer to their Points.",
                              "Targets")
        bspline.settle_tolerances(result.Faces[index])   # result is built on copies
        return result if owner.isSame(shape) else shape.replaceShape([(owner, result)])

    def _blended(self, obj, state, owner, index):
        patches, inner = {index: state.current}, set()
        for name in obj.Blend:
            inner |= self._blend(owner, patches, name, state.tol).get(index, set())
        if state.params:
            landed = [(u, v, np.array(tuple(t))) for (u, v), t in zip(state.params, obj.Targets)]
            patches[index] = self._reland(patches[index], landed, inner)
        return bspline.replaced_all(owner, {i: Part.Face(bspline.surface_from_arrays(p))
                                            for i, p in patches.items()})

    @staticmethod
    def _rebuilt(obj, state, surface):
        """The pushed face on its own: the new surface within its range, or, trimmed, with
        its boundary laid on the new surface through the pcurves."""
        if state.trim is None:
            return Part.Face(surface)
        face = bspline.face_on(surface, state.trim, "Element")
        if face is None:
            raise DeformError(f"{obj.Element}: its trimmed boundary could not be laid on "
                              "the pushed surface; move the Targets nearer to their "
                              "Points.", "Targets")
        return face

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
