"""Flashing from the window (thesis figure 38): the s19's regions with their partial ranges, a CALIB
flash with progress and verify, the working page into CAL ROM, cancel."""

from __future__ import annotations

import pytest
from gui_helpers import WAIT_MS, open_window, text_room
from PySide6.QtCore import Qt

from workbench import demo
from workbench.errors import Cancelled

FLASH_MS = 120_000


@pytest.fixture
def window(qtbot, demo_ecu, project):
    window = open_window(qtbot, project)
    yield window
    window.close()


def _planned(dialog, qtbot):
    qtbot.waitUntil(lambda: dialog.plan is not None, timeout=WAIT_MS)
    return {dialog.table.item(row, 0).text(): dialog.table.item(row, 4).text() for row in range(dialog.table.rowCount())}


def test_a_calib_flash_from_the_s19_programs_its_partial_ranges_and_verifies(window, qtbot):
    dialog = window.open_flash_dialog()
    assert dialog.path.text() == str(demo.s19()) and dialog.selected_regions() == ["CALIB"]
    info = _planned(dialog, qtbot)
    assert info["CALIB"].startswith("Partial: FC0000h-") and "FDFFF0h-FDFFFFh" in info["CALIB"]
    assert info["APPLICATIVE"].startswith("Partial: 840000h-") and info["APPLICATIVE"].endswith("(not selected)")
    for row in range(dialog.table.rowCount()):  # every region's name whole beside its check box
        room, needed = text_room(dialog.table, dialog.table.model().index(row, 0))
        assert room >= needed, dialog.table.item(row, 0).text()
    progress = []
    dialog.flash_started.connect(lambda task: task.progress.changed.connect(
        lambda done, total, label: progress.append((done, total, label)), Qt.DirectConnection))
    plot = window.plots[0]
    qtbot.waitUntil(lambda: plot.samples_shown() > 0, timeout=WAIT_MS)  # measuring while the dialog is open
    with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS) as flashed:
        dialog.start()
        assert window.hub.acquisition is None  # no DAQ while flashing: paused, and the status bar says why
        assert window.status.daq.text().startswith("DAQ paused: flashing since ")
    qtbot.waitUntil(lambda: dialog.flash_button.isEnabled(), timeout=WAIT_MS)
    result = flashed.args[0]
    assert "verified" in result.describe() and result.application_running
    assert progress and progress[-1][0] == progress[-1][1] == dialog.plan.size
    assert any("KiB/s" in label for _, _, label in progress)  # the rate and the time left
    assert dialog.progress.value() == dialog.progress.maximum()
    assert dialog.progress_label.text() == "done: verified, the application runs"  # not the last phase
    # measuring resumes by itself, the dialog still open; the pause is a gap in the line
    qtbot.waitUntil(lambda: window.hub.acquisition is not None and window.hub.acquisition.state.running,
                    timeout=WAIT_MS)
    assert window.status.daq.text().startswith("DAQ ") and "paused" not in window.status.daq.text()
    buffer = window.hub.buffer(plot.signals[0])
    qtbot.waitUntil(lambda: len(buffer.gaps) >= 1 and buffer.last()[0] > buffer.gaps[-1], timeout=WAIT_MS)
    dialog.close_button.click()


def test_the_working_page_flashed_into_cal_rom_becomes_the_reference_page(window, qtbot):
    session = window.controller.session
    session.write("xsSWITCH_TANK_THR", 27.5)
    assert session.read("xsSWITCH_TANK_THR", page="reference") == pytest.approx(20.0)
    with qtbot.waitSignal(window.parameter_sets.compared, timeout=WAIT_MS):
        window.parameter_sets.compare_pages()
    assert window.compare.rows_shown() == ["xsSWITCH_TANK_THR"]
    dialog = window.open_flash_dialog()
    dialog._working_page()
    with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS):
        dialog.start()
    assert session.read("xsSWITCH_TANK_THR", page="reference") == pytest.approx(27.5)
    # the comparison shown is of the pages before the flash: it says so (it read 20.00 beside 27.50 still)
    qtbot.waitUntil(lambda: "outdated: flashed since" in window.compare.summary.text(), timeout=WAIT_MS)
    dialog.close_button.click()


def test_a_cancelled_flash_says_what_state_the_ecu_is_in_and_a_second_flash_finishes(window, qtbot):
    dialog = window.open_flash_dialog(regions=["CALIB", "APPLICATIVE"])
    _planned(dialog, qtbot)
    def cancel_when_programming(task):  # in the flash's own thread, at its first block: no race with its end
        def cancel(done, total, label):
            if label.startswith("programming"):
                task.cancel()
        task.progress.changed.connect(cancel, Qt.DirectConnection)

    dialog.flash_started.connect(cancel_when_programming)
    with qtbot.waitSignal(dialog.flash_failed, timeout=FLASH_MS) as failed:
        dialog.start()
    dialog.flash_started.disconnect(cancel_when_programming)
    assert isinstance(failed.args[0], Cancelled)
    assert "cancelled: programming" in dialog.result.toPlainText() and "stays in boot" in dialog.result.toPlainText()
    qtbot.waitUntil(lambda: dialog.flash_button.isEnabled() and not dialog.cancel_button.isEnabled(), timeout=WAIT_MS)
    with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS) as flashed:
        dialog.start()
    assert flashed.args[0].application_running
    dialog.close_button.click()
