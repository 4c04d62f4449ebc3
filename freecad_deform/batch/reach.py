"""`reach`, the inverse problem of Wu & Ilies: a feature of the far part (a point and an
axis: a hole's centre and axis, a face's centre and normal) must end at a target point and
axis. The far part's rigid motion is the least rotation taking the axis to the target axis,
then the translation taking the point to the target point. A translation along the Plane's
normal is made as a Stretch, a rotation about an axis (no slide along it) as an exact Bend.
A motion that is neither (a screw, or a translation across the normal) is swept through key
frames (Step 6 of the paper): a Stretch whose far part ends at EndPlacement, the gap lofted
along the motion: direct, else along a smooth path leaving the Plane along its normal, else
lifted off the Plane first, where a more direct path would reach back into the part."""
import numpy as np

from . import model

App = model.App


def feature_frame(shape, element):
    """(point, unit axis) of a face: a cylinder's (or cone's) axis and the point on it
    nearest the face's centre of mass (a hole's centre); a plane's centre and normal."""
    face = shape.getElement(element)
    surface = face.Surface
    com = np.array(tuple(face.CenterOfMass))
    if hasattr(surface, "Axis") and hasattr(surface, "Center"):
        axis = np.array(tuple(surface.Axis))
        axis /= np.linalg.norm(axis)
        origin = np.array(tuple(surface.Center))
        return origin + ((com - origin) @ axis) * axis, axis
    if surface.TypeId == "Part::GeomPlane":
        u0, u1, v0, v1 = face.ParameterRange
        normal = np.array(tuple(face.normalAt((u0 + u1) / 2, (v0 + v1) / 2)))
        return com, normal / np.linalg.norm(normal)
    raise model.BatchError(f"{element} is a {surface.TypeId.split('::')[-1]}; pick a hole "
                           f"(a cylinder or cone) or a planar face as the feature.")


def least_rotation(a, b, normal):
    """The rotation matrix taking unit a to unit b about a x b (a half turn about the axis
    across a nearest the Plane's normal when they are opposite)."""
    u, c = np.cross(a, b), float(a @ b)
    s = np.linalg.norm(u)
    if s < 1e-15:
        if c > 0:
            return np.eye(3)
        u = np.cross(np.cross(a, normal), a)
        if np.linalg.norm(u) < 1e-12:
            u = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        u, s, c = u / np.linalg.norm(u), 0.0, -1.0
    else:
        u = u / s
    k = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return np.eye(3) + s * k + (1 - c) * k @ k


def motion_kind(p, a, q, b, origin, normal, tol):
    """("Stretch", distance), ("Bend", axis point, axis direction, degrees) or ("KeyFrames",
    4x4 matrix) for the rigid motion taking the point p and axis a to q and b."""
    rot = least_rotation(a, b, normal)
    shift = q - p
    angle = np.arccos(np.clip((np.trace(rot) - 1) / 2, -1, 1))
    end = np.eye(4)
    end[:3, :3], end[:3, 3] = rot, q - rot @ p
    if angle < 1e-15:
        across = shift - (shift @ normal) * normal
        if np.linalg.norm(across) > tol:
            return "KeyFrames", end
        return "Stretch", float(shift @ normal)
    w = np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    if np.linalg.norm(w) < 1e-12:  # a half turn: its axis from R + I
        w = (rot + np.eye(3))[np.argmax(np.diag(rot))]
    u = w / np.linalg.norm(w)
    if abs(float(shift @ u)) > tol:  # a screw: a turn and a slide along its axis
        return "KeyFrames", end
    # the axis: points c with (I - R)(c - p) = q - p, the one nearest the Plane's origin
    c0 = p + np.linalg.lstsq(np.eye(3) - rot, shift, rcond=None)[0]
    c0 = c0 - ((c0 - p) @ u) * u
    centre = c0 + ((origin - c0) @ u) * u
    return "Bend", centre, u, float(np.degrees(angle))


def key_frame_tries(end, origin, normal, centre):
    """(KeyPlacements, Interpolation) to try in turn for a key-frame sweep ending at `end`.
    Profiles stay normal to the path of the section's `centre`, so a path that leaves the
    Plane obliquely would reach back into the part: after the direct motion, a smooth one
    (8 keys on a cubic Hermite path of `centre` leaving along the normal and arriving along
    the turned normal, the turn eased in and out), then a lift off the Plane along its
    normal by half the far part's advance followed by the rest (a crease at the lift)."""
    advance = float((end[:3, :3] @ origin + end[:3, 3] - origin) @ normal)
    lift = np.eye(4)
    lift[:3, 3] = 0.5 * max(advance, 0.0) * normal
    return [([], "Rational"), (hermite_keys(end, normal, centre, 8), "Rational"),
            ([lift], "Screw"), ([lift], "Rational")]


def hermite_keys(end, normal, centre, count):
    """`count` - 1 key placements (the last, `end`, left out) on the motion whose point
    `centre` follows the cubic Hermite curve to end(centre) with tangents along the normal
    and the turned normal (lengths the chord), turning by slerp eased with 3s^2 - 2s^3."""
    from scipy.spatial.transform import Rotation, Slerp
    rot = end[:3, :3]
    target = rot @ centre + end[:3, 3]
    chord = float(np.linalg.norm(target - centre))
    turn = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([np.eye(3), rot])))
    keys = []
    for t in np.linspace(0.0, 1.0, count + 1)[1:-1]:
        h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, \
            -2 * t**3 + 3 * t**2, t**3 - t**2
        point = (h00 * centre + h10 * chord * normal + h01 * target
                 + h11 * chord * (rot @ normal))
        key = np.eye(4)
        key[:3, :3] = turn([3 * t**2 - 2 * t**3]).as_matrix()[0]
        key[:3, 3] = point - key[:3, :3] @ centre
        keys.append(key)
    return keys


def section_centre(shape, origin, normal):
    """The centroid of the shape's section at the Plane (the point whose path the key-frame
    profiles follow); the Plane's origin when the section has no face."""
    import Part
    wires = [w for w in shape.slice(App.Vector(*map(float, normal)), float(origin @ normal))
             if w.isClosed()]
    if not wires:
        return origin
    face = Part.makeFace(wires, "Part::FaceMakerBullseye")  # holes inside their outline
    return np.array(tuple(face.CenterOfMass)) if face.Area > 0 else origin


def _placement(matrix):
    return App.Placement(App.Matrix(*map(float, np.asarray(matrix).ravel())))


def reach(doc, base, plane, feature, target, tol=1e-9):
    """Make the Stretch or Bend of `base` at `plane` ((origin, normal)) that takes
    `feature` ("FaceN" of the base, or (point, axis)) to `target` ((point, axis)). Returns
    {"method", "object", and "distance", "axis"/"angle" or "keys"/"interpolation"}; the
    document is recomputed. "method" is Stretch, Bend or KeyFrames (a Stretch whose far part
    ends at EndPlacement through KeyPlacements)."""
    import freecad_deform as fd
    obj = model.find_object(doc, base) if isinstance(base, str) else base
    origin, normal = (np.asarray(v, float) for v in plane)
    normal = normal / np.linalg.norm(normal)
    if isinstance(feature, str):
        p, a = feature_frame(obj.Shape, feature)
    else:
        p, a = (np.asarray(v, float) for v in feature)
    q, b = (np.asarray(v, float) for v in target)
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    if (p - origin) @ normal <= 0:
        raise model.BatchError("the feature is not beyond the Plane (on the side its normal "
                               "points to), so it does not move; pick a feature of the far "
                               "part or flip the Plane.")
    scale = max(np.linalg.norm(p - origin), np.linalg.norm(q - origin), 1.0)
    kind = motion_kind(p, a, q, b, origin, normal, tol * scale)
    vec = lambda v: App.Vector(*map(float, v))  # noqa: E731
    if kind[0] == "Stretch":
        made = fd.make_stretch(obj, (vec(origin), vec(normal)), kind[1])
        info = {"distance": kind[1]}
    elif kind[0] == "Bend":
        _, centre, u, degrees = kind
        made = fd.make_bend(obj, (vec(origin), vec(normal)), degrees, (vec(centre), vec(u)))
        info = {"axis": (tuple(centre), tuple(u)), "angle": degrees}
    else:
        return _key_frames(doc, obj, origin, normal, kind[1], vec)
    valid, error = model.status(doc)
    if error:  # leave the document as it was
        _remove(doc, obj, made)
        raise model.BatchError(f"the {kind[0]} that reaches the target fails: {error}")
    return {"method": kind[0], "object": made.Name, **info}


def _remove(doc, base, made):
    doc.removeObject(made.Name)
    base.Visibility = True
    doc.recompute()


def _key_frames(doc, obj, origin, normal, end, vec):
    """The key-frame sweep ending at `end`: a Stretch with UseEndPlacement, trying the
    KeyPlacements of key_frame_tries until one recomputes valid."""
    import freecad_deform as fd
    advance = float((end[:3, :3] @ origin + end[:3, 3] - origin) @ normal)
    made = fd.make_stretch(obj, (vec(origin), vec(normal)), advance)
    made.UseEndPlacement = True
    made.EndPlacement = _placement(end)
    errors = []
    centre = section_centre(obj.Shape, origin, normal)
    for keys, interpolation in key_frame_tries(end, origin, normal, centre):
        made.KeyPlacements = [_placement(k) for k in keys]
        made.Interpolation = interpolation
        made.touch()
        doc.recompute()
        valid, error = model.status(doc)
        if not error:
            return {"method": "KeyFrames", "object": made.Name, "keys": len(keys),
                    "interpolation": interpolation}
        errors.append(error)
    _remove(doc, obj, made)
    raise model.BatchError(
        f"the key-frame sweep that reaches the target fails ({errors[-1]}); give a target the "
        f"far part reaches with less sideways motion for its advance along the Plane's normal "
        f"(each profile turns with the path, and the turn must stay wider than the section).")
