"""`sweep` on the stretched sample part: the results table's layout and numbers (A x d from
the section-area oracle), a failing variant, a resumed sweep, and the same table bit for
bit from 2 local worker processes and from a 2-worker local Dask cluster."""
import csv
import os

import Part
import pytest

from .conftest import FREECADCMD, App, cli, mod_home, saved_with_proxy

DISTANCES = ["10", "-500", "25.5", "3 cm", "3 kg"]  # -500 shrinks past the end, kg: fail
MM = [10.0, None, 25.5, 30.0, None]


def _write_table(folder):
    path = folder / "designs.csv"
    path.write_text("Stretch.Distance\n" + "\n".join(f'"{d}"' for d in DISTANCES) + "\n")
    return path


def _rows(folder):
    with open(folder / "results.csv", newline="") as f:
        return list(csv.reader(f))


def _without_seconds(rows):
    k = rows[0].index("seconds")
    return [r[:k] + r[k + 1:] for r in rows]


@pytest.fixture(scope="module")
def serial(part_doc, tmp_path_factory):
    """The sweep in this process's command (--jobs 1), STEP and FCStd exports."""
    folder = tmp_path_factory.mktemp("serial")
    done = cli("sweep", part_doc["path"], "--table", _write_table(folder), "--out",
               folder / "out", "--jobs", 1, "--export", "step,fcstd")
    return folder / "out", done


def test_sweep_table_and_oracle(part_doc, serial):
    out, done = serial
    rows = _rows(out)
    header = rows[0]
    assert header[0] == "Stretch.Distance"
    assert header[-3:] == ["valid", "seconds", "error"]
    assert "Stretch.VolumeChange" in header and "Stretch.Continuity" in header
    assert all(h.count(".") == 1 for h in header[:-3])
    assert [r[0] for r in rows[1:]] == DISTANCES  # table order
    col = header.index("Stretch.VolumeChange")
    for row, d in zip(rows[1:], MM):
        if d is None:
            continue
        assert row[-3] == "True" and row[-1] == ""
        expected = part_doc["A"] * d
        assert abs(float(row[col]) - expected) < 1e-6 * expected
        step = Part.read(str(out / "exports" / f"variant-{rows.index(row):04d}_Stretch.step"))
        assert step.isValid()
        assert abs(step.Volume - part_doc["V0"] - expected) < 1e-6 * step.Volume
    assert "ETA" in done.stderr and "5/5" in done.stderr


def test_failing_variant_is_recorded(serial):
    out, _ = serial
    failed = _rows(out)[2]
    assert failed[0] == "-500" and failed[-3] == "False"
    assert "Distance" in failed[-1] and "shrinks past the end" in failed[-1]
    assert not os.path.exists(out / "exports" / "variant-0002_Stretch.step")
    wrong_unit = _rows(out)[5]
    assert wrong_unit[-3] == "False"
    assert wrong_unit[-1].startswith("Stretch.Distance cannot take '3 kg' (Not matching "
                                     "Unit!); give a value of its kind")
    doc = App.openDocument(str(out / "exports" / "variant-0002.FCStd"))  # kept to look into
    try:
        assert doc.getObject("Stretch").Distance.Value == -500
    finally:
        App.closeDocument(doc.Name)


def test_resumed_sweep_skips_done_rows(part_doc, serial, tmp_path):
    """Rows 1 and 2 left from an interrupted run (their seconds set to a marker the run
    cannot produce): the rerun keeps them as they are and computes rows 3 to 5."""
    out, _ = serial
    rows = _rows(out)
    k = rows[0].index("seconds")
    kept = [r[:k] + ["-1.0"] + r[k + 1:] for r in rows[1:3]]
    (tmp_path / "out").mkdir()
    with open(tmp_path / "out" / "results.csv", "w", newline="") as f:
        csv.writer(f).writerows([rows[0]] + kept)
    done = cli("sweep", part_doc["path"], "--table", _write_table(tmp_path), "--out",
               tmp_path / "out", "--jobs", 1)
    assert "2 of 5 variants already" in done.stderr and "3/3" in done.stderr
    again = _rows(tmp_path / "out")
    assert again[1:3] == kept
    assert _without_seconds(again) == _without_seconds(rows)
    assert all(float(r[k]) > 0 for r in again[3:5])


def test_two_local_workers_same_table(part_doc, serial, tmp_path):
    """--jobs 2: two FreeCAD worker processes; the table is the serial one bit for bit
    (every cell but the measured seconds)."""
    cli("sweep", part_doc["path"], "--table", _write_table(tmp_path), "--out",
        tmp_path / "out", "--jobs", 2)
    assert _without_seconds(_rows(tmp_path / "out")) == _without_seconds(_rows(serial[0]))


def test_two_workers_under_freecadcmd_same_table(part_doc, serial, tmp_path):
    """The sweep started inside FreeCAD's console: its workers are Python processes (the
    Python FreeCAD is built on), the table the serial one bit for bit (but the seconds)."""
    cli("sweep", part_doc["path"], "--table", _write_table(tmp_path), "--out",
        tmp_path / "out", "--jobs", 2, prefix=FREECADCMD, home=mod_home(tmp_path / "home"))
    assert _without_seconds(_rows(tmp_path / "out")) == _without_seconds(_rows(serial[0]))


def test_two_worker_dask_cluster_same_table(part_doc, serial, tmp_path):
    """--scheduler: a local Dask cluster of 2 worker processes gets the same tasks; the
    table is the serial one bit for bit (but the seconds)."""
    from distributed import LocalCluster  # Debian: python3-distributed (.ci/install-deps)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        cli("sweep", part_doc["path"], "--table", _write_table(tmp_path), "--out",
            tmp_path / "out", "--scheduler", cluster.scheduler_address)
    assert _without_seconds(_rows(tmp_path / "out")) == _without_seconds(_rows(serial[0]))


def test_grid_from_the_command_line(part_doc, tmp_path):
    """--grid LO:HI:N writes the table it ran and gives one row per value."""
    cli("sweep", part_doc["path"], "--grid", "Stretch.Distance=5:15:3", "--out", tmp_path,
        "--jobs", 1)
    rows = _rows(tmp_path)
    assert [float(r[0]) for r in rows[1:]] == [5.0, 10.0, 15.0]
    assert (tmp_path / "table.csv").read_text().splitlines()[0] == "Stretch.Distance"


def test_unknown_column_is_refused(part_doc, tmp_path):
    (tmp_path / "t.csv").write_text("Stretch.Distanse\n10\n")
    done = cli("sweep", part_doc["path"], "--table", tmp_path / "t.csv", "--out", tmp_path,
               check=False)
    assert done.returncode == 2 and "Distanse" in done.stderr


CRASH = """import os


class Crash:
    '''A document object that kills its FreeCAD when Mode is 2.'''

    def __init__(self, obj):
        obj.Proxy = self
        obj.addProperty("App::PropertyInteger", "Mode", "Crash", "")
        obj.addProperty("App::PropertyFloat", "Value", "Crash", "", 1 | 8)

    def execute(self, obj):
        if obj.Mode == 2:
            os._exit(3)
        obj.Value = obj.Mode * 1.5

    def dumps(self):
        return None

    def loads(self, state):
        return None
"""


def test_a_crashing_variant_does_not_stop_the_sweep(tmp_path):
    """Variant 2 kills its worker process (as a FreeCAD crash would): it is recorded as a
    crash, and the others still run, each result right."""
    addon = tmp_path / "CrashAddon"  # installed in a Mod folder, as FreeCAD requires
    addon.mkdir()
    saved_with_proxy(addon, "crash_proxy", CRASH, "Crash", "App::FeaturePython",
                     tmp_path / "crash.FCStd")
    (tmp_path / "t.csv").write_text("Crash.Mode\n1\n2\n3\n4\n")
    cli("sweep", tmp_path / "crash.FCStd", "--table", tmp_path / "t.csv", "--out",
        tmp_path / "out", "--jobs", 2,
        home=mod_home(tmp_path / "home", "CrashAddon", addon))
    rows = _rows(tmp_path / "out")
    assert rows[0] == ["Crash.Mode", "Crash.Value", "valid", "seconds", "error"]
    assert [r[1] for r in rows[1:]] == ["1.5", "", "4.5", "6.0"]
    assert [r[2] for r in rows[1:]] == ["True", "False", "True", "True"]
    assert "crashed" in rows[2][4]
