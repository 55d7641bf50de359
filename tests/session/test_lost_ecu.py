"""A lost ECU in-process, on each transport: the simulator stops (or its power is cut) while DAQ runs or between
polled reads; the session says so as ConnectionLostError naming the link, sends nothing more, closes at once,
and a CONNECT reaches the ECU again when it is back."""

from __future__ import annotations

import time

import pytest
from session_helpers import FAST

from workbench import ConnectionLostError, EcuSilentError, Session, XcpTimeoutError
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.xcp_protocol import Cmd

SIGNALS = ["zsRailPressure", "xsDC"]  # Task4ms and Task100ms: DTOs are due within max(T1, 3 x 100 ms)


def serve(transport: str, channel: str, port: int):
    if transport == "CAN":
        return serve_demo({"interface": "virtual", "channel": channel}), {"interface": "virtual", "channel": channel}
    return serve_demo(ethernet=EthernetEndpoint("127.0.0.1", port, transport)), {
        "host": "127.0.0.1", "port": port, "protocol": transport.lower()}


@pytest.fixture(params=["CAN", "UDP", "TCP"])
def transport(request) -> str:
    return request.param


@pytest.fixture
def port(transport, free_udp_port, free_tcp_port) -> int:
    return free_tcp_port if transport == "TCP" else free_udp_port


def test_the_simulator_stopping_during_daq_is_said_and_the_session_closes_at_once(transport, channel, port):
    simulator, options = serve(transport, channel, port)
    session = Session.open(**options, timeouts=FAST)
    live = session.measure(SIGNALS).start()
    try:
        assert _read_until_lost(live, wanted=5) >= 5  # samples came before
        simulator.close()
        with pytest.raises(ConnectionLostError, match=f"XCP on {transport}") as lost:
            _read_until_lost(live)
        assert lost.value.when <= time.time()
        if transport == "TCP":
            assert "closed the TCP connection" in lost.value.reason  # said at once, no silence waited for
        with pytest.raises(ConnectionLostError):  # every call at once from then on
            session.read("xsSWITCH_TANK_THR")
        started = time.monotonic()
        session.close()  # no stop command waits out a timeout
        assert time.monotonic() - started < FAST.t1
        assert not live.running
    finally:
        session.close()
        simulator.close()


def test_an_ecu_that_stops_answering_polls_is_lost_and_connect_reaches_it_again(sim, channel):
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:
        sim.power_off()
        with pytest.raises(EcuSilentError, match=f"SHORT_UPLOAD: no response within {FAST.t1 * 1000:.0f} ms, none to "
                                                 "SYNCH") as silent:
            session.read("xsSWITCH_TANK_THR")
        assert isinstance(silent.value, XcpTimeoutError) and isinstance(silent.value, ConnectionLostError)
        sim.power_on()
        session.connect()
        assert session.read("xsSWITCH_TANK_THR") == 20.0


def test_closing_a_session_whose_ecu_was_found_silent_sends_nothing_more(sim, channel):
    session = Session.open(interface="virtual", channel=channel, timeouts=FAST)
    sim.power_off()
    with pytest.raises(EcuSilentError):
        session.read("xsSWITCH_TANK_THR")
    sent, exchange = [], session.link.exchange
    session.link.exchange = lambda packet, *args, **kwargs: sent.append(packet) or exchange(packet, *args, **kwargs)
    session.close()
    assert sent == [] and session.link.closed  # no DISCONNECT waiting out T1 twice


@pytest.mark.parametrize("protocol", ["UDP", "TCP"])
def test_an_ethernet_ecu_gone_between_polls_is_said_at_once(protocol, free_udp_port, free_tcp_port):
    port = free_udp_port if protocol == "UDP" else free_tcp_port
    simulator, options = serve(protocol, "", port)
    try:
        with Session.open(**options, timeouts=FAST) as session:
            assert session.read("xsSWITCH_TANK_THR") == 20.0
            simulator.close()
            started = time.monotonic()
            with pytest.raises(ConnectionLostError, match="closed the TCP connection|nothing listens"):
                for _ in range(3):  # UDP: the host's ICMP answer comes with the next datagram
                    session.read("xsSWITCH_TANK_THR")
            assert time.monotonic() - started < 2 * FAST.t1  # not after T1 and SYNCH's T1 each time
    finally:
        simulator.close()


def _read_until_lost(live, wanted: int | None = None, timeout_s: float = 10.0) -> int:
    """Read until ``wanted`` samples came (or, with None, until read() raises); the samples read."""
    samples, deadline = 0, time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        samples += sum(len(batch) for batch in live.read(0.05))
        if wanted is not None and samples >= wanted:
            return samples
    raise AssertionError(f"{samples} samples, and the ECU was not found lost within {timeout_s} s")


@pytest.mark.parametrize("action", ["read scalar", "read map", "write scalar"])
def test_a_dead_ecu_is_said_after_the_command_and_its_synch_whatever_the_access(sim, channel, action):
    """Bound: T1 for the command, T1 for the SYNCH the standard sends before repeating it (ASAM XCP's pre-action
    for a timeout); then nothing more waits: no repeat from SET_MTA, no further SYNCH (counted, not timed)."""
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:
        session.read("zvRailPConv")
        sim.power_off()
        waits = []  # (command, answered) of every wait for the ECU
        exchange, receive = session.link.exchange, session.link.receive
        session.link.exchange = lambda packet, *a, **k: _noted(waits, packet[0], exchange(packet, *a, **k))
        session.link.receive = lambda *a, **k: _noted(waits, None, receive(*a, **k))
        with pytest.raises(EcuSilentError, match="none to SYNCH either"):
            if action == "read scalar":
                session.read("xsSWITCH_TANK_THR")
            elif action == "read map":
                session.read("zvRailPConv")
            else:
                session.write("xsSWITCH_TANK_THR", 21.0)
        first = {"read scalar": Cmd.SHORT_UPLOAD, "read map": Cmd.SET_MTA, "write scalar": Cmd.GET_SEED}[action]
        assert waits == [(first, False), (Cmd.SYNCH, False)]  # each waited T1 once


def _noted(waits: list, command: int | None, response):
    waits.append((command, response is not None))
    return response


def test_a_new_session_is_not_misled_by_the_dtos_an_earlier_master_left_running(channel):
    """The earlier master died with DAQ running (its link gone without a stop): the ECU still sends its DTOs on
    the response id while the next session connects and reads; they are dropped, never taken for the CONNECT
    response or a read's."""
    import can

    simulator, options = serve("CAN", channel, 0)
    try:
        earlier = Session.open(**options, timeouts=FAST)
        live = earlier.measure(SIGNALS).start()
        assert _read_until_lost(live, wanted=5) >= 5
        earlier.link.close()  # killed: DAQ keeps running in the ECU (closing it later sends nothing)
        with can.Bus(interface="virtual", channel=channel) as wire, Session.open(**options, timeouts=FAST) as session:
            assert session.master.connect_info.max_cto == 8
            assert [session.read("xsSWITCH_TANK_THR") for _ in range(20)] == [20.0] * 20
            dtos = 0
            while (frame := wire.recv(0)) is not None:
                dtos += frame.arbitration_id == 0x7F1 and frame.data[0] < 0xFC
            assert dtos > 0  # they came, between the responses
        earlier.close()
    finally:
        simulator.close()


def test_a_second_master_that_stops_the_daq_is_named_as_the_likely_cause(sim, channel):
    """A second master on the same ids (another terminal's `cal set` while `measure` records) connects and
    disconnects: the ECU stops the first master's DAQ. The first master hears the answers to commands it never
    sent, and its 'connection lost' says so instead of only 'nothing from the ECU' (user trial 6)."""
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as first:
        live = first.measure(SIGNALS).start()
        assert _read_until_lost(live, wanted=5) >= 5
        with Session.open(interface="virtual", channel=channel, timeouts=FAST) as second:
            assert second.read("xsSWITCH_TANK_THR") == 20.0
        with pytest.raises(ConnectionLostError, match=r"nothing from the ECU for .*; \d+ response\(s\) came that this "
                                                      "master did not ask for: another master on these ids"):
            _read_until_lost(live)


@pytest.mark.parametrize("how", ["UDP, the simulator closed", "CAN, the power cut"])
def test_an_ecu_whose_events_state_no_cycle_is_asked_when_silent_and_found_lost(how, channel, free_udp_port):
    """XCPlite's events state no cycle (A2L and GET_DAQ_EVENT_INFO; profile sporadic-events): no silence tells a lost
    ECU, so after PROBE_AFTER_S without a DTO the master asks (GET_STATUS). Before, `workbench measure --daq` on a
    killed XCPlite (UDP: the master sends nothing while DAQ runs, so no ICMP answer came either) ran to its end and
    said '0 lost'."""
    if how.startswith("UDP"):
        serving = serve_demo(ethernet=EthernetEndpoint("127.0.0.1", free_udp_port, "UDP"), profile="sporadic-events")
        options = {"host": "127.0.0.1", "port": free_udp_port, "protocol": "udp"}
    else:
        serving = serve_demo({"interface": "virtual", "channel": channel}, profile="sporadic-events")
        options = {"interface": "virtual", "channel": channel}
    with serving as simulator, Session.open(simulator.a2l, **options, timeouts=FAST) as session:
        live = session.measure(SIGNALS).start()
        assert live.stream.silence_limit() is None  # the premise: no event measured states a cycle
        assert _read_until_lost(live, wanted=5) >= 5
        if how.startswith("UDP"):
            simulator.close()
            expected = "nothing listens"
        else:
            simulator.power_off()
            expected = "nothing from the ECU for .* s while DAQ ran, and it answers neither GET_STATUS nor SYNCH"
        with pytest.raises(ConnectionLostError, match=expected):
            _read_until_lost(live)


def test_a_second_master_taking_an_ethernet_ecu_over_is_named_as_the_likely_cause(free_udp_port):
    """`workbench measure --daq` in one terminal, `workbench cal set` in another, on XCPlite over UDP: the ECU takes the
    new master and ignores the first (its DTOs go to the new one). The first master has nothing to hear the other by
    (Ethernet: each master its own address): its probe finds the ECU silent and says who may have taken it."""
    endpoint = EthernetEndpoint("127.0.0.1", free_udp_port, "UDP")
    options = {"host": "127.0.0.1", "port": free_udp_port, "protocol": "udp", "timeouts": FAST}
    with serve_demo(ethernet=endpoint, profile="sporadic-events") as simulator, \
            Session.open(simulator.a2l, **options) as first:
        live = first.measure(SIGNALS).start()
        assert _read_until_lost(live, wanted=5) >= 5
        with Session.open(simulator.a2l, **options) as second:
            assert second.read("xsSWITCH_TANK_THR") == 20.0
            with pytest.raises(ConnectionLostError, match="another master connected to it"):
                _read_until_lost(live)
        started = time.monotonic()
        first.close()  # the link is lost: no stop command waits out T1
        assert time.monotonic() - started < FAST.t1
