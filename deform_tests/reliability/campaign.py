"""The reliability campaign (issue 11): draw cases with hypothesis, run each in its own
process with a time limit on 2 workers, classify, print the table.

    python3 -m deform_tests.reliability.campaign [--per-feature N] [--seed S] [--timeout T] [-v]

Classes: hang (time limit), crash (the process died), runner_error (this suite's own
bug), leftover, base_changed, broken_save, silent_wrong (accepted, an oracle failed),
bad_refusal (in error, but the message is empty, raw or does not name its property),
refused (a clean refusal), raised (make_* refused, the document as it was), accepted
(checked by the oracles).
"""
import argparse
import collections
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import seed as hseed

from . import cases as cs

for _path in ("/usr/lib/freecad-python3/lib", "/usr/share/freecad/Mod/Part"):
    if os.path.isdir(_path) and _path not in sys.path:
        sys.path.append(_path)

RUNNER = os.path.join(os.path.dirname(os.path.realpath(__file__)), "runner.py")
PYTHON = "/usr/bin/python3"
FAILURES = ("hang", "crash", "runner_error", "leftover", "base_changed", "broken_save",
            "silent_wrong", "bad_refusal")
CLASSES = FAILURES + ("refused", "raised", "accepted")


def features():
    """The features to draw: Taper only once make_taper exists."""
    names = [f for f in cs.STRATEGIES if f != "taper"]
    try:
        from freecad_deform import api  # noqa: F401  (needs FreeCAD on sys.path)
        if hasattr(api, "make_taper"):
            names.append("taper")
    except ImportError:
        pass
    return names


def draw(per_feature, seed=None):
    """`per_feature` cases per feature drawn by hypothesis (derandomized unless `seed`),
    distinct, in a fixed order."""
    drawn = []
    for name in features() if per_feature > 0 else ():
        found = []

        @settings(max_examples=per_feature, derandomize=seed is None, database=None,
                  phases=[Phase.generate], deadline=None,
                  suppress_health_check=list(HealthCheck))
        @given(cs.STRATEGIES[name]())
        def collect(case):
            found.append(case)

        collect_fn = collect if seed is None else hseed(seed)(collect)
        collect_fn()
        seen = set()
        for case in found:
            key = json.dumps(case, sort_keys=True)
            if key not in seen:
                seen.add(key)
                drawn.append(case)
    return drawn


def run_case(case, timeout):
    """(class, result dict, seconds) of one case in its own process."""
    start = time.monotonic()
    try:
        proc = subprocess.run([PYTHON, RUNNER, json.dumps(case)], capture_output=True,
                              encoding="utf-8", errors="replace", timeout=timeout,
                              env={**os.environ, "QT_QPA_PLATFORM": "offscreen"})
    except subprocess.TimeoutExpired:
        return "hang", {"problems": [f"hang: no answer in {timeout} s"]}, timeout
    seconds = time.monotonic() - start
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr or proc.stdout)[-400:]
        return "crash", {"problems": [f"crash: exit {proc.returncode}: {tail}"]}, seconds
    out = json.loads(lines[-1])
    return out["cls"], out, seconds


def run(cases, workers=2, timeout=60.0, progress=None):
    """Run every case on `workers` processes at a time; [(case, class, result, seconds)]."""
    def one(case):
        cls, out, seconds = run_case(case, timeout)
        if progress:
            progress(case, cls, seconds)
        return case, cls, out, seconds
    with ThreadPoolExecutor(workers) as pool:
        return list(pool.map(one, cases))


def label(case):
    return case.get("name") or f"{case['feature']} on {case['base'].get('shape')}" \
        f"/{case['base'].get('as', 'shape')}"


def table(results, wall=None):
    """The campaign's table: counts per class, per feature, then every failing case."""
    lines = []
    total = collections.Counter(cls for _, cls, _, _ in results)
    lines.append("class          count")
    for cls in CLASSES:
        lines.append(f"{cls:<14} {total.get(cls, 0):5d}")
    lines.append(f"{'cases':<14} {len(results):5d}" + (f"   wall {wall:.0f} s" if wall else ""))
    lines.append("")
    names = sorted({c["feature"] for c, _, _, _ in results})
    short = [c[:8] for c in CLASSES]
    lines.append(f"{'feature':<16}" + "".join(f"{s:>9}" for s in short))
    for name in names:
        counts = collections.Counter(cls for c, cls, _, _ in results if c["feature"] == name)
        lines.append(f"{name:<16}" + "".join(f"{counts.get(cls, 0):9d}" for cls in CLASSES))
    failing = [(c, cls, out, s) for c, cls, out, s in results if cls in FAILURES]
    if failing:
        lines.append("")
        lines.append("failing cases:")
        for c, cls, out, s in failing:
            lines.append(f"- [{cls}] {label(c)} ({s:.1f} s): "
                         + "; ".join(out.get("problems", []))[:400])
            lines.append(f"  case: {json.dumps({k: v for k, v in c.items() if k != 'name'})}")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--per-feature", type=int, default=60,
                        help="cases drawn per feature (plus the issue's fixed cases)")
    parser.add_argument("--seed", type=int, default=None, help="draw at random with this seed "
                        "(default: derandomized, the same cases every run)")
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-fixed", action="store_true", help="leave out the issue's cases")
    parser.add_argument("-k", default="", help="only features whose name contains this")
    parser.add_argument("-v", action="store_true", help="print each case as it ends")
    args = parser.parse_args(argv)
    todo = ([] if args.no_fixed else list(cs.ISSUE)) + draw(args.per_feature, args.seed)
    todo = [c for c in todo if args.k in c["feature"]]
    start = time.monotonic()

    def progress(case, cls, seconds):
        if args.v:
            print(f"{cls:<13} {seconds:6.1f} s  {label(case)}", flush=True)
    results = run(todo, args.workers, args.timeout, progress)
    wall = time.monotonic() - start
    print(table(results, wall))
    return 1 if any(cls in FAILURES for _, cls, _, _ in results) else 0


if __name__ == "__main__":
    sys.exit(main())
