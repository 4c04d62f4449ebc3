"""The workbench's commands, one class per entry of registry.TOOLBAR (its command_class,
here <Name>Command unless the registry says otherwise). The registry gives each its name,
icon, menu text and tooltip; the class gives what the selection must hold and what it
creates.

A command is enabled only when the selection fits (read_selection), creates the feature
through the macro API inside one transaction, and opens the feature's task panel, which
commits that transaction on OK and aborts it on Cancel.
"""
import FreeCAD as App
import FreeCADGui as Gui

from .. import registry
from ..geometry.errors import DeformError
from . import icon_path, selection
from .task_panel import is_invalid
from .view_providers import feature_type, panel_class

# What creating a feature may raise for bad input: DeformError (a ValueError) with its one
# sentence, FreeCAD's Base.FreeCADError (a RuntimeError) from OCCT or a property set.
CREATE_ERRORS = (ValueError, RuntimeError)


class CommandBase:
    """A FreeCAD command made from its registry entry (registry.Tool or Feature).
    Subclasses implement create(base, plane) (or read_selection and Activated).

    With AXIS = True the selection may also hold a straight edge or a datum line, and
    create(base, plane, axis) gets it as (point, direction) or None.
    """

    AXIS = False       # the selection may give an axis (a straight edge or a datum line)

    def __init__(self, tool):
        self.tool = tool
        self.NAME = tool.command     # FreeCAD command name, "Deform_<Name>"
        self.TYPE = tool.name        # the feature's TYPE, its transaction's name
        self.MENU_TEXT = tool.menu_text
        self.TOOL_TIP = tool.tool_tip

    def GetResources(self):
        return {"Pixmap": icon_path(self.tool.icon), "MenuText": self.MENU_TEXT,
                "ToolTip": self.TOOL_TIP}

    def IsActive(self):
        if Gui.ActiveDocument is None or Gui.Control.activeDialog():
            return False
        return self.fits() is not None

    def fits(self):
        """read_selection(), None also when a selected object was deleted meanwhile."""
        try:
            return self.read_selection()
        except ReferenceError:
            return None

    def read_selection(self):
        """What create() needs from the selection, or None when it does not fit."""
        return selection.read(Gui.Selection.getSelectionEx(), axis=self.AXIS)

    def create(self, base, picked_plane, picked_axis=None):
        """Make the feature object (through freecad_deform.api) and return it."""
        raise NotImplementedError

    def Activated(self):
        fits = self.fits()
        if fits is None:
            App.Console.PrintError(f"{self.MENU_TEXT}: {self.TOOL_TIP}\n")
            return
        base, *picked = fits
        visible = {base.Name: bool(base.ViewObject.Visibility)} if base.ViewObject else {}
        # Persistent, so the transaction outlives this command invocation: the task panel
        # commits it on OK (one undo step) or aborts it on Cancel.
        transaction = App.setActiveTransaction(self.TYPE, True) or None
        obj = None
        try:
            self._hide(base)
            obj = self.create(base, *picked)
        except CREATE_ERRORS as e:
            App.Console.PrintError(f"{self.MENU_TEXT}: {e}\n")
        finally:
            if obj is None and transaction:
                App.closeActiveTransaction(True, transaction)
        if obj is None:
            return
        Gui.Selection.clearSelection()
        panel = panel_class(obj)(obj, transaction=transaction, created=True,
                                 restore_visibility=visible)
        Gui.Control.showDialog(panel)

    @staticmethod
    def _hide(base):
        """Hide the Base as a recorded change. That also opens the document's transaction
        now (FreeCAD opens it on the first change), so make_* joins it instead of
        committing one of its own, and Undo / Cancel show the Base again."""
        vobj = base.ViewObject
        if vobj is None:
            return
        if not vobj.Visibility:
            vobj.Visibility = True  # no redraw happens in between: nothing flickers
        vobj.Visibility = False


class StretchCommand(CommandBase):
    def create(self, base, picked_plane):
        from ..api import make_stretch
        return make_stretch(base, selection.suggested_plane(base, picked_plane), 0.0)


class BendCommand(CommandBase):
    AXIS = True
    ANGLE = 30.0

    def create(self, base, picked_plane, picked_axis=None):
        from ..api import make_bend
        plane, axis = selection.suggested_bend(base, picked_plane, picked_axis)
        return make_bend(base, plane, self.ANGLE, axis)


class RegionCommand(CommandBase):
    """Twist and Taper: the region between Plane and Plane2 (at 1/3 and 2/3 of the part's
    longest side, or from a picked plane), about a picked line or the default axis;
    subclasses implement make(base, plane, plane2, axis or None)."""

    AXIS = True

    def create(self, base, picked_plane, picked_axis=None):
        plane, plane2 = selection.suggested_twist(base, picked_plane)
        axis = None if picked_axis is None else selection.axis_through(picked_axis, plane)
        return self.make(base, plane, plane2, axis)


class TwistCommand(RegionCommand):
    ANGLE = 30.0

    def make(self, base, plane, plane2, axis):
        from ..api import make_twist
        return make_twist(base, plane, plane2, self.ANGLE, axis)


class TaperCommand(RegionCommand):
    SCALE = 0.8

    def make(self, base, plane, plane2, axis):
        from ..api import make_taper
        return make_taper(base, plane, plane2, self.SCALE, axis)


class DimensionDriveCommand(CommandBase):
    TARGET = 1.0  # placeholder; the panel sets Target to the current value once picked

    def read_selection(self):
        """(base, face or None, picked point or None): one mesh or solid, maybe one face."""
        items = Gui.Selection.getSelectionEx()
        if len(items) != 1 or selection.base_kind(items[0].Object) not in ("Mesh", "Part"):
            return None
        item = items[0]
        names = [n for n in item.SubElementNames if n]
        if not names:
            return item.Object, None, None
        if len(names) != 1 or not names[0].startswith("Face"):
            return None
        points = item.PickedPoints
        return item.Object, item.SubObjects[0], (points[0] if points else None)

    def create(self, base, face=None, picked=None):
        import Part
        from ..api import make_dimension_drive
        regions, kind = [], "Distance"
        if face is not None:
            regions = [point_on_face(face, picked)]
            if isinstance(face.Surface, Part.Cylinder):
                kind = "Radius"
        return make_dimension_drive(base, kind, regions, self.TARGET)


def point_on_face(face, picked):
    """The picked point when it lies on `face` (or an edge; a selection made without a
    click reports none, or exactly the origin: not a pick even on a face through it), else
    the point of it nearest its centre of mass."""
    import Part
    size = max(face.BoundBox.DiagonalLength, 1e-9)
    if picked is not None and App.Vector(picked).Length > 0 \
            and face.distToShape(Part.Vertex(picked))[0] < 1e-6 * size:
        return App.Vector(picked)
    return App.Vector(face.distToShape(Part.Vertex(face.CenterOfMass))[1][0][0])


class MatchingDriveCommand(CommandBase):
    def read_selection(self):
        """(drive, other): a DimensionDrive and one other object, else None."""
        items = [i.Object for i in Gui.Selection.getSelectionEx()]
        if len(items) != 2:
            return None
        drives = [o for o in items if feature_type(o) == "DimensionDrive"]
        others = [o for o in items if o not in drives[:1]]
        if not drives or len(others) != 1 or not (
                selection.base_kind(others[0]) in ("Mesh", "Part")
                or others[0].isDerivedFrom("Fem::FemMeshObject")):
            return None
        return drives[0], others[0]

    def Activated(self):
        fits = self.fits()
        if fits is None:
            App.Console.PrintError(f"{self.MENU_TEXT}: {self.TOOL_TIP}\n")
            return
        from ..api import make_matching_drive
        drive, other = fits
        try:
            obj = make_matching_drive(drive, other)
        except CREATE_ERRORS as e:
            App.Console.PrintError(f"{self.MENU_TEXT}: {e}\n")
            return
        if obj.ViewObject is not None:
            other.ViewObject.Visibility = False
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(obj)


def one_element(prefixes):
    """(object, "<Prefix>N", picked point or None) when the selection is exactly one
    element (its name starting with one of `prefixes`) of one Part object, else None."""
    items = Gui.Selection.getSelectionEx()
    if len(items) != 1 or not items[0].Object.isDerivedFrom("Part::Feature"):
        return None
    names = [n for n in items[0].SubElementNames if n]
    if len(names) != 1 or not names[0].startswith(prefixes):
        return None
    points = items[0].PickedPoints
    return items[0].Object, names[0], (points[0] if points else None)


class AreaConstrainCommand(CommandBase):
    TARGET = "100%"  # the face as it is: a valid start, the user then sets the target

    def read_selection(self):
        """(base, "FaceN"): exactly one face of one Part object, else None."""
        fits = one_element(("Face",))
        return fits[:2] if fits else None

    def create(self, base, face):
        from ..api import make_area_constrain
        return make_area_constrain(base, face, self.TARGET, poles=self.start_poles(base, face))

    @staticmethod
    def start_poles(base, face):
        """None (every interior pole), or every pole when the face has no interior one (a
        plane or a cylinder converts to 2 rows of poles)."""
        from ..shapes import bspline
        try:
            surface, _ = bspline.bspline_of(bspline.face_of(base.Shape, face)[1])
        except (DeformError, RuntimeError):
            return None  # the object will say what is wrong with the face
        nu, nv = surface.NbUPoles, surface.NbVPoles
        if nu > 2 and nv > 2:
            return None
        return [(i, j) for i in range(1, nu + 1) for j in range(1, nv + 1)]


class DirectPushCommand(CommandBase):
    def read_selection(self):
        """(base, "EdgeN" or "FaceN", picked point or None): exactly one edge or one face
        of one Part object, else None."""
        return one_element(("Edge", "Face"))

    def create(self, base, element, picked=None):
        """The object without pushes. make_direct_push needs one: a zero push at the picked
        point (or the element's centre) checks that the element can be pushed, then goes."""
        from ..api import make_direct_push
        point = point_on_face(base.Shape.getElement(element), picked)
        obj = make_direct_push(base, element, point, point)
        if is_invalid(obj):
            raise DeformError(obj.getStatusString())
        obj.Points, obj.Targets = [], []
        obj.Document.recompute()
        return obj


def register():
    """Add every command of the registry to FreeCAD once (Initialize may run again after a
    reload)."""
    known = set(Gui.listCommands())
    for tool in registry.TOOLBAR:
        if tool.command not in known:
            Gui.addCommand(tool.command, registry.load(tool.command_class)(tool))


register()
