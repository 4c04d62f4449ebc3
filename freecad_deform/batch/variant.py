"""One design variant, computed where it is sent: this process, a local worker process or a
Dask worker. The task carries the document's bytes and sends the exports back as bytes, so a
worker needs no shared disk; everything in and out is plain data."""
import os
import tempfile
import time

from . import model

App = model.App


def run_variant(task):
    """Open the document, set the row's values, recompute everything, read every output,
    export. task: index, doc (bytes), values [(path, text)], outputs [path], formats, stem.
    Returns index, cells {output: text}, valid, seconds, error, files {name: bytes}. A
    variant that fails comes back with its error and empty outputs; it never raises."""
    out = {"index": task["index"], "cells": {}, "valid": False, "seconds": 0.0, "error": "",
           "files": {}}
    with tempfile.TemporaryDirectory(prefix="deform-variant-") as tmp:
        path = os.path.join(tmp, "model.FCStd")
        with open(path, "wb") as f:
            f.write(task["doc"])
        try:
            doc = model.open_document(path)
        except model.BatchError as e:
            out["error"] = str(e)
            return out
        try:
            _compute(doc, task, out, tmp)
        finally:
            App.closeDocument(doc.Name)
    return out


def _compute(doc, task, out, tmp):
    try:
        for path, value in task["values"]:
            model.set_value(doc, path, value)
    except model.BatchError as e:
        out["error"] = str(e)
        return
    for obj in doc.Objects:
        obj.touch()
    start = time.perf_counter()
    doc.recompute()
    out["seconds"] = round(time.perf_counter() - start, 3)
    out["valid"], out["error"] = model.status(doc)
    failed = any("Invalid" in o.State or "Error" in o.State for o in doc.Objects)
    if not failed:
        out["cells"] = {p: model.text(model.read_value(doc, p)) for p in task["outputs"]}
    # a failed variant keeps only its document (to open and see why), no result files
    formats = [f for f in task["formats"] if not failed or f == "fcstd"]
    if formats:
        folder = os.path.join(tmp, "exports")
        try:
            written = model.export(doc, formats, folder, task["stem"])
        except (OSError, RuntimeError) as e:  # OCCT's writers raise Part.OCCError
            out["valid"], out["error"] = False, f"export failed: {e}"
            return
        for name in written:
            with open(os.path.join(folder, name), "rb") as f:
                out["files"][name] = f.read()
