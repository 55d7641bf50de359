"""Programming: flash semantics, block mode, sectors, reset into boot or application, power loss."""

import struct

import pytest
from mini_ecu import EPK, XcpProbe, make_ecu

from workbench.sim.ecu import EcuState
from workbench.sim.memory_map import HDS9
from workbench.sim.xcp.parameters import PgmParameters, XcpParameters
from workbench.xcp_protocol import Cmd, Err, Resource

CALIB = HDS9.region("CALIB")
SHARED = HDS9.region("SHARED")


@pytest.fixture
def pgm(xcp):
    xcp.unlock(Resource.PGM)
    return xcp


def start(probe):
    response = probe.ok(Cmd.PROGRAM_START)
    assert response == bytes([0, 0x01, 8, 42, 0, 0])  # master block mode, MAX_BS 42, MIN_ST 0
    return response


def clear(probe, address, size):
    probe.set_mta(address)
    return probe.send(Cmd.PROGRAM_CLEAR, 0, 0, 0, struct.pack("<I", size))


def program(probe, address, data):
    """PROGRAM in master block mode (255-byte blocks), as a flash tool sends it."""
    probe.set_mta(address)
    for offset in range(0, len(data), 255):
        block = data[offset : offset + 255]
        first, rest = block[:6], block[6:]
        answers = probe.send(Cmd.PROGRAM, len(block), first)
        while rest:
            answers = probe.send(Cmd.PROGRAM_NEXT, len(rest), rest[:6])
            rest = rest[6:]
        assert answers == [b"\xff"], answers


def test_pgm_processor_and_sector_info(pgm):
    assert pgm.ok(Cmd.GET_PGM_PROCESSOR_INFO) == bytes([0x43, 3])  # absolute + functional, non-sequential
    infos = []
    for number in range(3):
        clear_seq, program_seq, _, address = struct.unpack("<BBBI", pgm.ok(Cmd.GET_SECTOR_INFO, 0, number))
        length = struct.unpack("<BBBI", pgm.ok(Cmd.GET_SECTOR_INFO, 1, number))[3]
        name = pgm.upload(pgm.ok(Cmd.GET_SECTOR_INFO, 2, number)[0])
        infos.append((name, address, length, clear_seq, program_seq))
    assert infos == [
        (b"APPLICATIVE", 0x840000, 0x780000, 1, 0),
        (b"CALIB", 0xFC0000, 0x20000, 2, 1),
        (b"SHARED", 0xFE0000, 0x4000, 0, 2),  # the key: cleared first, programmed last
    ]
    assert pgm.err(Cmd.GET_SECTOR_INFO, 0, 3) == Err.OUT_OF_RANGE


def test_full_calib_program_in_block_mode_then_reset(pgm, ecu):
    start(pgm)
    assert ecu.state is EcuState.HALTED
    assert clear(pgm, CALIB.start, CALIB.size) == [b"\xff"]
    assert ecu.read(CALIB.start, 16) == b"\xff" * 16
    image = bytes((i * 7) & 0xFF for i in range(CALIB.size))
    program(pgm, CALIB.start, image)
    assert pgm.ok(Cmd.PROGRAM, 0) == b""  # end of segment
    assert ecu.read(CALIB.start, CALIB.size) == image
    assert pgm.ok(Cmd.PROGRAM_RESET) == b""
    assert ecu.state is EcuState.APPLICATION
    assert ecu.read(0x40000000, 64) == image[:64]  # CAL ROM copied to CAL RAM at start-up
    pgm.silent(Cmd.GET_STATUS)  # the reset ended the session


def test_flash_rules(pgm, ecu):
    assert pgm.err(Cmd.PROGRAM_CLEAR, 0, 0, 0, struct.pack("<I", 0x4000)) == Err.SEQUENCE  # before PROGRAM_START
    start(pgm)
    assert clear(pgm, CALIB.start, 0x4000) == [bytes([0xFE, Err.OUT_OF_RANGE])]  # not the whole sector
    assert clear(pgm, 0x40000000, 0x4000) == [bytes([0xFE, Err.OUT_OF_RANGE])]  # RAM is not flash
    assert clear(pgm, 0x800000, 0x40000) == [bytes([0xFE, Err.WRITE_PROTECTED])]  # BOOT
    assert pgm.err(Cmd.PROGRAM_CLEAR, 1, 0, 0, struct.pack("<I", 0x08)) == Err.OUT_OF_RANGE  # no such area
    assert pgm.err(Cmd.PROGRAM_CLEAR, 2, 0, 0, struct.pack("<I", 0x01)) == Err.MODE_NOT_VALID
    pgm.set_mta(0x800000)
    assert pgm.err(Cmd.PROGRAM, 4, b"boot") == Err.WRITE_PROTECTED
    pgm.set_mta(CALIB.start)
    assert pgm.err(Cmd.PROGRAM, 4, b"abcd") == Err.ACCESS_DENIED  # not erased
    pgm.set_mta(0x40000000)
    assert pgm.err(Cmd.PROGRAM, 4, b"abcd") == Err.OUT_OF_RANGE  # not flash
    pgm.set_mta(CALIB.end - 4)
    assert pgm.err(Cmd.PROGRAM, 8, b"abcdef") == Err.OUT_OF_RANGE  # block runs out of the region
    assert pgm.ok(Cmd.PROGRAM_CLEAR, 1, 0, 0, struct.pack("<I", 0x01)) == b""  # functional: calibration area
    assert ecu.read(CALIB.start, 4) == b"\xff" * 4
    pgm.set_mta(CALIB.end - 7)
    assert pgm.ok(Cmd.PROGRAM_MAX, b"1234567") == b""
    assert ecu.read(CALIB.end - 7, 7) == b"1234567"


def test_program_next_out_of_sequence(pgm):
    start(pgm)
    clear(pgm, CALIB.start, CALIB.size)
    assert pgm.err(Cmd.PROGRAM_NEXT, 6, bytes(6)) == Err.SEQUENCE
    pgm.set_mta(CALIB.start)
    pgm.silent(Cmd.PROGRAM, 12, bytes(6))
    assert pgm.send(Cmd.PROGRAM_NEXT, 5, bytes(5)) == [bytes([0xFE, Err.SEQUENCE, 6])]


def test_calibration_and_daq_wait_while_programming(pgm):
    pgm.unlock_all()
    start(pgm)
    assert pgm.err(Cmd.FREE_DAQ) == Err.PGM_ACTIVE
    assert pgm.err(Cmd.GET_CAL_PAGE, 1, 0) == Err.PGM_ACTIVE


def test_clearing_the_key_leaves_the_ecu_in_boot_and_reflashable(pgm, ecu):
    start(pgm)
    clear(pgm, SHARED.start, SHARED.size)
    pgm.ok(Cmd.PROGRAM_RESET)
    assert ecu.state is EcuState.BOOT
    probe = XcpProbe(ecu)
    assert probe.connect()[0] == Resource.PGM  # boot offers programming only
    assert probe.err(Cmd.FREE_DAQ) == Err.CMD_UNKNOWN
    assert probe.err(Cmd.GET_CAL_PAGE, 1, 0) == Err.CMD_UNKNOWN
    length = struct.unpack("<BBBI", probe.ok(Cmd.GET_ID, 5))[3]
    assert probe.upload(length) == EPK  # the EPK in flash stays readable
    probe.unlock(Resource.PGM)
    start(probe)
    program(probe, HDS9.app_key_address, HDS9.app_key)
    probe.ok(Cmd.PROGRAM_RESET)
    assert ecu.state is EcuState.APPLICATION


def test_boot_without_key_never_runs_the_application():
    ecu = make_ecu(key=False)
    assert ecu.power_on() is EcuState.BOOT
    ecu.advance(1.0)
    assert ecu.application is None
    assert ecu.read(0x40020000, 4) == bytes(4)


def test_power_loss_at_the_nth_program_frame_keeps_what_was_written():
    ecu = make_ecu()
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.unlock(Resource.PGM)
    start(probe)
    clear(probe, SHARED.start, SHARED.size)  # the flash tool clears the key first
    clear(probe, CALIB.start, CALIB.size)
    ecu.faults.power_loss_at_program(3)
    probe.set_mta(CALIB.start)
    probe.silent(Cmd.PROGRAM, 18, b"AAAAAA")
    probe.silent(Cmd.PROGRAM_NEXT, 12, b"BBBBBB")
    probe.silent(Cmd.PROGRAM_NEXT, 6, b"CCCCCC")  # the power fails here
    assert ecu.faults.fired == ["power loss at PROGRAM frame 3"]
    assert ecu.state is EcuState.OFF
    probe.silent(Cmd.CONNECT, 0)
    assert ecu.power_on() is EcuState.BOOT  # key cleared: the ECU stays reachable in boot
    assert ecu.read(CALIB.start, 18) == b"AAAAAABBBBBB" + b"\xff" * 6
    assert ecu.read(0x40000000, 4) == bytes(4)  # RAM lost, no CAL ROM copy in boot
    probe.connect()


def test_a_page_at_a_time_driver_writes_a_page_when_full_or_at_the_end_of_a_segment():
    """PgmParameters.page_size: a page's data wait in RAM (UPLOAD reads the flash) until the page is full or a PROGRAM
    with size 0 ends the memory segment; a reset loses what waits."""
    ecu = make_ecu(params=XcpParameters(pgm=PgmParameters(page_size=256)))
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.unlock(Resource.PGM)
    start(probe)
    clear(probe, CALIB.start, CALIB.size)
    data = bytes(range(256)) + b"\x5a" * 44
    program(probe, CALIB.start, data)
    assert ecu.read(CALIB.start, 300) == data[:256] + b"\xff" * 44  # the first page is full, the second waits
    assert probe.ok(Cmd.PROGRAM, 0) == b""
    assert ecu.read(CALIB.start, 300) == data
    program(probe, CALIB.start + 300, b"\xa5" * 20)
    probe.ok(Cmd.PROGRAM_RESET)
    assert ecu.read(CALIB.start + 300, 20) == b"\xff" * 20  # never ended: lost with the reset
