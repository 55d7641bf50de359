"""The link's XCP on CAN against a scripted slave on a virtual bus: the frames on the wire (ids, lengths,
CAN FD, padding), which frames are XCP, and who reads the bus (the caller, or one Notifier with DAQ)."""

from __future__ import annotations

import itertools
import threading
import time

import can
import pytest

from workbench.bus_defaults import BusSpec
from workbench.errors import ConnectionLostError, WorkbenchError
from workbench.xcp.link import Link, LinkSettings
from workbench.xcp.transport.can import frame_length
from workbench.xcp_protocol import CanId

_channels = itertools.count()
MASTER, SLAVE, DAQ_ID = 0x7F0, 0x7F1, 0x1234567


class ScriptedSlave:
    """Answers each command frame with ``answer(data) -> [(id, extended, data), ...]`` and keeps what it got."""

    def __init__(self, channel: str, answer, fd: bool = False):
        self.bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self.answer = answer
        self.fd = fd
        self.received: list[can.Message] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            message = self.bus.recv(0.02)
            if message is None:
                continue
            self.received.append(message)
            for identifier, extended, data in self.answer(bytes(message.data)):
                self.bus.send(can.Message(arbitration_id=identifier, is_extended_id=extended, data=data,
                                          is_fd=self.fd or len(data) > 8))

    def send(self, identifier: int, data: bytes, extended: bool = False) -> None:
        self.bus.send(can.Message(arbitration_id=identifier, is_extended_id=extended, data=data, is_fd=len(data) > 8))

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.bus.shutdown()


def echo(data: bytes):
    """A positive response carrying the command's bytes after the PID."""
    return [(SLAVE, False, bytes([0xFF]) + data[1:])]


@pytest.fixture
def channel() -> str:
    return f"link-can-{next(_channels)}"


def settings(channel: str, **changes) -> LinkSettings:
    return LinkSettings(**{"transport": "CAN", "bus": BusSpec("virtual", channel), "can_id_master": CanId(MASTER),
                           "can_id_slave": CanId(SLAVE), **changes})


@pytest.mark.parametrize(("size", "fd", "max_dlc", "required", "length"), [
    (2, False, 8, False, 2), (2, False, 8, True, 8), (8, False, 8, False, 8),
    (9, True, 64, False, 12), (13, True, 64, False, 16), (33, True, 64, False, 48), (2, True, 64, False, 2),
    (2, True, 64, True, 64), (2, True, 32, True, 32), (64, True, 64, False, 64),
])
def test_frame_lengths_follow_the_dlc_table(size, fd, max_dlc, required, length):
    assert frame_length(size, fd=fd, max_dlc=max_dlc, max_dlc_required=required) == length


@pytest.mark.parametrize(("size", "fd"), [(9, False), (65, True)])
def test_a_packet_longer_than_a_frame_is_refused(size, fd):
    with pytest.raises(ValueError, match=f"{size} bytes does not fit"):
        frame_length(size, fd=fd, max_dlc=64, max_dlc_required=False)


def test_commands_and_responses_on_extended_ids_padded_as_the_a2l_says(channel):
    slave = ScriptedSlave(channel, lambda data: [(0x18FF0001, True, bytes([0xFF, 1, 2]))])
    try:
        with Link(settings(channel, can_id_master=CanId(0x18FF0000, extended=True),
                           can_id_slave=CanId(0x18FF0001, extended=True), max_dlc_required=True)) as link:
            assert link.exchange(bytes([0xFC]), 1.0) == bytes([0xFF, 1, 2])
        sent = slave.received[0]
        assert (sent.arbitration_id, sent.is_extended_id) == (0x18FF0000, True)
        assert bytes(sent.data) == bytes([0xFC]) + bytes(7)
    finally:
        slave.close()


def test_can_fd_frames_carry_long_packets_padded_to_a_dlc_length(channel):
    padded = bytes([0xFF]) + bytes(range(40)) + bytes(7)  # 41 bytes travel in a 48-byte frame
    slave = ScriptedSlave(channel, lambda data: [(SLAVE, False, padded)], fd=True)
    try:
        with Link(settings(channel, fd=True, max_dlc=64)) as link:
            assert link.exchange(bytes([0xF5]) + bytes(range(10)), 1.0) == padded
        sent = slave.received[0]
        assert sent.is_fd and len(sent.data) == 12 and bytes(sent.data) == bytes([0xF5]) + bytes(range(10)) + b"\0"
    finally:
        slave.close()


def test_other_frames_events_and_dtos_are_not_responses(channel):
    def answer(data):
        return [(0x100, False, bytes([0xFF, 9])),  # another node's frame with a response's PID
                (SLAVE, False, bytes([0xFD, 0x00])),  # EV_RESUME_MODE
                (SLAVE, False, bytes([0xFC, 0x01, 0x41])),  # SERV_TEXT
                (SLAVE, False, bytes([0x00, 1, 2, 3])),  # a DTO
                (SLAVE, False, bytes([0xFE, 0x20]))]  # the answer: ERR_CMD_UNKNOWN

    slave = ScriptedSlave(channel, answer)
    try:
        with Link(settings(channel)) as link:
            assert link.exchange(bytes([0xC0]), 1.0) == bytes([0xFE, 0x20])
            assert list(link.events) == [bytes([0xFD, 0x00]), bytes([0xFC, 0x01, 0x41])]
    finally:
        slave.close()


@pytest.mark.parametrize("daq", [False, True], ids=["caller-reads", "receiver-reads"])
def test_ev_cmd_pending_restarts_the_wait_for_the_response(channel, daq):
    """A slave that needs longer than the command's timeout (a long erase) says so with EV_CMD_PENDING: each one
    starts the wait over (six 0.1 s apart, the answer 0.7 s after the command: with a 0.5 s timeout)."""
    def busy():
        for _ in range(6):
            time.sleep(0.1)
            slave.send(SLAVE, bytes([0xFD, 0x05]))
        time.sleep(0.1)
        slave.send(SLAVE, bytes([0xFF]))

    slave = ScriptedSlave(channel, lambda data: threading.Thread(target=busy, daemon=True).start() or [])
    try:
        with Link(settings(channel)) as link:
            if daq:
                link.dto_handler = lambda packet, host_ns: None
            assert link.exchange(bytes([0xD1, 0, 0, 0, 0, 0, 0, 0]), 0.5) == bytes([0xFF])
            assert list(link.events).count(bytes([0xFD, 0x05])) == 6
    finally:
        slave.close()


def test_a_doubled_response_is_dropped_before_the_next_command(channel):
    def answer(data):
        response = (SLAVE, False, bytes([0xFF, data[1]]))
        return [response, response] if data[1] == 1 else [response]

    slave = ScriptedSlave(channel, answer)
    try:
        with Link(settings(channel)) as link:
            assert link.exchange(bytes([0xF4, 1]), 1.0) == bytes([0xFF, 1])
            time.sleep(0.1)  # the double arrives
            assert link.exchange(bytes([0xF4, 2]), 1.0) == bytes([0xFF, 2])
            link.send(bytes([0xF4, 1]))  # no exchange drops this one's double ...
            assert link.receive(1.0) == bytes([0xFF, 1])
            assert link.receive(1.0) == bytes([0xFF, 1])  # ... so receive() hands it out
    finally:
        slave.close()


def test_during_daq_one_notifier_reads_dtos_on_every_daq_id_and_responses_reach_the_caller(channel):
    slave = ScriptedSlave(channel, echo)
    dtos = []
    try:
        with Link(settings(channel, daq_can_ids=(CanId(DAQ_ID, extended=True),))) as link:
            link.dto_handler = lambda packet, host_ns: dtos.append((packet, host_ns))
            assert can.Notifier.find_instances(link._transport.bus)
            before = time.time_ns()
            slave.send(SLAVE, bytes([0x00, 1]))
            slave.send(DAQ_ID, bytes([0x01, 2]), extended=True)
            slave.send(DAQ_ID, bytes([0x02, 3]), extended=False)  # the standard id of that number: not XCP
            assert link.exchange(bytes([0xF4, 7]), 1.0) == bytes([0xFF, 7])
            _wait_for(lambda: len(dtos) >= 2)
            assert [packet for packet, _ in dtos] == [bytes([0x00, 1]), bytes([0x01, 2])]
            assert all(before <= host_ns <= time.time_ns() for _, host_ns in dtos)
            link.dto_handler = None  # the caller's thread reads again
            assert not [n for n in can.Notifier.find_instances(link._transport.bus) if not n.stopped]
            slave.send(SLAVE, bytes([0x00, 4]))
            assert link.exchange(bytes([0xF4, 8]), 1.0) == bytes([0xFF, 8])
            assert len(dtos) == 2
    finally:
        slave.close()


def test_a_bus_someone_else_reads_with_a_notifier_gets_the_links_listener_added(channel):
    slave = ScriptedSlave(channel, echo)
    bus = can.Bus(interface="virtual", channel=channel)
    others = []
    notifier = can.Notifier(bus, [others.append], timeout=0.05)
    try:
        with Link(settings(channel), bus=bus) as link:
            link.dto_handler = lambda packet, host_ns: None
            assert link.exchange(bytes([0xF4, 5]), 1.0) == bytes([0xFF, 5])
            link.dto_handler = None
            assert len(notifier.listeners) == 1 and not notifier.stopped
        _wait_for(lambda: others)
        assert bytes(others[0].data) == bytes([0xFF, 5])  # the other listener heard the response too
        assert not bus._is_shutdown  # the caller's bus stays open
    finally:
        notifier.stop()
        bus.shutdown()
        slave.close()


def test_a_bus_that_fails_under_the_notifier_loses_the_link_at_once(channel, capfd):
    bus = can.Bus(interface="virtual", channel=channel)
    link = Link(settings(channel), bus=bus)
    try:
        link.dto_handler = lambda packet, host_ns: None
        bus.shutdown()  # the device is gone: recv raises in the Notifier's thread
        _wait_for(lambda: link.lost is not None)
        with pytest.raises(ConnectionLostError, match="the CAN bus failed"):
            link.exchange(bytes([0xFC]), 1.0)
    finally:
        link.close()
    assert "Traceback" not in capfd.readouterr().err


def test_a_closed_link_says_so(channel):
    link = Link(settings(channel))
    link.close()
    with pytest.raises(WorkbenchError, match="the XCP link is closed"):
        link.exchange(bytes([0xFC]), 0.1)


def _wait_for(condition, timeout_s: float = 5.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.005)


def test_a_bus_the_link_opens_filters_the_xcp_ids_except_while_others_listen(channel):
    with Link(settings(channel, daq_can_ids=(CanId(DAQ_ID, extended=True),))) as link:
        bus = link.can_bus
        assert bus.filters == [{"can_id": SLAVE, "can_mask": 0x7FF, "extended": False},
                               {"can_id": DAQ_ID, "can_mask": 0x1FFFFFFF, "extended": True}]
        heard = []
        link.add_listener(heard.append)
        assert bus.filters is None and [n for n in can.Notifier.find_instances(bus) if not n.stopped]
        link.remove_listener(heard.append)
        assert len(bus.filters) == 2 and not [n for n in can.Notifier.find_instances(bus) if not n.stopped]
