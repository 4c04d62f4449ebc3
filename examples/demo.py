"""The `make demo` job: every Deform feature on real models, exported, pictured and checked.

    /usr/bin/python3 examples/demo.py [OUTPUT_DIR] [--quick]  # default: <repo>/demo_out/
    DEFORM_DEMO_OUT=/tmp/out freecadcmd examples/demo.py   # freecadcmd takes no script options

Builds one document from ../shared/testdata (relative to the repo root):
  Stretch      the machined sample part stretched by 40 mm along +X at x = 150
  TwoPlanes    the region between z = 100 and z = 150 stretched by 30 mm along +Z
  Shrink       the sample part shrunk by 40 mm along +X at x = 150
  MeshStretch  a mesh of the part, stretched like Stretch
  CloudStretch a point cloud sampled on the part, stretched like Stretch
  AS1Stretch   the AS1 assembly (18 solids) stretched by 800 mm along +X at x = 400
  Bend         the sample part bent by -60 deg at x = 150 about an axis in the plane (exact revolve)
  TwoPlaneBend the region between x = 90 and x = 140 bent by -60 deg, its cross-section kept
  Twist        a 60 x 20 x 150 bar twisted by 90 deg between z = 40 and z = 110
  MeshBend     the mesh of the part, bent like Bend
  BladeStretch a turbine-blade-like point cloud (Wu & Ilies, Fig. 9): its airfoil extended 3x
  BladeTwist   ... then twisted by 30 deg, the centroids of its cross-sections on the vertical
  Taper        a 60 x 40 x 150 bar scaled to 0.6 across its axis between z = 40 and z = 110
  DimensionDrive  fandisk.obj: the distance between two parallel faces driven 4.8279 -> 4.65 mm
  AreaConstrain   splinecage.stp Face2 given 103 % of its area (least pole movement)
  DirectPush      a point of splinecage.stp Face2 pushed along its normal
  Batch           the command line: a 3-variant sweep on 2 workers (A x d per row), a goal
                  seek ((V - V0) / A) and reach landing the bracket's end hole by key frames

`--quick` runs one section per feature (Stretch, Bend, Twist and the four above) and the
reopen (no batch section); report.md opens with the features table (feature, base, inputs, outputs, valid,
seconds, the oracle and its relative error), report.json holds it as "features".

Writes demo.FCStd, one STEP per solid result, STL for the meshes, PLY for the clouds,
before/after PNGs rendered by FreeCAD's 3D view (the GUI under xvfb-run runs
demo_pictures.py; the "Pictures" section checks them) and report.md / report.json. Every invariant is measured against an
independent oracle (a section's area from Shape.slice, a common with a box, the normals
of the base's faces, an edge count of the mesh, a nearest-neighbour query, Pappus' theorem,
rotations written out with Rodrigues' formula, point means per layer). The job exits
with status 1 if any of them fails (a feature that raises counts as a failed check; the
others still run and the report is written); "warn" marks a quality expectation that is
reported but does not fail the job.
"""
import json
import os
import sys
import time

for _path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(_path) and _path not in sys.path:
        sys.path.append(_path)
REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
if REPO not in sys.path:
    sys.path.insert(0, REPO)
TESTDATA = os.environ.get("DEFORM_TESTDATA", os.path.join(os.path.dirname(REPO), "shared", "testdata"))

import FreeCAD as App  # noqa: E402  (FreeCAD before Part, or Part segfaults)
import numpy as np  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import freecad_deform as fd  # noqa: E402
# the oracles shared with the tests (OCCT sections and commons, the Mesh checks)
from deform_tests.oracles.shapes import (closed_manifold, mesh_section_area,  # noqa: E402
                                         section_area, slab_volume)

V = App.Vector
X, Y, Z = np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0])
REL = 1e-6          # relative tolerance of an exact B-rep volume against its oracle
REVOLUTION = {"Plane", "Cylinder", "Cone", "Toroid", "Sphere", "SurfaceOfRevolution"}


# ---------------------------------------------------------------------------- oracles

def section_face(shape, origin, normal):
    """The shape's cross-section in the plane (Shape.slice wires made into faces), or None."""
    n = V(*normal).normalize()
    wires = shape.slice(n, n.dot(V(*origin)))
    return Part.makeFace(wires, "Part::FaceMakerBullseye") if wires else None


def pappus(face, axis_point, axis_direction, angle):
    """(volume, centroid radius): the solid the planar face sweeps turning by `angle` degrees
    about the axis, by Pappus' theorem: area x centroid radius x angle in radians."""
    w = np.asarray(axis_direction, float) / np.linalg.norm(axis_direction)
    radius = float(np.linalg.norm(np.cross(np.array(tuple(face.CenterOfMass)) - axis_point, w)))
    return face.Area * radius * abs(np.radians(angle)), radius


def rodrigues(points, axis_point, axis_direction, angle):
    """Points turned by `angle` degrees (one angle, or one per point) about the axis, right-hand
    rule: Rodrigues' formula v cos a + (w x v) sin a + w (w . v)(1 - cos a), written out."""
    w = np.asarray(axis_direction, float) / np.linalg.norm(axis_direction)
    c = np.asarray(axis_point, float)
    a = np.radians(np.asarray(angle, float))[..., None]
    v = np.asarray(points, float).reshape(-1, 3) - c
    return c + v * np.cos(a) + np.cross(w, v) * np.sin(a) + np.outer(v @ w, w) * (1 - np.cos(a))


def lemma1(shape, planes, normal, tangent=None, fractions=(0.5,)):
    """{face name: "G1"/"C0"} by hand: the normal of each face a plane cuts, at `fractions` of
    its section edges (the middle by default), against the motion (G1 when perpendicular).
    tangent(point) is the trajectory's direction there; default the normal (a translation)."""
    found = {}
    for origin in planes:
        d = float(np.dot(origin, normal))
        for i, face in enumerate(shape.Faces, start=1):
            edges = [e for w in face.slice(V(*normal), d) for e in w.Edges]
            lo, hi = _extent(face, normal)
            if not edges or not lo < d - 1e-7 or not hi > d + 1e-7:
                continue
            kinds = []
            for e in edges:
                for f in fractions:
                    p = e.valueAt(e.FirstParameter + f * (e.LastParameter - e.FirstParameter))
                    nrm = np.array(tuple(face.normalAt(*face.Surface.parameter(p))))
                    t = normal if tangent is None else tangent(np.array(tuple(p)))
                    kinds.append("G1" if abs(nrm @ t) < 1e-6 * np.linalg.norm(t) else "C0")
            name = f"Face{i}"
            found[name] = "C0" if "C0" in kinds + [found.get(name)] else "G1"
    return found


def _extent(shape, normal):
    pts = np.array([tuple(v.Point) for v in shape.Vertexes] or [[0, 0, 0]]) @ normal
    bb = shape.BoundBox  # a cylinder face's vertices may all lie on one side: use the box too
    corners = np.array([[x, y, z] for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
                        for z in (bb.ZMin, bb.ZMax)]) @ normal
    return min(pts.min(), corners.min()), max(pts.max(), corners.max())


def mesh_section(mesh, origin, normal):
    """(area, centroid) of the mesh's cross-section polylines (Mesh.crossSections), by the
    shoelace formula; holes count negative by their orientation."""
    u = np.cross([0, 0, 1], normal) if abs(normal[2]) < 0.9 else np.cross([1, 0, 0], normal)
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    total, moment = 0.0, np.zeros(2)
    for polyline in mesh.crossSections([(V(*origin), V(*normal))])[0]:
        p = np.array([tuple(q) for q in polyline]) - origin
        x, y = p @ u, p @ w
        x1, y1 = np.roll(x, -1), np.roll(y, -1)
        cross = x * y1 - x1 * y
        total += 0.5 * cross.sum()
        moment += [((x + x1) * cross).sum() / 6, ((y + y1) * cross).sum() / 6]
    centroid = origin + (moment[0] * u + moment[1] * w) / total if total else origin
    return abs(total), centroid


def mesh_volume(mesh):
    """Volume of a closed mesh in float64: the divergence theorem over its facets."""
    points, facets = mesh.Topology
    p = np.array([tuple(q) for q in points], float)[np.array(facets, int)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def check_closed_mesh(rep, obj, mesh, before, change):
    """The checks every mesh result gets: VolumeChange is the float64 change measured here,
    and the mesh is closed, manifold and in as many pieces as before."""
    rep.check("VolumeChange = the float64 volume change", obj.VolumeChange, change, rel=1e-6,
              note="measured here on the stored mesh, whose points are float32")
    rep.check("mesh.isSolid() (closed)", mesh.isSolid(), True)
    rep.check("mesh.hasNonManifolds()", mesh.hasNonManifolds(), False)
    rep.check("every edge shared by two facets, opposite directions (numpy edge count)",
              closed_manifold(mesh), True)
    rep.check("mesh.countComponents()", mesh.countComponents(), before.countComponents())


def face_types(shape):
    return sorted({type(f.Surface).__name__ for f in shape.Faces})


def face_type_counts(shape):
    names = [type(f.Surface).__name__ for f in shape.Faces]
    return {n: names.count(n) for n in sorted(set(names))}


def points_of(pts):
    return np.array([tuple(p) for p in pts], float).reshape(-1, 3)


# ---------------------------------------------------------------------------- report

class Report:
    def __init__(self):
        self.sections, self.failed, self.warned = [], 0, 0

    def section(self, name, what):
        print(f"{name}: {what}")
        self.sections.append({"name": name, "what": what, "checks": [], "facts": {}})

    def fact(self, key, value):
        self.sections[-1]["facts"][key] = value

    def check(self, what, value, oracle, ok=None, rel=None, note="", warn=False):
        """One invariant: `value` measured on the result against `oracle`, computed apart.

        warn=True marks a quality expectation rather than an invariant: reported, flagged,
        but it does not fail the job."""
        if ok is None:
            if rel is not None:
                ok = abs(value - oracle) <= rel * max(abs(oracle), 1e-12)
            else:
                ok = value == oracle
        status = "ok" if ok else "warn" if warn else "FAIL"
        entry = {"check": what, "value": _plain(value), "oracle": _plain(oracle),
                 "status": status, "tolerance": f"rel {rel:g}" if rel is not None else "exact"}
        if rel is not None:
            entry["rel_error"] = abs(value - oracle) / max(abs(oracle), 1e-12)
        if note:
            entry["note"] = note
        self.sections[-1]["checks"].append(entry)
        self.failed += status == "FAIL"
        self.warned += status == "warn"
        print(f"  [{status}] {what}: {_text(value)} vs {_text(oracle)}"
              + (f" ({note})" if note else ""))

    def markdown(self, header):
        lines = [header, ""]
        for s in self.sections:
            lines += [f"## {s['name']}", "", s["what"], ""]
            if s["facts"]:
                lines += [f"- {k}: {_text(v)}" for k, v in s["facts"].items()] + [""]
            lines += ["| check | result | oracle | rel. error (tolerance) | |",
                      "| --- | --- | --- | --- | --- |"]
            for c in s["checks"]:
                tol = (f"{c['rel_error']:.1e} (<= {c['tolerance'][4:]})" if "rel_error" in c
                       else c["tolerance"])
                lines.append(f"| {c['check']}{' (' + c['note'] + ')' if 'note' in c else ''} | "
                             f"{_text(c['value'])} | {_text(c['oracle'])} | {tol} | "
                             f"{c['status'] if c['status'] == 'ok' else '**' + c['status'] + '**'} |")
            lines.append("")
        return "\n".join(lines)


def _plain(v):
    if isinstance(v, (np.floating, np.integer, np.bool_)):
        return v.item()
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    return v


def _text(v):
    if isinstance(v, float):
        return f"{v:.6g}" if abs(v) < 1e5 else f"{v:,.1f}"
    if isinstance(v, dict):
        return ", ".join(f"{k}: {x}" for k, x in v.items()) or "-"
    if isinstance(v, (list, tuple)):
        return ", ".join(str(x) for x in v) or "-"
    return str(v)


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t


def recompute_time(doc, obj, runs=3):
    """Median seconds of touch() + doc.recompute() of `obj`."""
    times = []
    for _ in range(runs):
        _, t = timed(lambda: (obj.touch(), doc.recompute()))
        times.append(t)
    return float(np.median(times))


# ---------------------------------------------------------------------------- pictures

def triangles_of(shape, tol=0.5):
    pts, tris = shape.tessellate(tol)
    return np.array([tuple(p) for p in pts], float).reshape(-1, 3), np.array(tris, int).reshape(-1, 3)


# ---------------------------------------------------------------------------- the demo

def stretch_checks(rep, base_shape, obj, origin, normal, distance):
    """The invariants of a one-plane stretch (distance > 0) of a solid."""
    result = obj.Shape
    area = section_area(base_shape, origin, normal)
    rep.check("VolumeChange = section area x distance", obj.VolumeChange, area * distance, rel=REL)
    rep.check("Volume(result) - Volume(base) = section area x distance",
              result.Volume - base_shape.Volume, area * distance, rel=REL)
    rep.check("isValid()", result.isValid(), True)
    rep.check("number of solids", len(result.Solids), len(base_shape.Solids))
    rep.check("face types", face_types(result), face_types(base_shape),
              note="an exact stretch keeps planes planes and cylinders cylinders")
    k = int(np.argmax(np.abs(normal)))
    rep.check("length along the normal grows by distance",
              _length(result, k), _length(base_shape, k) + distance, rel=1e-9)
    continuity_check(rep, base_shape, obj, [origin], normal)


def continuity_check(rep, base_shape, obj, planes, normal, **trajectory):
    """The object's Continuity against lemma1 by hand; `trajectory`: lemma1's tangent and
    fractions, for a motion that is not a translation along the normal."""
    entries = dict(e.split(": ") for e in obj.Continuity.split("; ")) if obj.Continuity else {}
    rep.check("Continuity report (Lemma 1) = face normals at the section, by hand",
              entries, lemma1(base_shape, planes, normal, **trajectory))
    rep.check("SplitFaces = the faces the plane(s) cut", list(obj.SplitFaces),
              sorted(entries, key=lambda name: int(name[4:])))


def bend_tangent(origin, normal, axis_point, axis_direction):
    """Trajectory direction at a joint point p of a bend: w x (q - c), q the point p brought
    back onto Plane (a point on Plane2 is where the plane's point was before the shift)."""
    w = np.asarray(axis_direction, float) / np.linalg.norm(axis_direction)
    return lambda p: np.cross(w, p - ((p - origin) @ normal) * normal - axis_point)


def rigid_check(rep, base_shape, result, origin, normal, far_motion, gap=0.0):
    """The base's vertices before Plane kept, those beyond Plane2 (Plane when gap = 0) moved by
    far_motion(points): each must be a vertex of the result (nearest-neighbour distance)."""
    before = points_of([v.Point for v in base_shape.Vertexes])
    s = (before - origin) @ normal
    expected = np.vstack([before[s < -1e-9], far_motion(before[s > gap + 1e-9])])
    dist = _nearest(points_of([v.Point for v in result.Vertexes]), expected)
    rep.check("vertices before the plane kept, beyond it moved rigidly (the rotation written "
              "out): max distance to the nearest result vertex, mm", dist, 0.0, ok=dist < 1e-7)


def _nearest(points, expected):
    """The largest distance from an expected point to the nearest of `points`."""
    return float(cKDTree(points).query(expected)[0].max()) if len(expected) else 0.0


def _turn(before, after):
    """Angle (degrees) of the rotation about the origin that best maps the 2-D points `before`
    onto `after` (Procrustes: atan2 of the summed cross and dot products)."""
    a, b = before - before.mean(axis=0), after - after.mean(axis=0)
    return float(np.degrees(np.arctan2((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum(),
                                       (a * b).sum())))


def _count(obj):
    return obj.Mesh.CountFacets if hasattr(obj, "Mesh") else obj.Points.CountPoints


def _box(shape, shift=np.zeros(3)):
    bb = shape.BoundBox
    return np.array([bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax]) + np.tile(shift, 2)


def _length(shape, k):
    bb = shape.BoundBox
    return (bb.XLength, bb.YLength, bb.ZLength)[k]


class Demo:
    """The demo's document and outputs; one method per feature, each guarded, so a feature
    that raises is reported as a failed check and the others still run."""

    def __init__(self, out):
        self.out, self.rep, self.timings, self.exports = out, Report(), {}, []
        self.features, self.seconds, self.jobs = [], 0.0, []
        self.sample_path = os.path.join(TESTDATA, "face_recognition_sample_part.stp")
        self.as1_path = os.path.join(TESTDATA, "as1_pe_203.stp")
        for path in (self.sample_path, self.as1_path):
            if not os.path.isfile(path):
                sys.exit(f"test model {path} is missing; set DEFORM_TESTDATA")
        self.doc = App.newDocument("DeformDemo")
        self.mesh_base = None
        self.shape = Part.read(self.sample_path)
        self.base = self.doc.addObject("Part::Feature", "SamplePart")
        self.base.Shape = self.shape

    def guarded(self, section):
        try:
            section()
        except Exception as exc:
            import traceback
            traceback.print_exc()
            if not self.rep.sections:
                self.rep.section(section.__name__, "")
            self.rep.check(f"{section.__name__} ran to the end", f"{type(exc).__name__}: {exc}",
                           "no exception", ok=False)

    def create(self, label, base, plane, distance, **options):
        """make_stretch, timed; then the recompute alone, timed; the object."""
        return self.make(label, "make_stretch",
                         lambda: fd.make_stretch(base, plane, distance, **options))

    def make(self, label, maker, fn, check="recomputed without error"):
        """fn() (a make_* call named `maker`), timed; then the recompute alone, timed; the
        object. An object in error fails a check, and the section stops there."""
        obj, t = timed(fn)
        obj.Label = label
        status = obj.getStatusString() if "Invalid" in obj.State else "ok"
        self.rep.check(check, status, "ok")
        if status != "ok":
            raise RuntimeError(f"{label} is in error: {status}")
        self.timings[f"{label}: {maker} (create + recompute)"] = t
        self.timings[f"{label}: recompute"] = recompute_time(self.doc, obj)
        self.seconds = t
        return obj

    def feature_row(self, feature, base, inputs, outputs, valid, oracle, error, tol):
        """One row of the features table: the result checked against its oracle (relative
        error `error`, passing at `tol`); the section's checks must pass too."""
        self.features.append({"feature": feature, "base": base, "inputs": inputs,
                              "outputs": outputs, "valid": bool(valid), "seconds": self.seconds,
                              "oracle": oracle, "error": float(error), "tolerance": tol,
                              "section": len(self.rep.sections) - 1})

    def export_step(self, obj, name):
        obj.Shape.exportStep(os.path.join(self.out, name))
        self.exports.append(name)

    def picture(self, name, title, obj, view=(22, -120), document=None):
        """Ask for a before/after picture of `obj` (of demo.FCStd, or of `document`), seen
        from elevation and azimuth `view` (degrees); pictures() renders them all at the end."""
        self.jobs.append({"png": os.path.join(self.out, name), "title": title,
                          "object": obj.Name, "type": obj.Proxy.TYPE, "view": view,
                          "document": document or os.path.join(self.out, "demo.FCStd")})

    # -- 1. one plane, +40 mm along +X at x = 150
    def one_plane(self):
        rep, shape = self.rep, self.shape
        origin, normal, distance = np.array([150.0, 0, 0]), X, 40.0
        rep.section("Stretch: one plane", "face_recognition_sample_part.stp (23 faces) stretched "
                    "by 40 mm along +X at the plane x = 150.")
        self.export_step(self.base, "sample_part.step")
        obj = self.create("Stretch", self.base, (V(*origin), V(*normal)), distance)
        rep.fact("faces before / after", f"{len(shape.Faces)} / {len(obj.Shape.Faces)}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        stretch_checks(rep, shape, obj, origin, normal, distance)
        area = section_area(shape, origin, normal)
        self.feature_row("Stretch", "face_recognition_sample_part.stp", "Distance 40 mm at x = 150",
                         f"VolumeChange {obj.VolumeChange:.6g} mm^3", obj.Shape.isValid(),
                         "A x d (A: Shape.slice section)",
                         abs(obj.VolumeChange - area * distance) / (area * distance), REL)
        self.export_step(obj, "stretch.step")
        self.picture("stretch.png", "Stretch: +40 mm along +X at x = 150", obj)

    # -- 2. two planes: z = 100 .. 150 stretched by 30 mm
    def two_planes(self):
        rep, shape = self.rep, self.shape
        o1, o2, normal, distance = np.array([0, 0, 100.0]), np.array([0, 0, 150.0]), Z, 30.0
        gap = 50.0
        rep.section("TwoPlanes: the region between two planes",
                    "The region between z = 100 and z = 150 stretched by 30 mm along +Z, its "
                    "cross-sections kept; the part above z = 150 moves up rigidly.")
        obj = self.create("TwoPlanes", self.base, (V(*o1), V(*normal)), distance,
                          plane2=(V(*o2), V(*normal)))
        result = obj.Shape
        between = slab_volume(shape, o1, normal, gap)
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        rep.fact("face types before / after", f"{_text(face_type_counts(shape))} / "
                 f"{_text(face_type_counts(result))}")
        rep.check("VolumeChange = volume between the planes x distance / gap",
                  obj.VolumeChange, between * distance / gap, rel=REL)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        # An affine stretch along Z keeps planes planar and cylinders along Z cylindrical; other
        # cylinders become elliptic (B-spline). Outside the region every face keeps its type.
        top = 100 + gap + distance
        splines = [f for f in result.Faces if isinstance(f.Surface, Part.BSplineSurface)]
        rep.check(f"B-spline faces lie between the two planes (after the stretch: z = 100 .. "
                  f"{top:g})", all(100 - 1e-6 <= f.BoundBox.ZMin and f.BoundBox.ZMax <= top + 1e-6
                                     for f in splines), True)
        elliptic = [f for f in shape.Faces if isinstance(f.Surface, Part.Cylinder)
                    and abs(np.dot(tuple(f.Surface.Axis), normal)) < 1 - 1e-9
                    and f.BoundBox.ZMin < 150 - 1e-6 and f.BoundBox.ZMax > 100 + 1e-6]
        rep.check("curved B-spline faces = base cylinders in the region not along Z",
                  sum(f.findPlane() is None for f in splines), len(elliptic))
        flat = [f"Face{i}" for i, f in enumerate(result.Faces, 1)
                if isinstance(f.Surface, Part.BSplineSurface) and f.findPlane() is not None]
        rep.check("flat faces between the planes stored as Part.Plane (an affine map keeps "
                  "planes planar)", flat, [], warn=True,
                  note="quality, not validity: a flat B-spline face is still exact")
        for frac in (0.25, 0.5, 0.8):
            rep.check(f"section area at {frac:g} of the region (z = {100 + frac * gap:g} -> "
                      f"{100 + frac * (gap + distance):g})",
                      section_area(result, o1 + frac * (gap + distance) * normal, normal),
                      section_area(shape, o1 + frac * gap * normal, normal), rel=REL)
        rep.check("height grows by distance", result.BoundBox.ZLength,
                  shape.BoundBox.ZLength + distance, rel=1e-9)
        continuity_check(rep, shape, obj, [o1, o2], normal)
        self.export_step(obj, "two_planes.step")
        self.picture("two_planes.png", "TwoPlanes: z = 100 .. 150 stretched by 30 mm along +Z", obj)

    # -- 3. shrink by 40 mm along +X at x = 150
    def shrink(self):
        rep, shape = self.rep, self.shape
        origin, normal, width = np.array([150.0, 0, 0]), X, 40.0
        rep.section("Shrink", "The sample part shrunk by 40 mm along +X at x = 150: the slab "
                    "150 < x < 190 removed, the part beyond moved back.")
        obj = self.create("Shrink", self.base, (V(*origin), V(*normal)), -width)
        result = obj.Shape
        removed = slab_volume(shape, origin, normal, width)
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        rep.check("VolumeChange = -(volume of the removed slab, a common with a box)",
                  obj.VolumeChange, -removed, rel=REL)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        rep.check("face types", face_types(result), face_types(shape))
        rep.check("length along X shrinks by 40", result.BoundBox.XLength,
                  shape.BoundBox.XLength - width, rel=1e-9)
        continuity_check(rep, shape, obj, [origin], normal)
        self.export_step(obj, "shrink.step")
        self.picture("shrink.png", "Shrink: -40 mm along +X at x = 150", obj)

    # -- 4. a mesh of the part
    def mesh(self):
        import MeshPart
        rep, shape = self.rep, self.shape
        origin, normal, distance = np.array([150.0, 0, 0]), X, 40.0
        rep.section("MeshStretch", "A mesh of the part (MeshPart.meshFromShape, MaxLength 12 mm) "
                    "stretched by 40 mm along +X at x = 150.")
        self.mesh_base = mesh_base = self.doc.addObject("Mesh::Feature", "SampleMesh")
        mesh_base.Mesh = MeshPart.meshFromShape(Shape=shape, MaxLength=12)
        obj = self.create("MeshStretch", mesh_base, (V(*origin), V(*normal)), distance)
        mesh, before = obj.Mesh, mesh_base.Mesh
        rep.fact("facets before / after", f"{before.CountFacets} / {mesh.CountFacets}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        change = mesh_volume(mesh) - mesh_volume(before)
        rep.check("volume change (float64 sum over the facets) = mesh section area x distance "
                  "(Mesh.crossSections)", change,
                  mesh_section_area(before, origin, normal) * distance, rel=1e-6)
        rep.check("VolumeChange = exact section area x distance (within the tessellation)",
                  obj.VolumeChange, section_area(shape, origin, normal) * distance, rel=1e-2)
        check_closed_mesh(rep, obj, mesh, before, change)
        rep.check("length along X grows by distance", mesh.BoundBox.XLength,
                  before.BoundBox.XLength + distance, rel=1e-9)
        before.write(os.path.join(self.out, "sample_mesh.stl"))
        mesh.write(os.path.join(self.out, "mesh_stretch.stl"))
        self.exports += ["sample_mesh.stl", "mesh_stretch.stl"]
        self.picture("mesh_stretch.png", "MeshStretch: +40 mm along +X at x = 150", obj)

    # -- 5. a point cloud sampled on the part
    def cloud(self):
        rep, shape = self.rep, self.shape
        origin, normal, distance = np.array([150.0, 0, 0]), X, 40.0
        rep.section("CloudStretch", "200,000 points sampled uniformly on the part's surface, "
                    "stretched by 40 mm along +X at x = 150.")
        cloud_base = self.doc.addObject("Points::Feature", "SampleCloud")
        cloud_base.Points = Points.Points([V(*p) for p in surface_samples(shape, 200_000).tolist()])
        cloud = points_of(cloud_base.Points.Points)  # as stored (float32)
        obj = self.create("CloudStretch", cloud_base, (V(*origin), V(*normal)), distance)
        out_pts = points_of(obj.Points.Points)
        s = (cloud - origin) @ normal
        expected = np.vstack([cloud[s <= 0], cloud[s > 0] + distance * normal])
        so = (out_pts - origin) @ normal
        fill = out_pts[(so > 1e-3) & (so < distance - 1e-3)]
        rep.fact("points before / after / in the gap",
                 f"{len(cloud):,} / {len(out_pts):,} / {len(fill):,}")
        moved = float(cKDTree(out_pts).query(expected)[0].max())
        rep.check("every point kept (moved by distance beyond the plane): max distance to the "
                  "nearest result point, mm", moved, 0.0, ok=moved < 1e-4, note="float32 storage")
        band = np.abs(s) < 2.0
        outline = cKDTree((cloud[band] - np.outer(s[band], normal))[:, 1:])
        offset = float(outline.query(fill[:, 1:])[0].max()) if len(fill) else np.inf
        rep.check("points fill the gap", len(fill) > 0, True)
        rep.check("each gap point lies on the section outline swept along X: max offset, mm",
                  offset, 0.0, ok=offset < 1e-3)
        rep.check("length along X grows by distance", float(np.ptp(out_pts[:, 0])),
                  float(np.ptp(cloud[:, 0]) + distance), rel=1e-6)
        cloud_base.Points.write(os.path.join(self.out, "sample_cloud.ply"))
        obj.Points.write(os.path.join(self.out, "cloud_stretch.ply"))
        self.exports += ["sample_cloud.ply", "cloud_stretch.ply"]
        self.picture("cloud_stretch.png", "CloudStretch: +40 mm along +X at x = 150", obj)

    # -- 6. the AS1 assembly
    def assembly(self):
        rep = self.rep
        as1 = Part.read(self.as1_path)
        c = as1.BoundBox.Center
        origin, normal, distance = np.array([400.0, c.y, c.z]), X, 800.0
        rep.section("AS1Stretch", f"The AS1 assembly ({len(as1.Solids)} solids) stretched by "
                    f"{distance:g} mm along +X at x = {origin[0]:g}, through the plates and the "
                    f"bracket on the right: each solid the plane crosses is stretched, the others "
                    f"stay or move rigidly.")
        as1_base = self.doc.addObject("Part::Feature", "AS1")
        as1_base.Shape = as1
        obj = self.create("AS1Stretch", as1_base, (V(*origin), V(*normal)), distance)
        result = obj.Shape
        crossed = [sd for sd in as1.Solids if sd.BoundBox.XMin < origin[0] < sd.BoundBox.XMax]
        area = sum(section_area(sd, origin, normal) for sd in crossed)
        rep.fact("solids crossed by the plane", len(crossed))
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.check("VolumeChange = sum of the crossed solids' section areas x distance",
                  obj.VolumeChange, area * distance, rel=REL)
        rep.check("number of solids", len(result.Solids), len(as1.Solids))
        expected = [(_box(sd, distance * normal if sd.BoundBox.XMin >= origin[0] else 0 * normal),
                     sd.Volume) for sd in as1.Solids if sd.BoundBox.XMin >= origin[0]
                    or sd.BoundBox.XMax <= origin[0]]
        got = [(_box(sd), sd.Volume) for sd in result.Solids]
        rep.check("solids the plane misses: kept, or moved by distance (same volume, box shifted)",
                  sum(any(np.allclose(b, g, atol=1e-6) and abs(v - w) <= 1e-9 * v for g, w in got)
                      for b, v in expected), len(expected))
        rep.check("every solid isValid()", all(sd.isValid() for sd in result.Solids), True)
        rep.check("face types", face_types(result), face_types(as1))
        rep.check("length along X grows by distance", result.BoundBox.XLength,
                  as1.BoundBox.XLength + distance, rel=1e-9)
        self.export_step(as1_base, "as1.step")
        self.export_step(obj, "as1_stretch.step")
        self.picture("as1_stretch.png", f"AS1Stretch: +{distance:g} mm along +X at x = {origin[0]:g}",
                     obj)

    # -- 7. bend at x = 150 by -60 deg about an axis in the plane
    def bend(self):
        rep, shape = self.rep, self.shape
        origin, normal, angle = np.array([150.0, 0, 0]), X, -60.0
        axis = (np.array([150.0, 0, 260]), Y)
        rep.section("Bend", "The sample part bent at the plane x = 150 by -60 deg about the axis "
                    "through (150, 0, 260) along +Y: the axis lies in the plane, 35 mm above the "
                    "part, so the part beyond the plane swings up and the gap is the section "
                    "revolved (exact).")
        obj = self.make("Bend", "make_bend", lambda: fd.make_bend(
            self.base, (V(*origin), V(*normal)), angle, (V(*axis[0]), V(*axis[1]))))
        result = obj.Shape
        sec = section_face(shape, origin, normal)
        volume, radius = pappus(sec, *axis, angle)
        rep.fact("faces before / after", f"{len(shape.Faces)} / {len(result.Faces)}")
        rep.fact("section at x = 150 (Shape.slice): area (mm^2) / centroid radius (mm)",
                 f"{sec.Area:.6g} / {radius:.6g}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        rep.fact("face types after", face_type_counts(result))
        rep.check("VolumeChange = section area x centroid radius x angle (Pappus)",
                  obj.VolumeChange, volume, rel=REL)
        rep.check("Volume(result) - Volume(base) = Pappus", result.Volume - shape.Volume, volume,
                  rel=REL)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        rep.check("face types other than planes, cylinders, cones, tori, spheres and surfaces of "
                  "revolution", sorted(set(face_types(result)) - REVOLUTION), [],
                  note="a revolve is exact: no B-spline")
        rigid_check(rep, shape, result, origin, normal, lambda p: rodrigues(p, *axis, angle))
        self.feature_row("Bend", "face_recognition_sample_part.stp",
                         "Angle -60 deg at x = 150, axis (150, 0, 260) along +Y",
                         f"VolumeChange {obj.VolumeChange:.6g} mm^3", result.isValid(),
                         "Pappus (section area x centroid radius x angle)",
                         abs(result.Volume - shape.Volume - volume) / volume, REL)
        mid = rodrigues(normal, np.zeros(3), axis[1], angle / 2)[0]
        rep.check("section area at half the angle (the plane through the axis turned by -30 deg)",
                  section_area(result, axis[0], mid), sec.Area, rel=REL)
        continuity_check(rep, shape, obj, [origin], normal,
                         tangent=bend_tangent(origin, normal, *axis))
        self.export_step(obj, "bend.step")
        self.picture("bend.png", "Bend: -60 deg at x = 150 about the axis through (150, 0, 260) "
                     "along +Y", obj)

    # -- 8. two planes: the slab x = 90 .. 140 bent by -60 deg
    def two_plane_bend(self):
        rep, shape = self.rep, self.shape
        o1, o2, normal, angle, gap = np.array([90.0, 0, 0]), np.array([140.0, 0, 0]), X, -60.0, 50.0
        axis = (np.array([90.0, 0, 260]), Y)
        rep.section("TwoPlaneBend", "The region between x = 90 and x = 140 (one constant "
                    "cross-section) bent by -60 deg about the axis through (90, 0, 260) along +Y, "
                    "in Plane: the slab becomes the section revolved, its cross-section kept, and "
                    "the part beyond x = 140 turns with its end.")
        obj = self.make("TwoPlaneBend", "make_bend", lambda: fd.make_bend(
            self.base, (V(*o1), V(*normal)), angle, (V(*axis[0]), V(*axis[1])),
            plane2=(V(*o2), V(*normal))))
        result = obj.Shape
        sec = section_face(shape, o1, normal)
        volume, radius = pappus(sec, *axis, angle)
        slab = slab_volume(shape, o1, normal, gap)
        rep.fact("section at x = 90: area (mm^2) / centroid radius (mm)",
                 f"{sec.Area:.6g} / {radius:.6g}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        rep.fact("face types after", face_type_counts(result))
        rep.check("section area at Plane2 = at Plane (the region between is prismatic)",
                  section_area(shape, o2, normal), sec.Area, rel=1e-9)
        rep.check("VolumeChange = Pappus (section revolved) - volume between the planes "
                  "(a common with a box)", obj.VolumeChange, volume - slab, rel=REL)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        rep.check("face types other than planes, cylinders, cones, tori, spheres and surfaces of "
                  "revolution", sorted(set(face_types(result)) - REVOLUTION), [],
                  note="a prismatic region is revolved exactly")
        rigid_check(rep, shape, result, o1, normal,
                    lambda p: rodrigues(p - gap * normal, *axis, angle), gap=gap)
        for frac in (0.25, 0.5, 0.8):
            turned = rodrigues(normal, np.zeros(3), axis[1], frac * angle)[0]
            rep.check(f"section area at {frac:g} of the angle (the plane through the axis turned "
                      f"by {frac * angle:g} deg)", section_area(result, axis[0], turned), sec.Area,
                      rel=REL)
        continuity_check(rep, shape, obj, [o1, o2], normal, tangent=bend_tangent(o1, normal, *axis))
        self.export_step(obj, "two_plane_bend.step")
        self.picture("two_plane_bend.png", "TwoPlaneBend: x = 90 .. 140 bent by -60 deg about the "
                     "axis through (90, 0, 260) along +Y", obj)

    # -- 9. a bar twisted by 90 deg between two planes
    def twist(self):
        rep = self.rep
        bar = Part.makeBox(60, 20, 150)
        o1, o2, normal, angle, gap = np.array([0, 0, 40.0]), np.array([0, 0, 110.0]), Z, 90.0, 70.0
        axis = (np.array([30.0, 10.0, 0.0]), Z)   # the section's centroid: the default axis
        rep.section("Twist", "A 60 x 20 x 150 mm bar twisted by 90 deg between z = 40 and z = 110 "
                    "about the default axis (the Plane normal through the centroid of the section "
                    "at Plane, x = 30, y = 10), Samples 16: the sections between turn "
                    "progressively, the part above z = 110 turns rigidly, the length is kept.")
        base = self.doc.addObject("Part::Feature", "Bar")
        base.Shape = bar
        obj = self.make("Twist", "make_twist", lambda: fd.make_twist(
            base, (V(*o1), V(*normal)), (V(*o2), V(*normal)), angle))
        result = obj.Shape
        rep.fact("faces before / after", f"{len(bar.Faces)} / {len(result.Faces)}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.fact("Continuity", obj.Continuity)
        rep.fact("face types after", face_type_counts(result))
        rep.check("volume kept (a loft through 17 profiles)", result.Volume, bar.Volume, rel=1e-3)
        rep.check("|VolumeChange| <= 1e-3 x volume", obj.VolumeChange, 0.0,
                  ok=abs(obj.VolumeChange) <= 1e-3 * bar.Volume)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        for frac in (0.25, 0.5, 0.8):
            z = o1 + frac * gap * normal
            rep.check(f"section area at {frac:g} of the span (z = {z[2]:g}"
                      f"{', mid-span' if frac == 0.5 else ''})", section_area(result, z, normal),
                      section_area(bar, z, normal), rel=1e-3)
        centre = o1 + 0.5 * gap * normal
        mid = points_of([v.Point for v in section_face(result, centre, normal).Vertexes])
        corners = points_of([v.Point for v in section_face(bar, centre, normal).Vertexes])
        err = _nearest(mid, rodrigues(corners, *axis, angle / 2))
        rep.check("mid-span section corners = the bar's corners turned by 45 deg (Rodrigues): "
                  "max distance, mm", err, 0.0, ok=len(mid) == 4 and err < 1e-6,
                  note="profile 8 of 16 lies there")
        rep.check("length along Z kept", result.BoundBox.ZLength, bar.BoundBox.ZLength, rel=1e-9)
        rigid_check(rep, bar, result, o1, normal, lambda p: rodrigues(p, *axis, angle), gap=gap)
        self.feature_row("Twist", "60 x 20 x 150 bar (made here)",
                         "Angle 90 deg between z = 40 and z = 110, Samples 16",
                         f"VolumeChange {obj.VolumeChange:.3g} mm^3", result.isValid(),
                         "mid-span section = the bar's corners turned 45 deg (Rodrigues), mm",
                         err, 1e-6)
        continuity_check(rep, bar, obj, [o1, o2], normal, fractions=np.linspace(0.05, 0.95, 7),
                         tangent=lambda p: normal + np.radians(angle) / gap * np.cross(
                             axis[1], p - axis[0]))
        self.export_step(base, "bar.step")
        self.export_step(obj, "twist.step")
        self.picture("twist.png", "Twist: a 60 x 20 x 150 bar, 90 deg between z = 40 and z = 110",
                     obj, (18, -60))

    # -- 10. the mesh of the part, bent like Bend
    def mesh_bend(self):
        import MeshPart
        rep = self.rep
        origin, normal, angle, samples = np.array([150.0, 0, 0]), X, -60.0, 16
        axis = (np.array([150.0, 0, 260]), Y)
        rep.section("MeshBend", f"The mesh of the part (SampleMesh: MeshPart, MaxLength 12 mm) "
                    f"bent like Bend, -60 deg at x = 150 about (150, 0, 260) along +Y: the far "
                    f"part turned, the gap the section ring turned through {samples} steps "
                    f"(Samples).")
        if self.mesh_base is None:
            self.mesh_base = self.doc.addObject("Mesh::Feature", "SampleMesh")
            self.mesh_base.Mesh = MeshPart.meshFromShape(Shape=self.shape, MaxLength=12)
        mesh_base = self.mesh_base
        obj = self.make("MeshBend", "make_bend", lambda: fd.make_bend(
            mesh_base, (V(*origin), V(*normal)), angle, (V(*axis[0]), V(*axis[1]))))
        mesh, before = obj.Mesh, mesh_base.Mesh
        area, centroid = mesh_section(before, origin, normal)
        radius = float(np.linalg.norm(np.cross(centroid - axis[0], axis[1])))
        a = abs(np.radians(angle))
        change = mesh_volume(mesh) - mesh_volume(before)
        rep.fact("facets before / after", f"{before.CountFacets} / {mesh.CountFacets}")
        rep.fact("mesh section at x = 150 (Mesh.crossSections): area (mm^2) / centroid radius "
                 "(mm)", f"{area:.6g} / {radius:.6g}")
        rep.fact("VolumeChange (mm^3)", obj.VolumeChange)
        rep.check(f"volume change (float64 sum over the facets) = mesh section area x centroid "
                  f"radius x {samples} sin(angle / {samples}) (Pappus along the {samples} chords "
                  f"of the arc)", change, area * radius * samples * np.sin(a / samples), rel=1e-4)
        rep.check(f"volume change = Pappus with the exact arc (the {samples} chords fall short by "
                  f"1 - sin(x)/x = {1 - np.sin(a / samples) / (a / samples):.1e})", change,
                  area * radius * a, rel=1e-3)
        check_closed_mesh(rep, obj, mesh, before, change)
        v0, v1 = points_of(before.Topology[0]), points_of(mesh.Topology[0])
        v0 = v0[np.unique(np.array(before.Topology[1], int))]   # MeshPart leaves unused points
        s = (v0 - origin) @ normal
        expected = np.vstack([v0[s < -1e-6], rodrigues(v0[s > 1e-6], *axis, angle)])
        moved = _nearest(v1, expected)
        rep.check("facet corners before the plane kept, beyond it turned (Rodrigues): max "
                  "distance to the nearest result vertex, mm", moved, 0.0, ok=moved < 1e-4,
                  note="float32 storage")
        mesh.write(os.path.join(self.out, "mesh_bend.stl"))
        self.exports.append("mesh_bend.stl")
        self.picture("mesh_bend.png", "MeshBend: -60 deg at x = 150 about the axis through "
                     "(150, 0, 260) along +Y", obj)

    # -- 11. the paper's turbine blade (Fig. 9): extended 3x, then twisted by 30 deg
    def blade(self):
        rep = self.rep
        span, distance, angle = 100.0, 200.0, 30.0
        rep.section("Blade: Stretch, then Twist", "Wu & Ilies' turbine-blade example (Fig. 9) on "
                    "a point cloud: a blade-like cloud (a root platform, a cambered, tapered, "
                    "pre-twisted airfoil stacked along Z from z = 0 to 100, a tip shroud; every "
                    "horizontal layer's points centred on x = y = 0) whose airfoil is extended "
                    "3x (BladeStretch: two planes z = 0 and z = 100, Distance 200) and then "
                    "twisted by 30 deg (BladeTwist on BladeStretch: planes z = 0 and z = 300, "
                    "default axis) so the centroids of the horizontal cross-sections stay on "
                    "the vertical line.")
        cloud, layer = blade_cloud(span)
        base = self.doc.addObject("Points::Feature", "BladeCloud")
        base.Points = Points.Points([V(*p) for p in cloud.tolist()])
        cloud = points_of(base.Points.Points)  # as stored (float32)
        stretch = self.make("BladeStretch", "make_stretch", lambda: fd.make_stretch(
            base, (V(0, 0, 0), V(*Z)), distance, plane2=(V(0, 0, span), V(*Z))),
            "BladeStretch recomputed without error")
        top = span + distance
        twist = self.make("BladeTwist", "make_twist", lambda: fd.make_twist(
            stretch, (V(0, 0, 0), V(*Z)), (V(0, 0, top), V(*Z)), angle),
            "BladeTwist (its Base: BladeStretch) recomputed without error")
        stretched, twisted = points_of(stretch.Points.Points), points_of(twist.Points.Points)
        airfoil = (cloud[:, 2] >= -1e-9) & (cloud[:, 2] <= span + 1e-9)
        rep.fact("points / layers (airfoil layers)",
                 f"{len(cloud):,} / {layer.max() + 1} ({len(np.unique(layer[airfoil]))})")
        rep.check("points kept by the Stretch and by the Twist", [len(stretched), len(twisted)],
                  [len(cloud), len(cloud)])
        rep.check("airfoil span (z of its top layer - z of its root layer) extended 3x",
                  float(np.ptp(stretched[airfoil, 2])), 3 * float(np.ptp(cloud[airfoil, 2])),
                  rel=1e-6)
        # the two maps written out: z scaled between the planes, then each layer turned about
        # the vertical line x = y = 0 by angle x (its height / the new span)
        z = cloud[:, 2]
        expected_s = cloud + np.outer(np.clip(z / span, 0, 1) * distance, Z)
        expected_t = rodrigues(expected_s, np.zeros(3), Z,
                               angle * np.clip(expected_s[:, 2] / top, 0, 1))
        err_s = float(np.abs(stretched - expected_s).max())
        err_t = float(np.abs(twisted - expected_t).max())
        rep.check("every point where the two-plane stretch puts it (z scaled by 3 between the "
                  "planes, the shroud moved up 200): max error, mm", err_s, 0.0, ok=err_s < 1e-3,
                  note="float32 storage")
        rep.check("every point turned by 30 deg x its height / 300 about the vertical x = y = 0 "
                  "(Rodrigues): max error, mm", err_t, 0.0, ok=err_t < 1e-3, note="float32 storage")
        drift = max(float(np.linalg.norm(twisted[layer == k, :2].mean(axis=0)))
                    for k in range(layer.max() + 1))
        rep.fact("largest centroid offset of a layer before, mm",
                 max(float(np.linalg.norm(cloud[layer == k, :2].mean(axis=0)))
                     for k in range(layer.max() + 1)))
        rep.check("centroid of every horizontal cross-section (the mean of its layer's points) "
                  "on the vertical line x = y = 0 after both edits: largest offset, mm", drift,
                  0.0, ok=drift < 1e-4, note="float32 storage")
        turns = np.array([_turn(cloud[layer == k, :2], twisted[layer == k, :2])
                          for k in range(layer.max() + 1)])
        heights = np.array([twisted[layer == k, 2].mean() for k in range(layer.max() + 1)])
        want = angle * np.clip(heights / top, 0, 1)
        rep.check("each layer turned as a rigid cross-section by 30 deg x height / 300 (2-D "
                  "Procrustes fit): largest error, deg", float(np.abs(turns - want).max()), 0.0,
                  ok=float(np.abs(turns - want).max()) < 1e-3)
        rep.check("root platform kept (bit-identical)", bool(np.array_equal(
            twisted[cloud[:, 2] < 0], cloud[cloud[:, 2] < 0])), True)
        shroud = cloud[:, 2] > span
        err = float(np.abs(twisted[shroud] - rodrigues(cloud[shroud] + distance * Z, np.zeros(3),
                                                       Z, angle)).max())
        rep.check("tip shroud moved up by 200 and turned by 30 deg: max error, mm", err, 0.0,
                  ok=err < 1e-3)
        base.Points.write(os.path.join(self.out, "blade_cloud.ply"))
        twist.Points.write(os.path.join(self.out, "blade_twist.ply"))
        self.exports += ["blade_cloud.ply", "blade_twist.ply"]
        self.picture("blade.png", "BladeTwist: the airfoil extended 3x (BladeStretch), twisted by "
                     "30 deg", twist, (32, -60))

    # -- 12. Taper: a bar's middle scaled to 0.6 across its axis
    def taper(self):
        rep = self.rep
        o1, o2, normal, scale = np.array([0, 0, 40.0]), np.array([0, 0, 110.0]), Z, 0.6
        size, length, gap = (60.0, 40.0), 150.0, 70.0
        rep.section("Taper", "A 60 x 40 x 150 mm bar whose region between z = 40 and z = 110 is "
                    "scaled across its axis (the Plane normal through the section centroid) "
                    "linearly from 1 to 0.6 (Profile Linear); the part above z = 110 is scaled "
                    "by 0.6 across the axis and moved with the region's end.")
        base = self.doc.addObject("Part::Feature", "TaperBar")
        base.Shape = bar = Part.makeBox(size[0], size[1], length)
        obj = self.make("Taper", "make_taper", lambda: fd.make_taper(
            base, (V(*o1), V(*normal)), (V(*o2), V(*normal)), scale))
        result = obj.Shape
        area = size[0] * size[1]
        # the section scales by s(t)^2, s = 1 + (S - 1) t: the region holds A L (1 + (S - 1)
        # + (S - 1)^2 / 3), the part beyond A S^2 x its length
        closed = area * (o1[2] + gap * (1 + (scale - 1) + (scale - 1) ** 2 / 3)
                         + scale ** 2 * (length - o2[2]))
        rep.fact("faces before / after", f"{len(bar.Faces)} / {len(result.Faces)}")
        rep.fact("face types after", face_type_counts(result))
        rep.fact("MaxDeviation (mm)", obj.MaxDeviation)
        rep.check("Volume = A (40 + 70 (1 + (S - 1) + (S - 1)^2 / 3) + S^2 x 40) (closed form)",
                  result.Volume, closed, rel=REL)
        rep.check("isValid()", result.isValid(), True)
        rep.check("number of solids", len(result.Solids), 1)
        for z, s_ in ((20.0, 1.0), (75.0, 1 + (scale - 1) * 0.5), (110.0, scale), (130.0, scale)):
            rep.check(f"section area at z = {z:g} = A x {s_:g}^2 (Shape.slice)",
                      section_area(result, np.array([0, 0, z]), normal), area * s_ ** 2, rel=REL)
        rep.check("length along Z kept", result.BoundBox.ZLength, length, rel=1e-9)
        self.feature_row("Taper", "60 x 40 x 150 bar (made here)",
                         "Scale 0.6 between z = 40 and z = 110",
                         f"MaxDeviation {obj.MaxDeviation:.2g} mm", result.isValid(),
                         "closed-form volume (section scaled by s(t)^2)",
                         abs(result.Volume - closed) / closed, REL)
        self.export_step(obj, "taper.step")
        self.picture("taper.png", "Taper: a 60 x 40 x 150 bar, scale 0.6 between z = 40 and "
                     "z = 110", obj, (18, -60))

    # -- 13. DimensionDrive: the fandisk's thickness 4.8279 -> 4.65
    def dimension_drive(self):
        import Mesh
        from deform_tests.oracles import fits
        rep = self.rep
        target = 4.65
        hints = np.array([[4.83, 15.63, -0.29], [0.0, 14.98, -1.31]])   # moving, reference
        planes = [(np.array([4.8279, 0, 0]), X), (np.zeros(3), -X)]
        rep.section("DimensionDrive", "fandisk.obj (the CAD part mesh of the dimension paper, "
                    "12,946 triangles): the distance between the plane x = 4.8279 and the plane "
                    "x = 0 driven to 4.65 mm (Kind Distance); the regions are picked by the "
                    "triangle centres nearest two points on those faces.")
        base = self.doc.addObject("Mesh::Feature", "Fandisk")
        base.Mesh = Mesh.Mesh(os.path.join(TESTDATA, "fandisk.obj"))
        v0, t0 = points_of(base.Mesh.Topology[0]), np.array(base.Mesh.Topology[1], int)
        centres = v0[t0].mean(axis=1)
        regions = [centres[np.argmin(np.linalg.norm(centres - h, axis=1))] for h in hints]
        obj = self.make("DimensionDrive", "make_dimension_drive", lambda: fd.make_dimension_drive(
            base, "Distance", [V(*r) for r in regions], target))
        v1, t1 = points_of(obj.Mesh.Topology[0]), np.array(obj.Mesh.Topology[1], int)
        size = float(np.linalg.norm(np.ptp(v0, axis=0)))
        # the vertices of each plane's face, selected on the base: on the plane, near its hint
        picked = [np.flatnonzero((np.abs((v0 - o) @ n) <= 2e-4 * size)
                                 & (np.linalg.norm(v0 - h, axis=1) <= 1.5))
                  for (o, n), h in zip(planes, hints)]
        (na, ca, ra), (nb, cb, rb) = (fits.plane_fit(v1[i]) for i in picked)
        if na @ nb < 0:
            nb, cb = -nb, -cb
        achieved = abs(ca - cb)
        fit_tol = 1e-6 * size + 4 * 1.2e-7 * np.abs(v0).max()    # float32 storage
        rep.fact("triangles / vertices on the two faces", f"{len(t0)} / {len(picked[0])}, "
                 f"{len(picked[1])}")
        rep.fact("Current / Achieved / Reachable (mm)",
                 f"{obj.Current:.6g} / {obj.Achieved:.6g} / {_text(list(obj.Reachable))}")
        rep.check("distance between the SVD planes fitted to the two faces' vertices = Target",
                  achieved, target, ok=abs(achieved - target) <= fit_tol,
                  note=f"within {fit_tol:.1e} mm: float32 vertices")
        rep.check("both faces stay planes (largest rms of the fits), mm", max(ra, rb), 0.0,
                  ok=max(ra, rb) <= fit_tol)
        rep.check("the faces stay parallel (|n_a x n_b|)", float(np.linalg.norm(np.cross(na, nb))),
                  0.0, ok=float(np.linalg.norm(np.cross(na, nb))) <= 1e-6)
        rep.check("topology kept (the same triangles)", bool(np.array_equal(t0, t1)), True)
        n0 = np.cross(v0[t0[:, 1]] - v0[t0[:, 0]], v0[t0[:, 2]] - v0[t0[:, 0]])
        n1 = np.cross(v1[t1[:, 1]] - v1[t1[:, 0]], v1[t1[:, 2]] - v1[t1[:, 0]])
        rep.check("no triangle turned over", int((np.einsum("ij,ij->i", n0, n1) <= 0).sum()), 0)
        rep.check("Achieved = Target", obj.Achieved, target,
                  ok=abs(obj.Achieved - target) <= fit_tol)
        self.feature_row("DimensionDrive", "fandisk.obj", "Kind Distance, Target 4.65 mm "
                         "(was 4.8279)", f"Achieved {obj.Achieved:.6g} mm", np.array_equal(t0, t1),
                         "SVD plane fits of the two faces' vertices",
                         abs(achieved - target) / target, fit_tol / target)
        obj.Mesh.write(os.path.join(self.out, "dimension_drive.stl"))
        self.exports.append("dimension_drive.stl")
        self.picture("dimension_drive.png", "DimensionDrive: the fandisk's plane x = 4.83 "
                     "driven to 4.65 mm from x = 0", obj, (25, -35))

    def _splinecage(self):
        if not hasattr(self, "cage"):
            self.cage = self.doc.addObject("Part::Feature", "SplineCage")
            self.cage.Shape = Part.read(os.path.join(TESTDATA, "splinecage.stp"))
        return self.cage

    # -- 14. AreaConstrain: a B-spline face of splinecage.stp +3 %
    def area_constrain(self):
        from deform_tests.oracles import nurbs
        rep, ratio = self.rep, 1.03
        base = self._splinecage()
        face = base.Shape.Face2
        rep.section("AreaConstrain", "splinecage.stp (4 B-spline faces, no solid): Face2 (2 x 7 "
                    "poles) given 103 % of its area with the least movement of its poles (every "
                    "pole but the corners, along the control-net normals).")
        obj = self.make("AreaConstrain", "make_area_constrain",
                        lambda: fd.make_area_constrain(base, "Face2", "103%"))
        result = obj.Shape
        new = min(result.Faces, key=lambda f: (f.CenterOfMass - face.CenterOfMass).Length)
        a0, c0 = nurbs.converged_area(*surface_arrays(face))
        a1, c1 = nurbs.converged_area(*surface_arrays(new))
        rep.fact("OriginalArea / AchievedArea (mm^2)", f"{obj.OriginalArea:.10g} / "
                 f"{obj.AchievedArea:.10g}")
        rep.fact("Iterations / MaxPoleMove (mm)", f"{obj.Iterations} / {obj.MaxPoleMove:.4g}")
        rep.check("area / original area (Gauss quadrature of the B-spline, converged)", a1 / a0,
                  ratio, rel=1e-10, note=f"quadrature converged to {max(c0, c1):.1e}")
        rep.check("AchievedArea = the quadrature's area", obj.AchievedArea, a1, rel=1e-10)
        rep.check("isValid()", result.isValid(), True)
        rep.fact("result", f"{len(result.Faces)} face(s): a Base that is not one shell or solid "
                 f"gives the constrained face alone")
        rep.check("knots, degrees and pole counts kept",
                  [new.Surface.UDegree, new.Surface.VDegree, new.Surface.NbUPoles,
                   new.Surface.NbVPoles, list(new.Surface.getUKnots()), list(new.Surface.getVKnots())],
                  [face.Surface.UDegree, face.Surface.VDegree, face.Surface.NbUPoles,
                   face.Surface.NbVPoles, list(face.Surface.getUKnots()),
                   list(face.Surface.getVKnots())])
        self.feature_row("AreaConstrain", "splinecage.stp Face2", "TargetArea 103 %",
                         f"AchievedArea {obj.AchievedArea:.10g} mm^2", result.isValid(),
                         "converged Gauss quadrature of the B-spline's area",
                         abs(a1 / a0 - ratio) / ratio, 1e-10)
        self.export_step(obj, "area_constrain.step")
        self.picture("area_constrain.png", "AreaConstrain: splinecage Face2 +3 %", obj)

    # -- 15. DirectPush: a point of the same face pushed along its normal
    def direct_push(self):
        rep = self.rep
        base = self._splinecage()
        face = base.Shape.Face2
        u0, u1, v0, v1 = face.ParameterRange
        u, v = u0 + 0.43 * (u1 - u0), v0 + 0.57 * (v1 - v0)
        size = face.BoundBox.DiagonalLength
        point = face.valueAt(u, v)
        target = point + face.normalAt(u, v) * (0.02 * size)
        rep.section("DirectPush", f"splinecage.stp Face2: its point at (u, v) = 43 %, 57 % of "
                    f"the parameter range pushed by 2 % of the face's size ({0.02 * size:.3g} "
                    f"mm) along its normal; the poles and knots follow.")
        obj = self.make("DirectPush", "make_direct_push",
                        lambda: fd.make_direct_push(base, "Face2", point, target))
        result = obj.Shape
        landed = result.distToShape(Part.Vertex(target))[0]
        others = sorted(f.Area for f in base.Shape.Faces if not f.isSame(face))
        rep.check("the pushed point lands: distance of the result to the target (OCCT "
                  "distToShape), mm", landed, 0.0, ok=landed <= 1e-7 * size)
        rep.check("isValid()", result.isValid(), True)
        rep.check("faces kept", len(result.Faces), len(base.Shape.Faces))
        kept = sum(any(abs(f.Area - a) <= 1e-12 * a for f in result.Faces) for a in others)
        rep.check("the other faces' areas kept", kept, len(others))
        self.feature_row("DirectPush", "splinecage.stp Face2",
                         f"Point -> Target, {0.02 * size:.3g} mm along the normal",
                         f"landed {landed:.2g} mm off", result.isValid(),
                         "OCCT distToShape(result, target) / face size", landed / size, 1e-7)
        self.export_step(obj, "direct_push.step")
        self.picture("direct_push.png", "DirectPush: a point of splinecage Face2 pushed 2 % "
                     "of its size", obj)

    # -- 16. the command line: a sweep, a goal seek and reach
    def batch(self):
        import csv
        rep, shape = self.rep, self.shape
        folder = os.path.join(self.out, "batch")
        os.makedirs(folder, exist_ok=True)
        origin, d_solve = np.array([150.0, 0, 0]), 37.25
        rep.section("Batch: sweep, goal seek, reach", "The command line (`python3 -m "
                    "freecad_deform`) on documents the demo saves in batch/: part.FCStd (the "
                    "sample part and a Stretch at x = 150) swept over Distance 10, 30, 50 on 2 "
                    "workers, solved for the Distance that gives the volume V0 + A x 37.25, "
                    "and the bracket fc_Schenkel.stp made to land its end hole (Face338) where "
                    "a 30, 3, 2 mm slide with a 3 deg turn about Z takes it: neither a Stretch "
                    "nor a Bend, so a key-frame sweep (Method KeyFrames).")
        doc = App.newDocument("DemoBatch")
        doc.addObject("Part::Feature", "Model").Shape = shape
        fd.make_stretch(doc.Model, (V(*origin), V(*X)), 40)
        part = os.path.join(folder, "part.FCStd")
        doc.saveAs(part)
        App.closeDocument(doc.Name)
        area, v0 = section_area(shape, origin, X), shape.Volume
        study = os.path.join(folder, "study")
        done = command("sweep", part, "--grid", "Stretch.Distance=10:50:3", "--out", study,
                       "--jobs", "2")
        with open(os.path.join(study, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        rep.fact("sweep", f"{len(rows)} variants in {done['seconds']:.1f} s (exit {done['code']})")
        worst = max((abs(float(r["Stretch.VolumeChange"]) - area * float(r["Stretch.Distance"]))
                     / (area * float(r["Stretch.Distance"])) for r in rows), default=np.inf)
        rep.check("sweep: 3 valid variants, Distance 10, 30, 50",
                  [(float(r["Stretch.Distance"]), r["valid"]) for r in rows],
                  [(10.0, "True"), (30.0, "True"), (50.0, "True")])
        rep.check("sweep: each row's Stretch.VolumeChange = A x Distance (largest rel. error)",
                  worst, 0.0, ok=worst <= REL)
        volume = float(v0 + area * d_solve)
        done = command("solve", part, "--vary", "Stretch.Distance=0:100", "--target",
                       f"Stretch.Shape.Volume={volume!r}", "--out",
                       os.path.join(folder, "solved.FCStd"))
        name, _, value = done["last"].partition(" = ")
        found = float(value) if name == "Stretch.Distance" else np.nan
        rep.fact("solve", f"{done['last']} in {done['seconds']:.1f} s")
        rep.check("solve: Distance = (V - V0) / A (A: Shape.slice section), mm", found,
                  (volume - v0) / area, ok=abs(found - (volume - v0) / area) <= 1e-8)
        bracket = Part.read(os.path.join(TESTDATA, "fc_Schenkel.stp"))
        doc = App.newDocument("DemoReach")
        doc.addObject("Part::Feature", "Model").Shape = bracket
        path = os.path.join(folder, "bracket.FCStd")
        doc.saveAs(path)
        App.closeDocument(doc.Name)
        turn = (np.array([140.0, 0, 0]), Z, 3.0)
        shift = np.array([30.0, 3.0, 2.0])
        q = rodrigues([140.0, 0, 0], *turn)[0] + shift
        b = rodrigues(X, np.zeros(3), Z, 3.0)[0]
        text = lambda v: ",".join(repr(float(c)) for c in v)  # noqa: E731  (numpy 2 repr)
        done = command("reach", path, "--base", "Model", "--plane", "120,0,0:1,0,0",
                       "--feature", "Face338", "--target", f"{text(q)}:{text(b)}", "--out",
                       os.path.join(folder, "reached.FCStd"))
        rep.fact("reach", f"{done['last']} in {done['seconds']:.1f} s")
        rep.check("reach: the method used", done["last"], "Method = KeyFrames")
        doc = App.openDocument(os.path.join(folder, "reached.FCStd"))
        try:
            result = doc.getObject("Stretch").Shape
            rims = [rodrigues(p, *turn)[0] + shift for p in ([135.0, 0, 0], [145.0, 0, 0])]
            off, tilt = hole_rims(result, 2.0, rims, b)
            rep.check("reach: the hole's rim circles (Edge.Curve Center) at the slide and turn "
                      "written out (Rodrigues), largest distance, mm", off, 0.0, ok=off <= 1e-9)
            rep.check("reach: the rims' axes along the turned axis, rad", tilt, 0.0,
                      ok=tilt <= 1e-9)
            rep.check("reach: isValid(), one solid", [result.isValid(), len(result.Solids)],
                      [True, 1])
            self.picture("reach.png", "reach: the bracket's end hole made to land by a slide "
                         "and a 3 deg turn (key frames)", doc.getObject("Stretch"), (35, -70),
                         os.path.join(folder, "reached.FCStd"))
        finally:
            App.closeDocument(doc.Name)

    # -- 17. save, reopen, recompute: the same results
    def reopen(self):
        rep, doc = self.rep, self.doc
        rep.section("Document", "demo.FCStd saved, closed, reopened and recomputed.")
        path = os.path.join(self.out, "demo.FCStd")
        volumes = {o.Name: o.Shape.Volume for o in doc.Objects if o.TypeId == "Part::FeaturePython"}
        counts = {o.Name: _count(o) for o in doc.Objects
                  if o.TypeId in ("Mesh::FeaturePython", "Points::FeaturePython")}
        names = [o.Name for o in doc.Objects]
        doc.saveAs(path)
        App.closeDocument(doc.Name)
        self.doc = doc = App.openDocument(path)
        for o in doc.Objects:
            if o.Name in volumes or o.Name in counts:
                o.touch()
        doc.recompute()
        rep.check("objects after reopening", [o.Name for o in doc.Objects], names)
        rep.check("no object in error after recompute",
                  [o.Label for o in doc.Objects if "Invalid" in o.State], [])
        for name, volume in volumes.items():
            rep.check(f"{doc.getObject(name).Label}: volume after reopen + recompute",
                      doc.getObject(name).Shape.Volume, volume, rel=1e-9)
        for name, count in counts.items():
            obj = doc.getObject(name)
            rep.check(f"{obj.Label}: {'facets' if hasattr(obj, 'Mesh') else 'points'} after "
                      f"reopen + recompute", _count(obj), count)


    # -- 18. the pictures, by FreeCAD's own 3D view
    def pictures(self):
        rep = self.rep
        rep.section("Pictures", "Each feature's Base (before, blue) and result (after, orange) "
                    "from one camera in FreeCAD's 3D view (the GUI under xvfb-run, "
                    "examples/demo_pictures.py), its task panel open as a user opens it: the "
                    "planes in use as translucent red sheets, the axis as a red line, the "
                    "handles (draggers); DimensionDrive, AreaConstrain and DirectPush show "
                    "what their panels show.")
        done, seconds = render(self.jobs, self.out)
        rep.fact("rendered", f"{len(done['done'])} of {len(self.jobs)} pictures in "
                 f"{seconds:.1f} s")
        rep.check("pictures that failed", sorted(done["failed"]), [])
        types = {job["png"]: job["type"] for job in self.jobs}
        for row in done["done"]:
            name = os.path.basename(row["png"])
            left, right = halves(row["png"])
            rep.check(f"{name}: share of the before / after sides the part covers (not white)",
                      [round(left, 3), round(right, 3)], "> 0.005 each",
                      ok=min(left, right) > 0.005)
            if types[row["png"]] in ("Stretch", "Bend", "Twist", "Taper"):
                rep.check(f"{name}: planes drawn, draggers in the scene", [row["planes"],
                          row["handles"]], ">= 1 plane, >= 2 draggers",
                          ok=row["planes"] >= 1 and row["handles"] >= 2)
        self.exports += [os.path.basename(row["png"]) for row in done["done"]]


def render(jobs, out):
    """The pictures of `jobs` rendered by FreeCAD's GUI under xvfb-run
    (examples/demo_pictures.py) with the workbench installed in a throwaway HOME:
    ({"done": [{"png", "planes", "handles"}], "failed": {png: traceback}}, seconds)."""
    import tempfile
    from freecad_deform.batch.gui_run import install, run_script
    path = os.path.join(out, "pictures.json")
    with open(path, "w") as f:
        json.dump(jobs, f)
    t = time.perf_counter()
    with tempfile.TemporaryDirectory() as home:
        install(home)
        done = run_script(os.path.join(REPO, "examples", "demo_pictures.py"), home, 600,
                          DEFORM_PICTURES=path)
    try:
        with open(path + ".done.json") as f:
            report = json.load(f)
    except FileNotFoundError:
        report = {"done": [], "failed": {"*": f"no report; FreeCAD exited {done.returncode}:\n"
                                          f"{done.stdout[-2000:]}{done.stderr[-2000:]}"}}
    for name in (path, path + ".done.json"):
        if os.path.exists(name):
            os.remove(name)
    return report, time.perf_counter() - t


def halves(png):
    """The share of non-white pixels on the left and the right half of a picture below its
    title (read with matplotlib, independent of the Qt that wrote it)."""
    from matplotlib.image import imread
    rgb = imread(png)[60:, :, :3]
    ink = (rgb < 0.95).any(axis=2)
    w = ink.shape[1] // 2
    return float(ink[:, :w].mean()), float(ink[:, w:].mean())


FEATURES = ("Stretch", "Bend", "Twist", "Taper", "DimensionDrive", "AreaConstrain", "DirectPush")


def features_table(demo):
    """The features table: one row per feature, valid when its result is valid, its oracle
    error within tolerance and every check of its section passed; a feature that never
    reached its row is listed as not valid."""
    rows = []
    for name in FEATURES:
        row = next((r for r in demo.features if r["feature"] == name), None)
        if row is None:
            rows.append({"feature": name, "base": "-", "inputs": "-", "outputs": "-",
                         "valid": False, "seconds": 0.0, "oracle": "did not run", "error": None,
                         "tolerance": None})
            continue
        checks = demo.rep.sections[row["section"]]["checks"]
        row = dict(row, valid=row["valid"] and row["error"] <= row["tolerance"]
                   and all(c["status"] != "FAIL" for c in checks))
        rows.append({k: v for k, v in row.items() if k != "section"})
    lines = ["## Features", "", "| feature | base | inputs | outputs | valid | seconds | oracle "
             "| rel. error (tolerance) |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        err = "-" if r["error"] is None else f"{r['error']:.1e} (<= {r['tolerance']:.0e})"
        lines.append(f"| {r['feature']} | {r['base']} | {r['inputs']} | {r['outputs']} | "
                     f"{'yes' if r['valid'] else '**no**'} | {r['seconds']:.2f} | {r['oracle']} "
                     f"| {err} |")
    return rows, "\n".join(lines) + "\n"


def run(out, quick=False):
    """The demo into `out`; quick: one section per feature (Stretch, Bend, Twist, Taper,
    DimensionDrive, AreaConstrain, DirectPush) and the document reopened, no more (no
    batch section)."""
    os.makedirs(out, exist_ok=True)
    t_start = time.perf_counter()
    demo = Demo(out)
    sections = ((demo.one_plane, demo.bend, demo.twist) if quick else
                (demo.one_plane, demo.two_planes, demo.shrink, demo.mesh, demo.cloud,
                 demo.assembly, demo.bend, demo.two_plane_bend, demo.twist, demo.mesh_bend,
                 demo.blade))
    for section in sections + (demo.taper, demo.dimension_drive, demo.area_constrain,
                               demo.direct_push) + (() if quick else (demo.batch,)) + (
                                   demo.reopen, demo.pictures):
        demo.guarded(section)
    if demo.doc.Name in App.listDocuments():
        App.closeDocument(demo.doc.Name)
    rep, timings = demo.rep, demo.timings
    checks = sum(len(s["checks"]) for s in rep.sections)
    total = time.perf_counter() - t_start
    rows, table = features_table(demo)
    header = (f"# Deform demo: every feature\n\n"
              f"FreeCAD {'.'.join(App.Version()[:3])}, OCCT "
              f"{Part.OCC_VERSION}, numpy {np.__version__}. {checks} checks, {rep.failed} failed, "
              f"{rep.warned} warned. Total {total:.1f} s.\n\nFiles: demo.FCStd, "
              + ", ".join(demo.exports) + ", and a before/after PNG per feature.\n\n"
              "Timings (seconds; recompute = median of 3 touch() + doc.recompute()):\n\n"
              + "\n".join(f"- {k}: {v:.4f}" for k, v in timings.items()) + "\n\n" + table)
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write(rep.markdown(header))
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump({"freecad": ".".join(App.Version()[:3]), "occt": Part.OCC_VERSION,
                   "checks": checks, "failed": rep.failed, "warned": rep.warned,
                   "timings_s": timings, "files": demo.exports + ["demo.FCStd"],
                   "features": _plain(rows),
                   "sections": _plain(rep.sections), "total_s": total}, f, indent=2)
    print(table)
    print(f"{rep.failed} of {checks} checks failed, {rep.warned} warned; output in {out}")
    return rep.failed + sum(not r["valid"] for r in rows)


def command(*args):
    """`python3 -m freecad_deform ARGS` in its own process: {"code", "last" (its last
    line), "seconds"}."""
    import subprocess
    python = sys.executable if os.path.basename(sys.executable).startswith("python") \
        else "/usr/bin/python3"   # under freecadcmd, sys.executable is FreeCAD itself
    t = time.perf_counter()
    done = subprocess.run([python, "-m", "freecad_deform", *map(str, args)], cwd=REPO,
                          env=dict(os.environ, PYTHONPATH=REPO), capture_output=True,
                          encoding="utf-8", errors="replace", timeout=900)
    lines = done.stdout.strip().splitlines()
    if done.returncode:
        print(done.stdout[-2000:], done.stderr[-2000:], file=sys.stderr)
    return {"code": done.returncode, "last": lines[-1] if lines else "",
            "seconds": time.perf_counter() - t}


def hole_rims(shape, radius, centres, axis):
    """(largest distance from each expected centre to the nearest circle edge of `radius`
    on a cylinder face within 1 mm, largest angle of those circles' axes to `axis`)."""
    edges = {e.hashCode(): e for f in shape.Faces if f.Surface.TypeId == "Part::GeomCylinder"
             for e in f.Edges}.values()
    circles = [(np.array(tuple(e.Curve.Center)), np.array(tuple(e.Curve.Axis)))
               for e in edges if e.Curve.TypeId == "Part::GeomCircle"
               and abs(e.Curve.Radius - radius) < 1e-9]
    off, tilt = 0.0, 0.0
    for c in centres:
        near = [(np.linalg.norm(p - c), a) for p, a in circles if np.linalg.norm(p - c) < 1.0]
        if not near:
            return np.inf, np.inf
        off = max(off, max(d for d, _ in near))
        tilt = max(tilt, max(float(np.arctan2(np.linalg.norm(np.cross(a, axis)), abs(a @ axis)))
                             for _, a in near))
    return off, tilt


def surface_arrays(face):
    """A face's B-spline surface as the arrays of the quadrature oracle (poles, weights,
    flat knots, degrees, parameter range)."""
    S = face.Surface
    poles = np.array([[tuple(p) for p in row] for row in S.getPoles()])
    u0, u1, v0, v1 = face.ParameterRange
    return (poles, np.array(S.getWeights()), np.repeat(S.getUKnots(), S.getUMultiplicities()),
            np.repeat(S.getVKnots(), S.getVMultiplicities()), S.UDegree, S.VDegree, (u0, u1),
            (v0, v1))


def surface_samples(shape, count, seed=0):
    """`count` points spread uniformly over the shape's surface (a fine tessellation)."""
    vertices, triangles = triangles_of(shape, 0.1)
    rng = np.random.default_rng(seed)
    p0, p1, p2 = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    pick = rng.choice(len(triangles), size=count, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(count))[:, None], rng.random(count)[:, None]
    return (1 - r1) * p0[pick] + r1 * (1 - r2) * p1[pick] + r1 * r2 * p2[pick]


def blade_cloud(span=100.0, step=1.0, per_layer=240):
    """A turbine-blade-like point cloud, as stacked horizontal outlines (a scan's layers):
    a root platform (z = -10 .. -2), an airfoil from z = 0 to `span` every `step` (a NACA
    4-digit-like section, 5 % camber at 40 %, 14 % thick, the chord tapering from 48 to 36 mm,
    pre-twisted from 25 to 50 deg) and a tip shroud (z = span + 2 .. span + 6). Every layer's
    points are centred on x = y = 0. Returns (points (N, 3), layer index of each point)."""
    def airfoil(chord, stagger):
        beta = np.linspace(0.0, np.pi, per_layer // 2)
        x = 0.5 * (1 - np.cos(beta))                         # cosine spacing, 0 .. 1
        t, m, p = 0.14, 0.05, 0.4
        yt = 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3
                      - 0.1036 * x ** 4)                     # closed trailing edge
        yc = np.where(x < p, m / p ** 2 * (2 * p * x - x ** 2),
                      m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x ** 2))
        upper = np.column_stack([x, yc + yt])[::-1]
        lower = np.column_stack([x, yc - yt])[1:-1]
        outline = (np.vstack([upper, lower]) - [0.5, 0.0]) * chord
        c, s = np.cos(np.radians(stagger)), np.sin(np.radians(stagger))
        return outline @ np.array([[c, s], [-s, c]])

    def rectangle(a, b):
        u = np.linspace(0.0, 2 * (a + b), per_layer, endpoint=False)   # along the perimeter
        x = np.select([u < a, u < a + b, u < 2 * a + b], [u, a, 2 * a + b - u], 0.0)
        y = np.select([u < a, u < a + b, u < 2 * a + b], [0.0, u - a, b], 2 * (a + b) - u)
        return np.column_stack([x - a / 2, y - b / 2])

    layers = [(z, rectangle(70, 36)) for z in np.arange(-10.0, -1.0, 2.0)]
    for z in np.arange(0.0, span + step / 2, step):
        f = z / span
        layers.append((z, airfoil(48 - 12 * f, 25 + 25 * f)))
    layers += [(z, rectangle(56, 28)) for z in span + np.arange(2.0, 7.0, 2.0)]
    points, index = [], []
    for k, (z, xy) in enumerate(layers):
        xy = xy - xy.mean(axis=0)
        points.append(np.column_stack([xy, np.full(len(xy), z)]))
        index.append(np.full(len(xy), k))
    return np.vstack(points), np.concatenate(index)


def main(argv):
    quick = "--quick" in argv
    argv = [a for a in argv if a != "--quick"]
    out = os.path.abspath(argv[0] if argv else os.environ.get("DEFORM_DEMO_OUT")
                          or os.path.join(REPO, "demo_out"))
    failed = run(out, quick)
    if failed:
        print(f"demo: {failed} invariant(s) failed", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__" or sys.argv[:1] and os.path.realpath(sys.argv[0]) == os.path.realpath(__file__):
    try:
        main(sys.argv[1:] if __name__ == "__main__" else [])
    except Exception:  # freecadcmd exits 0 on an uncaught exception: fail the job explicitly
        import traceback
        traceback.print_exc()
        sys.exit(2)
