"""Third-party DBCs (tests/corpus/dbc, see its README): what the tool must say about each.

Every file loads, through the library and through ``workbench dbc table|check|fixcal`` run in a
temporary folder; the load warnings are the ones listed, located at those lines; and every
message, signal and value description the file spells is read as it spells it, checked against a
plain reading of the text that shares no code with the loader.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from workbench import demo
from workbench.can.dbc_file import load_dbc
from workbench.cli import main
from workbench.findings import Severity

CORPUS = Path(__file__).resolve().parents[1] / "corpus" / "dbc"
_A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")


@dataclass(frozen=True)
class Expected:
    warnings: dict[str, tuple[int, ...]]
    """Load warnings: kind → the lines, in file order."""
    messages: int
    check: str
    """The summary line of ``workbench dbc check``."""
    check_exit: int


def _lines(first: int, *more: int) -> tuple[int, ...]:
    return (first, *more)


EXPECTED = {
    "opendbc/mazda_2017.dbc": Expected(
        {"name-syntax": _lines(273, 572, 604, 606, 608, 614, 617, 620), "missing-semicolon": _lines(790, 791)},
        102, "5 errors, 11 warnings, 1 hint in 1 file", 1),
    "opendbc/psa_aee2010_r3.dbc": Expected({"name-syntax": _lines(165, 166)}, 107,
                                           "1 error, 3 warnings, 1 hint in 1 file", 1),
    "opendbc/toyota_2017_ref_pt.dbc": Expected(
        {"id-range": _lines(387, 402, 408, 428, 434, 453, 470, 489, 496, 506, 519, 525, 536, 550, 556, 617, 1221,
                            1229, 1248, 1261, 1270, 1278, 1286, 1292, 1314, 1322, 1331, 1355, 1374, 1618, 1627,
                            1633)},
        111, "33 warnings in 1 file", 1),
    "opendbc/toyota_radar_dsu_tssp.dbc": Expected({"missing-semicolon": _lines(138, 147, 156, 166, 176, 186)}, 19,
                                                  "7 warnings, 1 hint in 1 file", 1),
    "opendbc/chrysler_cusw.dbc": Expected({"id-format": _lines(182, 185),
                                           "unknown-reference": _lines(199, 200, 201, 203)},
                                          26, "7 warnings, 1 hint in 1 file", 1),
    "opendbc/gm_global_a_lowspeed.dbc": Expected(
        {"id-format": _lines(45, 48, 55, 60, 63, 66, 72, 76, 82, 86, 89, 92, 95), "unknown-reference": _lines(117)},
        13, "15 warnings, 1 hint in 1 file", 1),
    "opendbc/honda_common.dbc": Expected({"comment-syntax": _lines(207, 208)}, 23, "3 warnings, 1 hint in 1 file", 1),
    "opendbc/stellantis_common.dbc": Expected({"number-syntax": _lines(16, 17), "missing-semicolon": _lines(178)},
                                              21, "4 warnings, 1 hint in 1 file", 1),
    "opendbc/can_tests_test.dbc": Expected({"name-syntax": _lines(24, 25), "unknown-reference": _lines(27)}, 3,
                                           "4 warnings, 1 hint in 1 file", 1),
    "opendbc/tesla_can.dbc": Expected({"unknown-reference": _lines(783)}, 44, "2 warnings, 1 hint in 1 file", 1),
    "cantools/issue_199.dbc": Expected({"id-format": _lines(45, 48, 55, 60, 63, 66, 72, 76, 82, 86, 89)}, 11,
                                       "12 warnings in 1 file", 1),
    "cantools/issue_199_extended.dbc": Expected(
        {"id-range": _lines(45), "id-format": _lines(48, 55, 60, 63, 66, 72, 76, 82, 86, 89)}, 10,
        "12 warnings in 1 file", 1),
    "cantools/issue_62.dbc": Expected({}, 0, "no problems in 1 file", 0),
    "cantools/abs.dbc": Expected({}, 18, "1 hint in 1 file", 0),
    "cantools/foobar.dbc": Expected({}, 5, "1 hint in 1 file", 0),
    "cantools/motohawk.dbc": Expected({}, 1, "1 warning in 1 file", 1),
    "cantools/multiplex_2.dbc": Expected({}, 4, "4 warnings, 1 hint in 1 file", 1),
    "cantools/sig_groups.dbc": Expected({}, 4, "4 warnings, 1 hint in 1 file", 1),
    "cantools/vframeformat_int.dbc": Expected({}, 2, "1 warning in 1 file", 1),
    "cantools/BU_BO_REL_.dbc": Expected({}, 1, "1 warning in 1 file", 1),
    "cantools/cp1252.dbc": Expected({}, 0, "no problems in 1 file", 0),
    "canmatrix/from_sym_test.dbc": Expected({"attribute-type": _lines(414, 415, 418, 419)}, 28,
                                            "1 error, 19 warnings, 2 hints in 1 file", 1),
    "canmatrix/from_xls_test.dbc": Expected(
        {"id-format": _lines(11, 24, 37, 41, 45, 70, 74, 78, 83, 88, 110, 131, 135, 139, 143, 147, 152, 157, 162,
                             187, 192, 198, 203, 208, 211),
         "attribute-type": _lines(222)},
        25, "31 errors, 39 warnings, 2 hints in 1 file", 1),
}
FILES = sorted(EXPECTED)


def test_every_corpus_file_has_its_expectation_and_its_licence():
    on_disk = {str(path.relative_to(CORPUS)) for path in CORPUS.rglob("*.dbc")}
    assert on_disk == set(EXPECTED)
    readme = (CORPUS / "README.md").read_text(encoding="utf-8")
    assert all(f"`{name}`" in readme for name in EXPECTED)
    assert all((CORPUS / folder / "LICENSE").is_file() for folder in {name.split("/")[0] for name in EXPECTED})


@pytest.mark.parametrize("name", FILES)
def test_library_loads_with_the_listed_warnings(name):
    path = CORPUS / name
    dbc = load_dbc(path)
    found: dict[str, list[int]] = {}
    for warning in dbc.warnings:
        found.setdefault(warning.kind, []).append(warning.line)
        assert (warning.file, warning.severity) == (str(path), Severity.WARNING)
        assert str(warning).startswith(f"{path}:{warning.line}: warning: ") and "\n" not in str(warning)
    assert {kind: tuple(lines) for kind, lines in found.items()} == EXPECTED[name].warnings
    assert len(dbc.database.messages) == EXPECTED[name].messages


# A plain reading of the text, for the values: BO_ lines, their SG_ lines, VAL_ lines.
_MESSAGE = re.compile(r"^BO_ (\d+) (\w+) ?:")
_SIGNAL = re.compile(r"^\s+SG_ (\w+) [^:]*: ?(\d+)\|(\d+)@([01])([+-]) ?\(([^,]+),([^)]+)\)")
_CHOICES = re.compile(r'^VAL_ (\d+) (\w+)((?: -?\d+ "[^"]*")+)')
_CHOICE = re.compile(r'(-?\d+) "([^"]*)"')
_FLAG, _STANDARD_MAX, _EXTENDED_MAX = 0x80000000, 0x7FF, 0x1FFFFFFF


def _spelled(path: Path) -> tuple[list[tuple], dict[tuple[int, str], dict[int, str]]]:
    """(name, id, extended, signals) per CAN message the text defines, and its value descriptions by (id, signal)."""
    messages: list[tuple] = []
    choices = {}
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        message, signal, described = _MESSAGE.match(line), _SIGNAL.match(line), _CHOICES.match(line)
        if message:
            written = int(message.group(1))
            frame_id = written & ~_FLAG
            is_can = frame_id <= _EXTENDED_MAX and message.group(2) != "VECTOR__INDEPENDENT_SIG_MSG"
            messages.append((message.group(2), frame_id, bool(written & _FLAG) or frame_id > _STANDARD_MAX, [],
                             is_can))
        elif signal and messages:
            name, start, length, order, sign, factor, offset = signal.groups()
            messages[-1][3].append((name, int(start), int(length), "little_endian" if order == "1" else "big_endian",
                                    sign == "-", float(factor), float(offset)))
        elif described:
            choices[(int(described.group(1)) & ~_FLAG, described.group(2))] = {
                int(value): text for value, text in _CHOICE.findall(described.group(3))}
    return [m[:4] for m in messages if m[4]], choices


@pytest.mark.parametrize("name", FILES)
def test_every_value_is_what_the_file_spells(name):
    path = CORPUS / name
    spelled, choices = _spelled(path)
    database = load_dbc(path).database
    read = [(m.name, m.frame_id, m.is_extended_frame,
             [(s.name, s.start, s.length, s.byte_order, s.is_signed, s.scale, s.offset) for s in m.signals])
            for m in database.messages]
    assert read == spelled
    for message in database.messages:
        for signal in message.signals:
            expected = choices.get((message.frame_id, signal.name))
            if expected is not None:
                assert {int(value): str(text) for value, text in signal.choices.items()} == expected


@pytest.mark.parametrize("name", FILES)
def test_cli_table_and_check_agree_on_what_loads(name, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    path = CORPUS / name
    expected = EXPECTED[name]
    assert main(["dbc", "table", str(path), "--json"]) == 0
    out, err = capsys.readouterr()
    table = json.loads(out)
    assert len(table["messages"]) == expected.messages
    assert table["networks"] == [{"file": str(path), "network": "CAN2", "assumed": True}]
    assert len(table["warnings"]) == sum(len(lines) for lines in expected.warnings.values())
    assert f"{path}: note: no CAN1..CAN4 in the file name: assumed on CAN2 (--network chooses)" in err
    assert err.count(": warning: ") == len(table["warnings"])
    assert main(["dbc", "table", str(path)]) == 0  # the text table too
    capsys.readouterr()
    assert main(["dbc", "check", str(path), "--json"]) == expected.check_exit
    report = json.loads(capsys.readouterr().out)
    assert report["summary"] == expected.check and report["ok"] is (expected.check_exit == 0)
    load_warnings = [f for f in report["findings"] if f["kind"] in expected.warnings]
    assert len(load_warnings) >= len(table["warnings"])
    assert list(tmp_path.iterdir()) == []  # table and check write nothing


@pytest.mark.parametrize(("name", "arguments", "calibrations"), [
    ("opendbc/mazda_2017.dbc", ["--node", "XXX", "--qualified"], 1132),
    ("opendbc/psa_aee2010_r3.dbc", ["--node", "BSI___Kombiinstrument", "--qualified"], 123),
    ("cantools/abs.dbc", ["--node", "ABS"], 192),
    ("cantools/foobar.dbc", ["--node", "FOO"], 18),
])
def test_cli_fixcal_writes_c_and_a2l(name, arguments, calibrations, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["dbc", "fixcal", str(CORPUS / name), *arguments]) == 0
    stem = Path(name).stem
    out, err = capsys.readouterr()
    assert out.split() == [f"{stem}_fixcal.h", f"{stem}_fixcal.c", f"{stem}_fixcal.a2l"]
    assert f"{calibrations} calibrations for {arguments[1]}" in err
    if shutil.which("gcc"):
        subprocess.run(["gcc", "-std=c99", "-Wall", "-Werror", "-fsyntax-only", "-I", str(demo.path("assets", "ecu")),
                        f"{stem}_fixcal.c"], check=True, capture_output=True, text=True)
    if _A2LTOOL:
        done = subprocess.run([_A2LTOOL, f"{stem}_fixcal.a2l", "--check"], capture_output=True, text=True)
        assert done.returncode == 0 and "No problems found" in done.stdout + done.stderr


def test_cli_fixcal_names_from_digit_led_messages_stay_identifiers(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    mazda = CORPUS / "opendbc" / "mazda_2017.dbc"
    assert main(["dbc", "fixcal", str(mazda), "--node", "XXX"]) == 2  # CTR in 31 messages
    assert "cfCTR_VALUE would be defined by" in capsys.readouterr().err and list(tmp_path.iterdir()) == []
    assert main(["dbc", "fixcal", str(mazda), "--node", "XXX", "--qualified", "--c-only"]) == 0
    header = (tmp_path / "mazda_2017_fixcal.h").read_text()
    assert "extern uint8_T cs2017_5_En;" in header and "extern uint8_T cf2017_5_COUNTER_EN;" in header
    capsys.readouterr()
    assert main(["dbc", "fixcal", str(CORPUS / "canmatrix" / "from_sym_test.dbc"), "--node", "XXX"]) == 2
    assert "node 'XXX' is not in this DBC (nodes: none)" in capsys.readouterr().err
