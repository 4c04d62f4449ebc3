"""Shared set-up of the headless FreeCAD tests: import FreeCAD (never skip), find the test data."""
import contextlib
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


RAISED = {}  # object name -> the exception its feature's last execute raised


@contextlib.contextmanager
def recorded_errors():
    """Keep in RAISED the exception each feature's execute raises (FreeCAD keeps only its
    text), so that a refusal (a DeformError, with its prop) is told apart from a crash."""
    from freecad_deform import api  # noqa: F401  (loads every feature class)
    from freecad_deform.features.base import DeformFeature
    classes, todo = [], [DeformFeature]
    while todo:
        cls = todo.pop()
        classes.append(cls)
        todo += cls.__subclasses__()
    saved = {cls: cls.__dict__["execute"] for cls in classes if "execute" in cls.__dict__}

    def wrap(fn):
        def execute(self, obj):
            RAISED.pop(obj.Name, None)
            try:
                return fn(self, obj)
            except BaseException as exc:
                RAISED[obj.Name] = exc
                raise
        return execute

    for cls, fn in saved.items():
        cls.execute = wrap(fn)
    try:
        yield RAISED
    finally:
        for cls, fn in saved.items():
            cls.execute = fn
