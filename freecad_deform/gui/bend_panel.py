"""The Bend task panel: Plane, Angle, Axis (point, direction, or picked), UsePlane2 / Plane2,
Samples, Profile, Tolerance, and the results."""
import FreeCAD as App
from PySide import QtGui

from ..geometry.errors import DeformError
from ..shapes.convert import plane_placement
from . import selection
from .planes_panel import PlanesPanel
from .widgets import direction_of


class BendPanel(PlanesPanel):
    TYPE = "Bend"
    EDITABLE = ("Plane", "Angle", "Axis", "UsePlane2", "Plane2", "Samples", "Profile",
                "Tolerance")
    HANDLES = ("Plane", "Angle")

    def build(self, layout):
        self.add_plane(layout)
        form = QtGui.QFormLayout()
        self.angle = self.add_quantity(form, "Angle", "deg", -360.0, 360.0)
        layout.addLayout(form)
        self.add_axis(layout)
        form = QtGui.QFormLayout()
        self.add_use_plane2(form)
        self.add_plane2_offset(form)
        self.add_samples(form, minimum=1)
        self.add_flex(form)
        layout.addLayout(form)
        self.add_results(layout)

    def picked_axis(self, line):
        """A picked edge or datum line has no meaningful direction: it is turned so that
        the current Angle swings the far part away from the near part."""
        obj = self.obj
        axis = selection.axis_through(line, obj.Plane)
        return selection.oriented_bend_axis(obj.Base, obj.Plane, axis, obj.Angle.Value or 1.0)

    def on_pick_plane(self):
        """Axis follows a picked Plane: moved with it along the normal when the normal stays,
        else suggested afresh for the new plane (in it, just outside the part)."""
        old = self.obj.Plane
        super().on_pick_plane()
        new = self.obj.Plane
        n_old, n_new = direction_of(old), direction_of(new)
        if self.closed or (new.Base.isEqual(old.Base, 1e-12) and n_new.isEqual(n_old, 1e-12)):
            return
        try:
            if n_old.isEqual(n_new, 1e-9):
                axis = App.Placement(self.obj.Axis)
                axis.Base = axis.Base + n_new * (new.Base - old.Base).dot(n_new)
            else:
                axis = selection.default_bend_axis(self.obj.Base, new)
                axis = selection.oriented_bend_axis(self.obj.Base, new, axis,
                                                    self.obj.Angle.Value or 1.0)
        except DeformError as e:
            self.refuse(e)
            return
        self.set_property("Axis", axis)
        self.reload()

    def on_flip_plane(self):
        """The other side moves; the Axis direction turns too, so the bend stays valid."""
        if self._loading or self.closed:
            return
        axis = self.obj.Axis
        if self.set_property("Axis", plane_placement((axis.Base, -direction_of(axis)), "Axis")):
            super().on_flip_plane()
