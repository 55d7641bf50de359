"""Tools ▸ Requirement tests…: ``workbench test`` run in a process of its own from the window, each verdict in the
table as its test ends, Cancel as Ctrl-C, the report at the end; on the window's own ECU, released while the tests
run and connected again after them; errors in one line each (a bad folder, no test found, the ECU lost)."""

from __future__ import annotations

import pytest
from gui_helpers import WAIT_MS, offline_window, open_window

RUN_MS = 180_000  # a run starts python, pytest and the tests' ECUs: generous on a loaded machine

TESTS = '''
import time
from pathlib import Path

import pytest
from workbench.testbench import requirement, within


@requirement("R1")
def test_on_the_ecu(ecu):
    ecu.watch("xsDC")
    ecu.expect("xsDC", within(0, 100), for_s=0.1)


@requirement("R2")
def test_fails():
    assert 1 + 1 == 3


@requirement("R3")
def test_broke():
    raise ValueError("no such thing")


@pytest.fixture
def broken():
    raise RuntimeError("cannot start")


@requirement("R4")
def test_cannot_start(broken):
    pass


@requirement("R5")
def test_waits():
    while not Path(__file__).with_name("go").exists():
        time.sleep(0.05)
'''


def _states(dialog) -> dict[str, str]:
    return {row["nodeid"].split("::")[-1]: dialog.model.data(dialog.model.index(number, 0))
            for number, row in enumerate(dialog.model.rows)}


def _column(dialog, name: str, column: int) -> str:
    number = next(n for n, row in enumerate(dialog.model.rows) if row["nodeid"].endswith(name))
    return dialog.model.data(dialog.model.index(number, column))


@pytest.fixture
def opened(qtbot, monkeypatch):
    from PySide6.QtGui import QDesktopServices

    window = offline_window(qtbot)
    opened = []
    monkeypatch.setattr(QDesktopServices, "openUrl", lambda url: opened.append(url.toString()) or True)
    window.tests_action.trigger()
    yield window.tests_dialog, opened
    window.close()


def test_each_verdict_shows_as_its_test_ends_and_cancel_stops_the_run(qtbot, opened, tmp_path, monkeypatch):
    dialog, urls = opened
    (tmp_path / "tests").mkdir()
    monkeypatch.chdir(tmp_path / "tests")  # the node ids below: see tests/testbench/test_run.py
    (tmp_path / "tests" / "test_mine.py").write_text(TESTS, encoding="utf-8")
    assert not dialog.ecu_radio.isEnabled() and "not connected" in dialog.ecu_note.text()  # offline: no ECU to lend
    dialog.paths.setText(str(tmp_path / "tests"))
    dialog.paths.textEdited.emit(dialog.paths.text())
    dialog.folder.setText(str(tmp_path / "report"))
    dialog.run_button.click()
    assert dialog.own_radio.isChecked() and not dialog.run_button.isEnabled() and dialog.cancel_button.isEnabled()
    # the first four ended while the run goes on (the last waits for a file nobody writes)
    qtbot.waitUntil(lambda: _states(dialog).get("test_waits") == "running", timeout=RUN_MS)
    assert _states(dialog) == {"test_on_the_ecu": "PASSED", "test_fails": "FAILED", "test_broke": "NOT JUDGED",
                               "test_cannot_start": "ERROR", "test_waits": "running"}
    assert _column(dialog, "test_fails", 1) == "R2" and _column(dialog, "test_fails", 4) == "assert (1 + 1) == 3"
    assert _column(dialog, "test_broke", 4) == "ValueError: no such thing"
    assert "RuntimeError: cannot start" in _column(dialog, "test_cannot_start", 4)
    assert dialog.status.text().startswith("Running: 1 passed, 1 failed, 1 not judged, 1 error; 1 running")

    with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS) as ended:
        dialog.cancel_button.click()
    assert ended.args[0].exit_code == 130  # interrupted as Ctrl-C interrupts it, not killed
    assert _states(dialog)["test_waits"] == "CANCELLED"
    assert dialog.status.text().startswith("Cancelled in ")
    assert dialog.message.text().startswith("Cancelled: the report holds the tests that ended")
    assert "INTERRUPTED" in (tmp_path / "report" / "report.html").read_text(encoding="utf-8")
    assert dialog.run_button.isEnabled() and dialog.open_report_button.isEnabled()
    dialog.open_report_button.click()
    dialog.open_folder_button.click()
    failed = dialog.model.index(next(n for n, row in enumerate(dialog.model.rows) if row["state"] == "failed"), 2)
    dialog.table.doubleClicked.emit(failed)  # the failed test in the report
    report = (tmp_path / "report" / "report.html").as_uri()
    assert urls == [report, (tmp_path / "report").as_uri(), f"{report}#t-test-mine-py--test-fails"]
    assert 'id="t-test-mine-py--test-fails"' in (tmp_path / "report" / "report.html").read_text(encoding="utf-8")

    assert dialog.rerun_button.isEnabled()  # the failed, the not judged and the one that could not start, again
    with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS) as ended:
        dialog.rerun_button.click()
    assert _states(dialog) == {"test_fails": "FAILED", "test_broke": "NOT JUDGED", "test_cannot_start": "ERROR"}
    assert ended.args[0].options.paths == [f"{tmp_path / 'tests' / 'test_mine.py'}::{name}"
                                           for name in ("test_fails", "test_broke", "test_cannot_start")]


def test_a_bad_folder_and_no_test_found_are_one_line_each(qtbot, opened, tmp_path):
    from PySide6.QtTest import QTest

    dialog, _ = opened
    dialog.req.setFocus()
    QTest.keyClicks(dialog.req, "SW_REQ_ID_001.1 006.")  # the FLCU suite's catalogue completes the id being typed
    completer = dialog.req_completer
    assert completer.completionCount() == 2  # SW_REQ_ID_006.1 and .2
    assert completer.currentCompletion() == "SW_REQ_ID_001.1 SW_REQ_ID_006.1 "
    dialog.req.clear()
    dialog.paths.setText(str(tmp_path / "missing"))
    dialog.own_radio.setChecked(True)
    dialog.folder.setText(str(tmp_path / "report"))
    with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS):
        dialog.run_button.click()
    assert dialog.message.text() == f"Not run: {tmp_path / 'missing'}: no such test file or folder"
    assert dialog.model.rows == [] and not dialog.open_report_button.isEnabled()

    dialog.suite_radio.setChecked(True)  # the FLCU suite, but a name no test has
    dialog.keyword.setText("no_test_is_named_so")
    with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS):
        dialog.run_button.click()
    assert dialog.message.text() == "Not run: no tests found (check PATH, -k and --req)"


def _on_udp(port: int):
    """A bus another process reaches (the tests' process), and the demo project connecting there."""
    from workbench.gui.project import Connection, demo_project

    bus = {"interface": "udp_multicast", "channel": "239.74.163.66", "port": port}
    project = demo_project()
    project.connection = Connection(interface="udp_multicast", channel=bus["channel"], bus_kwargs={"port": port})
    return bus, project


ON_THE_ECU = '''
from workbench.testbench import requirement, within


@requirement("R1")
def test_reads_the_duty_cycle(ecu):
    ecu.watch("xsDC")
    ecu.expect("xsDC", within(0, 100), for_s=0.1)
'''


def test_on_the_windows_ecu_the_window_lets_go_of_it_and_connects_again(qtbot, tmp_path, free_udp_port, monkeypatch):
    from workbench.sim import serve_demo

    bus, project = _on_udp(free_udp_port)
    (tmp_path / "test_ecu.py").write_text(ON_THE_ECU, encoding="utf-8")
    with serve_demo(bus):
        window = open_window(qtbot, project)
        dialog = window.open_requirement_tests()
        assert dialog.ecu_radio.isEnabled() and "disconnects while the tests run" in dialog.ecu_note.text()
        dialog.ecu_radio.setChecked(True)
        assert not dialog.workers.isEnabled()  # one master at a time: no -n
        dialog.paths.setText(str(tmp_path / "test_ecu.py"))
        dialog.own_radio.setChecked(True)
        dialog.folder.setText(str(tmp_path / "report"))
        in_use = []
        dialog.model.dataChanged.connect(lambda *_: in_use.append((window.controller.session,
                                                                     window.status.daq.text())))
        with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS) as ended:
            dialog.run_button.click()
        assert dialog.isModal() is False and in_use  # released while the test ran, and the window says why
        assert {session for session, _ in in_use} == {None}
        assert all(daq.startswith("DAQ paused: the requirement tests use the ECU since ") for _, daq in in_use)
        assert f"port={free_udp_port}" in " ".join(ended.args[0].command)
        assert _states(dialog) == {"test_reads_the_duty_cycle": "PASSED"} and ended.args[0].exit_code == 0
        assert not dialog.message.isVisible()
        qtbot.waitUntil(lambda: window.controller.session is not None, timeout=WAIT_MS)  # connected again
        window.close()
    assert not window.errors


def test_the_demo_ecu_on_a_virtual_bus_cannot_be_lent_and_closing_the_window_stops_a_run(qtbot, project, demo_ecu,
                                                                                          tmp_path):
    window = open_window(qtbot, project)
    dialog = window.open_requirement_tests()
    assert not dialog.ecu_radio.isEnabled()
    assert "virtual bus" in dialog.ecu_note.text() and "only this process reaches" in dialog.ecu_note.text()
    (tmp_path / "test_forever.py").write_text("import time\n\ndef test_forever():\n    time.sleep(600)\n")
    dialog.paths.setText(str(tmp_path / "test_forever.py"))
    dialog.own_radio.setChecked(True)
    dialog.folder.setText(str(tmp_path / "report"))
    dialog.run_button.click()
    run = dialog.run
    qtbot.waitUntil(lambda: _states(dialog).get("test_forever") == "running", timeout=RUN_MS)
    window.close()  # no process of the run outlives the window
    assert run.process.poll() is not None and dialog.run is None


LOSES_THE_ECU = '''
from pathlib import Path

from workbench.testbench import requirement, within


@requirement("R1")
def test_long(ecu):
    ecu.watch("xsDC")
    ecu.wait_until("xsDC", within(0, 100), timeout=10)
    Path(__file__).with_name("measuring").write_text("yes")
    ecu.expect("xsDC", within(0, 100), for_s=120)


@requirement("R2")
def test_after(ecu):
    pass
'''


def test_the_ecu_lost_during_a_test_is_one_message_and_the_window_stays_disconnected(qtbot, tmp_path,
                                                                                      free_udp_port, monkeypatch):
    from workbench.sim import serve_demo

    monkeypatch.chdir(tmp_path)  # the node id in the message: see tests/testbench/test_run.py

    bus, project = _on_udp(free_udp_port)
    (tmp_path / "test_lost.py").write_text(LOSES_THE_ECU, encoding="utf-8")
    with serve_demo(bus):
        window = open_window(qtbot, project)
        dialog = window.open_requirement_tests()
        dialog.ecu_radio.setChecked(True)
        dialog.paths.setText(str(tmp_path / "test_lost.py"))
        dialog.own_radio.setChecked(True)
        dialog.folder.setText(str(tmp_path / "report"))
        dialog.run_button.click()
        assert dialog.isModal()  # the window waits while its ECU is lent
        qtbot.waitUntil((tmp_path / "measuring").exists, timeout=RUN_MS)
    with qtbot.waitSignal(dialog.finished_run, timeout=RUN_MS):
        pass  # the ECU's power cut during test_long's expectation
    assert _states(dialog) == {"test_long": "NOT JUDGED", "test_after": "ERROR"}
    message = dialog.message.text()
    assert message.startswith("The ECU stopped answering during test_lost.py::test_long (connection to the ECU lost at")
    assert "after the test" not in message and ". The 1 test after it could not reach it" in message
    assert message.endswith("The window stays disconnected: Connect (F9) once the ECU answers again.")
    assert window.controller.session is None and window.connect_action.isEnabled() and not window.errors
    assert dialog.sim_radio.isChecked() and not dialog.ecu_radio.isEnabled()
    with serve_demo(bus):  # the ECU back
        with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
            window.connect_ecu()
        assert dialog.ecu_radio.isChecked()  # the choice made before the window lost its ECU
        window.close()


def test_a_close_the_window_refuses_leaves_the_run_going(qtbot, opened, tmp_path):
    dialog, _ = opened
    window = dialog.window_
    (tmp_path / "test_waits.py").write_text("import time\n\ndef test_waits():\n    time.sleep(60)\n", encoding="utf-8")
    dialog.paths.setText(str(tmp_path / "test_waits.py"))
    dialog.own_radio.setChecked(True)
    dialog.folder.setText(str(tmp_path / "report"))
    dialog.run_button.click()
    run = dialog.run
    window.offline_image.may_close = lambda: False  # the user keeps the window (an image with unsaved changes)
    try:
        window.close()
        assert window.isVisible() and dialog.run is run and run.process.poll() is None  # not killed with no word
    finally:
        del window.offline_image.may_close
    window.close()  # closed now: the run ends with it
    assert dialog.run is None and run.process.poll() is not None


def test_a_run_cancelled_while_the_window_lets_go_of_its_ecu_is_not_started_by_the_next(qtbot, opened, tmp_path,
                                                                                        monkeypatch):
    """Run on the window's ECU, Cancel while the session still closes, Run on a simulated ECU: the first run's
    release, when it comes, starts nothing (it started the second run's process again, the first left running)."""
    from workbench.gui.widgets import tests_dialog

    dialog, _ = opened
    controller = dialog.window_.controller
    monkeypatch.setattr(tests_dialog, "connected_ecu_options", lambda window: (["--a2l", "x.a2l"], "the ECU"))
    monkeypatch.setattr(type(controller), "closing", property(lambda self: True))  # its session closes in a worker
    monkeypatch.setattr(dialog.window_, "connect_ecu", lambda *args: None)
    dialog.refresh_target()
    dialog.ecu_radio.setChecked(True)
    dialog.paths.setText(str(tmp_path / "missing.py"))  # each run ends by itself: no test there
    dialog.own_radio.setChecked(True)
    dialog.folder.setText(str(tmp_path / "report"))
    dialog.run_button.click()
    assert dialog.run is not None and dialog.run.process is None  # waiting for the ECU's release
    dialog.cancel_button.click()
    dialog.sim_radio.setChecked(True)
    dialog.run_button.click()
    started = dialog.run.process
    controller.released.emit()  # the first run's release
    second = dialog.run.process if dialog.run is not None else started
    if second is not started:
        started.kill()
        started.wait()
    assert second is started
