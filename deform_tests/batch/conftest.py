"""Shared set-up of the batch tests: real FreeCAD (never skipped), models from the shared
test data, the command line as a user runs it (a new process), and the oracles."""
import os
import subprocess
import sys

import pytest

from deform_tests.features.fc import REPO, App  # noqa: F401  (imports FreeCAD)
from deform_tests.features.fc import testdata as model_path

import Part  # noqa: E402

PART = "face_recognition_sample_part.stp"
CUT_X = 150.0  # the Stretch plane of the part: x = 150, normal +X


def cli(*args, cwd=REPO, check=True, prefix=(sys.executable, "-m", "freecad_deform"),
        home=None):
    """Run the command line in its own process; returns the CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=REPO, **({"HOME": str(home)} if home else {}))
    done = subprocess.run([*prefix, *map(str, args)], cwd=cwd, env=env, capture_output=True,
                          encoding="utf-8", errors="replace", timeout=600)
    if check and done.returncode != 0:
        raise AssertionError(f"exit {done.returncode}\n{done.stdout}\n{done.stderr}")
    return done


def mod_home(folder, addon="freecad_deform", source=REPO):
    """A HOME whose FreeCAD Mod folders (0.20, 1.0, 1.1) hold an add-on: FreeCAD restores
    the Python objects of installed add-ons only."""
    for mod in (".local/share/FreeCAD/Mod", ".local/share/FreeCAD/v1-1/Mod", ".FreeCAD/Mod"):
        (folder / mod).mkdir(parents=True, exist_ok=True)
        (folder / mod / addon).symlink_to(source)
    return folder


def saved_with_proxy(folder, module, source, cls, type_id, path):
    """Save at `path` a document holding one `type_id` object whose proxy is `cls` of the
    module `module` (its `source` written into `folder`, which is on sys.path only while
    the document is made): a Python object only FreeCAD installs of that folder restore."""
    (folder / f"{module}.py").write_text(source)
    sys.path.insert(0, str(folder))
    try:
        proxy = getattr(__import__(module), cls)
        doc = App.newDocument(cls)
        proxy(doc.addObject(type_id, cls))
        doc.saveAs(str(path))
        App.closeDocument(doc.Name)
    finally:
        sys.path.remove(str(folder))


FREECADCMD = ("freecadcmd", f"{REPO}/freecad_deform/batch/freecadcmd.py", "--")


def section_area(shape, x):
    """Area of the shape's section by the plane at x (normal +X): OCCT's slice wires made
    into a face (holes included) by FreeCAD's bullseye face maker."""
    wires = shape.slice(App.Vector(1, 0, 0), x)
    return Part.makeFace(wires, "Part::FaceMakerBullseye").Area


@pytest.fixture(scope="session")
def part_doc(tmp_path_factory):
    """part.FCStd: the machined sample part (Model) stretched by 40 mm at x = 150 (Stretch);
    with the part's volume V0 and section area A there, measured independently."""
    import freecad_deform as fd
    folder = tmp_path_factory.mktemp("batch")
    doc = App.newDocument("BatchPart")
    model = doc.addObject("Part::Feature", "Model")
    model.Shape = Part.read(model_path(PART))
    fd.make_stretch(model, (App.Vector(CUT_X, 0, 0), App.Vector(1, 0, 0)), 40)
    path = str(folder / "part.FCStd")
    doc.saveAs(path)
    v0, area = model.Shape.Volume, section_area(model.Shape, CUT_X)
    App.closeDocument(doc.Name)
    return {"path": path, "V0": v0, "A": area}
