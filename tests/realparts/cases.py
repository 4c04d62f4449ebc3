"""The real-parts matrix (issue 10): every feature on every model of ../shared/testdata it
applies to, each case checked by the oracles of oracles.py. test_matrix.py runs each case
as a pytest test; matrix.py prints the table (`make realparts`)."""
import contextlib
import functools
import time
from typing import NamedTuple

import numpy as np

from . import oracles as orc

import FreeCAD as App  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.features.base import DeformFeature  # noqa: E402
from freecad_deform.features.dimension_drive import DimensionDrive  # noqa: E402
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
BREP = {  # model: plane fractions along the longest bounding-box axis
    "face_recognition_sample_part.stp": (0.3, 0.5, 0.7),
    "as1_pe_203.stp": (0.3, 0.5, 0.7),
    "nist_ctc_01_asme1_rd.stp": (0.3, 0.5, 0.7),
    "nist_ftc_09_asme1_rd.stp": (0.3, 0.5, 0.7),
    "nist_ftc_10_asme1_rb.stp": (0.3, 0.5, 0.7),
    "fc_Schenkel.stp": (0.3, 0.5, 0.7),
    "fc_shelf.brep": (0.3, 0.5, 0.7),
    "fc_blocks144.brep": (0.3, 0.5, 0.7),
    "occt_Bottom.brep": (0.3, 0.5, 0.7),
    "trimesh_box_sides.STEP": (0.3, 0.5, 0.7),
}
STRETCH = 0.1      # distance, x the longest extent
BEND = 30.0        # degrees
TWIST = 30.0       # degrees, between the plane and the plane 0.1 x the extent beyond
TWIST_GAP = 0.1


def _short(model):
    return model.split(".")[0]


def brep_cases():
    out = []
    for model, fracs in BREP.items():
        for feature in ("Stretch", "Bend", "Twist"):
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
    t1 = time.perf_counter()
    noise = orc.split_noise(shape, planes)
    floor_s = time.perf_counter() - t1 if floor else None
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
    vtol = rel + (4 * noise + 1e-9 * shape.Volume) / scale
    errors["volume"] = (abs(change - expected_change) / scale, vtol)
    errors["VolumeChange"] = (abs(obj.VolumeChange - expected_change) / scale, vtol)
    before = orc.away_parts(shape, origin, n, gap, 1e-3 * size)
    missing, worst = orc.unchanged_parts(before, result, motion, 1e-6 * size)
    errors["away faces"] = (missing + worst, 0.5)
    errors["loose"] = (orc.followed(orc.loose_vertices(shape), orc.loose_vertices(result),
                                    origin, n, motion, gap) / size, 1e-9)
    return Outcome("ok", "", errors, seconds, floor_s)


# --- meshes and point clouds: Stretch, Bend, Twist ------------------------------------------
MESHES = ("fandisk.obj", "occt_TR12J_OCC.stl", "occt_sh2.stl", "trimesh_counter.unitsmm.STL")
SCANS = ("pcl_milk.pcd", "pcl_table_scene_mug_stereo_textured.pcd", "pcl_lamppost.pcd")
SAMPLES = 16  # the features' default Samples


def discrete_cases():
    out = []
    for group, models in (("mesh", MESHES), ("points", SCANS)):
        for model in models:
            for feature in ("Stretch", "Bend", "Twist"):
                for f in (0.3, 0.5, 0.7):
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


def rigid_parts(before, after, origin, n, motion, gap, tol):
    """Worst distance from where the points away from the edit must be (kept before the
    plane, moved by `motion` beyond `gap`) to the nearest point of the result."""
    from scipy.spatial import cKDTree
    s = (before - origin) @ n
    expected = np.vstack([before[s < -tol], orc.apply(motion, before[s > gap + tol])])
    return float(cKDTree(after).query(expected)[0].max())


def run_mesh(case, doc, floor):
    from ..geometry import mesh_oracles as mo
    mesh = mesh_of(case.model)
    base = doc.addObject("Mesh::Feature", "Base")
    base.Mesh = mesh
    box = box_of(mesh)
    size = float(np.linalg.norm(box[1] - box[0]))
    t0 = time.perf_counter()
    obj, origin, n, motion, gap, axis, length = apply_edit(case, base, box)
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
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
    t0 = time.perf_counter()
    obj, origin, n, motion, gap, axis, length = apply_edit(case, base, box)
    seconds = time.perf_counter() - t0
    status, message = outcome_of(obj)
    if status != "ok":
        return Outcome(status, message, {}, seconds)
    out = np.array([tuple(p) for p in obj.Points.Points], float)
    errors = {"IgnoredPoints": (abs(obj.IgnoredPoints - int((~finite).sum())), 0.5),
              "NaN in result": (float((~np.isfinite(out)).any()), 0.5)}
    tol = 1e-6 * size   # Points store float32
    errors["rigid parts"] = (rigid_parts(P, out, origin, n, motion, gap, tol) / size, 1e-6)
    fill = len(out) - len(P)
    if case.feature == "Twist":
        errors["count"] = (abs(fill), 0.5)
    else:
        from scipy.spatial import cKDTree
        s = (P - origin) @ n
        kept = np.vstack([P[s <= 0], orc.apply(motion, P[s > 0])])
        extra = out[cKDTree(kept).query(out)[0] > tol]
        s0 = (extra - origin) @ n
        s1 = (extra - orc.apply(motion, origin[None])[0]) @ (motion[:3, :3] @ n)
        outside = (s0 < -tol) | (s1 > tol)          # fill outside the gap
        errors["count"] = (float(fill <= 0), 0.5)
        errors["fill in gap"] = (float(outside.sum()), 0.5)
    return Outcome("ok", "", errors, seconds)


# --- running a case -------------------------------------------------------------------------
_RAISED = {}


@contextlib.contextmanager
def recorded_errors():
    """Keep the exception each feature's execute raised (FreeCAD keeps only its text), so a
    DeformError (a refusal) is told apart from a crash."""
    saved = {cls: cls.__dict__["execute"] for cls in (DeformFeature, DimensionDrive)}

    def wrap(fn):
        def execute(self, obj):
            _RAISED.pop(obj.Name, None)
            try:
                return fn(self, obj)
            except Exception as exc:
                _RAISED[obj.Name] = exc
                raise
        return execute

    for cls, fn in saved.items():
        cls.execute = wrap(fn)
    try:
        yield
    finally:
        for cls, fn in saved.items():
            cls.execute = fn


def outcome_of(obj):
    """("ok", "") or ("refused", message) for a DeformError, else ("FAILED", what)."""
    if "Invalid" not in obj.State:
        return "ok", ""
    exc = _RAISED.get(obj.Name)
    if isinstance(exc, DeformError):
        return "refused", str(exc)
    what = f"{type(exc).__name__}: {exc}" if exc is not None else obj.getStatusString()
    return "FAILED", what


RUNNERS = {"brep": run_brep, "mesh": run_mesh, "points": run_points}


def all_cases():
    return brep_cases() + discrete_cases()


def run(case, floor=False):
    """Run one case in a new document; an exception in the test code is FAILED too."""
    doc = App.newDocument("RealParts")
    doc.UndoMode = 0
    t0 = time.perf_counter()
    try:
        with recorded_errors():
            return RUNNERS[case.group](case, doc, floor)
    except Exception as exc:  # a crash of the case is reported, never hides the rest
        return Outcome("FAILED", f"{type(exc).__name__}: {exc}", {}, time.perf_counter() - t0)
    finally:
        App.closeDocument(doc.Name)
