"""The feature tests also pass under FreeCAD's own runner, with the add-on found in Mod/."""
import os
import subprocess
import tempfile

from .fc import REPO


def test_freecadcmd_runs_the_registered_tests():
    home = tempfile.mkdtemp()
    for mod in (".local/share/FreeCAD/Mod", ".FreeCAD/Mod"):
        os.makedirs(os.path.join(home, mod))
        os.symlink(REPO, os.path.join(home, mod, "freecad_deform"))
    run = subprocess.run(["freecadcmd", "-t", "TestDeformApp"], cwd=home, capture_output=True,
                         encoding="utf-8", errors="replace", timeout=600,
                         env=dict(os.environ, HOME=home))
    out = run.stdout + run.stderr
    assert "\nOK" in out and "Ran " in out, out[-3000:]
