"""Handles in the 3D view for the Stretch, Bend, Twist and Taper panels: a trim plane is
dragged along its normal, and Distance, Angle or Scale follow a handle of their own (Coin's
translate and disc draggers). They sit just outside the part's bounding box, so the mouse
finds them in front of the part; every drag sets the property and the preview follows.
The planes in use are drawn as translucent sheets reaching the handles, the axis as a line
(Guides)."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore

from ..geometry.sweep.defaults import across
from ..shapes.convert import vector
from .coin_nodes import Guides, Handle
from .selection import bound_box
from .widgets import direction_of

SIZE = 0.08      # dragger size, x the Base's bounding-box diagonal
OUT = 0.6        # distance of a handle from the box centre's projection, x the diagonal
POLL_MS = 30     # how often a dragged handle is read
DISC = 2.5       # the angle disc's size, x a slider's: room to sweep it far from its centre


class Frame:
    """Where the handles and guides are laid out, from the Base's box and the Plane's
    normal now: the box, its centre, reach (how far beside the part), the normal and the
    side the handles sit on."""

    def __init__(self, obj):
        self.box = bound_box(obj.Base)
        self.centre = App.Vector(self.box.Center)
        self.reach = OUT * self.box.DiagonalLength
        self.normal = direction_of(obj.Plane)
        self.side = vector(across(tuple(self.normal)))

    def in_plane(self, placement):
        """The box centre's projection onto the plane of `placement`."""
        return self.centre + self.normal * (placement.Base - self.centre).dot(self.normal)


class PanelHandles:
    """The handles of one panel (its HANDLES: "Plane", "Plane2", "Distance", "Angle",
    "Scale"), in the active 3D view while the panel is open."""

    def __init__(self, panel, names):
        self.panel, self.obj = panel, panel.obj
        self.handles, self.start, self.dragging = {}, {}, False
        from pivy import coin  # noqa: F401  (FreeCAD 1.1 wraps the scene graph only after it)
        view = Gui.ActiveDocument.ActiveView if Gui.ActiveDocument else None
        self.scene = None
        if hasattr(view, "getSceneGraph"):   # a 3D view (not a page, spreadsheet, ...)
            try:
                self.scene = view.getSceneGraph()
            except RuntimeError as e:  # FreeCAD could not hand the scene graph to pivy
                App.Console.PrintWarning(f"{panel.TYPE}: no handles in the 3D view ({e})\n")
        if self.scene is None:
            return
        self.guides = Guides()
        self.scene.addChild(self.guides.root)
        for name in names:
            self.handles[name] = Handle("turn" if name == "Angle" else "slide")
            self.scene.addChild(self.handles[name].root)
        self.place()
        self.amounts = {}
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self.poll)
        self.timer.start()

    def poll(self):
        """Follow a dragger while it is dragged; at its release recompute and re-place."""
        for name, handle in self.handles.items():
            amount = handle.amount()
            if handle.active():
                if amount != self.amounts.get(name, 0.0):
                    self.amounts[name] = amount
                    self.dragged(name, amount)
            elif self.dragging and name in self.amounts:
                self.dragged(name, amount)   # the last motion before the release
                self.amounts = {}
                self.released()
                return

    # --- where each handle sits -------------------------------------------------------------
    def geometry(self, name, f):
        """(point, direction) of a handle in the frame `f`, from the object's properties now."""
        obj = self.obj
        if name == "Plane":
            return f.in_plane(obj.Plane) + f.side * f.reach, f.normal
        if name == "Plane2":
            return f.in_plane(obj.Plane2) + f.side * f.reach, f.normal
        if name == "Distance":
            return f.in_plane(obj.Plane) - f.side * f.reach + f.normal * obj.Distance.Value, \
                f.normal
        if name == "Scale":
            return f.in_plane(obj.Plane2) - f.side * f.reach, -f.side
        # Angle: about the Axis (Bend), or about the normal beyond Plane2 (Twist)
        if self.panel.TYPE == "Bend":
            return obj.Axis.Base, direction_of(obj.Axis)
        return f.in_plane(obj.Plane2) - f.side * f.reach, f.normal

    def guide_geometry(self, f):
        """(sheets, axes) of the Guides in the frame `f`: each separating plane in use as a
        rectangle from handle to handle across the part, the Axis in use as a segment
        across it."""
        obj = self.obj
        up = f.normal.cross(f.side)
        half = 0.55 * sum(abs(c) * length for c, length in
                          zip(up, (f.box.XLength, f.box.YLength, f.box.ZLength)))
        planes = [] if len(getattr(obj, "Polyline", ())) else [obj.Plane]
        if hasattr(obj, "Plane2") and getattr(obj, "UsePlane2", True):
            planes.append(obj.Plane2)
        sheets = [[f.in_plane(placement) + f.side * a * f.reach + up * b * half
                   for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))] for placement in planes]
        axes = []
        if self.panel.TYPE == "Bend" or getattr(obj, "UseAxis", False):
            direction = direction_of(obj.Axis)
            foot = obj.Axis.Base + direction * (f.centre - obj.Axis.Base).dot(direction)
            axes.append([foot - direction * f.reach, foot + direction * f.reach])
        return sheets, axes

    def place(self):
        """Every handle where the object's properties put it, its drag reset."""
        if self.scene is None:
            return
        f = Frame(self.obj)   # one read of the Base's box (45 ms for 996 faces)
        size = SIZE * max(f.box.DiagonalLength, 1e-6)
        for name, handle in self.handles.items():
            point, direction = self.geometry(name, f)
            handle.place(point, direction, size * (DISC if handle.kind == "turn" else 1.0))
        self.guides.set(*self.guide_geometry(f))
        self.start = {n: self._value(n) for n in self.handles}

    def _value(self, name):
        value = getattr(self.obj, name)
        if name in ("Plane", "Plane2"):
            return App.Placement(value)
        if name == "Angle":
            return value.Value + 360.0 * getattr(self.obj, "Turns", 0)
        return float(getattr(value, "Value", value))

    # --- dragging ---------------------------------------------------------------------------
    def dragged(self, name, amount):
        """Set the property `amount` (mm, degrees, or mm across for Scale) from where the
        drag began; the panel shows it and previews."""
        start, panel = self.start[name], self.panel
        self.dragging = True
        if name in ("Plane", "Plane2"):
            moved = App.Placement(start)
            moved.Base = start.Base + direction_of(start) * amount
            if name == "Plane":
                panel.set_plane_dragged(moved)
            else:
                panel.set_property("Plane2", moved)
        elif name == "Angle":
            panel.set_angle_dragged(start + amount)
        elif name == "Scale":
            reach = OUT * bound_box(self.obj.Base).DiagonalLength
            panel.set_property("Scale", max(start * (1.0 + amount / reach), 1e-3))
        else:
            panel.set_property(name, start + amount)
        panel.reload()

    def released(self):
        self.dragging = False
        self.panel.recompute()
        self.place()

    def remove(self):
        if self.scene is not None:
            self.timer.stop()
            for handle in self.handles.values():
                self.scene.removeChild(handle.root)
            self.scene.removeChild(self.guides.root)
        self.handles = {}
