"""Faces that touch tangentially at a joint and still cross where the tolerances at the joint
may rise no further (brep.tangent_touches_settled past its cap, the feature's Tolerance on
the mapped path): the result was returned as it was, valid, Up-to-date and failing OCCT's
BOP check (SelfIntersect). And a Linear Taper's planes, whose images are planes, were
B-splines (flat to 3e-11 mm), which the joint check took for free-form faces (seconds a
pair on OCCT's Pump_TopCover).

Oracles: OCCT's isValid and BOP check (Shape.check(True)); the refusal's property; the
frustum's closed-form volume.
"""
import pytest

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.geometry.errors import DeformError  # noqa: E402

from .test_unseen_brep_fixes19 import dome  # noqa: E402

V = App.Vector


def test_touch_past_tolerance_is_refused_naming_tolerance():
    """The dome of test_unseen_brep_fixes19 twisted 30 deg about its centre between z = 0 and
    32, with Tolerance 1e-5 mm: the mapped faces continue the far part's sphere faces
    across the joint vertices, and OCCT's check of two of them passes only once the
    tolerances there reach 2.7e-4 mm, above Tolerance. The result came out valid and
    Up-to-date, and the check of the whole solid found it self-intersecting. Now: refused
    naming Tolerance, or Up-to-date and passing the check; the Base kept. At the default
    Tolerance (1e-3 mm) it is Up-to-date and passes (test_unseen_brep_fixes19)."""
    solid = dome()
    volume = solid.Volume
    doc = fc.new_document("UnseenTwistDomeTight20")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = solid
        with fc.recorded_errors() as raised:
            obj = fd.make_twist(base, (V(0, 0, 0), V(0, 0, 1)), (V(0, 0, 32), V(0, 0, 1)),
                                30.0, axis=(V(0, 0, 0), V(0, 0, 1)))
            obj.Tolerance = 1e-5
            doc.recompute()
        exc = raised.get(obj.Name)
        if "Invalid" in obj.State:
            assert isinstance(exc, DeformError) and exc.prop == "Tolerance", exc
            assert "raise Tolerance" in str(exc)
        else:
            assert obj.State == ["Up-to-date"], obj.getStatusString()
            result = obj.Shape
            assert result.isValid()
            result.check(True)   # raised on BOPAlgo SelfIntersect
        assert base.Shape.Volume == volume   # Base kept
        assert base.Shape.isValid()
    finally:
        App.closeDocument(doc.Name)



def test_a_linear_taper_keeps_a_box_all_planes():
    """A 20 x 20 x 100 box about the z axis tapered (Linear) from 1 at z = 40 to 0.8 at
    z = 60: every face of the region and of the scaled far part is flat, and each is a
    Part.Plane (they were B-splines); the volume is the closed form 400 (40 + 20 (1 + 0.8 +
    0.64) / 3 + 0.64 * 40)."""
    doc = fc.new_document("TaperPlanes20")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = Part.makeBox(20, 20, 100, V(-10, -10, 0))
        obj = fd.make_taper(base, (V(0, 0, 40), V(0, 0, 1)), (V(0, 0, 60), V(0, 0, 1)), 0.8,
                            axis=(V(0, 0, 0), V(0, 0, 1)))
        assert obj.State == ["Up-to-date"], obj.getStatusString()
        result = obj.Shape
        assert result.isValid()
        result.check(True)
        assert {f.Surface.TypeId for f in result.Faces} == {"Part::GeomPlane"}
        assert result.Volume == pytest.approx(400 * (40 + 20 * 2.44 / 3 + 0.64 * 40),
                                              rel=1e-9)
    finally:
        App.closeDocument(doc.Name)
