"""Fixtures of the sync tests: the demo ECU on a virtual bus of its own (its FaultPlan counts the traffic) and a
Session on it."""

from __future__ import annotations

import itertools

import pytest

from workbench import Session
from workbench.sim import serve_demo
from sync_helpers import FAST

_channels = itertools.count()


@pytest.fixture
def channel() -> str:
    return f"sync-test-{next(_channels)}"


@pytest.fixture
def sim(channel):
    with serve_demo({"interface": "virtual", "channel": channel}) as simulator:
        yield simulator


@pytest.fixture
def ecu(sim, channel):
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:
        yield session
