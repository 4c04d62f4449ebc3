"""Finding FreeCAD: Debian installs its Python modules outside Python's own path."""
import os
import sys

FREECAD_PATHS = ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part",
                 "/usr/lib/freecad/lib")


def load_freecad():
    """Import and return the FreeCAD module, adding Debian's FreeCAD folders to sys.path
    first (FREECAD_LIB names another folder). FreeCAD is imported before Part, or Part
    crashes."""
    extra = [os.environ["FREECAD_LIB"]] if os.environ.get("FREECAD_LIB") else []
    for path in (*extra, *FREECAD_PATHS):
        if os.path.isdir(path) and path not in sys.path:
            sys.path.append(path)
    import FreeCAD
    return FreeCAD
