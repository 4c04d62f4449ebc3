"""What the Stretch, Bend, Twist and Taper pipelines share (Wu & Ilies's split at separating
planes, sweep, join): the per-solid driver, the loft of a general motion, the joints'
continuity report (Lemma 1), cross-sections and their centroids, and the outputs every
kind of Base gives (VolumeChange, IgnoredPoints)."""
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.sweep import continuity
from ..geometry.sweep import motion as mo
from ..geometry.sweep import planes as pl
from ..geometry.sweep.defaults import extents as box_extents
from ..shapes import brep


def check_crossing(parts, origin, normal, gap=None):
    """The planes must cut the part (by more than the modelling tolerance): one that misses
    or only touches it is bad input for Plane or Plane2."""
    lo = min(brep.extent(s, origin, normal)[0] for s in parts)
    hi = max(brep.extent(s, origin, normal)[1] for s in parts)
    _check_extent(lo, hi, gap)
    try:
        _check_extent(*_vertex_extent(parts, origin, normal), gap)
    except DeformError:
        # OCCT's BoundBox of a file's solid can be loose (bounded by the poles: 3 times
        # occt_screw.step's width), and a plane that misses the material passes it; the
        # vertices lie on the part, so they settle most planes, the geometry's own box
        # (0.1 to 1 s on a big part) the rest, near the part's ends
        boxes = [s.optimalBoundingBox(False) for s in parts]
        rows = np.array([(b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax) for b in boxes])
        ends = box_extents(rows[:, :3], rows[:, 3:], origin, normal)
        _check_extent(float(ends[0].min()), float(ends[1].max()), gap)


def _check_extent(lo, hi, gap):
    """The planes cross a part reaching from lo to hi beyond Plane."""
    pl.check_crossing([lo, hi], "Plane", brep.TOL)
    if gap is not None:
        pl.check_crossing([lo - gap, hi - gap], "Plane2", 0.0, where=None)


def _vertex_extent(parts, origin, normal):
    """(min, max) signed distance of the parts' vertices to the plane: within the part's."""
    pts = np.array([tuple(v.Point) for s in parts for v in s.Vertexes], float).reshape(-1, 3)
    if not len(pts):
        return 0.0, 0.0
    d = (pts - origin) @ normal
    return float(d.min()), float(d.max())


def deform_shape(shape, origin, normal, gap, solid_fn, loose_fn):
    """Each solid through `solid_fn(solid)`, wireframes through `loose_fn(parts)`.

    solid_fn returns one solid or None; the result is one solid or a compound.
    """
    import Part
    solids = brep.solids_of(shape, loose_allowed=True)
    loose = brep.loose_parts(shape)
    check_crossing(solids + loose, origin, normal, gap)
    out = [r for r in (solid_fn(s) for s in solids) if r is not None]
    out += loose_fn(loose)
    return out[0] if len(out) == 1 else Part.makeCompound(out)


_REPORTS = []  # (shape, key, report) of recent joint reports, most recently used last


def joint_report(shape, joints, key=None):
    """Output values for the faces that the planes cut.

    `joints` are (origin, normal, tangents[, keep]) with tangents(points) the trajectory
    tangents of the joint points and keep(points) an optional mask of the points that lie
    on the joint (a segment of a Polyline's surface); a face is G1 only if it is G1 at every
    joint it crosses. A hashable `key` that fixes the joints (tangents too) has the report
    remembered for the last few shapes: it depends on the Base and the planes alone, so a
    Distance edit need not slice the Base again.
    """
    if key is not None:
        hit = next((k for k, (held, held_key, _) in enumerate(_REPORTS)
                    if held_key == key and held.isEqual(shape)), None)
        if hit is None:
            import Part
            # a handle of its own on the same shape (holding it keeps the identity unique):
            # the caller's object may be moved in place (translate, Placement) and must miss
            _REPORTS.append((Part.Shape(shape), key, joint_report(shape, joints)))
            del _REPORTS[:-4]
        else:
            _REPORTS.append(_REPORTS.pop(hit))
        report = _REPORTS[-1][2]
        return {**report, "SplitFaces": list(report["SplitFaces"])}
    worst = {}
    for origin, normal, tangents, *keep in joints:
        for name, face, edges in brep.crossing_faces(shape, origin, normal):
            points, normals = brep.joint_normals(face, edges)
            if keep:
                mask = keep[0](points)
                points, normals = points[mask], normals[mask]
            if not len(points):
                continue
            kind = continuity.joint_continuity(normals, tangents(points))
            worst[name] = "C0" if "C0" in (kind, worst.get(name)) else kind
    entries = sorted(worst.items(), key=lambda item: int(item[0][4:]))
    return {"Continuity": continuity.report(entries), "SplitFaces": [n for n, _ in entries]}


def motion_joints(origin, normal, motion):
    """Joint planes and Lemma 1 tangents of a Case 1 sweep by `motion`: at the Plane, and
    at the far part's face (tangents at t = 1 turned back to the original frame)."""
    end = motion.matrix(1.0)
    return [(origin, normal, lambda p: motion.velocity(p, 0.0)),
            (mo.apply(end, origin[None])[0], end[:3, :3] @ normal,
             lambda p: motion.velocity(mo.apply(np.linalg.inv(end), p), 1.0) @ end[:3, :3])]


def sweep_solid(solid, origin, normal, motion, samples, prop="KeyPlacements"):
    """Case 1 with a general motion (Steps 4-7): the section swept through profiles normal
    to the path of its centroid, placed and turned by the motion, and lofted."""
    near, far = brep.split_zones(solid, origin, normal, [0.0])
    cut = brep.shared_section(near, far, origin, normal)  # the loft starts from near's faces
    end = motion.matrix(1.0)
    if not cut:  # this solid lies on one side: kept or moved whole
        return (near + brep.transformed(far, end))[0]
    centroid = sum(np.array(tuple(f.CenterOfMass)) * f.Area for f in cut) / sum(
        f.Area for f in cut)
    ts = np.linspace(0.0, 1.0, samples + 1)
    frames = mo.profile_frames(motion, centroid, ts)
    across = brep.projected(cut, origin, normal, frames[0])
    profiles = ([cut] + [brep.transformed(across, f @ np.linalg.inv(frames[0]))
                         for f in frames[1:-1]] + [brep.transformed(cut, end)])
    for t, profile in zip(ts[1:], profiles[1:]):  # the sweep must not reach back into the part
        reach = min(float(((brep.sample_points(f) - origin) @ normal).min()) for f in profile)
        if reach < -brep.TOL:
            raise DeformError(f"The path leaves Plane too obliquely: the profile at t = {t:.2g} "
                              f"reaches {-reach:.3g} mm behind Plane; change {prop} or "
                              f"Interpolation.", prop)
    joints = [(origin, normal), (mo.apply(end, origin[None])[0], end[:3, :3] @ normal)]
    return lofted_join(near, cut, profiles, far, (origin, normal), end, joints, prop)


def lofted_join(near, cut, profiles, far, far_plane, end, joints, prop):
    """One solid from the near pieces, the loft through `profiles` (from the near part's
    `cut` faces to the far part's section at `far_plane`, moved by `end`) and the far
    pieces: their faces sewn, the cut faces left out."""
    import Part
    moved = brep.transformed(far, end)  # the same faces in the same order, moved
    brep.check_apart(near, moved, prop, joints[0])  # the near pieces lie behind Plane
    far_cut = brep.faces_on_plane(far, *far_plane)
    sides = brep.loft_sides(profiles, prop)
    faces = ([f for s in near for f in s.Faces if not any(f.isSame(c) for c in cut)]
             + sides
             + [g for s, t in zip(far, moved) for f, g in zip(s.Faces, t.Faces)
                if not any(f.isSame(c) for c in far_cut)])
    return brep.glue(near + [Part.makeCompound(sides)] + moved, faces, joints) or \
        brep.join_faces(faces, joints, prop)


def sections(solids, origin, normal, offsets):
    """The cross-section faces of `solids` at each offset along `normal` (one list each),
    solid by solid: the solids of an assembly may overlap, and one face maker over all their
    wires would nest one solid's outline in another's."""
    import Part
    out = []
    for off in offsets:
        d = float(np.dot(origin + off * normal, normal))
        faces = []
        for solid in solids:
            wires = _slice(solid, normal, d)
            if wires:
                faces += Part.makeFace(wires, "Part::FaceMakerBullseye").Faces
        out.append(faces)
    return out


def _slice(solid, normal, d):
    """solid.slice(normal, d): OCCT slices a solid through a boolean with a half-space, which
    takes 0.86 s on fc_blocks144's 996 faces. Where the plane meets only planar faces, in
    general position (no vertex within its tolerance of the plane), the section of the
    faces whose boxes reach it, as shells, gives the same loops in 0.057 s; those are
    taken when every one is closed, else (a box too tight) the solid's slice. (Across
    curved faces the two differ: 1.2 % of the area on occt_Bottom's B-spline faces, where
    the half-space's is 0.2 % from a thin slab's volume.)"""
    import Part
    import FreeCAD as App
    n = App.Vector(*normal)
    size = float(np.linalg.norm(normal))
    unit, at = np.asarray(normal, float) / size, d / size      # the plane unit . x = at
    vertices = solid.Vertexes
    s = np.array([tuple(v.Point) for v in vertices], float).reshape(-1, 3) @ unit - at
    if len(s) and (np.abs(s) > np.array([v.Tolerance for v in vertices]) + brep.TOL).all():
        faces = solid.Faces
        lo, hi = brep.extents(faces, at * unit, unit)
        near = [faces[i] for i in np.flatnonzero((lo <= brep.TOL) & (hi >= -brep.TOL))]
        if near and all(isinstance(f.Surface, Part.Plane) for f in near):
            wires = Part.makeShell(near).slice(n, d)
            if wires and all(w.isClosed() for w in wires):
                return wires
    return solid.slice(n, d)


def section_centroid(solids, origin, normal):
    """Area centroid of the cross-section at the plane (the default twist axis passes here)."""
    faces = sections(solids, origin, normal, [0.0])[0]
    if not faces:
        raise pl.missed("Plane")
    area = sum(f.Area for f in faces)
    return sum(np.array(tuple(f.CenterOfMass)) * f.Area for f in faces) / area


def section_centroid_mesh(mesh, origin, normal, arrays=None):
    """Area centroid of the mesh's cross-section at the plane, as section_centroid's of a
    solid (a mesh tessellated from it twists about nearly the same axis); `arrays` are the
    mesh's (vertices, triangles) when already at hand.

    Each facet crossing the plane gives one edge of the section, oriented by the facet's
    outward normal, so holes count negative; an open mesh's section without area (a sheet
    cut across) gives the centroid of its polylines instead. In numpy on the arrays: 20x
    faster than FreeCAD's crossSections for a million facets."""
    from ..shapes.convert import mesh_arrays
    V, T = mesh_arrays(mesh) if arrays is None else arrays
    o, n = np.asarray(origin, float), np.asarray(normal, float)
    s = (V - o) @ n
    pos = (s > 0).view(np.int8).take(T)
    rows = np.flatnonzero((pos.sum(axis=1) % 3) != 0)       # one or two corners beyond
    if not len(rows):
        raise pl.missed("Plane")
    tri = T[rows]
    side = pos[rows].astype(bool)
    ends = []
    for j in range(3):               # the point where edge j (corner j -> j+1) crosses
        i, k = tri[:, j], tri[:, (j + 1) % 3]
        t = (s[i] / np.where(s[i] == s[k], 1.0, s[i] - s[k]))[:, None]
        ends.append((side[:, j] != side[:, (j + 1) % 3], V[i] + t * (V[k] - V[i]) - o))
    (c0, e0), (c1, e1), (c2, e2) = ends
    p = np.where(c0[:, None], e0, e1)                       # the first crossing edge's point
    q = np.where(c0[:, None] & c1[:, None], e1, e2)         # and the second's
    a, b, c = (V[tri[:, j]] for j in range(3))
    ccw = np.einsum("ij,ij->i", q - p, np.cross(n, np.cross(b - a, c - a))) >= 0
    p, q = np.where(ccw[:, None], p, q), np.where(ccw[:, None], q, p)
    w = np.cross(p, q) @ n                                   # twice each edge's triangle
    area = w.sum() / 2
    length = np.linalg.norm(q - p, axis=1)
    if abs(area) <= 1e-9 * max(length.sum(), 1e-300) ** 2:
        mid = (p + q) / 2
        return o + (length @ mid / length.sum() if length.sum() > 0 else mid.mean(axis=0))
    centre = ((p + q) * w[:, None]).sum(axis=0) / (6 * area)
    return o + centre - (centre @ n) * n


def section_centroid_cloud(points, origin, normal):
    """Mean of the cloud's section points (points.stretch.section_band), put on the plane."""
    from ..geometry.points.stretch import section_band, spacing
    s = (points - origin) @ normal
    near = points[section_band(s, 2 * spacing(points))]
    if len(near) == 0:
        raise pl.missed("Plane")
    return near.mean(axis=0) - ((near.mean(axis=0) - origin) @ normal) * normal


def mesh_result(base_arrays, vertices, triangles):
    """The new Mesh and its VolumeChange, measured in float64 on the arrays (the Base's
    `base_arrays`, (vertices, triangles), and the result's)."""
    from ..geometry.mesh.measure import mesh_volume
    from ..shapes.convert import mesh_from_arrays
    change = mesh_volume(vertices, triangles) - mesh_volume(*base_arrays)
    return mesh_from_arrays(vertices, triangles), {"VolumeChange": change}


def cloud(points):
    """The finite points of a Points.Points and the IgnoredPoints output."""
    from ..shapes.convert import points_array
    pts = points_array(points)
    return pts, {"IgnoredPoints": points.CountPoints - len(pts)}


def volume_change(result, shape):
    """Material gained, from the solids alone (loose faces have no volume; a reversed
    Base solid counts as the material it bounds)."""
    return {"VolumeChange": brep.solids_volume(result) - brep.solids_volume(shape)}


def constant(vector):
    """A tangent field equal to `vector` everywhere (a translation)."""
    return lambda points: np.broadcast_to(vector, np.shape(points))


def profiled(of_s, profile):
    """The motion of the fraction s / gap of a region (twist_motion, bend_motion) taken at
    profile(s) instead of s, as the solids' space maps do (space_map.SpaceMap: p ->
    A(profile(s)) p): a Smooth Twist or two-plane Bend of a mesh or cloud was Linear."""
    from ..geometry.sweep import space_map
    if profile == "Linear":
        return of_s
    space_map.profile_value(profile, 0.0)       # an unknown Profile is refused here

    def motion(frac):
        return of_s(space_map.profile_value(profile, frac))
    motion.vectorized = True
    return motion
