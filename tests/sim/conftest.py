"""Fixtures: a powered mini ECU and an XCP probe connected to it; no test leaves simulator threads behind."""

from __future__ import annotations

import threading
import time

import pytest
from mini_ecu import XcpProbe, make_ecu

from workbench.sim.ecu import SimulatedEcu


@pytest.fixture
def ecu() -> SimulatedEcu:
    ecu = make_ecu()
    ecu.power_on()
    return ecu


@pytest.fixture
def xcp(ecu) -> XcpProbe:
    probe = XcpProbe(ecu)
    probe.connect()
    return probe


@pytest.fixture(autouse=True)
def no_simulator_threads_left():
    """Every test closes what it started: no simulator thread outlives it."""
    yield
    deadline = time.monotonic() + 2.0
    while (left := [t.name for t in threading.enumerate() if t.name.startswith("sim-")]) and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not left, f"simulator threads still running: {left}"
