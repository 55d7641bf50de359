"""``workbench sim`` in a process of its own, for the tests of the two-process workflow and of signals."""

from __future__ import annotations

import subprocess
import sys
import threading

import pytest


def start_sim_process(*args: str, timeout_s: float = 30.0) -> tuple[subprocess.Popen, str]:
    """Start ``workbench sim ARGS``; returns the process and its banner once it says it serves.

    :raises pytest.fail: it exits or says nothing of serving within ``timeout_s`` (it is killed then).
    """
    process = subprocess.Popen(
        [sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "sim", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    banner: list[str] = []
    serving = threading.Event()

    def watch() -> None:  # a thread, so that a silent process cannot block the test
        for line in process.stdout:
            banner.append(line)
            if line.startswith("serving"):
                serving.set()
                return

    threading.Thread(target=watch, daemon=True).start()
    if not serving.wait(timeout_s):
        process.kill()
        out, err = process.communicate(timeout=10)
        pytest.fail(f"workbench sim did not start: {''.join(banner)}{out} {err}")
    return process, "".join(banner)
