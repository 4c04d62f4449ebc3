"""The demo's pictures, rendered by FreeCAD's own 3D view (run inside the FreeCAD GUI under
Xvfb by demo.py; see render() there).

For each job of the JSON list in $DEFORM_PICTURES ({"png", "title", "document", "object",
"view"}): the feature's task panel is opened as a user opens it, so its planes, axis and
handles (or its control net, regions, markers) are in the 3D view; the Base is shown alone
("before", blue), then the result alone ("after", orange), both from the same camera; the
two screenshots are put side by side under the title. The Base and the result are never
changed: the panel is closed with Cancel and no document is saved. Writes a JSON report
($DEFORM_PICTURES + ".done.json": per picture the planes drawn and the draggers in the
scene) and ends FreeCAD with os._exit.
"""
import json
import math
import os
import sys
import traceback

sys.path.insert(0, os.environ["DEFORM_REPO"])

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

SIZE = (800, 600)                  # pixels of one side
HEADER = 56                        # pixels above the two sides for the title and the labels
BEFORE, AFTER = (0.45, 0.62, 0.9), (0.98, 0.62, 0.3)


def camera(elevation, azimuth):
    """The camera orientation (quaternion x, y, z, w) looking at the part from `elevation`
    above the XY plane and `azimuth` about Z (degrees, as matplotlib's view_init), Z up."""
    e, a = math.radians(elevation), math.radians(azimuth)
    back = App.Vector(math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e))
    up = App.Vector(0, 0, 1) - back * back.z
    up.normalize()
    right = up.cross(back)
    m = App.Matrix(right.x, up.x, back.x, 0, right.y, up.y, back.y, 0,
                   right.z, up.z, back.z, 0, 0, 0, 0, 1)
    return App.Rotation(m).Q


def process(seconds=0.3):
    end = QtCore.QTime.currentTime().addMSecs(int(seconds * 1000))
    while QtCore.QTime.currentTime() < end:
        QtGui.QApplication.processEvents()


def base_of(obj):
    base = obj.Base
    return base[0] if isinstance(base, (tuple, list)) else base


def paint(obj, colour):
    vobj = obj.ViewObject
    vobj.ShapeColor = colour
    if hasattr(vobj, "DiffuseColor"):     # an imported part's colours per face
        vobj.DiffuseColor = [colour]
    if hasattr(vobj, "PointSize"):
        vobj.PointSize = 2


def only(doc, shown):
    for o in doc.Objects:
        if o.ViewObject is not None:
            o.ViewObject.Visibility = o in shown


def compose(path, title, left, right):
    """The two screenshots side by side under the title, each labelled."""
    w, h = SIZE
    image = QtGui.QImage(2 * w, h + HEADER, QtGui.QImage.Format_RGB32)
    image.fill(QtGui.QColor("white"))
    painter = QtGui.QPainter(image)
    painter.drawImage(0, HEADER, QtGui.QImage(left))
    painter.drawImage(w, HEADER, QtGui.QImage(right))
    painter.setPen(QtGui.QColor(200, 200, 200))
    painter.drawLine(w, HEADER, w, h + HEADER)
    painter.setPen(QtGui.QColor("black"))
    font = painter.font()
    font.setPixelSize(20)
    painter.setFont(font)
    painter.drawText(QtCore.QRect(0, 4, 2 * w, 26), QtCore.Qt.AlignCenter, title)
    font.setPixelSize(16)
    painter.setFont(font)
    for k, label in enumerate(("before", "after")):
        painter.drawText(QtCore.QRect(k * w, 32, w, 22), QtCore.Qt.AlignCenter, label)
    painter.end()
    image.save(path)
    for side in (left, right):
        os.remove(side)


def in_view(view):
    """(planes drawn as Guides sheets, draggers) in the view's scene graph now."""
    from pivy import coin
    from freecad_deform.gui.coin_nodes import GUIDE_NAME

    def tails(kind):
        """The (tail, names on the path) of every `kind` node, read while the search (which
        owns the paths) lives."""
        search = coin.SoSearchAction()
        search.setType(kind.getClassTypeId(), True)
        search.setInterest(coin.SoSearchAction.ALL)
        search.apply(view.getSceneGraph())
        found = []
        for i in range(search.getPaths().getLength()):
            path = search.getPaths()[i]
            names = {str(path.getNode(k).getName()) for k in range(path.getLength())}
            found.append((path.getTail(), names))
        return found

    sheets = sum(tail.numVertices.getNum() for tail, names in tails(coin.SoFaceSet)
                 if GUIDE_NAME in names)
    return sheets, len(tails(coin.SoDragger))


def picture(job, doc):
    from freecad_deform.gui.view_providers import panel_class
    obj = doc.getObject(job["object"])
    base = base_of(obj)
    view = Gui.getDocument(doc.Name).ActiveView
    panel = panel_class(obj)(obj)
    Gui.Control.showDialog(panel)
    try:
        process()
        paint(base, BEFORE)
        paint(obj, AFTER)
        if hasattr(panel, "show_regions"):    # DimensionDrive: the regions in colour
            panel.show_regions()
        only(doc, (base, obj))
        view.setCameraOrientation(camera(*job["view"]))
        for _ in range(2):      # the first fit may still see the old bounding box
            view.fitAll()
            process()
        sheets, draggers = in_view(view)
        sides = []
        for k, shown in enumerate((base, obj)):
            only(doc, (shown,))
            process()
            sides.append(job["png"] + f".{k}.png")
            view.saveImage(sides[-1], *SIZE, "White")
    finally:
        panel.reject()
        process()
    compose(job["png"], job["title"], *sides)
    return {"png": job["png"], "planes": sheets, "handles": draggers}


def run():
    path = os.environ["DEFORM_PICTURES"]
    report = {"done": [], "failed": {}}
    try:
        with open(path) as f:
            jobs = json.load(f)
        for document in dict.fromkeys(j["document"] for j in jobs):
            doc = App.openDocument(document)
            process()
            for job in (j for j in jobs if j["document"] == document):
                try:
                    report["done"].append(picture(job, doc))
                except Exception:
                    report["failed"][job["png"]] = traceback.format_exc()
                    if Gui.Control.activeDialog():
                        Gui.Control.closeDialog()
            App.closeDocument(doc.Name)
    except Exception:
        report["failed"]["*"] = traceback.format_exc()
    finally:
        with open(path + ".done.json", "w") as f:
            json.dump(report, f, indent=1)
        sys.stdout.flush()
        os._exit(0)


QtCore.QTimer.singleShot(200, run)
