"""OCCT operations on B-rep solids through Part: split at planes, sweep sections, join."""
import FreeCAD as App
import numpy as np
import Part
from scipy.spatial import cKDTree

from ..geometry.errors import DeformError
from ..geometry.sweep.defaults import extents as box_extents
from ..geometry.sweep.planes import frame
from .convert import vector  # noqa: F401  (re-exported for features)

TOL = 1e-7


def solids_of(shape, prop="Base", loose_allowed=False):
    """Oriented copies of the solids of a shape; a shape without any (unless it has loose
    faces or wires and `loose_allowed`) is bad input for `prop`.

    Copies, because OCCT's booleans raise the tolerances of the shapes they touch, and its
    face merge adds curves on the new faces to the edges it keeps; the Base is only read.
    Copies of the topology only: tolerances and those curves live there, while the curves
    and surfaces (shared, 40 % of a deep copy's time) are never changed in place.
    """
    solids = [oriented(s) for s in shape.Solids]
    if not solids and not (loose_allowed and loose_parts(shape)):
        raise DeformError(f"{prop} has no solid to deform; give {prop} a solid, a compound of "
                          f"solids, a mesh or a point cloud.", prop)
    return solids


def oriented(solid):
    """A copy of `solid` whose outer shell bounds material outward and whose inner (void)
    shells face the cavities: STEP files bring reversed solids and voids oriented as
    material, which booleans would hand back as separate solids."""
    volumes = shell_volumes(solid)
    outer = int(np.argmax(np.abs(volumes)))
    if all((v > 0) == (k == outer) for k, v in enumerate(volumes)):
        copy = solid.copy(False)
        _remember(copy, volumes)  # the same shells: their volumes are known
        return copy
    if len(volumes) == 1:
        return solid.reversed().copy(False)
    return solid_of_shells([sh.copy(False) for sh in solid.Shells]) or solid.copy(False)


_VOLUMES = []  # (shape, signed shell volumes) of recent solids, most recently used last


def shell_volumes(solid, remember=True):
    """Signed volume of each shell of `solid` (negative: it faces inward), remembered for
    the last few solids when `remember`: a Base is read at every recompute, and OCCT's
    volume of B-spline faces costs up to a second."""
    for entry in _VOLUMES:
        if entry[0].isEqual(solid):  # same orientation too
            _VOLUMES.remove(entry)  # the most recently used last
            _VOLUMES.append(entry)
            return entry[1]
    volumes = [sh.Volume for sh in solid.Shells]
    if remember:
        _remember(solid, volumes)
    return volumes


_BOXES = []  # (shape, BoundBox) of recent solids, most recently used last


def bound_box(shape):
    """shape.BoundBox, remembered for the last few shapes: a Base's box is asked for by
    several steps of every recompute, and OCCT computes it afresh each time (45 ms for
    996 faces). Only a shape's own box: a copy's differs from its original's (OCCT bounds
    a shape with a triangulation by it, one without by its poles: 6 mm apart on
    occt_Bottom), and the split then differs with the box's size."""
    for entry in _BOXES:
        if entry[0].isEqual(shape):
            _BOXES.remove(entry)
            _BOXES.append(entry)
            return entry[1]
    _BOXES.append((shape, shape.BoundBox))
    del _BOXES[:-16]
    return _BOXES[-1][1]


def _remember(solid, volumes):
    _VOLUMES.append((solid, volumes))  # holding the shape keeps its identity unique
    del _VOLUMES[:-24]  # a Base of 12 solids and their oriented copies


def solid_of_shells(shells):
    """One solid from closed shells: the largest bounds it, the others are its voids, each
    turned the way that makes it so; None when a smaller shell lies outside the largest
    (two bodies, not a body with voids)."""
    if len(shells) == 1:
        return Part.Solid(shells[0])  # Part.Solid orients a lone shell outward
    shells = sorted(shells, key=lambda sh: -abs(sh.Volume))
    turned = [sh if (sh.Volume > 0) == (k == 0) else sh.reversed()
              for k, sh in enumerate(shells)]
    body = Part.Solid(turned[0])
    if not all(body.isInside(sh.Vertexes[0].Point, TOL, False) for sh in turned[1:]):
        return None
    return Part.makeSolid(Part.makeCompound(turned))


def solids_volume(shape, remember=False):
    """The material volume of a shape's solids, whatever their shells' orientation: the
    outer shell's volume less its voids' (loose faces and wires have none). Read from the
    memory, written to it only when `remember`: a Base's solids are in it (`oriented`
    reads them at every recompute), a result is mostly measured once."""
    total = 0.0
    for solid in shape.Solids:
        volumes = sorted(np.abs(shell_volumes(solid, remember)), reverse=True)
        total += volumes[0] - sum(volumes[1:]) if volumes else 0.0
    return total


def loose_parts(shape):
    """Top-level shells, faces, wires, edges and vertices of `shape` outside its solids.

    Imported STEP files often carry such wireframes; they follow the deformation
    instead of being dropped.
    """
    if shape.ShapeType in ("Solid", "CompSolid"):
        return []
    if shape.ShapeType == "Compound":
        return [p for child in shape.childShapes() for p in loose_parts(child)]
    return [shape.copy()]  # booleans and sewing would raise the Base's own tolerances


def split_loose(parts, origin, normal, offsets):
    """Like split_zones, for loose parts: their pieces (edges, faces, vertices) per zone.

    Pieces wholly inside one zone are sorted by their bounding box; only those a plane
    crosses are split, each on its own (SplitAPI's boolean over a whole wireframe can drop
    pieces it need not touch).
    """
    zones = [[] for _ in range(len(offsets) + 1)]
    crossing = []
    for leaf in (leaf for part in parts for leaf in _leaves(part)):
        if leaf.ShapeType == "Vertex":
            s = float(np.dot(np.array(tuple(leaf.Point)) - origin, normal))
            zones[int(np.searchsorted(offsets, s))].append(leaf)
            continue
        lo, hi = extent(leaf, origin, normal)
        first, last = np.searchsorted(offsets, [lo - TOL, hi + TOL])
        if first == last:
            zones[int(first)].append(leaf)
        else:
            crossing.append(leaf)
    from BOPTools import SplitAPI  # FreeCAD's Part workbench: keeps only the pieces of `parts`
    for leaf in crossing:
        tools = [plane_face(leaf, origin + off * normal, normal) for off in offsets]
        for piece in _leaves(SplitAPI.slice(leaf, tools, "Split")):
            point = piece.Point if piece.ShapeType == "Vertex" else piece.CenterOfMass
            s = float(np.dot(np.array(tuple(point)) - origin, normal))
            zones[int(np.searchsorted(offsets, s))].append(piece)
    return zones


def _leaves(shape):
    if shape.ShapeType == "Compound":
        return [leaf for child in shape.childShapes() for leaf in _leaves(child)]
    return [shape]


def points_on_plane(shapes, origin, normal):
    """Vertices of `shapes` lying in the plane, each once."""
    found = []
    for shape in shapes:
        for v in shape.Vertexes:
            p = np.array(tuple(v.Point))
            if abs(np.dot(p - origin, normal)) < TOL and all(
                    np.linalg.norm(p - q) > TOL for q in found):
                found.append(p)
    return found


def split_sheet(pieces, origin, normal):
    """(faces, edges of those faces in the plane, other pieces): loose faces cut at a plane
    are swept by their cut edges, wires by their cut points."""
    faces = [p for p in pieces if p.ShapeType in ("Face", "Shell")]
    others = [p for p in pieces if p.ShapeType not in ("Face", "Shell")]
    edges = []
    for edge in (e for f in faces for e in f.Edges):
        points = np.array([tuple(v.Point) for v in edge.Vertexes] + [tuple(edge.valueAt(
            0.5 * (edge.FirstParameter + edge.LastParameter)))])
        if np.all(np.abs((points - origin) @ normal) < TOL) and not any(
                edge.isSame(e) for e in edges):
            edges.append(edge)
    return faces, edges, others


def sew(faces, tol=None):
    """A compound of `faces` (or shells) sewn (at `tol` where FreeCAD passes it on). OCCT's
    sewing projects onto each surface over its whole parameter range; on a surface swept
    along an unbounded hyperbola (or any unbounded curved one) that overflows ('Result of
    Cosh exceeds the maximum value'): such faces are then converted to B-splines over their
    own domain (exact: OCCT writes a conic as a rational B-spline) and all sewn again. A
    second failure raises OCCT's error."""
    args = () if tol is None else (tol,)
    sewn = Part.makeCompound(faces)
    try:
        sewn.sewShape(*args)
        return sewn
    except Part.OCCError:
        faces = [f for s in faces for f in s.Faces]
        if not any(map(_unbounded, faces)):
            raise
    sewn = Part.makeCompound([f.toNurbs().Faces[0] if _unbounded(f) else f for f in faces])
    sewn.sewShape(*args)
    return sewn


def _unbounded(face):
    """The face lies on a surface with an infinite parameter range that is not a plane,
    cylinder or cone (whose points grow linearly with it)."""
    surface = face.Surface
    return surface.TypeId not in ("Part::GeomPlane", "Part::GeomCylinder", "Part::GeomCone") \
        and max(abs(b) for b in surface.bounds()) >= 1e99


def sheets(pieces):
    """The face pieces sewn where they meet (a cut free face made whole again with the face
    swept across the gap), the other pieces as they are."""
    faces = [f for p in pieces if p.ShapeType in ("Face", "Shell") for f in p.Faces]
    if len(faces) < 2:
        return list(pieces)
    shells, free = shells_of(settled(sew(faces)))
    return shells + free + [p for p in pieces if p.ShapeType not in ("Face", "Shell")]


def shells_of(sewn):
    """(shells, faces in none) of a sewn compound."""
    in_shells = {f.hashCode() for sh in sewn.Shells for f in sh.Faces}
    return list(sewn.Shells), [f for f in sewn.Faces if f.hashCode() not in in_shells]


def closed_shells(sewn):
    """The closed shells of a sewn compound, or None unless every face is in one. A face
    closed on itself (a spherical void) comes back from sewing without a shell: it is one."""
    shells, free = shells_of(sewn)
    shells += [Part.Shell([f]) for f in free]
    return shells if shells and all(sh.isClosed() for sh in shells) else None


def swept_points(points, vec):
    """Straight edges swept by `points` along `vec`: the gap of a cut wireframe."""
    return [Part.makeLine(vector(p), vector(p + vec)) for p in points]


def extent(shape, origin, normal):
    """(min, max) signed distance of the shape's bounding-box corners to the plane."""
    low, high = _box_extents(_rows([bound_box(shape)]), origin, normal)
    return float(low[0]), float(high[0])


def plane_face(shape, origin, normal):
    """A square planar face at the plane, larger than the shape."""
    box = bound_box(shape)
    return square_face(origin, normal, box.DiagonalLength + np.linalg.norm(
        np.array(tuple(box.Center)) - origin) + 1.0)


def square_face(origin, normal, size):
    """The planar face of the square about `origin` across `normal`, 2 `size` wide."""
    u, v, _ = frame(normal)
    corners = [origin + size * (a * u + b * v) for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1), (1, 1))]
    return Part.Face(Part.makePolygon([vector(c) for c in corners]))


def split_zones(solid, origin, normal, offsets):
    """Split `solid` by the planes at `offsets` (ascending) along `normal`.

    Returns one list of solids per zone: zone 0 before the first plane, zone k between
    plane k-1 and plane k, the last zone beyond the last plane.
    """
    tools = [plane_face(solid, origin + off * normal, normal) for off in offsets]
    return split_by(solid, tools, lambda p: (p - origin) @ normal, offsets)


# the largest tolerance of an edge or vertex, x the solid's size, that a split is given:
# beyond it a file's tolerance is a mistake (OCCT's data/occ/solid.brep: a hole's exact
# circle 1.5708 mm, pi / 2, on a 240 mm part)
LOOSE = 1e-3


def tightened(solid, cap):
    """A copy of `solid` with the tolerances of its edges and vertices over `cap` lowered
    to that when the copy is valid (OCCT's check: the geometry meets within the lowered
    tolerances), else `solid`. OCCT's split honours a tolerance of 1.57 mm on a hole of
    radius 10 and gave pieces 1947 mm^3 (0.75 %) more than the part, and a Stretch
    through the hole 1686 mm^3 more than the section x Distance, Up-to-date."""
    out = solid.copy()
    out.limitTolerance(TOL, cap)
    return out if out.isValid() else solid


def split_by(solid, tools, offset, offsets):
    """Split `solid` with the tool shapes; zone of a piece by `offset(points)` vs `offsets`.

    A piece is classified at its vertices and edge midpoints off the tools: every point of
    a piece lies in the closure of its zone, so this holds for zones that are not convex.
    """
    cap = LOOSE * solid.BoundBox.DiagonalLength
    loose = solid.getTolerance(1) > cap       # (a tolerance over LOOSE x the size)
    pieces, _ = (tightened(solid, cap) if loose else solid).generalFuse(tools)
    if loose:
        lost = sum(p.Volume for p in pieces.Solids) - solid.Volume
        if abs(lost) > 1e-6 * abs(solid.Volume):
            raise DeformError(f"OCCT's split at the plane gives pieces {lost:+.4g} mm^3 off "
                              f"the Base's volume: the Base has tolerances up to "
                              f"{solid.getTolerance(1):.3g} mm, which the split cannot keep; "
                              f"move Plane off its loose edges, or repair the Base.", "Plane")
    zones = [[] for _ in range(len(offsets) + 1)]
    for piece in pieces.Solids:
        s = offset(np.array([tuple(v.Point) for v in piece.Vertexes]).reshape(-1, 3))
        away = np.min(np.abs(s[:, None] - np.asarray(offsets)[None, :]), axis=1)
        if not (away > TOL).any():  # the edge midpoints only where no vertex is off the tools
            s = np.r_[s, offset(np.array(
                [tuple(e.valueAt(0.5 * (e.FirstParameter + e.LastParameter)))
                 for e in piece.Edges]).reshape(-1, 3))]
            away = np.min(np.abs(s[:, None] - np.asarray(offsets)[None, :]), axis=1)
        if (away > TOL).any():
            # the point farthest from the tools: a vertex a few TOL from a plane may lie
            # on its other side (a sliver face ending at the plane, split 1.4e-7 off it)
            probe = s[np.argmax(away)]
        elif np.ptp(s) > TOL:  # a slab with every vertex and edge on two planes: between them
            probe = 0.5 * (s.min() + s.max())
        else:  # OCCT's centre of mass strays on thin pieces with curved faces
            probe = float(offset(np.array([tuple(piece.CenterOfMass)]))[0])
        zones[int(np.searchsorted(offsets, probe))].append(piece)
    return zones


def polyline_sheet(shape, surface, shift=0.0):
    """The faces of a PolylineSurface (moved `shift` along its normal), wide enough for `shape`."""
    size = shape.BoundBox.DiagonalLength + 1.0
    pts = surface.points + shift * surface.normal
    ends = surface.lateral_axis * size
    pts = np.vstack([pts[0] - ends, pts[1:-1], pts[-1] + ends]) if len(pts) > 2 else np.vstack(
        [pts[0] - ends, pts[-1] + ends])
    centre = np.array(tuple(shape.BoundBox.Center))
    e = surface.extrusion * (size + abs((centre - pts[0]) @ surface.extrusion))
    faces = [Part.Face(Part.makePolygon([vector(a - e), vector(b - e), vector(b + e),
                                         vector(a + e), vector(a - e)]))
             for a, b in zip(pts[:-1], pts[1:])]
    return Part.Shell(faces)


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
            # within a vertex's own tolerance: OCCT's split snaps a plane that close to a
            # face of the part onto it
            if all(abs(np.dot(np.array(tuple(v.Point)) - origin, normal)) < max(TOL, v.Tolerance)
                   for v in face.Vertexes):
                found.append(face)
    return found


def section_faces(beyond, origin, normal):
    """The section just beyond the plane that an edit sweeps or extrudes: the faces of the
    `beyond` pieces (the zone after the plane) lying in it, turned to face along the
    normal as the near pieces' cut faces do (a face shared with a near piece is that very
    face). A face of the part itself in the plane with nothing beyond it (a step) bounds
    the near side only and is left out; one that bounds the far side (an overhang) is in:
    the section is the material the moving side starts from, as for a mesh's vertices."""
    return [f.reversed() for f in faces_on_plane(beyond, origin, normal)]


def shared_section(near, beyond, origin, normal):
    """The part of the section just beyond the plane that the near pieces share (the faces
    a loft from the near part can start from; section_faces with the overhangs left out)."""
    ours = _face_codes(near)
    return [f for f in section_faces(beyond, origin, normal) if f.hashCode() in ours]


def all_shared(faces, pieces):
    """Whether every face is one of the pieces' faces (a section the split made, not a
    face of the part itself lying in the plane)."""
    theirs = _face_codes(pieces)
    return all(f.hashCode() in theirs for f in faces)


def _face_codes(pieces):
    return {f.hashCode() for s in pieces for f in s.Faces}


def faces_on_surface(solids, surface):
    """Faces of `solids` lying on a PolylineSurface (the section faces a Case 3 split made)."""
    return [face for solid in solids for face in solid.Faces
            if isinstance(face.Surface, Part.Plane) and np.all(np.abs(surface.offset(
                np.array([tuple(v.Point) for v in face.Vertexes]))) < TOL)]


def translated(solids, vec):
    return [s.translated(vector(vec)) for s in solids]


def extruded(faces, vec):
    """The prisms swept by the faces along `vec`: an exact extrusion, planes stay planes."""
    return [f.extrude(vector(vec)) for f in faces]


def is_prismatic(solids, origin, normal, gap, samples=5):
    """True if every face of `solids` but the caps in the two planes is parallel to `normal`.

    The region between the planes then has one constant cross-section.
    """
    caps = (faces_on_plane(solids, origin, normal)
            + faces_on_plane(solids, origin + gap * normal, normal))
    grid = np.linspace(0.1, 0.9, samples)
    for face in (f for s in solids for f in s.Faces):
        if any(face.isSame(c) for c in caps):
            continue
        u0, u1, v0, v1 = face.ParameterRange
        for a in grid:
            for b in grid:
                n = face.normalAt(u0 + a * (u1 - u0), v0 + b * (v1 - v0))
                if abs(np.dot(np.array(tuple(n)), normal)) > 1e-9:
                    return False
    return True


def on_planes(planes):
    """A joint test for `join`: are all these points on one of the (origin, normal) planes?
    Its `planes` let joint_vertices test many points at once."""
    def on_surface(pts):
        return any(np.all(np.abs((pts - o) @ n) < TOL) for o, n in planes)
    on_surface.planes = planes
    return on_surface


def joint_vertices(shape, on_surface):
    """hashCodes of the vertices of `shape` that lie on a joint."""
    verts = shape.Vertexes
    pts = np.array([tuple(v.Point) for v in verts]).reshape(-1, 3)
    planes = getattr(on_surface, "planes", None)
    if planes is None:
        mask = [on_surface(p[None]) for p in pts]
    else:
        mask = np.zeros(len(pts), bool)
        for o, n in planes:
            mask |= np.abs((pts - o) @ n) < TOL
    return {v.hashCode() for v, m in zip(verts, mask) if m}


def touching(joint):
    """A test `meets(sub)`: has the sub-shape a vertex whose hashCode is in `joint`?"""
    def meets(sub):
        return any(v.hashCode() in joint for v in sub.Vertexes)
    return meets


def _replaced(solid, gone, new):
    """`solid` with the faces `gone` replaced by the faces `new` (BRepTools_ReShape: no
    search over the rest of it), or None where OCCT refuses."""
    try:
        out = solid.removeShape(gone[1:]) if len(gone) > 1 else solid
        return out.replaceShape([(gone[0], Part.makeCompound(new))])
    except Part.OCCError:
        return None


def join(solids, joints, prop="Plane"):
    """One valid solid from the pieces, merging faces only across the joints.

    `joints` are (origin, normal) planes, or a test `joints(points) -> bool` saying whether
    points lie on a joint surface. The pieces meet on faces that coincide by construction,
    so their other faces are sewn with those left out (no boolean); a boolean fuse is the
    fallback when that does not give a valid solid. Faces the split cut at the joints are
    merged again (no seams), while every edge and vertex elsewhere, including the Base's
    own, is kept. `prop` is the input a failure is blamed on.
    """
    on_surface = joints if callable(joints) else on_planes(joints)
    if len(solids) > 1:
        faces = _unshared_faces(solids, on_surface)
        solid = _glued(solids, faces, on_surface)  # merged and checked
        if solid is not None:
            return solid
        for sew in (lambda: _sewn_pieces(solids, faces), lambda: _sewn(faces)):
            sewn = sew()
            if sewn is not None:
                solid, _ = _merged(sewn, on_surface)
                if solid is not None:
                    return solid
    try:
        fused = solids[0] if len(solids) == 1 else solids[0].fuse(solids[1:])
    except (Part.OCCError, RuntimeError, ValueError):  # a tangent contact: "Multi fuse
        # failed" (FreeCAD 0.20), "Null shape" (1.1)
        raise DeformError(f"OCCT could not join the pieces into one solid (its fuse failed); "
                          f"move {prop} a little, off the Base's edges and vertices.",
                          prop) from None
    solid, failure = _merged(fused, on_surface)
    if solid is None:
        raise DeformError(f"OCCT could not join the pieces into one valid solid ({failure}); "
                          f"move {prop} a little, off the Base's edges and vertices.", prop)
    return solid


def glue(pieces, faces, joints):
    """The pieces joined into one solid of `faces` where they meet at the (origin, normal)
    `joints`, merged there and checked (see _glued), or None: for pieces whose faces at
    the joints are known, e.g. a loft's sides (a compound of faces, not a first piece)
    between the near and far parts."""
    return _glued(pieces, faces, on_planes(joints))


def _unshared_faces(solids, on_surface):
    """The faces of the pieces but those on a joint that another piece also has there
    (same centre of mass and area, to 1e-9 of the pieces' size). With joint planes only
    the faces whose box reaches a plane (to 1e-3 of the size) are tested, each first by its
    outer wire: a face with hundreds of holes across the joint has that many vertices."""
    size = max(s.BoundBox.DiagonalLength for s in solids)
    planes = getattr(on_surface, "planes", None)

    def key(face):
        c = face.CenterOfMass
        return np.array([c.x / size, c.y / size, c.z / size, face.Area / size ** 2])

    def candidates(faces):
        if planes is None:
            return range(len(faces))
        boxes, near = _boxes(faces), np.zeros(len(faces), bool)
        for o, n in planes:
            lo, hi = _box_extents(boxes, o, n)
            near |= (lo < 1e-3 * size) & (hi > -1e-3 * size)
        return np.flatnonzero(near)

    def on_joint(shape):
        return on_surface(np.array([tuple(v.Point) for v in shape.Vertexes]))

    pieces = [s.Faces for s in solids]
    found = [(i, m) for i, fs in enumerate(pieces) for m in candidates(fs)
             if on_joint(fs[m].OuterWire) and on_joint(fs[m])]
    shared = set()
    if found:  # pairs of keys within 1e-9 in every component, of faces of two pieces
        tree = cKDTree(np.array([key(pieces[i][m]) for i, m in found]))
        for a, b in tree.query_pairs(1e-9, p=np.inf):
            if found[a][0] != found[b][0]:
                shared |= {found[a], found[b]}
    return [f for i, fs in enumerate(pieces) for m, f in enumerate(fs) if (i, m) not in shared]


def _glued(solids, faces, on_surface):
    """The pieces joined into one solid of `faces` (theirs but those they meet on), the
    faces split at the joints merged and checked; None where this does not work.

    Only the faces with a vertex on a joint are sewn and merged (without their holes clear
    of the joint, put back after); sewing and merging keep the edges these share with the
    pieces' other faces, so they go into the first piece in place of its own faces at the
    joints, with the other pieces' faces (BRepTools_ReShape): no search over the whole part.
    Pieces with voids are left to the full sewing. The sewn faces must keep their
    orientation: an edge they share has opposite orientations in its two faces, and an edge
    they share with the rest the one it had before.
    """
    if any(s.ShapeType == "Solid" and len(s.Shells) != 1 for s in solids):
        return None
    keep = {f.hashCode() for f in faces}
    joint = set().union(*(joint_vertices(s, on_surface) for s in solids))
    meets = touching(joint)  # sees the vertices sewing adds to `joint` below
    touched = [f for f in faces if meets(f)]
    mine = {f.hashCode() for f in touched}
    reduced, holes = _clear_holes_out(touched, meets)
    before = joint_edges(reduced, joint)
    sewn = Part.makeCompound(reduced)
    try:
        sewn.sewShape()
    except Part.OCCError:
        return None
    if len(sewn.Faces) != len(touched) or not _kept_orientation(reduced, sewn.Faces):
        return None
    joint |= joint_vertices(sewn, on_surface)  # sewing made new vertices at the joints
    merged = _unified(sewn.Faces, joint, on_surface)
    if merged is None or not _holes_back(reduced, holes, merged, mine):
        return None
    # sewing and merging hand back as they were the faces they had nothing to do with:
    # those of the first piece stay in it; no face may be both replaced and replacing
    host = solids[0]
    own = {f.hashCode() for f in host.Faces}
    stays = {f.hashCode() for f in merged} & own
    gone = [f for f in host.Faces if f.hashCode() not in stays and (
        f.hashCode() not in keep or f.hashCode() in mine)]
    new = [f for f in merged if f.hashCode() not in mine]
    others = keep - mine - own
    added = [f for f in merged if f.hashCode() not in own] + [
        f for s in solids[1:] for f in s.Faces if f.hashCode() in others]
    if not gone or not added:
        return None
    out = _replaced(host, gone, added)
    if out is None or out.ShapeType != "Solid" or len(out.Faces) != len(faces) - len(
            touched) + len(merged) or not _valid_faces(new, meets) or not _manifold(
            merged, meets) or not _shells_valid(out):
        return None
    return _settled_at_joints(kept_tolerances(out, new, before, joint), on_surface, merged)


def _kept_orientation(before, after):
    """Whether the sewn faces `after` are oriented as `before`: each edge of theirs that
    `before` had is used as often in each orientation, and each new one once each way."""
    def uses(faces):
        found = {}
        for face in faces:
            for edge in (e for w in face.Wires for e in w.OrderedEdges if not e.Degenerated):
                found.setdefault(edge.hashCode(), []).append(edge.Orientation)
        return found

    old, new = uses(before), uses(after)
    return all(sorted(o) == sorted(old[h]) if h in old else sorted(o) == ["Forward", "Reversed"]
               for h, o in new.items())


def _sewn_pieces(solids, faces):
    """The solid the pieces close when sewn with only `faces` of theirs, or None. Each piece
    goes to the sewing as its shells, the faces left out removed: sewing then has only the
    open edges at the joints to match (a third of the time of sewing loose faces on a
    1000-face plate)."""
    keep = {f.hashCode() for f in faces}
    shells = []
    for solid in solids:
        drop = [f for f in solid.Faces if f.hashCode() not in keep]
        try:
            shells += (solid.removeShape(drop) if drop else solid).Shells
        except Part.OCCError:
            return None
    return _sewn(shells)


def _sewn(faces, retry=False):
    """The solid the faces (or shells) close when sewn, or None when they do not close one
    (the callers then fuse or map the pieces). OCCT's own sewing; `sew`'s second try on
    B-splines only where `retry` (the last join before a refusal): taken first, it gave
    occt_Bottom stretched at 30 % a solid 1.5e-3 of the volume off, where the fuse after
    a failed sewing is right."""
    sewn = Part.makeCompound(faces)
    try:
        if retry:
            sewn = sew(faces)
        else:
            sewn.sewShape()
    except Part.OCCError:  # OCCT's sewing fails on some degenerate B-spline faces, and
        return None        # on faces swept along a whole hyperbola (see sew)
    shells = closed_shells(sewn)
    return None if shells is None else solid_of_shells(shells)


def join_faces(faces, joints, prop):
    """Sew faces that close a solid (no boolean): for swept lofts, whose end profiles are
    the cut faces themselves, where OCCT's fuse of B-spline lofts is slow or drops pieces."""
    sewn = _sewn(faces, retry=True)
    if sewn is None:
        raise DeformError(f"The swept faces do not close a solid; change {prop}.", prop)
    return merge_joints(sewn, joints, prop)


def merge_joints(solid, joints, prop):
    """A solid (sewn already) with its faces split at the joints merged and checked there,
    as join_faces gives it; a DeformError blaming `prop` when that is not valid."""
    merged, failure = _merged(solid, joints if callable(joints) else on_planes(joints))
    if merged is None:
        raise DeformError(f"The swept faces do not make one valid solid ({failure}); change "
                          f"{prop}.", prop)
    return merged


def _merged(fused, on_surface):
    """(the solid with the split faces merged across the joints, None) or (None, what
    failed)."""
    from Part import ShapeUpgrade

    def on_joint(sub):
        return on_surface(np.array([tuple(v.Point) for v in sub.Vertexes]))

    if len(fused.Solids) != 1:
        return None, f"they make {len(fused.Solids)} solids"
    solid = _merged_at_joints(fused.Solids[0], on_surface)
    if solid is not None:
        return _settled_at_joints(solid, on_surface), None
    unify = ShapeUpgrade.UnifySameDomain(fused, True, True, False)
    unify.keepShapes([e for e in fused.Edges if not on_joint(e)]
                     + [v for v in fused.Vertexes if not on_joint(v)])
    unify.build()
    # OCCT's face merge can nest wires wrongly on folded joints; then merge all, or none.
    # Those two change faces anywhere (removeSplitter merged a void's faces into an
    # invalid solid whose faces and shells each pass): all of their result is checked.
    for result, whole in ((unify.shape, False), (fused.removeSplitter, True),
                          (lambda: fused, True)):
        try:
            shape = result()
        except Part.OCCError:  # removeSplitter raises where it cannot merge
            continue
        if len(shape.Solids) == 1 and _valid_at_joints(shape, on_surface) and (
                not whole or shape.isValid()):
            return _settled_at_joints(shape.Solids[0], on_surface), None
    return None, "the faces at a joint fail OCCT's check"


def joint_edges(faces, joint):
    """The edges of `faces` (each once) with a vertex whose hashCode is in `joint`."""
    out = {}
    for face in faces:
        for edge in face.Edges:
            if not edge.Degenerated and any(v.hashCode() in joint for v in edge.Vertexes):
                out.setdefault(edge.hashCode(), edge)
    return list(out.values())


def kept_tolerances(shape, faces, before, joint):
    """`shape`, or a copy of it with each edge that reaches a joint (a vertex's hashCode in
    `joint`) raised to the largest tolerance of the edges in `before` it was sewn from
    (the same ends, its midpoint within both tolerances) where that is over twice its
    own. Sewing sets the tolerance of every edge of the faces it sews from its own
    samples: the far joint of a stretch kept
    1.2e-7 where the split had given the same cut edge 8.4e-6 at the near one, and a face
    tangent to the cut face there (OCCT's Pump_TopCover: a sphere tangent to a B-spline
    face), touching the swept side only at a vertex, grazes it beyond that (OCCT's BOP
    check: SelfIntersect). `faces`: those of `shape` sewing made; `before`: the pieces'
    edges reaching the joints, as sewing got them."""
    before = [e for e in before if e.Tolerance > 2.0 * TOL]  # none is below TOL
    if not before:
        return shape
    ends = np.array([[tuple(e.valueAt(e.FirstParameter)), tuple(e.valueAt(e.LastParameter))]
                     for e in before], float)
    tols = np.array([e.Tolerance for e in before])
    own = {e.hashCode() for e in before}
    raise_to = {}
    for edge in joint_edges(faces, joint):
        if edge.hashCode() in own or 2.0 * edge.Tolerance >= tols.max():
            continue
        a, b = (np.array(tuple(edge.valueAt(t))) for t in (edge.FirstParameter,
                                                            edge.LastParameter))
        slack = tols + edge.Tolerance + TOL
        same = np.minimum(np.maximum(np.linalg.norm(ends[:, 0] - a, axis=1),
                                     np.linalg.norm(ends[:, 1] - b, axis=1)),
                          np.maximum(np.linalg.norm(ends[:, 0] - b, axis=1),
                                     np.linalg.norm(ends[:, 1] - a, axis=1))) <= slack
        same &= tols > 2.0 * edge.Tolerance   # far more than sewing left it
        for k in np.flatnonzero(same):
            old = before[k]
            mid = old.valueAt(0.5 * (old.FirstParameter + old.LastParameter))
            if edge.distToShape(Part.Vertex(mid))[0] <= slack[k]:
                h = edge.hashCode()
                raise_to[h] = max(raise_to.get(h, 0.0), tols[k])
    if not raise_to:
        return shape
    index = {e.hashCode(): k for k, e in enumerate(shape.Edges)}
    out = shape.copy()
    edges = out.Edges
    for h, tol in raise_to.items():
        edges[index[h]].limitTolerance(tol)
    return out


def _settled_at_joints(solid, on_surface, at_joints=None):
    """The solid with the tolerance of each edge reaching a joint raised to twice the gap
    between its 3D curve and its pcurves, on a copy when one must rise (settled), and
    raised where two faces touch tangentially at a joint vertex (tangent_touches_settled;
    not when `at_joints`, all the faces with a vertex on a joint, has no free-form one)."""
    solid = settled(solid, joint_vertices(solid, on_surface))
    if at_joints is not None and all(_surface_kind(f) != FREE for f in at_joints):
        return solid
    return tangent_touches_settled(solid, on_surface, edges=False)


def passes_bop_check(shape):
    """OCCT's BOP check (Shape.check(True)) of a shape finds nothing (a few tenths of a
    second on a refit face)."""
    return not bop_errors(shape)


def bop_errors(shape):
    """The kinds of error OCCT's BOP check finds in a shape ({"SelfIntersect",
    "GeomAbs_C0", "InvalidCurveOnSurface", ...}; empty when it passes)."""
    return set(bop_report(shape))


def bop_report(shape):
    """The kind of each error OCCT's BOP check finds in a shape, one per faulty sub-shape,
    read from FreeCAD's report ("Error in Vertex: BOPAlgo SelfIntersect", one line each):
    ["SelfIntersect", "SelfIntersect", "TooSmallEdge"], ["unknown"] for a report without
    such lines, [] when the check passes."""
    try:
        shape.check(True)
    except ValueError as report:  # FreeCAD's report of the check's findings
        return [line.split("BOPAlgo", 1)[1].strip(" _") for line in str(report).splitlines()
                if "BOPAlgo" in line] or ["unknown"]
    return []


def settled(shape, joint=None):
    """`shape`, or a copy of it with the tolerance of each edge (each with a vertex in
    `joint`, hashCodes, when given) raised to twice the gap between its 3D curve and its
    pcurves (bspline.pcurve_gaps) where that is more: sewing sets a merged edge's
    tolerance from its own samples, below the gap of a pcurve OCCT's split approximated
    (a sphere cut off its axis: 1.246e-7 against 1.234e-7; a cut B-spline sheet: 9.3e-5
    against 4.6e-5), and so it does for every edge of the faces it sews, and merging the
    faces across a joint gives those from the joint to a fillet's end new pcurves (4.97e-6
    for a gap of 5.1e-6 on a filleted tee); OCCT's BOP check and booleans reject such an
    edge. A copy, so that edges shared with the Base are never changed."""
    from .bspline import pcurve_gaps
    index = {e.hashCode(): k for k, e in enumerate(shape.Edges)}
    low = {}
    def which(edge):
        return joint is None or any(v.hashCode() in joint for v in edge.Vertexes)

    for face in shape.Faces:
        if joint is not None and not any(v.hashCode() in joint for v in face.Vertexes):
            continue
        for edge, gap in pcurve_gaps(face, which=which):
            if np.isfinite(gap) and 2.0 * gap > edge.Tolerance:
                k = index[edge.hashCode()]
                low[k] = max(low.get(k, 0.0), 2.0 * gap)
    if not low:
        return shape
    out = shape.copy()
    edges = out.Edges
    for k, tol in low.items():
        edges[k].limitTolerance(tol)
    return out


def _merged_at_joints(solid, on_surface, many_wires=8):
    """`solid` with the faces split at the joints merged, or None where this fails its check.

    Only the faces with a vertex on a joint go through OCCT's UnifySameDomain, and of those
    only the wires that meet a joint (a face's other holes are put back into the face it
    merged into): merging a whole 1000-face solid, or faces with hundreds of holes, costs
    several times the split. The merged faces replace theirs in the solid; the rest of it
    (the Base's own faces, moved or not) is untouched.
    """
    joint = joint_vertices(solid, on_surface)
    meets = touching(joint)
    touched = [f for f in solid.Faces if meets(f)]
    if not touched:
        return solid if _valid_at_joints(solid, on_surface) else None
    reduced, holes = _clear_holes_out(touched, meets, many_wires)
    before = {f.hashCode() for f in touched}
    merged = _unified(reduced, joint, on_surface)
    if merged is None or not _holes_back(reduced, holes, merged, before):
        return None
    after = {f.hashCode() for f in merged}
    gone = [f for f in touched if f.hashCode() not in after]
    new = [f for f in merged if f.hashCode() not in before]
    out = _replaced(solid, gone, new) if gone and new else solid  # else nothing merged
    if out is None or out.ShapeType != "Solid" or \
            len(out.Faces) != len(solid.Faces) - len(gone) + len(new):
        return None
    if not (_valid_faces(merged, meets, many_wires) and _manifold(merged, meets)
            and _shells_valid(out)):
        return None
    return out


def _unified(faces, joint, on_surface):
    """`faces` merged across the edges that lie on a joint (OCCT's UnifySameDomain; every
    other edge and vertex kept as it is, the same shapes), or None."""
    from Part import ShapeUpgrade
    compound = Part.makeCompound(faces)
    unify = ShapeUpgrade.UnifySameDomain(compound, True, True, False)
    unify.setSafeInputMode(False)  # keep the edges the faces share with the rest
    unify.keepShapes([e for e in compound.Edges if not any(
        v.hashCode() in joint for v in e.Vertexes) or not on_surface(
        np.array([tuple(v.Point) for v in e.Vertexes]))]
        + [v for v in compound.Vertexes if v.hashCode() not in joint])
    try:
        unify.build()
        return unify.shape().Faces
    except Part.OCCError:
        return None


def _clear_holes_out(faces, meets, many_wires=8):
    """(faces, holes taken out of each): a face with more than `many_wires` wires without
    its holes that do not `meet` a joint (new faces; the others are given back as they
    are). Sewing and merging a face with hundreds of holes work on every one of them."""
    reduced, holes = [], []
    for face in faces:
        drop = []
        if len(face.Wires) > many_wires:
            outer = face.OuterWire
            drop = [w for w in face.Wires if not w.isSame(outer) and not meets(w)]
        reduced.append(face.removeShape(drop) if drop else face)
        holes.append(drop)
    return reduced, holes


def _holes_back(reduced, holes, faces, frozen=()):
    """Put each face's holes back into the one of `faces` (made from `reduced` by sewing
    or merging, which keep the edges they do not touch) that kept the most of its edges;
    False where that is not one face, or one whose hashCode is in `frozen` (a face handed
    back as it was, still part of a piece: it is changed in place)."""
    edges = [{e.hashCode() for e in f.Edges} for f in faces]
    for face, drop in zip(reduced, holes):
        if drop:
            own = {e.hashCode() for e in face.Edges}
            shared = [len(own & e) for e in edges]
            best = int(np.argmax(shared))
            if shared[best] == 0 or shared.count(shared[best]) > 1 or \
                    faces[best].hashCode() in frozen:
                return False
            faces[best].cutHoles(drop)
    return True


def _valid_faces(faces, meets, many_wires=8):
    """OCCT's check of faces that meet a joint; on a face with many holes only of its outer
    wire and the wires that meet the joint (BRepCheck of the whole face grows with the
    square of its holes)."""
    for face in faces:
        if len(face.Wires) <= many_wires:
            ok = face.isValid()
        else:
            outer = face.OuterWire
            ok = all(w.isValid() for w in face.Wires if meets(w) or w.isSame(outer))
        if not ok:
            return False
    return True


def _manifold(faces, meets):
    """Whether no edge at a joint is used by more than two of `faces` (every face of the
    solid that meets the joint): where both pieces kept the face they meet on, its edges
    have four, which neither the faces' check nor the shells' closure sees. (Faces, not
    uses: a seam is one edge used twice by one face, and FreeCAD 1.1 lists it once.)"""
    users = {}
    for k, face in enumerate(faces):
        for edge in face.Edges:
            if not edge.Degenerated and meets(edge):
                users.setdefault(edge.hashCode(), set()).add(k)
    return all(len(u) <= 2 for u in users.values())


def _shells_valid(shape, small_shell=64):
    """Every shell closed and of one piece, and every small one (a void's) valid as a whole
    (OCCT's check of a 1000-face shell takes seconds)."""
    shells = [sh for s in shape.Solids for sh in s.Shells]
    return all(sh.isClosed() for sh in shells) and all(
        sh.isValid() if len(sh.Faces) <= small_shell else _connected(sh) for sh in shells)


def _connected(shell):
    """Whether the faces of `shell` are one piece through their edges: two pieces that
    each close themselves (glued where no face joins them) make a closed, manifold shell
    that is not one."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    pairs = np.array([(i, e.hashCode()) for i, f in enumerate(shell.Faces) for e in f.Edges])
    _, edge = np.unique(pairs[:, 1], return_inverse=True)
    faces = len(shell.Faces)
    count = faces + int(edge.max()) + 1
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], faces + edge)), shape=(count, count))
    return connected_components(graph, directed=False)[0] == 1


def _valid_at_joints(shape, on_surface, many_wires=8, small_shell=64):
    """OCCT's check of what the edit made: closed shells, the faces that meet a joint, and
    every small shell whole (a void's: merging the faces across the joint took away the
    vertex where Plane touched a sphere's seam, and left that face unorientable).

    The rest of the solid is the Base's own, unchanged. On a face with many holes only
    the wires that meet a joint are checked: BRepCheck of the whole face grows with the
    square of its holes and would cost far more than the edit.
    """
    meets = touching(joint_vertices(shape, on_surface))
    faces = [f for f in shape.Faces if meets(f)]
    return _valid_faces(faces, meets, many_wires) and _manifold(faces, meets) and \
        _shells_valid(shape, small_shell)


def transformed(shapes, matrix):
    """Copies of `shapes` moved by a rigid 4x4 `matrix` (analytic surfaces stay analytic)."""
    m = App.Matrix(*np.asarray(matrix, float).ravel())
    return [s.transformed(m) for s in shapes]


def revolved(faces, axis_point, axis_direction, angle):
    """The solids swept by the faces turning by `angle` (radians) about the axis: exact."""
    return [in_period(f).revolve(vector(axis_point), vector(axis_direction),
                                 float(np.degrees(angle))) for f in faces]


def in_period(shape):
    """A planar face or an edge with its circle and ellipse edges trimmed within their first
    period. A split can leave an arc at parameters shifted by 2 pi (7.99 to 10.86 on a real
    file); the surface of revolution OCCT sweeps from it keeps the shifted range, and OCCT's
    own slice and booleans then miss that face (a bent part's section lost a region)."""
    def edge(e):
        if e.Degenerated or e.Curve.TypeId not in ("Part::GeomCircle", "Part::GeomEllipse"):
            return e
        k = np.floor(e.FirstParameter / (2 * np.pi) + 1e-12)
        if k == 0:
            return e
        new = e.Curve.toShape(e.FirstParameter - 2 * np.pi * k, e.LastParameter - 2 * np.pi * k)
        new.fixTolerance(e.Tolerance)
        if e.Orientation == "Reversed":
            new.reverse()
        return new

    if shape.ShapeType == "Edge":
        return edge(shape)
    if shape.ShapeType != "Face" or shape.Surface.TypeId != "Part::GeomPlane" or all(
            edge(e) is e for e in shape.Edges):
        return shape
    wires = [Part.Wire([edge(e) for e in w.OrderedEdges]) for w in shape.Wires]
    face = Part.makeFace(wires, "Part::FaceMakerBullseye")
    if len(face.Faces) != 1 or not face.isValid() or \
            abs(face.Area - shape.Area) > 1e-9 * max(shape.Area, 1.0):
        return shape
    face = face.Faces[0]
    normal = np.array(tuple(shape.normalAt(*shape.Surface.parameter(shape.CenterOfMass))))
    if normal @ np.array(tuple(face.normalAt(*face.Surface.parameter(face.CenterOfMass)))) < 0:
        face.reverse()
    return face


def arc(point, axis_point, axis_direction, angle):
    """The circular edge a point sweeps turning by `angle` (radians) about the axis."""
    face_free = Part.Vertex(vector(point))
    return face_free.revolve(vector(axis_point), vector(axis_direction),
                             float(np.degrees(angle)))


def sample_points(face, per_edge=9):
    """Points along the boundary of `face` (for checks on the section)."""
    return np.array([tuple(p) for e in face.Edges for p in e.discretize(per_edge)])


def check_apart(near, moved, prop, plane=None):
    """The moved part must not overlap the part that stays (an OCCT boolean check).

    `plane` (origin, normal): the near pieces lie behind it (they come from the split
    there), so a moved piece whose box lies beyond it cannot overlap them; nor can two
    pieces whose boxes are apart. Only the others go through the boolean.
    """
    for b in moved:
        if plane is not None and extent(b, *plane)[0] >= -TOL:
            continue
        for a in near:
            if not a.BoundBox.intersect(b.BoundBox):
                continue
            overlap = a.common(b).Volume
            if overlap > 1e-9 * max(a.Volume, b.Volume):
                raise DeformError(f"The moved or swept part overlaps the part that stays "
                                  f"({overlap:.6g} mm^3); change {prop}.", prop)


def projected(faces, origin, normal, placement):
    """The planar faces projected onto the XY plane of `placement` along its Z: the paper's
    f1', the section seen across the path. Faces already across it are returned as they are.
    """
    z, p = placement[:3, 2], placement[:3, 3]
    if np.linalg.norm(np.cross(z, normal)) < 1e-12:
        return faces
    # on the section's plane this is the orthogonal projection; off it, invertible
    lin = np.eye(3) - np.outer(z, z) + np.outer(z, normal)
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = lin, p - lin @ p
    return [f.transformGeometry(App.Matrix(*m.ravel())) for f in faces]


def loft_sides(profiles, prop="Samples"):
    """The side faces of the lofts of every wire through the K profiles (no caps)."""
    _check_profiles(profiles, prop)
    return [f for k in range(len(profiles[0])) for i in range(len(profiles[0][k].Wires))
            for f in Part.makeLoft([p[k].Wires[i] for p in profiles], False, False).Faces]


def _check_profiles(profiles, prop):
    shapes = {tuple(len(w.Edges) for f in p for w in f.Wires) for p in profiles}
    if len(shapes) > 1:
        raise DeformError("The cross-section changes its outline between Plane and Plane2, so no "
                          "loft can keep it; move Plane2 (or Plane) so the region between them "
                          "has one outline.", "Plane2")


def crossing_faces(shape, origin, normal):
    """(name, face, section edges) of the faces of `shape` the plane cuts, in face order."""
    faces = shape.Faces
    lo, hi = extents(faces, origin, normal)
    found = []
    for i in np.flatnonzero((lo < -TOL) & (hi > TOL)):
        face = faces[i]
        edges = [e for w in _near_wires(face, origin, normal).slice(
            vector(normal), float(np.dot(origin, normal))) for e in w.Edges]
        if edges:
            found.append((f"Face{i + 1}", face, edges))
    return found


def _near_wires(face, origin, normal, many_wires=8):
    """A copy of `face` (slicing raises the tolerances of the face's own vertices, the
    Base's) without the holes that stay clear of the plane: they cannot meet the section,
    and slicing a face with hundreds of holes classifies against every one."""
    if len(face.Wires) <= many_wires:
        return face.copy()
    outer = face.OuterWire
    wires = [w for w in face.Wires if not w.isSame(outer)]
    lo, hi = extents(wires, origin, normal)
    clear = [w for w, a, b in zip(wires, lo, hi) if a > TOL or b < -TOL]
    return (face.removeShape(clear) if clear else face).copy()


def extents(shapes, origin, normal):
    """(min, max) arrays: signed distances of each shape's bounding box to the plane, as
    extent() for one shape."""
    return _box_extents(_boxes(shapes), origin, normal)


def _boxes(shapes):
    """(N, 6) array of the shapes' bounding boxes: min corner, max corner."""
    return _rows(s.BoundBox for s in shapes)


def _rows(boxes):
    return np.array([(b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax)
                     for b in boxes]).reshape(-1, 6)


def _box_extents(boxes, origin, normal):
    return box_extents(boxes[:, :3], boxes[:, 3:], origin, normal)


def joint_normals(face, edges, samples=7):
    """Points and unit normals of `face`'s surface along its section `edges`.

    The surface's normal, not the face's: the same line up to sign (all Lemma 1 needs),
    without classifying the point on a face that may have hundreds of holes.
    """
    surface, points, normals = face.Surface, [], []
    for edge in edges:
        for t in np.linspace(edge.FirstParameter, edge.LastParameter, samples):
            p = edge.valueAt(t)
            points.append(tuple(p))
            normals.append(tuple(surface.normal(*surface.parameter(p))))
    return np.array(points, float), np.array(normals, float)


# the largest angle (radians) between two faces' normals at a point where OCCT's BOP check
# may find them crossing: along an edge they share (where the angle passes through zero),
# or at a vertex they alone share (OCCT's Pump_TopCover stretched twice: 7.6 deg; its
# intersection there spreads as the deviation / sin(angle))
TOUCH_ANGLE = 1e-3
VERTEX_ANGLE = 0.25
# the most a join raises a tolerance where two faces touch tangentially (tangent_touches)
TOUCH_CAP = 1e-3
# what a face's surface is, for tangent_touches_settled: a plane, another analytic surface
# (OCCT intersects two of those in closed form), or free-form (B-spline, Bezier, extrusion,
# revolution, offset: intersected by marching, where a tangent touch spreads)
FLAT, ANALYTIC, FREE = 0, 1, 2


def _surface_kind(face):
    surface = face.Surface
    if isinstance(surface, Part.Plane):
        return FLAT
    if isinstance(surface, (Part.Cylinder, Part.Cone, Part.Sphere, Part.Toroid)):
        return ANALYTIC
    return FREE


def tangent_touches_settled(solid, on_surface, cap=TOUCH_CAP, edges=True, vertices=True,
                            prop=None):
    """`solid`, or a copy with tolerances raised at the joints where two faces touch
    tangentially and OCCT's BOP check finds them crossing there (SelfIntersect):
    - two faces that share a joint vertex but no edge, tangent or nearly so there (normals
      within VERTEX_ANGLE): a mapped face continuing the surface of a rigid one diagonally
      across the vertex (a sphere split at its seam, twisted about its centre: both faces
      on the sphere, the mapped one fitted to it within 1e-7), or a stretch's swept side
      and a far sphere face at 7.6 deg to it (OCCT's Pump_TopCover stretched twice);
    - with `edges`, two that share a joint edge along which the angle between them passes
      through zero (a sphere twisted about an axis off its centre meets its rigid part with
      a kink that turns over at one point of the joint: Pump_TopCover twisted at 50 %).
    Near a tangency the intersection of the two surfaces spreads far beyond the edges'
    tolerances (to 5.8e-4 mm on a dome of radius 100). The edges of the two faces at the
    vertex, or the shared edge, and their vertices are raised ten-fold at a time up to
    `cap` until OCCT's check of those two faces finds no self-intersection (a few tenths
    of a second a check, only where faces touch so). A pair counts as crossing only where
    the check of the two finds more self-intersecting sub-shapes than the checks of each
    face alone: a face's own finding is no touch, and no tolerance at the joint settles it
    (OCCT's occt_Bottom under a Smooth Taper: the scaled image of a face bordering the
    Base's own 1.2e-6 mm edges, 9.3e-7 mm after scaling, under their 1.2e-6 tolerance,
    fails alone, as the Base fails where they are). Past `cap`: a DeformError naming
    `prop` (the two faces cross as OCCT's check of the whole solid finds them), or, without
    `prop`, the solid as it is."""
    joint = joint_vertices(solid, on_surface)
    if not joint:
        return solid
    faces = solid.Faces
    near = range(len(faces))
    planes = getattr(on_surface, "planes", None)
    if planes is not None:  # only the faces whose box reaches a joint plane are looked at
        boxes, reach = _boxes(faces), np.zeros(len(faces), bool)
        margin = 1e-3 * solid.BoundBox.DiagonalLength
        for o, n in planes:
            lo, hi = _box_extents(boxes, o, n)
            reach |= (lo < margin) & (hi > -margin)
        near = np.flatnonzero(reach)
    # only curved faces can touch so (two planes meet on a line), and a pair needs a free-
    # form one: OCCT intersects two analytic surfaces in closed form
    kinds = {int(k): _surface_kind(faces[k]) for k in near}
    if FREE not in kinds.values():
        return solid
    around = {}
    for k, kind in kinds.items():
        if kind == FLAT:
            continue
        for v in faces[k].Vertexes:
            if v.hashCode() in joint:
                around.setdefault(v.hashCode(), (v, set()))[1].add(k)
    index = {}

    def sub(kind, shape):  # (kind, index in solid): the index maps made when first needed
        if kind not in index:
            index[kind] = {s.hashCode(): k for k, s in enumerate(getattr(solid, kind))}
        return kind, index[kind][shape.hashCode()]

    meets = touching(joint)
    seen, todo, edges_of = set(), [], {}

    def hashed(k):  # face k's edges and their hashes (isSame: same TShape and Location)
        if k not in edges_of:
            es = faces[k].Edges
            edges_of[k] = es, {e.hashCode() for e in es}
        return edges_of[k]

    for vertex, ks in around.values():
        ks = sorted(ks)
        for i, a in enumerate(ks):
            for b in ks[i + 1:]:
                if FREE not in (kinds[a], kinds[b]):
                    continue
                fa, fb = faces[a], faces[b]
                common = hashed(a)[1] & hashed(b)[1]
                shared = [e for e in hashed(a)[0] if e.hashCode() in common
                          and not e.Degenerated] if common else []
                if shared:
                    if not edges or (a, b) in seen:
                        continue
                    seen.add((a, b))
                    turned = [e for e in shared if meets(e) and _in_joint(e, on_surface)
                              and _turns_over(fa, fb, e)]
                    if not turned:
                        continue
                    e = turned[0]
                    where = e.valueAt(0.5 * (e.FirstParameter + e.LastParameter))
                    subs = [sub("Edges", e) for e in turned] + [
                        sub("Vertexes", v) for e in turned for v in e.Vertexes]
                else:
                    if not vertices or planes is not None and not _across(
                            fa, fb, planes, margin):
                        continue
                    if not _tangent_at_vertex(fa, fb, vertex):
                        continue
                    where = vertex.Point
                    at = [e for f in (fa, fb) for e in f.Edges if not e.Degenerated
                          and any(w.isSame(vertex) for w in e.Vertexes)]
                    subs = [sub("Edges", e) for e in at] + [
                        sub("Vertexes", v) for e in at for v in e.Vertexes]
                todo.append((a, b, subs, where))
    # each pair checked alone (two faces: 0.01-0.3 s; all of them in one check intersects
    # every neighbouring pair too: 1.3-6 s on Pump_TopCover's and the dome's 4-11 faces)
    out, checked = None, set()
    for a, b, subs, where in todo:
        if (a, b) in checked:
            continue
        checked.add((a, b))
        now = (out or solid).Faces
        found = _crossings(Part.makeCompound([now[a], now[b]]))
        if not found:
            continue
        own = _crossings(now[a]) + _crossings(now[b])
        if found <= own:   # the faces' own findings, not their touch
            continue
        raised = _raised_until_passes(out or solid.copy(), a, b, subs, cap, own)
        if raised is None:
            if prop is None:
                return solid
            raise DeformError(
                f"Two faces touch tangentially at a joint near ({where.x:.4g}, "
                f"{where.y:.4g}, {where.z:.4g}) and cross there by more than {prop} "
                f"({cap:.3g} mm) allows; raise {prop}.", prop)
        out = raised
    return solid if out is None else out


def _in_joint(edge, on_surface):
    """Does `edge` lie in a joint (its ends and middle, within its tolerance)? An edge of
    the region's own, with one end on a joint, lies between two faces the map took alike."""
    t0, t1 = edge.FirstParameter, edge.LastParameter
    pts = np.array([tuple(edge.valueAt(t)) for t in (t0, 0.5 * (t0 + t1), t1)])
    planes = getattr(on_surface, "planes", None)
    if planes is None:
        return bool(on_surface(pts))
    slack = max(edge.Tolerance, TOL)
    return any(np.all(np.abs((pts - o) @ n) <= slack) for o, n in planes)


def _across(fa, fb, planes, margin):
    """Do the two faces lie on the two sides of one of the joint planes (each within
    `margin` of its side)? Faces touching at a vertex from one side (the Base's own, a free-
    form housing has hundreds at a joint) are left alone."""
    pts = [np.array([tuple(v.Point) for v in f.Vertexes] + [
        tuple(e.valueAt(0.5 * (e.FirstParameter + e.LastParameter)))
        for e in f.Edges if not e.Degenerated]).reshape(-1, 3) for f in (fa, fb)]
    for o, n in planes:   # at their vertices and edge midpoints (a sphere face's box
        sa, sb = ((p - o) @ n for p in pts)   # reaches far past the face)
        if (sa.max() < margin and sb.min() > -margin) or (
                sb.max() < margin and sa.min() > -margin):
            return True
    return False


def _crossings(shape):
    """How many of the shape's sub-shapes OCCT's BOP check finds self-intersecting."""
    return bop_report(shape).count("SelfIntersect")


def _raised_until_passes(out, a, b, subs, cap, own=0):
    """`out` with the tolerance of its sub-shapes `subs` ((kind, index)) raised ten-fold at
    a time until OCCT's BOP check of its faces a and b, which fails now, finds no more
    self-intersecting sub-shapes than the faces' `own` (checked alone), or None past
    `cap`."""
    faces = out.Faces
    pair = Part.makeCompound([faces[a], faces[b]])
    lists = {kind: getattr(out, kind) for kind, _ in subs}
    shapes = [lists[kind][k] for kind, k in dict.fromkeys(subs)]
    tol = max([s.Tolerance for s in shapes] + [TOL])
    while True:
        if tol >= cap:
            return None
        tol = min(10.0 * tol, cap)
        for shape in shapes:  # edges first, then their vertices: never below an edge's
            shape.limitTolerance(tol)
        if _crossings(pair) <= own:   # (a C0 Base's GeomAbs_C0: no matter)
            return out


def _uv_at(face, edge, t):
    """The (u, v) of `face`'s surface at parameter t of its `edge` (the edge's pcurve:
    projecting onto a fitted B-spline costs 9 ms a point), or None."""
    found = face.curveOnSurface(edge)
    if found is None:
        return None
    q = found[0].value(t)
    return q.x, q.y


def _tangent_at_vertex(fa, fb, vertex):
    """Are the faces' normals (anti)parallel at their common `vertex`, within VERTEX_ANGLE?
    Each normal at the end of an edge of that face at the vertex."""
    normals = []
    for face in (fa, fb):
        edge = next((e for e in face.Edges if not e.Degenerated
                     and any(w.isSame(vertex) for w in e.Vertexes)), None)
        if edge is None:
            return False
        t0, t1 = edge.FirstParameter, edge.LastParameter
        t = t0 if edge.valueAt(t0).distanceToPoint(vertex.Point) <= edge.valueAt(
            t1).distanceToPoint(vertex.Point) else t1
        uv = _uv_at(face, edge, t)
        if uv is None:
            return False
        normals.append(np.array(tuple(face.Surface.normal(*uv))))
    return np.linalg.norm(np.cross(*normals)) < np.sin(VERTEX_ANGLE)


def _turns_over(fa, fb, edge, samples=17):
    """Does the angle between the faces, measured about their shared `edge`, pass through
    zero (change sign, or come within TOUCH_ANGLE of it) inside the edge while it is not
    zero all along it (a tangent joint, as a Smooth profile makes)?"""
    ts = np.linspace(edge.FirstParameter, edge.LastParameter, samples)[1:-1]
    normals = []
    for face in (fa, fb):
        mine = next(e for e in face.Edges if e.isSame(edge))
        uvs = [_uv_at(face, mine, t) for t in ts]
        if any(uv is None for uv in uvs):
            return False
        normals.append(np.array([tuple(face.Surface.normal(*uv)) for uv in uvs]))
    tangents = np.array([tuple(edge.tangentAt(t)) for t in ts])
    signed = np.einsum("ij,ij->i", np.cross(*normals), tangents)
    if np.all(np.abs(signed) < TOUCH_ANGLE):
        return False
    # or a shallow kink all along (OCCT's Pump_TopCover tapered 0.8 at 40-60 %: 7.7-13.7 and
    # 12-19 deg, SelfIntersect until the edge had 1e-3 and 1e-4 mm)
    return bool(np.any(np.abs(signed) < np.sin(VERTEX_ANGLE))
                or np.any(signed[1:] * signed[:-1] < 0))
