"""The headless feature tests, for FreeCAD's own runner: `freecadcmd -t TestDeformApp`.
Every unittest TestCase under deform_tests/features is found, so the list is never kept by
hand; the package is named deform_tests so that it meets no other add-on's `tests` in Mod/."""
import os
import sys

_HERE = os.path.dirname(os.path.realpath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)


def load_tests(loader, tests, pattern):
    return loader.discover(os.path.join(_HERE, "deform_tests", "features"),
                           pattern="test_*.py", top_level_dir=_HERE)
