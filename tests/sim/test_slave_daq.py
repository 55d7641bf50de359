"""DAQ: the limits the slave publishes are enforced, DTOs carry timestamps and the right bytes."""

import struct

import pytest
from mini_ecu import CAL_GAIN, COUNTER, OUTPUT, XcpProbe, make_ecu

from workbench.sim.xcp.parameters import EventChannel, XcpParameters
from workbench.xcp_protocol import Cmd, Err, Resource


def daq_probe(dto_sink=None, **ecu_options) -> XcpProbe:
    """A connected probe with DAQ unlocked on a powered mini ECU whose DAQ samples go to ``dto_sink``."""
    ecu = make_ecu(dto_sink=dto_sink, **ecu_options)
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.unlock(Resource.DAQ)
    return probe


@pytest.fixture
def daq():
    dtos = []
    probe = daq_probe(dtos.extend)
    probe.dtos = dtos
    return probe


def alloc(probe, odts_per_list, entries):
    probe.ok(Cmd.FREE_DAQ)
    probe.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", len(odts_per_list)))
    for number, odts in enumerate(odts_per_list):
        probe.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", number), odts)
    for number, odt, count in entries:
        probe.ok(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", number), odt, count)


def write_daq(probe, daq_list, odt, entry, *elements):
    probe.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", daq_list), odt, entry)
    for address, size in elements:
        probe.ok(Cmd.WRITE_DAQ, 0xFF, size, 0, struct.pack("<I", address))


def test_processor_and_resolution_info(daq):
    properties, max_daq, max_event, min_daq, key = struct.unpack("<BHHBB", daq.ok(Cmd.GET_DAQ_PROCESSOR_INFO))
    assert properties == 0x11  # dynamic, timestamps (no prescaler)
    assert (max_daq, max_event, min_daq, key) == (16, 3, 0, 0x00)  # absolute PIDs, address extension free
    gran, max_entry, _, _, ts_mode, ticks = struct.unpack("<BBBBBH", daq.ok(Cmd.GET_DAQ_RESOLUTION_INFO))
    assert (gran, max_entry, ts_mode, ticks) == (1, 4, 0x44, 1)  # 10 us, 4 bytes, not fixed


def test_event_info_names_the_task(daq):
    properties, max_lists, name_length, cycle, unit, _ = daq.ok(Cmd.GET_DAQ_EVENT_INFO, 0, struct.pack("<H", 1))
    assert (cycle, unit, properties & 0x04) == (50, 6, 0x04)
    assert daq.upload(name_length) == b"Task50ms"
    assert daq.err(Cmd.GET_DAQ_EVENT_INFO, 0, struct.pack("<H", 3)) == Err.OUT_OF_RANGE


def test_dtos_on_the_50ms_event(daq):
    alloc(daq, [2], [(0, 0, 1), (0, 1, 2)])
    daq.ok(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 1), 1, 0)  # timestamps on
    write_daq(daq, 0, 0, 0, (COUNTER, 3))  # 3 data bytes after PID + timestamp
    write_daq(daq, 0, 1, 0, (OUTPUT, 4), (CAL_GAIN, 2))
    assert daq.ok(Cmd.START_STOP_DAQ_LIST, 2, struct.pack("<H", 0)) == b"\x00"  # select; FIRST_PID 0
    daq.ok(Cmd.START_STOP_SYNCH, 1)
    assert daq.ok(Cmd.GET_STATUS)[0] & 0x40  # DAQ running
    daq.ecu.advance(0.1)
    assert len(daq.dtos) == 4
    first, second = daq.dtos[2], daq.dtos[3]
    assert first[0] == 0 and second[0] == 1
    assert struct.unpack_from("<I", first, 1)[0] == 10_000  # 100 ms in 10 us ticks
    assert first[5:] == daq.ecu.read(COUNTER, 3)
    assert second[1:] == daq.ecu.read(OUTPUT, 4) + daq.ecu.read(CAL_GAIN, 2)
    daq.ok(Cmd.START_STOP_SYNCH, 0)
    daq.ecu.advance(0.1)
    assert len(daq.dtos) == 4


def test_a_list_without_timestamps_and_the_pids_of_a_second_list(daq):
    alloc(daq, [1, 1], [(0, 0, 1), (1, 0, 2)])
    write_daq(daq, 0, 0, 0, (COUNTER, 1))
    write_daq(daq, 1, 0, 0, (COUNTER, 4), (OUTPUT, 3))  # 7 bytes: the whole DTO without a timestamp
    daq.ok(Cmd.SET_DAQ_LIST_MODE, 0x00, struct.pack("<HH", 1, 0), 1, 0)
    assert daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 1)) == b"\x01"
    daq.ecu.advance(0.008)
    assert len(daq.dtos) == 2 and all(d[0] == 1 and len(d) == 8 for d in daq.dtos)
    assert daq.dtos[-1][1:] == daq.ecu.read(COUNTER, 4) + daq.ecu.read(OUTPUT, 3)
    assert daq.err(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 0)) == Err.DAQ_CONFIG  # list 0 has no event
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x00, struct.pack("<HH", 0, 0), 2, 0) == Err.OUT_OF_RANGE  # no prescaler


def test_entry_larger_than_max_odt_entry_size_is_out_of_range(daq):
    alloc(daq, [2], [(0, 0, 1), (0, 1, 2)])
    daq.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 1, 0)
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 5, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 0, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE


def test_odt_over_the_dto_is_a_daq_config_error(daq):
    alloc(daq, [2], [(0, 0, 2), (0, 1, 2)])
    daq.ok(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 1), 1, 0)
    daq.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 0, 0)
    daq.ok(Cmd.WRITE_DAQ, 0xFF, 2, 0, struct.pack("<I", COUNTER))
    # a timestamped first ODT carries 3 data bytes only
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 2, 0, struct.pack("<I", COUNTER)) == Err.DAQ_CONFIG
    daq.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 1, 0)
    daq.ok(Cmd.WRITE_DAQ, 0xFF, 4, 0, struct.pack("<I", COUNTER))
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 4, 0, struct.pack("<I", COUNTER)) == Err.DAQ_CONFIG  # 8 > 7


def test_timestamps_cannot_be_turned_on_over_a_full_first_odt(daq):
    alloc(daq, [1], [(0, 0, 2)])
    write_daq(daq, 0, 0, 0, (COUNTER, 4), (OUTPUT, 2))  # 6 bytes: fine without a timestamp
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 1), 1, 0) == Err.DAQ_CONFIG
    daq.ok(Cmd.SET_DAQ_LIST_MODE, 0x00, struct.pack("<HH", 0, 1), 1, 0)


def test_more_entries_than_an_odt_can_carry(daq):
    alloc(daq, [2], [])
    assert daq.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 8) == Err.OUT_OF_RANGE  # 7 bytes after the PID
    daq.ok(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 7)
    assert daq.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 1, 8) == Err.OUT_OF_RANGE


def test_allocation_out_of_order_is_a_sequence_error(daq):
    daq.ok(Cmd.FREE_DAQ)
    assert daq.err(Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 1) == Err.SEQUENCE
    daq.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 2))
    assert daq.err(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 2)) == Err.SEQUENCE
    assert daq.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 1) == Err.SEQUENCE
    daq.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 1)
    assert daq.err(Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 1) == Err.SEQUENCE  # list 0 twice
    daq.ok(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 1)
    assert daq.err(Cmd.ALLOC_ODT, 0, struct.pack("<H", 1), 1) == Err.SEQUENCE  # ODTs after entries
    assert daq.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 1) == Err.SEQUENCE  # ODT 0 twice
    assert daq.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 1), 0, 1) == Err.OUT_OF_RANGE  # list 1 has no ODTs
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 1, 0, struct.pack("<I", COUNTER)) == Err.SEQUENCE  # no DAQ pointer yet


def test_allocation_limits(daq):
    daq.ok(Cmd.FREE_DAQ)
    assert daq.err(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 17)) == Err.MEMORY_OVERFLOW
    daq.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 2))
    daq.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 250)
    assert daq.err(Cmd.ALLOC_ODT, 0, struct.pack("<H", 1), 3) == Err.MEMORY_OVERFLOW  # 252 PIDs in all


def test_write_daq_checks_address_and_modes(daq):
    alloc(daq, [1], [(0, 0, 1)])
    daq.ok(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 0, 0)
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 2, 0, struct.pack("<I", 0x100)) == Err.OUT_OF_RANGE  # unmapped
    assert daq.err(Cmd.WRITE_DAQ, 0x03, 1, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE  # bit-wise entry
    daq.ok(Cmd.WRITE_DAQ, 0xFF, 2, 0, struct.pack("<I", COUNTER))
    assert daq.err(Cmd.WRITE_DAQ, 0xFF, 1, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE  # past the last entry
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x02, struct.pack("<HH", 0, 1), 1, 0) == Err.MODE_NOT_VALID  # STIM
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x30, struct.pack("<HH", 0, 1), 1, 0) == Err.MODE_NOT_VALID  # PID_OFF
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 7), 1, 0) == Err.OUT_OF_RANGE  # event
    assert daq.err(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 1), 0, 0) == Err.OUT_OF_RANGE  # prescaler 0
    daq.ok(Cmd.SET_DAQ_LIST_MODE, 0x10, struct.pack("<HH", 0, 1), 1, 0)
    daq.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", 0))
    assert daq.err(Cmd.SET_DAQ_PTR, 0, struct.pack("<H", 0), 0, 0) == Err.DAQ_ACTIVE
    daq.unlock(Resource.PGM)
    assert daq.err(Cmd.PROGRAM_START) == Err.DAQ_ACTIVE


def test_daq_clock_counts_ticks_since_power_on(daq):
    daq.ecu.advance(0.25)
    assert struct.unpack("<3xI", daq.ok(Cmd.GET_DAQ_CLOCK))[0] == 25_000


def test_each_daq_list_sample_reaches_the_sink_whole():
    samples = []
    probe = daq_probe(samples.append)
    alloc(probe, [2, 3], [(0, 0, 1), (0, 1, 1), (1, 0, 1), (1, 1, 1), (1, 2, 1)])
    for daq_list in (0, 1):
        probe.ok(Cmd.SET_DAQ_LIST_MODE, 0x00, struct.pack("<HH", daq_list, 0), 1, 0)
        probe.ok(Cmd.START_STOP_DAQ_LIST, 1, struct.pack("<H", daq_list))
    probe.ecu.advance(0.004)
    assert [[dto[0] for dto in sample] for sample in samples] == [[0, 1], [2, 3, 4]]  # one call per list, absolute PIDs


@pytest.mark.parametrize(("period_s", "cycle", "unit"), [
    (0.004, 4, 6), (0.1, 100, 6),  # whole milliseconds: as the A2L states them
    (1.0, 100, 7), (0.0005, 50, 4),  # the thesis's 1000 ms task; a sub-millisecond one
    (0.0, 0, 6), (3600.0, 0, 6),  # not cyclic; beyond what a byte of 1 s units holds
])
def test_event_cycles_fit_a_byte(period_s, cycle, unit):
    probe = daq_probe(params=XcpParameters(events=(EventChannel(0, "Task", period_s),)))
    assert tuple(probe.ok(Cmd.GET_DAQ_EVENT_INFO, 0, struct.pack("<H", 0))[3:5]) == (cycle, unit)
