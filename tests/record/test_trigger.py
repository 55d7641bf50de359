"""Start and stop triggers: conditions as a CANape user writes them, the gate that holds the pre-trigger seconds
(bounded) and lets nothing through after the stop, and a recording of the demo ECU started and stopped by a fixed
rail pressure."""

from __future__ import annotations

import numpy as np
import pytest
from mdf_reading import channel, group_index, master

from workbench.errors import InputError, WorkbenchError
from workbench.record import Condition, Recorder, Trigger
from workbench.record.trigger import TriggerGate


def test_conditions_compare_numbers_and_texts():
    assert Condition.parse("zsRailPressure>=20") == Condition("zsRailPressure", ">=", 20.0)
    assert Condition.parse("zsRailPressure > 2.5bar") == Condition("zsRailPressure", ">", 2.5, unit="bar")
    state = Condition.parse("xsTankCtrlState == 'TANK2_ON'")
    assert state.first(np.array([b"OFF", b"TANK1_ON", b"TANK2_ON"], dtype=object)) == 2
    assert Condition.parse("x < -1.5").first(np.array([0.0, -1.0, -2.0])) == 2
    assert Condition.parse("x != 0").first(np.zeros(3)) is None
    for text, message in (("zsRailPressure 20", "write NAME OP VALUE"), ("x > high", "compares with a number"),
                          ("x >>> 3", "write NAME OP VALUE"), ("x => 3", "write NAME OP VALUE"),
                          ("x = 3", "write NAME OP VALUE")):
        with pytest.raises(InputError, match=message):
            Condition.parse(text)


def test_the_gate_holds_only_the_pre_trigger_seconds_and_nothing_after_the_stop():
    gate = TriggerGate(Trigger(Condition("v", ">", 5), Condition("v", "<", 0), pre_s=0.1))
    times = np.arange(0, 1.0, 0.01)
    values = np.where((times >= 0.5) & (times < 0.8), 10.0, 1.0)
    values[times >= 0.8] = -1.0
    written = []
    for start in range(0, 100, 10):  # reads of 10 samples: two groups, the second's records the first's times
        chunk = slice(start, start + 10)
        gate.observe(times[chunk], {"v": values[chunk]})
        for group in (0, 1):
            written += gate.passed(group, times[chunk], [values[chunk]], {"samples": 1})
        if start < 50:
            assert written == [] and sum(len(entry[1]) for entry in gate._held) <= 2 * 20  # bounded
    assert gate.started_s == pytest.approx(0.5) and gate.stopped_s == pytest.approx(0.8) and gate.done
    for group in (0, 1):
        kept = np.concatenate([entry[1] for entry in written if entry[0] == group])
        assert np.allclose(kept, times[(times >= 0.4 - 1e-9) & (times <= 0.8 + 1e-9)])


def test_a_recording_starts_and_stops_on_conditions(session, tmp_path, read_mdf):
    """A fixed rail pressure (zfRAILPRESSURE_EN/_VALUE) starts it, its release ends it by itself."""
    path = tmp_path / "triggered.mf4"
    trigger = Trigger(Condition.parse("zsRailPressure > 35"), Condition.parse("zsRailPressure < 30"), pre_s=0.2)
    with Recorder(session, path, ["zsRailPressure", "xsTankCtrlState"], trigger=trigger, raw_can=True) as rec:
        rec.wait(0.3)  # durations count from when DAQ ran
        session.write("zfRAILPRESSURE_VALUE", 40.0)
        session.write("zfRAILPRESSURE_EN", 1)
        rec.wait(0.8)
        session.write("zfRAILPRESSURE_EN", 0)
        rec.wait(60)  # returns when the stop condition ended it
        assert not rec.running
    stats = rec.stats
    mdf = read_mdf(path)
    pressure = channel(mdf, "Task4ms", "zsRailPressure")
    started = pressure.timestamps[np.argmax(pressure.samples > 35)]
    assert stats.started_s == pytest.approx(started) and "started at" in stats.describe()
    assert pressure.timestamps[0] == pytest.approx(started - 0.2, abs=0.0041)  # the pre-trigger 0.2 s, no more
    assert np.all(pressure.samples[pressure.timestamps < started] < 35)
    assert pressure.samples[-1] < 30 and np.all(pressure.samples[pressure.timestamps > started][:-1] >= 30)
    for acq_name in ("Task50ms", "CAN2"):  # every group within the same window
        times = master(mdf, acq_name)
        assert times[0] >= started - 0.2 - 1e-9 and times[-1] <= pressure.timestamps[-1] + 1e-9, acq_name
    assert stats.samples == sum(mdf.groups[group_index(mdf, name)].channel_group.cycles_nr
                                for name in ("Task4ms", "Task50ms"))
    said = "start when zsRailPressure &gt; 35 (0.2 s before kept), stop when zsRailPressure &lt; 30"  # XML
    assert said in mdf.header.comment


def test_a_condition_on_a_signal_not_recorded_is_refused(session, tmp_path):
    with pytest.raises(InputError, match="trigger on zsRailPressure: a condition's signal must be recorded"):
        Recorder(session, tmp_path / "x.mf4", ["xsDC"], trigger=Trigger(Condition.parse("zsRailPressure > 1")))
    assert not (tmp_path / "x.mf4").exists()


@pytest.mark.parametrize("condition, message", [
    ("xsTankCtrlState == OF", r"trigger condition 'xsTankCtrlState == OF': 'OF' is not one of its values \(OFF, "),
    ("xsDC == high", "trigger condition 'xsDC == high': xsDC has no value table; compare it with a number"),
    ("xsTankCtrlStat == OFF", "unknown symbol 'xsTankCtrlStat'.*did you mean 'xsTankCtrlState'"),
])
def test_a_condition_that_could_never_be_met_is_refused(session, tmp_path, condition, message):
    """A typo in a text or a name: the recording would have waited for ever (start) or never stopped."""
    with pytest.raises(WorkbenchError, match=message):  # an InputError or UnknownSymbolError: exit 2
        Recorder(session, tmp_path / "x.mf4", ["xsDC", "xsTankCtrlState"], trigger=Trigger(Condition.parse(condition)))
    assert not (tmp_path / "x.mf4").exists()


def test_a_text_in_another_case_is_the_table_s(session, tmp_path):
    recorder = Recorder(session, tmp_path / "x.mf4", ["xsTankCtrlState"],
                        trigger=Trigger(stop=Condition.parse("xsTankCtrlState != tank2_on")))
    assert str(recorder.trigger.stop) == "xsTankCtrlState != TANK2_ON"  # compared as the samples read
