"""GUI layer: commands, view providers and task panels; imported only with the GUI up.

This module itself stays light (no Qt, no FreeCADGui) because InitGui.py reads icon
paths from it while FreeCAD starts.

A new feature plugs in through its entry in freecad_deform/registry.py (the checklist is
that module's docstring): its icon is resources/icons/<TYPE>.svg (TYPE is the proxy's TYPE,
e.g. "Stretch"), its task panel class <TYPE>Panel in gui/<type>_panel.py (built from
task_panel.TaskPanelBase, bindings.py, widgets.py and coin_nodes.py), its command class
<TYPE>Command(commands.CommandBase) in gui/commands.py.
"""
import os

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPO_DIR = os.path.dirname(PACKAGE_DIR)
RESOURCES_DIR = os.path.join(REPO_DIR, "resources")
ICONS_DIR = os.path.join(RESOURCES_DIR, "icons")
UI_DIR = os.path.join(RESOURCES_DIR, "ui")


def icon_path(name):
    """Absolute path of resources/icons/<name>.svg; the workbench icon if there is none."""
    path = os.path.join(ICONS_DIR, name + ".svg")
    return path if os.path.isfile(path) else os.path.join(ICONS_DIR, "Deform.svg")
