"""The stability catalog (issue 12, ``hybrid_integrator/stability.py``): every case's outcome, on
real Mitsuba and real OpenGL. Slow cases (``slow=True``) are marked ``slow``: the test command
leaves them to ``scripts/stability_report.py``, which runs them all."""
from __future__ import annotations

import pytest

from hybrid_integrator.stability import catalog, run_case

CASES = catalog()


@pytest.mark.parametrize("case", [pytest.param(c, id=c.name, marks=[pytest.mark.slow] if c.slow else [])
                                  for c in CASES])
def test_case(case):
    result = run_case(case)
    assert result.passed, f"{case.name}: figure {result.figure} against bound {case.bound} ({case.outcome}): {result.detail}"


def test_catalog_covers_the_issue():
    groups = {c.group for c in CASES}
    assert groups == {"raster", "trace", "budget", "use"} and len(CASES) >= 60
    assert len({c.name for c in CASES}) == len(CASES)
