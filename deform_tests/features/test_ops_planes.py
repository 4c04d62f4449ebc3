"""The Stretch, Bend, Twist and Taper ops called directly, with no document: a Part shape, a
Mesh or a Points in, (result, outputs) out, as the panels, the batch runner and the
benchmarks call them. Oracles written here: A x d, Pappus, OCCT Volume/isValid, rotations
and scalings of the input points computed in the test."""
import ast
import os
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402

from freecad_deform.geometry.errors import DeformError  # noqa: E402
from freecad_deform.geometry.sweep.motion import ScrewMotion, translation  # noqa: E402
from freecad_deform.ops import bend, keyed, stretch, taper, twist  # noqa: E402

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])
AT_10 = np.array([0.0, 0.0, 10.0])
SECTION = 10 * 20   # the box's cross-section across z


def grid_cloud():
    """Points on a 1 mm grid filling the box 10 x 20 x 30 (every z level on the grid)."""
    x, y, z = np.meshgrid(np.arange(11.0), np.arange(21.0), np.arange(31.0), indexing="ij")
    pts = np.c_[x.ravel(), y.ravel(), z.ravel()]
    return Points.Points([V(*p) for p in pts]), pts


def cloud_array(points):
    return np.array([tuple(p) for p in points.Points])


class PlaneOps(unittest.TestCase):
    def setUp(self):
        self.box = Part.makeBox(10, 20, 30)

    def test_stretch_solid_adds_section_times_distance(self):
        result, out = stretch.solid(self.box, AT_10, Z, 5.0)
        self.assertTrue(result.isValid())
        self.assertAlmostEqual(result.Volume - self.box.Volume, SECTION * 5.0, delta=1e-7)
        self.assertAlmostEqual(out["VolumeChange"], SECTION * 5.0, delta=1e-7)
        self.assertEqual(len(out["SplitFaces"]), 4)   # the four sides across the plane
        self.assertAlmostEqual(result.BoundBox.ZMax, 35.0, delta=1e-9)
        self.assertAlmostEqual(self.box.Volume, 6000.0, delta=1e-9)  # the input is untouched

    def test_stretch_between_two_planes(self):
        result, out = stretch.solid(self.box, AT_10, Z, 6.0, gap=10.0)
        self.assertTrue(result.isValid())
        self.assertAlmostEqual(result.Volume, 6000.0 + SECTION * 6.0, delta=1e-7)
        self.assertEqual(out["MaxDeviation"], 0.0)

    def test_stretch_volume_change_is_what_occt_measures(self):
        """VolumeChange comes from the cut area (or the slab left out) on the plain paths and
        from the result's volume through the stretch map; on every path it must be what OCCT
        measures of the result against the Base."""
        part = Part.makeCylinder(4, 30).fuse(Part.makeBox(10, 20, 8, V(-5, -10, 0)))
        part = part.cut(Part.makeCylinder(1.5, 30, V(0, 6, 0))).removeSplitter()
        far = Part.makeBox(5, 5, 5, V(30, 0, 40))  # one solid on the near side only
        shell = Part.Shell(Part.makeSphere(3, V(0, 0, 20)).Faces).reversed()
        cases = (("stretch", part, 12.0, None, 5.0), ("shrink", part, 12.0, None, -6.0),
                 ("stretch into the box", part, 4.0, None, 7.0),
                 ("shrink across the step", part, 4.0, None, -6.0),
                 ("prismatic region", part, 12.0, 10.0, 5.0),
                 ("mapped region", part, 4.0, 10.0, 5.0),
                 ("mapped region shrunk", part, 4.0, 10.0, -3.0),
                 ("compound, one solid missed", Part.makeCompound([part, far]), 12.0, None, 5.0),
                 ("reversed sphere", Part.Solid(shell), 20.0, None, 4.0))
        for name, base, z, gap, distance in cases:
            with self.subTest(name):
                result, out = stretch.solid(base, np.array([0.0, 0, z]), Z, distance, gap)
                self.assertTrue(result.isValid())
                occt = (sum(abs(s.Volume) for s in result.Solids)
                        - sum(abs(s.Volume) for s in base.Solids))
                self.assertAlmostEqual(out["VolumeChange"], occt, delta=1e-6 * abs(occt))
                self.assertGreater(abs(occt), 1.0)

    def test_stretch_report_follows_the_base_and_planes(self):
        """The continuity report is remembered per Base and planes: another plane, another
        Base or a moved Base must give the report a fresh computation gives."""
        box, bigger = Part.makeBox(10, 20, 30), Part.makeCylinder(5, 30)
        moved = box.rotated(V(0, 0, 0), V(1, 0, 0), 90)  # the same faces, placed anew
        tower = box.fuse(Part.makeCylinder(3, 20, V(5, 10, 30))).removeSplitter()
        cases = (("box", box, 10.0), ("cylinder", bigger, 10.0), ("box at 20", box, 20.0),
                 ("moved box", moved, 10.0), ("tower", tower, 10.0),
                 ("tower at 40", tower, 40.0))  # other faces: the planes are in the key
        fresh = {}
        for name, base, z in cases:
            stretch.pp._REPORTS.clear()
            fresh[name] = stretch.solid(base, np.array([0.0, 0, z]), Z, 3.0)[1]
        self.assertNotEqual(fresh["tower"]["SplitFaces"], fresh["tower at 40"]["SplitFaces"])
        for name, base, z in cases + (("box", box, 10.0),):
            with self.subTest(name):
                out = stretch.solid(base, np.array([0.0, 0, z]), Z, 7.0)[1]
                self.assertEqual(out["Continuity"], fresh[name]["Continuity"])
                self.assertEqual(list(out["SplitFaces"]), list(fresh[name]["SplitFaces"]))
        # the caller's own shape moved in place after the report was remembered
        own = box.copy()
        stretch.solid(own, np.array([0.0, 0, 10.0]), Z, 3.0)
        own.rotate(V(0, 0, 0), V(1, 0, 0), 90)
        out = stretch.solid(own, np.array([0.0, 0, 10.0]), Z, 3.0)[1]
        self.assertEqual(list(out["SplitFaces"]), list(fresh["moved box"]["SplitFaces"]))
        self.assertEqual(len(fresh["cylinder"]["SplitFaces"]), 1)
        self.assertEqual(len(fresh["box"]["SplitFaces"]), 4)
        self.assertEqual(list(fresh["box"]["SplitFaces"]), ["Face1", "Face2", "Face3", "Face4"])
        self.assertEqual(list(fresh["moved box"]["SplitFaces"]),
                         ["Face1", "Face2", "Face5", "Face6"])

    def test_stretch_mesh_and_cloud(self):
        mesh = Mesh.Mesh(self.box.tessellate(1.0))
        result, out = stretch.mesh(mesh, AT_10, Z, 5.0)
        self.assertAlmostEqual(result.Volume, 6000.0 + SECTION * 5.0, delta=1e-3)
        self.assertAlmostEqual(out["VolumeChange"], SECTION * 5.0, delta=1e-6)
        cloud, pts = grid_cloud()
        result, out = stretch.points(cloud, AT_10, Z, 5.0)
        self.assertEqual(out, {"IgnoredPoints": 0})
        moved = cloud_array(result)
        far = pts[:, 2] > 10
        np.testing.assert_allclose(moved[:len(pts)][far], pts[far] + 5 * Z, atol=1e-5)
        self.assertAlmostEqual(moved[:, 2].max(), 35.0, delta=1e-5)

    def test_a_plane_that_misses_names_plane(self):
        with self.assertRaises(DeformError) as err:
            stretch.solid(self.box, np.array([0.0, 0, 40]), Z, 5.0)
        self.assertEqual(err.exception.prop, "Plane")
        self.assertEqual(str(err.exception), "Plane misses the part: the whole part lies on "
                         "one side of it; move Plane so it crosses the part.")
        with self.assertRaises(DeformError) as err:
            twist.solid(self.box, AT_10, Z, 25.0, np.radians(30))
        self.assertEqual(err.exception.prop, "Plane2")

    def test_bend_solid_pappus(self):
        """About a line in Plane 15 mm from the section's centroid: the gap is the section
        revolved, so the volume grows by A x angle x 15."""
        angle = np.radians(60)
        axis = (np.array([20.0, 0, 10]), np.array([0.0, 1, 0]))
        result, out = bend.solid(self.box, AT_10, Z, angle, axis)
        self.assertTrue(result.isValid())
        self.assertAlmostEqual(out["VolumeChange"], SECTION * angle * 15.0, delta=1e-6)
        self.assertAlmostEqual(result.Volume, 6000.0 + SECTION * angle * 15.0, delta=1e-6)

    def test_twist_points_turn_by_their_fraction(self):
        cloud, pts = grid_cloud()
        angle = np.radians(90)
        centre = np.array([5.0, 10.0, 0.0])
        result, out = twist.points(cloud, AT_10, Z, 10.0, angle, (centre, Z))
        moved = cloud_array(result)
        frac = np.clip((pts[:, 2] - 10) / 10, 0, 1)
        c, s = np.cos(frac * angle), np.sin(frac * angle)
        d = pts - centre
        expect = np.c_[centre[0] + c * d[:, 0] - s * d[:, 1],
                       centre[1] + s * d[:, 0] + c * d[:, 1], pts[:, 2]]
        np.testing.assert_allclose(moved, expect, atol=1e-5)
        self.assertEqual(out, {"IgnoredPoints": 0})

    def test_twist_default_axis_is_the_section_centroid(self):
        result, out = twist.solid(self.box, AT_10, Z, 10.0, np.radians(90))
        self.assertTrue(result.isValid())
        self.assertAlmostEqual(result.Volume, 6000.0, delta=1e-3)
        # the far part turned a quarter about (5, 10): its box is 20 x 10
        far = result.common(Part.makeBox(100, 100, 5, V(-50, -50, 24))).BoundBox
        self.assertAlmostEqual(far.XLength, 20.0, delta=1e-6)
        self.assertAlmostEqual(far.YLength, 10.0, delta=1e-6)
        self.assertAlmostEqual(far.Center.x, 5.0, delta=1e-6)

    def test_mesh_default_axis_is_the_section_area_centroid(self):
        """A holed, L-shaped solid meshed: the mesh's default twist axis is the area centroid
        of OCCT's section face of the solid (to the tessellation's error), whichever way
        the normal points; the far part turns about it."""
        import MeshPart
        from freecad_deform.ops import planes as pp
        solid = Part.makeBox(10, 20, 30).fuse(Part.makeBox(25, 6, 30)).cut(
            Part.makeCylinder(2, 30, V(4, 12, 0))).removeSplitter()
        mesh = MeshPart.meshFromShape(Shape=solid, LinearDeflection=0.01)
        face = Part.makeFace(solid.slice(V(0, 0, 1), 10.0), "Part::FaceMakerBullseye")
        want = np.array(tuple(face.CenterOfMass))
        for normal in (Z, -Z):
            got = pp.section_centroid_mesh(mesh, AT_10, normal)
            np.testing.assert_allclose(got, want, atol=2e-3)
        result, _ = twist.mesh(mesh, AT_10, Z, 10.0, np.radians(90))
        far = np.array([tuple(p) for p in result.Topology[0]])
        far = far[far[:, 2] > 20.5]
        before = np.array([tuple(p) for p in mesh.Topology[0]])
        before = before[before[:, 2] > 20.5]
        turned = np.c_[want[0] - (before[:, 1] - want[1]), want[1] + (before[:, 0] - want[0]),
                       before[:, 2]]
        from scipy.spatial import cKDTree
        self.assertLess(cKDTree(far).query(turned)[0].max(), 5e-3)

    def test_taper_points_scale_across_the_axis(self):
        cloud, pts = grid_cloud()
        centre = np.array([5.0, 10.0, 10.0])
        result, _ = taper.points(cloud, AT_10, Z, 10.0, 0.5, np.eye(3), centre)
        moved = cloud_array(result)
        scale = 1 - 0.5 * np.clip((pts[:, 2] - 10) / 10, 0, 1)
        expect = np.c_[centre[:2] + (pts[:, :2] - centre[:2]) * scale[:, None], pts[:, 2]]
        np.testing.assert_allclose(moved, expect, atol=1e-5)

    def test_taper_solid_volume(self):
        """Linear scale 1 -> 0.5 over 10 mm: the region keeps A x 10 x (1 - 1/2 + 1/12), the
        far part A x 10 / 4; the default axis passes through the section's centroid."""
        result, out = taper.solid(self.box, AT_10, Z, 10.0, 0.5, np.eye(3))
        self.assertTrue(result.isValid())
        expect = SECTION * 10 * (1 + (1 - 0.5 + 1 / 12) + 0.25)
        self.assertAlmostEqual(result.Volume, expect, delta=1e-6 * expect)
        self.assertAlmostEqual(result.BoundBox.Center.x, 5.0, delta=1e-6)

    def test_keyed_translation_is_a_stretch(self):
        result, out = keyed.solid(self.box, AT_10, Z, ScrewMotion(translation(5.0 * Z)), 4)
        self.assertTrue(result.isValid())
        self.assertAlmostEqual(out["VolumeChange"], SECTION * 5.0, delta=1e-6)


class Layers(unittest.TestCase):
    def test_ops_import_no_feature_and_no_gui(self):
        """ops/ sits below features/ and gui/ (DESIGN.md): it imports neither."""
        folder = os.path.join(fc.REPO, "freecad_deform", "ops")
        for name in sorted(os.listdir(folder)):
            if not name.endswith(".py"):
                continue
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                tree = ast.parse(f.read())
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom):
                    module = node.module or ""
                    self.assertFalse(module.split(".")[0] in ("features", "gui")
                                     and node.level >= 2, f"{name} imports {module}")
                    self.assertFalse(module.startswith(("freecad_deform.features",
                                                        "freecad_deform.gui")), name)


class SectionSlice(unittest.TestCase):
    """pp.sections slices a solid through the faces the plane meets (a shell) where it
    meets them in general position, and through OCCT's slice of the whole solid
    otherwise: on real parts both give the same section faces as solid.slice itself."""

    PARTS = ("fc_blocks144.brep", "fc_shelf.brep", "occt_Bottom.brep",
             "nist_ftc_10_asme1_rb.stp", "face_recognition_sample_part.stp")

    def check(self, solid, origin, normal):
        from freecad_deform.ops import planes as pp
        d = float(origin @ normal)
        wires = solid.slice(V(*normal), d)
        got = pp.sections([solid], origin, normal, [0.0])[0]
        if not wires:                         # (a plane through a vertex at the part's end)
            self.assertEqual(got, [])
            return
        want = Part.makeFace(wires, "Part::FaceMakerBullseye").Faces
        self.assertEqual(len(got), len(want))
        area = sum(f.Area for f in want)
        self.assertAlmostEqual(sum(f.Area for f in got), area, delta=1e-9 * abs(area))
        centre = sum(np.array(tuple(f.CenterOfMass)) * f.Area for f in want) / area
        np.testing.assert_allclose(pp.section_centroid([solid], origin, normal), centre,
                                   atol=1e-9 * solid.BoundBox.DiagonalLength)

    def test_sections_of_real_parts_are_the_solids_slices(self):
        from unittest import mock
        shells = 0
        for name in self.PARTS:
            shape = Part.Shape()
            shape.read(fc.testdata(name))
            solid = max(shape.Solids, key=lambda s: s.Volume)
            box = solid.BoundBox
            lo, hi = np.array([box.XMin, box.YMin, box.ZMin]), np.array([box.XMax, box.YMax,
                                                                         box.ZMax])
            vertex = np.array(tuple(solid.Vertexes[len(solid.Vertexes) // 2].Point))
            for k, normal in enumerate(np.eye(3)):
                for origin in [lo + f * (hi - lo) for f in (0.31, 0.77)] + [vertex]:
                    with self.subTest(name=name, axis=k, origin=origin), mock.patch(
                            "Part.makeShell", wraps=Part.makeShell) as shell:
                        self.check(solid, origin, normal)
                        shells += shell.call_count
            if name == "fc_blocks144.brep":   # its planes in general position: the shell
                self.assertGreater(shells, 0)
        oblique = np.array([0.48, 0.6, 0.64])
        self.check(solid, (lo + hi) / 2, oblique)
