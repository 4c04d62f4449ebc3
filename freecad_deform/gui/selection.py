"""Reading the user's selection: which object to deform, which plane and axis they picked,
and the values a new feature starts with when they picked none.

Shared by the commands (IsActive / Activated) and the task panels ("Pick" buttons).
Every reading function here is cheap and never raises on odd selections: IsActive runs often.
"""
import FreeCAD as App

from ..shapes.convert import plane_placement

Z = App.Vector(0, 0, 1)
DATUM_PLANE_TYPES = ("App::Plane", "PartDesign::Plane")
DATUM_LINE_TYPES = ("App::Line", "PartDesign::Line")
AXES = {"X_Axis": App.Vector(1, 0, 0), "Y_Axis": App.Vector(0, 1, 0),
        "Z_Axis": App.Vector(0, 0, 1)}


def base_kind(obj):
    """"Part", "Mesh" or "Points" when `obj` can be deformed, else None.

    A Part object counts only when its shape has a solid; datum planes never count.
    """
    try:
        if obj is None or is_datum_plane(obj):
            return None
        if obj.isDerivedFrom("Mesh::Feature"):
            return "Mesh"
        if obj.isDerivedFrom("Points::Feature"):
            return "Points"
        if obj.isDerivedFrom("Part::Feature"):
            shape = obj.Shape
            if shape.isNull():
                return None
            if shape.ShapeType == "Solid" or shape.Solids:
                return "Part"
    except Exception:
        return None
    return None


def is_datum_plane(obj):
    try:
        return any(obj.isDerivedFrom(t) for t in DATUM_PLANE_TYPES)
    except Exception:
        return False


def is_datum_line(obj):
    try:
        return any(obj.isDerivedFrom(t) for t in DATUM_LINE_TYPES)
    except Exception:
        return False


def datum_plane(obj):
    """The Placement of a datum plane (its XY is the plane), in global coordinates."""
    try:
        return App.Placement(obj.getGlobalPlacement())
    except Exception:
        return App.Placement(obj.Placement)


def face_plane(face):
    """Placement of a planar face's plane (origin at its centre, Z = its outward normal), or None."""
    try:
        import Part
        if not isinstance(face.Surface, Part.Plane):
            if face.findPlane() is None:
                return None
        u0, u1, v0, v1 = face.ParameterRange
        normal = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
        # The centre of mass of a planar face lies in its plane.
        return plane_placement((App.Vector(face.CenterOfMass), normal))
    except Exception:
        return None


def datum_line(obj):
    """(point, unit direction) of a datum line in global coordinates, or None.

    PartDesign::Line runs along its local Z. An App::Line of an origin (X_Axis, ...) runs
    along that axis of the origin's owner, whatever the FreeCAD version stores in its own
    Placement; any other App::Line along its local X (FreeCAD 0.20's convention).
    """
    try:
        try:
            glob = App.Placement(obj.getGlobalPlacement())
        except Exception:
            glob = App.Placement(obj.Placement)
        if obj.isDerivedFrom("PartDesign::Line"):
            direction = glob.Rotation.multVec(Z)
        else:
            role = getattr(obj, "Role", "")
            if role in AXES:
                owner = glob.multiply(App.Placement(obj.Placement).inverse())
                direction = owner.Rotation.multVec(AXES[role])
            else:
                direction = glob.Rotation.multVec(App.Vector(1, 0, 0))
        return App.Vector(glob.Base), App.Vector(direction).normalize()
    except Exception:
        return None


def edge_line(edge):
    """(point, unit direction) of a straight edge, from its start toward its end, or None."""
    try:
        import Part
        if not isinstance(edge.Curve, (Part.Line, Part.LineSegment)):
            return None
        start = edge.valueAt(edge.FirstParameter)
        direction = edge.valueAt(edge.LastParameter) - start
        if direction.Length < 1e-12:
            return None
        return App.Vector(start), direction.normalize()
    except Exception:
        return None


def _face_sub(sub_name):
    return sub_name.split(".")[-1].startswith("Face")


def _edge_sub(sub_name):
    return sub_name.split(".")[-1].startswith("Edge")


def read(selection, axis=False):
    """(base, plane or None) when the selection fits a deform command, else None; with
    `axis`, (base, plane or None, axis or None).

    `selection` is Gui.Selection.getSelectionEx(). It fits when it holds exactly one
    deformable object (a Part object with a solid, a Mesh::Feature or a Points::Feature)
    and at most one plane: a planar face (of that object or of another one) or a
    datum plane (App::Plane, PartDesign::Plane). With `axis` it may also hold one line: a
    straight edge (of that object or of another one) or a datum line (App::Line,
    PartDesign::Line), as (point, unit direction). Other edges, vertices, curved faces or
    a second candidate make it not fit. The object may also be given only by its own face
    and/or edge (the one selected element that belongs to a deformable object).
    """
    try:
        whole, owners, planes, lines = [], [], [], []
        for item in selection:
            obj = item.Object
            if is_datum_plane(obj):
                planes.append(datum_plane(obj))
                continue
            if axis and is_datum_line(obj):
                line = datum_line(obj)
                if line is None:
                    return None
                lines.append(line)
                continue
            subs = [s for s in item.SubElementNames if s]
            if not subs:
                whole.append(obj)
                continue
            for name, sub in zip(item.SubElementNames, item.SubObjects):
                if _face_sub(name):
                    found, plane = planes, face_plane(sub)
                elif axis and _edge_sub(name):
                    found, plane = lines, edge_line(sub)
                else:
                    return None
                if plane is None:
                    return None
                found.append(plane)
            if obj not in owners:
                owners.append(obj)
        if len(planes) > 1 or len(lines) > 1:
            return None
        candidates = [o for o in whole if base_kind(o)]
        if len(candidates) != len(whole):
            return None  # something whole that is neither a base nor a plane
        owning = [o for o in owners if base_kind(o)]
        if len(candidates) == 1:
            base = candidates[0]
        elif not candidates and len(owning) == 1:
            base = owning[0]   # faces / edges of the part itself give the plane / axis
        else:
            return None
        plane = planes[0] if planes else None
        if axis:
            return base, plane, (lines[0] if lines else None)
        return base, plane
    except Exception:
        return None


def picked_plane(selection):
    """The first planar face or datum plane in the selection, as a Placement, or None."""
    for item in selection:
        try:
            if is_datum_plane(item.Object):
                return datum_plane(item.Object)
            for name, sub in zip(item.SubElementNames, item.SubObjects):
                if _face_sub(name):
                    plane = face_plane(sub)
                    if plane is not None:
                        return plane
        except Exception:
            continue
    return None


def picked_axis(selection):
    """The first straight edge or datum line in the selection, as (point, unit direction),
    or None."""
    for item in selection:
        try:
            if is_datum_line(item.Object):
                line = datum_line(item.Object)
                if line is not None:
                    return line
                continue
            for name, sub in zip(item.SubElementNames, item.SubObjects):
                if _edge_sub(name):
                    line = edge_line(sub)
                    if line is not None:
                        return line
        except Exception:
            continue
    return None


def bound_box(base):
    kind = base_kind(base)
    data = {"Mesh": "Mesh", "Points": "Points"}.get(kind, "Shape")
    return getattr(base, data).BoundBox


def extent(base, plane):
    """(min, max) signed distance of the base's bounding-box corners to `plane`."""
    bb = bound_box(base)
    origin, normal = plane.Base, plane.Rotation.multVec(Z)
    values = [(App.Vector(x, y, z) - origin).dot(normal)
              for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax) for z in (bb.ZMin, bb.ZMax)]
    return min(values), max(values)


def default_plane(base):
    """Through the centre of the base's bounding box, normal along its longest side."""
    bb = bound_box(base)
    lengths = [bb.XLength, bb.YLength, bb.ZLength]
    axis = [App.Vector(1, 0, 0), App.Vector(0, 1, 0), App.Vector(0, 0, 1)][lengths.index(max(lengths))]
    return plane_placement((bb.Center, axis))


def crossing_plane(base, plane):
    """`plane`, or, when it misses the base (a face on the part's boundary), the parallel
    plane through the middle of the base: the picked face then only gives the direction."""
    lo, hi = extent(base, plane)
    tol = 1e-7 * max(1.0, bound_box(base).DiagonalLength)
    if lo < -tol and hi > tol:
        return App.Placement(plane)
    normal = plane.Rotation.multVec(Z)
    moved = App.Placement(plane)
    moved.Base = plane.Base + normal * (0.5 * (lo + hi))
    return moved


def suggested_plane(base, picked):
    """The plane a new feature starts with: the picked one (moved into the part if it
    misses it), else default_plane(base)."""
    if picked is None:
        return default_plane(base)
    return crossing_plane(base, picked)


# --- what a new Bend / Twist starts with ---------------------------------------------------------
def normal_of(placement):
    return placement.Rotation.multVec(Z)


def _unit_axes():
    return [App.Vector(1, 0, 0), App.Vector(0, 1, 0), App.Vector(0, 0, 1)]


def _corners(base):
    bb = bound_box(base)
    return [App.Vector(x, y, z) for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
            for z in (bb.ZMin, bb.ZMax)]


def turning_speed(point, plane, axis_point, axis_direction):
    """n . (w x (p - c)): how fast `point` leaves Plane along its normal when a positive
    Angle turns it about the axis (c, w). A bend is valid when this is positive over the
    cross-section at Plane."""
    return normal_of(plane).dot(axis_direction.cross(point - axis_point))


def section_centre(base, plane):
    """The bounding box's centre projected onto `plane`: the middle of where the
    cross-section can lie (every section point is inside the projected box)."""
    centre, normal = App.Vector(bound_box(base).Center), normal_of(plane)
    return centre - normal * (centre - plane.Base).dot(normal)


def axis_through(line, plane):
    """An Axis Placement on `line` (point, direction): its Base is the point of the line
    nearest to Plane's origin (in Plane when the line lies in it), its local Z the direction."""
    point, direction = App.Vector(line[0]), App.Vector(line[1]).normalize()
    point = point + direction * (plane.Base - point).dot(direction)
    return plane_placement((point, direction), "Axis")


def oriented_bend_axis(base, plane, axis, angle=1.0):
    """`axis` (a Placement), its direction reversed if that makes `angle`'s sign turn the
    middle of the cross-section away from the near part. Edges and datum lines have no
    meaningful direction, so a picked one is turned to suit the Angle already set."""
    speed = turning_speed(section_centre(base, plane), plane, axis.Base,
                          axis.Rotation.multVec(Z))
    if speed * angle < 0:
        return plane_placement((axis.Base, -axis.Rotation.multVec(Z)), "Axis")
    return App.Placement(axis)


def default_bend_axis(base, plane):
    """In Plane, parallel to the part's second-longest side, just outside its bounding
    box, and directed so that a positive Angle is a valid bend: every section point p
    then has n . (w x (p - c)) > 0."""
    bb = bound_box(base)
    lengths = [bb.XLength, bb.YLength, bb.ZLength]
    normal = normal_of(plane)
    # the side most along the normal is the one being bent; of the other two, the longer
    # one gives the axis direction
    along = max(range(3), key=lambda i: abs(_unit_axes()[i].dot(normal)))
    others = sorted((i for i in range(3) if i != along), key=lambda i: -lengths[i])
    for i in others:
        w = _unit_axes()[i] - normal * _unit_axes()[i].dot(normal)
        if w.Length > 1e-6:
            break
    w.normalize()
    u = normal.cross(w)  # in Plane, across the axis: the third side
    values = [(p - plane.Base).dot(u) for p in _corners(base)]
    low, high = min(values), max(values)
    margin = max(0.1 * (high - low), 1e-3 * bb.DiagonalLength, 1e-6)
    point = plane.Base + u * (low - margin)
    if turning_speed(section_centre(base, plane), plane, point, w) < 0:
        w = -w
    return plane_placement((point, w), "Axis")


def suggested_bend(base, picked_plane=None, picked_line=None):
    """(Plane, Axis) of a new Bend. Plane: the picked one (moved into the part if it misses
    it) or the default plane; when only a line was picked and it is parallel to that
    plane, the plane moves onto the line if it still crosses the part there. Axis: the
    picked line, directed so that a positive Angle is valid, else default_bend_axis."""
    plane = suggested_plane(base, picked_plane)
    if picked_line is None:
        return plane, default_bend_axis(base, plane)
    point, direction = App.Vector(picked_line[0]), App.Vector(picked_line[1]).normalize()
    normal = normal_of(plane)
    if picked_plane is None and abs(direction.dot(normal)) < 1e-9:
        moved = App.Placement(plane)
        moved.Base = plane.Base + normal * (point - plane.Base).dot(normal)
        lo, hi = extent(base, moved)
        tol = 1e-7 * max(1.0, bound_box(base).DiagonalLength)
        if lo < -tol and hi > tol:
            plane = moved
    return plane, oriented_bend_axis(base, plane, axis_through(picked_line, plane))


def suggested_twist(base, picked_plane=None):
    """(Plane, Plane2) of a new Twist or Taper: at 1/3 and 2/3 of the part's longest side;
    with a picked plane, that plane (moved into the part if it misses it) and Plane2 halfway
    from it to the far end of the part."""
    if picked_plane is None:
        bb = bound_box(base)
        lengths = [bb.XLength, bb.YLength, bb.ZLength]
        i = lengths.index(max(lengths))
        normal = _unit_axes()[i]
        lo = (bb.XMin, bb.YMin, bb.ZMin)[i]
        first = [bb.Center.x, bb.Center.y, bb.Center.z]
        first[i] = lo + lengths[i] / 3.0
        plane = plane_placement((App.Vector(*first), normal))
        offset = lengths[i] / 3.0
    else:
        plane = crossing_plane(base, picked_plane)
        _, hi = extent(base, plane)
        offset = 0.5 * hi
    plane2 = App.Placement(plane.Base + normal_of(plane) * offset, plane.Rotation)
    return plane, plane2


def default_twist_axis(base, plane):
    """The Plane normal through the middle of the cross-section (Twist's own default when
    UseAxis is false): the start value of Axis when the user turns UseAxis on."""
    centre = section_centre(base, plane)
    try:
        kind = base_kind(base)
        if kind == "Part":
            import Part
            normal = normal_of(plane)
            wires = base.Shape.slice(normal, normal.dot(plane.Base))
            if wires:
                centre = App.Vector(Part.makeFace(wires, "Part::FaceMakerBullseye").CenterOfMass)
    except Exception:
        pass
    return plane_placement((centre, normal_of(plane)), "Axis")
