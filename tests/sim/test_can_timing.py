"""Bit counts of CAN frames and the bus clock that paces the simulator's frames."""

from __future__ import annotations

import can
import pytest
from hypothesis import given
from hypothesis import strategies as st

from mini_ecu import make_ecu

from workbench.sim.can_timing import BusClock, _crc15, frame_bits
from workbench.sim.server import Simulator


def message(identifier: int, data: bytes, extended: bool = False) -> can.Message:
    return can.Message(arbitration_id=identifier, is_extended_id=extended, data=data)


def test_crc15_matches_the_catalogue_check_value():
    assert _crc15("".join(format(b, "08b") for b in b"123456789")) == 0x059E  # CRC-15/CAN


def test_known_frames():
    # 8 data bytes: 111 bits before stuffing (DESIGN: "an 8-byte standard frame is 111-135 bits")
    assert frame_bits(message(0x555, b"\x55" * 8)) == 112  # alternating bits: one stuff bit (CRC)
    assert frame_bits(message(0x7F1, bytes(8))) == 126  # zeros stuff every fifth bit
    assert frame_bits(message(0x000, b"")) == 47 + 6


@given(st.integers(0, 0x7FF), st.binary(max_size=8))
def test_standard_frames_stay_within_the_stuffing_bounds(identifier, data):
    unstuffed = 47 + 8 * len(data)
    assert unstuffed <= frame_bits(message(identifier, data)) <= unstuffed + (34 + 8 * len(data) - 1) // 4


@given(st.integers(0, 0x1FFFFFFF), st.binary(max_size=8))
def test_extended_frames_stay_within_the_stuffing_bounds(identifier, data):
    unstuffed = 67 + 8 * len(data)
    assert unstuffed <= frame_bits(message(identifier, data, True)) <= unstuffed + (54 + 8 * len(data) - 1) // 4


class FakeTime:
    def __init__(self):
        self.now = 100.0
        self.sleeps = []

    def clock(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


def test_frames_queue_behind_each_other_and_senders_keep_a_lead():
    time = FakeTime()
    bus = BusClock(1_000_000, clock=time.clock, sleep=time.sleep, lead_s=0.001)
    frame = message(0x7F1, bytes(8))
    ends = [bus.occupy(frame) for _ in range(10)]
    assert ends == pytest.approx([100.0 + 126e-6 * (i + 1) for i in range(10)])
    assert bus.is_due(ends[6]) and not bus.is_due(ends[9])
    bus.wait_until(ends[6])  # 0.88 ms ahead: within the lead, no sleep
    assert time.sleeps == []
    bus.wait_until(ends[9])  # 1.26 ms ahead: sleep until it is half the lead ahead, so the bus never idles
    assert time.sleeps == [pytest.approx(0.76e-3)] and time.now == pytest.approx(ends[9] - 0.5e-3)
    assert (bus.frames, bus.bits) == (10, 1260)


def test_an_idle_bus_starts_the_next_frame_now():
    time = FakeTime()
    bus = BusClock(500_000, clock=time.clock, sleep=time.sleep)
    bus.occupy(message(1, b"x"))
    time.now += 1.0
    assert bus.occupy(message(1, b"")) == pytest.approx(time.now + frame_bits(message(1, b"")) / 500_000)


def test_bitrate_must_be_positive():
    with pytest.raises(ValueError):
        BusClock(0)


def test_the_simulator_books_both_frames_of_a_round_trip():
    ecu = make_ecu()
    with can.Bus(interface="virtual", channel="timing-rig") as master, Simulator(
            ecu, {"interface": "virtual", "channel": "timing-rig"}, bitrate=125_000, time_scale=None) as sim:
        request = message(0x7F0, bytes([0xFF, 0]).ljust(8, b"\0"))  # padded: MAX_DLC_REQUIRED
        master.send(request)
        response = master.recv(2.0)
        assert response is not None and response.arbitration_id == 0x7F1
        clock = sim.bus_clock("CAN1")
        assert clock.frames == 2 and clock.bits == frame_bits(request) + frame_bits(response)
