"""The workbench's commands. CommandBase is the pattern every feature's command copies.

A command is enabled only when the selection fits (selection.read), creates the feature
through the macro API inside one transaction, and opens the feature's task panel, which
commits that transaction on OK and aborts it on Cancel.
"""
import FreeCAD as App
import FreeCADGui as Gui

from . import icon_path, selection
from .task_panel import is_invalid, panel_class
from .view_providers import feature_type


class CommandBase:
    """Subclass and set NAME, TYPE, MENU_TEXT, TOOL_TIP; implement create(base, plane).

    With AXIS = True the selection may also hold a straight edge or a datum line, and
    create(base, plane, axis) gets it as (point, direction) or None.
    """

    NAME = ""          # FreeCAD command name, "Deform_<TYPE>"
    TYPE = ""          # the proxy's TYPE: icon resources/icons/<TYPE>.svg, panel <TYPE>Panel
    MENU_TEXT = ""
    TOOL_TIP = ""
    AXIS = False       # the selection may give an axis (a straight edge or a datum line)

    def GetResources(self):
        return {"Pixmap": icon_path(self.TYPE), "MenuText": self.MENU_TEXT,
                "ToolTip": self.TOOL_TIP}

    def IsActive(self):
        if Gui.ActiveDocument is None or Gui.Control.activeDialog():
            return False
        return self.read_selection() is not None

    def read_selection(self):
        """What create() needs from the selection, or None when it does not fit."""
        return selection.read(Gui.Selection.getSelectionEx(), axis=self.AXIS)

    def create(self, base, picked_plane, picked_axis=None):
        """Make the feature object (through freecad_deform.api) and return it."""
        raise NotImplementedError

    def Activated(self):
        fits = self.read_selection()
        if fits is None:
            App.Console.PrintError(f"{self.MENU_TEXT}: {self.TOOL_TIP}\n")
            return
        base, *picked = fits
        visible = {base.Name: bool(base.ViewObject.Visibility)} if base.ViewObject else {}
        # Persistent, so the transaction outlives this command invocation: the task panel
        # commits it on OK (one undo step) or aborts it on Cancel.
        transaction = App.setActiveTransaction(self.TYPE, True) or None
        try:
            self._hide(base)
            obj = self.create(base, *picked)
        except Exception as e:
            if transaction:
                App.closeActiveTransaction(True, transaction)
            App.Console.PrintError(f"{self.MENU_TEXT}: {e}\n")
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
    NAME = "Deform_Stretch"
    TYPE = "Stretch"
    MENU_TEXT = "Stretch"
    TOOL_TIP = ("Stretch a solid, mesh or point cloud at a plane: the part beyond the plane "
                "moves by Distance, the gap is filled with the swept cross-section.\n"
                "Select one solid, mesh or point cloud, optionally with a planar face or a "
                "datum plane that gives the plane.")

    def create(self, base, picked_plane):
        from ..api import make_stretch
        return make_stretch(base, selection.suggested_plane(base, picked_plane), 0.0)


class BendCommand(CommandBase):
    NAME = "Deform_Bend"
    TYPE = "Bend"
    MENU_TEXT = "Bend"
    TOOL_TIP = ("Bend a solid, mesh or point cloud at a plane: the part beyond the plane turns "
                "by Angle about Axis, the gap is filled with the revolved cross-section.\n"
                "Select one solid, mesh or point cloud, optionally with a planar face or a "
                "datum plane that gives the plane and a straight edge or a datum line that "
                "gives the axis.")
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
    NAME = "Deform_Twist"
    TYPE = "Twist"
    MENU_TEXT = "Twist"
    TOOL_TIP = ("Twist a solid, mesh or point cloud between two parallel planes: sections "
                "between Plane and Plane2 turn progressively by up to Angle, the part beyond "
                "Plane2 turns rigidly; length and cross-sections are kept.\n"
                "Select one solid, mesh or point cloud, optionally with a planar face or a "
                "datum plane that gives Plane and a straight edge or a datum line that gives "
                "the axis (else the Plane normal through the section's centroid).")
    ANGLE = 30.0

    def make(self, base, plane, plane2, axis):
        from ..api import make_twist
        return make_twist(base, plane, plane2, self.ANGLE, axis)


class TaperCommand(RegionCommand):
    NAME = "Deform_Taper"
    TYPE = "Taper"
    MENU_TEXT = "Taper"
    TOOL_TIP = ("Taper a solid, mesh or point cloud between two parallel planes: sections "
                "between Plane and Plane2 are scaled across the axis from 1 to Scale, the part "
                "beyond Plane2 is scaled by Scale.\n"
                "Select one solid, mesh or point cloud, optionally with a planar face or a "
                "datum plane that gives Plane and a straight edge or a datum line that gives "
                "the axis (else the Plane normal through the section's centroid).")
    SCALE = 0.8

    def make(self, base, plane, plane2, axis):
        from ..api import make_taper
        return make_taper(base, plane, plane2, self.SCALE, axis)


class DimensionDriveCommand(CommandBase):
    NAME = "Deform_DimensionDrive"
    TYPE = "DimensionDrive"
    MENU_TEXT = "Drive dimension"
    TOOL_TIP = ("Change a dimension of a triangle mesh: the distance of two parallel planes, "
                "the radius of a cylinder or the position of a feature. The rest of the mesh "
                "follows without remeshing.\n"
                "Select one mesh or one solid (a solid is tessellated), optionally with a face "
                "of it that gives the first region; then click the regions in the task panel.")
    TARGET = 1.0  # placeholder; the panel sets Target to the current value once picked

    def read_selection(self):
        """(base, face or None, picked point or None): one mesh or solid, maybe one face."""
        try:
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
        except Exception:
            return None

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
    NAME = "Deform_MatchingDrive"
    TYPE = "DimensionDrive"
    MENU_TEXT = "Drive matching region"
    TOOL_TIP = ("Apply a DimensionDrive to the matching region of another part (a bore and "
                "the shaft in it): the new drive's Target follows the first one's, so one "
                "value changes both parts.\n"
                "Select a DimensionDrive, then the mesh, solid or FEM mesh of the other part.")

    def read_selection(self):
        """(drive, other): a DimensionDrive and one other object, else None."""
        try:
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
        except Exception:
            return None

    def Activated(self):
        fits = self.read_selection()
        if fits is None:
            App.Console.PrintError(f"{self.MENU_TEXT}: {self.TOOL_TIP}\n")
            return
        from ..api import make_matching_drive
        drive, other = fits
        try:
            obj = make_matching_drive(drive, other)
        except Exception as e:
            App.Console.PrintError(f"{self.MENU_TEXT}: {e}\n")
            return
        if obj.ViewObject is not None:
            other.ViewObject.Visibility = False
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(obj)


class AreaConstrainCommand(CommandBase):
    NAME = "Deform_AreaConstrain"
    TYPE = "AreaConstrain"
    MENU_TEXT = "Constrain area"
    TOOL_TIP = ("Give a B-spline face an exact area by moving chosen poles of its control net "
                "as little as possible (a face that is not a B-spline is converted).\n"
                "Select one face of a shape; then set the target area or percentage and pick "
                "the poles that may move in the task panel.")
    TARGET = "100%"  # the face as it is: a valid start, the user then sets the target

    def read_selection(self):
        """(base, "FaceN"): exactly one face of one Part object, else None."""
        try:
            items = Gui.Selection.getSelectionEx()
            if len(items) != 1 or not items[0].Object.isDerivedFrom("Part::Feature"):
                return None
            names = [n for n in items[0].SubElementNames if n]
            if len(names) != 1 or not names[0].startswith("Face"):
                return None
            return items[0].Object, names[0]
        except Exception:
            return None

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
        except Exception:
            return None  # the object will say what is wrong with the face
        nu, nv = surface.NbUPoles, surface.NbVPoles
        if nu > 2 and nv > 2:
            return None
        return [(i, j) for i in range(1, nu + 1) for j in range(1, nv + 1)]


class DirectPushCommand(CommandBase):
    NAME = "Deform_DirectPush"
    TYPE = "DirectPush"
    MENU_TEXT = "Direct push"
    TOOL_TIP = ("Push any point of a curve or surface where it must go: the poles and knots "
                "follow; a face of a solid bulges and the solid stays closed.\n"
                "Select one edge or one face of a shape; then drag it in the 3D view while "
                "the task panel is open (on a face, Shift at the press drags along its normal).")

    def read_selection(self):
        """(base, "EdgeN" or "FaceN", picked point or None): exactly one edge or one face
        of one Part object, else None."""
        try:
            items = Gui.Selection.getSelectionEx()
            if len(items) != 1 or not items[0].Object.isDerivedFrom("Part::Feature"):
                return None
            names = [n for n in items[0].SubElementNames if n]
            if len(names) != 1 or not names[0].startswith(("Edge", "Face")):
                return None
            points = items[0].PickedPoints
            return items[0].Object, names[0], (points[0] if points else None)
        except Exception:
            return None

    def create(self, base, element, picked=None):
        """The object without pushes. make_direct_push needs one: a zero push at the picked
        point (or the element's centre) checks that the element can be pushed, then goes."""
        from ..api import make_direct_push
        point = point_on_face(base.Shape.getElement(element), picked)
        obj = make_direct_push(base, element, point, point)
        if is_invalid(obj):
            raise ValueError(obj.getStatusString())
        obj.Points, obj.Targets = [], []
        obj.Document.recompute()
        return obj


COMMANDS = [StretchCommand, BendCommand, TwistCommand, TaperCommand, DimensionDriveCommand,
            MatchingDriveCommand,
            AreaConstrainCommand, DirectPushCommand]
TOOLBAR = [c.NAME for c in COMMANDS]


def register():
    """Add every command to FreeCAD once (Initialize may run again after a reload)."""
    known = set(Gui.listCommands())
    for cls in COMMANDS:
        if cls.NAME not in known:
            Gui.addCommand(cls.NAME, cls())


register()
