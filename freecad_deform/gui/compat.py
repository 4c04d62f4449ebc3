"""The few GUI calls whose Python form differs between FreeCAD 0.20 (Qt5, pivy 0.6.8), 1.0 and
1.1 (Qt6, PySide6, Python 3.14, pivy built with a newer SWIG); the rest of the GUI calls these
instead of testing a version.

pivy's Sb vectors: getValue() gives a tuple up to FreeCAD 1.0 but an opaque SwigPyObject in
1.1 ("cannot unpack non-iterable SwigPyObject"); indexing gives the numbers in all of them.
"""


def sb_values(vector):
    """The components of a pivy SbVec2s/SbVec2f/SbVec3f as a tuple of numbers."""
    return tuple(vector[i] for i in range(len(vector)))


def event_position(event):
    """(x, y) of a Coin mouse event: pixels of the view from its bottom left."""
    x, y = sb_values(event.getPosition())
    return x, y
