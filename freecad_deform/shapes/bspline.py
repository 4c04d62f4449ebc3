"""B-spline faces as arrays and back: poles, weights, knots of a Part.BSplineSurface, the
surface with new poles (same knots, degrees and weights), and a face replaced in its shell
or solid."""
import FreeCAD as App
import numpy as np
import Part

from ..geometry.bspline_area import Surface
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


def bspline_of(face, prop="Face"):
    """(BSplineSurface covering exactly the face, note on the conversion).

    A non-B-spline face is converted (NurbsConvert: exact for planes, cylinders, cones,
    spheres, tori, revolved and extruded surfaces); the surface is cut to the face's
    parameter range; the face must not be trimmed by anything else."""
    kind = face.Surface.TypeId.split("::Geom")[-1]
    if kind == "BSplineSurface":
        surface, note = face.Surface.copy(), "B-spline"
    else:
        surface = face.toNurbs().Faces[0].Surface
        note = (f"{kind} converted exactly" if kind in EXACT else
                f"{kind} approximated by NurbsConvert (not exact)")
    u0, u1, v0, v1 = face.ParameterRange
    b = surface.bounds()
    if max(abs(u0 - b[0]), abs(u1 - b[1]), abs(v0 - b[2]), abs(v1 - b[3])) > 1e-9:
        surface.segment(u0, u1, v0, v1)
        note += ", cut to the face's parameter range"
    for periodic, fix in ((surface.isUPeriodic, surface.setUNotPeriodic),
                          (surface.isVPeriodic, surface.setVNotPeriodic)):
        if periodic():
            fix()
    natural = Part.Face(surface)
    if len(face.Wires) != 1 or abs(natural.Area - face.Area) > 1e-3 * face.Area:
        raise DeformError(f"{prop} is trimmed (holes or a non-rectangular boundary); "
                          "AreaConstrain needs a face bounded by its surface's parameter "
                          "range.", prop)
    return surface, note


def surface_arrays(surface):
    """The Surface (numpy) of a Part.BSplineSurface."""
    poles = np.array([[tuple(p) for p in row] for row in surface.getPoles()], float)
    weights = np.array(surface.getWeights(), float)
    uk = np.repeat(surface.getUKnots(), surface.getUMultiplicities())
    vk = np.repeat(surface.getVKnots(), surface.getVMultiplicities())
    return Surface(poles, weights, np.asarray(uk, float), np.asarray(vk, float),
                   surface.UDegree, surface.VDegree)


def with_poles(surface, poles):
    """A copy of `surface` with its poles set to `poles` (nu, nv, 3), weights kept."""
    new = surface.copy()
    weights = surface.getWeights()
    for i, row in enumerate(np.asarray(poles, float).tolist()):
        for j, p in enumerate(row):
            new.setPole(i + 1, j + 1, App.Vector(*p), weights[i][j])
    return new


def replaced(shape, index, face):
    """`shape` (one shell or one solid) with face `index` replaced by `face`, sewn; None
    when the shape is not a single shell or solid or the result is not valid."""
    if len(shape.Solids) == 1:
        kind = "Solid"
    elif len(shape.Shells) == 1 and not shape.Solids:
        kind = "Shell"
    else:
        return None
    faces = [face if i == index else f for i, f in enumerate(shape.Faces)]
    try:
        shell = Part.Shell(faces)
        shell.sewShape()
        shell = shell.Shells[0] if shell.Shells else shell
        result = Part.Solid(shell) if kind == "Solid" else shell
    except Part.OCCError:  # the faces do not close up again (e.g. a seam that moved)
        return None
    if kind == "Solid" and result.Volume < 0:
        result.reverse()
    return result if result.isValid() and len(result.Faces) == len(faces) else None
