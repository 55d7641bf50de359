"""Offline calibration end to end, as a user works in a temporary folder with the demo's A2L and s19: cal get, set,
list, save and load with --image, the new image flashed into the simulated ECU (udp_multicast on a port of the
test's own) and read back online; a dataset loaded offline gives the bytes the same dataset loaded online gives."""

from __future__ import annotations

import json
import os
import re
import shutil

import bincopy
import pytest
from cli_helpers import run

from workbench import demo
from workbench.image import load_image
from workbench.sim import serve_demo

CALIB = (0xFC0000, 0xFE0000)


@pytest.fixture
def work(tmp_path):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    shutil.copy(demo.s19(), "app.s19")
    try:
        yield tmp_path
    finally:
        os.chdir(cwd)


@pytest.fixture
def bus(work, free_udp_port):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        yield ["--bus-kwargs", f"port={free_udp_port}"]



def test_set_offline_flash_and_read_online(bus, capsys, work):
    names = ("xsFULL_TANK_PRESS", "zvTankPConv", "xvPRV_DC_FF", "cfRAILPRESSURE_EN")
    offline, online = run(capsys, "cal", "get", *names, "--image", "app.s19"), run(capsys, "cal", "get", *names, *bus)
    assert offline == online and offline[0] == 0  # the same codec, the same text
    code, out, err = run(capsys, "cal", "set", "xsFULL_TANK_PRESS", "650 bar", "--image", "app.s19", "-o", "new.s19")
    assert (code, out) == (0, "xsFULL_TANK_PRESS = 650.00 bar (written into new.s19)\n")
    assert "`workbench flash new.s19 --region CALIB` programs them" in err
    code, out, _ = run(capsys, "cal", "set", "xvPRV_DC_FF[1,2]", "55", "--image", "new.s19", "-o", "new.s19")
    assert (code, out) == (0, "xvPRV_DC_FF[1, 2] = 55.00 % (written into new.s19)\n")
    assert run(capsys, "cal", "set", "cfRAILPRESSURE_EN", "ON", "--image", "new.s19", "-o", "new.s19")[0] == 0
    code, out, _ = run(capsys, "cal", "fix", "zfRAILPRESSURE", "30", "--image", "new.s19", "-o", "new.s19")
    assert code == 0 and out.startswith("zfRAILPRESSURE  ON   override 30.00 bar")
    assert (work / "app.s19").read_bytes() == demo.s19().read_bytes()  # the input untouched
    code, _, err = run(capsys, "flash", "new.s19", "--region", "CALIB", *bus)
    assert code == 0, err
    code, out, _ = run(capsys, "cal", "get", "xsFULL_TANK_PRESS", "xvPRV_DC_FF[1,2]", "cfRAILPRESSURE_EN",
                       "zfRAILPRESSURE_EN", "zfRAILPRESSURE_VALUE", *bus)
    assert out.splitlines() == ["xsFULL_TANK_PRESS = 650.00 bar", "xvPRV_DC_FF[1, 2] = 55.00 %",
                                "cfRAILPRESSURE_EN = ON", "zfRAILPRESSURE_EN = ON", "zfRAILPRESSURE_VALUE = 30.00 bar"]
    code, out, _ = run(capsys, "cal", "diff", "ecu", "new.s19", *bus)
    assert code == 0


def test_a_dataset_loaded_offline_gives_the_bytes_it_gives_online(bus, capsys, work):
    assert run(capsys, "cal", "save", "base.dcm", "--image", "app.s19")[1] == \
        "wrote base.dcm: 58 calibrations of app.s19\n"
    text = (work / "base.dcm").read_text(encoding="latin-1")
    text = re.sub(r"(FESTWERT xsPRV_KP\n(?:.*\n)*?\s*WERT\s+)\S+", r"\g<1>6.25", text)
    text = re.sub(r"(FESTWERT xsSWITCH_TANK_THR\n(?:.*\n)*?\s*WERT\s+)\S+", r"\g<1>24.5", text)
    text = re.sub(r"(FESTWERT cfFUELLEVEL_EN\n(?:.*\n)*?\s*TEXT\s+)\S+", r'\g<1>"ON"', text)
    (work / "tuned.dcm").write_text(text, encoding="latin-1")
    code, out, _ = run(capsys, "cal", "load", "tuned.dcm", "--image", "app.s19", "--dry-run")
    assert code == 0 and out.splitlines()[-1] == "tuned.dcm: dry run: 55 unchanged, 3 would change"
    assert not (work / "off.s19").exists()
    code, out, _ = run(capsys, "cal", "load", "tuned.dcm", "--image", "app.s19", "-o", "off.s19")
    assert code == 0 and out.splitlines()[-1] == "tuned.dcm: applied: 3 applied, 55 unchanged"
    assert run(capsys, "cal", "load", "tuned.dcm", *bus)[0] == 0
    assert run(capsys, "cal", "save", "ecu.s19", "--region", "CALIB", *bus)[0] == 0
    offline, online = load_image("off.s19"), load_image("ecu.s19")
    held = [r for r in offline.ranges if CALIB[0] <= r.start < CALIB[1]]
    assert held and all(offline.read(r.start, r.size) == online.read(r.start, r.size) for r in held)
    assert offline.read(0xFC0000, 0x200) != load_image(demo.s19()).read(0xFC0000, 0x200)


def test_json_carries_the_notes_stderr_gives(work, capsys):
    """What the text says on stderr before flashing (the region and command, the checksum not recomputed) is in
    the --json report as "notes": cal set (a value and a cell), cal fix, cal load."""
    code, _, err = run(capsys, "cal", "set", "xsFULL_TANK_PRESS", "650", "--image", "app.s19", "-o", "new.s19")
    said = [line.removeprefix("note: ") for line in err.splitlines()]
    assert code == 0 and any("`workbench flash new.s19 --region CALIB`" in note for note in said)
    run(capsys, "cal", "save", "tuned.dcm", "xsFULL_TANK_PRESS", "--image", "new.s19")
    for argv in (["set", "xsFULL_TANK_PRESS", "640"], ["set", "xvPRV_DC_FF[1,2]", "55"],
                 ["fix", "zfRAILPRESSURE", "30"]):
        code, out, err = run(capsys, "cal", *argv, "--image", "app.s19", "-o", "new.s19", "--json")
        data = json.loads(out)
        assert (code, err) == (0, "") and (data[0] if argv[0] == "fix" else data)["notes"] == said, argv
    code, out, _ = run(capsys, "cal", "load", "tuned.dcm", "--image", "app.s19", "-o", "load.s19", "--json")
    assert code == 0 and json.loads(out)["notes"] == [note.replace("new.s19", "load.s19") for note in said]


def test_what_is_refused_and_how(work, capsys, tmp_path):
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "25", "--image", "app.s19")
    assert (code, out) == (2, "") and err == ("error: --image app.s19 is not changed in place unless you name it: give "
                                              "-o NEW_FILE (or -o app.s19 to change it)\n")
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "9999", "--image", "app.s19", "-o", "new.s19")
    assert code == 2 and err == "error: xsSWITCH_TANK_THR: 9999.00 is above the upper limit 800.00 bar\n"
    code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK", "1", "--image", "app.s19", "-o", "new.s19")
    assert code == 2 and "xsSWITCH_TANK" in err and "did you mean" in err
    code, _, err = run(capsys, "cal", "get", "zsRailPressure", "--image", "app.s19")
    assert code == 2 and "a flash image holds calibrations only" in err
    code, out, err = run(capsys, "cal", "get", "xs*", "--image", "app.s19")  # a glob takes the calibrations only
    assert code == 0 and "xsSWITCH_TANK_THR = 20.00 bar" in out and "xsTankCtrlState" not in out
    code, _, err = run(capsys, "cal", "get", "xsPRV_KP", "--image", "app.s19", "--page", "reference")
    assert code == 2 and err.startswith("error: --page is for the ECU")
    code, _, err = run(capsys, "cal", "get", "xsPRV_KP", "--image", "gone.s19")
    assert code == 2 and "gone.s19" in err
    os.chmod("app.s19", 0o444)
    assert run(capsys, "cal", "get", "xsPRV_KP", "--image", "app.s19")[1] == "xsPRV_KP = 5.0000 %/bar\n"
    code, _, err = run(capsys, "cal", "set", "xsPRV_KP", "6", "--image", "app.s19", "-o", "app.s19")
    assert code == 2 and err == "error: app.s19: the file is read-only; not overwritten (make it writable, or write another file)\n"
    assert not list(tmp_path.glob("*.s19"))[1:] and (tmp_path / "app.s19").read_bytes() == demo.s19().read_bytes()
    code, out, _ = run(capsys, "cal", "list", "xsPRV_K*", "--image", "app.s19", "--json")
    assert code == 0 and [row["value"] for row in json.loads(out)] == [5.0, 2.0, 0.019999999552965164]


@pytest.mark.parametrize("argv", [["flash", "app.elf", "--region", "CALIB"],
                                  ["cal", "get", "xsPRV_KP", "--image", "app.elf"],
                                  ["cal", "sync", "app.elf"], ["cal", "diff", "app.elf", "app.s19"],
                                  ["cal", "get", "xsPRV_KP", "--image", "elf.s19"]])
def test_an_elf_where_an_image_is_expected_says_so(work, capsys, argv):
    """The build's two outputs are easily swapped: an ELF (by its first bytes, whatever its name) is named as one."""
    shutil.copy(demo.elf(), "app.elf")
    shutil.copy(demo.elf(), "elf.s19")
    code, out, err = run(capsys, *argv)
    name, hint = ("elf.s19", "") if "elf.s19" in argv else ("app.elf", " (app.s19 is beside it)")
    assert (code, out) == (2, "")
    assert err == f"error: {name}: is an ELF file, not a flash image: give the build's s19/hex{hint}\n"


@pytest.mark.parametrize(("cell", "message"), [
    ("zvTankPConv[9]", "zvTankPConv has 9 values: index 9 is beyond (0-8)"),  # a CURVE
    ("xvPRV_DC_FF[2,5]", "xvPRV_DC_FF has 6 x 5 values: y index 5 is beyond (0-4)"),  # a MAP, [x, y]
    ("xvPRV_DC_FF[2]", "xvPRV_DC_FF has 6 x 5 values: give 2 indices [x, y], not 1"),
    ("xaPRV_FF_TARGET[6]", "xaPRV_FF_TARGET has 6 points: index 6 is beyond (0-5)"),  # an AXIS_PTS
    ("xsPRV_KP[0]", "xsPRV_KP has one value: name it without an index"),
])
def test_a_cell_beyond_the_object_says_how_many_it_has(work, capsys, cell, message):
    assert run(capsys, "cal", "get", cell, "--image", "app.s19") == (2, "", f"error: {message}\n")


def test_a_c_style_format_shows_alike_in_cal_get_cal_diff_and_the_views(work, capsys):
    """A FORMAT as files in the wild write it ("%8.3lf", not ASAP2's "%8.3") gives its decimals to every face."""
    from workbench.a2l import load_a2l
    from workbench.a2l.model import value_decimals

    text = demo.a2l().read_text(encoding="utf-8").replace('IDENTICAL "%8.2" "bar"', 'IDENTICAL "%8.3lf" "bar"', 1)
    (work / "wild.a2l").write_text(text, encoding="utf-8")
    wild = ("--a2l", "wild.a2l")
    assert run(capsys, "cal", "get", "xsFULL_TANK_PRESS", "--image", "app.s19", *wild)[1] == \
        "xsFULL_TANK_PRESS = 700.000 bar\n"
    assert run(capsys, "cal", "set", "xsFULL_TANK_PRESS", "650", "--image", "app.s19", "-o", "new.s19", *wild)[0] == 0
    code, out, _ = run(capsys, "cal", "diff", "app.s19", "new.s19", *wild)
    assert code == 1 and "700.000 bar" in out and "650.000 bar" in out, out
    assert value_decimals(load_a2l("wild.a2l").model(), "xsFULL_TANK_PRESS") == 3  # the GUI's editors and compare view


def test_every_image_extension_is_read_written_and_named(work, capsys):
    """One list of image extensions (workbench.image.files): .sx is read and written as .s19 is, and the refusals
    name it too (the offline image's message once left it out while accepting it)."""
    from workbench.image import IMAGE_SUFFIXES

    os.rename("app.s19", "app.sx")
    assert run(capsys, "cal", "get", "xsPRV_KP", "--image", "app.sx")[1] == "xsPRV_KP = 5.0000 %/bar\n"
    assert run(capsys, "cal", "set", "xsPRV_KP", "6", "--image", "app.sx", "-o", "new.ihex")[0] == 0
    assert (work / "new.ihex").read_text().startswith(":")  # Intel HEX by its extension
    for refused in (("cal", "get", "xsPRV_KP", "--image", "app.txt"),
                    ("cal", "set", "xsPRV_KP", "6", "--image", "app.sx", "-o", "new.txt")):
        code, _, err = run(capsys, *refused)
        assert code == 2 and all(suffix in err for suffix in IMAGE_SUFFIXES), err


@pytest.mark.parametrize("encoding", ["utf-16", "cp1252"])
def test_a_spreadsheet_s_csv_in_its_own_encoding_is_taken(work, capsys, encoding):
    """Excel writes "Unicode text" as UTF-16 with a BOM and a plain CSV in Windows-1252 (the legend's µ, °)."""
    (work / "curve.csv").write_bytes("zvRailPConv: x [V] in µ-steps, values [bar] at 20 °C\n"
                                     "x 0.5 1 1.5 2 2.5 3 3.5 4 4.5\n"
                                     "value 0 6.25 12.5 18.75 25 31.25 37.5 43.75 49\n".encode(encoding))
    code, out, err = run(capsys, "cal", "set", "zvRailPConv", "--from", "curve.csv", "--image", "app.s19",
                         "-o", "new.s19")
    assert code == 0 and "43.75 49.00" in out
    (work / "bad.csv").write_bytes(b"0,1\n2,\x81\n")  # undefined in Windows-1252 too
    assert run(capsys, "cal", "set", "zvRailPConv", "--from", "bad.csv", "--image", "app.s19", "-o", "new.s19") == \
        (2, "", "error: bad.csv:2: not a value file (byte 0x81 is not UTF-8, UTF-16 or Windows-1252 text)\n")


def test_an_s0_header_in_another_encoding_is_kept(work, capsys):
    """A linker's S0 of latin-1 text and binary bytes: the image is edited and the header written back byte for byte
    (bincopy's default decodes it as UTF-8: a traceback in cal, flash and a2l check)."""
    header = bincopy.pack_srec("0", 0, 6, "Bü1d".encode("latin-1") + b"\xff\x00")
    work.joinpath("foreign.s19").write_text(header + "\n" + work.joinpath("app.s19").read_text().split("\n", 1)[1])
    code, out, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "21", "--image", "foreign.s19", "-o", "new.s19")
    assert (code, out) == (0, "xsSWITCH_TANK_THR = 21.00 bar (written into new.s19)\n"), err
    assert work.joinpath("new.s19").read_text().splitlines()[0] == header
    assert load_image("new.s19").header == "Bü1d".encode("latin-1") + b"\xff\x00"
    code, out, err = run(capsys, "a2l", "check", demo.a2l(), "--image", "foreign.s19")
    assert code == 0, err


def test_a_map_whose_shared_axis_a_dataset_moves_says_so(work, capsys):
    """A map given with other breakpoints than its COM_AXIS holds writes that AXIS_PTS too: said, as it moves the
    points of every object on that axis (it was written unsaid; user trial 10). Given with the axis, no warning."""
    run(capsys, "cal", "save", "map.dcm", "xvPRV_DC_FF", "xaPRV_FF_TARGET", "--image", "app.s19")
    text = open("map.dcm", encoding="utf-8").read()
    moved = text.replace("ST/X 0.0 10.0", "ST/X 0.0 12.0")  # in the map and in the axis
    open("moved.dcm", "w", encoding="utf-8").write(moved[:moved.index("STUETZSTELLENVERTEILUNG")])  # the map alone
    code, out, _ = run(capsys, "cal", "load", "moved.dcm", "--image", "app.s19", "--dry-run")
    assert code == 0 and ("warning: xvPRV_DC_FF: its X axis is the AXIS_PTS xaPRV_FF_TARGET (COM_AXIS): its points "
                          "are written too, as the dataset gives them") in out.splitlines()
    open("both.dcm", "w", encoding="utf-8").write(moved)  # the axis itself given alike: the user chose it
    code, out, _ = run(capsys, "cal", "load", "both.dcm", "--image", "app.s19", "--dry-run")
    assert code == 0 and "warning" not in out and "xaPRV_FF_TARGET  would change" in out


@pytest.mark.parametrize("suffix", ["dcm", "cdfx"])
def test_an_element_beyond_its_limits_is_named_at_its_own_line(work, capsys, suffix):
    """A cell of a map refused names the line that holds it, not the line where the map's values begin (a 16 x 16
    map's file:line led 40 lines away from the value; user trial 10)."""
    run(capsys, "cal", "save", f"maps.{suffix}", "xvPRV_DC_FF", "zvRailPConv", "--image", "app.s19")
    lines = open(f"maps.{suffix}", encoding="utf-8").read().splitlines(keepends=True)
    if suffix == "dcm":  # x along a WERT row, a row per y: [3, 3] is the fourth value of the fourth row
        row = [i for i, line in enumerate(lines) if line.startswith("  WERT 0.0 35.0")][0]
        lines[row] = "  WERT 0.0 35.0 35.0 135.0 35.0 35.0\n"
        point = [i for i, line in enumerate(lines) if line.startswith("  WERT 37.5")][0]
        lines[point] = "  WERT 37.5 53.75 50.0\n"
    else:  # one <V> a line, x fastest
        values = [i for i, line in enumerate(lines) if "<V>" in line and "SW-AXIS" not in line]
        curve = [i for i, line in enumerate(lines) if "<V>43.75</V>" in line][0]
        map_values = [i for i in values if i < curve][-30:]  # the map comes first; its 30 values before the curve's
        row = [i for i in map_values if "<V>35.0</V>" in lines[i]][2]  # x 3 of y 3: the third 35.0 of that row
        lines[row] = lines[row].replace("35.0", "135.0")
        point = curve
        lines[point] = lines[point].replace("43.75", "53.75")
    open(f"bad.{suffix}", "w", encoding="utf-8").writelines(lines)
    code, out, _ = run(capsys, "cal", "load", f"bad.{suffix}", "--image", "app.s19", "--dry-run")
    assert code == 2
    assert f"xvPRV_DC_FF  refused  bad.{suffix}:{row + 1}: 135.00 at [3, 3] is above the upper limit 100.00 %" in out
    assert f"zvRailPConv  refused  bad.{suffix}:{point + 1}: 53.75 at [7] is above the upper limit 50.00 bar" in out


def test_an_image_against_a_parameter_set_compares_the_set_s_objects(work, capsys):
    """As the ECU is compared with a parameter set (and the window compares the project's image with one): the objects
    the set holds; an image against a set of one equal object was 'different', 57 objects only in the image."""
    run(capsys, "cal", "save", "one.dcm", "xsSWITCH_TANK_THR", "--image", "app.s19")
    for sides in (("app.s19", "one.dcm"), ("one.dcm", "app.s19")):
        code, out, _ = run(capsys, "cal", "diff", *sides)
        assert (code, out.splitlines()[-1]) == (0, "1 object: 1 equal, 0 changed, 0 shape changed, 0 only in A, "
                                                   "0 only in B"), sides
    assert run(capsys, "cal", "diff", "app.s19", "app.s19")[1].splitlines()[-1].startswith("58 objects: 58 equal")


def test_an_image_of_another_build_compared_offline_says_so(work, capsys):
    """As cal get --image says it (and the ECU's compare refuses it): its values are read at this A2L's addresses,
    which another build may have moved (cal diff said nothing; user trial 10)."""
    other = bincopy.BinFile("app.s19")
    other[0xFC0000:0xFC000E] = b"10300020259999"
    open("other.s19", "w").write(other.as_srec())
    code, _, err = run(capsys, "cal", "diff", "other.s19", "app.s19")
    assert code == 0 and err == ("warning: other.s19 holds the EPK '10300020259999' in CALIB (FC0000h), the A2L "
                                 "'10300020250301': the A2L may not describe this software; its values are read at "
                                 "the A2L's addresses\n")
