"""Shared set-up of the headless FreeCAD tests: import FreeCAD (never skip), find the test data."""
import os
import sys

for path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if path not in sys.path and os.path.isdir(path):
        sys.path.append(path)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
if REPO not in sys.path:
    sys.path.insert(0, REPO)

import FreeCAD as App  # noqa: E402  (a missing FreeCAD must fail the run, not skip it)

TESTDATA = os.environ.get("DEFORM_TESTDATA",
                          os.path.join(os.path.dirname(REPO), "shared", "testdata"))


def testdata(name):
    path = os.path.join(TESTDATA, name)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"test model {path} is missing; set DEFORM_TESTDATA")
    return path


def new_document(name="DeformTest"):
    doc = App.newDocument(name)
    doc.UndoMode = 1
    return doc
