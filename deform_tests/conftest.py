"""pytest set-up: the repo on sys.path and FreeCAD's Python modules importable (Debian paths)."""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
sys.path.insert(0, REPO)
for path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)

try:
    from hypothesis import settings
except ImportError:  # the FreeCAD-only runs do not need it
    settings = None
if settings is not None:
    # CI replays the same examples every run (no flaky red builds); locally they vary
    settings.register_profile("ci", derandomize=True, deadline=None)
    settings.load_profile("ci" if os.environ.get("CI") else "default")
