"""Ctrl-C as the commands' help promises it, in a real process started as a user's script starts it:
``workbench ... &`` in a non-interactive shell starts with SIGINT ignored (POSIX), and Python leaves it so."""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys

import pytest

from workbench.sim import serve_demo

ENTRY = "from workbench.cli import entry_point; entry_point()"


def in_the_background(*argv: str, ready: str) -> tuple[subprocess.Popen, int, list[str]]:
    """``workbench ARGV &`` in a shell script; returns the script, the command's pid and its output up to the
    first line that starts with ``ready``."""
    command = " ".join([shlex.quote(sys.executable), "-c", shlex.quote(ENTRY), *map(shlex.quote, argv)])
    script = subprocess.Popen(["sh", "-c", f'{command} & echo "pid $!"; wait $!; echo "exit $?"'],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    pid = int(script.stdout.readline().split()[1])
    seen = []
    for line in script.stdout:
        seen.append(line)
        if line.startswith(ready):
            break
    return script, pid, seen


def stopped_by_sigint(script: subprocess.Popen, pid: int) -> tuple[list[str], str]:
    """Send SIGINT to the command; the script's lines after it (its ``exit N`` last) and its stderr."""
    try:
        os.kill(pid, signal.SIGINT)
        out, err = script.communicate(timeout=30)
        return out.splitlines(), err
    finally:
        for left in (pid, script.pid):  # whatever still runs after a failure
            try:
                os.kill(left, signal.SIGKILL)
            except ProcessLookupError:
                pass


def test_sim_in_the_background_of_a_script_stops_on_sigint(free_udp_port):
    script, pid, _ = in_the_background("sim", "--bus-kwargs", f"port={free_udp_port}", ready="serving; Ctrl-C stops")
    lines, err = stopped_by_sigint(script, pid)
    assert lines[-2:] == ["workbench sim: stopped", "exit 0"], err


def test_measure_in_the_background_of_a_script_stops_on_sigint(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        script, pid, seen = in_the_background("measure", "zsRailPressure", "--bus-kwargs", f"port={free_udp_port}",
                                              ready="")
        lines, err = stopped_by_sigint(script, pid)
    assert "zsRailPressure=" in seen[0] and lines[-1] == "exit 0", err


def test_ctrl_c_while_the_command_line_is_being_read_is_one_line(capsys, monkeypatch):
    """Ctrl-C at once after Enter falls into the parser's imports (python-can, pandas): no traceback."""
    import workbench.cli
    from workbench.cli import main

    def interrupted(group):
        raise KeyboardInterrupt

    monkeypatch.setattr(workbench.cli, "build_parser", interrupted)
    try:
        code = main(["record", "run.mf4", "zsRailPressure"])
    except KeyboardInterrupt:  # escaping, it would end the whole test run
        pytest.fail("Ctrl-C escaped main() as a traceback")
    assert code == 130
    assert capsys.readouterr().err == "error: interrupted\n"
