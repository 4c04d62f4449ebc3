"""AreaConstrain on real FreeCAD documents: a bicubic canopy face, a solid with a B-spline
top, a cylinder face (converted), errors, undo, save and reopen.

Oracle: the test's own Gauss-Legendre area, evaluating OCCT's surface derivatives
(Surface.getDN) at 12 nodes per knot span, independent of the add-on's basis matrices;
which poles moved is read off Surface.getPoles() before and after.
"""
import os
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector


def canopy_surface(n=6):
    xs, ys = np.linspace(0, 100, n), np.linspace(0, 60, n)
    poles = [[V(x, y, 25 * np.sin(np.pi * x / 100) * np.sin(np.pi * y / 60) + 0.1 * x)
              for y in ys] for x in xs]
    knots = list(np.linspace(0, 1, n - 2))
    mults = [4] + [1] * (n - 4) + [4]
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(poles, mults, mults, knots, knots, False, False, 3, 3)
    return s


def occt_area(surface, nodes=12):
    """Area by Gauss-Legendre over every knot span, with OCCT's own first derivatives."""
    x, w = np.polynomial.legendre.leggauss(nodes)

    def grid(knots):
        k = np.asarray(knots)
        half = np.diff(k) / 2
        return ((k[:-1] + k[1:])[:, None] / 2 + half[:, None] * x).ravel(), \
            (half[:, None] * w).ravel()
    (u, wu), (v, wv) = grid(surface.getUKnots()), grid(surface.getVKnots())
    total = 0.0
    for a, wa in zip(u, wu):
        for b, wb in zip(v, wv):
            total += wa * wb * surface.getDN(a, b, 1, 0).cross(surface.getDN(a, b, 0, 1)).Length
    return total


def poles(surface):
    return np.array([[tuple(p) for p in row] for row in surface.getPoles()])


class AreaCase(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("AreaConstrain")
        self.canopy = self.doc.addObject("Part::Feature", "Canopy")
        self.canopy.Shape = Part.Face(canopy_surface())
        self.doc.recompute()
        self.area0 = occt_area(canopy_surface())

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def result_surface(self, obj):
        return obj.Shape.Faces[0].Surface

    def assertValid(self, obj):
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())


class TestPaperCases(AreaCase):
    def test_all_interior_poles_along_normals(self):
        obj = fd.make_area_constrain(self.canopy, "Face1", "105%")
        self.assertValid(obj)
        new = self.result_surface(obj)
        self.assertAlmostEqual(occt_area(new) / (1.05 * self.area0), 1, delta=1e-10)
        self.assertAlmostEqual(obj.OriginalArea / self.area0, 1, delta=1e-12)
        self.assertAlmostEqual(obj.AchievedArea / (1.05 * self.area0), 1, delta=1e-13)
        moved = np.abs(poles(new) - poles(canopy_surface())).max(axis=2) > 0
        expected = np.zeros((6, 6), bool)
        expected[1:-1, 1:-1] = True
        np.testing.assert_array_equal(moved, expected)
        self.assertEqual((new.UDegree, new.VDegree, new.getUKnots()),
                         (3, 3, canopy_surface().getUKnots()))
        self.assertLess(obj.KKTResidual, 1e-9)
        self.assertGreater(obj.Iterations, 0)

    def test_one_pole_z_only(self):
        obj = fd.make_area_constrain(self.canopy, "Face1", 1.025 * self.area0, poles=[(2, 3)],
                                     dof="Z")
        self.assertValid(obj)
        d = poles(self.result_surface(obj)) - poles(canopy_surface())
        self.assertAlmostEqual(occt_area(self.result_surface(obj)) / (1.025 * self.area0), 1,
                               delta=1e-10)
        self.assertEqual(list(zip(*np.nonzero(d))), [(1, 2, 2)])     # pole (2, 3), z only
        self.assertAlmostEqual(obj.MaxPoleMove, abs(d[1, 2, 2]), delta=1e-12)

    def test_four_poles_z_only_minus(self):
        obj = fd.make_area_constrain(self.canopy, "Face1", 0.975 * self.area0,
                                     poles=[(3, 3), (3, 4), (4, 3), (4, 4)], dof="Z")
        self.assertValid(obj)
        self.assertAlmostEqual(occt_area(self.result_surface(obj)) / (0.975 * self.area0), 1,
                               delta=1e-10)

    def test_six_free_poles(self):
        obj = fd.make_area_constrain(self.canopy, "Face1", "105%",
                                     poles=[(2, 2), (2, 3), (3, 2), (3, 3), (4, 4), (4, 5)],
                                     dof="Free")
        self.assertValid(obj)
        self.assertAlmostEqual(occt_area(self.result_surface(obj)) / (1.05 * self.area0), 1,
                               delta=1e-10)
        self.assertLess(obj.KKTResidual, 1e-9)

    def test_half_the_area_with_one_pole_is_an_error_and_the_base_stays(self):
        before = poles(self.canopy.Shape.Faces[0].Surface)
        obj = fd.make_area_constrain(self.canopy, "Face1", "50%", poles=[(3, 3)], dof="Z")
        self.assertIn("Invalid", obj.State)
        self.assertRegex(obj.getStatusString(), r"TargetArea .* smallest area they give is")
        np.testing.assert_array_equal(poles(self.canopy.Shape.Faces[0].Surface), before)


class TestShapes(AreaCase):
    def test_a_solid_gets_its_face_replaced(self):
        solid = self.doc.addObject("Part::Feature", "Roof")
        solid.Shape = Part.Face(canopy_surface()).extrude(V(0, 0, -20))
        self.doc.recompute()
        index = next(i for i, f in enumerate(solid.Shape.Faces)
                     if f.Surface.TypeId == "Part::GeomBSplineSurface")
        obj = fd.make_area_constrain(solid, f"Face{index + 1}", "110%")
        self.assertValid(obj)
        self.assertTrue(obj.Replaced)
        shape = obj.Shape
        self.assertEqual(len(shape.Solids), 1)
        self.assertTrue(shape.isValid())
        self.assertEqual(len(shape.Faces), len(solid.Shape.Faces))
        top = next(f for f in shape.Faces if f.Surface.TypeId == "Part::GeomBSplineSurface")
        self.assertAlmostEqual(occt_area(top.Surface) / (1.1 * self.area0), 1, delta=1e-10)
        self.assertGreater(shape.Volume, solid.Shape.Volume)

    def test_a_cylinder_face_is_converted_exactly(self):
        cyl = self.doc.addObject("Part::Feature", "Cylinder")
        cyl.Shape = Part.makeCylinder(5, 20)
        self.doc.recompute()
        obj = fd.make_area_constrain(cyl, "Face1", "110%", poles=[(2, 1), (2, 2)], dof="Free")
        self.assertValid(obj)
        self.assertIn("Cylinder converted exactly", obj.Conversion)
        self.assertAlmostEqual(obj.OriginalArea, 2 * np.pi * 5 * 20, delta=1e-9)
        self.assertAlmostEqual(obj.AchievedArea / obj.OriginalArea, 1.1, delta=1e-12)
        self.assertFalse(obj.Replaced)                # a boundary pole moved: the face alone

    def test_bad_face_and_pole_name_the_property(self):
        obj = fd.make_area_constrain(self.canopy, "Face7", "105%")
        self.assertIn("Face", obj.getStatusString())
        obj.Face = "Face1"
        obj.Poles = ["9,9"]
        self.doc.recompute()
        self.assertIn("Pole (9, 9) is outside", obj.getStatusString())

    def test_undo_and_reopen(self):
        before = len(self.doc.Objects)
        obj = fd.make_area_constrain(self.canopy, "Face1", "105%")
        name = obj.Name
        self.doc.undo()
        self.assertEqual(len(self.doc.Objects), before)
        self.doc.redo()
        path = os.path.join(tempfile.mkdtemp(), "area.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        again = self.doc.getObject(name)
        again.TargetRatio = 0.0
        again.TargetArea = 1.02 * self.area0
        self.doc.recompute()
        self.assertValid(again)
        self.assertAlmostEqual(again.AchievedArea / (1.02 * self.area0), 1, delta=1e-13)


if __name__ == "__main__":
    unittest.main()
