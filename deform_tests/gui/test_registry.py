"""The registry (freecad_deform/registry.py) and what is derived from it agree: the macro API's
exports, the proxies' TYPE, the task panels, the command classes and the icons. The GUI run
(freecad_scenario.py) checks the toolbar and the registered commands in the real FreeCAD."""
import ast
import os
import subprocess
import sys

from deform_tests.features.fc import REPO  # FreeCAD importable (never skipped)

from freecad_deform import registry

PACKAGE = os.path.join(REPO, "freecad_deform")


def classes_in(path):
    """The top-level class names of a module, read without importing it (the GUI modules
    import FreeCADGui)."""
    with open(path, encoding="utf-8") as f:
        tree = ast.parse(f.read())
    return {node.name for node in tree.body if isinstance(node, ast.ClassDef)}


def module_file(dotted):
    return os.path.join(REPO, *dotted.split(".")) + ".py"


def test_registry_imports_without_freecad():
    code = ("import sys, freecad_deform, freecad_deform.registry\n"
            "bad = [m for m in sys.modules if m.split('.')[0] in ('FreeCAD', 'FreeCADGui', 'Part')]\n"
            "assert not bad, bad\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    subprocess.run([sys.executable, "-c", code], cwd=REPO, env=env, check=True)


def test_exports_are_the_registry_api():
    import freecad_deform
    from freecad_deform import api
    assert freecad_deform.__all__ == list(registry.API)
    assert [f.api for f in registry.FEATURES] == [f"make_{f.module}" for f in registry.FEATURES]
    for name in registry.API:
        assert callable(getattr(api, name)), name
        assert getattr(freecad_deform, name) is getattr(api, name)
    public = {n for n in vars(api) if n.startswith("make_")}
    assert public <= set(registry.API), public - set(registry.API)


def test_proxies_have_the_registry_name():
    for feature in registry.FEATURES:
        proxy = registry.load(feature.proxy_class)
        assert proxy.TYPE == feature.name, feature


def test_panels_commands_and_icons_exist():
    names = [t.name for t in registry.TOOLBAR]
    assert len(set(names)) == len(names), names
    assert [t for t in registry.TOOLBAR if isinstance(t, registry.Feature)] == \
        list(registry.FEATURES)
    for tool in registry.TOOLBAR:
        module, _, cls = tool.command_class.rpartition(".")
        assert cls in classes_in(module_file(module)), tool.command_class
        assert os.path.isfile(os.path.join(REPO, "resources", "icons", tool.icon + ".svg")), tool
        assert tool.menu_text and tool.tool_tip, tool
    for feature in registry.FEATURES:
        module, _, cls = feature.panel_class.rpartition(".")
        assert cls in classes_in(module_file(module)), feature.panel_class


def test_no_list_is_kept_by_hand():
    """The workbench, the commands and the GUI test take their lists from the registry: no
    feature name is spelled out there."""
    for path in ("InitGui.py", "freecad_deform/__init__.py",
                 "deform_tests/gui/freecad_scenario.py"):
        with open(os.path.join(REPO, path), encoding="utf-8") as f:
            text = f.read()
        for feature in registry.FEATURES:
            assert f'"{feature.command}"' not in text and f'"{feature.api}"' not in text, path
    with open(os.path.join(PACKAGE, "gui", "commands.py"), encoding="utf-8") as f:
        text = f.read()
    for tool in registry.TOOLBAR:
        assert f'"{tool.command}"' not in text and tool.tool_tip[:40] not in text, tool.name


def test_every_gui_scenario_is_run():
    here = os.path.dirname(os.path.abspath(__file__))
    modules = {n[len("scenario_"):-3] for n in os.listdir(here)
               if n.startswith("scenario_") and n.endswith(".py")}
    assert set(registry.SCENARIOS) == modules
    assert registry.SCENARIOS[0] == "stretch"   # it activates the workbench
