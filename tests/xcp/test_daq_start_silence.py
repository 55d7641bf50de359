"""A DAQ that sends nothing from its start while the ECU answers: what the master asks and says, on CAN (GET_DAQ_ID)
and on Ethernet (GET_STATUS, GET_DAQ_LIST_MODE), against the simulated demo ECU with its events held back."""

from __future__ import annotations

import itertools
import threading
import time

import pytest
from daq_samples import collect_until
from session_helpers import FAST
from xcp_helpers import refusal_of_a_silent_daq

from workbench import Session, demo
from workbench.errors import ConnectionLostError
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.xcp.daq import stream as stream_module
from workbench.xcp_protocol import EV_DAQ_OVERLOAD

_channels = itertools.count()


def _hold_events(sim, running: threading.Event) -> None:
    """The ECU's events send nothing until ``running`` is set (the lists run, their samples are dropped)."""
    send = sim.ecu.dto_sink
    sim.ecu.dto_sink = lambda sample: send(sample) if running.is_set() else None


def _read_until_refused(live) -> None:
    for _ in range(200):  # 40 s at most; refused after three silences of T1 + 3 periods of the event
        live.read(0.2)


def test_a_first_dto_while_the_last_silence_is_judged_is_measured(monkeypatch):
    """The first DTO comes while the third silence from the start is being judged (after GET_DAQ_ID answered, as the
    refusal is written): the measurement goes on; it was refused 'no DTO within ... of the start' all the same."""
    channel = f"start-silence-{next(_channels)}"
    running, live = threading.Event(), None
    real_ms = stream_module._ms

    def dto_while_judged(seconds: float) -> str:
        stream = live.stream if live is not None else None
        if stream is not None and not running.is_set() and seconds >= stream_module._START_CHECKS * stream._silence \
                and stream._start_checks == stream_module._START_CHECKS - 1:  # the third silence (the refusal's)
            running.set()  # the receiver takes the first DTO now, whatever the master's thread is doing
            deadline = time.monotonic() + 10.0
            while stream.assembler.dtos == 0 and time.monotonic() < deadline:
                time.sleep(0.005)
        return real_ms(seconds)

    monkeypatch.setattr(stream_module, "_ms", dto_while_judged)
    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=1.0) as sim, \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        _hold_events(sim, running)
        with session.measure(["zsRailPressure"]) as live:
            assert collect_until(live, lambda got: len(got) > 0)
    assert running.is_set()


@pytest.mark.parametrize("protocol", ["udp", "tcp"])
def test_on_ethernet_an_answering_ecu_whose_events_do_not_run_is_not_lost(protocol, free_udp_port, free_tcp_port):
    """XCP on Ethernet has no GET_DAQ_ID: GET_STATUS and GET_DAQ_LIST_MODE say the lists run, so the events do not;
    the session goes on (it was 'lost': the window reconnected to an ECU that had never gone)."""
    port = free_udp_port if protocol == "udp" else free_tcp_port
    running = threading.Event()
    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", port, protocol.upper()), time_scale=1.0) as sim, \
            Session.open(demo.a2l(), host="127.0.0.1", port=port, protocol=protocol, timeouts=FAST) as session:
        _hold_events(sim, running)
        refusal = refusal_of_a_silent_daq(session, ["zsRailPressure", "xsDC"])
    assert refusal == (
        "DAQ: no DTO within 900 ms of the start, though the ECU answers: GET_STATUS and GET_DAQ_LIST_MODE say DAQ "
        "lists 0, 1 run: the ECU's events do not run (is its application started?)")


def test_on_ethernet_lists_the_ecu_stopped_are_said_at_once(free_udp_port):
    """Lists stopped in the ECU right after their start (another master's START_STOP_SYNCH, say): GET_DAQ_LIST_MODE
    says which do not run, at the first silence."""
    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", free_udp_port, "UDP"), time_scale=1.0) as sim, \
            Session.open(demo.a2l(), host="127.0.0.1", port=free_udp_port, timeouts=FAST) as session:
        send = sim.ecu.dto_sink

        def stopped(sample) -> None:  # the lists stop before their first sample leaves
            for daq in sim.ecu.slave.daq.lists:
                daq.running = False

        sim.ecu.dto_sink = stopped
        refusal = refusal_of_a_silent_daq(session, ["zsRailPressure"])
        sim.ecu.dto_sink = send
    assert refusal == (
        "DAQ: no DTO within 300 ms of the start, though the ECU answers: GET_STATUS says no DAQ list runs: the ECU "
        "stopped them (another master, or its application?)")


def test_events_of_the_slave_while_daq_runs_end_it_or_count_as_overloads():
    """EV_DAQ_OVERLOAD counts in the measurement's overloads; EV_SESSION_TERMINATED ends it at once, named (it was a
    silence, said as 'nothing from the ECU' after three periods, and the overload was only logged)."""
    channel = f"start-silence-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=1.0) as sim, \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        with pytest.raises(ConnectionLostError, match=r"the ECU ended the XCP session \(EV_SESSION_TERMINATED\)"), \
                session.measure(["zsRailPressure"]) as live:
            assert collect_until(live, lambda got: len(got) > 0)
            sim.xcp.send_event(EV_DAQ_OVERLOAD)
            collect_until(live, lambda got: live.stats.overloads > 0)
            assert live.stats.overloads == 1
            sim.end_session()
            _read_until_refused(live)
