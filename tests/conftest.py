"""pytest set-up: the repo on sys.path and FreeCAD's Python modules importable (Debian paths)."""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
sys.path.insert(0, REPO)
for path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)
