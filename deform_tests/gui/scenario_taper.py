"""The Taper part of the GUI scenario (run by freecad_scenario.py inside FreeCAD): command,
panel, live preview against closed-form volumes, Profile, UseScaleXY, OK, one undo step,
Cancel. `h` is the scenario harness (check, wait, field, type_into, press, ...)."""
import FreeCAD as App
import FreeCADGui as Gui
import Part
from PySide import QtGui

V = App.Vector
SECTION, LENGTH = 40.0 * 20.0, 40.0  # the box's section and the region's length (x 40..80)


def tapered_box_volume(sx, sy):
    """Closed form for the 120 x 40 x 20 box tapered linearly between x = 40 and 80 to
    (sx, sy), the far 40 mm scaled by (sx, sy): A * L * integral of (1 + (sx - 1) t)
    (1 + (sy - 1) t) dt over t in 0..1, plus the near and far blocks."""
    a, b = sx - 1.0, sy - 1.0
    region = SECTION * LENGTH * (1.0 + (a + b) / 2.0 + a * b / 3.0)
    return SECTION * 40.0 + region + SECTION * sx * sy * 40.0


def taper(h):
    doc = App.newDocument("DeformTaperTest")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(120, 40, 20, V(0, 200, 0))
    doc.recompute()
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    cmd = Gui.Command.get("Deform_Taper")
    h.check("Taper registered, with its icon", cmd is not None
            and cmd.getInfo()["pixmap"].endswith("Taper.svg"), cmd and cmd.getInfo())
    toolbar = Gui.getMainWindow().findChild(QtGui.QToolBar, "Deform")
    texts = [a.text() for a in toolbar.actions()] if toolbar else []
    h.check("toolbar and menu: Taper after Twist", texts[:4] == ["Stretch", "Bend", "Twist",
                                                                   "Taper"]
            and (h.menu_texts() or [])[:4] == texts[:4], texts)
    Gui.Selection.clearSelection()
    h.check("Taper inactive with nothing selected", not cmd.isActive())
    Gui.Selection.addSelection(box)
    h.check("Taper active with the solid selected", cmd.isActive())
    cmd.run()
    h.check("Taper panel opens", h.wait(lambda: h.panel_form("Taper") is not None))
    obj = h.of_type(doc, "Taper")[0]
    h.check("Taper defaults: planes at x = 40 and 80, Scale 0.8, valid",
            obj.Plane.Base.isEqual(V(40, 220, 10), 1e-9)
            and obj.Plane2.Base.isEqual(V(80, 220, 10), 1e-9) and obj.Scale == 0.8
            and "Invalid" not in obj.State and obj.Shape.isValid()
            and abs(obj.Shape.Volume - tapered_box_volume(0.8, 0.8)) < 1e-6 * 96000,
            f"{obj.Plane} {obj.Plane2} {obj.Shape.Volume} {obj.getStatusString()}")
    labels = h.panel_texts("Taper")
    wanted = {"Plane", "Plane2 offset", "Scale", "UseScaleXY", "ScaleX", "ScaleY", "UseAxis",
              "Axis", "Profile", "Tolerance", "VolumeChange", "Continuity", "MaxDeviation"}
    h.check("Taper panel labels are the property names", wanted <= labels, sorted(labels))
    h.check("Taper: ScaleX, ScaleY and the Axis fields disabled while unused",
            not h.field("ScaleX", "Taper").isEnabled() and h.field("Scale", "Taper").isEnabled()
            and not h.field("AxisPointX", "Taper").isEnabled())
    h.type_into(h.field("Scale", "Taper"), "0.5")
    h.check("Taper: live preview, volume = closed form (Scale 0.5)",
            h.wait(lambda: obj.Scale == 0.5 and h.settled(obj)) and h.no_error("Taper")
            and abs(obj.Shape.Volume - tapered_box_volume(0.5, 0.5)) < 1e-6 * 96000,
            f"{obj.Shape.Volume} vs {tapered_box_volume(0.5, 0.5)} {obj.getStatusString()}")
    combo = h.field("Profile", "Taper")
    combo.setCurrentIndex(combo.findText("Smooth"))
    h.check("Taper: Profile Smooth previews a valid solid",
            h.wait(lambda: obj.Profile == "Smooth" and h.settled(obj)) and h.no_error("Taper")
            and obj.Shape.isValid(), obj.getStatusString())
    combo.setCurrentIndex(combo.findText("Linear"))
    h.wait(lambda: obj.Profile == "Linear" and h.settled(obj))
    h.field("UseScaleXY", "Taper").click()
    h.type_into(h.field("ScaleY", "Taper"), "1")
    h.type_into(h.field("ScaleX", "Taper"), "0.5")
    h.check("Taper: UseScaleXY scales along X and Y of the frame (closed form)",
            h.wait(lambda: obj.UseScaleXY and obj.ScaleX == 0.5 and obj.ScaleY == 1.0
                   and h.settled(obj)) and h.field("ScaleX", "Taper").isEnabled()
            and not h.field("Scale", "Taper").isEnabled()
            and abs(obj.Shape.Volume - tapered_box_volume(0.5, 1.0)) < 1e-6 * 96000,
            f"{obj.Shape.Volume} vs {tapered_box_volume(0.5, 1.0)} {obj.getStatusString()}")
    grab = f"{h.OUT}/taper_task_panel.png"
    h.panel_form("Taper").grab().save(grab)
    h.results["screenshots"].append(grab)
    h.press("OK")
    objs = h.of_type(doc, "Taper")
    h.check("Taper: one valid solid after OK", len(objs) == 1 and objs[0].Shape.isValid()
            and len(objs[0].Shape.Solids) == 1 and not Gui.Control.activeDialog())
    h.check("Taper: one undo step", doc.UndoCount == undo0 + 1 and doc.UndoNames[0] == "Taper",
            doc.UndoNames)
    h.screenshot("taper_result.png")
    Gui.runCommand("Std_Undo")
    h.process(0.1)
    h.check("Taper: undo removes it", [o.Name for o in doc.Objects] == names0
            and box.ViewObject.Visibility)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    cmd.run()
    h.wait(lambda: h.panel_form("Taper") is not None)
    h.type_into(h.field("Scale", "Taper"), "0.3")
    h.press("Cancel")
    h.check("Taper: Cancel leaves the document unchanged", [o.Name for o in doc.Objects] == names0
            and box.ViewObject.Visibility and doc.UndoCount == undo0
            and App.getActiveTransaction() is None)
    App.closeDocument(doc.Name)
    h.process(0.2)
