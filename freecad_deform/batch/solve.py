"""`solve` (goal seek): the values of properties, within bounds, that make outputs hit
targets (or make one output least or greatest), by recomputing the document.

One property and one target: Brent's root finder when the bounds bracket the target, else
bounded least squares. Several: scipy's bounded least_squares. Minimise or maximise: a
bounded scalar search for one property, L-BFGS-B for several."""
import math

import numpy as np
from scipy import optimize

from . import model


class _Model:
    """The document as a function of the varied values; counts recomputes. A value met
    before is answered from memory (Brent asks for the bounds again); settle(x) leaves
    the document recomputed at x."""

    def __init__(self, doc, names, outputs, progress=None):
        self.doc, self.names, self.outputs, self.calls = doc, names, outputs, 0
        self.last, self.progress, self.seen = None, progress, {}

    def settle(self, x):
        return self(x, settle=True)

    def __call__(self, x, settle=False):
        x = [float(v) for v in np.atleast_1d(x)]
        if not settle and tuple(x) in self.seen:
            return self.seen[tuple(x)]
        fresh = x != self.last
        if fresh:
            for name, value in zip(self.names, x):
                model.set_value(self.doc, name, value)
            self.doc.recompute()
            self.calls += 1
            self.last = x
        valid, error = model.status(self.doc)
        if error:
            at = ", ".join(f"{n} = {v!r}" for n, v in zip(self.names, x))
            raise model.BatchError(f"at {at} the model fails ({error}); narrow the bounds of "
                                   f"{', '.join(self.names)} (--vary).")
        values = [model.read_value(self.doc, p) for p in self.outputs]
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            raise model.BatchError(f"{', '.join(self.outputs)} must be a number to solve "
                                   f"for; pick a numeric output.")
        if fresh and self.progress is not None:
            self.progress(self.calls, x, values)
        self.seen[tuple(x)] = np.array(values, float)
        return self.seen[tuple(x)]


def _bounds(vary):
    names = list(vary)
    lo = np.array([float(vary[n][0]) for n in names])
    hi = np.array([float(vary[n][1]) for n in names])
    if not np.all(lo < hi):
        raise model.BatchError("every --vary range needs LO < HI; give the smaller bound "
                               "first.")
    return names, lo, hi


def solve(doc, vary, target=None, minimize=None, maximize=None, xtol=1e-12, max_calls=200,
          progress=None):
    """Goal seek on a document. vary: {"Object.Property": (lo, hi)}; target:
    {"Object.Output": value} (an output may be any attribute path, such as
    "Stretch.Shape.BoundBox.XLength"), or minimize / maximize: "Object.Output".
    Returns {name: value, ..., "residual": r, "iterations": n}: r the largest |output -
    target| ("minimum" or "maximum" instead: the output there), n the recomputes. The
    document is left recomputed at the solution. progress(n, values, outputs), when given,
    is called after each recompute (a GUI shows the iterations)."""
    names, lo, hi = _bounds(vary)
    goal = minimize or maximize
    if bool(target) == bool(goal) or (minimize and maximize):
        raise model.BatchError("give either targets or one output to minimise or maximise.")
    outputs = list(target) if target else [goal]
    f = _Model(doc, names, outputs, progress)
    if target:
        want = np.array([float(target[p]) for p in outputs])
        x = _seek(lambda v: f(v) - want, lo, hi, xtol, max_calls)
    else:
        sign = 1.0 if minimize else -1.0
        x = _optimum(lambda v: sign * f(v)[0], lo, hi, xtol, max_calls)
    value = f.settle(x)
    found = {n: float(v) for n, v in zip(names, np.atleast_1d(x))}
    if target:
        found["residual"] = float(np.max(np.abs(value - want)))
    else:
        found["minimum" if minimize else "maximum"] = float(value[0])
    return {**found, "iterations": f.calls}


def _seek(g, lo, hi, xtol, max_calls):
    at_lo = g(lo) if len(lo) == 1 else None
    if at_lo is not None and len(at_lo) == 1:
        a, b = at_lo[0], g(hi)[0]
        if a == 0 or b == 0:
            return lo if a == 0 else hi
        if a * b < 0:
            return np.array([optimize.brentq(lambda t: g([t])[0], lo[0], hi[0], xtol=xtol,
                                             rtol=4 * np.finfo(float).eps,
                                             maxiter=max_calls)])
    start = (lo + hi) / 2
    fit = optimize.least_squares(g, start, bounds=(lo, hi), x_scale=hi - lo,
                                 xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=max_calls)
    return fit.x


def _optimum(h, lo, hi, xtol, max_calls):
    if len(lo) == 1:
        best = optimize.minimize_scalar(lambda t: h([t]), bounds=(lo[0], hi[0]),
                                        method="bounded",
                                        options={"xatol": max(xtol, 1e-10 * (hi[0] - lo[0])),
                                                 "maxiter": max_calls})
        # a bounded search only nears a bound: the bounds themselves are candidates too
        return min((np.array([t]) for t in (best.x, lo[0], hi[0])), key=h)
    best = optimize.minimize(h, (lo + hi) / 2, method="L-BFGS-B", bounds=list(zip(lo, hi)),
                             options={"maxfun": max_calls})
    return best.x


def parse_ranges(specs):
    """["Obj.Prop=LO:HI", ...] -> {"Obj.Prop": (lo, hi)}."""
    vary = {}
    for spec in specs:
        path, _, rng = spec.partition("=")
        try:
            lo, hi = (float(v) for v in rng.split(":"))
        except ValueError:
            raise model.BatchError(f"--vary {spec!r} needs Object.Property=LO:HI with two "
                                   f"numbers.") from None
        model.split_path(path)
        vary[path.strip()] = (lo, hi)
    return vary


def parse_targets(specs):
    """["Obj.Output=VALUE", ...] -> {"Obj.Output": value}."""
    target = {}
    for spec in specs:
        path, _, value = spec.partition("=")
        try:
            target[path.strip()] = float(value)
        except ValueError:
            raise model.BatchError(f"--target {spec!r} needs Object.Output=VALUE with a "
                                   f"number.") from None
        model.split_path(path)
    return target
