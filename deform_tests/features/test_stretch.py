"""Stretch on real FreeCAD documents: solids, compounds, meshes, point clouds; save and reopen.

Oracles: OCCT's Volume and isValid(), the area of a section made by Shape.slice, a common
with a box for the slab a shrink removes, cKDTree distances for where vertices went.
"""
import os
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import freecad_deform as fd  # noqa: E402

from ..oracles.shapes import (closed_manifold, mesh_section_area, section_area,  # noqa: E402
                              slab_volume)

V = App.Vector


def points_of(shape):
    return np.array([tuple(v.Point) for v in shape.Vertexes])


class StretchSolid(unittest.TestCase):
    """The machined part: one solid, 23 faces (planes and cylinders)."""

    @classmethod
    def setUpClass(cls):
        cls.shape = Part.read(fc.testdata("face_recognition_sample_part.stp"))

    def setUp(self):
        self.doc = fc.new_document()
        self.base = self.doc.addObject("Part::Feature", "Part")
        self.base.Shape = self.shape

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def check_exact_stretch(self, origin, normal, distance):
        obj = fd.make_stretch(self.base, (V(*origin), V(*normal)), distance)
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        result, n = obj.Shape, np.asarray(normal, float) / np.linalg.norm(normal)
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        area = section_area(self.shape, origin, n)
        self.assertAlmostEqual((result.Volume - self.shape.Volume) / (area * distance), 1.0, delta=1e-6)
        self.assertAlmostEqual(obj.VolumeChange / (area * distance), 1.0, delta=1e-6)
        self.assertEqual({type(f.Surface).__name__ for f in result.Faces}, {"Plane", "Cylinder"})
        # where the vertices went: before the plane unchanged, beyond it moved by distance*n,
        # and every vertex of the result is one of those or lies on a joint plane
        before, after = points_of(self.shape), points_of(result)
        s = (before - origin) @ n
        expected = np.vstack([before[s < -1e-9], before[s > 1e-9] + distance * n])
        dist, _ = cKDTree(after).query(expected)
        self.assertLess(dist.max(), 1e-7, f"missing: {expected[dist > 1e-7]}")
        sa = (after - origin) @ n
        explained = cKDTree(expected).query(after)[0] < 1e-7
        on_joint = (np.abs(sa) < 1e-7) | (np.abs(sa - distance) < 1e-7)
        self.assertTrue(np.all(explained | on_joint))
        return obj

    def test_stretch_along_each_axis(self):
        for origin, normal, distance in (((150, 0, 0), (1, 0, 0), 40.0),
                                         ((0, -50, 0), (0, 1, 0), 25.0),
                                         ((0, 0, 100), (0, 0, 1), 30.0),
                                         ((0, 0, 100), (0, 0, -1), 12.5)):
            with self.subTest(normal=normal):
                self.check_exact_stretch(origin, normal, distance)

    def test_base_untouched_and_hidden(self):
        corners, volume = points_of(self.base.Shape), self.base.Shape.Volume
        fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        np.testing.assert_array_equal(points_of(self.base.Shape), corners)
        self.assertEqual(self.base.Shape.Volume, volume)
        self.assertFalse(self.base.Visibility)


    def test_continuity_report(self):
        obj = fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        entries = dict(e.split(": ") for e in obj.Continuity.split("; "))
        self.assertEqual(sorted(entries, key=lambda k: int(k[4:])), list(obj.SplitFaces))
        # oracle: Lemma 1 by hand, the face normal at a point of its section against the motion
        for name, kind in entries.items():
            face = self.shape.getElement(name)
            edge = face.slice(V(1, 0, 0), 150.0)[0].Edges[0]
            p = edge.valueAt(0.5 * (edge.FirstParameter + edge.LastParameter))
            nrm = face.normalAt(*face.Surface.parameter(p))
            self.assertEqual(kind, "G1" if abs(nrm.x) < 1e-6 else "C0", name)
        self.assertIn("G1", entries.values())

    def test_edit_distance_save_reopen(self):
        obj = fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        area = section_area(self.shape, (150, 0, 0), (1, 0, 0))
        obj.Distance = "2.5 cm"
        self.doc.recompute()
        self.assertAlmostEqual(obj.Shape.Volume - self.shape.Volume, area * 25.0, delta=1e-6 * area * 25)
        volume = obj.Shape.Volume
        path = os.path.join(tempfile.mkdtemp(), "stretch.FCStd")
        name = obj.Name
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        obj = self.doc.getObject(name)
        self.assertAlmostEqual(obj.Shape.Volume, volume, delta=1e-9 * volume)
        obj.touch()
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State)
        self.assertAlmostEqual(obj.Shape.Volume, volume, delta=1e-9 * volume)

    def test_expression_drives_distance(self):
        obj = fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        obj.setExpression("Distance", "10 mm * 3")
        self.doc.recompute()
        self.assertAlmostEqual(obj.Distance.Value, 30.0)
        area = section_area(self.shape, (150, 0, 0), (1, 0, 0))
        self.assertAlmostEqual(obj.VolumeChange / (area * 30.0), 1.0, delta=1e-6)

    def test_shrink_removes_slab(self):
        origin, normal, width = (150, 0, 0), (1, 0, 0), 40.0
        obj = fd.make_stretch(self.base, (V(*origin), V(*normal)), -width)
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertTrue(obj.Shape.isValid())
        self.assertEqual(len(obj.Shape.Solids), 1)
        removed = slab_volume(self.shape, origin, normal, width)
        self.assertAlmostEqual(self.shape.Volume - obj.Shape.Volume, removed, delta=1e-6 * removed)
        self.assertAlmostEqual(obj.Shape.BoundBox.XLength, self.shape.BoundBox.XLength - width, delta=1e-7)

    def test_two_planes_keep_cross_sections(self):
        origin, normal, gap, distance = (0, 0, 100), (0, 0, 1), 50.0, 30.0
        obj = fd.make_stretch(self.base, (V(*origin), V(*normal)), distance,
                              plane2=(V(0, 0, 100 + gap), V(*normal)))
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        result = obj.Shape
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        between = slab_volume(self.shape, origin, normal, gap)
        self.assertAlmostEqual((result.Volume - self.shape.Volume) / (between * distance / gap), 1.0,
                               delta=1e-6)
        for frac in (0.25, 0.5, 0.8):  # a section at s maps to s * (gap + d) / gap
            a0 = section_area(self.shape, (0, 0, 100 + frac * gap), normal)
            a1 = section_area(result, (0, 0, 100 + frac * (gap + distance)), normal)
            self.assertAlmostEqual(a1 / a0, 1.0, delta=1e-6)
        self.assertAlmostEqual(result.BoundBox.ZMax, self.shape.BoundBox.ZMax + distance, delta=1e-7)

    def test_plane_that_misses_is_an_error(self):
        before = self.base.Shape.Volume
        obj = fd.make_stretch(self.base, (V(0, 0, 400), V(0, 0, 1)), 30)
        self.assertIn("Invalid", obj.State)
        self.assertIn("Plane", obj.getStatusString())
        self.assertEqual(self.base.Shape.Volume, before)
        path, name = os.path.join(tempfile.mkdtemp(), "error.FCStd"), obj.Name
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        self.assertAlmostEqual(self.doc.getObject("Part").Shape.Volume, before, delta=1e-9 * before)
        stretch = self.doc.getObject(name)
        stretch.Plane = App.Placement(V(0, 0, 100), App.Rotation())  # fixing the property recovers
        self.doc.recompute()
        self.assertNotIn("Invalid", stretch.State)

    def test_shrink_past_the_end_is_an_error(self):
        obj = fd.make_stretch(self.base, (V(0, 0, 100), V(0, 0, 1)), -300)
        self.assertIn("Invalid", obj.State)
        self.assertIn("Distance", obj.getStatusString())

    def test_nonparallel_plane2_is_an_error(self):
        obj = fd.make_stretch(self.base, (V(0, 0, 100), V(0, 0, 1)), 10,
                              plane2=(V(0, 0, 150), V(0, 1, 1)))
        self.assertIn("Invalid", obj.State)
        self.assertIn("Plane2", obj.getStatusString())

    def test_undo_in_one_step(self):
        count = len(self.doc.Objects)
        fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        self.assertEqual(len(self.doc.Objects), count + 1)
        self.doc.undo()
        self.assertEqual(len(self.doc.Objects), count)

    def test_chained_stretch(self):
        first = fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        second = fd.make_stretch(first, (V(0, 0, 100), V(0, 0, 1)), 20)
        area = section_area(first.Shape, (0, 0, 100), (0, 0, 1))
        self.assertAlmostEqual(second.VolumeChange / (area * 20), 1.0, delta=1e-6)

    def test_old_document_gets_missing_properties(self):
        obj = fd.make_stretch(self.base, (V(150, 0, 0), V(1, 0, 0)), 40)
        obj.removeProperty("SplitFaces")
        path, name = os.path.join(tempfile.mkdtemp(), "old.FCStd"), obj.Name
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        self.assertIn("SplitFaces", self.doc.getObject(name).PropertiesList)


class StretchRegionMap(unittest.TestCase):
    def test_stepped_shaft_region_keeps_cylinders_and_scales_its_volume(self):
        """Two planes across a step: the region goes through the stretch's space map. Its
        cylinders along the normal stay cylinders (exact: MaxDeviation 0), and the volume
        grows by the region's volume x Distance / gap (OCCT's transformGeometry was 0.7 %
        off here: its circles are approximated)."""
        doc = App.newDocument("StretchRegionMap")
        try:
            shaft = Part.makeCylinder(10, 100).fuse(
                Part.makeCylinder(15, 30, App.Vector(0, 0, 40))).removeSplitter()
            base = doc.addObject("Part::Feature", "Shaft")
            base.Shape = shaft
            obj = fd.make_stretch(base, (App.Vector(0, 0, 20), App.Vector(0, 0, 1)), 30,
                                  plane2=(App.Vector(0, 0, 80), App.Vector(0, 0, 1)))
            self.assertNotIn("Invalid", obj.State, obj.getStatusString())
            result = obj.Shape
            self.assertTrue(result.isValid())
            region = np.pi * (10 ** 2 * 60 + (15 ** 2 - 10 ** 2) * 30)   # z 20..80
            self.assertAlmostEqual(result.Volume, shaft.Volume + region * 30 / 60,
                                   delta=1e-9 * shaft.Volume)
            kinds = sorted(type(f.Surface).__name__ for f in result.Faces)
            self.assertEqual(kinds, ["Cylinder"] * 5 + ["Plane"] * 4, kinds)
            self.assertEqual(obj.MaxDeviation, 0.0)
            # the step's shoulder moved to where the map puts z = 70: 20 + 50 x 1.5
            shoulder = [f for f in result.Faces if type(f.Surface).__name__ == "Plane"
                        and abs(f.BoundBox.ZLength) < 1e-9 and f.Area < 1000 and
                        60 < f.BoundBox.ZMin < 120]
            self.assertEqual(len(shoulder), 1)
            self.assertAlmostEqual(shoulder[0].BoundBox.ZMin, 95.0, delta=1e-9)
        finally:
            App.closeDocument(doc.Name)


class StretchCompound(unittest.TestCase):
    """The AS1 assembly: 18 solids; each crossed solid stretched, the rest kept or moved."""

    def test_assembly(self):
        doc = fc.new_document()
        try:
            shape = Part.read(fc.testdata("as1_pe_203.stp"))
            base = doc.addObject("Part::Feature", "AS1")
            base.Shape = shape
            c = shape.BoundBox.Center
            origin, normal, distance = (c.x + 1.234, c.y, c.z), (1, 0, 0), 15.0
            obj = fd.make_stretch(base, (V(*origin), V(*normal)), distance)
            self.assertNotIn("Invalid", obj.State, obj.getStatusString())
            self.assertEqual(len(obj.Shape.Solids), len(shape.Solids))
            self.assertTrue(all(s.isValid() for s in obj.Shape.Solids))
            area = sum(section_area(s, origin, normal) for s in shape.Solids
                       if s.BoundBox.XMin < origin[0] < s.BoundBox.XMax)
            self.assertAlmostEqual(obj.VolumeChange / (area * distance), 1.0, delta=1e-6)
        finally:
            App.closeDocument(doc.Name)


class StretchMesh(unittest.TestCase):
    """A mesh of the machined part: the result is closed and manifold, volume grows by A*d."""

    def test_mesh(self):
        doc = fc.new_document()
        try:
            shape = Part.read(fc.testdata("face_recognition_sample_part.stp"))
            base = doc.addObject("Mesh::Feature", "PartMesh")
            base.Mesh = Mesh.Mesh(shape.tessellate(0.5))
            origin, normal, distance = (150.0, 0.0, 0.0), (1.0, 0.0, 0.0), 40.0
            obj = fd.make_stretch(base, (V(*origin), V(*normal)), distance)
            self.assertNotIn("Invalid", obj.State, obj.getStatusString())
            mesh = obj.Mesh
            self.assertTrue(closed_manifold(mesh))
            self.assertFalse(mesh.hasNonManifolds())
            self.assertTrue(mesh.isSolid())
            area = mesh_section_area(base.Mesh, origin, normal)
            self.assertAlmostEqual((mesh.Volume - base.Mesh.Volume) / (area * distance), 1.0, delta=1e-4)
            exact = section_area(shape, origin, normal)
            self.assertAlmostEqual(obj.VolumeChange / (exact * distance), 1.0, delta=1e-2)
        finally:
            App.closeDocument(doc.Name)


class StretchPoints(unittest.TestCase):
    """A point cloud sampled on the part: rigid parts moved exactly, the gap filled."""

    def test_points(self):
        doc = fc.new_document()
        try:
            shape = Part.read(fc.testdata("face_recognition_sample_part.stp"))
            cloud = np.array([(p.x, p.y, p.z) for p in Mesh.Mesh(shape.tessellate(2.0)).Points])
            base = doc.addObject("Points::Feature", "Cloud")
            base.Points = Points.Points([V(*p) for p in cloud])
            origin, normal, distance = np.array([150.0, 0, 0]), np.array([1.0, 0, 0]), 40.0
            obj = fd.make_stretch(base, (V(*origin), V(*normal)), distance)
            self.assertNotIn("Invalid", obj.State, obj.getStatusString())
            out = np.array([tuple(p) for p in obj.Points.Points])
            s = (cloud - origin) @ normal
            expected = np.vstack([cloud[s <= 0], cloud[s > 0] + distance * normal])
            self.assertLess(cKDTree(out).query(expected)[0].max(), 1e-5)  # Points store float32
            so = (out - origin) @ normal
            gap = out[(so > 1e-3) & (so < distance - 1e-3)]
            self.assertGreater(len(gap), 0)
            # every fill point lies on the section's outline swept along the normal
            tree = cKDTree((cloud[np.abs(s) < 5.0] - np.outer(s[np.abs(s) < 5.0], normal))[:, 1:])
            self.assertLess(tree.query(gap[:, 1:])[0].max(), 1e-4)
        finally:
            App.closeDocument(doc.Name)


if __name__ == "__main__":
    unittest.main()


class StretchSections(unittest.TestCase):
    """Sections with holes and in separate pieces, on parts built here."""

    def setUp(self):
        self.doc = fc.new_document()

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def stretch(self, shape, origin, normal, distance, **kw):
        base = self.doc.addObject("Part::Feature", "Base")
        base.Shape = shape
        obj = fd.make_stretch(base, (V(*origin), V(*normal)), distance, **kw)
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertTrue(obj.Shape.isValid())
        self.assertEqual(len(obj.Shape.Solids), 1)
        return obj

    def test_section_in_two_pieces(self):
        fork = Part.makeBox(100, 60, 20).cut(Part.makeBox(70, 20, 20, V(30, 20, 0)))  # a U
        obj = self.stretch(fork, (60, 0, 0), (1, 0, 0), 35)
        wires = fork.slice(V(1, 0, 0), 60.0)
        self.assertEqual(len(wires), 2)
        self.assertAlmostEqual(obj.VolumeChange, 2 * 20 * 20 * 35, delta=1e-6)
        self.assertEqual(len(obj.Shape.Faces), len(fork.Faces))  # no seams left at the joints

    def test_section_with_holes(self):
        plate = Part.makeBox(120, 80, 10)
        for x in (30, 60, 90):
            plate = plate.cut(Part.makeCylinder(6, 10, V(x, 40, 0)))
        obj = self.stretch(plate, (0, 40, 0), (0, 1, 0), 15)  # through the three holes
        area = 120 * 10 - 3 * 12 * 10
        self.assertAlmostEqual(obj.VolumeChange / (area * 15), 1.0, delta=1e-9)
        self.assertEqual({type(f.Surface).__name__ for f in obj.Shape.Faces}, {"Plane", "Cylinder"})
        # each hole is now a stadium: two half cylinders and two planar walls of length 15
        walls = [f for f in obj.Shape.Faces if isinstance(f.Surface, Part.Plane)
                 and abs(f.Area - 15 * 10) < 1e-6]
        self.assertEqual(len(walls), 6)

    def test_two_planes_around_a_taper(self):
        shaft = Part.makeCylinder(10, 30).fuse(
            Part.makeCone(10, 5, 20, V(0, 0, 30))).fuse(Part.makeCylinder(5, 30, V(0, 0, 50)))
        obj = self.stretch(shaft, (0, 0, 30), (0, 0, 1), 10, plane2=(V(0, 0, 50), V(0, 0, 1)))
        self.assertAlmostEqual(obj.Shape.BoundBox.ZMax, 90.0, delta=1e-7)
        # the taper is scaled 1.5x along z: the section at 30 + 1.5 t has the radius at 30 + t.
        # (Its faces are B-splines, whose OCCT Volume is only good to ~1e-2; sections are exact.)
        for t in (2.0, 10.0, 17.5):
            radius = 10 - 5 * t / 20
            area = section_area(obj.Shape, (0, 0, 30 + 1.5 * t), (0, 0, 1))
            self.assertAlmostEqual(area / (np.pi * radius ** 2), 1.0, delta=1e-4)
        self.assertAlmostEqual(section_area(obj.Shape, (0, 0, 70), (0, 0, 1)), np.pi * 25, delta=1e-9)
        self.assertEqual((obj.Continuity, obj.SplitFaces), ("", []))  # the planes cut no face


class StretchFolded(unittest.TestCase):
    """Case 3 (Fig. 4/13): a folded separating surface avoids the faces a flat one would
    cut with C0, so every joint is G1 (Lemma 1), and the volume grows by A * d."""

    def setUp(self):
        self.doc = fc.new_document()
        notch = Part.Face(Part.makePolygon([V(80, 60, 0), V(100, 45, 0), V(120, 60, 0),
                                            V(80, 60, 0)])).extrude(V(0, 0, 20))
        self.shape = Part.makeBox(200, 60, 20).cut(notch)  # two slanted faces at y = 45..60
        self.base = self.doc.addObject("Part::Feature", "Notched")
        self.base.Shape = self.shape

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def test_flat_cut_is_c0_folded_cut_is_g1(self):
        flat = fd.make_stretch(self.base, (V(90, 0, 0), V(1, 0, 0)), 25)
        self.assertIn("C0", flat.Continuity)
        folded = fd.make_stretch(self.base, (V(90, 0, 0), V(1, 0, 0)), 25)
        folded.Polyline = [V(90, -10, 0), V(90, 30, 0), V(140, 50, 0), V(140, 70, 0)]
        self.doc.recompute()
        self.assertNotIn("Invalid", folded.State, folded.getStatusString())
        result = folded.Shape
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        self.assertAlmostEqual(result.Volume - self.shape.Volume, 60 * 20 * 25, delta=1e-6)
        kinds = dict(e.split(": ") for e in folded.Continuity.split("; "))
        self.assertEqual(set(kinds.values()), {"G1"})
        self.assertEqual(len(kinds), 4)  # bottom, top, and the two sides y = 0 and y = 60
        # the notch lies on the near side of the Polyline's surface: untouched, its apex in place
        apex = [v for v in result.Vertexes if abs(v.Point.y - 45) < 1e-9 and v.Point.z == 0]
        self.assertEqual([round(v.Point.x, 9) for v in apex], [100.0])

    def test_folded_shrink(self):
        obj = fd.make_stretch(self.base, (V(90, 0, 0), V(1, 0, 0)), -20)
        obj.Polyline = [V(90, -10, 0), V(90, 30, 0), V(140, 50, 0), V(140, 70, 0)]
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertTrue(obj.Shape.isValid())
        self.assertAlmostEqual(obj.Shape.Volume - self.shape.Volume, -60 * 20 * 20, delta=1e-6)

    def test_bad_polyline_is_an_error(self):
        obj = fd.make_stretch(self.base, (V(90, 0, 0), V(1, 0, 0)), 10)
        obj.Polyline = [V(90, -10, 0), V(95, 30, 0), V(90, 70, 0), V(80, 10, 0)]
        self.doc.recompute()
        self.assertIn("Invalid", obj.State)
        self.assertIn("Polyline", obj.getStatusString())
