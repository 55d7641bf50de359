"""An ECU that answers in its boot loader (the application-valid key cleared): the window says so where it
is read first and measures nothing (it showed 'EPK ✓', 'DAQ idle' and an ECU name cut before '(boot loader)')."""

from __future__ import annotations

from gui_helpers import open_window

from workbench.sim import serve_demo


def test_the_window_says_the_ecu_is_in_its_boot_loader(qtbot, channel, project):
    with serve_demo({"interface": "virtual", "channel": channel}, valid_key=False):
        window = open_window(qtbot, project)
        try:
            assert window.controller.info.boot and window.hub.acquisition is None
            assert window.status.ecu.text().startswith("boot loader · ")
            assert window.status.pause[0] == "the ECU is in its boot loader (flash the application)"
            assert window.flash_action.isEnabled() and not window.working_action.isEnabled()
        finally:
            window.close()
