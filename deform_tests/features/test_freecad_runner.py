"""The feature tests also pass under FreeCAD's own runner, with the add-on found in Mod/:
TestDeformApp.quick, a few modules (pytest runs every one of them already)."""
import os
import subprocess
import tempfile

from .fc import REPO

import TestDeformApp  # noqa: E402  (the repository is on sys.path)


def test_freecadcmd_runs_the_registered_tests():
    home = tempfile.mkdtemp()
    for mod in (".local/share/FreeCAD/Mod", ".FreeCAD/Mod"):
        os.makedirs(os.path.join(home, mod))
        os.symlink(REPO, os.path.join(home, mod, "freecad_deform"))
    run = subprocess.run(["freecadcmd", "-t", "TestDeformApp.quick"], cwd=home,
                         capture_output=True, encoding="utf-8", errors="replace", timeout=600,
                         env=dict(os.environ, HOME=home))
    out = run.stdout + run.stderr
    count = TestDeformApp.quick().countTestCases()
    assert count > 50 and f"Ran {count} tests" in out and "\nOK" in out, out[-3000:]
