"""DimensionDrive Kind "Angle" (issue 17) on an L bracket meshed by FreeCAD (Mefisto, FE-like
with interior vertices): the inner face of the upright turns about the line where it meets
the base's top face, 90 -> 80 degrees. Oracle: planes fitted here to the vertices the test
selects by coordinate on the Base, the angle between them, flips counted from the facets."""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

from ..oracles.mesh import arrays  # noqa: E402

V = App.Vector


def plane(P):
    c = P.mean(axis=0)
    n = np.linalg.svd(P - c)[2][-1]
    return c, n, np.abs((P - c) @ n).max()


class TestAngle(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("DimensionDriveAngle")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def test_bracket_90_to_80(self):
        bracket = Part.makeBox(100, 40, 10).fuse(Part.makeBox(10, 40, 80)).removeSplitter()
        base = self.doc.addObject("Mesh::Feature", "Bracket")
        base.Mesh = MeshPart.meshFromShape(Shape=bracket, MaxLength=4.0)
        self.doc.recompute()
        P, facets = arrays(base.Mesh)
        obj = fd.make_dimension_drive(base, "Angle", [(10, 20, 45), (55, 20, 10)], 80)
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        Q, facets2 = arrays(obj.Mesh)
        np.testing.assert_array_equal(facets, facets2)
        upright = (np.abs(P[:, 0] - 10) < 1e-9) & (P[:, 2] >= 10 - 1e-9)
        top = (np.abs(P[:, 2] - 10) < 1e-9) & (P[:, 0] >= 10 - 1e-9)
        cu, nu, du = plane(Q[upright])
        ct, nt, dt = plane(Q[top])
        self.assertLess(max(du, dt), 1e-4)                      # float32 storage
        angle = np.degrees(np.arccos(abs(nu @ nt)))
        print(f"\nbracket angle: fitted {angle:.9f} deg, Achieved {obj.Achieved:.9f}, "
              f"Reachable {list(obj.Reachable)}")
        self.assertAlmostEqual(angle, 80.0, delta=1e-6)           # float32 vertices: 2.5e-7
        self.assertAlmostEqual(obj.Achieved, 80.0, delta=1e-6)
        self.assertAlmostEqual(obj.Current, 90.0, delta=1e-6)
        n0 = np.cross(P[facets[:, 1]] - P[facets[:, 0]], P[facets[:, 2]] - P[facets[:, 0]])
        n1 = np.cross(Q[facets[:, 1]] - Q[facets[:, 0]], Q[facets[:, 2]] - Q[facets[:, 0]])
        self.assertEqual(int(np.count_nonzero(np.einsum("ij,ij->i", n0, n1) <= 0)), 0)
        lo, hi = obj.Reachable
        self.assertTrue(lo < 80 < hi)
        obj.TargetAngle = 100          # the upright's top end (10 thick, 70 up) pinches at 98
        self.doc.recompute()
        self.assertIn("Invalid", obj.State)
        self.assertRegex(obj.getStatusString(),
                         r"TargetAngle is beyond .*reachable [0-9.]+ to 98\.[0-9]+")
        self.assertEqual(obj.Proxy.error_prop, "TargetAngle")
        np.testing.assert_array_equal(arrays(base.Mesh)[0], P)
        obj.TargetAngle = 95
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertAlmostEqual(obj.Achieved, 95.0, delta=1e-6)


if __name__ == "__main__":
    unittest.main()
