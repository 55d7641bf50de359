"""``workbench measure ... --record`` end to end: against the simulated ECU (a virtual bus in the test's process; a
``workbench sim`` process on a udp_multicast port of the test's own for the recording process killed with SIGKILL),
options and exit codes as a user meets them."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from cli_helpers import run
from mdf_reading import channel, group_index, master
from sim_process import start_sim_process

from workbench import demo
from workbench.cli import main

CLI = [sys.executable, "-c", "from workbench.cli import entry_point; entry_point()"]


@pytest.fixture
def bus(demo_ecu) -> list[str]:
    return demo_ecu.cli_options



def test_record_with_can2_and_the_raw_bus(bus, capsys, tmp_path, read_mdf):
    path = tmp_path / "run.mf4"
    code, out, err = run(capsys, "measure", "zsRailPressure", "xsTankCtrlState", "--record", str(path),
                         "--can2", str(demo.dbc_can2()), "--raw-can", "--duration", "1.5", "--json", *bus)
    assert code == 0 and err == ""
    summary = json.loads(out)
    assert summary["path"] == str(path) and summary["lost"] == 0 and summary["samples"] > 300
    assert summary["can_frames"] > 10 and summary["raw_frames"] > summary["can_frames"]
    mdf = read_mdf(path)
    assert mdf.groups[group_index(mdf, "Task4ms")].channel_group.cycles_nr + \
        mdf.groups[group_index(mdf, "Task50ms")].channel_group.cycles_nr == summary["samples"]
    assert np.allclose(channel(mdf, "PCM_TO_FLCU_002", "TargetRailPressure").samples, 25.0)
    assert summary["file_bytes"] == path.stat().st_size
    code, out, _ = run(capsys, "measure", "xsDC", "--record", str(tmp_path / "text.mf4"), "--duration", "0.3", *bus)
    assert code == 0 and out.startswith(f"recorded {tmp_path / 'text.mf4'}: ") and "0 lost" in out


def test_an_existing_file_needs_overwrite(bus, capsys, tmp_path):
    path = tmp_path / "old.mf4"
    path.write_bytes(b"keep me")
    code, out, err = run(capsys, "measure", "xsDC", "--record", str(path), "--duration", "0.2", *bus)
    assert (code, out) == (2, "") and "old.mf4: exists" in err and path.read_bytes() == b"keep me"
    code, _, _ = run(capsys, "measure", "xsDC", "--record", str(path), "--overwrite", "--duration", "0.3", *bus)
    assert code == 0 and path.read_bytes()[:3] == b"MDF"


def test_a_protected_file_or_another_format_s_name_is_not_recorded_to(bus, capsys, tmp_path):
    """--overwrite replaces a recording, not a file the user made read-only (as every written file); an MDF4 file
    named .csv would be taken for one by the next tool."""
    released = tmp_path / "released.mf4"
    released.write_bytes(b"keep me")
    released.chmod(0o444)
    code, out, err = run(capsys, "measure", "xsDC", "--record", str(released), "--overwrite", "--duration", "0.2", *bus)
    assert (code, out) == (2, "") and "released.mf4: the file is read-only; not overwritten" in err
    assert released.read_bytes() == b"keep me"
    code, out, err = run(capsys, "record", str(tmp_path / "run.csv"), "xsDC", "--duration", "0.2", *bus)
    assert (code, out, err) == (2, "", f"error: {tmp_path / 'run.csv'}: a recording is an MDF4 file; name it .mf4\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["released.mf4"]


@pytest.mark.parametrize(("options", "message"), [
    (["--raw-can", "--overwrite"], "--raw-can, --overwrite: only with --record"),
    (["--record", "x.mf4", "--raw"], "--raw does not go with --record"),
    (["--pre-trigger", "1", "--stop-when", "xsDC > 1"], "--stop-when, --pre-trigger: only with --record"),
    (["--record", "x.mf4", "--pre-trigger", "1"], "--pre-trigger S: only with --start-when"),
    (["--record", "x.mf4", "--start-when", "xsDC 3"], "trigger condition 'xsDC 3': write NAME OP VALUE"),
])
def test_recording_options_out_of_place_are_usage_errors(capsys, tmp_path, options, message):
    code, out, err = run(capsys, "measure", "xsDC", *options)
    assert (code, out) == (2, "") and message in err and not (tmp_path / "x.mf4").exists()


def test_record_is_measure_record_as_a_command_of_its_own(bus, capsys, tmp_path, read_mdf):
    path = tmp_path / "run.mf4"
    code, out, err = run(capsys, "record", str(path), "xsDC", "xsTankCtrlState", "--duration", "0.3", *bus)
    assert code == 0 and err == "" and out.startswith(f"recorded {path}: ")
    assert len(channel(read_mdf(path), "Task50ms", "xsDC")) >= 5
    for argv, message in ((["record"], "name the file to record to"),
                          (["record", str(tmp_path / "none.mf4")], "nothing to record to"),
                          (["record", str(path), "--repair", str(path)], "--repair FILE... takes the files"),
                          (["record", "--repair", str(tmp_path / "gone.mf4")], "gone.mf4: no such file")):
        code, out, err = run(capsys, *argv, *bus)
        assert (code, out) == (2, "") and message in err, argv
    assert not (tmp_path / "none.mf4").exists()


def test_a_killed_recording_leaves_a_readable_file(free_udp_port, tmp_path, read_mdf, capsys):
    """SIGKILL, no chance to finalize: the file where it was asked for holds everything up to the last flush."""
    bus = ["--bus-kwargs", f"port={free_udp_port}"]
    sim, _ = start_sim_process("--pcm", *bus)
    path = tmp_path / "killed.mf4"
    recording = subprocess.Popen([*CLI, "measure", "zsRailPressure", "zsSensVolt", "xsTankCtrlState", "--record",
                                  str(path), "--can2", str(demo.dbc_can2()), "--raw-can", *bus],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        _wait_for_records(path, 500)  # two flushes of the 4 ms event at least
        os.kill(recording.pid, signal.SIGKILL)
        recording.wait(10)
    finally:
        recording.kill()
        sim.terminate()
        sim.wait(10)
    assert recording.returncode == -signal.SIGKILL
    assert path.read_bytes()[:8] == b"UnFinMF "  # it never came to finalize
    mdf = read_mdf(path)
    times = master(mdf, "Task4ms")
    assert len(times) >= 500 and np.allclose(np.diff(times), 0.004, atol=1e-6)  # no sample missing before the kill
    assert np.allclose(np.diff(master(mdf, "Task50ms")), 0.05, atol=1e-6)
    assert len(channel(mdf, "Task4ms", "zsSensVolt[3]")) == len(times)
    assert np.allclose(channel(mdf, "PCM_TO_FLCU_002", "TargetRailPressure").samples, 25.0)
    extracted = mdf.extract_bus_logging({"CAN": [(str(demo.dbc_can2()), 0)]})
    try:
        assert np.allclose(extracted.get("TargetRailPressure").samples, 25.0)
    finally:
        extracted.close()
    code = main(["record", "--repair", str(path), "--json"])  # for MATLAB's mdfInfo, which refuses unfinalized files
    (report,) = json.loads(capsys.readouterr().out)
    assert code == 0 and report["finalized"] and path.read_bytes()[:8] == b"MDF     "
    assert report["groups"]["Task4ms"] == len(master(read_mdf(path), "Task4ms")) == len(times)
    assert report["seconds"] >= times[-1]
    assert main(["record", "--repair", str(path)]) == 0
    assert capsys.readouterr().out.startswith(f"{path}: was finalized already; ")


@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_ctrl_c_or_sigterm_ends_the_recording_and_finalizes_it(free_udp_port, tmp_path, read_mdf, signal_number):
    """Ctrl-C, and SIGTERM as a service manager, `kill` or a CI timeout sends it, end a recording alike: the file
    finalized and the summary printed (SIGTERM killed the process before)."""
    bus = ["--bus-kwargs", f"port={free_udp_port}"]
    sim, _ = start_sim_process(*bus)
    path = tmp_path / "interrupted.mf4"
    recording = subprocess.Popen([*CLI, "measure", "xsDC", "--record", str(path), "--json", *bus],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _wait_for_records(path, 20)
        recording.send_signal(signal_number)
        out, err = recording.communicate(timeout=30)
    finally:
        recording.kill()
        sim.terminate()
        sim.wait(10)
    assert recording.returncode == 0, err
    assert path.read_bytes()[:8] == b"MDF     "
    assert len(master(read_mdf(path), "Task50ms")) == json.loads(out)["samples"] >= 20


def _wait_for_records(path, records: int) -> None:
    deadline = time.monotonic() + 60
    while _recorded(path) < records and time.monotonic() < deadline:
        time.sleep(0.2)


def _recorded(path) -> int:
    """Task4ms records in the file so far (0 before it exists)."""
    from asammdf import MDF

    if not path.exists():
        return 0
    with MDF(path) as mdf:
        return mdf.groups[0].channel_group.cycles_nr


@pytest.mark.parametrize("option", ["--stop-when", "--start-when"])
def test_a_condition_on_an_unknown_name_is_refused_with_its_text(capsys, tmp_path, option):
    """The refusal quotes the condition as typed: start and stop may name different signals. It comes before
    connecting: on a bus where no ECU answers, it was 'no ECU answers' after the CONNECT's timeout."""
    path = tmp_path / "x.mf4"
    nobody = ["--interface", "virtual", "--channel", f"nobody-{tmp_path.name}"]
    code, out, err = run(capsys, "record", str(path), "xsDC", option, "unknown==1", "--duration", "0.2", *nobody)
    role = option[2:-5]
    assert (code, out) == (2, "") and "unknown symbol 'unknown'" in err and f"({role} condition 'unknown==1')" in err
    assert err.count("\n") == 1 and not path.exists()


def test_a_csv_export_names_each_column_by_the_ecu_and_the_signal(bus, capsys, tmp_path, read_mdf):
    """asammdf names a channel by its source's path too ('<path>.<name>', what its CSV export writes as the column):
    the ECU's name, not the transport's description ('XCP on CAN (virtual record-test-0, ids 0x7F0/0x7F1)')."""
    path = tmp_path / "run.mf4"
    code, out, err = run(capsys, "record", path, "zsRailPressure", "PRVCtrl_DW.Integrator_DSTATE", "--duration", "0.3",
                         *bus)
    assert code == 0, err
    mdf = read_mdf(path)
    assert set(mdf.get("PRVCtrl_DW.Integrator_DSTATE").display_names) == {"FLCU.PRVCtrl_DW.Integrator_DSTATE"}
    source = mdf.groups[group_index(mdf, "Task4ms")].channel_group.acq_source
    assert (source.name, source.path) == ("FLCU", "FLCU") and source.comment.startswith("XCP on CAN (virtual ")
    mdf.export("csv", tmp_path / "run.csv", single_time_base=True)
    columns = (tmp_path / "run.csv").read_text().splitlines()[0]
    assert columns == ("timestamps,FLCU.HostTime_Task4ms,FLCU.zsRailPressure,FLCU.HostTime_Task50ms,"
                       "FLCU.PRVCtrl_DW.Integrator_DSTATE")


@pytest.mark.parametrize("condition, code, said", [
    ("zsSensVolt[2] > 3", 0, "stop when zsSensVolt[2] > 3: started at 0.000 s"),  # 4 V at once (the rail's [3] < 3)
    ("zsSensVolt[3] < 4.5 V", 0, "stop when zsSensVolt[3] < 4.5 V: started at 0.000 s"),
    ("zsSensVolt[4] > 1", 2, "error: trigger condition 'zsSensVolt[4] > 1': zsSensVolt has 4 elements\n"),
    ("zsSensVolt > 3", 2, "error: trigger condition 'zsSensVolt > 3': zsSensVolt has 4 elements: compare one of them "
                          "(zsSensVolt[0] ... zsSensVolt[3])\n"),  # the whole array was judged as one row of them
    ("zsSensVolt[0] > 4 bar", 2, "error: trigger condition 'zsSensVolt[0] > 4 bar': '4 bar' is in bar, zsSensVolt in V "
                                 "(no unit conversion)\n"),
])
def test_a_condition_on_an_array_s_element_in_the_signal_s_unit(bus, capsys, tmp_path, read_mdf, condition, code, said):
    """As the NAMEs take one element of an array (the array is recorded) and cal set a value with its unit."""
    path = tmp_path / "x.mf4"
    status, out, err = run(capsys, "record", path, "zsSensVolt[2]", "--stop-when", condition, "--duration", "5", *bus)
    assert status == code and said in (out if code == 0 else err), (out, err)
    if code == 0:
        assert len(channel(read_mdf(path), "Task4ms", "zsSensVolt[3]")) == 1  # the sample that met it is the last
    else:
        assert not path.exists()


def test_can2_channels_are_named_as_asammdf_names_the_bus_log_s_signals(bus, capsys, tmp_path, read_mdf):
    """A decoded CAN2 signal reads 'CAN2.<message>.<signal>', as asammdf's extract_bus_logging names the same signal
    from the raw log (it read '<the DBC file>.<signal>'); the raw log 'CAN2.CAN_DataFrame' (it read '<the bus's
    options>.CAN_DataFrame')."""
    path = tmp_path / "run.mf4"
    code, out, err = run(capsys, "record", path, "xsDC", "--can2", demo.dbc_can2(), "--raw-can", "--duration", "0.5",
                         *bus)
    assert code == 0, err
    mdf = read_mdf(path)
    assert set(mdf.get("TargetRailPressure").display_names) == {"CAN2.PCM_TO_FLCU_002.TargetRailPressure"}
    extracted = mdf.extract_bus_logging({"CAN": [(str(demo.dbc_can2()), 0)]})
    assert "CAN2.PCM_TO_FLCU_002.TargetRailPressure" in extracted.get("TargetRailPressure").display_names
    assert set(mdf.get("CAN_DataFrame").display_names) == {"CAN2.CAN_DataFrame"}
