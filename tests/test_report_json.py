"""Every command that prints a report: the JSON's ``ok`` is what the exit code says (0: ok), for
clean runs, runs with warnings only and failed runs, A2L and DBC alike."""

import json
from pathlib import Path

import pytest

from workbench.cli import main

A2L_FIXTURES = Path(__file__).parent / "a2l" / "fixtures"
ELF = Path(__file__).parent / "elf" / "fixtures" / "types_dwarf5.elf"
MODULE = 'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n /begin MODULE M ""\n{}\n /end MODULE\n/end PROJECT\n'
MEASUREMENT = '  /begin MEASUREMENT {} "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x10 /end MEASUREMENT'
DBC = 'VERSION ""\n\nNS_ :\n\nBS_:\n\nBU_: ECU PEER\n\n{}'


def _files(tmp_path: Path) -> dict[str, Path]:
    files = {"clean.a2l": MODULE.format(MEASUREMENT.format("a")),
             "warning.a2l": MODULE.format(MEASUREMENT.format("a") + "\n" + MEASUREMENT.format("b")),
             "error.a2l": MODULE.format(MEASUREMENT.format("a").replace("NO_COMPU_METHOD", "CM_GONE")),
             "conflict.a2l": MODULE.format(MEASUREMENT.format("a").replace("255", "127")),
             "warning_CAN2.dbc": DBC.format('BO_ 291 MSG: 8 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n'),
             "error_CAN2.dbc": DBC.format('BO_ 291 MSG: 1 ECU\n SG_ S : 4|8@1+ (1,0) [0|255] "" PEER\n')}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    return {name: tmp_path / name for name in files}


CASES = [
    ("a2l check clean", ["a2l", "check", "clean.a2l"], 0),
    ("a2l check warnings only", ["a2l", "check", "warning.a2l"], 1),
    ("a2l check errors", ["a2l", "check", "error.a2l"], 1),
    ("a2l merge", ["a2l", "merge", "clean.a2l", "warning.a2l", "-o", "out.a2l"], 0),
    ("a2l merge conflict", ["a2l", "merge", "clean.a2l", "conflict.a2l", "-o", "out.a2l"], 1),
    ("a2l merge warnings", ["a2l", "merge", "clean.a2l", "conflict.a2l", "-o", "out.a2l", "--on-conflict", "keep-first"], 0),
    ("a2l update with misses", ["a2l", "update", str(A2L_FIXTURES / "types.a2l"), str(ELF), "-o", "out.a2l", "--no-cache"], 0),
    ("a2l update strict", ["a2l", "update", str(A2L_FIXTURES / "types.a2l"), str(ELF), "-o", "out.a2l", "--no-cache",
                           "--strict"], 1),
    ("a2l diff same", ["a2l", "diff", "clean.a2l", "clean.a2l"], 0),
    ("a2l diff different", ["a2l", "diff", "clean.a2l", "warning.a2l"], 1),
    ("dbc check warnings only", ["dbc", "check", "warning_CAN2.dbc"], 1),
    ("dbc check errors", ["dbc", "check", "error_CAN2.dbc"], 1),
]


@pytest.mark.parametrize("argv, code", [case[1:] for case in CASES], ids=[case[0] for case in CASES])
def test_json_ok_is_the_exit_code(tmp_path, capsys, monkeypatch, argv, code):
    _files(tmp_path)
    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--json"]) == code
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] is (code == 0)


FAILURES = [
    ("a2l update without its ELF", ["a2l", "update", "clean.a2l", "gone.elf", "-o", "out.a2l"], 2, "gone.elf: no such file"),
    ("a2l check of a malformed file", ["a2l", "check", "broken.a2l"], 2, "broken.a2l:"),
    ("flash of a missing image", ["flash", "gone.s19", "--region", "CALIB"], 2, "gone.s19"),
    ("dbc check of a missing file", ["dbc", "check", "gone.dbc"], 2, "gone.dbc"),
]


@pytest.mark.parametrize("argv, code, message", [case[1:] for case in FAILURES], ids=[case[0] for case in FAILURES])
def test_a_command_that_fails_still_prints_its_json(tmp_path, capsys, monkeypatch, argv, code, message):
    """A script reading the JSON finds ok false and the reason (the one line on stderr too), not an empty stdout."""
    _files(tmp_path)
    (tmp_path / "broken.a2l").write_text(MODULE.format("  /begin MEASUREMENT m"))
    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--json"]) == code
    captured = capsys.readouterr()
    report = json.loads(captured.out)
    assert report["ok"] is False and report["exit_code"] == code and message in report["error"]
    assert captured.err.strip().splitlines()[-1] == f"error: {report['error']}"
