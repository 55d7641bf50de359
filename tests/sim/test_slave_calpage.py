"""Calibration pages: working (CAL RAM) and reference (CAL ROM) for the ECU and for XCP."""

import struct

from mini_ecu import CAL_GAIN, OUTPUT

from workbench.xcp_protocol import Cmd, Err, Resource

ECU, XCP, ALL = 0x01, 0x02, 0x80


def _unlocked(xcp):
    xcp.unlock(Resource.CAL_PAG)
    return xcp


def test_processor_and_segment_info(xcp):
    _unlocked(xcp)
    assert xcp.ok(Cmd.GET_PAG_PROCESSOR_INFO) == bytes([1, 0])
    assert struct.unpack("<3xI", xcp.ok(Cmd.GET_SEGMENT_INFO, 0, 0, 0, 0))[0] == 0x40000000
    assert struct.unpack("<3xI", xcp.ok(Cmd.GET_SEGMENT_INFO, 0, 0, 1, 0))[0] == 0x20000
    assert xcp.ok(Cmd.GET_SEGMENT_INFO, 1, 0, 0, 0) == bytes([2, 0, 1, 0, 0])  # 2 pages, 1 mapping
    mapping = [struct.unpack("<3xI", xcp.ok(Cmd.GET_SEGMENT_INFO, 2, 0, i, 0))[0] for i in range(3)]
    assert mapping == [0x40000000, 0xFC0000, 0x20000]
    assert xcp.err(Cmd.GET_SEGMENT_INFO, 0, 1, 0, 0) == Err.OUT_OF_RANGE
    assert xcp.err(Cmd.GET_SEGMENT_INFO, 2, 0, 0, 1) == Err.OUT_OF_RANGE


def test_xcp_reads_the_reference_page_and_cannot_write_it(xcp):
    _unlocked(xcp)
    xcp.set_mta(CAL_GAIN)
    xcp.ok(Cmd.DOWNLOAD, 4, struct.pack("<f", 9.0))
    assert xcp.ok(Cmd.SET_CAL_PAGE, XCP, 0, 1) == b""
    assert xcp.ok(Cmd.GET_CAL_PAGE, XCP, 0) == bytes([0, 0, 1])
    assert xcp.ok(Cmd.GET_CAL_PAGE, ECU, 0) == bytes([0, 0, 0])
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)  # ROM value
    xcp.set_mta(CAL_GAIN)
    assert xcp.err(Cmd.DOWNLOAD, 4, bytes(4)) == Err.WRITE_PROTECTED
    xcp.ok(Cmd.SET_CAL_PAGE, XCP, 0, 0)
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 9.0)


def test_the_application_follows_the_ecu_page(xcp, ecu):
    _unlocked(xcp)
    xcp.set_mta(CAL_GAIN)
    xcp.ok(Cmd.DOWNLOAD, 4, struct.pack("<f", 0.0))
    ecu.advance(0.05)
    assert struct.unpack("<f", ecu.read(OUTPUT, 4))[0] == 5.0  # gain 0 from RAM
    xcp.ok(Cmd.SET_CAL_PAGE, ECU | ALL, 0xFF, 1)
    ecu.advance(0.05)
    count = struct.unpack("<I", ecu.read(0x40020000, 4))[0]
    assert struct.unpack("<f", ecu.read(OUTPUT, 4))[0] == 2.0 * count + 5.0  # gain 2 from ROM


def test_copy_reference_to_working_page(xcp):
    _unlocked(xcp)
    xcp.set_mta(CAL_GAIN)
    xcp.ok(Cmd.DOWNLOAD, 4, struct.pack("<f", 7.0))
    assert xcp.err(Cmd.COPY_CAL_PAGE, 0, 0, 0, 1) == Err.WRITE_PROTECTED
    assert xcp.ok(Cmd.COPY_CAL_PAGE, 0, 1, 0, 0) == b""
    assert xcp.short_upload(CAL_GAIN, 4) == struct.pack("<f", 2.0)


def test_invalid_pages_segments_and_modes(xcp):
    _unlocked(xcp)
    assert xcp.err(Cmd.SET_CAL_PAGE, XCP, 0, 2) == Err.PAGE_NOT_VALID
    assert xcp.err(Cmd.SET_CAL_PAGE, XCP, 1, 0) == Err.SEGMENT_NOT_VALID
    assert xcp.err(Cmd.SET_CAL_PAGE, 0x04, 0, 0) == Err.MODE_NOT_VALID
    assert xcp.err(Cmd.GET_CAL_PAGE, 0x03, 0) == Err.MODE_NOT_VALID
    assert xcp.err(Cmd.COPY_CAL_PAGE, 1, 0, 0, 0) == Err.SEGMENT_NOT_VALID
    assert xcp.err(Cmd.COPY_CAL_PAGE, 0, 3, 0, 0) == Err.PAGE_NOT_VALID
