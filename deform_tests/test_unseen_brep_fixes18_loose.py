"""A Base with an absurd edge tolerance (OCCT's data/occ/solid.brep: a hole's exact circle
carries 1.5708 mm, pi / 2, on a 240 mm part), found by running every feature on public
B-rep models (see /work/notes/unseen_brep18.md), rebuilt here from primitives.

Oracles: OCCT's isValid, BOP check and Volume against the closed-form section x Distance.
"""
import numpy as np
import pytest

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector


def loose_plate():
    """A plate 240 x 60 x 20 with a hole of radius 10 through it at (210, 30), the hole's
    top circle given a tolerance of pi / 2 mm (its geometry exact, as the file's)."""
    plate = Part.makeBox(240, 60, 20).cut(Part.makeCylinder(10, 20, V(210, 30, 0))).Solids[0]
    top = next(e for e in plate.Edges if type(e.Curve).__name__ == "Circle"
               and abs(e.Vertexes[0].Point.z - 20) < 1e-9)
    top.limitTolerance(np.pi / 2)
    return plate


def test_loose_plate_is_what_the_test_needs():
    plate = loose_plate()
    assert plate.isValid()
    assert plate.getTolerance(1) == pytest.approx(np.pi / 2)
    assert plate.Volume == pytest.approx((240 * 60 - np.pi * 100) * 20, rel=1e-9)


@pytest.mark.parametrize("y", [27.47, 25.0, 35.0])
def test_stretch_through_a_hole_with_a_loose_edge(y):
    """Stretched across y through the hole by 6 mm: OCCT's split, keeping the 1.57 mm
    tolerance, gave pieces 1947 mm^3 more than the plate (at y = 27.47), and the result
    was 1686 mm^3 more than the section x 6, Up-to-date, and failed OCCT's BOP check
    (TooSmallEdge) at all three planes. The section of the plate at y is the closed form
    (240 - chord of the hole) x 20."""
    plate = loose_plate()
    chord = 2.0 * np.sqrt(100.0 - (y - 30.0) ** 2)
    section = (240.0 - chord) * 20.0
    doc = fc.new_document("UnseenLoosePlate")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = plate
        obj = fd.make_stretch(base, (V(120, y, 10), V(0, 1, 0)), 6.0)
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        result = obj.Shape
        assert result.isValid()
        assert result.Volume - plate.Volume == pytest.approx(section * 6.0, rel=1e-7)
        result.check(True)   # raises on TooSmallEdge
        assert base.Shape.getTolerance(1) == pytest.approx(np.pi / 2)   # the Base kept
    finally:
        App.closeDocument(doc.Name)
