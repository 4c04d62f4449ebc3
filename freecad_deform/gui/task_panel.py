"""TaskPanelBase: the live-preview task panel every Deform feature's panel derives from.

Life of a panel:
- Creating (a command): the command opened a persistent transaction, hid the Base and
  created the object in it; the panel gets that transaction's id. OK commits it (one
  undo step), Cancel aborts it: the object disappears and the Base shows again.
- Editing (double-click, setEdit): the panel remembers the editable properties (and their
  expressions) and opens its own transaction "Edit <TYPE>". OK commits it, Cancel puts the
  old values back and aborts it.
Every change in a field sets the property at once (apply / set_property) and recomputes
shortly after (a short timer merges fast typing into one recompute), so the user sees the
result while editing. Errors go to a red label in the panel, never to a dialog, and the
field of the property a refusal names is outlined (mark_field).
"""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from . import icon_path
from .bindings import SET_ERRORS, bound_quantity, number, on_value_changed, set_spin_value, \
    spin_value

ERROR_COLOR = "#c00000"
ERROR_STYLE = f"QLabel {{ color: {ERROR_COLOR}; font-weight: bold; }}"


def is_invalid(obj):
    state = obj.State
    return "Invalid" in state or "Error" in state


class TaskPanelBase:
    """Subclasses set TYPE (and TITLE) and EDITABLE, and implement build(layout) and
    load(); their fields come from add_quantity() and bindings.py, their handlers call
    set_property() or apply(), which set and preview."""

    TYPE = "Deform"
    TITLE = None              # defaults to TYPE
    EDITABLE = ()             # properties Cancel restores when editing an existing object
    PREVIEW_DELAY_MS = 150

    def __init__(self, obj, transaction=None, created=False, restore_visibility=None):
        self.obj = obj
        self.doc = obj.Document
        self.created = created
        self.restore_visibility = dict(restore_visibility or {})
        self.closed = False
        self._loading = False
        self.quantities = {}  # property -> (QuantitySpinBox, ExpressionBinding)
        self.labels = {}      # property -> its QLabel in a form
        if created:
            self.transaction = transaction
            self.saved = None
        else:
            self.saved = self._snapshot()
            # Persistent: the transaction outlives the double-click / command that opened us.
            self.transaction = App.setActiveTransaction(f"Edit {self.TYPE}", True) or None

        self._timer = QtCore.QTimer()
        self._timer.setSingleShot(True)
        self._timer.setInterval(self.PREVIEW_DELAY_MS)
        self._timer.timeout.connect(self.recompute)

        self.form = QtGui.QWidget()
        self.form.setObjectName(f"Deform{self.TYPE}Panel")
        self.form.setWindowTitle(self.TITLE or self.TYPE)
        self.form.setWindowIcon(QtGui.QIcon(icon_path(self.TYPE)))
        layout = QtGui.QVBoxLayout(self.form)
        self._loading = True  # a field's range set while building emits no edit
        try:
            self.build(layout)
        finally:
            self._loading = False
        self.error_label = QtGui.QLabel()
        self.error_label.setObjectName("ErrorLabel")
        self.error_label.setStyleSheet(ERROR_STYLE)
        self.error_label.setWordWrap(True)
        self.error_label.hide()
        layout.addWidget(self.error_label)
        layout.addStretch(1)
        self.reload()
        self.update_status()

    # --- for subclasses ---------------------------------------------------------------------
    def build(self, layout):
        """Add the fields to `layout` (a QVBoxLayout)."""

    def load(self):
        """Show the object's property values in the fields (signals are ignored meanwhile)."""

    def show_results(self):
        """Show the output properties after a successful recompute."""

    def clear_results(self):
        """Blank the output fields while the object is in error (they would be stale)."""

    # --- live preview -----------------------------------------------------------------------
    def reload(self):
        self._loading = True
        try:
            self.load()
        finally:
            self._loading = False

    def apply(self, change, *args):
        """A field was edited: run change(*args) (it sets properties), then schedule the
        preview. A refusal goes to the panel; False then, or while loading or closed."""
        if self._loading or self.closed:
            return False
        try:
            change(*args)
        except SET_ERRORS as e:
            self.refuse(e)
            return False
        self.schedule_recompute()
        return True

    def refuse(self, error):
        """Show a refused edit; a DeformError's property gets its field outlined."""
        self.show_error(str(error))
        if getattr(error, "prop", None):
            self.mark_field(error.prop)

    def set_property(self, name, value):
        """Set obj.<name> from a field and schedule the preview; errors go to the panel."""
        return self.apply(setattr, self.obj, name, value)

    # --- quantity fields ----------------------------------------------------------------------
    def add_quantity(self, form, prop, unit, minimum=-1e9, maximum=1e9):
        """A QuantitySpinBox named and labelled `prop` in `form`, bound to the property
        (bindings.bound_quantity: units, expressions); an edit calls on_quantity(prop)."""
        box, binding = bound_quantity(self.obj, prop, unit, minimum, maximum)
        self.quantities[prop] = (box, binding)
        on_value_changed(box, lambda *_: self.on_quantity(prop))
        self.labels[prop] = QtGui.QLabel(prop)  # made here: one Qt makes may come back dead
        form.addRow(self.labels[prop], box)
        return box

    def load_quantities(self):
        for prop, (box, _) in self.quantities.items():
            set_spin_value(box, number(getattr(self.obj, prop)))

    def on_quantity(self, prop):
        if not self._loading:
            self.quantity_edited(prop, *self.quantities[prop])

    def quantity_edited(self, prop, box, binding):
        """A QuantitySpinBox for `prop` was edited: an expression on it drives the property
        (recompute only); else a changed value is set."""
        if binding.hasExpression():
            self.schedule_recompute()
            return
        value = spin_value(box)
        if abs(value - number(getattr(self.obj, prop))) > 1e-12:
            self.set_property(prop, value)

    def schedule_recompute(self):
        if not self._loading and not self.closed:
            self._timer.start()

    def recompute(self):
        """Recompute now and show the outcome."""
        self._timer.stop()
        if self.closed:
            return
        try:
            self.doc.recompute()
        except RuntimeError as e:  # feature errors land in the object; this is the document's
            self.show_error(str(e))
            return
        self.update_status()

    def flush(self):
        """Run a pending preview now (before OK, or when a caller needs the result)."""
        if self._timer.isActive() or "Touched" in self.obj.State:
            self.recompute()

    def update_status(self):
        if is_invalid(self.obj):
            self.show_error(self.obj.getStatusString())
            self.mark_field(getattr(getattr(self.obj, "Proxy", None), "error_prop", None))
            self.clear_results()
        else:
            self.show_error(None)
            self.mark_field(None)
            self.show_results()

    def mark_field(self, prop):
        """Outline in red the field (or group) of the property a refusal names; clear the
        last one. A field is named after its property (a group: property + "Group")."""
        old = getattr(self, "_marked", None)
        if old is not None:
            try:
                old.setStyleSheet("")
                old.setProperty("deformError", False)
            except RuntimeError:   # its widget is gone
                pass
        self._marked = None
        if not prop:
            return
        widget = self.form.findChild(QtGui.QWidget, prop) or \
            self.form.findChild(QtGui.QWidget, prop + "Group")
        if widget is not None:
            widget.setStyleSheet(f"#{widget.objectName()} {{ border: 2px solid {ERROR_COLOR}; }}")
            widget.setProperty("deformError", True)
            self._marked = widget

    def show_error(self, message):
        if message:
            self.error_label.setText(message)
            self.error_label.show()
        else:
            self.error_label.clear()
            self.error_label.hide()

    # --- OK / Cancel --------------------------------------------------------------------------
    def accept(self):
        self.flush()
        if is_invalid(self.obj):
            self.show_error(self.obj.getStatusString() + "\nFix it, or press Cancel.")
            return False
        if self.transaction:
            App.closeActiveTransaction(False, self.transaction)
        self._close()
        return True

    def reject(self):
        self._timer.stop()
        if self.created:
            self._discard_created()
        else:
            self._restore_saved()
        self._close()
        return True

    def _discard_created(self):
        name = self.obj.Name
        if self.transaction:
            App.closeActiveTransaction(True, self.transaction)
        if self.doc.getObject(name) is not None:  # no transaction of ours to abort
            self.doc.removeObject(name)
        for base_name, visible in self.restore_visibility.items():
            base = self.doc.getObject(base_name)
            if base is not None and base.ViewObject is not None:
                base.ViewObject.Visibility = visible
        self.doc.recompute()

    def _snapshot(self):
        values = {name: getattr(self.obj, name) for name in self.EDITABLE}
        return values, list(self.obj.ExpressionEngine)

    def _restore_saved(self):
        values, expressions = self.saved
        for path, _ in list(self.obj.ExpressionEngine):
            self.obj.setExpression(path, None)
        for name, value in values.items():
            try:
                setattr(self.obj, name, value)
            except SET_ERRORS as e:
                App.Console.PrintWarning(f"Could not restore {name}: {e}\n")
        for path, expression in expressions:
            self.obj.setExpression(path, expression)
        if self.transaction:
            App.closeActiveTransaction(True, self.transaction)
        self.obj.touch()
        self.doc.recompute()

    def _close(self):
        self.closed = True
        Gui.Control.closeDialog()
        gdoc = Gui.getDocument(self.doc.Name)
        if gdoc is not None and gdoc.getInEdit() is not None:
            gdoc.resetEdit()
