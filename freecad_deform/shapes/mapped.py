"""A space map (geometry.sweep.space_map) applied to the B-rep of a region between two planes.

The solid is split at both planes (as every split-sweep-join feature does). The near part
stays, the far part moves by the map's end transform, and every face of the region goes
through the map:
- a face at one position s (a plane parallel to the planes) moves by A(s): exact;
- under a twist, a face on a surface of revolution about the twist axis stays on its very
  surface; only its pcurves change, u -> u + angle(s) (fitted in 2D to the tolerance),
  after the face is cut into pieces that stay within one period of u (_within_period);
- under an affine map (a Linear stretch) a plane stays a Part.Plane through its mapped
  edges;
- any other plane: a B-spline in the plane's (u, v) turned to run along its lines of
  constant s, which every map keeps straight: degree 1 along them, fitted only up the slope;
  put on a Part.Plane where that fit is planar (a Linear Taper of a plane parallel to the
  normal), as the planes of a far part that the map's end scales are;
- every other face: a B-spline fitted to the mapped points in the face's own (u, v)
  parametrisation (geometry.nurbs.surface_fit), the face rebuilt from its own pcurves;
  where its parameter rectangle reaches a fold of the map continued past the planes, the
  face must pass OCCT's BOP check, else FoldsPastPlanes is raised.
The mapped faces are sewn to the pieces' faces at the joints, which go into the pieces in
place of their own (the rest of the solid untouched); where that fails, or the far part is
scaled or a piece has voids, all faces are sewn (with the cut faces left out) into one
solid, voids kept. The largest deviation from the exact map is measured at points the fits
did not use.
"""
import numpy as np
import Part

from ..geometry.sweep import continuity
from ..geometry.nurbs import surface_fit
from ..geometry.nurbs.direct_push import knots_and_mults
from ..geometry.errors import DeformError
from ..geometry.vectors import unit
from . import brep, bspline
from .convert import vector

# OCCT's sewing on FreeCAD 0.20 works at 1e-6 mm whatever it is asked: faces fitted to
# this (two of them meet within twice it) sew; looser fits need the slow fuzzy fuse
SEW_FIT = 4e-7
DEGREE = 5   # fitted surfaces: the error falls as h^6, so a tight fit needs few spans

REVOLUTION = ("Part::GeomCylinder", "Part::GeomCone", "Part::GeomSphere", "Part::GeomToroid",
              "Part::GeomSurfaceOfRevolution")


def map_shape(shape, smap, tol, prop="Tolerance"):
    """(mapped shape, largest deviation) of every solid of `shape`: one solid or a
    compound; loose wires and vertices go through the map at their vertices' s (rigid
    pieces before and beyond the region, the others refit)."""
    solids = brep.solids_of(shape)
    out, worst = [], 0.0
    for solid in solids:
        result, dev = map_solid(solid, smap, tol, prop)
        out.append(result)
        worst = max(worst, dev)
    out += _loose(brep.loose_parts(shape), smap, tol)
    return (out[0] if len(out) == 1 else Part.makeCompound(out)), worst


def map_solid(solid, smap, tol, prop="Tolerance", zones=None):
    """(one solid, largest deviation) for a solid through the map; `zones`: its pieces
    (near, between, far) when the caller split it at both planes already."""
    o, n, gap = smap.origin, smap.normal, smap.gap
    near, between, far = zones or brep.split_zones(solid, o, n, [0.0, gap])
    if not between:  # the solid lies before Plane or beyond Plane2
        if near or smap.rigid:
            return (near + _moved(far, smap.end))[0], 0.0
        faces, dev = _moved_faces([f for s in far for f in s.Faces], smap.end, tol)
        return sewn_solid(faces, [], max(dev, tol), prop), dev
    cut, caps0 = _shared_on_plane(near, between, o, n)
    far_cut, caps1 = _shared_on_plane(far, between, o + gap * n, n)
    caps = caps0 + caps1
    inside = [f for s in between for f in s.Faces if not any(f.isSame(c) for c in caps)]
    points = [_face_points(f) for f in inside]
    smap.check_fold(np.vstack(points), "Axis" if smap.profile == "Linear" else "Profile")
    mapped, worst = _mapped_faces(inside, smap, tol, points)
    fit_tol = min(tol, SEW_FIT)
    end = smap.end
    joints = [(o, n), (end[:3, :3] @ (o + gap * n) + end[:3, 3],
                       unit(np.linalg.inv(end[:3, :3]).T @ n))]
    result = None
    if _rigid(end) and all(len(s.Shells) == 1 for s in near + between + far):
        result = _joined_locally(near, cut, far, far_cut, mapped, end, joints, worst)
    local = result is not None   # else sewn_solid checked the faces touching at a vertex
    if result is None:
        moved, dev = _moved_faces([f for s in far for f in s.Faces
                                   if not any(f.isSame(c) for c in far_cut)], end, fit_tol)
        worst = max(worst, dev)
        faces = ([f for s in near for f in s.Faces if not any(f.isSame(c) for c in cut)]
                 + mapped + moved)
        # the region's own faces meet only within their edges' and vertices' tolerances (a
        # real file's: up to 0.01 mm), and so do their images
        slack = max([v.Tolerance for f in inside for v in f.Vertexes]
                    + [e.Tolerance for f in inside for e in f.Edges])
        result = sewn_solid(faces, joints, worst, prop, slack)
    if len(result.Shells) != len(solid.Shells):
        # a void whose faces the planes cut by a hair (near a sphere's poles) came back in
        # pieces, and the volume with them (a void box twisted: +466 mm^3)
        raise DeformError(f"The mapped region's voids do not close again ({len(solid.Shells)} "
                          f"shells became {len(result.Shells)}); move Plane or Plane2 a "
                          f"little, off the voids' poles and seams.", "Plane2")
    # where two faces touch tangentially at a joint, tolerances raised up to Tolerance until
    # OCCT's BOP check of the two finds no crossing; past it a refusal naming `prop`
    return brep.tangent_touches_settled(result, brep.on_planes(joints), tol,
                                        vertices=local, prop=prop), worst


def _joined_locally(near, cut, far, far_cut, mapped, end, joints, deviation):
    """One solid of the near pieces, the far ones moved by the rigid `end` and the `mapped`
    faces, without the `cut` and `far_cut` faces; None where this does not work (then all
    faces are sewn). Only the mapped faces and the pieces' faces with a vertex on a joint
    are sewn (those with many holes without the holes clear of it, put back after) and
    merged across the joints (brep's join of split pieces does the same); they go into the
    first piece in place of its faces there, with the other pieces' faces. The rest of the
    solid keeps its topology, and only the faces sewing made get their tolerances settled:
    sewing and settling a 1000-face solid cost more than the region's fits."""
    dropped = [{k for k, f in enumerate(s.Faces) if any(f.isSame(c) for c in far_cut)}
               for s in far]
    moved = brep.transformed(far, end)  # faces in the same order: the cut ones by index
    pieces = near + moved
    if not pieces:
        return None
    keep = [f for s in near for f in s.Faces if not any(f.isSame(c) for c in cut)] + [
        f for s, drop in zip(moved, dropped) for k, f in enumerate(s.Faces) if k not in drop]
    on_surface = brep.on_planes(joints)
    joint = set().union(*(brep.joint_vertices(s, on_surface) for s in pieces))
    meets = brep.touching(joint)  # sees the vertices sewing adds to `joint` below
    touched = [f for f in keep if meets(f)]
    mine = {f.hashCode() for f in touched}
    reduced, holes = brep._clear_holes_out(touched, meets)
    sewn = Part.makeCompound(reduced + mapped)
    try:       # (no second try on B-splines, brep.sew: a first join, see brep._sewn)
        sewn.sewShape(max(4.0 * deviation, 1e-6))
    except Part.OCCError:
        return None
    if len(sewn.Faces) != len(reduced) + len(mapped) or \
            not brep._kept_orientation(reduced + mapped, sewn.Faces):
        return None
    joint |= brep.joint_vertices(sewn, on_surface)  # sewing made new vertices at the joints
    merged = brep._unified(sewn.Faces, joint, on_surface)
    if merged is None or not brep._holes_back(reduced, holes, merged, mine):
        return None
    host = pieces[0]
    own = {f.hashCode() for f in host.Faces}
    kept = {f.hashCode() for f in keep}
    stays = {f.hashCode() for f in merged} & own
    gone = [f for f in host.Faces if f.hashCode() not in stays and (
        f.hashCode() not in kept or f.hashCode() in mine)]
    new = [f for f in merged if f.hashCode() not in mine]
    added = [f for f in merged if f.hashCode() not in own] + [
        f for s in pieces[1:] for f in s.Faces if f.hashCode() in kept - mine - own]
    if not gone or not added:
        return None
    out = brep._replaced(host, gone, added)
    if out is None or out.ShapeType != "Solid" or len(out.Faces) != len(keep) - len(
            touched) + len(merged) or not brep._valid_faces(new, meets) or not \
            brep._manifold(merged, meets) or not brep._shells_valid(out):
        return None
    untouched = kept - mine
    for face in out.Faces:
        if face.hashCode() not in untouched:
            bspline.settle_tolerances(face)
    return out


def _rigid(matrix):
    m = np.asarray(matrix, float)
    return np.allclose(m[:3, :3].T @ m[:3, :3], np.eye(3), atol=1e-12)


def _mapped_faces(faces, smap, tol, points=None, what="A face"):
    """(the faces through the map, fitted to SEW_FIT or `tol` if tighter, the largest
    deviation); a face whose fit misses `tol` is refused. `points`: each face's
    _face_points, when the caller has them."""
    out, worst = [], 0.0
    for face, pts in zip(faces, points or [None] * len(faces)):
        pts = _face_points(face) if pts is None else pts
        pieces = _within_period(face, smap, pts)
        for piece in pieces:
            new, dev = map_face(piece, smap, min(tol, SEW_FIT),
                                pts if len(pieces) == 1 else None)
            if dev > tol:
                raise DeformError(f"{what} cannot be fitted to Tolerance ({tol:.3g} mm; it is "
                                  f"off by {dev:.3g} mm); raise Tolerance.", "Tolerance")
            out.append(new)
            worst = max(worst, dev)
    return out, worst


# the most bands _within_period cuts a face into (16 turns across it): each is two faces
# and a general fuse more (a sphere's zone turned 1000 times took 86 s and 8004 faces)
MOST_BANDS = 64


def _within_period(face, smap, pts):
    """A face of revolution about the twist axis cut into pieces that stay within one
    period of u once turned ([face] when it does already). A whole band (a shaft's
    cylinder, a sphere's zone) turned by any angle runs past its period, and OCCT's
    sections and booleans lose the part past it (_past_period), so the band is cut along
    meridians by half-planes from the axis into pieces at most half a period wide, and,
    where the turn across it exceeds a quarter of a turn, by planes parallel to Plane into
    bands that each turn by at most that (MOST_BANDS at most): every piece then stays on
    the exact surface (_turned_on_surface) instead of being fitted. The cuts are OCCT's general fuse of the
    face with those faces."""
    surface = face.Surface
    if getattr(smap, "twist_axis", None) is None or surface.TypeId not in REVOLUTION or \
            not surface.isUPeriodic() or not _coaxial(surface, *smap.twist_axis):
        return [face]
    period = surface.UPeriod()
    u0, u1, v0, v1 = face.ParameterRange
    s = smap.s(pts)                               # (clamped to the region)
    turn = abs(smap.angle_of(float(s.max())) - smap.angle_of(float(s.min())))
    if u1 - u0 + turn <= period * (1 - 1e-9) or turn < 1e-12:
        return [face]
    centre, k = smap.twist_axis
    size = 2.0 * (face.BoundBox.DiagonalLength + np.linalg.norm(
        np.array(tuple(face.BoundBox.Center)) - centre)) + 1.0
    tools = []
    cuts = max(2, int(np.ceil((u1 - u0) / (0.5 * period))))
    for u in u0 + (u1 - u0) * np.arange(1, cuts) / cuts:   # half-planes at the meridians
        r = np.array(tuple(surface.value(u, 0.5 * (v0 + v1)))) - centre
        r = unit(r - (r @ k) * k)
        if not r.any():                       # (the face's middle on the axis)
            return [face]
        corners = [centre - size * k, centre + size * k, centre + size * (k + r),
                   centre + size * (r - k), centre - size * k]
        tools.append(Part.Face(Part.makePolygon([vector(c) for c in corners])))
    bands = int(np.ceil(turn / (0.5 * np.pi)))
    if bands > MOST_BANDS:                    # (fitted, or refused naming Tolerance)
        return [face]
    for level in s.min() + (s.max() - s.min()) * np.arange(1, bands) / bands:
        tools.append(brep.square_face(smap.origin + level * smap.gap * smap.normal,
                                      smap.normal, size))
    try:
        _, parts = face.generalFuse(tools)
    except Part.OCCError:
        return [face]
    pieces = parts[0] if parts else []
    return pieces if len(pieces) > 1 else [face]


def _shared_on_plane(a, b, origin, normal):
    """The faces of pieces `a` and of pieces `b` in the plane that the split made. The
    split's general fuse gives both pieces the one face (looked up by hashCode: a scan of
    every face's surface costs 0.2 s on 1000 faces); pieces that share none are matched in
    the plane (each face with a partner of the same area and centre in the other). A face
    of the part that merely lies in the plane (a shoulder at Plane) has none and stays."""
    shared = {f.hashCode() for s in b for f in s.Faces} & {f.hashCode() for s in a
                                                          for f in s.Faces}
    if shared:
        return tuple([f for s in p for f in s.Faces if f.hashCode() in shared] for p in (a, b))
    fa, fb = (brep.faces_on_plane(p, origin, normal) for p in (a, b))
    size = max([s.BoundBox.DiagonalLength for s in a + b] + [1.0])

    def key(f):
        return np.array(tuple(f.CenterOfMass) + (f.Area / size,)) / size

    ka, kb = [key(f) for f in fa], [key(f) for f in fb]
    return ([f for f, k in zip(fa, ka) if any(np.allclose(k, q, atol=1e-9) for q in kb)],
            [f for f, k in zip(fb, kb) if any(np.allclose(k, q, atol=1e-9) for q in ka)])


def _moved_faces(faces, matrix, tol):
    """(faces moved by a 4x4 transform, deviation): exact for a rigid one; under a scaling
    refit like the region's faces (OCCT's own affine transform of a shape approximates
    its circles to about 1e-3)."""
    m = np.asarray(matrix, float)
    if _rigid(m):
        # moved as one compound: faces moved one by one lose their shared edges, and
        # sewing them again refits a real file's loose edges (areas off by 1e-6)
        return brep.transformed([Part.makeCompound(faces)], m)[0].Faces, 0.0
    out = [_fitted(f, lambda p: p @ m[:3, :3].T + m[:3, 3], tol) for f in faces]
    # an affine map takes a plane to a plane: put back on it exactly
    out = [(_on_surface(g, _plane_of(g)), d) if f.Surface.TypeId == "Part::GeomPlane" else
           (g, d) for f, (g, d) in zip(faces, out)]
    return [f for f, _ in out], max([d for _, d in out], default=0.0)


def _moved(shapes, matrix):
    """Shapes moved by the map's end transform: exact for a rigid one, else affine."""
    m = np.asarray(matrix, float)
    if _rigid(m):
        return brep.transformed(shapes, m)
    import FreeCAD as App
    return [s.transformGeometry(App.Matrix(*m.ravel())) for s in shapes]


def sewn_solid(faces, joints, deviation, prop, slack=0.0):
    """One valid solid from faces that meet within `deviation` (sewn at a few times it;
    voids kept), its faces merged again across the joint planes. Faces of a real file meet
    only within its edge tolerances (its pcurves miss each other by up to 5e-4 mm), farther
    than FreeCAD 0.20's sewing reaches (1e-6 mm, whatever it is asked): then all are sewn
    at twice the largest tolerance of the faces left open (_sewn_wide), doubled while gaps
    stay up to twice `slack` (the tolerance of the faces the map took), and the tolerances
    brought down again to what each edge needs."""
    tol = max(4.0 * deviation, 1e-6)
    try:
        sewn, wide = _sewn_closed(faces, tol, slack)
    except Part.OCCError as error:
        raise DeformError(f"OCCT cannot sew the mapped faces ({error}); move Plane or "
                          f"Plane2 a little, or change {prop}.", prop) from None
    shells = brep.closed_shells(sewn)
    if shells is None:
        raise DeformError(f"The mapped faces do not close a solid (gaps above "
                          f"{tol:.3g} mm); lower {prop}.", prop)
    solid = brep.solid_of_shells(shells)
    if solid is None:
        raise DeformError("The mapped region falls apart into separate bodies; change "
                          "Plane2 so the region is one piece.", "Plane2")
    if wide is not None:
        solid = _tightened(solid, wide)
    try:  # the split faces merged again across the joints, on a copy (OCCT edits in place)
        return _settled(brep.merge_joints(solid.copy(), joints, prop))  # sewn already
    except DeformError:
        pass
    if not solid.isValid():
        raise DeformError(f"The mapped faces do not join into one valid solid; lower {prop}.",
                          prop)
    # (merge_joints checks the faces that touch tangentially at a joint vertex; so here)
    return brep.tangent_touches_settled(_settled(solid.copy()), brep.on_planes(joints),
                                        edges=False)


def _sewn_closed(faces, tol, slack):
    """(the faces sewn, the wider tolerance it took or None): at `tol`, else as
    sewn_solid tells."""
    sewn = _sewn(faces, tol)
    loose = _with_free_edges(sewn.Faces)
    if not loose:
        return sewn, None
    wide = max([tol] + [2.0 * e.Tolerance for f in loose for e in f.Edges])
    sewn = _sewn_wide(faces, wide)
    while brep.closed_shells(sewn) is None and wide < 2.0 * slack:
        wide = min(2.0 * wide, 2.0 * slack)
        sewn = _sewn_wide(faces, wide)
    if brep.closed_shells(sewn) is None:
        # a fuzzy general fuse of the faces around the gaps shares them, then all is
        # sewn again (it works on copies: rigid faces next to the gaps may be refit)
        loose = _with_free_edges(sewn.Faces)
        fused = loose[0].generalFuse(loose[1:], wide)[0]
        keep = [f for f in sewn.Faces if not any(f.isSame(g) for g in loose)]
        sewn = _sewn(keep + fused.Faces, tol)
    return sewn, wide


def _settled(solid):
    """`solid` (a copy of ours, never the Base's) with its edge tolerances raised to their
    measured pcurve gaps: sewing leaves some a hair below them (2.369e-7 against 2.36e-7
    on a tapered sphere, 5.2e-7 against 4.9e-7 where a torus meets its mapped part), which
    the BOP check and booleans reject."""
    for face in solid.Faces:
        bspline.settle_tolerances(face)
    return solid


def _sewn_wide(faces, tol):
    """The faces sewn at `tol` (copies, their tolerances raised to it): FreeCAD 1.0 and
    later pass `tol` to OCCT's sewing; 0.20 does not, but its Part.makeShell sews an
    invalid shell at the mean tolerance of its parts, which is then `tol` (voids come back
    as more shells in a compound)."""
    compound = Part.makeCompound(faces).copy()
    compound.limitTolerance(tol)  # raised to tol, larger ones kept (a file's own 0.01 mm)
    sewn = brep.sew(compound.copy().Faces, tol)
    if not _with_free_edges(sewn.Faces):
        return sewn
    try:
        shells = Part.makeShell(compound.Faces)
    except Part.OCCError:
        return sewn
    return shells if not _with_free_edges(shells.Faces) else sewn


def _tightened(solid, tol):
    """The solid sewn at `tol` (fixed by OCCT if it is not valid), with each edge's
    tolerance set back to what its curves need when OCCT's shape fixing does that without
    changing a face (it bridges an edge whose tolerance a file set far above its gap)."""
    if not solid.isValid():
        solid = solid.copy()
        solid.fix(1e-7, 1e-7, tol)
    tight = solid.copy()
    tight.limitTolerance(1e-7, 1e-7)
    tight.fix(1e-7, 1e-7, tol)
    same = len(tight.Faces) == len(solid.Faces) and len(tight.Edges) == len(solid.Edges) \
        and all(abs(a.Area - b.Area) <= 1e-12 * max(a.Area, 1.0)
                for a, b in zip(tight.Faces, solid.Faces))
    return tight if same and tight.isValid() else solid


def _sewn(faces, tol):
    """The faces sewn (at `tol` where FreeCAD passes it on) into one compound."""
    return brep.sew(faces, tol)


def _with_free_edges(faces):
    """The faces that have an edge no other face shares (a seam is not free)."""
    count = {}
    for face in faces:
        for edge in face.Edges:
            count[edge.hashCode()] = count.get(edge.hashCode(), 0) + 1
    return [f for f in faces if any(count[e.hashCode()] == 1 and not e.isSeam(f)
                                    and not e.Degenerated for e in f.Edges)]


# --- faces -------------------------------------------------------------------------------

def map_face(face, smap, tol, points=None):
    """(mapped face, deviation measured between the fit samples); `points`: the face's
    _face_points, when the caller has them."""
    pts = _face_points(face) if points is None else points
    s = (pts - smap.origin) @ smap.normal / smap.gap
    if np.ptp(s) < 1e-12:  # the whole face at one position: moved by A(s)
        moved, dev = _moved_faces([face], smap.matrices([np.clip(s.mean(), 0.0, 1.0)])[0], tol)
        return moved[0], dev
    if getattr(smap, "twist_axis", None) is not None and \
            face.Surface.TypeId in REVOLUTION and _coaxial(face.Surface, *smap.twist_axis):
        built = _turned_on_surface(face, smap, tol)
        if built is not None:
            return built
    along = getattr(smap, "affine", False) and face.Surface.TypeId == "Part::GeomCylinder" \
        and _parallel(face.Surface.Axis, smap.normal)
    if along and bspline.natural(face):
        # a stretch along its axis keeps every point on the very same cylinder: the face is
        # its parameter rectangle with the axial bounds mapped
        return _stretched_rectangle(face, smap), 0.0
    if face.Surface.TypeId == "Part::GeomPlane":
        built, dev = _fitted_plane(face, smap, tol)
    else:
        built, dev = _fitted(face, lambda p: smap(p, clamp=False), tol, smap)
    if face.Surface.TypeId == "Part::GeomPlane" and (getattr(smap, "affine", False)
                                                     or _planar(built)):
        # (a Linear Taper keeps a plane parallel to its normal a plane: on it exactly)
        return _on_surface(built, _plane_of(built)), dev
    if getattr(smap, "affine", False):
        if along:
            return _on_surface(built, face.Surface.copy()), dev
    return built, dev


def _stretched_rectangle(face, smap):
    """A face that is its cylinder's (u0..u1, v0..v1) rectangle, on the same cylinder over
    (u0..u1, v0'..v1'): v0, v1 taken through the map along the axis."""
    surface = face.Surface
    u0, u1, v0, v1 = face.ParameterRange
    ends = smap(np.array([tuple(surface.value(u0, v)) for v in (v0, v1)]), clamp=False)
    w0, w1 = (surface.parameter(vector(p))[1] for p in ends)
    new = surface.copy().toShape(u0, u1, w0, w1)
    if face.Orientation == "Reversed":
        new.reverse()
    return new


def _parallel(direction, normal, tol=1e-12):
    return np.linalg.norm(np.cross(unit(np.array(tuple(direction), float)),
                                   unit(np.asarray(normal, float)))) < tol


# the farthest a fitted face's poles may lie from one plane for the face to be put on it
# (its surface lies in their convex hull); fits of exact planes came within 3e-11 mm
PLANAR = 1e-9


def _planar(built):
    """Does the fitted face's B-spline surface lie in one plane (its poles within PLANAR)?"""
    if not isinstance(built.Surface, Part.BSplineSurface):
        return False
    poles = np.array([tuple(p) for row in built.Surface.getPoles() for p in row], float)
    centre = poles.mean(axis=0)
    normal = np.linalg.svd(poles - centre)[2][2]
    return float(np.abs((poles - centre) @ normal).max()) <= PLANAR


def _plane_of(built):
    """The Part.Plane through three corners of a fitted planar face, along its normal."""
    import FreeCAD as App
    u0, u1, v0, v1 = built.ParameterRange
    p = surface_grid(built.Surface, [u0, u1], [v0, v1]).reshape(-1, 3)
    normal = np.cross(p[2] - p[0], p[1] - p[0])
    if np.dot(normal, np.array(tuple(built.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))))) < 0:
        normal = -normal
    return Part.Plane(App.Vector(*p[0]), App.Vector(*normal))


def _on_surface(built, surface):
    """The fitted image of a face under an affine map put back on the exact `surface` the
    map takes its surface to (a plane stays a plane, a cylinder along the stretch stays
    itself): bounded by the fitted face's wires, which lie on it to the fit's deviation.
    The fitted face when OCCT cannot build it valid with the same area (1e-6)."""
    forward = built.reversed() if built.Orientation == "Reversed" else built
    try:
        face = Part.Face(surface, forward.OuterWire)
        for wire in forward.Wires:
            if not wire.isSame(forward.OuterWire):
                face = Part.Face(face, wire)
        u0, u1, v0, v1 = forward.ParameterRange
        mid = (0.5 * (u0 + u1), 0.5 * (v0 + v1))
        uv = face.Surface.parameter(forward.valueAt(*mid))
        if face.normalAt(*uv).dot(forward.normalAt(*mid)) < 0:
            face.reverse()
    except Part.OCCError:
        return built
    if built.Orientation == "Reversed":
        face.reverse()
    return face if face.isValid() and abs(face.Area - built.Area) < 1e-6 * built.Area \
        else built


def _face_points(face, count=5):
    """Points of the face: its vertices, and a grid of its surface over its parameters."""
    u0, u1, v0, v1 = face.ParameterRange
    grid = surface_grid(face.Surface, np.linspace(u0, u1, count), np.linspace(v0, v1, count))
    return np.vstack([np.array([tuple(v.Point) for v in face.Vertexes], float).reshape(-1, 3),
                      grid.reshape(-1, 3)])


def surface_grid(surface, U, V):
    """Points (len(U), len(V), 3) of a Part surface on the grid U x V: planes and
    cylinders in closed form (their frame read off a few points, then checked), others
    point by point."""
    U, V = np.asarray(U, float), np.asarray(V, float)
    form = _closed_form(surface)
    if form is not None:
        return form(U[:, None], V[None, :])
    value = surface.value
    out = np.empty((len(U), len(V), 3))
    for i, u in enumerate(U):
        out[i] = [(p.x, p.y, p.z) for p in (value(u, v) for v in V)]
    return out


def _closed_form(surface):
    """f(U, V) -> points for a plane, cylinder, cone, sphere, torus or B-spline surface
    (frames read off a few of its points, poles from the surface), checked against the
    surface at probe points; None for any other surface or when the check fails."""
    def at(u, v):
        p = surface.value(u, v)
        return np.array([p.x, p.y, p.z])

    kind = surface.TypeId
    h = 0.5 * np.pi
    cos, sin = (lambda U: np.cos(U)[..., None]), (lambda U: np.sin(U)[..., None])
    if kind == "Part::GeomPlane":
        o, du, dv = at(0, 0), at(1, 0) - at(0, 0), at(0, 1) - at(0, 0)

        def form(U, V):
            return o + U[..., None] * du + V[..., None] * dv
    elif kind in ("Part::GeomCylinder", "Part::GeomCone"):
        c = 0.5 * (at(0, 0) + at(np.pi, 0))
        rx, ry = at(0, 0) - c, at(h, 0) - c
        d0, dpi = at(0, 1) - at(0, 0), at(np.pi, 1) - at(np.pi, 0)
        sx, cz = 0.5 * (d0 - dpi), 0.5 * (d0 + dpi)
        sy = at(h, 1) - at(h, 0) - cz

        def form(U, V):
            V = V[..., None]
            return c + cos(U) * (rx + V * sx) + sin(U) * (ry + V * sy) + V * cz
    elif kind == "Part::GeomSphere":
        c = 0.5 * (at(0, 0) + at(np.pi, 0))
        x, y, z = at(0, 0) - c, at(h, 0) - c, at(0, h) - c

        def form(U, V):
            return c + cos(V) * (cos(U) * x + sin(U) * y) + sin(V) * z
    elif kind == "Part::GeomToroid":
        c = 0.5 * (at(0, 0) + at(np.pi, 0))
        big_x = 0.5 * (at(0, 0) + at(0, np.pi)) - c
        small_x = 0.5 * (at(0, 0) - at(0, np.pi))
        big_y = 0.5 * (at(h, 0) + at(h, np.pi)) - c
        small_y = 0.5 * (at(h, 0) - at(h, np.pi))
        small_z = at(0, h) - c - big_x

        def form(U, V):
            return (c + cos(U) * (big_x + cos(V) * small_x)
                    + sin(U) * (big_y + cos(V) * small_y) + sin(V) * small_z)
    elif kind == "Part::GeomBSplineSurface" and not (surface.isUPeriodic()
                                                     or surface.isVPeriodic()):
        form = _bspline_form(surface)
    else:
        return None
    u0, u1, v0, v1 = surface.bounds()
    probe = (np.array([0.31, 0.77, 0.5]), np.array([0.62, 0.13, 0.5]))
    if all(np.isfinite([u0, u1, v0, v1])):
        probe = (u0 + probe[0] * (u1 - u0), v0 + probe[1] * (v1 - v0))
    else:
        probe = (probe[0] * 3 - 1, probe[1] * 3 - 1)
    exact = np.array([at(u, v) for u, v in zip(*probe)])
    size = max(1.0, float(np.abs(exact).max()))
    return form if np.abs(form(*probe) - exact).max() < 1e-11 * size else None


def _bspline_form(surface):
    """Vectorised evaluation of a (rational) non-periodic B-spline surface."""
    from ..geometry.nurbs.surface_fit import design
    poles = np.array([[(p.x, p.y, p.z) for p in row] for row in surface.getPoles()])
    w = np.array(surface.getWeights(), float)
    uk = np.repeat(surface.getUKnots(), surface.getUMultiplicities())
    vk = np.repeat(surface.getVKnots(), surface.getVMultiplicities())
    du, dv = surface.UDegree, surface.VDegree
    hom = np.concatenate([poles * w[..., None], w[..., None]], axis=-1)

    def form(U, V):
        U, V = np.broadcast_arrays(U, V)
        shape = U.shape
        bu, bv = design(U.ravel(), uk, du), design(V.ravel(), vk, dv)
        out = np.einsum("ka,abd,kb->kd", bu, hom, bv, optimize=True)
        return (out[:, :3] / out[:, 3:]).reshape(shape + (3,))

    return form


def _fitted(face, point_map, tol, smap=None):
    """The face on a B-spline fitted to its surface's points through `point_map` ((N, 3)
    -> (N, 3); for a region face the map `smap` continued past the planes, so it is smooth
    over the whole parameter rectangle), in the face's own parametrisation. Where that
    continuation folds inside the rectangle, the face is checked by OCCT's BOP check and
    FoldsPastPlanes raised when it fails (see there)."""
    surface = face.Surface
    u0, u1, v0, v1 = face.ParameterRange
    fold, looked = [], []

    def mapped(U, V):
        pts = surface_grid(surface, U, V).reshape(-1, 3)
        if smap is not None and not looked:  # once: the first samples span the rectangle
            looked.append(True)
            fold.extend(_fold_past_planes(smap, pts))
        return point_map(pts).reshape(len(U), len(V), 3)

    ub, vb = _breaks(surface, u0, u1, 0), _breaks(surface, v0, v1, 1)
    fit = surface_fit.fit_surface(mapped, (u0, u1), (v0, v1), tol, degree=DEGREE,
                                  breaks=(ub, vb))
    new = bspline_surface(fit)
    if bspline.natural(face):  # all of its surface's rectangle: OCCT bounds it itself
        built = Part.Face(new)     # (seams and degenerated edges made right)
        if face.Orientation == "Reversed":
            built.reverse()
    else:
        built = face_on_pcurves(new, face, lambda e, forward: forward.curveOnSurface(e))
    if fold and (built is None or not brep.passes_bop_check(built)):
        raise FoldsPastPlanes(fold[0])
    if built is None:
        raise DeformError("A mapped face could not be rebuilt on its fitted surface; "
                          "change Tolerance.", "Tolerance")
    return built, fit.deviation


class FoldsPastPlanes(DeformError):
    """A face's parameter rectangle reaches where the map, continued past the planes,
    folds (a taper's factor 1 + (Scale - 1) t passes zero there), and its fitted surface,
    folding there too (outside the face, inside the rectangle), fails OCCT's BOP check
    (self-intersecting: a cone between planes slanted to its axis, Scale 2.43; with the
    fold farther from the face the check may pass, and the face is kept). Leaving those
    samples out of the fit, with a low-weighted stand-in that does not fold, gave a face
    the check passes, but there the fold comes within a few hundredths of the rectangle of
    the face, and the fit took 230 x 230 poles and 130 s without reaching its tolerance
    (7.6e-5 mm): so the result is refused. `past`: how far (mm along the normal) before
    Plane (negative) or beyond Plane2 (positive) the fold was met, `side` that in words."""

    def __init__(self, past):
        self.past, self.side = past, "before Plane" if past < 0 else "beyond Plane2"
        super().__init__(f"A face's parameter range reaches {abs(past):.3g} mm {self.side}, "
                         f"where the deformation continued past the planes folds, and its "
                         f"refitted surface would fold too; move Plane2 farther from Plane.",
                         "Plane2")


FOLD_SHARE = 0.01  # the map counts as folding where its Jacobian determinant falls
#                   below this share of its value at the plane the walk starts from (a
#                   face is only refused when its BOP check fails as well)
FOLD_WALK = (8, 128)  # samples walked, steps along each walk: a factor passing zero is
#                       seen while it moves less than 0.2 a step (~8 ms a face)


def _fold_past_planes(smap, pts):
    """[the distance along the normal past the planes (mm; negative before Plane) of the
    fold nearest them] where the map continued past the planes folds between the region
    and any of the points (N, 3), else []: walking from each plane out to the farthest
    points along the normal (FOLD_WALK), the map's Jacobian determinant (central
    differences) dips below FOLD_SHARE of its value at the plane. (Its sign alone does
    not tell: a taper's factor f passing zero turns a section through the axis, and the
    determinant f^2 stays positive.) Inside the region check_fold has made it positive."""
    s = (pts - smap.origin) @ smap.normal / smap.gap
    for side, out in ((0.0, s < 0.0), (1.0, s > 1.0)):
        if not out.any():
            continue
        p, q = pts[out], s[out]
        pick = np.unique(np.linspace(0, len(p) - 1, FOLD_WALK[0]).round().astype(int))
        p, q = p[np.argsort(np.abs(q - side))][pick], np.sort(np.abs(q - side))[pick]
        sign = 1.0 if side else -1.0
        step = np.linspace(0.0, 1.0, FOLD_WALK[1])
        # each picked point slid along the normal from the plane out to where it is
        walk = (p[:, None, :] + ((side + sign * np.outer(q, step) - (side + sign * q)[:, None])
                                 * smap.gap)[..., None] * smap.normal).reshape(-1, 3)
        h = 1e-6 * smap.gap
        cols = [(smap(walk + h * e, clamp=False) - smap(walk - h * e, clamp=False)) / (2 * h)
                for e in np.eye(3)]
        det = np.linalg.det(np.stack(cols, axis=-1)).reshape(len(p), -1)
        folds = det < FOLD_SHARE * det[:, :1]
        if folds.any():  # the fold nearest the plane
            k, j = np.nonzero(folds)
            return [sign * float(np.min(q[k] * step[j])) * smap.gap]
    return []


def _fitted_plane(face, smap, tol):
    """(the plane face through the map, deviation): fitted in the plane's (u, v) turned so
    that u' runs along its lines of constant s and v' up the slope of s. Every map of ours
    moves the section at s by one affine A(s), so these lines stay straight and the image
    is exactly linear in u' (degree 1, one span: only the curve along v' is fitted), over
    the face's own range of s (the map never continued far past the planes). The fit and
    the map then differ linearly along u', most at its ends: checked there (exact along
    u', 15 points a span along v'), and the spans along v' (from 3, far fewer than a general
    fit's, so OCCT's Volume of the face costs a tenth) doubled until it holds. The pcurves
    turned the same way are the same curves (lines stay lines, circles circles)."""
    import FreeCAD as App
    o, x, y = surface_grid(face.Surface, [0.0, 1.0], [0.0, 1.0]).reshape(4, 3)[[0, 2, 1]]
    x, y = x - o, y - o  # a Part.Plane's unit, orthogonal u and v directions
    slope = np.array([x @ smap.normal, y @ smap.normal]) / smap.gap  # ds/du, ds/dv
    if np.linalg.norm(slope) * np.ptp(np.array(face.ParameterRange).reshape(2, 2),
                                      axis=1).max() < 1e-12:
        # s spread by rounding only over a plane parallel to the planes: no slope to turn
        # along (it would be 0 / 0); the general fit
        return _fitted(face, lambda p: smap(p, clamp=False), tol, smap)
    cx, cy = slope / np.linalg.norm(slope)
    turn = np.array([[cy, -cx], [cx, cy]])  # (u', v') = turn @ (u, v), a rotation
    u0, u1, v0, v1 = face.ParameterRange
    corners = turn @ np.array([[u0, u0, u1, u1], [v0, v1, v0, v1]])
    # s = s0 + |slope| v': the face lies where 0 <= s <= 1 (a hair beyond, in tolerance)
    s0, k = (o - smap.origin) @ smap.normal / smap.gap, np.linalg.norm(slope)
    lo = max(corners[1].min(), (-1e-3 - s0) / k)
    hi = min(corners[1].max(), (1.0 + 1e-3 - s0) / k)

    def mapped(U, V):
        u = turn[0, 0] * U[:, None] + turn[1, 0] * V[None, :]
        v = turn[0, 1] * U[:, None] + turn[1, 1] * V[None, :]
        pts = o + u[..., None] * x + v[..., None] * y
        return smap(pts.reshape(-1, 3), clamp=False).reshape(pts.shape)

    ends = np.array([corners[0].min(), corners[0].max()])
    spans = 3
    while True:
        fit = surface_fit.fit_surface(mapped, ends, (lo, hi), tol, degree=(1, DEGREE),
                                      spans=(1, spans))
        knots = np.unique(fit.vknots)
        dense = np.concatenate([np.linspace(a, b, 16)[1:] for a, b in zip(knots, knots[1:])])
        deviation = max(fit.deviation, float(np.linalg.norm(
            surface_fit.evaluate_surface(fit, ends, dense) - mapped(ends, dense), axis=-1).max()))
        if deviation <= tol or len(knots) > 256:
            break
        spans = 2 * (len(knots) - 1)
    angle = float(np.arctan2(cx, cy))

    def turned(edge, forward):
        c2d, a, b = forward.curveOnSurface(edge)
        c2d = c2d.copy()
        c2d.rotate(App.Base.Vector2d(0.0, 0.0), angle)
        return c2d, a, b

    built = face_on_pcurves(bspline_surface(fit), face, turned)
    if built is None:
        raise DeformError("A mapped face could not be rebuilt on its fitted surface; "
                          "change Tolerance.", "Tolerance")
    return built, deviation


def _breaks(surface, a, b, direction, most=64):
    """Initial fit breakpoints: the B-spline's own knots inside [a, b] (so its lower
    continuity there is kept), else four spans. (Fewer would make OCCT's Volume of the
    fitted face cheaper, about as the square of its spans, but from two spans a twisted
    plane of nist_ftc_10 passed its fit's midpoint checks and lay 1.9e-4 mm off the exact
    map elsewhere.)"""
    if surface.TypeId == "Part::GeomBSplineSurface":
        knots = np.array(surface.getUKnots() if direction == 0 else surface.getVKnots())
        inner = knots[(knots > a + 1e-12 * (b - a)) & (knots < b - 1e-12 * (b - a))]
        if len(inner) < most:
            return np.concatenate([[a], inner, [b]])
    return np.linspace(a, b, 5)


def bspline_surface(fit):
    """A Part.BSplineSurface from a SurfaceFit."""
    import FreeCAD as App
    uk, um = knots_and_mults(fit.uknots)
    vk, vm = knots_and_mults(fit.vknots)
    poles = [[App.Vector(*p) for p in row] for row in fit.poles.tolist()]
    pu, pv = surface_fit.degrees(fit.degree)
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(poles, um, vm, uk, vk, False, False, pu, pv)
    return s


def bspline_curve2d(fit):
    """A Geom2d B-spline curve from a CurveFit of 2D values."""
    import FreeCAD as App
    knots, mults = knots_and_mults(fit.knots)
    c = Part.Geom2d.BSplineCurve2d()
    c.buildFromPolesMultsKnots([App.Base.Vector2d(*p) for p in fit.poles.tolist()], mults,
                               knots, False, fit.degree)
    return c


def face_on_pcurves(surface, face, pcurve):
    """The face rebuilt on `surface`: every edge made from `pcurve(edge, forward face)` ->
    (Geom2d curve, first, last) on the new surface, wires in the face's order. A seam is made
    once and used both ways (OCCT's shape fixing then adds its second pcurve), so the
    face stays closed round it. None when OCCT cannot build a valid face."""
    forward = face.reversed() if face.Orientation == "Reversed" else face
    outer = forward.OuterWire
    wires = [outer] + [w for w in forward.Wires if not w.isSame(outer)]
    seamed = False
    try:
        built, made = [], {}
        for wire in wires:
            edges, ordered = [], wire.OrderedEdges
            twice = [e for e in ordered if sum(e.isSame(o) for o in ordered) == 2]
            # a seam first: OCCT's wire builder keeps its first edge and copies later
            # ones to join their vertices, which would split the seam's two uses
            first = next((k for k, e in enumerate(ordered) if e in twice), 0)
            for edge in ordered[first:] + ordered[:first]:
                if edge.Degenerated:  # left out: the shape fix below puts it back
                    continue
                twin = next((m for e, m in made.items() if e.isSame(edge)), None)
                if twin is not None and edge in twice:
                    edges.append(twin.reversed())
                    seamed = True
                    continue
                c2d, a, b = pcurve(edge, forward)
                new = c2d.toShape(surface, a, b)
                if edge.Orientation == "Reversed":
                    new.reverse()
                # a real file's pcurves meet only within its edges' tolerance
                new.fixTolerance(max([edge.Tolerance] + [v.Tolerance for v in edge.Vertexes]))
                made[edge] = new
                edges.append(new)
            _bridge_gaps(edges)
            built.append(Part.Wire(edges))
        result = Part.Face(surface, built[0])
        for wire in built[1:]:
            result = Part.Face(result, wire)
        valid = not seamed and not any(e.Degenerated for e in face.Edges) and result.isValid()
        if not valid:
            result.fix(1e-7, 1e-7, 1e-3)
            valid = result.isValid()
    except Part.OCCError:
        return None
    if face.Orientation == "Reversed":
        result.reverse()
    return result if valid else None


def _bridge_gaps(edges):
    """Raise the tolerance of consecutive edges (in wire order) to cover the gap between
    one's end and the next one's start: a real file's pcurves may miss each other by more
    than its stated tolerances, and OCCT's wire builder joins only within them."""
    def ends(e):
        a, b = e.valueAt(e.FirstParameter), e.valueAt(e.LastParameter)
        return (b, a) if e.Orientation == "Reversed" else (a, b)

    for e1, e2 in zip(edges, edges[1:] + edges[:1]):
        gap = (ends(e1)[1] - ends(e2)[0]).Length
        if gap > 0.5 * min(e1.Tolerance, e2.Tolerance):
            for e in (e1, e2):
                e.fixTolerance(max(e.Tolerance, 2.0 * gap))


# --- twist: surfaces of revolution about the axis ----------------------------------------

def _coaxial(surface, point, direction, tol=1e-9):
    """The surface's own axis lies on the twist axis (either sense)."""
    axis = np.array(tuple(surface.Axis if hasattr(surface, "Axis") else surface.Direction))
    loc = np.array(tuple(surface.Center if hasattr(surface, "Center") and
                         surface.TypeId != "Part::GeomSurfaceOfRevolution"
                         else surface.Location))
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    axis = axis / np.linalg.norm(axis)
    off = loc - np.asarray(point, float)
    return np.linalg.norm(np.cross(axis, d)) < tol and \
        np.linalg.norm(off - (off @ d) * d) < tol * max(1.0, np.linalg.norm(off))


def _turned_on_surface(face, smap, tol):
    """(face on its own surface with pcurves turned by u -> u +- angle(s), deviation), or
    None when OCCT cannot build it. The deviation bound is the 2D fit's, times the
    surface's largest speed |dS/du|, |dS/dv| over the face."""
    surface = face.Surface
    point, direction = smap.twist_axis
    axis = np.array(tuple(surface.Axis if hasattr(surface, "Axis") else surface.Direction))
    sign = 1.0 if axis @ np.asarray(direction, float) > 0 else -1.0
    u0, u1, v0, v1 = face.ParameterRange
    grid = surface_grid(surface, np.linspace(u0, u1, 9), np.linspace(v0, v1, 9))
    speed = max(np.linalg.norm(np.diff(grid, axis=0), axis=-1).max() * 8 / max(u1 - u0, 1e-300),
                np.linalg.norm(np.diff(grid, axis=1), axis=-1).max() * 8 / max(v1 - v0, 1e-300),
                1e-300)
    worst = [0.0]
    value = surface.value

    def pcurve(edge, forward):
        c2d, a, b = forward.curveOnSurface(edge)

        def turned(T):
            uv = np.array([(p.x, p.y) for p in map(c2d.value, T)], float)
            pts = np.array([tuple(value(u, v)) for u, v in uv], float)
            return uv + np.outer(sign * smap.angle_of(smap.s(pts)), [1.0, 0.0])

        probe = turned(np.linspace(a, b, 9))[:, 0] - np.array(
            [c2d.value(t).x for t in np.linspace(a, b, 9)])
        if np.ptp(probe) < 1e-13:  # an edge at one s: the pcurve shifted, exactly
            import FreeCAD as App
            moved = c2d.copy()
            moved.translate(App.Base.Vector2d(float(probe[0]), 0.0))
            return moved, a, b
        fit = surface_fit.fit_curve(turned, a, b, tol / (2 * speed))
        worst[0] = max(worst[0], fit.deviation * speed * 2)
        return bspline_curve2d(fit), a, b

    built = face_on_pcurves(surface, face, pcurve)
    if built is None or _past_period(built):
        return None
    return built, worst[0]


def _past_period(face):
    """Whether the face's parameter range is wider than its surface's period in u (a
    sphere's seam turned into a helix: the face runs from the seam's lower end round to
    its upper one). OCCT takes such a face as valid, but its sections and booleans lose
    the part past the period: a sphere twisted about its axis sliced to an open wire, and
    its common with a box was empty)."""
    u0, u1 = face.ParameterRange[:2]
    return face.Surface.isUPeriodic() and u1 - u0 > face.Surface.UPeriod() * (1 + 1e-12)


# --- loose wireframes --------------------------------------------------------------------

def map_loose(parts, smap, tol):
    """(loose parts of the region through the map, largest deviation): free faces and
    shells refit face by face as a solid's faces are (planes stay planes under an affine
    map) and sewn again; wires, edges and vertices as _loose maps them."""
    out, worst = [], 0.0
    for part in parts:
        if not part.Faces:
            out += _loose([part], smap, tol)
            continue
        faces, dev = _mapped_faces(part.Faces, smap, tol, what="A loose face")
        worst = max(worst, dev)
        if len(faces) == 1:
            out += faces
            continue
        # sewn again where they met: shells, and the faces sewing leaves in none
        shells, free = brep.shells_of(_sewn(faces, max(4.0 * dev, 1e-6)))
        out += shells + free
    return out, worst


def _loose(parts, smap, tol):
    """Loose edges and vertices: those at one s moved exactly, the others refit."""
    out = []
    for part in parts:
        pts = np.array([tuple(v.Point) for v in part.Vertexes], float)
        s = smap.s(pts) if len(pts) else np.zeros(1)
        if np.ptp(s) < 1e-12 and (s[0] <= 0 or s[0] >= 1 or part.ShapeType == "Vertex"):
            out += _moved([part], smap.matrices([s[0]])[0])
            continue
        edges = []
        for edge in part.Edges:
            def image(T, e=edge):
                return smap(np.array([tuple(e.valueAt(t)) for t in T]))
            a, b = edge.FirstParameter, edge.LastParameter
            curve = _curve3d(surface_fit.fit_curve(image, a, b, tol))
            # the ends exactly where the map puts them (the fit leaves them up to `tol`
            # off, 2e-5 mm on a 194 mm edge, and the edges of a wire would not meet)
            ends = image([a, b])
            curve.setPole(1, vector(ends[0]))
            curve.setPole(curve.NbPoles, vector(ends[1]))
            edges.append(curve.toShape())
        out.append(Part.Wire(edges) if part.ShapeType == "Wire" else Part.makeCompound(edges))
    return out


def _curve3d(fit):
    import FreeCAD as App
    knots, mults = knots_and_mults(fit.knots)
    c = Part.BSplineCurve()
    c.buildFromPolesMultsKnots([App.Vector(*p) for p in fit.poles.tolist()], mults, knots,
                               False, fit.degree)
    return c


# --- what the result reports -------------------------------------------------------------

def continuity_report(shape, smap):
    """Continuity and SplitFaces outputs: a face crossing a joint is G1 there when its
    normal is perpendicular to the jump of the map's derivative along the normal (zero
    for a Smooth profile: the joint is C1), else C0."""
    worst, faces = {}, shape.Faces
    for side, origin in ((0, smap.origin), (1, smap.origin + smap.gap * smap.normal)):
        found, sliced = [], []
        lo, hi = brep.extents(faces, origin, smap.normal)
        for i in np.flatnonzero((lo < -brep.TOL) & (hi > brep.TOL)):
            section = _polygon_section(faces[i], origin, smap.normal)
            if section is None:
                sliced.append(i)
            else:
                normal = np.array(tuple(faces[i].Surface.Axis), float)
                found.append((f"Face{i + 1}", section, np.tile(normal, (len(section), 1))))
        if sliced:  # OCCT's section of the other faces, named back by their index
            for name, face, edges in brep.crossing_faces(
                    Part.makeCompound([faces[i] for i in sliced]), origin, smap.normal):
                found.append((f"Face{sliced[int(name[4:]) - 1] + 1}",
                              *brep.joint_normals(face, edges)))
        found = [f for f in found if len(f[1])]
        if not found:
            continue
        # the map's derivative at all the faces' points at once (one solve, not one a face)
        points, normals = (np.vstack([f[k] for f in found]) for k in (1, 2))
        jump = smap.normal_derivative(points, side)
        size = np.linalg.norm(jump, axis=1)
        cos = np.abs(np.einsum("ij,ij->i", normals, jump)) / np.linalg.norm(normals, axis=1)
        g1 = (size < 1e-6) | (cos <= 1e-6 * np.maximum(size, 1e-300))
        ends = np.cumsum([len(f[1]) for f in found])[:-1]
        for (name, _, _), ok in zip(found, np.split(g1, ends)):
            kind = "G1" if np.all(ok) else "C0"
            worst[name] = "C0" if "C0" in (kind, worst.get(name)) else kind
    entries = sorted(worst.items(), key=lambda item: int(item[0][4:]))
    return {"Continuity": continuity.report(entries), "SplitFaces": [n for n, _ in entries]}


def _polygon_section(face, origin, normal):
    """The points where a planar face bounded by straight edges crosses the plane: the ends
    of its section's segments, exactly (no OCCT section, 3 ms a face). The map's jump is
    affine along them (every map of ours moves the section at s by an affine A(s)) and the
    face's normal is constant, so Lemma 1 holds on the segments when it holds at their
    ends. None for any other face, or one with a vertex on the plane (left to the slice)."""
    if face.Surface.TypeId != "Part::GeomPlane" or not all(
            isinstance(e.Curve, Part.Line) for e in face.Edges):
        return None
    ends = np.array([[tuple(v.Point) for v in e.Vertexes] for e in face.Edges], float)
    if ends.shape[1:] != (2, 3):
        return None
    s = (ends - origin) @ normal
    if np.any(np.abs(s) <= brep.TOL):
        return None
    cross = s[:, 0] * s[:, 1] < 0
    a, b = ends[cross, 0], ends[cross, 1]
    w = (s[cross, 0] / (s[cross, 0] - s[cross, 1]))[:, None]
    return a + w * (b - a)


def deviation_check(result, original_faces, smap, count=200, seed=0):
    """Largest distance from random points of the mapped original faces to the result
    (an independent check of MaxDeviation: the exact map of the original, not the fits)."""
    rng = np.random.default_rng(seed)
    pts = []
    for face in original_faces:
        u0, u1, v0, v1 = face.ParameterRange
        for _ in range(count):
            u, v = rng.uniform(u0, u1), rng.uniform(v0, v1)
            if face.isPartOfDomain(u, v):
                pts.append(tuple(face.Surface.value(u, v)))
    if not pts:
        return 0.0
    mapped = smap(np.array(pts, float))
    return max(result.distToShape(Part.Vertex(vector(p)))[0] for p in mapped)
