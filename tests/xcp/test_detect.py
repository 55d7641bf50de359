"""Finding XCP on CAN slaves with GET_SLAVE_ID: simulated slaves of different ids on one python-can bus, a slave
that does not implement the command, an answer with the wrong pattern, and a CONNECT + GET_ID + GET_DAQ_ID per
slave found."""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import can
import pytest

from workbench import detect_slaves
from workbench.sim.server import Simulator
from workbench.sim.xcp.parameters import XcpParameters
from workbench.xcp.detect import (
    SlaveIdMode,
    detect_can_slaves,
    get_slave_id_request,
    identify_slave,
    parse_slave_id_answer,
)
from workbench.xcp_protocol import CanId, Cmd, Resource

sys.path.insert(0, str(Path(__file__).parents[1] / "sim"))
from mini_ecu import EPK, make_ecu

BROADCAST = CanId(0x6F0)
_channels = itertools.count()
INTEL = XcpParameters(can_id_broadcast=BROADCAST, protected=Resource(0))
MOTOROLA_EXTENDED = XcpParameters(can_id_master=CanId(0x12345, True), can_id_slave=CanId(0x12346, True),
                                  can_id_broadcast=BROADCAST, byte_order=">", protected=Resource(0))
WITHOUT_TRANSPORT_LAYER_CMD = XcpParameters(can_id_master=CanId(0x600), can_id_slave=CanId(0x601),
                                            can_id_broadcast=BROADCAST, without=frozenset({Cmd.TRANSPORT_LAYER_CMD}))


@pytest.fixture
def channel():
    return f"detect-{next(_channels)}"


def serve(channel: str, params: XcpParameters) -> Simulator:
    return Simulator(make_ecu(params=params), {"interface": "virtual", "channel": channel}, time_scale=None)


def test_two_slaves_on_one_bus_both_answer_with_their_own_ids(channel):
    with serve(channel, INTEL), serve(channel, MOTOROLA_EXTENDED), can.Bus(interface="virtual", channel=channel) as bus:
        found = detect_can_slaves(bus, BROADCAST)
        identities = [identify_slave(bus, slave) for slave in found.slaves]
    assert [(slave.command_id, slave.response_id, slave.confirmed) for slave in found.slaves] == [
        (CanId(0x7F0), CanId(0x7F1), True), (CanId(0x12345, True), CanId(0x12346, True), True)]
    assert found.refused == ()
    assert [(identity.epk, identity.error) for identity in identities] == [(EPK.decode(), None)] * 2
    assert [str(ids) for identity in identities for ids in identity.daq_ids] == [
        "lists 0-15 on 0x7F1 (fixed)", "lists 0-15 on 0x12346 (extended) (fixed)"]


def test_a_slave_without_get_slave_id_stays_silent_and_the_others_are_found(channel):
    with serve(channel, WITHOUT_TRANSPORT_LAYER_CMD), can.Bus(interface="virtual", channel=channel) as bus:
        assert detect_can_slaves(bus, BROADCAST, wait_s=0.1).slaves == ()
        with serve(channel, INTEL):
            found = detect_can_slaves(bus, BROADCAST, wait_s=0.1)
    assert [slave.command_id for slave in found.slaves] == [CanId(0x7F0)]


def test_an_answer_with_the_wrong_pattern_is_refused_and_said(channel):
    """A node that answers GET_SLAVE_ID with 'XCQ' (and a positive response that is not the inverse echo) is no
    slave: it is listed as refused, with its id and what was wrong."""
    with can.Bus(interface="virtual", channel=channel) as impostor, \
            can.Bus(interface="virtual", channel=channel) as bus:
        def answer(message: can.Message) -> None:
            if message.arbitration_id == BROADCAST.id:
                impostor.send(can.Message(arbitration_id=0x655, is_extended_id=False,
                                          data=b"\xffXCQ\xf0\x07\x00\x00"))

        notifier = can.Notifier(impostor, [answer], timeout=0.01)
        try:
            found = detect_can_slaves(bus, BROADCAST, wait_s=0.3)
        finally:
            notifier.stop()
    assert found.slaves == ()
    assert found.refused == ((CanId(0x655), "pattern 58 43 51, not 58 43 50"),
                             (CanId(0x655), "pattern 58 43 51, not A7 BC AF"))


def test_the_slave_answers_on_its_command_id_too_and_only_xcp_requests(channel):
    """GET_SLAVE_ID on CAN_ID_MASTER (as pyxcp sends it) is answered unconnected; a request without 'XCP' or with
    mode 2 is not; GET_DAQ_ID waits for a session."""
    with serve(channel, INTEL), can.Bus(interface="virtual", channel=channel) as bus:
        def ask(data: bytes, can_id: int = 0x7F0) -> bytes | None:
            bus.send(can.Message(arbitration_id=can_id, is_extended_id=False, data=data.ljust(8, b"\0")))
            answer = bus.recv(0.5)
            return bytes(answer.data) if answer is not None else None

        assert ask(get_slave_id_request(SlaveIdMode.ECHO)) == b"\xffXCP\xf0\x07\x00\x00"
        assert ask(get_slave_id_request(SlaveIdMode.INVERSE_ECHO)) == b"\xff\xa7\xbc\xaf\xf0\x07\x00\x00"
        assert ask(b"\xf2\xffXCP\x02") is None
        assert ask(b"\xf2\xffXYZ\x00", BROADCAST.id) is None
        assert ask(b"\xf2\xfe\x00\x00") is None  # GET_DAQ_ID before CONNECT


def test_the_slave_confirms_by_inverse_echo_only_after_an_echo(channel):
    """As ETAS's XCP slave (XcpCan_CmdGetSlaveId): an inverse echo is answered only after an echo, once; a power
    cycle forgets the echo. The simulator answered every inverse echo."""
    inverse = get_slave_id_request(SlaveIdMode.INVERSE_ECHO).ljust(8, b"\0")
    with serve(channel, INTEL) as simulator, can.Bus(interface="virtual", channel=channel) as bus:
        def answers(*requests: bytes) -> list[bytes | None]:
            found = []
            for data in requests:
                bus.send(can.Message(arbitration_id=BROADCAST.id, is_extended_id=False, data=data))
                answer = bus.recv(0.3)
                found.append(bytes(answer.data[:4]) if answer is not None else None)
            return found

        assert answers(inverse) == [None]
        assert answers(get_slave_id_request(SlaveIdMode.ECHO).ljust(8, b"\0"), inverse, inverse) == [
            b"\xffXCP", b"\xff\xa7\xbc\xaf", None]
        answers(get_slave_id_request(SlaveIdMode.ECHO).ljust(8, b"\0"))
        simulator.power_off()
        simulator.power_on()
        assert answers(inverse) == [None]


def test_parse_reads_the_identifier_in_the_order_that_makes_one():
    echo = SlaveIdMode.ECHO
    assert parse_slave_id_answer(b"\xffXCP\x80\x01\x00\x00", echo) == CanId(0x180)
    assert parse_slave_id_answer(b"\xffXCP\x00\x00\x07\xf0", echo) == CanId(0x7F0)  # a Motorola slave, Intel assumed
    assert parse_slave_id_answer(b"\xffXCP\x00\x00\x01\x80", echo, ">") == CanId(0x180)
    assert parse_slave_id_answer(b"\xffXCP\xff\xff\xff\x7f", echo) == "identifier bytes FF FF FF 7F are no CAN identifier"
    assert parse_slave_id_answer(b"\xfe\x20", echo) is None
    assert parse_slave_id_answer(b"\xffXCP", echo) is None


def test_detect_slaves_checks_the_a2l_ids_and_needs_a_broadcast_id(channel, tmp_path):
    from session_helpers import edited_a2l

    from workbench import InputError
    from workbench.sim import serve_demo

    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=None):
        detection = detect_slaves(interface="virtual", channel=channel, identify=True)
        assert detection.a2l_slave == detection.slaves[0] and detection.slaves[0].command_id == CanId(0x7F0)
        assert detection.identities[0].text == "FLCU demo ECU (workbench simulated HDS9)"
        wrong = edited_a2l(tmp_path, "CAN_ID_SLAVE 0x7F1\n", "CAN_ID_SLAVE 0x7F2\n")
        assert detect_slaves(wrong, interface="virtual", channel=channel).a2l_slave is None
        unknown = detect_slaves(interface="virtual", channel=channel, broadcast_id=0x100, wait_s=0.05)
        assert unknown.slaves == () and unknown.a2l_ids is None
    without = edited_a2l(tmp_path, "CAN_ID_BROADCAST 0x6F0\n", "")
    with pytest.raises(InputError, match="XCP_ON_CAN has no CAN_ID_BROADCAST; give the broadcast identifier"):
        detect_slaves(without, interface="virtual", channel=channel)


def test_daq_lists_with_can_ids_of_their_own_are_said_by_get_daq_id_and_used(channel):
    """The daq-can-ids profile: GET_DAQ_ID names 0x7F2/0x7F3 for lists 0 and 1, and a measurement by its A2L's
    DAQ_LIST_CAN_ID gets its DTOs there (a spy on the bus sees them)."""
    from workbench import Session
    from workbench.sim import serve_demo

    with serve_demo({"interface": "virtual", "channel": channel}, profile="daq-can-ids", time_scale=1.0) as sim, \
            can.Bus(interface="virtual", channel=channel) as spy:
        detection = detect_slaves(sim.a2l, interface="virtual", channel=channel, identify=True)
        with Session.open(sim.a2l, interface="virtual", channel=channel) as session, \
                session.measure(["zsRailPressure"]) as live:
            batches = []
            for _ in range(20):  # 10 s at most: a DTO on an id the master does not hear never comes
                batches += live.read(0.5)
                if batches:
                    break
        seen = set()
        while (message := spy.recv(0)) is not None:
            seen.add(message.arbitration_id)
    assert [str(ids) for ids in detection.identities[0].daq_ids] == [
        "list 0 on 0x7F2 (fixed)", "list 1 on 0x7F3 (fixed)", "lists 2-15 on 0x7F1 (fixed)"]
    assert batches and 0x7F2 in seen


@pytest.mark.parametrize("profile", ["large-packets", "motorola"])
def test_a_can_fd_slave_and_a_motorola_one_are_found_and_identified(channel, profile):
    """CAN FD (the A2L's CAN_FD block: the requests as FD frames, the session unpadded) and XCP's own byte order
    Motorola (the answer's identifier and GET_DAQ_ID's in it)."""
    from workbench.sim import serve_demo

    with serve_demo({"interface": "virtual", "channel": channel}, profile=profile, time_scale=None) as sim:
        detection = detect_slaves(sim.a2l, interface="virtual", channel=channel, identify=True)
    [identity] = detection.identities
    assert detection.a2l_slave is not None and identity.slave.confirmed
    assert (identity.epk, identity.error, [str(ids) for ids in identity.daq_ids]) == (
        "10300020250301", None, ["lists 0-15 on 0x7F1 (fixed)"])


def test_a_slave_that_does_not_confirm_is_listed_but_never_connected_to(channel):
    """An answer to the echo but none to the inverse echo: listed unconfirmed, and --identify sends no CONNECT to
    the id it named (a stray frame must not make the master talk on an id nobody confirmed)."""
    heard: list[can.Message] = []
    with can.Bus(interface="virtual", channel=channel) as impostor, \
            can.Bus(interface="virtual", channel=channel) as bus:
        def answer(message: can.Message) -> None:
            heard.append(message)
            if message.arbitration_id == BROADCAST.id and message.data[5] == SlaveIdMode.ECHO:
                impostor.send(can.Message(arbitration_id=0x655, is_extended_id=False, data=b"\xffXCP\x54\x06\x00\x00"))

        notifier = can.Notifier(impostor, [answer], timeout=0.01)
        try:
            detection = detect_slaves(bus=bus, broadcast_id=BROADCAST, wait_s=0.1, identify=True)
        finally:
            notifier.stop()
    assert [(slave.command_id, slave.response_id, slave.confirmed) for slave in detection.slaves] == [
        (CanId(0x654), CanId(0x655), False)]
    assert detection.identities == () and {message.arbitration_id for message in heard} == {BROADCAST.id}
