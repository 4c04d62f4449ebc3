"""Widgets the Deform task panels share (the fields bound to single properties are in
bindings.py).

PlacementGroup shows a Placement property that stands for a point and a direction (Plane:
origin and normal; Axis: point and direction) with Pick and Flip buttons; results_box shows
read-only output properties. Widgets carry object names made from the property names
(PlaneOriginX, AxisDirectionZ, PickAxis, VolumeChange, ...) so tests and macros find them.
"""
import math

import FreeCAD as App
from PySide import QtGui

from ..geometry.errors import DeformError
from ..shapes.convert import plane_placement
from .bindings import on_value_changed, quantity_spin_box, set_spin_value, spin_value

Z = App.Vector(0, 0, 1)


def direction_of(placement):
    """The local Z of a Placement: a plane's normal, an axis's direction."""
    return placement.Rotation.multVec(Z)


class PlacementGroup:
    """A group box titled with the property name: point x, y, z (lengths with units and
    expressions), direction x, y, z (any length, normalized when set) and Pick / Flip.

    The owner connects the handlers with connect() and shows values with show(); value()
    reads the fields back as a Placement whose Base is the point and local Z the direction.
    """

    def __init__(self, prop, point, direction, tooltip, pick_text, pick_tip, flip_tip):
        self.prop = prop
        self.point_title, self.direction_title = point, direction
        self.box = QtGui.QGroupBox(prop)
        self.box.setObjectName(prop + "Group")
        self.box.setToolTip(tooltip)
        grid = QtGui.QGridLayout(self.box)
        self.point = [quantity_spin_box("mm", name=f"{prop}{point}{c}") for c in "XYZ"]
        self.direction = []
        for c in "XYZ":
            box = QtGui.QDoubleSpinBox()
            box.setObjectName(f"{prop}{direction}{c}")
            box.setRange(-1.0, 1.0)  # any length: the direction is normalized when set
            box.setDecimals(6)
            box.setSingleStep(0.1)
            self.direction.append(box)
        for first_row, title, boxes in ((0, point, self.point), (3, direction, self.direction)):
            grid.addWidget(QtGui.QLabel(title), first_row, 0)
            for i, (c, box) in enumerate(zip("xyz", boxes)):
                grid.addWidget(QtGui.QLabel(c), first_row + i, 1)
                grid.addWidget(box, first_row + i, 2, 1, 2)
        self.pick_button = QtGui.QPushButton(pick_text)
        self.pick_button.setObjectName("Pick" + prop)
        self.pick_button.setToolTip(pick_tip)
        self.flip_button = QtGui.QPushButton("Flip")
        self.flip_button.setObjectName("Flip" + prop)
        self.flip_button.setToolTip(flip_tip)
        grid.addWidget(self.pick_button, 6, 0, 1, 3)
        grid.addWidget(self.flip_button, 6, 3)
        grid.setColumnStretch(2, 1)

    def connect(self, on_edited, on_pick, on_flip):
        for box in self.point:
            on_value_changed(box, on_edited)
        for box in self.direction:
            box.valueChanged.connect(on_edited)
        self.pick_button.clicked.connect(on_pick)
        self.flip_button.clicked.connect(on_flip)

    def show(self, placement):
        for box, value in zip(self.point, placement.Base):
            set_spin_value(box, value)
        for box, value in zip(self.direction, direction_of(placement)):
            box.setValue(value)

    def value(self, current):
        """The Placement the fields show. While the direction equals `current`'s, the
        rotation about it is kept (a plane's in-plane orientation)."""
        point = App.Vector(*(spin_value(b) for b in self.point))
        direction = App.Vector(*(b.value() for b in self.direction))
        if direction.Length < 1e-12:
            raise DeformError(f"{self.prop} {self.direction_title.lower()} is zero; give "
                              f"{self.prop} a direction.", self.prop)
        if direction.normalize().isEqual(direction_of(current), 1e-9):
            return App.Placement(point, current.Rotation)
        return plane_placement((point, direction), self.prop)

    def setEnabled(self, enabled):
        self.box.setEnabled(enabled)

    def set_fields_enabled(self, enabled):
        """Enable or disable the value fields and Flip, keeping Pick usable."""
        for widget in self.point + self.direction + [self.flip_button]:
            widget.setEnabled(enabled)


def results_box(obj, names):
    """(a "Result" group with one read-only line per output property of `obj`, each named
    after it, its tooltip the property's documentation; {name: line})."""
    box = QtGui.QGroupBox("Result")
    form = QtGui.QFormLayout(box)
    lines = {}
    for name in names:
        line = QtGui.QLineEdit()
        line.setObjectName(name)
        line.setReadOnly(True)
        line.setToolTip(obj.getDocumentationOfProperty(name))
        form.addRow(name, line)
        lines[name] = line
    return box, lines


def pick_list(obj, prop, height):
    """(group, its grid, list widget): the list of what was picked for the list property
    `prop` (Poles, Regions), named and explained as the property is."""
    box = QtGui.QGroupBox(prop)
    box.setObjectName(prop + "Group")
    box.setToolTip(obj.getDocumentationOfProperty(prop))
    grid = QtGui.QGridLayout(box)
    items = QtGui.QListWidget()
    items.setObjectName(prop)
    items.setMaximumHeight(height)
    return box, grid, items


def pick_toggle(text, name, tip, toggled):
    """(check button that turns picking in the 3D view on and off, the hint label beside
    it)."""
    button = QtGui.QPushButton(text)
    button.setObjectName(name)
    button.setCheckable(True)
    button.setToolTip(tip)
    button.toggled.connect(toggled)
    hint = QtGui.QLabel()
    hint.setObjectName("PickHint")
    hint.setWordWrap(True)
    return button, hint


def show_texts(lines, texts):
    """Put texts[name] into lines[name], each shown from its start."""
    for name, text in texts.items():
        lines[name].setText(text)
        lines[name].setCursorPosition(0)


def length_text(value):
    """A length in the user's unit, "no limit" for an infinite one."""
    if math.isinf(value):
        return "no limit"
    return App.Units.Quantity(value, App.Units.Length).UserString
