"""Fixtures: the demo ECU served on a private bus (or Ethernet address) and a Session on it."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from workbench import Session, demo
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.xcp.master import Timeouts

_channels = itertools.count()
FAST = Timeouts(t1=0.3, t2=0.6, t3=0.6, t4=2.0, t5=0.3, t6=0.3, t7=0.02)


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


def demo_a2l_text() -> str:
    return Path(demo.a2l()).read_text(encoding="utf-8")


def edited_a2l(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    """The demo A2L with ``old`` replaced by ``new`` (it must occur), written to ``tmp_path``."""
    text = demo_a2l_text()
    assert old in text, old
    path = tmp_path / "edited.a2l"
    path.write_text(text.replace(old, new, count), encoding="utf-8")
    return path
