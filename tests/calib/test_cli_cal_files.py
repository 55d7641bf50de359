"""workbench cal convert / diff end to end in a temp dir: outputs, exit codes 0/1/2, one-line errors."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import run

from workbench import demo
from workbench.calib.dataset import load_dataset

CORPUS = Path(__file__).parents[1] / "corpus" / "datasets"



@pytest.fixture
def inca_dcm(tmp_path) -> Path:
    return Path(shutil.copy(CORPUS / "tools" / "inca_style.dcm", tmp_path / "base.dcm"))


def test_convert_both_ways_and_diff_equal(capsys, tmp_path, inca_dcm):
    cdfx, dcm = tmp_path / "out" / "base.cdfx", tmp_path / "again.dcm"
    code, out, err = run(capsys, "cal", "convert", inca_dcm, cdfx)
    assert code == 0 and cdfx.exists()
    assert err == f"wrote {cdfx}: 58 objects (DCM -> CDFX)\n"
    assert out == ""  # nothing the INCA file holds is lost in CDF
    assert run(capsys, "cal", "convert", cdfx, dcm)[0] == 0
    assert load_dataset(dcm).objects == load_dataset(inca_dcm).objects
    code, out, _ = run(capsys, "cal", "diff", inca_dcm, cdfx)
    assert code == 0 and out.splitlines()[-1] == "58 objects: 58 equal, 0 changed, 0 shape changed, 0 only in A, 0 only in B"


def test_diff_of_changed_files_exits_1_with_the_table_and_json(capsys, tmp_path, inca_dcm):
    tuned = tmp_path / "tuned.dcm"
    tuned.write_bytes(inca_dcm.read_bytes().replace(b"WERT 5.0000000000000000\r\nEND\r\n\r\nFESTWERT xsPRV_KI",
                                                    b"WERT 5.5\r\nEND\r\n\r\nFESTWERT xsPRV_KI"))
    code, out, _ = run(capsys, "cal", "diff", inca_dcm, tuned)
    assert code == 1
    assert ["xsPRV_KP", "changed", "value", "5", "%/bar", "5.5", "%/bar", "+0.5", "%/bar"] in [line.split() for line in out.splitlines()]
    code, out, _ = run(capsys, "cal", "diff", inca_dcm, tuned, "--a2l", str(demo.a2l()))  # its FORMAT "%8.4"
    assert ["xsPRV_KP", "changed", "value", "5.0000", "%/bar", "5.5000", "%/bar", "+0.5000", "%/bar"] in \
        [line.split() for line in out.splitlines()]
    code, out, _ = run(capsys, "cal", "diff", inca_dcm, tuned, "--json")
    data = json.loads(out)
    assert code == 1 and data["counts"]["changed"] == 1 and data["notes"] == []
    assert run(capsys, "cal", "diff", inca_dcm, tuned, "--tolerance", "0.5")[0] == 0
    assert run(capsys, "cal", "diff", inca_dcm, tuned, "--rel-tolerance", "0.05")[0] == 1
    assert run(capsys, "cal", "diff", inca_dcm, tuned, "--rel-tolerance", "0.1")[0] == 0


def test_cdfx_notes_are_warnings(capsys, tmp_path):
    source = tmp_path / "admin.cdfx"
    source.write_text('<MSRSW><SHORT-NAME>x</SHORT-NAME><CATEGORY>CDF20</CATEGORY><ADMIN-DATA/></MSRSW>')
    code, out, _ = run(capsys, "cal", "convert", source, tmp_path / "admin.dcm")
    assert code == 0 and out == f"{source}:1: warning: <ADMIN-DATA> (administrative data) is not kept\n"


def test_converting_cdf21_to_dcm_names_what_it_leaves_out_and_writes_the_rest(capsys, tmp_path):
    code, out, err = run(capsys, "cal", "convert", CORPUS / "constructs" / "cdf21_style.cdfx", tmp_path / "c.dcm")
    assert code == 0 and "flcu.cube.FILL: a CUBOID of 2 x 3 x 2 values cannot be written to DCM" in out
    assert out.count("left out of the file") == 4 and err.strip().endswith("wrote " + str(tmp_path / "c.dcm")
                                                                           + ": 10 objects (CDFX -> DCM)")
    assert list(load_dataset(tmp_path / "c.dcm"))[-2:] == ["flcu_limit[0]", "flcu_limit[1]"]


@pytest.mark.parametrize("argv, message", [
    (["convert", "{missing}", "{out}.cdfx"], "error: {missing}: no such file\n"),
    (["convert", "{bad}", "{out}.cdfx"], "error: {bad}:2:8: WERT: 'abc' is not a number\n"),
    (["convert", "{good}", "{out}.txt"], "error: {out}.txt: not a dataset file by its extension '.txt' (known: .dcm, .cdfx, .cdf, .xml)\n"),
    (["convert", "{good}", "{tmp}"], "error: {tmp}: no extension to tell the dataset format by (known: .dcm, .cdfx, .cdf, .xml)\n"),
    (["convert", "{good}", "{good}/x.dcm"], "error: {good}/x.dcm: cannot write (File exists)\n"),
    (["diff", "{good}", "{missing}"], "error: {missing}: no such file\n"),
])
def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path, argv, message):
    names = {"missing": tmp_path / "missing.dcm", "bad": tmp_path / "bad.dcm", "good": tmp_path / "good.dcm",
             "out": tmp_path / "out", "tmp": tmp_path}
    names["bad"].write_text("FESTWERT a\n  WERT abc\nEND\n")
    names["good"].write_text("FESTWERT a\n  WERT 1\nEND\n")
    code, out, err = run(capsys, "cal", *[a.format(**names) for a in argv])
    assert (code, out, err) == (2, "", message.format(**names))
    assert not (tmp_path / "out.cdfx").exists()


def test_usage_errors_exit_2(capsys, tmp_path):
    assert run(capsys, "cal", "diff", "a.dcm", "b.dcm", "--tolerance", "-1")[0] == 2
    assert run(capsys, "cal", "convert", "a.dcm")[0] == 2
    code, out, _ = run(capsys, "cal", "diff", "--help")
    assert code == 0 and "0 the datasets are equal, 1 they differ, 2 bad input" in " ".join(out.split())


def test_an_existing_output_is_replaced_atomically_and_kept_on_failure(capsys, tmp_path, inca_dcm):
    out = tmp_path / "out.cdfx"
    out.write_text("previous")
    bad = tmp_path / "bad.dcm"
    bad.write_text("FESTWERT a\n  WERT 1\n")
    assert run(capsys, "cal", "convert", bad, out)[0] == 2
    assert out.read_text() == "previous" and [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    assert run(capsys, "cal", "convert", inca_dcm, out)[0] == 0 and out.read_text().startswith("<?xml")


def test_encoding_option_writes_an_ansi_dcm(capsys, tmp_path):
    cdfx = CORPUS / "tools" / "canape_style.cdfx"
    ansi = tmp_path / "ansi.dcm"
    assert run(capsys, "cal", "convert", cdfx, ansi, "--encoding", "cp1252")[0] == 0
    assert "µs".encode("cp1252") in ansi.read_bytes() and load_dataset(ansi).objects == load_dataset(cdfx).objects


def test_the_installed_command_runs(tmp_path):
    """As a user types it: a separate process, the console script's entry point."""
    out = tmp_path / "demo.cdfx"
    code = ("import sys; from workbench.cli import entry_point; sys.argv[0] = 'workbench'; entry_point()")
    result = subprocess.run([sys.executable, "-c", code, "cal", "convert", str(CORPUS / "tools" / "matlab_style.dcm"),
                             str(out)], capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == f"wrote {out}: 58 objects (DCM -> CDFX)\n", result.stderr
