"""The Taper task panel: Plane, Plane2 offset, Scale (or UseScaleXY with ScaleX and ScaleY),
UseAxis / Axis, Profile, Tolerance, and the results."""
from PySide import QtGui

from .planes_panel import PlanesPanel


class TaperPanel(PlanesPanel):
    TYPE = "Taper"
    EDITABLE = ("Plane", "Plane2", "Scale", "UseScaleXY", "ScaleX", "ScaleY", "UseAxis", "Axis",
                "Profile", "Tolerance")
    HANDLES = ("Plane", "Plane2", "Scale")
    PLANE2 = "always"

    def build(self, layout):
        self.add_plane(layout)
        form = QtGui.QFormLayout()
        self.add_plane2_offset(form)
        self.add_quantity(form, "Scale", "", 1e-6, 1e6)
        self.add_check(form, "UseScaleXY", self.on_scale_xy)
        self.add_quantity(form, "ScaleX", "", 1e-6, 1e6)
        self.add_quantity(form, "ScaleY", "", 1e-6, 1e6)
        self.add_use_axis(form)
        layout.addLayout(form)
        self.add_axis(layout)
        form = QtGui.QFormLayout()
        self.add_flex(form)
        layout.addLayout(form)
        self.add_results(layout)

    def load(self):
        super().load()
        self.on_scale_xy(bool(self.obj.UseScaleXY))

    def on_scale_xy(self, checked):
        """Scale, or ScaleX and ScaleY: only the fields in use are enabled."""
        self.quantities["Scale"][0].setEnabled(not checked)
        for prop in ("ScaleX", "ScaleY"):
            self.quantities[prop][0].setEnabled(checked)
