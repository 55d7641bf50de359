"""``workbench a2l remove|cleanup|flatten`` and ``insert --create`` end to end: files in tmp_path, exit codes,
findings at file:line:column, --json, atomic and refused writes."""

from __future__ import annotations

import json
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import run
from pya2l_oracle import pya2l_import

from workbench import demo
from workbench.a2l import load_a2l

A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")


def _demo(tmp_path):
    path = tmp_path / "FLCU.a2l"
    shutil.copy(demo.a2l(), path)
    return path


def test_remove_writes_the_input_less_the_objects(tmp_path, capsys):
    source = _demo(tmp_path)
    code, out, err = run(capsys, "a2l", "remove", source, "-R", "zsTank.*Filt", "--range", "0x40020034", "0x40020035",
                         "-o", tmp_path / "out.a2l")
    assert code == 0 and out == ""
    assert err.strip() == f"wrote {tmp_path / 'out.a2l'}: 3 MEASUREMENT removed (3 reference(s) with them)"
    before, after = source.read_text().splitlines(), (tmp_path / "out.a2l").read_text().splitlines()
    assert [line for line in before if line not in after][0].strip() == "zsTank1VoltFilt"  # the LOC_MEASUREMENT entry
    assert all(line in before for line in after) and len(before) - len(after) == 3 * 16 + 3
    code, out, _ = run(capsys, "a2l", "check", tmp_path / "out.a2l")
    assert code == 0
    code, out, _ = run(capsys, "a2l", "remove", source, "-R", "zsManifoldVoltFilt", "--dry-run", "--json")
    report = json.loads(out)
    assert code == 0 and report["removed"] == {"MEASUREMENT": ["zsManifoldVoltFilt"]} and "output" not in report
    lines = [line.split("*/")[-1].strip() for line in source.read_text().splitlines()]
    entry, name = (index + 1 for index, line in enumerate(lines) if line == "zsManifoldVoltFilt")
    assert [f["line"] for f in report["findings"]] == [entry, name]


def test_remove_refuses_and_writes_nothing(tmp_path, capsys):
    source = _demo(tmp_path)
    code, out, err = run(capsys, "a2l", "remove", source, "-R", "xaPRV_FF_.*", "-o", tmp_path / "out.a2l")
    assert code == 1 and not (tmp_path / "out.a2l").exists()
    line = source.read_text().splitlines().index("        AXIS_PTS_REF xaPRV_FF_TARGET") + 1
    assert out.splitlines()[0].startswith(f"{source}:{line}:22: error: CHARACTERISTIC xvPRV_DC_FF AXIS_DESCR: "
                                          "AXIS_PTS_REF xaPRV_FF_TARGET would name a removed object")
    assert err.startswith("remove: 2 problem(s), nothing written: xaPRV_FF_TARGET")
    code, out, _ = run(capsys, "a2l", "remove", source, "-R", "zsRailVoltFilt", "-o", source,
                       "--drop-optional-references", "-v")  # in place
    assert code == 0 and "warning: CHARACTERISTIC zvRailPConv AXIS_DESCR: INPUT_QUANTITY zsRailVoltFilt" in out
    assert "zsRailVoltFilt" not in source.read_text()


def test_bad_input_is_exit_2(tmp_path, capsys):
    source = _demo(tmp_path)
    for argv in (["-R", "("], [], ["-R", "x"], ["--range", "0x10", "0x10", "-o", "o.a2l"]):
        code, _, err = run(capsys, "a2l", "remove", source, *argv)
        assert code == 2 and err.count("\n") <= 6, argv
    readonly = tmp_path / "readonly.a2l"
    readonly.write_text("kept")
    readonly.chmod(stat.S_IRUSR)
    code, _, err = run(capsys, "a2l", "cleanup", source, "-o", readonly)
    assert code == 2 and "read-only" in err and readonly.read_text() == "kept"
    code, _, err = run(capsys, "a2l", "remove", source, "-R", "nothing_named_so", "-o", tmp_path / "same.a2l")
    assert code == 0 and (tmp_path / "same.a2l").read_bytes() == source.read_bytes()


def test_cleanup_and_flatten(tmp_path, capsys):
    source = _demo(tmp_path)
    code, out, err = run(capsys, "a2l", "cleanup", source, "-o", tmp_path / "clean.a2l", "--json")
    report = json.loads(out)
    assert code == 0 and report["operation"] == "cleanup" and len(report["removed"]["RECORD_LAYOUT"]) == 7
    assert all(f["file"] == str(source) and f["line"] for f in report["findings"])
    code, out, err = run(capsys, "a2l", "flatten", demo.master_a2l(), "-o", tmp_path / "flat.a2l")
    assert code == 0 and err.strip() == f"wrote {tmp_path / 'flat.a2l'}: 1 /include(s) written inline"
    assert "struct Protocol_Layer" in (tmp_path / "flat.a2l").read_text()


def test_insert_create_makes_a_file_check_and_pya2ldb_accept(tmp_path, capsys):
    new = tmp_path / "new.a2l"
    code, _, err = run(capsys, "a2l", "insert", "--create", demo.elf(), "-o", new, "--measurement-regex", "zs.*",
                       "--characteristic-regex", "xs.*", "--target-group", "Demo")
    assert code == 0 and err.strip().startswith(f"wrote {new}: 13 MEASUREMENT, 40 CHARACTERISTIC inserted")
    text = new.read_text()
    assert "BYTE_ORDER MSB_LAST" in text and 'EPK "' in text and "/begin MODULE FLCU" in text
    code, out, _ = run(capsys, "a2l", "check", new, "--elf", demo.elf())
    assert code == 0, out
    assert pya2l_import(new)["MEASUREMENT"] == 13
    code, _, err = run(capsys, "a2l", "insert", "--create", demo.elf(), "-o", new, "-M", "zsRailPressure", "--module",
                       "2bad")
    assert code == 2 and "not an A2L name" in err
    code, _, err = run(capsys, "a2l", "insert", demo.elf(), "-o", new, "-M", "zsRailPressure")
    assert code == 2 and "--create" in err


@pytest.mark.parametrize("order", ["IN --create ELF", "--create ELF IN", "IN ELF --create"])
def test_insert_create_with_an_input_a2l_says_what_create_takes(tmp_path, capsys, order):
    """--create anywhere beside an input A2L: one line saying --create takes the ELF alone (argparse said
    'unrecognized arguments: ELF' for the first order, and the other two named the wrong file); nothing written."""
    source, new = _demo(tmp_path), tmp_path / "new.a2l"
    words = order.replace("IN", str(source)).replace("ELF", str(demo.elf())).split()
    code, out, err = run(capsys, "a2l", "insert", *words, "-o", new, "-M", "zsRailPressure")
    files = " ".join(word for word in words if word != "--create")
    assert (code, out, new.exists()) == (2, "", False)
    assert err == (f"error: insert --create ELF: --create makes a new A2L from one ELF, written to -o OUT.a2l; 2 files "
                   f"given ({files}): without --create, insert IN.a2l ELF adds to an existing A2L\n")


@pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
def test_insert_create_makes_the_objects_a2ltool_creates(tmp_path, capsys):
    options = ["--measurement-regex", "zs.*", "--characteristic-regex", "xs.*", "--target-group", "Demo"]
    assert run(capsys, "a2l", "insert", "--create", demo.elf(), "-o", tmp_path / "ours.a2l", *options)[0] == 0
    subprocess.run([A2LTOOL, "--create", "--elffile", str(demo.elf()), *options, "--output",
                    str(tmp_path / "theirs.a2l")], check=True, capture_output=True, timeout=60)

    def objects(path):
        module = load_a2l(path).module()
        named = {block.name for block in module.children if block.name}
        return named | {(block.keyword, block.name, block.text().split("\n", 2)[1].strip()) for block in module.children
                        if block.keyword in ("MEASUREMENT", "CHARACTERISTIC")}

    assert objects(tmp_path / "ours.a2l") == objects(tmp_path / "theirs.a2l")


def test_remove_takes_a2ltools_spelling_of_its_options(tmp_path, capsys):
    """A build script's ``a2ltool IN -R RE --remove-range MIN MAX -o OUT`` as ``workbench a2l remove``."""
    source = _demo(tmp_path)
    outputs = []
    for regex, address_range in (("-R", "--range"), ("--remove", "--remove-range")):
        outputs.append(tmp_path / f"{regex}.a2l")
        code, _, _ = run(capsys, "a2l", "remove", source, regex, "zsTank.*Filt", address_range, "0x40020034",
                         "0x40020035", "-o", outputs[-1])
        assert code == 0
    assert outputs[0].read_bytes() == outputs[1].read_bytes() != source.read_bytes()


def test_ctrl_c_during_remove_cleanup_or_flatten_writes_nothing(tmp_path, capsys, monkeypatch):
    """Ctrl-C while the job runs (here: at its last check point, the progress bar's report before the write)."""
    from workbench.cli.progressbar import ProgressBar

    def interrupted(self, done, total, label=""):
        if label == "writing":
            raise KeyboardInterrupt

    monkeypatch.setattr(ProgressBar, "update", interrupted)
    source, out = _demo(tmp_path), tmp_path / "out.a2l"
    for command in (["remove", "-R", "zsTank.*Filt"], ["cleanup"], ["flatten"]):
        code, stdout, stderr = run(capsys, "a2l", command[0], source, *command[1:], "-o", out)
        assert (code, stdout, stderr, out.exists()) == (130, "", "error: interrupted\n", False)
