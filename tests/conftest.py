"""Fixtures every test package may use."""

from __future__ import annotations

import socket

import pytest


def free_port(kind: socket.SocketKind) -> int:
    """A port of ``kind`` (SOCK_DGRAM: UDP, SOCK_STREAM: TCP) that nothing on this host holds right now."""
    with socket.socket(socket.AF_INET, kind) as probe:
        probe.bind(("", 0))
        return probe.getsockname()[1]


@pytest.fixture
def free_udp_port() -> int:
    """A UDP port of this test's own: for a udp_multicast bus (``bus_kwargs`` ``port``; python-can binds the
    port for every group, so a group of its own does not keep two tests apart) or XCP on UDP."""
    return free_port(socket.SOCK_DGRAM)


@pytest.fixture
def free_tcp_port() -> int:
    """A TCP port of this test's own, e.g. for XCP on TCP."""
    return free_port(socket.SOCK_STREAM)


@pytest.fixture
def another_free_udp_port(free_udp_port) -> int:
    """A second UDP port of this test's own, other than ``free_udp_port`` (for a second bus or simulator)."""
    while (port := free_port(socket.SOCK_DGRAM)) == free_udp_port:
        pass
    return port
