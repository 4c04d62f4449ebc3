"""The Twist task panel: Plane, Plane2 offset, Angle (whole turns included), UseAxis / Axis,
Samples, Profile, Tolerance, and the results."""
from PySide import QtGui

from . import selection
from .split_sweep_panel import SplitSweepPanel
from .task_panel import set_spin_value, spin_value


class TwistPanel(SplitSweepPanel):
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
        self.use_axis = QtGui.QCheckBox("UseAxis")
        self.use_axis.setObjectName("UseAxis")
        self.use_axis.setToolTip(self.obj.getDocumentationOfProperty("UseAxis"))
        self.use_axis.toggled.connect(self.on_use_axis)
        form.addRow(self.use_axis)
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
        self.use_axis.setChecked(bool(self.obj.UseAxis))
        self.axis.set_fields_enabled(bool(self.obj.UseAxis))  # Pick axis also turns it on

    def on_use_axis(self, checked):
        if self._loading or self.closed:
            return
        obj = self.obj
        self.axis.set_fields_enabled(checked)
        try:
            if checked and obj.Axis.isIdentity():
                # never set: start from the axis the twist used so far
                obj.Axis = selection.default_twist_axis(obj.Base, obj.Plane)
            obj.UseAxis = bool(checked)
        except Exception as e:
            self.show_error(str(e))
            return
        self.reload()
        self.schedule_recompute()

    def picked_axis(self, line):
        """Picking a line also switches UseAxis on: the twist turns about it."""
        axis = super().picked_axis(line)
        self.obj.UseAxis = True
        return axis

    def set_angle_dragged(self, degrees):
        self.set_total_angle(degrees)

    def set_total_angle(self, total):
        """Angle + 360 deg x Turns = total (whole turns to Turns)."""
        turns = int(total / 360.0)
        try:
            self.obj.Turns = turns
            self.obj.Angle = total - 360.0 * turns
        except Exception as e:
            self.show_error(str(e))
            return
        self.schedule_recompute()

    def quantity_edited(self, prop, box, binding):
        """The Angle field holds the whole twist: its whole turns go to Turns (an angle
        property holds at most 360 deg, and would clamp 720 to it silently)."""
        obj = self.obj
        if prop != "Angle" or binding.hasExpression():
            return super().quantity_edited(prop, box, binding)
        total = spin_value(box)
        if abs(total - (obj.Angle.Value + 360.0 * obj.Turns)) > 1e-12:
            self.set_total_angle(total)
