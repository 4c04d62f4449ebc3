"""brep.join's fallbacks, forced: when the local glue (`_glued`) or the local face merge
(`_merged_at_joints`) gives up after it has sewn and merged, the sewing of everything, the
whole merge and the fuse run on the same pieces. Those must still be what the split made:
the result is the same solid as without the failure, and no piece lost or gained a hole.

The part is a plate with 12 x 12 holes (its big faces have 145 wires: their holes clear of
the joint are taken out and put back), stretched by a plane through a column of holes.
Oracles: the volume A*d (A the section's area from Shape.slice), OCCT's isValid(), the
number of top faces and of their wires counted on the result, the pieces' wires and areas.
"""
import unittest
from unittest import mock

from . import fc
from ..oracles.shapes import section_area

import FreeCAD as App  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

from freecad_deform.ops import stretch  # noqa: E402
from freecad_deform.shapes import brep  # noqa: E402

V = App.Vector
SIZE, THICK, HOLES = 400.0, 10.0, 12
ORIGIN, NORMAL, DISTANCE = np.array([SIZE * 4.5 / HOLES, 0, 0]), np.array([1.0, 0, 0]), 20.0


def holed_plate():
    plate = Part.makeBox(SIZE, SIZE, THICK)
    holes = [Part.makeCylinder(4, THICK, V(SIZE * (i + 0.5) / HOLES, SIZE * (j + 0.5) / HOLES, 0))
             for i in range(HOLES) for j in range(HOLES)]
    return plate.cut(Part.makeCompound(holes)).Solids[0]


def failing_first(fn, count):
    """A stand-in for `fn` that answers False to its first `count` calls, then is `fn`."""
    calls = []

    def stand_in(*args, **kwargs):
        calls.append(1)
        return False if len(calls) <= count else fn(*args, **kwargs)
    stand_in.calls = calls
    return stand_in


def top_faces(shape):
    """The faces in the plane z = THICK (the plate's top), from their surfaces."""
    return [f for f in shape.Faces if f.Surface.__class__.__name__ == "Plane"
            and abs(f.CenterOfMass.z - THICK) < 1e-9 and abs(f.normalAt(0, 0).z) > 0.999]


class ForcedFallbacksTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        fc.new_document("BrepJoin")  # FreeCAD is up; the shapes need no document
        cls.base = holed_plate()
        cls.expected = cls.base.Volume + section_area(cls.base, ORIGIN, NORMAL) * DISTANCE

    def stretched(self):
        before = self.base.exportBrepToString()
        result = stretch.stretch_shape(self.base, ORIGIN, NORMAL, DISTANCE)
        self.assertEqual(self.base.exportBrepToString(), before, "the Base was changed")
        return result

    def check(self, result, label):
        self.assertTrue(result.isValid(), label)
        self.assertEqual(len(result.Solids), 1, label)
        self.assertAlmostEqual(result.Volume, self.expected, delta=1e-7 * self.expected,
                               msg=label)
        top = top_faces(result)
        self.assertEqual(len(top), 1, f"{label}: the top face is split at the joints")
        self.assertEqual(len(top[0].Wires), 1 + HOLES * HOLES, f"{label}: holes lost or doubled")
        # the cut holes became slots DISTANCE longer: the top face lost exactly their area
        slots = HOLES * 2 * 4 * DISTANCE
        area = (SIZE + DISTANCE) * SIZE - HOLES * HOLES * np.pi * 16 - slots
        self.assertAlmostEqual(top[0].Area, area, delta=1e-6 * area, msg=label)

    def test_without_failure(self):
        self.check(self.stretched(), "no failure")

    def test_glue_gives_up_after_merging(self):
        """_glued has sewn, merged and put the holes back; its last check fails: the full
        sewing and merge then run on the same pieces."""
        shells_valid = failing_first(brep._shells_valid, 1)
        with mock.patch.object(brep, "_shells_valid", shells_valid), \
                mock.patch.object(brep, "_sewn_pieces", wraps=brep._sewn_pieces) as sewn:
            result = self.stretched()
        self.assertGreaterEqual(len(shells_valid.calls), 2)
        self.assertEqual(sewn.call_count, 1, "the fallback sewing did not run")
        self.check(result, "glue failed")

    def test_local_merge_gives_up_after_merging(self):
        """The glue's and then the local merge's face check fail: OCCT's whole merge runs on
        the sewn solid whose faces the local merge already merged and gave holes to."""
        valid_faces = failing_first(brep._valid_faces, 2)
        with mock.patch.object(brep, "_valid_faces", valid_faces), \
                mock.patch.object(brep, "_merged_at_joints",
                                  wraps=brep._merged_at_joints) as local:
            result = self.stretched()
        self.assertGreaterEqual(local.call_count, 1)
        self.assertGreaterEqual(len(valid_faces.calls), 3, "the whole merge was not checked")
        self.check(result, "local merge failed")

    def test_faces_met_on_not_found(self):
        """The faces two pieces meet on at the far joint are not recognised (as when their
        centres of mass differ by more than the match's 1e-9): both stay, the glue closes each piece apart,
        which is closed and manifold but not one piece; that must not pass as valid."""
        unshared = brep._unshared_faces

        def first_joint_only(solids, on_surface):  # those at the far joint all stay
            return unshared(solids, brep.on_planes(on_surface.planes[:1]))

        with mock.patch.object(brep, "_unshared_faces", first_joint_only):
            result = self.stretched()
        self.check(result, "met-on faces kept")

    def test_pieces_keep_their_faces(self):
        """After a glue that gave up, every piece still has its faces, their wires and their
        areas (holes put back into a face the pieces still use would show here)."""
        solid = brep.oriented(self.base)
        near, far = brep.split_zones(solid, ORIGIN, NORMAL, [0.0])
        cut = brep.faces_on_plane(near, ORIGIN, NORMAL)
        pieces = near + brep.extruded(cut, DISTANCE * NORMAL) + brep.translated(
            far, DISTANCE * NORMAL)

        def faces_of(shapes):
            return [sorted((len(f.Wires), round(f.Area, 6)) for f in s.Faces) for s in shapes]

        before = faces_of(pieces)
        joints = [(ORIGIN, NORMAL), (ORIGIN + DISTANCE * NORMAL, NORMAL)]
        with mock.patch.object(brep, "_valid_faces", failing_first(brep._valid_faces, 2)):
            result = brep.join(pieces, joints)
        self.assertEqual(faces_of(pieces), before)
        self.check(result, "pieces after the fallback")


class LastResortsTest(unittest.TestCase):
    """When the local merge and OCCT's merge across the joints both fail their checks,
    the merge of everything (removeSplitter) and then no merge are tried. On a bar with a
    cylindrical cavity cut by Plane, removeSplitter merges the cavity's faces into a solid
    whose faces and shells each pass OCCT's check but the solid does not: it must not be
    handed back (a DeformError is fine, an invalid solid is not)."""

    def test_no_invalid_solid_from_the_last_resorts(self):
        from freecad_deform.geometry.errors import DeformError
        from .test_voids import turned_part
        fc.new_document("BrepLastResorts")
        valid_at_joints = failing_first(brep._valid_at_joints, 1)  # OCCT's merge's check
        with mock.patch.object(brep, "_merged_at_joints", lambda *a, **k: None), \
                mock.patch.object(brep, "_valid_at_joints", valid_at_joints):
            try:
                result = stretch.stretch_shape(turned_part(), np.array([75.0, 0, 0]), NORMAL, 10)
            except DeformError:
                return
        self.assertGreaterEqual(len(valid_at_joints.calls), 2, "the last resorts did not run")
        self.assertTrue(result.isValid())


class LoftedJoinTest(unittest.TestCase):
    """A twist of a region of one outline lofts its sides and glues them locally to the near
    and far parts (brep.glue), without sewing all their faces: the 12 x 12-hole plate with a
    plain 100 mm tail, twisted 90 deg in the tail. Oracles: the loft is glued (not sewn
    whole), isValid(), the volume kept to 1e-6, the far holes turned by the angle."""

    def test_twist_in_the_tail_is_glued(self):
        from freecad_deform.ops import twist
        fc.new_document("BrepLofted")
        solid = holed_plate().fuse(Part.makeBox(100, SIZE, THICK, V(SIZE, 0, 0))).removeSplitter()
        solid = solid.Solids[0]
        glued, glue = [], brep.glue

        def recorded(*args):
            glued.append(glue(*args))
            return glued[-1]

        x0 = np.array([SIZE + 30.0, 0, 0])
        axis = np.array([0, SIZE / 2, THICK / 2])
        with mock.patch.object(brep, "glue", recorded):
            result = twist.twist_shape(solid, x0, NORMAL, 40.0, np.radians(90), axis, NORMAL)
        self.assertTrue(glued and glued[-1] is not None, "the loft was not glued")
        self.assertTrue(result.isValid())
        self.assertEqual(len(result.Solids), 1)
        self.assertAlmostEqual(result.Volume, solid.Volume, delta=1e-6 * solid.Volume)
        # beyond Plane2 the tail is turned a quarter about the axis: its end face spans
        # the plate's thickness in y and its width in z
        end = [f for f in result.Faces if abs(f.CenterOfMass.x - (SIZE + 100)) < 1e-9]
        self.assertEqual(len(end), 1)
        box = end[0].BoundBox
        self.assertAlmostEqual(box.YLength, THICK, delta=1e-7)
        self.assertAlmostEqual(box.ZLength, SIZE, delta=1e-7)


class BaseOnlyReadTest(unittest.TestCase):
    """Stretch, Bend and Twist of the holed plate leave the Base as it was, to the byte of
    its BREP text (tolerances, curves on faces, geometry): the ops work on copies of its
    topology that share its curves and surfaces."""

    @classmethod
    def setUpClass(cls):
        fc.new_document("BrepOnlyRead")
        cls.base = holed_plate()
        cls.text = cls.base.exportBrepToString()

    def test_ops_leave_the_base(self):
        from freecad_deform.ops import bend, twist
        y = np.array([0.0, 1.0, 0.0])
        runs = {
            "stretch": lambda: stretch.stretch_shape(self.base, ORIGIN, NORMAL, DISTANCE),
            "bend": lambda: bend.bend_shape(self.base, ORIGIN, NORMAL, np.radians(30),
                                            ORIGIN + [0, 0, -40], y),
            # the region between the planes changes its outline: the twist map
            "twist": lambda: twist.twist_shape(self.base, ORIGIN, NORMAL, 30.0, np.radians(20),
                                               np.array([0, SIZE / 2, THICK / 2]), NORMAL)}
        for name, run in runs.items():
            result = run()
            self.assertTrue(result.isValid(), name)
            self.assertEqual(self.base.exportBrepToString(), self.text, f"{name} changed the Base")

    def test_ops_leave_a_bspline_base(self):
        """The same for Stretch, Bend, Twist and Taper of a cylinder whose faces are
        B-splines (toNurbs): the region between two planes goes through the space maps."""
        from freecad_deform.ops import bend, taper, twist
        base = Part.makeCylinder(10, 60, V(0, 0, 0), V(1, 0, 0)).toNurbs()
        text = base.exportBrepToString()
        o, o2, y = np.array([20.0, 0, 0]), np.array([40.0, 0, 0]), np.array([0, 1.0, 0])
        runs = {
            "stretch": lambda: stretch.stretch_shape(base, o, NORMAL, 5.0, gap=20.0),
            "bend": lambda: bend.bend_shape(base, o2, NORMAL, np.radians(20),
                                            o2 + [0, 0, -30], y),
            "twist": lambda: twist.twist_shape(base, o, NORMAL, 20.0, np.radians(30),
                                               np.zeros(3), NORMAL),
            "taper": lambda: taper.solid(base, o, NORMAL, 20.0, 0.8, np.eye(3)[[1, 2, 0]])[0]}
        for name, run in runs.items():
            result = run()
            self.assertTrue(result.isValid(), name)
            self.assertEqual(base.exportBrepToString(), text, f"{name} changed the Base")

if __name__ == "__main__":
    unittest.main()
