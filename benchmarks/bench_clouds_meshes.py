"""Point clouds and meshes (issue 16): Stretch, Bend and Twist on 10^6 points and Stretch and
Twist on 1.2 M triangles, kernels and recomputes, next to the numpy floor and with peak memory.

    /usr/bin/python3 benchmarks/bench_clouds_meshes.py            # median of 5 runs, ~3 minutes
    /usr/bin/python3 benchmarks/bench_clouds_meshes.py --quick    # 1 run, 10^5 points, 77k triangles
    /usr/bin/python3 benchmarks/bench_clouds_meshes.py --only points

Prints tables, asserts nothing about time. Every row runs in its own Python process (the
inputs are built once and handed over as .npy files), so its peak memory is its own: `base
RSS` is the process's resident memory once the input and the document are set up, `peak
RSS` the high-water mark of the timed runs alone (Linux: the mark is reset through
/proc/self/clear_refs before them), `page faults` the minor faults a timed run took (see
faults()). The floor is measured in the same process, right after:

  Stretch  numpy V + (s > 0)[:, None] * d * n over the same points
  Bend     numpy P @ R.T + t (the far part's rigid turn) over the same points
  Twist    the same rigid transform (the turn by the whole angle); beside it the turn
           floor (every point turned by its own angle) and, for meshes, the passes floor
           (that turn, the test which triangles straddle a plane and a copy of the
           triangles: passes_floor_fn), printed with its own ratio to the floor

The inputs: the sample part (face_recognition_sample_part.stp) tessellated at 1 mm and
subdivided 1-to-4 five times (1.2 M triangles), and 10^6 points sampled uniformly on it.
Stretch: plane x = 150, +40 mm. Bend: plane x = 150, axis through (150, 0, 260) along +y,
-60 deg. Twist: planes x = 100 and 200, 90 deg, the feature's default axis (the section's
centroid), Samples 16 for meshes. A recompute row also splits one profiled run into the
kernel, the two conversions (FreeCAD <-> arrays) and the rest.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from bench_stretch import (Timer, machine_line, options, print_table, profiled,  # noqa: E402
                           progress, recompute, run_as_script, runs_line, seconds, stl_mesh,
                           subdivided, surface_samples, testdata)

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402

V = App.Vector
X, Y = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
SAMPLES = 16
STRETCH = dict(origin=np.array([150.0, 0, 0]), distance=40.0)
BEND = dict(origin=np.array([150.0, 0, 0]), axis=(np.array([150.0, 0, 260]), Y), angle=-60.0)
TWIST = dict(origin=np.array([100.0, 0, 0]), gap=100.0, angle=90.0)
CALLS = (("kernel", ("stretch_points", "sweep_points", "map_points_between", "stretch_mesh",
                     "map_between")),
         ("to arrays", ("points_array", "mesh_arrays")),
         ("from arrays", ("points_from_array", "mesh_from_arrays")))
# (row name, base kind, deformation, kernel alone or recompute)
ROWS = [(f"{kind} {op} {what}", kind, op, what)
        for kind, ops in (("points", ("Stretch", "Bend", "Twist")), ("mesh", ("Stretch", "Twist")))
        for op in ops for what in ("kernel", "recompute")]


# ---------------------------------------------------------------------------- one row

def memory(field):
    """A VmRSS/VmHWM line of /proc/self/status, in MB."""
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith(field)) / 1024


def faults():
    """This process's minor page faults so far: memory the kernel had to map (and zero)
    afresh. glibc gives a freed heap back to the system when its top grows past a
    threshold, so the same call can fault in tens of MB or none from one process to the
    next; the column shows which of the two a row's timing had."""
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def reset_peak():
    """Start a new high-water mark of the resident memory (Linux 4.0 and later)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def turn(axis_point, axis_direction, degrees):
    from freecad_deform.geometry.sweep import motion as mo
    return mo.rotation(axis_point, axis_direction, np.radians(degrees))


def twist_axis(cloud_or_mesh):
    """The twist's axis for the kernel rows: the one the feature finds by default."""
    from freecad_deform.ops import planes as pp
    o = TWIST["origin"]
    if isinstance(cloud_or_mesh, np.ndarray):
        return pp.section_centroid_cloud(cloud_or_mesh, o, X), X
    return pp.section_centroid_mesh(cloud_or_mesh, o, X), X


def kernel_fn(kind, op, data, base):
    """The kernel alone on the arrays, and the floor's transform for it."""
    from freecad_deform.geometry.mesh.stretch import stretch_mesh
    from freecad_deform.geometry.mesh.sweep import map_between, twist_motion
    from freecad_deform.geometry.points import sweep as ps
    from freecad_deform.geometry.points.stretch import stretch_points
    from freecad_deform.geometry.sweep import motion as mo
    from freecad_deform.shapes.convert import mesh_eps
    if op == "Stretch":
        o, d = STRETCH["origin"], STRETCH["distance"]
        if kind == "points":
            return lambda: stretch_points(data, o, X, d)
        v, t = data
        return lambda: stretch_mesh(v, t, o, X, d, eps=mesh_eps(v))
    if op == "Bend":
        motion = mo.ScrewMotion(turn(*BEND["axis"], BEND["angle"]))
        return lambda: ps.sweep_points(data, BEND["origin"], X, motion)
    o, gap = TWIST["origin"], TWIST["gap"]
    of_s = twist_motion(o, X, gap, np.radians(TWIST["angle"]),
                        *twist_axis(base.Mesh if kind == "mesh" else data))
    if kind == "points":
        return lambda: ps.map_points_between(data, o, X, gap, of_s)
    v, t = data
    return lambda: map_between(v, t, o, X, gap, of_s, SAMPLES, mesh_eps(v))


def floor_fn(op, points):
    if op == "Stretch":
        o, d = STRETCH["origin"], STRETCH["distance"]

        def floor():
            s = (points - o) @ X
            return points + (s > 0)[:, None] * d * X
        return floor
    m = turn(*BEND["axis"], BEND["angle"]) if op == "Bend" else turn(
        TWIST["origin"], X, TWIST["angle"])
    return lambda: points @ m[:3, :3].T + m[:3, 3]


def turn_floor_fn(points, axis_point):
    """The twist's second floor: every point turned by its own angle (its fraction of the
    gap, clipped to [0, 1], times Angle) about the axis, Rodrigues in plain numpy, no cut."""
    o, gap, angle = TWIST["origin"], TWIST["gap"], np.radians(TWIST["angle"])
    K = np.array([[0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]]).T     # r @ K = X x r

    def floor():
        phi = np.clip((points - o) @ X / gap, 0.0, 1.0) * angle
        kr = (points - axis_point) @ K
        return points + np.sin(phi)[:, None] * kr + (1 - np.cos(phi))[:, None] * (kr @ K)
    return floor


def passes_floor_fn(points, triangles, axis_point):
    """The mesh Twist's third floor: the passes over the whole mesh any cut-and-turn makes,
    in bare numpy on one core: every vertex turned (the turn floor), the test which
    triangles straddle a plane (their corners' cells between the Samples planes), and a
    copy of the triangles (the result's rows)."""
    turn = turn_floor_fn(points, axis_point)
    o, gap = TWIST["origin"], TWIST["gap"]

    def floor():
        turned = turn()
        cells = np.floor((points - o) @ X * (SAMPLES / gap)).astype(np.int16).take(triangles)
        straddle = np.flatnonzero((cells[:, 0] != cells[:, 1]) | (cells[:, 1] != cells[:, 2]))
        return turned, straddle, triangles.copy()
    return floor


def make_feature(op, base):
    import freecad_deform as fd
    if op == "Stretch":
        return fd.make_stretch(base, (V(*STRETCH["origin"]), V(*X)), STRETCH["distance"])
    if op == "Bend":
        return fd.make_bend(base, (V(*BEND["origin"]), V(*X)), BEND["angle"],
                            tuple(V(*a) for a in BEND["axis"]))
    o = TWIST["origin"]
    return fd.make_twist(base, (V(*o), V(*X)), (V(*(o + TWIST["gap"] * X)), V(*X)),
                         TWIST["angle"], None)


def run_row(name, data_dir, runs, budget):
    """Time one row in this process; print its result as one JSON line."""
    _, kind, op, what = next(r for r in ROWS if r[0] == name)
    if kind == "points":
        data = np.load(os.path.join(data_dir, "cloud.npy"))
        points = data
    else:
        data = (np.load(os.path.join(data_dir, "verts.npy")),
                np.load(os.path.join(data_dir, "tris.npy")))
        points = data[0]
    doc = App.newDocument("Bench")
    doc.UndoMode = 0
    base = None
    if what == "recompute" or kind == "mesh":
        from freecad_deform.shapes.convert import points_from_array
        base = doc.addObject("Points::Feature" if kind == "points" else "Mesh::Feature", "Base")
        if kind == "points":
            base.Points = points_from_array(data)
        else:
            base.Mesh = stl_mesh(*data)
    if what == "recompute":
        obj = make_feature(op, base)
        doc.recompute()
        if "Invalid" in obj.State:
            raise RuntimeError(f"{name}: {obj.getStatusString()}")
        fn = recompute(doc, obj)
        size = obj.Points.CountPoints if kind == "points" else obj.Mesh.CountFacets
    else:
        fn = kernel_fn(kind, op, data, base)
        out = fn()
        size = len(out) if kind == "points" else len(out[1])
    timer = Timer(runs, budget)
    fn()   # warm: caches (the cloud's spacing) as a recompute of the same Base finds them
    base_rss = memory("VmRSS")
    clean = reset_peak()
    before = faults()
    ours, n = timer.median(fn)
    ours_faults = (faults() - before) / n
    peak = memory("VmHWM")
    before = faults()
    floor, m = timer.median(floor_fn(op, points), max(n, 5))
    floor_faults = (faults() - before) / m
    turn_floor = passes_floor = None
    if op == "Twist":
        axis_point = twist_axis(base.Mesh if kind == "mesh" else data)[0]
        turn_floor, _ = timer.median(turn_floor_fn(points, axis_point), max(n, 5))
        if kind == "mesh":
            passes_floor, _ = timer.median(passes_floor_fn(points, data[1], axis_point),
                                           max(n, 5))
    parts, total = profiled(fn, CALLS) if what == "recompute" else ({}, 0.0)
    print(json.dumps(dict(name=name, runs=n, ours=ours, floor=floor, turn_floor=turn_floor,
                          passes_floor=passes_floor,
                          faults=(ours_faults, floor_faults), base_rss=base_rss,
                          peak_rss=peak if clean else None, out=int(size), parts=parts,
                          total=total)))


# ---------------------------------------------------------------------------- Blender, the peer

BLENDER_SCRIPT = """
import bpy, json, statistics, sys, time
side, runs = int(sys.argv[-2]), int(sys.argv[-1])
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
bpy.ops.mesh.primitive_grid_add(x_subdivisions=side, y_subdivisions=side, size=2.0)
obj = bpy.context.active_object
dg = bpy.context.evaluated_depsgraph_get()

def evaluate():
    obj.data.update()            # tag the mesh, off the clock: the update re-evaluates it all
    t = time.perf_counter()
    dg.update()
    evaluated = obj.evaluated_get(dg)
    count = len(evaluated.to_mesh().vertices)
    seconds = time.perf_counter() - t
    evaluated.to_mesh_clear()
    return seconds, count

def median():
    evaluate()
    return statistics.median(evaluate()[0] for _ in range(runs))

out = dict(vertices=len(obj.data.vertices), version=bpy.app.version_string, none=median())
mod = obj.modifiers.new("deform", "SIMPLE_DEFORM")
for method, angle in (("STRETCH", 0.0), ("BEND", -1.0472), ("TWIST", 1.5708)):
    mod.deform_method, mod.deform_axis = method, "X"
    if method == "STRETCH":
        mod.factor = 0.2
    else:
        mod.angle = angle
    out[method] = median()
    if evaluate()[1] != out["vertices"]:
        raise RuntimeError(method + " changed the vertex count")
print("BLENDER_JSON " + json.dumps(out))
"""


def blender_peer(count, runs):
    """Blender's Simple Deform on a grid of about `count` vertices: {"none": s, "STRETCH": s,
    "BEND": s, "TWIST": s, "vertices": n, "version": v}, or a sentence saying why not."""
    import shutil
    exe = shutil.which("blender")
    if exe is None:
        return "blender is not installed on this machine"
    side = int(round(count ** 0.5)) - 1                     # (side + 1)^2 vertices
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
        f.write(BLENDER_SCRIPT)
    try:
        child = subprocess.run([exe, "-b", "--factory-startup", "--python", f.name, "--",
                                str(side), str(runs)], capture_output=True, text=True,
                               timeout=900)
    finally:
        os.unlink(f.name)
    line = next((x for x in child.stdout.splitlines() if x.startswith("BLENDER_JSON ")), None)
    if line is None:
        return f"blender ran but printed no time (exit {child.returncode})"
    return json.loads(line.split(" ", 1)[1])


# ---------------------------------------------------------------------------- the table

def inputs(quick, where):
    """The mesh and the cloud, saved as .npy files in `where`; returns their sizes."""
    import Part
    sample = Part.read(testdata("face_recognition_sample_part.stp")).Solids[0]
    pts, tris = sample.tessellate(1.0)
    verts = np.array([tuple(q) for q in pts], float)
    tris = np.array(tris, dtype=np.int64)
    for _ in range(3 if quick else 5):
        verts, tris = subdivided(verts, tris)
    cloud = surface_samples(verts, tris, 10 ** 5 if quick else 10 ** 6)
    for name, array in (("verts", verts), ("tris", tris), ("cloud", cloud)):
        np.save(os.path.join(where, f"{name}.npy"), array)
    return f"{len(cloud):,} points", f"{len(tris):,} tris"


def target(kind, op, what, r, peer):
    """Issue 16's target for a row: (the target as printed, met or not)."""
    if what == "kernel":
        return "ratio <= 5", r["ours"] <= 5 * r["floor"]
    if kind == "mesh":
        return "< 1 s", r["ours"] < 1.0
    if isinstance(peer, dict):
        limit = 2 * peer[op.upper()]
        return f"2 x Blender {seconds(peer[op.upper()])}", r["ours"] <= limit
    return "< 0.4 s", r["ours"] < 0.4


def blender_rows(peer):
    """The peer's table: the whole evaluation without and with each method, and the
    modifier alone (with minus without)."""
    rows = [("no modifier", f"{peer['vertices']:,} vertices", seconds(peer["none"]), "")]
    for method in ("STRETCH", "BEND", "TWIST"):
        rows.append((f"Simple Deform {method.lower()}", f"{peer['vertices']:,} vertices",
                     seconds(peer[method]), seconds(peer[method] - peer["none"])))
    return rows


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--row" in argv:
        k = argv.index("--row")
        name, data_dir = argv[k + 1], argv[k + 2]
        args, timer = options(argv[:k] + argv[k + 3:], __doc__)
        return run_row(name, data_dir, timer.runs, args.budget)
    only = None
    if "--only" in argv:
        k = argv.index("--only")
        only = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    args, timer = options(argv, __doc__)
    start = time.perf_counter()
    print(machine_line())
    print(runs_line(args, timer.runs) + "; each row in its own process")
    rows, profiles, goals = [], [], []
    peer = blender_peer(10 ** 5 if args.quick else 10 ** 6, timer.runs)
    progress(start, "Blender: " + (peer if isinstance(peer, str) else
                                   ", ".join(f"{k} {v}" for k, v in peer.items())))
    with tempfile.TemporaryDirectory() as where:
        sizes = dict(zip(("points", "mesh"), inputs(args.quick, where)))
        progress(start, f"inputs: {sizes['points']}, {sizes['mesh']}")
        for name, kind, op, what in ROWS:
            if only and only not in name:
                continue
            child = subprocess.run(
                [sys.executable, os.path.realpath(__file__), *argv, "--row", name, where],
                capture_output=True, text=True)
            if child.returncode:
                sys.exit(f"{name} failed:\n{child.stderr}")
            r = json.loads(child.stdout.strip().splitlines()[-1])
            peak = "?" if r["peak_rss"] is None else f"{r['peak_rss']:.0f}"
            turned, passes = r["turn_floor"], r["passes_floor"]
            rows.append((name, sizes[kind], r["runs"], seconds(r["ours"]), seconds(r["floor"]),
                         f"{r['ours'] / r['floor']:.1f}",
                         "" if turned is None else seconds(turned),
                         "" if turned is None else f"{r['ours'] / turned:.1f}",
                         "" if passes is None else seconds(passes),
                         "" if passes is None else f"{passes / r['floor']:.1f}",
                         f"{r['faults'][0]:.0f} / {r['faults'][1]:.0f}",
                         f"{r['base_rss']:.0f}", peak, f"{r['out']:,}"))
            goal, met = target(kind, op, what, r, peer)
            goals.append((name, sizes[kind], seconds(r["ours"]), goal, "yes" if met else "NO"))
            if r["parts"]:
                d = r["parts"]
                profiles.append((name, sizes[kind], seconds(r["total"]),
                                 *(seconds(d[c]) for c, _ in CALLS),
                                 seconds(r["total"] - sum(d.values()))))
            progress(start, f"{name}: {seconds(r['ours'])} s, floor {seconds(r['floor'])} s, "
                            f"peak {peak} MB")
    print_table("Point clouds and meshes: ours vs the numpy floor (seconds, median; RSS in MB)",
                ("case", "input", "runs", "ours", "floor", "ratio", "turn floor", "ratio",
                 "passes floor", "its ratio to the floor",
                 "page faults a run (ours / floor)", "base RSS", "peak RSS", "output"), rows)
    if isinstance(peer, dict):
        print_table(f"Blender {peer['version']} Simple Deform (blender -b, median of "
                    f"{timer.runs}): the whole evaluation (depsgraph update + to_mesh), and "
                    f"the modifier alone (with minus without)",
                    ("case", "input", "whole", "modifier"), blender_rows(peer))
    else:
        print(f"\nBlender peer: {peer}; the point recomputes' target is 0.4 s.")
    print_table("Issue 16's targets", ("case", "input", "ours", "target", "met"), goals)
    print_table("Where one profiled recompute spends its time (seconds, cumulative per call)",
                ("case", "input", "total", *(c for c, _ in CALLS), "rest"), profiles)
    print(f"\nTotal {time.perf_counter() - start:.0f} s.")


run_as_script(main, __name__, __file__)
