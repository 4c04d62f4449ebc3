"""Oracles on FreeCAD shapes and meshes, independent of the code under test: OCCT (slice,
face maker, common, Volume, isValid, CenterOfMass), closed forms (A*d, Pappus), the closed
2-manifold check of a Mesh, and the real-parts matrix's measures. Each returns numbers;
the tests compare them."""
import numpy as np
from scipy.spatial import cKDTree

from ..features import fc

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

V = App.Vector


def section_area(shape, origin, normal):
    """Area of the shape's cross-section in the plane, from Shape.slice and a face maker."""
    n = V(*normal).normalize()
    wires = shape.slice(n, n.dot(V(*origin)))
    return Part.makeFace(wires, "Part::FaceMakerBullseye").Area


def slab_volume(shape, origin, normal, width):
    """Volume of the part between the plane and the plane `width` beyond it (a common)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    size = 4 * shape.BoundBox.DiagonalLength
    box = Part.makeBox(size, size, width, V(-size / 2, -size / 2, 0))
    box.Placement = App.Placement(V(*origin), App.Rotation(V(0, 0, 1), V(*n)))
    return shape.common(box).Volume


def mesh_section_area(mesh, origin, normal):
    """Shoelace area of the mesh's cross-section polylines (Mesh.crossSections)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross([0, 0, 1], n) if abs(n[2]) < 0.9 else np.cross([1, 0, 0], n)
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    total = 0.0
    for polyline in mesh.crossSections([(V(*origin), V(*n))])[0]:
        p = np.array([tuple(q) for q in polyline]) - origin
        x, y = p @ u, p @ w
        total += 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return abs(total)


def closed_manifold(mesh):
    """Every undirected edge used by exactly two facets, once in each direction."""
    _, facets = mesh.Topology
    f = np.array(facets)
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    _, counts = np.unique(undirected, axis=0, return_counts=True)
    _, dcounts = np.unique(directed, axis=0, return_counts=True)
    return bool(np.all(counts == 2) and np.all(dcounts == 1))


def section_area_centroid(shape, origin, normal):
    """Area and centroid of the solids' section at the plane: Shape.slice + a face maker."""
    n = V(*normal).normalize()
    area, moment = 0.0, np.zeros(3)
    for solid in shape.Solids:
        wires = solid.slice(n, n.dot(V(*origin)))
        if not wires:
            continue
        for face in Part.makeFace(wires, "Part::FaceMakerBullseye").Faces:
            area += face.Area
            moment += np.array(tuple(face.CenterOfMass)) * face.Area
    return area, (moment / area if area else None)


def half_spaces(shape, origin, normal):
    """Two prisms that cover `shape` on either side of the plane."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    size = 4 * shape.BoundBox.DiagonalLength + 4 * np.linalg.norm(origin)
    u = np.cross(n, [0, 0, 1] if abs(n[2]) < 0.9 else [1, 0, 0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    c = [np.asarray(origin) + size * (a * u + b * w)
         for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1), (1, 1))]
    face = Part.Face(Part.makePolygon([V(*p) for p in c]))
    return [face.extrude(V(*(sign * size * n))) for sign in (-1, 1)]


def volume_noise(shape, origin, normal):
    """OCCT's volume precision on `shape` here: |the two halves' volumes - the whole|."""
    halves = sum(shape.common(h).Volume for h in half_spaces(shape, origin, normal))
    return abs(halves - solid_volume(shape))


def surface_area(face, nodes=10):
    """Area of a natural (untrimmed) face: Gauss-Legendre on each knot span of its surface,
    |S_u x S_v| from OCCT's derivatives (OCCT's Face.Area is off by 5e-3 on a converted
    torus)."""
    surface = face.Surface
    u0, u1, v0, v1 = face.ParameterRange
    knots = (getattr(surface, "getUKnots", lambda: [])(), getattr(surface, "getVKnots",
                                                                   lambda: [])())
    us = sorted({u0, u1, *[k for k in knots[0] if u0 < k < u1]})
    vs = sorted({v0, v1, *[k for k in knots[1] if v0 < k < v1]})
    x, w = np.polynomial.legendre.leggauss(nodes)
    total = 0.0
    for ua, ub in zip(us, us[1:]):
        for va, vb in zip(vs, vs[1:]):
            for xi, wi in zip(x, w):
                u = (ua + ub) / 2 + xi * (ub - ua) / 2
                for xj, wj in zip(x, w):
                    v = (va + vb) / 2 + xj * (vb - va) / 2
                    n = surface.getDN(u, v, 1, 0).cross(surface.getDN(u, v, 0, 1))
                    total += wi * wj * n.Length * (ub - ua) * (vb - va) / 4
    return total


def solid_volume(shape):
    return sum(abs(s.Volume) for s in shape.Solids)


def closed_mesh(mesh):
    return mesh.CountFacets > 0 and mesh.isSolid() and not mesh.hasNonManifolds()


def rotation(point, direction, degrees):
    """4x4 rotation by `degrees` about the line (point, direction), written here with
    FreeCAD's Rotation (not the code's motion module)."""
    r = App.Rotation(V(*direction), float(degrees))
    m = np.eye(4)
    m[:3, :3] = np.array(r.toMatrix().A).reshape(4, 4)[:3, :3]
    m[:3, 3] = np.asarray(point, float) - m[:3, :3] @ np.asarray(point, float)
    return m


def translation(vec):
    m = np.eye(4)
    m[:3, 3] = vec
    return m


def apply(m, pts):
    return np.asarray(pts, float) @ m[:3, :3].T + m[:3, 3]


def solids_compound(shape):
    return Part.makeCompound(shape.Solids)


def section(shape, origin, normal):
    """(area, centroid, bounded by B-spline edges) of the solids' section in the plane,
    solid by solid (an assembly's solids may overlap): Shape.slice and a face maker where
    the slice gives closed wires of lines and circles; where it gives B-spline edges or open
    wires (OCCT's slice of a B-spline or revolved B-spline face can be off by 2e-4, or
    drop a piece), the volume of a thin slab about the plane cut out by a boolean common
    (V(h) / h, exact to O(h^2))."""
    n = V(*normal).normalize()
    area, moment, spline = 0.0, np.zeros(3), False
    for solid in shape.Solids:
        wires = solid.slice(n, n.dot(V(*origin)))
        if not wires:
            continue
        curved = any(type(e.Curve).__name__ in ("BSplineCurve", "BezierCurve", "OffsetCurve")
                     for w in wires for e in w.Edges if not e.Degenerated)
        spline = spline or curved
        if (curved or not all(w.isClosed() for w in wires) or _free_form_across(
                solid, origin, normal)) and not _face_in_plane(solid, origin, normal):
            a, c = slab_section(solid, origin, normal)
            area, moment = area + a, moment + c * a
            continue
        for face in Part.makeFace(wires, "Part::FaceMakerBullseye").Faces:
            area += face.Area
            moment += np.array(tuple(face.CenterOfMass)) * face.Area
    return area, (moment / area if area else None), spline


ELEMENTARY = ("Plane", "Cylinder", "Cone", "Sphere", "Toroid")


def _free_form_across(solid, origin, normal):
    """Does the plane cross a face that is not elementary (B-spline, revolved, extruded)?
    OCCT's slice of such faces may drop whole wires without leaving an open one."""
    n = np.asarray(normal, float)
    for face in solid.Faces:
        if type(face.Surface).__name__ in ELEMENTARY:
            continue
        bb = face.BoundBox
        corners = np.array([[x, y, z] for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
                            for z in (bb.ZMin, bb.ZMax)])
        s = (corners - origin) @ n
        if s.min() < 0 < s.max():
            return True
    return False


def _face_in_plane(solid, origin, normal, tol=1e-7):
    """Does a planar face of the solid lie in the plane? A slab about it would hold only
    the half of its thickness on the solid's side."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    for face in solid.Faces:
        if type(face.Surface).__name__ != "Plane":
            continue
        axis = np.array(tuple(face.Surface.Axis))
        if np.linalg.norm(np.cross(axis, n)) < 1e-9 and all(
                abs((np.array(tuple(v.Point)) - origin) @ n) < tol for v in face.Vertexes):
            return True
    return False


def slab_section(solid, origin, normal):
    """(area, centroid) of the section from the common of `solid` with the slab of
    thickness h = 1e-4 of its size centred on the plane."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    h = 1e-4 * solid.BoundBox.DiagonalLength
    size = 4 * solid.BoundBox.DiagonalLength + 2 * np.linalg.norm(
        np.array(tuple(solid.BoundBox.Center)) - origin)
    box = Part.makeBox(size, size, h, V(-size / 2, -size / 2, -h / 2))
    box.Placement = App.Placement(V(*origin), App.Rotation(V(0, 0, 1), V(*n)))
    pieces = solid.common(box).Solids
    volume = sum(p.Volume for p in pieces)
    if volume <= 0:
        return 0.0, np.zeros(3)
    centre = sum(np.array(tuple(p.CenterOfMass)) * p.Volume for p in pieces) / volume
    return volume / h, centre


def split_noise(shape, planes, motion=None):
    """OCCT's volume precision on this edit: |sum of the volumes of the pieces that
    generalFuse cuts at the planes - the volume of each solid|, summed (the split moves
    nothing, so all of it is integration error), plus, with `motion` (4x4), how much the
    volume of the pieces beyond the last plane changes when they are only moved by it
    (OCCT integrates moved B-spline faces differently). Also the OCCT floor: the split
    and a fuse of the pieces again."""
    size = 2 * shape.BoundBox.DiagonalLength
    tools = [big_square(o, n, size) for o, n in planes]
    last_origin, last_normal = (np.asarray(v, float) for v in planes[-1])
    noise = 0.0
    for solid in shape.Solids:
        pieces = solid.generalFuse(tools)[0].Solids
        noise += abs(sum(p.Volume for p in pieces) - solid.Volume)
        if len(pieces) > 1:
            pieces[0].fuse(pieces[1:])
        if motion is None:
            continue
        m = App.Matrix(*np.asarray(motion, float).ravel())
        for p in pieces:
            if (np.array(tuple(p.CenterOfMass)) - last_origin) @ last_normal > 0:
                noise += abs(p.transformed(m).Volume - p.Volume)
    return noise


def distance_to_axis(point, axis_point, axis_direction):
    a = np.asarray(axis_direction, float) / np.linalg.norm(axis_direction)
    d = np.asarray(point, float) - axis_point
    return float(np.linalg.norm(d - (d @ a) * a))


def shells_per_solid(shape):
    return sorted(len(s.Shells) for s in shape.Solids)


def loose_vertices(shape):
    """Points of the vertices of every top-level part outside the solids."""
    def loose(s):
        if s.ShapeType in ("Solid", "CompSolid"):
            return []
        if s.ShapeType == "Compound":
            return [p for c in s.childShapes() for p in loose(c)]
        return [s]
    pts = [tuple(v.Point) for p in loose(shape) for v in p.Vertexes]
    return np.array(pts, float).reshape(-1, 3)


def followed(before, after, origin, normal, motion, gap=0.0, tol=1e-6):
    """Worst distance from where each loose vertex away from the edit must be (kept before
    the plane, moved by `motion` beyond `gap`) to the result's loose vertices."""
    if not len(before):
        return 0.0
    s = (before - origin) @ normal
    expected = np.vstack([before[s < -tol], apply(motion, before[s > gap + tol])])
    if not len(expected):
        return 0.0
    if not len(after):
        return np.inf
    return float(cKDTree(after).query(expected)[0].max())


def away_parts(shape, origin, normal, gap, margin):
    """(kind, area, centre) of the faces and void shells wholly before the plane (-1) or
    wholly beyond `gap` (+1), by more than `margin`; with the side."""
    out = []
    for solid in shape.Solids:
        items = list(solid.Faces) + [sh for sh in solid.Shells[1:]] if len(solid.Shells) > 1 \
            else list(solid.Faces)
        for item in items:
            bb = item.BoundBox
            c = np.array([[x, y, z] for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
                          for z in (bb.ZMin, bb.ZMax)])
            s = (c - origin) @ normal
            side = -1 if s.max() < -margin else 1 if s.min() > gap + margin else 0
            if side:
                kind = "Shell" if item.ShapeType == "Shell" else type(item.Surface).__name__
                out.append((side, kind, item.Area, np.array(tuple(item.CenterOfMass))))
    return out


def unchanged_parts(before, result, motion, tol_pos, tol_area=1e-9):
    """(missing count, worst relative area error) of the faces and void shells away from the
    edit: each must be in the result with the same type and area, where `motion` puts it."""
    faces = [(type(f.Surface).__name__, f.Area, np.array(tuple(f.CenterOfMass)))
             for f in result.Faces]
    shells = [("Shell", sh.Area, np.array(tuple(sh.CenterOfMass)))
              for s in result.Solids for sh in s.Shells[1:]]
    cands = faces + shells
    tree = cKDTree(np.array([c for _, _, c in cands]))
    missing, worst = 0, 0.0
    for side, kind, area, centre in before:
        want = centre if side < 0 else apply(motion, centre[None])[0]
        best = None
        for i in tree.query_ball_point(want, tol_pos):
            k, a, _ = cands[i]
            if k == kind:
                err = abs(a - area) / area
                best = err if best is None else min(best, err)
        if best is None or best > tol_area:
            missing += 1
        else:
            worst = max(worst, best)
    return missing, worst


def big_square(origin, normal, size):
    """A square planar face at the plane, `size` across (the OCCT floor's splitting tool)."""
    n = np.asarray(normal, float)
    u = np.cross(n, [0, 0, 1] if abs(n[2]) < 0.9 else [1, 0, 0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    c = [origin + size * (a * u + b * w) for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1), (1, 1))]
    return Part.Face(Part.makePolygon([V(*p) for p in c]))


def load_shape(name):
    shape = Part.Shape()
    shape.read(fc.testdata(name))
    return shape
