"""B-spline edges and faces as arrays and back: poles, weights, knots of a
Part.BSplineCurve / BSplineSurface, new ones from arrays, the exact Bezier form of a planar
four-sided face, and a face replaced in its shell or solid."""
import FreeCAD as App
import numpy as np
import Part
from scipy.optimize import linear_sum_assignment, minimize_scalar

from ..geometry.nurbs.bspline_area import Surface
from ..geometry.nurbs import direct_push as dp
from ..geometry.nurbs.direct_push import Curve
from ..geometry.errors import DeformError

# surface types NurbsConvert represents exactly (rational B-splines)
EXACT = {"Plane", "Cylinder", "Cone", "Sphere", "Toroid", "SurfaceOfRevolution",
         "SurfaceOfExtrusion", "BezierSurface", "BSplineSurface"}


def face_of(shape, name, prop="Face"):
    try:
        index = int(str(name).replace("Face", "")) - 1
        if index < 0:
            raise ValueError
        return index, shape.Faces[index]
    except (ValueError, IndexError):
        raise DeformError(f"{prop} {name!r} is not a face of the Base (Face1 to "
                          f"Face{len(shape.Faces)}).", prop)


def edge_of(shape, name, prop="Element"):
    try:
        index = int(str(name).replace("Edge", "")) - 1
        if index < 0 or not str(name).startswith("Edge"):
            raise ValueError
        return index, shape.Edges[index]
    except (ValueError, IndexError):
        raise DeformError(f"{prop} {name!r} is not an edge of the Base (Edge1 to "
                          f"Edge{len(shape.Edges)}).", prop)


def curve_of(edge, prop="Element"):
    """(BSplineCurve covering exactly the edge, note on the conversion)."""
    if edge.Degenerated:  # a point where a surface collapses: Edge.Curve raises TypeError
        raise DeformError(f"{prop} is a degenerated edge (a point where its face's surface "
                          "collapses); pick another edge.", prop)
    geom_type = edge.Curve.TypeId.split("::Geom")[-1]
    first, last = edge.FirstParameter, edge.LastParameter
    if geom_type == "BSplineCurve":
        curve, note = edge.Curve.copy(), "B-spline"
        a, b = curve.FirstParameter, curve.LastParameter
        if abs(a - first) > 1e-12 or abs(b - last) > 1e-12:
            curve.segment(first, last)
            note += ", cut to the edge"
    else:
        curve = edge.Curve.toBSpline(first, last)
        exact = geom_type in ("Line", "LineSegment", "Circle", "Ellipse", "BezierCurve",
                              "ArcOfCircle")
        note = f"{geom_type} converted exactly" if exact else \
            f"{geom_type} approximated (not exact)"
    if curve.isPeriodic():
        curve.setNotPeriodic()
    return curve, note


def curve_arrays(curve):
    poles = np.array([tuple(p) for p in curve.getPoles()], float)
    knots = np.repeat(curve.getKnots(), curve.getMultiplicities())
    return Curve(poles, np.array(curve.getWeights(), float), np.asarray(knots, float),
                 curve.Degree)


def curve_from_arrays(c):
    knots, mults = dp.knots_and_mults(c.knots)
    curve = Part.BSplineCurve()
    curve.buildFromPolesMultsKnots([App.Vector(*p) for p in c.poles.tolist()], mults, knots,
                                   False, c.degree, [float(w) for w in c.weights])
    return curve


def surface_from_arrays(s):
    uk, um = dp.knots_and_mults(s.uknots)
    vk, vm = dp.knots_and_mults(s.vknots)
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots([[App.Vector(*p) for p in row] for row in s.poles.tolist()],
                                     um, vm, uk, vk, False, False, s.udegree, s.vdegree,
                                     s.weights.tolist())
    return surface


def quad_corners(face):
    """The 4 corners of a planar face bounded by 4 straight edges, in order round the
    outer wire and turning with the face's normal; None for any other face."""
    if face.Surface.TypeId != "Part::GeomPlane" or len(face.Wires) != 1 or \
            len(face.Edges) != 4 or any(e.Degenerated or e.Curve.TypeId not in ("Part::GeomLine",
                                                                "Part::GeomLineSegment")
                                        for e in face.Edges):
        return None
    corners = [np.array(tuple(v.Point)) for v in face.OuterWire.OrderedVertexes]
    n = np.array(tuple(face.normalAt(*face.Surface.parameter(face.CenterOfMass))))
    if np.cross(corners[1] - corners[0], corners[3] - corners[0]) @ n < 0:
        corners = corners[::-1]
    return corners


def _note(geom_type):
    return "B-spline" if geom_type == "BSplineSurface" else (
        f"{geom_type} converted exactly" if geom_type in EXACT else
        f"{geom_type} approximated by NurbsConvert (not exact)")


def _surface_of(face):
    """(BSplineSurface over the face's parameter range, note on the conversion)."""
    geom_type = face.Surface.TypeId.split("::Geom")[-1]
    note = _note(geom_type)
    surface = face.Surface.copy() if geom_type == "BSplineSurface" else \
        face.toNurbs().Faces[0].Surface
    u0, u1, v0, v1 = face.ParameterRange
    for periodic, fix in ((surface.isUPeriodic, surface.setUNotPeriodic),
                          (surface.isVPeriodic, surface.setVNotPeriodic)):
        if periodic():
            fix()
    b = surface.bounds()
    if max(abs(u0 - b[0]), abs(u1 - b[1]), abs(v0 - b[2]), abs(v1 - b[3])) > 1e-9:
        surface.segment(u0, u1, v0, v1)
        note += ", cut to the face's parameter range"
    return surface, note


def trimmed(face):
    """Whether the face is less than its surface over its parameter range (holes, or a
    boundary that is not the range's; within 1e-3 of the area counts as the range's)."""
    return len(face.Wires) != 1 or \
        abs(Part.Face(_surface_of(face)[0]).Area - face.Area) > 1e-3 * face.Area


def pcurve_points(c2d, a, b, count):
    """`count` points of a 2D curve from a to b: discretize, or evenly in the parameter
    where FreeCAD 0.20 cannot discretize it (a whole Hyperbola2d: an 'Unknown C++
    exception'; a hexagonal nut's flats meet its chamfer cone in hyperbolas)."""
    try:
        return c2d.discretize(Number=count, First=a, Last=b)
    except App.Base.FreeCADError:
        return [c2d.value(t) for t in np.linspace(a, b, count)]


def natural(face):
    """Whether the face is exactly its surface over its parameter range: one wire whose
    pcurves all lie on the border of the range (a seam or a degenerated edge lies on it)."""
    if len(face.Wires) != 1:
        return False
    u0, u1, v0, v1 = face.ParameterRange
    tol = 1e-9 * max(1.0, abs(u0), abs(u1), abs(v0), abs(v1))
    for edge in face.Edges:
        found = face.curveOnSurface(edge)
        if found is None:
            return False
        c2d, a, b = found
        for p in pcurve_points(c2d, a, b, 16):
            if min(abs(p.x - u0), abs(p.x - u1), abs(p.y - v0), abs(p.y - v1)) > tol:
                return False
    return True


def smoothed(face):
    """(C2 B-spline, note) approximating the face's own surface over its parameter range,
    in that surface's (u, v), so the face's pcurves still hold; None when its exact NURBS
    form has no C0 knot (only rational circles have: there a push would crease it, and
    OCCT's BOP check calls the result self-intersecting) or the fit is not within 1e-9 of
    the face's size."""
    geom_type = face.Surface.TypeId.split("::Geom")[-1]
    if geom_type in ("BSplineSurface", "BezierSurface"):
        return None
    exact = face.toNurbs().Faces[0].Surface
    if not any(m >= degree for mults, degree in ((exact.getUMultiplicities(), exact.UDegree),
                                                  (exact.getVMultiplicities(), exact.VDegree))
               for m in mults[1:-1]):
        return None
    u0, u1, v0, v1 = face.ParameterRange
    tol = 1e-9 * face.BoundBox.DiagonalLength
    try:
        fit = Part.RectangularTrimmedSurface(face.Surface, u0, u1, v0, v1).toBSpline(
            tol, "C2", "C2", 6, 6, 400)
    except Part.OCCError:
        return None
    U, V = np.linspace(u0, u1, 41), np.linspace(v0, v1, 41)
    err = max((fit.value(u, v) - face.Surface.value(u, v)).Length for u in U for v in V)
    if err > 10 * tol:
        return None
    return fit, (f"{geom_type} approximated by a C2 B-spline to {err:.1g} mm (its exact form "
                 "is C0 at knots, where a push would crease it)")


def bspline_of(face, prop="Face", checked=False):
    """(BSplineSurface covering exactly the face, note on the conversion).

    A non-B-spline face is converted (NurbsConvert: exact for planes, cylinders, cones,
    spheres, tori, revolved and extruded surfaces); the surface is cut to the face's
    parameter range; the face must not be trimmed by anything else (`checked`: the caller
    knows it is not: natural(face))."""
    if not checked and trimmed(face):
        raise DeformError(f"{prop} is trimmed (holes or a non-rectangular boundary); "
                          "the face must be bounded by its surface's parameter "
                          "range.", prop)
    return _surface_of(face)


def no_straight_directions(surface):
    """Raise the degree of `surface` (in place, exactly) from 1 to 3 where it is 1 (a plane,
    a cylinder's lines): a push there would crease it along the knot lines. The note to
    add, or "" when nothing was raised."""
    u, v = (3 if d == 1 else d for d in (surface.UDegree, surface.VDegree))
    if (u, v) == (surface.UDegree, surface.VDegree):
        return ""
    try:
        surface.increaseDegree(u, v)
    except (Part.OCCError, App.Base.FreeCADError):
        return ""    # kept as it is: creased, but exact
    return ", degree 1 raised to 3 (a push does not crease it)"


def surface_arrays(surface):
    """The Surface (numpy) of a Part.BSplineSurface."""
    poles = np.array([[tuple(p) for p in row] for row in surface.getPoles()], float)
    weights = np.array(surface.getWeights(), float)
    uk = np.repeat(surface.getUKnots(), surface.getUMultiplicities())
    vk = np.repeat(surface.getVKnots(), surface.getVMultiplicities())
    return Surface(poles, weights, np.asarray(uk, float), np.asarray(vk, float),
                   surface.UDegree, surface.VDegree)


def with_poles(surface, poles):
    """A copy of `surface` with its poles set to `poles` (nu, nv, 3), weights kept (the
    copy's own: setPole with a weight rechecks every weight, 2.8 ms a pole on a
    312 x 323-pole terrain, 6 minutes for all; without, 1 us)."""
    new = surface.copy()
    for i, row in enumerate(np.asarray(poles, float).tolist()):
        for j, p in enumerate(row):
            new.setPole(i + 1, j + 1, App.Vector(*p))
    return new


def owner_of(shape, face):
    """(the solid, else the shell of more than one face, that holds `face` in `shape`,
    the face's index in it), or (None, None) for a face on its own."""
    for owner in list(shape.Solids) + [s for s in shape.Shells if len(s.Faces) > 1]:
        for i, f in enumerate(owner.Faces):
            if f.isSame(face):
                return owner, i
    return None, None


def replaced(shape, index, face):
    """`shape` (one shell or one solid) with face `index` replaced by `face`, sewn; None
    when the shape is not a single shell or solid or the result is not valid."""
    return replaced_all(shape, {index: face})


def replaced_all(shape, faces_by_index):
    """replaced() for several faces at once: {index: new face}."""
    if len(shape.Solids) == 1:
        shape_type = "Solid"
    elif len(shape.Shells) == 1 and not shape.Solids:
        shape_type = "Shell"
    else:
        return None
    # a copy: sewing may take over (and retune) the Base's own edges
    faces = [faces_by_index.get(i, f) for i, f in enumerate(shape.copy().Faces)]
    try:
        shell = Part.Shell(faces)
        shell.sewShape()
        if not shell.Shells:  # Part.Solid of no shell throws past Python on FreeCAD 1.1
            return None
        shell = shell.Shells[0]
        sewn = shell.Faces
        if len(sewn) == len(faces):
            ordered = in_order(sewn, faces)
            if any(not a.isSame(b) for a, b in zip(ordered, sewn)):
                shell = Part.Shell(ordered)
        result = Part.Solid(shell) if shape_type == "Solid" else shell
    except Part.OCCError:  # the faces do not close up again (e.g. a seam that moved)
        return None
    if shape_type == "Solid":
        box = result.BoundBox
        far = App.Vector(box.XMax, box.YMax, box.ZMax) + App.Vector(1, 1, 1) * box.DiagonalLength
        if result.isInside(far, 1e-9, True):   # inside out: a negative volume
            result.reverse()
    return result if result.isValid() and len(result.Faces) == len(faces) else None


def same_faces(before, after, skip, rel=1e-9):
    """Whether every face but `skip` kept its type and area (to `rel`); faces that are
    the very same shape are not measured."""
    return len(before.Faces) == len(after.Faces) and all(
        a.isSame(b) or (a.Surface.TypeId == b.Surface.TypeId and
                        abs(a.Area - b.Area) <= rel * a.Area)
        for i, (a, b) in enumerate(zip(before.Faces, after.Faces)) if i != skip)


def in_order(sewn, faces):
    """The sewn faces in the order of `faces` (sewing may reorder them; FaceN must stay
    FaceN): the very same faces first, the rest matched by centre of mass and area."""
    by_hash = {}
    for j, f in enumerate(sewn):
        by_hash.setdefault(f.hashCode(), []).append(j)
    order, left = [None] * len(faces), []
    for i, f in enumerate(faces):
        j = next((j for j in by_hash.get(f.hashCode(), ()) if sewn[j].isSame(f)), None)
        if j is None:
            left.append(i)
        else:
            order[i] = j
            by_hash[f.hashCode()].remove(j)
    rest = sorted(set(range(len(sewn))) - {j for j in order if j is not None})
    if left:
        def key(fs):
            return np.array([tuple(f.CenterOfMass) + (f.Area,) for f in fs])
        a, b = key([faces[i] for i in left]), key([sewn[j] for j in rest])
        cost = np.linalg.norm(a[:, None, :3] - b[None, :, :3], axis=2) + \
            np.abs(a[:, None, 3] - b[None, :, 3])
        for r, c in zip(*linear_sum_assignment(cost)):
            order[left[r]] = rest[c]
    return [sewn[j] for j in order]


def _oriented_pieces(face):
    """The outer wire as 4 B-spline curves in order round it (fewer edges: the longest
    piece cut in two at its middle until there are 4); None with more than 4 edges."""
    pieces = []
    for edge in face.OuterWire.OrderedEdges:
        curve, _ = curve_of(edge)
        if edge.Orientation == "Reversed":
            curve.reverse()
        pieces.append(curve)
    if len(pieces) > 4:
        return None
    while len(pieces) < 4:
        k = max(range(len(pieces)), key=lambda i: pieces[i].length())
        a, b = pieces[k].FirstParameter, pieces[k].LastParameter
        halves = [pieces[k].copy(), pieces[k].copy()]
        halves[0].segment(a, (a + b) / 2)
        halves[1].segment((a + b) / 2, b)
        pieces[k:k + 1] = halves
    return pieces


def _on_unit_interval(curve, degree):
    """Curve arrays of a Part curve raised to `degree`, its knots scaled to [0, 1]."""
    curve = curve.copy()
    if curve.Degree < degree:
        curve.increaseDegree(degree)
    c = curve_arrays(curve)
    return c._replace(knots=(c.knots - c.knots[0]) / (c.knots[-1] - c.knots[0]))


def _pair(a, b, reverse_a, reverse_b):
    """Two opposite sides, reversed as asked, with the same degree and knots (each
    other's inserted)."""
    degree = max(a.Degree, b.Degree)
    x, y = _on_unit_interval(a, degree), _on_unit_interval(b, degree)
    x, y = (dp.reversed_curve(x) if reverse_a else x), (dp.reversed_curve(y) if reverse_b else y)
    return dp.compatible(x, y)


def coons_of(face, prop="Element"):
    """(Surface, note): a planar face bounded by one wire of 1 to 4 edges as the Coons
    patch of its boundary cut into four sides (Pratt: split the boundary, parametrise the
    face as a four-sided patch). Exact: the border is the boundary, the patch is plane."""
    pieces = _oriented_pieces(face) if face.Surface.TypeId == "Part::GeomPlane" and \
        len(face.Wires) == 1 else None
    if pieces is None:
        raise DeformError(f"{prop} is trimmed and is not a planar face bounded by 1 to 4 "
                          "edges; it has no exact patch over its boundary here.", prop)
    # round the wire: V0 -e0-> V1 -e1-> V2 -e2-> V3 -e3-> V0; the patch's corners
    # (0,0) V0, (1,0) V1, (1,1) V2, (0,1) V3
    c0, c1 = _pair(pieces[0], pieces[2], False, True)
    d0, d1 = _pair(pieces[3], pieces[1], True, False)
    if not (np.allclose(c0.weights, c1.weights) and np.allclose(d0.weights, d1.weights)):
        raise DeformError(f"{prop}: opposite sides of its boundary have different weights; "
                          "no exact patch.", prop)
    patch = dp.coons_patch(c0, c1, d0, d1)
    P = patch.poles.reshape(-1, 3)
    normal = np.cross(dp.surface_row(patch, 0.5, 0.5, 1, 0) @ P,
                      dp.surface_row(patch, 0.5, 0.5, 0, 1) @ P)
    centre = dp.surface_row(patch, 0.5, 0.5) @ P
    if normal @ np.array(tuple(face.normalAt(*face.Surface.parameter(App.Vector(*centre))))) < 0:
        patch = dp.coons_patch(d0, d1, c0, c1)
    return patch, (f"planar face with {len(face.Edges)} edge(s): exact Coons patch of its "
                   "boundary (Pratt)")


# --- trimmed faces: the boundary kept in parameter space ---------------------------------------

def trimmed_surface(face, prop="Element"):
    """(BSplineSurface, face, note) of a trimmed face: its surface as a B-spline in the
    face's own parametrisation (cut to the parameter range, not periodic), and the face
    (its NURBS form when it was converted) whose pcurves lie on that surface."""
    geom_type = face.Surface.TypeId.split("::Geom")[-1]
    if geom_type != "BSplineSurface":
        try:
            face = face.toNurbs().Faces[0]
        except Part.OCCError:
            raise DeformError(f"{prop}: its {geom_type} surface has no B-spline form here; "
                              "pick another face.", prop)
    try:
        surface, _ = _surface_of(face)
    except Part.OCCError:
        raise DeformError(f"{prop}: OCCT cannot cut its surface to the face's parameter "
                          "range; pick another face.", prop)
    return surface, face, _note(geom_type) + ", trimmed: rebuilt on its boundary's pcurves"


def _pcurve(face, edge, prop):
    found = face.curveOnSurface(edge)
    if found is None:
        raise DeformError(f"{prop}: an edge of its boundary has no curve in the face's "
                          "parameter space; the face cannot be rebuilt.", prop)
    return found


def boundary_uv(face, surface, prop="Element"):
    """Parameter points (k, 2) along every pcurve of the face (both of a seam), dense
    enough to meet every knot span they cross."""
    count = int(min(4000, 64 + 8 * (surface.NbUPoles + surface.NbVPoles)))
    points = []
    for edge in face.Edges:
        for e in (edge, edge.reversed()) if edge.isSeam(face) else (edge,):
            c2d, a, b = _pcurve(face, e, prop)
            points += [(p.x, p.y) for p in pcurve_points(c2d, a, b, count)]
    return np.array(points, float)


def face_on(surface, face, prop="Element"):
    """The face rebuilt on `surface` with the same boundary in parameter space: every edge
    made again from its pcurve on the new surface, so the face is trimmed the same way in
    (u, v) (None when OCCT cannot build it). An imported face's pcurves may meet only
    within its vertices' tolerance, about an edge shorter than that tolerance (9 of the 247
    B-spline faces of an IGES impeller, 0.02 mm): OCCT's wire maker then leaves the new
    edges open, or joins both ends of the short one into one vertex (an invalid face);
    ShapeFix joins them, or drops that edge, within the face's tolerance."""
    forward = face.reversed() if face.Orientation == "Reversed" else face
    outer = forward.OuterWire
    wires = [outer] + [w for w in forward.Wires if not w.isSame(outer)]
    try:
        built = []
        for wire in wires:
            edges, tol = [], 0.0
            for edge in wire.OrderedEdges:
                c2d, a, b = _pcurve(forward, edge, prop)
                new = c2d.toShape(surface, a, b)
                if edge.Orientation == "Reversed":
                    new.reverse()
                own = max([edge.Tolerance] + [v.Tolerance for v in edge.Vertexes])
                new.fixTolerance(own)
                tol = max(tol, own)
                edges.append(new)
            joined = Part.Wire(edges)
            if not joined.isClosed():
                joined.fixWire(Part.Face(surface), tol)
            built.append(joined)
        result = Part.Face(surface, built[0])
        for wire in built[1:]:
            result = Part.Face(result, wire)
        if not result.isValid():
            tol = max(v.Tolerance for v in face.Vertexes)
            result.fix(tol, tol, tol)
    except Part.OCCError:
        return None
    if face.Orientation == "Reversed":
        result.reverse()
    return result if result.ShapeType == "Face" and result.isValid() else None


def with_surface(shape, index, surface):
    """`shape` (a solid, cavities too, or a shell) with face `index` put on `surface`,
    which equals the old surface along the face's boundary: the face keeps its very edges
    (shared with its neighbours, so nothing is sewn), OCCT adds their pcurves on the new
    surface. None when the result is not valid with every shell of a solid closed."""
    copy = shape.copy()
    face = copy.Faces[index]
    forward = face.reversed() if face.Orientation == "Reversed" else face
    try:
        # a point of the boundary (it did not move) tells how the new surface turns
        edge = next((e for e in face.Edges if not e.Degenerated), None)
        if edge is None:
            return None
        point = edge.valueAt(0.5 * (edge.FirstParameter + edge.LastParameter))
        uv = surface.parameter(point)
        old_uv = face.Surface.parameter(point)
        flipped = surface.normal(*uv).dot(forward.normalAt(*old_uv)) < 0
        new = Part.Face(surface)
        new = new.removeShape(new.Wires)
        for wire in forward.Wires:
            new.addWire(wire.reversed() if flipped else wire)
        tolerance = max([1e-7] + [e.Tolerance for e in face.Edges])
        new.fix(1e-7, 1e-7, max(1e-3, 2 * tolerance))
        if new.normalAt(*uv).dot(face.normalAt(*old_uv)) < 0:
            new.reverse()
        if not 0 < new.Area <= Part.Face(surface).Area * (1 + 1e-6):
            return None   # the boundary did not bound the same region of the new surface
        result = copy.replaceShape([(face, new)])
    except Part.OCCError:
        return None
    if len(result.Faces) != len(shape.Faces) or len(result.Shells) != len(shape.Shells) or \
            not all(s.isClosed() for solid in result.Solids for s in solid.Shells):
        return None
    # only the new face and the faces that share its edges changed: check those (a Base
    # that OCCT finds invalid elsewhere can still be pushed)
    new = result.Faces[index]
    size = new.BoundBox.DiagonalLength
    if any(gap > max(2.0 * e.Tolerance, 1e-5 * size) for e, gap in pcurve_gaps(new)):
        return None
    changed = {f.hashCode(): f for e in new.Edges for f in result.ancestorsOfType(e, Part.Face)}
    return result if new.isValid() and all(f.isValid() for f in changed.values()) else None


def _knots_in(knots, period, a, b):
    """The knots strictly inside (a, b), repeated by `period` (0: not periodic)."""
    k = np.asarray(knots, float)
    if period:
        k = np.concatenate([k[:-1] + i * period for i in range(
            int(np.floor((a - k[-1]) / period)), int(np.ceil((b - k[0]) / period)) + 1)])
    return k[(k > a) & (k < b)]


def _curve_knots(curve, a, b):
    if not hasattr(curve, "getKnots"):
        return np.zeros(0)
    knots = curve.getKnots()
    return _knots_in(knots, knots[-1] - knots[0] if curve.isPeriodic() else 0.0, a, b)


def _crossings(c2d, surface, ts):
    """Parameters of the pcurve where it crosses a knot line of a B-spline surface,
    interpolated between the parameters `ts` (exact for a straight pcurve)."""
    if not hasattr(surface, "getUKnots"):
        return np.zeros(0)
    uv = np.array([(p.x, p.y) for p in map(c2d.value, ts)])
    out = []
    for axis, knots, periodic, period in (
            (0, surface.getUKnots(), surface.isUPeriodic(), "UPeriod"),
            (1, surface.getVKnots(), surface.isVPeriodic(), "VPeriod")):
        x = uv[:, axis]
        k = _knots_in(knots, getattr(surface, period)() if periodic else 0.0, x.min(), x.max())
        if not len(k):
            continue
        x0, x1 = x[:-1], x[1:]
        first = np.searchsorted(k, np.minimum(x0, x1), side="right")
        stop = np.searchsorted(k, np.maximum(x0, x1), side="left")
        i = np.repeat(np.arange(len(x0)), np.maximum(stop - first, 0))
        if not len(i):
            continue
        j = np.concatenate([np.arange(f, s) for f, s in zip(first, stop) if s > f])
        out.append(ts[i] + (k[j] - x0[i]) / (x1[i] - x0[i]) * (ts[i + 1] - ts[i]))
    return np.concatenate(out) if out else np.zeros(0)


def _spread(cuts, count):
    """`count` parameters in each interval between consecutive `cuts` (sorted), ends
    shared, closer together toward the ends (Chebyshev-Lobatto: a polynomial's largest
    values there are the steepest)."""
    steps = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, count)[:-1])
    inner = cuts[:-1, None] + (cuts[1:] - cuts[:-1])[:, None] * steps
    return np.append(inner.ravel(), cuts[-1])


def _degree(geom):
    """A B-spline's or Bezier's degree (the larger of a surface's two); None for a line,
    conic or analytic surface."""
    if hasattr(geom, "UDegree"):
        return max(geom.UDegree, geom.VDegree)
    return getattr(geom, "Degree", None)


def _largest_gap(surface, edge, c2d, a, b, per_span):
    """The largest distance between the edge's 3D curve and its pcurve on the face at the
    same parameter. Where a B-spline is involved: samples in every piece where the gap is
    smooth (between the knots of the pcurve and of the 3D curve and the pcurve's crossings
    of the surface's knot lines: its peaks sit near them), the highest degree and two
    more (a degree-12 3D curve: 11 bumps), then a bounded search about the largest;
    `per_span` samples else (lines, conics, analytic surfaces: no spans, no bumps)."""
    curve = edge.Curve

    def gap(t):
        uv = c2d.value(t)
        return (surface.value(uv.x, uv.y) - edge.valueAt(t)).Length

    degrees = [d for d in map(_degree, (curve, c2d, surface)) if d is not None]
    if not degrees:
        return max(gap(t) for t in np.linspace(a, b, per_span))
    cuts = np.unique(np.concatenate([[a, b], _curve_knots(c2d, a, b),
                                     _curve_knots(curve, a, b)]))
    cuts = np.unique(np.concatenate([cuts, _crossings(c2d, surface, _spread(cuts, 5))]))
    ts = _spread(cuts, max(per_span, max(degrees) + 2))
    gaps = [gap(t) for t in ts]
    i = int(np.argmax(gaps))
    if gaps[i] < 1e-9:
        return gaps[i]   # the curves coincide (an isoline): no tolerance depends on it
    lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, len(ts) - 1)]
    found = minimize_scalar(lambda t: -gap(t), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-3 * (hi - lo)})
    return max(gaps[i], -found.fun)


def pcurve_gaps(face, per_span=9, which=None):
    """[(edge, largest distance between its 3D curve and its pcurve on `face`, at the same
    parameter)] for the face's edges (both pcurves of a seam); inf where an edge has no
    pcurve. OCCT's projected pcurves on a rational surface (a converted circle) can follow
    another parametrisation, and a refit surface's many spans bend a pcurve's image away
    from the 3D curve between samples: isValid() (23 samples an edge) passes, the BOP
    check (BOPAlgo_InvalidCurveOnSurface) and booleans fail. `which(edge)`: only those
    edges."""
    out = []
    surface = None                            # (face.Surface: 0.4 ms on a face of 1000 edges)
    for edge in face.Edges:
        if edge.Degenerated or (which is not None and not which(edge)):
            continue
        if surface is None:
            surface = face.Surface
            exact = _EXACT.get(type(surface).__name__)
        worst = 0.0
        for e in (edge, edge.reversed()) if edge.isSeam(face) else (edge,):
            found = face.curveOnSurface(e)
            if found is None:
                worst = np.inf
                break
            if not (exact and _exact(exact, edge, found[0])):
                worst = max(worst, _largest_gap(surface, e, *found, per_span))
        out.append((edge, worst))
    return out


_EXACT = {"Plane": (("Line", "Circle", "Ellipse"), ("Line2d", "Circle2d", "Ellipse2d")),
          "Cylinder": (("Line", "Circle"), ("Line2d",))}


def _exact(kinds, edge, pcurve):
    """Whether the pcurve is the 3D curve itself, for `kinds` = _EXACT[the surface's
    type]: a 2D line or conic on a plane for a 3D line or conic, a 2D line on a cylinder
    for a generatrix or a circle about its axis (OCCT writes both from one exact
    intersection: no gap to measure)."""
    curve = type(edge.Curve).__name__.replace("Segment", "").replace("ArcOf", "")
    flat = type(pcurve).__name__.replace("Segment", "").replace("ArcOf", "")
    return curve in kinds[0] and flat in kinds[1]


def settle_tolerances(face):
    """Raise the tolerance of the face's edges (and their vertices) to cover the gap
    between their 3D curves and pcurves, so the shape is what it says (the BOP check
    and booleans trust the tolerances). The largest gap, for the caller to judge."""
    worst = 0.0
    for edge, gap in pcurve_gaps(face):
        worst = max(worst, gap)
        if np.isfinite(gap) and 2.0 * gap > edge.Tolerance:
            # twice the gap found: a margin over OCCT's own search for the peak (a
            # tapered cone's edge was rejected at 2.21e-7 for 2.16e-7 measured)
            edge.limitTolerance(2.0 * gap)
    return worst


def moved(surface, before, after):
    """The Part surface of the arrays `after`: a copy of `surface` (whose arrays are
    `before`) with only the poles that moved set, when no knot was inserted (fast on a
    large surface, the knots exactly kept); built anew otherwise."""
    if before.poles.shape != after.poles.shape or not (
            np.array_equal(before.uknots, after.uknots) and
            np.array_equal(before.vknots, after.vknots)):
        return surface_from_arrays(after)
    new = surface.copy()
    for i, j in zip(*np.nonzero(np.any(before.poles != after.poles, axis=2))):
        new.setPole(int(i) + 1, int(j) + 1, App.Vector(*after.poles[i, j]),
                    float(after.weights[i, j]))
    return new



def cuts_others(shape, index, tol, region=None, estimate=False):
    """True when face `index` of `shape` crosses another of its faces that does not share
    an edge with it (a push through the opposite face): their section has a point farther
    than `tol` (plus the edges' tolerance) from the face's edges. `region` (u0, u1, v0,
    v1): only that part of the face's surface changed, so only it is sectioned, against
    the faces near it. The neighbours along its edges are left out: OCCT's section along
    a shared edge costs seconds on a real part (0.02 to 0.2 s without them).
    estimate: only the faces OCCT's distance finds within that slack are sectioned (3 to
    10x faster on a real part; the distance's search may miss a small crossing, so this
    is for estimates, such as how far a refused push can go, never for a verdict)."""
    face = shape.Faces[index]
    probe = face if region is None else face.Surface.toShape(*region)
    box = probe.BoundBox
    box.enlarge(tol)
    edges = face.Edges
    slack = tol + max([e.Tolerance for e in edges] + [0.0])
    others = [f for i, f in enumerate(shape.Faces) if i != index and f.BoundBox.intersect(box)
              and not any(e.isSame(x) for e in f.Edges for x in edges)]
    if estimate:
        others = [f for f in others if probe.distToShape(f)[0] <= slack]
    if not others:
        return False
    section = probe.section(Part.Compound(others))
    if not section.Vertexes:
        return False
    border = Part.Compound(edges)
    points = [v.Point for v in section.Vertexes]
    for e in section.Edges:
        points += e.discretize(5)
    # the region's surface reaches past a trimmed face's boundary (a cone of 11 edges,
    # OCCT's CrankArm): a point there is on no face of the result
    return any(border.distToShape(Part.Vertex(p))[0] > slack and
               face.distToShape(Part.Vertex(p))[0] <= slack for p in points)
