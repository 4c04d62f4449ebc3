"""Faces that touch tangentially at a joint, where OCCT's BOP check finds them crossing:
found on OCCT's Pump_TopCover (Twist at 50 / 70 % of its height, a Stretch applied twice;
see /work/notes/unseen_brep18.md and brep19.md), rebuilt here from primitives. The check
that settles them (brep.tangent_touches_settled) came back at stop 19 in a form that skips
the parts where it cannot matter, so a last test pins that down too.

Oracles: OCCT's isValid, BOP check (Shape.check(True)) and Volume (a twist keeps it; the
dome's closed form).
"""
import numpy as np
import pytest

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])


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
    vertex (BOPAlgo SelfIntersect; its tolerance had to reach 2.7e-4 mm before the check
    passed) and the result was Up-to-date. The twist keeps the volume."""
    solid = dome()
    doc = fc.new_document("UnseenTwistDome19")
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


def _raw_dome_twist(monkeypatch):
    """The dome's twist as the map and join leave it, before the tangent-touch check."""
    from freecad_deform.ops import twist
    from freecad_deform.shapes import brep
    monkeypatch.setattr(brep, "tangent_touches_settled", lambda solid, *a, **k: solid,
                        raising=False)
    raw, _ = twist.solid(dome(), np.zeros(3), Z, 32.0, np.radians(30.0), axis=(np.zeros(3), Z))
    monkeypatch.undo()
    assert raw.isValid()
    with pytest.raises(ValueError, match="SelfIntersect"):
        raw.check(True)   # the configuration this test needs
    return raw


def test_joins_settle_faces_that_touch_at_a_joint_vertex(monkeypatch):
    """The joins of split pieces (Stretch, Bend, the loft's) settle their joints through
    brep._settled_at_joints, which also raises the tolerances where two faces touch at a
    joint vertex only, nearly tangent there, and OCCT's BOP check finds them crossing
    (OCCT's Pump_TopCover stretched twice: a swept side and a far sphere face at 7.7 deg;
    no primitive reproduction of that join was found, so the dome's twisted solid, taken
    before its own check, stands in for it). The volume is not changed."""
    from freecad_deform.shapes import brep
    raw = _raw_dome_twist(monkeypatch)
    out = brep._settled_at_joints(raw, brep.on_planes([(np.zeros(3), Z), (32.0 * Z, Z)]))
    assert out.isValid()
    out.check(True)
    assert out.Volume == pytest.approx(raw.Volume, rel=1e-12)
    assert max(v.Tolerance for v in out.Vertexes) <= brep.TOUCH_CAP * (1 + 1e-9)


def test_the_check_costs_nothing_where_no_face_is_free_form(monkeypatch):
    """Two planes, or a plane and a cylinder, or any two analytic surfaces: OCCT intersects
    them in closed form, and a join of such faces (a holed plate bent and stretched through
    its holes, the bend's section swept into planes and cylinders) looks at no face pair
    at all (the stop-18 check, 64e7c75, spent 0.8 s of a 1.2 s Bend of a 998-face plate
    measuring such pairs' angles, and 1.5 s of a 1.5 s Twist of fc_blocks144 in one BOP
    check of 84 B-spline and planar faces). The results are valid and pass OCCT's check."""
    from freecad_deform.ops.bend import bend_shape
    from freecad_deform.ops.stretch import stretch_shape
    from freecad_deform.shapes import brep
    plate = Part.makeBox(60, 40, 6)
    for x in (10, 30, 50):
        for y in (10, 30):
            plate = plate.cut(Part.makeCylinder(3, 6, V(x, y, 0)))
    plate = plate.Solids[0]
    calls = []
    for name in ("bop_report", "_tangent_at_vertex", "_turns_over"):   # a pair looked at
        real = getattr(brep, name, None)
        if real is not None:
            monkeypatch.setattr(brep, name, lambda *a, real=real, name=name: calls.append(
                name) or real(*a))
    x = np.array([1.0, 0.0, 0.0])
    bent = bend_shape(plate, np.array([30.0, 0, 0]), x, np.radians(40.0),
                      np.array([30.0, 0, -20.0]), np.array([0.0, 1.0, 0.0]))
    stretched = stretch_shape(plate, np.array([30.0, 0, 0]), x, 7.0)
    assert calls == []
    for shape in (bent, stretched):
        assert shape.isValid()
        shape.check(True)
    # the stretch adds the section through the holes' centres (40 x 6 less 2 x 6 x 6) x 7
    assert stretched.Volume - plate.Volume == pytest.approx((40 * 6 - 2 * 6 * 6) * 7, rel=1e-9)
