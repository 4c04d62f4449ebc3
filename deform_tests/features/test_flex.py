"""Twist and Bend of regions whose outline changes (issue 14): the region between the planes
goes through the space map; faces are refit or kept exact and sewn with the rest.

Oracles written here: rotations, OCCT Volume/isValid/slice areas, Pappus summed over the
region's sections, distances from exactly turned points of the Base to the result."""
import os
import tempfile
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector


def fan(blades=5, pitch=12.0):
    """A hub (r 10, 60 long along z) carrying pitched blades: no outline is constant."""
    shape = Part.makeCylinder(10, 60)
    for k in range(blades):
        blade = Part.makeBox(25, 2, 50, V(8, -1, 5))
        blade.rotate(V(0, 0, 30), V(1, 0, 0), pitch)
        blade.rotate(V(0, 0, 0), V(0, 0, 1), 360.0 * k / blades)
        shape = shape.fuse(blade)
    return shape.removeSplitter()


def block_with_blind_holes():
    """40 x 20 x 60 block, one hole from below ending at z = 40, one from above ending at 35."""
    block = Part.makeBox(40, 20, 60)
    return block.cut(Part.makeCylinder(3, 40, V(10, 10, 0))).cut(
        Part.makeCylinder(3, 25, V(30, 10, 35)))


def turned_part():
    """A shaft with two grooves and two cavities (a cylinder and a sphere cut inside it)."""
    shape = Part.makeCylinder(15, 80)
    for z in (20, 50):
        shape = shape.cut(Part.makeCylinder(15, 4, V(0, 0, z)).cut(
            Part.makeCylinder(12, 4, V(0, 0, z))))
    return shape.cut(Part.makeCylinder(5, 15, V(0, 0, 30))).cut(Part.makeSphere(6, V(0, 0, 60)))


def turned_z(points, degrees, centre=(0.0, 0.0)):
    a = np.radians(degrees)
    p = np.asarray(points, float) - [centre[0], centre[1], 0]
    return np.stack([np.cos(a) * p[:, 0] - np.sin(a) * p[:, 1],
                     np.sin(a) * p[:, 0] + np.cos(a) * p[:, 1], p[:, 2]], 1) + [*centre, 0]


def slice_face(shape, z):
    wires = shape.slice(V(0, 0, 1), z)
    return Part.makeFace(wires, "Part::FaceMakerBullseye")


def random_points(shape, z0, z1, count, seed=0):
    """Points spread over the faces of `shape` strictly between the planes z0 and z1."""
    rng = np.random.default_rng(seed)
    out = []
    for face in shape.Faces:
        u0, u1, v0, v1 = face.ParameterRange
        for _ in range(count):
            u, v = rng.uniform(u0, u1), rng.uniform(v0, v1)
            p = face.Surface.value(u, v)
            if z0 + 1e-6 < p.z < z1 - 1e-6 and face.isPartOfDomain(u, v):
                out.append(tuple(p))
    return np.array(out)


class TwistFan(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.doc = fc.new_document("FlexFan")
        cls.base = cls.doc.addObject("Part::Feature", "Fan")
        cls.base.Shape = fan()
        cls.doc.recompute()
        cls.twist = fd.make_twist(cls.base, (V(0, 0, 18), V(0, 0, 1)),
                                  (V(0, 0, 42), V(0, 0, 1)), 20, axis=(V(0, 0, 0), V(0, 0, 1)))

    @classmethod
    def tearDownClass(cls):
        App.closeDocument(cls.doc.Name)

    def test_one_valid_solid_of_the_same_volume(self):
        shape = self.twist.Shape
        self.assertEqual(len(shape.Solids), 1)
        self.assertTrue(shape.isValid())
        self.assertLess(abs(shape.Volume / self.base.Shape.Volume - 1), 1e-6)

    def test_sections_are_the_original_turned(self):
        for s in (0.2, 0.5, 0.85):
            z = 18 + 24 * s
            got = slice_face(self.twist.Shape, z)
            want = slice_face(self.base.Shape, z)
            want.rotate(V(0, 0, 0), V(0, 0, 1), 20 * s)
            self.assertLess(abs(got.Area / want.Area - 1), 1e-5)
            self.assertLess(abs(got.common(want).Area / want.Area - 1), 1e-5)

    def test_max_deviation_checked_at_random_points(self):
        tol = self.twist.Tolerance.Value
        self.assertLessEqual(self.twist.MaxDeviation, tol)
        pts = random_points(self.base.Shape, 18, 42, 12)
        s = (pts[:, 2] - 18) / 24
        moved = np.vstack([turned_z(p[None], 20 * f) for p, f in zip(pts, s)])
        result = self.twist.Shape
        worst = max(result.distToShape(Part.Vertex(V(*p)))[0] for p in moved)
        self.assertLessEqual(worst, tol)

    def test_smooth_profile_is_g1_at_every_joint_and_reopens(self):
        self.twist.Profile = "Smooth"
        self.doc.recompute()
        self.assertTrue(self.twist.Shape.isValid())
        self.assertLess(abs(self.twist.Shape.Volume / self.base.Shape.Volume - 1), 1e-6)
        kinds = {entry.split(": ")[1] for entry in self.twist.Continuity.split("; ")}
        self.assertEqual(kinds, {"G1"})
        folder = tempfile.mkdtemp()
        self.doc.saveCopy(os.path.join(folder, "flex.FCStd"))
        doc = App.openDocument(os.path.join(folder, "flex.FCStd"))
        try:
            obj = doc.getObject(self.twist.Name)
            obj.touch()
            doc.recompute()
            self.assertEqual(obj.Profile, "Smooth")
            self.assertTrue(obj.Shape.isValid())
        finally:
            App.closeDocument(doc.Name)
        self.twist.Profile = "Linear"
        self.doc.recompute()


class BendBlindHoles(unittest.TestCase):
    def test_pappus_along_the_region(self):
        doc = fc.new_document("FlexBend")
        try:
            base = doc.addObject("Part::Feature", "Block")
            base.Shape = block_with_blind_holes()
            doc.recompute()
            z0, z1, theta = 18.0, 42.0, 30.0
            axis_point = np.array([100.0, 0, z0])
            bend = fd.make_bend(base, (V(0, 0, z0), V(0, 0, 1)), theta,
                                (V(*axis_point), V(0, 1, 0)), plane2=(V(0, 0, z1), V(0, 0, 1)))
            shape = bend.Shape
            self.assertTrue(shape.isValid())
            self.assertEqual(len(shape.Solids), 1)
            # the sections are constant between the holes' ends (35, 40): Gauss points
            # in each piece sum A(s) r(s) exactly
            length, total, region = z1 - z0, 0.0, 0.0
            g = np.polynomial.legendre.leggauss(3)
            for a, b in ((z0, 35.0), (35.0, 40.0), (40.0, z1)):
                for x, w in zip(*g):
                    z = 0.5 * (a + b) + 0.5 * (b - a) * x
                    face = slice_face(base.Shape, z)
                    r = axis_point[0] - face.CenterOfMass.x
                    total += 0.5 * (b - a) * w * face.Area * r * np.radians(theta) / length
                    region += 0.5 * (b - a) * w * face.Area
            bent = shape.Volume - (base.Shape.Volume - region)
            self.assertLess(abs(bent / total - 1), 1e-5)
            self.assertLessEqual(bend.MaxDeviation, bend.Tolerance.Value)
            # the far part turned exactly: the block's top corner
            a = np.radians(theta)
            corner = np.array([40.0, 20.0, 60.0]) - [0, 0, length] - axis_point
            want = axis_point + [np.cos(a) * corner[0] + np.sin(a) * corner[2], corner[1],
                                 -np.sin(a) * corner[0] + np.cos(a) * corner[2]]
            nearest = min(np.linalg.norm(np.array(tuple(v.Point)) - want)
                          for v in shape.Vertexes)
            self.assertLess(nearest, 1e-9)
        finally:
            App.closeDocument(doc.Name)


class TwistVoids(unittest.TestCase):
    def test_cavities_are_kept(self):
        doc = fc.new_document("FlexVoids")
        try:
            base = doc.addObject("Part::Feature", "Turned")
            base.Shape = turned_part()
            doc.recompute()
            for profile in ("Linear", "Smooth"):
                tw = fd.make_twist(base, (V(0, 0, 25), V(0, 0, 1)), (V(0, 0, 57), V(0, 0, 1)),
                                   35, axis=(V(0, 0, 0), V(0, 0, 1)))
                tw.Profile = profile
                doc.recompute()
                shape = tw.Shape
                self.assertTrue(shape.isValid())
                self.assertEqual([len(s.Shells) for s in shape.Solids], [3])
                self.assertLess(abs(shape.Volume / base.Shape.Volume - 1), 1e-9)
                self.assertLessEqual(tw.MaxDeviation, tw.Tolerance.Value)
        finally:
            App.closeDocument(doc.Name)


class RealParts(unittest.TestCase):
    def test_shelf_with_six_voids_smooth_twist_and_bend(self):
        doc = fc.new_document("FlexShelf")
        try:
            base = doc.addObject("Part::Feature", "Shelf")
            shape = Part.Shape()
            shape.read(fc.testdata("fc_shelf.brep"))
            base.Shape = shape
            doc.recompute()
            bb = shape.BoundBox
            axis = int(np.argmax([bb.XLength, bb.YLength, bb.ZLength]))
            n = V(*np.eye(3)[axis])
            lo, length = [bb.XMin, bb.YMin, bb.ZMin][axis], [bb.XLength, bb.YLength,
                                                             bb.ZLength][axis]
            centre = np.array(tuple(bb.Center))
            o1, o2 = centre.copy(), centre.copy()
            o1[axis], o2[axis] = lo + 0.37 * length, lo + 0.63 * length
            tw = fd.make_twist(base, (V(*o1), n), (V(*o2), n), 15)
            tw.Profile = "Smooth"
            doc.recompute()
            self.assertTrue(tw.Shape.isValid())
            self.assertEqual([len(s.Shells) for s in tw.Shape.Solids],
                             [len(s.Shells) for s in shape.Solids])
            self.assertLess(abs(tw.Shape.Volume / shape.Volume - 1), 1e-6)
            self.assertTrue(tw.Continuity)
            self.assertLessEqual(tw.MaxDeviation, tw.Tolerance.Value)
        finally:
            App.closeDocument(doc.Name)


def stepped_shaft():
    """r 15 for z 0..30, r 10 for 30..60, r 6 for 60..90."""
    return Part.makeCylinder(15, 30).fuse(Part.makeCylinder(10, 30, V(0, 0, 30))).fuse(
        Part.makeCylinder(6, 30, V(0, 0, 60))).removeSplitter()


class TaperShaft(unittest.TestCase):
    STEPS = ((20.0, 30.0, 15.0), (30.0, 60.0, 10.0), (60.0, 70.0, 6.0))

    @classmethod
    def setUpClass(cls):
        cls.doc = fc.new_document("FlexTaper")
        cls.base = cls.doc.addObject("Part::Feature", "Shaft")
        cls.base.Shape = stepped_shaft()
        cls.doc.recompute()
        cls.taper = fd.make_taper(cls.base, (V(0, 0, 20), V(0, 0, 1)), (V(0, 0, 70), V(0, 0, 1)),
                                  0.6)

    @classmethod
    def tearDownClass(cls):
        App.closeDocument(cls.doc.Name)

    def test_volume_is_the_integral_of_scaled_sections(self):
        shape = self.taper.Shape
        self.assertTrue(shape.isValid())
        self.assertEqual(len(shape.Solids), 1)
        x, w = np.polynomial.legendre.leggauss(4)
        region = 0.0
        for a, b, r in self.STEPS:  # A(s) scale(s)^2 is a quadratic on each step
            z = 0.5 * (a + b) + 0.5 * (b - a) * x
            k = 1 - 0.4 * (z - 20) / 50
            region += 0.5 * (b - a) * np.sum(w * np.pi * r * r * k * k)
        want = np.pi * 15 ** 2 * 20 + region + np.pi * 6 ** 2 * 20 * 0.36
        self.assertLess(abs(shape.Volume / want - 1), 1e-5)
        self.assertLessEqual(self.taper.MaxDeviation, self.taper.Tolerance.Value)

    def test_sections_are_scaled(self):
        for z, r in ((25, 15), (45, 10), (65, 6), (80, 6)):
            k = 1 - 0.4 * min((z - 20) / 50, 1.0)
            area = slice_face(self.taper.Shape, z).Area
            self.assertLess(abs(area / (np.pi * r * r * k * k) - 1), 1e-5)

    def test_two_scales_and_smooth_profile(self):
        t = self.taper
        t.UseScaleXY, t.ScaleX, t.ScaleY, t.Profile = True, 0.5, 1.2, "Smooth"
        self.doc.recompute()
        try:
            self.assertTrue(t.Shape.isValid())
            bb = slice_face(t.Shape, 80).BoundBox   # the far part: an ellipse 3 x 7.2
            self.assertAlmostEqual(bb.XLength, 6.0, delta=1e-5)
            self.assertAlmostEqual(bb.YLength, 14.4, delta=1e-5)
            kinds = {entry.split(": ")[1] for entry in t.Continuity.split("; ")}
            self.assertEqual(kinds, {"G1"})
        finally:
            t.UseScaleXY, t.Profile = False, "Linear"
            self.doc.recompute()

    def test_bad_scale_names_scale_and_keeps_the_base(self):
        before = self.base.Shape.Volume
        self.taper.Scale = -1.0
        self.doc.recompute()
        try:
            self.assertIn("Invalid", self.taper.State)
            self.assertEqual(self.base.Shape.Volume, before)
        finally:
            self.taper.Scale = 0.6
            self.doc.recompute()
        self.assertNotIn("Invalid", self.taper.State)

    def test_mesh_vertices_map_exactly(self):
        import Mesh
        mesh = self.doc.addObject("Mesh::Feature", "ShaftMesh")
        mesh.Mesh = Mesh.Mesh(stepped_shaft().tessellate(0.1))
        self.doc.recompute()
        t = fd.make_taper(mesh, (V(0, 0, 20), V(0, 0, 1)), (V(0, 0, 70), V(0, 0, 1)), 0.6,
                          axis=(V(0, 0, 0), V(0, 0, 1)))
        before = np.array([tuple(p) for p in mesh.Mesh.Topology[0]])
        after = np.array([tuple(p) for p in t.Mesh.Topology[0]])
        k = 1 - 0.4 * np.clip((before[:, 2] - 20) / 50, 0, 1)
        want = before * np.stack([k, k, np.ones_like(k)], 1)
        from scipy.spatial import cKDTree
        # FreeCAD reorders the points; the mesh is cut into 16 slabs first, so the points
        # that are not the Base's lie on the slab planes z = 20 + 50 j / 16
        self.assertLess(cKDTree(after).query(want)[0].max(), 1e-5)   # float32 storage
        new = after[cKDTree(want).query(after)[0] > 1e-5]
        level = (new[:, 2] - 20) / (50 / 16)
        self.assertLess(np.abs(level - np.round(level)).max() * 50 / 16, 1e-5)
        self.assertTrue(((level > -1e-6) & (level < 16 + 1e-6)).all())


class RealStepParts(unittest.TestCase):
    """Smooth Twist and Bend across the middle of real STEP solids (the bracket, the
    filleted machined part): one valid solid, voids and volume kept by the twist,
    Continuity reported, MaxDeviation within Tolerance."""

    def run_case(self, name, make):
        doc = fc.new_document("FlexStep")
        try:
            base = doc.addObject("Part::Feature", "Part")
            shape = Part.read(fc.testdata(name))
            base.Shape = shape
            doc.recompute()
            bb = shape.BoundBox
            axis = int(np.argmax([bb.XLength, bb.YLength, bb.ZLength]))
            lo = [bb.XMin, bb.YMin, bb.ZMin][axis]
            length = [bb.XLength, bb.YLength, bb.ZLength][axis]
            o1, o2 = np.array(tuple(bb.Center)), np.array(tuple(bb.Center))
            o1[axis], o2[axis] = lo + 0.37 * length, lo + 0.63 * length
            n = np.eye(3)[axis]
            obj = make(base, (V(*o1), V(*n)), (V(*o2), V(*n)), bb, axis)
            obj.Profile = "Smooth"
            doc.recompute()
            result = obj.Shape
            self.assertTrue(result.isValid())
            self.assertEqual([len(s.Shells) for s in result.Solids],
                             [len(s.Shells) for s in shape.Solids])
            self.assertTrue(obj.Continuity)
            self.assertLessEqual(obj.MaxDeviation, obj.Tolerance.Value)
            return shape, result
        finally:
            App.closeDocument(doc.Name)

    def test_bracket_twist(self):
        shape, result = self.run_case(
            "fc_Schenkel.stp", lambda base, p1, p2, bb, axis: fd.make_twist(base, p1, p2, 15))
        self.assertLess(abs(result.Volume / shape.Volume - 1), 1e-6)

    def test_filleted_part_bend(self):
        def bend(base, p1, p2, bb, axis):
            w = V(*np.eye(3)[(axis + 1) % 3])
            centre = np.array(tuple(p1[0])) + np.eye(3)[(axis + 2) % 3] * 1.5 * max(
                bb.XLength, bb.YLength, bb.ZLength)
            return fd.make_bend(base, p1, -20, (V(*centre), w), plane2=p2)
        self.run_case("nist_ftc_10_asme1_rb.stp", bend)


class StretchMapPlanes(unittest.TestCase):
    def test_affine_stretch_keeps_planes_and_adds_region_times_factor(self):
        from freecad_deform.geometry.sweep import space_map
        from freecad_deform.shapes import mapped
        shape = block_with_blind_holes()
        smap = space_map.stretch_map(np.array([0, 0, 18.0]), np.array([0, 0, 1.0]), 24, 12.0)
        result, deviation = mapped.map_shape(shape, smap, 1e-3)
        self.assertTrue(result.isValid())
        holes = np.pi * 9 * (17 + 2 * 5 + 2)          # hole lengths inside 18..42
        region = 40 * 20 * 24 - holes
        self.assertLess(abs((result.Volume - shape.Volume) / (region * 0.5) - 1), 1e-6)
        planes = [f for f in result.Faces if f.BoundBox.ZLength > 30 and
                  min(f.BoundBox.XLength, f.BoundBox.YLength) < 1e-9]   # the flat sides
        self.assertGreaterEqual(len(planes), 4)      # the block's sides, stretched
        self.assertTrue(all(f.Surface.TypeId == "Part::GeomPlane" for f in planes))
        self.assertLessEqual(deviation, 1e-3)

    def test_loose_faces_between_two_planes_go_through_the_map(self):
        """A box with two free faces beside it, stretched between x = -5 and 5 by 4: the
        free cylinder along the normal stays cylinders, its lateral area 2 pi 3 (40 + 4);
        the free tube across it (wholly in the region) is refit, and its points mapped back
        by the inverse stretch (written here) lie 3 mm from its axis within Tolerance."""
        doc = App.newDocument("LooseFaces")
        try:
            base = doc.addObject("Part::Feature", "Compound")
            along = Part.makeCylinder(3, 40, V(-20, 30, 0), V(1, 0, 0)).Faces[0]
            across = Part.makeCylinder(3, 10, V(0, -30, -5), V(0, 0, 1)).Faces[0]
            base.Shape = Part.makeCompound([Part.makeBox(40, 20, 10, V(-20, -10, -5)),
                                            along, across])
            s = fd.make_stretch(base, (V(-5, 0, 0), V(1, 0, 0)), 4, plane2=(V(5, 0, 0),
                                                                            V(1, 0, 0)))
            self.assertEqual(s.State, ["Up-to-date"], s.getStatusString())
            self.assertLessEqual(s.MaxDeviation, s.Tolerance.Value)
            solid_faces = {f.hashCode() for f in s.Shape.Solids[0].Faces}
            free = [f for f in s.Shape.Faces if f.hashCode() not in solid_faces]
            tubes = [f for f in free if f.BoundBox.YMin > 0]
            self.assertTrue(all(f.Surface.TypeId == "Part::GeomCylinder" for f in tubes))
            self.assertAlmostEqual(sum(f.Area for f in tubes), 2 * np.pi * 3 * 44, delta=1e-9)
            (mapped_tube,) = [f for f in free if f.BoundBox.YMax < -20]
            pts = np.array([tuple(p) for p in mapped_tube.tessellate(0.05)[0]])
            x = np.where(pts[:, 0] > 5 + 4, pts[:, 0] - 4,
                         np.where(pts[:, 0] > -5, -5 + (pts[:, 0] + 5) * 10 / 14, pts[:, 0]))
            radius = np.hypot(x, pts[:, 1] + 30)
            self.assertLess(np.abs(radius - 3).max(), s.Tolerance.Value)
        finally:
            App.closeDocument(doc.Name)
