"""Huge values and values a property cannot hold (the reliability rules: huge numbers are
inputs too, the error names the property, a failed make_* leaves nothing behind), and the
mesh Twist's bound on the turn of one slab.

Oracles: OCCT's Volume against A * d, the document's object list, FreeCAD's own
Mesh.hasSelfIntersections and isSolid.
"""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry import DeformError  # noqa: E402

V = App.Vector


class HugeValuesTest(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("Huge")
        self.box = self.doc.addObject("Part::Feature", "Box")
        self.box.Shape = Part.makeBox(40, 20, 10)

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def assert_refused(self, obj, prop):
        self.assertIn("Invalid", obj.State)
        self.assertIn(prop, obj.getStatusString())

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
