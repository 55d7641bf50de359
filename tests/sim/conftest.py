"""Fixtures: a powered mini ECU and an XCP probe connected to it."""

from __future__ import annotations

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
