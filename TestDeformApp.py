"""The headless feature tests, for FreeCAD's own runner: `freecadcmd -t TestDeformApp`.
Every unittest TestCase under tests/features is found, so the list is never kept by hand."""
import os
import sys
import unittest

_HERE = os.path.dirname(os.path.realpath(__file__))
if sys.path[0] != _HERE:
    sys.path.insert(0, _HERE)  # ours first: `tests` is a common package name


def load_tests(loader, tests, pattern):
    return loader.discover(os.path.join(_HERE, "tests", "features"), pattern="test_*.py",
                           top_level_dir=_HERE)
