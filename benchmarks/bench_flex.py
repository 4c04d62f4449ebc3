"""Flex benchmark (issue 14): Twist of a fan and Taper of a ~1000-face part through the space
map, and the same maps on a million mesh vertices and points, each next to its floor
measured in the same run.

    /usr/bin/python3 benchmarks/bench_flex.py            # median of 5 runs, a few minutes
    /usr/bin/python3 benchmarks/bench_flex.py --quick    # 1 run, small inputs (smoke run)

Prints tables, asserts nothing about time. Timing, inputs and output are bench_stretch's.
The floors:

  B-rep   what any map of the region must pay in OCCT: the split of the solid at both
          planes (solid.generalFuse([two plane faces])) and the sewing of the result's
          faces (Part.makeCompound(faces).sewShape()), timed apart and added
  mesh    a plain numpy rigid transform of the same vertices (P @ R.T + t)
  points  the same transform of the same points

"ours" is a document recompute (touch() + doc.recompute()) of the Twist or Taper object, or
the space map's kernel alone (SpaceMap(points)) where the row says so. Blender's Simple
Deform is timed on the same vertices when a `blender` executable is on PATH.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
# bench_stretch puts FreeCAD's modules and the repository on sys.path and imports FreeCAD first
from bench_stretch import (holed_plate, machine_line, options, print_table, progress,  # noqa: E402
                           recompute, run_as_script, runs_line, seconds, stl_mesh, subdivided,
                           surface_samples, testdata)

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.sweep import motion as mo  # noqa: E402
from freecad_deform.geometry.sweep import space_map  # noqa: E402
from freecad_deform.shapes import brep  # noqa: E402
from freecad_deform.shapes.convert import points_from_array  # noqa: E402
from deform_tests.features.test_flex import fan as fan_solid  # noqa: E402  (the tests' fan)

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])
X = np.array([1.0, 0.0, 0.0])




def occt_floor(solid, origin, normal, gap, result):
    """Seconds of the split at both planes plus the sewing of the result's faces."""
    tools = [brep.plane_face(solid, origin + off * normal, normal) for off in (0.0, gap)]
    t = time.perf_counter()
    solid.generalFuse(tools)
    split = time.perf_counter() - t
    faces = Part.makeCompound([f.copy() for f in result.Faces])
    t = time.perf_counter()
    faces.sewShape()
    return split + time.perf_counter() - t


def brep_row(timer, doc, label, solid, make, origin, normal, gap):
    base = doc.addObject("Part::Feature", "Base")
    base.Shape = solid
    obj = make(base)
    doc.recompute()
    if "Invalid" in obj.State:
        raise RuntimeError(f"{label}: {obj.getStatusString()}")
    ours, n = timer.median(recompute(doc, obj))
    floor, _ = timer.median(lambda: occt_floor(solid, origin, normal, gap, obj.Shape))
    return (label, f"{len(solid.Faces)} faces, MaxDeviation {obj.MaxDeviation:.2g} mm", n,
            ours, floor)


def rigid(points, angle):
    """The floor: one rigid turn of every point about z."""
    turn = mo.rotation(np.zeros(3), Z, angle)
    return points @ turn[:3, :3].T + turn[:3, 3]


def map_rows(timer, doc, kind, points, triangles=None):
    """Twist and Taper of a mesh (or cloud): the map kernel, the recompute, the floor."""
    lo, hi = points[:, 2].min(), points[:, 2].max()
    origin, gap = np.array([0, 0, lo + 0.3 * (hi - lo)]), 0.4 * (hi - lo)
    if kind == "mesh":
        base = doc.addObject("Mesh::Feature", "Mesh")
        base.Mesh = stl_mesh(points, triangles)
        label = f"{len(points)} vertices"
    else:
        base = doc.addObject("Points::Feature", "Points")
        base.Points = points_from_array(points)
        label = f"{len(points)} points"
    plane, plane2 = (V(*origin), V(*Z)), (V(*(origin + gap * Z)), V(*Z))
    rows = []
    floor, _ = timer.median(lambda: rigid(points, 0.3))
    for name, smap, make in (
            ("Twist 20 deg", space_map.twist_map(origin, Z, gap, np.radians(20.0),
                                                  np.zeros(3), Z),
             lambda: fd.make_twist(base, plane, plane2, 20.0, (V(0, 0, 0), V(*Z)))),
            ("Taper 0.6", space_map.taper_map(origin, Z, gap, 0.6, np.zeros(3)),
             lambda: fd.make_taper(base, plane, plane2, 0.6, (V(0, 0, 0), V(*Z))))):
        kernel, n = timer.median(lambda: smap(points))
        rows.append((f"{kind} {name}: map kernel", label, n, kernel, floor))
        if kind == "points" or name.startswith("Taper"):  # a mesh Twist sweeps Samples rings
            obj = make()
            doc.recompute()
            ours, n = timer.median(recompute(doc, obj))
            rows.append((f"{kind} {name}: recompute", label, n, ours, floor))
    return rows


BLENDER_SCRIPT = """
import bpy, bmesh, time, sys
import numpy as np
n = int(sys.argv[-1])
mesh = bpy.data.meshes.new("m")
verts = np.random.default_rng(0).random((n, 3))
mesh.vertices.add(n)
mesh.vertices.foreach_set("co", verts.ravel())
obj = bpy.data.objects.new("o", mesh)
bpy.context.collection.objects.link(obj)
mod = obj.modifiers.new("twist", "SIMPLE_DEFORM")
mod.deform_method = "TWIST"
mod.angle = 0.349
dg = bpy.context.evaluated_depsgraph_get()
t = time.perf_counter()
obj.evaluated_get(dg).to_mesh()
print("BLENDER_SECONDS", time.perf_counter() - t)
"""


def blender_row(count):
    """Blender's Simple Deform twist of `count` vertices, or None without Blender."""
    exe = shutil.which("blender")
    if exe is None:
        return None
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
        f.write(BLENDER_SCRIPT)
    out = subprocess.run([exe, "-b", "--python", f.name, "--", str(count)],
                         capture_output=True, text=True, timeout=600).stdout
    os.unlink(f.name)
    line = next((x for x in out.splitlines() if x.startswith("BLENDER_SECONDS")), None)
    return float(line.split()[1]) if line else None


def main(argv=None):
    args, timer = options(argv, __doc__, budget=60.0)
    start = time.perf_counter()
    print(machine_line())
    print(runs_line(args, timer.runs))
    doc = App.newDocument("BenchFlex")
    doc.UndoMode = 0
    rows = []

    def add(new):
        rows.extend(new)
        progress(start, ", ".join(f"{r[0]}: {seconds(r[3])} s" for r in new))

    # 1. Twist of the fan's middle 40 % by 20 deg
    blades = fan_solid().Solids[0]
    o, gap = np.array([0, 0, 18.0]), 24.0
    add([brep_row(timer, doc, "B-rep fan Twist 20 deg, middle 40 %", blades,
                  lambda b: fd.make_twist(b, (V(*o), V(*Z)), (V(*(o + gap * Z)), V(*Z)), 20.0),
                  o, Z, gap)])

    # 2. Taper of a plate with a grid of holes (about 1000 faces; quick: 8 x 8)
    nx, ny = (8, 8) if args.quick else (31, 32)
    plate = holed_plate(nx, ny)
    o, gap = np.array([150.0, 200.0, 5.0]), 100.0
    add([brep_row(timer, doc, "B-rep plate Taper 0.8, x 150..250", plate,
                  lambda b: fd.make_taper(b, (V(*o), V(*X)), (V(*(o + gap * X)), V(*X)), 0.8),
                  o, X, gap)])

    # 3. meshes and clouds of the sample part, about 10^6 vertices (quick: 10^5)
    sample = Part.read(testdata("face_recognition_sample_part.stp"))
    pts, tris = sample.tessellate(1.0)
    verts = np.array([tuple(q) for q in pts], float)
    tris = np.array(tris, dtype=np.int64)
    want = 10 ** 5 if args.quick else 10 ** 6
    while len(verts) < want:
        verts, tris = subdivided(verts, tris)
    add(map_rows(timer, doc, "mesh", verts, tris))
    add(map_rows(timer, doc, "points", surface_samples(verts, tris, want)))
    App.closeDocument(doc.Name)

    print_table("Flex: ours vs floor (seconds, median)",
                ("case", "input", "runs", "ours", "floor", "ratio"),
                [(c, s, n, seconds(t), seconds(f), f"{t / f:.1f}") for c, s, n, t, f in rows])
    blender = blender_row(want)
    print("\nBlender Simple Deform (twist) on the same number of vertices: "
          + ("blender is not installed on this machine" if blender is None and
             shutil.which("blender") is None else f"{seconds(blender)} s" if blender
             else "blender ran but printed no time"))
    print(f"\nfloor: B-rep = split at both planes + sewing the result's faces; mesh and "
          f"points = numpy P @ R.T + t. Total {time.perf_counter() - start:.0f} s.")


run_as_script(main, __name__, __file__)
