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


def hyperbola_face():
    """A planar face bounded by a whole-hyperbola edge and three lines: its pcurve is the
    plane's own projection, a Hyperbola2d (a hexagonal nut's flats meet its chamfer cone
    in such edges: OCCT's Pump_Nut)."""
    h = Part.Hyperbola()
    h.MajorRadius, h.MinorRadius = 2.0, 1.0
    edge = Part.Edge(h, -0.5, 0.5)
    p0, p1 = edge.Vertexes[0].Point, edge.Vertexes[1].Point
    corners = [p1, V(6, p1.y, 0), V(6, p0.y, 0), p0]
    return Part.Face(Part.Wire([edge] + [Part.makeLine(a, b) for a, b in zip(corners, corners[1:])]))


def test_push_a_face_with_a_hyperbola_edge():
    """FreeCAD 0.20 cannot discretize a whole Hyperbola2d ('Unknown C++ exception'): the
    test whether a face is its whole surface (bspline.natural) asked for it, and DirectPush
    on such a face, or Taper and Twist refitting one (Pump_Nut's flats), failed with that
    raw error."""
    import freecad_deform as fd
    face = hyperbola_face()
    assert type(face.curveOnSurface(face.Edges[0])[0]).__name__ == "Hyperbola2d"
    doc = fc.new_document("UnseenHyperbola")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = face
        target = V(4, 0, 0.5)
        obj = fd.make_direct_push(base, "Face1", V(4, 0, 0), target)
        assert "Invalid" not in obj.State, obj.getStatusString()
        assert obj.Shape.isValid()
        assert obj.Shape.distToShape(Part.Vertex(target))[0] < 1e-9
        # the boundary stays: the hyperbola edge's ends, the lines' corners
        before = sorted(tuple(round(c, 9) for c in v.Point) for v in face.Vertexes)
        after = sorted(tuple(round(c, 9) for c in v.Point) for v in obj.Shape.Vertexes)
        assert before == after
    finally:
        App.closeDocument(doc.Name)


@pytest.mark.parametrize("at", [-64.0, -36.0, 17.3])
def test_stretched_sphere_cut_off_its_axis_passes_the_bop_check(at):
    """A sphere whose axis lies in the plane (OCCT's Pump_TopCover) is cut along a circle
    that is no iso-line: OCCT's split approximates its pcurve, and the sewing of the joint
    set the merged edge's tolerance from its own samples, 1.234e-7 for a gap of 1.246e-7:
    a valid solid that OCCT's BOP check (and its booleans) rejected."""
    sphere = Part.makeSphere(100, V(0, 0, 0), V(0, 1, 0))
    result, _ = stretch.solid(sphere, np.array([0.0, 0.0, at]), Z, 32.0)
    assert result.isValid()
    assert result.Volume == pytest.approx(sphere.Volume + np.pi * (100 ** 2 - at ** 2) * 32.0,
                                          rel=1e-7)
    result.check(True)   # raises on BOPAlgo_InvalidCurveOnSurface
    assert sphere.isValid() and all(e.Tolerance <= 1e-7 for e in sphere.Edges)


def bumpy_sheet(turn):
    """A bicubic B-spline sheet, 50 x 50 with bumps of 4, turned `turn` degrees about z."""
    surface = Part.BSplineSurface()
    rng = np.random.default_rng(3)
    poles = [[V(10 * i, 10 * j, float(rng.uniform(-4, 4))) for j in range(6)] for i in range(6)]
    surface.buildFromPolesMultsKnots(poles, [4, 1, 1, 4], [4, 1, 1, 4], [0, 1, 2, 3],
                                     [0, 1, 2, 3], False, False, 3, 3)
    face = Part.Face(surface)
    face.rotate(V(25, 25, 0), V(0, 0, 1), turn)
    return face


@pytest.mark.parametrize("turn,at", [(0, 25.0), (17, 13.7), (30, 31.3), (45, 25.0)])
def test_stretched_bspline_sheet_passes_the_bop_check(turn, at):
    """A free B-spline face cut across its iso-lines (OCCT's MAT.brep): the sewing of the
    near piece, the swept strip and the moved piece gave the far joint edge a tolerance of
    4.6e-5 for a pcurve gap of 9.3e-5 (10 of these 12 plane positions failed the BOP check)."""
    sheet = bumpy_sheet(turn)
    y = np.array([0.0, 1.0, 0.0])
    result, _ = stretch.solid(sheet, np.array([0.0, at, 0.0]), y, 8.0)
    assert result.isValid() and len(result.Faces) == 3
    result.check(True)
    # the strip: the cut curve (the plane's slice of the sheet) extruded 8 along y; OCCT's
    # Area of such a strip is good to 1e-3 only, so its rims are measured
    cut = sum(w.Length for w in sheet.slice(V(0, 1, 0), at))
    strip = [f for f in result.Faces if type(f.Surface).__name__ == "SurfaceOfExtrusion"]
    assert len(strip) == 1
    assert np.allclose(tuple(strip[0].Surface.Direction), (0, 1, 0), atol=1e-12) or \
        np.allclose(tuple(strip[0].Surface.Direction), (0, -1, 0), atol=1e-12)
    for y in (at, at + 8.0):
        rim = [e for e in strip[0].Edges if abs(e.BoundBox.YMin - y) < 1e-6
               and abs(e.BoundBox.YMax - y) < 1e-6]
        assert sum(e.Length for e in rim) == pytest.approx(cut, rel=1e-6)


@pytest.mark.parametrize("at", [-14.0, 12.0])
def test_plane_beyond_the_material_inside_a_loose_box_is_refused(monkeypatch, at):
    """OCCT's BoundBox of a file's solid can be far larger than the solid (occt_screw.step:
    y from -34 to 32 for a part from -10.8 to 9.2). A plane between the material and the
    box's side passed the crossing test: Stretch gave the Base unchanged, VolumeChange 0,
    up to date, where a plane that misses the part must be refused naming Plane. The box
    is made loose here as the file's is, by what brep.extent reads."""
    from freecad_deform.geometry.errors import DeformError
    from freecad_deform.shapes import brep
    solid = Part.makeBox(20, 20, 20, V(-10, -10, -10))
    loose = App.BoundBox(-10, -34, -10, 10, 32, 10)
    monkeypatch.setattr(brep, "bound_box", lambda shape: loose)
    y = np.array([0.0, 1.0, 0.0])
    with pytest.raises(DeformError) as refused:
        stretch.solid(solid, np.array([0.0, at, 0.0]), y, 6.0)
    assert refused.value.prop == "Plane"
    result, report = stretch.solid(solid, np.array([0.0, 9.0, 0.0]), y, 6.0)  # crosses
    assert result.Volume == pytest.approx(8000.0 + 400.0 * 6.0, rel=1e-9)


@pytest.mark.parametrize("kind", ["solid", "compound"])
def test_push_on_a_placed_base_stays_in_place(kind):
    """A Base whose shape has a Placement (OCCT's Pump_TopCover.brep: a compound placed at
    (81.3, 447.2, 0), turned 90 deg; any Part feature moved by the user): DirectPush
    replaces one face and keeps the rest with the Base's Placement, and FreeCAD then gave
    the feature's Shape the object's own Placement (identity): the part jumped to its local
    frame, 85 mm from the target, up to date."""
    import freecad_deform as fd
    box = Part.makeBox(10, 10, 10)
    shape = box if kind == "solid" else Part.makeCompound([box])
    shape.Placement = App.Placement(V(100, 0, 0), App.Rotation(V(0, 0, 1), 90))
    doc = fc.new_document("UnseenPlaced")
    try:
        base = doc.addObject("Part::Feature", "Base")
        base.Shape = shape
        point = shape.Faces[5].CenterOfMass        # the top, z = 10, at (95, 5)
        target = point + V(0, 0, 3)
        obj = fd.make_direct_push(base, "Face6", point, target)
        assert "Invalid" not in obj.State, obj.getStatusString()
        result = obj.Shape
        assert result.isValid()
        assert result.distToShape(Part.Vertex(target))[0] < 1e-9
        bb = result.BoundBox
        assert (bb.XMin, bb.XMax, bb.YMin, bb.YMax, bb.ZMin) == pytest.approx(
            (90, 100, 0, 10, 0), abs=1e-9)
        # the bottom stays where the Base has it
        assert any(abs(f.CenterOfMass.z) < 1e-9 and abs(f.CenterOfMass.x - 95) < 1e-9
                   for f in result.Faces)
    finally:
        App.closeDocument(doc.Name)


def test_a_face_in_a_hole_is_not_cut_by_the_pushed_face():
    """The self-intersection check of DirectPush sections the moved region of the pushed
    face's surface with the faces near it; that region's rectangle reaches past a
    trimmed face's boundary (OCCT's CrankArm: a cone face of 11 edges), where another face
    may cross the surface without touching the face. Every push of that cone was refused
    ('can go about 0 mm'), after 2 minutes of bisection."""
    from freecad_deform.shapes import bspline

    def square(half, z=0.0):
        return Part.makePolygon([V(-half, -half, z), V(half, -half, z), V(half, half, z),
                                 V(-half, half, z), V(-half, -half, z)])

    holed = Part.makeFace([square(10.0), square(3.0)], "Part::FaceMakerBullseye")
    inside = Part.Face(Part.makePolygon([V(0, -1, -1), V(0, 1, -1), V(0, 1, 1), V(0, -1, 1),
                                         V(0, -1, -1)]))          # crosses z = 0 in the hole
    shape = Part.makeCompound([holed, inside])
    assert bspline.cuts_others(shape, 0, 1e-6, holed.ParameterRange) is False
    through = Part.Face(Part.makePolygon([V(6, -1, -1), V(6, 1, -1), V(6, 1, 1), V(6, -1, 1),
                                          V(6, -1, -1)]))         # crosses the face itself
    assert bspline.cuts_others(Part.makeCompound([holed, through]), 0, 1e-6,
                               holed.ParameterRange) is True
    for estimate in (True, False):        # the refusal's bisection sections only faces
        far = Part.Face(Part.makePolygon([V(6, -1, 0.5), V(6, 1, 0.5), V(6, 1, 2),   # near
                                          V(6, -1, 2), V(6, -1, 0.5)]))
        assert bspline.cuts_others(Part.makeCompound([holed, far, through]), 0, 1e-6,
                                   holed.ParameterRange, estimate) is True
        assert bspline.cuts_others(Part.makeCompound([holed, far]), 0, 1e-6,
                                   holed.ParameterRange, estimate) is False
