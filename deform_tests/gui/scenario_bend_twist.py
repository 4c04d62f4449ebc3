"""The bend twist part of the GUI scenario (run by freecad_scenario.py inside FreeCAD, on
the harness in harness.py)."""
import math
import os
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

from harness import (OUT, STEP, angle_done, check, direction, distance_to_line, edge_name,
    error_shown, field, menu_texts, no_error, of_type, panel_form, panel_texts,
    press, process, results, same_placement, screenshot, settled, type_into,
    wait)


def pappus(base_shape, obj):
    """Closed-form volume a single-plane bend adds: section area * centroid radius * angle."""
    import Part
    plane = obj.Plane
    normal = direction(plane)
    face = Part.makeFace(base_shape.slice(normal, normal.dot(plane.Base)), "Part::FaceMakerBullseye")
    radius = distance_to_line(face.CenterOfMass, obj.Axis.Base, direction(obj.Axis))
    return face.Area * radius * math.radians(obj.Angle.Value)


def bend_twist():
    import Part
    import Mesh
    import Points
    import freecad_deform as fd
    from freecad_deform.gui import selection
    t0 = time.time()
    V = App.Vector
    bend_cmd, twist_cmd = Gui.Command.get("Deform_Bend"), Gui.Command.get("Deform_Twist")
    stretch_cmd = Gui.Command.get("Deform_Stretch")
    check("Bend and Twist registered", bend_cmd is not None and twist_cmd is not None)
    toolbar = Gui.getMainWindow().findChild(QtGui.QToolBar, "Deform")
    texts = [a.text() for a in toolbar.actions()] if toolbar else []
    check("toolbar: Stretch, Bend, Twist", texts[:3] == ["Stretch", "Bend", "Twist"], texts)
    check("menu: Stretch, Bend, Twist", (menu_texts() or [])[:3] == ["Stretch", "Bend", "Twist"],
          menu_texts())
    check("command icons", bend_cmd.getInfo()["pixmap"].endswith("Bend.svg")
          and twist_cmd.getInfo()["pixmap"].endswith("Twist.svg"),
          (bend_cmd.getInfo()["pixmap"], twist_cmd.getInfo()["pixmap"]))

    doc = App.newDocument("DeformBendTest")
    part = doc.addObject("Part::Feature", "Part")
    part.Label = "face_recognition_sample_part"
    part.Shape = Part.read(STEP)
    line = doc.addObject("Part::Feature", "AxisLine")  # a straight edge beyond the part, -z
    line.Shape = Part.makeLine(V(157.5, 30, 225), V(157.5, 30, 0))
    doc.recompute()
    Gui.SendMsgToActiveView("ViewFit")
    process(0.2)
    shape0 = part.Shape  # the same TopoDS shape while nothing changes the Base
    bb = part.Shape.BoundBox

    # --- when the commands are enabled -----------------------------------------------------------
    both = lambda: (bend_cmd.isActive(), twist_cmd.isActive())  # noqa: E731
    Gui.Selection.clearSelection()
    process()
    check("Bend/Twist inactive with nothing selected", both() == (False, False), both())
    Gui.Selection.addSelection(part)
    check("Bend/Twist active with the solid selected", both() == (True, True), both())
    straight = edge_name(part.Shape, lambda e: isinstance(e.Curve, (Part.Line, Part.LineSegment)))
    curved = edge_name(part.Shape, lambda e: isinstance(e.Curve, Part.Circle))
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, part.Name, straight)
    check("Bend/Twist active with a straight edge of the solid (Stretch not)",
          both() == (True, True) and not stretch_cmd.isActive(), both())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, part.Name, curved)
    check("Bend/Twist inactive with a curved edge", both() == (False, False), both())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    Gui.Selection.addSelection(doc.Name, line.Name, "Edge1")
    check("Bend/Twist active with the solid and a straight edge", both() == (True, True), both())
    planar = next(f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
                  if isinstance(f.Surface, Part.Plane))
    Gui.Selection.addSelection(doc.Name, part.Name, planar)
    check("Bend/Twist active with the solid, a planar face and an edge",
          both() == (True, True), both())
    Gui.Selection.clearSelection()
    container = doc.addObject("App::Part", "Container")  # its origin holds datum lines
    doc.recompute()
    axes = {o.Role: o for o in container.Origin.OriginFeatures if o.isDerivedFrom("App::Line")}
    lines = {role: selection.datum_line(o) for role, o in axes.items()}
    check("datum lines of an origin give their axes",
          set(lines) == {"X_Axis", "Y_Axis", "Z_Axis"}
          and all(lines[r][1].isEqual(v, 1e-9) for r, v in selection.AXES.items()),
          {r: (tuple(p), tuple(d)) for r, (p, d) in lines.items()})
    Gui.Selection.addSelection(part)
    Gui.Selection.addSelection(axes["Z_Axis"])
    check("Bend/Twist active with the solid and a datum line", both() == (True, True), both())
    Gui.Selection.clearSelection()
    for name in [o.Name for o in doc.Objects if o.Name not in (part.Name, line.Name)]:
        if doc.getObject(name) is not None:
            doc.removeObject(name)
    doc.recompute()
    line.ViewObject.Visibility = False
    undo0 = doc.UndoCount
    names0 = [o.Name for o in doc.Objects]

    # --- Bend: suggested defaults, Angle typed with units, OK, Undo --------------------------------
    Gui.Selection.addSelection(part)
    t = time.time()
    bend_cmd.run()
    check("Bend panel opens", wait(lambda: panel_form("Bend") is not None))
    objs = of_type(doc, "Bend")
    check("one Bend while editing", len(objs) == 1, [o.Name for o in doc.Objects])
    obj = objs[0]
    check("Bend: Base hidden", not part.ViewObject.Visibility)
    check("Bend defaults: valid preview, no error",
          "Invalid" not in obj.State and obj.Shape.isValid() and no_error("Bend"),
          f"{obj.State} {obj.getStatusString()}")
    n, w, c = direction(obj.Plane), direction(obj.Axis), obj.Axis.Base
    check("Bend defaults: Plane through the box centre, normal along the longest side",
          obj.Plane.Base.isEqual(bb.Center, 1e-9) and n.isEqual(V(1, 0, 0), 1e-9), obj.Plane)
    check("Bend defaults: Angle 30 deg", abs(obj.Angle.Value - 30.0) < 1e-9, obj.Angle)
    check("Bend defaults: Axis in Plane, along the second-longest side, outside the box",
          abs((c - obj.Plane.Base).dot(n)) < 1e-9 and abs(abs(w.z) - 1) < 1e-9
          and not bb.isInside(c), f"{obj.Axis} {bb}")
    check("Bend defaults: VolumeChange = Pappus", abs(obj.VolumeChange / pappus(shape0, obj) - 1)
          < 1e-6, f"{obj.VolumeChange} {pappus(shape0, obj)}")
    labels = panel_texts("Bend")
    wanted = {"Plane", "Angle", "Axis", "UsePlane2", "Plane2 offset", "Samples", "VolumeChange",
              "Continuity"}
    check("Bend panel labels are the property names", wanted <= labels, sorted(labels))
    angle = field("Angle", "Bend")
    check("Bend: Angle is a Gui::QuantitySpinBox bound to the property",
          angle is not None and angle.metaObject().className() == "Gui::QuantitySpinBox"
          and Gui.ExpressionBinding(angle).isBound())
    check("Bend: Pick axis button", field("PickAxis", "Bend") is not None
          and field("PickAxis", "Bend").text() == "Pick axis")
    check("Bend: axis fields show Axis", abs(field("AxisPointY", "Bend").property("rawValue")
                                             - c.y) < 1e-9
          and abs(field("AxisDirectionZ", "Bend").value() - w.z) < 1e-6)

    type_into(angle, "-30 deg")  # the far part would swing into the near one
    check("Bend: wrong sign of Angle is a red error naming Angle",
          wait(lambda: error_shown("Bend", "Angle")), field("ErrorLabel", "Bend").text())
    check("Bend: the Angle field is outlined red", angle.property("deformError") is True,
          angle.styleSheet())
    check("Bend: no dialog for the error", QtGui.QApplication.activeModalWidget() is None)
    type_into(angle, "0.75 rad")
    check("Bend: live preview (0.75 rad)", wait(lambda: angle_done(obj, math.degrees(0.75)))
          and no_error("Bend"), f"{obj.Angle} {obj.State}")
    check("Bend: preview VolumeChange shown",
          field("VolumeChange", "Bend").text().startswith(f"{obj.VolumeChange:.6g}"),
          field("VolumeChange", "Bend").text())
    type_into(angle, "45 deg")
    check("Bend: live preview (45 deg)", wait(lambda: angle_done(obj, 45.0)), obj.Angle)
    v45 = obj.VolumeChange
    check("Bend: Continuity shown", field("Continuity", "Bend").text() == (obj.Continuity or "-"),
          field("Continuity", "Bend").text())
    # Flip: the other side bends about the same axis, turned: Pappus gives the same volume
    field("FlipPlane", "Bend").click()
    flipped = wait(lambda: settled(obj) or error_shown("Bend", ""))
    check("Bend: Flip bends the other side, still valid, same Pappus volume",
          flipped and direction(obj.Plane).isEqual(-n, 1e-9) and "Invalid" not in obj.State
          and abs(obj.VolumeChange / v45 - 1) < 1e-6,
          f"{obj.Plane} {obj.Axis} {obj.VolumeChange} {v45} {obj.getStatusString()}")
    field("FlipPlane", "Bend").click()
    wait(lambda: settled(obj))
    grab = os.path.join(OUT, "bend_task_panel.png")
    panel_form("Bend").grab().save(grab)
    results["screenshots"].append(grab)
    press("OK")
    results["timings"]["bend_create_and_accept"] = time.time() - t
    objs = of_type(doc, "Bend")
    check("Bend: one object after OK", len(objs) == 1 and not Gui.Control.activeDialog())
    obj = objs[0]
    result = obj.Shape
    check("Bend: Angle = 45 deg after OK", abs(obj.Angle.Value - 45.0) < 1e-9, obj.Angle)
    check("Bend: valid single solid", result.isValid() and len(result.Solids) == 1
          and "Invalid" not in obj.State, f"valid={result.isValid()} solids={len(result.Solids)}")
    check("Bend: VolumeChange = Pappus (OCCT volume)",
          abs((result.Volume - shape0.Volume) / pappus(shape0, obj) - 1) < 1e-6,
          f"dV={result.Volume - shape0.Volume} pappus={pappus(shape0, obj)}")
    check("Bend: one undo step", doc.UndoCount == undo0 + 1 and doc.UndoNames[0] == "Bend",
          f"{undo0} -> {doc.UndoCount} {doc.UndoNames}")
    check("Bend: no transaction left open", App.getActiveTransaction() is None)
    check("Bend: view provider and icon", obj.ViewObject.Proxy.getIcon().endswith("Bend.svg"))
    screenshot("bend_result.png")
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("Bend: undo removes it", [o.Name for o in doc.Objects] == names0
          and part.ViewObject.Visibility and doc.UndoCount == undo0,
          f"{[o.Name for o in doc.Objects]} {doc.UndoCount}")

    # --- Bend: Cancel leaves the document as it was ------------------------------------------------
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    bend_cmd.run()
    wait(lambda: panel_form("Bend") is not None)
    obj = of_type(doc, "Bend")[0]
    type_into(field("Angle", "Bend"), "60 deg")
    check("Bend: preview before Cancel", wait(lambda: angle_done(obj, 60.0)), obj.Angle)
    press("Cancel")
    check("Bend: Cancel leaves the document unchanged",
          [o.Name for o in doc.Objects] == names0 and part.ViewObject.Visibility
          and doc.UndoCount == undo0 and App.getActiveTransaction() is None,
          f"{[o.Name for o in doc.Objects]} {doc.UndoCount}")
    check("Bend: Cancel leaves the Base untouched", part.Shape.isSame(shape0))

    # --- Bend: Pick axis from a straight edge -----------------------------------------------------------
    Gui.Selection.addSelection(part)
    bend_cmd.run()
    wait(lambda: panel_form("Bend") is not None)
    obj = of_type(doc, "Bend")[0]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, line.Name, "Edge1")
    field("PickAxis", "Bend").click()
    picked = wait(lambda: settled(obj))
    w = direction(obj.Axis)
    check("Pick axis: Axis on the edge's line, nearest to Plane's origin",
          picked and distance_to_line(obj.Axis.Base, V(157.5, 30, 0), V(0, 0, 1)) < 1e-9
          and obj.Axis.Base.isEqual(V(157.5, 30, obj.Plane.Base.z), 1e-9), obj.Axis)
    check("Pick axis: the edge's direction turned so Angle stays valid",
          w.isEqual(V(0, 0, 1), 1e-9) and "Invalid" not in obj.State and no_error("Bend"),
          f"{w} {obj.getStatusString()}")
    check("Pick axis: fields updated", abs(field("AxisPointY", "Bend").property("rawValue") - 30)
          < 1e-9, field("AxisPointY", "Bend").property("rawValue"))
    check("Pick axis: VolumeChange = Pappus about the new axis",
          abs(obj.VolumeChange / pappus(shape0, obj) - 1) < 1e-6,
          f"{obj.VolumeChange} {pappus(shape0, obj)}")
    press("OK")
    obj = of_type(doc, "Bend")[0]
    check("Pick axis: kept after OK", obj.Axis.Base.isEqual(V(157.5, 30, obj.Plane.Base.z), 1e-9)
          and obj.Shape.isValid() and len(obj.Shape.Solids) == 1, obj.Axis)
    Gui.runCommand("Std_Undo")
    process(0.1)

    # the command takes the axis from a selected edge
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    Gui.Selection.addSelection(doc.Name, line.Name, "Edge1")
    bend_cmd.run()
    wait(lambda: panel_form("Bend") is not None)
    obj = of_type(doc, "Bend")[0]
    check("Bend from solid + edge: Axis from the edge, valid",
          obj.Axis.Base.isEqual(V(157.5, 30, obj.Plane.Base.z), 1e-9)
          and direction(obj.Axis).isEqual(V(0, 0, 1), 1e-9) and "Invalid" not in obj.State,
          f"{obj.Axis} {obj.getStatusString()}")
    press("Cancel")
    check("Bend from solid + edge: Cancel", [o.Name for o in doc.Objects] == names0)

    # --- Twist on the STEP part: its default region changes outline (mapped); Plane2 offset -------
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    twist_cmd.run()
    check("Twist panel opens", wait(lambda: panel_form("Twist") is not None))
    obj = of_type(doc, "Twist")[0]
    gap = (obj.Plane2.Base - obj.Plane.Base).dot(direction(obj.Plane))
    check("Twist defaults: Plane and Plane2 at 1/3 and 2/3 of the longest side",
          abs(obj.Plane.Base.x - bb.XLength / 3) < 1e-9 and abs(gap - bb.XLength / 3) < 1e-9
          and not obj.UseAxis and abs(obj.Angle.Value - 30) < 1e-9, f"{obj.Plane} {obj.Plane2}")
    check("Twist on the STEP part: the outline change goes through the space map, no error",
          wait(lambda: settled(obj) and no_error("Twist")) and obj.Shape.isValid(),
          f"{field('ErrorLabel', 'Twist').text()} {obj.getStatusString()}")
    type_into(field("Plane2Offset", "Twist"), "40 mm")  # 105..145 mm: one outline
    check("Twist: Plane2 offset previews, error clears",
          wait(lambda: settled(obj) and no_error("Twist"))
          and abs((obj.Plane2.Base - obj.Plane.Base).dot(direction(obj.Plane)) - 40) < 1e-9
          and obj.Shape.isValid() and len(obj.Shape.Solids) == 1,
          f"{obj.State} {obj.getStatusString()}")
    check("Twist keeps the volume (STEP part)", abs(obj.VolumeChange) < 1e-3 * shape0.Volume,
          obj.VolumeChange)
    press("Cancel")
    check("Twist: Cancel leaves the document unchanged", [o.Name for o in doc.Objects] == names0
          and doc.UndoCount == undo0 and part.ViewObject.Visibility)

    # --- editing an existing Bend: double-click, Cancel restores ----------------------------------
    obj = fd.make_bend(part, (V(160, 0, 0), V(1, 0, 0)), -60, (V(160, 0, 260), V(0, 1, 0)))
    check("make_bend gets the view provider",
          type(obj.ViewObject.Proxy).__name__ == "ViewProviderDeform"
          and "Invalid" not in obj.State, obj.getStatusString())
    undo2 = doc.UndoCount
    volume = obj.Shape.Volume
    obj.ViewObject.doubleClicked()
    check("Bend: double-click opens the panel", wait(lambda: panel_form("Bend") is not None))
    check("Bend panel shows Angle and Axis",
          abs(field("Angle", "Bend").property("rawValue") + 60) < 1e-9
          and abs(field("AxisPointZ", "Bend").property("rawValue") - 260) < 1e-9)
    type_into(field("Angle", "Bend"), "-20 deg")
    wait(lambda: angle_done(obj, -20.0))
    field("UsePlane2", "Bend").click()
    # Plane2 starts halfway to the far end, beyond the step at x = 195: the outline changes
    check("Bend: UsePlane2 across a step goes through the space map, no error",
          wait(lambda: obj.UsePlane2 and settled(obj) and no_error("Bend"))
          and obj.Shape.isValid() and field("Plane2Offset", "Bend").isEnabled(),
          f"{field('ErrorLabel', 'Bend').text()} {obj.getStatusString()}")
    type_into(field("Plane2Offset", "Bend"), "30 mm")  # 160..190 mm: one outline
    check("Bend: UsePlane2 previews", wait(lambda: settled(obj) and no_error("Bend"))
          and "Invalid" not in obj.State
          and abs((obj.Plane2.Base - obj.Plane.Base).dot(direction(obj.Plane)) - 30) < 1e-9,
          obj.getStatusString())
    # Pick plane: a planar face across the long side; Axis follows into the new Plane
    plane0, axis0 = App.Placement(obj.Plane), App.Placement(obj.Axis)
    step = next(f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
                if isinstance(f.Surface, Part.Plane) and abs(abs(f.Surface.Axis.x) - 1) < 1e-9
                and abs(f.CenterOfMass.x - 194.849) < 1e-2)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, part.Name, step)
    field("PickPlane", "Bend").click()
    wait(lambda: settled(obj) or error_shown("Bend", ""))
    n2, w2 = direction(obj.Plane), direction(obj.Axis)
    check("Bend: Pick plane, Axis follows into it, valid",
          abs(obj.Plane.Base.x - 194.849) < 1e-2 and abs(abs(n2.x) - 1) < 1e-9
          and abs(w2.dot(n2)) < 1e-9 and abs((obj.Axis.Base - obj.Plane.Base).dot(n2)) < 1e-9
          and "Invalid" not in obj.State and no_error("Bend"),
          f"{obj.Plane} {obj.Axis} {obj.getStatusString()}")
    press("Cancel")
    check("Bend: edit Cancel restores Plane and Axis", same_placement(obj.Plane, plane0)
          and same_placement(obj.Axis, axis0), f"{obj.Plane} {obj.Axis}")
    check("Bend: edit Cancel restores", abs(obj.Angle.Value + 60) < 1e-9 and not obj.UsePlane2
          and abs(obj.Shape.Volume - volume) < 1e-6 * volume and doc.UndoCount == undo2,
          f"{obj.Angle} {obj.UsePlane2} {doc.UndoCount}")
    results["timings"]["bend"] = time.time() - t0
    App.closeDocument(doc.Name)
    process(0.2)

    # --- Twist on a box: defaults, Angle, OK, Undo, Cancel, UseAxis, edge ----------------------------
    t1 = time.time()
    doc = App.newDocument("DeformTwistTest")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(120, 40, 20, V(0, 200, 0))
    doc.recompute()
    box0 = box.Shape.copy()
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    twist_cmd.run()
    check("Twist panel opens on a box", wait(lambda: panel_form("Twist") is not None))
    obj = of_type(doc, "Twist")[0]
    check("Twist defaults: valid preview, no error", "Invalid" not in obj.State and no_error("Twist")
          and obj.Shape.isValid(), f"{obj.State} {obj.getStatusString()}")
    check("Twist defaults: planes at x = 40 and 80", obj.Plane.Base.isEqual(V(40, 220, 10), 1e-9)
          and obj.Plane2.Base.isEqual(V(80, 220, 10), 1e-9), f"{obj.Plane} {obj.Plane2}")
    labels = panel_texts("Twist")
    wanted = {"Plane", "Plane2 offset", "Angle", "UseAxis", "Axis", "Samples", "VolumeChange",
              "Continuity"}
    check("Twist panel labels are the property names", wanted <= labels, sorted(labels))
    check("Twist: Axis fields disabled while UseAxis is off, Pick axis enabled",
          not field("AxisPointX", "Twist").isEnabled() and field("PickAxis", "Twist").isEnabled()
          and field("Plane2Offset", "Twist").isEnabled())
    angle = field("Angle", "Twist")
    check("Twist: Angle is a bound Gui::QuantitySpinBox",
          angle.metaObject().className() == "Gui::QuantitySpinBox"
          and Gui.ExpressionBinding(angle).isBound())
    type_into(angle, "90 deg")
    check("Twist: live preview (90 deg)", wait(lambda: angle_done(obj, 90.0)) and no_error("Twist"),
          f"{obj.Angle} {obj.getStatusString()}")
    v90 = obj.VolumeChange
    field("UseAxis", "Twist").click()
    wait(lambda: obj.UseAxis and settled(obj))
    check("Twist: UseAxis starts from the section centroid and the same result",
          obj.Axis.Base.isEqual(V(40, 220, 10), 1e-6) and direction(obj.Axis).isEqual(V(1, 0, 0), 1e-9)
          and field("AxisPointX", "Twist").isEnabled() and abs(obj.VolumeChange - v90) < 1e-6,
          f"{obj.Axis} {obj.VolumeChange} {v90}")
    field("UseAxis", "Twist").click()
    wait(lambda: not obj.UseAxis and settled(obj))
    type_into(angle, "400 deg")   # an angle property holds 360 at most: the turn goes to Turns
    check("Twist: Angle 400 deg is one turn (Turns) and 40 deg",
          wait(lambda: obj.Turns == 1 and angle_done(obj, 40.0)) and no_error("Twist"),
          f"{obj.Turns} {obj.Angle} {obj.getStatusString()}")
    type_into(angle, "90 deg")
    wait(lambda: obj.Turns == 0 and angle_done(obj, 90.0))
    field("Samples", "Twist").setValue(8)
    check("Twist: Samples previews", wait(lambda: obj.Samples == 8 and settled(obj)), obj.Samples)
    field("Samples", "Twist").setValue(16)
    wait(lambda: obj.Samples == 16 and settled(obj))
    grab = os.path.join(OUT, "twist_task_panel.png")
    panel_form("Twist").grab().save(grab)
    results["screenshots"].append(grab)
    press("OK")
    objs = of_type(doc, "Twist")
    check("Twist: one object after OK", len(objs) == 1 and not Gui.Control.activeDialog())
    obj = objs[0]
    result = obj.Shape
    check("Twist: valid single solid", result.isValid() and len(result.Solids) == 1
          and "Invalid" not in obj.State, f"{result.isValid()} {len(result.Solids)}")
    check("Twist keeps the volume (box)", abs(result.Volume - box0.Volume) < 1e-4 * box0.Volume,
          result.Volume - box0.Volume)
    # oracle: the mid section is the rectangle turned by 45 deg about the x axis through its centre
    mid = result.slice(V(1, 0, 0), 60.0)
    turn = App.Rotation(V(1, 0, 0), 45)
    centre = V(60, 220, 10)
    expected = [centre + turn.multVec(V(0, y, z)) for y in (-20, 20) for z in (-10, 10)]
    found = [v.Point for wire in mid for v in wire.Vertexes]
    worst = max(min((p - q).Length for q in found) for p in expected) if found else float("inf")
    check("Twist: mid section = the section turned by Angle/2", worst < 1e-4 and
          abs(Part.Face(mid[0]).Area - 800.0) < 1e-3, f"worst {worst} {found}")
    far = [v.Point for v in result.Vertexes if v.Point.x > 119.999]
    turn = App.Rotation(V(1, 0, 0), 90)
    expected = [V(120, 220, 10) + turn.multVec(V(0, y, z)) for y in (-20, 20) for z in (-10, 10)]
    worst = max(min((p - q).Length for q in far) for p in expected) if far else float("inf")
    check("Twist: far end turned rigidly by Angle", worst < 1e-6, f"worst {worst}")
    check("Twist: one undo step", doc.UndoCount == undo0 + 1 and doc.UndoNames[0] == "Twist",
          doc.UndoNames)
    check("Twist: no transaction left open", App.getActiveTransaction() is None)
    screenshot("twist_result.png")
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("Twist: undo removes it", [o.Name for o in doc.Objects] == names0
          and box.ViewObject.Visibility and doc.UndoCount == undo0)

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    twist_cmd.run()
    wait(lambda: panel_form("Twist") is not None)
    obj = of_type(doc, "Twist")[0]
    type_into(field("Angle", "Twist"), "120 deg")
    wait(lambda: angle_done(obj, 120.0))
    press("Cancel")
    check("Twist: Cancel leaves the document unchanged", [o.Name for o in doc.Objects] == names0
          and box.ViewObject.Visibility and doc.UndoCount == undo0
          and App.getActiveTransaction() is None)

    # an edge of the box gives the axis: UseAxis on
    edge = edge_name(box.Shape, lambda e: abs(e.Length - 120) < 1e-9
                     and e.Vertexes[0].Point.y == 200 and e.Vertexes[0].Point.z == 0)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, box.Name, edge)
    check("Twist active with an edge of the box", twist_cmd.isActive())
    twist_cmd.run()
    wait(lambda: panel_form("Twist") is not None)
    obj = of_type(doc, "Twist")[0]
    check("Twist from an edge: UseAxis, Axis on the edge, valid",
          obj.UseAxis and field("UseAxis", "Twist").isChecked()
          and abs(abs(direction(obj.Axis).x) - 1) < 1e-9
          and distance_to_line(obj.Axis.Base, V(0, 200, 0), V(1, 0, 0)) < 1e-9
          and "Invalid" not in obj.State, f"{obj.Axis} {obj.getStatusString()}")
    # and Pick axis takes another edge in the panel
    edge2 = edge_name(box.Shape, lambda e: abs(e.Length - 120) < 1e-9
                      and e.Vertexes[0].Point.y == 240 and e.Vertexes[0].Point.z == 20)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, box.Name, edge2)
    field("PickAxis", "Twist").click()
    wait(lambda: settled(obj))
    check("Twist: Pick axis takes an edge", distance_to_line(obj.Axis.Base, V(0, 240, 20),
                                                             V(1, 0, 0)) < 1e-9
          and "Invalid" not in obj.State, f"{obj.Axis} {obj.getStatusString()}")
    press("Cancel")
    check("Twist from an edge: Cancel", [o.Name for o in doc.Objects] == names0)

    # --- meshes and point clouds ----------------------------------------------------------------------
    mesh = doc.addObject("Mesh::Feature", "Mesh")
    mesh.Mesh = Mesh.createBox(30, 10, 10)
    cloud = doc.addObject("Points::Feature", "Points")
    cloud.Points = Points.Points([V(0.5 * i, 0.5 * j, 0.5 * k) for i in range(60)
                                  for j in range(20) for k in range(20)])
    doc.recompute()
    for base, data in ((mesh, "Mesh"), (cloud, "Points")):
        for cmd, kind in ((bend_cmd, "Bend"), (twist_cmd, "Twist")):
            Gui.Selection.clearSelection()
            Gui.Selection.addSelection(base)
            ok = cmd.isActive()
            cmd.run()
            wait(lambda: panel_form(kind) is not None)
            obj = of_type(doc, kind)[0]
            wait(lambda: settled(obj))
            ok = ok and "Invalid" not in obj.State and no_error(kind)
            press("OK")
            result = getattr(obj, data)
            if data == "Mesh":
                ok = ok and result.CountFacets > 0 and result.isSolid() and (
                    obj.VolumeChange > 0 if kind == "Bend" else abs(obj.VolumeChange) < 1e-2 * 3000)
                detail = f"{obj.TypeId} facets {result.CountFacets} dV {obj.VolumeChange}"
            else:
                ok = ok and result.CountPoints >= base.Points.CountPoints
                detail = f"{obj.TypeId} points {result.CountPoints}"
            check(f"{kind} on a {data} base: defaults valid, OK", ok,
                  f"{detail} {obj.State} {obj.getStatusString()}")
            doc.removeObject(obj.Name)
            base.ViewObject.Visibility = True
    results["timings"]["twist_and_discrete"] = time.time() - t1
