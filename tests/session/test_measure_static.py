"""session.measure(names), unchanged, against an ECU with static DAQ lists: values equal to the ECU's memory,
its timestamps, no allocation command, and a measurement the lists cannot hold refused before anything is sent."""

from __future__ import annotations

import time

import numpy as np
import pytest
from daq_samples import collect_until
from session_helpers import FAST

from workbench import Session
from workbench.a2l import read_xcp_config
from workbench.a2l.xcp import read_daq_events
from workbench.errors import InputError, XcpCommandError
from workbench.sim import serve_demo
from workbench.sim.profiles import SlaveProfile
from workbench.sim.xcp.parameters import DEMO_STATIC_LISTS
from workbench.xcp_protocol import Cmd


@pytest.fixture
def static_sim(channel):
    """The demo ECU with static DAQ lists on a virtual bus of its own; only the test moves its clock."""
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0, static_daq=True,
                    time_scale=None) as simulator:
        yield simulator


@pytest.fixture
def static_ecu(static_sim, channel):
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:
        yield session


def test_measure_by_name_gives_the_ecu_values_with_its_timestamps(static_sim, static_ecu):
    names = ["zsRailPressure", "zsSensVolt", "xsDC", "xsTankCtrlState", "xsFuelLevel"]
    batches: dict[str, list] = {"Task4ms": [], "Task50ms": []}
    with static_ecu.measure(names) as live:
        for step in range(1, 5):
            static_sim.advance(0.05)  # one Task50ms sample; the Task4ms ones before it arrive first
            deadline = time.monotonic() + 3.0
            while len(batches["Task50ms"]) < step and time.monotonic() < deadline:
                for batch in live.read(0.05):
                    batches[batch.event_name].append(batch)
            for event, event_batches in batches.items():  # the last samples are what the ECU's memory holds now
                for name, values in event_batches[-1].values.items():
                    assert np.array_equal(values[-1], static_ecu.read(name)), (step, event, name)
        assert live.stats.lost == 0
    assert set(batches["Task4ms"][0].values) == {"zsRailPressure", "zsSensVolt"}
    fast = np.concatenate([b.time for b in batches["Task4ms"]])
    assert len(fast) >= 48 and np.allclose(np.diff(fast), 0.004)  # ECU time: the host got them in four bursts
    assert np.allclose(np.diff(np.concatenate([b.time for b in batches["Task50ms"]])), 0.05)
    faults = static_sim.ecu.faults
    assert sum(faults.commands_seen(c) for c in (Cmd.FREE_DAQ, Cmd.ALLOC_DAQ, Cmd.ALLOC_ODT, Cmd.ALLOC_ODT_ENTRY)) == 0
    assert faults.commands_seen(Cmd.CLEAR_DAQ_LIST) == 4 and faults.commands_seen(Cmd.GET_DAQ_LIST_INFO) == 4


def test_a_measurement_the_static_lists_cannot_hold_is_refused_before_anything_is_configured(static_sim, static_ecu):
    model = static_ecu.model
    on = {event: [name for name in model.names("MEASUREMENT") if read_daq_events(model.block(name)).preferred == event]
          for event in (0, 1)}  # 52 bytes on Task4ms, 69 on Task50ms
    with pytest.raises(InputError) as refused:
        static_ecu.measure(on[0] + on[1], event="Task50ms").start()
    assert str(refused.value) == (
        "the slave's static DAQ lists cannot take this measurement: event 1 (Task50ms) fits no list (list 0 samples "
        "event 0 (Task4ms) only; list 1 has 12 ODTs of 3 entries, the signals need 18; list 2 has 16 ODTs of 4 entries, the signals "
        "need 18; list 3 has 4 ODTs of 4 entries, the signals need 18); measure fewer signals or events at once")
    assert static_sim.ecu.faults.commands_seen(Cmd.WRITE_DAQ) == 0
    with static_ecu.measure(on[0]) as live:  # nothing was left half configured; Task4ms's signals fill list 0 exactly
        static_sim.advance(0.01)
        deadline = time.monotonic() + 3.0
        while not (batches := live.read(0.05)) and time.monotonic() < deadline:
            pass
        assert batches and batches[0].event_name == "Task4ms"


def test_closing_the_session_stops_static_daq(static_sim, channel):
    session = Session.open(interface="virtual", channel=channel, timeouts=FAST)
    live = session.measure(["xsDC"]).start()
    assert static_sim.ecu.slave.daq.lists[1].running
    session.close()
    assert not live.running and not any(daq.running for daq in static_sim.ecu.slave.daq.lists)


def test_a_static_slave_without_get_daq_list_info_is_planned_from_the_a2ls_daq_lists(channel):
    """GET_DAQ_LIST_INFO is optional: the A2L's DAQ_LIST blocks (MAX_ODT, MAX_ODT_ENTRIES, EVENT_FIXED) stand in for it
    (the measurement failed 'GET_DAQ_LIST_INFO failed: ERR_CMD_UNKNOWN'); an A2L without them says which is missing."""
    quiet = SlaveProfile("static-no-list-info", "static DAQ without GET_DAQ_LIST_INFO", "",
                         xcp={"without": frozenset({Cmd.GET_DAQ_LIST_INFO})}, daq={"static_lists": DEMO_STATIC_LISTS})
    with serve_demo({"interface": "virtual", "channel": channel}, profile=quiet) as sim:
        assert [daq.max_odt for daq in read_xcp_config(sim.a2l).daq.lists] == [8, 12, 16, 4]
        with Session.open(sim.a2l, interface="virtual", channel=channel, timeouts=FAST) as session, \
                session.measure(["zsRailPressure", "xsDC"]) as live:
            batches = collect_until(live, lambda got: {b.event_name for b in got} == {"Task4ms", "Task50ms"})
            assert [daq.number for daq in live.stream.plan.lists] == [0, 1]  # the lists fixed to their events
        assert {b.event_name for b in batches} == {"Task4ms", "Task50ms"}
        with Session.open(interface="virtual", channel=channel, timeouts=FAST) as session:  # the demo's A2L: none
            with pytest.raises(XcpCommandError, match=r"DAQ list 0 \(the A2L's DAQ has no DAQ_LIST 0 to tell its "
                                                      r"ODTs\): XCP GET_DAQ_LIST_INFO failed: ERR_CMD_UNKNOWN"):
                session.measure(["zsRailPressure"]).start()
