# Deform workbench, application side (also loaded by FreeCADCmd): register the unit tests.
import FreeCAD

FreeCAD.__unit_test__ += ["TestDeformApp"]
