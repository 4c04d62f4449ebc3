"""The DirectPush task panel: the pushes (grabbed point -> target, each removable), Range,
the constraints (fixed points and straight spans, added by clicks on the element), the
results; and, while it is open, the element can be dragged in the 3D view.

Dragging: a left press on the pushed edge or face grabs the element's point under the
mouse; moving drags it in the plane through that point perpendicular to the view direction
(on a face with Shift held at the press: along the face's normal there); the release records
one push (a Points / Targets pair) and recomputes once. Meanwhile nothing is recomputed: the
panel has the element in numpy (the pushes replayed through the kernel as the feature does,
kept until the inputs change), pushes it for each mouse position and shows it in a Coin node
with the result's own display hidden, so the shape follows the mouse at interactive rates.

Removing a push or changing Range or a constraint changes the element each later push
grabs; each such push keeps its parameter on the element and its point moves with it, so
the later pushes stay on the element.
"""
import time

import numpy as np
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

from ..features.direct_push import inputs_of
from ..geometry.nurbs import direct_push as dp
from ..geometry.nurbs import push
from ..geometry.nurbs.push import Grab, point_at
from ..ops.direct_push import INPUTS, replay
from ..shapes import bspline
from ..geometry.errors import DeformError
from .bindings import int_spin_box
from .coin_nodes import Preview
from .compat import event_position, sb_values
from .task_panel import TaskPanelBase, is_invalid
from .widgets import length_text, results_box

OUTPUTS = ("MaxPoleMove", "PoleCount", "Conversion")
CURVE_SAMPLES = 300
SELECTION_OFF = 2          # SoFCUnifiedSelection's OFF (AUTO, ON, OFF)


# --- the element in numpy (the feature's replay) ----------------------------------------------
def input_key(inputs):
    """Equal for equal inputs: when the cached State still holds."""
    vectors = tuple(tuple(tuple(v) for v in inputs[name]) for name in INPUTS[1:3] + INPUTS[4:])
    return inputs["Shape"].hashCode(), str(inputs["Element"]), inputs["Range"], vectors


def grabbed_at(state, result, component, picked):
    """The parameter of the element at a click on `component` ("Edge1", "Face3") of the
    result shape at `picked`, or None when that is not the pushed element."""
    if not component.startswith("Edge" if state.shape_type == "Edge" else "Face"):
        return None
    if state.shape_type == "Edge":
        return dp.closest_parameter(state.current, picked)[0]
    if len(result.Faces) > 1 and not same_surface(result.getElement(component).Surface,
                                                  state.current):
        return None  # another face of the solid
    return dp.closest_uv(state.current, picked)[:2]


def same_surface(surface, s):
    """Whether the Part surface is the Surface `s` (its poles; the result's face was built
    from them)."""
    if surface.TypeId != "Part::GeomBSplineSurface" or \
            (surface.NbUPoles, surface.NbVPoles) != s.weights.shape:
        return False
    scale = max(1.0, float(np.abs(s.poles).max()))
    return np.allclose(bspline.surface_arrays(surface).poles, s.poles, rtol=0, atol=1e-6 * scale)


def samples(arrays):
    """Points for drawing: (k, 3) along a Curve, a grid (a, b, 3) over a Surface."""
    return push.sample_points(arrays, CURVE_SAMPLES)


# --- the mouse --------------------------------------------------------------------------------
def mouse_ray(view, x, y):
    """(point, unit direction) of the line of sight through pixel (x, y) of `view`
    (Coin's pixels, from the bottom left)."""
    point = np.array(tuple(view.getPoint(int(x), int(y))), float)
    if view.getCameraType() == "Perspective":
        direction = point - np.array(sb_values(view.getCameraNode().position.getValue()))
    else:
        direction = np.array(tuple(view.getViewDirection()), float)
    return point, direction / np.linalg.norm(direction)


class Drag:
    """One drag: where the grabbed point goes for a mouse position. It moves in the plane
    through it perpendicular to the view direction, or along the face's normal (unless
    that is seen end-on); the target is the grabbed point plus the mouse's move there."""

    def __init__(self, view, grab, x, y, along_normal=False):
        self.view, self.grab = view, grab
        self.plane = np.array(tuple(view.getViewDirection()), float)
        self.plane /= np.linalg.norm(self.plane)
        self.axis = grab.normal if along_normal else None
        if self.axis is not None and abs(self.axis @ self.plane) > 0.995:
            self.axis = None
        self.arrays, self.reached = grab.arrays, None
        self.start = self.under_mouse(x, y)

    def under_mouse(self, x, y):
        """The point of the drag's plane (or axis) under the mouse (nearest to it)."""
        origin, direction = mouse_ray(self.view, x, y)
        p = self.grab.point
        if self.axis is None:
            return origin + direction * ((p - origin) @ self.plane / (direction @ self.plane))
        b, w = self.axis @ direction, p - origin
        return p + self.axis * ((b * (direction @ w) - self.axis @ w) / (1.0 - b * b))

    def target(self, x, y):
        return self.grab.point + self.under_mouse(x, y) - self.start


# --- what the 3D view shows -------------------------------------------------------------------
def rest_of(shape, component):
    """(points, triangles) of the result's faces other than `component`, or None."""
    import Part
    faces = [f for i, f in enumerate(shape.Faces) if f"Face{i + 1}" != component]
    if not faces or len(faces) == len(shape.Faces):
        return None
    return Part.Compound(faces).tessellate(2e-3 * shape.BoundBox.DiagonalLength)


def vector_text(v):
    return f"({v[0]:.2f}, {v[1]:.2f}, {v[2]:.2f})"


# --- the panel --------------------------------------------------------------------------------
class DirectPushPanel(TaskPanelBase):
    TYPE = "DirectPush"
    TITLE = "Direct push"
    EDITABLE = INPUTS[1:]

    def __init__(self, obj, *args, **kwargs):
        self.preview = None        # Preview while the panel is open in a 3D view
        self.callbacks = []        # (event type, callback) registered in that view
        self.drag = None           # Drag while the mouse drags
        self.selection_modes = None  # the selection root's modes while a press is ours
        self.picking = None        # "Fixed" or "Straight" while adding one by clicks
        self.pending = None        # the first point of a straight span being added
        self.cache = None          # (input_key, State)
        self.frame_times = []      # seconds per preview update of the last drag
        self.recompute_time = None  # seconds of the recompute that recorded the last drag
        super().__init__(obj, *args, **kwargs)
        self.start_view()

    # --- fields -------------------------------------------------------------------------------
    def build(self, layout):
        obj = self.obj
        self.element = QtGui.QLabel()
        self.element.setObjectName("Element")
        self.element.setWordWrap(True)
        self.element.setToolTip(obj.getDocumentationOfProperty("Element"))
        layout.addWidget(self.element)
        box = QtGui.QGroupBox("Pushes")
        box.setToolTip(obj.getDocumentationOfProperty("Points"))
        grid = QtGui.QVBoxLayout(box)
        self.pushes = self.list_widget("Pushes", grid)
        self.button("RemovePush", "Remove push", "Remove the selected push; the later ones "
                    "keep where they grabbed the element.", self.on_remove_push, grid)
        layout.addWidget(box)
        form = QtGui.QFormLayout()
        self.range = int_spin_box(obj, "Range", 0, 99)
        self.range.setSpecialValueText("degree + 1")
        self.range.valueChanged.connect(self.on_range)
        form.addRow("Range", self.range)
        layout.addLayout(form)
        layout.addWidget(self.build_constraints())
        self.hint = QtGui.QLabel()
        self.hint.setObjectName("DragHint")
        self.hint.setWordWrap(True)
        layout.addWidget(self.hint)
        layout.addWidget(self.build_results())

    def build_constraints(self):
        """The constraints list and its buttons, stacked: the panel stays narrow."""
        box = QtGui.QGroupBox("Constraints")
        box.setToolTip("Fixed points keep their position and tangent; straight spans stay "
                       "straight. Both are given on the Base's element.")
        column = QtGui.QVBoxLayout(box)
        self.constraints = self.list_widget("Constraints", column)
        self.add_fixed = self.button(
            "AddFixed", "Add fixed point", self.obj.getDocumentationOfProperty("Fixed")
            + " Click the element in the 3D view.",
            lambda on: self.set_picking("Fixed" if on else None), column)
        self.add_straight = self.button(
            "AddStraight", "Add straight span", self.obj.getDocumentationOfProperty("Straight")
            + " Click its two ends in the 3D view.",
            lambda on: self.set_picking("Straight" if on else None), column)
        for button in (self.add_fixed, self.add_straight):
            button.setCheckable(True)
        self.button("RemoveConstraint", "Remove constraint", "Remove the selected constraint.",
                    self.on_remove_constraint, column)
        return box

    def build_results(self):
        box, self.outputs = results_box(self.obj, OUTPUTS)
        return box

    @staticmethod
    def list_widget(name, layout):
        widget = QtGui.QListWidget()
        widget.setObjectName(name)
        widget.setMaximumHeight(90)
        layout.addWidget(widget)
        return widget

    @staticmethod
    def button(name, text, tip, slot, layout):
        button = QtGui.QPushButton(text)
        button.setObjectName(name)
        button.setToolTip(tip)
        button.clicked.connect(slot)
        layout.addWidget(button)
        return button

    # --- showing values -----------------------------------------------------------------------
    def is_face(self):
        return str(self.obj.Element).startswith("Face")

    def load(self):
        obj = self.obj
        base = obj.Base.Label if obj.Base is not None else "-"
        self.element.setText(f"{obj.Element} of {base}")
        self.range.setValue(obj.Range)
        self.pushes.clear()
        for i, (p, q) in enumerate(zip(obj.Points, obj.Targets)):
            self.pushes.addItem(f"{i + 1}: {vector_text(p)}\n    -> {vector_text(q)}")
            self.pushes.item(i).setToolTip(f"pushed {length_text((q - p).Length)}")
        self.pushes.setCurrentRow(self.pushes.count() - 1)
        self.constraint_rows = [("Fixed", i) for i in range(len(obj.Fixed))]
        self.constraint_rows += [("Straight", i) for i in range(len(obj.Straight) // 2)]
        self.constraint_rows += [("Angles", i) for i in range(len(obj.Angles) // 2)]
        self.constraints.clear()
        for prop, i in self.constraint_rows:
            if prop == "Fixed":
                text = f"Fixed {vector_text(obj.Fixed[i])}"
            elif prop == "Straight":
                a, b = obj.Straight[2 * i:2 * i + 2]
                text = f"Straight {vector_text(a)} - {vector_text(b)}"
            else:
                text = f"Angle {obj.Angles[2 * i + 1].x:g} deg at {vector_text(obj.Angles[2 * i])}"
            self.constraints.addItem(text)
        self.add_straight.setEnabled(not self.is_face())
        self.show_hint()

    def show_hint(self):
        if self.picking == "Fixed":
            text = "Click the element in the 3D view where it must stay."
        elif self.picking == "Straight":
            text = f"Click the {'end' if self.pending is not None else 'start'} of the span."
        elif self.preview is None:
            text = ""
        else:
            text = "Drag the element in the 3D view to push it: press on it, move, release."
            if self.is_face():
                text += " Hold Shift at the press to push along the face's normal."
        self.hint.setText(text)

    def show_results(self):
        obj = self.obj
        texts = {"MaxPoleMove": length_text(obj.MaxPoleMove), "PoleCount": str(obj.PoleCount),
                 "Conversion": obj.Conversion}
        for prop, text in texts.items():
            self.outputs[prop].setText(text)
            self.outputs[prop].setCursorPosition(0)
        self.show_marks()

    def clear_results(self):
        for line in self.outputs.values():
            line.clear()
        self.show_marks()

    def show_marks(self):
        """The constraints where they are on the element now, and a span's pending start."""
        if self.preview is None:
            return
        points, segments = [], []
        try:
            state = self.state()
            points = [point_at(state.current, t) for t in state.fixed + state.corners]
            for a, b in state.spans:
                segments.append((len(points), len(points) + 1))
                points += [point_at(state.current, a), point_at(state.current, b)]
        except (DeformError, RuntimeError):  # bad inputs or OCCT: the feature says why
            pass
        if self.pending is not None:
            points.append(tuple(self.pending))
        self.preview.constraints.set(points, segments)

    # --- the element's state ------------------------------------------------------------------
    def state(self):
        """The State for the object's inputs now (replayed when they changed)."""
        inputs = inputs_of(self.obj)
        key = input_key(inputs)
        if self.cache is None or self.cache[0] != key:
            self.cache = (key, replay(inputs))
        return self.cache[1]

    def change(self, drop=None, **changes):
        """Set `changes` (property -> value) and remove push `drop`; every other push keeps
        the parameter where it grabbed the element. Then recompute."""
        if self._loading or self.closed:
            return
        obj = self.obj
        keep = [i for i in range(len(obj.Targets)) if i != drop]
        inputs = {**inputs_of(obj), **changes}
        inputs["Targets"] = [obj.Targets[i] for i in keep]
        inputs["Points"] = [obj.Points[i] for i in keep if i < len(obj.Points)]
        try:
            params = self.state().params
            state = replay(inputs, [params[i] for i in keep])
            inputs["Points"] = [App.Vector(*p) for p in state.points]
        except (DeformError, RuntimeError):  # bad inputs or OCCT: the feature says why
            state = None  # the points stay
        for name in ("Points", "Targets", *changes):
            setattr(obj, name, inputs[name])
        if state is not None:
            self.cache = (input_key(inputs_of(obj)), state)
        self.recompute()
        self.reload()

    # --- edits --------------------------------------------------------------------------------
    def on_range(self, value):
        if value != self.obj.Range:
            self.change(Range=value)

    def on_remove_push(self):
        row = self.pushes.currentRow()
        if 0 <= row < len(self.obj.Targets):
            self.change(drop=row)

    def on_remove_constraint(self):
        row = self.constraints.currentRow()
        if row < 0:
            return
        prop, i = self.constraint_rows[row]
        values = list(getattr(self.obj, prop))
        if prop == "Fixed":
            del values[i]
        else:
            del values[2 * i:2 * i + 2]
        self.change(**{prop: values})

    def set_picking(self, which):
        self.picking = which if self.preview is not None else None
        self.pending = None
        for button, name in ((self.add_fixed, "Fixed"), (self.add_straight, "Straight")):
            button.blockSignals(True)
            button.setChecked(self.picking == name)
            button.blockSignals(False)
        self.show_marks()
        self.show_hint()

    def add_constraint(self, state, at):
        """A click while adding a constraint: the Base's element at the clicked parameter
        (constraints are given on the Base)."""
        point = App.Vector(*point_at(state.original, at))
        if self.picking == "Fixed":
            self.set_picking(None)
            self.change(Fixed=list(self.obj.Fixed) + [point])
        elif self.pending is None:
            self.pending = point
            self.show_marks()
            self.show_hint()
        else:
            span = [self.pending, point]
            self.set_picking(None)
            self.change(Straight=list(self.obj.Straight) + span)

    # --- the 3D view --------------------------------------------------------------------------
    def start_view(self):
        from pivy import coin
        view = Gui.getDocument(self.doc.Name).ActiveView
        if not hasattr(view, "getSceneGraph") or self.obj.ViewObject is None:
            return
        self.preview = Preview(view, self.obj.ViewObject)
        for event, handler in ((coin.SoMouseButtonEvent, self.on_button),
                               (coin.SoLocation2Event, self.on_motion)):
            kind = event.getClassTypeId()
            self.callbacks.append((kind, view.addEventCallbackPivy(kind, handler)))
        self.show_marks()
        self.show_hint()

    def end_view(self):
        """Remove the nodes and the mouse callbacks (idempotent)."""
        self.set_picking(None)
        self.drag = None
        if self.preview is not None:
            self.hold_selection(False)
            for kind, callback in self.callbacks:
                self.preview.view.removeEventCallbackPivy(kind, callback)
            self.callbacks = []
            self.preview.remove()
            self.preview = None

    def on_button(self, event_callback):
        from pivy import coin
        event = event_callback.getEvent()
        if self.closed or event.getButton() != coin.SoMouseButtonEvent.BUTTON1:
            return
        x, y = event_position(event)
        if event.getState() == coin.SoMouseButtonEvent.DOWN:
            handled = self.press(x, y, event.wasShiftDown())
            self.hold_selection(handled)
        else:
            handled = self.selection_modes is not None
            self.release(x, y)
            self.hold_selection(False)
        if handled:
            event_callback.setHandled()

    def hold_selection(self, hold):
        """From a press on the element to its release the view's selection root (the scene
        graph's root) neither preselects nor selects: it would select on the release
        before passing it on to us, and a drag may end over another object."""
        if hold and self.selection_modes is None:
            root = self.preview.view.getSceneGraph()
            fields = [root.getField(name) for name in ("selectionMode", "highlightMode")]
            self.selection_modes = [(f, f.getValue()) for f in fields if f is not None]
            for field, _ in self.selection_modes:
                field.setValue(SELECTION_OFF)
        elif not hold and self.selection_modes is not None:
            for field, value in self.selection_modes:
                field.setValue(value)
            self.selection_modes = None

    def on_motion(self, event_callback):
        if self.drag is not None and not self.closed:
            self.move(*event_position(event_callback.getEvent()))
            event_callback.setHandled()

    def press(self, x, y, along_normal=False):
        """A left press at pixel (x, y): grab the element there (or add the constraint
        point being picked). True when it was on the element."""
        info = self.preview.view.getObjectInfo((int(x), int(y))) if self.preview else None
        if not info or info.get("Document") != self.doc.Name or \
                info.get("Object") != self.obj.Name:
            return False
        self.flush()
        if is_invalid(self.obj):
            return False
        component = info.get("Component", "")
        picked = np.array([info["x"], info["y"], info["z"]], float)
        try:
            state = self.state()
            at = grabbed_at(state, self.obj.Shape, component, picked)
            if at is None:
                return False
            if self.picking:
                self.add_constraint(state, at)
                return True
            self.drag = Drag(self.preview.view, Grab(state, state.current, at), x, y,
                             along_normal)
        except (DeformError, RuntimeError) as e:  # bad inputs or OCCT
            self.refuse(e)
            return False
        self.frame_times = []
        self.preview.begin(state.shape_type == "Edge", rest_of(self.obj.Shape, component))
        self.move(x, y)
        return True

    def move(self, x, y):
        """The element with the grabbed point at the mouse's target, shown (no recompute)."""
        start = time.perf_counter()
        drag = self.drag
        target = drag.target(x, y)
        try:
            drag.arrays = drag.grab.pushed(target)
        except DeformError as e:  # e.g. a fixed point right there: the last preview stays
            self.hint.setText(str(e))
            return
        drag.reached = target
        self.preview.update(samples(drag.arrays))
        self.preview.grab.set([drag.grab.point, target], [(0, 1)])
        self.frame_times.append(time.perf_counter() - start)

    def release(self, x, y):
        """End a drag: record the push (unless the mouse did not move) and recompute once."""
        if self.drag is None:
            return
        self.move(x, y)
        drag, self.drag = self.drag, None
        size = max(1.0, self.obj.Shape.BoundBox.DiagonalLength)
        if drag.reached is not None and \
                np.linalg.norm(drag.reached - drag.grab.point) > 1e-9 * size:
            self.record(drag)
        self.preview.end()
        self.show_hint()

    def record(self, drag):
        obj, grab = self.obj, drag.grab
        obj.Points = list(obj.Points) + [App.Vector(*grab.point)]
        obj.Targets = list(obj.Targets) + [App.Vector(*drag.reached)]
        state = grab.state  # after this push it is what the preview shows: no replay next time
        self.cache = (input_key(inputs_of(obj)), state._replace(
            current=drag.arrays, params=state.params + [grab.at],
            points=state.points + [grab.point]))
        start = time.perf_counter()
        self.recompute()
        self.recompute_time = time.perf_counter() - start
        self.reload()

    # --- OK / Cancel --------------------------------------------------------------------------
    def accept(self):
        self.flush()
        if not self.closed and not is_invalid(self.obj):
            self.end_view()
        return super().accept()

    def reject(self):
        self.end_view()
        return super().reject()
