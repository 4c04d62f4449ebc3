"""Assemblies (issue 17; Date & Onosato, Fig. 8): a DimensionDrive on a block's bore and the
matching drive on the shaft in it (two meshes), its Target bound by an expression: one
value changes both. Oracle: circles fitted here to the vertices of the bore and of the
shaft the test selects by coordinate on the Bases."""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.api import make_matching_drive  # noqa: E402

from ..oracles.fits import circle  # noqa: E402

V = App.Vector


def arrays(mesh):
    points, _ = mesh.Topology
    return np.array([tuple(p) for p in points])


class TestAssembly(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("DimensionDriveAssembly")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def mesh(self, shape, name):
        obj = self.doc.addObject("Mesh::Feature", name)
        obj.Mesh = MeshPart.meshFromShape(Shape=shape, MaxLength=3.0)
        self.doc.recompute()
        return obj

    def test_bore_and_shaft_follow_one_value(self):
        block = self.mesh(Part.makeBox(100, 60, 30).cut(
            Part.makeCylinder(8, 30, V(50, 30, 0))), "Block")
        shaft = self.mesh(Part.makeCylinder(8, 50, V(50, 30, -10)), "Shaft")
        P, S = arrays(block.Mesh), arrays(shaft.Mesh)
        bore = np.abs(np.hypot(P[:, 0] - 50, P[:, 1] - 30) - 8) < 1e-4
        side = np.abs(np.hypot(S[:, 0] - 50, S[:, 1] - 30) - 8) < 1e-4
        first = fd.make_dimension_drive(block, "Radius", [(58, 30, 15)], 9)
        second = make_matching_drive(first, shaft)
        self.assertNotIn("Invalid", second.State, second.getStatusString())
        self.assertEqual(second.Kind, "Radius")
        for value in (9.0, 9.5):
            first.Target = value
            self.doc.recompute()
            for obj in (first, second):
                self.assertNotIn("Invalid", obj.State, obj.getStatusString())
            c1, r1, d1 = circle(arrays(first.Mesh)[bore])
            c2, r2, d2 = circle(arrays(second.Mesh)[side])
            print(f"\nbore {r1:.9f}, shaft {r2:.9f} (target {value})")
            self.assertLess(abs(r1 - r2), 1e-6)            # float32 vertices: 4.9e-7 seen
            self.assertLess(abs(r1 - value), 2e-6)
            self.assertLess(max(d1, d2), 1e-5)
            np.testing.assert_allclose(c1, c2, atol=2e-6)
            self.assertAlmostEqual(second.Achieved, value, delta=1e-6)   # float32 Base
            self.assertAlmostEqual(first.Achieved, second.Achieved, delta=1e-6)

    def test_no_matching_surface_names_regions(self):
        block = self.mesh(Part.makeBox(100, 60, 30).cut(
            Part.makeCylinder(8, 30, V(50, 30, 0))), "Block")
        other = self.mesh(Part.makeCylinder(5, 50, V(50, 30, -10)), "Thin")
        first = fd.make_dimension_drive(block, "Radius", [(58, 30, 15)], 9)
        names = sorted(o.Name for o in self.doc.Objects)
        with self.assertRaisesRegex(ValueError, "Regions: the other mesh has no plane or "
                                                "cylinder"):
            make_matching_drive(first, other)
        self.assertEqual(sorted(o.Name for o in self.doc.Objects), names)
        self.assertTrue(other.Visibility)


if __name__ == "__main__":
    unittest.main()
