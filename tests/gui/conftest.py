"""GUI tests: pytest-qt's QApplication (offscreen, .ci/run sets QT_QPA_PLATFORM), the demo's files
read once, and the simulated ECU on a virtual bus of each test's own.

Offscreen, the window opens on a laptop's screen of 1366 x 768 (Qt's offscreen default is 800 x 600):
what the tests see is what a user with a small screen sees."""

from __future__ import annotations

import gc
import os
import uuid

import pytest

from workbench.gui.app import screenshot_screen
from workbench.gui.project import Connection, demo_project
from workbench.gui.workspace import load_workspace

SCREEN = (1366, 768)


@pytest.hookimpl(trylast=True)
def pytest_configure(config) -> None:
    """After tests/conftest.py chose the platform: ``pytest tests/gui`` reads this file before that choice, and an
    xdist worker beside a display's then rendered on offscreen's own 800 x 800 screen (the window did not fit)."""
    if os.environ.get("QT_QPA_PLATFORM") == "offscreen":
        screenshot_screen(SCREEN)


@pytest.fixture(scope="module", autouse=True)
def what_lives_longer_than_the_module_left_out_of_collections():
    """What was there before a module's tests (the imported modules, the session's fixtures: about 170,000 objects) is
    frozen out of the cycle collector's passes while they run (gc.freeze): a full pass over it held the GIL 0.4-1.8 s
    on a loaded machine, the module's simulated ECU answered nothing meanwhile, and was found silent (CI: "simulated
    time is 5.2 s behind", EcuSilentError, the window's tests after it without a session). After the module's
    window and ECU are gone, one pass over everything."""
    gc.collect()
    gc.freeze()
    yield
    gc.unfreeze()
    gc.collect()


@pytest.fixture(autouse=True)
def garbage_collected_on_the_gui_thread(qapp):
    """As the application does (workbench.gui.worker.collect_garbage_on_the_gui_thread): a test's DAQ thread
    collecting a window's Qt objects hung the test and its xdist worker for good."""
    from workbench.gui.worker import collect_garbage_on_the_gui_thread

    timer = collect_garbage_on_the_gui_thread(qapp)
    yield
    timer.stop()
    timer.deleteLater()
    gc.enable()
    gc.collect()  # this thread's: what the test left in cycles


@pytest.fixture(autouse=True)
def unsaved_edits_discarded_when_a_test_closes_its_window(monkeypatch):
    """A window closed with calibrations edited offline asks (QMessageBox.question, modal): a test that fails before it
    saves or undoes its edits would wait for an answer for good at its teardown. Tests of the question patch it too."""
    from PySide6.QtWidgets import QMessageBox

    monkeypatch.setattr(QMessageBox, "question", lambda *_args, **_kwargs: QMessageBox.Discard)


@pytest.fixture(scope="session")
def demo_workspace():
    return load_workspace(demo_project())


@pytest.fixture
def channel() -> str:
    return f"gui-test-{uuid.uuid4().hex[:10]}"


@pytest.fixture
def demo_ecu(channel):
    """The demo ECU served on a private virtual bus, with the PCM asking for 25 bar."""
    from workbench.sim import serve_demo

    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as simulator:
        yield simulator


@pytest.fixture
def project(channel):
    project = demo_project()
    project.connection = Connection(interface="virtual", channel=channel)
    return project

