"""GUI tests: pytest-qt's QApplication (offscreen, .ci/run sets QT_QPA_PLATFORM), the demo's files
read once, and the simulated ECU on a virtual bus of each test's own."""

from __future__ import annotations

import uuid

import pytest

from workbench.gui.project import Connection, demo_project
from workbench.gui.workspace import load_workspace


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

