"""`reach` on a real bracket (fc_Schenkel.stp): its end hole (Face338, radius 2, axis X at
x = 140) must land where a turn of -20 deg about an axis through (120, 0, 40) along Y takes
it (Rodrigues' formula, written here): a Bend, the hole found again on the result by its
radius lands to 1e-9 mm and 1e-9 rad; a target along the normal is a Stretch; a slide across
the normal with a turn, and a screw, are key-frame sweeps whose hole rims land to 1e-9; a
slide along the Plane is refused."""
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


def circles_on(shape, radius, near, reach=1.0):
    """(centre, axis) of every circular edge of `radius` within `reach` of `near`: the
    hole's rims measured on the result."""
    out = []
    edges = [e for f in shape.Faces if f.Surface.TypeId == "Part::GeomCylinder"
             for e in f.Edges]  # rims of cylinders (the file has degenerated edges elsewhere)
    for edge in {e.hashCode(): e for e in edges}.values():
        c = edge.Curve
        if c.TypeId == "Part::GeomCircle" and abs(c.Radius - radius) < 1e-9:
            centre = np.array(tuple(c.Center))
            if np.linalg.norm(centre - near) < reach:
                out.append((centre, np.array(tuple(c.Axis)) / c.Axis.Length))
    return out


def rigid(rot, centre, shift):
    """The motion x -> rot (x - centre) + centre + shift."""
    return lambda x: (np.atleast_2d(x) - centre) @ rot.T + centre + shift


@pytest.mark.parametrize("turn, shift", [
    # a slide across the normal (3 mm along Y, 2 along Z) with a 3 deg turn about Z
    (((140.0, 0, 0), (0, 0, 1.0), 3.0), (30.0, 3.0, 2.0)),
    # a screw: the Bend's -20 deg turn about Y plus a 1 mm slide along Y (lifted off first)
    (((120.0, 0, 40.0), (0, 1.0, 0), -20.0), (0.0, 1.0, 0.0)),
    # a wider slide (8 mm along Y, 2 along Z) with a -4 deg turn about Z: a smooth path
    (((140.0, 0, 0), (0, 0, 1.0), -4.0), (40.0, 8.0, 2.0)),
], ids=["slide-and-turn", "screw", "wide-slide"])
def test_reach_by_key_frames_lands_the_hole_rims(bracket, turn, shift):
    """Neither a Stretch nor a Bend: a Stretch whose far part ends at EndPlacement through
    key frames (Method KeyFrames). Oracle: the hole's two rim circles (x = 135 and 145 on
    the base) measured on the result, against the motion written here (Rodrigues)."""
    centre, axis, degrees = np.asarray(turn[0], float), np.asarray(turn[1], float), turn[2]
    _, rot = rodrigues(HOLE_CENTRE, centre, axis, degrees)
    move = rigid(rot, centre, np.asarray(shift, float))
    (q,) = move(HOLE_CENTRE)
    b = rot @ HOLE_AXIS
    doc = App.openDocument(bracket)
    try:
        found = reach.reach(doc, "Model", PLANE, "Face338", (q, b))
        assert found["method"] == "KeyFrames"
        obj = doc.getObject(found["object"])
        assert obj.UseEndPlacement and "Invalid" not in obj.State
        shape = obj.Shape
        assert shape.isValid() and len(shape.Solids) == 1
        for rim in ((135.0, 0, 0), (145.0, 0, 0)):
            (want,) = move(rim)
            rims = circles_on(shape, 2.0, want)  # the rim, whole or in arcs
            assert rims
            for landed, landed_axis in rims:
                assert np.linalg.norm(landed - want) < 1e-9
                assert angle_between_lines(landed_axis, b) < 1e-9
    finally:
        App.closeDocument(doc.Name)


def test_a_slide_along_the_plane_is_refused(bracket):
    """A target 6 mm across the normal and no advance: every sweep to it reaches back into
    the part; refused, the document keeps only its Model."""
    doc = App.openDocument(bracket)
    try:
        with pytest.raises(DeformError, match="key-frame sweep"):
            reach.reach(doc, "Model", PLANE, "Face338", (HOLE_CENTRE + [0, 6.0, 0], HOLE_AXIS))
        assert [o.Name for o in doc.Objects] == ["Model"]
    finally:
        App.closeDocument(doc.Name)


def test_end_placement_that_does_not_move_is_refused():
    """A Stretch with UseEndPlacement and the identity EndPlacement: the far part would not
    move; the object names EndPlacement, the Base is untouched."""
    import freecad_deform as fd
    doc = App.newDocument("EndPlacement")
    try:
        box = doc.addObject("Part::Feature", "Box")
        box.Shape = Part.makeBox(100, 40, 20)
        volume = box.Shape.Volume
        obj = fd.make_stretch(box, (App.Vector(50, 0, 0), App.Vector(1, 0, 0)), 10)
        obj.UseEndPlacement = True
        doc.recompute()
        assert "Invalid" in obj.State and "EndPlacement" in obj.getStatusString()
        obj.EndPlacement = App.Placement(App.Vector(12, 0, 0), App.Rotation())
        doc.recompute()
        # a translation along the normal as the end: the key-frame sweep is A x d
        assert "Invalid" not in obj.State
        assert abs(obj.Shape.Volume - volume - 40 * 20 * 12) < 1e-6 * volume
        assert box.Shape.Volume == volume
    finally:
        App.closeDocument(doc.Name)
