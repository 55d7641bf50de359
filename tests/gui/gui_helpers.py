"""Helpers of the GUI tests (a module of its own: pytest imports every conftest as "conftest")."""

from __future__ import annotations


WAIT_MS = 15_000


def open_window(qtbot, project):
    """A MainWindow on ``project``, shown, its files read, connected (for ``yield`` in a fixture)."""
    from workbench.gui.widgets.main_window import MainWindow

    window = MainWindow(project)
    qtbot.addWidget(window)
    window.show()
    with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
    with qtbot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    return window
