"""Stretch (Wu & Ilies, Cases 1 to 3): split at a plane, move the far part along the normal
by `distance`, fill the gap with the section swept; between two planes (`gap` beyond the
first) the region is stretched, its cross-sections kept; Case 3 splits at the surface the
Polyline extrudes.

solid(shape, ...), polyline(shape, ...), mesh(mesh, ...) and points(cloud, ...) give
(result, outputs); stretch_shape is the B-rep pipeline alone.
"""
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.mesh.stretch import stretch_mesh
from ..geometry.sweep.polyline import PolylineSurface
from ..geometry.points.stretch import stretch_points
from ..geometry.sweep import space_map
from ..shapes import brep, mapped
from ..shapes.convert import mesh_arrays, mesh_eps, points_from_array
from . import planes as pp


def solid(shape, origin, normal, distance, gap=None, tolerance=1e-3):
    """(shape, {VolumeChange, Continuity, SplitFaces, MaxDeviation}) of a B-rep stretched
    by `distance` beyond Plane (origin, unit normal), or between Plane and the plane `gap`
    beyond it; `tolerance` bounds the refit faces of a region whose outline changes."""
    report = {"MaxDeviation": 0.0, "VolumeChange": 0.0}
    result = stretch_shape(shape, origin, normal, distance, gap, tolerance, report)
    joints = [(origin, normal, pp.constant(normal))]
    if gap is not None:
        joints.append((origin + gap * normal, normal, pp.constant(normal)))
    key = ("translation", tuple(origin), tuple(normal), gap)  # the tangents are the normal
    return result, {**pp.joint_report(shape, joints, key), **report}


def mesh(base, origin, normal, distance, gap=None):
    """(Mesh, {VolumeChange}) of a closed triangle mesh stretched likewise."""
    second = () if gap is None else (origin + gap * normal, normal)
    v, t = mesh_arrays(base)
    return pp.mesh_result((v, t), *stretch_mesh(v, t, origin, normal, distance, *second,
                                              eps=mesh_eps(v)))


def points(base, origin, normal, distance, gap=None):
    """(Points, {IgnoredPoints}) of a point cloud stretched likewise, the gap filled at the
    cloud's spacing."""
    second = () if gap is None else (origin + gap * normal, normal)
    pts, ignored = pp.cloud(base)
    return points_from_array(stretch_points(pts, origin, normal, distance, *second)), ignored


def polyline(shape, points, normal, distance):
    """(shape, {VolumeChange, Continuity, SplitFaces}) of Case 3: split at the surface that
    extrudes the Polyline's corners `points` (in a plane containing `normal`), the far part
    moved by distance * normal, the gap the folded section extruded."""
    surface = PolylineSurface([tuple(p) for p in points], normal)
    result = stretch_polyline(shape, surface, distance)
    u = surface.lateral_axis
    lows = np.r_[-np.inf, surface.lateral[1:-1]]  # the end segments extend outward
    highs = np.r_[surface.lateral[1:-1], np.inf]
    joints = [(a, m, pp.constant(normal),
               lambda p, lo=lo, hi=hi: ((p @ u) >= lo - 1e-9) & ((p @ u) <= hi + 1e-9))
              for (a, m), lo, hi in zip(surface.segment_planes(), lows, highs)]
    return result, {**pp.volume_change(result, shape), **pp.joint_report(shape, joints)}


def stretch_polyline(shape, surface, distance):
    """Case 3: each solid split at the Polyline's surface, the far part moved, the gap extruded."""
    move = distance * surface.normal

    def joints(pts):  # on the Polyline's surface, or on its moved copy
        off = surface.offset(pts)
        return bool(np.all(np.abs(off) < 1e-7) or np.all(np.abs(off - distance) < 1e-7))

    def solid_fn(solid):
        if distance > 0:
            near, far = brep.split_by(solid, [brep.polyline_sheet(solid, surface)],
                                      surface.offset, [0.0])
            cut = brep.faces_on_surface(near, surface)
            pieces = near + brep.extruded(cut, move) + brep.translated(far, move)
            return brep.join(pieces, joints, "Polyline")
        near, slab, far = brep.split_by(
            solid, [brep.polyline_sheet(solid, surface),
                    brep.polyline_sheet(solid, surface, -distance)],
            surface.offset, [0.0, -distance])
        if near and slab and not far:
            raise DeformError(f"Distance {distance:g} shrinks past the end of the part; reduce "
                              f"Distance.", "Distance")
        return brep.join(near + brep.translated(far, move), joints,
                         "Polyline") if near or far else None

    def loose_fn(parts):
        return [p.translated(brep.vector(move)) if surface.offset(
            np.array([tuple(p.CenterOfMass if p.ShapeType != "Vertex" else p.Point)]))[0] > 0
            else p.copy() for p in parts]

    solids = brep.solids_of(shape)
    offsets = np.concatenate([surface.offset(np.array([tuple(v.Point) for v in s.Vertexes]))
                              for s in solids])
    if not (offsets.min() < 0 < offsets.max()):
        raise DeformError("Polyline misses the part: the whole part lies on one side of it; "
                          "move its points so the surface crosses the part.", "Polyline")
    import Part
    out = [r for r in map(solid_fn, solids) if r is not None] + loose_fn(brep.loose_parts(shape))
    return out[0] if len(out) == 1 else Part.makeCompound(out)


def stretch_shape(shape, origin, normal, distance, gap=None, tolerance=1e-3, report=None):
    """The stretched shape: each solid of `shape` split, moved, filled and joined; between
    two planes a region whose outline changes goes through the stretch's space map
    (shapes.mapped, faces refit within `tolerance`; report["MaxDeviation"] their largest
    deviation; report["VolumeChange"] the material gained, see _stretch_solid)."""
    if gap is not None and gap + distance <= 0:
        raise DeformError(f"Distance {distance:g} would collapse the region between the planes "
                          f"(gap {gap:g}); keep Distance above {-gap:g}.", "Distance")
    smap = None if gap is None else space_map.stretch_map(origin, normal, gap, distance)

    def refit(pieces, deviation):
        """The pieces the stretch map gave; their largest fit deviation is reported."""
        if report is not None:
            report["MaxDeviation"] = max(report.get("MaxDeviation", 0.0), deviation)
        return pieces

    def stretched(solid):
        result, change = _stretch_solid(solid, origin, normal, distance, gap,
                                        lambda zones: refit(*mapped.map_solid(
                                            solid, smap, tolerance, "Tolerance", zones)))
        if report is not None:
            if change is None:  # measured: the result's volume less the solid's (remembered)
                change = (brep.solids_volume(result) if result is not None else 0.0) - \
                    brep.solids_volume(solid)
            report["VolumeChange"] = report.get("VolumeChange", 0.0) + change
        return result

    return pp.deform_shape(
        shape, origin, normal, gap, stretched,
        lambda parts: _stretch_loose(parts, origin, normal, distance, gap,
                                     lambda between: refit(*mapped.map_loose(
                                         between, smap, tolerance))))


def _stretch_solid(solid, origin, normal, distance, gap, through_map):
    """(the solid stretched, or None when nothing of it is left; the volume it gains).
    `through_map(zones)` takes the split solid through the stretch map.

    The pieces of a split partition the solid, so where the result is made of them and of
    prisms its gain is exact without measuring the whole result: the prisms' volume (cut
    area times length) less the pieces left out (measured, a slab is small). A result
    through the stretch map gives None: it is measured."""
    move = distance * normal
    if distance == 0:
        return solid.copy(), 0.0
    if gap is not None:
        zones = brep.split_zones(solid, origin, normal, [0.0, gap])
        near, between, far = zones
        cut = brep.section_faces(between, origin, normal)
        if not between or (cut and brep.is_prismatic(between, origin, normal, gap)):
            middle = brep.extruded(cut, (gap + distance) * normal) if between else []
            change = _area(cut) * (gap + distance) - _volume(between) if between else 0.0
            return _joined(near + middle + brep.translated(far, move),
                           [(origin, normal), (origin + (gap + distance) * normal, normal)]), change
        # planes stay planes and cylinders along the normal stay themselves; other faces
        # are refit (OCCT's own affine transform approximates circles to about 1e-3)
        return through_map(zones), None
    if distance > 0:
        near, far = brep.split_zones(solid, origin, normal, [0.0])
        cut = brep.section_faces(far, origin, normal)
        return _joined(near + brep.extruded(cut, move) + brep.translated(far, move),
                       [(origin, normal), (origin + move, normal)]), _area(cut) * distance
    near, slab, far = brep.split_zones(solid, origin, normal, [0.0, -distance])
    if near and slab and not far:
        reach = max(brep.extent(s, origin, normal)[1] for s in slab) - brep.TOL
        raise DeformError(f"Distance {distance:.10g} shrinks past the end of the part, which "
                          f"reaches {reach:.10g} beyond Plane; keep Distance above "
                          f"{-reach:.10g}.", "Distance")
    return _joined(near + brep.translated(far, move), [(origin, normal)]), -_volume(slab)


def _area(faces):
    return sum(f.Area for f in faces)


def _volume(solids):
    return sum(brep.solids_volume(s) for s in solids)


def _joined(pieces, joints):
    return brep.join(pieces, joints) if pieces else None


def _stretch_loose(parts, origin, normal, distance, gap, through_map):
    """Wireframes and free faces: the same split and motion, cut points swept across the
    gap; between two planes the region's pieces go through the stretch map like a solid's
    faces (`through_map(pieces)`: planes stay planes, the rest refit)."""
    move = distance * normal
    if not parts or distance == 0:
        return [p.copy() for p in parts]
    if gap is not None:
        near, between, far = brep.split_loose(parts, origin, normal, [0.0, gap])
        return near + through_map(between) + brep.translated(far, move)
    if distance > 0:
        near, far = brep.split_loose(parts, origin, normal, [0.0])
        _, cut, wires = brep.split_sheet(near, origin, normal)
        fill = (brep.extruded(cut, move)
                + brep.swept_points(brep.points_on_plane(wires, origin, normal), move))
        return brep.sheets(near + fill + brep.translated(far, move))
    near, _, far = brep.split_loose(parts, origin, normal, [0.0, -distance])
    return brep.sheets(near + brep.translated(far, move))
