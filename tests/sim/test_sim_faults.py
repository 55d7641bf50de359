"""The Simulator on a virtual bus: fault injection seen by a raw master, MAX_DLC_REQUIRED, start/close life cycle."""

from __future__ import annotations

import itertools
import struct

import can
import pytest
from mini_ecu import CAL_GAIN, MINI_LAYOUT, make_ecu, mini_image
from raw_master import RawMaster

from workbench.sim.ecu import SimulatedEcu
from workbench.sim.server import Simulator
from workbench.xcp_protocol import Cmd, Err

_channels = itertools.count()
GET_STATUS = bytes([Cmd.GET_STATUS])
CONNECT = bytes([Cmd.CONNECT, 0])


@pytest.fixture
def rig():
    ecu = make_ecu()
    channel = f"sim-faults-{next(_channels)}"
    with Simulator(ecu, {"interface": "virtual", "channel": channel}, time_scale=None) as sim, RawMaster(channel) as master:
        assert master.request(CONNECT)[0][0] == 0xFF
        yield sim, master


def test_drop_the_next_response(rig):
    sim, master = rig
    sim.ecu.faults.drop_frame(1)
    assert master.request(GET_STATUS) == []
    assert len(master.request(GET_STATUS)) == 1
    assert sim.ecu.faults.fired == ["drop tx frame 2"]


def test_duplicate_and_delay_responses(rig):
    sim, master = rig
    sim.ecu.faults.duplicate_frame(1)
    first = master.request(GET_STATUS)
    assert len(first) == 2 and first[0] == first[1]
    sim.ecu.faults.delay_frame(1, 0.2)
    master.send(GET_STATUS)
    master.send(bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", CAL_GAIN))
    responses = master.responses(timeout_s=0.5)
    assert responses[0] == b"\xff" + struct.pack("<f", 2.0) + bytes(3)  # padded to DLC 8 (MAX_DLC_REQUIRED)
    assert responses[1][0] == 0xFF and len(responses) == 2  # the delayed GET_STATUS answer comes second


def test_master_frames_shorter_than_dlc_8_are_ignored(rig):
    sim, master = rig
    assert master.request(GET_STATUS, pad=False) == []  # MAX_DLC_REQUIRED binds the master too
    assert master.request(GET_STATUS)[0][0] == 0xFF
    assert sim.ecu.faults.fired == []


def test_received_frames_can_be_dropped_or_duplicated(rig):
    sim, master = rig
    sim.ecu.faults.drop_frame(1, direction="rx")
    assert master.request(GET_STATUS) == []
    sim.ecu.faults.duplicate_frame(1, direction="rx")
    assert len(master.request(GET_STATUS)) == 2


def test_reject_the_nth_command_of_a_kind(rig):
    sim, master = rig
    sim.ecu.faults.reject_command(2, Err.CMD_BUSY, command=Cmd.SHORT_UPLOAD)
    upload = bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", CAL_GAIN)
    assert master.request(upload)[0][0] == 0xFF
    assert master.request(GET_STATUS)[0][0] == 0xFF  # other commands do not count
    assert master.request(upload) == [bytes([0xFE, Err.CMD_BUSY]).ljust(8, b"\0")]
    assert master.request(upload)[0][0] == 0xFF


def test_power_off_silences_and_power_on_serves_again(rig):
    sim, master = rig
    sim.power_off()
    assert master.request(CONNECT) == []
    sim.power_on()
    assert master.request(CONNECT)[0][0] == 0xFF


def test_fault_arguments_are_checked():
    ecu = make_ecu()
    with pytest.raises(ValueError, match="counts from 1"):
        ecu.faults.drop_frame(0)
    with pytest.raises(ValueError, match="direction"):
        ecu.faults.drop_frame(1, direction="both")


def test_close_is_idempotent_and_closes_only_the_buses_it_opened():
    ecu = make_ecu()
    mine = can.Bus(interface="virtual", channel="sim-owned")
    sim = Simulator(ecu, mine, {"interface": "virtual", "channel": "sim-owned-can2"}, time_scale=1.0).start()
    opened = sim.buses["CAN2"]
    sim.close()
    sim.close()
    assert sim.closed
    with pytest.raises(can.CanOperationError):
        opened.send(can.Message(arbitration_id=1))
    mine.send(can.Message(arbitration_id=1))  # the caller's bus stays open
    mine.shutdown()


def test_a_failing_start_closes_what_it_opened():
    class Broken:
        TASKS = ()

        def __init__(self, memory, symbols, hardware):
            pass

        def initialize(self):
            raise RuntimeError("application init failed")

    ecu = SimulatedEcu(mini_image(), MINI_LAYOUT, Broken)
    sim = Simulator(ecu, {"interface": "virtual", "channel": "sim-broken"}, time_scale=1.0)
    with pytest.raises(RuntimeError, match="init failed"):
        sim.start()
    assert sim.closed
    with pytest.raises(can.CanOperationError):
        sim.buses["CAN1"].send(can.Message(arbitration_id=1))  # the bus it opened is shut down again
