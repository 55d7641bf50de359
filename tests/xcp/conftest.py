"""Fixtures: the demo ECU served on a private ``virtual`` bus, and an XcpMaster connected to it."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import pytest

from workbench.sim.demo_ecu import DemoEcu, build_demo_ecu
from workbench.sim.seedkey import compute_key
from workbench.sim.server import Simulator
from workbench.xcp.link import Link, LinkSettings
from workbench.xcp.master import Timeouts, XcpMaster

_channels = itertools.count()
FAST = Timeouts(t1=0.2, t2=0.4, t3=0.4, t4=1.0, t5=0.2, t6=0.2, t7=0.02)


@dataclass
class Rig:
    demo: DemoEcu
    simulator: Simulator
    link: Link
    master: XcpMaster


def can_settings(channel: str) -> LinkSettings:
    return LinkSettings("CAN", {"interface": "virtual", "channel": channel}, 0x7F0, 0x7F1, max_dlc_required=True)


@pytest.fixture
def rig():
    """The demo ECU (with its PCM) on its own virtual channel, real time, and a connected master with short timeouts."""
    channel = f"xcp-test-{next(_channels)}"
    demo = build_demo_ecu()
    simulator = Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, can2_driver=demo.can2,
                          pcm=demo.pcm_node(), time_scale=1.0)
    with simulator, Link(can_settings(channel)) as link:
        master = XcpMaster(link, timeouts=FAST, key_function=compute_key)
        master.connect()
        yield Rig(demo, simulator, link, master)
