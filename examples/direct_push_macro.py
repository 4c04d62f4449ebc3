# Push a curve and the top of a box directly: paste into FreeCAD's Python console (or run: freecadcmd direct_push_macro.py).
import math

import FreeCAD as App
import Part
import freecad_deform as fd

V = App.Vector
doc = App.newDocument("DirectPushExample")
curve = Part.BSplineCurve()
curve.interpolate([V(x, 10 * math.sin(x / 15.0), 0) for x in range(0, 71, 10)])
wire = doc.addObject("Part::Feature", "Curve")
wire.Shape = curve.toShape()
grab = curve.value(0.4 * curve.LastParameter)                # any point of the curve
keep = curve.value(0.55 * curve.LastParameter)               # a point that must not move
pushed = fd.make_direct_push(wire, "Edge1", grab, grab + V(0, 0, 6), fixed=[keep])
print("landed within", pushed.Shape.distToShape(Part.Vertex(grab + V(0, 0, 6)))[0], "mm;",
      "fixed point off the curve by", pushed.Shape.distToShape(Part.Vertex(keep))[0], "mm")
second = curve.value(0.2 * curve.LastParameter)              # pushes stay a list: add, edit or remove
pushed.Points = list(pushed.Points) + [second]
pushed.Targets = list(pushed.Targets) + [second + V(0, -4, 0)]
doc.recompute()
box = doc.addObject("Part::Feature", "Box")
box.Shape = Part.makeBox(20, 20, 10)
bulge = fd.make_direct_push(box, "Face6", V(10, 10, 10), V(10, 10, 14))   # Face6: the top
print("box:", bulge.Shape.isValid(), len(bulge.Shape.Solids), "solid, volume",
      round(box.Shape.Volume, 3), "->", round(bulge.Shape.Volume, 3), "|", bulge.Conversion)
