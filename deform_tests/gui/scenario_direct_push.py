"""The direct push part of the GUI scenario (run by freecad_scenario.py inside FreeCAD, on
the harness in harness.py)."""
import os

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore

from harness import (OUT, check, check_gate, click_3d, drag_3d, field, no_error, of_type, on_shape,
    open_panel, panel_form, press, process, results, settled, show_all, wait)


class RenderCounter:
    """Counts the scene's OpenGL renders (a callback node in the view's scene graph)."""

    def __init__(self, view):
        from pivy import coin
        self.root, self.count = view.getSceneGraph(), 0
        self.node = coin.SoCallback()
        self.node.setCallback(self.on_action)
        self.root.addChild(self.node)

    def on_action(self, _, action):
        from pivy import coin
        if action.isOfType(coin.SoGLRenderAction.getClassTypeId()):
            self.count += 1

    def remove(self):
        self.root.removeChild(self.node)


def preview_nodes(view):
    root = view.getSceneGraph()
    return [root.getChild(i) for i in range(root.getNumChildren())
            if root.getChild(i).getName() == "DeformDirectPush"]


def wavy_surface(n=20):
    """An n x n-pole bicubic B-spline surface over 100 x 100 mm, gently waved."""
    import numpy as np
    import Part
    xs = np.linspace(0, 100, n)
    poles = [[App.Vector(x, y, 8 * np.sin(x / 30) * np.cos(y / 40)) for y in xs] for x in xs]
    mults = [4] + [1] * (n - 4) + [4]
    knots = list(np.linspace(0, 1, n - 2))
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots(poles, mults, mults, knots, knots, False, False, 3, 3)
    return surface


def direct_push():
    """A curve: a fixed point and a straight span by clicks, a drag, OK, Undo; a 20 x 20-pole
    surface: a timed drag, a second drag, the first push removed; a box's top face pushed up
    along its normal."""
    import numpy as np
    import Part
    kind, V = "DirectPush", App.Vector
    Gui.activateWorkbench("DeformWorkbench")  # already active after main(); this part alone too
    cmd = Gui.Command.get("Deform_DirectPush")
    check("DirectPush: command icon", cmd is not None
          and cmd.getInfo()["pixmap"].endswith("DirectPush.svg"),
          cmd.getInfo()["pixmap"] if cmd else None)

    # --- (a) a B-spline curve ------------------------------------------------------------------
    doc = App.newDocument("DeformDirectPushTest")
    curve = doc.addObject("Part::Feature", "Curve")
    spline = Part.BSplineCurve()
    spline.interpolate([V(x, 10 * np.sin(x / 15), 0) for x in np.linspace(0, 70, 8)])
    curve.Shape = spline.toShape()
    doc.recompute()
    view = show_all()
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    check_gate(cmd, "DirectPush", curve, "Edge1", "an edge")
    Gui.runCommand("Deform_DirectPush")
    check("DirectPush: panel opens", wait(lambda: panel_form(kind) is not None))
    panel = open_panel("DirectPushPanel")
    obj = of_type(doc, kind)[0]
    check("DirectPush: starts without pushes, valid",
          len(obj.Points) == 0 and len(obj.Targets) == 0 and "Invalid" not in obj.State
          and no_error(kind) and field("Pushes", kind).count() == 0,
          f"{list(obj.Points)} {obj.getStatusString()}")
    check("DirectPush: Base hidden, result and the panel's nodes shown",
          not curve.ViewObject.Visibility and obj.ViewObject.Visibility
          and len(preview_nodes(view)) == 1)

    length = spline.LastParameter
    field("AddFixed", kind).click()
    click_3d(spline.value(0.8 * length))
    wait(lambda: settled(obj) and len(obj.Fixed) == 1)
    check("DirectPush: a click adds a fixed point on the curve",
          len(obj.Fixed) == 1 and on_shape(curve.Shape, obj.Fixed[0])
          and (obj.Fixed[0] - spline.value(0.8 * length)).Length < 1.0
          and not field("AddFixed", kind).isChecked() and field("Constraints", kind).count() == 1,
          list(obj.Fixed))
    field("AddStraight", kind).click()
    click_3d(spline.value(0.05 * length))
    click_3d(spline.value(0.2 * length))
    wait(lambda: settled(obj) and len(obj.Straight) == 2)
    check("DirectPush: two clicks add a straight span", len(obj.Straight) == 2
          and all(on_shape(curve.Shape, p) for p in obj.Straight) and no_error(kind)
          and field("Constraints", kind).count() == 2, list(obj.Straight))

    grab = spline.value(0.45 * length)
    before = obj.Shape.copy()  # the curve as the constraints left it: what the drag grabs
    end, _ = drag_3d(grab, [(0, 5 * k) for k in range(1, 11)])
    wait(lambda: settled(obj))
    check("DirectPush: one push recorded", len(obj.Points) == 1 and len(obj.Targets) == 1
          and "Invalid" not in obj.State and field("Pushes", kind).count() == 1,
          f"{list(obj.Points)} {list(obj.Targets)} {obj.getStatusString()}")
    point, target = obj.Points[0], obj.Targets[0]
    check("DirectPush: the grabbed point is on the result at the target (1e-6)",
          on_shape(obj.Shape, target) and on_shape(before, point)
          and (point - grab).Length < 1.0 and (target - point).Length > 1.0,
          f"{point} -> {target}: {obj.Shape.distToShape(Part.Vertex(target))[0]}")
    screen = view.getPointOnScreen(target)
    check("DirectPush: the target is where the mouse let go, in the view plane",
          abs(screen[0] - end[0]) <= 1.5 and abs(screen[1] - end[1]) <= 1.5
          and abs((target - point).dot(view.getViewDirection())) < 1e-4 * (target - point).Length,
          f"{screen} vs {end}")
    check("DirectPush: the drag does not select", not Gui.Selection.getSelection(),
          [o.Name for o in Gui.Selection.getSelection()])
    edge = obj.Shape.Edges[0]
    a, b = edge.Curve.parameter(obj.Straight[0]), edge.Curve.parameter(obj.Straight[1])
    span = [edge.Curve.value(a + (b - a) * k / 10) for k in range(11)]
    chord = span[-1] - span[0]
    bow = max((q - span[0]).cross(chord).Length / chord.Length for q in span)
    check("DirectPush: the fixed point stays, the span stays straight",
          on_shape(obj.Shape, obj.Fixed[0]) and bow < 1e-6, f"bow {bow}")
    field("Constraints", kind).setCurrentRow(1)
    field("RemoveConstraint", kind).click()
    wait(lambda: settled(obj))
    check("DirectPush: removing the span keeps the push valid",
          len(obj.Straight) == 0 and len(obj.Points) == 1 and "Invalid" not in obj.State
          and on_shape(obj.Shape, obj.Targets[0]), obj.getStatusString())
    press("OK")
    check("DirectPush: nodes gone after OK", not preview_nodes(view) and panel.preview is None
          and obj.ViewObject.SwitchNode.whichChild.getValue() != -1)
    check("DirectPush: one undo step", doc.UndoCount == undo0 + 1 and doc.UndoNames[0] == kind
          and App.getActiveTransaction() is None, doc.UndoNames)
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("DirectPush: undo removes it", [o.Name for o in doc.Objects] == names0
          and curve.ViewObject.Visibility, [o.Name for o in doc.Objects])
    App.closeDocument(doc.Name)

    # --- (b) a 20 x 20-pole surface: the drag's frame rate ------------------------------------
    doc = App.newDocument("DeformDirectPushSurface")
    sheet = doc.addObject("Part::Feature", "Surface")
    surface = wavy_surface()
    sheet.Shape = surface.toShape()
    doc.recompute()
    view = show_all()
    Gui.Selection.addSelection(doc.Name, sheet.Name, "Face1")
    Gui.runCommand("Deform_DirectPush")
    wait(lambda: panel_form(kind) is not None)
    panel = open_panel("DirectPushPanel")
    obj = of_type(doc, kind)[0]
    shown = {}

    def during():
        shown["hidden"] = obj.ViewObject.SwitchNode.whichChild.getValue() == -1
        path = os.path.join(OUT, "direct_push.png")
        view.saveImage(path, 1000, 750, "White")  # the camera as it is: the drag goes on
        results["screenshots"].append(path)
    grab = surface.value(0.45, 0.5)
    counter = RenderCounter(view)
    _, times = drag_3d(grab, [(0, 2 * k) for k in range(1, 31)], during=during)
    renders = counter.count
    counter.remove()
    wait(lambda: settled(obj))
    update = sorted(panel.frame_times)[len(panel.frame_times) // 2]
    drawn = renders / sum(times)  # frames the view drew per second of dragging
    results["timings"]["direct_push_drag"] = {
        "poles": "20 x 20", "moves": len(times), "preview_updates": len(panel.frame_times),
        "preview_update_median_s": update, "preview_fps": 1.0 / update,
        "drag_s": sum(times), "renders": renders, "rendered_fps": drawn,
        "recompute_on_release_s": panel.recompute_time}
    # The preview update (mouse position -> kernel push -> Coin nodes) is the panel's work
    # per move; the renders are the OpenGL driver's. Both are measured and reported, never
    # asserted (speed belongs to benchmarks/); the check is that every move updated it.
    check("DirectPush: the preview updates on every move", len(panel.frame_times) >= len(times),
          f"{len(panel.frame_times)} updates for {len(times)} moves; "
          f"preview update {1000 * update:.2f} ms = {1 / update:.0f} fps; the view drew "
          f"{renders} frames in {sum(times):.2f} s of {len(times)} moves = {drawn:.0f} fps; "
          f"recompute on release {1000 * (panel.recompute_time or 0):.0f} ms")
    check("DirectPush: surface preview shown while dragging, the result hidden",
          shown.get("hidden") is True and obj.ViewObject.SwitchNode.whichChild.getValue() != -1)
    first = (obj.Points[0], obj.Targets[0]) if len(obj.Points) == 1 else None
    check("DirectPush: surface push at the target (1e-6)", first is not None
          and on_shape(sheet.Shape, first[0]) and on_shape(obj.Shape, first[1])
          and "Invalid" not in obj.State, f"{list(obj.Targets)} {obj.getStatusString()}")
    drag_3d(surface.value(0.7, 0.3), [(3 * k, 0) for k in range(1, 8)])
    wait(lambda: settled(obj))
    second = obj.Targets[-1]
    check("DirectPush: a second drag adds a second push", len(obj.Points) == 2
          and on_shape(obj.Shape, first[1]) and on_shape(obj.Shape, second),
          f"{len(obj.Points)} {obj.getStatusString()}")
    field("Pushes", kind).setCurrentRow(0)
    field("RemovePush", kind).click()
    wait(lambda: settled(obj))
    check("DirectPush: removing the first push keeps the second valid",
          len(obj.Points) == 1 and obj.Targets[0] == second and "Invalid" not in obj.State
          and on_shape(obj.Shape, second) and no_error(kind) and field("Pushes", kind).count() == 1,
          obj.getStatusString())
    grab_panel = os.path.join(OUT, "direct_push_task_panel.png")
    panel_form(kind).grab().save(grab_panel)
    results["screenshots"].append(grab_panel)
    press("OK")
    App.closeDocument(doc.Name)

    # --- (c) a box's top face pushed up ----------------------------------------------------------
    doc = App.newDocument("DeformDirectPushBox")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(20, 20, 10)
    doc.recompute()
    view = show_all()
    top = next(i for i, f in enumerate(box.Shape.Faces) if abs(f.CenterOfMass.z - 10) < 1e-9)
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    for button in ("Cancel", "OK"):  # the same drag twice; OK is pressed further down
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(doc.Name, box.Name, f"Face{top + 1}")
        Gui.runCommand("Deform_DirectPush")
        wait(lambda: panel_form(kind) is not None)
        obj = of_type(doc, kind)[0]
        drag_3d(V(10, 10, 10), [(0, 4 * k) for k in range(1, 11)], QtCore.Qt.ShiftModifier)
        wait(lambda: settled(obj))
        if button == "Cancel":
            press("Cancel")
            check("DirectPush: Cancel after a drag leaves the document unchanged",
                  [o.Name for o in doc.Objects] == names0 and box.ViewObject.Visibility
                  and doc.UndoCount == undo0 and App.getActiveTransaction() is None,
                  [o.Name for o in doc.Objects])
    push = (obj.Targets[0] - obj.Points[0]) if len(obj.Points) == 1 else V()
    check("DirectPush: Shift drags the top face up along its normal", len(obj.Points) == 1
          and (obj.Points[0] - V(10, 10, 10)).Length < 0.5 and push.z > 1.0
          and abs(push.x) + abs(push.y) < 1e-9 * push.z, f"{list(obj.Points)} {push}")
    shape = obj.Shape
    check("DirectPush: box result one valid solid", shape.isValid() and len(shape.Solids) == 1
          and shape.Volume > 4000 and on_shape(shape, obj.Targets[0]) and no_error(kind),
          f"{shape.isValid()} {len(shape.Solids)} {shape.Volume} {obj.getStatusString()}")
    press("OK")
    pushes = (list(obj.Points), list(obj.Targets))
    obj.ViewObject.doubleClicked()
    wait(lambda: panel_form(kind) is not None)
    drag_3d(V(5, 12, shape.BoundBox.ZMax - 0.5), [(0, -3 * k) for k in range(1, 6)])
    wait(lambda: settled(obj))
    edited = len(obj.Points)
    press("Cancel")
    wait(lambda: settled(obj))
    check("DirectPush: edit, drag, Cancel restores the pushes", edited == 2
          and (list(obj.Points), list(obj.Targets)) == pushes and obj.Shape.isValid()
          and obj.ViewObject.SwitchNode.whichChild.getValue() != -1
          and doc.UndoCount == undo0 + 1, f"{edited} pushes while editing")

    # an element the feature cannot push (a cone's apex, a degenerated edge): the command
    # says so, creates nothing
    cone = doc.addObject("Part::Feature", "Cone")
    cone.Shape = Part.makeCone(5, 0, 10)
    doc.recompute()
    names1 = [o.Name for o in doc.Objects]
    edge = next(i for i, e in enumerate(cone.Shape.Edges) if e.Degenerated)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, cone.Name, f"Edge{edge + 1}")
    Gui.runCommand("Deform_DirectPush")
    process(0.2)
    check("DirectPush: a degenerated edge: no object, no panel",
          [o.Name for o in doc.Objects] == names1 and not Gui.Control.activeDialog()
          and cone.ViewObject.Visibility and App.getActiveTransaction() is None,
          [o.Name for o in doc.Objects])
    App.closeDocument(doc.Name)
    process(0.2)
