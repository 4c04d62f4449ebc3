"""`run`: a model file plus a recipe, and a saved document, recomputed and exported; the
table's numbers against the section-area oracle, the exports read back."""
import csv
import json

import Mesh
import Part

from .conftest import (CUT_X, FREECADCMD, PART, cli, mod_home, model_path, saved_with_proxy,
                       section_area)


def _table(path):
    with open(path, newline="") as f:
        return {(r["object"], r["output"]): r["value"] for r in csv.DictReader(f)}


def test_help_names_every_subcommand():
    text = cli("--help").stdout
    for word in ("run", "sweep", "solve", "Object.Property", "--scheduler"):
        assert word in text
    for command in ("run", "sweep", "solve"):
        assert "usage:" in cli(command, "--help").stdout


def test_run_recipe_on_step_file(tmp_path):
    """The STEP part stretched by a recipe (Distance set to 3 cm afterwards): VolumeChange
    is A x 30 mm, the exported STEP reads back valid with volume V0 + A x 30."""
    recipe = tmp_path / "recipe.json"
    recipe.write_text(json.dumps({
        "steps": [{"make": "stretch", "base": "Model", "label": "S",
                   "args": [[[CUT_X, 0, 0], [1, 0, 0]], 40]}],
        "set": {"S.Distance": "3 cm"}}))
    done = cli("run", model_path(PART), "--recipe", recipe, "--out", tmp_path / "out",
               "--export", "step,stl,fcstd")
    assert "Stretch.VolumeChange" in done.stdout
    table = _table(tmp_path / "out" / "results.csv")
    base = Part.read(model_path(PART))
    area = section_area(base, CUT_X)
    assert table[("Stretch", "valid")] == "True" and table[("Stretch", "error")] == ""
    assert abs(float(table[("Stretch", "VolumeChange")]) - area * 30) < 1e-6 * area * 30
    assert float(table[("Stretch", "seconds")]) > 0
    step = Part.read(str(tmp_path / "out" / "face_recognition_sample_part_Stretch.step"))
    assert step.isValid()
    assert abs(step.Volume - (base.Volume + area * 30)) < 1e-6 * step.Volume
    stl = Mesh.Mesh(str(tmp_path / "out" / "face_recognition_sample_part_Stretch.stl"))
    assert stl.isSolid() and not stl.hasNonManifolds()
    assert abs(stl.Volume - step.Volume) < 1e-2 * step.Volume  # tessellated
    assert (tmp_path / "out" / "face_recognition_sample_part.FCStd").stat().st_size > 0


def test_run_document_through_freecadcmd(part_doc, tmp_path):
    """The same command inside FreeCAD's console (the add-on in Mod/), after `--`: the
    table of the saved document (Distance 40 mm) with VolumeChange = A x 40."""
    done = cli("run", part_doc["path"], "--out", tmp_path, "--export", "brep",
               prefix=FREECADCMD, home=mod_home(tmp_path / "home"))
    assert "Stretch.VolumeChange" in done.stdout
    table = _table(tmp_path / "results.csv")
    expected = part_doc["A"] * 40
    assert abs(float(table[("Stretch", "VolumeChange")]) - expected) < 1e-6 * expected
    brep = Part.read(str(tmp_path / "part_Stretch.brep"))
    assert brep.isValid() and abs(brep.Volume - part_doc["V0"] - expected) < 1e-6 * brep.Volume


def test_objects_that_did_not_load_are_refused(tmp_path):
    """A document whose Python object comes from a module the command cannot import: the
    object would not recompute, so the run is refused (exit status 2) instead of reporting
    its stored results as new ones."""
    saved_with_proxy(tmp_path, "ghost_proxy",
                     "class Ghost:\n"
                     "    def __init__(self, obj):\n"
                     "        obj.Proxy = self\n"
                     "    def execute(self, obj):\n"
                     "        pass\n"
                     "    def dumps(self):\n"
                     "        return None\n"
                     "    def loads(self, state):\n"
                     "        return None\n",
                     "Ghost", "Part::FeaturePython", tmp_path / "ghost.FCStd")
    done = cli("run", tmp_path / "ghost.FCStd", "--out", tmp_path / "out", check=False)
    assert done.returncode == 2 and "Ghost did not load" in done.stderr
    assert not (tmp_path / "out" / "results.csv").exists()


def test_run_failing_document(tmp_path):
    """A recipe whose Stretch shrinks past the end of the part: exit status 1, the object's
    error in the table, naming Distance."""
    recipe = tmp_path / "recipe.json"
    recipe.write_text(json.dumps({
        "steps": [{"make": "stretch", "base": "Model",
                   "args": [[[CUT_X, 0, 0], [1, 0, 0]], 40]}],
        "set": {"Stretch.Distance": -500}}))
    done = cli("run", model_path(PART), "--recipe", recipe, "--out", tmp_path, check=False)
    assert done.returncode == 1
    table = _table(tmp_path / "results.csv")
    assert table[("Stretch", "valid")] == "False"
    assert "Distance" in table[("Stretch", "error")]


def test_run_mesh_recipe(tmp_path):
    """A real STL mesh (the finned housing) stretched through a recipe, exported as STL and
    PLY: both read back closed, with the result's facet count."""
    mesh = Mesh.Mesh(model_path("occt_sh2.stl"))
    box = mesh.BoundBox
    z = box.ZMin + 0.5 * box.ZLength
    recipe = tmp_path / "recipe.json"
    recipe.write_text(json.dumps({"steps": [{"make": "stretch", "base": "Model",
                                            "args": [[[0, 0, z], [0, 0, 1]], 10]}]}))
    cli("run", model_path("occt_sh2.stl"), "--recipe", recipe, "--out", tmp_path,
        "--export", "stl,ply")
    stl, ply = (Mesh.Mesh(str(tmp_path / f"occt_sh2_Stretch.{e}")) for e in ("stl", "ply"))
    assert stl.isSolid() and ply.isSolid()
    assert stl.CountFacets == ply.CountFacets > mesh.CountFacets
    assert abs(stl.BoundBox.ZLength - (box.ZLength + 10)) < 1e-4
