"""Starting the window: the Qt application, the demo ECU behind it, and screenshots.

:func:`run_window` opens a project (connecting at once when asked); :func:`run_demo` first starts
the simulated FLCU ECU in this process on a private python-can bus (a ``virtual`` channel of its
own), so ``workbench demo`` shows live signals with no hardware and without touching anyone
else's bus. With ``screenshot`` the window renders itself to a PNG once every measurement window
shows live samples (and ``settle_s`` more seconds have passed), then closes.
"""

from __future__ import annotations

import gc
import json
import logging
import os
import sys
import tempfile
import time
import uuid
from pathlib import Path

from PySide6.QtCore import QThreadPool, QtMsgType, QTimer, qInstallMessageHandler
from PySide6.QtWidgets import QApplication

from workbench.fileio import atomic_write_text
from workbench.gui import theme
from workbench.gui.project import Connection, Project, demo_project
from workbench.gui.widgets.main_window import MainWindow
from workbench.gui.worker import collect_garbage_on_the_gui_thread
from workbench.logs import logger

log = logger(__name__)

__all__ = ["application", "run_demo", "run_window", "screenshot_screen"]

SCREENSHOT_SCREEN = (1600, 1000)  # the screen of an offscreen screenshot when no size is given


def application() -> QApplication:
    """The process's QApplication (made and themed on first use)."""
    app = QApplication.instance()
    if app is None:
        qInstallMessageHandler(_log_qt_message)
        app = QApplication(sys.argv[:1])
        app.setApplicationName("workbench")
        app.setOrganizationName("workbench")
        theme.apply(app)
        # What is alive now (the modules imported, their classes and tables: ~80,000 objects) lives as long as the
        # process: moved out of the cycle collector's way, a full collection on the GUI thread takes ~10 ms instead
        # of ~100. No project is read yet, so nothing of one is kept from being collected once it is closed.
        gc.freeze()
        collect_garbage_on_the_gui_thread(app)
    return app


def _log_qt_message(kind: QtMsgType, context, message: str) -> None:
    """Qt's own messages into the log (``--debug`` shows them) rather than onto the user's stderr: the offscreen
    platform of a screenshot says "This plugin does not support propagateSizeHints()" on every window shown.
    Critical and fatal ones (Qt aborts after a fatal one) stay visible as errors."""
    level = logging.ERROR if kind in (QtMsgType.QtCriticalMsg, QtMsgType.QtFatalMsg) else logging.DEBUG
    log.log(level, "Qt: %s", message)


def screenshot_screen(size: tuple[int, int] | None) -> None:
    """Before the QApplication exists: render offscreen on one screen of ``size`` pixels (given, or
    :data:`SCREENSHOT_SCREEN` when offscreen already), so a screenshot shows the window as it fits that
    screen; without a size on a display, the display's own screen."""
    platform = os.environ.get("QT_QPA_PLATFORM", "")
    if QApplication.instance() is not None or (size is None and platform != "offscreen"):
        return
    width, height = size or SCREENSHOT_SCREEN
    config = Path(tempfile.gettempdir()) / f"workbench-screen-{width}x{height}.json"
    atomic_write_text(config, json.dumps({"screens": [{"name": f"{width}x{height}", "x": 0, "y": 0, "width": width,
                                                       "height": height, "logicalDpi": 96, "dpr": 1}]}))
    os.environ["QT_QPA_PLATFORM"] = f"offscreen:configfile={config}"


def demo_channel() -> str:
    """A virtual CAN channel nobody else uses."""
    return f"workbench-demo-{os.getpid()}-{uuid.uuid4().hex[:8]}"


def run_window(project: Project, *, connect: bool, screenshot: Path | None = None, settle_s: float = 4.0,
               live_timeout_s: float = 30.0, started: float | None = None,
               screen: tuple[int, int] | None = None) -> int:
    """Show the window on ``project`` until it is closed (or the screenshot is taken); returns the exit code.

    :param live_timeout_s: no live sample that long: the screenshot is taken as the window is, exit code 1.
    :param screen: the screenshot's screen (width, height): rendered offscreen on one of that size.
    """
    if screenshot is not None:
        screenshot_screen(screen)
    app = application()
    started = time.perf_counter() if started is None else started
    window = MainWindow(project)
    outcome = {"code": 0}
    if connect:
        window.loaded.connect(lambda: window.connect_ecu())
    if screenshot is not None:
        _take_screenshot_when_live(window, screenshot, settle_s, live_timeout_s, started, outcome)
        window.controller.failed.connect(lambda exc: _fail(app, outcome, exc))
    window.show()
    window.load()
    code = app.exec()
    QThreadPool.globalInstance().waitForDone(5000)  # a call still under way (a reconnect attempt) ends first
    return outcome["code"] or code


def _take_screenshot_when_live(window: MainWindow, path: Path, settle_s: float, live_timeout_s: float,
                               started: float, outcome: dict) -> None:
    late = QTimer(window)
    late.setSingleShot(True)

    def live() -> None:
        window.live.disconnect(live)
        late.stop()
        first = time.perf_counter() - started
        outcome["first_sample_s"] = first
        print(f"first live sample on screen {first:.2f} s after start", flush=True)
        QTimer.singleShot(int(settle_s * 1000), shoot)

    def shoot() -> None:
        QApplication.processEvents()  # the layouts of texts that changed just now
        if not window.grab().save(str(path)):
            print(f"error: cannot write the screenshot {path}", file=sys.stderr)
            outcome["code"] = 1
        else:
            print(f"screenshot: {path}", flush=True)
        window.close()

    def no_live_sample() -> None:
        window.live.disconnect(live)
        print(f"error: no live sample within {live_timeout_s:g} s (see the window's status bar); the screenshot "
              "shows the window as it is", file=sys.stderr)
        outcome["code"] = 1
        shoot()

    window.live.connect(live)
    late.timeout.connect(no_live_sample)
    late.start(int(live_timeout_s * 1000))


def _fail(app: QApplication, outcome: dict, exc: BaseException) -> None:
    print(f"error: {exc}", file=sys.stderr)
    outcome["code"] = 1
    app.quit()


# The simulated PCM's requests in the demo: the rail pressure follows a new target every few seconds,
# so the plots show the pressure control at work rather than a flat line
DEMO_TARGETS_BAR = (25.0, 35.0, 20.0, 30.0)
DEMO_STEP_S = 6.0


def run_demo(*, screenshot: Path | None = None, settle_s: float = 4.0, live_timeout_s: float = 30.0,
             time_scale: float = 1.0, pcm_target_bar: float | None = None,
             screen: tuple[int, int] | None = None) -> int:
    """Serve the demo ECU in this process on a private virtual bus and open the window on it.

    :param pcm_target_bar: the PCM's TargetRailPressure, held; None: it steps through
        :data:`DEMO_TARGETS_BAR`, one every :data:`DEMO_STEP_S` seconds.
    """
    started = time.perf_counter()
    from workbench.sim import serve_demo

    channel = demo_channel()
    project = demo_project()
    project.connection = Connection(interface="virtual", channel=channel)
    targets = DEMO_TARGETS_BAR if pcm_target_bar is None else (pcm_target_bar,)
    if screenshot is not None:
        screenshot_screen(screen)
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=targets[0],
                    time_scale=time_scale) as simulator:
        application()
        steps = QTimer()
        steps.setInterval(int(DEMO_STEP_S * 1000 / time_scale))
        cycle = {"step": 0}

        def next_target() -> None:
            cycle["step"] += 1
            simulator.pcm.target_bar = targets[cycle["step"] % len(targets)]

        steps.timeout.connect(next_target)
        if len(targets) > 1:
            steps.start()
        return run_window(project, connect=True, screenshot=screenshot, settle_s=settle_s,
                          live_timeout_s=live_timeout_s, started=started, screen=screen)
