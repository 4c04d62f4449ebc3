"""shapes.convert's fast paths against FreeCAD's own slow ones: a Mesh built from arrays
through FreeCAD's binary format carries the neighbours FreeCAD itself rebuilds; meshes
that are not closed 2-manifolds still come out right (through the STL reader); clouds
keep their points."""
import unittest

from . import fc  # noqa: F401  (FreeCAD on sys.path; a missing one fails)

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

from freecad_deform.shapes import convert  # noqa: E402

V = App.Vector


def holed_box_arrays():
    solid = Part.makeBox(10, 20, 30).cut(Part.makeCylinder(3, 30, V(5, 10, 0)))
    mesh = MeshPart.meshFromShape(Shape=solid, LinearDeflection=0.05)
    points, facets = mesh.Topology
    return (np.array([tuple(p) for p in points]), np.array(facets, np.int64), solid.Volume)


def neighbours(mesh):
    return [tuple(f.NeighbourIndices) for f in mesh.Facets]


class MeshFromArrays(unittest.TestCase):
    def test_closed_mesh_has_freecads_own_neighbours(self):
        v, t, volume = holed_box_arrays()
        extra = np.r_[v, [[100.0, 100.0, 100.0]]]          # an unused vertex is left out
        mesh = convert.mesh_from_arrays(extra, t)
        self.assertEqual((mesh.CountPoints, mesh.CountFacets), (len(v), len(t)))
        self.assertFalse(mesh.hasInvalidNeighbourhood())
        rebuilt = mesh.copy()
        rebuilt.rebuildNeighbourHood()
        self.assertEqual(neighbours(mesh), neighbours(rebuilt))
        self.assertTrue(mesh.isSolid())
        self.assertFalse(mesh.hasNonManifolds())
        self.assertAlmostEqual(mesh.Volume, volume, delta=2e-3 * volume)
        points = np.array([tuple(p) for p in mesh.Topology[0]])
        np.testing.assert_allclose(points, v, atol=1e-5)          # float32, same order
        self.assertEqual(np.array(mesh.Topology[1]).tolist(), t.tolist())

    def test_open_or_flipped_mesh_goes_through_the_stl_reader(self):
        v, t, _ = holed_box_arrays()
        for name, tris in (("open", t[1:]), ("flipped", np.r_[t[1:], t[:1, ::-1]])):
            self.assertIsNone(convert._neighbours(tris, len(v)), name)
            mesh = convert.mesh_from_arrays(v, tris)
            self.assertEqual(mesh.CountFacets, len(tris), name)
            self.assertFalse(mesh.hasInvalidNeighbourhood(), name)
            if name == "open":
                self.assertFalse(mesh.isSolid())
            else:                       # closed, the flipped facet kept as it was given
                self.assertEqual(mesh.countNonUniformOrientedFacets(), 1)

    def test_round_trip_through_arrays(self):
        v, t, _ = holed_box_arrays()
        mesh = convert.mesh_from_arrays(v, t)
        mesh.Placement = App.Placement(V(1, 2, 3), App.Rotation(10, 20, 30))
        got_v, got_t = convert.mesh_arrays(mesh)
        want = np.array([tuple(p) for p in mesh.Topology[0]])
        np.testing.assert_allclose(got_v, want, atol=1e-9)
        self.assertEqual(got_t.tolist(), np.array(mesh.Topology[1]).tolist())


class PointsArrays(unittest.TestCase):
    def test_cloud_round_trip_leaves_out_nan(self):
        rng = np.random.default_rng(3)
        pts = rng.random((1000, 3)) * 50
        cloud = convert.points_from_array(pts)
        np.testing.assert_allclose(convert.points_array(cloud), pts, atol=1e-4)
        holed = pts.copy()
        holed[7, 1] = np.nan
        got = convert.points_array(convert.points_from_array(holed))
        self.assertEqual(len(got), 999)
        np.testing.assert_allclose(got, np.delete(pts, 7, axis=0), atol=1e-4)


if __name__ == "__main__":
    unittest.main()
