"""DAQ as other slaves implement it: predefined lists before the allocated ones, MAX_DAQ counting what is
allocated, relative identification fields, timestamps of 1, 2 or no bytes, TIMESTAMP_FIXED."""

import struct

import pytest
from mini_ecu import COUNTER, OUTPUT
from test_slave_daq import alloc, daq_probe, write_daq

from workbench.sim.xcp.parameters import DaqParameters, PredefinedDaqList, XcpParameters
from workbench.xcp_protocol import Cmd, Err

PREDEFINED = (PredefinedDaqList(0, ((COUNTER, 4),)), PredefinedDaqList(1, ((OUTPUT, 4),)))


def probe(dtos: list, **daq):
    return daq_probe(dtos.extend, params=XcpParameters(daq=DaqParameters(**daq)))


def processor_info(xcp) -> tuple:
    return struct.unpack("<BHHBB", xcp.ok(Cmd.GET_DAQ_PROCESSOR_INFO))


def test_max_daq_counts_predefined_and_allocated_lists_and_the_limit_shows_at_alloc():
    xcp = probe([], predefined=PREDEFINED, max_daq_counts_allocated=True, max_daq=4)
    _, max_daq, _, min_daq, _ = processor_info(xcp)
    assert (max_daq, min_daq) == (2, 2)  # before ALLOC_DAQ: the predefined lists only
    xcp.ok(Cmd.FREE_DAQ)
    assert xcp.err(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 3)) == Err.MEMORY_OVERFLOW
    xcp.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 2))
    assert processor_info(xcp)[1] == 4
    assert xcp.err(Cmd.ALLOC_ODT, 0, struct.pack("<H", 1), 1) == Err.OUT_OF_RANGE  # a predefined list
    xcp.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", 2), 1)


def test_predefined_lists_are_described_started_never_rewritten_and_kept_by_free_daq():
    dtos = []
    xcp = probe(dtos, predefined=PREDEFINED)
    properties, odts, entries, event = struct.unpack("<BBBH", xcp.ok(Cmd.GET_DAQ_LIST_INFO, 0, struct.pack("<H", 1)))
    assert (properties & 0x03, odts, entries, event) == (0x03, 1, 1, 1)  # PREDEFINED, EVENT_FIXED
    xcp.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 0, 0)
    assert xcp.err(Cmd.WRITE_DAQ, 0xFF, 4, 0, struct.pack("<I", OUTPUT)) == Err.WRITE_PROTECTED
    xcp.ok(Cmd.FREE_DAQ)
    xcp.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 1))  # the first allocated list is number MIN_DAQ
    xcp.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", 2), 1)
    xcp.ok(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 2), 0, 1)
    write_daq(xcp, 2, 0, 0, (OUTPUT, 4))
    xcp.ok(Cmd.SET_DAQ_LIST_MODE, 0, struct.pack("<HHBB", 2, 0, 1, 0))
    assert xcp.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 2)) == bytes([2])  # PIDs after the predefined ODTs
    xcp.ok(Cmd.SET_DAQ_LIST_MODE, 0, struct.pack("<HHBB", 0, 0, 1, 0))
    assert xcp.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 0)) == bytes([0])
    xcp.ecu.advance(0.004)
    assert sorted(dto[0] for dto in dtos) == [0, 2]


@pytest.mark.parametrize(("field", "key", "header"), [
    ("RELATIVE_BYTE", 0x40, bytes([0, 1])),
    ("RELATIVE_WORD", 0x80, bytes([0, 1, 0])),
    ("RELATIVE_WORD_ALIGNED", 0xC0, bytes([0, 0, 1, 0])),
])
def test_relative_identification_fields_name_the_odt_then_the_list(field, key, header):
    dtos = []
    xcp = probe(dtos, identification_field=field)
    assert processor_info(xcp)[4] == key
    alloc(xcp, [1, 1], [(0, 0, 1), (1, 0, 1)])
    write_daq(xcp, 1, 0, 0, (COUNTER, 4))
    assert xcp.err(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 1)) == Err.SEQUENCE
    xcp.ok(Cmd.SET_DAQ_LIST_MODE, 0, struct.pack("<HHBB", 1, 0, 1, 0))
    assert xcp.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 1)) == bytes([0])  # no absolute FIRST_PID
    xcp.ecu.advance(0.004)
    assert dtos and dtos[0][:len(header)] == header and len(dtos[0]) == len(header) + 4


@pytest.mark.parametrize(("size", "fixed", "mode"), [(1, False, 0x61), (2, True, 0x3A), (0, False, 0x00)])
def test_timestamps_of_one_two_or_no_bytes_fixed_or_selectable(size, fixed, mode):
    dtos = []
    unit = 6 if size == 1 else 3
    xcp = probe(dtos, timestamp_size=size, timestamp_unit=unit, timestamp_ticks=10 if size == 2 else 1,
                timestamp_fixed=fixed)
    assert bool(processor_info(xcp)[0] & 0x10) == bool(size)
    assert struct.unpack("<BBBBBH", xcp.ok(Cmd.GET_DAQ_RESOLUTION_INFO))[4] == mode
    alloc(xcp, [1], [(0, 0, 1)])
    write_daq(xcp, 0, 0, 0, (COUNTER, 4))
    if not size:
        assert xcp.err(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HHBB", 0, 0, 1, 0)) == Err.MODE_NOT_VALID
    xcp.ok(Cmd.SET_DAQ_LIST_MODE, 0, struct.pack("<HHBB", 0, 0, 1, 0))  # timestamps not asked for
    xcp.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 0))
    xcp.ecu.advance(0.012)
    assert {len(dto) for dto in dtos} == {1 + (size if fixed else 0) + 4}
