# Drive dimensions of a mesh: paste into FreeCAD's Python console (or run: freecadcmd dimension_drive_macro.py).
import FreeCAD as App
import MeshPart
import Part
import freecad_deform as fd

doc = App.newDocument("DimensionDriveExample")
block = Part.makeBox(100, 60, 30).cut(Part.makeCylinder(8, 30, App.Vector(50, 30, 0)))
mesh = doc.addObject("Mesh::Feature", "Mesh")                 # a CAE mesh without its CAD model
mesh.Mesh = MeshPart.meshFromShape(Shape=block, MaxLength=3.0)
top, bottom, hole = (50, 5, 30), (50, 5, 0), (58, 30, 15)     # points on the regions; each picks the nearest one
thick = fd.make_dimension_drive(mesh, "Distance", [top, bottom], 40)   # the top moves, the bottom is the reference
print("Distance:", thick.Current, "->", thick.Achieved, "mm; reachable", thick.Reachable)
wide = fd.make_dimension_drive(thick, "Radius", [hole], 10)  # chained: the hole of the thicker block
print("Radius:", wide.Current, "->", wide.Achieved, "mm; reachable", wide.Reachable)
moved = fd.make_dimension_drive(mesh, "Position", [top, hole], (40, 25),   # (u, v) in the frame below
                                origin=(0, 0, 30), axis_point=(100, 0, 30))
print("Position:", (moved.Current, moved.CurrentV), "->", (moved.Achieved, moved.AchievedV))
wide.Target = 40                                              # beyond Reachable: the object is in error,
doc.recompute()                                               # the meshes before it are untouched
print(wide.getStatusString())
wide.setExpression("Target", "12 mm")                         # units and expressions work on every length
doc.recompute()
print("Radius with an expression:", wide.Achieved, "mm")
