"""The headless feature tests, for FreeCAD's own runner: `freecadcmd -t TestDeformApp`."""
import os
import sys
import unittest

_HERE = os.path.dirname(os.path.realpath(__file__))
if sys.path[0] != _HERE:
    sys.path.insert(0, _HERE)  # ours first: `tests` is a common package name

from tests.features import (test_area_constrain, test_bend_twist,  # noqa: E402
                            test_dimension_drive, test_direct_push, test_flex, test_stretch,
                            test_reliability, test_voids)


def load_tests(loader, tests, pattern):
    suite = unittest.TestSuite()
    for module in (test_stretch, test_bend_twist, test_dimension_drive, test_area_constrain,
                   test_direct_push, test_voids, test_reliability, test_flex):
        suite.addTests(loader.loadTestsFromModule(module))
    return suite
