"""DirectPush benchmark: one push on a 30 x 30-pole bicubic surface next to OCCT's own
BSplineSurface.movePoint (which FreeCAD exposes) in the same run, their ratio, and the
frame rate of a drag loop.

Run from anywhere (FreeCAD 0.20 on Debian):

    /usr/bin/python3 benchmarks/bench_direct_push.py            # median of 5 runs
    /usr/bin/python3 benchmarks/bench_direct_push.py --quick    # 1 run
    /usr/bin/python3 benchmarks/bench_direct_push.py --sweep    # every housing face

Prints tables, asserts nothing about time. Both pushes move the poles around the point
(5 x 5 for ours, the paper's m = degree + 1; the same index range for movePoint) so the
point lands on the target. The drag loop is what a live drag does per mouse move without
a document recompute: one push on the current surface and the Part face rebuilt from its
poles (what the viewer then shows); frames per second = 1 / (median time of one frame).
A document recompute of the DirectPush object (all pushes replayed from the Base, face
rebuilt) and the op it calls (ops.direct_push.face) are timed too, on a synthetic surface and on real models (the 312 x 323-pole
terrain, trimmed and natural faces of the 323-face cast housing).
"""
import os
import statistics
import sys
import time
import timeit

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from bench_stretch import machine_line, options, print_table, run_as_script  # noqa: E402

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.nurbs import direct_push as dp  # noqa: E402
from freecad_deform.ops import direct_push as push_op  # noqa: E402
from freecad_deform.shapes import bspline  # noqa: E402

from deform_tests.oracles.nurbs import canopy  # noqa: E402

V = App.Vector


def ms(t):
    return f"{1e3 * t:.3f} ms"


def push_rows(timer, n, calls=2000):
    """One push and one movePoint, each timed as the mean of `calls` calls (a single call
    of some 20 us is below the clock's noise), run by run in turn so that a change of load
    weighs on both; the landing errors by OCCT's evaluation of each result."""
    s = canopy(n, size=(100.0, 100.0))
    occ = bspline.surface_from_arrays(s)
    u, v = 0.43, 0.57
    P = s.poles.reshape(-1, 3)
    point = dp.surface_row(s, u, v) @ P
    normal = np.cross(dp.surface_row(s, u, v, 1, 0) @ P, dp.surface_row(s, u, v, 0, 1) @ P)
    target = point + 3.0 * normal / np.linalg.norm(normal)
    size = s.udegree + 2
    result = {}

    def ours():
        result["s"] = dp.push_surface(s, u, v, target, size)

    grid = np.abs(dp.surface_row(s, u, v).reshape(s.weights.shape))
    iu = dp.window(grid.sum(axis=1), size, 1, n - 2)
    iv = dp.window(grid.sum(axis=0), size, 1, n - 2)

    def theirs():
        surface = occ.copy()
        surface.movePoint(u, v, V(*target), iu[0] + 1, iu[-1] + 1, iv[0] + 1, iv[-1] + 1)
        result["occ"] = surface

    def per_call(fn):
        return timeit.timeit(fn, number=calls) / calls

    runs = timer.runs
    pairs = [(per_call(ours), per_call(theirs)) for _ in range(runs)]
    t_ours = statistics.median(p for p, _ in pairs)
    t_occ = statistics.median(q for _, q in pairs)
    ratio = statistics.median(p / q for p, q in pairs)
    landed = (bspline.surface_from_arrays(result["s"]).value(u, v) - V(*target)).Length
    landed_occ = (result["occ"].value(u, v) - V(*target)).Length
    label = f"{n}x{n} poles, x{calls}"
    return [("push (kernel)", label, runs, f"{1e3 * t_ours:.4f} ms", f"{landed:.1e}"),
            ("movePoint (OCCT)", label, runs, f"{1e3 * t_occ:.4f} ms", f"{landed_occ:.1e}"),
            ("push / movePoint", "same runs", runs, f"{ratio:.2f}x", "")]


def drag_rows(timer, n, frames=30):
    s0 = canopy(n, size=(100.0, 100.0))
    u, v = 0.43, 0.57
    P = s0.poles.reshape(-1, 3)
    start = dp.surface_row(s0, u, v) @ P
    normal = np.cross(dp.surface_row(s0, u, v, 1, 0) @ P, dp.surface_row(s0, u, v, 0, 1) @ P)
    normal /= np.linalg.norm(normal)

    def drag():
        s = s0
        times = []
        for k in range(1, frames + 1):
            t = time.perf_counter()
            s = dp.push_surface(s, u, v, start + 0.1 * k * normal, s0.udegree + 2)
            Part.Face(bspline.surface_from_arrays(s))
            times.append(time.perf_counter() - t)
        return float(np.median(times))

    frame, runs = timer.median(drag)
    return [("drag loop: push + face rebuild", f"{n}x{n} poles, {frames} moves", runs,
             ms(frame), f"{1 / frame:.0f} frames/s")]


def recompute(obj):
    """One recompute of `obj` (touched), which must succeed."""
    obj.touch()
    obj.Document.recompute()
    if "Invalid" in obj.State:
        raise RuntimeError(obj.getStatusString())


def recompute_rows(timer, n):
    doc = App.newDocument("BenchDirectPush")
    try:
        s = canopy(n, size=(100.0, 100.0))
        base = doc.addObject("Part::Feature", "Surface")
        base.Shape = Part.Face(bspline.surface_from_arrays(s))
        doc.recompute()
        P = s.poles.reshape(-1, 3)
        point = dp.surface_row(s, 0.43, 0.57) @ P
        obj = fd.make_direct_push(base, "Face1", V(*point), V(*(point + [0, 0, 3])))

        t, runs = timer.median(lambda: recompute(obj))
        t_op, runs_op = timer.median(lambda: push_op.face(
            base.Shape, "Face1", [V(*point)], [V(*(point + [0, 0, 3]))]))
        return [("document recompute", f"{n}x{n} poles, 1 push", runs, ms(t), ""),
                ("ops.direct_push.face", f"{n}x{n} poles, 1 push", runs_op, ms(t_op), "")]
    finally:
        App.closeDocument(doc.Name)


def testdata(name):
    folder = os.environ.get("DEFORM_TESTDATA", os.path.join(
        os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__)))),
        "shared", "testdata"))
    shape = Part.Shape()
    shape.read(os.path.join(folder, name))
    return shape


def real_rows(timer):
    """A document recompute of one push (replayed from the Base) on the terrain's 312 x
    323-pole face and on trimmed and natural B-spline faces of the cast housing (a solid
    of 323 faces: the face is put back with its own edges, the solid checked)."""
    doc = App.newDocument("BenchDirectPushReal")
    rows = []
    try:
        cases = [("occt_terrain.brep", 0, "terrain face, 312x323 poles"),
                 ("occt_Bottom.brep", 9, "housing Face10, trimmed"),
                 ("occt_Bottom.brep", 31, "housing Face32, trimmed (edge tol 0.01)"),
                 ("occt_Bottom.brep", 180, "housing Face181, 8x8 poles")]
        for name, index, label in cases:
            shape = testdata(name)
            base = doc.addObject("Part::Feature", "Base")
            base.Shape = shape
            face = shape.Faces[index]
            u0, u1, v0, v1 = face.ParameterRange
            grid = sorted(((u0 + a * (u1 - u0), v0 + b * (v1 - v0))
                           for a in np.linspace(0.1, 0.9, 9) for b in np.linspace(0.1, 0.9, 9)),
                          key=lambda x: abs(x[0] - 0.5 * (u0 + u1)) / (u1 - u0) +
                          abs(x[1] - 0.5 * (v0 + v1)) / (v1 - v0))
            uv = next(x for x in grid if face.isInside(face.valueAt(*x), 1e-9, True))
            point = face.valueAt(*uv)
            target = point + face.normalAt(*uv) * (0.02 * face.BoundBox.DiagonalLength)
            obj = fd.make_direct_push(base, f"Face{index + 1}", point, target)

            t, runs = timer.median(lambda: recompute(obj))
            pushed = obj.Shape.Faces[index]
            landed = pushed.distToShape(Part.Vertex(target))[0]
            rows.append(("document recompute", label, runs, ms(t),
                         f"{landed:.1e} mm, valid {obj.Shape.isValid()}"))
    finally:
        App.closeDocument(doc.Name)
    return rows


def sweep_rows():
    """Every B-spline face of the cast housing pushed outward by 2 % of its size at the
    inner point farthest from its edges (what deform_tests/features/test_direct_push.py does on
    five of them): per outcome the count, the median and largest recompute time and the
    largest landing error; every accepted result checked valid, closed and outward
    (OCCT's classifier halfway to the target)."""
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
    from deform_tests.features.test_direct_push import inner_point
    shape = testdata("occt_Bottom.brep")
    doc = App.newDocument("BenchDirectPushSweep")
    base = doc.addObject("Part::Feature", "Base")
    base.Shape = shape
    outcomes = {}
    try:
        for index, face in enumerate(shape.Faces):
            if face.Surface.TypeId != "Part::GeomBSplineSurface":
                continue
            point, normal = inner_point(face)
            target = point + normal * (0.02 * face.BoundBox.DiagonalLength)
            start = time.perf_counter()
            obj = fd.make_direct_push(base, f"Face{index + 1}", point, target)
            seconds = time.perf_counter() - start
            if "Invalid" in obj.State:
                kind, landed = "refused: " + obj.getStatusString()[:60], 0.0
            else:
                result = obj.Shape
                landed = result.Faces[index].distToShape(Part.Vertex(target))[0]
                mid = point + (target - point) * 0.5
                ok = result.isValid() and result.Shells[0].isClosed() and \
                    result.isInside(mid, 1e-9, True) and landed < 1e-7
                kind = "accepted, oracles pass" if ok else \
                    f"accepted, ORACLE FAILS (Face{index + 1})"
            outcomes.setdefault(kind, []).append((seconds, landed))
            doc.removeObject(obj.Name)
    finally:
        App.closeDocument(doc.Name)
    return [(kind, len(v), ms(float(np.median([t for t, _ in v]))), ms(max(t for t, _ in v)),
             f"{max(d for _, d in v):.1e} mm") for kind, v in sorted(outcomes.items())]


def main(argv):
    if "--sweep" in argv:
        print(machine_line())
        print_table("Every B-spline face of the 323-face housing pushed (--sweep)",
                    ("outcome", "faces", "median time", "max time", "max landing error"),
                    sweep_rows())
        return
    args, timer = options(argv, __doc__, budget=60.0)
    print(machine_line())
    print_table("One push on a 30x30-pole surface, and OCCT's movePoint in the same run",
                ("case", "input", "runs", "time", "landing error"),
                push_rows(timer, 30) + recompute_rows(timer, 30))
    print_table("Drag loop (per mouse move, no document recompute)",
                ("case", "input", "runs", "time per frame", "rate"),
                drag_rows(timer, 20) + drag_rows(timer, 30))
    print_table("One push on real models (default options)",
                ("case", "input", "runs", "time", "landing error"), real_rows(timer))


run_as_script(main, __name__, __file__)
