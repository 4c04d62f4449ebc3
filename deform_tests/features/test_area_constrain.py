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
        self.assertIn("Poles: pole (9, 9) is outside", obj.getStatusString())

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


def part_surface(arrays):
    """A Part.BSplineSurface from numpy arrays (deform_tests/oracles/nurbs.py)."""
    def knots_mults(full):
        k, m = np.unique(full, return_counts=True)
        return [float(x) for x in k], [int(x) for x in m]
    uk, um = knots_mults(arrays.uknots)
    vk, vm = knots_mults(arrays.vknots)
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots([[V(*p) for p in row] for row in arrays.poles.tolist()],
                               um, vm, uk, vk, False, False, arrays.udegree, arrays.vdegree)
    return s


def graded_area(surface, toward):
    """The area of a Part.BSplineSurface (non-rational) by scipy's BSpline on OCCT's poles
    and knots, Gauss-Legendre (30 nodes) on every knot span and on a grid graded
    geometrically toward the corner `toward` (u, v), where |S_u x S_v| -> 0."""
    from ..oracles.nurbs import own_area
    from freecad_deform.geometry.nurbs.bspline_area import Surface
    full = [np.repeat(k, m) for k, m in ((surface.getUKnots(), surface.getUMultiplicities()),
                                         (surface.getVKnots(), surface.getVMultiplicities()))]
    arrays = Surface(poles(surface), np.ones((surface.NbUPoles, surface.NbVPoles)), *full,
                     surface.UDegree, surface.VDegree)
    return own_area(arrays, nodes=30, toward=toward)


class TestRealSurfaces(AreaCase):
    """IGES-like C1 bicubic faces (18 x 8 and 18 x 14 poles, inner knots doubled) with a
    collapsed pole row (a degenerate edge) and a degenerate corner, and real files."""

    def hood(self, nv):
        from ..oracles.nurbs import hood
        obj = self.doc.addObject("Part::Feature", f"Hood{nv}")
        obj.Shape = Part.Face(part_surface(hood(18, nv)))
        self.doc.recompute()
        return obj

    def test_collapsed_row_default_normal_plus_three_percent(self):
        for nv in (8, 14):
            base = self.hood(nv)
            obj = fd.make_area_constrain(base, "Face1", "103%")
            self.assertValid(obj)
            before, new = base.Shape.Faces[0].Surface, self.result_surface(obj)
            self.assertAlmostEqual(obj.OriginalArea / graded_area(before, (1.0, 0.0)), 1,
                                   delta=1e-10)
            self.assertAlmostEqual(graded_area(new, (1.0, 0.0)) / (1.03 * obj.OriginalArea),
                                   1, delta=1e-10)
            self.assertEqual(list(obj.HeldPoles), [f"2,{j}" for j in range(2, nv)])
            P = poles(new)
            self.assertTrue(np.all(P[:2] == P[0, 0]))        # the degenerate edge stays
            self.assertGreater(obj.AreaError, 0)
            self.assertLess(obj.AreaError, 1e-11 * obj.OriginalArea)
            self.assertLess(obj.KKTResidual, 1e-9)

    def test_a_pole_without_net_normal_falls_back_to_the_surface_normal(self):
        s = canopy_surface()
        c = s.getPole(3, 3)
        e = V(12, 7, 1)
        for (i, j), f in (((2, 3), -1), ((4, 3), 1), ((3, 2), -0.5), ((3, 4), 0.5)):
            s.setPole(i, j, c + e * f)
        base = self.doc.addObject("Part::Feature", "Flat")
        base.Shape = Part.Face(s)
        self.doc.recompute()
        obj = fd.make_area_constrain(base, "Face1", "102%", poles=[(3, 3), (4, 4)])
        self.assertValid(obj)
        self.assertEqual(list(obj.NormalFallbacks), ["3,3"])
        uk, vk = s.getUKnots(), s.getVKnots()
        full_u = np.repeat(uk, s.getUMultiplicities())
        full_v = np.repeat(vk, s.getVMultiplicities())
        n = s.normal(float(np.mean(full_u[3:6])), float(np.mean(full_v[3:6])))
        d = self.result_surface(obj).getPole(3, 3) - c
        self.assertGreater(d.Length, 0)
        self.assertLess(d.cross(n).Length, 1e-9 * d.Length)
        self.assertAlmostEqual(occt_area(self.result_surface(obj)) / (1.02 * occt_area(s)), 1,
                               delta=1e-10)

    def test_splinecage_faces_with_default_options(self):
        base = self.doc.addObject("Part::Feature", "Cage")
        shape = Part.Shape()
        shape.read(fc.testdata("splinecage.stp"))
        base.Shape = shape
        self.doc.recompute()
        for k, face in enumerate(shape.Faces):    # ruled 2 x n faces: no interior pole
            obj = fd.make_area_constrain(base, f"Face{k + 1}", "103%")
            self.assertValid(obj)
            new = self.result_surface(obj)
            corner = (new.getUKnots()[0], new.getVKnots()[0])
            self.assertAlmostEqual(graded_area(new, corner) /
                                   (1.03 * graded_area(face.Surface, corner)), 1, delta=1e-10)

    def test_a_rational_terrain_with_default_poles_is_refused_naming_poles(self):
        """Every interior pole of the terrain is solved matrix-free (the real-parts case
        areaconstrain-occt_terrain-Face1-default, minutes); that solver takes non-rational
        faces only, so one weight changed makes the default a refusal."""
        shape = Part.Shape()
        shape.read(fc.testdata("occt_terrain.brep"))
        surface = shape.Faces[0].Surface.copy()
        surface.setWeight(156, 160, 0.9)
        base = self.doc.addObject("Part::Feature", "Terrain")
        base.Shape = Part.Face(surface)
        self.doc.recompute()
        obj = fd.make_area_constrain(base, "Face1", "101%")
        self.assertIn("Invalid", obj.State)
        self.assertRegex(obj.getStatusString(), r"99510 poles .* non-rational .* list in Poles")


if __name__ == "__main__":
    unittest.main()
