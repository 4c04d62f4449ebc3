"""The Twist task panel: Plane, Plane2 offset, Angle (whole turns included), UseAxis / Axis,
Samples, Profile, Tolerance, and the results."""
from PySide import QtGui

from .bindings import set_spin_value, spin_value
from .planes_panel import PlanesPanel


class TwistPanel(PlanesPanel):
    TYPE = "Twist"
    EDITABLE = ("Plane", "Plane2", "Angle", "Turns", "UseAxis", "Axis", "Samples", "Profile",
                "Tolerance")
    HANDLES = ("Plane", "Plane2", "Angle")
    PLANE2 = "always"

    def build(self, layout):
        self.add_plane(layout)
        form = QtGui.QFormLayout()
        self.add_plane2_offset(form)
        self.angle = self.add_quantity(form, "Angle", "deg", -1e6, 1e6)
        self.add_use_axis(form)
        layout.addLayout(form)
        self.add_axis(layout)
        form = QtGui.QFormLayout()
        self.add_samples(form, minimum=2)
        self.add_flex(form)
        layout.addLayout(form)
        self.add_results(layout)

    def load(self):
        super().load()
        set_spin_value(self.angle, self.obj.Angle.Value + 360.0 * self.obj.Turns)

    def set_angle_dragged(self, degrees):
        self.set_total_angle(degrees)

    def set_total_angle(self, total):
        """Angle + 360 deg x Turns = total (whole turns to Turns)."""
        turns = int(total / 360.0)

        def change():
            self.obj.Turns = turns
            self.obj.Angle = total - 360.0 * turns
        self.apply(change)

    def quantity_edited(self, prop, box, binding):
        """The Angle field holds the whole twist: its whole turns go to Turns (an angle
        property holds at most 360 deg, and would clamp 720 to it silently)."""
        obj = self.obj
        if prop != "Angle" or binding.hasExpression():
            return super().quantity_edited(prop, box, binding)
        total = spin_value(box)
        if abs(total - (obj.Angle.Value + 360.0 * obj.Turns)) > 1e-12:
            self.set_total_angle(total)
