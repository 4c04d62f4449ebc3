"""Goal seek (`solve`, fd.solve) on the stretched sample part, against closed forms: the
Distance that gives a prescribed volume is (V - V0) / A (A: the section measured by OCCT's
slice and a face maker), and stretch distances that give prescribed bounding-box lengths."""
import pytest

import freecad_deform as fd
from freecad_deform.geometry.errors import DeformError

from .conftest import App, cli

D = 37.25  # mm: the prescribed volume is V0 + A x D


def test_solve_command_hits_closed_form(part_doc, tmp_path):
    volume = part_doc["V0"] + part_doc["A"] * D
    solved = tmp_path / "solved.FCStd"
    done = cli("solve", part_doc["path"], "--vary", "Stretch.Distance=0:100", "--target",
               f"Stretch.Shape.Volume={volume!r}", "--out", solved)
    last = done.stdout.strip().splitlines()[-1]
    name, _, value = last.partition(" = ")
    assert name == "Stretch.Distance"
    closed_form = (volume - part_doc["V0"]) / part_doc["A"]
    assert abs(float(value) - closed_form) < 1e-8  # mm (measured: 2e-14)
    doc = App.openDocument(str(solved))
    try:
        obj = doc.getObject("Stretch")
        assert obj.Distance.Value == float(value)
        assert obj.Shape.isValid() and abs(obj.Shape.Volume - volume) < 1e-6 * volume
    finally:
        App.closeDocument(doc.Name)


def test_fd_solve_leaves_the_document_at_the_solution(part_doc):
    doc = App.openDocument(part_doc["path"])
    try:
        change = part_doc["A"] * 12.5
        found = fd.solve(doc, vary={"Stretch.Distance": (-100, 100)},
                         target={"Stretch.VolumeChange": change})
        assert set(found) == {"Stretch.Distance", "residual", "iterations"}
        assert abs(found["Stretch.Distance"] - 12.5) < 1e-8
        assert found["residual"] < 1e-6 * change and 1 <= found["iterations"] < 30
        obj = doc.getObject("Stretch")
        assert obj.Distance.Value == found["Stretch.Distance"]
        assert "Touched" not in obj.State
        assert abs(obj.Shape.Volume - part_doc["V0"] - change) < 1e-6 * obj.Shape.Volume
    finally:
        App.closeDocument(doc.Name)


def test_two_properties_two_targets(part_doc):
    """Bounded least squares: a second Stretch along +Z at z = 100; XLength 350 and ZLength
    250 of the 315 x 225 part need Distances 35 and 25."""
    doc = App.openDocument(part_doc["path"])
    try:
        fd.make_stretch(doc.getObject("Stretch"),
                        (App.Vector(0, 0, 100), App.Vector(0, 0, 1)), 10)
        found = fd.solve(doc, vary={"Stretch.Distance": (0, 80), "Stretch001.Distance":
                                    (0, 80)},
                         target={"Stretch001.Shape.BoundBox.XLength": 350.0,
                                 "Stretch001.Shape.BoundBox.ZLength": 250.0})
        assert abs(found["Stretch.Distance"] - 35) < 1e-8
        assert abs(found["Stretch001.Distance"] - 25) < 1e-8
        assert found["residual"] < 1e-6
    finally:
        App.closeDocument(doc.Name)


def test_bounds_where_the_model_fails_are_named(part_doc):
    doc = App.openDocument(part_doc["path"])
    try:
        with pytest.raises(DeformError, match="--vary"):
            fd.solve(doc, vary={"Stretch.Distance": (-500, 100)},
                     target={"Stretch.VolumeChange": 1.0})
    finally:
        App.closeDocument(doc.Name)


def test_maximize_at_a_bound(part_doc):
    """--maximize the part's length over Distance in [-50, 50]: the bound 50 exactly,
    length 315 + 50 (the optimum of a bounded search checked against its bounds)."""
    done = cli("solve", part_doc["path"], "--vary", "Stretch.Distance=-50:50", "--maximize",
               "Stretch.Shape.BoundBox.XLength")
    lines = dict(line.split(" = ") for line in done.stdout.strip().splitlines())
    assert float(lines["Stretch.Distance"]) == 50.0
    assert abs(float(lines["maximum"]) - 365.0) < 1e-9


def test_progress_lists_each_recompute(part_doc):
    """progress(n, values, outputs) once per recompute (the GUI's list), n counting up to
    the iterations reported; a value met before is not recomputed during the search (the
    last recompute puts the document back at the solution)."""
    doc = App.openDocument(part_doc["path"])
    try:
        seen = []
        change = part_doc["A"] * 12.5
        found = fd.solve(doc, vary={"Stretch.Distance": (0, 100)},
                         target={"Stretch.VolumeChange": change},
                         progress=lambda n, x, out: seen.append((n, x[0], out[0])))
        assert [n for n, _, _ in seen] == list(range(1, found["iterations"] + 1))
        assert len({x for _, x, _ in seen[:-1]}) == len(seen) - 1
        assert abs(seen[-1][1] - found["Stretch.Distance"]) < 1e-9
        assert abs(found["Stretch.Distance"] - 12.5) < 1e-8
    finally:
        App.closeDocument(doc.Name)
