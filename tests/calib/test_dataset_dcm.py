"""DCM: every keyword read as a tool writes it, every malformed file named at file:line:column, the writer's layout."""

from __future__ import annotations

import math

import numpy as np
import pytest

from workbench.calib.dataset import load_dataset, load_dataset_string
from workbench.calib.dataset.dcm_write import losses, write
from workbench.calib.dataset.model import Dataset, FunctionInfo, ObjectInfo
from workbench.calib.values import Axis, CalValue
from workbench.errors import DatasetParseError, InputError

EVERY_KEYWORD = r'''* file comment
! second style of comment
. third style
KONSERVIERUNG_FORMAT 2.0
MODULKOPF Projekt "FLCU"
MODULKOPF "second line"
FUNKTIONEN
  FKT PRVCtrl "1.0.0" "Rail pressure control"
  FKT PressSens
END
VARIANTENKODIERUNG
  KRITERIUM Engine V6 V8
END

FESTWERT xsPRV_KP
  LANGNAME "PID \"proportional\" gain, C:\temp"
  DISPLAYNAME "KP gain"
  FUNKTION PRVCtrl PressSens
  VAR Engine=V6, Market="EU"
* inside the block
  EINHEIT_W "%/bar"
  WERT 5.0
END
FESTWERT zfRAILPRESSURE_EN
  FUNKTION "PressSens"
  TEXT "OFF"
END
TEXTSTRING xtVERSION
  TEXT "a ""quoted"" word"
END
FESTWERTEBLOCK xbBlock 3
  WERT 1 2
  WERT 3
END
FESTWERTEBLOCK xbMatrix 3 @ 2
  WERT 1 2 3
  WERT 4 5 6
END
KENNLINIE zvTankPConv 3
  EINHEIT_X "V"
  EINHEIT_W "bar"
  ST/X 0.5 2.5
  ST/X 4.5
  WERT 0 400.0 800
END
FESTKENNLINIE xfFixed 2
  ST/X 0 10
  WERT 1.5 2.5
END
KENNLINIE xtVerbal 3
  ST_TX/X "low" "mid" "high"
  TEXT "OFF" "ON"
  WERT 7
END
GRUPPENKENNLINIE xgGroup 2
*SSTX	xaShared
  ST/X 1 2
  WERT 3 4
END
KENNFELD xvMap 3 2
  EINHEIT_X "rpm"
  EINHEIT_Y "bar"
  EINHEIT_W "%"
  ST/X 1000 2000 3000
  ST/Y 50
  WERT 1 2
  WERT 3
  ST/Y 100
  WERT 4 5 6
END
FESTKENNFELD xvFixedMap 1 2
  ST/X 0
  ST_TX/Y "a"
  WERT 1
  ST_TX/Y "b"
  TEXT "x"
END
GRUPPENKENNFELD xvGroupMap 2 1
*SSTX xaX
*SSTY xaY
  ST/X 1 2
  ST/Y 3
  WERT 4 5
END
STUETZSTELLENVERTEILUNG xaShared 2
  EINHEIT_X "bar"
  ST/X 1 2
END
'''


def read(text: str, path: str = "test.dcm") -> Dataset:
    return load_dataset_string(text, "dcm", path)


def test_every_keyword_as_written_by_tools():
    ds = read(EVERY_KEYWORD)
    assert ds.comments == ["file comment", "second style of comment", "third style"]
    assert ds.module_header == [("Projekt", "FLCU"), ("", "second line")]
    assert ds.functions == {"PRVCtrl": FunctionInfo("1.0.0", "Rail pressure control"), "PressSens": FunctionInfo()}
    assert ds.variant_criteria == {"Engine": ("V6", "V8")}

    kp = ds["xsPRV_KP"]
    assert kp == CalValue("xsPRV_KP", "VALUE", 5.0, unit="%/bar")
    assert kp.comment == 'PID "proportional" gain, C:\\temp'  # a backslash before other characters stays
    assert ds.info["xsPRV_KP"] == ObjectInfo(display_name="KP gain", functions=("PRVCtrl", "PressSens"),
                                             comments=("inside the block",), variants=(("Engine", "V6"), ("Market", "EU")),
                                             category="FESTWERT", line=15, value_line=22,
                                             value_runs=((22, 1),))
    assert ds["zfRAILPRESSURE_EN"].value == "OFF" and ds.info["zfRAILPRESSURE_EN"].functions == ("PressSens",)
    assert ds["xtVERSION"] == CalValue("xtVERSION", "ASCII", 'a "quoted" word')

    block = ds["xbBlock"].value
    assert block.dtype == np.int64 and block.tolist() == [1, 2, 3]
    assert ds["xbMatrix"].value.shape == (3, 2) and ds["xbMatrix"].value[:, 1].tolist() == [4, 5, 6]

    curve = ds["zvTankPConv"]
    assert curve.value.dtype == np.float64 and curve.value.tolist() == [0, 400, 800]
    assert curve.axes == (Axis(np.array([0.5, 2.5, 4.5]), "STD_AXIS", unit="V"),) and curve.unit == "bar"
    assert ds["xfFixed"].axes[0].kind == "FIX_AXIS"
    verbal = ds["xtVerbal"]
    assert verbal.axes[0].values.tolist() == ["low", "mid", "high"] and verbal.value.tolist() == ["OFF", "ON", 7]
    assert ds["xgGroup"].axes[0] == Axis(np.array([1, 2]), "COM_AXIS", "xaShared")

    fmap = ds["xvMap"]
    assert fmap.value.shape == (3, 2) and fmap.value[2, 0] == 3 and fmap.value[0, 1] == 4
    assert [a.unit for a in fmap.axes] == ["rpm", "bar"] and fmap.axes[1].values.tolist() == [50, 100]
    assert ds["xvFixedMap"].axes[1].values.tolist() == ["a", "b"] and ds["xvFixedMap"].value.tolist() == [[1, "x"]]
    group = ds["xvGroupMap"]
    assert [(a.kind, a.name) for a in group.axes] == [("COM_AXIS", "xaX"), ("COM_AXIS", "xaY")]
    assert ds["xaShared"] == CalValue("xaShared", "AXIS_PTS", np.array([1, 2]), unit="bar")


def test_comments_outside_blocks_belong_to_the_file_and_sstx_outside_groups_is_a_comment():
    ds = read("FESTWERT a\n WERT 1\nEND\n* between\nKENNLINIE b 1\n*SSTX c\n ST/X 1\n WERT 2\nEND\n* after\n")
    assert ds.comments == ["between", "after"]
    assert ds.info["b"].comments == ("SSTX c",) and ds["b"].axes[0].name is None


@pytest.mark.parametrize("data, text", [
    (b"\xef\xbb\xbfFESTWERT a\r\n  EINHEIT_W \"\xc2\xb5s\"\r\n  WERT 1\r\nEND\r\n", "µs"),  # UTF-8 with BOM, CRLF
    ("FESTWERT a\r  EINHEIT_W \"µs\"\r  WERT 1\rEND\r".encode("utf-16"), "µs"),  # UTF-16 with BOM, CR only
    (b"FESTWERT a\n  EINHEIT_W \"\xb5s \x80\"\n  WERT 1\nEND\n", "µs €"),  # Windows-1252 (INCA's ANSI code page)
    (b"FESTWERT a\n  EINHEIT_W \"\x81\xb5\"\n  WERT 1\nEND\n", "\x81µ"),  # a byte Windows-1252 leaves undefined
])
def test_encodings_and_line_ends(data, text):
    assert load_dataset_string(data, "dcm")["a"].unit == text


@pytest.mark.parametrize("text, where, message", [
    ("FOO x\n", ":1:1:", "unknown keyword 'FOO'"),
    ("FESTWERT a\n  GEWICHT 1\nEND\n", ":2:", "unknown keyword 'GEWICHT' in FESTWERT a"),
    ("KENNLINIE a 1\n  ST/Y 1\nEND\n", ":2:", "ST/Y does not belong in KENNLINIE"),
    ("FESTWERT a\n  WERT 1\n", ":2:", "FESTWERT a (line 1) is not closed by END"),
    ("FESTWERT a\n  WERT 1\nFESTWERT b\n  WERT 2\nEND\n", ":3:", "FESTWERT a (line 1) is not closed by END before 'FESTWERT'"),
    ("KENNLINIE a 3\n  ST/X 1 2\n  WERT 1 2 3\nEND\n", ":1:11:", "KENNLINIE a: 3 X points declared, 2 found"),
    ("FESTWERTEBLOCK a 2 @ 2\n  WERT 1 2 3\nEND\n", ":1:", "4 values declared, 3 found"),
    ("FESTWERT a\n  WERT \"1\"\nEND\n", ":2:8:", "the text '1' belongs on a TEXT line"),
    ("FESTWERT a\n  WERT 1,5\nEND\n", ":2:8:", "decimal comma"),
    ("FESTWERT a\n  WERT 1x\nEND\n", ":2:8:", "'1x' is not a number"),
    ("FESTWERT a\n  WERT 2.5  * tuned\nEND\n", ":2:13:", "'*' is not a number (a comment takes a line of its own"),
    ("FESTWERT a\n  LANGNAME \"open\nEND\n", ":2:12:", "text without its closing quote"),
    ("FESTWERT a\n WERT 1\nEND\nFESTWERT a\n WERT 2\nEND\n", ":4:10:", "a is defined twice (first at line 1)"),
    ("FESTWERT a\n  WERT 1 2\nEND\n", ":1:", "expects one WERT or TEXT, found 2"),
    ("FESTWERT a\nEND\n", ":1:", "expects one WERT or TEXT, found 0"),
    ("KONSERVIERUNG_FORMAT 3.0\n", ":1:22:", "KONSERVIERUNG_FORMAT 3.0 is not supported"),
    ("KENNFELD a 1 1\n  ST/X 1\n  WERT 1\n  ST/Y 1\nEND\n", ":3:", "WERT before the first ST/Y"),
    ("KENNFELD a 2 1\n  ST/X 1 2\n  ST/Y 1\n  WERT 1\nEND\n", ":1:", "the row of Y point 1 has 1 values, 2 declared"),
    ("KENNFELD a 1 1\n  ST/X 1\n  ST/Y 1 2\n  WERT 1\nEND\n", ":3:", "ST/Y carries one Y point"),
    ("KENNLINIE a 0\nEND\n", ":1:13:", "'0' is not a count above 0"),
    ("KENNLINIE a\nEND\n", ":1:", "KENNLINIE expects a name and the number of values"),
    ("FESTWERT a\n  LANGNAME \"x\"\n  LANGNAME \"y\"\n  WERT 1\nEND\n", ":3:", "LANGNAME again in FESTWERT a (first at line 2)"),
    ("FESTWERT a\n  VAR Engine\n  WERT 1\nEND\n", ":2:", "VAR expects criterion=value pairs"),
    ("END\n", ":1:1:", "END without a block to close"),
    ("FUNKTIONEN\n  FKT \"quoted\"\nEND\n", ":2:", "FKT expects a function name"),
    ("FESTWERT a\n  WERT 99999999999999999999\nEND\n", ":1:", "does not fit a 64-bit integer"),
])
def test_a_malformed_file_names_file_line_column_and_what_was_expected(text, where, message):
    with pytest.raises(DatasetParseError) as caught:
        read(text, "bad.dcm")
    error = str(caught.value)
    assert error.startswith("bad.dcm" + where) and message in error, error
    assert "\n" not in error


def test_a_bom_that_lies_is_named_with_its_line():
    with pytest.raises(DatasetParseError, match=r"^x.dcm:2: not valid UTF-8"):
        load_dataset_string(b"\xef\xbb\xbfFESTWERT a\n WERT \xff\nEND\n", "dcm", "x.dcm")


def test_numbers_keep_their_type_and_special_values():
    ds = read("FESTWERTEBLOCK a 6\n  WERT 1. .5 1e3 -0.0 NaN -inf\nEND\nFESTWERTEBLOCK b 3\n  WERT 0x1F +7 18446744073709551615\nEND\n")
    a = ds["a"].value
    assert a[:3].tolist() == [1.0, 0.5, 1000.0] and math.copysign(1, a[3]) == -1 and math.isnan(a[4]) and a[5] == -math.inf
    b = ds["b"].value
    assert b.dtype == np.uint64 and b.tolist() == [31, 7, 2**64 - 1]


def test_the_writer_wraps_six_values_a_line_and_reads_back():
    ds = Dataset()
    ds.add(CalValue("c", "CURVE", np.arange(8.0), axes=(Axis(np.arange(8) * 10),), unit="bar"))
    text = write(ds).decode()
    assert "  ST/X 0 10 20 30 40 50\n  ST/X 60 70\n" in text
    assert "  WERT 0.0 1.0 2.0 3.0 4.0 5.0\n  WERT 6.0 7.0\n" in text
    assert load_dataset_string(text, "dcm")["c"] == ds["c"]


def test_the_writer_keeps_texts_exactly_and_mixes_wert_and_text_lines():
    ds = Dataset(comments=["two\nlines"])
    ds.add(CalValue("t", "VAL_BLK", np.array(['say "hi"', "C:\\dir\\", 3, "Größe"], dtype=object)),
           ObjectInfo(display_name="shown name", comments=("c",)))
    text = write(ds).decode()
    assert '  TEXT "say \\"hi\\"" "C:\\\\dir\\\\"\n  WERT 3\n  TEXT "Größe"\n' in text
    assert text.startswith("* two\n* lines\n")
    back = load_dataset_string(text, "dcm")
    assert back["t"] == ds["t"] and back.info["t"].display_name == "shown name"


def test_what_dcm_cannot_hold_is_listed_and_left_out():
    ds = Dataset(a2l_file="FLCU.a2l")
    ds.add(CalValue("m", "MAP", np.zeros((1, 1)), axes=(Axis(np.zeros(1), "RES_AXIS", "r"), Axis(np.zeros(1)))),
           ObjectInfo(category="BOOLEAN"))
    messages = [f.message for f in losses(ds)]
    assert any("A2L file name 'FLCU.a2l'" in m for m in messages)
    assert "m: the RES_AXIS is written as a group axis (COM_AXIS)" in messages
    assert any(m.startswith("m: the axes' kinds RES_AXIS and STD_AXIS") for m in messages)
    cube = Dataset()
    cube.add(CalValue("q", "CUBOID", np.zeros((1, 1, 1)), axes=(Axis(np.zeros(1)),) * 3))
    cube.add(CalValue("a b", "VALUE", 1))
    cube.add(CalValue("v", "VALUE", 2))
    assert [f.message for f in losses(cube)] == [
        "q: a CUBOID of 1 x 1 x 1 values cannot be written to DCM (one or two dimensions); left out of the file",
        "a b: this name cannot be written to DCM (DCM names are identifiers); left out of the file"]
    assert list(read(write(cube).decode())) == ["v"]  # the rest is written


def test_an_encoding_that_cannot_hold_a_character_names_the_line():
    ds = Dataset()
    ds.add(CalValue("a", "VALUE", "日本"))
    with pytest.raises(InputError, match=r"line 6: '日' cannot be written in cp1252"):
        write(ds, "cp1252")


def test_a_missing_file_is_one_line(tmp_path):
    with pytest.raises(InputError, match=r"no such file"):
        load_dataset(tmp_path / "missing.dcm")
