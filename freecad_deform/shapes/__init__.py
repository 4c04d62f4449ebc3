"""The only layer that converts FreeCAD objects to arrays and back, and calls OCCT through Part."""
