"""The headless feature tests, for FreeCAD's own runner: `freecadcmd -t TestDeformApp`."""
import importlib.util
import os
import sys
import unittest

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)


def _load(name):
    spec = importlib.util.spec_from_file_location(
        f"deform_{name}", os.path.join(_HERE, "tests", "features", f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_tests(loader, tests, pattern):
    suite = unittest.TestSuite()
    for name in ("test_stretch", "test_bend_twist"):
        suite.addTests(loader.loadTestsFromModule(_load(name)))
    return suite
