"""Runs inside the real FreeCAD GUI (started by test_gui.py under xvfb-run).

It drives the Deform workbench the way a user does, one part per feature (the modules
scenario_*.py, on the harness in harness.py): selection, toolbar command, typing into the
task panel, OK / Cancel buttons, Undo, double-click, drags in the 3D view, save and
reopen. Every check lands in a JSON file (DEFORM_GUI_RESULT); the pytest side asserts on
it. The script ends FreeCAD with os._exit, also when something goes wrong.

DEFORM_GUI_ONLY (optional) names the parts to run, e.g. "stretch,taper" (stretch first:
it activates the workbench).
"""
import importlib
import inspect
import os
import sys
import traceback

import FreeCADGui as Gui
from PySide import QtCore

from freecad_deform import registry

sys.path.insert(0, os.path.join(os.environ["DEFORM_REPO"], "deform_tests", "gui"))
import harness  # noqa: E402


def part(name):
    """scenario_<name>.<name>, given the harness when it takes an argument."""
    function = getattr(importlib.import_module("scenario_" + name), name)
    return (lambda: function(harness)) if inspect.signature(function).parameters else function


# The features' and tools' parts in the registry's order (stretch first: it activates the workbench).
PARTS = {name: part(name) for name in registry.SCENARIOS}


def registry_agrees():
    """The toolbar, the menu and the registered commands are the registry's, with its icons
    (once the workbench was activated)."""
    from PySide import QtGui
    toolbar = Gui.getMainWindow().findChild(QtGui.QToolBar, "Deform")
    if toolbar is None:
        return
    texts = [a.text().replace("&", "") for a in toolbar.actions()]
    harness.check("registry: toolbar and menu are its commands, in order",
                  texts == [t.menu_text for t in registry.TOOLBAR] == harness.menu_texts(),
                  texts)
    infos = [Gui.Command.get(t.command) for t in registry.TOOLBAR]
    harness.check("registry: every command registered, with its icon",
                  all(c is not None and c.getInfo()["pixmap"].endswith(t.icon + ".svg")
                      for c, t in zip(infos, registry.TOOLBAR)),
                  [c and c.getInfo()["pixmap"] for c in infos])


def run():
    code = 0
    try:
        only = os.environ.get("DEFORM_GUI_ONLY")
        for name, part in PARTS.items():
            if only and name not in only.split(","):
                continue
            try:  # one failing part does not hide the others' checks
                part()
            except Exception:
                harness.results["error"] = (harness.results["error"] or "") + \
                    traceback.format_exc()
                code = 1
                if Gui.Control.activeDialog():  # leave no dialog open for the next part
                    Gui.Control.closeDialog()
        registry_agrees()
    finally:
        harness.dump()
        sys.stdout.flush()
        os._exit(code)


# Run once the event loop is up, as a user would.
QtCore.QTimer.singleShot(200, run)
