"""XcpMaster against the simulated ECU over a python-can bus: commands, memory, seed & key, errors, faults."""

from __future__ import annotations

import struct
import subprocess
import sys
import time
from pathlib import Path

import pytest
from xcp_helpers import FAST, can_settings, serve

import workbench
from workbench.errors import ConnectionLostError, EcuSilentError, WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.image import ChecksumType, checksum
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.profiles import SlaveProfile
from workbench.xcp.link import Link
from workbench.sim.seedkey import compute_key
from workbench.xcp.master import Timeouts, XcpMaster
from workbench.xcp_protocol import Cmd, Err, IdType, Resource

CAL_RAM = 0x40000000
THRESHOLD = "xsSWITCH_TANK_THR"



@pytest.fixture
def threshold(rig) -> int:
    from workbench.elf import ElfSymbols

    return ElfSymbols(rig.demo.files.elf).symbol(THRESHOLD).address


def test_connect_reports_what_the_slave_offers(rig):
    info = rig.master.connect_info
    assert (info.max_cto, info.max_dto, info.byte_order) == (8, 8, "<")
    assert info.resources == Resource.CAL_PAG | Resource.DAQ | Resource.PGM
    assert rig.master.comm_mode.master_block_mode and rig.master.comm_mode.max_bs == 42
    assert rig.master.protected == Resource.CAL_PAG | Resource.DAQ | Resource.PGM  # locked until needed


def test_epk_by_get_id_and_by_address(rig):
    epk = rig.demo.a2l.epk()
    assert rig.master.get_id(IdType.EPK).decode() == epk
    assert rig.master.read(rig.demo.a2l.addr_epk(), len(epk)).decode() == epk


def test_short_and_block_reads_agree_with_the_ecu_memory(rig, threshold):
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0
    whole = rig.master.read(CAL_RAM, 0x1C4)  # slave block mode UPLOAD, 255 bytes a command
    assert whole == rig.demo.ecu.read(CAL_RAM, 0x1C4)


def test_a_write_unlocks_cal_pag_and_uses_master_block_mode(rig, threshold):
    data = bytes(range(250)) + bytes(range(50))
    start = threshold - (threshold - CAL_RAM) % 4  # somewhere inside .cal_ram, restored below
    before = rig.master.read(CAL_RAM + 0x10, len(data))
    rig.master.write(CAL_RAM + 0x10, data)
    assert not rig.master.protected & Resource.CAL_PAG
    assert rig.master.read(CAL_RAM + 0x10, len(data)) == data
    rig.master.write(CAL_RAM + 0x10, before)
    assert start >= CAL_RAM


def test_build_checksum_matches_the_local_crc(rig):
    kind, value = rig.master.build_checksum(CAL_RAM, 0x200)
    assert kind == ChecksumType.CRC_32
    assert value == checksum(rig.demo.ecu.read(CAL_RAM, 0x200), ChecksumType.CRC_32)


def test_a_negative_response_names_the_command_and_the_error(rig):
    with pytest.raises(XcpCommandError) as caught:
        rig.master.read(0x10, 4)
    assert str(caught.value) == "XCP SHORT_UPLOAD failed: ERR_OUT_OF_RANGE (0x22)"
    with pytest.raises(XcpCommandError, match="DOWNLOAD failed: ERR_WRITE_PROTECTED"):
        rig.master.write(0xFC0000, b"\x00")  # flash is not writable by DOWNLOAD


def test_a_wrong_key_is_refused_by_the_ecu(rig):
    rig.master.key_function = lambda seed, resource: b"\x00\x00\x00\x00"
    with pytest.raises(XcpCommandError, match="UNLOCK failed: ERR_ACCESS_LOCKED"):
        rig.master.write(CAL_RAM + 0x10, b"\x01")


def test_no_key_function_says_what_to_give(rig):
    rig.master.key_function = None
    with pytest.raises(WorkbenchError, match="protects CAL/PAG with seed & key.*module:function"):
        rig.master.write(CAL_RAM + 0x10, b"\x01")


def test_a_failing_key_function_is_one_line(rig):
    def broken(seed, resource):
        raise ValueError("no licence")

    rig.master.key_function = broken
    with pytest.raises(WorkbenchError, match="seed & key function .*failed for DAQ: ValueError: no licence"):
        rig.master.free_daq()


def test_a_lost_response_is_recovered_by_synch_and_repeat(rig, threshold):
    rig.demo.ecu.faults.drop_frame(1, "tx")
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0
    assert [f.split(" frame")[0] for f in rig.demo.ecu.faults.fired] == ["drop tx"]


def test_a_lost_block_frame_is_repeated_from_set_mta(rig):
    rig.demo.ecu.faults.drop_frame(3, "tx")  # a frame in the middle of a slave-block UPLOAD
    assert rig.master.read(CAL_RAM, 100) == rig.demo.ecu.read(CAL_RAM, 100)
    assert rig.demo.ecu.faults.fired


def test_a_master_block_refused_with_err_sequence_is_written_again_from_set_mta(rig):
    """A DOWNLOAD_NEXT frame lost on its way: the slave refuses the next with ERR_SEQUENCE; the error matrix's SET_MTA
    and repeat writes the block (it was an error for people)."""
    before = rig.master.read(CAL_RAM + 0x10, 40)
    data = bytes(range(1, 41))
    try:
        rig.master.get_status()  # the unlock's commands before the block: the fault counts from the write's frames
        rig.master.unlock(Resource.CAL_PAG)
        rig.demo.ecu.faults.drop_frame(3, "rx")  # SET_MTA, DOWNLOAD, DOWNLOAD_NEXT (lost)
        rig.master.write(CAL_RAM + 0x10, data)
        assert rig.demo.ecu.read(CAL_RAM + 0x10, 40) == data
        assert [fired.split(" frame")[0] for fired in rig.demo.ecu.faults.fired] == ["drop rx"]
    finally:
        rig.master.write(CAL_RAM + 0x10, before)


def test_a_master_block_refused_busy_is_written_again_t7_later(rig):
    """ERR_CMD_BUSY for a block's first DOWNLOAD (its DOWNLOAD_NEXT frames then ERR_SEQUENCE): SYNCH, T7, the block
    again from SET_MTA (it was 'DOWNLOAD_NEXT failed: ERR_CMD_BUSY')."""
    before = rig.master.read(CAL_RAM + 0x10, 40)
    data = bytes(range(1, 41))
    try:
        rig.master.unlock(Resource.CAL_PAG)
        rig.demo.ecu.faults.reject_command(1, Err.CMD_BUSY, command=Cmd.DOWNLOAD)
        rig.master.write(CAL_RAM + 0x10, data)
        assert rig.demo.ecu.read(CAL_RAM + 0x10, 40) == data
        assert rig.demo.ecu.faults.fired == [f"reject command 0x{Cmd.DOWNLOAD:02X} with CMD_BUSY"]
    finally:
        rig.master.write(CAL_RAM + 0x10, before)


def test_an_unlock_refused_with_err_sequence_starts_over_with_get_seed(rig, threshold):
    rig.demo.ecu.faults.reject_command(1, Err.SEQUENCE, command=Cmd.UNLOCK)
    rig.master.write(threshold, struct.pack("<f", 20.0))  # CAL/PAG unlocked at the second GET_SEED
    assert rig.demo.ecu.faults.fired == [f"reject command 0x{Cmd.UNLOCK:02X} with SEQUENCE"]


@pytest.mark.parametrize("code", [Err.CMD_BUSY, Err.PGM_ACTIVE, Err.RESOURCE_TEMPORARY_NOT_ACCESSIBLE],
                         ids=["CMD_BUSY", "PGM_ACTIVE", "RESOURCE_TEMPORARY_NOT_ACCESSIBLE"])
def test_busy_is_waited_out(rig, threshold, code):
    """ASAM's error matrix: ERR_CMD_BUSY and ERR_PGM_ACTIVE, wait T7 and repeat; a resource temporarily not
    accessible, say so and repeat (the last two were errors at once)."""
    rig.demo.ecu.faults.reject_command(1, code)
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0
    assert rig.demo.ecu.faults.fired == [f"reject command 0x{Cmd.SHORT_UPLOAD:02X} with {code.name}"]


def test_an_ecu_that_ends_the_session_is_said_lost_at_once_and_connect_starts_over(rig, threshold):
    """EV_SESSION_TERMINATED: the next command says so at once (it waited T1 and SYNCH's T1 for a silent ECU)."""
    rig.simulator.end_session()
    with pytest.raises(ConnectionLostError, match=r"the ECU ended the XCP session \(EV_SESSION_TERMINATED\)"):
        rig.master.read(threshold, 4)
    rig.master.connect()
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0


def test_a_vanished_ecu_is_reported_within_two_timeouts(rig, threshold):
    rig.simulator.power_off()
    started = time.monotonic()
    with pytest.raises(XcpTimeoutError, match="SHORT_UPLOAD: no response within 200 ms"):
        rig.master.read(threshold, 4)
    assert time.monotonic() - started < 10 * FAST.t1  # generous: a hang would be the failure


def test_nothing_answers_connect_on_an_empty_bus():
    with Link(can_settings("xcp-test-nobody")) as link:
        with pytest.raises(XcpTimeoutError, match="CONNECT"):
            XcpMaster(link, timeouts=FAST).connect()


def test_the_link_is_ours_pyxcp_stays_out_of_the_workbench():
    """pyxcp is the independent reference master of the tests and benchmarks, nothing the workbench imports."""
    code = (
        "import sys\n"
        "from workbench.sim.demo_ecu import build_demo_ecu\n"
        "from workbench.sim.server import Simulator\n"
        "from workbench.bus_defaults import BusSpec\n"
        "from workbench.xcp.link import Link, LinkSettings\n"
        "from workbench.xcp_protocol import CanId\n"
        "from workbench.xcp.master import XcpMaster\n"
        "settings = LinkSettings('CAN', BusSpec('virtual', 'h'), CanId(0x7F0), CanId(0x7F1), max_dlc_required=True)\n"
        "with Simulator(build_demo_ecu().ecu, {'interface': 'virtual', 'channel': 'h'}, time_scale=None):\n"
        "    with Link(settings) as link:\n"
        "        XcpMaster(link).connect()\n"
        "assert 'pyxcp' not in sys.modules\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout == "" and result.stderr == ""
    sources = Path(workbench.__file__).parent.rglob("*.py")
    assert [path.name for path in sources if "import pyxcp" in path.read_text() or "from pyxcp" in path.read_text()] == []


def test_an_unknown_interface_is_bad_input():
    from workbench.bus_defaults import BusSpec
    from workbench.errors import InputError
    from workbench.xcp.link import LinkSettings

    with pytest.raises(InputError, match="unknown python-can interface 'nosuchcan'"):
        Link(LinkSettings("CAN", BusSpec("nosuchcan", "x")))


def test_late_answers_do_not_desynchronise_the_commands(rig, threshold):
    """The read's response comes after its timeout (the SYNCH after it takes it as the ECU's sign of life);
    the answer to that SYNCH comes late too, while the repeated read waits: ERR_CMD_SYNCH is dropped, not
    taken for the read's answer, which comes after it."""
    t1 = FAST.t1
    rig.demo.ecu.faults.delay_frame(1, 1.5 * t1, "tx")  # the read's response: at 1.5 t1
    rig.demo.ecu.faults.delay_frame(2, 0.7 * t1, "tx")  # SYNCH (sent at t1) answered at 1.7 t1
    rig.demo.ecu.faults.delay_frame(3, 0.4 * t1, "tx")  # the repeated read (sent at 1.5 t1) answered at 1.9 t1
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0
    assert len(rig.demo.ecu.faults.fired) == 3
    rig.master.set_mta(CAL_RAM)  # the next commands get their own answers
    assert rig.master.read(CAL_RAM, 20) == rig.demo.ecu.read(CAL_RAM, 20)


def test_a_command_after_an_unanswered_synch_is_not_answered_by_the_late_responses(rig, threshold):
    """The read's answer comes after its T1 and after the T1 of the SYNCH sent then (SYNCH's answer waits its turn
    behind it): the ECU is said silent. The next command must not take the read's late answer (5 bytes) for its own:
    "GET_DAQ_PROCESSOR_INFO: the response has 5 bytes, expected 8" (a full test run at load 10-20). A master that found
    the ECU silent synchronises first (SYNCH until its ERR_CMD_SYNCH, the late answers before it dropped)."""
    processor = rig.master.get_daq_processor_info()
    rig.demo.ecu.faults.delay_answer(Cmd.SHORT_UPLOAD, 2.5 * FAST.t1)
    with pytest.raises(EcuSilentError, match="SHORT_UPLOAD: no response .* none to SYNCH either"):
        rig.master.read(threshold, 4)
    assert rig.master.get_daq_processor_info() == processor  # the late answers arrive during this command
    assert rig.demo.ecu.faults.fired == [f"answer command 0x{Cmd.SHORT_UPLOAD:02X} {2.5 * FAST.t1} s late"]
    assert struct.unpack("<f", rig.master.read(threshold, 4))[0] == 20.0
    assert rig.master.read(CAL_RAM, 20) == rig.demo.ecu.read(CAL_RAM, 20)


def test_a_late_answer_to_connect_does_not_shift_the_answers_after_it():
    """A slow slave (every answer 0.6 T1 late) whose first CONNECT answer comes after T1: the repeated CONNECT
    takes it, and the repeat's own answer, still on its way, must not become the answer of the command after
    it (on CAN responses carry no tag), nor shift every answer after that by one."""
    slow = SlaveProfile("slow", "", "", xcp={"response_delay_s": 0.6 * FAST.t1})
    demo = build_demo_ecu(slave_profile=slow)
    demo.ecu.faults.delay_frame(1, 0.7 * FAST.t1, "tx")  # CONNECT's answer at 1.3 T1: the master gave up on it
    with serve(demo, None) as rig:  # connects
        assert demo.ecu.faults.fired == ["delay tx frame 1"]
        assert rig.master.comm_mode.max_bs == 42
        assert rig.master.protected == Resource.CAL_PAG | Resource.DAQ | Resource.PGM
        assert rig.master.read(CAL_RAM, 20) == demo.ecu.read(CAL_RAM, 20)


def test_an_unlock_answered_after_its_timeout_is_not_sent_again():
    """UNLOCK consumes its seed: repeated after a timeout it is ERR_SEQUENCE even though the first one unlocked.
    The master starts over with GET_SEED instead, which says (length 0) that the resource is open."""
    late = SlaveProfile("late-unlock", "", "", xcp={"response_delay_s": 1.5 * FAST.t1, "delayed_every": 5})
    demo = build_demo_ecu(slave_profile=late)
    with serve(demo, None) as rig:  # CONNECT, GET_COMM_MODE_INFO, GET_STATUS: answers 1-3
        rig.master.unlock(Resource.CAL_PAG)  # GET_SEED (answer 4), UNLOCK (answer 5, after T1)
        assert not rig.master.protected & Resource.CAL_PAG
        assert rig.master.get_status().protected == Resource.DAQ | Resource.PGM
        assert rig.master.read(CAL_RAM, 20) == demo.ecu.read(CAL_RAM, 20)


class _StaleNode:
    """A node that answers every CONNECT on ``channel`` at once with ``packet``: the late answer of a command of an
    earlier session (a killed master's SHORT_UPLOAD), which a positive response cannot be told apart from by its PID."""

    def __init__(self, channel: str, packet: bytes):
        import can

        self.bus = can.Bus(interface="virtual", channel=channel)
        self.packet = packet
        self.notifier = can.Notifier(self.bus, [self._heard])

    def _heard(self, message) -> None:
        import can

        if message.arbitration_id == 0x7F0 and message.data[:1] == b"\xff":
            self.bus.send(can.Message(arbitration_id=0x7F1, is_extended_id=False, data=self.packet))

    def close(self) -> None:
        self.notifier.stop()
        self.bus.shutdown()


def test_a_stale_answer_before_the_connect_response_is_dropped(caplog):
    from workbench.sim.server import Simulator

    demo = build_demo_ecu()
    demo.ecu.faults.delay_frame(1, 1.0, "tx")  # the ECU's answer to CONNECT comes a second after the stale one
    stale = _StaleNode("xcp-test-stale", bytes.fromhex("ff 00 00 00 00 00 00 00"))
    slow = Timeouts(t1=3.0, t2=3.0, t3=3.0, t4=3.0, t5=3.0, t6=3.0, t7=0.02)
    try:
        with Simulator(demo.ecu, {"interface": "virtual", "channel": "xcp-test-stale"}, time_scale=1.0), \
                Link(can_settings("xcp-test-stale")) as link, caplog.at_level("INFO", "workbench.xcp.master"):
            master = XcpMaster(link, timeouts=slow, key_function=compute_key)
            info = master.connect()
            assert (info.max_cto, info.max_dto, info.protocol_version) == (8, 8, 1)
            assert master.read(CAL_RAM, 20) == demo.ecu.read(CAL_RAM, 20)
    finally:
        stale.close()
    assert demo.ecu.faults.fired == ["delay tx frame 1"]
    assert "XCP CONNECT: ff 00 00 00 00 00 00 00 dropped, no CONNECT response: MAX_CTO 0, below 8" in caplog.text


def test_only_a_stale_answer_to_connect_says_what_was_wrong():
    stale = _StaleNode("xcp-test-stale-only", bytes.fromhex("ff 00 00 00 00 00 00 00"))
    try:
        with Link(can_settings("xcp-test-stale-only")) as link:
            with pytest.raises(WorkbenchError, match=r"^XCP CONNECT: the answer ff 00 00 00 00 00 00 00 is no CONNECT "
                                                     r"response: MAX_CTO 0, below 8; another master on the bus, or a "
                                                     r"packet of an earlier session\?$"):
                XcpMaster(link, timeouts=FAST).connect()
    finally:
        stale.close()


@pytest.mark.parametrize("packet, max_packet, problem", [
    ("ff 1d 80 08 08 00 01 01", 8, None),  # the demo on CAN
    ("ff 1d c0 ff 00 04 01 01", 0xFFFF, None),  # MAX_CTO 255, MAX_DTO 1024 on Ethernet
    ("ff 1d 81 40 00 40 01 01", 64, None),  # Motorola, CAN FD 64 bytes
    ("ff 1d 80 08 08 00 01", 8, "7 bytes, a CONNECT response has 8"),
    ("ff 1d 80 08 00 04 01 01", 8, "MAX_DTO 1024, more than the 8 bytes the transport carries"),
    ("ff 1d 80 40 08 00 01 01", 8, "MAX_CTO 64, more than the 8 bytes the transport carries (XCP on CAN FD? the "
                                   "A2L's XCP_ON_CAN has no CAN_FD block)"),  # a CAN FD ECU, a classic CAN A2L
    ("ff 1d 80 ff 08 00 01 01", 64, "MAX_CTO 255, more than the 64 bytes the transport carries"),
    ("ff 1d 80 08 04 00 01 01", 8, "MAX_DTO 4, below 8"),
    ("ff 1d 86 08 08 00 01 01", 8, "address granularity 3, which is reserved"),
    ("ff 1d 80 08 08 00 00 00", 8, "XCP protocol layer version 0, not 1"),
])
def test_what_makes_a_packet_no_connect_response(packet, max_packet, problem):
    from workbench.xcp.info import ConnectInfo

    assert ConnectInfo.problem(bytes.fromhex(packet), max_packet) == problem


def test_options_the_interface_refuses_are_bad_input():
    """``--bus-kwargs port=abc``: python-can's ValueError is the user's input, exit 2, not a failed operation."""
    from workbench.bus_defaults import BusSpec
    from workbench.errors import InputError
    from workbench.xcp.link import LinkSettings

    with pytest.raises(InputError, match=r"cannot open the CAN bus \(udp_multicast .*\): Port config must be a number"):
        Link(LinkSettings("CAN", BusSpec("udp_multicast", "239.74.163.2", options={"port": "abc"})))
