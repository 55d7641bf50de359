"""``workbench cal save|load|diff|sync`` end to end in a temporary folder, against the simulated ECU on a
udp_multicast port of the test's own: output, files and exit codes as a user meets them."""

from __future__ import annotations

import json
import os
import shutil
import signal

import pytest
from cli_helpers import run
from sync_helpers import edited_a2l

from workbench import demo
from workbench.image import load_image
from workbench.sim import serve_demo


@pytest.fixture
def bus(free_udp_port, tmp_path):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
            yield ["--bus-kwargs", f"port={free_udp_port}"]
    finally:
        os.chdir(cwd)



def test_save_change_diff_load_and_diff_again(bus, capsys, tmp_path):
    code, out, err = run(capsys, "cal", "save", "base.dcm", *bus)
    assert (code, out, err) == (0, "wrote base.dcm: 58 calibrations of the working page\n", "")
    assert run(capsys, "cal", "save", "some.cdfx", "xsPRV_K*", "--page", "reference", *bus)[1] == \
        "wrote some.cdfx: 3 calibrations of the reference page\n"
    run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "25", *bus)
    run(capsys, "cal", "set", "xsPRV_KP", "6", *bus)

    code, out, _ = run(capsys, "cal", "diff", "base.dcm", "ecu", *bus)
    assert code == 1
    rows = [line.split() for line in out.splitlines()[3:-1]]
    assert [(row[0], *row[3:]) for row in rows] == [
        ("xsPRV_KP", "5.0000", "%/bar", "6.0000", "%/bar", "+1.0000", "%/bar"),
        ("xsSWITCH_TANK_THR", "20.00", "bar", "25.00", "bar", "+5.00", "bar")]  # the A2L's decimals, as cal get
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1] == "xsSWITCH_TANK_THR = 25.00 bar\n"
    assert out.splitlines()[-1] == "58 objects: 56 equal, 2 changed, 0 shape changed, 0 only in A, 0 only in B"
    code, out, _ = run(capsys, "cal", "diff", "ecu", "base.dcm", "--json", *bus)
    data = json.loads(out)
    assert code == 1 and data["a"] == "ECU" and data["counts"]["changed"] == 2 and data["ok"] is False
    assert [d["delta"] for o in data["objects"] for d in o["differences"]] == [-1.0, -5.0]

    code, out, _ = run(capsys, "cal", "load", "base.dcm", "--dry-run", *bus)
    assert code == 0 and "xsPRV_KP           would change" in out
    assert out.splitlines()[-1] == "base.dcm: dry run: 56 unchanged, 2 would change"
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 6.0000 %/bar\n"
    code, out, _ = run(capsys, "cal", "load", "base.dcm", *bus)
    assert (code, out.splitlines()[-1]) == (0, "base.dcm: applied: 2 applied, 56 unchanged")
    code, out, _ = run(capsys, "cal", "diff", "base.dcm", "ecu", *bus)
    assert (code, out.splitlines()[-1]) == (0, "58 objects: 58 equal, 0 changed, 0 shape changed, 0 only in A, "
                                               "0 only in B")


def test_a_first_ctrl_c_stops_a_load_at_the_next_object_and_names_what_was_written(bus, capsys, tmp_path,
                                                                                     monkeypatch):
    from workbench.session import Session

    run(capsys, "cal", "save", "base.dcm", *bus)
    text = (tmp_path / "base.dcm").read_text()
    for name, new in (("xsPRV_KP", "7.0"), ("xsPRV_KI", "3.0")):
        start = text.index(f"FESTWERT {name}\n")
        value = text.index("  WERT ", start)
        text = text[:value] + f"  WERT {new}" + text[text.index("\n", value):]
    (tmp_path / "tuned.dcm").write_text(text)
    write = Session.write

    def write_then_ctrl_c(self, *args, **kwargs):  # the user presses Ctrl-C while the first object is written
        result = write(self, *args, **kwargs)
        signal.raise_signal(signal.SIGINT)
        return result

    monkeypatch.setattr(Session, "write", write_then_ctrl_c)
    code, out, err = run(capsys, "cal", "load", "tuned.dcm", *bus)
    assert code == 130 and "xsPRV_KP  applied" in out and "xsPRV_KI  not written  cancelled before xsPRV_KI" in out
    assert err.splitlines()[-1] == ("error: cancelled: writing xsPRV_KI at 1/2; objects that reached the ECU: "
                                    "xsPRV_KP; 1 not written")
    assert "stopping at the next object (Ctrl-C again to interrupt at once)" in err


def test_a_bad_object_is_listed_and_nothing_is_written(bus, capsys, tmp_path):
    run(capsys, "cal", "save", "base.dcm", *bus)
    text = (tmp_path / "base.dcm").read_text()
    tuned = text.replace("FESTWERT xsPRV_KP \n", "FESTWERT xsPRV_KP \n", 1)
    tuned = tuned.replace("FESTWERT xsPRV_KI", "FESTWERT xsPRV_KX", 1)  # a name the A2L lacks
    start = tuned.index("FESTWERT xsPRV_KP")
    block = tuned[start:tuned.index("END", start)]
    tuned = tuned.replace(block, block.replace("WERT 5.0", "WERT 7.0"), 1)
    (tmp_path / "tuned.dcm").write_text(tuned)
    code, out, err = run(capsys, "cal", "load", "tuned.dcm", *bus)
    assert code == 2
    line = tuned[:tuned.index("FESTWERT xsPRV_KX")].count("\n") + 1  # the line that names the unknown object
    unknown = "not in the A2L; did you mean xsPRV_KP, xsPRV_KI, xsPRV_KD?"
    assert out.splitlines() == ["xsPRV_KP  not written  other objects were refused",
                                f"xsPRV_KX  refused  tuned.dcm:{line}: " + unknown,
                                "tuned.dcm: not applied: 56 unchanged, 1 refused, 1 not written"]
    assert err.startswith(f"error: 1 of 58 objects refused, nothing written: xsPRV_KX: tuned.dcm:{line}: not in the A2L")
    assert err.endswith("; --skip-unknown leaves out the objects the A2L lacks\n")
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 5.0000 %/bar\n"

    # a dataset of another software version, as CANape loads it: the names the A2L lacks left out, listed
    code, out, err = run(capsys, "cal", "load", "tuned.dcm", "--skip-unknown", "--dry-run", *bus)
    assert (code, err, out.splitlines()[-1]) == (0, "", "tuned.dcm: dry run: 56 unchanged, 1 would change, 1 skipped")
    code, out, err = run(capsys, "cal", "load", "tuned.dcm", "--skip-unknown", *bus)
    assert (code, err) == (0, "")
    assert out.splitlines() == ["xsPRV_KP  applied",
                                f"xsPRV_KX  skipped  tuned.dcm:{line}: " + unknown,
                                "tuned.dcm: applied: 1 applied, 56 unchanged, 1 skipped"]
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 7.0000 %/bar\n"
    (tmp_path / "beyond.dcm").write_text(tuned.replace("WERT 7.0", "WERT 700.0"))  # other refusals still refuse
    code, out, err = run(capsys, "cal", "load", "beyond.dcm", "--skip-unknown", *bus)
    assert code == 2 and err.startswith("error: 1 of 58 objects refused, nothing written: xsPRV_KP: ")
    assert "--skip-unknown" not in err


def test_a_dry_run_exits_as_the_load_would(bus, capsys, tmp_path):
    run(capsys, "cal", "save", "curve.dcm", "zvTankPConv", "xsSWITCH_TANK_THR", *bus)
    text = (tmp_path / "curve.dcm").read_text()
    (tmp_path / "beyond.dcm").write_text(text.replace("WERT 600.0 700.0 800.0", "WERT 600.0 700.0 900.0")
                                         .replace("WERT 20.0", "WERT 25.0"))
    for argv in (["cal", "load", "beyond.dcm", "--dry-run"], ["cal", "load", "beyond.dcm"]):
        code, out, err = run(capsys, *argv, *bus)
        assert code == 2 and "zvTankPConv" in out and "refused" in out, argv
        assert err.count("\n") == 1 and err.startswith("error: 1 of 2 objects refused, nothing written: zvTankPConv: ")
    code, out, err = run(capsys, "cal", "load", "beyond.dcm", "--dry-run", "--json", *bus)
    report = json.loads(out)  # ok, error and exit_code as every failing command's --json (they lacked the last two)
    assert code == 2 and report["counts"]["refused"] == 1 and report["ok"] is False and report["exit_code"] == 2
    assert "error: " + report["error"] + "\n" == err
    assert run(capsys, "cal", "load", "curve.dcm", "--dry-run", *bus)[0] == 0
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1] == "xsSWITCH_TANK_THR = 20.00 bar\n"


def test_a_dataset_loads_into_the_working_page_while_the_ecu_runs_the_reference(bus, capsys, tmp_path):
    """As cal save reads and cal sync --download writes: the working page, whichever page XCP was on (before, the
    dry run said 'would change' and the load then failed on the reference page, exit 1)."""
    run(capsys, "cal", "save", "base.dcm", "xsSWITCH_TANK_THR", *bus)
    (tmp_path / "tuned.dcm").write_text((tmp_path / "base.dcm").read_text().replace("WERT 20.0", "WERT 25.5"))
    run(capsys, "cal", "page", "reference", *bus)
    warning = ("warning: the ECU runs the reference page of segment 0: the working page's values take effect after "
               "`workbench cal page working` (Session.set_page('working'))")
    code, out, err = run(capsys, "cal", "load", "tuned.dcm", *bus)
    assert (code, err, out.splitlines()[-2:]) == (0, "", [warning, "tuned.dcm: applied: 1 applied"])
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1] == "xsSWITCH_TANK_THR = 20.00 bar\n"  # CAL ROM
    assert run(capsys, "cal", "page", *bus)[1] == "segment 0: ECU on the reference page, XCP on the reference page\n"
    run(capsys, "cal", "page", "working", *bus)
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1] == "xsSWITCH_TANK_THR = 25.50 bar\n"
    assert run(capsys, "cal", "load", "tuned.dcm", *bus)[1] == "tuned.dcm: applied: 1 unchanged\n"


def test_sync_download_refuses_what_load_refuses(bus, capsys, tmp_path):
    """One rule: a dataset that cal load refuses (a name the A2L lacks) is refused by cal sync --download too."""
    run(capsys, "cal", "save", "some.dcm", "xsPRV_K*", *bus)
    text = (tmp_path / "some.dcm").read_text()
    (tmp_path / "tuned.dcm").write_text(text.replace("WERT 5.0", "WERT 7.0").replace("xsPRV_KI", "xsPRV_KX"))
    load = run(capsys, "cal", "load", "tuned.dcm", *bus)
    code, out, err = run(capsys, "cal", "sync", "--reference", "tuned.dcm", "--download", *bus)
    assert load[0] == code == 2 and err == load[2] and err.endswith("--skip-unknown leaves out the objects the A2L lacks\n")
    assert out.splitlines()[-3:] == load[1].splitlines()
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 5.0000 %/bar\n"  # nothing written
    code, out, _ = run(capsys, "cal", "sync", "--reference", "tuned.dcm", "--download", "--json", *bus)
    report = json.loads(out)
    assert code == 2 and report["download"]["counts"]["refused"] == 1
    assert (report["ok"], report["exit_code"], report["error"]) == (False, 2, err.removeprefix("error: ").strip())
    # the compare leaves the unknown name out (a note says so); the download may too
    code, out, err = run(capsys, "cal", "sync", "tuned.dcm", "--download", "--skip-unknown", *bus)
    assert (code, err) == (0, "") and out.splitlines()[-1] == "downloaded 1 object; verified: 1 objects read back " \
                                                                "equal the file's"
    assert run(capsys, "cal", "get", "xsPRV_KP", *bus)[1] == "xsPRV_KP = 7.0000 %/bar\n"


def test_sync_report_upload_and_download(bus, capsys, tmp_path):
    code, out, _ = run(capsys, "cal", "sync", *bus)
    assert code == 0 and out.splitlines()[-1] == ('the data in the ECU equals "FLCU.s19" (58 objects); 0 bytes read '
                                                  'from the ECU')
    run(capsys, "cal", "set", "xsEMPTY_TANK_THR", "7.5", *bus)
    code, out, _ = run(capsys, "cal", "sync", *bus)
    lines = out.splitlines()
    assert code == 1 and lines[-1] == "choose --upload (ECU -> file) or --download (file -> ECU)"
    assert lines[-2].startswith('the data in the ECU differs from "FLCU.s19": 1 object differs; ')
    assert lines[-2].endswith(" bytes read from the ECU") and "uploaded" not in out  # nothing went to a file
    assert lines[0] == f"file: {demo.s19()}" and lines[2].split() == ["name", "status", "where", "file", "ECU", "ECU",
                                                                      "-", "file"]
    assert any(line.split()[:9] == ["xsEMPTY_TANK_THR", "changed", "value", "5.00", "bar", "7.50", "bar",
                                                   "+2.50", "bar"] for line in lines)

    shutil.copy(demo.s19(), tmp_path / "mine.s19")
    code, out, _ = run(capsys, "cal", "sync", "--reference", "mine.s19", "--upload", *bus)
    assert code == 0 and out.splitlines()[-1] == "upload: wrote mine.s19 with the ECU's data"
    code, out, _ = run(capsys, "cal", "sync", "mine.s19", "--json", *bus)
    assert code == 0 and json.loads(out)["report"]["equal"] is True and json.loads(out)["ok"] is True
    run(capsys, "cal", "set", "xsEMPTY_TANK_THR", "8", *bus)
    code, out, _ = run(capsys, "cal", "sync", "mine.s19", "--json", *bus)
    assert code == 1 and json.loads(out)["ok"] is False  # ok: what the exit code says, as in cal diff and a2l diff
    assert run(capsys, "cal", "sync", "mine.s19", "--download", *bus)[0] == 0

    code, out, _ = run(capsys, "cal", "sync", "--download", *bus)  # the demo's s19 back into the ECU
    assert code == 0 and out.splitlines()[-1].startswith("downloaded 1 object (1 byte); verified: BUILD_CHECKSUM")
    assert run(capsys, "cal", "sync", *bus)[0] == 0
    code, out, _ = run(capsys, "cal", "sync", "--reference", "mine.s19", "--output", "copy.s19", "--upload", *bus)
    assert code == 0 and (tmp_path / "copy.s19").exists()
    assert load_image(tmp_path / "copy.s19") == load_image(demo.s19())


def test_a_dataset_uploaded_holds_the_values_cal_save_writes(bus, capsys, tmp_path):
    """A FLOAT32 value uploaded into a dataset reads as cal save writes it, 0.03, not the 0.029999999329447746 the
    float32 holds (every upload of a parameter set changed its digits; user trial 10)."""
    run(capsys, "cal", "save", "gains.dcm", "xsPRV_K*", *bus)
    run(capsys, "cal", "set", "xsPRV_KD", "0.03", *bus)
    code, out, _ = run(capsys, "cal", "sync", "gains.dcm", "--upload", *bus)
    assert code == 0 and out.splitlines()[-1] == "upload: wrote gains.dcm with the ECU's data"
    run(capsys, "cal", "save", "saved.dcm", "xsPRV_K*", *bus)
    values = [[line for line in (tmp_path / name).read_text(encoding="utf-8").splitlines() if "WERT" in line]
              for name in ("gains.dcm", "saved.dcm")]
    assert values[0] == values[1] and "  WERT 0.03" in values[0]


def test_the_saved_image_is_what_flash_takes(bus, capsys, tmp_path):
    code, out, _ = run(capsys, "cal", "save", "cal.s19", "--region", "CALIB", *bus)
    assert (code, out) == (0, "wrote cal.s19: CALIB FC0000h-FC01C3h FDFFF0h-FDFFFFh (468 bytes, EPK "
                              "'10300020250301')\n")
    code, out, err = run(capsys, "flash", "cal.s19", "--region", "CALIB", "--verify-only", *bus)
    assert (code, err) == (0, "2 of 2 ranges match the file\n")
    run(capsys, "cal", "set", "xsFULL_TANK_PRESS", "650", *bus)
    run(capsys, "cal", "save", "tuned.hex", "--region", "calib", *bus)
    assert run(capsys, "flash", "tuned.hex", "--region", "CALIB", "--verify-only", *bus)[0] == 1  # CAL ROM: 700
    code, _, err = run(capsys, "flash", "tuned.hex", "--region", "CALIB", *bus)
    assert code == 0, err
    assert run(capsys, "cal", "get", "xsFULL_TANK_PRESS", "--page", "reference", *bus)[1] == \
        "xsFULL_TANK_PRESS = 650.00 bar\n"
    code, out, _ = run(capsys, "cal", "diff", "ecu", "tuned.hex", *bus)
    assert code == 0
    code, out, _ = run(capsys, "cal", "diff", "tuned.hex", str(demo.s19()))
    assert code == 1 and out.splitlines()[3].split() == ["xsFULL_TANK_PRESS", "changed", "value", "650.00", "bar",
                                                         "700.00", "bar", "+50.00", "bar"]


@pytest.mark.parametrize("argv, message", [
    (["cal", "save", "out.txt"], "out.txt: not a dataset file by its extension '.txt'"),
    (["cal", "save", "out.s19"], "give --region (e.g. --region CALIB)"),
    (["cal", "save", "out.s19", "xsPRV_KP", "--region", "CALIB"], "give no NAME"),
    (["cal", "save", "out.dcm", "--region", "CALIB"], "--region is for an image"),
    (["cal", "save", "out.s19", "--region", "APPLICATIVE"], "the working page is flashed into CALIB, not into "
                                                             "'APPLICATIVE'"),
    (["cal", "save", "out.dcm", "nothing*"], "no calibration matches 'nothing*'"),
    (["cal", "load", "missing.dcm"], "missing.dcm: no such file"),
    (["cal", "sync", "--upload"], "--upload would overwrite the built-in demo's s19"),
    (["cal", "sync", "--output", "x.s19"], "--output names the file --upload writes"),
    (["cal", "sync", "--reference", "missing.s19"], "missing.s19: no such file"),
    (["cal", "sync", "--reference", "notes.txt"], "notes.txt: neither an image"),
    (["cal", "sync", "missing.dcm"], "missing.dcm: no such file"),
    (["cal", "sync", "a.s19", "--reference", "b.s19"], "give the reference FILE or --reference FILE, not both"),
    (["cal", "diff", "ecu", "ECU"], "give 'ecu' as one side only"),
])
def test_bad_input_exits_2_with_one_line(bus, capsys, argv, message):
    code, out, err = run(capsys, *argv, *bus)
    assert code == 2 and message in err and err.count("\n") == 1 and err.startswith("error: ")


def test_another_a2l_needs_a_reference(bus, capsys, tmp_path):
    a2l = edited_a2l(tmp_path, "/* T2 [ms]: BUILD_CHECKSUM, COPY_CAL_PAGE */", "/* T2 */")
    code, _, err = run(capsys, "cal", "sync", "--a2l", str(a2l), *bus)
    assert code == 2 and "give the reference FILE" in err
    assert run(capsys, "cal", "sync", "--a2l", str(a2l), "--reference", str(demo.s19()), *bus)[0] == 0
    assert run(capsys, "cal", "sync", str(demo.s19()), "--a2l", str(a2l), *bus)[0] == 0  # as cal load FILE


def test_diff_and_dry_run_show_values_as_cal_get_does(bus, capsys):
    """A physical value with its unit, an enum's text bare (as cal get shows them), in every form of cal diff and in
    load --dry-run; --json keeps its numbers and texts and gives the units beside them."""
    names = ("xsSWITCH_TANK_THR", "cfTANK1PSDIAGSTATUS_VALUE", "zvTankPConv")
    run(capsys, "cal", "save", "base.dcm", *names, *bus)
    run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "22.5", *bus)
    run(capsys, "cal", "set", "cfTANK1PSDIAGSTATUS_VALUE", "OPEN_LOAD", *bus)
    run(capsys, "cal", "set", "zvTankPConv[3]", "310", *bus)
    assert run(capsys, "cal", "get", "cfTANK1PSDIAGSTATUS_VALUE", *bus)[1] == "cfTANK1PSDIAGSTATUS_VALUE = OPEN_LOAD\n"
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1] == "xsSWITCH_TANK_THR = 22.50 bar\n"
    expected = [["xsSWITCH_TANK_THR", "changed", "value", "20.00", "bar", "22.50", "bar", "+2.50", "bar"],
                ["cfTANK1PSDIAGSTATUS_VALUE", "changed", "value", "NO_ERROR", "OPEN_LOAD"],
                ["zvTankPConv", "changed", "value[3]", "(x", "2.000", "V)", "300.00", "bar", "310.00", "bar", "+10.00", "bar"]]
    table = run(capsys, "cal", "get", "zvTankPConv", *bus)[1].splitlines()
    assert "2.000" in table[1].split() and "310.00" in table[2].split()
    code, out, _ = run(capsys, "cal", "diff", "base.dcm", "ecu", *bus)  # the A2L's decimals, as cal get
    assert code == 1 and [line.split() for line in out.splitlines()[3:-1]] == expected
    run(capsys, "cal", "save", "tuned.cdfx", *names, *bus)
    code, out, _ = run(capsys, "cal", "diff", "base.dcm", "tuned.cdfx", "--a2l", str(demo.a2l()))
    assert code == 1 and [line.split() for line in out.splitlines()[3:-1]] == expected and "'" not in out
    code, out, _ = run(capsys, "cal", "diff", "base.dcm", "tuned.cdfx")  # two files, no A2L: no FORMAT to follow
    assert [line.split() for line in out.splitlines()[3:-1]] == [
        ["xsSWITCH_TANK_THR", "changed", "value", "20", "bar", "22.5", "bar", "+2.5", "bar"], expected[1],
        ["zvTankPConv", "changed", "value[3]", "(x", "2", "V)", "300", "bar", "310", "bar", "+10", "bar"]]
    code, out, _ = run(capsys, "cal", "load", "base.dcm", "--dry-run", *bus)
    assert code == 0 and ["cfTANK1PSDIAGSTATUS_VALUE", "changed", "value", "OPEN_LOAD", "NO_ERROR"] in \
        [line.split() for line in out.splitlines()]
    assert ["xsSWITCH_TANK_THR", "changed", "value", "22.50", "bar", "20.00", "bar", "-2.50", "bar"] in \
        [line.split() for line in out.splitlines()]  # the dry run's diff as cal diff shows it
    data = json.loads(run(capsys, "cal", "diff", "base.dcm", "ecu", "--json", *bus)[1])
    first, enum = data["objects"][:2]
    assert first["unit"] == {"a": "bar", "b": "bar"} and first["differences"][0] == {
        "where": "value", "a": 20.0, "b": 22.5, "delta": 2.5, "at": [], "unit": {"a": "bar", "b": "bar"}}
    assert (enum["differences"][0]["a"], enum["differences"][0]["b"]) == ("NO_ERROR", "OPEN_LOAD")


def test_a_file_value_the_ecu_cannot_take_is_a_note_naming_the_object_once(bus, capsys, tmp_path):
    (tmp_path / "short.dcm").write_text("KONSERVIERUNG_FORMAT 2.0\n\nKENNLINIE zvRailPConv 8\n"
                                        "  ST/X 0.5 1.0 1.5 2.0 2.5 3.0 3.5 4.0\n"
                                        "  WERT 0.0 6.25 12.5 18.75 25.0 31.25 37.5 43.75\nEND\n")
    code, out, _ = run(capsys, "cal", "sync", "short.dcm", *bus)
    assert code == 1 and ("note: zvRailPConv: the file's value cannot be written as it is (axis X has 9 points, the "
                          "value 8; its number of points is not stored in memory, so it cannot change)") in out
