"""Fixtures: the demo ECU served on a private bus (or Ethernet address) and a Session on it."""

from __future__ import annotations

import itertools

import pytest
from session_helpers import FAST

from workbench import Session
from workbench.sim import EthernetEndpoint, serve_demo

_channels = itertools.count()


@pytest.fixture
def channel() -> str:
    return f"session-test-{next(_channels)}"


@pytest.fixture
def sim(channel):
    """The demo ECU on a virtual bus of its own, in real time, with the PCM asking for 25 bar."""
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as simulator:
        yield simulator


@pytest.fixture
def ecu(sim, channel):
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:
        yield session


@pytest.fixture(params=["UDP", "TCP"])
def ethernet_ecu(request, free_udp_port, free_tcp_port):
    """The demo ECU served over XCP on UDP or TCP, and a Session on it."""
    port = free_udp_port if request.param == "UDP" else free_tcp_port
    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", port, request.param), pcm_target_bar=25.0):
        with Session.open(host="127.0.0.1", port=port, protocol=request.param.lower(), timeouts=FAST) as session:
            yield session
