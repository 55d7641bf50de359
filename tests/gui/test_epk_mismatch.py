"""The software version check (thesis figure 37): an A2L whose EPK is not the ECU's."""

from __future__ import annotations

import pytest
from gui_helpers import WAIT_MS, open_window
from PySide6.QtWidgets import QLabel

from workbench import demo

OLD_EPK = "08493820231002"


@pytest.fixture
def window(qtbot, demo_ecu, project, tmp_path):
    text = demo.a2l().read_text(encoding="utf-8")
    assert text.count('EPK "10300020250301"') == 1
    (tmp_path / "old.a2l").write_text(text.replace('EPK "10300020250301"', f'EPK "{OLD_EPK}"'), encoding="utf-8")
    project.a2l = tmp_path / "old.a2l"
    window = open_window(qtbot, project)
    yield window
    window.close()


def test_the_dialog_shows_both_epks_and_nothing_is_measured_before_the_user_chose(window):
    dialog = window.epk_dialog
    assert dialog is not None and dialog.isVisible()
    texts = [label.text() for label in dialog.findChildren(QLabel)]
    assert repr(OLD_EPK) in texts and "'10300020250301'" in texts  # as workbench.errors.epk_text shows an EPK
    assert window.hub.acquisition is None
    assert window.status.epk.text() == "EPK ✗ read-only"


def test_working_read_only_measures_but_refuses_calibration(window, qtbot):
    window.epk_dialog.read_only_button.click()
    assert window.hub.acquisition is not None
    plot = window.plots[0]
    qtbot.waitUntil(lambda: plot.samples_shown() > 0, timeout=WAIT_MS)
    editor = window.open_editor("xsSWITCH_TANK_THR")
    qtbot.waitUntil(lambda: editor.value is not None, timeout=WAIT_MS)
    assert not editor.field.input.isEnabled()
    assert "EPK differs" in editor.status.text()
    assert not window.copy_action.isEnabled()
    assert not window.working_action.isEnabled() and not window.reference_action.isEnabled()  # no page switches


def test_disconnect_closes_the_session(window, qtbot):
    with qtbot.waitSignal(window.controller.released, timeout=WAIT_MS):
        window.epk_dialog.disconnect_button.click()
        assert window.controller.session is None and not window.connect_action.isEnabled()  # until let go of
    assert window.connect_action.isEnabled()


NEW_EPK = b"10300020259999"


@pytest.fixture
def calib_of_another_build(qtbot, demo_ecu, project, tmp_path):
    """The window on the A2L of build ...9999 and an ECU that runs build ...0301 with ...9999's CALIB (what an
    accepted CALIB flash leaves): GET_ID reports ...9999, the application's header still ...0301."""
    from workbench.image import MemoryImage

    text = demo.a2l().read_bytes()
    (tmp_path / "new.a2l").write_bytes(text.replace(b"10300020250301", NEW_EPK))
    demo_ecu.ecu.memory.load_flash(MemoryImage.from_bytes(0xFC0000, NEW_EPK))
    project.a2l = tmp_path / "new.a2l"
    window = open_window(qtbot, project)
    yield window
    window.close()


def test_a_calibration_of_another_build_shows_which_part_differs(calib_of_another_build):
    window = calib_of_another_build
    assert window.status.epk.text() == "EPK ✗ APPLICATIVE read-only"
    assert "APPLICATIVE (840008h): ECU '10300020250301', A2L '10300020259999': MISMATCH" in window.status.epk.toolTip()
    dialog = window.epk_dialog
    assert dialog is not None and dialog.isVisible()
    labels = dialog.findChildren(QLabel)
    texts = [label.text() for label in labels]
    assert "<b>APPLICATIVE in the ECU is another build's.</b><br>What would you like to do?" in texts
    row = texts.index("EPK in APPLICATIVE (840008h)")
    assert texts[row + 1:row + 3] == ["'10300020259999'", "'10300020250301'"]  # A2L, ECU
    assert "EPK in CALIB (FC0000h)" in texts
    assert window.hub.acquisition is None


def test_flash_software_selects_the_part_of_another_build(calib_of_another_build):
    window = calib_of_another_build
    dialog = window.epk_dialog
    assert dialog.flash_button.toolTip() == "open the flash dialog with APPLICATIVE selected"
    dialog.flash_button.click()
    flash = window.flash_dialog
    assert flash is not None and flash.isVisible()
    assert flash.selected_regions() == ["APPLICATIVE"]  # the CALIB that stays is this build's


def test_flash_software_selects_the_whole_software_when_every_part_differs(window):
    window.epk_dialog.flash_button.click()
    assert window.flash_dialog.selected_regions() == ["APPLICATIVE", "CALIB"]
