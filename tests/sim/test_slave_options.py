"""The slave's other implementations of XCP's options (what the profiles are made of), command by command:
byte order, address granularity, block modes, GET_ID, long seeds, segments, EV/SERV packets."""

import struct

import pytest
from mini_ecu import CAL_GAIN, CAL_OFFSET, EPK, XcpProbe, make_ecu

from workbench.image import AddressRange
from workbench.sim.seedkey import compute_key
from workbench.sim.xcp.parameters import XcpParameters
from workbench.xcp_protocol import Cmd, Err, Resource

ECU_AND_XCP, XCP, ALL = 0x03, 0x02, 0x80


def probe(**params) -> XcpProbe:
    ecu = make_ecu(params=XcpParameters(**params))
    ecu.power_on()
    xcp = XcpProbe(ecu)
    xcp.connect()
    return xcp


def test_motorola_byte_order_in_connect_and_every_multi_byte_field():
    xcp = probe(byte_order=">", protected=Resource(0))
    resources, basic, max_cto, max_dto = struct.unpack(">BBBH", xcp.connect()[:5])
    assert basic & 0x01 and (max_cto, max_dto) == (8, 8)
    xcp.ok(Cmd.SET_MTA, 0, 0, 0, struct.pack(">I", CAL_GAIN))
    assert xcp.upload(4) == struct.pack("<f", 2.0)  # data stay as the ECU holds them (Intel)
    assert struct.unpack(">BHHBB", xcp.ok(Cmd.GET_DAQ_PROCESSOR_INFO))[1] == 16
    assert xcp.ok(Cmd.GET_ID, 5)[3:] == struct.pack(">I", len(EPK))


@pytest.mark.parametrize("granularity", [2, 4])
def test_a_granularity_above_byte_counts_elements_aligns_and_pads(granularity):
    xcp = probe(address_granularity=granularity, protected=Resource(0))
    assert (xcp.connect()[1] >> 1) & 0x03 == {2: 1, 4: 2}[granularity]
    response = xcp.ok(Cmd.SHORT_UPLOAD, 4 // granularity, 0, 0, struct.pack("<I", CAL_GAIN))
    assert response == bytes(granularity - 1) + struct.pack("<f", 2.0)  # alignment bytes, then the element(s)
    assert xcp.err(Cmd.SHORT_UPLOAD, 1, 0, 0, struct.pack("<I", CAL_GAIN + 1)) == Err.OUT_OF_RANGE  # misaligned
    xcp.set_mta(CAL_OFFSET)
    xcp.ok(Cmd.DOWNLOAD, 4 // granularity, bytes(max(2, granularity) - 2), struct.pack("<f", 7.5))
    assert xcp.ecu.read(CAL_OFFSET, 4) == struct.pack("<f", 7.5)
    xcp.set_mta(CAL_GAIN + 2 if granularity == 4 else CAL_GAIN + 1)
    assert xcp.err(Cmd.UPLOAD, 1) == Err.OUT_OF_RANGE


def test_without_block_modes_one_packet_carries_each_transfer():
    xcp = probe(slave_block_mode=False, master_block_mode=False, max_bs=1, protected=Resource(0))
    assert not xcp.connect()[1] & 0x40
    comm_mode = xcp.ok(Cmd.GET_COMM_MODE_INFO)
    assert (comm_mode[1], comm_mode[3]) == (0, 1)  # no master block mode, MAX_BS 1 all the same
    xcp.set_mta(CAL_GAIN)
    assert xcp.err(Cmd.UPLOAD, 8) == Err.OUT_OF_RANGE
    assert len(xcp.send(Cmd.UPLOAD, 7)) == 1
    xcp.set_mta(CAL_GAIN)
    assert xcp.err(Cmd.DOWNLOAD, 8, bytes(6)) == Err.OUT_OF_RANGE  # a block of two frames
    assert xcp.ok(Cmd.PROGRAM_START)[1] == 0  # no master block mode for programming either


def test_no_get_id_leaves_the_epk_to_addr_epk():
    xcp = probe(get_id=False)
    assert xcp.err(Cmd.GET_ID, 5) == Err.CMD_UNKNOWN
    assert Cmd.GET_ID not in xcp.ecu.slave.commands and Cmd.UPLOAD in xcp.ecu.slave.commands
    assert xcp.short_upload(0xFC0000, 7) == EPK[:7]


def test_a_seed_longer_than_a_packet_comes_in_parts_and_so_does_its_key():
    xcp = probe(seed_length=20)
    first = xcp.ok(Cmd.GET_SEED, 0, Resource.CAL_PAG)
    seed, remaining = first[1:], first[0]
    assert remaining == 20 and len(seed) == 6
    while len(seed) < 20:
        part = xcp.ok(Cmd.GET_SEED, 1, 0)
        assert part[0] == 20 - len(seed)
        seed += part[1:1 + min(part[0], 6)]
    key = compute_key(seed, Resource.CAL_PAG)
    for start in range(0, 20, 6):
        status = xcp.ok(Cmd.UNLOCK, 20 - start, key[start:start + 6])[0]
    assert not status & Resource.CAL_PAG
    assert xcp.err(Cmd.UNLOCK, 4, bytes(4)) == Err.SEQUENCE  # the seed is used up


def test_a_wrong_part_of_a_long_key_locks_and_ends_the_session():
    xcp = probe(seed_length=12)
    seed = xcp.ok(Cmd.GET_SEED, 0, Resource.DAQ)[1:]
    seed += xcp.ok(Cmd.GET_SEED, 1, 0)[1:]
    key = bytearray(compute_key(seed[:12], Resource.DAQ))
    key[-1] ^= 0xFF
    xcp.ok(Cmd.UNLOCK, 12, key[:6])
    assert xcp.err(Cmd.UNLOCK, 6, key[6:]) == Err.ACCESS_LOCKED
    assert not xcp.ecu.slave.connected


SEGMENTS = (AddressRange(0x40000000, 0x40000010), AddressRange(0x40000010, 0x40020000))


@pytest.mark.parametrize("all_segments", [True, False])
def test_segments_switch_alone_or_all_at_once_where_the_slave_has_it(all_segments):
    xcp = probe(segments=SEGMENTS, all_segments_mode=all_segments, protected=Resource(0))
    assert xcp.ok(Cmd.GET_PAG_PROCESSOR_INFO)[0] == 2
    assert struct.unpack("<3xI", xcp.ok(Cmd.GET_SEGMENT_INFO, 2, 1, 1, 0))[0] == 0xFC0010  # segment 1's mapping
    xcp.set_mta(CAL_GAIN)
    xcp.ok(Cmd.DOWNLOAD, 4, struct.pack("<f", 9.0))
    xcp.ok(Cmd.SET_CAL_PAGE, XCP, 0, 1)  # the EPK segment only: the calibrations stay on the working page
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 9.0)
    assert xcp.err(Cmd.SHORT_UPLOAD, 4, 0, 0, struct.pack("<I", 0x4000000E)) == Err.OUT_OF_RANGE  # 2 pages at once
    if all_segments:
        xcp.ok(Cmd.SET_CAL_PAGE, ECU_AND_XCP | ALL, 0, 1)
        assert xcp.ecu.pages.ecu_pages == [1, 1] and xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)
    else:
        assert xcp.err(Cmd.SET_CAL_PAGE, ECU_AND_XCP | ALL, 0, 1) == Err.MODE_NOT_VALID
        xcp.ok(Cmd.SET_CAL_PAGE, XCP, 1, 1)
        assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)
    assert xcp.err(Cmd.SET_CAL_PAGE, XCP, 2, 1) == Err.SEGMENT_NOT_VALID
    xcp.ok(Cmd.SET_CAL_PAGE, XCP, 1, 0)
    xcp.ok(Cmd.COPY_CAL_PAGE, 1, 1, 1, 0)  # reference over working, segment 1 only
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)


def test_ev_and_serv_packets_come_before_responses_in_turn():
    ecu = make_ecu(params=XcpParameters(service_packets=True))
    ecu.power_on()
    xcp = XcpProbe(ecu)
    first, second = xcp.send(Cmd.CONNECT, 0), xcp.send(Cmd.GET_STATUS)
    assert [p[0] for p in first] == [0xFD, 0xFF] and first[0][1] == 0xFE  # EV_USER
    assert [p[0] for p in second] == [0xFC, 0xFF] and second[0][1] == 0x01  # SERV_TEXT
    assert len(second[0]) <= 8
