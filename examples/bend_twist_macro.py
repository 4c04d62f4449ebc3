# Bend a STEP part and twist a box: paste into FreeCAD's Python console (or run: freecadcmd bend_twist_macro.py).
import FreeCAD as App
import Part
import freecad_deform as fd

doc = App.newDocument("BendTwistExample")
part = doc.addObject("Part::Feature", "Part")
part.Shape = Part.read("face_recognition_sample_part.stp")   # the path to your STEP file
plane = (App.Vector(150, 0, 0), App.Vector(1, 0, 0))         # a point, and the normal toward the side that turns
axis = (App.Vector(150, 0, 260), App.Vector(0, 1, 0))        # a point on the axis and its direction: in the plane, outside the part
bend = fd.make_bend(part, plane, -60, axis)                  # degrees, right-hand rule about the axis; already recomputed
print("Bend  VolumeChange:", bend.VolumeChange, "mm^3")      # = section area x centroid radius x angle (Pappus)
print("Bend  Continuity:", bend.Continuity)                  # an Angle of the wrong sign puts the object in error:
                                                             # bend.getStatusString() names the property to change
box = doc.addObject("Part::Feature", "Box")
box.Shape = Part.makeBox(60, 20, 150)
bottom = (App.Vector(0, 0, 40), App.Vector(0, 0, 1))         # the region between the two planes twists,
top = (App.Vector(0, 0, 110), App.Vector(0, 0, 1))           # the part above the second one turns rigidly
twist = fd.make_twist(box, bottom, top, 90)                  # about the normal through the section's centroid
print("Twist VolumeChange:", twist.VolumeChange, "mm^3")     # about 0: the length and the sections are kept
print("Twist Continuity:", twist.Continuity)
twist.Angle = "45 deg"                                       # a number, a quantity or, with setExpression, a formula
doc.recompute()
print("Twist VolumeChange at 45 deg:", twist.VolumeChange, "mm^3")
