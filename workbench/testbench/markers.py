"""The marks a requirement test carries: which requirements it verifies, and whether it needs the simulated ECU.

::

    from workbench.testbench import needs_simulator, requirement

    @requirement("SW_REQ_ID_005.5", "SW_REQ_ID_008.4")
    @needs_simulator
    def test_rail_pressure_saturates(ecu): ...

The plugin records each id as a JUnit testcase property ``requirement`` and the report traces it;
a test marked :data:`needs_simulator` is skipped (with the reason) against a real ECU instead of failing.
"""

from __future__ import annotations

import pytest

__all__ = ["REQUIREMENT_MARK", "SIMULATOR_MARK", "needs_simulator", "requirement"]

REQUIREMENT_MARK = "requirement"
SIMULATOR_MARK = "needs_simulator"


def requirement(*ids: str) -> pytest.MarkDecorator:
    """Mark a test as verifying the requirements ``ids`` (one or several, e.g. ``"SW_REQ_ID_002.2"``)."""
    if not ids or not all(isinstance(i, str) and i.strip() for i in ids):
        raise ValueError(f"requirement() takes one or more requirement ids as text, got {ids!r}")
    return getattr(pytest.mark, REQUIREMENT_MARK)(*(i.strip() for i in ids))


needs_simulator = getattr(pytest.mark, SIMULATOR_MARK)
"""Mark a test that injects faults or plant inputs (``ecu.sim``): skipped where no simulated ECU answers."""
