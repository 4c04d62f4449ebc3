"""The demo (`make demo`) in its quick form: one section per feature on real models
(face_recognition_sample_part.stp, fandisk.obj, splinecage.stp) and shapes it makes, each
checked by the demo against an independent oracle (A x d, Pappus, Rodrigues, a closed-form
taper volume, SVD plane fits, a converged quadrature, OCCT's distToShape). The report must
list all seven features valid, with the exports written and the pictures rendered by
FreeCAD's 3D view (before and after differ; the planes' red sheets show)."""
import json
import os
import subprocess
import sys

import numpy as np

from .conftest import REPO

FEATURES = ["Stretch", "Bend", "Twist", "Taper", "DimensionDrive", "AreaConstrain",
            "DirectPush"]


def sides(png):
    """The before and after halves of a demo picture below its title, as RGB in 0..1."""
    from matplotlib.image import imread
    rgb = imread(str(png))[60:, :, :3]
    w = rgb.shape[1] // 2
    return rgb[:, :w], rgb[:, w:2 * w]


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
        before, after = sides(out / f"{name}.png")
        # FreeCAD's 3D view drew the part on both sides, and the two differ
        assert 0.005 < (before < 0.95).any(axis=2).mean() < 0.9, name
        assert 0.005 < (after < 0.95).any(axis=2).mean() < 0.9, name
        assert np.abs(before - after).mean() > 0.002, name
        if name in ("stretch", "bend", "twist", "taper"):
            # the planes' translucent red sheets: pixels far redder than grey, blue or orange
            red = (before[..., 0] - before[..., 1] > 0.12) & (before[..., 0] - before[..., 2] > 0.12)
            assert red.mean() > 0.002, name
    pictures = next(s for s in report["sections"] if s["name"] == "Pictures")
    assert pictures["checks"] and all(c["status"] == "ok" for c in pictures["checks"])
    for name in ("stretch.step", "taper.step", "dimension_drive.stl", "area_constrain.step",
                 "direct_push.step", "demo.FCStd"):
        assert (out / name).stat().st_size > 0
