"""Point clouds and meshes (issue 16): Stretch, Bend and Twist on 10^6 points and Stretch and
Twist on 1.2 M triangles, kernels and recomputes, next to the numpy floor and with peak memory.

    /usr/bin/python3 benchmarks/bench_clouds_meshes.py            # median of 5 runs, ~3 minutes
    /usr/bin/python3 benchmarks/bench_clouds_meshes.py --quick    # 1 run, 10^5 points, 77k triangles
    /usr/bin/python3 benchmarks/bench_clouds_meshes.py --only points

Prints tables, asserts nothing about time. Every row runs in its own Python process (the
inputs are built once and handed over as .npy files), so its peak memory is its own: `base
RSS` is the process's resident memory once the input and the document are set up, `peak
RSS` the high-water mark of the timed runs alone (Linux: the mark is reset through
/proc/self/clear_refs before them). The floor is measured in the same process, right after:

  Stretch  numpy V + (s > 0)[:, None] * d * n over the same points
  Bend     numpy P @ R.T + t (the far part's rigid turn) over the same points
  Twist    the same rigid transform (the turn by the whole angle)

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
    ours, n = timer.median(fn)
    peak = memory("VmHWM")
    floor, _ = timer.median(floor_fn(op, points), max(n, 5))
    parts, total = profiled(fn, CALLS) if what == "recompute" else ({}, 0.0)
    print(json.dumps(dict(name=name, runs=n, ours=ours, floor=floor, base_rss=base_rss,
                          peak_rss=peak if clean else None, out=int(size), parts=parts,
                          total=total)))


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
    rows, profiles = [], []
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
            rows.append((name, sizes[kind], r["runs"], seconds(r["ours"]), seconds(r["floor"]),
                         f"{r['ours'] / r['floor']:.1f}", f"{r['base_rss']:.0f}", peak,
                         f"{r['out']:,}"))
            if r["parts"]:
                d = r["parts"]
                profiles.append((name, sizes[kind], seconds(r["total"]),
                                 *(seconds(d[c]) for c, _ in CALLS),
                                 seconds(r["total"] - sum(d.values()))))
            progress(start, f"{name}: {seconds(r['ours'])} s, floor {seconds(r['floor'])} s, "
                            f"peak {peak} MB")
    print_table("Point clouds and meshes: ours vs the numpy floor (seconds, median; RSS in MB)",
                ("case", "input", "runs", "ours", "floor", "ratio", "base RSS", "peak RSS",
                 "output"), rows)
    print_table("Where one profiled recompute spends its time (seconds, cumulative per call)",
                ("case", "input", "total", *(c for c, _ in CALLS), "rest"), profiles)
    print(f"\nTotal {time.perf_counter() - start:.0f} s.")


run_as_script(main, __name__, __file__)
