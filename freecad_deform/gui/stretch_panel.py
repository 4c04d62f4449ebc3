"""The Stretch task panel: Plane (origin, normal, or picked), Distance, UsePlane2 / Plane2."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

from ..shapes.convert import plane_placement
from . import selection
from .task_panel import (TaskPanelBase, on_value_changed, quantity_spin_box, set_spin_value,
                         spin_value)

Z = App.Vector(0, 0, 1)


def _normal(placement):
    return placement.Rotation.multVec(Z)


class StretchPanel(TaskPanelBase):
    TYPE = "Stretch"
    EDITABLE = ("Plane", "Distance", "UsePlane2", "Plane2")

    # --- fields -------------------------------------------------------------------------------
    def build(self, layout):
        plane_box = QtGui.QGroupBox("Plane")
        plane_box.setToolTip(self.obj.getDocumentationOfProperty("Plane"))
        grid = QtGui.QGridLayout(plane_box)
        self.origin = [quantity_spin_box("mm", name=f"PlaneOrigin{c}") for c in "XYZ"]
        self.normal = []
        for c in "XYZ":
            box = QtGui.QDoubleSpinBox()
            box.setObjectName(f"PlaneNormal{c}")
            box.setRange(-1.0, 1.0)  # any length: the normal is normalized when set
            box.setDecimals(6)
            box.setSingleStep(0.1)
            self.normal.append(box)
        for first_row, title, boxes in ((0, "Origin", self.origin), (3, "Normal", self.normal)):
            grid.addWidget(QtGui.QLabel(title), first_row, 0)
            for i, (c, box) in enumerate(zip("xyz", boxes)):
                grid.addWidget(QtGui.QLabel(c), first_row + i, 1)
                grid.addWidget(box, first_row + i, 2, 1, 2)
        self.pick_button = QtGui.QPushButton("Pick plane")
        self.pick_button.setObjectName("PickPlane")
        self.pick_button.setToolTip("Select a planar face or a datum plane, then press this to "
                                    "take Plane from it. A face on the part's boundary only "
                                    "gives the normal: Plane then goes through the middle of "
                                    "the part.")
        self.flip_button = QtGui.QPushButton("Flip")
        self.flip_button.setObjectName("FlipPlane")
        self.flip_button.setToolTip("Reverse the normal: the part on the other side moves.")
        grid.addWidget(self.pick_button, 6, 0, 1, 3)
        grid.addWidget(self.flip_button, 6, 3)
        grid.setColumnStretch(2, 1)
        layout.addWidget(plane_box)

        form = QtGui.QFormLayout()
        self.distance = quantity_spin_box("mm", name="Distance")
        self.distance.setMinimumWidth(70)
        self.distance.setToolTip(self.obj.getDocumentationOfProperty("Distance"))
        self.distance_binding = Gui.ExpressionBinding(self.distance)
        self.distance_binding.bind(self.obj, "Distance")
        form.addRow("Distance", self.distance)
        self.use_plane2 = QtGui.QCheckBox("UsePlane2")
        self.use_plane2.setObjectName("UsePlane2")
        self.use_plane2.setToolTip(self.obj.getDocumentationOfProperty("UsePlane2"))
        form.addRow(self.use_plane2)
        self.plane2_offset = quantity_spin_box("mm", name="Plane2Offset")
        self.plane2_offset.setMinimumWidth(70)
        self.plane2_offset.setToolTip("Plane2 lies parallel to Plane, this far beyond it "
                                      "along the normal.")
        form.addRow("Plane2 offset", self.plane2_offset)
        layout.addLayout(form)

        result_box = QtGui.QGroupBox("Result")
        form = QtGui.QFormLayout(result_box)
        self.volume_change = QtGui.QLineEdit()
        self.volume_change.setObjectName("VolumeChange")
        self.volume_change.setReadOnly(True)
        self.volume_change.setToolTip(self.obj.getDocumentationOfProperty("VolumeChange"))
        self.continuity = QtGui.QLineEdit()
        self.continuity.setObjectName("Continuity")
        self.continuity.setReadOnly(True)
        self.continuity.setToolTip(self.obj.getDocumentationOfProperty("Continuity"))
        form.addRow("VolumeChange", self.volume_change)
        form.addRow("Continuity", self.continuity)
        layout.addWidget(result_box)

        for box in self.origin:
            on_value_changed(box, self.on_plane_edited)
        for box in self.normal:
            box.valueChanged.connect(self.on_plane_edited)
        self.pick_button.clicked.connect(self.on_pick)
        self.flip_button.clicked.connect(self.on_flip)
        on_value_changed(self.distance, self.on_distance_edited)
        self.use_plane2.toggled.connect(self.on_use_plane2)
        on_value_changed(self.plane2_offset, self.on_plane2_edited)

    def load(self):
        obj = self.obj
        plane = obj.Plane
        for box, value in zip(self.origin, plane.Base):
            set_spin_value(box, value)
        for box, value in zip(self.normal, _normal(plane)):
            box.setValue(value)
        set_spin_value(self.distance, obj.Distance.Value)
        self.use_plane2.setChecked(bool(obj.UsePlane2))
        set_spin_value(self.plane2_offset, self._plane2_offset())
        self.plane2_offset.setEnabled(bool(obj.UsePlane2))

    def _plane2_offset(self):
        """Plane2's distance beyond Plane along the normal; a guess when Plane2 is unset."""
        obj = self.obj
        if obj.UsePlane2:
            return (obj.Plane2.Base - obj.Plane.Base).dot(_normal(obj.Plane))
        try:
            _, hi = selection.extent(obj.Base, obj.Plane)
        except Exception:
            hi = 0.0
        return 0.5 * hi if hi > 0 else 10.0

    def show_results(self):
        obj = self.obj
        self.volume_change.setText(f"{obj.VolumeChange:.6g} mm³")
        self.continuity.setText(obj.Continuity or "-")
        self.continuity.setCursorPosition(0)
        self.continuity.setToolTip("\n".join((obj.Continuity or "-").split("; "))
                                   + "\n\n" + obj.getDocumentationOfProperty("Continuity"))

    def clear_results(self):
        self.volume_change.clear()
        self.continuity.clear()

    # --- handlers -----------------------------------------------------------------------------
    def _field_plane(self):
        origin = App.Vector(*(spin_value(b) for b in self.origin))
        normal = App.Vector(*(b.value() for b in self.normal))
        if normal.Length < 1e-12:
            raise ValueError("Plane normal is zero; give the normal a direction.")
        current = self.obj.Plane
        if normal.normalize().isEqual(_normal(current), 1e-9):
            return App.Placement(origin, current.Rotation)  # keep the in-plane orientation
        return plane_placement((origin, normal))

    def _set_plane(self, plane):
        if self._loading or self.closed:
            return
        try:
            self.obj.Plane = plane
            if self.obj.UsePlane2:
                self._set_plane2()
        except Exception as e:
            self.show_error(str(e))
            return
        self.schedule_recompute()

    def _set_plane2(self):
        plane = self.obj.Plane
        offset = spin_value(self.plane2_offset)
        self.obj.Plane2 = App.Placement(plane.Base + _normal(plane) * offset, plane.Rotation)

    def on_plane_edited(self, *_):
        if self._loading:
            return
        try:
            plane = self._field_plane()
        except Exception as e:
            self.show_error(str(e))
            return
        self._set_plane(plane)

    def on_pick(self):
        picked = selection.picked_plane(Gui.Selection.getSelectionEx())
        if picked is None:
            self.show_error("Select a planar face or a datum plane, then press "
                            "'Pick plane'.")
            return
        try:
            plane = selection.suggested_plane(self.obj.Base, picked)
        except Exception:
            plane = picked
        Gui.Selection.clearSelection()
        self._set_plane(plane)
        self.reload()

    def on_flip(self):
        plane = self.obj.Plane
        self._set_plane(plane_placement((plane.Base, -_normal(plane))))
        self.reload()

    def on_distance_edited(self, *_):
        if self._loading:
            return
        if self.distance_binding.hasExpression():
            self.schedule_recompute()  # the expression drives Distance
            return
        value = spin_value(self.distance)
        if abs(value - self.obj.Distance.Value) > 1e-12:
            self.set_property("Distance", value)

    def on_use_plane2(self, checked):
        if self._loading or self.closed:
            return
        self.plane2_offset.setEnabled(checked)
        try:
            if checked:
                self._set_plane2()
            self.obj.UsePlane2 = bool(checked)
        except Exception as e:
            self.show_error(str(e))
            return
        self.schedule_recompute()

    def on_plane2_edited(self, *_):
        if self._loading or self.closed or not self.obj.UsePlane2:
            return
        try:
            self._set_plane2()
        except Exception as e:
            self.show_error(str(e))
            return
        self.schedule_recompute()
