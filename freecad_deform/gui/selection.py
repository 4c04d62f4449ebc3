"""Reading the user's selection: which object to deform, which plane they picked.

Shared by the commands (IsActive / Activated) and the task panels ("Pick" buttons).
Every function here is cheap and never raises on odd selections: IsActive runs often.
"""
import FreeCAD as App

from ..shapes.convert import plane_placement

Z = App.Vector(0, 0, 1)
DATUM_PLANE_TYPES = ("App::Plane", "PartDesign::Plane")


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


def _face_sub(sub_name):
    return sub_name.split(".")[-1].startswith("Face")


def read(selection):
    """(base, plane or None) when the selection fits a deform command, else None.

    `selection` is Gui.Selection.getSelectionEx(). It fits when it holds exactly one
    deformable object (a Part object with a solid, a Mesh::Feature or a Points::Feature)
    and at most one plane: a planar face (of that object or of another one) or a
    datum plane (App::Plane, PartDesign::Plane). Edges, vertices, curved faces or a
    second candidate make it not fit.
    """
    try:
        whole, face_owners, planes = [], [], []
        for item in selection:
            obj = item.Object
            if is_datum_plane(obj):
                planes.append(datum_plane(obj))
                continue
            subs = [s for s in item.SubElementNames if s]
            if not subs:
                whole.append(obj)
                continue
            if len(subs) != 1 or not _face_sub(subs[0]):
                return None
            plane = face_plane(item.SubObjects[0])
            if plane is None:
                return None
            planes.append(plane)
            face_owners.append(obj)
        if len(planes) > 1:
            return None
        candidates = [o for o in whole if base_kind(o)]
        if len(candidates) != len(whole):
            return None  # something whole that is neither a base nor a plane
        if len(candidates) == 1:
            base = candidates[0]
        elif not candidates and len(face_owners) == 1 and base_kind(face_owners[0]):
            base = face_owners[0]   # one face of the part itself: it gives the plane
        else:
            return None
        return base, (planes[0] if planes else None)
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
