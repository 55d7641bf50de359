"""What the window says about a measurement the ECU does not take as asked: a signal its DAQ refuses to sample is
named while the others are measured (it stopped every plot), and a slave without DAQ timestamps is said to be timed
by the master's receive time."""

from __future__ import annotations

from gui_helpers import WAIT_MS, open_window

from workbench import demo
from workbench.gui.project import Connection, PlotSpec, Project

BOGUS = ('/begin MEASUREMENT zzNowhere "at an address the ECU does not sample" UWORD NO_COMPU_METHOD 0 0 0 65535 '
         "ECU_ADDRESS 0x12345670 /end MEASUREMENT\n    ")


def project_on(channel: str, a2l, signals) -> Project:
    return Project(a2l=a2l, connection=Connection(interface="virtual", channel=channel),
                   plots=[PlotSpec("Measurement", list(signals))])


def test_a_signal_the_ecu_refuses_to_sample_is_named_and_the_others_are_measured(demo_ecu, channel, tmp_path, qtbot):
    text = demo.a2l().read_text(encoding="utf-8")
    at = text.index("/begin MEASUREMENT")
    a2l = tmp_path / "nowhere.a2l"
    a2l.write_text(text[:at] + BOGUS + text[at:], encoding="utf-8")
    window = open_window(qtbot, project_on(channel, a2l, ["zsRailPressure", "zzNowhere", "xsDC"]))
    qtbot.waitUntil(lambda: bool(window.errors), timeout=WAIT_MS)
    (box,) = window.errors
    assert box.text().startswith("not measured by DAQ")
    assert "zzNowhere: sampling 2 bytes at 0x12345670: XCP WRITE_DAQ failed: ERR_OUT_OF_RANGE (0x22)" in box.text()
    state = window.hub.acquisition.state
    qtbot.waitUntil(lambda: state.running and state.samples > 0, timeout=WAIT_MS)
    assert state.signals == ("xsDC", "zsRailPressure") and list(state.refused) == ["zzNowhere"]
    window.status.refresh()
    assert window.status.daq.text().endswith(" · 1 not measurable")
    assert "not measured: zzNowhere: sampling 2 bytes" in window.status.daq.toolTip()
    plot = window.plots[0]
    row = plot.signals.index("zzNowhere")  # the legend says it where the value would be
    qtbot.waitUntil(lambda: plot.legend.item(row, 1).text() == "no DAQ", timeout=WAIT_MS)
    assert plot.legend.item(row, 1).toolTip().startswith("not measured: sampling 2 bytes at 0x12345670: XCP WRITE_DAQ")
    plot.add_signals(["zsTank1Pressure"])  # another set: the refused one is not asked for again
    qtbot.waitUntil(lambda: state.running and "zsTank1Pressure" in state.signals, timeout=WAIT_MS)
    assert "zzNowhere" not in state.signals and len(window.errors) == 1


def test_a_signal_on_an_event_the_ecu_lacks_is_named_with_its_event(demo_ecu, channel, tmp_path, qtbot):
    """An A2L of another build names an event the ECU does not have: SET_DAQ_LIST_MODE refused stopped every plot."""
    text = demo.a2l().read_text(encoding="utf-8")
    at = text.index("/begin MEASUREMENT")
    elsewhere = BOGUS.replace("zzNowhere", "zzElsewhere").replace("ECU_ADDRESS 0x12345670", (
        "ECU_ADDRESS 0x4002004C /begin IF_DATA XCP /begin DAQ_EVENT VARIABLE /begin DEFAULT_EVENT_LIST EVENT 0x0009 "
        "/end DEFAULT_EVENT_LIST /end DAQ_EVENT /end IF_DATA"))
    a2l = tmp_path / "elsewhere.a2l"
    a2l.write_text(text[:at] + elsewhere + text[at:], encoding="utf-8")
    window = open_window(qtbot, project_on(channel, a2l, ["zsRailPressure", "zzElsewhere"]))
    qtbot.waitUntil(lambda: bool(window.errors), timeout=WAIT_MS)
    assert ("zzElsewhere: XCP SET_DAQ_LIST_MODE failed: ERR_OUT_OF_RANGE (0x22) (its DAQ event, event 9: one the ECU "
            "does not have?)") in window.errors[0].text()
    state = window.hub.acquisition.state
    qtbot.waitUntil(lambda: state.running and state.samples > 0, timeout=WAIT_MS)
    assert state.signals == ("zsRailPressure",)


def test_a_slave_without_daq_timestamps_is_said_to_be_timed_by_the_receive_time(channel, tmp_path, qtbot):
    from workbench.sim import serve_demo

    with serve_demo({"interface": "virtual", "channel": channel}, profile="no-timestamp") as simulator:
        a2l = tmp_path / "no-timestamp.a2l"  # the profile's A2L, as `workbench sim --write-a2l` writes it
        a2l.write_bytes(simulator.a2l.source.file_bytes(simulator.a2l.data))
        window = open_window(qtbot, project_on(channel, a2l, ["zsRailPressure"]))
        state = window.hub.acquisition.state
        qtbot.waitUntil(lambda: state.running and state.samples > 0, timeout=WAIT_MS)
        window.status.refresh()
        assert window.status.daq.text().endswith(" · receive time")
        assert "timed by the master's receive time" in window.status.daq.toolTip()
        window.close()
