"""The stretch part of the GUI scenario (run by freecad_scenario.py inside FreeCAD, on
the harness in harness.py)."""
import os
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from harness import (OUT, STEP, check, field, panel_form, press, process, results, same_placement,
    screenshot, type_into, wait)


def stretches(doc):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "TYPE", None) == "Stretch"]


def tree_double_click(obj):
    """Double-click the object's item in the Model tree (FreeCAD wraps that in its own
    "Double click" transaction, which the panel must take over)."""
    Gui.Selection.clearSelection()
    for tree in Gui.getMainWindow().findChildren(QtGui.QTreeWidget):
        try:
            if tree.metaObject().className() != "Gui::TreeWidget":
                continue
            flags = QtCore.Qt.MatchExactly | QtCore.Qt.MatchRecursive
            items = tree.findItems(obj.Label, flags, 0)
        except RuntimeError:
            continue
        if not items:
            continue
        tree.scrollToItem(items[0])
        pos = tree.visualItemRect(items[0]).center()
        for kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease,
                     QtCore.QEvent.MouseButtonDblClick, QtCore.QEvent.MouseButtonRelease):
            event = QtGui.QMouseEvent(kind, QtCore.QPointF(pos), QtCore.Qt.LeftButton,
                                      QtCore.Qt.LeftButton, QtCore.Qt.NoModifier)
            QtGui.QApplication.sendEvent(tree.viewport(), event)
        process(0.1)
        return
    raise RuntimeError(f"{obj.Label} not found in the tree")


def preview_done(obj, distance):
    return abs(obj.Distance.Value - distance) < 1e-9 and "Touched" not in obj.State


def section_area(shape, plane):
    """Area of the cross-section of `shape` at `plane`: the oracle for a stretch (A * d)."""
    import Part
    normal = plane.Rotation.multVec(App.Vector(0, 0, 1))
    wires = shape.slice(normal, normal.dot(plane.Base))
    return Part.makeFace(wires, "Part::FaceMakerBullseye").Area


def stretch():
    import Part
    t0 = time.time()

    # --- the workbench, found through the user Mod directory -------------------------------------
    check("workbench listed", "DeformWorkbench" in Gui.listWorkbenches(),
          sorted(Gui.listWorkbenches()))
    Gui.activateWorkbench("DeformWorkbench")
    process(0.2)
    check("workbench active", Gui.activeWorkbench().name() == "DeformWorkbench",
          Gui.activeWorkbench().name())
    wb = Gui.getWorkbench("DeformWorkbench")
    check("workbench icon", wb.Icon.endswith("Deform.svg") and os.path.isfile(wb.Icon), wb.Icon)
    import freecad_deform
    repo = os.path.dirname(os.path.dirname(os.path.abspath(freecad_deform.__file__)))
    check("loaded from the user Mod dir",
          os.path.realpath(repo) == os.path.realpath(os.environ["DEFORM_REPO"])
          and os.path.join(App.getUserAppDataDir(), "Mod") in freecad_deform.__file__,
          freecad_deform.__file__)
    check("command registered", "Deform_Stretch" in Gui.listCommands())
    toolbar = Gui.getMainWindow().findChild(QtGui.QToolBar, "Deform")
    check("toolbar", toolbar is not None and any(
        a.objectName() == "Deform_Stretch" or a.text() == "Stretch" for a in toolbar.actions()),
        [a.text() for a in toolbar.actions()] if toolbar else None)
    results["timings"]["start"] = time.time() - t0

    # --- a real STEP part ------------------------------------------------------------------------
    doc = App.newDocument("DeformGuiTest")
    part = doc.addObject("Part::Feature", "Part")
    part.Label = "face_recognition_sample_part"
    part.Shape = Part.read(STEP)
    doc.recompute()
    Gui.SendMsgToActiveView("ViewFit")
    process(0.2)
    base_volume = part.Shape.Volume

    cmd = Gui.Command.get("Deform_Stretch")
    Gui.Selection.clearSelection()
    process()
    check("inactive with nothing selected", not cmd.isActive())
    Gui.Selection.addSelection(doc.Name, part.Name, "Edge1")
    check("inactive with an edge selected", not cmd.isActive())
    Gui.Selection.clearSelection()
    planar = next(f"Face{i + 1}" for i, f in enumerate(part.Shape.Faces)
                  if isinstance(f.Surface, Part.Plane))
    Gui.Selection.addSelection(doc.Name, part.Name, planar)
    check("active with a planar face of the solid", cmd.isActive())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    check("active with the solid selected", cmd.isActive())

    undo0 = doc.UndoCount
    names0 = [o.Name for o in doc.Objects]

    # --- create, type a Distance with units, OK -------------------------------------------------
    t = time.time()
    cmd.run()
    check("task panel opens", wait(lambda: panel_form() is not None), Gui.Control.activeDialog())
    check("inactive while the panel is open", not cmd.isActive())
    objs = stretches(doc)
    check("one Stretch while editing", len(objs) == 1, [o.Name for o in doc.Objects])
    obj = objs[0]
    check("Base hidden", not part.ViewObject.Visibility)
    distance = field("Distance")
    check("Distance is a Gui::QuantitySpinBox",
          distance is not None and distance.metaObject().className() == "Gui::QuantitySpinBox")
    check("Distance bound to the property", Gui.ExpressionBinding(distance).isBound())
    check("suggested plane crosses the part", "Invalid" not in obj.State,
          obj.getStatusString())

    type_into(distance, "1 in")
    check("live preview (1 in = 25.4 mm)", wait(lambda: preview_done(obj, 25.4)),
          f"{obj.Distance} {obj.State}")
    v_in = obj.VolumeChange
    check("preview VolumeChange shown", field("VolumeChange").text().startswith(f"{v_in:.6g}"),
          field("VolumeChange").text())
    type_into(distance, "25 mm")
    check("live preview (25 mm)", wait(lambda: preview_done(obj, 25.0)), obj.Distance)
    check("preview Continuity shown", field("Continuity").text() == (obj.Continuity or "-"),
          field("Continuity").text())
    check("no error shown", not field("ErrorLabel").isVisible(), field("ErrorLabel").text())
    # A plane that misses the part: the error is shown in the panel, red, not in a dialog.
    origin_x = field("PlaneOriginX")
    normal = obj.Plane.Rotation.multVec(App.Vector(0, 0, 1))
    old_x = origin_x.property("rawValue")
    type_into(origin_x, "5000 mm")
    shown = wait(lambda: field("ErrorLabel").isVisible())
    check("bad Plane: red error in the panel",
          shown and "Plane" in field("ErrorLabel").text()
          and "c00000" in field("ErrorLabel").styleSheet(),
          f"{field('ErrorLabel').text()!r} normal={normal}")
    check("bad Plane: the Plane group is outlined red",
          field("PlaneGroup").property("deformError") is True
          and "c00000" in field("PlaneGroup").styleSheet(), field("PlaneGroup").styleSheet())
    check("bad Plane: no dialog", QtGui.QApplication.activeModalWidget() is None)
    grab = os.path.join(OUT, "stretch_task_panel_error.png")
    panel_form().grab().save(grab)
    results["screenshots"].append(grab)
    type_into(origin_x, f"{old_x} mm")
    check("error clears", wait(lambda: not field("ErrorLabel").isVisible())
          and not field("PlaneGroup").property("deformError"), field("ErrorLabel").text())
    screenshot("stretch_panel.png")
    grab = os.path.join(OUT, "stretch_task_panel.png")
    panel_form().grab().save(grab)
    results["screenshots"].append(grab)
    window = os.path.join(OUT, "stretch_window.png")
    Gui.getMainWindow().grab().save(window)
    results["screenshots"].append(window)

    press("OK")
    results["timings"]["create_and_accept"] = time.time() - t
    check("panel closed", not Gui.Control.activeDialog())
    objs = stretches(doc)
    check("one Stretch after OK", len(objs) == 1, [o.Name for o in doc.Objects])
    obj = objs[0]
    shape = obj.Shape
    check("Distance = 25 mm", abs(obj.Distance.Value - 25.0) < 1e-9, obj.Distance)
    check("valid single solid", shape.isValid() and len(shape.Solids) == 1,
          f"valid={shape.isValid()} solids={len(shape.Solids)}")
    check("VolumeChange > 0", obj.VolumeChange > 0, obj.VolumeChange)
    area = section_area(part.Shape, obj.Plane)
    check("VolumeChange = section area * Distance (OCCT oracle)",
          abs(shape.Volume - base_volume - area * 25.0) < 1e-6 * shape.Volume,
          f"dV={shape.Volume - base_volume} A*d={area * 25.0}")
    check("one undo step", doc.UndoCount == undo0 + 1 and doc.UndoNames[0] == "Stretch",
          f"{undo0} -> {doc.UndoCount} {doc.UndoNames}")
    check("no transaction left open", App.getActiveTransaction() is None,
          App.getActiveTransaction())
    vp = obj.ViewObject.Proxy
    check("view provider", type(vp).__name__ == "ViewProviderDeform"
          and vp.getIcon().endswith("Stretch.svg"), vp)
    check("Base claimed as child", vp.claimChildren() == [part])
    check("Base stays hidden, result shown",
          not part.ViewObject.Visibility and obj.ViewObject.Visibility)
    screenshot("stretch_result.png")

    # --- Undo removes it in one step ----------------------------------------------------------
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("undo removes the Stretch", not stretches(doc) and [o.Name for o in doc.Objects] == names0,
          [o.Name for o in doc.Objects])
    check("undo shows the Base", part.ViewObject.Visibility)
    check("undo count back", doc.UndoCount == undo0, doc.UndoCount)

    # --- Cancel leaves the document as it was --------------------------------------------------
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    undo1 = doc.UndoCount
    cmd.run()
    check("panel opens again", wait(lambda: panel_form() is not None))
    obj = stretches(doc)[0]
    type_into(field("Distance"), "10 mm")
    check("preview before Cancel", wait(lambda: preview_done(obj, 10.0)), obj.Distance)
    press("Cancel")
    check("cancel: no new object", [o.Name for o in doc.Objects] == names0,
          [o.Name for o in doc.Objects])
    check("cancel: Base visible", part.ViewObject.Visibility)
    check("cancel: no undo step", doc.UndoCount == undo1, f"{undo1} -> {doc.UndoCount}")
    check("cancel: no transaction left open", App.getActiveTransaction() is None,
          App.getActiveTransaction())

    # --- other bases: a mesh and a point cloud also enable the command ---------------------------
    import Mesh
    import Points
    mesh = doc.addObject("Mesh::Feature", "Mesh")
    mesh.Mesh = Mesh.createBox(10, 10, 10)
    cloud = doc.addObject("Points::Feature", "Points")
    cloud.Points = Points.Points([App.Vector(i, 0, 0) for i in range(10)])
    doc.recompute()
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(mesh)
    check("active with a mesh", cmd.isActive())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(cloud)
    check("active with a point cloud", cmd.isActive())
    Gui.Selection.addSelection(part)
    check("inactive with two bases", not cmd.isActive())
    # The whole round trip on a mesh and a point cloud: their results are
    # Mesh::FeaturePython / Points::FeaturePython with the same view provider.
    for base, data, expected in ((mesh, "Mesh", 1000.0 + 4.0 * 100.0), (cloud, "Points", None)):
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(base)
        cmd.run()
        wait(lambda: panel_form() is not None)
        obj = stretches(doc)[0]
        type_into(field("Distance"), "4 mm")
        wait(lambda: preview_done(obj, 4.0))
        press("OK")
        result = getattr(obj, data)
        ok = (type(obj.ViewObject.Proxy).__name__ == "ViewProviderDeform"
              and "Invalid" not in obj.State and not base.ViewObject.Visibility)
        if expected is not None:
            ok = ok and abs(result.Volume - expected) < 1e-6 * expected
            detail = f"{obj.TypeId} volume {result.Volume}"
        else:
            # the far points move by 4 mm; the gap may be filled with new samples
            ok = (ok and result.CountPoints >= base.Points.CountPoints
                  and abs(result.BoundBox.XLength - (base.Points.BoundBox.XLength + 4.0)) < 1e-9)
            detail = (f"{obj.TypeId} {result.BoundBox} count {result.CountPoints} "
                      f"vp {obj.ViewObject.Proxy} base shown {base.ViewObject.Visibility}")
        check(f"{data} base: create and OK", ok, f"{detail} {obj.State} {obj.getStatusString()}")
        doc.removeObject(obj.Name)
        base.ViewObject.Visibility = True
    Gui.Selection.clearSelection()
    doc.removeObject(mesh.Name)
    doc.removeObject(cloud.Name)
    part.ViewObject.Visibility = True

    # --- a datum plane gives the plane ------------------------------------------------------------
    datum = doc.addObject("App::Plane", "DatumPlane")
    datum.Placement = App.Placement(App.Vector(0, -50, 100), App.Rotation(App.Vector(0, 0, 1), 0))
    doc.recompute()
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(part)
    Gui.Selection.addSelection(datum)
    check("active with the solid and a datum plane", cmd.isActive())
    names1 = [o.Name for o in doc.Objects]
    cmd.run()
    wait(lambda: panel_form() is not None)
    obj = stretches(doc)[0]
    check("datum plane becomes Plane", same_placement(obj.Plane, datum.Placement)
          and "Invalid" not in obj.State, f"{obj.Plane} {obj.getStatusString()}")
    press("Cancel")
    check("cancel after datum", [o.Name for o in doc.Objects] == names1, [o.Name for o in doc.Objects])
    doc.removeObject(datum.Name)
    Gui.Selection.clearSelection()

    # --- editing an existing object: double-click, Cancel restores, OK is one step ------------
    import freecad_deform as fd
    plane = App.Placement(App.Vector(part.Shape.BoundBox.Center),
                          App.Rotation(App.Vector(0, 0, 1), App.Vector(1, 0, 0)))
    obj = fd.make_stretch(part, plane, 25)
    v25 = obj.VolumeChange
    check("make_stretch attaches the view provider",
          type(obj.ViewObject.Proxy).__name__ == "ViewProviderDeform")
    undo2 = doc.UndoCount
    obj.ViewObject.doubleClicked()
    check("double-click opens the panel", wait(lambda: panel_form() is not None))
    check("panel shows Distance", abs(field("Distance").property("rawValue") - 25.0) < 1e-9,
          field("Distance").property("rawValue"))
    # Flip: the other side moves; a straight stretch adds the same A * d.
    field("FlipPlane").click()
    flipped = wait(lambda: "Touched" not in obj.State)
    normal = obj.Plane.Rotation.multVec(App.Vector(0, 0, 1))
    check("Flip reverses the normal", flipped and normal.isEqual(App.Vector(-1, 0, 0), 1e-9)
          and abs(obj.VolumeChange - v25) < 1e-6 * v25, f"{normal} {obj.VolumeChange}")
    # UsePlane2: Plane2 parallel to Plane, the offset defaults to half the part beyond Plane.
    field("UsePlane2").click()
    done = wait(lambda: obj.UsePlane2 and "Touched" not in obj.State)
    offset = (obj.Plane2.Base - obj.Plane.Base).dot(normal)
    check("UsePlane2 previews", done and field("Plane2Offset").isEnabled() and offset > 0
          and obj.Shape.isValid() and "Invalid" not in obj.State,
          f"offset={offset} {obj.State} {obj.getStatusString()}")
    type_into(field("Plane2Offset"), "40 mm")
    moved = wait(lambda: abs((obj.Plane2.Base - obj.Plane.Base).dot(normal) - 40) < 1e-9
                 and "Touched" not in obj.State)
    check("Plane2 offset previews", moved and "Invalid" not in obj.State, obj.getStatusString())
    # Pick: a planar face of the shown result whose normal is along Z gives the plane.
    face = next(f"Face{i + 1}" for i, f in enumerate(obj.Shape.Faces)
                if isinstance(f.Surface, Part.Plane) and abs(f.Surface.Axis.z) > 0.999)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, obj.Name, face)
    field("PickPlane").click()
    picked = wait(lambda: "Touched" not in obj.State)
    normal = obj.Plane.Rotation.multVec(App.Vector(0, 0, 1))
    lo, hi = (lambda bb: (bb.ZMin, bb.ZMax))(part.Shape.BoundBox)
    check("Pick takes the plane from a face", picked and abs(abs(normal.z) - 1) < 1e-9
          and lo < obj.Plane.Base.z < hi and "Invalid" not in obj.State,
          f"{obj.Plane} {obj.getStatusString()}")
    check("Pick updates the fields", abs(abs(field("PlaneNormalZ").value()) - 1) < 1e-9,
          field("PlaneNormalZ").value())
    type_into(field("Distance"), "40 mm")
    check("edit preview", wait(lambda: preview_done(obj, 40.0)) and obj.VolumeChange > v25,
          f"{obj.Distance} {obj.VolumeChange}")
    press("Cancel")
    check("edit cancel restores Distance", abs(obj.Distance.Value - 25.0) < 1e-9, obj.Distance)
    check("edit cancel restores Plane and UsePlane2", same_placement(obj.Plane, plane)
          and not obj.UsePlane2, f"{obj.Plane} {obj.UsePlane2}")
    check("edit cancel restores the result", abs(obj.VolumeChange - v25) < 1e-6 * abs(v25)
          and "Touched" not in obj.State, f"{obj.VolumeChange} {v25} {obj.State}")
    check("edit cancel: no undo step", doc.UndoCount == undo2, f"{undo2} -> {doc.UndoCount}")
    check("edit cancel: leaves edit mode", Gui.ActiveDocument.getInEdit() is None)

    tree_double_click(obj)  # this time through the tree, as a user does
    check("tree double-click opens the panel", wait(lambda: panel_form() is not None))
    type_into(field("Distance"), "30 mm")
    wait(lambda: preview_done(obj, 30.0))
    press("OK")
    check("edit OK keeps Distance", abs(obj.Distance.Value - 30.0) < 1e-9, obj.Distance)
    check("edit OK is one undo step", doc.UndoCount == undo2 + 1
          and doc.UndoNames[0] == "Edit Stretch", doc.UndoNames)
    check("edit OK: no transaction left open", App.getActiveTransaction() is None,
          App.getActiveTransaction())
    Gui.runCommand("Std_Undo")
    process(0.1)
    doc.recompute()
    check("undo of the edit", abs(obj.Distance.Value - 25.0) < 1e-9, obj.Distance)

    # An expression on Distance shows in the panel (the spin box is bound to the property).
    obj.setExpression("Distance", "2 * 10 mm")
    doc.recompute()
    obj.ViewObject.doubleClicked()
    wait(lambda: panel_form() is not None)
    check("expression shown in the panel",
          abs(field("Distance").property("rawValue") - 20.0) < 1e-9
          and Gui.ExpressionBinding(field("Distance")).hasExpression(),
          field("Distance").property("rawValue"))
    press("Cancel")
    check("expression kept after Cancel", obj.ExpressionEngine == [("Distance", "2 * 10mm")]
          or [p for p, _ in obj.ExpressionEngine] == ["Distance"], obj.ExpressionEngine)

    # --- save, reopen: the view provider comes back ----------------------------------------------
    path = os.path.join(OUT, "stretch_gui.FCStd")
    if os.path.exists(path):
        os.remove(path)
    doc.saveAs(path)
    name = obj.Name
    App.closeDocument(doc.Name)
    process(0.2)
    doc = App.openDocument(path)
    process(0.3)
    obj = doc.getObject(name)
    vobj = obj.ViewObject
    check("reopen: view provider restored", type(vobj.Proxy).__name__ == "ViewProviderDeform",
          vobj.Proxy)
    check("reopen: icon", vobj.Proxy.getIcon().endswith("Stretch.svg")
          and not vobj.Icon.isNull(), vobj.Proxy.getIcon())
    check("reopen: Base claimed", [o.Name for o in vobj.claimChildren()] == ["Part"])
    obj.touch()
    doc.recompute()
    check("reopen: recomputes", obj.Shape.isValid() and "Invalid" not in obj.State
          and abs(obj.Distance.Value - 20.0) < 1e-9, f"{obj.State} {obj.Distance}")
    vobj.doubleClicked()
    check("reopen: double-click opens the panel", wait(lambda: panel_form() is not None))
    press("Cancel")
    screenshot("stretch_reopened.png")
    # Deleting the Stretch shows its Base again.
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(obj)
    Gui.runCommand("Std_Delete")
    process(0.2)
    check("delete shows the Base", doc.getObject(name) is None
          and doc.getObject("Part").ViewObject.Visibility, [o.Name for o in doc.Objects])
    results["timings"]["total"] = time.time() - t0
