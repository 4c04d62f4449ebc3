"""PlanesPanel: what the Stretch, Bend, Twist and Taper task panels share (Wu & Ilies's split,
sweep, join): the Plane group, the Plane2 offset, the Axis group, fields bound to their
properties (bindings.py), Samples, and the results. Each panel's build() lays out its own
selection of these pieces, in the order of its properties.
"""
import FreeCAD as App
import FreeCADGui as Gui

from ..geometry.errors import DeformError
from ..shapes.convert import plane_placement
from . import selection
from .bindings import (check_box, combo_box, int_spin_box, on_value_changed, quantity_spin_box,
                       set_spin_value, show_combo, spin_value)
from .handles import PanelHandles
from .task_panel import TaskPanelBase
from .widgets import PlacementGroup, direction_of, results_box, show_texts


class PlanesPanel(TaskPanelBase):
    """Subclasses set TYPE, EDITABLE and PLANE2 and write build(layout) from add_plane,
    add_quantity, add_check, add_choice, add_use_plane2, add_plane2_offset, add_axis,
    add_samples, add_flex, add_results."""

    PLANE2 = "optional"   # "optional": UsePlane2 switches Plane2 on; "always": Twist
    HANDLES = ()          # the 3D-view handles (gui.handles): Plane, Plane2, Distance, ...

    def __init__(self, *args, **kwargs):
        self.checks, self.choices = {}, {}  # property -> QCheckBox / QComboBox
        self.plane = self.axis = self.results = self.handles = None
        self.use_plane2 = self.plane2_offset = self.samples = None
        super().__init__(*args, **kwargs)
        if self.HANDLES:
            try:
                self.handles = PanelHandles(self, self.HANDLES)
            except ImportError as e:  # a FreeCAD without pivy: the panel works without them
                if e.name != "pivy":
                    raise
                App.Console.PrintWarning(f"{self.TYPE}: no handles in the 3D view ({e})\n")

    # --- the 3D-view handles --------------------------------------------------------------
    def update_status(self):
        super().update_status()
        if self.handles is not None and not self.handles.dragging:
            self.handles.place()   # where the (maybe typed) values put them now

    def set_plane_dragged(self, plane):
        self._set_plane(plane)

    def set_angle_dragged(self, degrees):
        self.set_property("Angle", degrees)

    def _close(self):
        if self.handles is not None:
            self.handles.remove()
        super()._close()

    # --- building blocks ------------------------------------------------------------------------
    def add_plane(self, layout):
        self.plane = PlacementGroup(
            "Plane", "Origin", "Normal", self.obj.getDocumentationOfProperty("Plane"),
            "Pick plane",
            "Select a planar face or a datum plane, then press this to take Plane from it. "
            "A face on the part's boundary only gives the normal: Plane then goes through "
            "the middle of the part.",
            "Reverse the normal: the part on the other side moves. With Plane2 the same "
            "region deforms and the part beyond its other end moves.")
        self.plane.connect(self.on_plane_edited, self.on_pick_plane, self.on_flip_plane)
        layout.addWidget(self.plane.box)

    def add_axis(self, layout):
        self.axis = PlacementGroup(
            "Axis", "Point", "Direction", self.obj.getDocumentationOfProperty("Axis"),
            "Pick axis",
            "Select a straight edge or a datum line, then press this to take Axis from it "
            "(through the point of the line nearest to Plane's origin).",
            "Reverse the direction: the same Angle turns the other way.")
        self.axis.connect(self.on_axis_edited, self.on_pick_axis, self.on_flip_axis)
        layout.addWidget(self.axis.box)

    def add_check(self, form, prop, toggled=None):
        """A check box named `prop`, bound to the bool property; `toggled(checked)` runs
        after the property is set (before the preview)."""
        box = check_box(self.obj, prop)
        box.toggled.connect(lambda checked: self.on_check(prop, checked, toggled))
        self.checks[prop] = box
        form.addRow(box)
        return box

    def add_use_axis(self, form):
        """UseAxis (Twist, Taper): switched on with Axis never set, Axis starts from the
        default axis (the Plane normal through the section's centroid), the result the
        same; the Axis fields are enabled with it. Add the Axis group too."""
        self.add_check(form, "UseAxis", self.on_use_axis)

    def on_use_axis(self, checked):
        self.axis.set_fields_enabled(checked)
        if checked and self.obj.Axis.isIdentity():
            self.obj.Axis = selection.default_twist_axis(self.obj.Base, self.obj.Plane)
            self.reload()

    def add_choice(self, form, prop):
        """A combo box named `prop` with the enumeration property's values."""
        combo = combo_box(self.obj, prop)
        combo.currentIndexChanged.connect(lambda _: self.on_choice(prop, combo.currentText()))
        self.choices[prop] = combo
        form.addRow(prop, combo)
        return combo

    def add_flex(self, form):
        """Profile and Tolerance: how the space map grows and how close its fits stay."""
        self.add_choice(form, "Profile")
        self.add_quantity(form, "Tolerance", "mm", 1e-9, 1e6)

    def add_use_plane2(self, form):
        self.use_plane2 = check_box(self.obj, "UsePlane2")
        self.use_plane2.toggled.connect(self.on_use_plane2)
        form.addRow(self.use_plane2)

    def add_plane2_offset(self, form):
        self.plane2_offset = quantity_spin_box("mm", name="Plane2Offset")
        self.plane2_offset.setMinimumWidth(70)
        self.plane2_offset.setToolTip("Plane2 lies parallel to Plane, this far beyond it "
                                      "along the normal.\n\n"
                                      + self.obj.getDocumentationOfProperty("Plane2"))
        on_value_changed(self.plane2_offset, self.on_plane2_edited)
        form.addRow("Plane2 offset", self.plane2_offset)

    def add_samples(self, form, minimum=1):
        self.samples = int_spin_box(self.obj, "Samples", minimum, 1000)
        self.samples.valueChanged.connect(self.on_samples_edited)
        form.addRow("Samples", self.samples)

    def add_results(self, layout):
        """VolumeChange, Continuity, and MaxDeviation where the feature has it."""
        names = ["VolumeChange", "Continuity"]
        if "MaxDeviation" in self.obj.PropertiesList:  # the features with a space map
            names.append("MaxDeviation")
        box, self.results = results_box(self.obj, names)
        layout.addWidget(box)

    # --- showing values ---------------------------------------------------------------------------
    def load(self):
        obj = self.obj
        if self.plane is not None:
            self.plane.show(obj.Plane)
        if self.axis is not None:
            self.axis.show(obj.Axis)
        self.load_quantities()
        for prop, box in self.checks.items():
            box.setChecked(bool(getattr(obj, prop)))
        for prop, combo in self.choices.items():
            show_combo(combo, getattr(obj, prop))
        if "UseAxis" in self.checks:   # Pick axis also turns it on
            self.axis.set_fields_enabled(bool(obj.UseAxis))
        if self.use_plane2 is not None:
            self.use_plane2.setChecked(bool(obj.UsePlane2))
        if self.plane2_offset is not None:
            set_spin_value(self.plane2_offset, self._plane2_offset())
            self.plane2_offset.setEnabled(self.uses_plane2())
        if self.samples is not None:
            self.samples.setValue(int(obj.Samples))

    def show_results(self):
        if self.results is None:
            return
        obj, lines = self.obj, self.results
        continuity = obj.Continuity or "-"
        texts = {"VolumeChange": f"{obj.VolumeChange:.6g} mm³", "Continuity": continuity}
        if "MaxDeviation" in lines:
            texts["MaxDeviation"] = f"{obj.MaxDeviation:.3g} mm"
        show_texts(lines, texts)
        lines["Continuity"].setToolTip("\n".join(continuity.split("; ")) + "\n\n"
                                       + obj.getDocumentationOfProperty("Continuity"))

    def clear_results(self):
        for line in (self.results or {}).values():
            line.clear()

    # --- Plane and Plane2 -------------------------------------------------------------------------
    def uses_plane2(self):
        return self.PLANE2 == "always" or bool(self.obj.UsePlane2)

    def _plane2_offset(self):
        """Plane2's distance beyond Plane along the normal; a guess when Plane2 is unset."""
        obj = self.obj
        if self.uses_plane2():
            return (obj.Plane2.Base - obj.Plane.Base).dot(direction_of(obj.Plane))
        hi = selection.extent(obj.Base, obj.Plane)[1] if selection.base_kind(obj.Base) else 0.0
        return 0.5 * hi if hi > 0 else 10.0

    def _set_plane2(self):
        plane = self.obj.Plane
        offset = spin_value(self.plane2_offset)
        self.obj.Plane2 = App.Placement(plane.Base + direction_of(plane) * offset, plane.Rotation)

    def _set_plane(self, plane):
        """Set Plane; Plane2, when used, follows at the same offset."""
        def change():
            self.obj.Plane = plane
            if self.uses_plane2():
                self._set_plane2()
        self.apply(change)

    def on_plane_edited(self, *_):
        if self._loading:
            return
        try:
            plane = self.plane.value(self.obj.Plane)
        except DeformError as e:   # a zero normal
            self.refuse(e)
            return
        self._set_plane(plane)

    def on_pick_plane(self):
        picked = selection.picked_plane(Gui.Selection.getSelectionEx())
        if picked is None:
            self.show_error("Select a planar face or a datum plane, then press "
                            "'Pick plane'.")
            return
        plane = selection.suggested_plane(self.obj.Base, picked) \
            if selection.base_kind(self.obj.Base) else picked
        Gui.Selection.clearSelection()
        self._set_plane(plane)
        self.reload()

    def on_flip_plane(self):
        plane = self.obj.Plane
        normal = direction_of(plane)
        origin = plane.Base
        if self.uses_plane2():  # the same region, seen from its other end
            origin = plane.Base + normal * spin_value(self.plane2_offset)
        self._set_plane(plane_placement((origin, -normal)))
        self.reload()

    def on_use_plane2(self, checked):
        if self._loading or self.closed:
            return
        self.plane2_offset.setEnabled(checked)

        def change():
            if checked:
                self._set_plane2()
            self.obj.UsePlane2 = bool(checked)
        self.apply(change)

    def on_plane2_edited(self, *_):
        if not (self._loading or self.closed) and self.uses_plane2():
            self.apply(self._set_plane2)

    # --- Axis -------------------------------------------------------------------------------------
    def on_axis_edited(self, *_):
        if self._loading:
            return
        try:
            axis = self.axis.value(self.obj.Axis)
        except DeformError as e:   # a zero direction
            self.refuse(e)
            return
        self.set_property("Axis", axis)

    def picked_axis(self, line):
        """The Axis a picked line gives (Bend turns it to suit Angle); with a UseAxis
        field, picking a line also switches it on: the part turns or scales about it."""
        if "UseAxis" in self.checks:
            self.obj.UseAxis = True
        return selection.axis_through(line, self.obj.Plane)

    def on_pick_axis(self):
        line = selection.picked_axis(Gui.Selection.getSelectionEx())
        if line is None:
            self.show_error("Select a straight edge or a datum line, then press 'Pick axis'.")
            return
        try:
            axis = self.picked_axis(line)
        except DeformError as e:
            self.refuse(e)
            return
        Gui.Selection.clearSelection()
        self.set_property("Axis", axis)
        self.reload()

    def on_flip_axis(self):
        axis = self.obj.Axis
        self.set_property("Axis", plane_placement((axis.Base, -direction_of(axis)), "Axis"))
        self.reload()

    # --- quantities, checks and Samples -----------------------------------------------------------
    def on_check(self, prop, checked, toggled=None):
        def change():
            setattr(self.obj, prop, bool(checked))
            if toggled is not None:
                toggled(checked)
        self.apply(change)

    def on_choice(self, prop, value):
        if value and value != getattr(self.obj, prop):
            self.set_property(prop, value)

    def on_samples_edited(self, value):
        if not self._loading and int(value) != self.obj.Samples:
            self.set_property("Samples", int(value))
