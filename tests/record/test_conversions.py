"""COMPU_METHODs carried into the MDF as conversions (raw values stored) where asammdf computes what the
workbench computes, physical values where it cannot: each kind alone, and in a recording of signals the
demo's A2L is edited to convert otherwise."""

from __future__ import annotations

import re

import numpy as np
import pytest
from mdf_reading import channel, group_index

from workbench import demo
from workbench.a2l.compu import conversion_for
from workbench.a2l.objects import CompuMethod, CompuTab, CompuVtab, CompuVtabRange
from workbench.record import Recorder, mdf_encoding, record

# MDF4 cc_type: 1 linear, 2 rational, 3 algebraic, 4 table with interpolation, 5 table, 7 value to text,
# 8 value range to text
LINEAR, RATIONAL, ALGEBRAIC, TABLE_INTERPOLATED, TABLE, TEXT, RANGE_TEXT = 1, 2, 3, 4, 5, 7, 8


def method(kind: str, **fields) -> CompuMethod:
    return CompuMethod("CM_T", "", kind, "%8.3", "u", **fields)


def check_with_asammdf(conversion, raw: np.ndarray):
    """The encoding's conversion, evaluated by asammdf on ``raw``."""
    from asammdf.blocks.conversion_utils import from_dict

    encoding = mdf_encoding(conversion, raw.dtype)
    return encoding, from_dict(dict(encoding.conversion)).convert(raw, as_object=True)


@pytest.mark.parametrize(("kind", "fields", "table", "dtype", "expected_type"), [
    ("LINEAR", {"coeffs_linear": (0.5, -3.0)}, None, "u2", LINEAR),
    ("RAT_FUNC", {"coeffs": (0, 2, -1, 0, 0, 1)}, None, "f4", RATIONAL),
    ("FORM", {"formula": "X1 * 0.1 - 40"}, None, "u2", ALGEBRAIC),
    ("FORM", {"formula": "sqrt(X1) * 2 + sin(X1)"}, None, "f4", ALGEBRAIC),
    ("TAB_INTP", {"compu_tab_ref": "T"}, CompuTab("T", "", "TAB_INTP", ((0, 10), (10, 20), (100, 50))), "u1",
     TABLE_INTERPOLATED),
    ("TAB_NOINTP", {"compu_tab_ref": "T"}, CompuTab("T", "", "TAB_NOINTP", ((0, 10), (10, 20), (100, 50))), "i2",
     TABLE),
])
def test_numeric_methods_map_and_compute_alike(kind, fields, table, dtype, expected_type):
    from asammdf.blocks.conversion_utils import from_dict

    conversion = conversion_for(method(kind, **fields), table)
    keys_only = kind == "TAB_NOINTP"  # between its keys MDF takes the nearest entry (see the note test below)
    raw = np.array([0, 10, 100] if keys_only else [0, 1, 10, 55, 100], dtype=dtype)
    encoding, theirs = check_with_asammdf(conversion, raw)
    assert not encoding.physical and from_dict(dict(encoding.conversion)).conversion_type == expected_type
    assert np.allclose(theirs.astype(float), conversion.to_physical(raw), rtol=1e-6)


def test_verbal_tables_keep_the_workbench_texts():
    states = conversion_for(method("TAB_VERB", compu_tab_ref="V"), CompuVtab("V", "", ((0, "OFF"), (1, "ON"))))
    encoding, theirs = check_with_asammdf(states, np.array([0, 1, 7], dtype="u1"))
    assert [v.decode() if isinstance(v, bytes) else int(v) for v in theirs] == ["OFF", "ON", 7]  # as the session shows 7
    ranges = conversion_for(method("TAB_VERB", compu_tab_ref="R"),
                            CompuVtabRange("R", "", ((0, 9.5, "LOW"), (10, 100, "HIGH")), "?"))
    encoding, theirs = check_with_asammdf(ranges, np.array([0.0, 9.5, 9.7, 100.0, 150.0], dtype="f4"))
    assert [v.decode() for v in theirs] == ["LOW", "LOW", "?", "HIGH", "?"]  # ASAP2's upper bounds are inclusive


def test_what_does_not_map_is_stored_physical_or_raw_with_a_reason():
    c_operators = mdf_encoding(conversion_for(method("FORM", formula="X1 ^ 3"), None), np.dtype("u1"))
    assert c_operators.physical and "physical values" in c_operators.note  # ^ is XOR in ASAP2, a power in MDF
    natural_log = mdf_encoding(conversion_for(method("FORM", formula="log(X1)"), None), np.dtype("f4"))
    assert natural_log.physical  # MDF's log is not C's
    quadratic = mdf_encoding(conversion_for(method("RAT_FUNC", coeffs=(1, 2, 1, 0, 0, 1)), None), np.dtype("f4"))
    assert quadratic.conversion is None and not quadratic.physical and "quadratic" in quadratic.note
    table = conversion_for(method("TAB_NOINTP", compu_tab_ref="T"), CompuTab("T", "", "TAB_NOINTP", ((0, 1), (2, 3)), None, -1))
    assert "nearest" in mdf_encoding(table, np.dtype("u1")).note  # mapped, the difference said


EDITS = {  # measurement -> COMPU_METHOD given to it in the edited A2L
    "csPCM_TO_FLCU_002_TargetRailPressure": "CM_T_LINEAR",
    "xsDC": "CM_T_RAT",
    "zsRailPressure": "CM_T_FORM",
    "xsPRVDutyCmd": "CM_T_FORM_C",
    "xsValve1State": "CM_T_TAB",
    "xsLEDEn": "CM_T_RANGE",
}
METHODS = """
    /begin COMPU_METHOD CM_T_LINEAR "" LINEAR "%8.2" "kPa" COEFFS_LINEAR 2 1 /end COMPU_METHOD
    /begin COMPU_METHOD CM_T_RAT "" RAT_FUNC "%8.2" "%" COEFFS 0 2 -1 0 0 1 /end COMPU_METHOD
    /begin COMPU_METHOD CM_T_FORM "" FORM "%8.2" "psi" /begin FORMULA "X1*14.5-2" /end FORMULA /end COMPU_METHOD
    /begin COMPU_METHOD CM_T_FORM_C "" FORM "%8.2" "" /begin FORMULA "pow(X1, 2)" /end FORMULA /end COMPU_METHOD
    /begin COMPU_METHOD CM_T_TAB "" TAB_INTP "%8.2" "%" COMPU_TAB_REF TAB_T /end COMPU_METHOD
    /begin COMPU_TAB TAB_T "" TAB_INTP 2 0 0 1 100 /end COMPU_TAB
    /begin COMPU_METHOD CM_T_RANGE "" TAB_VERB "%3.0" "" COMPU_TAB_REF VTABR_T /end COMPU_METHOD
    /begin COMPU_VTAB_RANGE VTABR_T "" 2 0 0 "dark" 1 255 "lit" /end COMPU_VTAB_RANGE
"""


@pytest.fixture
def edited_a2l(tmp_path):
    text = demo.a2l().read_text(encoding="utf-8")
    for name, new in EDITS.items():
        text, count = re.subn(rf"(\*/ {name}\n(?:.*\n){{1,3}}?\s*/\* Conversion method\s*\*/ )\w+", rf"\g<1>{new}", text)
        assert count == 1, name
    anchor = "/begin COMPU_METHOD CM_bar "
    text = text.replace(anchor, METHODS.strip() + "\n    " + anchor, 1)
    path = tmp_path / "edited.a2l"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_recording_carries_the_conversions_the_session_reads(demo_ecu, edited_a2l, tmp_path, read_mdf):
    path = tmp_path / "converted.mf4"
    delivered = []
    with demo_ecu.open_session(edited_a2l) as ecu:
        with Recorder(ecu, path, list(EDITS), event="Task100ms", on_samples=delivered.append) as rec:
            rec.wait(1.5)
        target = ecu.read("csPCM_TO_FLCU_002_TargetRailPressure")
    assert target == pytest.approx(51.0)  # 25 bar raw, LINEAR 2x + 1
    mdf = read_mdf(path)
    index = group_index(mdf, "Task100ms")
    kinds = {cn.name: (cn.conversion.conversion_type if cn.conversion else None) for cn in mdf.groups[index].channels}
    assert kinds == {"time": None, "HostTime_Task100ms": None, "csPCM_TO_FLCU_002_TargetRailPressure": LINEAR,
                     "xsDC": RATIONAL, "zsRailPressure": ALGEBRAIC, "xsPRVDutyCmd": None,
                     "xsValve1State": TABLE_INTERPOLATED, "xsLEDEn": RANGE_TEXT}
    session_values = {name: np.concatenate([b.values[name] for b in delivered]) for name in EDITS}
    for name in EDITS:
        signal = channel(mdf, "Task100ms", name)
        if name == "xsLEDEn":
            assert [v.decode() for v in signal.samples] == session_values[name].tolist()
        else:
            assert np.allclose(signal.samples.astype(float), session_values[name], rtol=1e-6), name
    assert channel(mdf, "Task100ms", "csPCM_TO_FLCU_002_TargetRailPressure").samples[-1] == pytest.approx(51.0)
    assert channel(mdf, "Task100ms", "csPCM_TO_FLCU_002_TargetRailPressure", raw=True).samples[-1] == pytest.approx(25.0)
    power = channel(mdf, "Task100ms", "xsPRVDutyCmd")
    assert power.samples.dtype == np.float64 and "physical values" in power.comment
    assert channel(mdf, "Task100ms", "zsRailPressure").unit == "psi"


BIT_FIELDS = """
    /begin MEASUREMENT TRP_HighNibble "" UBYTE CM_Identity 0 0 0 15 BIT_MASK 0xF0 ECU_ADDRESS 0x400200A6 /end MEASUREMENT
    /begin MEASUREMENT TRP_Bit2 "" UBYTE CM_Identity 0 0 0 1 BIT_MASK 0x04 ECU_ADDRESS 0x400200A6 /end MEASUREMENT
    /begin MEASUREMENT TRP_Middle "" UWORD CM_Identity 0 0 0 255 BIT_MASK 0x0FF0 ECU_ADDRESS 0x400200A6 /end MEASUREMENT
    /begin MEASUREMENT TRP_Signed "" SBYTE CM_Identity 0 0 -8 7 BIT_MASK 0xF0 ECU_ADDRESS 0x400200A6 /end MEASUREMENT
"""


def test_bit_fields_are_recorded_in_their_elements_type(demo_ecu, tmp_path, read_mdf):
    """BIT_MASK fields of the received TargetRailPressure (raw 2500 = 0x09C4, little-endian at 0x400200A6): each
    value moved down to bit 0, sign-extended for a signed type, stored in the element's own type (a flag of a
    UBYTE took 8 bytes a sample as int64)."""
    a2l = tmp_path / "bits.a2l"
    text = demo.a2l().read_text(encoding="utf-8")
    a2l.write_text(text.replace("    /begin MEASUREMENT", BIT_FIELDS.strip("\n") + "\n    /begin MEASUREMENT", 1),
                   encoding="utf-8")
    expected = {"TRP_HighNibble": (12, "u1"), "TRP_Bit2": (1, "u1"), "TRP_Middle": (0x9C, "<u2"),
                "TRP_Signed": (-4, "i1")}
    with demo_ecu.open_session(a2l) as ecu:
        record(ecu, tmp_path / "bits.mf4", list(expected), event="Task100ms", duration=0.5)
    mdf = read_mdf(tmp_path / "bits.mf4")
    for name, (value, dtype) in expected.items():
        samples = channel(mdf, "Task100ms", name).samples
        assert samples.dtype == np.dtype(dtype) and samples[-1] == value, name
