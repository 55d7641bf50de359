"""Another master on the ECU's ids before CONNECT (CANape beside us, or a DAQ nobody stopped), as the window says
it: a badge beside the EPK's, the whole line in its tooltip, while the session lasts.
A raw python-can bus plays the other master; connected again on a quiet bus, the window says nothing."""

from __future__ import annotations

import can
from gui_helpers import WAIT_MS, open_window

from workbench.session import session as session_module


def test_another_masters_dtos_before_connect_are_shown_until_a_quiet_connect(qtbot, demo_ecu, project, channel,
                                                                             monkeypatch):
    monkeypatch.setattr(session_module, "LISTEN_BEFORE_CONNECT_S", 0.2)  # a loaded machine misses no 5 ms DTO in it
    said = session_module.other_master

    def heard_then_quiet(heard, seconds):  # the other master stops as the listening ends: its DTOs during our
        task.stop()  # session (a live second master) would break our DAQ, which is not what this test is about
        return said(heard, seconds)

    monkeypatch.setattr(session_module, "other_master", heard_then_quiet)
    with can.Bus(interface="virtual", channel=channel) as other:
        foreign = can.Message(arbitration_id=0x7F1, is_extended_id=False, data=bytes((0xF0, 1, 2, 3, 4, 5, 6, 7)))
        task = other.send_periodic(foreign, 0.005)  # the other master's DAQ list, PID 0xF0, on the ECU's id
        try:
            window = open_window(qtbot, project)
        finally:
            task.stop()
    status = window.status
    heard = window.controller.session.other_master
    assert heard.startswith("before CONNECT, the ECU's id 0x7F1 carried ") and "DTO(s) within 200 ms" in heard
    assert status.other_master.isVisible() and status.other_master.text() == "⚠ other master?"
    assert status.other_master.toolTip() == heard

    with qtbot.waitSignal(window.controller.disconnected, timeout=WAIT_MS):
        window.controller.close()
    assert not status.other_master.isVisible()
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    assert window.controller.session.other_master == "" and not status.other_master.isVisible()
    window.close()
    assert not window.errors, [box.text() for box in window.errors]
