"""DirectPush (Yamashita & Fukui's DDM; Pratt for faces of solids): grab points of a
B-spline edge or face and push them where they must go, in order, from the Base's shape;
poles and knots follow.

curve(shape, element, ...) and face(shape, element, ...) give (result shape, outputs);
replay(inputs) gives the element in numpy after its constraints and pushes (what the task
panel drags). `inputs` holds the feature's property values by name (INPUTS) and "Shape".
A face becomes a B-spline patch (a planar four-sided face: its exact bicubic Bezier form)
whose border poles never move; a trimmed face keeps its boundary in parameter space
(rebuilt on its pcurves), and in a solid or shell also the poles that move that boundary
stay, so the face goes back with its own edges and the solid stays closed.
"""
import FreeCAD as App
import numpy as np
import Part

from ..geometry.errors import DeformError
from ..geometry.nurbs import direct_push as dp
from ..geometry.nurbs import push
from ..shapes import brep, bspline

INPUTS = ("Element", "Points", "Targets", "Range", "Fixed", "Straight", "Angles")


def inputs_for(shape, element, points=(), targets=(), range=0, fixed=(), straight=(),
           angles=()):
    """The inputs of a replay, by property name."""
    return {"Shape": shape, "Element": str(element), "Points": list(points),
            "Targets": list(targets), "Range": int(range), "Fixed": list(fixed),
            "Straight": list(straight), "Angles": list(angles)}


def curve(shape, element, points=(), targets=(), range=0, fixed=(), straight=(), angles=()):
    """(the pushed edge, outputs): Points[i] of edge `element` of `shape` goes to
    targets[i], in order; fixed, straight (pairs) and angles (pairs: corner, (degrees,
    leg before, leg after)) are points on the edge of `shape`; range is the paper's m."""
    return _pushed(inputs_for(shape, element, points, targets, range, fixed, straight, angles))


def face(shape, element, points=(), targets=(), range=0, fixed=(), straight=(), angles=(),
         blend=()):
    """(shape with the pushed face, outputs): as curve() for face `element`; blend: edges
    of its solid rounded the way Pratt proposes (C1)."""
    return _pushed(inputs_for(shape, element, points, targets, range, fixed, straight, angles),
                   list(blend))


def _pushed(inputs, blend=()):
    if len(inputs["Points"]) != len(inputs["Targets"]):
        raise DeformError(f"Points has {len(inputs['Points'])} entries and Targets "
                          f"{len(inputs['Targets'])}; give one target per point.", "Targets")
    state, result = _build(inputs, blend)
    outputs = {"MaxPoleMove": push.max_pole_move(state.start, state.current),
               "PoleCount": int(len(state.current.weights.ravel())),
               "Conversion": state.note, "RangeUsed": state.size - 1}
    if state.shape_type == "Face" and len(inputs["Targets"]):
        if _cuts(inputs, state, result):
            raise _unreachable(inputs, blend)
        wrong = _folds(inputs, result)
        if wrong:
            raise _unreachable(inputs, blend, f"fails OCCT's check: the pushed face {wrong}")
    _landed(inputs, state, result)
    return result, outputs


def tolerance(shape):
    """How far a point may be from the element: 1e-6 of the shape's size (at least 1 mm)."""
    return 1e-6 * max(1.0, shape.BoundBox.DiagonalLength) + 1e-7


def start(inputs):
    """The State of the element of inputs["Shape"] under its constraints, before a push."""
    shape, name = inputs["Shape"], inputs["Element"]
    tol = tolerance(shape)
    constraints = {k.lower(): inputs[k] for k in ("Fixed", "Straight", "Angles", "Range")}
    if not str(name).startswith("Face"):
        curve_, note = bspline.curve_of(bspline.edge_of(shape, name)[1])
        return push.curve_state(bspline.curve_arrays(curve_), tol=tol, note=note, name=name,
                                **constraints)
    element = bspline.face_of(shape, name, "Element")[1]
    s, note, surface, trim, boundary = face_element(shape, element)
    return push.surface_state(s, tol=tol, note=note, name=name, surface=surface, trim=trim,
                              boundary=boundary, **constraints)


def where(state, current, x, what="Points", name="the element"):
    """Where the point x grabs `current`: its parameter there, or on the Base's element
    when the constraints reshaped it (a point given before them)."""
    x = np.array(tuple(x), float)
    if state.shape_type == "Edge":
        t, d = dp.closest_parameter(current, x)
        if d > state.tol:
            t, d = dp.closest_parameter(state.original, x)
        at = t
    else:
        u, v, d = dp.closest_uv(current, x)
        if d > state.tol:
            u, v, d = dp.closest_uv(state.original, x)
        at = (u, v)
    push.check_on(d, state.tol, what, name)
    if state.shape_type == "Face" and state.trim is not None and \
            not state.trim.isPartOfDomain(*at):
        raise DeformError(f"{what} is on the surface of {name} but outside the face (beyond "
                          "its trimmed boundary); pick a point on the face.", "Points")
    return at


def replay(inputs, params=None):
    """The State after the constraints and every push, as the result shows it; with
    `params`, push i grabs the element at params[i] instead of at Points[i]."""
    state = start(inputs)
    name = inputs["Element"]

    def grab_at(i, current):
        if params is not None:
            return params[i]
        return where(state, current, inputs["Points"][i], f"Points[{i}]", name)
    return push.replay(state, inputs["Targets"], grab_at)


def _planar_few_edges(face):
    return face.Surface.TypeId == "Part::GeomPlane" and len(face.Wires) == 1 and \
        len(face.Edges) <= 4


_ELEMENTS = {}   # a few recent faces: (face, what face_element made of it)


def face_element(shape, face):
    """(arrays, note, Part surface or None, trimmed face or None, boundary (u, v) or None)
    of a face of `shape`: its patch, its surface as arrays, and for a trimmed face of a
    solid or shell its pcurves' points. Kept for the last few faces (the entry holds the
    face, so its hash stays its own): a replay on a 100k-pole terrain face then costs no
    copy of its poles."""
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


def _landed(inputs, state, result):
    """The last target is on the result's element (OCCT rebuilt what was solved; an
    earlier push's point may move with the later pushes)."""
    targets, name = inputs["Targets"], inputs["Element"]
    if not len(targets):
        return
    element = result if state.shape_type == "Edge" or result.ShapeType == "Face" else \
        result.Faces[bspline.face_of(inputs["Shape"], name, "Element")[0]]
    i = len(targets) - 1
    miss = element.distToShape(Part.Vertex(App.Vector(*tuple(targets[i]))))[0]
    if miss > 10 * state.tol:
        raise DeformError(f"Targets[{i}]: the pushed {name} as OCCT builds it misses this "
                          f"target by {miss:.3g} mm (a push this far is beyond what the "
                          f"element can take); move Targets[{i}] nearer to its point.",
                          "Targets")


def _build(inputs, blend):
    """(state, shape): the pushes of `inputs` replayed and the result built."""
    state = replay(inputs)
    try:
        if state.shape_type == "Edge":
            return state, bspline.curve_from_arrays(state.current).toShape()
        return state, _face(inputs, state, blend)
    except Part.OCCError:   # OCCT refused the new curve or face
        raise DeformError(f"OCCT could not build the pushed {inputs['Element']}; move the "
                          "Targets nearer to their Points.", "Targets") from None


def _cuts(inputs, state, result, estimate=False):
    """The pushed face of a solid or shell crosses another face of the result (estimate:
    see bspline.cuts_others)."""
    shape = inputs["Shape"]
    index = bspline.face_of(shape, inputs["Element"], "Element")[0]
    if bspline.owner_of(shape, shape.Faces[index])[0] is None:
        return False
    region = push.moved_region(state.start, state.current)
    return region is not None and bspline.cuts_others(result, index, 10 * state.tol, region,
                                                       estimate)


def _folds(inputs, result):
    """What OCCT's BOP check finds wrong with the pushed face and not with the Base's:
    "intersects itself" (SelfIntersect: bulged past its own boundary) or "leaves its
    edges" (InvalidCurveOnSurface); None when nothing. A crease the constraints put in
    (GeomAbs_C0) is not wrong. The Base's findings are kept per face. Faces of more than
    CHECKED_POLES poles are not checked: the check grows with the face, not with the push
    (13 s on the 312 x 323-pole terrain, 0.1 to 0.5 s on faces of a few hundred), and a
    region patch alone misses the folds (they meet the face's own edges)."""
    index, old = bspline.face_of(inputs["Shape"], inputs["Element"], "Element")
    new = result if result.ShapeType == "Face" else result.Faces[index]
    if new.Surface.NbUPoles * new.Surface.NbVPoles > CHECKED_POLES:
        return None
    key = old.hashCode()
    if key not in _CHECKED:
        if len(_CHECKED) >= 8:
            _CHECKED.pop(next(iter(_CHECKED)))
        _CHECKED[key] = (old, brep.bop_errors(old))   # (held: its hash stays its own)
    found = brep.bop_errors(new) - _CHECKED[key][1]
    reasons = [why for kind, why in (("SelfIntersect", "intersects itself"),
                                     ("InvalidCurveOnSurface", "leaves its edges"))
               if kind in found]
    return " and ".join(reasons) or None


_CHECKED = {}   # a few recent faces of Bases: (face, what OCCT's BOP check finds)
CHECKED_POLES = 20000


def _unreachable(inputs, blend, why=None, steps=7):
    """The refusal of a push that makes the solid cut itself, or the face fail OCCT's
    check (`why`, see _folds), with how far along the last push the point can go
    (bisection on its length, to 1/2^steps of it; each step's cut found by the faster
    estimate: it only sets the length the message gives)."""
    k = len(inputs["Targets"]) - 1
    p = np.array(tuple(inputs["Points"][k]), float)
    t = np.array(tuple(inputs["Targets"][k]), float)
    length = float(np.linalg.norm(t - p))
    lo, hi = 0.0, 1.0
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        trial = dict(inputs, Targets=list(inputs["Targets"][:k]) +
                     [App.Vector(*(p + mid * (t - p)))])
        try:
            state, result = _build(trial, blend)
            bad = _cuts(trial, state, result, True) or why is not None and _folds(trial, result)
        except DeformError:
            bad = True
        lo, hi = (lo, mid) if bad else (mid, hi)
    name = inputs["Element"]
    why = why or "cuts through other faces of its solid (the result would intersect itself)"
    return DeformError(f"Targets[{k}]: pushed that far, {name} {why}; along this push the "
                       f"point can go about {lo * length:.3g} mm of the {length:.3g} mm "
                       f"asked: set Targets[{k}] nearer to Points[{k}].", "Targets")


def _face(inputs, state, blend):
    """The shape with the pushed face in place of the element (alone when the shape is
    the face). A face of a solid or shell keeps its edges, shared with its neighbours
    (the border and boundary poles did not move), so the solid stays closed; a blend
    rounds edges and the faces are sewn again. Everything else in the shape stays."""
    shape, name = inputs["Shape"], inputs["Element"]
    face = bspline.face_of(shape, name, "Element")[1]
    if state.surface is not None:
        surface = bspline.moved(state.surface, state.original, state.current)
    else:
        surface = bspline.surface_from_arrays(state.current)
    owner, index = bspline.owner_of(shape, face)
    if owner is None:
        if len(blend):
            raise DeformError("Blend needs a face of a solid or shell; empty Blend or pick "
                              "such a face in Element.", "Blend")
        new = _rebuilt(name, state, surface)
        return new if shape.ShapeType == "Face" else shape.replaceShape([(face, new)])
    if not blend:
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
        result = _blended(inputs["Targets"], state, owner, index, blend)
    if result is None:
        raise DeformError(f"{name} could not be joined to its neighbours again after the "
                          "push; move the Targets nearer to their Points.", "Targets")
    bspline.settle_tolerances(result.Faces[index])   # result is built on copies
    result = brep.settled(result, {v.hashCode() for v in result.Faces[index].Vertexes})
    return result if owner.isSame(shape) else shape.replaceShape([(owner, result)])


def _blended(targets, state, owner, index, blend):
    patches, inner = {index: state.current}, set()
    for name in blend:
        inner |= _blend(owner, patches, name, state.tol).get(index, set())
    if state.params:
        landed = [(u, v, np.array(tuple(t), float)) for (u, v), t in zip(state.params, targets)]
        patches[index] = push.reland(patches[index], landed, inner)
    return bspline.replaced_all(owner, {i: Part.Face(bspline.surface_from_arrays(p))
                                        for i, p in patches.items()})


def _rebuilt(name, state, surface):
    """The pushed face on its own: the new surface within its range, or, trimmed, with
    its boundary laid on the new surface through the pcurves."""
    if state.trim is None:
        return Part.Face(surface)
    face = bspline.face_on(surface, state.trim, "Element")
    if face is None:
        raise DeformError(f"{name}: its trimmed boundary could not be laid on the pushed "
                          "surface; move the Targets nearer to their Points.", "Targets")
    return face


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
    rows = [push.border_rows(patches[i], ends, tol, name) for i in faces]
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


def _patch(face, name):
    corners = bspline.quad_corners(face)
    if corners is None:
        raise DeformError(f"Blend {name}: its faces and the faces at its ends must be planar "
                          "and four-sided (they become Bezier patches).", "Blend")
    return dp.bezier_patch(corners)
