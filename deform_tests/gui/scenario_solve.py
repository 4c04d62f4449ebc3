"""The goal-seek part of the GUI scenario (run by freecad_scenario.py inside FreeCAD): the
Solve command on a box Stretch, its panel's fields, Solve with iterations and residual, OK
as one undo step, Cancel restoring the old value. Oracle: the volume change of a box
stretch is A x d (A = 40 x 20 mm, the box's section written here), so VolumeChange = V
needs Distance = V / A."""
import FreeCAD as App
import FreeCADGui as Gui
import Part

import freecad_deform as fd

V = App.Vector
AREA = 40.0 * 20.0  # the 100 x 40 x 20 box's section across X


def fill(h, vary, lower, upper, output, target):
    h.field("Vary", "Solve").setEditText(vary)
    h.field("Lower", "Solve").setText(lower)
    h.field("Upper", "Solve").setText(upper)
    h.field("Output", "Solve").setEditText(output)
    goal = h.field("Goal", "Solve")
    goal.setCurrentIndex(goal.findText("Target"))
    h.field("Target", "Solve").setText(target)
    h.field("Solve", "Solve").click()
    h.process(0.1)


def solve(h):
    doc = App.newDocument("DeformSolveTest")
    box = doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(100, 40, 20, V(0, 0, 0))
    stretch = fd.make_stretch(box, (V(50, 0, 0), V(1, 0, 0)), 10)
    doc.recompute()
    cmd = Gui.Command.get("Deform_Solve")
    h.check("Solve registered, with its icon", cmd is not None
            and cmd.getInfo()["pixmap"].endswith("Solve.svg"), cmd and cmd.getInfo())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(stretch)
    h.check("Solve active with a Deform object in the document", cmd.isActive())
    undo0 = doc.UndoCount
    cmd.run()
    h.check("Solve panel opens", h.wait(lambda: h.panel_form("Solve") is not None))
    h.check("Solve preset from the selection: Stretch.Distance, Stretch.VolumeChange",
            h.field("Vary", "Solve").currentText() == "Stretch.Distance"
            and h.field("Output", "Solve").currentText() == "Stretch.VolumeChange",
            (h.field("Vary", "Solve").currentText(), h.field("Output", "Solve").currentText()))
    wanted = 23.5
    fill(h, "Stretch.Distance", "0", "100", "Stretch.VolumeChange", repr(AREA * wanted))
    iterations = h.field("Iterations", "Solve").text()
    h.check("Solve: iterations and residual shown, each recompute listed",
            iterations.isdigit() and int(iterations) > 0
            and float(h.field("Residual", "Solve").text()) < 1e-6
            and h.field("Log", "Solve").count() == int(iterations),
            (iterations, h.field("Residual", "Solve").text(), h.field("Log", "Solve").count(),
             h.field("ErrorLabel", "Solve").text()))
    h.check("Solve: Distance = target / A (closed form A x d, 1e-9 mm)",
            abs(stretch.Distance.Value - wanted) < 1e-9 and h.settled(stretch)
            and abs(stretch.VolumeChange - AREA * wanted) < 1e-6 * AREA * wanted,
            f"{stretch.Distance.Value!r} {stretch.VolumeChange!r}")
    grab = f"{h.OUT}/solve_task_panel.png"
    h.panel_form("Solve").grab().save(grab)
    h.results["screenshots"].append(grab)
    h.press("OK")
    h.check("Solve: one undo step", doc.UndoCount == undo0 + 1, (undo0, doc.UndoCount))
    doc.undo()
    doc.recompute()
    h.check("Solve: undo restores Distance 10",
            abs(stretch.Distance.Value - 10) < 1e-12
            and abs(stretch.VolumeChange - AREA * 10) < 1e-6 * AREA * 10,
            f"{stretch.Distance.Value!r} {stretch.VolumeChange!r}")
    doc.redo()
    doc.recompute()
    h.check("Solve: redo applies the value found again",
            abs(stretch.Distance.Value - wanted) < 1e-9, repr(stretch.Distance.Value))
    doc.undo()
    doc.recompute()
    undo1 = doc.UndoCount
    Gui.Selection.clearSelection()
    cmd.run()
    h.wait(lambda: h.panel_form("Solve") is not None)
    fill(h, "Stretch.Distance", "-500", "100", "Stretch.VolumeChange", repr(AREA * 30.0))
    message = h.field("ErrorLabel", "Solve").text()
    h.check("Solve: bounds where the model fails: the panel names the property to narrow",
            "narrow the bounds of Stretch.Distance" in message, message)
    fill(h, "Stretch.Distance", "0", "100", "Stretch.VolumeChange", repr(AREA * 30.0))
    solved = abs(stretch.Distance.Value - 30.0) < 1e-9
    h.press("Cancel")
    h.check("Solve: Cancel leaves the document unchanged",
            solved and abs(stretch.Distance.Value - 10) < 1e-12 and doc.UndoCount == undo1
            and abs(stretch.VolumeChange - AREA * 10) < 1e-6 * AREA * 10,
            f"{solved} {stretch.Distance.Value!r} {doc.UndoCount} vs {undo1}")
    App.closeDocument(doc.Name)
