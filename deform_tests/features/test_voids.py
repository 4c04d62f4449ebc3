"""Stretch, Bend and Twist of solids with inner void shells, with voids oriented as material
(as some STEP writers give them) and of reversed solids; the Base is only read.

Oracles: OCCT's isValid() and Volume, a section's area (Shape.slice and a face maker),
Pappus written here, the void shells' centres of mass, the Base's vertex tolerances.
"""
import unittest

from . import fc
from ..oracles.shapes import section_area

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector


def turned_part():
    """A grooved bar along x (r 20, length 300) with two cavities: a cylinder at x 50..100
    and a sphere at x 200: one solid, three shells."""
    body = Part.makeCylinder(20, 300, V(0, 0, 0), V(1, 0, 0))
    for x in range(20, 280, 20):
        body = body.cut(Part.makeTorus(20, 3, V(x, 0, 0), V(1, 0, 0)))
    body = body.cut(Part.makeCylinder(6, 50, V(50, 0, 0), V(1, 0, 0)))
    return body.cut(Part.makeSphere(8, V(200, 0, 0))).Solids[0]


def material_volume(solid):
    """|outer shell| - sum |void shells|, from OCCT's signed shell volumes."""
    v = sorted((abs(s.Volume) for s in solid.Shells), reverse=True)
    return v[0] - sum(v[1:])


def void_centres(shape):
    """Centres of mass of the inner shells (all but the largest), sorted by x."""
    centres = []
    for solid in shape.Solids:
        shells = sorted(solid.Shells, key=lambda s: -abs(s.Volume))
        centres += [np.array(tuple(Part.Solid(s).CenterOfMass)) for s in shells[1:]]
    return sorted(centres, key=lambda c: c[0])


class VoidsTest(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("Voids")
        self.solid = turned_part()
        self.assertEqual(len(self.solid.Shells), 3)

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def base(self, shape):
        obj = self.doc.addObject("Part::Feature", "Base")
        obj.Shape = shape
        return obj

    def variants(self):
        outer, v1, v2 = sorted(self.solid.Shells, key=lambda s: -abs(s.Volume))
        flipped = Part.makeSolid(Part.makeCompound([outer, v1.reversed(), v2.reversed()]))
        return {"voids": self.solid, "voids as material": flipped,
                "reversed": self.solid.reversed()}

    def check(self, obj, label):
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, f"{label}: {obj.getStatusString()}")
        self.assertTrue(obj.Shape.isValid(), label)
        self.assertEqual([len(s.Shells) for s in obj.Shape.Solids], [3], label)
        return obj.Shape.Solids[0]

    def test_stretch_keeps_voids_and_moves_the_far_one(self):
        """Plane at x 150, +30: volume change = section area * 30; the void at x 75
        stays, the one at x 200 moves by 30."""
        area = section_area(self.solid, (150, 0, 0), (1, 0, 0))
        before = void_centres(self.solid)
        for label, shape in self.variants().items():
            s = fd.make_stretch(self.base(shape), (V(150, 0, 0), V(1, 0, 0)), 30)
            result = self.check(s, label)
            change = material_volume(result) - material_volume(self.solid)
            self.assertAlmostEqual(change / (30 * area), 1.0, delta=1e-6, msg=label)
            self.assertAlmostEqual(s.VolumeChange / (30 * area), 1.0, delta=1e-6, msg=label)
            after = void_centres(result)
            self.assertLess(np.linalg.norm(after[0] - before[0]), 1e-6, label)
            self.assertLess(np.linalg.norm(after[1] - before[1] - [30, 0, 0]), 1e-6, label)

    def test_stretch_through_a_void(self):
        """Plane at x 75 cuts the cylindrical cavity: it is stretched with the part (the
        section has a hole there), still one inner shell."""
        area = section_area(self.solid, (75, 0, 0), (1, 0, 0))
        s = fd.make_stretch(self.base(self.solid), (V(75, 0, 0), V(1, 0, 0)), 20)
        result = self.check(s, "through")
        self.assertAlmostEqual(s.VolumeChange / (20 * area), 1.0, delta=1e-6)
        cavity = sorted(result.Shells, key=lambda sh: -abs(sh.Volume))[1]
        self.assertAlmostEqual(abs(cavity.Volume), np.pi * 36 * 70, delta=1e-6 * 36 * 70)

    def test_bend_keeps_voids(self):
        """Bend 40 deg about an axis 30 mm beside the bar: Pappus (A * r_c * angle)."""
        axis_point, axis_dir = np.array([150.0, 0, 50]), np.array([0.0, 1, 0])
        area = section_area(self.solid, (150, 0, 0), (1, 0, 0))
        for label, shape in self.variants().items():
            b = fd.make_bend(self.base(shape), (V(150, 0, 0), V(1, 0, 0)), -40,
                             (V(*axis_point), V(*axis_dir)))
            result = self.check(b, label)
            pappus = area * 50.0 * np.radians(40)  # the section's centroid is on the x axis
            change = material_volume(result) - material_volume(self.solid)
            self.assertAlmostEqual(change / pappus, 1.0, delta=1e-6, msg=label)

    def test_twist_of_a_region_through_a_void_keeps_volume(self):
        """Twist x 64..76 (between two grooves; the cavity crosses the whole region) by 30
        deg: volume kept."""
        for label, shape in self.variants().items():
            t = fd.make_twist(self.base(shape), (V(64, 0, 0), V(1, 0, 0)),
                              (V(76, 0, 0), V(1, 0, 0)), 30)
            result = self.check(t, label)
            self.assertAlmostEqual(material_volume(result) / material_volume(self.solid), 1.0,
                                   delta=1e-4, msg=label)

    def test_base_is_only_read(self):
        """A plane through the Base's vertices: its tolerances and geometry stay."""
        box = Part.makeBox(40, 20, 10)
        base = self.base(box)
        before = [v.Tolerance for v in base.Shape.Vertexes] + [
            e.Tolerance for e in base.Shape.Edges]
        s = fd.make_stretch(base, (V(20, 0, 0), V(1, 0, 0)), 5)
        s2 = fd.make_bend(base, (V(0, 10, 0), V(0, 1, 0)), 30, (V(0, 10, 30), V(1, 0, 0)))
        self.doc.recompute()
        self.assertNotIn("Invalid", s.State)
        self.assertNotIn("Invalid", s2.State, s2.getStatusString())
        after = [v.Tolerance for v in base.Shape.Vertexes] + [
            e.Tolerance for e in base.Shape.Edges]
        self.assertEqual(before, after)
        self.assertAlmostEqual(base.Shape.Volume, 8000.0, delta=1e-9)


if __name__ == "__main__":
    unittest.main()
