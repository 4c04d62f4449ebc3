"""Lemma 1: G1 exactly when the surface normal is perpendicular to the trajectory tangent."""
import numpy as np
from hypothesis import given, strategies as st

from freecad_deform.geometry.sweep.continuity import joint_continuity, report
from freecad_deform.geometry.sweep.planes import frame


def test_box_side_is_g1_wedge_slope_is_c0():
    t = np.array([1.0, 0, 0])
    box_side = np.array([[0, 1.0, 0], [0, 0, 1.0], [0, -1.0, 0]])
    wedge_slope = np.array([[0.5, 0, np.sqrt(0.75)]])
    assert joint_continuity(box_side, t) == "G1"
    assert joint_continuity(wedge_slope, t) == "C0"
    assert joint_continuity(np.vstack([box_side, wedge_slope]), t) == "C0"


@given(st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1),
       st.floats(0, 2 * np.pi), st.floats(1e-3, 1.0))
def test_perpendicular_normals_are_g1_tilted_c0(direction, angle, tilt):
    u, v, n = frame(direction)
    normal = np.cos(angle) * u + np.sin(angle) * v
    assert joint_continuity(normal[None], n) == "G1"
    assert joint_continuity((normal + tilt * n)[None], n) == "C0"


def test_report_line():
    assert report([("Face3", "G1"), ("Face7", "C0")]) == "Face3: G1; Face7: C0"
