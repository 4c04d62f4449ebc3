"""Stretch benchmark: B-rep, mesh and point-cloud stretch next to the floor measured in the same run.

Run from anywhere (FreeCAD 0.20 on Debian):

    /usr/bin/python3 benchmarks/bench_stretch.py            # median of 5 runs, ~3 minutes
    /usr/bin/python3 benchmarks/bench_stretch.py --quick    # 1 run, small inputs (CI smoke run)
    DEFORM_BENCH_ARGS=--quick freecadcmd benchmarks/bench_stretch.py   # through FreeCAD's own
                                                            # Python, which takes no script options

Prints tables, asserts nothing about time. Each row is the median of --runs runs; a row
whose single run is so slow that --runs of them would exceed --budget seconds gets 3 runs
(the table says how many). The floor is what any implementation has to pay:

  B-rep   the raw OCCT split of the solid at the plane (solid.generalFuse([plane face]))
          plus the fuse of the two pieces back together (near.fuse(far)), run in turn
          with the recompute (one run of each, then the next)
  mesh    a plain numpy product over the same vertices: V + (s > 0)[:, None] * d * n
  points  the same numpy translation over the same points

"ours" is a document recompute of the Stretch object (touch() + doc.recompute(), so it
includes the FreeCAD <-> array conversions and the output properties VolumeChange,
Continuity, SplitFaces), or the kernel alone where the row says so. Further tables split
one profiled recompute per row into its main calls. Progress goes to stderr.
"""
import argparse
import cProfile
import os
import platform
import statistics
import sys
import tempfile
import time

for _path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(_path) and _path not in sys.path:
        sys.path.append(_path)
REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
if REPO not in sys.path:
    sys.path.insert(0, REPO)
TESTDATA = os.environ.get("DEFORM_TESTDATA", os.path.join(os.path.dirname(REPO), "shared", "testdata"))

import FreeCAD as App  # noqa: E402  (FreeCAD before Part, or Part segfaults)
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
import pstats  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.ops.stretch import stretch_shape  # noqa: E402
from freecad_deform.geometry.mesh.stretch import stretch_mesh  # noqa: E402
from freecad_deform.geometry.points.stretch import stretch_points  # noqa: E402
from freecad_deform.shapes import brep  # noqa: E402
from freecad_deform.shapes.convert import points_from_array  # noqa: E402

V = App.Vector
X = np.array([1.0, 0.0, 0.0])

# Calls a profiled recompute is split into: (column, the names the profiler may give it).
BREP_CALLS = (("base copy", "oriented"), ("split", "generalFuse"), ("fuse", "fuse"),
              ("sew", "sewShape"),
              ("unify", "Part.ShapeUpgrade.UnifySameDomain"),
              ("reshape", ("replaceShape", "removeShape")), ("isValid", "isValid"),
              ("continuity", ("joint_report", "_joints")), ("volume", "solids_volume"))
MESH_CALLS = (("kernel", "stretch_mesh"), ("to arrays", "mesh_arrays"),
              ("from arrays", "mesh_from_arrays"))
POINT_CALLS = (("kernel", "stretch_points"), ("to arrays", "points_array"),
               ("from arrays", "points_from_array"))


# ---------------------------------------------------------------------------- timing

class Timer:
    def __init__(self, runs, budget):
        self.runs, self.budget = runs, budget

    def count(self, first):
        """How many runs a row gets, given how long its first run took."""
        if self.runs <= 1 or first * self.runs <= self.budget:
            return self.runs
        return min(self.runs, max(3, int(self.budget / first)))

    def median(self, fn, count=None):
        """(median seconds, runs) of fn(); fn may return its own time (for split timings)."""
        times = [_timed(fn)]
        n = count or self.count(times[0])
        times += [_timed(fn) for _ in range(n - 1)]
        return statistics.median(times), n

    def profiled_median(self, fn, calls):
        """(median seconds, runs, {column: seconds}, profiled seconds) of fn().

        The runs are timed without the profiler; the split into `calls` comes from one
        extra profiled run, not timed (cProfile costs about a microsecond a Python call:
        a B-rep Twist of fc_blocks144 makes half a million and took 1.58 s plain, 2.06 s
        profiled, medians of 5 in turn).
        """
        times = [_timed(fn)]
        n = self.count(times[0])
        times += [_timed(fn) for _ in range(n - 1)]
        return (statistics.median(times), n, *profiled(fn, calls))

    def paired_median(self, fn, floor, calls):
        """As profiled_median, and the floor's median over as many runs of `floor()` (which
        returns its own seconds), run by run in turn with fn(): on a shared machine a
        change of load then weighs on both medians alike."""
        times, floors = [_timed(fn)], []
        n = self.count(times[0])
        floors.append(_timed(floor))
        for _ in range(n - 1):
            times.append(_timed(fn))
            floors.append(_timed(floor))
        return (statistics.median(times), n, *profiled(fn, calls),
                statistics.median(floors))


def _timed(fn):
    t = time.perf_counter()
    own = fn()
    return own if isinstance(own, float) else time.perf_counter() - t


def profiled(fn, calls):
    """Seconds spent in each of `calls` during one profiled fn(), and the total."""
    prof = cProfile.Profile()
    t = time.perf_counter()
    prof.enable()
    fn()
    prof.disable()
    total = time.perf_counter() - t
    stats = pstats.Stats(prof).stats
    parts = {}
    for column, names in calls:  # a Python function by its name, a C method as <method 'name' ...>
        names = (names,) if isinstance(names, str) else names
        parts[column] = sum(ct for (_, _, func), (_, _, _, ct, _) in stats.items()
                            if any(func == name or f"'{name}'" in func for name in names))
    return parts, total


# ---------------------------------------------------------------------------- inputs

def testdata(name):
    path = os.path.join(TESTDATA, name)
    if not os.path.isfile(path):
        sys.exit(f"test model {path} is missing; set DEFORM_TESTDATA")
    return path


def holed_plate(nx, ny, size=400.0, thick=10.0, radius=4.0):
    """A size x size x thick plate with an nx x ny grid of round through holes (one cut)."""
    plate = Part.makeBox(size, size, thick)
    holes = [Part.makeCylinder(radius, thick, V(size * (i + 0.5) / nx, size * (j + 0.5) / ny, 0))
             for i in range(nx) for j in range(ny)]
    return plate.cut(Part.makeCompound(holes)).Solids[0]


def blocks_plane(solid, frac):
    """(origin, normal, length): the plane across the longest bounding-box axis at `frac`
    of it, through the box's centre otherwise (as the real-parts matrix places it)."""
    bb = solid.BoundBox
    lo, hi = np.array([bb.XMin, bb.YMin, bb.ZMin]), np.array([bb.XMax, bb.YMax, bb.ZMax])
    k = int(np.argmax(hi - lo))
    origin = (lo + hi) / 2
    origin[k] = lo[k] + frac * (hi[k] - lo[k])
    return origin, np.eye(3)[k], hi[k] - lo[k]


def subdivided(vertices, triangles):
    """Each triangle split in four at its edge midpoints (shared edges share the midpoint)."""
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    unique, inverse = np.unique(np.sort(edges, axis=1), axis=0, return_inverse=True)
    ab, bc, ca = (len(vertices) + inverse.reshape(3, -1))
    a, b, c = triangles.T
    return (np.concatenate([vertices, 0.5 * (vertices[unique[:, 0]] + vertices[unique[:, 1]])]),
            np.concatenate([np.stack(t, 1) for t in
                            ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]))


def stl_mesh(vertices, triangles):
    """A Mesh.Mesh read from a binary STL written with numpy: 4x faster than a list of
    App.Vector for a million facets, at float32 precision (fine for a benchmark input)."""
    rec = np.zeros(len(triangles), dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)),
                                          ("attribute", "<u2")])
    rec["corners"] = vertices[triangles]
    handle, path = tempfile.mkstemp(suffix=".stl")
    try:
        with os.fdopen(handle, "wb") as f:
            f.write(b"\0" * 80 + np.uint32(len(triangles)).tobytes() + rec.tobytes())
        return Mesh.Mesh(path)
    finally:
        os.unlink(path)


def surface_samples(vertices, triangles, count, seed=0):
    """`count` points uniformly distributed over the triangle mesh's surface."""
    rng = np.random.default_rng(seed)
    p0, p1, p2 = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    pick = rng.choice(len(triangles), size=count, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(count))[:, None], rng.random(count)[:, None]
    return (1 - r1) * p0[pick] + r1 * (1 - r2) * p1[pick] + r1 * r2 * p2[pick]


# ---------------------------------------------------------------------------- cases

def stretch_object(base, origin, distance, normal=X):
    """A Stretch of `base` at the plane (origin, normal) by `distance`, created at Distance 0
    (a cheap first recompute) so the timed runs are the only full ones."""
    obj = fd.make_stretch(base, (V(*origin), V(*normal)), 0)
    obj.Distance = distance
    return obj


def recompute(doc, obj):
    def run():
        obj.touch()
        doc.recompute()
        if "Invalid" in obj.State:
            raise RuntimeError(f"{obj.Label} failed: {obj.getStatusString()}")
    return run


def occt_floor(solid, origin, normal):
    """One run of the floor: generalFuse at the plane, then near.fuse(far); returns seconds."""
    tool = brep.plane_face(solid, origin, normal)
    t0 = time.perf_counter()
    pieces, _ = solid.generalFuse([tool])
    t1 = time.perf_counter()
    near, far = [], []
    for piece in pieces.Solids:  # classified off the clock, by bounding-box centre
        (far if np.dot(np.array(tuple(piece.BoundBox.Center)) - origin, normal) > 0 else near).append(piece)
    t2 = time.perf_counter()
    fused = near[0].fuse(near[1:] + far)
    t3 = time.perf_counter()
    assert len(fused.Solids) == 1
    return (t1 - t0) + (t3 - t2)


def brep_rows(timer, doc, name, solid, origin, distance, label, normal=X):
    base = doc.addObject("Part::Feature", name)
    base.Shape = solid
    obj = stretch_object(base, origin, distance, normal)
    ours, n, parts, total, floor = timer.paired_median(
        recompute(doc, obj), lambda: occt_floor(solid, origin, normal), BREP_CALLS)
    size = f"{len(solid.Faces)} faces"
    return ([(label, size, n, ours, floor)],
            [(label, size, total, parts)],
            obj)


def mesh_rows(timer, doc, vertices, triangles, origin, distance):
    size = f"{len(triangles):,} tris"
    base = doc.addObject("Mesh::Feature", "Mesh")
    base.Mesh = stl_mesh(vertices, triangles)
    obj = stretch_object(base, origin, distance)
    kernel, n = timer.median(lambda: stretch_mesh(vertices, triangles, origin, X, distance))
    floor, _ = timer.median(lambda: np_floor(vertices, origin, X, distance), max(n, 5))
    feature, m, parts, total = timer.profiled_median(recompute(doc, obj), MESH_CALLS)
    doc.removeObject(obj.Name)
    doc.removeObject(base.Name)
    return ([("mesh kernel (stretch_mesh)", size, n, kernel, floor),
             ("mesh feature (recompute)", size, m, feature, floor)],
            [("mesh feature (recompute)", size, total, parts)])


def points_rows(timer, doc, cloud, origin, distance):
    size = f"{len(cloud):,} points"
    kernel, n = timer.median(lambda: stretch_points(cloud, origin, X, distance))
    floor, _ = timer.median(lambda: np_floor(cloud, origin, X, distance), max(n, 5))
    base = doc.addObject("Points::Feature", "Cloud")
    base.Points = points_from_array(cloud)
    obj = stretch_object(base, origin, distance)
    feature, m, parts, total = timer.profiled_median(recompute(doc, obj), POINT_CALLS)
    return ([("points kernel (stretch_points)", size, n, kernel, floor),
             ("points feature (recompute)", size, m, feature, floor)],
            [("points feature (recompute)", size, total, parts)])


def np_floor(points, origin, normal, distance):
    s = (points - origin) @ normal
    return points + (s > 0)[:, None] * distance * normal


# ---------------------------------------------------------------------------- output

def machine_line():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    import scipy
    return (f"machine: {os.cpu_count()} CPUs ({cpu}), Python {platform.python_version()}, "
            f"FreeCAD {'.'.join(App.Version()[:3])}, OCCT {Part.OCC_VERSION}, "
            f"numpy {np.__version__}, scipy {scipy.__version__}")


def progress(start, what):
    print(f"[{time.perf_counter() - start:5.0f} s] {what}", file=sys.stderr, flush=True)


def print_table(title, header, rows):
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    print(f"\n{title}")
    for k, row in enumerate([header] + rows):
        cells = [str(c).ljust(w) if i < 2 else str(c).rjust(w)
                 for i, (c, w) in enumerate(zip(row, widths))]
        print("  ".join(cells).rstrip())
        if k == 0:
            print("  ".join("-" * w for w in widths))
    sys.stdout.flush()


def seconds(t):
    return f"{t:.4f}" if t < 0.1 else f"{t:.3f}" if t < 10 else f"{t:.2f}"


def print_profiles(parts, kinds):
    """One table per kind: where a profiled recompute spends its time, per main call."""
    for kind, calls in kinds:
        mine = [row for row in parts if row[0].startswith(kind)]
        columns = [c for c, _ in calls]
        print_table(f"{kind}: where one profiled recompute spends its time (seconds, "
                    f"cumulative per call, profiler overhead included)",
                    ("case", "input", "total", *columns, "rest"),
                    [(c, s, seconds(t), *(seconds(d[k]) for k in columns),
                      seconds(t - sum(d.values()))) for c, s, t, d in mine])


def run_as_script(main, name, path):
    """Run `main` when the file is the script: from python3 with its arguments, or from
    freecadcmd (which runs it under its own name and takes no script options: they come in
    DEFORM_BENCH_ARGS, e.g. DEFORM_BENCH_ARGS=--quick freecadcmd bench_stretch.py)."""
    if not (name == "__main__" or sys.argv[:1] and
            os.path.realpath(sys.argv[0]) == os.path.realpath(path)):
        return
    try:
        main(sys.argv[1:] if name == "__main__" else os.environ.get("DEFORM_BENCH_ARGS", "").split())
    except Exception:  # freecadcmd exits 0 on an uncaught exception: fail the job explicitly
        import traceback
        traceback.print_exc()
        sys.exit(2)


def options(argv, doc, budget=15.0):
    """(args, Timer) from the options every benchmark takes: --runs, --budget, --quick."""
    parser = argparse.ArgumentParser(description=doc.split("\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="runs per row; the median is shown")
    parser.add_argument("--budget", type=float, default=budget,
                        help=f"seconds a row may take before it gets only 3 runs "
                             f"(default {budget:g})")
    parser.add_argument("--quick", action="store_true", help="1 run, small inputs (CI smoke run)")
    args = parser.parse_args(argv)
    return args, Timer(1 if args.quick else max(1, args.runs), args.budget)


def runs_line(args, runs):
    """What the timing columns are: the median of how many runs, at which sizes."""
    return (f"runs: median of {runs}" + ("" if runs == 1 else
            f" (3 for a row whose {runs} runs would take over {args.budget:g} s)")
            + (", quick sizes" if args.quick else ""))


def main(argv=None):
    args, timer = options(argv, __doc__)
    runs = timer.runs
    grid = (8, 8) if args.quick else (31, 32)
    levels = (0, 2) if args.quick else (2, 4, 5)
    n_points = 10 ** 5 if args.quick else 10 ** 6

    start = time.perf_counter()
    print(machine_line())
    print(runs_line(args, runs))

    doc = App.newDocument("BenchStretch")
    doc.UndoMode = 0
    rows, parts = [], []

    def add(new_rows, new_parts):
        rows.extend(new_rows)
        parts.extend(new_parts)
        progress(start, ", ".join(f"{r[0].strip()} ({r[1]}): {seconds(r[3])} s" for r in new_rows))

    # 1. the machined sample part, 23 faces
    sample = Part.read(testdata("face_recognition_sample_part.stp"))
    solid = sample.Solids[0]
    r, p, _ = brep_rows(timer, doc, "Sample", solid, np.array([150.0, 0, 0]), 40.0,
                        "B-rep sample part, x=150, +40 mm")
    t, n = timer.median(lambda: stretch_shape(solid, np.array([150.0, 0, 0]), X, 40.0))
    add(r + [("  stretch_shape() alone", f"{len(solid.Faces)} faces", n, t, r[-1][4])], p)

    # 2. a plate with a grid of holes, about 1000 faces
    nx, ny = grid
    t = time.perf_counter()
    plate = holed_plate(nx, ny)
    built = time.perf_counter() - t
    for where, x in (("through a hole column", 400.0 * (nx // 2 + 0.5) / nx),
                     ("between hole columns", 400.0 * (nx // 2) / nx)):
        r, p, _ = brep_rows(timer, doc, "Plate", plate, np.array([x, 0, 0]), 40.0,
                            f"B-rep plate, x={x:.1f} {where}, +40 mm")
        add(r, p)

    # 3. fc_blocks144.brep: one solid of 996 planar faces; the plane across its longest
    # axis (z) at the middle, stretched by a tenth of that length (the real-parts case)
    blocks = Part.read(testdata("fc_blocks144.brep")).Solids[0]
    origin, normal, length = blocks_plane(blocks, 0.5)
    r, p, _ = brep_rows(timer, doc, "Blocks", blocks, origin, 0.1 * length,
                        f"B-rep fc_blocks144, z={origin[2]:.2f} (middle), "
                        f"+{0.1 * length:.2f} mm", normal)
    add(r, p)

    # 4. meshes of the sample part, subdivided
    pts, tris = sample.tessellate(1.0)
    verts = np.array([tuple(q) for q in pts], float)
    tris = np.array(tris, dtype=np.int64)
    mesh_origin = np.array([150.0, 0, 0])
    for level in range(max(levels) + 1):
        if level:
            verts, tris = subdivided(verts, tris)
        if level in levels:
            add(*mesh_rows(timer, doc, verts, tris, mesh_origin, 40.0))

    # 5. a point cloud sampled on the part's surface
    cloud = surface_samples(verts, tris, n_points)
    add(*points_rows(timer, doc, cloud, mesh_origin, 40.0))
    App.closeDocument(doc.Name)

    print_table("Stretch: ours vs floor (seconds, median)",
                ("case", "input", "runs", "ours", "floor", "ratio"),
                [(c, s, n, seconds(o), seconds(f), f"{o / f:.1f}") for c, s, n, o, f in rows])
    print_profiles(parts, (("B-rep", BREP_CALLS), ("mesh", MESH_CALLS), ("points", POINT_CALLS)))
    print(f"\nfloor: B-rep = solid.generalFuse([plane face]) + near.fuse(far); mesh and points = "
          f"numpy V + (s > 0)[:, None] * d * n. Plate built in {built:.1f} s "
          f"({nx} x {ny} holes, one cut). Total {time.perf_counter() - start:.0f} s.")


run_as_script(main, __name__, __file__)
