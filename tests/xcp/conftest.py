"""Fixtures: the demo ECU served on a private ``virtual`` bus, and an XcpMaster connected to it (:mod:`xcp_helpers`)."""

from __future__ import annotations

import pytest
from xcp_helpers import serve

from workbench.sim.demo_ecu import build_demo_ecu


@pytest.fixture
def rig():
    """The demo ECU in real time and a connected master."""
    with serve(build_demo_ecu(), 1.0) as served:
        yield served


@pytest.fixture
def static_rig():
    """The demo ECU with static DAQ lists, its clock moved only by the test (``simulator.advance``), and a master."""
    with serve(build_demo_ecu(static_daq=True), None) as served:
        yield served
