"""A face of revolution about the twist axis whose seam the twist turns (a sphere's, a
torus's) stays on its own surface only while its parameter range stays within one period.
Past it (the seam turned into a helix, the face running from its lower end round to its
upper one) OCCT called the face valid, but its sections lost the arc past the period and a
boolean with it came out empty (stop 19: a sphere twisted about its axis sliced to an open
wire 118.0 mm long instead of 123.1, and its common with a box had no volume). Such a face
is cut along meridians (and, past a quarter turn across it, into bands) so that every piece
stays within one period, and stays exact on its surface (stop 19 fitted it instead).

Oracles: closed forms for the sphere (the circle's length at a height, the cap's volume
pi h^2 (3R - h) / 3) and the torus (the two circles at a height), OCCT's slice, common,
Volume and isValid() on the result. (Until stop 20 these tests passed the angle in radians
as if in degrees: 30 rad, not 30 deg.)
"""
import math

import numpy as np
import pytest

from . import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

from freecad_deform.ops import twist  # noqa: E402

V = App.Vector
Z = np.array([0.0, 0.0, 1.0])
ANGLE = 30.0
R = 20.0


def twisted(shape, z0, gap, profile, degrees=ANGLE):
    result, _ = twist.solid(shape, np.array([0.0, 0.0, z0]), Z, gap, np.radians(degrees),
                            (np.zeros(3), Z), profile=profile)
    assert result.isValid()
    return result


@pytest.mark.parametrize("degrees", [30.0, 200.0, 720.0])
def test_a_twisted_sphere_stays_an_exact_sphere(degrees):
    """Every face of the result is on a sphere, and its sections are the sphere's circles
    to rounding (a fitted band missed them by 2e-9 to 9e-9 of their length)."""
    result = twisted(Part.makeSphere(R), -8.0, 8.0, "Linear", degrees)
    assert {f.Surface.TypeId for f in result.Faces} == {"Part::GeomSphere"}
    for z in (-7.0, -4.0, -1.0):
        wires = result.slice(V(0, 0, 1), z)
        assert len(wires) == 1 and wires[0].isClosed()
        assert wires[0].Length == pytest.approx(2 * math.pi * math.sqrt(R * R - z * z),
                                                rel=1e-12)
    assert result.Volume == pytest.approx(4 / 3 * math.pi * R ** 3, rel=1e-12)
    result.check(True)                               # OCCT's BOP check: raises on a finding


@pytest.mark.parametrize("profile", ["Linear", "Smooth"])
def test_a_sphere_twisted_about_its_axis_slices_and_cuts_whole(profile):
    result = twisted(Part.makeSphere(R), -8.0, 8.0, profile)
    for z in (-6.0, -2.0) if profile == "Linear" else (-4.0,):   # in the region
        wires = result.slice(V(0, 0, 1), z)
        assert len(wires) == 1 and wires[0].isClosed()
        assert wires[0].Length == pytest.approx(2 * math.pi * math.sqrt(R * R - z * z),
                                                rel=1e-7)
    if profile == "Smooth":                          # the same faces: a section enough
        return
    h = R + 4.0                                      # the cap above z = -4
    cap = result.common(Part.makeBox(60, 60, 60, V(-30, -30, -4.0)))
    assert cap.Volume == pytest.approx(math.pi * h * h * (3 * R - h) / 3, rel=1e-6)
    assert result.Volume == pytest.approx(4 / 3 * math.pi * R ** 3, rel=1e-6)


def test_a_torus_twisted_about_its_axis_slices_and_cuts_whole():
    torus = Part.makeTorus(20.0, 5.0)                # about z, tube centre at z = 0
    result = twisted(torus, -3.0, 5.0, "Linear")
    for z in (-2.0,):
        wires = sorted(result.slice(V(0, 0, 1), z), key=lambda w: w.Length)
        d = math.sqrt(25.0 - z * z)
        assert len(wires) == 2 and all(w.isClosed() for w in wires)
        assert wires[0].Length == pytest.approx(2 * math.pi * (20.0 - d), rel=1e-7)
        assert wires[1].Length == pytest.approx(2 * math.pi * (20.0 + d), rel=1e-7)
    half = result.common(Part.makeBox(80, 80, 20, V(-40, -40, 0.0)))
    assert half.Volume == pytest.approx(math.pi * 25.0 * 2 * math.pi * 20.0 / 2, rel=1e-6)


def test_a_thousand_turns_are_refused_not_cut_without_end():
    """Past 16 turns across a face (MOST_BANDS) it is no longer cut into bands but fitted,
    and a fit cannot follow 1000 turns: refused naming Tolerance at once (cut into bands,
    it took 86 s and 8004 faces), the Base kept."""
    from freecad_deform.geometry.errors import DeformError
    sphere = Part.makeSphere(R)
    with pytest.raises(DeformError) as refused:
        twisted(sphere, -8.0, 8.0, "Linear", 360.0 * 1000)
    assert refused.value.prop == "Tolerance"
    assert sphere.isValid() and sphere.Volume == pytest.approx(4 / 3 * math.pi * R ** 3,
                                                               rel=1e-12)
