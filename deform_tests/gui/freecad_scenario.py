"""Runs inside the real FreeCAD GUI (started by test_gui.py under xvfb-run).

It drives the Deform workbench the way a user does, one part per feature (the modules
scenario_*.py, on the harness in harness.py): selection, toolbar command, typing into the
task panel, OK / Cancel buttons, Undo, double-click, drags in the 3D view, save and
reopen. Every check lands in a JSON file (DEFORM_GUI_RESULT); the pytest side asserts on
it. The script ends FreeCAD with os._exit, also when something goes wrong.

DEFORM_GUI_ONLY (optional) names the parts to run, e.g. "stretch,taper" (stretch first:
it activates the workbench).
"""
import os
import sys
import traceback

import FreeCADGui as Gui
from PySide import QtCore

sys.path.insert(0, os.path.join(os.environ["DEFORM_REPO"], "deform_tests", "gui"))
import harness  # noqa: E402
import scenario_area_constrain  # noqa: E402
import scenario_bend_twist  # noqa: E402
import scenario_dimension_drive  # noqa: E402
import scenario_direct_push  # noqa: E402
import scenario_handles  # noqa: E402
import scenario_stretch  # noqa: E402
import scenario_taper  # noqa: E402

PARTS = {
    "stretch": scenario_stretch.stretch,
    "bend_twist": scenario_bend_twist.bend_twist,
    "taper": lambda: scenario_taper.taper(harness),
    "handles": lambda: scenario_handles.handles(harness),
    "dimension_drive": scenario_dimension_drive.dimension_drive,
    "area_constrain": scenario_area_constrain.area_constrain,
    "direct_push": scenario_direct_push.direct_push,
}


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
    finally:
        harness.dump()
        sys.stdout.flush()
        os._exit(code)


# Run once the event loop is up, as a user would.
QtCore.QTimer.singleShot(200, run)
