"""Static DAQ: fixed lists the master only fills, GET_DAQ_LIST_INFO, CLEAR_DAQ_LIST, no allocation commands,
and the transmission ending at the first empty ODT entry."""

import struct

import pytest
from mini_ecu import CAL_GAIN, COUNTER, OUTPUT
from test_slave_daq import daq_probe, write_daq

from workbench.sim.xcp.parameters import DaqParameters, StaticDaqList, XcpParameters
from workbench.xcp_protocol import Cmd, Err

LISTS = (StaticDaqList(odts=2, entries=2, fixed_event=1), StaticDaqList(odts=3, entries=3), StaticDaqList(odts=1, entries=1))


@pytest.fixture
def daq():
    dtos = []
    probe = daq_probe(dtos.extend, params=XcpParameters(daq=DaqParameters(static_lists=LISTS)))
    probe.dtos = dtos
    return probe


def mode(probe, daq_list, event, timestamps=False):
    probe.ok(Cmd.SET_DAQ_LIST_MODE, 0x10 if timestamps else 0x00, struct.pack("<HH", daq_list, event), 1, 0)


def test_processor_info_says_static_and_counts_the_lists(daq):
    properties, max_daq, max_event, min_daq, key = struct.unpack("<BHHBB", daq.ok(Cmd.GET_DAQ_PROCESSOR_INFO))
    assert properties == 0x10  # DAQ_CONFIG_TYPE static, timestamps
    assert (max_daq, max_event, min_daq, key) == (3, 3, 0, 0x00)


def test_list_info_tells_the_shape_and_the_fixed_event(daq):
    def info(number):
        return struct.unpack("<BBBH", daq.ok(Cmd.GET_DAQ_LIST_INFO, 0, struct.pack("<H", number)))

    assert info(0) == (0x06, 2, 2, 1)  # DAQ, EVENT_FIXED, not PREDEFINED; 2 ODTs of 2 entries; event 1
    assert info(1) == (0x04, 3, 3, 0)
    assert info(2) == (0x04, 1, 1, 0)
    assert daq.err(Cmd.GET_DAQ_LIST_INFO, 0, struct.pack("<H", 3)) == Err.OUT_OF_RANGE


@pytest.mark.parametrize("command", [
    (Cmd.FREE_DAQ,), (Cmd.ALLOC_DAQ, 0, struct.pack("<H", 1)), (Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 1),
    (Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 1),
], ids=["FREE_DAQ", "ALLOC_DAQ", "ALLOC_ODT", "ALLOC_ODT_ENTRY"])
def test_the_dynamic_commands_do_not_exist(daq, command):
    assert daq.err(*command) == Err.CMD_UNKNOWN


def test_pids_follow_the_lists_odts_and_an_empty_entry_ends_the_transmission(daq):
    write_daq(daq, 1, 0, 0, (COUNTER, 4), (OUTPUT, 2))
    write_daq(daq, 1, 1, 0, (CAL_GAIN, 4))
    write_daq(daq, 1, 2, 1, (OUTPUT, 4))  # ODT 2's first entry stays empty: ODT 2 is not sent
    mode(daq, 1, 0)
    assert daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 1)) == b"\x02"  # after list 0's 2 ODTs
    daq.ecu.advance(0.004)
    assert [dto[0] for dto in daq.dtos] == [2, 3]
    assert daq.dtos[0][1:] == daq.ecu.read(COUNTER, 4) + daq.ecu.read(OUTPUT, 2)
    assert daq.dtos[1][1:] == daq.ecu.read(CAL_GAIN, 4)


def test_an_empty_entry_ends_its_odt(daq):
    write_daq(daq, 1, 0, 0, (COUNTER, 2))
    write_daq(daq, 1, 0, 2, (OUTPUT, 4))  # behind the empty entry 1: not sent
    mode(daq, 1, 2)
    daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 1))
    daq.ecu.advance(0.1)
    (dto,) = daq.dtos
    assert dto == b"\x02" + daq.ecu.read(COUNTER, 2)  # PID and entry 0 only


def test_a_fixed_event_list_takes_only_its_event(daq):
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x00, struct.pack("<HH", 0, 0), 1, 0) == Err.OUT_OF_RANGE
    write_daq(daq, 0, 0, 0, (COUNTER, 4))
    daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 0))  # its event needs no SET_DAQ_LIST_MODE
    daq.ecu.advance(0.1)
    assert [dto[0] for dto in daq.dtos] == [0, 0]  # 50 ms twice


def test_the_limits_of_a_static_list(daq):
    assert daq.err(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 2), 0, 1) == Err.OUT_OF_RANGE  # list 2 has 1 entry
    assert daq.err(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 2, 0) == Err.OUT_OF_RANGE  # list 0 has 2 ODTs
    write_daq(daq, 2, 0, 0, (COUNTER, 4))
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 1, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE  # past the last entry
    daq.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 1), 0, 0)
    daq.ok(Cmd.WRITE_DAQ, 0xFF, 4, 0, struct.pack("<I", COUNTER))
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 4, 0, struct.pack("<I", OUTPUT)) == Err.DAQ_CONFIG  # 8 bytes > 7


def test_clear_daq_list_empties_a_stopped_list(daq):
    write_daq(daq, 2, 0, 0, (COUNTER, 2))
    mode(daq, 2, 0, timestamps=True)
    daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 2))
    assert daq.err(Cmd.CLEAR_DAQ_LIST, 0, struct.pack("<H", 2)) == Err.DAQ_ACTIVE
    daq.ok(Cmd.START_STOP_DAQ_LIST, 0, struct.pack("<H", 2))
    daq.ok(Cmd.CLEAR_DAQ_LIST, 0, struct.pack("<H", 2))
    assert daq.err(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 2)) == Err.DAQ_CONFIG  # no event, nothing to send
    mode(daq, 2, 0)
    assert daq.err(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 2)) == Err.DAQ_CONFIG  # still nothing to send
    assert daq.err(Cmd.CLEAR_DAQ_LIST, 0, struct.pack("<H", 3)) == Err.OUT_OF_RANGE


def test_a_new_session_finds_the_lists_empty(daq):
    write_daq(daq, 2, 0, 0, (COUNTER, 4))
    mode(daq, 2, 0)
    daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 2))
    daq.ok(Cmd.DISCONNECT)
    daq.connect()
    daq.ecu.advance(0.01)
    (emptied,) = daq.ecu.slave.daq.lists[2].odts[0]
    assert daq.dtos == [] and emptied.size == 0


def test_a_dynamic_slave_has_no_static_commands():
    probe = daq_probe()
    assert probe.err(Cmd.GET_DAQ_LIST_INFO, 0, struct.pack("<H", 0)) == Err.CMD_UNKNOWN
    assert probe.err(Cmd.CLEAR_DAQ_LIST, 0, struct.pack("<H", 0)) == Err.CMD_UNKNOWN


def test_static_lists_must_fit_the_absolute_pids():
    with pytest.raises(ValueError, match="more than 252 ODTs"):
        DaqParameters(static_lists=(StaticDaqList(200, 1), StaticDaqList(53, 1)))
