"""package.xml as the Addon Manager reads it: FreeCAD's own metadata reader (App.Metadata) and
the rules of the current manifest spec (FreeCAD Addon Academy, "Addon Manifest"): a required
icon (an SVG the Addon Manager accepts), an SPDX license with its file, at least one maintainer
and author, freecadmin, typed dependencies (internal workbenches, Python packages).
The FreeCAD running the tests must be one of the versions the manifest says were tested."""
import os
import re
import xml.etree.ElementTree as ET

import FreeCAD as App

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PACKAGE_XML = os.path.join(REPO, "package.xml")
NS = "{https://wiki.freecad.org/Package_Metadata}"
# The Addon Manager's test of SVG icon data: optional BOM, comments, XML declaration, doctype,
# then the <svg> root.
SVG_ROOT = re.compile(rb"^\s*(?:\xEF\xBB\xBF)?(?:<!--.*?-->|\s|<\?xml[^>]*\?>|<!DOCTYPE[^>]*>)*"
                      rb"<\s*svg(?=[\s>])", re.IGNORECASE | re.DOTALL)


def _metadata():
    return App.Metadata(PACKAGE_XML)


def _check_icon(relative):
    path = os.path.join(REPO, relative)
    assert os.path.isfile(path), relative
    data = open(path, "rb").read()
    assert SVG_ROOT.search(data), f"{relative}: no <svg> root where the Addon Manager looks"
    ET.fromstring(data)  # well-formed XML


def test_read_by_freecad():
    meta = _metadata()
    assert meta.Name == "Deform"
    assert meta.supportsCurrentFreeCAD()
    assert str(meta.FreeCADMin).startswith("0.20"), meta.FreeCADMin
    import freecad_deform
    assert re.fullmatch(r"\d+\.\d+\.\d+", str(meta.Version)), meta.Version
    assert str(meta.Version) == freecad_deform.__version__
    date = ET.parse(PACKAGE_XML).getroot().find(NS + "date").text
    assert re.fullmatch(r"\d{4}-\d\d-\d\d", date), date


def test_people_and_license():
    meta = _metadata()
    assert meta.Maintainer and meta.Author
    assert [lic["name"] for lic in meta.License] == ["LGPL-2.1-or-later"]
    text = open(os.path.join(REPO, meta.License[0]["file"])).read()
    assert "LESSER GENERAL PUBLIC LICENSE" in text and "Version 2.1" in text


def test_icons():
    meta = _metadata()
    _check_icon(meta.Icon)
    for workbench in meta.Content["workbench"]:
        _check_icon(os.path.join(workbench.Subdirectory, workbench.Icon))


def test_workbench_class_and_dependencies():
    (workbench,) = _metadata().Content["workbench"]
    init_gui = open(os.path.join(REPO, workbench.Subdirectory, "InitGui.py")).read()
    assert re.search(rf"^class {workbench.Classname}\(Workbench\)", init_gui, re.M)
    node = ET.parse(PACKAGE_XML).getroot().find(f"{NS}content/{NS}workbench")
    depends = [(d.get("type"), d.text) for d in node.findall(NS + "depend")]
    assert {kind for kind, _ in depends} == {"internal", "python"}, depends
    import importlib
    for kind, name in depends:
        # an internal workbench is named in lower case; its module is capitalised
        importlib.import_module(name.capitalize() if kind == "internal" else name)


def test_running_freecad_is_listed_as_tested():
    major, minor = App.Version()[:2]
    tags = _metadata().Tag
    assert f"FreeCAD {major}.{minor}" in tags, tags
