"""DAQ by name against the simulated ECU: events from the A2L, physical batches, ECU time, one at a time."""

from __future__ import annotations

import struct
import threading
import time

import numpy as np
import pytest
from daq_samples import collect_until, samples
from session_helpers import FAST, edited_a2l
from xcp_commands import CommandLog

from workbench import Session
from workbench.errors import InputError


def test_each_signal_is_sampled_on_its_a2l_event(ecu):
    with ecu.measure(["zsRailPressure", "xsDC", "csPCM_TO_FLCU_002_TargetRailPressure"]) as live:
        batches = collect_until(live, lambda got: samples(b for b in got if b.event_name == "Task100ms") > 5
                                and {b.event_name for b in got} == {"Task4ms", "Task50ms", "Task100ms"})
    by_event = {}
    for batch in batches:
        by_event.setdefault(batch.event_name, []).append(batch)
    assert set(by_event) == {"Task4ms", "Task50ms", "Task100ms"}
    fast = np.concatenate([b.time for b in by_event["Task4ms"]])
    assert np.allclose(np.diff(fast), 0.004)
    assert set(by_event["Task50ms"][0].values) == {"xsDC"}
    target = np.concatenate([b.values["csPCM_TO_FLCU_002_TargetRailPressure"] for b in by_event["Task100ms"]])
    assert target[-1] == pytest.approx(25.0)  # the PCM's request, decoded by the ECU
    assert live.stats.lost == 0


def test_an_event_named_by_the_user_takes_every_signal(ecu):
    with ecu.measure(["zsRailPressure", "xsDC", "zsSensVolt"], event="Task100ms") as live:
        batches = collect_until(live, lambda got: samples(got) > 3)
    assert {b.event_name for b in batches} == {"Task100ms"}
    assert batches[-1].values["zsSensVolt"].shape[1:] == (4,)
    with pytest.raises(InputError, match="no DAQ event 'Task7ms'"):
        ecu.measure(["xsDC"], event="Task7ms")


def test_samples_go_to_a_callback(ecu):
    arrived = []
    done = threading.Event()

    def on_samples(batch):
        arrived.append(batch)
        if sum(len(b) for b in arrived) >= 20:
            done.set()

    with ecu.measure(["zsRailPressure"]) as live:
        live.on_samples(on_samples)
        assert done.wait(3.0)
    assert all(b.values["zsRailPressure"].dtype.kind == "f" for b in arrived)


def test_one_daq_measurement_at_a_time(ecu):
    with ecu.measure(["zsRailPressure"]):
        with pytest.raises(InputError, match="a DAQ measurement is running"):
            ecu.measure(["xsDC"]).start()
    with ecu.measure(["xsDC"]) as live:  # after the first stopped, a new one may start
        assert collect_until(live, samples)


def test_curves_and_maps_are_polled_not_sampled(ecu):
    with pytest.raises(InputError, match=r"zvRailPConv is a CHARACTERISTIC \(CURVE\): DAQ samples MEASUREMENTs and "
                                         "VALUE or VAL_BLK calibrations"):
        ecu.measure(["zvRailPConv"])


def test_a_value_calibration_is_sampled_as_a_measurement_would_be(ecu):
    """As CANape measures a calibration (XCPlite gives its stack parameters a DAQ_EVENT and writes its measured arrays
    as VAL_BLKs): the value as the ECU holds it, converted, on the event named."""
    with ecu.measure(["xsSWITCH_TANK_THR", "zsRailPressure"], event="Task50ms") as live:
        before = collect_until(live, lambda got: samples(got) > 2)
        ecu.write("xsSWITCH_TANK_THR", 21.0)
        after = collect_until(live, lambda got: any(b.values["xsSWITCH_TANK_THR"][-1] == 21.0 for b in got))
        before, after = (np.concatenate([b.values["xsSWITCH_TANK_THR"] for b in read]) for read in (before, after))
    assert set(before) == {20.0} and after[-1] == 21.0


def test_closing_the_session_stops_daq(sim, channel):
    from workbench import Session

    session = Session.open(interface="virtual", channel=channel, timeouts=FAST)
    live = session.measure(["zsRailPressure"]).start()
    collect_until(live, samples)
    session.close()
    assert not live.running
    assert not any(daq.running for daq in sim.ecu.slave.daq.lists)


def test_a_prescaler_the_ecu_does_not_offer_is_refused(ecu):
    with pytest.raises(InputError, match="no prescaler"):
        ecu.measure(["xsDC"], prescaler=2).start()
    with ecu.measure(["xsDC"]) as live:  # nothing was left half configured
        assert collect_until(live, samples)


WAIT_S = 10.0  # a read's timeout that a loaded machine never comes near when nothing waits for it


def test_a_session_whose_ecu_vanished_says_so_closes_quickly_and_frees_the_bus(sim, channel):
    from workbench import ConnectionLostError, Session

    session = Session.open(interface="virtual", channel=channel, timeouts=FAST)
    live = session.measure(["zsRailPressure"]).start()
    collect_until(live, samples)
    sim.power_off()
    with pytest.raises(ConnectionLostError, match="XCP on CAN .*: nothing from the ECU for"):
        session.read("xsDC")  # the DTOs stopped: said by the read that notices it, within max(T1, 3 periods)
    with pytest.raises(ConnectionLostError):  # the samples that came before the loss (on a loaded machine
        for _ in range(100):                  # some may still wait to be read), then the loss
            live.read(0)
    started = time.monotonic()
    for _ in range(2):  # at once from then on: a read does not wait out its timeout (the second finds no
        with pytest.raises(ConnectionLostError):  # DTO's wake-up left over from before the loss)
            live.read(WAIT_S)
    assert time.monotonic() - started < WAIT_S
    with CommandLog(channel) as log:
        session.close()  # nothing is sent to a lost ECU: no stop commands waiting out their timeouts
        assert log.take() == []
    assert session.link.closed and not live.running


def test_samples_lost_on_a_bus_too_slow_for_the_plan_say_so(channel):
    """Every zs* signal on the 4 ms task asks 2,000 DTOs/s of a bus that carries about 1,000 at 125 kbit/s (the
    simulator paces its frames as that bus would): the samples lost are put down to it, with what to do (the
    measure summary said only '61 lost'; user trial 6)."""
    from workbench import Session
    from workbench.sim import serve_demo

    signals = [f"zs{name}" for name in ("SensVolt", "Tank1VoltFilt", "Tank2VoltFilt", "ManifoldVoltFilt", "RailVoltFilt",
                                        "RailPressureTmp", "Tank1Pressure", "Tank2Pressure", "ManifoldPressure",
                                        "RailPressure")]
    bus = {"interface": "virtual", "channel": channel, "bitrate": 125_000}
    with serve_demo(bus), Session.open(**bus, timeouts=FAST) as ecu:
        with ecu.measure(signals) as live:
            deadline = time.monotonic() + 10.0
            while not live.stats.lost and time.monotonic() < deadline:
                live.read(0.05)
        assert live.stream.dtos_per_second == pytest.approx(2000.0)
        assert live.loss_cause() == ("the DAQ lists send 2,000 DTOs/s, 200% of the about 1,000 frames/s CAN carries at "
                                     "125 kbit/s: measure fewer signals on the fast events, or on a slower event")


def test_the_dtos_are_read_as_the_ecu_reports_them_not_as_its_a2l_says(tmp_path, sim, channel):
    """XCPlite's A2L says IDENTIFICATION_FIELD_TYPE_RELATIVE_BYTE while its GET_DAQ_PROCESSOR_INFO (and its DTOs) use
    RELATIVE_WORD_ALIGNED: the slave's word is the one that counts. Here the demo slave sends ABSOLUTE PIDs and its A2L
    is edited to say RELATIVE_BYTE."""
    from session_helpers import edited_a2l

    from workbench import Session

    a2l = edited_a2l(tmp_path, "IDENTIFICATION_FIELD_TYPE_ABSOLUTE\n", "IDENTIFICATION_FIELD_TYPE_RELATIVE_BYTE\n")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        assert ecu.config.daq.identification_field == "RELATIVE_BYTE"
        with ecu.measure(["zsRailPressure", "xsDC"]) as live:
            batches = collect_until(live, lambda got: samples(got) > 20)
        assert live.stream.plan.identification_field == "ABSOLUTE"
        assert {batch.event_name for batch in batches} >= {"Task4ms"} and live.stats.lost == 0
        assert live.stats.unknown == 0  # every DTO was a sample of the plan's lists


def test_a_signal_longer_than_a_dto_is_split_over_odts_and_measured_whole(sim, channel, tmp_path):
    """An 8-byte double on classic CAN (MAX_DTO 8: a DTO carries 7 bytes after its PID, the first 3 after its
    timestamp, an ODT entry 4): its bytes go in entries of two ODTs of one sample, and come back as the double."""
    before = "    /begin MEASUREMENT\n      /* Name                   */ xsTankCtrlState"
    double = ('    /begin MEASUREMENT zdDouble "8 bytes in CAL RAM" FLOAT64_IEEE NO_COMPU_METHOD 0 0 -1e12 1e12\n'
              "      ECU_ADDRESS 0x40000010\n    /end MEASUREMENT\n\n")
    with Session.open(edited_a2l(tmp_path, before, double + before), interface="virtual", channel=channel,
                      timeouts=FAST) as session:
        kept = session.master.read(0x40000010, 8)
        try:
            session.master.write(0x40000010, struct.pack("<d", 12345.678))
            with session.measure(["zdDouble"]) as live:
                batches = collect_until(live, lambda got: samples(got) > 3)
                odts = live.stream.plan.lists[0].odts
                stamped = live.ecu_timestamps
        finally:
            session.master.write(0x40000010, kept)
    assert stamped and len([odt for odt in odts if odt.entries]) == 2
    assert np.all(np.concatenate([b.values["zdDouble"] for b in batches]) == 12345.678)
