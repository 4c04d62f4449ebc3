"""Bend and Twist on real FreeCAD documents, on parts built here (a filleted I-beam, a box,
a wedge) and the machined STEP part.

Oracles: Pappus (A * r_c * angle), OCCT Volume/isValid, section areas from Shape.slice,
rotation matrices written out here, cKDTree distances.
"""
import os
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402
import Points  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector
REVOLUTION = {"Plane", "Cylinder", "Toroid", "Cone", "Sphere", "SurfaceOfRevolution"}


def i_beam(length=200.0, width=60.0, height=80.0, flange=10.0, web=8.0, fillet=4.0):
    """An I-beam along x with filleted web-flange edges (the fillets run along x)."""
    beam = Part.makeBox(length, width, flange).fuse(
        Part.makeBox(length, width, flange, V(0, 0, height - flange))).fuse(
        Part.makeBox(length, web, height - 2 * flange, V(0, (width - web) / 2, flange)))
    beam = beam.removeSplitter()
    edges = [e for e in beam.Edges if isinstance(e.Curve, Part.Line)
             and abs(e.Length - length) < 1e-9
             and flange - 1e-9 < e.Vertexes[0].Point.z < height - flange + 1e-9
             and abs(e.Vertexes[0].Point.y - width / 2) < web / 2 + 1e-9]
    return beam.makeFillet(fillet, edges)


def rotation_matrix(axis, angle_deg):
    a = np.radians(angle_deg)
    w = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k  # Rodrigues


def section(shape, origin, normal):
    n = V(*normal).normalize()
    return Part.makeFace(shape.slice(n, n.dot(V(*origin))), "Part::FaceMakerBullseye")


def points_of(shape):
    return np.array([tuple(v.Point) for v in shape.Vertexes])


class Document(unittest.TestCase):
    def setUp(self):
        self.doc = fc.new_document()

    def tearDown(self):
        App.closeDocument(self.doc.Name)

    def base(self, shape, name="Base"):
        obj = self.doc.addObject("Part::Feature", name)
        obj.Shape = shape
        return obj

    def ok(self, obj):
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertTrue(obj.Shape.isValid())
        self.assertEqual(len(obj.Shape.Solids), 1)
        return obj.Shape


class BendTest(Document):
    plane = ((120.0, 0, 0), (1.0, 0, 0))
    axis = ((120.0, 0, -40.0), (0, 1.0, 0))  # in the plane, 40 below the beam

    def test_bend_is_exact_pappus_and_rigid(self):
        beam = i_beam()
        angle = 50.0
        obj = fd.make_bend(self.base(beam), (V(*self.plane[0]), V(*self.plane[1])), angle,
                           (V(*self.axis[0]), V(*self.axis[1])))
        result = self.ok(obj)
        sec = section(beam, *self.plane)
        c = np.array(tuple(sec.CenterOfMass))
        r_c = np.linalg.norm(np.cross(c - self.axis[0], self.axis[1]))
        pappus = sec.Area * r_c * np.radians(angle)
        self.assertAlmostEqual((result.Volume - beam.Volume) / pappus, 1.0, delta=1e-6)
        self.assertAlmostEqual(obj.VolumeChange / pappus, 1.0, delta=1e-6)
        self.assertLessEqual({type(f.Surface).__name__ for f in result.Faces}, REVOLUTION)
        # near vertices unchanged, far ones rotated about the axis (Rodrigues written here)
        before, after = points_of(beam), points_of(result)
        s = before[:, 0] - 120.0
        rot = rotation_matrix(self.axis[1], angle)  # right-hand about +y: the far end swings down
        far = (before[s > 1e-9] - self.axis[0]) @ rot.T + self.axis[0]
        expected = np.vstack([before[s < -1e-9], far])
        self.assertLess(cKDTree(after).query(expected)[0].max(), 1e-7)
        # the cross-section at mid-angle equals the original
        mid = rotation_matrix(self.axis[1], angle / 2) @ np.array(self.plane[1])
        self.assertAlmostEqual(section(result, self.axis[0], mid).Area / sec.Area, 1.0, delta=1e-6)

    def test_wrong_direction_and_small_radius_are_errors(self):
        base = self.base(i_beam())
        before = base.Shape.Volume
        wrong = fd.make_bend(base, (V(*self.plane[0]), V(*self.plane[1])), -50,  # into x < 120
                             (V(*self.axis[0]), V(*self.axis[1])))
        self.assertIn("Invalid", wrong.State)
        self.assertIn("Angle", wrong.getStatusString())
        inside = fd.make_bend(base, (V(*self.plane[0]), V(*self.plane[1])), 50,
                              (V(120, 0, 40), V(0, 1, 0)))
        self.assertIn("Invalid", inside.State)
        self.assertIn("Axis", inside.getStatusString())
        self.assertEqual(base.Shape.Volume, before)
        path = os.path.join(tempfile.mkdtemp(), "bend_error.FCStd")
        self.doc.saveAs(path)
        self.assertTrue(os.path.isfile(path))

    def test_two_planes_keep_the_section(self):
        beam = i_beam()
        obj = fd.make_bend(self.base(beam), (V(80, 0, 0), V(1, 0, 0)), 30,
                           (V(80, 0, -40), V(0, 1, 0)), plane2=(V(120, 0, 0), V(1, 0, 0)))
        result = self.ok(obj)
        sec = section(beam, (80, 0, 0), (1, 0, 0))
        r_c = np.linalg.norm(np.cross(np.array(tuple(sec.CenterOfMass)) - [80, 0, -40], [0, 1, 0]))
        between = sec.Area * 40.0
        expected = sec.Area * r_c * np.radians(30) - between
        self.assertAlmostEqual(obj.VolumeChange / expected, 1.0, delta=1e-6)
        mid = rotation_matrix((0, 1, 0), 15) @ np.array([1.0, 0, 0])
        self.assertAlmostEqual(section(result, (80, 0, -40), mid).Area / sec.Area, 1.0, delta=1e-6)

    def test_machined_part_and_edit_and_reopen(self):
        shape = Part.read(fc.testdata("face_recognition_sample_part.stp"))
        obj = fd.make_bend(self.base(shape, "Part"), (V(150, 0, 0), V(1, 0, 0)), -60,
                           (V(150, 0, 260), V(0, 1, 0)))
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertEqual(len(obj.Shape.Solids), 1)
        sec = section(shape.Solids[0], (150, 0, 0), (1, 0, 0))
        r_c = np.linalg.norm(np.cross(np.array(tuple(sec.CenterOfMass)) - [150, 0, 260], [0, 1, 0]))
        obj.Angle = "-0.5 rad"
        self.doc.recompute()
        self.assertAlmostEqual(obj.VolumeChange / (sec.Area * r_c * 0.5), 1.0, delta=1e-6)
        volume, name = obj.Shape.Volume, obj.Name
        path = os.path.join(tempfile.mkdtemp(), "bend.FCStd")
        self.doc.saveAs(path)
        App.closeDocument(self.doc.Name)
        self.doc = App.openDocument(path)
        obj = self.doc.getObject(name)
        obj.touch()
        self.doc.recompute()
        self.assertAlmostEqual(obj.Shape.Volume, volume, delta=1e-9 * volume)

    def test_point_cloud_bend(self):
        import MeshPart
        beam = i_beam()
        mesh = MeshPart.meshFromShape(Shape=beam, MaxLength=4.0)  # a scan-like even sampling
        cloud = np.array([(p.x, p.y, p.z) for p in mesh.Points])
        base = self.doc.addObject("Points::Feature", "Cloud")
        base.Points = Points.Points([V(*p) for p in cloud])
        cloud = np.array([tuple(p) for p in base.Points.Points])  # as stored (float32)
        obj = fd.make_bend(base, (V(*self.plane[0]), V(*self.plane[1])), 50,
                           (V(*self.axis[0]), V(*self.axis[1])))
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        out = np.array([tuple(p) for p in obj.Points.Points])
        s = cloud[:, 0] - 120.0
        rot = rotation_matrix(self.axis[1], 50)
        expected = np.vstack([cloud[s <= 0], (cloud[s > 0] - self.axis[0]) @ rot.T + self.axis[0]])
        self.assertLess(cKDTree(out).query(expected)[0].max(), 1e-4)  # Points are float32
        rest = out[cKDTree(expected).query(out)[0] > 1e-3]
        self.assertGreater(len(rest), 0)  # the gap is filled ...
        rel = rest - self.axis[0]
        theta = np.degrees(np.arctan2(rel[:, 0], rel[:, 2]))  # ... inside the swept wedge
        self.assertTrue(np.all((theta > -1e-6) & (theta < 50 + 1e-6)))


class TwistTest(Document):
    def test_box_twist_90(self):
        box = Part.makeBox(20, 20, 100)
        obj = fd.make_twist(self.base(box), (V(0, 0, 30), V(0, 0, 1)), (V(0, 0, 70), V(0, 0, 1)), 90)
        result = self.ok(obj)
        self.assertAlmostEqual(result.Volume / box.Volume, 1.0, delta=1e-3)
        self.assertAlmostEqual(result.BoundBox.ZLength, 100.0, delta=1e-7)
        self.assertAlmostEqual(section(result, (0, 0, 50), (0, 0, 1)).Area / 400.0, 1.0, delta=1e-3)
        top = points_of(result)[points_of(result)[:, 2] > 100 - 1e-9]
        corners = (np.array([[0, 0], [20, 0], [0, 20], [20, 20.0]]) - 10) @ rotation_matrix(
            (0, 0, 1), 90)[:2, :2].T + 10
        self.assertLess(cKDTree(top[:, :2]).query(corners)[0].max(), 1e-7)
        self.assertEqual(len(top), 4)

    def test_i_beam_twist_keeps_section(self):
        beam = i_beam()
        obj = fd.make_twist(self.base(beam), (V(60, 0, 0), V(1, 0, 0)), (V(140, 0, 0), V(1, 0, 0)), 45)
        result = self.ok(obj)
        sec = section(beam, (100, 0, 0), (1, 0, 0)).Area
        self.assertAlmostEqual(section(result, (100, 0, 0), (1, 0, 0)).Area / sec, 1.0, delta=1e-3)
        self.assertAlmostEqual(result.Volume / beam.Volume, 1.0, delta=1e-3)
        self.assertAlmostEqual(result.BoundBox.XLength, 200.0, delta=1e-7)

    def test_coinciding_planes_are_an_error(self):
        base = self.base(Part.makeBox(20, 20, 100))
        obj = fd.make_twist(base, (V(0, 0, 50), V(0, 0, 1)), (V(0, 0, 50), V(0, 0, 1)), 30)
        self.assertIn("Invalid", obj.State)
        self.assertIn("Plane2", obj.getStatusString())
        self.assertAlmostEqual(base.Shape.Volume, 40000.0, delta=1e-9)


class ContinuityTest(Document):
    def test_stretched_box_is_g1_everywhere_wedge_slope_c0(self):
        box = fd.make_stretch(self.base(Part.makeBox(100, 20, 30)), (V(50, 0, 0), V(1, 0, 0)), 10)
        kinds = dict(e.split(": ") for e in box.Continuity.split("; "))
        self.assertEqual(len(kinds), 4)
        self.assertEqual(set(kinds.values()), {"G1"})
        profile = Part.makePolygon([V(0, 0, 0), V(100, 0, 0), V(100, 0, 20), V(0, 0, 40),
                                    V(0, 0, 0)])
        wedge = Part.Face(profile).extrude(V(0, 20, 0))  # a slanted top face
        obj = fd.make_stretch(self.base(wedge, "Wedge"), (V(50, 0, 0), V(1, 0, 0)), 10)
        kinds = dict(e.split(": ") for e in obj.Continuity.split("; "))
        slanted = [f"Face{i}" for i, f in enumerate(wedge.Faces, 1)
                   if 1e-6 < abs(f.normalAt(0, 0).x) < 1 - 1e-6]
        self.assertTrue(slanted)
        for name in slanted:
            self.assertEqual(kinds[name], "C0")
        self.assertIn("G1", kinds.values())


class KeyMotionTest(Document):
    """General motion (Fig. 2c, Fig. 5): the far part passes through key placements; the gap
    is a loft through profiles normal to the path of the section's centroid (Step 6)."""

    plane, axis = (V(100, 0, 0), V(1, 0, 0)), (V(100, 0, -40), V(0, 1, 0))

    def keyed_bend(self, lift, interpolation):
        bar = Part.makeBox(200, 20, 10)
        obj = fd.make_bend(self.base(bar), self.plane, 60, self.axis)
        half = App.Placement(V(0, 0, 0), App.Rotation(V(0, 1, 0), 30), V(100, 0, -40))
        obj.KeyPlacements = [App.Placement(V(0, lift, 0), App.Rotation()).multiply(half)]
        obj.Interpolation = interpolation
        self.doc.recompute()
        return bar, obj

    def test_key_on_the_circle_gives_the_bend(self):
        for interpolation in ("Rational", "Screw"):
            bar, obj = self.keyed_bend(0.0, interpolation)
            self.ok(obj)
            pappus = 200.0 * 45.0 * np.radians(60)  # section 20 x 10, centroid 45 from the axis
            self.assertAlmostEqual(obj.VolumeChange / pappus, 1.0, delta=1e-3)  # a loft, not exact

    def test_key_off_the_circle_lands_and_passes_its_profiles(self):
        bar, obj = self.keyed_bend(5.0, "Screw")
        result = self.ok(obj)
        # the far end lands exactly where the plain bend puts it
        rot = rotation_matrix((0, 1, 0), 60)
        ends = (points_of(bar)[points_of(bar)[:, 0] > 199] - [100, 0, -40]) @ rot.T + [100, 0, -40]
        self.assertLess(cKDTree(points_of(result)).query(ends)[0].max(), 1e-7)
        # the loft passes through its profile at t = 1/4 (sample 4 of 16): the section, in the
        # plane normal to the centroid's path, turned by the motion. The frame is built here,
        # its tangent by a finite difference.
        from freecad_deform.geometry.sweep.motion import PiecewiseScrew
        from freecad_deform.geometry.sweep.planes import frame
        key = np.array(obj.KeyPlacements[0].toMatrix().A).reshape(4, 4)
        end = np.eye(4)
        end[:3, :3], end[:3, 3] = rot, np.array([100, 0, -40]) - rot @ [100, 0, -40]
        motion = PiecewiseScrew([np.eye(4), key, end])
        centre = np.array([100.0, 10, 5])

        def at(t):
            m = motion.matrix(t)
            return m[:3, :3] @ centre + m[:3, 3]

        def placement(t, x0):
            z = (at(t + 1e-7) - at(t - 1e-7)) / 2e-7 if t > 0 else (at(1e-7) - at(0)) / 1e-7
            z /= np.linalg.norm(z)
            x = motion.matrix(t)[:3, :3] @ x0
            x -= (x @ z) * z
            x /= np.linalg.norm(x)
            return np.column_stack([x, np.cross(z, x), z]), at(t)

        x0 = frame([1.0, 0, 0])[0]
        (r0, _), (r1, o1) = placement(0.0, x0), placement(0.25, x0)
        for dy, dz in ((10, 5), (10, -5), (-10, 5), (-10, -5)):
            offset = np.array([0, dy, dz])  # a corner of the section, from its centroid ...
            local = r0.T @ (offset - (offset @ r0[:, 2]) * r0[:, 2])  # ... seen across the path
            corner = Part.Vertex(V(*(o1 + r1 @ local)))
            self.assertLess(result.distToShape(corner)[0], 1e-5)
        self.assertGreater(abs(obj.VolumeChange - 200.0 * 45.0 * np.radians(60)), 1.0)

    def test_oblique_path_is_an_error(self):
        bar, obj = self.keyed_bend(10.0, "Screw")  # the path leaves Plane 11 deg off its normal
        self.assertIn("Invalid", obj.State)
        self.assertIn("KeyPlacements", obj.getStatusString())
        self.assertAlmostEqual(obj.Base.Shape.Volume, 40000.0, delta=1e-9)

    def test_key_on_a_mesh_and_bad_interpolation(self):
        import Mesh
        base = self.doc.addObject("Mesh::Feature", "BarMesh")
        base.Mesh = Mesh.Mesh(Part.makeBox(200, 20, 10).tessellate(0.1))
        obj = fd.make_stretch(base, (V(100, 0, 0), V(1, 0, 0)), 60)
        obj.KeyPlacements = [App.Placement(V(30, 15, 0), App.Rotation())]
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertTrue(obj.Mesh.isSolid())
        self.assertFalse(obj.Mesh.hasNonManifolds())
        obj.UsePlane2 = True
        obj.Plane2 = App.Placement(V(150, 0, 0), App.Rotation(V(0, 0, 1), V(1, 0, 0)))
        self.doc.recompute()
        self.assertIn("KeyPlacements", obj.getStatusString())


class SteepTwistTest(Document):
    def test_too_steep_for_the_loft_goes_through_the_map(self):
        """90 deg over 4 mm of a 400 mm strip: a loft through 16 profiles cuts inside the
        path, so the region goes through the twist map instead. Oracles: OCCT's BOP check,
        the volume, the mid-section turned by 45 deg (its box (400 + 10) / sqrt 2 wide)."""
        strip = self.base(Part.makeBox(400, 10, 100, V(-200, -5, 0)))
        obj = fd.make_twist(strip, (V(0, 0, 48), V(0, 0, 1)), (V(0, 0, 52), V(0, 0, 1)), 90)
        self.assertEqual(obj.State, ["Up-to-date"], obj.getStatusString())
        obj.Shape.check(True)
        self.assertAlmostEqual(obj.Shape.Volume / 400000.0, 1.0, delta=1e-9)
        self.assertLessEqual(obj.MaxDeviation, obj.Tolerance.Value)
        mid = Part.makeFace(obj.Shape.slice(V(0, 0, 1), 50.0), "Part::FaceMakerBullseye")
        self.assertAlmostEqual(mid.Area, 4000.0, delta=4000.0 * 1e-6)
        self.assertAlmostEqual(mid.BoundBox.XLength, 410.0 / np.sqrt(2), delta=0.01)
        obj.Plane2 = App.Placement(V(0, 0, 98), App.Rotation())  # a longer twist is lofted
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        self.assertAlmostEqual(obj.Shape.Volume / 400000.0, 1.0, delta=1e-3)
