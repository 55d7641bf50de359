"""What a session checks around CONNECT: another master's traffic on the ECU's ids is said before connecting
(CANape beside us), and an unanswered CONNECT says what to check in the transport's own terms."""

from __future__ import annotations

import re
import socket

import can
import pytest
from session_helpers import FAST

from workbench import Session
from workbench.cli import main
from workbench.errors import InputError, XcpTimeoutError
from workbench.session import session as session_module
from workbench.session.session import other_master
from workbench.sim import serve_demo
from workbench.xcp_protocol import CanId


def test_a_quiet_bus_gives_no_warning(ecu):
    assert ecu.other_master == ""


@pytest.fixture
def listening_long(monkeypatch):
    """A window a loaded machine cannot miss the other master's 4 ms DTOs in (the product listens 10 ms)."""
    monkeypatch.setattr(session_module, "LISTEN_BEFORE_CONNECT_S", 0.2)


def test_another_masters_daq_is_said_before_connect(ecu, channel, listening_long):
    with ecu.measure(["zsRailPressure"]) as live:  # the other master: its DAQ runs on the 4 ms event
        live.read(1.0)
        with Session.open(interface="virtual", channel=channel, timeouts=FAST) as second:
            said = second.other_master
    assert re.fullmatch(r"before CONNECT, the ECU's id 0x[0-9A-F]+ carried \d+ DTO\(s\) within 200 ms: another "
                        r"master \(CANape, a second workbench\) is talking to this ECU, .*", said), said
    assert f"id {ecu.link.settings.can_id_slave} carried" in said


def test_packets_queued_before_a_reconnect_are_not_another_master(ecu, channel, listening_long):
    """What came on the ECU's ids before the listening starts is not news: this bus's earlier session (its own late
    DTOs before a reconnect after a flash, a window's Disconnect/Connect) or a burst that is over. A reconnect on
    a quiet bus says nothing; it used to call them another master."""
    slave = ecu.link.settings.can_id_slave
    with can.Bus(interface="virtual", channel=channel) as other:
        for counter in range(20):
            other.send(can.Message(arbitration_id=slave.id, is_extended_id=slave.extended,
                                   data=bytes((0xF0, counter, 0, 0, 0, 0, 0, 0))))
    ecu.connect()
    assert ecu.other_master == ""


def test_another_masters_daq_is_said_in_the_cli_in_one_line(free_udp_port, capsys, listening_long):
    """A session measuring by DAQ beside the command (on udp_multicast, between buses): the command warns and goes on."""
    options = {"interface": "udp_multicast", "bus_kwargs": {"port": free_udp_port}}
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        with Session.open(**options, timeouts=FAST) as first, first.measure(["zsRailPressure"]) as live:
            live.read(1.0)
            code = main(["cal", "get", "xsSWITCH_TANK_THR", "--bus-kwargs", f"port={free_udp_port}"])
    out, err = capsys.readouterr()
    assert code == 0 and out.startswith("xsSWITCH_TANK_THR = "), err
    assert err.startswith("warning: before CONNECT, the ECU's id 0x") and err.count("\n") == 1, err


def test_responses_and_dtos_are_told_apart():
    heard = [(CanId(0x7F1), bytes((0xFF, 0))), (CanId(0x7F1), bytes((0x00, 1, 2))), (CanId(0x123, True), bytes(2)),
             (CanId(0x7F1), bytes((0xFD, 0x0A)))]  # a response, two DTOs, an event (to a master as much as a response)
    assert other_master(heard, 0.01).startswith("before CONNECT, the ECU's ids 0x7F1, 0x123 (extended) carried "
                                                "2 DTO(s), 2 response(s) within 10 ms: another master")
    assert other_master([], 0.01) == ""


def test_an_unanswered_connect_on_can_asks_for_the_bus_and_ids():
    with pytest.raises(XcpTimeoutError, match=r"no ECU answers on XCP on CAN \(virtual nobody-here, ids "
                                              r"0x[0-9A-F]+/0x[0-9A-F]+\): is it powered, on this bus, with these ids\?"):
        Session.open(interface="virtual", channel="nobody-here", timeouts=FAST)


def test_an_unanswered_connect_on_udp_asks_for_the_address_and_protocol(free_udp_port):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as silent:  # something takes the datagrams, answers none
        silent.bind(("127.0.0.1", free_udp_port))
        with pytest.raises(XcpTimeoutError) as raised:
            Session.open(host="127.0.0.1", port=free_udp_port, protocol="udp", timeouts=FAST)
    assert str(raised.value).endswith(f"no ECU answers on XCP on UDP (127.0.0.1:{free_udp_port}): is it powered, at "
                                      f"127.0.0.1:{free_udp_port}, serving XCP on UDP (--protocol tcp for TCP)?")


def test_an_unanswered_connect_on_tcp_names_another_master(free_tcp_port):
    """XCPlite on TCP serves one client: a second master's connection is taken (the listen backlog) and waits,
    its CONNECT unanswered, while `measure` runs in another terminal. 'Is it powered?' misled: it is there."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as busy:  # takes connections, serves none of them
        busy.bind(("127.0.0.1", free_tcp_port))
        busy.listen(4)
        with pytest.raises(XcpTimeoutError) as raised:
            Session.open(host="127.0.0.1", port=free_tcp_port, protocol="tcp", timeouts=FAST)
    assert str(raised.value).endswith(f"no ECU answers on XCP on TCP (127.0.0.1:{free_tcp_port}): it took the TCP "
                                      "connection but answers no CONNECT: another master (a second workbench, CANape) "
                                      "may hold it, an XCP server serves one at a time (XCPlite lets the next wait); "
                                      "or it speaks no XCP")


def test_a_bus_option_the_bus_would_ignore_is_refused_before_a_frame_is_sent(channel):
    """``import workbench``'s way: a typo python-can ignores (prot for port) reached the default port's bus, another
    user's simulator perhaps; only the CLI refused it."""
    with pytest.raises(InputError, match=r"^bus option recieve_own_messages=True: python-can's virtual bus has no "
                                         r"option 'recieve_own_messages' and would ignore it \(did you mean "
                                         r"receive_own_messages\? "):
        Session.open(interface="virtual", channel=channel, bus_kwargs={"recieve_own_messages": True}, timeouts=FAST)
