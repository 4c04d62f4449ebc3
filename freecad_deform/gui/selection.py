"""Reading the user's selection: which object to deform, which plane and axis they picked,
and the values a new feature starts with when they picked none (computed by
geometry.sweep.defaults from the part's bounding box; this module only converts).

Shared by the commands (IsActive / Activated) and the task panels ("Pick" buttons).
Every reading function here is cheap and answers None on odd selections: IsActive runs often.
"""
import FreeCAD as App
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.sweep import defaults
from ..shapes.convert import box_arrays, plane_arrays, plane_placement, vector

Z = App.Vector(0, 0, 1)
DATUM_PLANE_TYPES = ("App::Plane", "PartDesign::Plane")
DATUM_LINE_TYPES = ("App::Line", "PartDesign::Line")
AXES = {"X_Axis": App.Vector(1, 0, 0), "Y_Axis": App.Vector(0, 1, 0),
        "Z_Axis": App.Vector(0, 0, 1)}


def base_kind(obj):
    """"Part", "Mesh" or "Points" when `obj` can be deformed, else None.

    A Part object counts only when its shape has a solid; datum planes never count.
    """
    if obj is None or is_datum_plane(obj):
        return None
    if obj.isDerivedFrom("Mesh::Feature"):
        return "Mesh"
    if obj.isDerivedFrom("Points::Feature"):
        return "Points"
    if obj.isDerivedFrom("Part::Feature"):
        shape = obj.Shape
        if not shape.isNull() and (shape.ShapeType == "Solid" or shape.Solids):
            return "Part"
    return None


def is_datum_plane(obj):
    return any(obj.isDerivedFrom(t) for t in DATUM_PLANE_TYPES)


def is_datum_line(obj):
    return any(obj.isDerivedFrom(t) for t in DATUM_LINE_TYPES)


def datum_plane(obj):
    """The Placement of a datum plane (its XY is the plane), in global coordinates."""
    return App.Placement(obj.getGlobalPlacement())


def face_plane(face):
    """Placement of a planar face's plane (origin at its centre, Z = its outward normal), or None."""
    import Part
    try:
        if not isinstance(face.Surface, Part.Plane) and face.findPlane() is None:
            return None
        u0, u1, v0, v1 = face.ParameterRange
        normal = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
        # The centre of mass of a planar face lies in its plane.
        return plane_placement((App.Vector(face.CenterOfMass), normal))
    except (RuntimeError, DeformError):  # OCCT has no surface or normal there
        return None


def datum_line(obj):
    """(point, unit direction) of a datum line in global coordinates.

    PartDesign::Line runs along its local Z. An App::Line of an origin (X_Axis, ...) runs
    along that axis of the origin's owner, whatever the FreeCAD version stores in its own
    Placement; any other App::Line along its local X (FreeCAD 0.20's convention).
    """
    glob = App.Placement(obj.getGlobalPlacement())
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


def edge_line(edge):
    """(point, unit direction) of a straight edge, from its start toward its end, or None."""
    import Part
    try:
        curve = edge.Curve
    except RuntimeError:  # OCCT has no curve there (a degenerated edge)
        return None
    if not isinstance(curve, (Part.Line, Part.LineSegment)):
        return None
    start = edge.valueAt(edge.FirstParameter)
    direction = edge.valueAt(edge.LastParameter) - start
    if direction.Length < 1e-12:
        return None
    return App.Vector(start), direction.normalize()


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
        return _read(selection, axis)
    except ReferenceError:  # an object deleted while it is still selected
        return None


def _read(selection, axis):
    whole, owners, planes, lines = [], [], [], []
    for item in selection:
        obj = item.Object
        if is_datum_plane(obj):
            planes.append(datum_plane(obj))
            continue
        if axis and is_datum_line(obj):
            lines.append(datum_line(obj))
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


def picked_plane(selection):
    """The first planar face or datum plane in the selection, as a Placement, or None."""
    return _first_picked(selection, is_datum_plane, datum_plane, _face_sub, face_plane)


def picked_axis(selection):
    """The first straight edge or datum line in the selection, as (point, unit direction),
    or None."""
    return _first_picked(selection, is_datum_line, datum_line, _edge_sub, edge_line)


def _first_picked(selection, is_datum, of_datum, is_sub, of_sub):
    """The first datum object (of_datum) or sub-element (of_sub, None when it does not
    fit) in the selection, or None."""
    for item in selection:
        if is_datum(item.Object):
            return of_datum(item.Object)
        for name, sub in zip(item.SubElementNames, item.SubObjects):
            if is_sub(name):
                found = of_sub(sub)
                if found is not None:
                    return found
    return None


def bound_box(base):
    kind = base_kind(base)
    data = {"Mesh": "Mesh", "Points": "Points"}.get(kind, "Shape")
    return getattr(base, data).BoundBox


# --- what a new feature starts with: FreeCAD values to arrays, geometry.sweep.defaults, back --
def box(base):
    """(lo, hi) corners of the base's bounding box, as arrays."""
    return box_arrays(bound_box(base))


def _axis(point_direction):
    point, direction = point_direction
    return plane_placement((vector(point), vector(direction)), "Axis")


def _line(line):
    return np.array(tuple(line[0]), float), np.array(tuple(line[1]), float)


def _moved(plane, origin):
    """`plane` (its rotation kept) with its Base at `origin`."""
    moved = App.Placement(plane)
    moved.Base = vector(origin)
    return moved


def extent(base, plane):
    """(min, max) signed distance of the base's bounding-box corners to `plane`."""
    return defaults.extent(*box(base), *plane_arrays(plane))


def default_plane(base):
    """Through the centre of the base's bounding box, normal along its longest side."""
    origin, normal = defaults.default_plane(*box(base))
    return plane_placement((vector(origin), vector(normal)))


def crossing_plane(base, plane):
    """`plane`, or, when it misses the base (a face on the part's boundary), the parallel
    plane through the middle of the base: the picked face then only gives the direction."""
    return _moved(plane, defaults.crossing_origin(*box(base), *plane_arrays(plane)))


def suggested_plane(base, picked):
    """The plane a new feature starts with: the picked one (moved into the part if it
    misses it), else default_plane(base)."""
    if picked is None:
        return default_plane(base)
    return crossing_plane(base, picked)


def axis_through(line, plane):
    """An Axis Placement on `line` (point, direction): its Base is the point of the line
    nearest to Plane's origin (in Plane when the line lies in it), its local Z the direction."""
    return _axis(defaults.axis_through(*_line(line), plane_arrays(plane)[0]))


def oriented_bend_axis(base, plane, axis, angle=1.0):
    """`axis` (a Placement), its direction reversed if that makes `angle`'s sign turn the
    middle of the cross-section away from the near part. Edges and datum lines have no
    meaningful direction, so a picked one is turned to suit the Angle already set."""
    return _axis(defaults.oriented_axis(*box(base), *plane_arrays(plane),
                                        *plane_arrays(axis), angle))


def default_bend_axis(base, plane):
    """In Plane, parallel to the part's second-longest side, just outside its bounding
    box, and directed so that a positive Angle is a valid bend."""
    return _axis(defaults.default_bend_axis(*box(base), *plane_arrays(plane)))


def suggested_bend(base, picked_plane=None, picked_line=None):
    """(Plane, Axis) of a new Bend. Plane: the picked one (moved into the part if it misses
    it) or the default plane; when only a line was picked and it is parallel to that
    plane, the plane moves onto the line if it still crosses the part there. Axis: the
    picked line, directed so that a positive Angle is valid, else default_bend_axis."""
    plane = suggested_plane(base, picked_plane)
    if picked_line is None:
        return plane, default_bend_axis(base, plane)
    if picked_plane is None:
        plane = _moved(plane, defaults.plane_onto_line(*box(base), *plane_arrays(plane),
                                                       *_line(picked_line)))
    return plane, oriented_bend_axis(base, plane, axis_through(picked_line, plane))


def suggested_twist(base, picked_plane=None):
    """(Plane, Plane2) of a new Twist or Taper: at 1/3 and 2/3 of the part's longest side;
    with a picked plane, that plane (moved into the part if it misses it) and Plane2 halfway
    from it to the far end of the part."""
    if picked_plane is None:
        origin, normal, offset = defaults.region_planes(*box(base))
        plane = plane_placement((vector(origin), vector(normal)))
    else:
        origin, normal, offset = defaults.region_planes(*box(base), *plane_arrays(picked_plane))
        plane = _moved(picked_plane, origin)
    plane2 = App.Placement(vector(origin + normal * offset), plane.Rotation)
    return plane, plane2


def default_twist_axis(base, plane):
    """The Plane normal through the centroid of the cross-section, as Twist takes it when
    UseAxis is false (ops.planes.section_centroid*, per kind of Base): the start value of
    Axis when the user turns UseAxis on, so the result stays the same."""
    from ..ops import planes as pp
    from ..shapes.brep import solids_of
    origin, normal = plane_arrays(plane)
    kind = base_kind(base)
    try:
        if kind == "Part":
            centre = pp.section_centroid(solids_of(base.Shape), origin, normal)
        elif kind == "Mesh":
            centre = pp.section_centroid_mesh(base.Mesh, origin, normal)
        else:
            centre = pp.section_centroid_cloud(pp.cloud(base.Points)[0], origin, normal)
    except DeformError:  # Plane misses the part (the feature says so): the box's middle
        centre = defaults.section_centre(*box(base), origin, normal)
    return _axis((centre, normal))
