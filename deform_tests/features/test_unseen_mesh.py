"""Failures found by running the mesh, cloud and FEM features on public models the project
had not seen (trimesh, common-3d-test-models, PCL, sfepy), rebuilt here on generated
bases.

Oracles written here: a closed box's cross-sections (shoelace area of the section
segments, deform_tests/oracles/mesh.mesh_section), the volume of the exactly tapered box
(the integral of A k(s)^2, which a mesh of frustum slabs meets exactly), the closed
2-manifold check, and the vertices before Plane kept bit for bit.
"""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import Fem  # noqa: E402
import Mesh  # noqa: E402
import numpy as np  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402

from ..oracles.mesh import arrays, assert_closed_manifold, mesh_section, volume  # noqa: E402

V = App.Vector


def box_mesh(lx, ly, lz):
    """A closed box [0, lx] x [-ly/2, ly/2] x [-lz/2, lz/2] of 12 triangles: each face two
    triangles reaching from end to end (as CAD exporters write planar faces)."""
    corners = np.array([(x, y, z) for x in (0, lx) for y in (-ly / 2, ly / 2)
                        for z in (-lz / 2, lz / 2)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return Mesh.Mesh([[V(*corners[i]) for i in t] for t in tris])


class TaperOfLongTriangles(unittest.TestCase):
    """trimesh's ADIS16480.STL, plate_holes.STL and 1002_tray_bottom.STL: a mesh Taper moved
    only the vertices, so a triangle reaching across the region stayed flat from end to
    end: the part before Plane changed its section (and thin walls crossed each other)."""

    def setUp(self):
        self.doc = fc.new_document("UnseenTaper")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def test_box_of_long_triangles(self):
        base = self.doc.addObject("Mesh::Feature", "Box")
        base.Mesh = box_mesh(100.0, 20.0, 20.0)
        axis = (V(0, 0, 0), V(1, 0, 0))
        obj = fd.make_taper(base, (V(40, 0, 0), V(1, 0, 0)), (V(60, 0, 0), V(1, 0, 0)), 0.5,
                            axis)
        self.assertNotIn("Invalid", obj.State)
        V0, T0 = arrays(base.Mesh)
        V1, T1 = arrays(obj.Mesh)
        assert_closed_manifold(V1, T1)
        n = np.array([1.0, 0, 0])
        # the scale is 1 before Plane, 1 - 0.5 t across the region, 0.5 beyond: the
        # section's area 400 k^2 (at x = 50 a slab plane, where the mesh is exact)
        for x, k in ((10, 1.0), (30, 1.0), (39, 1.0), (50, 0.75), (61, 0.5), (90, 0.5)):
            area = mesh_section(V1, T1, np.array([x, 0, 0.0]), n)[0]
            self.assertAlmostEqual(area, 400.0 * k * k, delta=1e-9 * 400, msg=f"x = {x}")
        # each slab a frustum of square sections: the integral of 400 k(s)^2 exactly
        expected = 400 * 40 + 400 * 20 * (1 - 0.5 + 0.25 / 3) + 100 * 40
        self.assertAlmostEqual(volume(V1, T1), expected, delta=1e-9 * expected)
        self.assertAlmostEqual(obj.VolumeChange, expected - volume(V0, T0),
                               delta=1e-9 * expected)
        # the vertices before Plane are the Base's, bit for bit
        before = V0[V0[:, 0] < 40]
        kept = {tuple(p) for p in V1.tolist()}
        self.assertTrue(all(tuple(p) in kept for p in before.tolist()))

    def test_smooth_profile(self):
        base = self.doc.addObject("Mesh::Feature", "Box")
        base.Mesh = box_mesh(100.0, 20.0, 20.0)
        obj = fd.make_taper(base, (V(40, 0, 0), V(1, 0, 0)), (V(60, 0, 0), V(1, 0, 0)), 0.5,
                            (V(0, 0, 0), V(1, 0, 0)))
        obj.Profile = "Smooth"
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State)
        V1, T1 = arrays(obj.Mesh)
        assert_closed_manifold(V1, T1)
        n = np.array([1.0, 0, 0])
        for x, k in ((30, 1.0), (50, 0.75), (70, 0.5)):   # smooth(1/2) = 1/2
            area = mesh_section(V1, T1, np.array([x, 0, 0.0]), n)[0]
            self.assertAlmostEqual(area, 400.0 * k * k, delta=1e-9 * 400, msg=f"x = {x}")


class FarFromTheOrigin(unittest.TestCase):
    """PCL-style georeferenced clouds (trimesh points_agisoft.xyz: UTM metres, 5.6e6) and
    a Base with a Placement far away: the result was stored in global float32, whose step
    there is 0.5, so a 30 mm box came back 0.12 mm off and a cloud 0.25 off. Oracle: every
    Base point moved by the stretch written here (kept before the plane, moved by the
    distance beyond) has a result point within 1e-6 of the part's size."""

    OFFSET = V(665000.123, 5648000.377, 300.31)

    def setUp(self):
        self.doc = fc.new_document("UnseenFar")

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def check(self, before, after, origin, distance, size, axis=2):
        from scipy.spatial import cKDTree
        beyond = (before[:, axis] > origin[axis])[:, None]
        want = np.where(beyond, before + distance * np.eye(3)[axis], before)
        self.assertLess(cKDTree(after).query(want)[0].max(), 1e-6 * size)

    def test_placed_mesh_and_cloud(self):
        import MeshPart
        import Part
        import Points
        box = Part.makeBox(10.3, 20.7, 30.1, V(-5.1, -10.2, -15.3))
        mesh = MeshPart.meshFromShape(Shape=box, LinearDeflection=0.5)
        mesh.Placement = App.Placement(self.OFFSET, App.Rotation())
        base = self.doc.addObject("Mesh::Feature", "Placed")
        base.Mesh = mesh
        cloud = Points.Points([V(*p) for p in
                               np.random.default_rng(1).uniform(-5, 5, (500, 3)).tolist()])
        cloud.Placement = App.Placement(self.OFFSET, App.Rotation())
        pbase = self.doc.addObject("Points::Feature", "PlacedCloud")
        pbase.Points = cloud
        self.doc.recompute()
        origin = np.array(tuple(self.OFFSET)) + [0, 0, 0.37]
        plane = (V(*origin), V(0, 0, 1))
        for b, read in ((base, lambda o: o.Mesh.Topology[0]), (pbase, lambda o: o.Points.Points)):
            obj = fd.make_stretch(b, plane, 5.3)
            self.assertNotIn("Invalid", obj.State)
            before = np.array([tuple(p) for p in read(b)])
            after = np.array([tuple(p) for p in read(obj)])
            self.check(before, after, origin, 5.3, 40.0)
        V1, T1 = arrays(self.doc.getObject("Stretch").Mesh)
        assert_closed_manifold(V1, T1, min_area=0.0)

    def test_georeferenced_cloud(self):
        import Points
        pts = np.random.default_rng(2).uniform(-20, 20, (2000, 3)) + [665187.5, 5648349.9, 241.8]
        base = self.doc.addObject("Points::Feature", "Utm")
        base.Points = Points.Points([V(*p) for p in pts.tolist()])   # stored float32 as read
        self.doc.recompute()
        before = np.array([tuple(p) for p in base.Points.Points])
        origin = before.mean(axis=0)
        obj = fd.make_stretch(base, (V(*origin), V(0, 1, 0)), 5.3)    # along the northing
        self.assertNotIn("Invalid", obj.State)
        after = np.array([tuple(p) for p in obj.Points.Points])
        self.check(before, after, origin, 5.3, 70.0, axis=1)


def loose_box_ply(path, lx, ly, lz):
    """An ASCII PLY of the box [0, lx] x [0, ly] x [0, lz] whose six faces each have their
    own four corners (24 vertices, as exporters that write per-face normals do); FreeCAD's
    PLY reader keeps them apart."""
    corners = [(x, y, z) for x in (0, lx) for y in (0, ly) for z in (0, lz)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    points = [corners[i] for q in quads for i in q]
    faces = [(4 * k + a, 4 * k + b, 4 * k + c) for k in range(6) for a, b, c in ((0, 1, 2),
                                                                              (0, 2, 3))]
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(points)}\nproperty float x\n"
                f"property float y\nproperty float z\nelement face {len(faces)}\n"
                "property list uchar int vertex_indices\nend_header\n")
        f.writelines(f"{x} {y} {z}\n" for x, y, z in points)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces)


class LooseFaces(unittest.TestCase):
    """common-3d-test-models / PCL cube.ply style meshes whose faces do not share their
    corners: DimensionDrive moved the picked face alone (Achieved = Target, Up-to-date)
    and left the side faces where they were, the box torn open. Oracle: every corner at
    x = 10 goes to the target, the rest stay, and the loose faces still bound a box of the
    target's volume (divergence theorem, written here)."""

    def test_distance_on_a_box_of_loose_faces(self):
        import os
        import tempfile
        doc = fc.new_document("UnseenLoose")
        folder = tempfile.mkdtemp()
        try:
            path = os.path.join(folder, "box.ply")
            loose_box_ply(path, 10.0, 20.0, 30.0)
            base = doc.addObject("Mesh::Feature", "Loose")
            base.Mesh = Mesh.Mesh(path)
            self.assertEqual(base.Mesh.CountPoints, 24)
            doc.recompute()
            obj = fd.make_dimension_drive(base, "Distance", [V(10, 10, 15), V(0, 10, 15)], 12.0)
            self.assertNotIn("Invalid", obj.State)
            V0, T0 = arrays(base.Mesh)
            V1, T1 = arrays(obj.Mesh)
            self.assertEqual(T0.tolist(), T1.tolist())
            far = V0[:, 0] == 10
            np.testing.assert_allclose(V1[far, 0], 12.0, atol=1e-9)
            np.testing.assert_array_equal(V1[~far], V0[~far])
            np.testing.assert_array_equal(V1[:, 1:], V0[:, 1:])
            self.assertAlmostEqual(volume(V1, T1), 12 * 20 * 30, delta=1e-9 * 7200)
        finally:
            App.closeDocument(doc.Name)
            for name in os.listdir(folder):
                os.remove(os.path.join(folder, name))
            os.rmdir(folder)


class FemElementKinds(unittest.TestCase):
    """sfepy's hsphere8.vtk and bridge3d.vtk (hexahedra only): the refusal said the Base
    'mixes element types'; it names what the Base holds."""

    def test_hexahedra_named(self):
        doc = fc.new_document("UnseenFem")
        try:
            m = Fem.FemMesh()
            for i, (x, y, z) in enumerate([(x, y, z) for z in (0, 1) for y in (0, 1)
                                           for x in (0, 1)], 1):
                m.addNode(float(x), float(y), float(z), i)
            m.addVolume([1, 2, 4, 3, 5, 6, 8, 7])
            base = doc.addObject("Fem::FemMeshObject", "Hex")
            base.FemMesh = m
            doc.recompute()
            with fc.recorded_errors() as raised:
                obj = fd.make_dimension_drive(base, "Distance", [V(0.5, 0.5, 1), V(0.5, 0.5, 0)],
                                              2.0)
            self.assertIn("Invalid", obj.State)
            exc = raised.get(obj.Name)
            self.assertIsInstance(exc, DeformError)
            self.assertEqual(exc.prop, "Base")
            self.assertIn("hexahedra", str(exc))
            self.assertNotIn("mixes", str(exc))
        finally:
            App.closeDocument(doc.Name)


if __name__ == "__main__":
    unittest.main()
