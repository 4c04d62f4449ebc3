"""Taper (Wu & Ilies, the scaling function of Step 6 and Fig. 11): the region between Plane
and the plane `gap` beyond it is scaled across an axis by scale(s), 1 at Plane to `scale`
at the far plane (a pair: along the axis frame's X and Y); the part beyond is scaled by
`scale`. Solids go through the space map face by face (shapes.mapped), meshes and point
clouds vertex by vertex (a mesh cut into slabs first).

The axis frame `rows` is a 3x3 array whose rows are its X, Y and Z (Z along the normal);
`point` is a point on the axis, or None for the centroid of the section at Plane.
solid(shape, ...), mesh(mesh, ...) and points(cloud, ...) give (result, outputs).
"""
import numpy as np

from ..geometry.errors import DeformError
from ..geometry.mesh import sweep as mesh_sweep
from ..geometry.sweep import space_map
from ..shapes import brep, mapped
from ..shapes.convert import mesh_arrays, mesh_eps, points_from_array
from . import planes as pp


def solid(shape, origin, normal, gap, scale, rows, point=None, profile="Linear",
          tolerance=1e-3):
    """(shape, {VolumeChange, MaxDeviation, Continuity, SplitFaces}) of a tapered B-rep.
    Refused, naming Scale, where a refit face would fold where the factor, continued past
    the planes over the face's parameter range, passes zero (mapped.FoldsPastPlanes)."""
    solids = brep.solids_of(shape)
    pp.check_crossing(solids, origin, normal, gap)
    if point is None:
        point = pp.section_centroid(solids, origin, normal)
    _check_scale(shape, scale, point, rows[2], tolerance, gap)
    smap = taper_map(origin, normal, gap, scale, rows, point, profile)
    try:
        result, deviation = mapped.map_shape(shape, smap, tolerance)
    except mapped.FoldsPastPlanes as fold:
        scales = np.atleast_1d(np.asarray(scale, float))
        raise DeformError(f"Scale {scales[np.argmax(np.abs(scales - 1.0))]:g} takes the "
                          f"taper's factor down to zero about {abs(fold.past):.3g} mm "
                          f"{fold.side}, "
                          f"inside the parameter range of a face the region cuts, whose "
                          f"refitted surface then folds (self-intersecting); bring Scale "
                          f"nearer 1 or move Plane2 farther from Plane.", "Scale") from None
    return result, {**pp.volume_change(result, shape), "MaxDeviation": deviation,
                    **mapped.continuity_report(shape, smap)}


FOLD_MARGIN = 20.0  # the narrowest tapered width, in Tolerances, that refits keep unfolded


STEEPEST = 500.0  # the sideways move across the region per length along it, at most


def _check_scale(shape, scale, point, axis, tolerance, gap):
    """A solid shrunk to a width of a few Tolerances gets refitted faces that fold (OCCT's
    check: self-intersecting; a cylinder 16 mm across at Scale 0.001), and one scaled over a
    region far thinner than its width tilts faces so steeply that the refit faces no
    longer meet (OCCT's fuzzy fuse of them never returned): refuse both."""
    bb = shape.BoundBox
    corners = np.array([(x, y, z) for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
                        for z in (bb.ZMin, bb.ZMax)]) - point
    width = np.linalg.norm(corners - np.outer(corners @ axis, axis), axis=1).max()
    least = float(np.min(scale))
    if 0 < least * width < FOLD_MARGIN * tolerance:
        raise DeformError(f"Scale {least:g} would shrink the part to about {least * width:.3g} "
                          f"mm across, within {FOLD_MARGIN:g} x Tolerance of nothing, where "
                          f"refitted faces fold; keep Scale at "
                          f"{FOLD_MARGIN * tolerance / width:.3g} or more (or lower "
                          f"Tolerance).", "Scale")
    scales = np.atleast_1d(np.asarray(scale, float))
    steepest = float(scales[np.argmax(np.abs(scales - 1.0))])   # the scale farthest from 1
    steep = abs(steepest - 1.0) * width / gap
    if steep > STEEPEST:
        raise DeformError(f"Scale {steepest:g} over the {gap:.3g} mm between Plane and Plane2 moves "
                          f"the part {steep:.3g} times farther sideways than along the region "
                          f"(at most {STEEPEST:g}); move Plane2 farther from Plane (at least "
                          f"{gap * steep / STEEPEST:.3g} mm) or bring Scale nearer 1.", "Plane2")


MESH_SLABS = 16  # the region of a mesh is cut into this many slabs before the map


def mesh(base, origin, normal, gap, scale, rows, point=None, profile="Linear"):
    """(Mesh, {VolumeChange}): the mesh cut at Plane, Plane2 and the planes of MESH_SLABS
    slabs between (a triangle reaching across the region would keep the part before
    Plane and beyond Plane2 flat with it, and cut corners inside), then every vertex
    through the taper map."""
    v, t = mesh_arrays(base)
    if point is None:
        point = pp.section_centroid_mesh(base, origin, normal, (v, t))
    smap = taper_map(origin, normal, gap, scale, rows, point, profile)
    w, cut = mesh_sweep.slab_cut(v, t, origin, normal, gap, MESH_SLABS, mesh_eps(v))
    return pp.mesh_result((v, t), smap(w), cut)


def points(base, origin, normal, gap, scale, rows, point=None, profile="Linear"):
    """(Points, {IgnoredPoints}): every point through the taper map."""
    pts, ignored = pp.cloud(base)
    if point is None:
        point = _near_centre(pts, origin, normal, gap)
    smap = taper_map(origin, normal, gap, scale, rows, point, profile)
    return points_from_array(smap(pts)), ignored


def taper_map(origin, normal, gap, scale, rows, point, profile="Linear"):
    """The taper's space map about the axis through `point` along rows[2], which must be
    parallel to the normal."""
    if np.linalg.norm(np.cross(rows[2], normal)) > 1e-9:
        raise DeformError("Axis must be parallel to the Plane normal for a taper; turn "
                          "Axis.", "Axis")
    return space_map.taper_map(origin, normal, gap, scale, point, rows, profile)


def _near_centre(points, origin, normal, gap):
    """Mean of the cloud points in the first tenth of the region, put on Plane. A sparse
    cloud with none there (trimesh's points_cloudcompare.xyz: 101 points over 84 m) takes
    the points of the region within a tenth of it from the nearest one instead."""
    s = (points - origin) @ normal
    inside = (s >= 0) & (s <= gap)
    if not inside.any():
        raise DeformError("No point lies between Plane and Plane2; move Plane so the region "
                          "between them crosses the cloud, or UseAxis.", "Plane")
    first = s[inside].min()
    near = points[inside & (s <= max(first, 0.0) + 0.1 * gap)]
    c = near.mean(axis=0)
    return c - ((c - origin) @ normal) * normal
