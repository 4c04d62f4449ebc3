"""The dimension drive part of the GUI scenario (run by freecad_scenario.py inside FreeCAD, on
the harness in harness.py)."""
import os

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

from harness import (OUT, check, click_3d, error_shown, field, no_error, of_type, open_panel,
    panel_form, press, process, results, screenshot, settled, type_into, wait)


def dimension_drive():
    """A block with a hole as a mesh: pick the top and the bottom plane, drive the height
    from 30 to 40 mm, the regions in colour meanwhile; OK, Undo, Cancel."""
    import MeshPart
    import Part
    V = App.Vector
    kind = "DimensionDrive"
    toolbar = Gui.getMainWindow().findChild(QtGui.QToolBar, "Deform")
    texts = [a.text() for a in toolbar.actions()] if toolbar else []
    check("toolbar: Drive dimension", "Drive dimension" in texts, texts)
    cmd = Gui.Command.get("Deform_DimensionDrive")
    check("DimensionDrive: command icon", cmd.getInfo()["pixmap"].endswith("DimensionDrive.svg"),
          cmd.getInfo()["pixmap"])

    doc = App.newDocument("DeformDimensionDriveTest")
    block = Part.makeBox(100, 60, 30).cut(Part.makeCylinder(8, 30, V(50, 30, 0)))
    mesh = doc.addObject("Mesh::Feature", "Block")
    mesh.Mesh = MeshPart.meshFromShape(Shape=block, LinearDeflection=0.1, AngularDeflection=0.5,
                                       Relative=False)
    doc.recompute()
    Gui.ActiveDocument.ActiveView.viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    process(0.2)
    names0, undo0 = [o.Name for o in doc.Objects], doc.UndoCount
    Gui.Selection.clearSelection()
    check("DimensionDrive: inactive with nothing selected", not cmd.isActive())
    Gui.Selection.addSelection(mesh)
    check("DimensionDrive: active with a mesh selected", cmd.isActive())

    Gui.runCommand("Deform_DimensionDrive")
    check("DimensionDrive: panel opens", wait(lambda: panel_form(kind) is not None))
    panel = open_panel("DimensionDrivePanel")
    obj = of_type(doc, kind)[0]
    vobj = obj.ViewObject
    facets = mesh.Mesh.CountFacets
    check("DimensionDrive: Pick is on, empty Regions is a red error",
          panel.observer is not None and field("PickRegions", kind).isChecked()
          and error_shown(kind, "Regions"), field("ErrorLabel", kind).text())
    check("DimensionDrive: regions in colour while open",
          len(obj.RegionColors) == facets == obj.Mesh.CountFacets and vobj.Coloring
          and obj.RegionCount > 1, f"{len(obj.RegionColors)} {facets} {vobj.Coloring}")
    combo = field("Kind", kind)
    combo.setCurrentIndex(combo.findText("Distance"))
    # two clicks on the mesh, through the observer a click reaches
    panel.observer.addSelection(doc.Name, obj.Name, "", (50, 5, 30))
    process(0.1)
    panel.observer.addSelection(doc.Name, obj.Name, "", (50, 5, 0))
    settle = wait(lambda: settled(obj) and len(obj.Regions) == 2)
    regions = list(obj.Regions)
    check("DimensionDrive: picks give the top and bottom planes",
          settle and abs(regions[0].z - 30) < 1e-6 and abs(regions[1].z) < 1e-6
          and panel.observer is None, regions)
    check("DimensionDrive: Target starts at the current value, valid",
          abs(obj.Target.Value - 30) < 1e-6 and abs(obj.Current - 30) < 1e-6
          and no_error(kind) and "Invalid" not in obj.State,
          f"{obj.Target} {obj.Current} {obj.getStatusString()}")
    # a real click on the top re-picks the moving plane
    field("Regions", kind).setCurrentRow(0)
    field("PickRegions", kind).click()
    click_3d(V(20, 20, 30))
    wait(lambda: settled(obj) and not Gui.Selection.getSelection())
    check("DimensionDrive: a click in the 3D view picks a region",
          abs(obj.Regions[0].z - 30) < 1e-6 and (obj.Regions[0] - regions[0]).Length > 1e-3
          and panel.observer is None and "Invalid" not in obj.State,
          f"{list(obj.Regions)} {obj.getStatusString()}")
    type_into(field("Target", kind), "40 mm")
    check("DimensionDrive: live preview (40 mm)",
          wait(lambda: abs(obj.Target.Value - 40) < 1e-9 and settled(obj))
          and abs(obj.Achieved - 40) < 1e-6 and no_error(kind),
          f"{obj.Achieved} {obj.getStatusString()}")
    check("DimensionDrive: Current and Reachable shown",
          field("Current", kind).text().startswith("30") and "to" in field("Reachable", kind).text(),
          (field("Current", kind).text(), field("Reachable", kind).text()))
    check("DimensionDrive: still in colour after the preview",
          vobj.Coloring and len(obj.RegionColors) == obj.Mesh.CountFacets)
    screenshot("dimension_drive.png")
    grab = os.path.join(OUT, "dimension_drive_task_panel.png")
    panel_form(kind).grab().save(grab)
    results["screenshots"].append(grab)

    press("OK")
    objs = of_type(doc, kind)
    check("DimensionDrive: one object after OK", len(objs) == 1 and not Gui.Control.activeDialog())
    result = obj.Mesh
    bb = result.BoundBox
    check("DimensionDrive: valid, Achieved = 40",
          "Invalid" not in obj.State and abs(obj.Achieved - 40) < 1e-6
          and result.CountFacets == facets and result.isSolid()
          and abs(bb.ZLength - 40) < 1e-4 and abs(bb.XLength - 100) < 1e-4,
          f"{obj.State} {obj.Achieved} {bb}")
    check("DimensionDrive: Coloring restored on close", not vobj.Coloring)
    check("DimensionDrive: one undo step", doc.UndoCount == undo0 + 1
          and doc.UndoNames[0] == kind and App.getActiveTransaction() is None, doc.UndoNames)
    Gui.runCommand("Std_Undo")
    process(0.1)
    check("DimensionDrive: undo removes it", [o.Name for o in doc.Objects] == names0
          and mesh.ViewObject.Visibility and doc.UndoCount == undo0, [o.Name for o in doc.Objects])

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(mesh)
    Gui.runCommand("Deform_DimensionDrive")
    wait(lambda: panel_form(kind) is not None)
    panel = open_panel("DimensionDrivePanel")
    panel.observer.addSelection(doc.Name, of_type(doc, kind)[0].Name, "", (50, 5, 30))
    process(0.1)
    press("Cancel")
    check("DimensionDrive: Cancel leaves the document unchanged",
          [o.Name for o in doc.Objects] == names0 and mesh.ViewObject.Visibility
          and doc.UndoCount == undo0 and App.getActiveTransaction() is None)
    App.closeDocument(doc.Name)
    process(0.2)
    matching_drive()


def matching_drive():
    """A block's bore and the shaft in it: a Radius drive on the bore, then the command on
    the drive and the shaft: the shaft's drive follows the bore's Target."""
    import MeshPart
    import Part
    import freecad_deform as fd
    V = App.Vector
    doc = App.newDocument("DeformMatchingTest")

    def mesh(shape, name):
        obj = doc.addObject("Mesh::Feature", name)
        obj.Mesh = MeshPart.meshFromShape(Shape=shape, MaxLength=3.0)
        return obj
    block = mesh(Part.makeBox(100, 60, 30).cut(Part.makeCylinder(8, 30, V(50, 30, 0))), "Block")
    shaft = mesh(Part.makeCylinder(8, 50, V(50, 30, -10)), "Shaft")
    doc.recompute()
    first = fd.make_dimension_drive(block, "Radius", [(58, 30, 15)], 9)
    cmd = Gui.Command.get("Deform_MatchingDrive")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(first)
    check("Drive matching region: inactive with the drive alone", not cmd.isActive())
    Gui.Selection.addSelection(shaft)
    check("Drive matching region: active with a drive and a mesh", cmd.isActive())
    cmd.run()
    process(0.2)
    made = [o for o in of_type(doc, "DimensionDrive") if o is not first]
    first.Target = 9.5
    doc.recompute()
    ok = len(made) == 1 and made[0].Kind == "Radius" and "Invalid" not in made[0].State
    check("Drive matching region: the shaft's drive follows the bore's Target (1e-6)",
          ok and abs(made[0].Achieved - 9.5) < 1e-6 and abs(first.Achieved - 9.5) < 1e-6
          and any(path == "Target" for path, _ in made[0].ExpressionEngine),
          [(o.Name, o.Kind, o.Achieved, o.getStatusString()) for o in made])
    App.closeDocument(doc.Name)
    process(0.2)
