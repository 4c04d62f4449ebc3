"""Failures found by running every B-rep feature on public models the project had not seen
(OCCT's data/occ, pythonocc-demos, trimesh), each rebuilt here from Part primitives.

Oracles: OCCT's Volume and isValid() against closed forms (A x d, Pappus), bounding boxes
of the part that must stay, OCCT's BOP check.
"""
import numpy as np
import pytest

from . import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

from freecad_deform.ops import bend, stretch  # noqa: E402

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])


def shaft_with_cone():
    """A cylinder r 5 from z = -10 to 0 with a cone (r 5 to 2) on it: the joint circle at
    z = 0 is where OCCT's Pump_Nut has a sliver cone face ending."""
    return Part.makeCylinder(5, 10, V(0, 0, -10)).fuse(
        Part.makeCone(5, 2, 10, V(0, 0, 0))).removeSplitter().Solids[0]


@pytest.mark.parametrize("below", [1.2e-7, 1.4e-7, 1.9e-7])
def test_plane_just_below_a_joint_keeps_the_near_part(below):
    """A plane 1.2e-7 to 1.9e-7 below the joint: OCCT merges the cut points with the joint's
    vertices, so the piece before the plane keeps vertices up to 1.9e-7 beyond it. It was
    sorted by its first vertex off the plane, one of those: the whole part was taken as
    far, moved, and the result had the volume of the Base (Pump_Nut, stretch at 50 %)."""
    solid = shaft_with_cone()
    origin = np.array([0.0, 0.0, -below])
    result, report = stretch.solid(solid, origin, Z, 5.0)
    assert result.isValid()
    assert len(result.Solids) == 1
    assert result.Volume == pytest.approx(solid.Volume + 25 * np.pi * 5.0, rel=1e-9)
    assert result.BoundBox.ZMin == pytest.approx(-10.0, abs=1e-9)
    assert result.BoundBox.ZMax == pytest.approx(15.0, abs=1e-6)
    result.check(True)   # the BOP check raises on self-intersections


def test_bend_at_a_plane_just_below_a_joint():
    solid = shaft_with_cone()
    origin = np.array([0.0, 0.0, -1.4e-7])
    axis = (np.array([15.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    angle = np.radians(30.0)
    result, _ = bend.solid(solid, origin, Z, angle, axis)
    assert result.isValid()
    # Pappus: the section (r 5, centroid on the part's axis, 15 from the bend axis)
    assert result.Volume == pytest.approx(solid.Volume + 25 * np.pi * 15.0 * angle, rel=1e-6)
    assert result.BoundBox.ZMin == pytest.approx(-10.0, abs=1e-9)
