"""One connection value and one bus object: Session.open takes a BusSpec whole and shows it; every listener on
a bus (a recorder, the window's CAN monitor) shares one python-can Notifier, on the XCP bus the link's own."""

from __future__ import annotations

import itertools
import time

import can
import pytest
from session_helpers import FAST

from workbench import Session
from workbench.bus_defaults import BusSpec
from workbench.errors import InputError

THRESHOLD = "xsSWITCH_TANK_THR"
_others = itertools.count()


def running_notifiers(bus) -> list:
    return [notifier for notifier in can.Notifier.find_instances(bus) if not notifier.stopped]


def wait_for(condition, timeout_s: float = 5.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.01)


def test_a_session_takes_the_bus_whole_and_shows_it(sim, channel):
    spec = BusSpec("virtual", channel)
    with Session.open(bus=spec, timeouts=FAST) as ecu:
        assert ecu.bus_spec == spec and ecu.read(THRESHOLD) == 20.0
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as ecu:  # as the README writes it
        assert ecu.bus_spec == spec
    with pytest.raises(InputError, match=r"a BusSpec or as python-can options \(interface\), not both"):
        Session.open(bus=spec, interface="virtual")


def test_listeners_on_the_xcp_bus_share_the_links_notifier_and_hear_every_frame(sim, channel):
    with Session.open(bus=BusSpec("virtual", channel), timeouts=FAST) as ecu:
        bus, first, second = ecu.link.can_bus, [], []
        with ecu.listen_can(first.append), ecu.listen_can(second.append):
            assert len(running_notifiers(bus)) == 1  # one receive thread on the one bus object
            assert ecu.read(THRESHOLD) == 20.0  # polling goes on through it
            wait_for(lambda: {0x110, 0x220} <= {frame.arbitration_id for frame in second})  # the PCM's CAN2 frames
            sent = [frame for frame in first if frame.arbitration_id == 0x7F0]
            assert sent and not sent[0].is_rx  # the link's own commands too, as sent
            assert any(frame.arbitration_id == 0x7F1 for frame in first)  # and the ECU's answers
        assert running_notifiers(bus) == []  # the caller's thread reads the bus again
        assert ecu.read(THRESHOLD) == 20.0


def test_listeners_on_another_bus_share_one_bus_object_closed_with_the_last(sim, channel):
    other = BusSpec("virtual", f"{channel}-can2-{next(_others)}")
    with Session.open(bus=BusSpec("virtual", channel), timeouts=FAST) as ecu, can.Bus(**other.kwargs()) as sender:
        first, second = [], []
        one, two = ecu.listen_can(first.append, other), ecu.listen_can(second.append, other)
        assert one.bus is two.bus and one.describe() == f"virtual {other.channel}"
        sender.send(can.Message(arbitration_id=0x123, is_extended_id=False, data=b"\1"))
        wait_for(lambda: first and second)
        one.close()
        assert not two.bus._is_shutdown
        two.close()
        assert two.bus._is_shutdown


def test_a_session_on_ethernet_names_the_can2_bus(ethernet_ecu):
    with pytest.raises(InputError, match=r"the session runs XCP on (UDP|TCP) .*: name the CAN2 bus"):
        ethernet_ecu.listen_can(print)
