"""Taper of a cone between planes slanted to its axis (Scale > 1): a face the region cuts
spans a parameter rectangle reaching past the planes, where the taper's factor
1 + (Scale - 1) t, continued, may pass zero. Where it does the refit would fold (OCCT's BOP
check: self-intersecting), and the Taper is refused naming Scale; elsewhere the result is
valid, passes the BOP check, and is checked against the exact taper map and the volume
integral written here (moments of the Base's region piece from OCCT)."""
import unittest

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402
from freecad_deform.geometry.sweep.planes import frame  # noqa: E402
from freecad_deform.ops import taper  # noqa: E402

V = App.Vector
DIAGONAL = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)


def exact_taper(points, origin, normal, gap, scale, centre):
    """The Linear taper: factor 1 + (scale - 1) t across the axis through `centre` along
    the normal, t the position along the region clamped to [0, 1]."""
    d = points - centre
    along = np.outer(d @ normal, normal)
    t = np.clip((points - origin) @ normal / gap, 0.0, 1.0)
    return centre + along + (1.0 + (scale - 1.0) * t)[:, None] * (d - along)


def slab(origin, normal, a, b, size=500.0):
    """The box of points whose distance along `normal` from `origin` is within [a, b]."""
    x, y, n = frame(normal)
    corner = origin + a * n - 0.5 * size * (x + y)
    box = Part.makeBox(size, size, b - a)
    box.Placement = App.Placement(V(*corner), App.Rotation(V(*x), V(*y), V(*n), "ZXY"))
    return box


def tapered_volume(base, origin, normal, gap, scale):
    """The volume integral of the scaled sections: before Plane 1, in the region
    (1 + k sigma)^2 (k = (scale - 1) / gap, sigma the distance past Plane) from the region
    piece's volume, first and second moments along the normal, beyond Plane2 scale^2."""
    big = 1e4
    before = base.common(slab(origin, normal, -big, 0.0)).Volume
    beyond = base.common(slab(origin, normal, gap, big)).Volume
    piece = base.common(slab(origin, normal, 0.0, gap)).Solids[0]
    vol, com = piece.Volume, np.array(tuple(piece.CenterOfMass)) - origin
    inertia = np.array(piece.MatrixOfInertia.A).reshape(4, 4)[:3, :3]
    m1 = vol * (com @ normal)
    m2 = vol * (com @ normal) ** 2 + 0.5 * np.trace(inertia) - normal @ inertia @ normal
    k = (scale - 1.0) / gap
    return before + vol + 2 * k * m1 + k * k * m2 + scale * scale * beyond


def points_on(shape, count, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    for k, face in enumerate(shape.Faces):
        u0, u1, v0, v1 = face.ParameterRange
        while len(out) < count * (k + 1):
            u, v = rng.uniform(u0, u1), rng.uniform(v0, v1)
            if face.isPartOfDomain(u, v):
                out.append(tuple(face.Surface.value(u, v)))
    return np.array(out)


class ConeTaper(unittest.TestCase):
    CASES = (  # (cone radii and height, plane origin, normal, gap, scale)
        ((10, 0, 40), (0, 0, 0), DIAGONAL, 1.5, 2.43),
        ((10, 0, 40), (3, 3, 0), DIAGONAL, 8.0, 2.43),
        ((8, 2, 30), (0, 0, 10), np.array([1.0, 0, 1.0]) / np.sqrt(2.0), 4.0, 0.6),
    )

    def test_valid_result_on_the_exact_map(self):
        for cone, origin, normal, gap, scale in self.CASES:
            with self.subTest(cone=cone, origin=origin, gap=gap, scale=scale):
                base = Part.makeCone(*cone)
                origin = np.array(origin, float)
                centre = origin + np.array([0.0, 0.0, 5.0])  # the taper's axis: along the normal
                result, out = taper.solid(base, origin, normal, gap, scale, frame(normal),
                                          point=centre)
                self.assertTrue(result.isValid())
                result.check(True)  # OCCT's BOP check: raises on a self-intersection
                mapped = exact_taper(points_on(base, 40), origin, normal, gap, scale, centre)
                far = max(result.distToShape(Part.Vertex(V(*p)))[0] for p in mapped)
                self.assertLess(far, 1e-5)
                self.assertLessEqual(out["MaxDeviation"], 1e-3)
                want = tapered_volume(base, origin, normal, gap, scale)
                self.assertLess(abs(result.Volume / want - 1), 1e-6)


class ConeTaperFolding(unittest.TestCase):
    """Scale 2.43 over 1.5 mm from (3, 3, 0): the factor passes zero 1.05 mm before Plane,
    inside the rectangle of the cone's face the region cuts (before this refusal the result
    was accepted, valid by isValid but self-intersecting by OCCT's BOP check)."""

    def test_op_refuses_naming_scale(self):
        o = np.array([3.0, 3.0, 0.0])
        for gap in (0.15, 1.5):
            with self.subTest(gap=gap):
                with self.assertRaises(DeformError) as caught:
                    taper.solid(Part.makeCone(10, 0, 40), o, DIAGONAL, gap, 2.43,
                                frame(DIAGONAL))
                self.assertEqual(caught.exception.prop, "Scale")

    def test_feature_refuses_and_keeps_the_base(self):
        doc = fc.new_document("TaperFold")
        try:
            base = doc.addObject("Part::Feature", "Cone")
            base.Shape = Part.makeCone(10, 0, 40)
            doc.recompute()
            before = base.Shape.Volume
            n = V(1, 1, 0).normalize()
            obj = fd.make_taper(base, (V(3, 3, 0), n), (V(3, 3, 0) + n * 1.5, n), 2.43)
            self.assertIn("Invalid", obj.State)
            self.assertIn("Scale", obj.getStatusString())
            self.assertEqual(base.Shape.Volume, before)
            obj.Scale = 0.8  # nearer 1 (and below it): no fold, a valid result
            doc.recompute()
            self.assertEqual(obj.State, ["Up-to-date"], obj.getStatusString())
            self.assertTrue(obj.Shape.isValid())
        finally:
            App.closeDocument(doc.Name)


if __name__ == "__main__":
    unittest.main()


class FlatFaceAcrossNoSlope(unittest.TestCase):
    def test_plane_parallel_to_the_planes_falls_back_to_the_general_fit(self):
        """mapped._fitted_plane turns the plane's (u, v) along its slope of s: a face
        parallel to the planes has none (0 / 0 gave NaN poles); it takes the general fit,
        the section at s = 0.5 scaled by 0.75 about the axis (the corners checked)."""
        from freecad_deform.geometry.sweep import space_map
        from freecad_deform.shapes import mapped
        face = Part.makePlane(10, 10, V(1, 2, 5))
        smap = space_map.taper_map(np.zeros(3), np.array([0.0, 0, 1]), 10.0, 0.5,
                                   np.zeros(3))
        built, dev = mapped._fitted_plane(face, smap, 1e-7)
        self.assertTrue(built.isValid())
        self.assertLessEqual(dev, 1e-7)
        corners = np.array([tuple(v.Point) for v in face.Vertexes])
        want = corners * [0.75, 0.75, 1.0]
        got = np.array([tuple(v.Point) for v in built.Vertexes])
        self.assertLess(max(np.linalg.norm(got - w, axis=1).min() for w in want), 1e-9)
        self.assertAlmostEqual(built.Area, 100 * 0.75 ** 2, delta=1e-7)
