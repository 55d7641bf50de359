"""An ECU that answers in its boot loader (the application-valid key cleared): the window says so where it
is read first and measures nothing (it showed 'EPK ✓', 'DAQ idle' and an ECU name cut before '(boot loader)'); the
editors and the fix panel say why they are read-only instead of an error dialog each (they read, the ECU has no
calibrations there), and read the ECU once a flash has brought the application back."""

from __future__ import annotations

from gui_helpers import WAIT_MS, open_window

from workbench.gui.ecu import IN_BOOT
from workbench.sim import serve_demo


def test_the_window_says_the_ecu_is_in_its_boot_loader(qtbot, channel, project):
    with serve_demo({"interface": "virtual", "channel": channel}, valid_key=False):
        window = open_window(qtbot, project)
        try:
            assert window.controller.info.boot and window.hub.acquisition is None
            assert window.status.ecu.text().startswith("boot loader · ")
            assert window.status.pause[0] == "the ECU is in its boot loader (flash the application)"
            assert window.flash_action.isEnabled() and not window.working_action.isEnabled()
            editor, panel = window.editors["xsSWITCH_TANK_THR"], window.fix_panel
            qtbot.waitUntil(lambda: editor.status.text().startswith(f"read-only: {IN_BOOT}"), timeout=WAIT_MS)
            qtbot.waitUntil(lambda: panel.model.read_only == IN_BOOT, timeout=WAIT_MS)
            assert not editor.field.input.isEnabled() and panel.model.stale

            dialog = window.open_flash_dialog()
            dialog.select_regions(dialog.software_regions())
            dialog.start()
            qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
            assert dialog.progress_label.text() == "done: verified, the application runs", dialog.result.toPlainText()
            qtbot.waitUntil(lambda: editor.value is not None and not editor.value_source, timeout=WAIT_MS)
            qtbot.waitUntil(lambda: panel.model.read_only == "" and not panel.model.stale, timeout=WAIT_MS)
            assert editor.field.input.isEnabled() and window.hub.acquisition is not None
            assert not window.errors  # a dialog per editor and one from the fix panel, each 'flash its software'
        finally:
            window.close()
