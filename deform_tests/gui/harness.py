"""The harness of the GUI scenario, inside the real FreeCAD GUI: the report every check
lands in (a JSON file, DEFORM_GUI_RESULT) and what the parts use to drive FreeCAD the way a
user does (fields, buttons, typing, clicks and drags in the 3D view, waiting, screenshots).

Environment: DEFORM_GUI_RESULT (JSON path), DEFORM_GUI_OUT (directory for screenshots and
the saved document), DEFORM_TESTDATA (the shared testdata directory), DEFORM_REPO (the
repository the user Mod dir links to).
"""
import json
import os
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

RESULT = os.environ["DEFORM_GUI_RESULT"]
OUT = os.environ["DEFORM_GUI_OUT"]
TESTDATA = os.environ["DEFORM_TESTDATA"]
STEP = os.path.join(TESTDATA, "face_recognition_sample_part.stp")

results = {"checks": [], "screenshots": [], "error": None, "timings": {}}



def check(name, ok, detail=""):
    results["checks"].append({"name": name, "ok": bool(ok), "detail": str(detail)})
    return bool(ok)


def dump():
    with open(RESULT, "w") as f:
        json.dump(results, f, indent=1)


def process(seconds=0.0):
    end = time.time() + seconds
    while True:
        QtGui.QApplication.processEvents()
        if time.time() >= end:
            return
        time.sleep(0.01)


def wait(condition, timeout=30.0):
    end = time.time() + timeout
    while time.time() < end:
        QtGui.QApplication.processEvents()
        try:
            if condition():
                return True
        except Exception:
            pass
        time.sleep(0.02)
    return bool(condition())


def of_type(doc, kind):
    return [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "TYPE", None) == kind]


def panel_form(kind="Stretch"):
    for w in QtGui.QApplication.allWidgets():
        try:
            if w.objectName() == f"Deform{kind}Panel":
                return w
        except RuntimeError:  # FreeCAD 0.20's PySide may list dead wrappers
            continue
    return None


def field(name, kind="Stretch"):
    form = panel_form(kind)
    return form.findChild(QtGui.QWidget, name) if form is not None else None


def type_into(spin_box, text):
    """Type into a QuantitySpinBox the way the keyboard does (through its line edit)."""
    spin_box.setFocus()
    line = spin_box.lineEdit()
    line.selectAll()
    line.setText(text)
    process(0.05)


def press(which):
    """Click the task view's OK or Cancel button.

    Found from the TaskView down by its text: walking up from a button through its
    QDialogButtonBox can meet a stale PySide wrapper ("already deleted") in FreeCAD 0.20.
    Waited for: FreeCAD 1.1 shows the buttons of a dialog opened by a double-click only
    after some events.
    """
    def visible_button():
        """(task view, button): the view's wrapper is kept while the button is used (PySide6
        invalidates a child's wrapper found by findChildren when its parent's goes)."""
        for view in QtGui.QApplication.allWidgets():
            try:
                if view.metaObject().className() != "Gui::TaskView::TaskView":
                    continue
                buttons = [b for b in view.findChildren(QtGui.QPushButton)
                           if b.isVisible() and b.text().replace("&", "") == which]
            except RuntimeError:
                continue
            if buttons:
                return view, buttons[0]
        return None

    if not wait(lambda: visible_button() is not None, 10):
        raise RuntimeError(f"no {which} button in the task view")
    _view, button = visible_button()
    button.click()
    return wait(lambda: not Gui.Control.activeDialog(), 60)


def screenshot(name):
    view = Gui.ActiveDocument.ActiveView
    process(0.2)  # FreeCAD 1.0 shows a recompute's result only after the events: fit after
    view.viewIsometric()
    for _ in range(2):  # and its first fit may still see the old bounding box
        view.fitAll()
        process(0.3)
    path = os.path.join(OUT, name)
    view.saveImage(path, 1000, 750, "White")
    results["screenshots"].append(path)


def same_placement(a, b, tol=1e-9):
    return all(a.multVec(v).isEqual(b.multVec(v), tol) for v in
               (App.Vector(0, 0, 0), App.Vector(1, 0, 0), App.Vector(0, 1, 0), App.Vector(0, 0, 1)))


def menu_texts(title="Deform"):
    for menu in Gui.getMainWindow().menuBar().findChildren(QtGui.QMenu):
        try:
            if menu.title().replace("&", "") == title:
                return [a.text().replace("&", "") for a in menu.actions()]
        except RuntimeError:
            continue
    return None


def panel_texts(kind):
    """The labels a panel shows: QLabel texts, group-box titles and check-box texts."""
    form = panel_form(kind)
    texts = {w.text() for w in form.findChildren(QtGui.QLabel)}
    texts |= {w.title() for w in form.findChildren(QtGui.QGroupBox)}
    texts |= {w.text() for w in form.findChildren(QtGui.QCheckBox)}
    return texts


def angle_done(obj, degrees):
    return abs(obj.Angle.Value - degrees) < 1e-9 and "Touched" not in obj.State


def settled(obj):
    return "Touched" not in obj.State


def direction(placement):
    return placement.Rotation.multVec(App.Vector(0, 0, 1))


def distance_to_line(point, line_point, line_direction):
    return (point - line_point).cross(App.Vector(line_direction).normalize()).Length


def edge_name(shape, test):
    return next(f"Edge{i + 1}" for i, e in enumerate(shape.Edges) if test(e))


def error_shown(kind, word):
    label = field("ErrorLabel", kind)
    return label is not None and label.isVisible() and word in label.text()


def no_error(kind):
    label = field("ErrorLabel", kind)
    return label is not None and not label.isVisible()


def open_panel(cls_name):
    """The open task panel object (Python) of that class: FreeCAD hands back only its form."""
    import gc
    return next((o for o in gc.get_objects() if type(o).__name__ == cls_name
                 and not getattr(o, "closed", True)), None)


def click_3d(point):
    """A left click in the active 3D view where `point` shows, as the mouse makes it."""
    view = Gui.ActiveDocument.ActiveView
    x, y = view.getPointOnScreen(App.Vector(point))  # device pixels from the bottom left
    target = view.graphicsView().viewport()
    scale = target.devicePixelRatioF()  # Qt positions are device-independent pixels
    pos = QtCore.QPointF(x / scale, (view.getSize()[1] - 1 - y) / scale)
    for kind, buttons in ((QtCore.QEvent.MouseButtonPress, QtCore.Qt.LeftButton),
                          (QtCore.QEvent.MouseButtonRelease, QtCore.Qt.NoButton)):
        event = QtGui.QMouseEvent(kind, pos, QtCore.Qt.LeftButton, buttons, QtCore.Qt.NoModifier)
        QtGui.QApplication.sendEvent(target, event)
        process(0.05)


def show_all():
    """The active view isometric and fitted to the document's shapes; returns the view."""
    view = Gui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    process(0.2)
    return view


def check_gate(cmd, label, obj, sub, what):
    """The command is inactive with nothing or the whole object selected, and active with
    its element `sub` (described as `what`) selected."""
    Gui.Selection.clearSelection()
    check(f"{label}: inactive with nothing selected", not cmd.isActive())
    Gui.Selection.addSelection(obj)
    check(f"{label}: inactive with the whole object", not cmd.isActive())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(obj.Document.Name, obj.Name, sub)
    check(f"{label}: active with {what} selected", cmd.isActive())


def drag_3d(point, moves, modifiers=QtCore.Qt.NoModifier, during=None):
    """A left drag in the active 3D view, as the mouse makes it (see click_3d): press where
    `point` shows (with `modifiers` held), move by each (dx, dy) of `moves` (pixels from the
    press, y up) in turn, the events processed after each, release at the last. `during`
    runs before the release. Returns (the release's pixel, seconds each move took)."""
    # a press soon after another click is held back by FreeCAD's navigation until its
    # release (it may be a double-click's second press): no drag would show meanwhile
    process(QtGui.QApplication.doubleClickInterval() / 1000.0 + 0.05)
    view = Gui.ActiveDocument.ActiveView
    x0, y0 = view.getPointOnScreen(App.Vector(point))
    target = view.graphicsView().viewport()
    scale = target.devicePixelRatioF()
    height = view.getSize()[1]

    def send(kind, dx, dy, button, buttons, mods=QtCore.Qt.NoModifier):
        pos = QtCore.QPointF((x0 + dx) / scale, (height - 1 - y0 - dy) / scale)
        QtGui.QApplication.sendEvent(target, QtGui.QMouseEvent(kind, pos, button, buttons, mods))

    left, none = QtCore.Qt.LeftButton, QtCore.Qt.NoButton
    send(QtCore.QEvent.MouseButtonPress, 0, 0, left, left, modifiers)
    process(0.05)
    times = []
    for dx, dy in moves:
        start = time.perf_counter()
        send(QtCore.QEvent.MouseMove, dx, dy, none, left)
        QtGui.QApplication.processEvents()  # the view redraws (Coin schedules it)
        times.append(time.perf_counter() - start)
    if during is not None:
        during()
    send(QtCore.QEvent.MouseButtonRelease, dx, dy, left, none)
    process(0.05)
    return (x0 + dx, y0 + dy), times


def on_shape(shape, point, tol=1e-6):
    import Part
    return shape.distToShape(Part.Vertex(App.Vector(point)))[0] < tol
