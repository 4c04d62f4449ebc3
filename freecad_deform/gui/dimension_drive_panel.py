"""The DimensionDrive task panel: Kind, the picked regions, Target (for Position also
TargetV and the Origin / AxisPoint frame), FeatureAngle, and the results (the current
value, the reachable range).

Regions are picked by clicking the mesh in the 3D view while Pick is on: a selection
observer gets each click's point. The result shows the Base deformed facet for facet, so
a click on it is mapped to the same facet of the Base (the dimension is defined there).
While the panel is open the mesh shows its segmented regions in colour (the view's
Coloring), so the user sees what a click picks; the previous Coloring comes back on close.
"""
import numpy as np
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from ..geometry.mesh.regions import region_colours
from ..ops import dimension_drive as op
from ..geometry.errors import DeformError
from ..geometry.sweep.defaults import across
from .bindings import (check_box, combo_box, on_value_changed, quantity_spin_box,
                       set_spin_value, spin_value)
from .task_panel import TaskPanelBase
from .widgets import length_text, pick_list, pick_toggle, results_box

# What each picked point means, by Kind; Position takes further feature regions after these.
ROLES = {"Distance": ("Moving plane", "Reference plane"), "Radius": ("Cylinder",),
         "Position": ("Base plane", "Feature")}
MORE = "More feature (optional)"
MOST = {"Distance": 2, "Radius": 1}   # how many regions a kind reads; Position: any
FRAME = ("Origin", "AxisPoint")       # Position's frame points, also pickable


# --- from a click to a point of the Base ---------------------------------------------------------
def facet_at(mesh, point, direction):
    """Index of the facet of `mesh` under a click at `point` seen along `direction`, or None
    when the point is not on the mesh (a selection from the tree reports (0, 0, 0)). A ray
    through a shared edge can miss both facets, so a few rays a hair apart are tried."""
    size = max(mesh.BoundBox.DiagonalLength, 1e-9)
    d = App.Vector(direction)
    if d.Length < 1e-12:
        return None
    d.normalize()
    u = d.cross(App.Vector(1, 0, 0) if abs(d.x) < 0.9 else App.Vector(0, 1, 0)).normalize()
    w = d.cross(u)
    for offset in (App.Vector(), u, -u, w, -w):
        start = point + offset * (1e-5 * size) - d * (1e-3 * size)
        for index, hit in mesh.nearestFacetOnRay(tuple(start), tuple(d)).items():
            if (App.Vector(*hit) - point).Length <= 1e-3 * size:
                return int(index)
    return None


def facet_centre(mesh, index):
    points = mesh.meshFromSegment([index]).Facets[0].Points
    return App.Vector(*(sum(c) / 3.0 for c in zip(*points)))


def base_point(obj, picked, sub, point, direction):
    """The point of obj's Base that a click on `picked` (a result or the Base) stands for,
    or None when the click is not on either."""
    base = obj.Base
    if base is not None and picked.Name == base.Name:
        if base.isDerivedFrom("Mesh::Feature"):
            return point if facet_at(base.Mesh, point, direction) is not None else None
        return point if sub.startswith("Face") else None
    if picked.Name != obj.Name:
        return None
    facet = facet_at(obj.Mesh, point, direction)
    if facet is None:
        return None
    mesh = obj.Proxy.base_mesh(obj)[2]  # the same facets, undeformed
    return facet_centre(mesh, facet) if facet < mesh.CountFacets else None


# --- what the regions give -----------------------------------------------------------------------
def model_of(obj):
    """The feature's segmented Base (cached by the proxy), or None while there is none."""
    try:
        return obj.Proxy.model(obj)[0]
    except (DeformError, RuntimeError):  # no mesh yet, or OCCT cannot tessellate the Base
        return None


def measured(obj):
    """The dimension the picked regions have on the Base: (value,) or (u, v); None while
    they do not define one."""
    model = model_of(obj)
    if model is None:
        return None
    try:
        return op.measure(model, obj.Kind, obj.Regions, tuple(obj.Origin), tuple(obj.AxisPoint))
    except DeformError:
        return None


def default_frame(obj, point):
    """(Origin, AxisPoint) for Position: at `point` on the base plane, u along the global
    axis that lies most in that plane; None when `point` is on no plane."""
    model = model_of(obj)
    label = model.region_at(tuple(point)) if model is not None else None
    if label is None or not model.planar[label]:
        return None
    u = across(model.planes[label].normal)
    return App.Vector(point), App.Vector(point) + App.Vector(*(float(c) for c in u))


def swatch(rgb):
    pixmap = QtGui.QPixmap(12, 12)
    pixmap.fill(QtGui.QColor.fromRgbF(*rgb))
    return QtGui.QIcon(pixmap)


class PickObserver:
    """Gui.Selection observer while Pick is on: each click hands its point to the panel."""

    def __init__(self, panel):
        self.panel = panel

    def addSelection(self, doc, obj, sub, pnt):
        self.panel.on_click(doc, obj, sub, App.Vector(*pnt))


class DimensionDrivePanel(TaskPanelBase):
    TYPE = "DimensionDrive"
    TITLE = "Drive dimension"
    EDITABLE = ("Kind", "Regions", "Target", "TargetV", "Origin", "AxisPoint", "FeatureAngle",
                "Rehandle")

    def __init__(self, obj, *args, **kwargs):
        self.quantities = {}   # property -> (QuantitySpinBox, ExpressionBinding)
        self.frame = {}        # "Origin" / "AxisPoint" -> three QuantitySpinBoxes
        self.observer = None   # PickObserver while Pick is on
        self.slot = 0          # what the next click sets: a row of the list, or a FRAME name
        self.target_edited = self.frame_edited = False
        vobj = obj.ViewObject
        self.coloring = bool(vobj.Coloring) if vobj is not None else None
        super().__init__(obj, *args, **kwargs)
        self.show_base_mesh()
        if self.created:
            self.slot = len(obj.Regions)
            self.regions_changed()
            if len(obj.Regions) < len(ROLES[obj.Kind]):
                self.set_picking(True)
        self.show_regions()

    # --- fields ------------------------------------------------------------------------------
    def build(self, layout):
        obj = self.obj
        form = QtGui.QFormLayout()
        self.kind = combo_box(obj, "Kind")
        self.kind.currentIndexChanged.connect(self.on_kind)
        form.addRow("Kind", self.kind)
        layout.addLayout(form)
        layout.addWidget(self.build_regions())
        form = QtGui.QFormLayout()
        self.add_quantity(form, "Target", "mm")
        self.position_only = [self.add_quantity(form, "TargetV", "mm"), self.labels["TargetV"]]
        layout.addLayout(form)
        frame = QtGui.QGroupBox("Frame")
        frame.setObjectName("FrameGroup")
        frame.setToolTip("Position only: u runs from Origin toward AxisPoint, on the base "
                         "plane; Target and TargetV are the feature's u and v.")
        grid = QtGui.QGridLayout(frame)
        for row, prop in enumerate(FRAME):
            self.add_frame_point(grid, row, prop)
        self.position_only.append(frame)
        layout.addWidget(frame)
        form = QtGui.QFormLayout()
        self.add_quantity(form, "FeatureAngle", "deg", 0.0, 180.0)
        self.rehandle = check_box(obj, "Rehandle")
        self.rehandle.toggled.connect(self.on_rehandle)
        form.addRow(self.rehandle)
        layout.addLayout(form)
        layout.addWidget(self.build_results())

    def build_regions(self):
        box, grid, self.regions = pick_list(self.obj, "Regions", 90)
        self.regions.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        self.regions.currentRowChanged.connect(self.on_row)
        self.pick, self.hint = pick_toggle(
            "Pick", "PickRegions", "While on, a click on the mesh in the 3D view sets the "
            "selected row; the regions are shown in colour.", self.set_picking)
        clear = QtGui.QPushButton("Clear")
        clear.setObjectName("ClearRegions")
        clear.setToolTip("Forget the picked regions and pick them again.")
        clear.clicked.connect(self.on_clear)
        grid.addWidget(self.regions, 0, 0, 1, 2)
        grid.addWidget(self.pick, 1, 0)
        grid.addWidget(clear, 1, 1)
        grid.addWidget(self.hint, 2, 0, 1, 2)
        return box

    def add_frame_point(self, grid, row, prop):
        boxes = [quantity_spin_box("mm", name=prop + c) for c in "XYZ"]
        grid.addWidget(QtGui.QLabel(prop), row, 0)
        for column, box in enumerate(boxes):
            box.setToolTip(self.obj.getDocumentationOfProperty(prop))
            on_value_changed(box, lambda *_: self.on_frame(prop))
            grid.addWidget(box, row, column + 1)
        pick = QtGui.QPushButton("Pick")
        pick.setObjectName("Pick" + prop)
        pick.setToolTip(f"The next click on the mesh sets {prop}.")
        pick.clicked.connect(lambda: self.pick_frame(prop))
        grid.addWidget(pick, row, 4)
        self.frame[prop] = boxes

    def build_results(self):
        box, self.outputs = results_box(self.obj, ("Current", "Achieved", "Reachable",
                                                   "Handles", "RegionCount"))
        return box

    # --- showing values ------------------------------------------------------------------------
    def roles(self):
        """The list's rows: the role of each point the kind reads (Position: and one more)."""
        kind, count = self.obj.Kind, len(self.obj.Regions)
        roles = list(ROLES[kind])
        if kind == "Position":
            roles += ["Feature"] * max(0, count - len(roles)) + [MORE]
        return roles + ["Unused"] * max(0, count - len(roles))

    def load(self):
        obj = self.obj
        self.kind.setCurrentIndex(max(0, self.kind.findText(obj.Kind)))
        for prop, (box, _) in self.quantities.items():
            set_spin_value(box, getattr(obj, prop).Value)
        for prop, boxes in self.frame.items():
            for box, value in zip(boxes, getattr(obj, prop)):
                set_spin_value(box, value)
        for widget in self.position_only:
            widget.setVisible(obj.Kind == "Position")
        self.rehandle.setChecked(bool(obj.Rehandle))
        self.load_regions()

    def load_regions(self):
        """One row per role: the picked point, in the colour of the region it picks."""
        model = model_of(self.obj)
        if model is not None:
            colours = region_colours(np.arange(model.count))
        points = list(self.obj.Regions)
        self.regions.clear()
        for i, role in enumerate(self.roles()):
            item = QtGui.QListWidgetItem(role + ": -")
            if i < len(points):
                p = points[i]
                item.setText(f"{role}: ({p.x:.2f}, {p.y:.2f}, {p.z:.2f})")
                item.setToolTip(f"{role}: the region nearest ({p.x:.6g}, {p.y:.6g}, "
                                f"{p.z:.6g}) on the Base")
                if model is not None:
                    item.setIcon(swatch(colours[model.region_at(tuple(p))]))
            self.regions.addItem(item)
        if isinstance(self.slot, int):
            self.slot = min(self.slot, self.regions.count() - 1)
            self.regions.setCurrentRow(self.slot)
        self.show_hint()

    def show_hint(self):
        if self.observer is None:
            self.hint.setText("Press Pick, then click the mesh in the 3D view.")
            return
        roles = self.roles()
        what = self.slot if self.slot in FRAME else roles[min(self.slot, len(roles) - 1)]
        self.hint.setText(f"Click the mesh in the 3D view: {what}.")

    def show_results(self):
        obj = self.obj
        if obj.Kind == "Position":
            current = f"u {length_text(obj.Current)}, v {length_text(obj.CurrentV)}"
            achieved = f"u {length_text(obj.Achieved)}, v {length_text(obj.AchievedV)}"
        else:
            current, achieved = length_text(obj.Current), length_text(obj.Achieved)
        reach = list(obj.Reachable)
        if len(reach) == 2 and obj.Kind == "Position":
            reach = f"{length_text(-reach[0])} back, {length_text(reach[1])} forward"
        elif len(reach) == 2:
            reach = f"{length_text(reach[0])} to {length_text(reach[1])}"
        else:
            reach = ""
        for prop, text in (("Current", current), ("Achieved", achieved), ("Reachable", reach)):
            self.outputs[prop].setText(text)
            self.outputs[prop].setCursorPosition(0)
        self.outputs["RegionCount"].setText(str(obj.RegionCount))
        self.outputs["Handles"].setText(str(obj.Handles))

    def clear_results(self):
        for prop in ("Current", "Achieved", "Reachable", "Handles"):
            self.outputs[prop].clear()
        self.outputs["RegionCount"].setText(str(self.obj.RegionCount))

    # --- regions in colour -----------------------------------------------------------------------
    def show_base_mesh(self):
        """A result still empty (no regions picked yet) shows the undeformed Base mesh, so
        there is something to colour and to click."""
        obj = self.obj
        if obj.Mesh.CountFacets == 0:
            try:
                obj.Mesh = obj.Proxy.base_mesh(obj)[2]
            except (DeformError, RuntimeError) as e:  # the Base, or OCCT tessellating it
                self.refuse(e)

    def show_regions(self):
        """Colour the mesh by region. The view does not follow a new Mesh or colour list by
        itself: setting Coloring (again) refreshes it."""
        obj, vobj = self.obj, self.obj.ViewObject
        if vobj is not None and 0 < obj.Mesh.CountFacets == len(obj.RegionColors):
            vobj.Coloring = True

    def restore_coloring(self):
        vobj = self.obj.ViewObject
        if vobj is not None and self.coloring is not None:
            vobj.Coloring = self.coloring

    def recompute(self):
        super().recompute()
        if not self.closed:
            self.show_regions()
            self._loading = True  # the swatches follow a new segmentation; no field is reset
            try:
                self.load_regions()
            finally:
                self._loading = False

    # --- picking ---------------------------------------------------------------------------------
    def set_picking(self, on):
        if on and self.observer is None and not self.closed:
            self.observer = PickObserver(self)
            Gui.Selection.addObserver(self.observer)
        elif not on and self.observer is not None:
            Gui.Selection.removeObserver(self.observer)
            self.observer = None
        self.pick.blockSignals(True)
        self.pick.setChecked(self.observer is not None)
        self.pick.blockSignals(False)
        if not on and self.slot in FRAME:
            self.slot = max(0, self.regions.currentRow())
        self.show_hint()

    def on_row(self, row):
        if not self._loading and row >= 0:
            self.slot = row
            self.show_hint()

    def pick_frame(self, prop):
        self.slot = prop
        self.set_picking(True)

    def on_click(self, doc, name, sub, point):
        """A click in the 3D view (through PickObserver): set the point the slot names."""
        if self.closed or doc != self.doc.Name:
            return
        picked = self.doc.getObject(name)
        if picked is None:
            return
        try:
            view = Gui.getDocument(doc).ActiveView
            point = base_point(self.obj, picked, sub, point, App.Vector(view.getViewDirection()))
        except (DeformError, RuntimeError) as e:  # the Base, or OCCT tessellating it
            self.refuse(e)
            return
        if point is None:
            return
        QtCore.QTimer.singleShot(0, Gui.Selection.clearSelection)  # the colours show again
        if self.slot in FRAME:
            self.set_frame_point(self.slot, point)
        else:
            self.set_region(self.slot, point)

    def set_region(self, row, point):
        """Put `point` into Regions at `row` (appended past the end); Pick stays on until
        every region the kind needs is there."""
        obj = self.obj
        regions = list(obj.Regions)
        row = min(row, len(regions))
        regions[row:row + 1] = [point]
        self.set_property("Regions", regions)
        if row == 0:
            self.default_frame()
        self.slot = row + 1
        if len(regions) >= len(ROLES[obj.Kind]):
            self.set_picking(False)
        self.regions_changed()

    def set_frame_point(self, prop, point):
        self.frame_edited = True
        self.set_property(prop, point)
        self.set_picking(False)
        self.regions_changed()

    def on_clear(self):
        self.slot = 0
        self.target_edited = False
        self.set_property("Regions", [])
        self.regions_changed()
        self.set_picking(True)

    def on_kind(self, index):
        if self._loading or self.closed:
            return
        kind = self.kind.itemText(index)
        regions = list(self.obj.Regions)[:MOST.get(kind)]
        self.set_property("Kind", kind)
        self.set_property("Regions", regions)
        self.target_edited = False  # a Target of another kind of dimension means nothing here
        self.default_frame()
        self.slot = 0  # the points mean something else now: the next click replaces the first
        self.regions_changed()
        self.set_picking(True)

    def default_frame(self):
        """Position's frame on the picked base plane: on a new object until the user sets
        it, else only while it is unset (Origin = AxisPoint)."""
        obj = self.obj
        if obj.Kind != "Position" or not obj.Regions:
            return
        if (self.created and not self.frame_edited) or obj.Origin == obj.AxisPoint:
            frame = default_frame(obj, obj.Regions[0])
            if frame is not None:
                obj.Origin, obj.AxisPoint = frame

    def regions_changed(self):
        self.follow_current()
        self.reload()
        self.schedule_recompute()

    def follow_current(self):
        """On a new object, Target follows the picked dimension's current value until the
        user types one: the preview stays valid while picking, and the user types the change."""
        if not self.created or self.target_edited:
            return
        if any(self.quantities[p][1].hasExpression() for p in ("Target", "TargetV")):
            return
        current = measured(self.obj)
        if current is not None:
            self.obj.Target = current[0]
            self.obj.TargetV = current[1] if len(current) > 1 else 0.0

    # --- edits -----------------------------------------------------------------------------------
    def on_quantity(self, prop):
        if self._loading:
            return
        if prop in ("Target", "TargetV"):
            self.target_edited = True
        self.quantity_edited(prop, *self.quantities[prop])

    def on_rehandle(self, checked):
        if not self._loading:
            self.set_property("Rehandle", bool(checked))

    def on_frame(self, prop):
        if not self._loading:
            self.frame_edited = True
            self.set_property(prop, App.Vector(*(spin_value(b) for b in self.frame[prop])))

    # --- OK / Cancel -----------------------------------------------------------------------------
    def accept(self):
        self.flush()
        self.set_picking(False)
        self.restore_coloring()  # still inside the panel's transaction: one undo step
        if super().accept():
            return True
        self.show_regions()
        return False

    def reject(self):
        self.set_picking(False)
        self.restore_coloring()
        return super().reject()
