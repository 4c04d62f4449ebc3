"""The `make demo` job: Stretch features on real models, exported, pictured and checked.

    /usr/bin/python3 examples/demo.py [OUTPUT_DIR]        # default: <repo>/demo_out/
    DEFORM_DEMO_OUT=/tmp/out freecadcmd examples/demo.py   # freecadcmd takes no script options

Builds one document from ../shared/testdata (relative to the repo root):
  Stretch      the machined sample part stretched by 40 mm along +X at x = 150
  TwoPlanes    the region between z = 100 and z = 150 stretched by 30 mm along +Z
  Shrink       the sample part shrunk by 40 mm along +X at x = 150
  MeshStretch  a mesh of the part, stretched like Stretch
  CloudStretch a point cloud sampled on the part, stretched like Stretch
  AS1Stretch   the AS1 assembly (18 solids) stretched by 800 mm along +X at x = 400

Writes demo.FCStd, one STEP per solid result, STL for the meshes, PLY for the clouds,
before/after PNGs and report.md / report.json. Every invariant is measured against an
independent oracle (a section's area from Shape.slice, a common with a box, the normals
of the base's faces, an edge count of the mesh, a nearest-neighbour query). The job exits
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

V = App.Vector
X, Z = np.array([1.0, 0, 0]), np.array([0, 0, 1.0])
REL = 1e-6          # relative tolerance of an exact B-rep volume against its oracle


# ---------------------------------------------------------------------------- oracles

def section_area(shape, origin, normal):
    """Area of the shape's cross-section in the plane: Shape.slice wires made into faces."""
    n = V(*normal).normalize()
    wires = shape.slice(n, n.dot(V(*origin)))
    return Part.makeFace(wires, "Part::FaceMakerBullseye").Area if wires else 0.0


def slab_volume(shape, origin, normal, width):
    """Volume of the part between the plane and the plane `width` beyond it (a box common)."""
    size = 4 * shape.BoundBox.DiagonalLength
    box = Part.makeBox(size, size, width, V(-size / 2, -size / 2, 0))
    box.Placement = App.Placement(V(*origin), App.Rotation(V(0, 0, 1), V(*normal)))
    return shape.common(box).Volume


def lemma1(shape, planes, normal):
    """{face name: "G1"/"C0"} by hand: the normal of each face a plane cuts, at the middle of
    its section edges, against the motion (G1 when perpendicular)."""
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
                p = e.valueAt(0.5 * (e.FirstParameter + e.LastParameter))
                nrm = np.array(tuple(face.normalAt(*face.Surface.parameter(p))))
                kinds.append("G1" if abs(nrm @ normal) < 1e-6 else "C0")
            name = f"Face{i}"
            found[name] = "C0" if "C0" in kinds + [found.get(name)] else "G1"
    return found


def _extent(shape, normal):
    pts = np.array([tuple(v.Point) for v in shape.Vertexes] or [[0, 0, 0]]) @ normal
    bb = shape.BoundBox  # a cylinder face's vertices may all lie on one side: use the box too
    corners = np.array([[x, y, z] for x in (bb.XMin, bb.XMax) for y in (bb.YMin, bb.YMax)
                        for z in (bb.ZMin, bb.ZMax)]) @ normal
    return min(pts.min(), corners.min()), max(pts.max(), corners.max())


def mesh_section_area(mesh, origin, normal):
    """Shoelace area of the mesh's cross-section polylines (Mesh.crossSections)."""
    u = np.cross([0, 0, 1], normal) if abs(normal[2]) < 0.9 else np.cross([1, 0, 0], normal)
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    total = 0.0
    for polyline in mesh.crossSections([(V(*origin), V(*normal))])[0]:
        p = np.array([tuple(q) for q in polyline]) - origin
        x, y = p @ u, p @ w
        total += 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return abs(total)


def mesh_volume(mesh):
    """Volume of a closed mesh in float64: the divergence theorem over its facets."""
    points, facets = mesh.Topology
    p = np.array([tuple(q) for q in points], float)[np.array(facets, int)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def edge_manifold(mesh):
    """Every undirected edge used by exactly two facets, once in each direction."""
    f = np.array(mesh.Topology[1])
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    _, counts = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    _, dcounts = np.unique(directed, axis=0, return_counts=True)
    return bool(np.all(counts == 2) and np.all(dcounts == 1))


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


def refined(vertices, triangles, max_edge, cap=150_000):
    """Triangles bisected at their longest edge until no edge exceeds max_edge (or there are
    `cap` of them), so the painter's algorithm of matplotlib's 3D axes sorts them well.
    Only a picture needs this: the T-junctions it leaves do not matter there."""
    V, T = vertices, triangles
    for _ in range(24):
        p = V[T]
        length = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=2)   # edge k: corner k -> k+1
        k = length.argmax(axis=1)
        long = length.max(axis=1) > max_edge
        if not long.any() or len(T) + long.sum() > cap:
            break
        turn = (k[long, None] + np.arange(3)) % 3
        a, b, c = np.take_along_axis(T[long], turn, axis=1).T
        m = len(V) + np.arange(len(a))
        V = np.concatenate([V, 0.5 * (V[a] + V[b])])
        T = np.concatenate([T[~long], np.stack([a, m, c], 1), np.stack([m, b, c], 1)])
    return V, T


def shaded(vertices, triangles, color):
    """The triangles' corners and RGBA colours lit from one direction (both sides lit)."""
    p = vertices[triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    light = np.array([-0.3, -0.8, 0.5])
    shade = 0.3 + 0.7 * np.abs(n @ (light / np.linalg.norm(light)))
    rgb = np.clip(np.asarray(color)[None, :] * shade[:, None], 0, 1)
    return p, np.column_stack([rgb, np.ones(len(p))])


def plane_quads(planes, lo, hi, pieces=12):
    """Each separating plane as a grid of translucent quads across the box (lo, hi): small
    pieces, so the painter's algorithm puts each one in front of or behind the part."""
    quads = []
    for origin, normal in planes:
        k = int(np.argmax(np.abs(normal)))
        i, j = [a for a in range(3) if a != k]
        a = np.linspace(lo[i], hi[i], pieces + 1)
        b = np.linspace(lo[j], hi[j], pieces + 1)
        for a0, a1 in zip(a, a[1:]):
            for b0, b1 in zip(b, b[1:]):
                quad = np.zeros((4, 3))
                quad[:, i], quad[:, j], quad[:, k] = (a0, a1, a1, a0), (b0, b0, b1, b1), origin[k]
                quads.append(quad)
    return quads


def picture(path, title, panels, planes_before=(), planes_after=(), view=(22, -120)):
    """Before and after side by side, in one common box so both are at the same scale.

    panels: two (label, kind, data) with kind "solid" (vertices, triangles), "mesh" (the same,
    facet edges drawn) or "points" (an (N, 3) array).
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    allpts = np.vstack([d[0] if kind != "points" else d for _, kind, d in panels])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    pad = 0.03 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    fig = plt.figure(figsize=(14, 6.4), dpi=110)
    for k, ((label, kind, data), planes) in enumerate(zip(panels, (planes_before, planes_after))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        quads = plane_quads(planes, lo, hi)
        plane_rgba = np.tile([0.9, 0.15, 0.1, 0.22], (len(quads), 1))
        if kind == "points":
            pick = np.random.default_rng(0).choice(len(data), size=min(len(data), 60000), replace=False)
            q = data[pick]
            ax.scatter(q[:, 0], q[:, 1], q[:, 2], s=0.3, c=q[:, 0], cmap="viridis", depthshade=False)
            if quads:
                ax.add_collection3d(Poly3DCollection(quads, facecolors=plane_rgba, edgecolors="none"))
        else:
            polys, rgba = shaded(*data, color=(0.55, 0.7, 0.92) if k == 0 else (0.98, 0.72, 0.42))
            # facets edged in their own colour (no hairline seams between them), a mesh's
            # in grey; part and planes in one collection, so they are depth-sorted together
            edges = np.tile([0.2, 0.2, 0.2, 0.5], (len(rgba), 1)) if kind == "mesh" else rgba
            ax.add_collection3d(Poly3DCollection(
                list(polys) + quads, facecolors=np.vstack([rgba, plane_rgba]),
                edgecolors=np.vstack([edges, np.tile([0.8, 0.1, 0.0, 0.0], (len(quads), 1))]),
                linewidths=0.2 if kind == "mesh" else 0.3))
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(hi - lo)          # equal scale on the three axes
        ax.view_init(elev=view[0], azim=view[1])
        ax.set_xlabel("X (mm)")
        ax.set_ylabel("Y (mm)")
        ax.set_zlabel("Z (mm)")
        ax.tick_params(labelsize=7)
        ax.set_title(label, fontsize=11)
    fig.suptitle(title, fontsize=13)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.9, wspace=0.0)
    fig.savefig(path)
    plt.close(fig)


def solid_panel(shape, label):
    v, t = triangles_of(shape)
    return label, "solid", refined(v, t, 0.04 * shape.BoundBox.DiagonalLength)


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


def continuity_check(rep, base_shape, obj, planes, normal):
    entries = dict(e.split(": ") for e in obj.Continuity.split("; ")) if obj.Continuity else {}
    rep.check("Continuity report (Lemma 1) = face normals at the section, by hand",
              entries, lemma1(base_shape, planes, normal))
    rep.check("SplitFaces = the faces the plane(s) cut", list(obj.SplitFaces),
              sorted(entries, key=lambda name: int(name[4:])))


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
        self.sample_path = os.path.join(TESTDATA, "face_recognition_sample_part.stp")
        self.as1_path = os.path.join(TESTDATA, "as1_pe_203.stp")
        for path in (self.sample_path, self.as1_path):
            if not os.path.isfile(path):
                sys.exit(f"test model {path} is missing; set DEFORM_TESTDATA")
        self.doc = App.newDocument("DeformDemo")
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
        obj, t = timed(lambda: fd.make_stretch(base, plane, distance, **options))
        obj.Label = label
        self.rep.check("recomputed without error",
                       obj.getStatusString() if "Invalid" in obj.State else "ok", "ok")
        self.timings[f"{label}: make_stretch (create + recompute)"] = t
        self.timings[f"{label}: recompute"] = recompute_time(self.doc, obj)
        return obj

    def export_step(self, obj, name):
        obj.Shape.exportStep(os.path.join(self.out, name))
        self.exports.append(name)

    def picture(self, name, *args):
        picture(os.path.join(self.out, name), *args)

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
        self.export_step(obj, "stretch.step")
        self.picture("stretch.png", "Stretch: +40 mm along +X at x = 150",
                     [solid_panel(shape, "before"), solid_panel(obj.Shape, "after")],
                     [(origin, normal)], [(origin, normal), (origin + distance * normal, normal)])

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
        self.picture("two_planes.png", "TwoPlanes: z = 100 .. 150 stretched by 30 mm along +Z",
                     [solid_panel(shape, "before"), solid_panel(result, "after")],
                     [(o1, normal), (o2, normal)], [(o1, normal), (o2 + distance * normal, normal)])

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
        self.picture("shrink.png", "Shrink: -40 mm along +X at x = 150",
                     [solid_panel(shape, "before"), solid_panel(result, "after")],
                     [(origin, normal), (origin + width * normal, normal)], [(origin, normal)])

    # -- 4. a mesh of the part
    def mesh(self):
        import MeshPart
        rep, shape = self.rep, self.shape
        origin, normal, distance = np.array([150.0, 0, 0]), X, 40.0
        rep.section("MeshStretch", "A mesh of the part (MeshPart.meshFromShape, MaxLength 12 mm) "
                    "stretched by 40 mm along +X at x = 150.")
        mesh_base = self.doc.addObject("Mesh::Feature", "SampleMesh")
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
        rep.check("VolumeChange = the float64 volume change", obj.VolumeChange, change, rel=1e-5,
                  warn=True, note="Mesh.Volume sums in float32")
        rep.check("mesh.isSolid()", mesh.isSolid(), True)
        rep.check("mesh.hasNonManifolds()", mesh.hasNonManifolds(), False)
        rep.check("every edge shared by two facets, opposite directions (numpy edge count)",
                  edge_manifold(mesh), True)
        rep.check("mesh.countComponents()", mesh.countComponents(), before.countComponents())
        rep.check("length along X grows by distance", mesh.BoundBox.XLength,
                  before.BoundBox.XLength + distance, rel=1e-9)
        before.write(os.path.join(self.out, "sample_mesh.stl"))
        mesh.write(os.path.join(self.out, "mesh_stretch.stl"))
        self.exports += ["sample_mesh.stl", "mesh_stretch.stl"]
        panels = []
        for label, m in (("before", before), ("after", mesh)):
            points, facets = m.Topology
            panels.append((label, "mesh", (points_of(points), np.array(facets, int))))
        self.picture("mesh_stretch.png", "MeshStretch: +40 mm along +X at x = 150", panels,
                     [(origin, normal)], [(origin, normal), (origin + distance * normal, normal)])

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
        self.picture("cloud_stretch.png", "CloudStretch: +40 mm along +X at x = 150",
                     [("before", "points", cloud), ("after", "points", out_pts)],
                     [(origin, normal)], [(origin, normal), (origin + distance * normal, normal)])

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
                     [solid_panel(as1, "before"), solid_panel(result, "after")],
                     [(origin, normal)], [(origin, normal), (origin + distance * normal, normal)])

    # -- 7. save, reopen, recompute: the same results
    def reopen(self):
        rep, doc = self.rep, self.doc
        rep.section("Document", "demo.FCStd saved, closed, reopened and recomputed.")
        path = os.path.join(self.out, "demo.FCStd")
        volumes = {o.Name: o.Shape.Volume for o in doc.Objects if o.TypeId == "Part::FeaturePython"}
        names = [o.Name for o in doc.Objects]
        doc.saveAs(path)
        App.closeDocument(doc.Name)
        self.doc = doc = App.openDocument(path)
        for o in doc.Objects:
            if o.Name in volumes:
                o.touch()
        doc.recompute()
        rep.check("objects after reopening", [o.Name for o in doc.Objects], names)
        rep.check("no object in error after recompute",
                  [o.Label for o in doc.Objects if "Invalid" in o.State], [])
        for name, volume in volumes.items():
            rep.check(f"{doc.getObject(name).Label}: volume after reopen + recompute",
                      doc.getObject(name).Shape.Volume, volume, rel=1e-9)


def run(out):
    os.makedirs(out, exist_ok=True)
    t_start = time.perf_counter()
    demo = Demo(out)
    for section in (demo.one_plane, demo.two_planes, demo.shrink, demo.mesh, demo.cloud,
                    demo.assembly, demo.reopen):
        demo.guarded(section)
    if demo.doc.Name in App.listDocuments():
        App.closeDocument(demo.doc.Name)
    rep, timings = demo.rep, demo.timings
    checks = sum(len(s["checks"]) for s in rep.sections)
    total = time.perf_counter() - t_start
    header = (f"# Deform demo: Stretch\n\nFreeCAD {'.'.join(App.Version()[:3])}, OCCT "
              f"{Part.OCC_VERSION}, numpy {np.__version__}. {checks} checks, {rep.failed} failed, "
              f"{rep.warned} warned. Total {total:.1f} s.\n\nFiles: demo.FCStd, "
              + ", ".join(demo.exports) + ", and a before/after PNG per feature.\n\n"
              "Timings (seconds; recompute = median of 3 touch() + doc.recompute()):\n\n"
              + "\n".join(f"- {k}: {v:.4f}" for k, v in timings.items()) + "\n")
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write(rep.markdown(header))
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump({"freecad": ".".join(App.Version()[:3]), "occt": Part.OCC_VERSION,
                   "checks": checks, "failed": rep.failed, "warned": rep.warned,
                   "timings_s": timings, "files": demo.exports + ["demo.FCStd"],
                   "sections": _plain(rep.sections), "total_s": total}, f, indent=2)
    print(f"{rep.failed} of {checks} checks failed, {rep.warned} warned; output in {out}")
    return rep.failed


def surface_samples(shape, count, seed=0):
    """`count` points spread uniformly over the shape's surface (a fine tessellation)."""
    vertices, triangles = triangles_of(shape, 0.1)
    rng = np.random.default_rng(seed)
    p0, p1, p2 = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    pick = rng.choice(len(triangles), size=count, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(count))[:, None], rng.random(count)[:, None]
    return (1 - r1) * p0[pick] + r1 * (1 - r2) * p1[pick] + r1 * r2 * p2[pick]


def main(argv):
    out = os.path.abspath(argv[0] if argv else os.environ.get("DEFORM_DEMO_OUT")
                          or os.path.join(REPO, "demo_out"))
    failed = run(out)
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
