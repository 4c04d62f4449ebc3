"""The AreaConstrain task panel: the face, the target (an area, or a percentage of the
original area), Dof, Method, the movable poles, and the results.

While the panel is open the face's control net is drawn in the 3D view (pivy nodes in the
view's scene graph, removed on close), the movable poles in orange, so the user sees what
moves and can pick poles: with Pick poles on, a click within a few pixels of a pole (the
poles projected to the screen) adds it to Poles or removes it. The Base shows
semi-transparent under the result, so the new surface is seen over the old one.
"""
import FreeCADGui as Gui
from PySide import QtGui

from ..geometry.errors import DeformError
from ..geometry.nurbs.area_constrain import parse_poles
from ..shapes.bspline import bspline_of, face_of
from .bindings import bound_quantity, combo_box, on_value_changed, set_spin_value
from .coin_nodes import ControlNet
from .compat import event_position
from .task_panel import TaskPanelBase, is_invalid
from .widgets import length_text, pick_list, pick_toggle, results_box

BASE_TRANSPARENCY = 70    # the old surface while the panel is open
OUTPUTS = ("OriginalArea", "AchievedArea", "Iterations", "MaxPoleMove", "KKTResidual",
           "Conversion", "Replaced")


def area_text(value):
    return f"{value:.10g} mm²"


def base_surface(obj):
    """The B-spline surface of obj's face on the Base (its poles are what Poles names),
    or None when there is none yet (the feature then shows why)."""
    if obj.Base is None:
        return None
    try:
        return bspline_of(face_of(obj.Base.Shape, obj.Face)[1])[0]
    except (DeformError, RuntimeError):  # no such face, or OCCT cannot convert it
        return None


class AreaConstrainPanel(TaskPanelBase):
    TYPE = "AreaConstrain"
    TITLE = "Constrain area"
    EDITABLE = ("TargetArea", "TargetRatio", "Poles", "Dof", "Method")

    def __init__(self, obj, *args, **kwargs):
        self.net = None           # ControlNet while the panel is open
        self.callback = None      # the 3D view's mouse callback while Pick poles is on
        self.base_view = None     # the Base's (Visibility, Transparency) to restore
        super().__init__(obj, *args, **kwargs)
        self.start_preview()

    # --- fields --------------------------------------------------------------------------------
    def build(self, layout):
        obj = self.obj
        self.face = QtGui.QLabel()
        self.face.setObjectName("Face")
        self.face.setWordWrap(True)
        self.face.setToolTip(obj.getDocumentationOfProperty("Face"))
        layout.addWidget(self.face)
        layout.addWidget(self.build_target())
        form = QtGui.QFormLayout()
        self.combos = {}
        for prop in ("Dof", "Method"):
            combo = combo_box(obj, prop)
            combo.currentIndexChanged.connect(
                lambda index, p=prop: self.set_property(p, self.combos[p].itemText(index)))
            self.combos[prop] = combo
            form.addRow(QtGui.QLabel(prop), combo)
        layout.addLayout(form)
        layout.addWidget(self.build_poles())
        layout.addWidget(self.build_results())

    def build_target(self):
        box = QtGui.QGroupBox("Target")
        box.setObjectName("TargetGroup")
        grid = QtGui.QGridLayout(box)
        self.by_area = QtGui.QRadioButton("TargetArea")
        self.by_area.setObjectName("ByArea")
        self.by_area.setToolTip(self.obj.getDocumentationOfProperty("TargetArea"))
        self.by_ratio = QtGui.QRadioButton("Percent of original")
        self.by_ratio.setObjectName("ByRatio")
        self.by_ratio.setToolTip(self.obj.getDocumentationOfProperty("TargetRatio"))
        self.area, self.area_binding = bound_quantity(self.obj, "TargetArea", "mm^2", 0.0, 1e15)
        on_value_changed(self.area, lambda *_: self.on_area())
        self.percent = QtGui.QDoubleSpinBox()
        self.percent.setObjectName("TargetPercent")
        self.percent.setRange(0.01, 1e6)
        self.percent.setDecimals(4)
        self.percent.setSuffix(" %")
        self.percent.setToolTip(self.obj.getDocumentationOfProperty("TargetRatio"))
        self.percent.valueChanged.connect(self.on_percent)
        group = QtGui.QButtonGroup(box)
        group.addButton(self.by_area)
        group.addButton(self.by_ratio)
        self.by_ratio.toggled.connect(self.on_mode)
        grid.addWidget(self.by_area, 0, 0)
        grid.addWidget(self.area, 0, 1)
        grid.addWidget(self.by_ratio, 1, 0)
        grid.addWidget(self.percent, 1, 1)
        grid.setColumnStretch(1, 1)
        return box

    def build_poles(self):
        box, grid, self.poles = pick_list(self.obj, "Poles", 70)
        self.all_interior = QtGui.QPushButton("All interior")
        self.all_interior.setObjectName("AllInterior")
        self.all_interior.setToolTip("Let every interior pole move (Poles empty): the face's "
                                     "boundary stays, so it stays joined to its neighbours.")
        self.all_interior.clicked.connect(lambda: self.set_poles([]))
        self.pick, self.hint = pick_toggle(
            "Pick poles", "PickPoles", "While on, a click on a pole of the control net in the "
            "3D view adds it to the movable poles or removes it.", self.set_picking)
        grid.addWidget(self.poles, 0, 0, 1, 2)
        grid.addWidget(self.all_interior, 1, 0)
        grid.addWidget(self.pick, 1, 1)
        grid.addWidget(self.hint, 2, 0, 1, 2)
        return box

    def build_results(self):
        box, self.outputs = results_box(self.obj, OUTPUTS)
        return box

    # --- showing values ------------------------------------------------------------------------
    def original_area(self):
        """OriginalArea once computed, else OCCT's area of the face (before the first run)."""
        obj = self.obj
        if obj.OriginalArea > 0:
            return obj.OriginalArea
        if obj.Base is None:
            return 0.0
        try:
            return face_of(obj.Base.Shape, obj.Face)[1].Area
        except DeformError:  # no such face: the feature says so
            return 0.0

    def load(self):
        obj = self.obj
        for prop, combo in self.combos.items():
            combo.setCurrentIndex(max(0, combo.findText(getattr(obj, prop))))
        ratio = obj.TargetRatio > 0
        (self.by_ratio if ratio else self.by_area).setChecked(True)
        self.show_target()
        self.show_face()
        self.load_poles()

    def show_target(self):
        """Both fields show the target; the one not in use is greyed and follows the other."""
        obj, original = self.obj, self.original_area()
        ratio = obj.TargetRatio > 0
        self.area.setEnabled(not ratio)
        self.percent.setEnabled(ratio)
        if ratio:
            set_spin_value(self.area, obj.TargetRatio * original)
            self.percent.setValue(100.0 * obj.TargetRatio)
        else:
            set_spin_value(self.area, obj.TargetArea.Value)
            if original > 0:
                self.percent.setValue(100.0 * obj.TargetArea.Value / original)

    def show_face(self):
        obj = self.obj
        surface = base_surface(obj)
        text = f"{obj.Face} of {obj.Base.Label if obj.Base else '-'}"
        if surface is not None:
            text += (f": {surface.NbUPoles} x {surface.NbVPoles} poles, degree "
                     f"{surface.UDegree} x {surface.VDegree}")
        self.face.setText(text)

    def load_poles(self):
        entries = list(self.obj.Poles)
        self.poles.clear()
        if entries:
            self.poles.addItems(entries)
        else:
            self.poles.addItem("All interior poles")
        if self.net is not None:
            try:
                shape = (len(self.net.poles), len(self.net.poles[0]))
                self.net.set_movable(parse_poles(entries, shape))
            except DeformError:
                self.net.set_movable(())  # a bad entry: the feature's error says which
        self.show_hint()

    def show_hint(self):
        if self.net is None:
            self.hint.setText("")
        elif self.callback is None:
            self.hint.setText("Orange poles move. Press Pick poles to choose them in the 3D view.")
        else:
            self.hint.setText("Click a pole of the control net to add or remove it.")

    def show_results(self):
        obj = self.obj
        texts = {"OriginalArea": area_text(obj.OriginalArea),
                 "AchievedArea": area_text(obj.AchievedArea),
                 "Iterations": str(obj.Iterations),
                 "MaxPoleMove": length_text(obj.MaxPoleMove),
                 "KKTResidual": f"{obj.KKTResidual:.3g}",
                 "Conversion": obj.Conversion,
                 "Replaced": ("yes: the Base with the face replaced" if obj.Replaced
                              else "no: the face alone")}
        for prop, text in texts.items():
            self.outputs[prop].setText(text)
            self.outputs[prop].setCursorPosition(0)
        self._loading = True  # the greyed target field follows; no property is set
        try:
            self.show_target()
        finally:
            self._loading = False

    def clear_results(self):
        for line in self.outputs.values():
            line.clear()

    # --- edits ---------------------------------------------------------------------------------
    def on_mode(self, by_ratio):
        """Switch between the two targets, keeping the value: the result stays the same."""
        if self._loading or self.closed:
            return
        obj, original = self.obj, self.original_area()
        if by_ratio:
            ratio = obj.TargetArea.Value / original if original > 0 else 1.0
            self.set_property("TargetRatio", ratio if ratio > 0 else 1.0)
        else:
            self.set_property("TargetArea", obj.TargetRatio * original)
            self.set_property("TargetRatio", 0.0)
        self.reload()

    def on_area(self):
        if self._loading or self.by_ratio.isChecked():
            return
        self.quantity_edited("TargetArea", self.area, self.area_binding)

    def on_percent(self, value):
        if not self._loading and self.by_ratio.isChecked():
            self.set_property("TargetRatio", value / 100.0)

    def set_poles(self, entries):
        self.set_property("Poles", entries)
        self.reload()

    # --- the control net and picking -----------------------------------------------------------
    def start_preview(self):
        """Draw the control net and show the Base semi-transparent under the result."""
        view = Gui.getDocument(self.doc.Name).ActiveView
        surface = base_surface(self.obj)
        if surface is not None and hasattr(view, "getSceneGraph"):
            self.net = ControlNet(view, surface.getPoles())
            self.reload()
        base = self.obj.Base
        vobj = base.ViewObject if base is not None else None
        if vobj is not None:
            self.base_view = (bool(vobj.Visibility), vobj.Transparency)
            vobj.Transparency = BASE_TRANSPARENCY
            vobj.Visibility = True

    def end_preview(self):
        """Remove the net and the mouse callback; the Base looks as before (idempotent)."""
        self.set_picking(False)
        if self.net is not None:
            self.net.remove()
            self.net = None
        base = self.obj.Base
        if self.base_view is not None and base is not None and base.ViewObject is not None:
            base.ViewObject.Visibility, base.ViewObject.Transparency = self.base_view
        self.base_view = None

    def set_picking(self, on):
        from pivy import coin
        if on and self.callback is None and self.net is not None and not self.closed:
            self.callback = self.net.view.addEventCallbackPivy(
                coin.SoMouseButtonEvent.getClassTypeId(), self.on_mouse)
        elif not on and self.callback is not None:
            self.net.view.removeEventCallbackPivy(coin.SoMouseButtonEvent.getClassTypeId(),
                                                  self.callback)
            self.callback = None
        self.pick.blockSignals(True)
        self.pick.setChecked(self.callback is not None)
        self.pick.blockSignals(False)
        self.show_hint()

    def on_mouse(self, event_callback):
        """A mouse button in the 3D view: a left press near a pole toggles it (and is not
        passed on, so it does not select the surface)."""
        from pivy import coin
        event = event_callback.getEvent()
        if (event.getButton() == coin.SoMouseButtonEvent.BUTTON1
                and event.getState() == coin.SoMouseButtonEvent.DOWN):
            x, y = event_position(event)
            if self.click(x, y):
                event_callback.setHandled()

    def click(self, x, y):
        """Toggle the pole nearest the screen point (x, y) in Poles; True when one was near.
        From All interior, the first pick starts a list with just that pole."""
        if self.net is None or self.closed:
            return False
        pole = self.net.pole_at(x, y)
        if pole is None:
            return False
        entry = f"{pole[0]},{pole[1]}"
        entries = list(self.obj.Poles)
        if entry in entries:
            entries.remove(entry)
        else:
            entries.append(entry)
        self.set_poles(entries)
        return True

    # --- OK / Cancel -----------------------------------------------------------------------------
    def accept(self):
        self.flush()
        if not self.closed and not is_invalid(self.obj):
            self.end_preview()  # inside the panel's transaction: the Base's look is no change
        return super().accept()

    def reject(self):
        self.end_preview()
        return super().reject()
