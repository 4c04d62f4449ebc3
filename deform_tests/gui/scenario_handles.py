"""The 3D-view handles of the Twist panel (run by freecad_scenario.py inside FreeCAD): the
draggers are found in Coin's scene graph, dragged with the mouse, and the properties must
change by what the drag shows on screen: a plane lands where its handle was let go, the
disc turns Angle by the angle swept in its plane. `h` is the scenario harness."""
import math

import FreeCAD as App
import FreeCADGui as Gui
import Part

V = App.Vector


def draggers(view):
    """[(dragger type name, its frame's translation, its frame's rotation)] in the scene."""
    from pivy import coin
    found = []
    for kind in ("SoTranslate1Dragger", "SoRotateDiscDragger"):
        search = coin.SoSearchAction()
        search.setType(coin.SoType.fromName(kind))
        search.setInterest(coin.SoSearchAction.ALL)
        search.apply(view.getSceneGraph())
        for i in range(search.getPaths().getLength()):
            path = search.getPaths()[i]
            parent = path.getNodeFromTail(1)
            transform = parent.getChild(0)
            t = V(*transform.translation.getValue().getValue())
            q = transform.rotation.getValue()
            found.append((kind, t, q))
    return found


def guide_points(view):
    """The points of the Guides node (4 per plane sheet, then 2 per axis), from the scene."""
    from pivy import coin
    from freecad_deform.gui.coin_nodes import GUIDE_NAME
    search = coin.SoSearchAction()
    search.setType(coin.SoCoordinate3.getClassTypeId())
    search.setInterest(coin.SoSearchAction.ALL)
    search.apply(view.getSceneGraph())
    for i in range(search.getPaths().getLength()):
        path = search.getPaths()[i]
        if any(str(path.getNode(k).getName()) == GUIDE_NAME for k in range(path.getLength())):
            points = path.getTail().point
            return [V(*points[k].getValue()) for k in range(points.getNum())]
    return []


def screen(view, p):
    return V(*view.getPointOnScreen(p), 0)


def in_plane(view, pixel, point, normal):
    """Where the view's ray through `pixel` meets the plane through `point` along `normal`."""
    p = V(*view.getPoint(int(round(pixel[0])), int(round(pixel[1]))))
    d = V(*view.getViewDirection())
    return p + d * ((point - p).dot(normal) / d.dot(normal))


def handles(h):
    doc = App.newDocument("DeformHandlesTest")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(120, 40, 20, V(0, 200, 0))
    doc.recompute()
    Gui.SendMsgToActiveView("ViewFit")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    Gui.Command.get("Deform_Twist").run()
    h.wait(lambda: h.panel_form("Twist") is not None)
    obj = h.of_type(doc, "Twist")[0]
    view = Gui.ActiveDocument.ActiveView
    h.screenshot("twist_handles.png")   # isometric, fitted: the view the drags are made in
    found = draggers(view)
    slides = sorted((t for k, t, _ in found if k == "SoTranslate1Dragger"), key=lambda t: t.x)
    discs = [t for k, t, _ in found if k == "SoRotateDiscDragger"]
    h.check("Twist handles: two plane sliders and an angle disc in the 3D view",
            len(slides) == 2 and len(discs) == 1 and abs(slides[0].x - 40) < 1e-9
            and abs(slides[1].x - 80) < 1e-9, found)
    corners = guide_points(view)
    bb = box.Shape.BoundBox
    h.check("Twist guides: a sheet in each plane (x = 40, 80) across the box, no axis line",
            len(corners) == 8 and all(abs(p.x - 40) < 1e-9 for p in corners[:4])
            and all(abs(p.x - 80) < 1e-9 for p in corners[4:])
            and min(p.y for p in corners) < bb.YMin and max(p.y for p in corners) > bb.YMax
            and min(p.z for p in corners) < bb.ZMin and max(p.z for p in corners) > bb.ZMax,
            corners)
    # Plane: drag its slider along the screen image of the normal (+x)
    start = slides[0]
    px0, px1 = screen(view, start), screen(view, start + V(10, 0, 0))
    along = px1 - px0                      # pixels per 10 mm along the normal
    unit = V(along).normalize()
    moves = [(unit.x * 4 * k, unit.y * 4 * k) for k in range(1, 16)]   # 60 px
    release, _ = h.drag_3d(start, moves)
    h.wait(lambda: h.settled(obj))
    dragged = (V(release[0], release[1], 0) - px0).dot(along) / along.Length ** 2 * 10.0
    mm_per_px = 10.0 / along.Length
    h.check("Twist handle: Plane lands where its handle was let go (1 px)",
            abs(obj.Plane.Base.x - (40.0 + dragged)) < mm_per_px
            and abs(obj.Plane2.Base.x - obj.Plane.Base.x - 40.0) < 1e-6
            and "Invalid" not in obj.State,
            f"Plane x {obj.Plane.Base.x}, expected {40 + dragged} (1 px = {mm_per_px:.3g} mm); "
            f"Plane2 x {obj.Plane2.Base.x}; {obj.getStatusString()}")
    # Angle: sweep the disc from one point of it to another, about its axis (the normal)
    centre = [t for k, t, _ in draggers(view) if k == "SoRotateDiscDragger"][0]
    radius = 0.12 * box.Shape.BoundBox.DiagonalLength   # on the disc (its radius is 0.2 x)
    a0 = obj.Angle.Value + 360.0 * obj.Turns

    def on_disc(theta):
        return centre + V(0, math.cos(theta), math.sin(theta)) * radius

    first = screen(view, on_disc(0.0))
    sweep = math.radians(50.0)
    moves = [tuple(screen(view, on_disc(sweep * k / 10.0)) - first)[:2] for k in range(1, 11)]
    release, _ = h.drag_3d(on_disc(0.0), moves)
    h.wait(lambda: h.settled(obj))
    turned = obj.Angle.Value + 360.0 * obj.Turns - a0
    # the angle the pixels pressed and let go at sweep in the disc's plane. Coin's disc
    # dragger starts from the point it picked on its geometry, a little off the pressed
    # pixel's ray in its plane: within 5 deg (measured on 0.20: 2.5)
    a, b = (in_plane(view, px, centre, V(1, 0, 0)) - centre for px in (first, release))
    swept = math.degrees(math.atan2(a.cross(b).x, a.dot(b)))
    h.check("Twist handle: the disc turns Angle by the angle swept in its plane (5 deg)",
            abs(abs(turned) - abs(swept)) < 5.0 and abs(swept) > 30.0
            and "Invalid" not in obj.State,
            f"Angle {a0} -> {obj.Angle.Value + 360.0 * obj.Turns}: {turned} deg; "
            f"swept {swept} deg")
    h.press("Cancel")
    h.check("Twist handles gone after Cancel", not draggers(view), draggers(view))
    App.closeDocument(doc.Name)
    h.process(0.2)
