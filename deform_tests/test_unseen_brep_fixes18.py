"""Robustness defects found by running every feature on public B-rep models the project had
not seen (OCCT's data/occ and data/step, see /work/notes/unseen_brep18.md), each rebuilt
here from primitives.

Oracles: OCCT's isValid, BOP check (Shape.check(True)) and Volume (a twist keeps it).
"""
import numpy as np
import pytest

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector


def dome():
    """Half of a hollow sphere (radii 120 and 100 about the origin, poles on the y axis),
    the half y >= 0: the plane z = 0 holds its centre and both inner and outer poles, as
    OCCT's Pump_TopCover's spheres."""
    outer = Part.makeSphere(120, V(0, 0, 0), V(0, 1, 0))
    inner = Part.makeSphere(100, V(0, 0, 0), V(0, 1, 0))
    return outer.cut(inner).common(Part.makeBox(400, 200, 400, V(-200, 0, -200))).Solids[0]


def test_dome_is_what_the_test_needs():
    solid = dome()
    assert solid.isValid()
    solid.check(True)   # the Base passes OCCT's BOP check
    assert solid.Volume == pytest.approx(2.0 / 3.0 * np.pi * (120 ** 3 - 100 ** 3), rel=1e-9)


def test_twist_of_a_dome_about_its_centre():
    """Twisted about the z axis through its centre between z = 0 and 32 (Linear, 30 deg),
    each sphere goes into itself: the region's faces, fitted within 1e-7 of it, continue
    the far part's sphere faces diagonally across the joint vertices where the seam-split
    faces meet, tangent there. OCCT's BOP check found the two faces crossing about such a
    vertex (BOPAlgo SelfIntersect; its tolerance had to reach 5.8e-4 mm before the check
    passed) and the result was Up-to-date. The twist keeps the volume."""
    solid = dome()
    doc = fc.new_document("UnseenTwistDome")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = solid
        obj = fd.make_twist(base, (V(0, 0, 0), V(0, 0, 1)), (V(0, 0, 32), V(0, 0, 1)), 30.0,
                            axis=(V(0, 0, 0), V(0, 0, 1)))
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        result = obj.Shape
        assert result.isValid()
        result.check(True)   # raises on BOPAlgo SelfIntersect
        assert result.Volume == pytest.approx(solid.Volume, rel=1e-6)
        # within the feature's Tolerance (1e-3 mm) of the exact twist
        assert max(v.Tolerance for v in result.Vertexes) <= obj.Tolerance.Value * (1 + 1e-9)
        assert base.Shape.Volume == pytest.approx(solid.Volume, rel=1e-12)   # Base kept
    finally:
        App.closeDocument(doc.Name)


def test_joins_settle_faces_that_touch_at_a_joint_vertex(monkeypatch):
    """The joins of split pieces (Stretch, Bend, the loft's) settle their joints through
    brep._settled_at_joints, which now also raises the tolerances where two faces touch
    at a joint vertex only, nearly tangent there, and OCCT's BOP check finds them crossing
    (OCCT's Pump_TopCover stretched twice: a swept side and a far sphere face at 7.6 deg;
    no primitive reproduction of that join was found, so the dome's twisted solid, taken
    before its own settling, stands in for it). The volume is not changed."""
    from freecad_deform.ops import twist
    from freecad_deform.shapes import brep
    monkeypatch.setattr(brep, "tangent_touches_settled", lambda solid, *a, **k: solid,
                        raising=False)
    z = np.array([0.0, 0.0, 1.0])
    raw, _ = twist.solid(dome(), np.zeros(3), z, 32.0, np.radians(30.0), axis=(np.zeros(3), z))
    monkeypatch.undo()
    assert raw.isValid()
    with pytest.raises(ValueError, match="SelfIntersect"):
        raw.check(True)   # the configuration this test needs
    out = brep._settled_at_joints(raw, brep.on_planes([(np.zeros(3), z), (32.0 * z, z)]))
    assert out.isValid()
    out.check(True)
    assert out.Volume == pytest.approx(raw.Volume, rel=1e-12)
    assert max(v.Tolerance for v in out.Vertexes) <= brep.TOUCH_CAP * (1 + 1e-9)
