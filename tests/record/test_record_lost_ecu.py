"""A recording whose ECU is lost: it ends with ConnectionLostError naming the link and what the file holds, and the
file is finalized with every sample that came before (in-process, and ``workbench measure --record`` against
``workbench sim`` killed in its own process)."""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest
from mdf_reading import master
from sim_process import start_sim_process

from workbench import ConnectionLostError
from workbench.record import Recorder

CLI = [sys.executable, "-c", "from workbench.cli import entry_point; entry_point()"]


def test_a_recording_ends_when_the_ecu_is_lost_and_the_file_holds_what_came(demo_ecu, session, tmp_path, read_mdf):
    path = tmp_path / "lost.mf4"
    recorder = Recorder(session, path, ["zsRailPressure", "xsDC"]).start()
    try:
        recorder.wait(0.5)
        demo_ecu.simulator.close()
        expected = (rf"XCP on CAN .*nothing from the ECU for .*; {re.escape(str(path))}: [\d.]+ s, [\d,]+ samples "
                    r".* recorded before")
        with pytest.raises(ConnectionLostError, match=expected):
            recorder.wait(30)
    finally:
        recorder.stop()
    assert path.read_bytes()[:8] == b"MDF     "  # finalized
    times = master(read_mdf(path), "Task4ms")
    assert len(times) >= 50 and np.allclose(np.diff(times), 0.004, atol=1e-6)


def test_workbench_measure_record_ends_with_one_line_when_the_simulator_is_killed(free_udp_port, tmp_path, read_mdf):
    bus = ["--bus-kwargs", f"port={free_udp_port}"]
    simulator, _ = start_sim_process(*bus)
    path = tmp_path / "killed-ecu.mf4"
    recording = subprocess.Popen([*CLI, "measure", "zsRailPressure", "xsTankCtrlState", "--record", str(path),
                                  "--duration", "60", *bus], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _wait_for_bytes(path, 20_000, recording)
        simulator.kill()
        out, err = recording.communicate(timeout=60)
    finally:
        recording.kill()
        simulator.kill()
        simulator.communicate(timeout=10)
    assert (recording.returncode, out) == (1, ""), err
    assert re.fullmatch(rf"error: connection to the ECU lost at \d\d:\d\d:\d\d\.\d{{3}}: XCP on CAN \(udp_multicast "
                        rf"239\.74\.163\.2 port {free_udp_port}, ids 0x7F0/0x7F1\): nothing from the ECU for "
                        rf"[\d.]+ m?s while DAQ runs \(a DTO was due within 1000 ms\); {re.escape(str(path))}: "
                        r".* recorded before\n", err), err
    assert path.read_bytes()[:8] == b"MDF     "
    times = master(read_mdf(path), "Task4ms")
    assert len(times) >= 100 and np.allclose(np.diff(times), 0.004, atol=1e-6)


def _wait_for_bytes(path, size: int, recording: subprocess.Popen) -> None:
    import time

    deadline = time.monotonic() + 60
    while not (path.exists() and path.stat().st_size >= size):
        if recording.poll() is not None:  # it ended before: say why (a flake under load was only "did not grow")
            raise AssertionError(f"the recording ended (exit {recording.returncode}): {recording.communicate()}")
        assert time.monotonic() < deadline, "the recording did not grow"
        time.sleep(0.1)
