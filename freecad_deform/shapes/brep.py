"""OCCT operations on B-rep solids through Part: split at planes, sweep sections, join."""
import FreeCAD as App
import numpy as np
import Part

from ..geometry.errors import DeformError
from ..geometry.planes import frame
from .convert import vector

TOL = 1e-7


def solids_of(shape, prop="Base"):
    """The solids of a shape; a shape without any is bad input for `prop`."""
    solids = list(shape.Solids)
    if not solids:
        raise DeformError(f"{prop} has no solid to deform; give {prop} a solid, a compound of "
                          f"solids, a mesh or a point cloud.", prop)
    return solids


def extent(shape, origin, normal):
    """(min, max) signed distance of the shape's bounding-box corners to the plane."""
    bb = shape.BoundBox
    corners = np.array([[x, y, z] for x in (bb.XMin, bb.XMax)
                        for y in (bb.YMin, bb.YMax) for z in (bb.ZMin, bb.ZMax)])
    s = (corners - origin) @ normal
    return s.min(), s.max()


def plane_face(shape, origin, normal):
    """A square planar face at the plane, larger than the shape."""
    size = shape.BoundBox.DiagonalLength + np.linalg.norm(
        np.array(tuple(shape.BoundBox.Center)) - origin) + 1.0
    u, v, _ = frame(normal)
    corners = [origin + size * (a * u + b * v) for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1), (1, 1))]
    return Part.Face(Part.makePolygon([vector(c) for c in corners]))


def split_zones(solid, origin, normal, offsets):
    """Split `solid` by the planes at `offsets` (ascending) along `normal`.

    Returns one list of solids per zone: zone 0 before the first plane, zone k between
    plane k-1 and plane k, the last zone beyond the last plane.
    """
    tools = [plane_face(solid, origin + off * normal, normal) for off in offsets]
    pieces, _ = solid.generalFuse(tools)
    zones = [[] for _ in range(len(offsets) + 1)]
    for piece in pieces.Solids:
        s = float(np.dot(np.array(tuple(piece.CenterOfMass)) - origin, normal))
        zones[int(np.searchsorted(offsets, s))].append(piece)
    return zones


def faces_on_plane(solids, origin, normal):
    """Faces of `solids` lying in the plane: the section faces a split created."""
    found = []
    for solid in solids:
        for face in solid.Faces:
            surf = face.Surface
            if not isinstance(surf, Part.Plane):
                continue
            if np.linalg.norm(np.cross(np.array(tuple(surf.Axis)), normal)) > TOL:
                continue
            if all(abs(np.dot(np.array(tuple(v.Point)) - origin, normal)) < TOL for v in face.Vertexes):
                found.append(face)
    return found


def translated(solids, vec):
    return [s.translated(vector(vec)) for s in solids]


def extruded(faces, vec):
    """The prisms swept by the faces along `vec`: an exact extrusion, planes stay planes."""
    return [f.extrude(vector(vec)) for f in faces]


def affine_stretched(solids, origin, normal, factor):
    """Solids scaled by `factor` along `normal` about the plane through `origin` (B-spline faces)."""
    u, v, n = frame(normal)
    rows = np.array([u, v, n]).T @ np.diag([1.0, 1.0, factor]) @ np.array([u, v, n])
    shift = origin - rows @ origin
    m = App.Matrix(*rows[0], shift[0], *rows[1], shift[1], *rows[2], shift[2], 0, 0, 0, 1)
    return [s.transformGeometry(m) for s in solids]


def is_prismatic(solids, origin, normal, gap, samples=5):
    """True if every face of `solids` off the two planes has its normal perpendicular to `normal`."""
    for solid in solids:
        for face in solid.Faces:
            u0, u1, v0, v1 = face.ParameterRange
            for a in np.linspace(0.1, 0.9, samples):
                for b in np.linspace(0.1, 0.9, samples):
                    uv = (u0 + a * (u1 - u0), v0 + b * (v1 - v0))
                    p = np.array(tuple(face.valueAt(*uv)))
                    s = float(np.dot(p - origin, normal))
                    if abs(s) < TOL or abs(s - gap) < TOL:
                        break
                    if abs(np.dot(np.array(tuple(face.normalAt(*uv))), normal)) > 1e-9:
                        return False
    return True


def join(solids, prop="Distance"):
    """Fuse the pieces and merge the faces the split cut (no seams left): one valid solid."""
    if len(solids) == 1:
        result = solids[0]
    else:
        result = solids[0].fuse(solids[1:]).removeSplitter()
    if not result.isValid() or len(result.Solids) != 1:
        raise DeformError(f"The pieces did not join into one valid solid; change {prop}.", prop)
    return result.Solids[0]


def crossing_faces(shape, origin, normal):
    """Names and faces of `shape` that the plane cuts, in face order."""
    found = []
    for i, face in enumerate(shape.Faces, start=1):
        lo, hi = extent(face, origin, normal)
        if lo < -TOL and hi > TOL and face.section(plane_face(face, origin, normal)).Edges:
            found.append((f"Face{i}", face))
    return found


def joint_normals(face, origin, normal, samples=7):
    """Points and unit surface normals of `face` along its intersection with the plane."""
    points, normals = [], []
    for edge in face.section(plane_face(face, origin, normal)).Edges:
        for t in np.linspace(edge.FirstParameter, edge.LastParameter, samples):
            p = edge.valueAt(t)
            uv = face.Surface.parameter(p)
            points.append(tuple(p))
            normals.append(tuple(face.normalAt(*uv)))
    return np.array(points, float), np.array(normals, float)
