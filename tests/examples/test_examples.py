"""The scripts in examples/ run as a user runs them: a separate process against the simulated ECU, twice in a row
(what one run leaves behind, a file or a value in the ECU, must not break the next)."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

from workbench.sim import serve_demo

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture
def port(free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}, pcm_target_bar=25.0):
        yield str(free_udp_port)


def run(script: str, *args: str) -> str:
    """The output of the second of two runs in a row."""
    for _ in range(2):
        result = subprocess.run([sys.executable, str(EXAMPLES / script), *args], capture_output=True, text=True,
                                timeout=60)
        assert result.returncode == 0, result.stderr
        assert result.stderr == ""
    return result.stdout


def test_measure(port):
    out = run("measure.py", port).splitlines()
    assert out[0].startswith("EPK match") and len(out) == 11
    assert all(line.startswith("rail ") for line in out[1:])


def test_calibrate(port):
    out = run("calibrate.py", port)
    assert "now: 25.0 bar" in out and "refused: xsSWITCH_TANK_THR: 2500.00 is above the upper limit 800.00" in out
    assert "restored: 20.0 bar, 35.0 %" in out


def test_override(port):
    out = run("override.py", port)
    assert "rail pressure with the fix: 30.00 bar" in out and "zfRAILPRESSURE" in out


def test_daq_to_csv(port, tmp_path):
    out = run("daq_to_csv.py", str(tmp_path / "daq.csv"), port)
    assert out.endswith("0 lost -> " + str(tmp_path / "daq.csv") + "\n")
    with open(tmp_path / "daq.csv") as file:
        rows = list(csv.DictReader(file))
    rail = [float(row["time_s"]) for row in rows if row["signal"] == "zsRailPressure"]
    assert len(rail) > 300 and rail == sorted(rail)
    assert {row["event"] for row in rows} == {"Task4ms", "Task50ms"}


def test_record_mdf(port, tmp_path):
    out = run("record_mdf.py", str(tmp_path / "run.mf4"), port).splitlines()
    assert out[0].startswith(f"recorded {tmp_path / 'run.mf4'}: ") and " 0 lost" in out[0]
    assert out[1].startswith("zsRailPressure: ") and " bar at " in out[1]
    assert out[2] in ("xsTankCtrlState: OFF", "xsTankCtrlState: TANK1_ON", "xsTankCtrlState: TANK2_ON")
    assert out[3] == "TargetRailPressure from the raw bus log: 25.00 bar"
