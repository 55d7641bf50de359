"""``workbench sim``: banner, clean stop (also by Ctrl-C/SIGTERM in a real process), one-line errors."""

from __future__ import annotations

import json
import signal
import time

import pytest
from sim_process import start_sim_process

from workbench.cli import main
from workbench.image import MemoryImage


def test_serves_for_a_duration_and_stops_cleanly(capsys):
    assert main(["sim", "--interface", "virtual", "--channel", "cli-sim-1", "--pcm", "--duration", "0.3"]) == 0
    out = capsys.readouterr().out
    assert "master 0x7F0 -> ECU, ECU -> master 0x7F1" in out
    assert "EPK          10300020250301" in out and "TargetRailPressure 25.0 bar" in out
    assert out.rstrip().endswith("workbench sim: stopped")


def test_json_banner(capsys):
    assert main(["sim", "--interface", "virtual", "--channel", "cli-sim-2", "--json", "--duration", "0.1",
                 "--bitrate", "500000", "--no-app-key"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert (info["state"], info["bitrate"], info["xcp"]["can_id_master"]) == ("boot", 500000, 0x7F0)
    assert info["xcp"]["transport"] == "CAN" and info["buses"]["CAN1"]["channel"] == "cli-sim-2"


def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path):
    assert main(["sim", "--interface", "virtual", "--s19", str(tmp_path / "none.s19")]) == 2
    assert capsys.readouterr().err.strip() == f"error: {tmp_path / 'none.s19'}: no such file"
    assert main(["sim", "--interface", "virtual", "--pcm", "--pcm-target", "80"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: PCM TargetRailPressure 80.0 bar: PCM_TO_FLCU_002:") and err.count("\n") == 1
    assert main(["sim", "--time-scale", "0"]) == 2
    MemoryImage.from_bytes(0x100, b"code").save(tmp_path / "outside.s19")
    assert main(["sim", "--interface", "virtual", "--s19", str(tmp_path / "outside.s19")]) == 2
    assert capsys.readouterr().err.strip().splitlines()[-1] == (
        f"error: {tmp_path / 'outside.s19'}: data outside the ECU's flash (BOOT/APPLICATIVE/CALIB/SHARED): 100h-103h")
    assert main(["sim", "--can2-interface", "virtual"]) == 2
    assert capsys.readouterr().err.strip().splitlines()[-1] == "error: --can2-interface needs --can2-channel (without it CAN2 shares CAN1)"


@pytest.mark.parametrize("option", [["--bitrate", "-5"], ["--bitrate", "0"], ["--duration", "-1"], ["--time-scale", "nan"]])
def test_a_number_out_of_range_is_a_usage_error(capsys, option):
    assert main(["sim", "--interface", "virtual", *option]) == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"must be positive, got {option[1]}")


def test_unknown_interface_is_bad_input_in_one_line(capsys):
    assert main(["sim", "--interface", "no_such_interface", "--duration", "0.1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: CAN1: unknown python-can interface 'no_such_interface' (known: ")
    assert "virtual" in err and err.count("\n") == 1


def test_help_names_the_options(capsys):
    assert main(["sim", "--help"]) == 0
    out = capsys.readouterr().out
    for option in ("--pcm", "--pcm-target", "--can2-channel", "--bitrate", "--time-scale", "--unlocked", "--a2l", "--elf", "--s19"):
        assert option in out


@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_a_signal_stops_the_process_cleanly(signal_number):
    process, _ = start_sim_process("--interface", "virtual", "--channel", f"cli-sim-signal-{signal_number}", "--pcm",
                                   "--bitrate", "1000000")
    time.sleep(0.3)  # the clock, the PCM and the transmitter are running
    process.send_signal(signal_number)
    try:
        out, err = process.communicate(timeout=15)
    finally:
        process.kill()
    assert process.returncode == 0, err
    assert out.rstrip().endswith("workbench sim: stopped") and err == ""
