"""Fixtures: the demo ECU on a virtual bus of the test's own (the PCM asking for 25 bar on CAN2), a Session on
it, and a reader that closes the files it opens."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

import pytest

from workbench import Session
from workbench.sim import serve_demo

_channels = itertools.count()


@dataclass
class DemoEcu:
    """The simulated ECU on the virtual bus ``channel``."""

    channel: str
    simulator: object

    def open_session(self, a2l: Path | None = None) -> Session:
        return Session.open(a2l, interface="virtual", channel=self.channel)

    @property
    def cli_options(self) -> list[str]:
        """The bus options of a ``workbench`` command that talks to it."""
        return ["--interface", "virtual", "--channel", self.channel]


@pytest.fixture
def demo_ecu():
    channel = f"record-test-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, pcm_target_bar=25.0) as simulator:
        yield DemoEcu(channel, simulator)


@pytest.fixture
def session(demo_ecu):
    with demo_ecu.open_session() as opened:
        yield opened


@pytest.fixture
def read_mdf():
    """``read_mdf(path)``: the file opened with asammdf (closed after the test)."""
    from asammdf import MDF

    opened = []

    def read(path):
        mdf = MDF(path)
        opened.append(mdf)
        return mdf

    yield read
    for mdf in opened:
        mdf.close()
