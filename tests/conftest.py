"""Fixtures every test package may use, and the settings of the whole run: Qt offscreen when no display
answers, and under pytest-xdist ports of each worker's own.

A test imports helpers by module name, never from a conftest (pytest imports every directory's conftest.py
as ``conftest``, so which one such an import finds depends on the directories collected): a helper of one
directory's tests lives beside them (pytest puts a test's directory on sys.path), one that several
directories share lives in tests/ itself (pyproject's ``pythonpath``); tests/test_suite_layout.py keeps it so."""

from __future__ import annotations

import faulthandler
import os
import shutil
import socket
import sys
import tempfile
import zlib

import pytest
from hypothesis import settings

# Hypothesis' deadline (200 ms an example) is a wall-clock assertion: on a loaded machine (CI, xdist workers, a
# first example that imports a library) it failed tests whose code was right; tests never assert times.
settings.register_profile("workbench", deadline=None)
settings.load_profile("workbench")

# The suite starts many Python processes (xdist workers, `workbench` commands, examples): each reads the
# bytecode this one leaves (asserts rewritten, site-packages compiled), which PYTHONDONTWRITEBYTECODE would
# forbid; compiling the imports again costs a process about three times their import time.
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)


_OWN_CACHE: list[str] = []  # the ELF index cache folder this process made for the run (removed at its end)


def pytest_configure(config) -> None:
    """The run keeps the ELF index cache in a folder of its own (WORKBENCH_CACHE_DIR, which xdist's workers
    inherit), not in the user's cache folder: tests copy ELFs into temporary folders, and each copy's path was an
    entry there.

    The README's test command runs on a machine without a screen too: Qt's offscreen platform is chosen when
    no display answers (Qt's xcb platform would abort the interpreter); an explicit QT_QPA_PLATFORM stays.

    With a display, one process of the run uses it (the first xdist worker), the others render offscreen: two
    processes' windows on one display take the keyboard's focus from each other, and a key test of one then
    types into a window that is not active (its shortcuts, Ctrl+Z, never fire)."""
    from workbench.gui.display import display_problem

    if not os.environ.get("WORKBENCH_CACHE_DIR"):
        _OWN_CACHE.append(tempfile.mkdtemp(prefix="workbench-test-cache-"))
        os.environ["WORKBENCH_CACHE_DIR"] = _OWN_CACHE[0]

    if display_problem() is not None or os.environ.get("PYTEST_XDIST_WORKER", "gw0") != "gw0":
        os.environ["QT_QPA_PLATFORM"] = os.environ.get("QT_QPA_PLATFORM") or "offscreen"


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config) -> None:
    """A process (the run's or an xdist worker) that outlives its tests by two minutes prints where each thread
    stands and ends with exit code 1: what keeps it (a thread, a Qt pool task that never returns) is a bug to see,
    and CI must fail instead of waiting for its time limit. Twice a run's process stayed after its last test
    without a word; pytest-timeout only watches the tests themselves."""
    faulthandler.dump_traceback_later(120, exit=True)
    for folder in _OWN_CACHE:
        shutil.rmtree(folder, ignore_errors=True)


def free_port(kind: socket.SocketKind) -> int:
    """A port of ``kind`` (SOCK_DGRAM: UDP, SOCK_STREAM: TCP) that nothing on this host holds right now.

    Under pytest-xdist a worker takes only the ports that hash to its own number, so tests running at once on
    two workers never share a port (python-can's udp_multicast binds with SO_REUSEADDR: two buses on one port
    hear each other whatever their group); the kernel's choice keeps them apart from other processes on the
    host. A hash, not the remainder: Linux hands out even TCP ports to bind() first.
    """
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    worker = int(os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw") or 0)
    for _ in range(100 * workers):
        with socket.socket(socket.AF_INET, kind) as probe:
            probe.bind(("", 0))
            port = probe.getsockname()[1]
        if zlib.crc32(port.to_bytes(2, "big")) % workers == worker:
            return port
    raise RuntimeError(f"no free port for xdist worker {worker} of {workers}")


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
