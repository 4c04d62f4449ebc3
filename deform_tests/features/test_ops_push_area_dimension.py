"""The ops of DirectPush, AreaConstrain and DimensionDrive called without a document (as the
panels' previews, the benchmarks and the batch runner call them): Part and Mesh objects
in, (result, outputs) out, the input never changed.

Oracles: OCCT's distToShape, Area, isValid and Volume on the results; plane heights read
off the mesh's vertices; the area by Gauss-Legendre on OCCT's own derivatives."""
import unittest

from . import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import numpy as np  # noqa: E402
import Part  # noqa: E402

from freecad_deform.geometry.errors import DeformError  # noqa: E402
from freecad_deform.ops import area_constrain, dimension_drive, direct_push  # noqa: E402

from .test_area_constrain import canopy_surface, occt_area  # noqa: E402

V = App.Vector


def wavy_edge():
    curve = Part.BSplineCurve()
    curve.interpolate([V(x, 10 * np.sin(x / 15.0), 2 * np.cos(x / 25.0))
                       for x in np.linspace(0, 70, 8)])
    return curve.toShape()


class TestDirectPushOp(unittest.TestCase):
    def test_a_curve_push_lands_and_the_base_stays(self):
        edge = wavy_edge()
        before = [tuple(p) for p in edge.Curve.getPoles()]
        point = edge.valueAt(edge.FirstParameter + 0.4 * (edge.LastParameter - edge.FirstParameter))
        target = point + V(0, 6, 3)
        result, outputs = direct_push.curve(edge, "Edge1", [point], [target], fixed=[])
        self.assertLess(result.distToShape(Part.Vertex(target))[0], 1e-7)
        self.assertEqual([tuple(p) for p in edge.Curve.getPoles()], before)
        self.assertGreater(outputs["MaxPoleMove"], 0)
        self.assertEqual(set(outputs), {"MaxPoleMove", "PoleCount", "Conversion", "RangeUsed"})

    def test_a_face_push_of_a_box_keeps_the_solid_closed(self):
        box = Part.makeBox(40, 30, 20)
        top = next(i for i, f in enumerate(box.Faces) if abs(f.CenterOfMass.z - 20) < 1e-9)
        point, target = V(20, 15, 20), V(20, 15, 26)
        result, outputs = direct_push.face(box, f"Face{top + 1}", [point], [target])
        self.assertTrue(result.isValid())
        self.assertTrue(result.Shells[0].isClosed())
        self.assertLess(result.Faces[top].distToShape(Part.Vertex(target))[0], 1e-7)
        self.assertGreater(result.Volume, box.Volume)
        self.assertAlmostEqual(box.Volume, 40 * 30 * 20, delta=1e-9)

    def test_replay_gives_the_state_a_panel_drags(self):
        edge = wavy_edge()
        point = edge.valueAt(edge.FirstParameter + 0.5 * (edge.LastParameter - edge.FirstParameter))
        inputs = direct_push.inputs_for(edge, "Edge1", [point], [point + V(0, 0, 4)])
        state = direct_push.replay(inputs)
        self.assertEqual(state.shape_type, "Edge")
        self.assertEqual(len(state.params), 1)
        self.assertLess(np.linalg.norm(state.points[0] - np.array(tuple(point))), 1e-6)

    def test_unequal_points_and_targets_name_targets(self):
        with self.assertRaises(DeformError) as e:
            direct_push.curve(wavy_edge(), "Edge1", [V(0, 0, 0)], [])
        self.assertEqual(e.exception.prop, "Targets")


class TestAreaConstrainOp(unittest.TestCase):
    def test_the_face_reaches_the_target_area(self):
        face = Part.Face(canopy_surface())
        result, outputs = area_constrain.face(face, "Face1", target_ratio=1.04)
        before = occt_area(face.Surface)
        self.assertAlmostEqual(occt_area(result.Surface), 1.04 * before, delta=1e-9 * before)
        self.assertAlmostEqual(outputs["OriginalArea"], before, delta=1e-9 * before)
        self.assertTrue(result.isValid())

    def test_a_negative_ratio_names_target_ratio(self):
        with self.assertRaises(DeformError) as e:
            area_constrain.face(Part.Face(canopy_surface()), "Face1", target_ratio=-1.0)
        self.assertEqual(e.exception.prop, "TargetRatio")


class TestDimensionDriveOp(unittest.TestCase):
    def test_a_plane_distance_is_driven_on_a_box_mesh(self):
        mesh = MeshPart.meshFromShape(Shape=Part.makeBox(100, 60, 30), MaxLength=5.0)
        points = np.array([tuple(p) for p in mesh.Topology[0]])
        model = dimension_drive.handle(points, np.array(mesh.Topology[1]),
                                       handle_tolerance=0.0)
        regions = [(50, 30, 30), (50, 30, 0)]       # top moves, bottom stays
        self.assertAlmostEqual(dimension_drive.measure(model, "Distance", regions)[0], 30,
                               delta=1e-4)
        result, outputs = dimension_drive.mesh(model, mesh, "Distance", regions, 36.0)
        moved = np.array([tuple(p) for p in result.Topology[0]])
        top, bottom = points[:, 2] > 30 - 1e-6, points[:, 2] < 1e-6
        np.testing.assert_allclose(moved[top, 2], 36.0, atol=1e-5)
        np.testing.assert_allclose(moved[bottom], points[bottom], atol=1e-9)
        self.assertAlmostEqual(outputs["Achieved"], 36.0, delta=1e-5)
        self.assertAlmostEqual(outputs["Current"], 30.0, delta=1e-5)
        self.assertEqual(result.CountFacets, mesh.CountFacets)
        self.assertTrue(np.allclose(np.array([tuple(p) for p in mesh.Topology[0]]), points))

    def test_a_feature_angle_out_of_range_names_it(self):
        with self.assertRaises(DeformError) as e:
            dimension_drive.handle(np.eye(3), np.array([[0, 1, 2]]), feature_angle=180)
        self.assertEqual(e.exception.prop, "FeatureAngle")

    def test_a_refusal_carries_what_was_measured(self):
        mesh = MeshPart.meshFromShape(Shape=Part.makeBox(100, 60, 30), MaxLength=5.0)
        model = dimension_drive.handle(np.array([tuple(p) for p in mesh.Topology[0]]),
                                       np.array(mesh.Topology[1]))
        with self.assertRaises(DeformError) as e:
            dimension_drive.mesh(model, mesh, "Distance", [(50, 30, 30), (50, 30, 0)], -5.0)
        self.assertEqual(e.exception.prop, "Target")
        self.assertIsInstance(getattr(e.exception, "outputs", None), dict)


if __name__ == "__main__":
    unittest.main()
