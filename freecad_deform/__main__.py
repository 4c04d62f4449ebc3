"""`python3 -m freecad_deform {run,sweep,solve} ...`: batch runs (see --help).

Inside FreeCAD's console: `freecadcmd freecad_deform/batch/freecadcmd.py -- sweep ...`
(freecadcmd does not run a file called __main__.py)."""
import sys

from freecad_deform.batch.cli import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
