# Stretch a STEP part: paste into FreeCAD's Python console (or run: freecadcmd stretch_macro.py).
import FreeCAD as App
import Part
import freecad_deform as fd

doc = App.newDocument("StretchExample")
part = doc.addObject("Part::Feature", "Part")
part.Shape = Part.read("face_recognition_sample_part.stp")   # the path to your STEP file
plane = (App.Vector(150, 0, 0), App.Vector(1, 0, 0))         # a point, and the normal toward the side that moves
stretch = fd.make_stretch(part, plane, 40)                   # 40 mm along +X, already recomputed
print("VolumeChange:", stretch.VolumeChange, "mm^3")
print("Continuity:", stretch.Continuity)
stretch.Distance = "25 mm"                                   # a number, a quantity or, with setExpression, a formula
doc.recompute()
print("VolumeChange:", stretch.VolumeChange, "mm^3, length:", stretch.Shape.BoundBox.XLength, "mm")
