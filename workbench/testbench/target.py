"""The ECU requirement tests run against: a fresh simulated demo ECU per test, or the one the bus options reach.

Without bus options every test gets its own simulated FLCU on a ``virtual`` bus of its own (in the test's
process, in real time: the bench's CAN2 frames and clocks are the host's, and a simulated ECU running
faster would see the PCM's 100 ms frames arrive every 200 ms of its time, a NewData error the real
system never has), with its faults reachable in-process. With bus options every test opens a session on
that ECU; the simulator's control channel is looked up under those options (``workbench sim`` registers
one), and without it the tests that need the simulator are skipped, as they are on a real ECU.
"""

from __future__ import annotations

import itertools
import os
import sys
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from workbench.errors import EpkMismatchError, InputError
from workbench.testbench.bench import Bench
from workbench.testbench.simulator import LocalSimulator, NoSimulator, RemoteSimulator, SimulatorControl

__all__ = ["EcuTarget"]

_channels = itertools.count(1)


@dataclass
class EcuTarget:
    """Where the tests' ECU is. ``bus``: python-can settings (XCP on CAN); ``ethernet``: host/port/protocol;
    neither: the simulated demo ECU, built from ``sim_s19`` (or the demo's s19)."""

    a2l: Path | None = None
    bus: dict[str, Any] | None = None
    ethernet: dict[str, Any] | None = None
    can2_bus: dict[str, Any] | None = None
    dbc: Path | None = None
    key_function: str | None = None
    accept_epk_mismatch: bool = False
    sim_s19: Path | None = None
    sim_control: str | None = None  # HOST:PORT of a simulator's control channel, instead of looking it up
    _doc: Any = field(default=None, init=False, repr=False)
    _dbc: Any = field(default=None, init=False, repr=False)

    @property
    def simulated(self) -> bool:
        return self.bus is None and self.ethernet is None

    def describe(self) -> str:
        if self.simulated:
            return "a simulated demo ECU per test (virtual bus, real time)" + (f", flash {self.sim_s19}" if self.sim_s19 else "")
        if self.bus is not None:
            shown = {k: v for k, v in self.bus.items() if k != "receive_own_messages"}
            return "the ECU on " + " ".join(f"{k}={v}" for k, v in shown.items())
        return "the ECU at {protocol} {host}:{port}".format(**self.ethernet)

    def _load(self) -> None:
        if self._doc is None:
            from workbench import demo
            from workbench.a2l.includes import load_a2l_to_work
            from workbench.can import load_dbc

            self._doc = load_a2l_to_work(self.a2l or demo.a2l())
            self._dbc = load_dbc(self.dbc or demo.dbc_can2())

    @contextmanager
    def bench(self, evidence: Path) -> Iterator[Bench]:
        """A bench on a session with the ECU, its evidence recorded to ``evidence``; everything closed after."""
        self._load()
        with ExitStack() as stack:
            if self.simulated:
                session, control = self._simulated(stack)
                can2_bus = None
            else:
                session, control = self._real(stack)
                can2_bus = self.can2_bus
            bench = Bench(session, dbc=self._dbc, can2_bus=can2_bus, simulator=control, evidence=evidence)
            stack.callback(bench.close)
            bench.note(f"ECU: {self.describe()}; simulator control: {control.where}")
            yield bench

    def _simulated(self, stack: ExitStack):
        from workbench.session import Session
        from workbench.sim import DemoFiles, build_demo_ecu, serve_demo
        from workbench.sim.inject import FlcuFaults

        files = DemoFiles.defaults()
        if self.a2l is not None:
            files.a2l = Path(self.a2l)
        if self.sim_s19 is not None:
            files.s19 = Path(self.sim_s19)
        files.dbc = Path(self._dbc.path)
        demo = build_demo_ecu(files)
        # the simulated ECU's clock, the bus threads and the bench share this process's GIL: switching
        # every millisecond instead of five keeps a frame from waiting behind the plant's arithmetic
        sys.setswitchinterval(min(sys.getswitchinterval(), 0.001))
        channel = f"workbench-test-{os.getpid()}-{next(_channels)}"
        simulator = stack.enter_context(serve_demo({"interface": "virtual", "channel": channel}, demo=demo))
        session = stack.enter_context(Session.open(self._doc, interface="virtual", channel=channel))
        return session, LocalSimulator(FlcuFaults(demo, simulator.lock, simulator.pcm))

    def _real(self, stack: ExitStack):
        from workbench.session import Session

        bus = dict(self.bus or {})
        ethernet = self.ethernet or {}
        session = stack.enter_context(Session.open(
            self._doc, interface=bus.pop("interface", None), channel=bus.pop("channel", None),
            bitrate=bus.pop("bitrate", None), bus_kwargs=bus, host=ethernet.get("host"), port=ethernet.get("port"),
            protocol=ethernet.get("protocol"), key_function=self.key_function,
            accept_epk_mismatch=self.accept_epk_mismatch))
        if session.epk.matches is False and not self.accept_epk_mismatch:  # verdicts on other software than the A2L's
            raise EpkMismatchError(session.epk.a2l or "", session.epk.ecu or "",
                                   "the tests would judge other software than the A2L describes: flash the matching "
                                   "software, give its A2L (--a2l), or --accept-epk-mismatch to test it anyway")
        session.require_application()
        return session, self._control(session)

    def _control(self, session) -> SimulatorControl:
        from workbench.sim.control import ControlClient, endpoint_key, find_control

        if self.sim_control:
            host, _, port = self.sim_control.rpartition(":")
            if not host or not port.isdigit():
                raise InputError(f"--sim-control {self.sim_control!r}: expected HOST:PORT (workbench sim prints it)")
            return RemoteSimulator(ControlClient(host, int(port)))
        settings = session.link.settings
        if settings.transport == "CAN":
            key = endpoint_key(settings.bus.kwargs() if settings.bus else {})
        else:
            key = endpoint_key(host=settings.host, port=settings.port, protocol=settings.transport)
        client = find_control(key)
        if client is None:
            return NoSimulator(f"no simulator registered a control channel for {settings.describe()} "
                               "(a real ECU, or workbench sim on another host: give --sim-control HOST:PORT)")
        return RemoteSimulator(client)
