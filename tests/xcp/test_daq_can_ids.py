"""DAQ lists on CAN ids the master chooses: the A2L's DAQ_LIST_CAN_ID VARIABLE, SET_DAQ_ID before the lists start,
GET_DAQ_ID, against the simulated slave's daq-can-ids-variable profile (lists 0 and 1 VARIABLE, starting on
0x7F4/0x7F5 the A2L does not state; list 2 FIXED on 0x7F3) on python-can's virtual bus, with a spy on the bus."""

from __future__ import annotations

import itertools
import threading
import time

import can
import pytest
from daq_samples import collect_until
from session_helpers import FAST, edited_a2l
from xcp_helpers import refusal_of_a_silent_daq

from workbench import Session, demo
from workbench.a2l import load_a2l, read_xcp_config
from workbench.a2l.xcp import XcpDaqListCanId, XcpOnCan
from workbench.errors import ConnectionLostError, InputError, WorkbenchError, XcpCommandError
from workbench.session.connection import (
    Connection,
    assigned_daq_can_ids,
    daq_can_ids_of,
    link_settings,
)
from workbench.sim import serve_demo
from workbench.sim.profiles import SlaveProfile
from workbench.xcp_protocol import CanId, Cmd, Err

_channels = itertools.count()
PROFILE = "daq-can-ids-variable"


@pytest.fixture
def channel():
    return f"daq-can-ids-{next(_channels)}"


def _measure_both_events(session: Session) -> set[int]:
    """The events whose samples came within 10 s (list 0: event 0, 4 ms; list 1: event 1)."""
    events: set[int] = set()
    with session.measure(["zsRailPressure", "xsDC"]) as live:
        assert [(daq.number, daq.event) for daq in live.stream.plan.lists] == [(0, 0), (1, 1)]
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and events != {0, 1}:
            events |= {batch.event for batch in live.read(0.2)}
    return events


def test_variable_lists_send_where_set_daq_id_put_them(channel):
    """List 0 (no id given) is moved to CAN_ID_SLAVE, list 1 to the id given; their DTOs come there and never on the
    ids they started on; GET_DAQ_ID reads the ids back, configurable, and list 2 fixed."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile=PROFILE, time_scale=1.0) as sim, \
            can.Bus(interface="virtual", channel=channel) as spy:
        with Session.open(sim.a2l, interface="virtual", channel=channel, daq_can_ids={1: 0x7F6}) as session:
            events = _measure_both_events(session)
            read_back = [session.master.get_daq_id(number) for number in range(3)]
        seen: dict[int, int] = {}
        while (message := spy.recv(0)) is not None:
            seen[message.arbitration_id] = seen.get(message.arbitration_id, 0) + 1
    assert read_xcp_config(sim.a2l).can.optional_tl_subcommands == ("GET_SLAVE_ID", "GET_DAQ_ID", "SET_DAQ_ID")
    assert events == {0, 1}
    assert seen.get(0x7F6) and 0x7F4 not in seen and 0x7F5 not in seen
    assert read_back == [(CanId(0x7F1), False), (CanId(0x7F6), False), (CanId(0x7F3), True)]


def test_the_slave_refuses_set_daq_id_for_a_fixed_list_and_a_measurement_says_which(channel):
    with serve_demo({"interface": "virtual", "channel": channel}, profile=PROFILE, time_scale=None) as sim:
        with pytest.raises(InputError, match=r"DAQ list 2 sends on CAN id 0x7F3 \(the A2L's DAQ_LIST_CAN_ID 2 FIXED\)"):
            Session.open(sim.a2l, interface="virtual", channel=channel, daq_can_ids={2: 0x7F7})
        with Session.open(sim.a2l, interface="virtual", channel=channel) as session:
            with pytest.raises(XcpCommandError) as fixed:
                session.master.set_daq_id(2, CanId(0x7F7))
            with pytest.raises(XcpCommandError) as commands_id:  # the slave's own command id: refused too
                session.master.set_daq_id(0, CanId(0x7F0))
    assert (fixed.value.command, fixed.value.code) == ("TRANSPORT_LAYER_CMD SET_DAQ_ID", Err.OUT_OF_RANGE)
    assert commands_id.value.code == Err.OUT_OF_RANGE


def test_which_lists_the_master_moves_and_where():
    can_block = XcpOnCan(0x100, CanId(0x7F0), CanId(0x7F1), None, None, True, daq_list_can_ids=(
        XcpDaqListCanId(0, None), XcpDaqListCanId(1, None), XcpDaqListCanId(2, CanId(0x7F3))))
    assert assigned_daq_can_ids(can_block, {}) == ((0, CanId(0x7F1)), (1, CanId(0x7F1)))
    extended = CanId(0x1234, extended=True)
    assert assigned_daq_can_ids(can_block, {1: extended, 2: CanId(0x7F3), 5: CanId(0x7F9)}) == (
        (0, CanId(0x7F1)), (1, extended), (5, CanId(0x7F9)))
    with pytest.raises(InputError, match="DAQ list 2 sends on CAN id 0x7F3"):
        assigned_daq_can_ids(can_block, {2: CanId(0x7F4)})
    config = read_xcp_config(load_a2l(demo.a2l()))
    with pytest.raises(InputError, match="DAQ lists' CAN ids .* are XCP on CAN's; this is XCP on Ethernet"):
        link_settings(config, Connection(host="127.0.0.1", daq_can_ids=((0, CanId(0x7F6)),)))
    with pytest.raises(InputError, match="DAQ list 0's CAN id: CAN id 0x800 does not fit a standard frame"):
        daq_can_ids_of({0: 0x800})


def _read_until_refused(live) -> None:
    for _ in range(200):  # 40 s at most; the refusal comes after T1 + 3 of the 4 ms event's periods (0.3 s)
        live.read(0.2)


def test_a_daq_silent_from_its_start_says_where_get_daq_id_puts_the_lists(channel):
    """The daq-can-ids profile sends lists 0 and 1 on 0x7F2/0x7F3; the demo's A2L does not say so, so the master
    listens on 0x7F1 alone and hears no DTO. The ECU answers, so it is not lost (it was said so): the error names
    where the lists send and what the A2L should state, and the session goes on."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile="daq-can-ids", time_scale=1.0), \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        refusal = refusal_of_a_silent_daq(session, ["zsRailPressure", "xsDC"])
    assert refusal == (
        "DAQ: no DTO within 300 ms of the start, though the ECU answers: GET_DAQ_ID puts DAQ list 0 on 0x7F2 (fixed), "
        "list 1 on 0x7F3 (fixed), where this master does not listen (it listens on 0x7F1); the A2L's XCP_ON_CAN "
        "should say so: DAQ_LIST_CAN_ID 0 FIXED 0x7F2, DAQ_LIST_CAN_ID 1 FIXED 0x7F3")


def test_events_that_start_late_are_waited_for_when_the_lists_send_where_the_master_listens(channel):
    """An ECU whose events start only after the first silence (still starting; or a loaded host that heard
    nothing yet) is measured: GET_DAQ_ID says the lists send where the master listens, so it waits further
    silences before saying the events do not run (it refused at the first: a CI flake under load)."""
    asked = threading.Event()
    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=1.0) as sim, \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        send, get_daq_id = sim.ecu.dto_sink, session.master.get_daq_id
        sim.ecu.dto_sink = lambda sample: send(sample) if asked.is_set() else None  # events silent until asked

        def get_daq_id_then_events_run(daq_list: int):
            found = get_daq_id(daq_list)
            asked.set()
            return found

        session.master.get_daq_id = get_daq_id_then_events_run
        with session.measure(["zsRailPressure"]) as live:
            assert collect_until(live, lambda got: len(got) > 0)
        assert asked.is_set()


def test_a_link_lost_while_get_daq_id_is_asked_is_said_lost(channel, monkeypatch):
    """The bus breaks while the silent DAQ's GET_DAQ_ID is under way: the connection is lost (the window offers to
    reconnect), not 'though the ECU answers'."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile="daq-can-ids", time_scale=1.0), \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        def bus_broken(daq_list: int):
            raise ConnectionLostError("XCP on CAN (virtual)", "the bus broke")

        monkeypatch.setattr(session.master, "get_daq_id", bus_broken)
        with pytest.raises(ConnectionLostError, match="the bus broke"), \
                session.measure(["zsRailPressure"]) as live:
            _read_until_refused(live)


def test_an_ecu_without_get_daq_id_is_said_to_answer_and_one_gone_before_a_dto_is_lost(channel):
    """No GET_DAQ_ID (no TRANSPORT_LAYER_CMD): the refusal says so; an ECU whose power is cut right after the start
    answers neither GET_DAQ_ID nor SYNCH: lost, as before."""
    quiet = SlaveProfile("daq-can-ids-unsaid", "daq-can-ids without TRANSPORT_LAYER_CMD", "", can={
        "daq_can_ids": ((0, CanId(0x7F2)),), "without": frozenset({Cmd.TRANSPORT_LAYER_CMD})})
    with serve_demo({"interface": "virtual", "channel": channel}, profile=quiet, time_scale=1.0), \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
        with pytest.raises(WorkbenchError, match=r"though the ECU answers: it does not say where its DAQ lists send "
                                                 r"\(TRANSPORT_LAYER_CMD GET_DAQ_ID: ERR_CMD_UNKNOWN\); this master "
                                                 r"listens on 0x7F1: "), session.measure(["zsRailPressure"]) as live:
            _read_until_refused(live)
    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=1.0) as sim, \
            Session.open(sim.a2l, interface="virtual", channel=channel, timeouts=FAST) as session:
        with pytest.raises(ConnectionLostError, match="nothing from the ECU for .* while DAQ runs"), \
                session.measure(["zsRailPressure"]) as live:
            sim.power_off()  # before the first DTO, or just after it: lost either way
            _read_until_refused(live)


def test_a_power_cycle_forgets_the_ids_set_and_the_master_sets_them_again(channel):
    """SET_DAQ_ID's ids are RAM: after a power cycle list 1 is back on 0x7F5 (the simulator kept 0x7F6), and the
    next measurement of the reconnected session moves it again before its start."""
    with serve_demo({"interface": "virtual", "channel": channel}, profile=PROFILE, time_scale=1.0) as sim, \
            Session.open(sim.a2l, interface="virtual", channel=channel, daq_can_ids={1: 0x7F6}) as session:
        assert _measure_both_events(session) == {0, 1}
        assert session.master.get_daq_id(1) == (CanId(0x7F6), False)
        sim.power_off()
        sim.power_on()
        session.connect()
        assert session.master.get_daq_id(1) == (CanId(0x7F5), False)  # as after power-on
        assert _measure_both_events(session) == {0, 1}
        assert session.master.get_daq_id(1) == (CanId(0x7F6), False)


def test_a_list_silent_beside_others_says_where_get_daq_id_puts_it(channel, tmp_path):
    """The A2L states list 0's id of the daq-can-ids profile (0x7F2) but not list 1's (0x7F3): list 0's samples come,
    list 1's never would; the measurement says so instead of leaving xsDC without a value."""
    a2l = edited_a2l(tmp_path, "        MAX_DLC_REQUIRED\n",
                     "        MAX_DLC_REQUIRED\n        /begin DAQ_LIST_CAN_ID 0 FIXED 0x7F2 /end DAQ_LIST_CAN_ID\n")
    with serve_demo({"interface": "virtual", "channel": channel}, profile="daq-can-ids", time_scale=1.0), \
            Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as session:
        events, deadline = set(), time.monotonic() + 30.0  # said within T1 + 3 periods of the 50 ms event (0.6 s)
        with pytest.raises(WorkbenchError) as refused, session.measure(["zsRailPressure", "xsDC"]) as live:
            while time.monotonic() < deadline:
                events |= {batch.event for batch in live.read(0.2)}
    assert events == {0}
    assert str(refused.value) == (
        "DAQ: no DTO of list 1 within 300 ms of the start, though the others' came: GET_DAQ_ID puts DAQ list 1 on "
        "0x7F3 (fixed), where this master does not listen (it listens on 0x7F1, 0x7F2); the A2L's XCP_ON_CAN should "
        "say so: DAQ_LIST_CAN_ID 1 FIXED 0x7F3")


def test_an_ecu_gone_when_a_silent_list_is_asked_is_lost_as_when_none_came(channel, tmp_path, monkeypatch):
    """List 0's DTOs came, list 1 is silent, and the ECU answers neither GET_DAQ_ID nor SYNCH: the link is lost (every
    command says so at once, the window reconnects), in the words of a DAQ silent from its start."""
    from workbench.errors import EcuSilentError

    a2l = edited_a2l(tmp_path, "        MAX_DLC_REQUIRED\n",
                     "        MAX_DLC_REQUIRED\n        /begin DAQ_LIST_CAN_ID 0 FIXED 0x7F2 /end DAQ_LIST_CAN_ID\n")
    with serve_demo({"interface": "virtual", "channel": channel}, profile="daq-can-ids", time_scale=1.0), \
            Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as session:
        def gone(daq_list: int):
            raise EcuSilentError(session.master.link.describe(), "TRANSPORT_LAYER_CMD", 0.1)

        monkeypatch.setattr(session.master, "get_daq_id", gone)
        with pytest.raises(ConnectionLostError, match="nor an answer to GET_DAQ_ID or SYNCH"), \
                session.measure(["zsRailPressure", "xsDC"]) as live:
            _read_until_refused(live)
        assert session.master.link.lost is not None
