"""The xcp tests' rig: the demo ECU served on a private ``virtual`` bus and an XcpMaster connected to it with
short timeouts (the fixtures of conftest.py stand on it; tests import it by name, never from conftest)."""

from __future__ import annotations

import itertools
from contextlib import contextmanager
from dataclasses import dataclass

from workbench.bus_defaults import BusSpec
from workbench.errors import ConnectionLostError, WorkbenchError
from workbench.sim.demo_ecu import DemoEcu
from workbench.sim.seedkey import compute_key
from workbench.sim.server import Simulator
from workbench.xcp.link import Link, LinkSettings
from workbench.xcp.master import Timeouts, XcpMaster
from workbench.xcp_protocol import CanId

__all__ = ["FAST", "Rig", "can_settings", "refusal_of_a_silent_daq", "serve"]

_channels = itertools.count()
FAST = Timeouts(t1=0.2, t2=0.4, t3=0.4, t4=1.0, t5=0.2, t6=0.2, t7=0.02)


@dataclass
class Rig:
    demo: DemoEcu
    simulator: Simulator
    link: Link
    master: XcpMaster


def can_settings(channel: str) -> LinkSettings:
    return LinkSettings("CAN", BusSpec("virtual", channel), CanId(0x7F0), CanId(0x7F1), max_dlc_required=True)


@contextmanager
def serve(demo: DemoEcu, time_scale: float | None):
    """``demo`` (with its PCM) on a virtual channel of its own and a master connected to it with short timeouts."""
    channel = f"xcp-test-{next(_channels)}"
    simulator = Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, can2_driver=demo.can2,
                          pcm=demo.pcm_node(), time_scale=time_scale)
    with simulator, Link(can_settings(channel)) as link:
        master = XcpMaster(link, timeouts=FAST, key_function=compute_key)
        master.connect()
        yield Rig(demo, simulator, link, master)


def refusal_of_a_silent_daq(session, names: list[str]) -> str:
    """What a DAQ measurement of ``names`` that hears no DTO ends with, the ECU answering: not a lost connection, and
    the session goes on (read until refused: 40 s at most; it comes after three silences of T1 + 3 event periods)."""
    try:
        with session.measure(names) as live:
            for _ in range(200):
                live.read(0.2)
    except ConnectionLostError as lost:
        raise AssertionError(f"said lost: {lost}") from lost
    except WorkbenchError as refused:
        assert session.read("xsSWITCH_TANK_THR") == 20.0  # still connected
        return str(refused)
    raise AssertionError("the measurement was not refused")

