"""DimensionDrive benchmark on the paper's model, fandisk.obj (Date & Onosato, Figs. 3-4).

Run from anywhere (FreeCAD 0.20 on Debian):

    /usr/bin/python3 benchmarks/bench_dimension_drive.py            # median of 5 runs
    /usr/bin/python3 benchmarks/bench_dimension_drive.py --quick    # 1 run, no 1M row

Prints tables, asserts nothing about time.

1. Handle generation on fandisk (12,946 triangles; paper: 2.1 s on a Pentium 4 3.8 GHz):
   segmentation, region fits (and merging regions that lie on a neighbour's surface),
   simplification, prisms and Warren coordinates, in wall and in CPU time (the median of
   each over the same runs); the op (ops.dimension_drive: handle and drive, FreeCAD
   conversions included) and a document recompute for a new Target, with their CPU time.
2. Handle generation on the STL models of testdata (sh2, TR12J, counter), a 400 x 400 x 10
   plate with a 12 x 12 grid of round holes tessellated by OCCT (0.05 mm) and a bumpy
   sphere of 81,920 triangles (deform_tests' large-mesh test: collapsed whole, in batches
   first, like a scan): the meshes the outline simplification must not make slower than
   collapsing them whole (issue 16); CPU time, and the simplification's route.
3. Update for 300,000 and 1,000,000 vertices (paper: under 30 ms for 300,000 vertices
   and 10 handle vertices): fandisk subdivided four times (1.66M vertices, every child
   triangle in its parent's region, the same simplified mesh), bound to the handle; the
   first N vertices' rows of the coordinate matrix are the update of N vertices.
   "eq. 2.3" is x + B (P' - P) for new handle positions P'; "drive" is a whole new target
   (constraint vectors, the product, the flip range). The floor is a plain scipy CSR
   product of the same shape and non-zeros with random values, measured in the same run.
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from bench_stretch import (holed_plate, machine_line, options, print_table,  # noqa: E402
                           run_as_script, seconds, subdivided, testdata)

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
from scipy.sparse import csr_matrix  # noqa: E402

import freecad_deform as fd  # noqa: E402
from deform_tests.geometry.test_dimension_drive_large import icosphere  # noqa: E402
from freecad_deform.geometry.mesh import dimension_drive as dd  # noqa: E402
from freecad_deform.geometry.mesh import simplify as simplification  # noqa: E402
from freecad_deform.geometry.mesh.dimension_handle import build_handle  # noqa: E402
from freecad_deform.ops import dimension_drive as op  # noqa: E402
from freecad_deform.shapes.convert import mesh_arrays  # noqa: E402

PLANES = ((3.6315, 15.1064, -1.4288), (3.6393, 14.2951, -1.2787))  # the two parallel
# planar faces that end the cylindrical grooves (0.825 apart)


def fandisk():
    mesh = Mesh.Mesh(testdata("fandisk.obj"))
    return mesh, *mesh_arrays(mesh)


def handle_rows(timer, V, T):
    """Handle generation (DimensionModel), split at its progress steps: the medians of the
    wall times, and of the CPU times (time.process_time, this process) of the same runs,
    which a loaded machine stretches less."""
    steps = {"wall": [], "cpu": []}

    def run():
        marks = [(time.perf_counter(), time.process_time())]
        model = op.handle(V, T, progress=lambda: marks.append((time.perf_counter(),
                                                                time.process_time())))
        wall, cpu = np.diff(np.array(marks), axis=0).T
        steps["wall"].append(np.r_[wall.sum(), wall])
        steps["cpu"].append(np.r_[cpu.sum(), cpu])
        steps.update(simplified=len(model.simplified.triangles), regions=model.count,
                     points=len(model.handle.points), outside=model.handle.outside)
        return wall.sum()

    _, n = timer.median(run)
    notes = (f"{steps['regions']} regions, {steps['simplified']} t simplified, "
             f"{steps['points']} handle pts, {steps['outside']} out")
    rows = []
    for label, key in (("handle (kernel)", "wall"), ("handle (kernel), CPU", "cpu")):
        total, segment, fits, simplify, bind = np.median(steps[key], axis=0)
        rows.append((label, f"{len(V)} v / {len(T)} t", n, seconds(total), seconds(segment),
                     seconds(fits), seconds(simplify), seconds(bind), notes))
    return rows


def other_meshes(quick):
    """(name, vertices, triangles) of the STL models and the tessellated holed plate."""
    files = (("occt_sh2.stl",) if quick else
             ("occt_sh2.stl", "occt_TR12J_OCC.stl", "trimesh_counter.unitsmm.STL"))
    for name in files:
        yield (name, *mesh_arrays(Mesh.Mesh(testdata(name))))
    if not quick:
        points, tris = holed_plate(12, 12).tessellate(0.05)
        yield ("plate, 12 x 12 holes", np.array([tuple(p) for p in points]),
               np.array(tris, np.int64))
        V, T = icosphere(6)
        x, y, z = V.T
        yield ("bumpy sphere", 50 * V * (1 + 0.1 * np.sin(3 * x) * np.sin(4 * y)
                                         * np.cos(2 * z))[:, None], T)


def route(V, T, model):
    """How the simplification went: the outline route, or the whole mesh collapsed."""
    tol = dd.HANDLE_TOLERANCE * model.size
    try:
        simplification._Outlines(V, T, model.labels, tol).run()
        return "outlines"
    except simplification._Unfit:
        return "collapsed whole"


def other_rows(timer, quick):
    rows = []
    for name, V, T in other_meshes(quick):
        cpu, simplify, out = [], [], {}

        def run():
            marks = [time.process_time()]
            out["model"] = op.handle(V, T, progress=lambda: marks.append(time.process_time()))
            cpu.append(marks[-1] - marks[0])
            simplify.append(marks[3] - marks[2])
        timer.median(run)
        model = out["model"]
        rows.append((name, f"{len(V)} v / {len(T)} t", len(cpu),
                     seconds(float(np.median(cpu))), seconds(float(np.median(simplify))),
                     f"{model.count} regions, {len(model.simplified.triangles)} t simplified, "
                     f"{route(V, T, model)}"))
    return rows


def recompute_rows(timer, mesh):
    doc = App.newDocument("BenchDimensionDrive")
    try:
        base = doc.addObject("Mesh::Feature", "Fandisk")
        base.Mesh = mesh
        obj = fd.make_dimension_drive(base, "Distance", list(PLANES), 1.0)
        if "Invalid" in obj.State:
            raise RuntimeError(obj.getStatusString())

        outputs = {}

        def cold():   # the feature's pipeline with a handle built anew
            V, T = mesh_arrays(mesh)
            outputs.update(op.mesh(op.handle(V, T), mesh, "Distance", list(PLANES), 0.9)[1])

        def warm():
            obj.Target = 0.9 + 0.1 * np.random.rand()
            doc.recompute()
            outputs.update(Current=obj.Current, Achieved=obj.Achieved)

        rows = []
        for label, fn in (("op, new handle", cold), ("recompute, new Target", warm)):
            cpu = []

            def timed():
                start = time.process_time()
                fn()
                cpu.append(time.process_time() - start)
            t, n = timer.median(timed)
            rows.append((label, f"{mesh.CountPoints} v", n, seconds(t), "", "", "", "",
                         f"CPU {seconds(float(np.median(cpu)))}; Current "
                         f"{outputs['Current']:.4f} -> Achieved {outputs['Achieved']:.4f}"))
        return rows
    finally:
        App.closeDocument(doc.Name)


def update_rows(timer, V, T, counts):
    """The update of N vertices bound to fandisk's handle, next to a plain CSR product."""
    model = op.handle(V, T)
    big_V, big_T, labels = V, T, model.labels
    while len(big_V) < max(counts):
        big_V, big_T = subdivided(big_V, big_T)
        labels = np.tile(labels, 4)
    t = time.perf_counter()
    handle = build_handle(big_V, big_T, labels, model.planar, model.simplified)
    bind = time.perf_counter() - t
    drive = dd.drive(model, "Distance", list(PLANES), 1.0)
    moves = np.zeros_like(handle.points)
    moves[np.isin(handle.owner, model.control([model.region_at(PLANES[0])]))] = [0, 0.01, 0]
    rng = np.random.default_rng(0)
    rows = []
    for n in counts:
        B = handle.weights[:n]
        x = big_V[:n]
        floor_matrix = csr_matrix((rng.random(B.nnz), B.indices, B.indptr), shape=B.shape)
        floor, nf = timer.median(lambda: floor_matrix @ moves)
        ours, no = timer.median(lambda: x + B @ moves)
        rows.append(("eq. 2.3 update", f"{n} v, {B.shape[1]} handle pts, {B.nnz} nnz", no,
                     seconds(ours), seconds(floor), f"{ours / floor:.2f}x", nf))
    rows.append(("bind (1 time)", f"{len(big_V)} v", 1, seconds(bind), "", "", ""))
    t, n = timer.median(lambda: dd.drive(model, "Distance", list(PLANES), 1.0))
    rows.append(("drive (new target)", f"{len(V)} v", n, seconds(t), "", "",
                 f"reach {drive.reach[0]:.3f}..{drive.reach[1]:.3f}"))
    return rows


def main(argv):
    args, timer = options(argv, __doc__, budget=60.0)
    print(machine_line())
    mesh, V, T = fandisk()
    print_table("Handle generation on fandisk.obj (paper: 2.1 s, Pentium 4 3.8 GHz)",
                ("case", "input", "runs", "total", "segment", "fits", "simplify", "bind", "notes"),
                handle_rows(timer, V, T) + recompute_rows(timer, mesh))
    print_table("Handle generation on STL models and a tessellated plate (CPU)",
                ("mesh", "input", "runs", "handle CPU", "simplify CPU", "notes"),
                other_rows(timer, args.quick))
    counts = (300_000,) if args.quick else (300_000, 1_000_000)
    print_table("Update (paper: < 30 ms for 300,000 vertices); floor: CSR product, same shape "
                "and nnz", ("case", "input", "runs", "ours", "floor", "ours/floor", "floor runs"),
                update_rows(timer, V, T, counts))


run_as_script(main, __name__, __file__)
