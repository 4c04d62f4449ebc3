"""Mesh Twist against Samples (issue 11): the band's cost, next to the floor measured in the same run.

Run from anywhere (FreeCAD 0.20 on Debian):

    /usr/bin/python3 benchmarks/mesh_samples.py                  # median of 5 runs, ~1 minute
    /usr/bin/python3 benchmarks/mesh_samples.py --quick          # 1 run (CI smoke run)
    /usr/bin/python3 benchmarks/mesh_samples.py --before 689de8c^  # also the kernel of an older
                                                                 # commit (read with git archive)

Prints tables, asserts nothing about time. Each row is the median of --runs runs (3 for a
row whose runs would exceed --budget seconds). Two meshes: the 12-triangle box 40 x 20 x 20
(Part.makeBox tessellated) and the finned housing occt_sh2.stl (7,196 triangles); planes
across the middle half of the longest side, 90 deg about the centre line, Samples 16, 64,
256, 1024 and 4096. Columns:

  in / out   triangles of the Base and of the result
  kernel     mesh_sweep.map_between alone (the cut at every Samples plane and the map)
  recompute  touch() + doc.recompute() of the Mesh Twist object (conversions, VolumeChange)
  floor map  a plain numpy twist of the result's vertices: each turned by angle * clip(s/gap)
             about the axis (cos, sin and one product per vertex), what any map must pay
  floor sect FreeCAD's own Mesh.crossSections at the same Samples + 1 planes (C++): finding
             the section polylines alone, without cutting or mapping anything
  before     with --before REV: the same kernel as it was at REV (one run when that took
             over --budget seconds); a row whose time, extrapolated quadratically from the
             row above, would exceed 4 x --budget is skipped and shows that estimate

A second table does the same for a point-cloud Twist (10^5 points sampled on the housing's
surface), whose points are each mapped alone: Samples does not enter its cost.

Progress goes to stderr.
"""
import importlib
import importlib.util
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
# bench_stretch puts FreeCAD's modules and the repository on sys.path and imports FreeCAD first
from bench_stretch import (REPO, machine_line, options, print_table, progress,  # noqa: E402
                           run_as_script, runs_line, seconds, surface_samples, testdata)

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.features.planes import MAX_SAMPLES  # noqa: E402
from freecad_deform.geometry.mesh.sweep import map_between, twist_motion  # noqa: E402
from freecad_deform.geometry.points.sweep import map_points_between  # noqa: E402
from freecad_deform.shapes.convert import mesh_arrays, mesh_eps  # noqa: E402

V = App.Vector
SAMPLES = (16, 64, 256, 1024, 4096)
ANGLE = 90.0


def meshes():
    return (("box 40x20x20", Mesh.Mesh(Part.makeBox(40, 20, 20).tessellate(1.0))),
            ("occt_sh2.stl", Mesh.Mesh(testdata("occt_sh2.stl"))))


def twist_setup(vertices):
    """(origin, normal, gap, axis point): planes at 1/4 and 3/4 of the longest side, the
    axis along it through the bounding box centre."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    k = int(np.argmax(hi - lo))
    n = np.eye(3)[k]
    origin = lo + 0.25 * (hi - lo) * n
    return origin, n, 0.5 * (hi - lo)[k], (lo + hi) / 2


def numpy_twist(points, origin, n, gap, centre):
    """The floor: every point turned by angle * clip(s/gap, 0, 1) about (centre, n)."""
    phi = np.radians(ANGLE) * np.clip((points - origin) @ n / gap, 0.0, 1.0)
    r = points - centre
    along = (r @ n)[:, None] * n
    perp = r - along
    return centre + along + np.cos(phi)[:, None] * perp + np.sin(phi)[:, None] * np.cross(n, perp)


def old_kernel(rev):
    """map_between as it was at `rev`: the package read with git archive into a temp dir."""
    where = tempfile.mkdtemp(prefix="deform_before_")
    archive = subprocess.run(["git", "-C", REPO, "archive", rev, "freecad_deform"],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", where], input=archive, check=True)
    spec = importlib.util.spec_from_file_location(
        "deform_before", os.path.join(where, "freecad_deform", "__init__.py"),
        submodule_search_locations=[os.path.join(where, "freecad_deform")])
    package = importlib.util.module_from_spec(spec)
    sys.modules["deform_before"] = package
    spec.loader.exec_module(package)
    try:
        return importlib.import_module("deform_before.geometry.mesh.sweep").map_between
    except ImportError:  # a revision before the kernels were grouped by domain
        return importlib.import_module("deform_before.geometry.mesh_sweep").map_between


def main(argv=None):
    import argparse
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--before", default=None)
    extra, rest = pre.parse_known_args(argv)
    args, timer = options(rest, __doc__)
    before = old_kernel(extra.before) if extra.before else None
    start = time.perf_counter()
    print(machine_line())
    print(runs_line(args, timer.runs))
    print(f"MAX_SAMPLES (features/planes.py): {MAX_SAMPLES}")
    doc = App.newDocument("MeshSamples")
    rows = []
    for name, mesh in meshes():
        V0, T0 = mesh_arrays(mesh)
        eps = mesh_eps(V0)
        origin, n, gap, centre = twist_setup(V0)
        f = twist_motion(origin, n, gap, np.radians(ANGLE), centre, n)
        base = doc.addObject("Mesh::Feature", "Base")
        base.Mesh = mesh
        obj = fd.make_twist(base, (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n)), ANGLE,
                            (V(*centre), V(*n)))
        last = None       # (Samples, seconds) of the previous before-run
        for samples in SAMPLES[:3] if args.quick else SAMPLES:
            progress(start, f"{name}, Samples {samples}")
            out = map_between(V0, T0, origin, n, gap, f, samples, eps)
            kernel, runs = timer.median(
                lambda: map_between(V0, T0, origin, n, gap, f, samples, eps))
            obj.Samples = samples
            obj.touch()
            doc.recompute()
            if obj.State == ["Up-to-date"]:
                assert obj.Mesh.CountFacets == len(out[1]), "the feature and the kernel differ"

                def recompute():
                    obj.touch()
                    doc.recompute()
                whole = seconds(timer.median(recompute, runs)[0])
            else:
                whole = "refused"
            floor_map = timer.median(lambda: numpy_twist(out[0], origin, n, gap, centre), runs)[0]
            planes = [(V(*(origin + gap * j / samples * n)), V(*n)) for j in range(samples + 1)]
            floor_sect = timer.median(lambda: mesh.crossSections(planes), runs)[0]
            old = ""
            guess = last and last[1] * (samples / last[0]) ** 2   # if it were quadratic
            if before is not None and guess and guess > 4 * args.budget:
                old = f"(~{guess:.0f} skipped)"
            elif before is not None:
                t = time.perf_counter()
                before(V0, T0, origin, n, gap, f, samples, eps)
                first = time.perf_counter() - t
                old = seconds(first if first > args.budget else timer.median(
                    lambda: before(V0, T0, origin, n, gap, f, samples, eps), runs)[0])
                last = (samples, first)
            rows.append((name, samples, len(T0), len(out[1]), runs, seconds(kernel), whole,
                         seconds(floor_map), seconds(floor_sect), old or "-"))
    header = ("mesh", "Samples", "in", "out", "runs", "kernel", "recompute", "floor map",
              "floor sect", f"before {extra.before}" if extra.before else "before")
    print_table(f"mesh Twist {ANGLE:g} deg over the middle half, seconds (median)", header, rows)
    print_table(f"point-cloud Twist {ANGLE:g} deg, the same planes: each point is mapped alone, "
                f"Samples is not used (seconds, median)",
                ("cloud", "Samples", "points", "runs", "kernel", "recompute", "floor map"),
                cloud_rows(doc, timer, start, args.quick))
    App.closeDocument(doc.Name)


def cloud_rows(doc, timer, start, quick):
    """A Points Twist of 10^5 points sampled on the housing's surface, at each Samples."""
    V0, T0 = mesh_arrays(Mesh.Mesh(testdata("occt_sh2.stl")))
    cloud = surface_samples(V0, T0, 10 ** 5)
    origin, n, gap, centre = twist_setup(cloud)
    f = twist_motion(origin, n, gap, np.radians(ANGLE), centre, n)
    base = doc.addObject("Points::Feature", "Cloud")
    base.Points = Points.Points([tuple(p) for p in cloud])
    obj = fd.make_twist(base, (V(*origin), V(*n)), (V(*(origin + gap * n)), V(*n)), ANGLE,
                        (V(*centre), V(*n)))
    rows = []
    for samples in SAMPLES[:3] if quick else SAMPLES:
        progress(start, f"cloud, Samples {samples}")
        kernel, runs = timer.median(lambda: map_points_between(cloud, origin, n, gap, f))
        obj.Samples = samples

        def recompute():
            obj.touch()
            doc.recompute()
        whole = timer.median(recompute, runs)[0]
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        floor = timer.median(lambda: numpy_twist(cloud, origin, n, gap, centre), runs)[0]
        rows.append(("housing surface", samples, len(cloud), runs, seconds(kernel),
                     seconds(whole), seconds(floor)))
    return rows


run_as_script(main, __name__, __file__)
