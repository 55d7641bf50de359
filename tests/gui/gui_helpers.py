"""Helpers of the GUI tests (a module of its own: pytest imports every conftest as "conftest")."""

from __future__ import annotations

import threading

from PySide6.QtCore import Qt

WAIT_MS = 15_000


def offline_window(qtbot, project=None):
    """A MainWindow on ``project`` (the demo's), shown, its files read, no ECU."""
    from workbench.gui.project import demo_project
    from workbench.gui.widgets.main_window import MainWindow

    window = MainWindow(project or demo_project())
    qtbot.addWidget(window)
    window.show()
    with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
    return window


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


def shared_window(request, channel: str, plots=None):
    """A MainWindow on the demo project, connected to the ECU on ``channel``, for a module's tests
    (``yield`` it from a module-scoped fixture; it is closed after them). ``plots``: instead of the demo's."""
    from pytestqt.qtbot import QtBot

    from workbench.gui.project import Connection, demo_project
    from workbench.gui.widgets.main_window import MainWindow

    project = demo_project()
    project.connection = Connection(interface="virtual", channel=channel)
    if plots is not None:
        project.plots = plots
    window = MainWindow(project)
    window.show()
    bot = QtBot(request)
    with bot.waitSignal(window.loaded, timeout=WAIT_MS):
        window.load()
    with bot.waitSignal(window.controller.connected, timeout=WAIT_MS):
        window.connect_ecu()
    window.activateWindow()
    bot.waitUntil(window.isActiveWindow, timeout=WAIT_MS)
    return window


def press(key, modifiers=Qt.NoModifier):
    """A key (with ``modifiers``) to the widget that has the keyboard focus, as a keyboard sends it; that widget."""
    from PySide6.QtTest import QTest
    from PySide6.QtWidgets import QApplication

    focused = QApplication.focusWidget()
    assert focused is not None, "no widget has the keyboard focus"  # (Qt would abort on a key sent to none)
    QTest.keyClick(focused, key, modifiers)
    return focused


def focus(widget) -> None:
    """The keyboard's focus on ``widget``, its window made the active one first (another test's window may be)."""
    from PySide6.QtTest import QTest

    window = widget.window()
    window.activateWindow()
    for _ in range(WAIT_MS // 10):
        if window.isActiveWindow():
            break
        QTest.qWait(10)
    widget.setFocus()


def ecu_and_window_fixtures(prefix: str):
    """A module's ``ecu`` (the demo ECU on a virtual bus of its own) and ``window`` (one window on it without plots,
    shared by the module's tests) fixtures: ``ecu, window = ecu_and_window_fixtures("gui-keys")`` at module level."""
    import pytest

    @pytest.fixture(scope="module")
    def ecu():
        yield from demo_ecu_on_a_channel_of_its_own(prefix)

    @pytest.fixture(scope="module")
    def window(qapp, ecu, request):
        window = shared_window(request, ecu[0], plots=[])
        yield window
        window.close()
        window.deleteLater()

    return ecu, window


def demo_ecu_on_a_channel_of_its_own(prefix: str):
    """The demo ECU on a virtual bus of its own: ``(channel, simulator)`` (``yield from`` in a fixture)."""
    import uuid

    from workbench.sim import serve_demo

    channel = f"{prefix}-{uuid.uuid4().hex[:10]}"
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as simulator:
        yield channel, simulator



def text_rect(view, index):
    """The rectangle the view's style gives the text of cell ``index`` (its margins and padding taken off)."""
    from PySide6.QtWidgets import QStyle, QStyleOptionViewItem

    option = QStyleOptionViewItem()
    view.itemDelegate().initStyleOption(option, index)
    option.rect = view.visualRect(index)
    return view.style().subElementRect(QStyle.SE_ItemViewItemText, option, view)


def text_room(view, index) -> tuple[int, int]:
    """(the width the view's style gives the text of cell ``index``, the width its text needs): a cell whose room
    is smaller shows it cut ("APPLICATI…")."""
    from PySide6.QtGui import QFontMetrics

    font = index.data(Qt.FontRole) or view.font()
    return text_rect(view, index).width(), QFontMetrics(font).horizontalAdvance(str(index.data() or ""))


def run_a2l_tools(dialog, qtbot):
    """Run the A2L tools dialog's job; its outcome once the dialog is ready for the next."""
    with qtbot.waitSignal(dialog.done, timeout=WAIT_MS) as done:
        assert dialog.run() is not None
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    return done.args[0]


def hold_a2l_tools_job(dialog, label: str | None = None) -> tuple[threading.Event, threading.Event]:
    """(reached, go_on): the dialog's job waits in its worker at its progress report labelled ``label`` (None: its
    first) until ``go_on`` is set, so that a test presses Cancel while it runs there."""
    reached, go_on = threading.Event(), threading.Event()

    def hold(done: int, total: int, text: str) -> None:
        if label is None or text == label:
            reached.set()
            go_on.wait(WAIT_MS / 1000)

    dialog.started.connect(lambda task: task.progress.changed.connect(hold, Qt.DirectConnection))
    return reached, go_on
