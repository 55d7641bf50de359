"""``workbench test``: bad input is exit 2; the shipped suite, run with the command's pytest arguments (in this
process, as pytester runs pytest: a process of its own would cost its imports), fails naming the requirement
against a demo ECU whose s19 breaks it while an unrelated one passes, and passes against ``workbench sim`` in
another process given only bus options, fault injection included."""

from __future__ import annotations

import argparse
import re
import struct
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from sim_process import start_sim_process

from workbench import demo
from workbench.cli import build_parser, main
from workbench.cli.test import pytest_arguments
from workbench.elf import ElfSymbols
from workbench.image import load_image

CAL_RAM, CAL_ROM = 0x40000000, 0xFC0000
PRV = "rail_pressure_follows_the_target"  # SW_REQ_ID_003.1
FUEL = "fuel_level_from_both_tank_pressures"  # SW_REQ_ID_006.1


pytest_plugins = ["pytester"]


def _run(pytester, *args: str):
    """``workbench test ARGS`` as the command runs pytest, in this process."""
    parsed: argparse.Namespace = build_parser().parse_args(["test", *args])
    return pytester.runpytest_inprocess(*pytest_arguments(parsed))


def _outcomes(junit) -> dict[str, tuple[str, list[str]]]:
    outcomes = {}
    for case in ET.parse(junit).iter("testcase"):
        kinds = [child.tag for child in case if child.tag in ("failure", "error", "skipped")]
        outcomes[case.get("name")] = (kinds[0] if kinds else "passed",
                                      [p.get("value") for p in case.iter("property") if p.get("name") == "requirement"])
    return outcomes


def test_repeat_without_pytest_repeat_says_what_to_install(monkeypatch, capsys):
    import importlib.util

    find_spec = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *args: None if name == "pytest_repeat" else find_spec(name, *args))
    assert main(["test", "--repeat", "2"]) == 2
    assert capsys.readouterr().err.strip() == "error: --repeat needs pytest-repeat: pip install pytest-repeat"


def test_bad_input_is_exit_2(capsys, tmp_path):
    assert main(["test", str(tmp_path / "none.py")]) == 2
    assert capsys.readouterr().err.strip() == f"error: {tmp_path / 'none.py'}: no such test file or folder"
    assert main(["test", "-n", "2", "--interface", "virtual", "--channel", "x"]) == 2
    assert "a real ECU (bus options) takes one master at a time" in capsys.readouterr().err
    (tmp_path / "file").write_text("")
    assert main(["test", "--report", str(tmp_path / "file")]) == 2
    assert capsys.readouterr().err.strip() == f"error: --report {tmp_path / 'file'}: is a file; name a folder"
    assert main(["test", "--report", str(tmp_path / "file" / "out")]) == 2  # below a file: no traceback at the end
    assert capsys.readouterr().err.strip().startswith(f"error: --report {tmp_path / 'file' / 'out'}: cannot be "
                                                      "created (")
    report = tmp_path / "out"  # a catalogue that cannot be read is refused before any test runs
    assert main(["test", "--report", str(report), "--requirements", str(tmp_path / "none.csv")]) == 2
    assert capsys.readouterr().err.strip() == f"error: {tmp_path / 'none.csv'}: no such file"
    assert not (report / "junit.xml").exists()
    assert main(["test", "--verdict-log", str(tmp_path)]) == 2  # a folder, not a file: no INTERNALERROR traceback
    assert capsys.readouterr().err.strip() == f"error: --verdict-log {tmp_path}: is a folder; name a file"
    assert main(["test", "--verdict-log", str(tmp_path / "file" / "v.jsonl")]) == 2  # below a file
    assert f"--verdict-log {tmp_path / 'file' / 'v.jsonl'}: cannot be written (" in capsys.readouterr().err


def test_a_flash_whose_calibration_breaks_a_requirement_fails_that_requirement(pytester, tmp_path):
    """xsPRV_DC_MAX = 0 % in the s19's CAL ROM: the PRV cannot open, the rail cannot follow its target."""
    image = load_image(demo.s19())
    address = ElfSymbols(demo.elf()).symbol("xsPRV_DC_MAX").address - CAL_RAM + CAL_ROM
    assert struct.unpack("<f", image.read(address, 4)) == (100.0,)
    image.add(address, struct.pack("<f", 0.0), overwrite=True)
    broken = tmp_path / "broken.s19"
    image.save(broken)
    run = _run(pytester, "--sim-s19", str(broken), "-k", f"{PRV} or {FUEL}", "--report", str(tmp_path / "out"))
    assert run.ret == 1
    run.stdout.fnmatch_lines(["FAILED SW_REQ_ID_003.1: test_prv_ctrl.py::test_rail_pressure_follows_the_target"])
    outcomes = _outcomes(tmp_path / "out" / "junit.xml")
    assert outcomes == {"test_rail_pressure_follows_the_target": ("failure", ["SW_REQ_ID_003.1"]),
                        "test_fuel_level_from_both_tank_pressures": ("passed", ["SW_REQ_ID_006.1"])}
    html = (tmp_path / "out" / "report.html").read_text()
    assert "wait until zsRailPressure within [24, 26] bar (timeout 2.3 s): not within 2.3 s; last 0 bar" in html
    evidence = sorted(p.name for p in (tmp_path / "out" / "evidence").iterdir())
    assert evidence == ["test_fuel_level.py-test_fuel_level_from_both_tank_pressures.mf4",
                        "test_prv_ctrl.py-test_rail_pressure_follows_the_target.mf4"]  # one file each: all watched


def test_the_suite_runs_against_workbench_sim_in_another_process(pytester, tmp_path, free_udp_port):
    bus = ["--interface", "udp_multicast", "--bus-kwargs", f"port={free_udp_port}"]
    process, banner = start_sim_process(*bus)
    try:
        assert "control      127.0.0.1:" in banner
        run = _run(pytester, *bus, "-k", "outside_its_span and rail", "--report", str(tmp_path / "out"))
    finally:
        process.terminate()
        process.wait(timeout=30)
    assert run.ret == 0
    assert _outcomes(tmp_path / "out" / "junit.xml") == {  # passed, not skipped: the faults reached the other process
        "test_a_sensor_outside_its_span_is_diagnosed[rail]": ("passed", ["SW_REQ_ID_008.4"])}


def test_a_can2_bus_of_its_own_reaches_the_tests_whole():
    """``workbench test --can2-bus-kwargs`` goes to the plugin, which builds the CAN2 bus beside the XCP bus."""
    from argparse import Namespace

    from workbench.testbench.options import target_from_options

    parsed = build_parser().parse_args(["test", "--interface", "udp_multicast", "--bus-kwargs", "port=43200",
                                        "--can2-channel", "239.74.163.9", "--can2-bus-kwargs", "port=43201",
                                        "bitrate=500000"])
    argv = pytest_arguments(parsed)
    assert argv[argv.index("--can2-bus-kwargs"):][:3] == ["--can2-bus-kwargs", "port=43201", "bitrate=500000"]
    options = {name: None for name in ("a2l", "interface", "channel", "bitrate", "bus_kwargs", "host", "port",
                                       "protocol", "key_function", "accept_epk_mismatch", "dbc", "can2_interface",
                                       "can2_channel", "can2_bus_kwargs", "sim_s19", "sim_control")}
    options.update(interface="udp_multicast", bus_kwargs=["port=43200"], can2_channel="239.74.163.9",
                   can2_bus_kwargs=["port=43201", "bitrate=500000"])
    target = target_from_options(Namespace(**options))
    assert target.can2_bus == {"interface": "udp_multicast", "channel": "239.74.163.9", "port": 43201,
                               "receive_own_messages": False, "bitrate": 500_000}
    options.update(interface=None, bus_kwargs=None, host="127.0.0.1", port=43220, can2_channel=None,  # as measure
                   can2_interface="udp_multicast", can2_bus_kwargs=["port=43221"])  # takes it (was refused: trial 6)
    target = target_from_options(Namespace(**options))
    assert target.can2_bus == {"interface": "udp_multicast", "channel": "239.74.163.2", "port": 43221,
                               "receive_own_messages": False}


def test_tests_chosen_by_requirement_repeated_and_pytest_options_after_the_double_dash(pytester):
    """--req picks the tests that verify a requirement or one below it, a misspelt id is bad input (it would run
    less than asked, and pass); --repeat N runs each N times; what follows -- is pytest's (user trial 7: the
    command took none of these, and -x, -v or --lf needed plain pytest)."""
    pytester.makepyfile(test_reqs="""
from workbench.testbench import requirement

@requirement("REQ_1.1")
def test_one():
    pass

@requirement("REQ_1.2", "REQ_2")
def test_two():
    pass

@requirement("REQ_11")
def test_eleven():
    assert False
""")
    run = _run(pytester, "test_reqs.py", "--req", "REQ_1", "--repeat", "2", "--", "-v", "-x")
    assert run.ret == 0
    run.stdout.fnmatch_lines(["*test_one?1-2? PASSED*", "*test_one?2-2? PASSED*", "*test_two?2-2? PASSED*",
                              "*4 passed, 2 deselected*"])
    run = _run(pytester, "test_reqs.py", "--req", "REQ_2", "--req", "REQ_11", "--", "-x")
    assert run.ret == 1
    run.stdout.fnmatch_lines(["*1 failed, 1 passed*"])  # -x: stopped at the first failure
    run = _run(pytester, "test_reqs.py", "--req", "REQ_3")
    assert run.ret == pytest.ExitCode.USAGE_ERROR
    run.stderr.fnmatch_lines(["*--req REQ_3: no test collected verifies it; did you mean *"])
    parsed = build_parser().parse_args(["test", "test_reqs.py", "--report", "out", "--", "--lf", "-m", "slow"])
    assert parsed.paths == ["test_reqs.py"] and pytest_arguments(parsed)[-3:] == ["--lf", "-m", "slow"]
    parsed = build_parser().parse_args(["test", "test_reqs.py", "--interface", "virtual", "--channel", "x"])
    assert pytest_arguments(parsed)[-2:] == ["-n", "0"]  # one master, whatever -n a project's addopts give


def test_a_test_file_that_does_not_import_is_bad_input_in_one_line(capsys, tmp_path):
    """pytest says 'Interrupted: 1 error during collection' for a file it cannot import, and exits as Ctrl-C makes
    it exit: the command said nothing on stderr and exited 130 (the window then said 'stopped'). Bad input: exit 2,
    the file and line and the error in one line."""
    broken = tmp_path / "test_broken.py"
    broken.write_text("def test_x(:\n    pass\n", encoding="utf-8")
    assert main(["test", str(tmp_path), "--", "-q"]) == 2
    assert capsys.readouterr().err.strip() == f"error: {broken}:1: cannot be collected: SyntaxError: invalid syntax"


def test_tests_keep_their_file_in_their_names_beside_an_a2l_from_elsewhere(pytester):
    """pytest takes every word of its command line that names an existing file or folder for a test path when it
    chooses its root folder: an --a2l (or --dbc, --requirements) elsewhere made it /, and the tests of test_names.py
    were '::test_one' in the terminal, JUnit, the report and the window's table. The command gives its options'
    values as --option=VALUE."""
    pytester.makepyfile(test_names="def test_one():\n    pass\n")
    run = _run(pytester, str(pytester.path / "test_names.py"), "--a2l", str(demo.a2l()), "--dbc", str(demo.dbc_can2()),
               "--", "--collect-only", "-q")
    run.stdout.fnmatch_lines(["test_names.py::test_one"])


def test_the_example_requirement_tests_pass(pytester):
    """examples/test_requirements.py, the file a test engineer copies, runs as the docs say (a simulated ECU each)."""
    example = Path(__file__).resolve().parents[2] / "examples" / "test_requirements.py"
    run = _run(pytester, str(example))
    assert run.ret == 0
    run.stdout.fnmatch_lines(["4 verified, 0 failed"])


def test_the_docs_example_requirement_test_passes_as_written(pytester):
    """The test docs/requirement-tests.md shows under 'Writing a test', copied into a file, passes."""
    docs = (Path(__file__).resolve().parents[2] / "docs" / "requirement-tests.md").read_text(encoding="utf-8")
    (code,) = re.findall(r"^```python\n(.*?)^```", docs, re.MULTILINE | re.DOTALL)
    pytester.makepyfile(test_from_the_docs=code)
    run = _run(pytester, "test_from_the_docs.py")
    assert run.ret == 0
    run.stdout.fnmatch_lines(["1 verified, 0 failed"])
