"""An A2L loaded for work (session, image, flash, cal/measure/info): a missing A2ML include (.aml, XCPlite's
XCP_104.aml) is a warning naming file:line:column, any other missing include stays the error load_a2l raises."""

from __future__ import annotations

import logging
import shutil
import struct
from pathlib import Path

import bincopy
import pytest

from workbench import ImageCalibration
from workbench.a2l import load_a2l
from workbench.a2l.check import check_file
from workbench.a2l.includes import load_a2l_to_work
from workbench.cli import main
from workbench.errors import A2lParseError

XCPLITE = Path(__file__).parents[1] / "corpus" / "a2l" / "xcplite"
WITH_AML = sorted(path for path in XCPLITE.glob("*.a2l") if '/include "XCP_104.aml"' in path.read_text("latin-1"))


@pytest.mark.parametrize("path", WITH_AML, ids=lambda path: path.name)
def test_a_missing_a2ml_include_is_a_warning(path, caplog):
    with pytest.raises(A2lParseError, match="cannot include"):
        load_a2l(path)  # the strict loader (merge, update) is unchanged
    with caplog.at_level(logging.WARNING, logger="workbench"):
        doc = load_a2l_to_work(path)
    assert [r.getMessage() for r in caplog.records] == [f'{path}:8:1: /include "XCP_104.aml" left out: no such file']
    assert doc.model().names("CHARACTERISTIC") or doc.model().names("MEASUREMENT")
    assert [f.kind for f in check_file(path).findings if f.name == "XCP_104.aml"] == ["include-not-found"]


def test_any_other_missing_include_stays_an_error(tmp_path):
    text = (XCPLITE / "hello_xcp.a2l").read_text("latin-1").replace('"XCP_104.aml"', '"params.a2l"')
    (tmp_path / "ecu.a2l").write_text(text, "latin-1")
    with pytest.raises(A2lParseError) as raised:
        load_a2l_to_work(tmp_path / "ecu.a2l")
    assert (raised.value.line, raised.value.column) == (8, 1) and "params.a2l: no such file" in str(raised.value)
    said = f"cannot include {tmp_path / 'params.a2l'}: no such file"  # the path once, as load_a2l and check say it
    with pytest.raises(A2lParseError) as strict:
        load_a2l(tmp_path / "ecu.a2l")
    assert raised.value.reason == strict.value.reason == said
    assert [f.message for f in check_file(tmp_path / "ecu.a2l").findings if f.kind == "include-not-found"] == [
        f"{said} (the rest is checked without it)"]


def test_cal_get_and_set_with_an_image_through_xcplites_a2l(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(XCPLITE / "hello_xcp.a2l", "ecu.a2l")  # as `workbench info --save-a2l` writes it: no .aml beside it
    image = bincopy.BinFile()
    image.add_binary(struct.pack("<HHIf", 1000, 0, 50000, 0.5), address=0x80010000)  # params of hello_xcp
    Path("app.hex").write_text(image.as_ihex())
    warning = 'warning: ecu.a2l:8:1: /include "XCP_104.aml" left out: no such file\n'
    assert main(["cal", "get", "params.counter_max", "params.flow_rate", "--image", "app.hex", "--a2l", "ecu.a2l"]) == 0
    out, err = capsys.readouterr()
    assert (out, err) == ("params.counter_max = 1000\nparams.flow_rate = 0.5 m3/h\n", warning)
    assert main(["cal", "set", "params.counter_max", "1200", "--image", "app.hex", "-o", "new.hex", "--a2l",
                 "ecu.a2l"]) == 0
    assert capsys.readouterr()[1].startswith(warning)
    assert ImageCalibration.open("new.hex", "ecu.a2l").read("params.counter_max") == 1200  # the library's way in
    (tmp_path / "ecu.a2l").write_text(Path("ecu.a2l").read_text("latin-1").replace("XCP_104.aml", "x.a2l"), "latin-1")
    assert main(["cal", "get", "params.counter_max", "--image", "app.hex", "--a2l", "ecu.a2l"]) == 2
    err = capsys.readouterr()[1]
    assert err.startswith("error: ecu.a2l:8:1: cannot include") and err.count("\n") == 1
