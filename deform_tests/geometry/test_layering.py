"""The geometry kernels import without FreeCAD (DESIGN.md layer rule)."""
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))


def test_geometry_imports_without_freecad():
    code = ("import sys, pkgutil, importlib, freecad_deform.geometry as g\n"
            "for m in pkgutil.walk_packages(g.__path__, g.__name__ + '.'): importlib.import_module(m.name)\n"
            "import freecad_deform\n"
            "bad = [m for m in sys.modules if m.split('.')[0] in ('FreeCAD', 'Part', 'Mesh', 'FreeCADGui')]\n"
            "assert not bad, bad\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    subprocess.run([sys.executable, "-c", code], cwd=REPO, env=env, check=True)
