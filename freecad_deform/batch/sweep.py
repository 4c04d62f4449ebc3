"""`sweep`: a design table becomes one recomputed variant per row and one row of
DIR/results.csv each (the table's columns, every output as "Object.Output", valid, seconds,
error), in table order. Rows already in results.csv are skipped on a rerun."""
import csv
import itertools
import os
import shutil
import sys
import time

import numpy as np

from . import model
from .variant import run_variant

TAIL = ["valid", "seconds", "error"]


def read_table(path):
    """(header, rows) of a CSV design table; every column an "Object.Property"."""
    with open(path, newline="") as f:
        lines = [r for r in csv.reader(f) if any(c.strip() for c in r)]
    if not lines:
        raise model.BatchError(f"--table {path} is empty; give a header of Object.Property "
                               f"columns and one row per variant.")
    header = [h.strip() for h in lines[0]]
    for h in header:
        model.split_path(h)
    rows = lines[1:]
    for i, row in enumerate(rows, 1):
        if len(row) != len(header):
            raise model.BatchError(f"row {i} of --table {path} has {len(row)} cells for "
                                   f"{len(header)} columns; give one value per column.")
    return header, [[c.strip() for c in r] for r in rows]


def grid_table(specs):
    """Command-line ranges as a table: "Obj.Prop=LO:HI:N" (N values, ends included) or
    "Obj.Prop=a,b,c"; several give every combination (the first varies slowest)."""
    header, axes = [], []
    for spec in specs:
        path, sep, values = spec.partition("=")
        if not sep:
            raise model.BatchError(f"--grid {spec!r} needs Object.Property=LO:HI:N or "
                                   f"=a,b,c.")
        model.split_path(path)
        if ":" in values:
            try:
                lo, hi, n = values.split(":")
                axis = [repr(float(v)) for v in np.linspace(float(lo), float(hi), int(n))]
            except ValueError:
                raise model.BatchError(f"--grid {spec!r}: give LO:HI:N with numbers and a "
                                       f"whole N.") from None
        else:
            axis = [v.strip() for v in values.split(",")]
        header.append(path.strip())
        axes.append(axis)
    return header, [list(r) for r in itertools.product(*axes)]


def _done_rows(path, header, table):
    """Result rows of an earlier run that match the table, by table index."""
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    if not lines:
        return {}
    if lines[0] != header:
        raise model.BatchError(f"{path} was written for another table or document; give "
                               f"another --out or remove it.")
    waiting = [list(r) for r in lines[1:]]
    done, k = {}, len(table[0]) if table else 0
    for i, row in enumerate(table):
        match = next((r for r in waiting if r[:k] == row), None)
        if match is not None:
            waiting.remove(match)
            done[i] = match
    return done


def _write(path, header, rows):
    tmp = path + ".part"
    with open(tmp, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows[i] for i in sorted(rows))
    os.replace(tmp, path)


class Progress:
    """A progress bar with the time left on stderr, one line per finished variant."""

    def __init__(self, total, stream=sys.stderr):
        self.total, self.done, self.start, self.stream = total, 0, time.monotonic(), stream

    def step(self, note):
        self.done += 1
        elapsed = time.monotonic() - self.start
        left = elapsed / self.done * (self.total - self.done)
        bar = "#" * round(20 * self.done / self.total)
        self.stream.write(f"[{bar:<20}] {self.done}/{self.total} elapsed {elapsed:.0f} s, "
                          f"ETA {left:.0f} s  {note}\n")
        self.stream.flush()


def _crashed(index):
    return {"index": index, "cells": {}, "valid": False, "seconds": 0.0, "files": {},
            "error": "FreeCAD crashed on this variant (its worker process died)."}


def worker_python():
    """The Python the workers run: this one, or inside freecadcmd the Python FreeCAD is
    built on (the one in its prefix; another python3 on PATH may not restore its objects)."""
    if os.path.basename(sys.executable or "").startswith("python"):
        return sys.executable
    own = os.path.join(sys.base_exec_prefix, "bin", "python%d.%d" % sys.version_info[:2])
    return own if os.path.isfile(own) else shutil.which("python3")


def _executor(jobs, scheduler):
    """Where the variants run: a Dask cluster, local worker processes (spawned: each one
    its own FreeCAD), or this process when jobs is 1. Yields results as they finish."""
    if scheduler:
        try:
            from distributed import Client, KilledWorker, as_completed
        except ImportError:
            raise model.BatchError("--scheduler needs Dask's distributed package (Debian: "
                                   "python3-distributed); install it or leave --scheduler "
                                   "out.") from None

        def run(tasks):
            with Client(scheduler) as client:
                futures = [client.submit(run_variant, t, pure=False) for t in tasks]
                index = {f.key: t["index"] for f, t in zip(futures, tasks)}
                for future in as_completed(futures):
                    try:
                        yield future.result()
                    except KilledWorker:  # the variant killed every worker it was given
                        yield _crashed(index[future.key])
        return run
    if jobs == 1:
        return lambda tasks: map(run_variant, tasks)

    def run(tasks):
        import concurrent.futures as cf
        import multiprocessing
        ctx = multiprocessing.get_context("spawn")
        ctx.set_executable(worker_python())
        left = []
        with cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
            futures = {pool.submit(run_variant, t): t for t in tasks}
            for future in cf.as_completed(futures):
                try:
                    yield future.result()
                except cf.process.BrokenProcessPool:  # a worker died: FreeCAD crashed
                    left.append(futures[future])
        # after a crash, each variant left runs in a process of its own, so the one that
        # crashes is found and the others still run
        for task in sorted(left, key=lambda t: t["index"]):
            with cf.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as alone:
                try:
                    yield alone.submit(run_variant, task).result()
                except cf.process.BrokenProcessPool:
                    yield _crashed(task["index"])
    return run


def sweep(doc_path, out, table=None, grid=(), jobs=None, scheduler=None, formats=(),
          retry_failed=False, stream=sys.stderr):
    """Run every variant not yet in out/results.csv; returns the rows by table index.
    A variant's exports are out/exports/variant-NNNN_Object.ext (NNNN: its table row)."""
    if table:
        header, rows = read_table(table)
    elif grid:
        header, rows = grid_table(grid)
    else:
        raise model.BatchError("give a design table with --table, or ranges with --grid.")
    os.makedirs(out, exist_ok=True)
    if not table:
        with open(os.path.join(out, "table.csv"), "w", newline="") as f:
            csv.writer(f).writerows([header] + rows)
    doc = model.open_document(doc_path)
    with open(doc_path, "rb") as f:
        data = f.read()
    try:
        outputs = model.output_names(doc)
        for path in header:
            name, attrs = model.split_path(path)
            if attrs[0] not in model.find_object(doc, name).PropertiesList:
                raise model.BatchError(f"{name} has no property {attrs[0]!r}; check the "
                                       f"column {path!r}.")
    finally:
        model.App.closeDocument(doc.Name)
    columns = header + outputs + TAIL
    results_path = os.path.join(out, "results.csv")
    done = _done_rows(results_path, columns, rows)
    if retry_failed:
        done = {i: r for i, r in done.items() if r[-3] == "True"}
    tasks = [{"index": i, "doc": data, "values": list(zip(header, row)), "outputs": outputs,
              "formats": list(formats), "stem": f"variant-{i + 1:04d}"}
             for i, row in enumerate(rows) if i not in done]
    if done:
        stream.write(f"{len(done)} of {len(rows)} variants already in {results_path}; "
                     f"running the other {len(tasks)}\n")
    progress = Progress(max(len(tasks), 1), stream)
    jobs = jobs or os.cpu_count() or 1
    for result in _executor(min(jobs, max(len(tasks), 1)), scheduler)(tasks):
        i = result["index"]
        for name, blob in result["files"].items():
            os.makedirs(os.path.join(out, "exports"), exist_ok=True)
            with open(os.path.join(out, "exports", name), "wb") as f:
                f.write(blob)
        done[i] = rows[i] + [result["cells"].get(p, "") for p in outputs] + [
            str(result["valid"]), repr(result["seconds"]), result["error"]]
        _write(results_path, columns, done)
        note = "valid" if result["valid"] else f"FAILED: {result['error']}"
        progress.step(f"row {i + 1}: {note} ({result['seconds']} s)")
    if not tasks:
        _write(results_path, columns, done)
    return columns, [done[i] for i in sorted(done)]
