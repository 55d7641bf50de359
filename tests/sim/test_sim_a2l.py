"""The demo A2L states what the simulated ECU answers: the simulator's limits are the truth."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import pytest
from mini_ecu import XcpProbe

from workbench.a2l import load_a2l, read_xcp_config
from workbench.errors import InputError
from workbench.sim.demo_ecu import DemoFiles, build_demo_ecu
from workbench.sim.memory_map import HDS9
from workbench.xcp_protocol import Cmd, Resource

UNIT_SECONDS = {0b0100: 10e-6}


@pytest.fixture(scope="module")
def config():
    return read_xcp_config(load_a2l(DemoFiles.defaults().a2l))


@pytest.fixture(scope="module")
def slave():
    demo = build_demo_ecu(unlocked=True)
    demo.ecu.power_on()
    probe = XcpProbe(demo.ecu)
    probe.connect()
    return probe


def test_protocol_layer(config, slave):
    resource, comm_mode, max_cto, max_dto = struct.unpack_from("<BBBH", slave.connect())
    assert (config.max_cto, config.max_dto) == (max_cto, max_dto)
    assert config.byte_order == "MSB_LAST" and not comm_mode & 0x01  # Intel
    assert config.address_granularity == 1 and not comm_mode & 0x06
    _, optional, _, max_bs, min_st, _, _ = slave.ok(Cmd.GET_COMM_MODE_INFO)
    mode = config.communication_mode
    assert mode.slave_block_mode == bool(comm_mode & 0x40)
    assert mode.master_block_mode == bool(optional & 0x01)
    assert (mode.max_bs, mode.min_st_s) == (max_bs, min_st * 100e-6)
    assert config.seed_and_key_function == "workbench.sim.seedkey:compute_key"
    assert resource == Resource.CAL_PAG | Resource.DAQ | Resource.PGM


@pytest.mark.parametrize("transport", ["UDP", "TCP"])
def test_ethernet_packet_sizes(config, transport):
    """XCP_ON_UDP_IP / XCP_ON_TCP_IP overrule MAX_CTO/MAX_DTO (and MAX_CTO_PGM); the slave on Ethernet says the same."""
    demo = build_demo_ecu(transport=transport, unlocked=True)
    demo.ecu.power_on()
    probe = XcpProbe(demo.ecu)
    _, _, max_cto, max_dto = struct.unpack_from("<BBBH", probe.connect())
    ethernet = config.for_transport(transport)
    assert (ethernet.max_cto, ethernet.max_dto) == (max_cto, max_dto) == (255, 1024)
    assert ethernet.pgm.max_cto_pgm == probe.ok(Cmd.PROGRAM_START)[2]
    assert (config.max_cto, config.max_dto) == (8, 8)  # the common blocks stay classic CAN's


def test_daq_limits(config, slave):
    daq = config.daq
    properties, max_daq, max_events, min_daq, key = struct.unpack("<BHHBB", slave.ok(Cmd.GET_DAQ_PROCESSOR_INFO))
    assert daq.config_type == ("DYNAMIC" if properties & 0x01 else "STATIC")
    assert (daq.max_daq, daq.max_event_channels, daq.min_daq) == (max_daq, max_events, min_daq)
    assert daq.prescaler_supported == bool(properties & 0x02)
    assert daq.identification_field == "ABSOLUTE" and key >> 6 == 0
    assert daq.address_extension == "ADDRESS_EXTENSION_FREE" and (key >> 4) & 0x3 == 0
    assert daq.optimisation_type == "OPTIMISATION_TYPE_DEFAULT" and key & 0x0F == 0
    granularity, max_entry, _, _, ts_mode, ticks = struct.unpack("<BBBBBH", slave.ok(Cmd.GET_DAQ_RESOLUTION_INFO))
    assert (daq.granularity, daq.max_odt_entry_size) == (granularity, max_entry)
    assert (daq.timestamp is not None) == bool(properties & 0x10)
    assert daq.timestamp.size == ts_mode & 0x07
    assert daq.timestamp.fixed == bool(ts_mode & 0x08)
    assert daq.timestamp.unit_s == pytest.approx(UNIT_SECONDS[ts_mode >> 4])
    assert daq.timestamp.ticks == ticks


def test_events(config, slave):
    assert len(config.daq.events) == config.daq.max_event_channels
    for event in config.daq.events:
        _, max_lists, name_length, cycle, unit, priority = slave.ok(Cmd.GET_DAQ_EVENT_INFO, 0, struct.pack("<H", event.number))
        assert slave.upload(name_length).decode() == event.name
        assert (event.period_s, event.max_daq_lists, event.priority) == pytest.approx((cycle * 1e-3, max_lists, priority))
        assert unit == 6  # 1 ms


def test_calibration_segment(config, slave):
    assert config.max_segments == slave.ok(Cmd.GET_PAG_PROCESSOR_INFO)[0]
    (segment,) = config.segments
    pages, _, max_mapping = slave.ok(Cmd.GET_SEGMENT_INFO, 1, 0, 0, 0)[:3]
    assert (segment.number, segment.page_count, len(segment.address_mappings)) == (0, pages, max_mapping)
    mapping = [struct.unpack("<3xI", slave.ok(Cmd.GET_SEGMENT_INFO, 2, 0, i, 0))[0] for i in range(3)]
    (a2l_mapping,) = segment.address_mappings
    assert (a2l_mapping.source, a2l_mapping.destination, a2l_mapping.length) == tuple(mapping)
    assert (segment.address, segment.size) == (HDS9.cal_ram.start, HDS9.cal_ram.size)
    assert segment.checksum_type == "XCP_CRC_32"


def test_memory_segments_are_the_simulated_memory_map():
    segments = {s.name: (s.address, s.size) for s in load_a2l(DemoFiles.defaults().a2l).memory_segments()}
    simulated = {region.name: (region.start, region.size) for region in HDS9.flash}
    simulated.update({"CALRAM": (HDS9.cal_ram.start, HDS9.cal_ram.size), "RAM_DATA": (HDS9.ram.start, HDS9.ram.size)})
    assert segments == simulated
    assert HDS9.cal_rom_start == HDS9.region("CALIB").start and HDS9.cal_ram.size == HDS9.region("CALIB").size


def test_checksum_block_limit(slave):
    # XcpSegment does not carry CHECKSUM's MAX_BLOCK_SIZE yet: read it from the A2L text
    text = Path(DemoFiles.defaults().a2l).read_text(encoding="utf-8")
    limits = {int(value, 0) for value in re.findall(r"/begin CHECKSUM XCP_\w+\s+MAX_BLOCK_SIZE\s+(\w+)", text)}
    slave.set_mta(HDS9.cal_rom_start)
    refusal = slave.send(Cmd.BUILD_CHECKSUM, 0, 0, 0, struct.pack("<I", 0x20000 + 4))
    assert refusal[0][:2] == bytes([0xFE, 0x22])  # ERR_OUT_OF_RANGE names the largest block
    assert limits == {struct.unpack_from("<I", refusal[0], 4)[0]}
    assert slave.ok(Cmd.BUILD_CHECKSUM, 0, 0, 0, struct.pack("<I", min(limits)))[0] == 0x09  # CRC-32 over all of it


def test_programming(config, slave):
    pgm = config.pgm
    properties, sectors = slave.ok(Cmd.GET_PGM_PROCESSOR_INFO)
    assert pgm.mode == "PGM_MODE_ABSOLUTE_AND_FUNCTIONAL" and properties & 0x03 == 0x03
    assert pgm.max_sectors == sectors == len(pgm.sectors)
    for sector in pgm.sectors:
        clear_seq, program_seq, method, address = struct.unpack("<BBBI", slave.ok(Cmd.GET_SECTOR_INFO, 0, sector.number))
        length = struct.unpack("<3xI", slave.ok(Cmd.GET_SECTOR_INFO, 1, sector.number))[0]
        name = slave.upload(slave.ok(Cmd.GET_SECTOR_INFO, 2, sector.number)[0]).decode()
        assert (sector.name, sector.address, sector.length) == (name, address, length)
        assert (sector.clear_sequence, sector.program_sequence, sector.program_method) == (clear_seq, program_seq, method)
    response = slave.ok(Cmd.PROGRAM_START)
    assert pgm.max_cto_pgm == response[2]
    assert pgm.communication_mode.max_bs == response[3] and pgm.communication_mode.master_block_mode


def test_can_ids_and_epk(config):
    doc = load_a2l(DemoFiles.defaults().a2l)
    demo = build_demo_ecu()
    params = demo.ecu.params
    assert (params.can_id_master, params.can_id_slave, params.baudrate) == (
        config.can.can_id_master, config.can.can_id_slave, config.can.baudrate)
    assert demo.ecu.read(doc.addr_epk(), len(doc.epk())).decode() == doc.epk()


def _demo_with_a2l(tmp_path, old: str, new: str):
    files = DemoFiles.defaults()
    text = Path(files.a2l).read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "edited.a2l"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return build_demo_ecu(DemoFiles(path, files.elf, files.s19, files.dbc), unlocked=True)


def test_an_event_name_beyond_ascii_is_served_with_replacement_characters(tmp_path):
    demo = _demo_with_a2l(tmp_path, '"Task4ms"     /* name */', '"Tâche4ms"     /* name */')
    demo.ecu.power_on()
    probe = XcpProbe(demo.ecu)
    probe.connect()
    name_length = probe.ok(Cmd.GET_DAQ_EVENT_INFO, 0, struct.pack("<H", 0))[2]
    assert probe.upload(name_length) == b"T?che4ms"


def test_a_checksum_type_the_simulator_cannot_compute_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="edited.a2l: the simulated ECU cannot compute the CHECKSUM type XCP_USER_DEFINED"):
        _demo_with_a2l(tmp_path, "/begin CHECKSUM XCP_CRC_32", "/begin CHECKSUM XCP_USER_DEFINED")
