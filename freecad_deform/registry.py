"""The one list of the workbench's features and commands. The macro API's exports
(freecad_deform.__all__), the GUI commands (gui/commands.py), the toolbar and menu
(InitGui.py), the task panel a double-click opens (gui/view_providers.py) and the GUI test
parts are read from here. Importable without FreeCAD.

Adding a feature <Name> (module <name>, e.g. "DimensionDrive", "dimension_drive"):
1. geometry/<domain>/...: the kernel, tests in deform_tests/geometry (hypothesis where
   invariants exist).
2. ops/<name>.py: the pipeline per base kind, tested on real models.
3. features/<name>.py: class <Name> (TYPE = "<Name>"), properties with tooltips and units,
   execute; api.py: make_<name>.
4. gui/<name>_panel.py: class <Name>Panel(task_panel.TaskPanelBase), its fields from
   gui/bindings.py and gui/widgets.py, its 3D-view nodes from gui/coin_nodes.py;
   gui/commands.py: class <Name>Command(CommandBase) with create();
   resources/icons/<Name>.svg.
5. One Feature(...) entry in FEATURES below, in toolbar order (menu text, tooltip, GUI
   test parts; the names above follow from <Name> and <name>). A command that makes no
   feature (a tool on existing objects) is a Tool(...) in TOOLS with the path of its
   command class.
6. deform_tests/features/test_<name>.py, deform_tests/gui/scenario_<name>.py (its part
   named in `scenarios`), rows in the real-parts matrix, a benchmark, a README section and
   an example macro.
deform_tests/gui/test_registry.py checks that the exports, proxies, panels, commands, icons
and GUI test parts agree with this list; the GUI run checks the toolbar, menu and icons.
"""
from dataclasses import dataclass, field
import re

PACKAGE = __name__.rpartition(".")[0] or "freecad_deform"


def snake(name):
    """"DimensionDrive" -> "dimension_drive"."""
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


@dataclass(frozen=True)
class Tool:
    """A toolbar and menu command. `command_class`: "module.Class" of its FreeCAD command,
    constructed with this entry (gui.commands.<name>Command unless given; a subclass of
    gui.commands.CommandBase); `api`: the macro function it stands for; `scenarios`: its
    parts of the GUI test (deform_tests/gui/scenario_<part>.py, function <part>); `after`:
    the toolbar entry it follows (a tool not given one comes last)."""

    name: str
    menu_text: str
    tool_tip: str
    icon: str = ""
    command_class: str = ""
    api: str = ""
    scenarios: tuple = field(default=())
    after: str = ""

    def __post_init__(self):
        if not self.icon:
            object.__setattr__(self, "icon", self.name)
        if not self.command_class:
            object.__setattr__(self, "command_class",
                               f"{PACKAGE}.gui.commands.{self.name}Command")

    @property
    def command(self):
        """The FreeCAD command name."""
        return "Deform_" + self.name


@dataclass(frozen=True)
class Feature(Tool):
    """A feature: a document object whose proxy's TYPE is `name`, made by api.make_<module>,
    its proxy class <name> in features/<module>.py and its task panel <name>Panel in
    gui/<module>_panel.py (none when `panel` is False)."""

    panel: bool = True

    @property
    def module(self):
        return snake(self.name)

    def __post_init__(self):
        super().__post_init__()
        if not self.api:
            object.__setattr__(self, "api", "make_" + self.module)

    @property
    def proxy_class(self):
        return f"{PACKAGE}.features.{self.module}.{self.name}"

    @property
    def panel_class(self):
        return f"{PACKAGE}.gui.{self.module}_panel.{self.name}Panel" if self.panel else None


FEATURES = (
    Feature("Stretch", "Stretch",
            "Stretch a solid, mesh or point cloud at a plane: the part beyond the plane moves "
            "by Distance, the gap is filled with the swept cross-section.\n"
            "Select one solid, mesh or point cloud, optionally with a planar face or a datum "
            "plane that gives the plane.", scenarios=("stretch",)),
    Feature("Bend", "Bend",
            "Bend a solid, mesh or point cloud at a plane: the part beyond the plane turns by "
            "Angle about Axis, the gap is filled with the revolved cross-section.\n"
            "Select one solid, mesh or point cloud, optionally with a planar face or a datum "
            "plane that gives the plane and a straight edge or a datum line that gives the "
            "axis.", scenarios=("bend_twist",)),
    Feature("Twist", "Twist",
            "Twist a solid, mesh or point cloud between two parallel planes: sections between "
            "Plane and Plane2 turn progressively by up to Angle, the part beyond Plane2 turns "
            "rigidly; length and cross-sections are kept.\n"
            "Select one solid, mesh or point cloud, optionally with a planar face or a datum "
            "plane that gives Plane and a straight edge or a datum line that gives the axis "
            "(else the Plane normal through the section's centroid).",
            scenarios=("bend_twist", "handles")),
    Feature("Taper", "Taper",
            "Taper a solid, mesh or point cloud between two parallel planes: sections between "
            "Plane and Plane2 are scaled across the axis from 1 to Scale, the part beyond "
            "Plane2 is scaled by Scale.\n"
            "Select one solid, mesh or point cloud, optionally with a planar face or a datum "
            "plane that gives Plane and a straight edge or a datum line that gives the axis "
            "(else the Plane normal through the section's centroid).", scenarios=("taper",)),
    Feature("DimensionDrive", "Drive dimension",
            "Change a dimension of a triangle mesh: the distance of two parallel planes, the "
            "radius of a cylinder or the position of a feature. The rest of the mesh follows "
            "without remeshing.\n"
            "Select one mesh or one solid (a solid is tessellated), optionally with a face of "
            "it that gives the first region; then click the regions in the task panel.",
            scenarios=("dimension_drive",)),
    Feature("AreaConstrain", "Constrain area",
            "Give a B-spline face an exact area by moving chosen poles of its control net as "
            "little as possible (a face that is not a B-spline is converted).\n"
            "Select one face of a shape; then set the target area or percentage and pick the "
            "poles that may move in the task panel.", scenarios=("area_constrain",)),
    Feature("DirectPush", "Direct push",
            "Push any point of a curve or surface where it must go: the poles and knots "
            "follow; a face of a solid bulges and the solid stays closed.\n"
            "Select one edge or one face of a shape; then drag it in the 3D view while the "
            "task panel is open (on a face, Shift at the press drags along its normal).",
            scenarios=("direct_push",)),
)

_BY_NAME = {f.name: f for f in FEATURES}

# Commands that make no feature of their own: tools on existing objects.
TOOLS = (
    Tool("MatchingDrive", "Drive matching region",
         "Apply a DimensionDrive to the matching region of another part (a bore and the "
         "shaft in it): the new drive's Target follows the first one's, so one value changes "
         "both parts.\n"
         "Select a DimensionDrive, then the mesh, solid or FEM mesh of the other part.",
         icon="DimensionDrive", api="make_matching_drive", after="DimensionDrive"),
    Tool("Solve", "Goal seek",
         "Find the value of a property, within bounds, that makes an output (VolumeChange, "
         "Achieved, AchievedArea, a bounding-box length) hit a target, or least or greatest; "
         "the value found is applied in one undo step.\n"
         "Needs a Deform object in the document; select one to preset its property and "
         "output.", command_class=f"{PACKAGE}.gui.solve_panel.SolveCommand", api="solve",
         scenarios=("solve",)),
)


def _toolbar(features, tools):
    """The features in order, each tool after the entry it names (else at the end)."""
    entries = list(features)
    for tool in tools:
        names = [e.name for e in entries]
        entries.insert(names.index(tool.after) + 1 if tool.after in names else len(entries),
                       tool)
    return tuple(entries)


# The toolbar and menu, in order.
TOOLBAR = _toolbar(FEATURES, TOOLS)

# The macro API (freecad_deform.<name>, from api.py): every tool's function.
API = tuple(dict.fromkeys(t.api for t in TOOLBAR if t.api))

# The GUI test's parts (deform_tests/gui/scenario_<part>.py), in the order they run.
SCENARIOS = tuple(dict.fromkeys(s for t in TOOLBAR for s in t.scenarios))


def feature(name):
    """The Feature whose proxy TYPE is `name`, or None."""
    return _BY_NAME.get(name)


def load(path):
    """The object a "package.module.Name" path names (its module imported)."""
    import importlib
    module, _, name = path.rpartition(".")
    return getattr(importlib.import_module(module), name)
