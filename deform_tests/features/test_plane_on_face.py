"""A Plane or Plane2 lying on a face of the part, as when a user snaps it to a step. The
section that Stretch extrudes, Bend revolves and Twist lofts is the material just beyond
the plane, as it is for a mesh's vertices. A face of the part lying in the plane with
nothing beyond it (a step) stays where it is; one that bounds the far side (an overhang)
is part of the section. Before, the step was extruded or revolved too, and material
appeared above it (the L gained 1000 mm^3 instead of 500), or an overhang's region was
rebuilt from the near section alone and lost material.

Oracles: OCCT's Volume and isValid() of the result against A*d and Pappus, with A and the
centroid from the boxes' own dimensions; isInside at a point above the step.
"""
import numpy as np
import pytest

from . import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

from freecad_deform.geometry.errors import DeformError  # noqa: E402
from freecad_deform.geometry.sweep.motion import ScrewMotion, translation  # noqa: E402
from freecad_deform.ops import bend, keyed, stretch, twist  # noqa: E402

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])
AT = np.array([0.0, 0.0, 10.0])          # Plane, on the face at z = 10
ANGLE = np.radians(30.0)
BEND_AXIS = (np.array([40.0, 0.0, 10.0]), np.array([0.0, 1.0, 0.0]))


def box(x, y, z, at=(0, 0, 0)):
    return Part.makeBox(x, y, z, V(*at))


def fused(*boxes):
    return boxes[0].fuse(list(boxes[1:])).removeSplitter().Solids[0]


# (solid, its volume, the section beyond z = 10: area and centroid x); all 10 mm deep in y
STEP = (fused(box(20, 10, 10), box(10, 10, 30)), 4000.0, 100.0, 5.0)   # L: a step at z = 10
OVERHANG = (fused(box(10, 10, 10), box(20, 10, 10, (0, 0, 10)), box(10, 10, 20, (0, 0, 20))),
            5000.0, 200.0, 10.0)                                      # wider beyond z = 10
CASES = {"step": STEP, "overhang": OVERHANG}


def checked(result, volume, rel=1e-9):
    assert result.isValid()
    assert len(result.Solids) == 1
    assert result.Volume == pytest.approx(volume, rel=rel)
    return result


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("gap", [None, 10.0])
def test_stretch_extrudes_the_section_beyond_the_plane(case, gap):
    solid, volume, area, _ = CASES[case]
    result, report = stretch.solid(solid, AT, Z, 5.0, gap)
    checked(result, volume + area * 5.0)
    assert report["VolumeChange"] == pytest.approx(area * 5.0, rel=1e-9)
    if case == "step":  # nothing grew on the step
        assert not result.isInside(V(15, 5, 12), 1e-7, True)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("gap", [None, 10.0])
def test_bend_revolves_the_section_beyond_the_plane(case, gap):
    """Pappus: the section turned about the axis, its centroid 40 - x from it."""
    solid, volume, area, x = CASES[case]
    swept = area * (BEND_AXIS[0][0] - x) * ANGLE
    result, _ = bend.solid(solid, AT, Z, ANGLE, BEND_AXIS, gap)
    checked(result, volume + swept - (0.0 if gap is None else area * gap))
    if case == "step":
        assert not result.isInside(V(15, 5, 12), 1e-7, True)


TWISTED = {
    **CASES,
    "step at Plane2": fused(box(10, 10, 20), box(20, 10, 20, (0, 0, 20))),
    "narrowing at Plane2": fused(box(20, 10, 20), box(10, 10, 20, (0, 0, 20))),
}


@pytest.mark.parametrize("case", TWISTED)
def test_twist_with_a_plane_on_a_face_keeps_the_volume(case):
    """A twist about the column's axis keeps every section's area: the volume stays (to
    the loft's and refit's 1e-6; the old code refused three of these, naming Angle)."""
    solid = TWISTED[case][0] if isinstance(TWISTED[case], tuple) else TWISTED[case]
    result, report = twist.solid(solid, AT, Z, 10.0, ANGLE, (np.array([5.0, 5.0, 0.0]), Z))
    checked(result, solid.Volume, 1e-6)
    assert abs(report["VolumeChange"]) < 1e-6 * solid.Volume


def test_keyed_lofts_the_section_the_near_part_shares():
    """KeyPlacements' loft starts from the near part's faces: on the L it lofts the
    column's section (+100 x 5), not the step; a solid lying on Plane with nothing before
    it moves whole (as before this change, which had the loft refused for it)."""
    motion = ScrewMotion(translation(5.0 * Z))
    checked(keyed.solid(STEP[0], AT, Z, motion, 4)[0], STEP[1] + 100.0 * 5.0)
    lying = Part.makeCompound([box(10, 10, 10, (0, 0, 10)), box(5, 5, 20, (30, 0, 0))])
    result = keyed.solid(lying, AT, Z, motion, 4)[0]
    assert all(s.isValid() for s in result.Solids)
    assert result.Volume == pytest.approx(1000.0 + 500.0 + 25.0 * 5.0, rel=1e-9)


def test_bend_maps_a_solid_that_starts_between_the_planes():
    """A solid of a compound with no section at Plane but a piece between the planes goes
    through the bend map (the piece was dropped: 300 of 800 mm^3 lost). Pappus on the part
    of the region it fills (s from 0.4 to 1 of the gap) plus the far part, moved whole."""
    lone = box(10, 10, 8, (0, 0, 12))
    crossing = box(5, 5, 20, (30, 0, 0))   # crosses both planes: the whole region bent
    result, _ = bend.solid(Part.makeCompound([lone, crossing]), AT, Z, ANGLE, BEND_AXIS, 5.0)
    assert len(result.Solids) == 2 and all(s.isValid() for s in result.Solids)
    want = sorted([100.0 * (BEND_AXIS[0][0] - 5.0) * ANGLE * 0.6 + 500.0,
                   250.0 + 25.0 * (BEND_AXIS[0][0] - 32.5) * ANGLE + 125.0])
    assert sorted(s.Volume for s in result.Solids) == pytest.approx(want, rel=1e-6)


def test_a_fuse_that_fails_names_plane():
    """A hole tangent to Plane from below: OCCT's fuse of the pieces fails; the refusal is a
    DeformError naming Plane, not OCCT's RuntimeError."""
    solid = box(20, 10, 20).cut(Part.makeCylinder(3, 10, V(10, 0, 7), V(0, 1, 0)))
    with pytest.raises(DeformError) as err:
        stretch.solid(solid, AT, Z, 5.0)
    assert err.value.prop == "Plane"
