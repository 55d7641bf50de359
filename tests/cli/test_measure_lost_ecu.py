"""A lost ECU as a user meets it on the command line, each process of its own: nothing at an Ethernet address,
and ``workbench sim`` killed while ``workbench measure --daq`` runs. stderr holds our lines only (never a
traceback), the exit code is 1, and the command ends at once instead of running to its deadline."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time

import pytest
from sim_process import start_sim_process

CLI = [sys.executable, "-c", "from workbench.cli import entry_point; entry_point()"]
LOST = re.compile(r"error: connection to the ECU lost at \d\d:\d\d:\d\d\.\d{3}: "
                  r"XCP on (UDP|TCP) \(127\.0\.0\.1:\d+\): ")


@pytest.mark.parametrize("protocol", ["udp", "tcp"])
def test_nothing_at_an_ethernet_address_is_our_one_line(protocol, free_udp_port, free_tcp_port):
    port = free_udp_port if protocol == "udp" else free_tcp_port
    result = subprocess.run([*CLI, "cal", "get", "xsSWITCH_TANK_THR", "--host", "127.0.0.1", "--port", str(port),
                             "--protocol", protocol], capture_output=True, text=True, timeout=120)
    assert (result.returncode, result.stdout) == (1, "")
    kind = protocol.upper()
    assert result.stderr == (f"error: cannot reach the ECU: XCP on {kind} (127.0.0.1:{port}): nothing listens at "
                             f"127.0.0.1:{port} (connection refused)\n")  # UDP and TCP alike


@pytest.mark.parametrize("protocol", ["udp", "tcp"])
def test_killing_the_simulator_ends_measure_daq_with_one_line(protocol, free_udp_port, free_tcp_port):
    port = str(free_udp_port if protocol == "udp" else free_tcp_port)
    ethernet = ["--host", "127.0.0.1", "--port", port, "--protocol", protocol]
    simulator, _ = start_sim_process(*ethernet)
    measure = subprocess.Popen([*CLI, "measure", "zsRailPressure", "xsDC", "--daq", "--duration", "60", "--json",
                                *ethernet], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(50):  # samples come: the measurement runs
            assert measure.stdout.readline(), measure.stderr.read()
        simulator.kill()
        killed = time.monotonic()
        out, err = measure.communicate(timeout=60)
        ended = time.monotonic() - killed
    finally:
        measure.kill()
        simulator.kill()
        simulator.communicate(timeout=10)
    assert measure.returncode == 1, err
    rows = [json.loads(line) for line in out.splitlines()]  # JSON Lines to the end: the failure too (it was indented)
    assert rows[-1] == {"ok": False, "error": err.splitlines()[-1].removeprefix("error: "), "exit_code": 1}
    lines = err.splitlines()
    assert len(lines) == 2 and re.fullmatch(r"measure: \d+ samples, 0 lost, 0 overload indications", lines[0]), err
    assert LOST.match(lines[1]), err
    if protocol == "tcp":
        assert lines[1].endswith("the ECU closed the TCP connection")
    else:  # XCP on UDP says nothing when the slave ends: the DTOs stop, T1 (1 s) is the A2L's bound
        assert "nothing from the ECU for" in lines[1]
    assert ended < 30  # not at the 60 s deadline, nor after seconds of stop commands timing out
