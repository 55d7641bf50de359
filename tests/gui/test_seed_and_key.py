"""A failing seed & key in the window is one dialog that names the resources left locked and where the key function
is set: the ECU refusing the key failed the connect without a word (the slave disconnects after a wrong key, and the
connect ended as a lost connection), a key function that fails gave a dialog per call that needed a resource."""

from __future__ import annotations

import dataclasses

from gui_helpers import WAIT_MS, offline_window

from workbench.sim.seedkey import compute_key


def refused_key(seed: bytes, resource: int) -> bytes:
    return bytes(len(seed))


def failing_key(seed: bytes, resource: int) -> bytes:
    raise ValueError("no key for this seed")


def wrong_for_daq(seed: bytes, resource: int) -> bytes:
    return refused_key(seed, resource) if resource == 0x04 else compute_key(seed, resource)


def _window(qtbot, project, function: str):
    project.connection = dataclasses.replace(project.connection, key_function=f"{__file__}:{function}")
    return offline_window(qtbot, project)


def test_a_key_the_ecu_refuses_fails_the_connect_in_one_dialog_that_says_so(qtbot, demo_ecu, project):
    window = _window(qtbot, project, "wrong_for_daq")
    window.connect_ecu()
    qtbot.waitUntil(lambda: bool(window.errors) and window.connect_action.isEnabled(), timeout=WAIT_MS)
    qtbot.wait(100)
    assert [box.text() for box in window.errors] == [
        "Seed & key failed: DAQ (measurement) of the ECU stays locked. Check the key function (ECU > Connection…, "
        "seed & key), then connect again."]
    assert "the ECU refused the key of" in window.errors[0].informativeText()
    assert window.controller.session is None and window.status.link.text() == "○ not connected"
    window.close()


def test_a_key_function_that_fails_is_one_dialog_for_every_resource_it_left_locked(qtbot, demo_ecu, project):
    window = _window(qtbot, project, "failing_key")
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()  # connected: what needs no resource works
    qtbot.waitUntil(lambda: any("CAL/PAG" in box.text() and "DAQ" in box.text() for box in window.errors)
                    or len(window.errors) > 1, timeout=WAIT_MS)  # the cache check's upload, DAQ
    assert len(window.errors) == 1 and window.errors[0].text().startswith(
        "Seed & key failed: CAL/PAG (calibration), DAQ (measurement) of the ECU stay locked.")
    details = window.errors[0].informativeText().split("\n")
    assert all("failing_key failed for" in line and "ValueError: no key for this seed" in line for line in details)
    window.close()
