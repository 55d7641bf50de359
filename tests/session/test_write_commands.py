"""What a write costs on the bus, counted command by command on the virtual CAN bus: a value is one DOWNLOAD and
one read-back, a map cell only its own bytes, a refused write nothing at all; pages and read-only sessions."""

from __future__ import annotations

import struct
from dataclasses import replace

import numpy as np
import pytest
from session_helpers import FAST, WRITE, demo_a2l_text, edited_a2l, refused_on_the_reference_page
from xcp_commands import CommandLog

from workbench import EpkMismatchError, PageError, Session
from workbench.errors import ConversionError, InputError, LimitsError, UnknownSymbolError, XcpCommandError
from workbench.xcp_protocol import Err

FIRST_WRITE = ["GET_SEED", "UNLOCK", "GET_CAL_PAGE"]  # once a session: CAL/PAG unlocked, the page XCP is on asked


@pytest.fixture
def log(sim, channel):
    with CommandLog(channel) as commands:
        yield commands


def _mta(frame) -> int:
    return struct.unpack_from("<I", bytes(frame.data), 4)[0]


def _downloaded(log) -> tuple[int, bytes]:
    """(address, bytes) of the one SET_MTA + DOWNLOAD of the last take."""
    mta, download = (f for f in log.frames if f.data[0] in (0xF6, 0xF0))
    return _mta(mta), bytes(download.data[2:2 + download.data[1]])


def test_a_value_is_one_download_and_one_read_back(ecu, sim, log):
    log.take()
    written = ecu.write("xsSWITCH_TANK_THR", 25.5)
    assert log.take() == FIRST_WRITE + WRITE
    address = ecu.model.characteristic("xsSWITCH_TANK_THR").address
    assert _downloaded(log) == (address, struct.pack("<f", 25.5))
    assert written.value == 25.5 and struct.unpack("<f", sim.ecu.read(address, 4))[0] == 25.5
    assert ecu.write("xsSWITCH_TANK_THR", 30.0).value == 30.0
    assert log.take() == WRITE  # unlocked, and the page is known now
    assert ecu.write("cfENABLEFLCU_VALUE", "Enabled").value == "Enabled"
    assert log.take() == WRITE


def test_the_value_returned_is_the_one_read_back(ecu, log):
    written = ecu.write("xsSWITCH_TANK_THR", 20.1)  # a FLOAT32_IEEE: the ECU holds the nearest float32
    assert log.take()[-1] == "SHORT_UPLOAD"
    assert written.value == float(np.float32(20.1)) != 20.1
    assert ecu.write_cells("xvPRV_DC_FF", {(0, 1): 33.3}) == {(0, 1): float(np.float32(33.3))}


def test_a_map_cell_after_reading_the_map_sends_only_that_cell(ecu, sim, log):
    ff = ecu.read_value("xvPRV_DC_FF")
    ecu.write("xsSWITCH_TANK_THR", 21.0)  # unlocked, page known
    log.take()
    new = ff.value.copy()
    new[2, 3] = 42.0
    written = ecu.write("xvPRV_DC_FF", new)
    assert log.take() == WRITE
    cell = ecu.model.characteristic("xvPRV_DC_FF").address + 4 * (3 * 6 + 2)  # [manifold][target] floats
    assert _downloaded(log) == (cell, struct.pack("<f", 42.0))
    assert np.array_equal(written.value, new) and written.axes == ff.axes  # decoded from what is known
    assert struct.unpack("<f", sim.ecu.read(cell, 4))[0] == 42.0


def test_one_axis_point_sends_that_point_only(ecu, log):
    points = ecu.read_value("xaPRV_FF_TARGET").value.copy()
    ecu.write("xsSWITCH_TANK_THR", 21.0)
    log.take()
    points[2] = 21.0
    assert ecu.write("xaPRV_FF_TARGET", points).value.tolist() == points.tolist()
    assert log.take() == WRITE
    assert ecu.read_value("xvPRV_DC_FF").axes[0].values.tolist() == points.tolist()  # the map's axis


def test_one_axis_point_by_index_is_checked_among_the_others_and_sent_alone(ecu, sim, log):
    points = ecu.read_value("xaPRV_FF_TARGET").value  # known to the session: nothing is read again
    ecu.write("xsSWITCH_TANK_THR", 21.0)
    log.take()
    assert ecu.write_cells("xaPRV_FF_TARGET", {2: 21.0}) == {(2,): 21.0}
    assert log.take() == WRITE
    address = ecu.model.axis_pts("xaPRV_FF_TARGET").address
    assert _downloaded(log) == (address + 4 * 2, struct.pack("<f", 21.0))
    with pytest.raises(LimitsError, match=r"xaPRV_FF_TARGET: points 2 and 3 \(35, 30\) break MON_INCREASE"):
        ecu.write_cells("xaPRV_FF_TARGET", {2: 35.0})  # its order against the points the ECU holds
    with pytest.raises(LimitsError, match=r"xaPRV_FF_TARGET\[2\]: 60.00 is above the upper limit 50.00 bar"):
        ecu.write_cells("xaPRV_FF_TARGET", {2: 60.0})
    with pytest.raises(LimitsError, match=r"has 6 points at most: index 6 is beyond \(0-5\)"):
        ecu.write_cells("xaPRV_FF_TARGET", {6: 60.0})
    assert log.take() == [] and ecu.read("xaPRV_FF_TARGET")[2] == 21.0 != points[2]


def test_a_map_cell_by_index_needs_nothing_read(ecu, sim, log):
    log.take()
    assert ecu.write_cells("xvPRV_DC_FF", {(2, 3): 42.0}) == {(2, 3): 42.0}
    assert log.take() == FIRST_WRITE + WRITE
    cell = ecu.model.characteristic("xvPRV_DC_FF").address + 4 * (3 * 6 + 2)
    assert _downloaded(log) == (cell, struct.pack("<f", 42.0))
    assert ecu.write_cells("zvRailPConv", {0: 1.0, 1: 9.0}) == {(0,): 1.0, (1,): 9.0}  # indices as tuples
    assert log.take() == ["SET_MTA", "DOWNLOAD", "DOWNLOAD_NEXT", "SET_MTA", "UPLOAD"]  # neighbours: one 8-byte block
    assert ecu.read("zvRailPConv")[:2].tolist() == [1.0, 9.0]


def test_a_map_not_read_before_is_read_once(ecu, log):
    ecu.write("xsSWITCH_TANK_THR", 21.0)
    log.take()
    new = ecu.read("xvPRV_DC_FF")  # read(): values only, nothing the write may rely on
    log.take()
    new[1, 1] = 7.0
    assert ecu.write("xvPRV_DC_FF", new).value[1, 1] == 7.0
    commands = log.take()
    assert commands[-2:] == ["DOWNLOAD", "SHORT_UPLOAD"] and commands.count("DOWNLOAD") == 1
    reads = commands[:commands.index("DOWNLOAD") - 1]
    assert "SHORT_UPLOAD" not in reads and reads.count("UPLOAD") >= 1 and set(reads) == {"SET_MTA", "UPLOAD"}


def test_what_the_session_knows_is_forgotten_when_the_memory_changes(ecu, sim):
    ff = ecu.read_value("xvPRV_DC_FF")
    ecu.write_cells("xvPRV_DC_FF", {(2, 3): 42.0})
    ecu.copy_reference_to_working()  # the ECU holds the flashed map again; the session knew 42 at [2, 3]
    new = ff.value.copy()
    new[2, 3], new[1, 1] = 42.0, 7.0
    written = ecu.write("xvPRV_DC_FF", new)
    assert np.array_equal(written.value, new) and np.array_equal(ecu.read("xvPRV_DC_FF"), new)


@pytest.mark.parametrize("name, value, error, message", [
    ("xsSWITCH_TANK_THR", 900.0, LimitsError, "xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar"),
    ("xsSWITCH_TANK_THR", "abc", LimitsError,
     r"xsSWITCH_TANK_THR: 'abc' is not a number \(a value from 0.00 to 800.00 bar\)"),
    ("cfENABLEFLCU_VALUE", "Foo", LimitsError, r"cfENABLEFLCU_VALUE: 'Foo' is not one of its values \(Disabled, "
                                                r"Enabled\)"),
    ("xvPRV_DC_FF", np.zeros((5, 6)), LimitsError, r"xvPRV_DC_FF has shape \(6, 5\), the value \(5, 6\)"),
    ("xaPRV_FF_TARGET", [0, 10, 5, 30, 40, 50], LimitsError, "break MON_INCREASE"),
    ("zsRailPressure", 3.0, InputError, "zsRailPressure is a MEASUREMENT"),
    ("xsSWITCH_TANK_TRH", 3.0, UnknownSymbolError, "did you mean 'xsSWITCH_TANK_THR'"),
])
def test_a_refused_write_sends_nothing(ecu, log, name, value, error, message):
    log.take()
    with pytest.raises(error, match=message):
        ecu.write(name, value)
    assert log.take() == []


@pytest.mark.parametrize("cells, message", [
    ({(2, 3): 200.0}, r"xvPRV_DC_FF\[2, 3\]: 200.00 is above the upper limit 100.00 %"),
    ({(6, 0): 1.0}, r"xvPRV_DC_FF has 6 x 5 values: x index 6 is beyond \(0-5\)"),
    ({(1,): 1.0}, r"xvPRV_DC_FF has 6 x 5 values: give 2 indices \[x, y\], not 1"),
    ({(0, 0): "x"}, r"xvPRV_DC_FF\[0, 0\]: 'x' is not a number"),
])
def test_a_refused_cell_sends_nothing(ecu, log, cells, message):
    log.take()
    with pytest.raises(LimitsError, match=message):
        ecu.write_cells("xvPRV_DC_FF", cells)
    assert log.take() == []


def test_a_read_only_calibration_and_memory_outside_the_writable_are_refused_before_sending(tmp_path, sim, channel):
    a2l = edited_a2l(tmp_path, "DATA RAM INTERN 0x40000000 0x20000", "DATA RAM INTERN 0x40000000 0x10")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu, CommandLog(channel) as log:
        with pytest.raises(InputError, match="xsSWITCH_TANK_THR: its bytes at 0x.* lie outside the A2L's writable"):
            ecu.write("xsSWITCH_TANK_THR", 21.0)
        with pytest.raises(InputError, match=r"xvPRV_DC_FF: the value \[0, 0\] at .* outside the A2L's writable"):
            ecu.write_cells("xvPRV_DC_FF", {(0, 0): 1.0})
        assert log.take() == []


def test_what_the_data_type_cannot_hold_is_refused_before_sending(tmp_path, sim, channel):
    text = demo_a2l_text()
    start = text.index("*/ xsSWITCH_TANK_THR\n")
    limit = text.index("/* Upper Limit            */ 800", start)
    a2l = tmp_path / "wide.a2l"  # an upper limit beyond what a FLOAT32_IEEE holds
    a2l.write_text(text[:limit] + text[limit:].replace("*/ 800", "*/ 1e40", 1), encoding="utf-8")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu, CommandLog(channel) as log:
        with pytest.raises(ConversionError, match="xsSWITCH_TANK_THR: 1e\\+39 does not fit FLOAT32_IEEE"):
            ecu.write("xsSWITCH_TANK_THR", 1e39)
        assert log.take() == []


def test_the_reference_page_is_refused_before_the_download_saying_how_to_switch(ecu, log):
    refused_on_the_reference_page(ecu, log, 0)


def test_a_page_switched_by_someone_else_is_said_when_the_ecu_refuses(ecu, sim):
    ecu.write("xsSWITCH_TANK_THR", 21.0)  # the session knows: XCP is on the working page
    sim.ecu.pages.xcp_pages[0] = 1  # another master switched it
    with pytest.raises(PageError, match="the reference page of segment 0 is active") as refused:
        ecu.write("xsSWITCH_TANK_THR", 22.0)
    assert "ERR_WRITE_PROTECTED" in str(refused.value.__cause__)
    sim.ecu.pages.xcp_pages[0] = 0


def test_a_read_only_session_refuses_page_switches_before_sending(tmp_path, sim, channel):
    a2l = edited_a2l(tmp_path, 'EPK "10300020250301"', 'EPK "99999920991231"')
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu, CommandLog(channel) as log:
        assert ecu.read_only
        for refused in (lambda: ecu.set_page("reference"), ecu.copy_reference_to_working,
                        lambda: ecu.write("xsSWITCH_TANK_THR", 21.0),
                        lambda: ecu.write_cells("xvPRV_DC_FF", {(0, 0): 1.0})):
            with pytest.raises(EpkMismatchError, match=r"read-only \(no writes, no page switches\)"):
                refused()
        assert log.take() == []
        assert ecu.read("xsSWITCH_TANK_THR", page="reference") == 20.0  # reading another page is fine
    assert sim.ecu.pages.xcp_pages == sim.ecu.pages.ecu_pages == [0]


class _MemoryMaster:
    """A master on plain bytes (no bus): what the session reads and writes, for layouts the demo ECU has not."""

    def __init__(self, content: dict[int, bytes]):
        self.memory = bytearray(0x400)
        for address, data in content.items():
            self.memory[address:address + len(data)] = data
        self.memory_changes, self.xcp_pages, self.connect_info, self.log = 0, {}, None, []

    def read(self, address: int, size: int, extension: int = 0) -> bytes:
        self.log.append(("read", address, size))
        return bytes(self.memory[address:address + size])

    def write(self, address: int, data: bytes, extension: int = 0) -> None:
        self.memory_changes += 1
        self.log.append(("write", address, data))
        self.memory[address:address + len(data)] = data

    def get_pag_processor_info(self):
        raise XcpCommandError("GET_PAG_PROCESSOR_INFO", Err.CMD_UNKNOWN)  # plain bytes have no pages


def test_a_curve_whose_count_lies_in_memory_takes_more_points_and_is_decoded_from_what_was_read_back():
    from types import SimpleNamespace

    from workbench.a2l import load_a2l_string
    from workbench.calib.values import Axis, CalValue

    doc = load_a2l_string(
        'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n/begin MOD_COMMON "" BYTE_ORDER MSB_FIRST '
        '/end MOD_COMMON\n/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 SWORD INDEX_INCR DIRECT '
        'FNC_VALUES 3 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n/begin CHARACTERISTIC k "" CURVE 0x100 K 0 '
        'NO_COMPU_METHOD 0 1000\n  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 5 -100 100 '
        '/end AXIS_DESCR\n/end CHARACTERISTIC\n/end MODULE\n/end PROJECT\n', "dynamic.a2l")
    master = _MemoryMaster({0x100: bytes.fromhex("03 00 FFF6 0000 000A 0064 00C8 012C")})
    ecu = Session(doc, SimpleNamespace(segments=()), None, master)
    longer = CalValue("k", "CURVE", np.array([1, 2, 3, 4]), (Axis(np.array([-10, 0, 10, 20])),))
    written = ecu.write("k", longer)
    assert written.same_values(longer)
    assert bytes(master.memory[0x100:0x112]) == bytes.fromhex("04 00 FFF6 0000 000A 0014 0001 0002 0003 0004")
    reads = [entry for entry in master.log if entry[0] == "read"]
    assert reads == [("read", 0x100, 1), ("read", 0x100, 14), ("read", 0x100, 18)]  # count, object, read-back
    master.log.clear()
    again = CalValue("k", "CURVE", np.array([1, 2, 7, 4]), written.axes)
    assert ecu.write("k", again).same_values(again)
    assert master.log == [("write", 0x10E, bytes.fromhex("0007")), ("read", 0x10E, 2)]  # the one value, known


def _wrong_key(seed: bytes, resource: int) -> bytes:
    return bytes(len(seed))


def test_a_key_the_ecu_refuses_is_said_where_it_is_refused(sim, channel):
    """The wrong key's ERR_ACCESS_LOCKED (after which the slave disconnects) is the error, not the next command's
    timeout: the page check that met it while unlocking CAL/PAG must not swallow it."""
    with (Session.open(interface="virtual", channel=channel, timeouts=FAST, key_function=_wrong_key) as session,
          pytest.raises(XcpCommandError) as refused):
        session.write("xsSWITCH_TANK_THR", 21.0)
    assert (refused.value.command, refused.value.code) == ("UNLOCK", Err.ACCESS_LOCKED)
    assert "_wrong_key" in str(refused.value) and "CAL/PAG" in str(refused.value)


def test_several_values_side_by_side_are_one_download_and_one_read_back(ecu, sim, log):
    """A sweep's step of three gains (user trial 10: three writes, three SET_MTA, DOWNLOAD and read-back each)."""
    ecu.write("xsSWITCH_TANK_THR", 21.0)  # unlocked, page known
    log.take()
    written = ecu.write_many({"xsPRV_KP": 5.5, "xsPRV_KI": 2.5, "xsPRV_KD": 0.03})
    assert log.take() == ["SET_MTA", "DOWNLOAD", "DOWNLOAD_NEXT", "SET_MTA", "UPLOAD"]
    assert {name: value.value for name, value in written.items()} == {
        "xsPRV_KP": 5.5, "xsPRV_KI": 2.5, "xsPRV_KD": float(np.float32(0.03))}
    assert ecu.read_many(["xsPRV_KP", "xsPRV_KI", "xsPRV_KD"])["xsPRV_KI"] == 2.5
    log.take()
    with pytest.raises(LimitsError, match="xsPRV_KD: 500.0000 is above"):
        ecu.write_many({"xsPRV_KP": 6.0, "xsPRV_KD": 500.0})  # every value checked before anything is sent
    assert log.take() == []
    map_value = ecu.read_value("xvPRV_DC_FF")
    axis = ecu.read_value("xaPRV_FF_TARGET").value.copy()
    axis[1] = 12.0
    points = map_value.axes[0].values.copy()
    points[1] = 14.0
    map_value = replace(map_value, axes=(replace(map_value.axes[0], values=points), map_value.axes[1]))
    log.take()
    with pytest.raises(InputError, match="give other bytes for"):  # the map's shared axis given twice, two ways
        ecu.write_many({"xaPRV_FF_TARGET": axis, "xvPRV_DC_FF": map_value})
    assert "DOWNLOAD" not in log.take()
