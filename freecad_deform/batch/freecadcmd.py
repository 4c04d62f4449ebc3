"""The command line inside FreeCAD's console, for the add-on installed in a Mod folder
(FreeCAD restores only installed add-ons' objects there):

    freecadcmd /path/to/freecad_deform/batch/freecadcmd.py -- sweep DOC.FCStd --table ...

`--` keeps freecadcmd from reading the options itself. Exits with the command's status."""
import os
import sys
import traceback

if not __package__:  # run as a file by freecadcmd, not imported
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.realpath(__file__)))))
    from freecad_deform.batch.cli import main

    # FreeCAD 0.20 gives [script, "--", args], 1.1 also its own path: take what follows "--"
    # (or else this script)
    argv = sys.argv
    if "--" in argv:
        argv = argv[argv.index("--") + 1:]
    else:
        mine = [i for i, a in enumerate(argv) if a.endswith("freecadcmd.py")]
        argv = argv[mine[0] + 1:] if mine else argv[1:]
    try:  # freecadcmd would print an uncaught error and exit with status 0
        status = main(argv)
    except Exception:
        traceback.print_exc()
        status = 1
    sys.stdout.flush()  # FreeCAD 1.1 exits without flushing Python's buffers
    sys.stderr.flush()
    sys.exit(status)
