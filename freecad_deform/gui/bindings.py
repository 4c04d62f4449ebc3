"""Property <-> widget bindings of the task panels: one field per property, named after it
(so a refusal naming the property outlines that field, and tests and macros find it), its
tooltip the property's documentation, its value read and shown in the property's unit.
Quantities are Gui::QuantitySpinBox fields with an ExpressionBinding (units, expressions,
the f(x) button).
"""
import FreeCADGui as Gui
from PySide import QtCore, QtGui

# What setting a property from a field may raise: DeformError (a ValueError) or a value the
# property refuses (ValueError: not in an enumeration, TypeError: the wrong type), and
# FreeCAD's Base.FreeCADError (a RuntimeError: a quantity it cannot parse, ...).
SET_ERRORS = (ValueError, TypeError, RuntimeError)


def quantity_spin_box(unit="mm", minimum=-1e9, maximum=1e9, name=None):
    """A Gui::QuantitySpinBox from FreeCAD's UiLoader. FreeCAD 0.20's PySide may hand back
    the dead wrapper of an earlier, deleted widget whose address the new one reuses (a
    RuntimeError on first use); a new one is asked for then (the dead one stays hidden)."""
    for _ in range(20):
        try:
            return _quantity_spin_box(unit, minimum, maximum, name)
        except RuntimeError:
            continue
    return _quantity_spin_box(unit, minimum, maximum, name)


def _quantity_spin_box(unit, minimum, maximum, name):
    box = Gui.UiLoader().createWidget("Gui::QuantitySpinBox")
    box.setProperty("unit", unit)
    box.setProperty("minimum", minimum)
    box.setProperty("maximum", maximum)
    if name:
        box.setObjectName(name)
    return box


def on_value_changed(box, slot):
    """Connect a QuantitySpinBox's valueChanged. The widget comes wrapped as its nearest
    Qt class (QAbstractSpinBox), so the signal is looked up dynamically; the string form
    is the fallback for bindings that do not do that."""
    try:
        box.valueChanged.connect(slot)
    except AttributeError:
        QtCore.QObject.connect(box, QtCore.SIGNAL("valueChanged(double)"), slot)


def spin_value(box):
    """The value of a QuantitySpinBox in its unit's internal scale (mm, deg...)."""
    return float(box.property("rawValue"))


def set_spin_value(box, value):
    box.setProperty("rawValue", float(value))


def number(value):
    """A property's value as a float: a Quantity's Value, or the float itself."""
    return float(getattr(value, "Value", value))


def bound_quantity(obj, prop, unit, minimum=-1e9, maximum=1e9):
    """(QuantitySpinBox named `prop`, its ExpressionBinding to obj.<prop>)."""
    box = quantity_spin_box(unit, minimum, maximum, name=prop)
    box.setMinimumWidth(70)
    box.setToolTip(obj.getDocumentationOfProperty(prop))
    binding = Gui.ExpressionBinding(box)
    binding.bind(obj, prop)
    return box, binding


def check_box(obj, prop):
    """A QCheckBox labelled and named `prop`, for a bool property."""
    box = QtGui.QCheckBox(prop)
    box.setObjectName(prop)
    box.setToolTip(obj.getDocumentationOfProperty(prop))
    return box


def combo_box(obj, prop):
    """A QComboBox named `prop` with the enumeration property's values."""
    combo = QtGui.QComboBox()
    combo.setObjectName(prop)
    combo.addItems(obj.getEnumerationsOfProperty(prop))
    combo.setToolTip(obj.getDocumentationOfProperty(prop))
    return combo


def int_spin_box(obj, prop, minimum, maximum):
    """A QSpinBox named `prop`, for an integer property."""
    box = QtGui.QSpinBox()
    box.setObjectName(prop)
    box.setRange(minimum, maximum)
    box.setToolTip(obj.getDocumentationOfProperty(prop))
    return box


def show_combo(combo, text):
    """Select `text` in `combo` (the first entry when it is not there)."""
    combo.setCurrentIndex(max(0, combo.findText(text)))
