"""The join of a region taken through a space map (shapes.mapped): loose faces sewn again
without losing any, and a solid whose mapped faces go into the pieces locally.

Oracles: areas and volumes in closed form (a Linear stretch scales lengths along the normal
by (gap + distance) / gap; a twist keeps volume and turns each section), OCCT's isValid(),
its BOP check (BOPAlgo_ArgumentAnalyzer through Shape.check(True)), Shape.slice.
"""
import unittest
from unittest import mock

from . import fc

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.sweep import space_map  # noqa: E402
from freecad_deform.shapes import mapped  # noqa: E402

V = App.Vector


def stepped_bar(steps=6):
    """A bar along z with `steps` square teeth on one side, each 2 mm high: its section
    changes between any two planes 2 mm apart, so a twist goes through the space map."""
    bar = Part.makeBox(10, 10, 40)
    for k in range(steps):
        bar = bar.fuse(Part.makeBox(3, 4, 2, V(10, 3, 4 + 5 * k)))
    return bar.removeSplitter().Solids[0]


class LooseFacesThroughTheMap(unittest.TestCase):
    def test_faces_sewing_leaves_outside_a_shell_are_kept(self):
        """A loose shell (as an open shell of a STEP file may be) of two faces that meet
        and one apart: sewing makes one shell of the two; the third must stay beside it
        (it was dropped whenever a shell formed)."""
        shell = stepped_bar(1).Shells[0]

        def at(face, x=None, y=None):
            c = face.CenterOfMass
            return (x is None or abs(c.x - x) < 1e-9) and (y is None or abs(c.y - y) < 1e-9)

        keep = [f for f in shell.Faces if at(f, x=0) or at(f, y=0) or at(f, x=13)]
        self.assertEqual(len(keep), 3)
        part = shell.removeShape([f for f in shell.Faces if not any(f.isSame(k) for k in keep)])
        # the region z = 0..40 stretched to 60: every face is upright, its area grows 1.5 x
        smap = space_map.stretch_map(np.zeros(3), np.array([0, 0, 1.0]), 40.0, 20.0)
        out, deviation = mapped.map_loose([part], smap, 1e-3)
        result = Part.makeCompound(out)
        self.assertEqual(len(result.Faces), 3)
        self.assertEqual(len(result.Shells), 1)
        self.assertAlmostEqual(result.Area, 1.5 * (400 + 400 + 8), places=6)
        self.assertLess(deviation, 1e-3)
        self.assertTrue(all(f.isValid() for f in result.Faces))


class LocalJoin(unittest.TestCase):
    def twisted(self, solid, z0, z1, angle, profile=None):
        doc = fc.new_document("MappedJoin")
        self.addCleanup(App.closeDocument, doc.Name)
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = solid
        doc.recompute()
        obj = fd.make_twist(base, (V(0, 0, z0), V(0, 0, 1)), (V(0, 0, z1), V(0, 0, 1)), angle,
                            axis=(V(5, 5, 0), V(0, 0, 1)))
        if profile:
            obj.Profile = profile
            doc.recompute()
        self.assertNotIn("Invalid", obj.State, obj.getStatusString())
        return obj

    def test_twist_of_a_region_that_changes_its_outline(self):
        solid = stepped_bar()
        z0, z1, angle = 7.5, 22.5, 30.0
        joined, local = [], mapped._joined_locally

        def recorded(*args):
            joined.append(local(*args))
            return joined[-1]

        with mock.patch.object(mapped, "_joined_locally", recorded):
            obj = self.twisted(solid, z0, z1, angle)
        self.assertTrue(joined and all(j is not None for j in joined),
                        "the local join gave up: the full sewing made this result")
        result = obj.Shape
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        self.assertEqual(len(result.Shells), 1)
        result.check(True)  # raises on any BOP check failure (self-intersection included)
        # a twist keeps volume; VolumeChange is the result's volume less the Base's
        self.assertLess(abs(result.Volume - solid.Volume), 1e-7 * solid.Volume)
        self.assertLess(abs(obj.VolumeChange - (result.Volume - solid.Volume)), 1e-9)
        # faces: the Base's, those the planes cut counted twice (four sides of the bar at
        # each plane; the teeth lie clear of the planes)
        cut = sum(1 for f in solid.Faces for z in (z0, z1)
                  if f.BoundBox.ZMin < z - 1e-9 and f.BoundBox.ZMax > z + 1e-9)
        self.assertEqual(cut, 8)
        self.assertEqual(len(result.Faces), len(solid.Faces) + cut)
        # each section turned by its share of the angle, area kept
        for z in (8.0, 15.0, 22.0):
            want = Part.makeFace(solid.slice(V(0, 0, 1), z), "Part::FaceMakerBullseye")
            got = Part.makeFace(result.slice(V(0, 0, 1), z), "Part::FaceMakerBullseye")
            turn = App.Rotation(V(0, 0, 1), angle * (z - z0) / (z1 - z0))
            centre = turn.multVec(want.CenterOfMass - V(5, 5, z)) + V(5, 5, z)
            self.assertLess(abs(got.Area / want.Area - 1), 1e-7, z)
            self.assertLess((got.CenterOfMass - centre).Length, 1e-6, z)
        # faces away from the region kept as they were (the far ones turned by the angle)
        turn = App.Rotation(V(0, 0, 1), angle)
        for face in solid.Faces:
            box = face.BoundBox
            if box.ZMax < z0 - 1e-9:
                where = face.CenterOfMass
            elif box.ZMin > z1 + 1e-9:
                where = turn.multVec(face.CenterOfMass - V(5, 5, 0)) + V(5, 5, 0)
            else:
                continue
            kept = min(result.Faces, key=lambda g: (g.CenterOfMass - where).Length)
            self.assertLess((kept.CenterOfMass - where).Length, 1e-9)
            self.assertLess(abs(kept.Area / face.Area - 1), 1e-12)

    def test_slanted_planes_under_a_smooth_twist(self):
        """A box tilted across the planes: its region's faces are planes whose (u, v) run
        neither along the sections nor up the slope, each fitted as a ruled image (straight
        along its lines of constant s). Random points of the region's faces, turned by the
        exact Smooth twist written here, lie on the result within MaxDeviation, which is
        within Tolerance; the volume is kept to MaxDeviation x the region's area."""
        solid = Part.makeBox(10, 10, 40)
        solid.rotate(V(5, 5, 20), V(1, 0.3, 0), 17)
        z0, z1, angle = 12.0, 28.0, 40.0
        obj = self.twisted(solid, z0, z1, angle, "Smooth")
        result = obj.Shape
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        result.check(True)
        self.assertLessEqual(obj.MaxDeviation, obj.Tolerance.Value)
        region = solid.common(Part.makeBox(100, 100, z1 - z0, V(-50, -50, z0)))
        slanted = [f for f in region.Faces if abs(f.normalAt(0, 0).z) < 1 - 1e-9]
        self.assertEqual(len(slanted), 4)
        self.assertLess(abs(result.Volume - solid.Volume),
                        obj.MaxDeviation * region.Area + 1e-9 * solid.Volume)
        ruled = [f for f in result.Faces if f.Surface.TypeId == "Part::GeomBSplineSurface"]
        self.assertEqual(len(ruled), 4)
        self.assertTrue(all(1 in (f.Surface.UDegree, f.Surface.VDegree) for f in ruled))
        rng = np.random.default_rng(3)
        worst = 0.0
        for face in slanted:
            u0, u1, v0, v1 = face.ParameterRange
            for u, v in rng.uniform((u0, v0), (u1, v1), (40, 2)):
                if not face.isPartOfDomain(u, v):
                    continue
                p = face.valueAt(u, v)
                s = (p.z - z0) / (z1 - z0)
                turn = App.Rotation(V(0, 0, 1), angle * s * s * (3 - 2 * s))
                image = turn.multVec(p - V(5, 5, 0)) + V(5, 5, 0)
                worst = max(worst, result.distToShape(Part.Vertex(image))[0])
        self.assertLessEqual(worst, obj.MaxDeviation + 1e-9)


class ContinuityOfPlanarFaces(unittest.TestCase):
    def test_report_matches_occt_sections(self):
        """Planar faces with straight edges get their section's ends without OCCT's section:
        the report must equal Lemma 1 judged here on OCCT's slice of every face (points
        along the section edges, the face's normal there), under a bend whose joints are
        G1 on some faces and C0 on others, at both planes."""
        # tilted about the bend axis's direction: the faces facing it stay G1, the others
        # (and the hole, sectioned by OCCT in the report too) turn C0
        solid = Part.makeBox(10, 10, 40).cut(Part.makeCylinder(2, 40, V(5, 5, 0)))
        solid.rotate(V(5, 5, 20), V(0, 1, 0), 17)
        n, z0, gap = np.array([0, 0, 1.0]), 12.0, 16.0
        smap = space_map.bend_map(np.array([0, 0, z0]), n, gap, np.radians(30),
                                  np.array([60.0, 0, 20]), np.array([0, 1.0, 0]))
        out = mapped.continuity_report(solid, smap)
        want = {}
        for side, z in ((0, z0), (1, z0 + gap)):
            for k, face in enumerate(solid.Faces):
                edges = [e for w in face.copy().slice(V(*n), z) for e in w.Edges]
                if not edges:
                    continue
                pts = np.array([tuple(e.valueAt(t)) for e in edges
                                for t in np.linspace(e.FirstParameter, e.LastParameter, 9)])
                normals = np.array([tuple(face.Surface.normal(*face.Surface.parameter(V(*p))))
                                    for p in pts])
                jump = smap.normal_derivative(pts, side)
                size = np.linalg.norm(jump, axis=1)
                ok = (size < 1e-6) | (np.abs(np.einsum("ij,ij->i", normals, jump)) <= 1e-6 * size)
                name = f"Face{k + 1}"
                want[name] = "C0" if not ok.all() or want.get(name) == "C0" else "G1"
        self.assertEqual({"G1", "C0"}, set(want.values()))
        self.assertEqual(list(out["SplitFaces"]), sorted(want, key=lambda k: int(k[4:])))
        self.assertEqual(dict(e.split(": ") for e in out["Continuity"].split("; ")), want)


if __name__ == "__main__":
    unittest.main()
