"""``workbench sim``: banner, clean stop (also by Ctrl-C/SIGTERM in a real process), one-line errors,
XCP on Ethernet end to end."""

from __future__ import annotations

import json
import signal
import socket
import struct
import subprocess
import sys
import time

import pytest
from eth_master import RawEthMaster
from sim_process import start_sim_process

from workbench.cli import main
from workbench.image import MemoryImage
from workbench.xcp_protocol import Cmd


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


def test_options_the_interface_refuses_are_bad_input_in_one_line(capsys):
    """``--bus-kwargs port=abc``: python-can's ValueError is the user's input (exit 2), as the master says it."""
    assert main(["sim", "--interface", "udp_multicast", "--bus-kwargs", "port=abc", "--duration", "0.1"]) == 2
    assert capsys.readouterr().err == ("error: cannot open CAN1 bus (udp_multicast 239.74.163.2): "
                                       "Port config must be a number!\n")


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


def test_xcp_on_tcp_end_to_end_in_a_process_of_its_own(free_tcp_port):
    process, banner = start_sim_process("--host", "127.0.0.1", "--port", str(free_tcp_port), "--protocol", "tcp",
                                        "--duration", "2")
    try:
        assert f"XCP          on TCP at 127.0.0.1:{free_tcp_port} (MAX_CTO 255, MAX_DTO 1024)" in banner
        assert "CAN2 (FLCU)  not connected" in banner
        with RawEthMaster(("127.0.0.1", free_tcp_port), "TCP") as master:
            (ctr, response), = master.request(bytes([Cmd.CONNECT, 0]))
            assert ctr == 0 and response[0] == 0xFF and struct.unpack_from("<BH", response, 3) == (255, 1024)
            assert master.request(bytes([Cmd.GET_STATUS]))[0][0] == 1
        out, err = process.communicate(timeout=15)  # --duration 2: it stops by itself
    finally:
        process.kill()
    assert process.returncode == 0 and err == ""
    assert out.rstrip().endswith("workbench sim: stopped")


def test_a_second_simulator_on_the_same_can_bus_is_refused(capsys, free_udp_port):
    """Two ECUs on one bus and ids answer every command twice (in two byte orders with two profiles)."""
    bus = ["--bus-kwargs", f"port={free_udp_port}"]
    process, _ = start_sim_process(*bus, "--duration", "30")
    try:
        assert main(["sim", *bus, "--profile", "motorola", "--duration", "0.1"]) == 2
    finally:
        process.kill()
        process.communicate(timeout=15)
    assert capsys.readouterr().err == (
        f"error: another workbench sim (pid {process.pid}) serves on udp_multicast 239.74.163.2 "
        f"(port={free_udp_port}): two ECUs on the same ids answer every command twice; stop it, or serve on a port "
        "of its own (--bus-kwargs port=N)\n")


def test_xcp_on_udp_json_banner_names_the_port_it_took(capsys):
    assert main(["sim", "--host", "127.0.0.1", "--port", "0", "--json", "--duration", "0.1"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["xcp"]["transport"] == "UDP" and info["xcp"]["port"] > 0 and info["buses"] == {}
    assert (info["xcp"]["max_cto"], info["xcp"]["max_dto"]) == (255, 1024)


@pytest.mark.parametrize("protocol, kind", [("udp", socket.SOCK_DGRAM), ("tcp", socket.SOCK_STREAM)])
def test_a_port_in_use_fails_in_one_line(capsys, protocol, kind):
    with socket.socket(socket.AF_INET, kind) as taken:
        taken.bind(("127.0.0.1", 0))
        if kind == socket.SOCK_STREAM:
            taken.listen(1)
        port = taken.getsockname()[1]
        assert main(["sim", "--host", "127.0.0.1", "--port", str(port), "--protocol", protocol, "--duration", "0.1"]) == 1
    assert capsys.readouterr().err == f"error: cannot serve XCP on {protocol.upper()} at 127.0.0.1:{port}: Address already in use\n"


@pytest.mark.parametrize("options", [["--protocol", "tcp"], ["--port", "5555"]])
def test_ethernet_options_without_host_are_bad_input(capsys, options):
    assert main(["sim", *options, "--duration", "0.1"]) == 2
    assert capsys.readouterr().err == (
        "error: --port and --protocol are for XCP on Ethernet: give --host too (e.g. --host 127.0.0.1)\n")


@pytest.mark.parametrize("options, message", [
    (["--protocol", "sctp"], "invalid choice: 'sctp'"),
    (["--port", "70000"], "must be 0..65535, got 70000"),
    (["--bus-kwargs", "port"], "Unable to parse bus keyword argument 'port'"),
])
def test_malformed_options_are_usage_errors(capsys, options, message):
    assert main(["sim", "--host", "127.0.0.1", *options]) == 2
    assert message in capsys.readouterr().err.splitlines()[-1]


def test_the_bus_options_cost_nothing_until_a_command_needs_them():
    """python-can's options import python-can (and asammdf): only the commands that talk to a bus pay for it."""
    code = ("import sys, contextlib, io\nfrom workbench.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    main(sys.argv[1:])\n"
            "print('can' in sys.modules)")
    loaded = {args[0]: subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True).stdout.strip()
              for args in (["--help"], ["a2l", "check", "--help"], ["sim", "--help"])}
    assert loaded == {"--help": "False", "a2l": "False", "sim": "True"}
