"""Bend and Twist benchmark: B-rep, point-cloud and mesh maps next to the floor measured in the same run.

Run from anywhere (FreeCAD 0.20 on Debian):

    /usr/bin/python3 benchmarks/bench_bend_twist.py            # median of 5 runs, ~2 minutes
    /usr/bin/python3 benchmarks/bench_bend_twist.py --quick    # 1 run, small inputs (CI smoke run)
    DEFORM_BENCH_ARGS=--quick freecadcmd benchmarks/bench_bend_twist.py   # through FreeCAD's
                                                            # own Python, which takes no script options

Prints tables, asserts nothing about time. Timing, inputs and output are bench_stretch's
(imported from it): each row is the median of --runs runs, a row whose --runs runs would
exceed --budget seconds gets 3. The floor is what any split-sweep-join implementation has
to pay, measured on the same input in the same run (for the B-rep rows run by run in turn
with ours, so that a change of load weighs on both):

  Bend    the raw OCCT split of the solid at the plane (solid.generalFuse([plane face])),
          the revolve of the section faces about the axis (face.revolve) and the fuse of
          the pieces (near.fuse(revolved + far turned))
  Twist   the split at both planes, the loft through the 17 profiles (the section at Plane
          turned by i/16 of the angle, Part.makeLoft of each wire, solid) and the same fuse
  points  a plain numpy rigid transform of the same points: P @ R.T + t
  mesh    the same numpy transform of the mesh's vertices

Off the floor's clock: classifying the split pieces, finding the section faces, placing the
profiles and turning the far part (all cheap). "ours" is a document recompute of the Bend or
Twist object (touch() + doc.recompute(): conversions and the output properties VolumeChange,
Continuity, SplitFaces included), or the kernel alone where the row says so. Further tables
split one profiled recompute per row into its main calls. Progress goes to stderr.
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
# bench_stretch puts FreeCAD's modules and the repository on sys.path and imports FreeCAD first
from bench_stretch import (blocks_plane, holed_plate, machine_line, options,  # noqa: E402
                           print_profiles, print_table, progress, recompute, run_as_script, runs_line,
                           seconds, stl_mesh, subdivided, surface_samples, testdata)

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.ops.bend import bend_shape  # noqa: E402
from freecad_deform.ops.twist import twist_shape  # noqa: E402
from freecad_deform.geometry.sweep import motion as mo  # noqa: E402
from freecad_deform.geometry.mesh.sweep import map_between, sweep_mesh, twist_motion  # noqa: E402
from freecad_deform.geometry.points.sweep import map_points_between, sweep_points  # noqa: E402
from freecad_deform.ops.planes import section_centroid  # noqa: E402
from freecad_deform.shapes import brep  # noqa: E402
from freecad_deform.shapes.convert import points_from_array  # noqa: E402

V = App.Vector
X, Y = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
SAMPLES = 16

# Calls a profiled recompute is split into (column, the names the profiler may give them);
# none of them calls another, so the columns add up.
BREP_CALLS = (("split", "generalFuse"), ("sweep", ("revolve", "makeLoft")), ("fuse", "fuse"),
              ("sew", "sewShape"), ("unify", "Part.ShapeUpgrade.UnifySameDomain"),
              ("reshape", ("replaceShape", "removeShape")), ("isValid", "isValid"),
              ("apart", "common"),
              ("continuity", ("joint_report", "_joints", "continuity_report")))
MAP_CALLS = (("kernel", ("sweep_points", "map_points_between", "sweep_mesh", "map_between")),
             ("to arrays", ("points_array", "mesh_arrays")),
             ("from arrays", ("points_from_array", "mesh_from_arrays")))


class Bend:
    """A bend set-up: Plane (origin, normal), Axis (point, direction), Angle in degrees."""

    def __init__(self, origin, axis_point, angle, normal=X, axis_direction=Y):
        self.origin, self.normal = np.asarray(origin, float), np.asarray(normal, float)
        self.axis = (np.asarray(axis_point, float), np.asarray(axis_direction, float))
        self.angle = float(angle)

    def turn(self, fraction=1.0):
        return mo.rotation(*self.axis, np.radians(fraction * self.angle))

    def make(self, base):
        return fd.make_bend(base, (V(*self.origin), V(*self.normal)), self.angle,
                            tuple(V(*a) for a in self.axis))

    def shape(self, solid):
        return bend_shape(solid, self.origin, self.normal, np.radians(self.angle), *self.axis)


class Twist:
    """A twist set-up: Plane, Plane2 at origin + gap * normal, Angle in degrees, Axis."""

    def __init__(self, origin, gap, angle, axis_point, normal=X):
        self.origin, self.normal = np.asarray(origin, float), np.asarray(normal, float)
        self.gap, self.angle = float(gap), float(angle)
        self.axis = (np.asarray(axis_point, float), self.normal)

    def turn(self, fraction=1.0):
        return mo.rotation(*self.axis, np.radians(fraction * self.angle))

    def make(self, base, axis=True):
        return fd.make_twist(base, (V(*self.origin), V(*self.normal)),
                             (V(*(self.origin + self.gap * self.normal)), V(*self.normal)),
                             self.angle, tuple(V(*a) for a in self.axis) if axis else None)

    def shape(self, solid):
        return twist_shape(solid, self.origin, self.normal, self.gap, np.radians(self.angle),
                           *self.axis, SAMPLES)


# ---------------------------------------------------------------------------- inputs

def i_beam(length=200.0, width=60.0, height=80.0, flange=10.0, web=8.0, fillet=4.0):
    """An I-beam along x, its four web-flange edges filleted (the fillets run along x)."""
    beam = Part.makeBox(length, width, flange).fuse(
        [Part.makeBox(length, width, flange, V(0, 0, height - flange)),
         Part.makeBox(length, web, height - 2 * flange, V(0, (width - web) / 2, flange))])
    beam = beam.removeSplitter()
    inner = [e for e in beam.Edges if isinstance(e.Curve, Part.Line)
             and abs(e.Length - length) < 1e-9
             and flange - 1e-9 < e.Vertexes[0].Point.z < height - flange + 1e-9
             and abs(e.Vertexes[0].Point.y - width / 2) < web / 2 + 1e-9]
    return beam.makeFillet(fillet, inner).Solids[0]


def sample_mesh(angular, level):
    """The sample part meshed (MeshPart, LinearDeflection 0.1, AngularDeflection `angular`),
    then subdivided 1-to-4 `level` times: vertices (N, 3), triangles (M, 3)."""
    mesh = MeshPart.meshFromShape(Shape=Part.read(testdata("face_recognition_sample_part.stp")),
                                  LinearDeflection=0.1, AngularDeflection=angular)
    points, facets = mesh.Topology
    verts = np.array([tuple(p) for p in points], float)
    tris = np.array(facets, dtype=np.int64)
    for _ in range(level):
        verts, tris = subdivided(verts, tris)
    return verts, tris


# ---------------------------------------------------------------------------- floors

def _classify(pieces, origin, normal, offsets):
    """Split pieces per zone by the bounding-box centre (off the clock)."""
    zones = [[] for _ in range(len(offsets) + 1)]
    for piece in pieces.Solids:
        s = np.dot(np.array(tuple(piece.BoundBox.Center)) - origin, normal)
        zones[int(np.searchsorted(offsets, s))].append(piece)
    return zones


def _fused(near, middle, moved):
    fused = near[0].fuse(near[1:] + middle + moved)
    assert len(fused.Solids) == 1, "the floor's fuse did not give one solid"
    return fused


def bend_floor(solid, bend):
    """One run of the bend floor: split + revolve + fuse; returns seconds."""
    origin, normal = bend.origin, bend.normal
    tool = brep.plane_face(solid, origin, normal)
    t0 = time.perf_counter()
    pieces, _ = solid.generalFuse([tool])
    t1 = time.perf_counter()
    near, far = _classify(pieces, origin, normal, [0.0])
    cut = brep.faces_on_plane(near, origin, normal)
    t2 = time.perf_counter()
    revolved = [f.revolve(V(*bend.axis[0]), V(*bend.axis[1]), bend.angle) for f in cut]
    t3 = time.perf_counter()
    moved = brep.transformed(far, bend.turn())
    t4 = time.perf_counter()
    _fused(near, revolved, moved)
    return (t1 - t0) + (t3 - t2) + (time.perf_counter() - t4)


def twist_floor(solid, twist):
    """One run of the twist floor: split at both planes + loft + fuse; returns seconds."""
    origin, normal, gap = twist.origin, twist.normal, twist.gap
    tools = [brep.plane_face(solid, origin + off * normal, normal) for off in (0.0, gap)]
    t0 = time.perf_counter()
    pieces, _ = solid.generalFuse(tools)
    t1 = time.perf_counter()
    near, _, far = _classify(pieces, origin, normal, [0.0, gap])
    cut = brep.faces_on_plane(near, origin, normal)
    fracs = np.linspace(0.0, 1.0, SAMPLES + 1)
    profiles = [brep.transformed(cut, twist.turn(f) @ mo.translation(f * gap * normal))
                for f in fracs]
    t2 = time.perf_counter()
    lofts = []
    for k, face in enumerate(cut):
        wires = [[p[k].Wires[i] for p in profiles] for i in range(len(face.Wires))]
        solids = [Part.makeLoft(w, True, False) for w in wires]    # outer wire first
        lofts.append(solids[0].cut(solids[1:]) if len(solids) > 1 else solids[0])
    t3 = time.perf_counter()
    moved = brep.transformed(far, twist.turn())
    t4 = time.perf_counter()
    _fused(near, lofts, moved)
    return (t1 - t0) + (t3 - t2) + (time.perf_counter() - t4)


def np_floor(points, matrix):
    return points @ matrix[:3, :3].T + matrix[:3, 3]


# ---------------------------------------------------------------------------- cases

def brep_rows(timer, doc, name, solid, setup, floor, label, alone=None):
    """The recompute of a Bend/Twist of `solid` (and the kernel alone) next to the floor."""
    base = doc.addObject("Part::Feature", name)
    base.Shape = solid
    obj = setup.make(base)
    if "Invalid" in obj.State:
        raise RuntimeError(f"{label}: {obj.getStatusString()}")
    ours, n, parts, total, low = timer.paired_median(recompute(doc, obj),
                                                     lambda: floor(solid, setup), BREP_CALLS)
    size = f"{len(solid.Faces)} faces"
    rows = [(label, size, n, ours, low)]
    if alone:
        t, m = timer.median(lambda: setup.shape(solid))
        rows.append((f"  {alone}() alone", size, m, t, low))
    return rows, [(label, size, total, parts)]


def map_row(timer, label, size, count, kernel, floor):
    """A kernel next to its numpy floor; `count` points or triangles for the rate columns."""
    t, n = timer.median(kernel)
    low, _ = timer.median(floor, max(n, 5))
    return (label, size, n, t, low, count)


def feature_row(timer, doc, label, size, count, obj, floor):
    if "Invalid" in obj.State:
        raise RuntimeError(f"{label}: {obj.getStatusString()}")
    t, n, parts, total = timer.profiled_median(recompute(doc, obj), MAP_CALLS)
    low, _ = timer.median(floor, max(n, 5))
    return (label, size, n, t, low, count), (label, size, total, parts)


def points_rows(timer, doc, cloud, bend, twist, features):
    size, count = f"{len(cloud):,} points", len(cloud)
    motion = mo.ScrewMotion(bend.turn())
    of_s = twist_motion(twist.origin, twist.normal, twist.gap, np.radians(twist.angle),
                        *twist.axis)
    floor = (lambda: np_floor(cloud, bend.turn()))
    rows = [map_row(timer, "points Bend: sweep_points (ScrewMotion)", size, count,
                    lambda: sweep_points(cloud, bend.origin, bend.normal, motion), floor),
            map_row(timer, "points Twist: map_points_between (twist_motion)", size, count,
                    lambda: map_points_between(cloud, twist.origin, twist.normal, twist.gap,
                                               of_s), floor)]
    parts = []
    if features:
        base = doc.addObject("Points::Feature", "Cloud")
        base.Points = points_from_array(cloud)
        for label, obj in (("points Bend feature (recompute)", bend.make(base)),
                           ("points Twist feature (recompute, default axis)",
                            twist.make(base, axis=False))):
            row, part = feature_row(timer, doc, label, size, count, obj, floor)
            rows.append(row)
            parts.append(part)
            doc.removeObject(obj.Name)
        doc.removeObject(base.Name)
    return rows, parts


def mesh_rows(timer, doc, verts, tris, bend, twist, features):
    size, count = f"{len(tris):,} tris", len(tris)
    motion = mo.ScrewMotion(bend.turn())
    of_s = twist_motion(twist.origin, twist.normal, twist.gap, np.radians(twist.angle),
                        *twist.axis)
    floor = (lambda: np_floor(verts, bend.turn()))
    rows = [map_row(timer, f"mesh Bend: sweep_mesh (ScrewMotion, Samples {SAMPLES})", size,
                    count, lambda: sweep_mesh(verts, tris, bend.origin, bend.normal, motion,
                                              SAMPLES), floor),
            map_row(timer, f"mesh Twist: map_between (twist_motion, Samples {SAMPLES})", size,
                    count, lambda: map_between(verts, tris, twist.origin, twist.normal,
                                               twist.gap, of_s, SAMPLES), floor)]
    parts = []
    if features:
        base = doc.addObject("Mesh::Feature", "Mesh")
        base.Mesh = stl_mesh(verts, tris)
        for label, obj in (("mesh Bend feature (recompute)", bend.make(base)),
                           ("mesh Twist feature (recompute)", twist.make(base))):
            row, part = feature_row(timer, doc, label, size, count, obj, floor)
            rows.append(row)
            parts.append(part)
            doc.removeObject(obj.Name)
        doc.removeObject(base.Name)
    return rows, parts


# ---------------------------------------------------------------------------- output

def rate(count, t):
    per_s = count / t
    return f"{per_s / 1e6:.1f}M/s" if per_s >= 1e6 else f"{per_s / 1e3:.0f}k/s"


def only_rows(argv):
    """(argv without `--only WORDS`, a test `wanted(label)`): with --only, a row runs only
    when its label holds one of the comma-separated words (any case)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if "-h" in argv or "--help" in argv:
        print("  --only WORDS     run only the rows whose label holds one of these "
              "comma-separated words, e.g. --only fc_blocks144,tail ('points' and 'mesh' "
              "pick those tables)")
    words = []
    while "--only" in argv:
        k = argv.index("--only")
        words += [w.lower() for w in argv[k + 1].split(",") if w]
        del argv[k:k + 2]
    return argv, lambda label: not words or any(w in label.lower() for w in words)


def main(argv=None):
    argv, wanted = only_rows(argv)
    args, timer = options(argv, __doc__)
    runs = timer.runs
    grid = (8, 8) if args.quick else (31, 32)
    # (AngularDeflection, subdivision level) of the sample-part meshes: 97,280 and 1,032,192
    # triangles (1,520 and 16,128 when quick); mesh features only on the smaller one
    meshes = ((0.5, 1), (0.12, 2)) if args.quick else ((0.5, 4), (0.12, 5))
    n_points = 10 ** 5 if args.quick else 10 ** 6

    start = time.perf_counter()
    print(machine_line())
    print(runs_line(args, runs))

    doc = App.newDocument("BenchBendTwist")
    doc.UndoMode = 0
    brep, maps, parts = [], [], []

    def add(into, new_rows, new_parts):
        into.extend(new_rows)
        parts.extend(new_parts)
        progress(start, ", ".join(f"{r[0].strip()} ({r[1]}): {seconds(r[3])} s" for r in new_rows))

    def brep_case(name, solid, setup, floor, label, alone=None):
        if wanted(label):
            add(brep, *brep_rows(timer, doc, name, solid, setup, floor, label, alone))

    # 1. Bend, axis in the plane: the gap is the section revolved (exact)
    sample = Part.read(testdata("face_recognition_sample_part.stp")).Solids[0]
    brep_case("Sample", sample, Bend([150.0, 0, 0], [150.0, 0, 260], -60),
              bend_floor, "B-rep sample part: Bend x=150, axis (150,0,260) || y, "
                          "-60 deg", alone="bend_shape")
    nx, ny = grid
    t = time.perf_counter()
    plate = holed_plate(nx, ny)
    built = time.perf_counter() - t
    for where, x in (("through a hole column", 400.0 * (nx // 2 + 0.5) / nx),
                     ("between hole columns", 400.0 * (nx // 2) / nx)):
        brep_case("Plate", plate, Bend([x, 0, 0], [x, 0, -40.0], 60),
                  bend_floor, f"B-rep plate: Bend x={x:.1f} {where}, axis z=-40 || y, "
                              f"+60 deg")

    # 2. Twist by 90 degrees between two planes, Samples 16: a loft through the profiles
    beam = i_beam()
    brep_case("Beam", beam, Twist([60.0, 0, 0], 80.0, 90, [60.0, 30, 40]),
              twist_floor, f"B-rep I-beam: Twist x=60..140, 90 deg, Samples {SAMPLES}",
              alone="twist_shape")
    # the twist needs a constant section between the planes: a 200 mm plain tail on the plate
    tailed = plate.fuse(Part.makeBox(200, 400, 10, V(400, 0, 0))).Solids[0]
    brep_case("TailedPlate", tailed,
              Twist([450.0, 0, 0], 100.0, 90, [450.0, 200, 5]), twist_floor,
              f"B-rep plate + 200 mm tail: Twist x=450..550, 90 deg, "
              f"Samples {SAMPLES}")

    # 3. fc_blocks144.brep (one solid, 996 planar faces), as in the real-parts matrix: Bend at
    # 30 % of the longest axis (z), 30 deg about an axis across the part a quarter of its
    # second extent (y) beyond it; Twist between 30 % and 40 %, 30 deg about the default axis
    blocks = Part.read(testdata("fc_blocks144.brep")).Solids[0]
    bb = blocks.BoundBox
    origin, normal, length = blocks_plane(blocks, 0.3)
    side = Y * (bb.YMax + 0.25 * bb.YLength - origin[1])
    brep_case("Blocks", blocks,
              Bend(origin, origin + side, 30, normal, np.cross(normal, Y)),
              bend_floor, f"B-rep fc_blocks144: Bend z={origin[2]:.2f} (30 %), axis "
                          f"y={origin[1] + side[1]:.1f} || x, 30 deg")
    centroid = section_centroid([blocks], origin, normal)
    brep_case("Blocks", blocks,
              Twist(origin, 0.1 * length, 30, centroid, normal), twist_floor,
              f"B-rep fc_blocks144: Twist z={origin[2]:.2f}..{origin[2] + 0.1 * length:.2f}"
              f" (30..40 %), 30 deg, Samples {SAMPLES}")

    # 4. point clouds sampled on the part's surface
    bend = Bend([150.0, 0, 0], [150.0, 0, 260], -60)
    twist = Twist([100.0, 0, 0], 100.0, 90, [100.0, -52.5, 112.5])
    finest = sample_mesh(*meshes[-1]) if wanted("points") or wanted("mesh") else None
    if wanted("points"):
        cloud = surface_samples(*finest, n_points)
        add(maps, *points_rows(timer, doc, cloud, bend, twist, features=True))

    # 5. meshes of the part
    for k, spec in enumerate(meshes if wanted("mesh") else ()):
        verts, tris = finest if k == len(meshes) - 1 else sample_mesh(*spec)
        add(maps, *mesh_rows(timer, doc, verts, tris, bend, twist, features=k == 0))
    App.closeDocument(doc.Name)

    print_table("Bend and Twist on B-rep solids: ours vs floor (seconds, median)",
                ("case", "input", "runs", "ours", "floor", "ratio"),
                [(c, s, n, seconds(o), seconds(f), f"{o / f:.1f}") for c, s, n, o, f in brep])
    print_table("Point clouds and meshes: ours vs floor (seconds, median; rate = input points "
                "or triangles per second)",
                ("case", "input", "runs", "ours", "floor", "ratio", "ours rate", "floor rate"),
                [(c, s, n, seconds(o), seconds(f), f"{o / f:.1f}", rate(k, o), rate(k, f))
                 for c, s, n, o, f, k in maps])
    print_profiles(parts, (("B-rep", BREP_CALLS), ("points", MAP_CALLS), ("mesh", MAP_CALLS)))
    print(f"\nfloor: Bend = generalFuse at the plane + revolve of the section faces + fuse; "
          f"Twist = generalFuse at both planes + makeLoft through {SAMPLES + 1} profiles + fuse; "
          f"points and mesh = numpy P @ R.T + t. Plate built in {built:.1f} s ({nx} x {ny} "
          f"holes, one cut). Total {time.perf_counter() - start:.0f} s.")


run_as_script(main, __name__, __file__)
