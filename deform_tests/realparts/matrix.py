"""Print the real-parts matrix as a table (`make realparts`): case, result, the oracle
closest to its tolerance, seconds and, for B-rep cases, the OCCT floor (split + fuse).

    python3 -m deform_tests.realparts.matrix [substring ...]   # only the cases whose id has one
"""
import sys
import time

from . import cases


def row(case, out):
    if out.status == "ok":
        result = "ok" if out.passed(case) else "FAILED (oracle)"
    elif out.status == "refused":
        result = ("refused" if out.passed(case) or case.expect == "ok" else "FAILED") + \
            f": {out.message}"
    else:
        result = f"FAILED: {out.message}"
    if case.expect != "ok" and out.status != "refused":
        result = f"FAILED (expected a refusal naming {case.expect}): " + result
    worst = out.worst() if out.passed(case) else max(
        ((k, *v) for k, v in out.errors.items()), key=lambda e: e[1] / e[2], default=None)
    if "-v" in sys.argv and out.errors:
        print("   ", {k: (float(f"{e:.3g}"), float(f"{t:.3g}")) for k, (e, t) in out.errors.items()})
    oracle = f"{worst[0]} {worst[1]:.2g} (tol {worst[2]:.0g})" if worst else ""
    floor = f"{out.floor:.2f}" if out.floor is not None else ""
    return case.id, result, oracle, f"{out.seconds:.2f}", floor


def main(argv):
    argv = [a for a in argv if a != "-v"]
    picked = [c for c in cases.all_cases() if not argv or any(a in c.id for a in argv)]
    print("| case | result | oracle error | s | OCCT floor s |")
    print("| --- | --- | --- | --- | --- |")
    counts, start, cpu = {}, time.perf_counter(), time.process_time()
    for case in picked:
        out = cases.run(case, floor=True)
        cells = row(case, out)
        key = "ok" if out.passed(case) and out.status == "ok" else (
            "refused" if out.passed(case) else "refused (unexpected)"
            if out.status == "refused" else "FAILED")
        counts[key] = counts.get(key, 0) + 1
        print("| " + " | ".join(c.replace("|", "/").replace("\n", " ") for c in cells) + " |",
              flush=True)
    print(f"\n{len(picked)} cases in {time.perf_counter() - start:.0f} s "
          f"({time.process_time() - cpu:.0f} s of CPU): "
          + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    return 0 if counts.get("FAILED", 0) == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
