"""The real-parts matrix as pytest tests: one test per case of cases.py, same oracles as the
table of `make realparts`. A case expecting "ok" must pass every oracle; a case expecting
a refusal must be a DeformError naming that property."""
import pytest

from . import cases

CASES = cases.all_cases()


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_case(case):
    out = cases.run(case)
    if case.expect != "ok":
        assert out.status == "refused", f"expected a refusal naming {case.expect}: {out}"
        assert case.expect in out.message, out.message
        return
    assert out.status == "ok", f"{out.status}: {out.message}"
    bad = {k: v for k, v in out.errors.items() if v[0] > v[1]}
    assert not bad, "oracles past tolerance (error, tolerance): " + repr(bad)
