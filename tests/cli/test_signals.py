"""Ctrl-C as the commands' help promises it, in a real process started as a user's script starts it."""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys

ENTRY = "from workbench.cli import entry_point; entry_point()"


def test_sim_started_in_the_background_of_a_script_stops_on_sigint(free_udp_port):
    """``workbench sim &`` in a non-interactive shell starts with SIGINT ignored (POSIX); its banner says Ctrl-C
    stops it, so the command installs the handler itself."""
    command = f"{shlex.quote(sys.executable)} -c {shlex.quote(ENTRY)} sim --bus-kwargs port={free_udp_port}"
    script = f'{command} & echo "pid $!"; wait $!; echo "exit $?"'
    process = subprocess.Popen(["sh", "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    pid = int(process.stdout.readline().split()[1])
    try:
        for line in process.stdout:
            if line.startswith("serving; Ctrl-C stops"):
                break
        os.kill(pid, signal.SIGINT)
        out, err = process.communicate(timeout=30)
    finally:
        for left in (pid, process.pid):  # whatever still runs after a failure
            try:
                os.kill(left, signal.SIGKILL)
            except ProcessLookupError:
                pass
    assert out.splitlines()[-2:] == ["workbench sim: stopped", "exit 0"], err
