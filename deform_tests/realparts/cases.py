"""The real-parts matrix (issue 10): every feature on every model of ../shared/testdata it
applies to, each case checked by the oracles of oracles.py. test_matrix.py runs each case
as a pytest test; matrix.py prints the table (`make realparts`)."""
import functools
import time
from typing import NamedTuple

import numpy as np

from ..features import fc
from ..oracles import shapes as orc

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402

V = App.Vector


class Case(NamedTuple):
    id: str
    group: str           # brep, mesh, points, dimension, area, push
    model: str
    feature: str
    params: dict
    expect: str = "ok"   # "ok", or the property a refusal must name


class Outcome(NamedTuple):
    status: str          # ok / refused / FAILED
    message: str
    errors: dict         # oracle name -> (error, tolerance)
    seconds: float
    floor: float = None  # OCCT split + fuse seconds (B-rep cases)

    def worst(self):
        """(name, error, tolerance) of the oracle closest to (or past) its tolerance."""
        if not self.errors:
            return None
        name = max(self.errors, key=lambda k: self.errors[k][0] / self.errors[k][1])
        return (name, *self.errors[name])

    def passed(self, case):
        if case.expect == "ok":
            return self.status == "ok" and all(e <= t for e, t in self.errors.values())
        return self.status == "refused" and case.expect in self.message


# --- the B-rep solids -------------------------------------------------------------------------
THREE = {"Stretch": (0.3, 0.5, 0.7), "Bend": (0.3, 0.5, 0.7), "Twist": (0.3, 0.5, 0.7)}
BREP = {  # model: plane fractions along the longest bounding-box axis, per feature
    "face_recognition_sample_part.stp": THREE,
    "as1_pe_203.stp": THREE,
    "nist_ctc_01_asme1_rd.stp": THREE,
    "nist_ftc_09_asme1_rd.stp": THREE,
    "nist_ftc_10_asme1_rb.stp": THREE,
    "fc_shelf.brep": THREE,
    "trimesh_box_sides.STEP": THREE,
    # 400 to 1000 faces: one plane per feature keeps the matrix within CI's minutes
    "fc_Schenkel.stp": {"Stretch": (0.5,), "Bend": (0.3,), "Twist": (0.5,)},
    "fc_blocks144.brep": {"Stretch": (0.5,), "Bend": (0.3,), "Twist": (0.3,)},
    "occt_Bottom.brep": {"Stretch": (0.3,), "Bend": (0.7,), "Twist": (0.5,)},
}
STRETCH = 0.1      # distance, x the longest extent
BEND = 30.0        # degrees
TWIST = 30.0       # degrees, between the plane and the plane 0.1 x the extent beyond
TWIST_GAP = 0.1


def _short(model):
    return model.split(".")[0]


def brep_cases():
    out = []
    for model, planes in BREP.items():
        for feature, fracs in planes.items():
            for f in fracs:
                out.append(Case(f"{feature.lower()}-{_short(model)}-{int(round(f * 100))}",
                                "brep", model, feature, {"frac": f}))
    out.append(Case("stretch-face_recognition_sample_part-miss", "brep",
                    "face_recognition_sample_part.stp", "Stretch", {"frac": 1.2}, "Plane"))
    return out


@functools.lru_cache(maxsize=None)
def shape_of(model):
    return orc.load_shape(model)


def box_of(shape):
    bb = shape.BoundBox
    return np.array([bb.XMin, bb.YMin, bb.ZMin]), np.array([bb.XMax, bb.YMax, bb.ZMax])


def frame_of(box, frac):
    """(origin, normal, length, side axis, side extent): a plane across the longest axis of
    the box (lo, hi) at `frac`, and the second-longest axis for a bend."""
    lo, hi = box
    order = np.argsort(hi - lo)[::-1]
    k, j = order[0], order[1]
    origin = (lo + hi) / 2
    origin[k] = lo[k] + frac * (hi[k] - lo[k])
    return origin, np.eye(3)[k], hi[k] - lo[k], np.eye(3)[j], (lo[j], hi[j])


def bend_axis(origin, n, side, side_extent):
    """A bend axis in the plane, parallel to a bounding-box edge, a quarter of the side
    extent beyond the part, turning the far part away for a positive angle."""
    side_lo, side_hi = side_extent
    margin = 0.25 * (side_hi - side_lo)
    return origin + (side_hi + margin - origin @ side) * side, np.cross(n, side)


def run_brep(case, doc, floor):
    shape = shape_of(case.model)
    origin, n, length, side, side_extent = frame_of(box_of(shape), case.params["frac"])
    base = doc.addObject("Part::Feature", "Base")
    base.Shape = shape
    size = shape.BoundBox.DiagonalLength
    area, centroid, spline = orc.section(shape, origin, n)
    errors, gap, planes = {}, 0.0, [(origin, n)]
    t0 = time.perf_counter()
    if case.feature == "Stretch":
        d = STRETCH * length
        obj = fd.make_stretch(base, (V(*origin), V(*n)), d)
        motion = orc.translation(d * n)
        probes = [(origin + f * d * n, n) for f in (0.37, 0.81)]
        expected_change = area * d
    elif case.feature == "Bend":
        axis_point, axis_dir = bend_axis(origin, n, side, side_extent)
        obj = fd.make_bend(base, (V(*origin), V(*n)), BEND, (V(*axis_point), V(*axis_dir)))
        motion = orc.rotation(axis_point, axis_dir, BEND)
        half = orc.rotation(axis_point, axis_dir, BEND / 2)
        probes = [(axis_point, half[:3, :3] @ n)]
        expected_change = (area * orc.distance_to_axis(centroid, axis_point, axis_dir)
                           * np.radians(BEND)) if centroid is not None else 0.0
    else:
        gap = TWIST_GAP * length
        planes.append((origin + gap * n, n))
        obj = fd.make_twist(base, (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n)), TWIST)
        motion = (orc.rotation(centroid, n, TWIST) if centroid is not None else np.eye(4))
        probes = []
        for f in (0.25, 0.5):  # sample planes of the loft (Samples = 16)
            a_f = orc.section(shape, origin + f * gap * n, n)[0]
            probes.append((origin + f * gap * n, n, a_f))
        expected_change = 0.0
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    noise, floor_s = None, None
    if floor:  # the table times OCCT's own split and fuse of the same planes
        t1 = time.perf_counter()
        noise = orc.split_noise(shape, planes, motion)
        floor_s = time.perf_counter() - t1
    if status != "ok":
        return Outcome(status, message, {}, seconds, floor_s)
    result = obj.Shape
    errors["valid"] = (0.0 if result.isValid() else 1.0, 0.5)
    errors["solids"] = (abs(len(result.Solids) - len(shape.Solids)), 0.5)
    errors["shells"] = (0.0 if orc.shells_per_solid(result) == orc.shells_per_solid(shape)
                        else 1.0, 0.5)
    for k, p in enumerate(probes):
        a_p, _, spline_p = orc.section(result, p[0], p[1])
        want = p[2] if len(p) > 2 else area
        errors[f"section{k + 1}"] = (abs(a_p - want) / want,
                                     1e-5 if spline or spline_p else 1e-6)
    change = result.Volume - shape.Volume
    # relative to the expected change (Twist: to the twisted slab, A * gap); the tolerance
    # is 1e-6 of it plus OCCT's own volume precision on this split (split_noise)
    scale = abs(expected_change) if case.feature != "Twist" else area * gap
    rel = 1e-6 if case.feature != "Twist" else 2e-4   # a twist's loft approximates helicoids
    err = abs(change - expected_change) / scale
    if err > rel and noise is None:   # past the plain tolerance: measure OCCT's precision
        noise = orc.split_noise(shape, planes, motion)
    # OCCT integrates B-spline faces to about 1e-6 of the solid's volume (3e-5 at worst)
    freeform = any(type(f.Surface).__name__ in ("BSplineSurface", "BezierSurface")
                   for f in shape.Faces)
    vtol = rel + (4 * (noise or 0.0) + (1e-6 if freeform else 1e-9) * shape.Volume) / scale
    errors["volume"] = (err, vtol)
    errors["VolumeChange"] = (abs(obj.VolumeChange - expected_change) / scale, vtol)
    before = orc.away_parts(shape, origin, n, gap, 1e-3 * size)
    missing, worst = orc.unchanged_parts(before, result, motion, 1e-6 * size)
    errors["away faces"] = (missing + worst, 0.5)
    errors["loose"] = (orc.followed(orc.loose_vertices(shape), orc.loose_vertices(result),
                                    origin, n, motion, gap) / size, 1e-9)
    return Outcome("ok", "", errors, seconds, floor_s)


# --- Smooth Twist, Bend and Taper of a region (issue 14) --------------------------------------
FLEX = {"Twist": 20.0, "Bend": 30.0, "Taper": 0.8}   # degrees, degrees, scale at Plane2
FLEX_REGION = (0.4, 0.6)   # the planes, as fractions of the longest bounding-box axis
FLEX_SAMPLES = 120         # result points checked through the inverse map


def flex_cases():
    return [Case(f"smooth-{feature.lower()}-{_short(model)}", "flex", model, feature,
                 {"value": value}) for model in BREP for feature, value in FLEX.items()]


def smooth(t):
    """The Smooth profile as the issue gives it: zero slope at both planes (3t^2 - 2t^3)."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def inverse_map(feature, value, pts, origin, n, gap, centre):
    """Where the Smooth Twist or Taper took the points from: both keep s (the distance
    along the normal), so the inverse is a turn by -angle(s) or a scaling by 1 / scale(s)
    about the axis through `centre` along n (written here, not the code's space map)."""
    s = (pts - origin) @ n
    f = smooth(s / gap)
    rel = pts - centre
    along = rel @ n
    across = rel - along[:, None] * n
    if feature == "Taper":
        return centre + along[:, None] * n + across / (1.0 + (value - 1.0) * f)[:, None]
    u = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    x, y = across @ u, across @ w
    a = -np.radians(value) * f
    c, si = np.cos(a), np.sin(a)
    return centre + along[:, None] * n + (c * x - si * y)[:, None] * u + (si * x + c * y)[:, None] * w


def result_points(result, origin, n, count, seed=7):
    """`count` points of the result's faces beyond Plane (tessellation nodes lie on the
    faces' surfaces), drawn at random."""
    pts = np.vstack([np.array([tuple(v) for v in f.tessellate(0.5)[0]]).reshape(-1, 3)
                     for f in result.Faces])
    pts = pts[(pts - origin) @ n > 0]
    rng = np.random.default_rng(seed)
    return pts[rng.choice(len(pts), min(count, len(pts)), replace=False)]


def distance_to_faces(shape, point, margin):
    """Distance from `point` to the shape's faces whose bounding box (enlarged by `margin`)
    holds it (OCCT's distToShape of the whole of a 996-face solid takes seconds a point);
    inf when none does."""
    found = [f.distToShape(Part.Vertex(V(*point)))[0] for f in shape.Faces
             if _near_box(f.BoundBox, point, margin)]
    return min(found, default=float("inf"))


def edge_slack(shape, point, margin):
    """The largest tolerance of the Base's edges near `point`: a file's faces meet their
    edges only within it (nist_ftc_10's, 2e-3 to 3.6e-3 mm), so a result point on such an
    edge, mapped back, is that far from the faces' surfaces by the file's own making."""
    return max((e.Tolerance for e in shape.Edges if _near_box(e.BoundBox, point, margin)),
               default=0.0)


def _near_box(bb, p, margin):
    return (bb.XMin - margin <= p[0] <= bb.XMax + margin and bb.YMin - margin <= p[1] <=
            bb.YMax + margin and bb.ZMin - margin <= p[2] <= bb.ZMax + margin)


def run_flex(case, doc, floor):
    """A Smooth Twist, Bend or Taper of the region between 40 % and 60 % of the longest
    axis: one valid solid per solid with its voids, Continuity and MaxDeviation reported,
    MaxDeviation <= Tolerance; Twist and Taper: random points of the result mapped back by
    the inverse map lie on the Base within Tolerance (distToShape); Bend: the far part
    turned exactly, the near part untouched."""
    shape = shape_of(case.model)
    origin, n, length, side, side_extent = frame_of(box_of(shape), FLEX_REGION[0])
    gap = (FLEX_REGION[1] - FLEX_REGION[0]) * length
    base = doc.addObject("Part::Feature", "Base")
    base.Shape = shape
    size = shape.BoundBox.DiagonalLength
    _, centre, _ = orc.section(shape, origin, n)
    if centre is None:
        centre = origin
    plane, plane2 = (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n))
    value = case.params["value"]
    t0 = time.perf_counter()
    if case.feature == "Twist":
        obj = fd.make_twist(base, plane, plane2, value, axis=(V(*centre), V(*n)))
    elif case.feature == "Taper":
        obj = fd.make_taper(base, plane, plane2, value, axis=(V(*centre), V(*n)))
    else:
        # the axis beyond the part by gap / angle at least: the Smooth profile's steepest
        # turn (1.5 x the mean) then outruns its pull back along the normal (at r < gap / (3
        # angle) from the axis the map folds the region, and the bend is refused)
        lo, hi = side_extent
        margin = max(0.25 * (hi - lo), gap / np.radians(value))
        axis_point = origin + (hi + margin - origin @ side) * side
        axis_dir = np.cross(n, side)
        obj = fd.make_bend(base, plane, value, (V(*axis_point), V(*axis_dir)), plane2=plane2)
    obj.Profile = "Smooth"
    doc.recompute()
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
    result, tol = obj.Shape, obj.Tolerance.Value
    errors = {"valid": (0.0 if result.isValid() else 1.0, 0.5),
              "solids": (abs(len(result.Solids) - len(shape.Solids)), 0.5),
              "shells": (0.0 if orc.shells_per_solid(result) == orc.shells_per_solid(shape)
                         else 1.0, 0.5),
              "Continuity": (0.0 if obj.Continuity else 1.0, 0.5),
              "MaxDeviation": (obj.MaxDeviation / tol, 1.0)}
    if case.feature == "Bend":
        motion = orc.rotation(axis_point, axis_dir, value) @ orc.translation(-gap * n)
        before = orc.away_parts(shape, origin, n, gap, 1e-3 * size)
        missing, worst = orc.unchanged_parts(before, result, motion, 1e-6 * size)
        errors["away faces"] = (missing + worst, 0.5)
    else:
        pts = result_points(result, origin, n, FLEX_SAMPLES)
        back = inverse_map(case.feature, value, pts, origin, n, gap, centre)
        errors["inverse map"] = (max(max(0.0, distance_to_faces(shape, p, 10 * tol)
                                         - edge_slack(shape, p, 10 * tol)) for p in back)
                                 / tol, 1.0)
    return Outcome("ok", "", errors, seconds)


# --- meshes and point clouds: Stretch, Bend, Twist ------------------------------------------
MESHES = ("fandisk.obj", "occt_TR12J_OCC.stl", "occt_sh2.stl", "trimesh_counter.unitsmm.STL")
SCANS = ("pcl_milk.pcd", "pcl_table_scene_mug_stereo_textured.pcd", "pcl_lamppost.pcd")
SAMPLES = 16  # the features' default Samples


def discrete_cases():
    out = []
    for group, models in (("mesh", MESHES), ("points", SCANS)):
        for model in models:
            big = model in ("trimesh_counter.unitsmm.STL",
                            "pcl_table_scene_mug_stereo_textured.pcd")
            for feature in ("Stretch", "Bend", "Twist"):
                for f in (0.5,) if big else (0.3, 0.5, 0.7):
                    out.append(Case(f"{feature.lower()}-{_short(model)}-{int(round(f * 100))}",
                                    group, model, feature, {"frac": f}))
        out.append(Case(f"stretch-{_short(models[1])}-miss", group, models[1], "Stretch",
                        {"frac": -0.2}, "Plane"))
    return out


@functools.lru_cache(maxsize=None)
def mesh_of(model):
    import Mesh
    return Mesh.Mesh(orc.fc.testdata(model))


def arrays(mesh):
    points, facets = mesh.Topology
    flat = np.fromiter((c for p in points for c in p), float, count=3 * len(points))
    return flat.reshape(-1, 3), np.array(facets, np.int64).reshape(-1, 3)


def apply_edit(case, base, box):
    """Make the case's feature on `base`; returns (obj, origin, normal, far motion, gap,
    axis point, axis direction, length). Twist gets an explicit axis (the box centre line)
    so the oracle knows it."""
    origin, n, length, side, side_extent = frame_of(box, case.params["frac"])
    gap, axis = 0.0, (None, None)
    if case.feature == "Stretch":
        d = STRETCH * length
        obj = fd.make_stretch(base, (V(*origin), V(*n)), d)
        motion = orc.translation(d * n)
    elif case.feature == "Bend":
        axis = bend_axis(origin, n, side, side_extent)
        obj = fd.make_bend(base, (V(*origin), V(*n)), BEND, tuple(V(*a) for a in axis))
        motion = orc.rotation(*axis, BEND)
    else:
        gap = TWIST_GAP * length
        centre = (box[0] + box[1]) / 2
        axis = (centre - ((centre - origin) @ n) * n, n)
        obj = fd.make_twist(base, (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n)), TWIST,
                            tuple(V(*a) for a in axis))
        motion = orc.rotation(*axis, TWIST)
    return obj, origin, n, motion, gap, axis, length


def timed_edit(case, base, box):
    """(what apply_edit gives, its seconds, None or the Outcome of a refusal or failure)."""
    t0 = time.perf_counter()
    edit = apply_edit(case, base, box)
    seconds = time.perf_counter() - t0
    status, message = outcome_of(edit[0])
    return edit, seconds, None if status == "ok" else Outcome(status, message, {}, seconds)


def rigid_parts(before, after, origin, n, motion, gap, tol):
    """Worst distance from where the points away from the edit must be (kept before the
    plane, moved by `motion` beyond `gap`) to the nearest point of the result."""
    from scipy.spatial import cKDTree
    s = (before - origin) @ n
    expected = np.vstack([before[s < -tol], orc.apply(motion, before[s > gap + tol])])
    if len(expected) > SAMPLE:   # a fixed random sample keeps big scans within seconds
        expected = expected[np.random.default_rng(0).choice(len(expected), SAMPLE, False)]
    return float(cKDTree(after).query(expected)[0].max())


SAMPLE = 20000


def run_mesh(case, doc, floor):
    from ..oracles import mesh as mo
    mesh = mesh_of(case.model)
    base = doc.addObject("Mesh::Feature", "Base")
    base.Mesh = mesh
    box = box_of(mesh)
    size = float(np.linalg.norm(box[1] - box[0]))
    (obj, origin, n, motion, gap, axis, length), seconds, refused = timed_edit(case, base, box)
    if refused:
        return refused
    V0, T0 = arrays(mesh)
    V1, T1 = arrays(obj.Mesh)
    area, centroid, (p, q) = mo.mesh_section(V0, T0, origin, n, segments=True)
    errors = {}
    try:
        mo.assert_closed_manifold(V1, T1, min_area=0.0)
        errors["closed"] = (0.0, 0.5)
    except AssertionError:
        errors["closed"] = (1.0, 0.5)
    change = mo.volume(V1, T1) - mo.volume(V0, T0)
    step = np.radians(BEND if case.feature == "Bend" else TWIST) / SAMPLES
    if case.feature == "Stretch":
        expected, scale, tol = area * STRETCH * length, area * STRETCH * length, 1e-6
    elif case.feature == "Bend":
        expected = area * orc.distance_to_axis(centroid, *axis) * np.radians(BEND)
        scale, tol = expected, step ** 2 / 4   # 16 flat rings round an arc: ~ step^2 / 6
    else:
        # flat facets between section rings turned by `step` sag by at most r * step^2 / 8
        # off the helicoid: over the perimeter P and the gap, a volume P * gap * r step^2/8
        r = max(orc.distance_to_axis(x, *axis) for x in np.vstack([p, q]))
        perimeter = np.linalg.norm(q - p, axis=1).sum()
        expected, scale, tol = 0.0, area * gap, perimeter * r * step ** 2 / 8 / area
    # the mesh stores float32: each vertex is off by 6e-8 of its coordinates
    tol += 1e-7 * np.abs(V0).max() * mo.volume(V0, T0) / size / scale
    errors["volume"] = (abs(change - expected) / scale, tol)
    errors["VolumeChange"] = (abs(obj.VolumeChange - change) / scale, tol)
    errors["rigid parts"] = (rigid_parts(V0, V1, origin, n, motion, gap, 1e-6 * size) / size,
                             1e-6)
    return Outcome("ok", "", errors, seconds)


def run_points(case, doc, floor):
    import Points
    Points.insert(orc.fc.testdata(case.model), doc.Name)
    base = doc.Objects[-1]
    P0 = np.array([tuple(p) for p in base.Points.Points], float)
    finite = np.isfinite(P0).all(axis=1)
    P = P0[finite]
    box = (P.min(axis=0), P.max(axis=0))
    size = float(np.linalg.norm(box[1] - box[0]))
    (obj, origin, n, motion, gap, axis, length), seconds, refused = timed_edit(case, base, box)
    if refused:
        return refused
    out = np.array([tuple(p) for p in obj.Points.Points], float)
    errors = {"IgnoredPoints": (abs(obj.IgnoredPoints - int((~finite).sum())), 0.5),
              "NaN in result": (float((~np.isfinite(out)).any()), 0.5)}
    tol = 1e-6 * size   # Points store float32
    errors["rigid parts"] = (rigid_parts(P, out, origin, n, motion, gap, tol) / size, 1e-6)
    fill = len(out) - len(P)
    if case.feature == "Twist":
        errors["count"] = (abs(fill), 0.5)
    else:
        s = (P - origin) @ n
        kept = np.vstack([P[s <= 0], orc.apply(motion, P[s > 0])])
        extra = out[len(P):]      # the fill follows the moved points
        errors["moved in order"] = (float(np.abs(out[:len(P)] - kept[np.argsort(
            np.r_[np.flatnonzero(s <= 0), np.flatnonzero(s > 0)])]).max()) / size, 1e-6)
        s0 = (extra - origin) @ n
        s1 = (extra - orc.apply(motion, origin[None])[0]) @ (motion[:3, :3] @ n)
        outside = (s0 < -tol) | (s1 > tol)          # fill outside the gap
        errors["count"] = (float(fill <= 0), 0.5)
        errors["fill in gap"] = (float(outside.sum()), 0.5)
    return Outcome("ok", "", errors, seconds)


# --- DimensionDrive on the meshes ----------------------------------------------------------
# Surfaces are given by hand from the models (a plane: point, normal; a cylinder: point on
# the axis, axis, radius) with a hint point and a radius around it; the test selects the
# vertices on them itself and fits planes and cylinders to those vertices before and after.
def _plane(point, normal, hint, reach):
    return ("plane", np.array(point, float), np.array(normal, float), np.array(hint, float),
            reach)


def _cyl(point, axis, radius, hint, reach):
    return ("cyl", np.array(point, float), np.array(axis, float), radius,
            np.array(hint, float), reach)


DIMENSIONS = {  # id: (model, kind, surfaces, target, origin, axis point)
    "dimension-fandisk-distance": (
        "fandisk.obj", "Distance",
        [_plane((4.8279, 0, 0), (1, 0, 0), (4.83, 15.63, -0.29), 1.5),
         _plane((0, 0, 0), (-1, 0, 0), (0, 14.98, -1.31), 1.5)], 4.65, None, None),
    "dimension-sh2-distance": (
        "occt_sh2.stl", "Distance",
        [_plane((-55.5, 0, 0), (1, 0, 0), (-55.5, -17.89, -32), 20),
         _plane((-159, 0, 0), (-1, 0, 0), (-159, -18.75, -32), 20)], 100.0, None, None),
    "dimension-sh2-radius": (
        "occt_sh2.stl", "Radius",
        [_cyl((0, 0, -32), (1, 0, 0), 29.0, (-109.25, -29, -32), 200)], 28.0, None, None),
    "dimension-TR12J-distance": (
        "occt_TR12J_OCC.stl", "Distance",
        [_plane((0, 0, 320.5), (0, 0, 1), (232, 0, 320.5), 600),
         _plane((0, 0, 0), (0, 0, -1), (2.75, -56.4, 0), 150)], 310.0, None, None),
    "dimension-TR12J-radius": (
        "occt_TR12J_OCC.stl", "Radius",
        [_cyl((0, 0, 0), (0, 0, 1), 85.0, (-85, 0, 30), 200)], 88.0, None, None),
    "dimension-counter-radius": (
        "trimesh_counter.unitsmm.STL", "Radius",
        [_cyl((153.93, 75.87, 0), (0, 0, 1), 7.938, (153.93, 75.87, 276.94), 12)], 8.2,
        None, None),
    "dimension-counter-position": (
        "trimesh_counter.unitsmm.STL", "Position",
        [_plane((0, 0, 281.7), (0, 0, 1), (100, 157.98, 281.7), 200),
         _cyl((180.61, 157.98, 0), (0, 0, 1), 7.938, (180.61, 157.98, 276.62), 12)],
        (139.7, 1.0), (40.91, 157.98, 281.7), (80.0, 157.98, 281.7)),
    "dimension-counter-distance": (
        "trimesh_counter.unitsmm.STL", "Distance",
        [_plane((0, 0, 281.7), (0, 0, 1), (100, 157.98, 281.7), 200),
         _plane((0, 0, 269), (0, 0, -1), (40.28, 158.95 + 60, 269), 200)], 13.0, None, None),
}


def dimension_cases():
    out = [Case(k, "dimension", v[0], "DimensionDrive", {}) for k, v in DIMENSIONS.items()]
    out.append(Case("dimension-sh2-radius-too-far", "dimension", "occt_sh2.stl",
                    "DimensionDrive", {"like": "dimension-sh2-radius", "target": 60.0},
                    "Target"))
    return out


def on_surface(V, surface, tol):
    """Indices of the vertices on a hand-given plane or cylinder, near its hint."""
    if surface[0] == "plane":
        _, point, normal, hint, reach = surface
        near = np.abs((V - point) @ normal) <= tol
    else:
        _, point, axis, radius, hint, reach = surface
        d = V - point
        near = np.abs(np.linalg.norm(d - np.outer(d @ axis, axis), axis=1) - radius) <= tol
    return np.flatnonzero(near & (np.linalg.norm(V - hint, axis=1) <= reach))


def pick(V, T, idx, hint):
    """(point, vertices): a point on the mesh inside the selected surface (the centre of a
    triangle whose corners are all selected, nearest the hint) and the vertices of the
    patch of such triangles connected to it through edges (one face, not a coplanar face
    of another piece)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    inside = np.flatnonzero(np.isin(T, idx).all(axis=1))
    tri = T[inside]
    centres = V[tri].mean(axis=1)
    start = int(np.argmin(np.linalg.norm(centres - hint, axis=1)))
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(tri)), 3)
    _, key = np.unique(edges, axis=0, return_inverse=True)
    key = key.reshape(-1)
    order = np.argsort(key, kind="stable")
    same = key[order][1:] == key[order][:-1]
    a, b = owner[order][1:][same], owner[order][:-1][same]
    graph = coo_matrix((np.ones(len(a)), (a, b)), (len(tri), len(tri)))
    _, label = connected_components(graph, directed=False)
    patch = np.unique(tri[label == label[start]])
    return centres[start], patch


_DRIVES = {}


def _drive_object(model, doc):
    """One DimensionDrive per model, kept across cases: its handle (segmentation, fits,
    prisms) is built once, as when a user edits the dimension of one object."""
    key = model
    if key not in _DRIVES or _DRIVES[key][0] not in App.listDocuments().values():
        mdoc = App.newDocument("RealPartsDimension")
        base = mdoc.addObject("Mesh::Feature", "Base")
        base.Mesh = mesh_of(model)
        _DRIVES[key] = (mdoc, base, None)
    mdoc, base, obj = _DRIVES[key]
    return mdoc, base, obj


def run_dimension(case, doc, floor):
    from ..oracles import fits
    spec = DIMENSIONS[case.params.get("like", case.id)]
    model, kind, surfaces, target, origin, axis_point = spec
    target = case.params.get("target", target)
    mesh = mesh_of(model)
    V0, T0 = arrays(mesh)
    size = float(np.linalg.norm(V0.max(axis=0) - V0.min(axis=0)))
    tol = 2e-4 * size
    sel = [on_surface(V0, sf, tol) for sf in surfaces]
    for sf, idx in zip(surfaces, sel):
        if len(idx) < 6:
            raise AssertionError(f"the test's {sf[0]} near {sf[-2]} has {len(idx)} vertices")
    picked = [pick(V0, T0, idx, sf[-2]) for sf, idx in zip(surfaces, sel)]
    regions = [V(*p) for p, _ in picked]
    sel = [patch for _, patch in picked]
    mdoc, base, obj = _drive_object(model, doc)
    t0 = time.perf_counter()
    if obj is None:
        options = {}
        if kind == "Position":
            options = {"origin": origin, "axis_point": axis_point}
        obj = fd.make_dimension_drive(base, kind, regions, target, **options)
        _DRIVES[model] = (mdoc, base, obj)
    else:
        obj.Kind = kind
        obj.Regions = regions
        if kind == "Position":
            obj.Target, obj.TargetV = target
            obj.Origin, obj.AxisPoint = V(*origin), V(*axis_point)
        else:
            obj.Target = target
        mdoc.recompute()
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
    V1, T1 = arrays(obj.Mesh)
    errors = {"topology": (float(not np.array_equal(T0, T1)), 0.5)}
    n0 = np.cross(V0[T0[:, 1]] - V0[T0[:, 0]], V0[T0[:, 2]] - V0[T0[:, 0]])
    n1 = np.cross(V1[T1[:, 1]] - V1[T1[:, 0]], V1[T1[:, 2]] - V1[T1[:, 0]])
    errors["flipped"] = (float((np.einsum("ij,ij->i", n0, n1) <= 0).sum()), 0.5)
    fit_tol = 1e-6 * size + 4 * 1.2e-7 * np.abs(V0).max()   # float32 storage
    if kind == "Distance":
        (na, ca, ra), (nb, cb, rb) = fits.plane_fit(V1[sel[0]]), fits.plane_fit(V1[sel[1]])
        if na @ nb < 0:
            nb, cb = -nb, -cb
        achieved = abs(ca - cb)
        errors["planes flat"] = (max(ra, rb), fit_tol)
        errors["parallel"] = (float(np.linalg.norm(np.cross(na, nb))), 1e-6)
    elif kind == "Radius":
        _, _, achieved, rms = fits.cylinder_fit(V1[sel[0]], surfaces[0][2])
        errors["cylinder round"] = (rms, fit_tol)
    else:
        nb, cb, rb = fits.plane_fit(V1[sel[0]])
        c, a, r, rms = fits.cylinder_fit(V1[sel[1]], surfaces[1][2])
        foot = c + (cb - c @ nb) / (a @ nb) * a
        o = np.asarray(origin, float)
        eu = np.asarray(axis_point, float) - o
        eu -= (eu @ nb) * nb
        eu /= np.linalg.norm(eu)
        ev = np.cross(nb, eu)
        achieved = float(np.linalg.norm([(foot - o) @ eu - target[0], (foot - o) @ ev - target[1]]))
        errors["hole round"] = (rms, fit_tol)
        errors["hole radius kept"] = (abs(r - fits.cylinder_fit(V0[sel[1]], surfaces[1][2])[2]),
                                      fit_tol)
        target = 0.0
    errors["dimension"] = (abs(achieved - target), fit_tol)
    if kind != "Position":
        errors["Achieved"] = (abs(obj.Achieved - target), fit_tol)
    return Outcome("ok", "", errors, seconds)


# --- AreaConstrain and DirectPush on B-spline faces -------------------------------------------
FACES = (("occt_Bottom.brep", "Face23"), ("occt_Bottom.brep", "Face20"),
         ("occt_terrain.brep", "Face1"), ("splinecage.stp", "Face2"))
# every interior pole of the 312 x 323-pole terrain (100,000 unknowns) did not finish in
# 25 minutes: its AreaConstrain case frees the 8 x 8 poles in the middle, +0.01 %
TERRAIN_POLES = [(i, j) for i in range(153, 161) for j in range(158, 166)]
# AreaConstrain +3 % on more housing faces, one per kind that failed once: Face163 (the
# solve stalled at a converged point), Face246 (nearly collapsed edge: quartering grew to
# 6000 rectangles); Face32 is trimmed by a non-rectangular boundary (a refusal naming Face)
AREA_FACES = ("Face163", "Face246")


def surface_cases():
    out = []
    for model, face in FACES:
        for feature in ("AreaConstrain", "DirectPush"):
            params = {"face": face, "ratio": 1.03}
            if model == "occt_terrain.brep" and feature == "AreaConstrain":
                out.append(Case("areaconstrain-occt_terrain-Face1-default", "surface", model,
                                feature, {"face": face, "ratio": 1.01}))
                # 8 x 8 poles asked +0.01 % of the whole face, about 10 % of the area they
                # shape: Lagrange-Newton does not converge, a refusal naming TargetArea
                params.update(ratio=1.0001, poles=TERRAIN_POLES)
                out.append(Case(f"{feature.lower()}-{_short(model)}-{face}", "surface", model,
                                feature, params, "TargetArea"))
                continue
            out.append(Case(f"{feature.lower()}-{_short(model)}-{face}", "surface", model,
                            feature, params))
    for face in AREA_FACES:
        out.append(Case(f"areaconstrain-occt_Bottom-{face}", "surface", "occt_Bottom.brep",
                        "AreaConstrain", {"face": face, "ratio": 1.03}))
    out.append(Case("areaconstrain-occt_Bottom-holes", "surface", "occt_Bottom.brep",
                    "AreaConstrain", {"face": "holes", "ratio": 1.03}, "Face"))
    out.append(Case("areaconstrain-occt_Bottom-Face32", "surface", "occt_Bottom.brep",
                    "AreaConstrain", {"face": "Face32", "ratio": 1.03}, "Face"))
    return out


def surface_of(face):
    """The arrays of a face's B-spline surface for oracles.nurbs.bspline_area."""
    S = face.Surface
    def flat(knots, mults):
        return np.repeat(knots, mults)
    poles = np.array([[tuple(p) for p in row] for row in S.getPoles()])
    weights = np.array(S.getWeights())
    u0, u1, v0, v1 = face.ParameterRange
    return (poles, weights, flat(S.getUKnots(), S.getUMultiplicities()),
            flat(S.getVKnots(), S.getVMultiplicities()), S.UDegree, S.VDegree,
            (u0, u1), (v0, v1))


def _moved_support(before, after):
    """The parameter rectangle outside which the surface did not change: the knot spans
    that the moved poles reach (a pole i of degree p acts on knots i .. i + p + 1)."""
    moved = np.argwhere(np.abs(after[0] - before[0]).max(axis=-1) > 0)
    (i0, j0), (i1, j1) = moved.min(axis=0), moved.max(axis=0)
    tu, tv, p, q = before[2], before[3], before[4], before[5]
    return (tu[i0], tu[i1 + p + 1]), (tv[j0], tv[j1 + q + 1])


def _face_with_holes(shape):
    return next(f"Face{i}" for i, f in enumerate(shape.Faces, 1) if len(f.Wires) > 1)


def run_surface(case, doc, floor):
    from ..oracles import nurbs
    shape = shape_of(case.model)
    name = case.params["face"]
    if name == "holes":
        name = _face_with_holes(shape)
    face = shape.getElement(name)
    base = doc.addObject("Part::Feature", "Base")
    base.Shape = shape
    size = face.BoundBox.DiagonalLength
    t0 = time.perf_counter()
    if case.feature == "AreaConstrain":
        obj = fd.make_area_constrain(base, name, f"{100 * case.params['ratio']:g}%",
                                     poles=case.params.get("poles"))
    else:
        u0, u1, v0, v1 = face.ParameterRange
        u, v = u0 + 0.43 * (u1 - u0), v0 + 0.57 * (v1 - v0)
        p, nrm = face.valueAt(u, v), face.normalAt(u, v)
        target = p + nrm * (0.02 * size)
        obj = fd.make_direct_push(base, name, p, target)
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
    result = obj.Shape
    centre = np.array(tuple(face.CenterOfMass))
    errors = {"valid": (0.0 if result.isValid() else 1.0, 0.5)}
    if case.feature == "AreaConstrain":
        cands = [f for f in result.Faces if type(f.Surface).__name__ == "BSplineSurface"
                 and f.Surface.NbUPoles == face.Surface.NbUPoles
                 and f.Surface.NbVPoles == face.Surface.NbVPoles]
        new = min(cands, key=lambda f: np.linalg.norm(np.array(tuple(f.CenterOfMass)) - centre))
        before, after = surface_of(face), surface_of(new)
        if before[0].size < 30000:
            a0, c0 = nurbs.converged_area(*before)
            a1, c1 = nurbs.converged_area(*after)
        else:  # the terrain: the change, converged over the spans the moved poles reach
            ur, vr = _moved_support(before, after)
            a0, c0 = nurbs.bspline_area(*before, nodes=6), 0.0   # 1e-6 of it is enough
            d0, c0 = nurbs.converged_area_pieces(*before[:6], ur, vr)
            d1, c1 = nurbs.converged_area_pieces(*after[:6], ur, vr)
            if np.allclose(ur + vr, before[6] + before[7], rtol=0, atol=1e-9):
                a0 = d0       # every interior pole moved: the change is the whole area's
            a1 = a0 + (d1 - d0)
        errors["area"] = (abs(a1 / a0 - case.params["ratio"]), 1e-10)
        errors["quadrature converged"] = (max(c0, c1), 1e-12)
        errors["AchievedArea"] = (abs(obj.AchievedArea / a0 - a1 / a0), 1e-10)
    else:
        errors["push lands"] = (result.distToShape(Part.Vertex(target))[0] / size, 1e-7)
        if len(shape.Solids):
            errors["solids"] = (abs(len(result.Solids) - len(shape.Solids)), 0.5)
    return Outcome("ok", "", errors, seconds)


# --- running a case -------------------------------------------------------------------------
def outcome_of(obj):
    """("ok", "") or ("refused", message) for a DeformError, else ("FAILED", what)."""
    if "Invalid" not in obj.State:
        return "ok", ""
    exc = fc.RAISED.get(obj.Name)
    if isinstance(exc, DeformError):
        return "refused", str(exc)
    what = f"{type(exc).__name__}: {exc}" if exc is not None else obj.getStatusString()
    return "FAILED", what


from .fem_cases import fem_cases, run_fem  # noqa: E402  (it imports this module's names)

RUNNERS = {"brep": run_brep, "flex": run_flex, "fem": run_fem, "mesh": run_mesh, "points": run_points,
           "dimension": run_dimension, "surface": run_surface}


def all_cases():
    return (brep_cases() + flex_cases() + discrete_cases() + dimension_cases()
            + fem_cases() + surface_cases())


def run(case, floor=False):
    """Run one case in a new document; an exception in the test code is FAILED too."""
    doc = App.newDocument("RealParts")
    doc.UndoMode = 0
    t0 = time.perf_counter()
    try:
        with fc.recorded_errors():
            return RUNNERS[case.group](case, doc, floor)
    except Exception as exc:  # a crash of the case is reported, never hides the rest
        return Outcome("FAILED", f"{type(exc).__name__}: {exc}", {}, time.perf_counter() - t0)
    finally:
        App.closeDocument(doc.Name)
