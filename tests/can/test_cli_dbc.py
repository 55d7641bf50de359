"""`workbench dbc ...`: outputs, exit codes 0/1/2 and one-line errors."""

from __future__ import annotations

import csv
import io
import json
import re
import shutil

import pytest
from crafted import timing

from workbench import demo
from workbench.can.mailboxes import MailboxOrder
from workbench.cli import main
from workbench.cli.dbc import MAILBOX_ORDERS

FLCU = str(demo.dbc_can2())
CAN3 = str(demo.dbc_can3())


def test_order_choices_are_the_mailbox_orders():
    assert MAILBOX_ORDERS == tuple(order.value for order in MailboxOrder)


def test_table_text(capsys):
    assert main(["dbc", "table", FLCU, "--node", "FLCU"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["MboxId", "Role", "Name", "ID", "NetworkType", "Type", "DLC", "Period", "Timeout",
                                "Enable", "UniqueID"]
    assert lines[2].split() == ["CAN2_MSG_TX_000", "TX", "FLCU_TO_PCM_001", "0x167", "CAN2", "std", "4", "100", "300",
                                "yes", "yes"]
    assert lines[3].split()[:5] == ["FuelLevelLow", "0", "1", "Intel", "unsigned"]


def test_table_json_reverse_order(capsys):
    assert main(["dbc", "table", CAN3, "--node", "EAXLE", "--order", "reverse", "--json"]) == 0
    table = json.loads(capsys.readouterr().out)
    assert len(table["messages"]) == 64 and table["order"] == "reverse"
    c3rxaaa = next(m for m in table["messages"] if m["Name"] == "C3RXAAA")
    assert {k: c3rxaaa[k] for k in ("ID", "DLC", "Period", "Timeout", "MboxId", "Role", "Type", "UniqueID")} == {
        "ID": "0x300", "DLC": 1, "Period": 100, "Timeout": 300, "MboxId": "CAN3_MSG_RX_031", "Role": "RX",
        "Type": "std", "UniqueID": True}
    assert c3rxaaa["Signals"][0]["Name"] == "Sgn1"


def test_table_csv_has_one_row_per_signal(capsys):
    assert main(["dbc", "table", FLCU, "--node", "FLCU", "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert len(rows) == 13
    assert (rows[1]["MboxId"], rows[1]["Signal"], rows[1]["Factor"], rows[1]["Unit"]) == (
        "CAN2_MSG_TX_000", "FuelLevel", "0.01", "%")


def test_table_marks_default_timeouts_and_messages_outside_the_table(write_dbc, capsys):
    path = write_dbc(
        'BO_ 1 MINE: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n\n'
        'BO_ 2 OTHER: 1 PEER\n SG_ T : 0|8@1+ (1,0) [0|255] "" Vector__XXX\n',
        timing(1, 10) + timing(2, 10, 30),
    )
    assert main(["dbc", "table", str(path), "--node", "ECU"]) == 0
    out = capsys.readouterr().out
    assert " 30*" in out and "* no GenMsgTimeoutTime in the DBC: 3 x period" in out
    assert "not in ECU's table (neither sent nor received by it): OTHER" in out


def test_table_bad_input_is_exit_2_with_one_line(tmp_path, capsys):
    assert main(["dbc", "table", str(tmp_path / "nope_CAN2.dbc")]) == 2
    assert main(["dbc", "table", FLCU, "--node", "XYZ"]) == 2
    assert main(["dbc", "table", FLCU, "--network", "CAN9"]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert len(errors) == 3 and all(line.startswith("error: ") for line in errors)
    assert main(["dbc", "table", FLCU, "--order", "sideways"]) == 2  # argparse usage error


def test_table_of_a_dbc_whose_name_says_no_network_assumes_can2_and_says_so(tmp_path, capsys):
    vehicle = shutil.copy(FLCU, tmp_path / "vehicle.dbc")
    assert main(["dbc", "table", str(vehicle), "--node", "FLCU"]) == 0
    out, err = capsys.readouterr()
    assert err == f"{vehicle}: note: no CAN1..CAN4 in the file name: assumed on CAN2 (--network chooses)\n"
    assert out.splitlines()[2].split()[:5] == ["CAN2_MSG_TX_000", "TX", "FLCU_TO_PCM_001", "0x167", "CAN2"]
    assert main(["dbc", "table", str(vehicle), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["networks"] == [{"file": str(vehicle), "network": "CAN2",
                                                                "assumed": True}]
    assert main(["dbc", "table", str(vehicle), "--network", "CAN4"]) == 0
    out, err = capsys.readouterr()
    assert err == "" and out.splitlines()[2].split()[4] == "CAN4"
    assert main(["dbc", "callbacks", str(vehicle), "--node", "FLCU", "--api", str(tmp_path / "api.c")]) == 2
    assert "cannot tell the network from the file name; give --network" in capsys.readouterr().err  # code: no guess


@pytest.mark.parametrize("command", [["table", "--network", "CAN2"], ["check"], ["fixcal", "--node", "FLCU"],
                                     ["callbacks", "--node", "FLCU", "--network", "CAN2", "--api", "api.c"]])
@pytest.mark.parametrize("make_input", ["missing", "folder", "empty", "binary", "garbage"])
def test_bad_dbc_is_exit_2_with_one_line_and_writes_nothing(tmp_path, monkeypatch, capsys, command, make_input):
    monkeypatch.chdir(tmp_path)
    dbc = tmp_path / "input.dbc"
    if make_input == "folder":
        dbc.mkdir()
    elif make_input != "missing":
        dbc.write_bytes({"empty": b"", "binary": demo.path("assets", "FLCU.elf").read_bytes()[:4096],
                         "garbage": b"\xff" * 5000}[make_input])
    api = shutil.copy(demo.path("assets", "ecu", "api.c"), tmp_path / "api.c").read_bytes()
    before = sorted(p.name for p in tmp_path.iterdir())
    assert main(["dbc", command[0], str(dbc), *command[1:]]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith(f"error: {dbc}") and err.count("\n") == 1 and len(err) < 300
    assert sorted(p.name for p in tmp_path.iterdir()) == before and (tmp_path / "api.c").read_bytes() == api


def test_fixcal_writes_the_three_files(tmp_path, capsys):
    assert main(["dbc", "fixcal", FLCU, "--node", "FLCU", "-o", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert [line.rsplit("/", 1)[-1] for line in out.splitlines()] == [
        "FLCU_CAN2_fixcal.h", "FLCU_CAN2_fixcal.c", "FLCU_CAN2_fixcal.a2l"]
    assert "29 calibrations for FLCU" in err
    assert main(["dbc", "fixcal", FLCU, "--node", "FLCU", "-o", str(tmp_path / "a2l"), "--a2l-only"]) == 0
    assert [p.name for p in (tmp_path / "a2l").iterdir()] == ["FLCU_CAN2_fixcal.a2l"]
    assert main(["dbc", "fixcal", FLCU, "--node", "FLCU", "--a2l-only", "--c-only"]) == 2


def test_fixcal_c_only_refuses_the_options_of_the_a2l_fragment(tmp_path, capsys):
    """--master and --measurements shape only the A2L fragment: with --c-only they would be ignored silently."""
    csv_file = str(demo.path("dbc", "FLCU_CAN2_measurements.csv"))
    for given, named in ((["--master", str(demo.master_a2l())], "--master"), (["--measurements", csv_file],
                         "--measurements"), (["--master", "x.a2l", "--measurements", "y.csv"], "--master and --measurements")):
        code = main(["dbc", "fixcal", FLCU, "--node", "FLCU", "--c-only", "-o", str(tmp_path), *given])
        out, err = capsys.readouterr()
        assert (code, out, err.count("\n")) == (2, "", 1) and err.startswith(f"error: {named} shape"), err
    assert not list(tmp_path.iterdir())  # nothing written


def test_fixcal_links_each_value_to_the_measurements_the_csv_names(tmp_path, capsys):
    """The demo's CSV makes the generated fragment's calibrations those of a2l/modules/CANRX and CANTX."""
    measurements = demo.path("dbc", "FLCU_CAN2_measurements.csv")
    assert main(["dbc", "fixcal", FLCU, "--node", "FLCU", "-o", str(tmp_path), "--a2l-only",
                 "--measurements", str(measurements)]) == 0
    text = (tmp_path / "FLCU_CAN2_fixcal.a2l").read_text()
    demo_text = "".join(demo.path("a2l", "modules", f"{m}.a2l").read_text() for m in ("CANRX", "CANTX"))
    links = re.findall(r"COMPARISON_QUANTITY (\w+)", text)
    assert len(links) == 13 and "xsLEDEn" in links and links == re.findall(r"COMPARISON_QUANTITY (\w+)", demo_text)
    bad = tmp_path / "bad.csv"
    bad.write_text("signal,measurement\nFuelLevelLow,xsLEDEn\nLowFuel,xsLEDEn\n")
    capsys.readouterr()
    assert main(["dbc", "fixcal", FLCU, "--node", "FLCU", "-o", str(tmp_path / "no"), "--measurements", str(bad)]) == 2
    assert capsys.readouterr().err == (f"error: {FLCU}: LowFuel (given the measurement xsLEDEn): not a signal of the "
                                       "node's messages\n")
    assert not (tmp_path / "no").exists()


def test_fixcal_refuses_collisions_and_suggests_qualified_names(tmp_path, capsys):
    assert main(["dbc", "fixcal", CAN3, "--node", "EAXLE", "-o", str(tmp_path)]) == 2
    error = capsys.readouterr().err
    assert "cfSGN1_VALUE would be defined by" in error and error.endswith("(--qualified) avoid this\n")
    assert list(tmp_path.iterdir()) == []
    assert main(["dbc", "fixcal", CAN3, "--node", "EAXLE", "-o", str(tmp_path), "--qualified"]) == 0
    assert "608 calibrations for EAXLE" in capsys.readouterr().err
    assert "CAL_RAM uint8_T cfC3RXAAA_SGN1_EN = 0U;" in (tmp_path / "CAN3_validation_fixcal.c").read_text()


def test_callbacks_round_trip_on_the_demo_api_c(tmp_path, capsys):
    api = shutil.copy(demo.path("assets", "ecu", "api.c"), tmp_path / "api.c")
    before = api.read_bytes()
    assert main(["dbc", "callbacks", FLCU, "--api", str(api), "--node", "FLCU"]) == 0
    assert "unchanged (5 messages of FLCU)" in capsys.readouterr().out
    assert main(["dbc", "callbacks", FLCU, "--api", str(api), "--node", "FLCU", "--order", "reverse"]) == 0
    assert "regenerated" in capsys.readouterr().out and api.read_bytes() != before
    assert main(["dbc", "callbacks", FLCU, "--api", str(api), "--node", "FLCU"]) == 0
    assert api.read_bytes() == before


def test_callbacks_marker_error_is_exit_2(tmp_path, capsys):
    api = tmp_path / "api.c"
    api.write_text("void f(void) {\n// <initCbk>\n}\n")
    assert main(["dbc", "callbacks", FLCU, "--api", str(api), "--node", "FLCU"]) == 2
    assert capsys.readouterr().err == f"error: {api}: no '// </initCbk>' marker line\n"


def test_check_exit_codes(write_dbc, capsys):
    assert main(["dbc", "check", FLCU]) == 0
    assert capsys.readouterr().err == "no problems in 1 file\n"
    bad = write_dbc('BO_ 2048 BIG: 1 ECU\n SG_ S : 4|8@1+ (1,0) [0|255] "" PEER\n')
    assert main(["dbc", "check", str(bad), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    kinds = [f["kind"] for f in report["findings"]]
    assert sorted(kinds) == ["beyond-dlc", "id-format", "missing-period"]
    assert report["ok"] is False and report["summary"] == "1 error, 2 warnings in 1 file"
    assert {f["severity"] for f in report["findings"] if f["kind"] != "beyond-dlc"} == {"warning"}
    warned_only = write_dbc('BO_ 2048 BIG: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n', timing(2147485696, 10, 30))
    assert main(["dbc", "check", str(warned_only), "--json"]) == 1  # a check fails on warnings too
    report = json.loads(capsys.readouterr().out)
    assert (report["ok"], report["summary"]) == (False, "1 warning in 1 file")


def test_check_states_fixcal_collisions_once_as_a_hint(capsys):
    assert main(["dbc", "check", CAN3]) == 0  # a hint is not a problem of the DBC: ok, exit 0
    out, err = capsys.readouterr()
    (line,) = out.splitlines()
    assert line.startswith(f"{CAN3}:") and ": info: " in line and "would define 8 fix calibration names" in line
    assert line.endswith("message-qualified names (--qualified) avoid this") and err == "1 hint in 1 file\n"
    assert main(["dbc", "check", CAN3, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] is True
    assert main(["dbc", "check", CAN3, "--qualified"]) == 0
    assert capsys.readouterr() == ("", "no problems in 1 file\n")


def test_check_unreadable_dbc_is_exit_2(write_dbc, capsys):
    bad = write_dbc('BO_ 16 M: 1 ECU\n SG_ S 0|8@1+ (1,0) [0|255] "" PEER\n')
    assert main(["dbc", "check", str(bad)]) == 2
    assert capsys.readouterr().err.startswith(f"error: {bad}:14:8: Invalid syntax")
