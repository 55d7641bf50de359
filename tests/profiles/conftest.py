"""The demo ECU served through every slave profile, on CAN and on Ethernet, and a Session on each.

One simulator per (profile, transport) and one session on it (the profile's A2L, its timeouts), shared
by the tests of the module as a user's long session would be (pytest runs the tests grouped by it; with
pytest-xdist each worker has its own); each test leaves the ECU and the session as it found them. Ethernet
alternates UDP and TCP over the profiles, so both run without doubling the matrix.
"""

from __future__ import annotations

import itertools
import socket
from dataclasses import dataclass, field

import pytest

from workbench import Session
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.sim.profiles import PROFILES
from workbench.sim.server import Simulator

_channels = itertools.count()
CASES = [(name, transport) for index, name in enumerate(PROFILES)
         for transport in ("CAN", "UDP" if index % 2 == 0 else "TCP")]


@dataclass
class Served:
    profile: str
    transport: str
    simulator: Simulator
    where: dict = field(default_factory=dict)  # Session.open's bus or Ethernet keywords
    session: Session | None = None

    def open(self) -> Session:
        return Session.open(self.simulator.a2l, **self.where)

    def memory(self, address: int, size: int) -> bytes:
        """What the ECU holds, past XCP (its working page)."""
        with self.simulator.lock:
            return self.simulator.ecu.read(address, size)


def _free_port(kind: socket.SocketKind) -> int:
    with socket.socket(socket.AF_INET, kind) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module", params=CASES, ids=[f"{name}-{transport}" for name, transport in CASES])
def served(request) -> Served:
    name, transport = request.param
    if transport == "CAN":
        channel = f"profile-{name}-{next(_channels)}"
        where = {"interface": "virtual", "channel": channel}
        serving = serve_demo(dict(where), profile=name, pcm_target_bar=25.0)
    else:
        port = _free_port(socket.SOCK_DGRAM if transport == "UDP" else socket.SOCK_STREAM)
        where = {"host": "127.0.0.1", "port": port, "protocol": transport.lower()}
        serving = serve_demo(ethernet=EthernetEndpoint("127.0.0.1", port, transport), profile=name,
                             pcm_target_bar=25.0)
    with serving as simulator:
        served = Served(name, transport, simulator, where)
        with served.open() as served.session:
            yield served


@pytest.fixture
def ecu(served) -> Session:
    return served.session

