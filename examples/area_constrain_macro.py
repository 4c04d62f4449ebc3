# Give a canopy exactly the area asked for: paste into FreeCAD's Python console (or run: freecadcmd area_constrain_macro.py).
import FreeCAD as App
import Part
import freecad_deform as fd

doc = App.newDocument("AreaConstrainExample")
n, size = 6, (100.0, 60.0)                                   # a 6 x 6-pole bicubic canopy, 100 x 60 mm
poles = [[App.Vector(size[0] * i / (n - 1), size[1] * j / (n - 1),
                     20.0 * (i * (n - 1 - i) * j * (n - 1 - j)) / 36.0) for j in range(n)] for i in range(n)]
surface = Part.BSplineSurface()
surface.buildFromPolesMultsKnots(poles, [4, 1, 1, 4], [4, 1, 1, 4], [0, 1 / 3, 2 / 3, 1], [0, 1 / 3, 2 / 3, 1],
                                 False, False, 3, 3)
canopy = doc.addObject("Part::Feature", "Canopy")
canopy.Shape = Part.Face(surface)
bigger = fd.make_area_constrain(canopy, "Face1", "105%")     # every interior pole, along its control-net normal
print("+5 %:", bigger.OriginalArea, "->", bigger.AchievedArea, "mm^2 in", bigger.Iterations, "iterations;",
      "largest pole move", round(bigger.MaxPoleMove, 3), "mm")
one = fd.make_area_constrain(canopy, "Face1", "102.5%", poles=[(3, 3)], dof="Z")   # the paper's first case
print("one pole in z:", one.AchievedArea / one.OriginalArea)
one.TargetRatio = 0.5                                        # out of reach for one pole: the object is in error
doc.recompute()                                              # and says how small the area can get
print(one.getStatusString())
