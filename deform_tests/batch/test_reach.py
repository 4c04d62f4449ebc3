"""`reach` on a real bracket (fc_Schenkel.stp): its end hole (Face338, radius 2, axis X at
x = 140) must land where a turn of -20 deg about an axis through (120, 0, 40) along Y takes
it (Rodrigues' formula, written here): a Bend, the hole found again on the result by its
radius lands to 1e-9 mm and 1e-9 rad; a target along the normal is a Stretch; a screw
motion is refused."""
import numpy as np
import pytest

import Part

from freecad_deform.batch import reach
from freecad_deform.geometry.errors import DeformError

from .conftest import App, cli, model_path

PLANE = ((120.0, 0.0, 0.0), (1.0, 0.0, 0.0))
HOLE_CENTRE, HOLE_AXIS = np.array([140.0, 0, 0]), np.array([1.0, 0, 0])


def rodrigues(points, centre, axis, degrees):
    th = np.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + np.sin(th) * k + (1 - np.cos(th)) * k @ k
    return centre + (np.atleast_2d(points) - centre) @ rot.T, rot


def hole_on(shape, near):
    """(centre, axis) of the radius-2 cylinder face whose axis point (nearest its centre of
    mass) is nearest `near`."""
    best = None
    for face in shape.Faces:
        s = face.Surface
        if s.TypeId != "Part::GeomCylinder" or abs(s.Radius - 2) > 1e-9:
            continue
        axis = np.array(tuple(s.Axis)) / s.Axis.Length
        origin = np.array(tuple(s.Center))
        centre = origin + ((np.array(tuple(face.CenterOfMass)) - origin) @ axis) * axis
        if best is None or np.linalg.norm(centre - near) < np.linalg.norm(best[0] - near):
            best = (centre, axis)
    return best


def angle_between_lines(a, b):
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(a @ b)))


@pytest.fixture(scope="module")
def bracket(tmp_path_factory):
    doc = App.newDocument("Bracket")
    doc.addObject("Part::Feature", "Model").Shape = Part.read(model_path("fc_Schenkel.stp"))
    path = str(tmp_path_factory.mktemp("reach") / "bracket.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    return path


def test_reach_by_bend_lands_the_end_hole(bracket, tmp_path):
    centre, axis = np.array([120.0, 0, 40]), np.array([0, 1.0, 0])
    (q,), rot = rodrigues(HOLE_CENTRE, centre, axis, -20)
    b = rot @ HOLE_AXIS
    vec = lambda v: ",".join(repr(float(c)) for c in v)  # noqa: E731
    done = cli("reach", bracket, "--base", "Model", "--plane", "120,0,0:1,0,0",
               "--feature", "Face338", "--target", f"{vec(q)}:{vec(b)}",
               "--out", tmp_path / "reached.FCStd")
    assert done.stdout.strip().splitlines()[-1] == "Method = Bend"
    doc = App.openDocument(str(tmp_path / "reached.FCStd"))
    try:
        shape = doc.getObject("Bend").Shape
        assert shape.isValid() and len(shape.Solids) == 1
        landed, landed_axis = hole_on(shape, q)
        assert np.linalg.norm(landed - q) < 1e-9
        assert angle_between_lines(landed_axis, b) < 1e-9
    finally:
        App.closeDocument(doc.Name)


def test_reach_along_the_normal_is_a_stretch(bracket):
    doc = App.openDocument(bracket)
    try:
        q = HOLE_CENTRE + [15.0, 0, 0]
        found = reach.reach(doc, "Model", PLANE, "Face338", (q, HOLE_AXIS))
        assert found["method"] == "Stretch" and found["distance"] == 15.0
        shape = doc.getObject(found["object"]).Shape
        assert shape.isValid()
        landed, landed_axis = hole_on(shape, q)
        assert np.linalg.norm(landed - q) < 1e-9
        assert angle_between_lines(landed_axis, HOLE_AXIS) < 1e-9
    finally:
        App.closeDocument(doc.Name)


def test_screw_motion_is_refused(bracket):
    """The Bend's turn plus a 5 mm slide along its axis: no Stretch or Bend makes it; the
    document keeps only its Model."""
    (q,), rot = rodrigues(HOLE_CENTRE, np.array([120.0, 0, 40]), np.array([0, 1.0, 0]), -20)
    doc = App.openDocument(bracket)
    try:
        with pytest.raises(DeformError, match="screw motion"):
            reach.reach(doc, "Model", PLANE, "Face338", (q + [0, 5.0, 0], rot @ HOLE_AXIS))
        assert [o.Name for o in doc.Objects] == ["Model"]
    finally:
        App.closeDocument(doc.Name)
