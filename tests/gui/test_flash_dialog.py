"""Flashing from the window (thesis figure 38): the s19's regions with their partial ranges, a CALIB
flash with progress and verify, the working page into CAL ROM, cancel."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from gui_helpers import WAIT_MS, open_window, text_room
from PySide6.QtCore import Qt

from workbench import demo
from workbench.errors import Cancelled
from workbench.flash import FlashRefused
from workbench.image import MemoryImage, load_image
from workbench.sim.memory_map import HDS9

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
    # the whole software (the EPK dialog's Flash software): BOOT and SHARED were in it (a table item is checkable
    # unless told), so that flash was refused ('BOOT holds the boot loader ... --allow-boot')
    assert dialog.software_regions() == ["APPLICATIVE", "CALIB"]
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


def test_the_window_does_not_close_while_it_flashes(window, qtbot):
    """Closing mid-flash blocked the window for seconds (the session closed under the erase) and cut the flash off,
    the ECU left in its boot loader: the window stays open and says why, as the flash dialog itself does."""
    import threading

    dialog = window.open_flash_dialog(regions=["CALIB"])
    _planned(dialog, qtbot)
    reached, go_on = threading.Event(), threading.Event()

    def hold(task):  # in the flash's own thread, at its first progress report
        task.progress.changed.connect(lambda *_: (reached.set(), go_on.wait(WAIT_MS / 1000)), Qt.DirectConnection)

    dialog.flash_started.connect(hold)
    dialog.start()
    qtbot.waitUntil(reached.is_set, timeout=WAIT_MS)
    try:
        assert not window.close() and window.isVisible()
        assert window.errors and "a flash is under way" in window.errors[-1].text()
    finally:
        go_on.set()
    qtbot.waitUntil(lambda: dialog.task is None, timeout=FLASH_MS)
    assert dialog.progress_label.text() == "done: verified, the application runs"
    dialog.close_button.click()


# --- the refusals the CLI's options override: shown, and a choice the user makes explicitly ---------------------------

CALIB_START, TRAILER = 0xFC0000, 0xFDFFF0  # the CALT trailer: in CALIB's one sector, beyond the file below
OLD_EPK, NEW_EPK = b"10300020250301", b"10300020259999"


def _calib_file(tmp_path, end: int, epk: bytes | None = None):
    image = load_image(demo.s19()).crop(CALIB_START, end)
    if epk is not None:
        image.add(CALIB_START, epk, overwrite=True)  # ADDR_EPK
    path = tmp_path / "calib.s19"
    image.save(path)
    return path


def _refused(dialog, qtbot):
    with qtbot.waitSignal(dialog.flash_failed, timeout=FLASH_MS) as failed:
        dialog.start()
    qtbot.waitUntil(lambda: dialog.flash_button.isEnabled(), timeout=WAIT_MS)
    assert isinstance(failed.args[0], FlashRefused)
    assert dialog.progress_label.text() == "refused, nothing was flashed: see below"
    return dialog.result.toPlainText()


def test_bytes_the_file_does_not_give_back_are_erased_only_after_the_user_ticks_the_override(window, qtbot,
                                                                                            demo_ecu, tmp_path):
    ecu = demo_ecu.ecu
    trailer = ecu.read(TRAILER, 16)
    assert trailer != b"\xff" * 16
    dialog = window.open_flash_dialog()
    dialog.path.setText(str(_calib_file(tmp_path, 0xFDFF00)))
    dialog.replan()
    _planned(dialog, qtbot)
    erase = dialog.overrides["erase_beyond_file"]
    assert erase.isHidden() and dialog.chosen_overrides() == frozenset()  # offered only when a refusal needs it
    before = ecu.read(CALIB_START, 0x20000)
    for _ in range(2):  # refused, and refused again while the box is not ticked ("no")
        text = _refused(dialog, qtbot)
        assert "would also erase FDFFF0h-FDFFFFh" in text and "(nothing was erased)" in text
        assert erase.isVisible() and not erase.isChecked() and dialog.flash_button.text() == "Flash"
        assert erase.width() >= erase.sizeHint().width()  # its text whole at the dialog's size
        assert dialog.overrides["accept_epk_mismatch"].isHidden()
        assert ecu.read(CALIB_START, 0x20000) == before
    dialog.path.editingFinished.emit()  # the same file again: the refusal and its choice stay
    assert erase.isVisible() and "FDFFF0h-FDFFFFh" in dialog.result.toPlainText()
    erase.click()
    assert dialog.flash_button.text() == "Flash anyway"
    with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS) as flashed:
        dialog.start()
    assert "erased and not written again (--erase-beyond-file): FDFFF0h-FDFFFFh" in flashed.args[0].describe()
    assert "erased and not written again (--erase-beyond-file): FDFFF0h-FDFFFFh" in dialog.result.toPlainText()
    assert ecu.read(TRAILER, 16) == b"\xff" * 16
    assert erase.isHidden() and dialog.flash_button.text() == "Flash"  # the next flash asks again
    qtbot.waitUntil(lambda: dialog.flash_button.isEnabled(), timeout=WAIT_MS)
    dialog.close_button.click()


@pytest.fixture
def new_software(qtbot, demo_ecu, project, tmp_path):
    """The window on the A2L of another build (EPK ...9999) than the ECU runs (...0301)."""
    text = demo.a2l().read_bytes()
    assert text.count(OLD_EPK) >= 1
    (tmp_path / "new.a2l").write_bytes(text.replace(OLD_EPK, NEW_EPK))
    project.a2l = tmp_path / "new.a2l"
    window = open_window(qtbot, project)
    yield window
    window.close()


def test_a_calib_flash_of_another_epk_is_refused_then_flashed_when_the_user_accepts_the_mismatch(
        new_software, qtbot, demo_ecu, tmp_path):
    window, ecu = new_software, demo_ecu.ecu
    window.epk_dialog.flash_button.click()  # "flash the software that matches the A2L" ... only its CALIB
    dialog = window.flash_dialog
    dialog.path.setText(str(_calib_file(tmp_path, 0xFE0000, NEW_EPK)))
    dialog.select_regions(["CALIB"])
    _planned(dialog, qtbot)
    before = ecu.read(CALIB_START, 0x20000)
    text = _refused(dialog, qtbot)
    assert "CALIB only, with EPK '10300020259999', but the ECU reports EPK '10300020250301'" in text
    accept = dialog.overrides["accept_epk_mismatch"]
    assert accept.isVisible() and not accept.isChecked() and dialog.overrides["erase_beyond_file"].isHidden()
    assert accept.width() >= accept.sizeHint().width()
    assert ecu.read(CALIB_START, 0x20000) == before
    accept.click()
    with qtbot.waitSignal(dialog.flashed, timeout=FLASH_MS):
        dialog.start()
    assert "MISMATCH accepted" in dialog.result.toPlainText()
    assert ecu.read(CALIB_START, 14) == NEW_EPK
    qtbot.waitUntil(lambda: dialog.flash_button.isEnabled(), timeout=WAIT_MS)
    dialog.close_button.click()


def test_a_cleared_key_with_another_region_differing_offers_to_select_that_region(window, qtbot, demo_ecu):
    """What a flash of CALIB killed half-way leaves: the key cleared, CALIB not the file's; APPLICATIVE alone is
    refused (no override) and the dialog offers to select CALIB too."""
    unfinished = MemoryImage()
    unfinished.add(HDS9.app_key_address, b"\xff" * len(HDS9.app_key))
    unfinished.add(0xFC0100, b"\xff" * 16)
    demo_ecu.ecu.memory.load_flash(unfinished)
    dialog = window.open_flash_dialog(regions=["APPLICATIVE"])
    _planned(dialog, qtbot)
    text = _refused(dialog, qtbot)
    assert "the application key is cleared (a flash did not finish) and CALIB on the ECU differs" in text
    assert all(box.isHidden() for box in dialog.overrides.values())  # nothing to tick: only flashing CALIB too helps
    assert dialog.add_regions_button.isVisible() and dialog.add_regions_button.text() == "Select CALIB too"
    dialog.add_regions_button.click()
    assert dialog.selected_regions() == ["APPLICATIVE", "CALIB"] and dialog.add_regions_button.isHidden()
    _planned(dialog, qtbot)
    dialog.close_button.click()


def test_a_calib_flash_over_a_half_written_application_is_refused_and_offers_applicative(window, qtbot, demo_ecu,
                                                                                        tmp_path):
    """What a power cut half-way through APPLICATIVE leaves: the key cleared, the application's EPK (programmed last)
    erased. A CALIB-only file is refused with the CLI's line (no override); the dialog offers to select APPLICATIVE."""
    unfinished = MemoryImage()
    unfinished.add(HDS9.app_key_address, b"\xff" * len(HDS9.app_key))
    unfinished.add(0x840008, b"\xff" * 14)  # APPLICATIVE's ADDR_EPK
    demo_ecu.ecu.memory.load_flash(unfinished)
    dialog = window.open_flash_dialog(regions=["CALIB"])
    dialog.path.setText(str(_calib_file(tmp_path, 0xFE0000)))
    dialog.replan()
    _planned(dialog, qtbot)
    text = _refused(dialog, qtbot)
    assert ("APPLICATIVE's EPK at 840008h reads erased (14 bytes FF): a flash of APPLICATIVE probably broke off, so "
            "the application key is not set and the ECU stays in its boot loader") in text
    assert all(box.isHidden() for box in dialog.overrides.values())
    assert dialog.add_regions_button.text() == "Select APPLICATIVE too"
    dialog.close_button.click()


def test_the_browse_filter_offers_every_image_extension(qtbot, monkeypatch):
    from PySide6.QtWidgets import QFileDialog

    from workbench.a2l import load_a2l, read_xcp_config
    from workbench.gui.widgets.flash_dialog import FlashDialog
    from workbench.image import IMAGE_SUFFIXES

    offered = []
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *args: offered.append(args[-1]) or ("", ""))
    doc = load_a2l(demo.a2l())
    dialog = FlashDialog(SimpleNamespace(doc=doc, config=read_xcp_config(doc)))  # what the dialog reads of a session
    qtbot.addWidget(dialog)
    dialog._browse()
    assert offered and all(f"*{suffix}" in offered[0] for suffix in IMAGE_SUFFIXES), offered
