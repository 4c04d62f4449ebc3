"""The demo (`make demo`) in its quick form: one section per feature on real models
(face_recognition_sample_part.stp, fandisk.obj, splinecage.stp) and shapes it makes, each
checked by the demo against an independent oracle (A x d, Pappus, Rodrigues, a closed-form
taper volume, SVD plane fits, a converged quadrature, OCCT's distToShape). The report must
list all seven features valid, with the exports and pictures written."""
import json
import os
import subprocess
import sys

from .conftest import REPO

FEATURES = ["Stretch", "Bend", "Twist", "Taper", "DimensionDrive", "AreaConstrain",
            "DirectPush"]


def test_quick_demo_lists_every_feature_valid(tmp_path):
    out = tmp_path / "demo_out"
    done = subprocess.run([sys.executable, os.path.join(REPO, "examples", "demo.py"), str(out),
                           "--quick"], cwd=REPO, capture_output=True, encoding="utf-8",
                          errors="replace", timeout=600)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-4000:]
    report = json.loads((out / "report.json").read_text())
    rows = {r["feature"]: r for r in report["features"]}
    assert list(rows) == FEATURES
    for name, row in rows.items():
        assert row["valid"], row
        assert row["error"] <= row["tolerance"], row
    assert report["failed"] == 0
    markdown = (out / "report.md").read_text()
    assert "## Features" in markdown and markdown.count("| yes |") == len(FEATURES)
    for name in ("stretch", "bend", "twist", "taper", "dimension_drive", "area_constrain",
                 "direct_push"):
        assert (out / f"{name}.png").stat().st_size > 10_000
    for name in ("stretch.step", "taper.step", "dimension_drive.stl", "area_constrain.step",
                 "direct_push.step", "demo.FCStd"):
        assert (out / name).stat().st_size > 0
