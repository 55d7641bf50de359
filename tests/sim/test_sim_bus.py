"""Transmitter and receiver: DAQ overload drops whole samples, responses overtake queued DTOs, no hang, no log flood."""

from __future__ import annotations

import itertools
import logging
import time

import can
import pytest

from workbench.sim.bus import EchoFilter, Receiver, Transmitter
from workbench.sim.can_timing import BusClock

_channels = itertools.count()
SLOW_BITRATE = 20_000  # an 8-byte frame takes about 6 ms: the buffers fill while a test runs


@pytest.fixture
def buses():
    channel = f"sim-bus-{next(_channels)}"
    sender = can.Bus(interface="virtual", channel=channel)
    observer = can.Bus(interface="virtual", channel=channel)
    yield sender, observer
    sender.shutdown()
    observer.shutdown()


def frame(identifier: int, marker: int) -> can.Message:
    return can.Message(arbitration_id=identifier, is_extended_id=False, data=bytes([marker]) * 8)


def received(observer: can.BusABC, count: int) -> list[tuple[int, int]]:
    out = []
    while len(out) < count and (message := observer.recv(5.0)) is not None:
        out.append((message.arbitration_id, message.data[0]))
    return out


def test_an_overload_drops_whole_samples(buses):
    sender, observer = buses
    transmitter = Transmitter(sender, BusClock(SLOW_BITRATE, lead_s=0.0), capacity=4)
    try:
        assert transmitter.send_dtos([frame(0x7F1, pid) for pid in range(4)])  # fills the buffer (one may be on the bus)
        assert not transmitter.send_dtos([frame(0x7F1, pid) for pid in range(10, 12)])  # 3 or 4 + 2 > 4: neither
        assert received(observer, 2) == [(0x7F1, 0), (0x7F1, 1)]
        assert transmitter.send_dtos([frame(0x7F1, pid) for pid in range(20, 22)])  # at most 2 wait: both fit
        assert received(observer, 4) == [(0x7F1, pid) for pid in (2, 3, 20, 21)]
        assert (transmitter.sent, transmitter.dropped) == (6, 2)
    finally:
        transmitter.close()


def test_responses_go_before_queued_dtos(buses):
    sender, observer = buses
    transmitter = Transmitter(sender, BusClock(SLOW_BITRATE, lead_s=0.0))
    try:
        transmitter.send_dtos([frame(0x7F1, pid) for pid in range(4)])
        transmitter.send(frame(0x7F1, 0xFF))  # a response: at the latest right after the DTO already on the bus
        order = [marker for _, marker in received(observer, 5)]
        assert order.index(0xFF) <= 1 and [m for m in order if m != 0xFF] == [0, 1, 2, 3]
    finally:
        transmitter.close()


def test_without_a_clock_frames_go_out_at_once_in_the_callers_thread(buses):
    sender, observer = buses
    transmitter = Transmitter(sender)
    assert transmitter.send_dtos([frame(0x7F1, pid % 256) for pid in range(300)])  # no buffer, nothing to overload
    assert len(received(observer, 300)) == 300 and transmitter.sent == 300
    transmitter.close()


def test_close_drops_what_waits_and_is_idempotent(buses):
    sender, _ = buses
    transmitter = Transmitter(sender, BusClock(1_000, lead_s=0.0))  # 0.1 s a frame
    transmitter.send_dtos([frame(0x7F1, pid) for pid in range(50)])
    transmitter.close()
    transmitter.close()
    assert not transmitter.send_dtos([frame(0x7F1, 0)])
    transmitter.send(frame(0x7F1, 0xFF))  # refused quietly after close
    assert transmitter.sent <= 2 and transmitter.dropped == 2


class FailingOnce:
    """A bus whose first send fails with ``error``."""

    def __init__(self, bus: can.BusABC, error: Exception):
        self.bus, self.error = bus, error

    def send(self, message: can.Message) -> None:
        if self.error is not None:
            error, self.error = self.error, None
            raise error
        self.bus.send(message)


def test_a_failed_send_is_counted_and_the_next_frame_goes_out(buses, caplog):
    sender, observer = buses
    transmitter = Transmitter(FailingOnce(sender, can.CanOperationError("bus off")))
    transmitter.send(frame(0x7F1, 1))
    transmitter.send(frame(0x7F1, 2))
    assert received(observer, 1) == [(0x7F1, 2)]
    assert (transmitter.sent, transmitter.dropped) == (1, 1)
    assert "frame 0x7F1 not sent: bus off" in caplog.text


@pytest.mark.parametrize("error", [can.CanOperationError("bus off"), RuntimeError("driver bug")], ids=str)
def test_the_paced_transmitter_survives_a_failing_send(buses, error):
    sender, observer = buses
    transmitter = Transmitter(FailingOnce(sender, error), BusClock(SLOW_BITRATE, lead_s=0.0))
    try:
        transmitter.send_dtos([frame(0x7F1, 1), frame(0x7F1, 2)])  # queued: the thread meets the failure
        assert received(observer, 1) == [(0x7F1, 2)]
        assert (transmitter.sent, transmitter.dropped) == (1, 1)
    finally:
        transmitter.close()


def test_a_receiver_whose_bus_goes_away_says_so_once_and_stops_cleanly(buses, caplog):
    caplog.set_level(logging.DEBUG, logger="workbench.sim")
    sender, _ = buses
    frames = []
    receiver = Receiver(sender, frames.append, name="CAN1")
    sender.shutdown()  # the caller closed its bus under the simulator
    time.sleep(0.3)  # several polls
    receiver.stop()
    levels = [r.levelname for r in caplog.records if "receive failed" in r.getMessage()]
    assert levels[0] == "WARNING" and set(levels[1:]) == {"DEBUG"}  # once, then quietly while it lasts


def test_the_echo_filter_recognises_our_frames_in_sending_order():
    echoes = EchoFilter(max_age_s=10.0)
    ours = [frame(0x7F1, 1), frame(0x123, 2)]
    for message in ours:
        echoes.sent(message)
    assert not echoes.is_echo(frame(0x7F0, 1))  # the master's frame
    assert [echoes.is_echo(message) for message in ours] == [True, True]
    assert not echoes.is_echo(frame(0x7F1, 1))  # the same frame again: it was only sent once


def test_the_echo_filter_forgets_what_never_came_back():
    echoes = EchoFilter(max_age_s=0.0)
    echoes.sent(frame(0x7F1, 1))
    time.sleep(0.01)
    assert not echoes.is_echo(frame(0x7F1, 1))
