"""DimensionDrive's Rehandle and the hole grown into the wall (issue 17) on the FE-like
block-with-hole mesh of the chain tests (interior vertices on every face, float32 in a
Mesh::Feature): beyond Reachable it is refused, with Rehandle met through
new handles; grown into the outer wall, refused with the range that stays clear, the Base
intact, and a target inside that range accepted.

Oracles written in the tests: the least-squares cylinder of the hole's vertices
(oracles.fits), SVD planes, triangles flipped (oracles.mesh), the closed-manifold check,
the facet lists compared for topology, the Base's points compared array to array."""
import re
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402

import freecad_deform as fd  # noqa: E402
from .test_dimension_drive import arrays  # noqa: E402
from ..geometry.block_mesh import block_with_hole  # noqa: E402
from ..oracles.fits import cylinder_fit, plane_fit  # noqa: E402
from ..oracles.mesh import assert_closed_manifold, flips  # noqa: E402

PICK = [(58, 30, 15)]
WALL = 30.0       # the hole's axis is 30 mm from the block's sides y = 0 and y = 60


class RehandleCase(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document("DimensionDriveRehandle")
        self.base = self.doc.addObject("Mesh::Feature", "Block")
        V, T = block_with_hole()
        self.base.Mesh = Mesh.Mesh([[tuple(V[i]) for i in tri] for tri in T.tolist()])
        self.doc.recompute()
        self.P, self.facets = arrays(self.base.Mesh)
        self.size = float(np.linalg.norm(np.ptp(self.P, axis=0)))
        self.hole = np.abs(np.hypot(self.P[:, 0] - 50, self.P[:, 1] - 30) - 8) < 1e-4

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def status(self, obj):
        self.assertIn("Invalid", obj.State)
        status = obj.getStatusString()
        self.assertIn("Target", status)
        return status

    def assert_base_intact(self):
        P, facets = arrays(self.base.Mesh)
        np.testing.assert_array_equal(P, self.P)
        np.testing.assert_array_equal(facets, self.facets)

    def assert_hole(self, obj, radius):
        """The result: the hole's vertices on a cylinder of `radius` (1e-6 of the size, the
        stored float32 points), the block's top and bottom planes, nothing flipped, the
        same facets, a closed manifold."""
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        Q, facets = arrays(obj.Mesh)
        np.testing.assert_array_equal(facets, self.facets)
        self.assertEqual(Q.shape, self.P.shape)
        point, axis, r, rms = cylinder_fit(Q[self.hole], (0, 0, 1))
        self.assertLess(abs(r - radius), 1e-6 * self.size)
        self.assertLess(rms, 1e-6 * self.size)
        self.assertLess(np.linalg.norm(np.cross(axis, (0, 0, 1))), 1e-6)
        for z in (0, 30):
            n, offset, rms = plane_fit(Q[self.P[:, 2] == z])
            self.assertLess(rms, 1e-6 * self.size)
            self.assertAlmostEqual(abs(offset), z, delta=1e-6 * self.size)
        self.assertEqual(flips(self.P, Q, self.facets), 0)
        assert_closed_manifold(Q, self.facets)
        return abs(r - radius) / self.size


class TestRehandle(RehandleCase):
    def test_beyond_reachable_refused_then_met_with_rehandle(self):
        obj = fd.make_dimension_drive(self.base, "Radius", PICK, 12)
        self.assertFalse(obj.Rehandle)
        self.assertEqual(obj.Handles, 1)
        high = obj.Reachable[1]
        target = round(high + 2.0, 1)
        self.assertLess(target, WALL)
        obj.Target = target
        self.doc.recompute()
        status = self.status(obj)
        self.assertIn("beyond the deformable range", status)
        self.assert_base_intact()
        obj.Rehandle = True
        self.doc.recompute()
        error = self.assert_hole(obj, target)
        self.assertGreater(obj.Handles, 1)
        self.assertAlmostEqual(obj.Achieved, target, delta=1e-6 * self.size)
        self.assertAlmostEqual(obj.Current, 8, delta=1e-5)
        self.assert_base_intact()
        print(f"\nrehandle: radius 8 -> {target} (one handle reaches {high:.4g}) with "
              f"{obj.Handles} handles, fit error / size {error:.2g}")

    def test_old_documents_get_rehandle_off(self):
        obj = fd.make_dimension_drive(self.base, "Radius", PICK, 10)
        obj.removeProperty("Rehandle")
        obj.Proxy.onDocumentRestored(obj)
        self.assertFalse(obj.Rehandle)
        self.doc.recompute()
        self.assert_hole(obj, 10)


class TestHoleIntoTheWall(RehandleCase):
    def clear_range(self, status):
        """(low, high) of the range a refusal gives as staying clear."""
        m = re.search(r"(?:reachable|went from|stays clear from) ([0-9.e+-]+) to ([0-9.e+-]+)",
                      status)
        self.assertIsNotNone(m, status)
        return float(m.group(1)), float(m.group(2))

    def check(self, rehandle):
        obj = fd.make_dimension_drive(self.base, "Radius", PICK, 40, rehandle=rehandle)
        low, high = self.clear_range(self.status(obj))   # through the wall at 30
        self.assertLess(low, 8 + 1e-4)
        self.assertTrue(8 < high < WALL, high)
        self.assertEqual(obj.Handles > 1, rehandle)         # how many it took to get there
        self.assert_base_intact()
        target = round(high - 0.1, 1)
        obj.Target = target
        self.doc.recompute()
        self.assert_hole(obj, target)
        self.assert_base_intact()
        return high, obj.Handles

    def test_refused_with_the_clear_range(self):
        high, _ = self.check(False)
        print(f"\nhole into the wall: clear up to {high:.4g} with one handle")

    def test_refused_with_the_range_rehandle_reached(self):
        high, handles = self.check(True)
        print(f"\nhole into the wall, Rehandle: clear up to {high:.4g}; {high - 0.1:.1f} met "
              f"with {handles} handles")


if __name__ == "__main__":
    unittest.main()
