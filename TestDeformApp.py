"""The headless feature tests, for FreeCAD's own runner: `freecadcmd -t TestDeformApp`.
Every unittest TestCase under deform_tests/features is found, so the list is never kept by
hand; the package is named deform_tests so that it meets no other add-on's `tests` in Mod/.
`freecadcmd -t TestDeformApp.quick` runs a few of them (see quick)."""
import os
import sys
import unittest

_HERE = os.path.dirname(os.path.realpath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)


def load_tests(loader, tests, pattern):
    return loader.discover(os.path.join(_HERE, "deform_tests", "features"),
                           pattern="test_*.py", top_level_dir=_HERE)


# one module or more per feature, about half a minute in all
QUICK = ("test_stretch", "test_bend_twist", "test_area_constrain", "test_dimension_drive",
         "test_ops_push_area_dimension", "test_convert", "test_voids")


def quick():
    """The QUICK modules' tests: CI's check that FreeCAD's runner finds the add-on in Mod/
    and runs its tests (pytest runs them all; all 231 again under this runner took 4.3
    minutes beside other jobs, 3.1 of CPU)."""
    loader = unittest.defaultTestLoader
    return unittest.TestSuite(loader.loadTestsFromName(f"deform_tests.features.{name}")
                              for name in QUICK)
