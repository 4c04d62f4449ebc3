"""Regression tests of the reliability campaign (issue 11): self-links and cycles, values
that are not finite or huge, values a property cannot hold, failed make_* calls, the Base
only read, the mesh Twist's bound on the turn of one slab.

Oracles: OCCT's Volume of the Base's box (closed form), the document's object list,
FreeCAD's own transaction state, its Mesh.hasSelfIntersections and isSolid.
"""
import os
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Mesh  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry import DeformError  # noqa: E402

V = App.Vector
NAN, INF = float("nan"), float("inf")


class ReliabilityTest(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("Reliability")
        self.box = self.doc.addObject("Part::Feature", "Box")
        self.box.Shape = Part.makeBox(40, 20, 10)

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def assert_refused(self, obj, prop):
        self.assertIn("Invalid", obj.State)
        message = obj.getStatusString()
        self.assertIn(prop, message)
        return message

    def test_self_link_is_refused_and_nothing_grows(self):
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
        self.assertAlmostEqual(s.Shape.Volume, 45 * 200, delta=1e-6)
        s.Base = s
        for _ in range(3):
            s.touch()
            self.doc.recompute()
            self.assert_refused(s, "Base")
            self.assertAlmostEqual(s.Shape.Volume, 45 * 200, delta=1e-6)
        s.Base = self.box
        self.doc.recompute()
        self.assertEqual(s.State, ["Up-to-date"])

    def test_cycle_is_refused_and_reopens_as_saved(self):
        a = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
        b = fd.make_stretch(a, (V(20, 0, 0), V(1, 0, 0)), 5)
        self.assertAlmostEqual(b.Shape.Volume, 50 * 200, delta=1e-6)
        a.Base = b
        self.doc.recompute()
        self.assert_refused(a, "Base")
        self.assertAlmostEqual(a.Shape.Volume, 45 * 200, delta=1e-6)
        path = os.path.join(tempfile.mkdtemp(), "cycle.FCStd")
        self.doc.saveAs(path)
        name = self.doc.Name
        App.closeDocument(name)
        self.doc = App.openDocument(path)
        self.doc.recompute()
        for obj in self.doc.Objects:
            if obj.Name != "Box":
                self.assertLessEqual(obj.Shape.Volume, 50 * 200 + 1e-6, obj.Name)

    def test_values_that_are_not_finite_are_refused(self):
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
        for value in (NAN, INF, -INF):
            s.Distance = value
            self.doc.recompute()
            self.assert_refused(s, "Distance")
        s.Distance = 5
        s.Plane = App.Placement(V(NAN, 0, 0), App.Rotation())
        self.doc.recompute()
        self.assert_refused(s, "Plane")
        b = fd.make_bend(self.box, (V(20, 0, 0), V(1, 0, 0)), -30, (V(20, 0, 40), V(0, 1, 0)))
        self.assertEqual(b.State, ["Up-to-date"])
        b.Axis = App.Placement(V(20, INF, 40), App.Rotation(V(0, 0, 1), V(0, 1, 0)))
        self.doc.recompute()
        self.assert_refused(b, "Axis")
        self.assertAlmostEqual(self.box.Shape.Volume, 8000.0, delta=1e-9)

    def test_dimension_drive_gets_the_same_checks(self):
        """DimensionDrive writes its own execute(): a self-link and a NaN Target are refused
        all the same, naming Base and Target; the mesh stays as the last good result."""
        import Mesh
        mesh = self.doc.addObject("Mesh::Feature", "Mesh")
        mesh.Mesh = Mesh.Mesh(self.box.Shape.tessellate(0.1))
        d = fd.make_dimension_drive(mesh, "Distance", [(20, 10, 10), (20, 10, 0)], 12)
        self.assertEqual(d.State, ["Up-to-date"], d.getStatusString())
        self.assertAlmostEqual(d.Mesh.BoundBox.ZLength, 12.0, delta=1e-5)
        d.Target = NAN
        self.doc.recompute()
        self.assert_refused(d, "Target")
        d.Target = 12
        d.Base = d
        for _ in range(2):
            d.touch()
            self.doc.recompute()
            self.assert_refused(d, "Base")
        self.assertAlmostEqual(d.Mesh.BoundBox.ZLength, 12.0, delta=1e-5)

    def test_push_to_a_target_that_is_not_finite_is_refused(self):
        e = self.doc.addObject("Part::Feature", "Curve")
        e.Shape = Part.makeCircle(10)
        p = fd.make_direct_push(e, "Edge1", V(0, 10, 0), V(0, 12, 0))
        self.assertEqual(p.State, ["Up-to-date"])
        p.Targets = [V(NAN, 0, 0)]
        self.doc.recompute()
        self.assert_refused(p, "Targets")

    def test_twist_axis_off_the_normal_is_refused(self):
        t = fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)), 40,
                          axis=(V(0, 10, 5), V(1, 0, 0)))
        self.assertEqual(t.State, ["Up-to-date"])
        self.assertAlmostEqual(t.Shape.BoundBox.XLength, 40, delta=1e-7)  # length kept
        t.Axis = App.Placement(V(0, 10, 5), App.Rotation(V(0, 0, 1), V(1, 0, 1)))
        self.doc.recompute()
        self.assertIn("45 degrees", self.assert_refused(t, "Axis"))

    def test_twist_of_two_turns(self):
        """make_twist(720), Angle 0 + Turns 2 and Angle set to 720 deg are one request: the
        far part back where it was (a 720 deg turn), the volume kept, the section an eighth
        of the way along turned by 90 deg (its bounding box 10 x 30 instead of 30 x 10).
        Infinite is refused."""
        bar = self.doc.addObject("Part::Feature", "Bar")
        bar.Shape = Part.makeBox(30, 10, 100, V(-15, -5, 0))
        t = fd.make_twist(bar, (V(0, 0, 20), V(0, 0, 1)), (V(0, 0, 80), V(0, 0, 1)), 720)
        t.Samples = 96
        self.doc.recompute()
        self.assertEqual((t.Angle.Value, t.Turns), (0.0, 2))
        self.assert_two_turns(t)
        t.Turns = 0
        t.Angle = 720  # held as given: an angle property would clamp it to 360
        self.assertEqual(t.Angle.Value, 720.0)
        self.doc.recompute()
        self.assert_two_turns(t)
        t2 = fd.make_twist(bar, (V(0, 0, 20), V(0, 0, 1)), (V(0, 0, 80), V(0, 0, 1)), INF)
        self.assert_refused(t2, "Angle")

    def assert_two_turns(self, t):
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        self.assertAlmostEqual(t.Shape.Volume / 30000.0, 1.0, delta=1e-3)
        top = sorted(tuple(round(c, 6) for c in v.Point) for v in t.Shape.Vertexes
                     if abs(v.Point.z - 100) < 1e-9)
        self.assertEqual(top, sorted((x, y, 100.0) for x in (-15.0, 15.0) for y in (-5.0, 5.0)))
        wires = t.Shape.slice(V(0, 0, 1), 27.5)
        box = Part.makeFace(wires, "Part::FaceMakerBullseye").BoundBox
        self.assertAlmostEqual(box.XLength, 10.0, delta=0.05)
        self.assertAlmostEqual(box.YLength, 30.0, delta=0.05)

    def test_twist_angle_of_an_older_document(self):
        """A document saved when Twist's Angle was a PropertyAngle (bounded at 360 deg) opens
        with the unbounded quantity, its value and expression kept; the degree unit, which
        FreeCAD does not save, is back after reopening."""
        t = fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)), 40)
        t.removeProperty("Angle")
        t.addProperty("App::PropertyAngle", "Angle", "Motion", "")
        t.setExpression("Angle", "30 deg + 20 deg")
        self.doc.recompute()
        path = os.path.join(tempfile.mkdtemp(), "old_twist.FCStd")
        self.doc.saveAs(path)
        name = t.Name
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        t = self.doc.getObject(name)
        self.assertEqual(t.getTypeIdOfProperty("Angle"), "App::PropertyQuantity")
        self.assertEqual(str(t.Angle.Unit), str(App.Units.Unit("deg")))
        self.assertEqual(t.Angle.Value, 50.0)
        self.assertEqual(dict(t.ExpressionEngine)["Angle"].replace(" ", ""), "30deg+20deg")
        t.Angle = 400
        self.assertEqual(t.Angle.Value, 400.0)

    def test_infinite_length_is_refused(self):
        """A PropertyLength clamps infinity to the largest float; that is refused as
        infinite too (naming Tolerance), not squared into an OverflowError."""
        t = fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)), 40)
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        t.Tolerance = INF
        self.doc.recompute()
        self.assert_refused(t, "Tolerance")

    def test_samples_beyond_the_bound_are_refused(self):
        t = fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)), 40)
        for samples in (1, 10 ** 6):
            t.Samples = samples
            self.doc.recompute()
            self.assert_refused(t, "Samples")

    def test_plane_at_a_cone_apex(self):
        """1e-6 below the apex the tip moves (valid, apex at 20 + 5); within the modelling
        tolerance (1e-8) the plane only touches the part: refused naming Plane."""
        cone = self.doc.addObject("Part::Feature", "Cone")
        cone.Shape = Part.makeCone(10, 0, 20)
        s = fd.make_stretch(cone, (V(0, 0, 20 - 1e-6), V(0, 0, 1)), 5)
        self.assertEqual(s.State, ["Up-to-date"])
        self.assertTrue(s.Shape.isValid())
        self.assertAlmostEqual(s.Shape.BoundBox.ZMax, 25.0, delta=1e-6)
        s.Plane = App.Placement(V(0, 0, 20 - 1e-8), App.Rotation())
        self.doc.recompute()
        self.assert_refused(s, "Plane")

    def test_free_face_in_a_compound_is_swept_not_torn(self):
        """A box and a free face 40 x 10 beside it: Stretch by 5 gives one sheet of area
        45 x 10 (the strip swept by the cut edge), Bend adds the cut edge's revolved strip
        (its length times the arc of its distance to the axis); no open gap."""
        sheet = Part.Face(Part.makePolygon([V(0, 30, 0), V(40, 30, 0), V(40, 30, 10),
                                            V(0, 30, 10), V(0, 30, 0)]))
        self.box.Shape = Part.makeCompound([Part.makeBox(40, 20, 10), sheet])
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
        self.assertEqual(s.State, ["Up-to-date"])
        faces = [f for f in s.Shape.Faces if abs(f.CenterOfMass.y - 30) < 1e-9]
        self.assertAlmostEqual(sum(f.Area for f in faces), 450.0, delta=1e-9)
        free = [e for sh in s.Shape.Shells if abs(sh.CenterOfMass.y - 30) < 1e-9
                for e in sh.Edges if len(sh.ancestorsOfType(e, Part.Face)) == 1]
        self.assertAlmostEqual(sum(e.Length for e in free), 2 * (45 + 10), delta=1e-9)
        b = fd.make_bend(self.box, (V(20, 0, 0), V(1, 0, 0)), -30, (V(20, 0, 40), V(0, 1, 0)))
        self.assertEqual(b.State, ["Up-to-date"], b.getStatusString())
        strip = sum(f.Area for f in b.Shape.Faces if abs(f.CenterOfMass.y - 30) < 1e-9)
        arc = np.radians(30) * (40 * 10 - 10 ** 2 / 2)  # integral of angle * (40 - z), z 0..10
        self.assertAlmostEqual(strip, 400.0 + arc, delta=1e-6)

    def test_stretch_of_free_surfaces_alone(self):
        """A compound of B-spline surfaces and no solid (splinecage.stp): stretched, every
        cut surface closed again by its swept strip."""
        shape = Part.Shape()
        shape.read(fc.testdata("splinecage.stp"))
        self.box.Shape = shape
        bb = shape.BoundBox
        s = fd.make_stretch(self.box, (bb.Center, V(1, 0, 0)), 10)
        self.assertEqual(s.State, ["Up-to-date"], s.getStatusString())
        self.assertAlmostEqual(s.Shape.BoundBox.XLength, bb.XLength + 10, delta=1e-6)
        before = sum(f.Area for f in shape.Faces)
        cut = sum(e.Length for e in shape.slice(V(1, 0, 0), bb.Center.x) for e in e.Edges)
        self.assertAlmostEqual(sum(f.Area for f in s.Shape.Faces), before + 10 * cut,
                               delta=1e-4 * before)

    def test_below_the_modelling_tolerance_nothing_moves(self):
        """Distance or Angle 1e-12 (OCCT's sweeps fail there): the Base's shape, unchanged."""
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 1e-12)
        b = fd.make_bend(self.box, (V(20, 0, 0), V(1, 0, 0)), -1e-12,
                         (V(20, 0, 40), V(0, 1, 0)))
        for obj in (s, b):
            self.assertEqual(obj.State, ["Up-to-date"], obj.getStatusString())
            self.assertAlmostEqual(obj.Shape.Volume, 8000.0, delta=1e-9)
            self.assertTrue(obj.Shape.BoundBox.isInside(self.box.Shape.BoundBox))
            self.assertTrue(self.box.Shape.BoundBox.isInside(obj.Shape.BoundBox))

    def test_shrink_limit_is_given_unrounded(self):
        """The part reaches 20 beyond Plane: -19.9999999 works (a sliver stays), the message
        for -20.5 gives the limit with its digits."""
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), -20.5)
        message = self.assert_refused(s, "Distance")
        self.assertIn("above -19.9999999", message)
        s.Distance = -19.99999
        self.doc.recompute()
        self.assertEqual(s.State, ["Up-to-date"], s.getStatusString())
        self.assertAlmostEqual(s.Shape.BoundBox.XLength, 20.00001, delta=1e-9)

    def test_base_of_another_kind_is_refused(self):
        """A Stretch made on a solid whose Base becomes a mesh, and a Base with an empty
        shape: both name Base."""
        import Mesh
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
        mesh = self.doc.addObject("Mesh::Feature", "Mesh")
        mesh.Mesh = Mesh.Mesh(self.box.Shape.tessellate(0.1))
        s.Base = mesh
        self.doc.recompute()
        self.assertIn("mesh", self.assert_refused(s, "Base"))
        empty = self.doc.addObject("Part::Feature", "Empty")
        s.Base = empty
        self.doc.recompute()
        self.assertIn("empty", self.assert_refused(s, "Base"))

    def test_make_on_an_empty_base_opens_no_transaction(self):
        """An empty mesh as Base: make_* refuses it naming Base before anything is opened;
        the application has no transaction left active (FreeCAD keeps one open when a
        transaction was opened and nothing was recorded)."""
        import Mesh
        empty = self.doc.addObject("Mesh::Feature", "Empty")
        empty.Mesh = Mesh.Mesh()
        names = [o.Name for o in self.doc.Objects]
        with self.assertRaises(ValueError) as raised:  # DeformError
            fd.make_bend(empty, (V(20, 0, 0), V(1, 0, 0)), 30, (V(20, 0, 40), V(0, 1, 0)))
        self.assertIn("Base", str(raised.exception))
        self.assertEqual([o.Name for o in self.doc.Objects], names)
        self.assertFalse(self.doc.HasPendingTransaction)
        self.assertIsNone(App.getActiveTransaction())

    def test_oblique_plane_through_base_vertices_keeps_its_tolerances(self):
        """The issue's case: plane x + 2y = 0 through four vertices of a box (and a compound
        with a free face): the Base's vertex, edge and face tolerances stay 1e-7."""
        sheet = Part.Face(Part.makePolygon([V(-10, 30, 0), V(10, 30, 0), V(10, 30, 10),
                                            V(-10, 30, 10), V(-10, 30, 0)]))
        self.box.Shape = Part.makeCompound([Part.makeBox(40, 20, 10, V(-20, -10, 0)), sheet])
        tolerances = [x.Tolerance for x in self.box.Shape.Vertexes + self.box.Shape.Edges
                      + self.box.Shape.Faces]
        normal = V(1, 2, 0).normalize()
        fd.make_stretch(self.box, (V(0, 0, 0), normal), 5)
        fd.make_bend(self.box, (V(0, 0, 0), normal), 20, (V(0, 0, 40), V(2, -1, 0)))
        self.doc.recompute()
        self.assertEqual(tolerances, [x.Tolerance for x in self.box.Shape.Vertexes
                                      + self.box.Shape.Edges + self.box.Shape.Faces])

    def test_planes_closer_than_the_tolerance_are_refused(self):
        t = fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(10 + 1e-7, 0, 0), V(1, 0, 0)),
                          -720)
        self.assert_refused(t, "Plane2")

    def test_twist_of_a_thin_region_keeps_the_far_part(self):
        """Planes 0.001 mm apart across a sphere: the slab between them has every vertex
        and edge on the planes, and OCCT's centre of mass put it beyond Plane2; the far
        part was then dropped (6,011 of 14,137 mm^3, Up-to-date). Oracle: 4/3 pi r^3."""
        ball = self.doc.addObject("Part::Feature", "Ball")
        ball.Shape = Part.makeSphere(15)
        t = fd.make_twist(ball, (V(-1.5, 0, 0), V(1, 0, 0)), (V(-1.499, 0, 0), V(1, 0, 0)),
                          1e-12)
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        self.assertTrue(t.Shape.isValid())
        self.assertAlmostEqual(t.Shape.Volume / (4.0 / 3.0 * np.pi * 15 ** 3), 1.0, delta=1e-6)

    def test_taper_of_curved_solids_passes_the_bop_check(self):
        """A taper across a sphere and a torus: sewing left edge tolerances a hair below
        their pcurve gaps (2.369e-7 against 2.36e-7; 5.2e-7 against 4.9e-7), which OCCT's
        BOP check (the oracle) rejects though isValid() passes."""
        for name, shape, planes in (("Ball", Part.makeSphere(15), (0.0, 3.0)),
                                    ("Ring", Part.makeTorus(15, 4), (2.0, 4.0))):
            base = self.doc.addObject("Part::Feature", name)
            base.Shape = shape
            t = fd.make_taper(base, (V(planes[0], 0, 0), V(1, 0, 0)),
                              (V(planes[1], 0, 0), V(1, 0, 0)), 1.6)
            self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
            for solid in t.Shape.Solids:
                solid.check(True)  # raises with the BOP check's findings

    def test_plane_touching_a_void_at_its_seam(self):
        """Plane x = 5 touches a spherical void (radius 5) at a point of its seam: merging
        the faces across the joint left the void's face unorientable (isValid() false,
        Up-to-date). Oracle: isValid() and the closed form 40*20*20 - 4/3 pi 5^3 + A*d."""
        part = self.doc.addObject("Part::Feature", "Voided")
        part.Shape = Part.makeBox(40, 20, 20, V(-20, -10, -10)).cut(Part.makeSphere(5))
        for d in (1.0, -6.103515625e-05):
            s = fd.make_stretch(part, (V(5, 0, 0), V(1, 0, 0)), d)
            self.assertEqual(s.State, ["Up-to-date"], s.getStatusString())
            self.assertTrue(s.Shape.isValid())
            self.assertAlmostEqual(s.Shape.Volume, 16000 - 4 / 3 * np.pi * 125 + 400 * d,
                                   delta=1e-6)

    def test_cloud_stretch_beyond_any_memory_is_refused(self):
        """A point cloud stretched by 1e8 mm would fill the gap with 1e8 points (a 2.4 GB
        array; 1e12 mm, 1.46 TiB, a MemoryError, is now beyond the 1e9 mm every length
        keeps below); it is refused naming Distance, and fast."""
        cloud = self.doc.addObject("Points::Feature", "Cloud")
        cloud.Points = Points.Points([(x, y, 0.0) for x in range(-20, 21, 5)
                                      for y in range(-10, 11, 5)])
        s = fd.make_stretch(cloud, (V(0.5, 0, 0), V(1, 0, 0)), 1e8)
        self.assertIn("keep Distance below", self.assert_refused(s, "Distance"))

    def test_bend_by_nothing_of_a_reversed_solid(self):
        """A reversed box bent by 0 deg came back reversed (volume -8000): the result is
        the oriented solid. Oracle: OCCT's Volume of the box, 40 * 20 * 10."""
        flipped = self.doc.addObject("Part::Feature", "Flipped")
        flipped.Shape = self.box.Shape.reversed()
        self.assertLess(flipped.Shape.Volume, 0)
        b = fd.make_bend(flipped, (V(20, 0, 0), V(1, 0, 0)), 0.0, (V(20, 0, 40), V(0, 1, 0)))
        self.assertEqual(b.State, ["Up-to-date"], b.getStatusString())
        self.assertAlmostEqual(b.Shape.Volume, 8000.0, delta=1e-6)

    def test_drive_of_a_solid_tessellated_too_finely_is_refused(self):
        """DimensionDrive on a solid tessellates it with Tolerance; at 1e-9 mm OCCT's mesher
        throws a C++ exception that no Python code can catch (the process then runs on
        corrupted). Tolerance below 1e-4 of the solid's size is refused naming it."""
        ring = self.doc.addObject("Part::Feature", "Ring")
        ring.Shape = Part.makeTorus(15, 4)
        mesh = self.doc.addObject("Mesh::Feature", "BoxMesh")
        mesh.Mesh = Mesh.Mesh(self.box.Shape.tessellate(0.1))
        drive = fd.make_dimension_drive(mesh, "Distance", [V(20, 10, 10), V(20, 10, 0)], 12)
        self.assertEqual(drive.State, ["Up-to-date"], drive.getStatusString())
        drive.Tolerance = 1e-12
        drive.Base = ring
        self.doc.recompute()
        self.assertIn("raise Tolerance", self.assert_refused(drive, "Tolerance"))

    def test_area_beyond_a_valid_face_is_refused(self):
        """A sphere's face asked for 1e12 times its area (Dof Z) reached it with poles
        3e13 mm away and a face that fails isValid(), yet Up-to-date. Oracle: OCCT's
        isValid() of the face the op builds; refused naming TargetRatio."""
        ball = self.doc.addObject("Part::Feature", "Ball")
        ball.Shape = Part.makeSphere(15)
        a = fd.make_area_constrain(ball, "Face1", "1e14%", dof="Z")
        self.assertIn("nearer the original", self.assert_refused(a, "TargetRatio"))
        self.assertTrue(ball.Shape.isValid())

    def test_taper_of_a_cone_passes_the_bop_check(self):
        """A cone tapered up to its apex region: an edge's tolerance (2.21e-7) covered the
        sampled pcurve gap (2.16e-7) but not the peak OCCT's BOP check (the oracle) finds."""
        cone = self.doc.addObject("Part::Feature", "Cone")
        cone.Shape = Part.makeCone(10, 0, 40, V(-20, 0, 0), V(1, 0, 0))
        t = fd.make_taper(cone, (V(0, 0, 0), V(1, 0, 0)),
                          (V(16.05768740177155, 0, 0), V(1, 0, 0)), 1.563738855137635)
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        for solid in t.Shape.Solids:
            solid.check(True)

    def test_taper_to_nothing_is_refused(self):
        """A cylinder 16 mm across tapered to Scale 0.001 got refitted faces that fold (BOP
        check: SelfIntersect), Up-to-date; Scale 0.01 stays valid and self-intersection
        free (the oracle: OCCT's BOP check)."""
        rod = self.doc.addObject("Part::Feature", "Rod")
        rod.Shape = Part.makeCylinder(8, 40, V(-20, 0, 0), V(1, 0, 0))
        t = fd.make_taper(rod, (V(0.1, 0, 0), V(1, 0, 0)), (V(2.6, 0, 0), V(1, 0, 0)), 0.001)
        self.assertIn("keep Scale at", self.assert_refused(t, "Scale"))
        t.Scale = 0.01
        self.doc.recompute()
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        t.Shape.Solids[0].check(True)

    def test_steep_taper_is_refused_fast(self):
        """Scale 2.43 over 0.0007 mm of a cone: OCCT's fuzzy fuse of the refit faces never
        returned (5 minutes and more); refused naming Plane2, with the gap that would do."""
        cone = self.doc.addObject("Part::Feature", "Cone")
        cone.Shape = Part.makeCone(10, 0, 40, V(-20, 0, 0), V(1, 0, 0))
        t = fd.make_taper(cone, (V(0, 0, 0), V(1, 1, 0)), (V(0.001, 0, 0), V(1, 1, 0)), 2.4347)
        self.assertIn("move Plane2 farther", self.assert_refused(t, "Plane2"))

    def test_steep_taper_names_the_scale_that_makes_it_steep(self):
        """Scale (1, 3) over 0.01 mm: the refusal names Scale 3 (the one far from 1), not 1."""
        box = self.doc.addObject("Part::Feature", "Box")
        box.Shape = Part.makeBox(40, 20, 20, V(-20, -10, -10))
        t = fd.make_taper(box, (V(0, 0, 0), V(1, 0, 0)), (V(0.01, 0, 0), V(1, 0, 0)), (1.0, 3.0))
        self.assertIn("Scale 3 over", self.assert_refused(t, "Plane2"))

    def test_twist_through_a_void_near_its_poles(self):
        """Plane 0.0026 mm off a spherical void's poles: the void came back in two shells and
        the volume grew by 466 mm^3, Up-to-date; now refused naming Plane2, and with Plane
        moved to x = 0.5 the volume is kept (oracle: 40*20*20 - 4/3 pi 5^3, one void)."""
        part = self.doc.addObject("Part::Feature", "Voided")
        part.Shape = Part.makeBox(40, 20, 20, V(-20, -10, -10)).cut(Part.makeSphere(5))
        t = fd.make_twist(part, (V(-0.0025634765625, 0, 0), V(1, 0, 0)),
                          (V(2.4896240266971295, 0, 0), V(1, 0, 0)), 170)
        self.assertIn("voids", self.assert_refused(t, "Plane2"))
        t.Plane = App.Placement(V(0.5, 0, 0), App.Rotation(V(0, 0, 1), V(1, 0, 0)))
        self.doc.recompute()
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        self.assertEqual(len(t.Shape.Solids[0].Shells), 2)
        self.assertAlmostEqual(t.Shape.Volume, 16000 - 4 / 3 * np.pi * 125, delta=1e-3)

    def test_failed_make_leaves_the_document_as_it_was(self):
        for undo_mode in (0, 1):
            self.doc.UndoMode = undo_mode
            names = [o.Name for o in self.doc.Objects]
            with self.assertRaises(ValueError):
                fd.make_area_constrain(self.box, "Face1", 900.0, dof="Sideways")
            with self.assertRaises(TypeError):
                fd.make_dimension_drive(self.box, "Distance", [(0, 0, 10), (0, 0, 0)], 5,
                                        colour="red")
            self.assertEqual([o.Name for o in self.doc.Objects], names)
            self.assertTrue(self.box.Visibility)
            self.assertFalse(self.doc.HasPendingTransaction)
            self.assertIsNone(App.getActiveTransaction())
            # a later success is one object, and one undo step where undo is on
            s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 5)
            self.assertIsNone(App.getActiveTransaction())
            self.doc.removeObject(s.Name)
            self.box.Visibility = True


    def test_lengths_beyond_1e9_mm_are_refused_naming_the_property(self):
        """1e8 mm is stretched (Volume 8000 + 200 x 1e8); 2e9 mm and a Plane at 1e12 mm are
        refused naming Distance and Plane (4d43f99: OCCT's 'gp_Dir() - input vector has
        zero norm' for 1e200), the Base untouched; a DirectPush target at 1e12 mm names
        Targets (4d43f99: 'BRepExtrema_DistShapeShape failed')."""
        s = fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), 1e8)
        self.assertEqual(s.State, ["Up-to-date"], s.getStatusString())
        self.assertAlmostEqual(s.Shape.Volume / (8000 + 200 * 1e8), 1.0, delta=1e-9)
        for prop, value in (("Distance", 2e9), ("Distance", 1e200),
                            ("Plane", App.Placement(V(1e12, 0, 0), App.Rotation()))):
            keep = getattr(s, prop)
            setattr(s, prop, value)
            self.doc.recompute()
            self.assert_refused(s, prop)
            self.assertIn("1e9 mm", s.getStatusString())
            setattr(s, prop, keep)
        self.assertAlmostEqual(self.box.Shape.Volume, 8000.0, delta=1e-9)
        face = self.doc.addObject("Part::Feature", "Face")
        surface = Part.BSplineSurface()
        surface.interpolate([[V(10 * i, 10 * j, (i * j) % 3) for j in range(6)]
                             for i in range(6)])
        face.Shape = surface.toShape()
        p = fd.make_direct_push(face, "Face1", V(25, 25, 1), V(25, 25, 1e12))
        self.assert_refused(p, "Targets")

    def test_make_twist_beyond_the_turn_count_leaves_nothing(self):
        before = [o.Name for o in self.doc.Objects]
        with self.assertRaises(DeformError) as caught:
            fd.make_twist(self.box, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)),
                          1e300)
        self.assertEqual(caught.exception.prop, "Angle")
        self.assertEqual([o.Name for o in self.doc.Objects], before)

    def test_make_with_a_value_its_property_cannot_hold(self):
        """FreeCAD's refusal to set a property (a parser or type error) is a DeformError
        naming it; the object is removed and the Base shown again."""
        before = [o.Name for o in self.doc.Objects]
        for value in ("abc", [1, 2]):
            with self.assertRaises(DeformError) as caught:
                fd.make_stretch(self.box, (V(20, 0, 0), V(1, 0, 0)), value)
            self.assertEqual(caught.exception.prop, "Distance")
            self.assertEqual([o.Name for o in self.doc.Objects], before)
            self.assertTrue(self.box.Visibility)

    def test_mesh_twist_turns_a_slab_by_at_most_45_degrees(self):
        """A thin-walled C section twisted 60 deg per slab (Samples 16, 960 deg) crosses
        itself (FreeCAD's hasSelfIntersections; 4d43f99 marked it Up-to-date): refused
        naming Samples and the count it needs (22); with 22 Samples the result is a closed
        solid without self-intersections."""
        c = Part.makeBox(40, 30, 30).cut(Part.makeBox(40, 26, 26, V(0, 2, 2))).cut(
            Part.makeBox(40, 4, 10, V(0, 26, 10)))
        mesh = self.doc.addObject("Mesh::Feature", "C")
        mesh.Mesh = Mesh.Mesh(c.tessellate(0.3))
        t = fd.make_twist(mesh, (V(10, 0, 0), V(1, 0, 0)), (V(30, 0, 0), V(1, 0, 0)), 960)
        self.assert_refused(t, "Samples")
        self.assertIn("at least 22", t.getStatusString())
        t.Samples = 22
        self.doc.recompute()
        self.assertEqual(t.State, ["Up-to-date"], t.getStatusString())
        self.assertTrue(t.Mesh.isSolid())
        self.assertFalse(t.Mesh.hasSelfIntersections())

if __name__ == "__main__":
    unittest.main()
