"""The Coin nodes the task panels put into the 3D view while they are open: markers and
segments (Marks), a dragged element's live shape (Preview, DirectPush), a surface's control
net with pickable poles (ControlNet, AreaConstrain), draggers (Handle: the planes, Distance,
Angle and Scale of Stretch, Bend, Twist and Taper) and the separating planes and the axis
they act on (Guides). Each is added to the view's scene graph
by its constructor or its owner and removed with remove(); names let tests find them.
pivy is imported inside each class: it is there only with the GUI up.
"""
import math

NODE_NAME = "DeformDirectPush"      # Preview's root
NET_NAME = "DeformControlNet"       # ControlNet's root
GRAB_COLOUR = MOVABLE_COLOUR = (1.0, 0.45, 0.0)
CONSTRAINT_COLOUR = (0.0, 0.35, 0.85)
NET_COLOUR = (0.15, 0.15, 0.15)
GUIDE_COLOUR = (0.85, 0.15, 0.1)    # the separating planes and the axis
GUIDE_NAME = "DeformGuides"         # Guides' root
FIXED_COLOUR = (0.3, 0.3, 0.3)
PICK_RADIUS = 10                    # pixels: a click this near a pole picks it


class Marks:
    """Points as markers and index pairs as segments, in one colour."""

    def __init__(self, colour):
        from pivy import coin
        self.root = coin.SoSeparator()
        base = coin.SoBaseColor()
        base.rgb = colour
        style = coin.SoDrawStyle()
        style.lineWidth = 2
        self.coords = coin.SoCoordinate3()
        markers = coin.SoMarkerSet()
        markers.markerIndex = coin.SoMarkerSet.CIRCLE_FILLED_9_9
        self.lines = coin.SoIndexedLineSet()
        for node in (base, style, self.coords, markers, self.lines):
            self.root.addChild(node)
        self.set([])

    def set(self, points, segments=()):
        points = [tuple(float(c) for c in p) for p in points]
        index = [i for a, b in segments for i in (a, b, -1)]
        self.lines.coordIndex.setNum(len(index))
        if index:
            self.lines.coordIndex.setValues(0, len(index), index)
        self.coords.point.setNum(len(points))
        if points:
            self.coords.point.setValues(0, len(points), points)


class Preview:
    """Coin nodes in the 3D view while the panel is open, never picked: during a drag the
    element as pushed (and the rest of a solid), the result's own display hidden; on top,
    the constraints (blue) and the push being made (orange)."""

    def __init__(self, view, vobj):
        from pivy import coin
        self.view, self.vobj = view, vobj
        self.root = coin.SoSeparator()
        self.root.setName(NODE_NAME)
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        self.shape = coin.SoSwitch()
        self.constraints, self.grab = Marks(CONSTRAINT_COLOUR), Marks(GRAB_COLOUR)
        top = coin.SoAnnotation()
        top.addChild(self.constraints.root)
        top.addChild(self.grab.root)
        for node in (pick, self.shape, top):
            self.root.addChild(node)
        self.hidden = None       # the result's whichChild while a drag hides it
        view.getSceneGraph().addChild(self.root)

    def begin(self, curve, rest=None):
        """Show a drag: a curve or a surface (update() gives its points), `rest` (points,
        triangles) as it is; the result's display hidden."""
        from pivy import coin
        group = coin.SoSeparator()
        material = coin.SoMaterial()
        material.diffuseColor = self._view_property("LineColor" if curve else "ShapeColor",
                                                    (0.8, 0.8, 0.8))[:3]
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE  # lit from both sides
        hints.creaseAngle = 1.0
        style = coin.SoDrawStyle()
        style.lineWidth = self._view_property("LineWidth", 2.0)
        for node in (material, hints, style):
            group.addChild(node)
        if rest is not None:
            points, triangles = rest
            part = coin.SoSeparator()
            coords = coin.SoCoordinate3()
            coords.point.setValues(0, len(points), [tuple(p) for p in points])
            faces = coin.SoIndexedFaceSet()
            index = [i for triangle in triangles for i in (*triangle, -1)]
            faces.coordIndex.setValues(0, len(index), index)
            part.addChild(coords)
            part.addChild(faces)
            group.addChild(part)
        self.coords = coin.SoCoordinate3()
        self.mesh = coin.SoLineSet() if curve else coin.SoQuadMesh()
        group.addChild(self.coords)
        group.addChild(self.mesh)
        self.shape.removeAllChildren()
        self.shape.addChild(group)
        self.shape.whichChild = 0
        switch = self.vobj.SwitchNode
        if self.hidden is None:
            self.hidden = switch.whichChild.getValue()
        switch.whichChild = -1

    def update(self, points):
        """The dragged element's points: (k, 3) along a curve, (a, b, 3) over a surface."""
        if points.ndim == 3:
            self.mesh.verticesPerColumn, self.mesh.verticesPerRow = points.shape[:2]
        else:
            self.mesh.numVertices.setValue(len(points))
        flat = points.reshape(-1, 3)
        self.coords.point.setValues(0, len(flat), flat.tolist())

    def end(self):
        self.shape.whichChild = -1
        self.shape.removeAllChildren()
        self.grab.set([])
        if self.hidden is not None:
            self.vobj.SwitchNode.whichChild = self.hidden
            self.hidden = None

    def remove(self):
        self.end()
        self.view.getSceneGraph().removeChild(self.root)

    def _view_property(self, name, default):
        return getattr(self.vobj, name, default)


class ControlNet:
    """A surface's control net drawn into a 3D view over everything else (a net mostly
    lies inside the surface's bulge; every pole must be seen to be clicked): net lines and
    the poles as markers, movable ones in colour."""

    def __init__(self, view, poles):
        from pivy import coin
        self.view = view
        self.poles = poles                        # rows of App.Vector, poles[i][j]
        nu, nv = len(poles), len(poles[0])
        points = [tuple(p) for row in poles for p in row]
        self.root = coin.SoAnnotation()
        self.root.setName(NET_NAME)
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(points), points)
        self.root.addChild(coords)

        lines = coin.SoSeparator()
        colour = coin.SoBaseColor()
        colour.rgb = NET_COLOUR
        style = coin.SoDrawStyle()
        style.lineWidth = 1.5
        index = []
        for i in range(nu):
            index += [i * nv + j for j in range(nv)] + [-1]
        for j in range(nv):
            index += [i * nv + j for i in range(nu)] + [-1]
        net = coin.SoIndexedLineSet()
        net.coordIndex.setValues(0, len(index), index)
        for node in (colour, style, net):
            lines.addChild(node)
        self.root.addChild(lines)

        markers = coin.SoSeparator()
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX
        self.material = coin.SoMaterial()
        marker_set = coin.SoMarkerSet()
        marker_set.markerIndex = coin.SoMarkerSet.CIRCLE_FILLED_9_9
        for node in (binding, self.material, marker_set):
            markers.addChild(node)
        self.root.addChild(markers)
        self.set_movable(())
        view.getSceneGraph().addChild(self.root)

    def set_movable(self, flat):
        """Colour the poles whose flat index (i * nv + j, 0-based) is in `flat`."""
        nv = len(self.poles[0])
        count = len(self.poles) * nv
        flat = set(flat)
        colours = [MOVABLE_COLOUR if k in flat else FIXED_COLOUR for k in range(count)]
        self.material.diffuseColor.setValues(0, count, colours)

    def pole_at(self, x, y):
        """(i, j), 1-based, of the pole nearest the screen point (x, y) (pixels from the
        bottom left, as Coin and getPointOnScreen count) within PICK_RADIUS, else None."""
        best, found = PICK_RADIUS ** 2, None
        for i, row in enumerate(self.poles):
            for j, pole in enumerate(row):
                px, py = self.view.getPointOnScreen(pole)
                d2 = (px - x) ** 2 + (py - y) ** 2
                if d2 <= best:
                    best, found = d2, (i + 1, j + 1)
        return found

    def remove(self):
        self.view.getSceneGraph().removeChild(self.root)


class Handle:
    """One Coin dragger: "slide" moves along the local X of its frame, "turn" turns about its
    local Z. Its amount is read by polling, not by a dragger callback: pivy runs those
    without taking Python's lock, which crashes when the event comes from Python."""

    def __init__(self, kind):
        from pivy import coin
        self.kind, self.size = kind, 1.0
        self.root = coin.SoSeparator()
        self.transform = coin.SoTransform()
        self.dragger = coin.SoTranslate1Dragger() if kind == "slide" else \
            coin.SoRotateDiscDragger()
        self.root.addChild(self.transform)
        self.root.addChild(self.dragger)

    def place(self, point, direction, size):
        """Put the dragger at `point`, its slide (or turn axis) along `direction`."""
        from pivy import coin
        local = coin.SbVec3f(1, 0, 0) if self.kind == "slide" else coin.SbVec3f(0, 0, 1)
        self.size = size
        self.transform.translation.setValue(point.x, point.y, point.z)
        self.transform.rotation.setValue(
            coin.SbRotation(local, coin.SbVec3f(direction.x, direction.y, direction.z)))
        self.transform.scaleFactor.setValue(size, size, size)
        if self.kind == "slide":
            self.dragger.translation.setValue(0, 0, 0)
        else:
            self.dragger.rotation.setValue(coin.SbRotation())

    def active(self):
        return bool(self.dragger.isActive.getValue())

    def amount(self):
        """mm along the slide, or degrees about the turn axis, since the last place()."""
        if self.kind == "slide":
            return self.dragger.translation.getValue()[0] * self.size
        x, y, z, w = self.dragger.rotation.getValue().getValue()
        return math.degrees(2.0 * math.atan2(z, w))


class Guides:
    """The separating planes as translucent sheets with an outline, and the axis as a line,
    never picked (the part and the handles behind them stay clickable)."""

    def __init__(self):
        from pivy import coin
        self.root = coin.SoSeparator()
        self.root.setName(GUIDE_NAME)
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE   # lit from both sides
        material = coin.SoMaterial()
        material.diffuseColor = GUIDE_COLOUR
        material.emissiveColor = tuple(0.4 * c for c in GUIDE_COLOUR)
        material.transparency = 0.7
        style = coin.SoDrawStyle()
        style.lineWidth = 2
        self.coords = coin.SoCoordinate3()
        self.sheets = coin.SoFaceSet()
        lines = coin.SoSeparator()
        colour = coin.SoBaseColor()
        colour.rgb = GUIDE_COLOUR
        self.lines = coin.SoIndexedLineSet()
        for node in (colour, self.lines):
            lines.addChild(node)
        for node in (pick, hints, style, self.coords, material, self.sheets, lines):
            self.root.addChild(node)
        self.set([], [])

    def set(self, sheets, axes):
        """sheets: rectangles as 4 corners each; axes: segments as 2 end points each."""
        points = [tuple(float(c) for c in p) for corners in (*sheets, *axes) for p in corners]
        self.coords.point.setNum(len(points))
        if points:
            self.coords.point.setValues(0, len(points), points)
        self.sheets.numVertices.setNum(len(sheets))
        if sheets:
            self.sheets.numVertices.setValues(0, len(sheets), [4] * len(sheets))
        index = [i for k in range(len(sheets)) for i in (4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3,
                                                         4 * k, -1)]
        start = 4 * len(sheets)
        index += [i for k in range(len(axes)) for i in (start + 2 * k, start + 2 * k + 1, -1)]
        self.lines.coordIndex.setNum(len(index))
        if index:
            self.lines.coordIndex.setValues(0, len(index), index)
