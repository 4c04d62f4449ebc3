"""The area constrain part of the GUI scenario (run by freecad_scenario.py inside FreeCAD, on
the harness in harness.py)."""
import os

import FreeCAD as App
import FreeCADGui as Gui

from harness import (OUT, check, check_gate, click_3d, error_shown, field, no_error, of_type,
    open_panel, panel_form, press, process, results, screenshot, settled,
    show_all, type_into, wait)


def net_nodes(view):
    """The control-net nodes the AreaConstrain panel put into the view's scene graph."""
    root = view.getSceneGraph()
    return [root.getChild(i) for i in range(root.getNumChildren())
            if root.getChild(i).getName() == "DeformControlNet"]


def canopy_surface():
    """A 6 x 6 bicubic B-spline canopy over 100 x 60 mm, 25 mm high, slightly tilted."""
    import numpy as np
    import Part
    n = 6
    xs, ys = np.linspace(0, 100, n), np.linspace(0, 60, n)
    poles = [[App.Vector(x, y, 25 * np.sin(np.pi * x / 100) * np.sin(np.pi * y / 60) + 0.1 * x)
              for y in ys] for x in xs]
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots(poles, [4, 1, 1, 4], [4, 1, 1, 4], [0, 1 / 3, 2 / 3, 1],
                                     [0, 1 / 3, 2 / 3, 1], False, False, 3, 3)
    return surface


def gauss_area(surface, order=20):
    """Area of a B-spline surface: Gauss-Legendre on every knot span, |Su x Sv| from OCCT's
    derivatives (Face.Area's default precision is only about 1e-4 relative)."""
    import numpy as np
    nodes, weights = np.polynomial.legendre.leggauss(order)
    total = 0.0
    uk, vk = surface.getUKnots(), surface.getVKnots()
    for u0, u1 in zip(uk[:-1], uk[1:]):
        for v0, v1 in zip(vk[:-1], vk[1:]):
            for a, wa in zip(nodes, weights):
                u = 0.5 * (u0 + u1 + (u1 - u0) * a)
                for b, wb in zip(nodes, weights):
                    v = 0.5 * (v0 + v1 + (v1 - v0) * b)
                    normal = surface.getDN(u, v, 1, 0).cross(surface.getDN(u, v, 0, 1))
                    total += 0.25 * (u1 - u0) * (v1 - v0) * wa * wb * normal.Length
    return total


def area_constrain():
    """The canopy's Face1 selected, the command, a pole picked by a click on the control net,
    All interior, the target 105 %; OK, Undo, Cancel."""
    kind = "AreaConstrain"
    cmd = Gui.Command.get("Deform_AreaConstrain")
    check("AreaConstrain: command icon", cmd is not None
          and cmd.getInfo()["pixmap"].endswith("AreaConstrain.svg"),
          cmd.getInfo()["pixmap"] if cmd else None)
    doc = App.newDocument("DeformAreaConstrainTest")
    canopy = doc.addObject("Part::Feature", "Canopy")
    surface = canopy_surface()
    canopy.Shape = surface.toShape()
    doc.recompute()
    view = show_all()
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    check_gate(cmd, "AreaConstrain", canopy, "Face1", "a face")

    Gui.runCommand("Deform_AreaConstrain")
    check("AreaConstrain: panel opens", wait(lambda: panel_form(kind) is not None))
    panel = open_panel("AreaConstrainPanel")
    obj = of_type(doc, kind)[0]
    check("AreaConstrain: starts at 100 %, valid, no change",
          obj.TargetRatio == 1.0 and "Invalid" not in obj.State and no_error(kind)
          and obj.AchievedArea == obj.OriginalArea and obj.MaxPoleMove == 0.0,
          f"{obj.TargetRatio} {obj.OriginalArea} {obj.AchievedArea} {obj.getStatusString()}")
    check("AreaConstrain: control net drawn while open",
          len(net_nodes(view)) == 1 and panel.net is not None, len(net_nodes(view)))
    vbase = canopy.ViewObject
    check("AreaConstrain: Base shown semi-transparent under the result",
          vbase.Visibility and vbase.Transparency > 0 and obj.ViewObject.Visibility,
          f"{vbase.Visibility} {vbase.Transparency}")
    check("AreaConstrain: TargetArea is a bound Gui::QuantitySpinBox in mm^2",
          field("TargetArea", kind).metaObject().className() == "Gui::QuantitySpinBox"
          and Gui.ExpressionBinding(field("TargetArea", kind)).isBound()
          and abs(field("TargetArea", kind).property("rawValue") - obj.OriginalArea) < 1e-6,
          field("TargetArea", kind).property("rawValue"))

    # a click at pole (2, 3) on the screen, through the 3D view's mouse callback
    field("PickPoles", kind).click()
    check("AreaConstrain: Pick poles on", panel.callback is not None
          and field("PickPoles", kind).isChecked())
    pole = surface.getPole(2, 3)
    x, y = view.getPointOnScreen(pole)
    click_3d(pole)
    wait(lambda: settled(obj) and list(obj.Poles))
    check("AreaConstrain: a click on pole (2, 3) picks it", list(obj.Poles) == ["2,3"]
          and field("Poles", kind).item(0).text() == "2,3", f"{list(obj.Poles)} at {x}, {y}")
    check("AreaConstrain: the click does not select the surface", not Gui.Selection.getSelection(),
          [o.Name for o in Gui.Selection.getSelection()])
    x2, y2 = view.getPointOnScreen(pole)  # the view may have changed size meanwhile
    panel.click(x2, y2)  # the same handler: the second click removes it again
    check("AreaConstrain: a second click removes it", list(obj.Poles) == [],
          f"{list(obj.Poles)} at {x2}, {y2} (first at {x}, {y})")
    x, y = x2, y2
    panel.click(x, y)  # and back: All interior below clears a list
    field("PickPoles", kind).click()
    check("AreaConstrain: Pick poles off", panel.callback is None)
    field("AllInterior", kind).click()
    check("AreaConstrain: All interior clears Poles", list(obj.Poles) == []
          and field("Poles", kind).item(0).text() == "All interior poles", list(obj.Poles))

    combo = field("Dof", kind)
    combo.setCurrentIndex(combo.findText("Normal"))
    field("ByRatio", kind).click()
    field("TargetPercent", kind).setValue(105.0)
    done = wait(lambda: abs(obj.TargetRatio - 1.05) < 1e-12 and settled(obj))
    check("AreaConstrain: live preview at 105 %", done and no_error(kind)
          and abs(obj.AchievedArea / obj.OriginalArea - 1.05) < 1e-9,
          f"{obj.TargetRatio} {obj.AchievedArea} {obj.getStatusString()}")
    check("AreaConstrain: results shown",
          field("AchievedArea", kind).text().startswith(f"{obj.AchievedArea:.10g}")
          and field("Iterations", kind).text() == str(obj.Iterations)
          # the greyed TargetArea follows at display precision (the spin box re-reads its text)
          and abs(field("TargetArea", kind).property("rawValue") - obj.AchievedArea) < 1.0
          and not field("TargetArea", kind).isEnabled(),
          (field("AchievedArea", kind).text(), field("Iterations", kind).text(),
           field("TargetArea", kind).property("rawValue"), field("TargetArea", kind).isEnabled()))
    screenshot("area_constrain.png")
    check("AreaConstrain: net still drawn for the screenshot", len(net_nodes(view)) == 1)
    grab = os.path.join(OUT, "area_constrain_task_panel.png")
    panel_form(kind).grab().save(grab)
    results["screenshots"].append(grab)

    press("OK")
    objs = of_type(doc, kind)
    check("AreaConstrain: one object after OK", len(objs) == 1 and not Gui.Control.activeDialog())
    check("AreaConstrain: AchievedArea / OriginalArea = 1.05",
          "Invalid" not in obj.State and abs(obj.AchievedArea / obj.OriginalArea - 1.05) < 1e-9
          and list(obj.Poles) == [] and obj.Dof == "Normal",
          f"{obj.AchievedArea / obj.OriginalArea!r} {obj.getStatusString()}")
    area = gauss_area(obj.Shape.Faces[0].Surface)
    check("AreaConstrain: the result's area (independent quadrature) = AchievedArea",
          abs(area - obj.AchievedArea) < 1e-9 * area, f"{area!r} {obj.AchievedArea!r}")
    check("AreaConstrain: net gone after OK", not net_nodes(view) and panel.net is None)
    check("AreaConstrain: Base hidden, its transparency back",
          not vbase.Visibility and vbase.Transparency == 0 and obj.ViewObject.Visibility,
          f"{vbase.Visibility} {vbase.Transparency}")
    check("AreaConstrain: one undo step", doc.UndoCount == undo0 + 1
          and doc.UndoNames[0] == kind and App.getActiveTransaction() is None, doc.UndoNames)
    obj.ViewObject.doubleClicked()
    check("AreaConstrain: double-click edits, net drawn", wait(lambda: panel_form(kind) is not None)
          and len(net_nodes(view)) == 1 and field("ByRatio", kind).isChecked()
          and vbase.Visibility, len(net_nodes(view)))
    field("TargetPercent", kind).setValue(110.0)
    wait(lambda: abs(obj.TargetRatio - 1.1) < 1e-12 and settled(obj))
    press("Cancel")
    check("AreaConstrain: edit Cancel restores TargetRatio, the Base's look, no net",
          abs(obj.AchievedArea / obj.OriginalArea - 1.05) < 1e-9 and obj.TargetRatio == 1.05
          and not vbase.Visibility and vbase.Transparency == 0 and not net_nodes(view)
          and doc.UndoCount == undo0 + 1, f"{obj.TargetRatio} {vbase.Visibility} {doc.UndoNames}")
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("AreaConstrain: undo removes it", [o.Name for o in doc.Objects] == names0
          and vbase.Visibility and doc.UndoCount == undo0, [o.Name for o in doc.Objects])

    # an area with units, then Cancel
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(doc.Name, canopy.Name, "Face1")
    Gui.runCommand("Deform_AreaConstrain")
    wait(lambda: panel_form(kind) is not None)
    obj = of_type(doc, kind)[0]
    field("ByArea", kind).click()
    type_into(field("TargetArea", kind), "0.75 dm^2")
    done = wait(lambda: abs(obj.TargetArea.Value - 7500) < 1e-9 and settled(obj))
    check("AreaConstrain: TargetArea with units previews", done and obj.TargetRatio == 0
          and abs(obj.AchievedArea - 7500) < 1e-6 and no_error(kind),
          f"{obj.TargetArea} {obj.AchievedArea} {obj.getStatusString()}")
    type_into(field("TargetArea", kind), "1000 mm^2")
    check("AreaConstrain: an unreachable area is a red error naming TargetArea",
          wait(lambda: error_shown(kind, "TargetArea")), field("ErrorLabel", kind).text())
    press("Cancel")
    check("AreaConstrain: Cancel leaves the document unchanged",
          [o.Name for o in doc.Objects] == names0 and vbase.Visibility
          and vbase.Transparency == 0 and not net_nodes(view)
          and doc.UndoCount == undo0 and App.getActiveTransaction() is None,
          f"{[o.Name for o in doc.Objects]} {vbase.Visibility} {vbase.Transparency}")
    App.closeDocument(doc.Name)
    process(0.2)
