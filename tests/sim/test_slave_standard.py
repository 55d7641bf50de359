"""Standard commands, silences, memory transfer and resource protection, with raw CTOs."""

import struct

import pytest
from pyxcp import checksum as pyxcp_checksum

from mini_ecu import CAL_GAIN, CAL_OFFSET, COUNTER, EPK, XcpProbe, make_ecu
from workbench.image import ChecksumType
from workbench.sim.seedkey import compute_key
from workbench.sim.xcp.parameters import XcpParameters
from workbench.xcp_protocol import Cmd, Err, Resource


def test_silent_until_connected(ecu):
    probe = XcpProbe(ecu)
    probe.silent(Cmd.GET_STATUS)
    probe.silent(b"")
    response = probe.ok(Cmd.CONNECT, 0)
    resource, comm_mode, max_cto, max_dto = struct.unpack_from("<BBBH", response)
    assert resource == Resource.CAL_PAG | Resource.DAQ | Resource.PGM
    assert comm_mode == 0xC0  # OPTIONAL, SLAVE_BLOCK_MODE, Intel, byte granularity
    assert (max_cto, max_dto) == (8, 8)


def test_status_reports_protection_until_unlocked(xcp):
    session, protection = xcp.ok(Cmd.GET_STATUS)[:2]
    assert session == 0 and protection == Resource.CAL_PAG | Resource.DAQ | Resource.PGM
    assert xcp.unlock(Resource.DAQ) == Resource.CAL_PAG | Resource.PGM
    assert xcp.ok(Cmd.GET_STATUS)[1] == Resource.CAL_PAG | Resource.PGM
    assert xcp.ok(Cmd.GET_SEED, 0, Resource.DAQ) == b"\x00"  # already unlocked: empty seed


def test_locked_resources_answer_access_locked(xcp):
    xcp.set_mta(CAL_GAIN)
    assert xcp.err(Cmd.DOWNLOAD, 4, struct.pack("<f", 1.0)) == Err.ACCESS_LOCKED
    assert xcp.err(Cmd.FREE_DAQ) == Err.ACCESS_LOCKED
    assert xcp.err(Cmd.PROGRAM_START) == Err.ACCESS_LOCKED


def test_wrong_key_is_refused_and_ends_the_session(xcp):
    seed = xcp.ok(Cmd.GET_SEED, 0, Resource.CAL_PAG)
    key = bytearray(compute_key(seed[1:5], Resource.CAL_PAG))
    key[0] ^= 0xFF
    assert xcp.err(Cmd.UNLOCK, 4, bytes(key)) == Err.ACCESS_LOCKED
    xcp.silent(Cmd.GET_STATUS)  # disconnected
    xcp.connect()
    assert xcp.ok(Cmd.GET_STATUS)[1] & Resource.CAL_PAG


def test_unlock_without_seed_and_bad_seed_requests(xcp):
    assert xcp.err(Cmd.UNLOCK, 4, bytes(4)) == Err.SEQUENCE
    assert xcp.err(Cmd.GET_SEED, 0, 0x05) == Err.OUT_OF_RANGE  # two resources at once
    assert xcp.err(Cmd.GET_SEED, 0, Resource.STIM) == Err.OUT_OF_RANGE  # no STIM in this ECU
    assert xcp.err(Cmd.GET_SEED, 1, 0) == Err.SEQUENCE


def test_get_id_epk_then_upload(xcp):
    mode, _, _, length = struct.unpack("<BBBI", xcp.ok(Cmd.GET_ID, 5))
    assert (mode, length) == (0, len(EPK))
    packets = xcp.send(Cmd.UPLOAD, length)
    assert [p[0] for p in packets] == [0xFF, 0xFF]  # slave block mode: 7 + 7 bytes
    assert b"".join(p[1:] for p in packets) == EPK


def test_get_id_asam_name_and_unknown_type(xcp):
    length = struct.unpack("<BBBI", xcp.ok(Cmd.GET_ID, 1))[3]
    assert xcp.upload(length) == b"FLCU"
    assert xcp.err(Cmd.GET_ID, 4) == Err.OUT_OF_RANGE


def test_upload_of_255_bytes_in_slave_block_mode(xcp, ecu):
    xcp.set_mta(0xFC0000)
    packets = xcp.send(Cmd.UPLOAD, 255)
    assert len(packets) == 37 and all(p[0] == 0xFF for p in packets)
    assert b"".join(p[1:] for p in packets) == ecu.read(0xFC0000, 255)


def test_short_upload_limits(xcp):
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)
    assert xcp.err(Cmd.SHORT_UPLOAD, 8, 0, 0, struct.pack("<I", CAL_GAIN)) == Err.OUT_OF_RANGE
    assert xcp.err(Cmd.SHORT_UPLOAD, 4, 0, 1, struct.pack("<I", CAL_GAIN)) == Err.OUT_OF_RANGE  # address extension
    assert xcp.err(Cmd.SHORT_UPLOAD, 4, 0, 0, struct.pack("<I", 0x10)) == Err.OUT_OF_RANGE  # unmapped
    assert xcp.err(Cmd.SHORT_UPLOAD, 4) == Err.CMD_SYNTAX


def test_download_in_master_block_mode(xcp):
    xcp.unlock(Resource.CAL_PAG)
    xcp.set_mta(CAL_GAIN)
    data = struct.pack("<ff", 3.5, -1.25) + bytes(4)
    xcp.silent(Cmd.DOWNLOAD, 12, data[:6])
    assert xcp.ok(Cmd.DOWNLOAD_NEXT, 6, data[6:]) == b""
    assert xcp.short_upload(CAL_GAIN, 7) == data[:7]


def test_download_next_with_wrong_count_names_the_expected_one(xcp):
    xcp.unlock(Resource.CAL_PAG)
    xcp.set_mta(CAL_GAIN)
    xcp.silent(Cmd.DOWNLOAD, 10, bytes(6))
    assert xcp.send(Cmd.DOWNLOAD_NEXT, 3, bytes(3)) == [bytes([0xFE, Err.SEQUENCE, 4])]
    assert xcp.err(Cmd.DOWNLOAD_NEXT, 4, bytes(4)) == Err.SEQUENCE  # the block was abandoned


def test_writes_outside_cal_ram_section_and_to_flash_are_refused(xcp):
    xcp.unlock(Resource.CAL_PAG)
    xcp.set_mta(0x40000000)  # CAL RAM, but before .cal_ram
    assert xcp.err(Cmd.DOWNLOAD, 4, bytes(4)) == Err.WRITE_PROTECTED
    xcp.set_mta(0xFC0010)  # CAL ROM
    assert xcp.err(Cmd.DOWNLOAD, 4, bytes(4)) == Err.WRITE_PROTECTED
    xcp.set_mta(CAL_OFFSET + 8)  # the range runs past the end of .cal_ram
    assert xcp.err(Cmd.DOWNLOAD, 6, bytes(6)) == Err.WRITE_PROTECTED
    xcp.set_mta(COUNTER)  # ordinary RAM is writable
    assert xcp.ok(Cmd.DOWNLOAD_MAX, bytes(7)) == b""
    assert xcp.err(Cmd.SHORT_DOWNLOAD, 1, 0, 0, struct.pack("<I", COUNTER)) == Err.OUT_OF_RANGE  # no room on CAN


@pytest.mark.parametrize("kind", list(ChecksumType))
def test_build_checksum_matches_pyxcp(kind):
    ecu = make_ecu(params=XcpParameters(checksum_type=kind))
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.set_mta(0xFC0000)
    kind_byte, _, _, value = struct.unpack("<BBBI", probe.ok(Cmd.BUILD_CHECKSUM, 0, 0, 0, struct.pack("<I", 0x100)))
    assert kind_byte == kind
    assert value == pyxcp_checksum.check(ecu.read(0xFC0000, 0x100), "XCP_" + kind.name)


def test_build_checksum_limits():
    ecu = make_ecu(params=XcpParameters(checksum_type=ChecksumType.ADD_44, max_checksum_block=0x1000))
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.set_mta(0xFC0000)
    assert probe.err(Cmd.BUILD_CHECKSUM, 0, 0, 0, struct.pack("<I", 6)) == Err.OUT_OF_RANGE  # not whole dwords
    assert probe.send(Cmd.BUILD_CHECKSUM, 0, 0, 0, struct.pack("<I", 0x2000)) == [
        bytes([0xFE, Err.OUT_OF_RANGE, 0, 0]) + struct.pack("<I", 0x1000)
    ]


def test_synch_and_unknown_commands(xcp):
    assert xcp.err(Cmd.SYNCH) == Err.CMD_SYNCH
    assert xcp.err(Cmd.SET_REQUEST, 0, 0, 0) == Err.CMD_UNKNOWN
    assert xcp.err(0xC0) == Err.CMD_UNKNOWN


def test_disconnect_ends_the_session(xcp):
    assert xcp.ok(Cmd.DISCONNECT) == b""
    xcp.silent(Cmd.GET_STATUS)


def test_comm_mode_info(xcp):
    _, optional, _, max_bs, min_st, queue, _ = xcp.ok(Cmd.GET_COMM_MODE_INFO)
    assert optional == 0x01 and (1 + max_bs) * 6 >= 255 and min_st == 0 and queue == 0
