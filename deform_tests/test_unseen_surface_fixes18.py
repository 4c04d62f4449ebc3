"""Defects found by running AreaConstrain and DirectPush on the B-spline faces of a public
IGES model (pyiges' impeller: 247 trimmed, rational faces, edges toleranced to 0.02 mm),
each rebuilt here from primitives.

Oracles: OCCT's isValid and Area of the face as built, the pushed point's distance to the
target by OCCT's distToShape.
"""
import numpy as np
import pytest

from .features import fc  # noqa: F401  (FreeCAD on sys.path)

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import freecad_deform as fd  # noqa: E402
from freecad_deform.shapes import bspline  # noqa: E402

V, V2 = App.Vector, App.Base.Vector2d
TOL = 0.01


def bump():
    """A bicubic B-spline bump, 30 x 30 mm."""
    s = Part.BSplineSurface()
    poles = [[V(10 * i, 10 * j, 3.0 * np.sin(i + 0.5 * j)) for j in range(4)] for i in range(4)]
    s.buildFromPolesMultsKnots(poles, [4, 4], [4, 4], [0, 1], [0, 1], False, False, 3, 3)
    return s


def with_short_edge(surface, start):
    """The bump trimmed by a pentagon in (u, v) with one side 2e-4 long (6 um on the
    surface), shorter than its edges' tolerance (TOL): a face as imported IGES faces come.
    ShapeFix joins the pcurves into a valid face, which keeps the short edge between two
    vertices; `start` is where its wire begins."""
    uv = [(0.2, 0.2), (0.2002, 0.2), (0.8, 0.25), (0.75, 0.8), (0.25, 0.7)][::-1]
    uv = uv[start:] + uv[:start]
    edges = []
    for k in range(5):
        edge = Part.Geom2d.Line2dSegment(V2(*uv[k]), V2(*uv[(k + 1) % 5])).toShape(surface)
        edge.fixTolerance(TOL)
        edges.append(edge)
    wire = Part.Wire(edges)
    wire.fixWire(Part.Face(surface), TOL)
    face = Part.Face(surface, wire)
    assert face.isValid() and len(face.Edges) == 5
    return face


@pytest.mark.parametrize("start", range(5))
def test_a_face_with_an_edge_shorter_than_its_tolerance_is_rebuilt(start):
    """face_on (DirectPush's trimmed faces) made every edge again from its pcurve and let
    OCCT's wire maker join them: the short edge's two ends fell within one tolerance and
    were merged into one vertex, and the face was invalid; face_on gave None, and a push
    on 9 of the impeller's 247 faces was refused ("its trimmed boundary could not be laid
    on the pushed surface") for any push at all. Rebuilt on its own surface, the face must
    be valid with the same area."""
    surface = bump()
    face = with_short_edge(surface, start)
    again = bspline.face_on(surface, face)
    assert again is not None and again.isValid()
    assert again.Area == pytest.approx(face.Area, rel=1e-9)


def test_direct_push_on_a_face_with_a_short_edge():
    """The whole feature on such a face: a push of its middle 2 mm along its normal is
    Up-to-date, valid, and reaches the target."""
    doc = fc.new_document("ShortEdge")
    try:
        face = with_short_edge(bump(), 3)
        base = doc.addObject("Part::Feature", "Skin")
        base.Shape = face
        u0, u1, v0, v1 = face.ParameterRange
        um, vm = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
        point = face.valueAt(um, vm)
        target = point + face.normalAt(um, vm) * 2.0
        push = fd.make_direct_push(base, "Face1", point, target)
        doc.recompute()
        assert push.State == ["Up-to-date"], push.getStatusString()
        assert push.Shape.isValid()
        assert push.Shape.distToShape(Part.Vertex(target))[0] < 1e-6
        assert len(base.Shape.Edges) == 5 and base.Shape.Area == face.Area   # Base kept
    finally:
        App.closeDocument(doc.Name)


def tube():
    """A tube 72 long, 10.2 and 6 in radius: the shape of a solid of OCCT's CrankArm."""
    return Part.makeCylinder(10.2, 72).cut(Part.makeCylinder(6, 72)).Solids[0]


def passes_bop_check(shape):
    try:
        shape.check(True)
    except ValueError:
        return False
    return True


@pytest.mark.parametrize("b", [0.3, 0.7])
def test_a_push_that_folds_the_face_is_refused(b):
    """A push of a face of a solid that leaves the face intersecting itself (OCCT's BOP
    check: SelfIntersect, on 7.6 and 7.9 alike), without crossing the other faces, was
    Up-to-date: the tube's outer face pushed 3 mm out near its seam (u at 95 % of its
    range), as on OCCT's CrankArm and Pump_TopCover. It must be refused naming Targets,
    with how far the point can go; a push of 1 mm there stays Up-to-date, passes the check
    and lands."""
    doc = fc.new_document("Fold")
    try:
        solid = tube()
        assert passes_bop_check(solid)
        index = max(range(len(solid.Faces)), key=lambda i: solid.Faces[i].Area)
        face = solid.Faces[index]
        u0, u1, v0, v1 = face.ParameterRange
        u, v = u0 + 0.95 * (u1 - u0), v0 + b * (v1 - v0)
        point, normal = face.valueAt(u, v), face.normalAt(u, v)
        base = doc.addObject("Part::Feature", "Tube")
        base.Shape = solid
        far = fd.make_direct_push(base, f"Face{index + 1}", point, point + normal * 3.0)
        doc.recompute()
        assert "Invalid" in far.State
        assert "Targets[0]" in far.getStatusString()
        assert "intersects itself" in far.getStatusString()
        target = point + normal * 1.0
        near = fd.make_direct_push(base, f"Face{index + 1}", point, target)
        doc.recompute()
        assert near.State == ["Up-to-date"], near.getStatusString()
        assert passes_bop_check(near.Shape)
        assert near.Shape.Faces[index].distToShape(Part.Vertex(target))[0] < 1e-6
        assert base.Shape.Volume == solid.Volume and len(base.Shape.Faces) == 4   # Base kept
    finally:
        App.closeDocument(doc.Name)
