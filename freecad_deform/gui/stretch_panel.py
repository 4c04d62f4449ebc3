"""The Stretch task panel: Plane (origin, normal, or picked), Distance, UsePlane2 / Plane2."""
from PySide import QtGui

from .planes_panel import PlanesPanel


class StretchPanel(PlanesPanel):
    TYPE = "Stretch"
    EDITABLE = ("Plane", "Distance", "UsePlane2", "Plane2")
    HANDLES = ("Plane", "Distance")

    def build(self, layout):
        self.add_plane(layout)
        form = QtGui.QFormLayout()
        self.distance = self.add_quantity(form, "Distance", "mm")
        self.distance_binding = self.quantities["Distance"][1]
        self.add_use_plane2(form)
        self.add_plane2_offset(form)
        layout.addLayout(form)
        self.add_results(layout)
