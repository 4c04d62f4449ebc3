"""Goal seek in the GUI: the Solve command and its task panel.

The user picks the property to vary (Object.Property) and its bounds, the output to hit
(an output property such as VolumeChange, Achieved or AchievedArea, or an attribute path such
as Stretch.Shape.BoundBox.XLength) and a target, or asks for its least or greatest value.
Solve runs freecad_deform.batch.solve (Brent, bounded least squares, bounded search) on
the document, listing each recompute with its value and output; the panel shows the
iterations and the residual. Every change the search makes lands in one transaction, so
OK leaves one undo step ("Goal seek") from the old value to the found one and Cancel puts
the old value back.
"""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

from .. import registry
from ..batch import model
from ..batch.solve import solve
from ..geometry.errors import DeformError
from .commands import CommandBase

GOALS = ("Target", "Minimize", "Maximize")
PREFERRED = ("VolumeChange", "Achieved", "AchievedArea", "Shape.Volume")  # preset output
SHAPE_OUTPUTS = ("Shape.Volume", "Shape.BoundBox.XLength", "Shape.BoundBox.YLength",
                 "Shape.BoundBox.ZLength")


def _number(value):
    """A float from a float, an int or a Quantity; None for anything else."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return float(value)
    return float(value.Value) if hasattr(value, "Value") and hasattr(value, "Unit") else None


def is_deform(obj):
    """A Deform feature object (its proxy's TYPE is in the registry)."""
    return registry.feature(getattr(getattr(obj, "Proxy", None), "TYPE", None)) is not None


def deform_objects(doc):
    return [o for o in doc.Objects if is_deform(o)]


def candidates(doc):
    """(varied, outputs): "Object.Property" names of the Deform objects' numeric inputs,
    and of their numeric outputs (the Result group) and shape measures."""
    varied, outputs = [], []
    for obj in deform_objects(doc):
        for prop in obj.PropertiesList:
            value = _number(getattr(obj, prop, None))
            if value is None or isinstance(getattr(obj, prop), int):
                continue
            group = obj.getGroupOfProperty(prop)
            if group == "Result":
                outputs.append(f"{obj.Name}.{prop}")
            elif "ReadOnly" not in obj.getPropertyStatus(prop) and group != "Base":
                varied.append(f"{obj.Name}.{prop}")
        if obj.isDerivedFrom("Part::Feature"):
            outputs += [f"{obj.Name}.{path}" for path in SHAPE_OUTPUTS]
    return varied, outputs


class SolvePanel:
    """The goal-seek task panel on `doc`, preset for `obj` (a Deform object) when given."""

    def __init__(self, doc, obj=None):
        self.doc, self.transaction, self.result = doc, None, None
        self.form = QtGui.QWidget()
        self.form.setObjectName("DeformSolvePanel")
        self.form.setWindowTitle("Goal seek")
        layout = QtGui.QFormLayout(self.form)
        varied, outputs = candidates(doc)
        self.vary = self._combo("Vary", varied)
        self.lower, self.upper = self._line("Lower"), self._line("Upper")
        self.output = self._combo("Output", outputs)
        self.goal = QtGui.QComboBox()
        self.goal.setObjectName("Goal")
        self.goal.addItems(list(GOALS))
        self.target = self._line("Target")
        self.run_button = QtGui.QPushButton("Solve")
        self.run_button.setObjectName("Solve")
        self.progress = QtGui.QProgressBar()
        self.progress.setObjectName("Progress")
        self.iterations, self.residual = self._line("Iterations"), self._line("Residual")
        for field in (self.iterations, self.residual):
            field.setReadOnly(True)
        self.log = QtGui.QListWidget()
        self.log.setObjectName("Log")
        self.status = QtGui.QLabel()
        self.status.setObjectName("ErrorLabel")
        self.status.setWordWrap(True)
        for label, widget in (("Vary", self.vary), ("Lower", self.lower), ("Upper", self.upper),
                              ("Output", self.output), ("Goal", self.goal),
                              ("Target", self.target), ("", self.run_button),
                              ("Progress", self.progress), ("Iterations", self.iterations),
                              ("Residual", self.residual), ("Recomputes", self.log),
                              ("", self.status)):
            layout.addRow(label, widget)
        self.goal.currentIndexChanged.connect(self._goal_changed)
        self.run_button.clicked.connect(self.run)
        self._preset(obj, varied, outputs)

    @staticmethod
    def _combo(name, items):
        combo = QtGui.QComboBox()
        combo.setObjectName(name)
        combo.setEditable(True)  # any Object.Property path may be typed
        combo.addItems(items)
        return combo

    @staticmethod
    def _line(name):
        line = QtGui.QLineEdit()
        line.setObjectName(name)
        return line

    def _preset(self, obj, varied, outputs):
        """The selected object's first input and output; bounds around its value."""
        if obj is not None:
            mine = [v for v in varied if v.startswith(obj.Name + ".")]
            outs = [o for o in outputs if o.startswith(obj.Name + ".")]
            if mine:
                self.vary.setCurrentIndex(varied.index(mine[0]))
            outs.sort(key=lambda o: PREFERRED.index(o.split(".", 1)[1])
                      if o.split(".", 1)[1] in PREFERRED else len(PREFERRED))
            if outs:
                self.output.setCurrentIndex(outputs.index(outs[0]))
        try:
            value = model.read_value(self.doc, self.vary.currentText())
            current = model.read_value(self.doc, self.output.currentText())
        except DeformError:
            return
        if isinstance(value, float):
            span = max(abs(value), 1.0)
            self.lower.setText(repr(value - span))
            self.upper.setText(repr(value + span))
        if isinstance(current, float):
            self.target.setText(repr(current))

    def _goal_changed(self):
        self.target.setEnabled(self.goal.currentText() == "Target")

    def _numbers(self):
        try:
            lo, hi = float(self.lower.text()), float(self.upper.text())
        except ValueError:
            raise DeformError("Lower and Upper must be numbers; give the bounds of Vary.",
                              "Lower") from None
        target = None
        if self.goal.currentText() == "Target":
            try:
                target = float(self.target.text())
            except ValueError:
                raise DeformError("Target must be a number; give the value Output must "
                                  "reach.", "Target") from None
        return lo, hi, target

    def _progress(self, count, values, outputs):
        self.log.addItem(f"{count}: {', '.join(f'{v:.12g}' for v in values)} -> "
                         f"{', '.join(f'{o:.12g}' for o in outputs)}")
        self.log.scrollToBottom()
        self.progress.setValue(min(count, self.progress.maximum()))
        self.iterations.setText(str(count))
        QtGui.QApplication.processEvents()

    def run(self):
        """Solve, inside this panel's transaction (opened at the first run)."""
        name, output, goal = self.vary.currentText().strip(), self.output.currentText().strip(), \
            self.goal.currentText()
        self.status.setText("")
        self.log.clear()
        self.progress.setRange(0, 200)
        self.progress.setValue(0)
        try:
            lo, hi, target = self._numbers()
            if self.transaction is None:
                self.transaction = App.setActiveTransaction("Goal seek", True) or None
            kwargs = ({"target": {output: target}} if goal == "Target" else
                      {goal.lower(): output})
            self.run_button.setEnabled(False)
            self.result = solve(self.doc, {name: (lo, hi)}, progress=self._progress, **kwargs)
        except DeformError as e:
            self.status.setText(str(e))
            self.result = None
        finally:
            self.run_button.setEnabled(True)
        if self.result is not None:
            key = "residual" if goal == "Target" else goal.lower()[:3] + "imum"
            self.residual.setText(f"{self.result[key]:.6g}" + ("" if goal == "Target" else
                                                               f" ({key})"))
            self.iterations.setText(str(self.result["iterations"]))
            self.progress.setValue(self.progress.maximum())
            self.status.setText(f"{name} = {self.result[name]!r}")
        if Gui.ActiveDocument is not None:
            Gui.ActiveDocument.ActiveView.fitAll()

    def accept(self):
        """One undo step from the old value to the one found (the last Solve)."""
        if self.transaction is not None:
            App.closeActiveTransaction(False, self.transaction)
        Gui.Control.closeDialog()
        return True

    def reject(self):
        """The document as before the panel: the transaction aborted, recomputed."""
        if self.transaction is not None:
            App.closeActiveTransaction(True, self.transaction)
            self.doc.recompute()
        Gui.Control.closeDialog()
        return True


class SolveCommand(CommandBase):
    """Goal seek on the active document; enabled when it holds a Deform object."""

    def read_selection(self):
        doc = App.ActiveDocument
        if doc is None or not deform_objects(doc):
            return None
        picked = [s.Object for s in Gui.Selection.getSelectionEx()
                  if s.Object.Document == doc and is_deform(s.Object)]
        return doc, (picked[0] if picked else None)

    def Activated(self):
        fits = self.fits()
        if fits is None:
            App.Console.PrintError(f"{self.MENU_TEXT}: {self.TOOL_TIP}\n")
            return
        Gui.Control.showDialog(SolvePanel(*fits))
