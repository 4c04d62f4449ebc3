"""The Deform workbench in the real FreeCAD GUI, under Xvfb.

FreeCAD runs with a temporary HOME whose user Mod directory (asked from FreeCAD itself)
links to this repository, so the workbench is found the way a user installs it
(freecad_deform.batch.gui_run). The scenario (freecad_scenario.py) runs inside the GUI
and writes a JSON report; this file asserts on it. Screenshots and the saved document go to deform_tests/gui/_out/ (or $DEFORM_GUI_OUT).

Run: /usr/bin/python3 -m pytest deform_tests/gui -q
Missing FreeCAD or xvfb-run is a failure, not a skip.
"""
import json
import os
import subprocess
import time

import pytest

from freecad_deform.batch.gui_run import install, run_script, tool

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
TESTDATA = os.path.normpath(os.path.join(REPO, "..", "shared", "testdata"))
OUT = os.environ.get("DEFORM_GUI_OUT") or os.path.join(HERE, "_out")  # make test-freecad11 sets it
SCENARIO = os.path.join(HERE, "freecad_scenario.py")
TIMEOUT = 300  # seconds for the whole GUI run; it takes about 40 s


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    assert os.path.isfile(os.path.join(TESTDATA, "face_recognition_sample_part.stp")), TESTDATA
    home = tmp_path_factory.mktemp("home")
    try:
        tool("freecad", "FreeCAD"), tool("xvfb-run")
        mod_dir = install(home)
    except (FileNotFoundError, RuntimeError) as e:
        pytest.fail(f"the GUI tests need FreeCAD's GUI and xvfb-run: {e}")
    assert mod_dir.startswith(str(home)), mod_dir

    os.makedirs(OUT, exist_ok=True)
    result_path = os.path.join(OUT, "gui_result.json")
    if os.path.exists(result_path):
        os.remove(result_path)
    start = time.time()
    try:
        proc = run_script(SCENARIO, home, TIMEOUT, DEFORM_GUI_RESULT=result_path,
                          DEFORM_GUI_OUT=OUT, DEFORM_TESTDATA=TESTDATA)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"FreeCAD GUI did not finish in {TIMEOUT} s\n{e.stdout}\n{e.stderr}")
    elapsed = time.time() - start
    log = f"exit {proc.returncode} after {elapsed:.1f} s\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
    if not os.path.exists(result_path):
        pytest.fail("the GUI scenario wrote no result\n" + log)
    with open(result_path, encoding="utf-8") as f:
        result = json.load(f)
    result["log"] = log
    result["output"] = proc.stdout + proc.stderr
    with open(os.path.join(OUT, "gui_output.txt"), "w", encoding="utf-8") as f:
        f.write(result["output"])   # FreeCAD's console: look here when a check fails
    result["elapsed"] = elapsed
    return result


def test_scenario_finished(gui_run):
    assert gui_run["error"] is None, gui_run["error"] + "\n" + gui_run["log"]


def test_no_python_error_escaped(gui_run):
    """No exception escaped a command, a field's handler or a drag into FreeCAD or Qt (they
    print a traceback and the user sees nothing): the only tracebacks in FreeCAD's console
    are its reports of a feature's refusal (a DeformError raised in execute)."""
    for block in gui_run["output"].split("Traceback (most recent call last)")[1:]:
        frames = [line for line in block.splitlines() if line.strip().startswith("File ")]
        refusal = frames and frames[0].endswith(", in execute") and "DeformError" in block
        assert refusal, block[:3000]


def test_all_checks_pass(gui_run):
    failed = [c for c in gui_run["checks"] if not c["ok"]]
    assert gui_run["checks"], "no checks ran\n" + gui_run["log"]
    assert not failed, "\n".join(f"{c['name']}: {c['detail']}" for c in failed)


@pytest.mark.parametrize("name", [
    "workbench active", "active with the solid selected", "inactive with nothing selected",
    "one Stretch after OK", "valid single solid", "VolumeChange > 0", "one undo step",
    "undo removes the Stretch", "cancel: no new object", "cancel: Base visible",
    "edit cancel restores Distance", "reopen: view provider restored", "reopen: icon",
    "toolbar: Stretch, Bend, Twist", "Bend/Twist active with the solid selected",
    "Bend/Twist inactive with nothing selected", "Bend defaults: valid preview, no error",
    "Bend: valid single solid", "Bend: VolumeChange = Pappus (OCCT volume)", "Bend: one undo step",
    "Bend: undo removes it", "Bend: Cancel leaves the document unchanged",
    "Pick axis: Axis on the edge's line, nearest to Plane's origin",
    "Twist defaults: valid preview, no error", "Twist: valid single solid",
    "Twist: mid section = the section turned by Angle/2", "Twist: one undo step",
    "Twist: Cancel leaves the document unchanged",
    "Twist from an edge: UseAxis, Axis on the edge, valid",
    "DimensionDrive: regions in colour while open", "DimensionDrive: picks give the top and bottom planes",
    "DimensionDrive: a click in the 3D view picks a region", "DimensionDrive: valid, Achieved = 40",
    "Twist: Angle 400 deg is one turn (Turns) and 40 deg",
    "bad Plane: the Plane group is outlined red", "Bend: the Angle field is outlined red",
    "Taper registered, with its icon", "toolbar and menu: Taper after Twist",
    "Taper active with the solid selected", "Taper panel opens",
    "Taper defaults: planes at x = 40 and 80, Scale 0.8, valid",
    "Taper panel labels are the property names",
    "Taper: ScaleX, ScaleY and the Axis fields disabled while unused",
    "Taper: live preview, volume = closed form (Scale 0.5)",
    "Taper: Profile Smooth previews a valid solid",
    "Taper: UseScaleXY scales along X and Y of the frame (closed form)",
    "Taper: one valid solid after OK", "Taper: one undo step", "Taper: undo removes it",
    "Taper: Cancel leaves the document unchanged",
    "Twist handles: two plane sliders and an angle disc in the 3D view",
    "Twist guides: a sheet in each plane (x = 40, 80) across the box, no axis line",
    "Twist handle: Plane lands where its handle was let go (1 px)",
    "Twist handle: the disc turns Angle by the angle swept in its plane (5 deg)",
    "Twist handles gone after Cancel",
    "Drive matching region: active with a drive and a mesh",
    "Drive matching region: the shaft's drive follows the bore's Target (1e-6)",
    "DimensionDrive: one undo step", "DimensionDrive: undo removes it",
    "DimensionDrive: Cancel leaves the document unchanged",
    "AreaConstrain: active with a face selected", "AreaConstrain: control net drawn while open",
    "AreaConstrain: a click on pole (2, 3) picks it",
    "AreaConstrain: AchievedArea / OriginalArea = 1.05", "AreaConstrain: net gone after OK",
    "AreaConstrain: one undo step", "AreaConstrain: undo removes it",
    "AreaConstrain: Cancel leaves the document unchanged",
    "DirectPush: active with an edge selected",
    "DirectPush: a click adds a fixed point on the curve",
    "DirectPush: two clicks add a straight span", "DirectPush: one push recorded",
    "DirectPush: the grabbed point is on the result at the target (1e-6)",
    "DirectPush: the target is where the mouse let go, in the view plane",
    "DirectPush: the drag does not select", "DirectPush: one undo step",
    "DirectPush: undo removes it", "DirectPush: the preview updates on every move",
    "DirectPush: surface preview shown while dragging, the result hidden",
    "DirectPush: removing the first push keeps the second valid",
    "DirectPush: Shift drags the top face up along its normal",
    "DirectPush: box result one valid solid",
    "DirectPush: Cancel after a drag leaves the document unchanged",
    "DirectPush: edit, drag, Cancel restores the pushes",
    "DirectPush: a degenerated edge: no object, no panel",
    "Solve registered, with its icon", "Solve: iterations and residual shown, each recompute listed",
    "Solve: Distance = target / A (closed form A x d, 1e-9 mm)", "Solve: one undo step",
    "Solve: undo restores Distance 10", "Solve: Cancel leaves the document unchanged",
])
def test_key_check(gui_run, name):
    found = [c for c in gui_run["checks"] if c["name"] == name]
    assert found, f"check {name!r} did not run (scenario stopped early?)\n{gui_run['error']}"
    assert found[0]["ok"], found[0]["detail"]


def test_screenshots_written(gui_run, capsys):
    shots = gui_run["screenshots"]
    with capsys.disabled():  # shown also in a quiet run: look at them
        print(f"\nGUI run {gui_run['elapsed']:.1f} s; screenshots:")
        for path in shots:
            print(f"  {path}")
    names = sorted(os.path.basename(p) for p in shots)
    assert names == sorted([
        "stretch_task_panel_error.png", "stretch_panel.png", "stretch_task_panel.png",
        "stretch_window.png", "stretch_result.png", "stretch_reopened.png",
        "bend_task_panel.png", "bend_result.png", "twist_task_panel.png",
        "twist_result.png", "taper_task_panel.png", "taper_result.png", "twist_handles.png", "dimension_drive.png", "dimension_drive_task_panel.png",
        "area_constrain.png", "area_constrain_task_panel.png", "direct_push.png",
        "direct_push_task_panel.png", "solve_task_panel.png"]), names
    for path in shots:
        assert os.path.getsize(path) > 5000, path
        assert _drawn_fraction(path) > 0.02, f"{path} is (nearly) blank"


def test_direct_push_drag_rate(gui_run, capsys):
    """The drag preview's rate on a 20 x 20-pole surface, shown also in a quiet run
    (reported, not asserted: speed is measured in benchmarks/)."""
    found = [c for c in gui_run["checks"] if c["name"] ==
             "DirectPush: the preview updates on every move"]
    assert found, "the DirectPush drag was not measured"
    with capsys.disabled():
        print(f"\nDirectPush drag, 20 x 20 poles: {found[0]['detail']}")


def _drawn_fraction(path):
    """Share of pixels that differ from the white background (matplotlib reads the PNG)."""
    from matplotlib import image
    pixels = image.imread(path)[..., :3]
    return float((pixels < 0.95).any(axis=-1).mean())
